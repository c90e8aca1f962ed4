// The try-on's order form on a garment page: the size (sizes.js), the fabric, the walk's length
// and the quality; "Try it on" starts the try-on (POST /api/tryons) and opens its page, or, with
// no body yet, a link to set one up.

import { createTryon, ApiError } from '../api.js';
import { urls, navigate } from '../router.js';
import { h, clear, nextId } from '../ui/dom.js';
import { errorNotice, notice } from '../ui/feedback.js';
import { fabricName, PRESETS, WALK_LENGTHS } from '../format.js';
import { getBodyId, forgetBody } from '../store.js';

/**
 * The form around the `sizes` picker (sizePicker's); `size()` the size picked, `bodyId` the
 * shopper's body (none: no "Try it on").
 */
export function tryonForm( g, ctx, { sizes, size, bodyId } ) {

	const form = h( 'form', { class: 'tryon-form', novalidate: true } );
	const fabric = select( 'Fabric', g.fabrics.map( ( f, i ) => [ f, i === 0 ? `${ fabricName( f ) } (as designed)` : fabricName( f ) ] ), g.fabric );
	const seconds = select( 'Walk length', WALK_LENGTHS.map( ( s ) => [ String( s ), `${ s } second${ s === 1 ? '' : 's' }` ] ), '4' );
	const preset = select( 'Quality', PRESETS.map( ( [ v, name, hint ] ) => [ v, `${ name } — ${ hint }` ] ), 'balanced' );
	const formError = h( 'div', { class: 'form-error', 'aria-live': 'assertive' } );
	const submit = h( 'button', { type: 'submit', class: 'button button--primary button--wide' }, 'Try it on' );
	form.append(
		sizes.el,
		h( 'div', { class: 'field-row' }, fabric.wrap ),
		h( 'div', { class: 'field-row field-row--2' }, seconds.wrap, preset.wrap ),
		formError,
		bodyId ? submit : needBody(),
	);
	const fieldErrors = { size: sizes.error, fabric: fabric.err, seconds: seconds.err, preset: preset.err };

	form.addEventListener( 'submit', ( e ) => {

		e.preventDefault();
		for ( const el of Object.values( fieldErrors ) ) el.textContent = '';
		clear( formError );
		const body = getBodyId();
		if ( ! body ) return;
		start( {
			body_id: body,
			garment_id: g.id,
			size: size(),
			fabric: fabric.el.value === g.fabric ? null : fabric.el.value,
			seconds: Number( seconds.el.value ),
			preset: preset.el.value,
		}, { submit, formError, fieldErrors }, ctx );

	} );
	return form;

}

/** A labelled select of `[value, text]` options, `value` selected: `{ wrap, el, err }`. */
function select( label, options, value, hint = null ) {

	const id = nextId( 'sel' );
	const el = h( 'select', { id, name: label } );
	for ( const [ v, text ] of options ) el.append( h( 'option', { value: v, selected: v === value }, text ) );
	const err = h( 'p', { class: 'field__error', 'aria-live': 'polite' } );
	const wrap = h( 'div', { class: 'field' }, h( 'label', { for: id }, label ), el, hint ? h( 'p', { class: 'field__hint' }, hint ) : null, err );
	return { wrap, el, err };

}

function needBody() {

	return h( 'div', { class: 'need-body' },
		h( 'p', {}, 'To try it on we need your body: a few measurements or a 3D scan.' ),
		h( 'a', { class: 'button button--primary button--wide', href: urls.body(), 'data-link': '' }, 'Set up your body' ),
	);

}

/** Start the try-on `request` and open its page; a refusal shown at its field, or under the form. */
async function start( request, { submit, formError, fieldErrors }, ctx ) {

	submit.disabled = true;
	submit.textContent = 'Starting…';
	try {

		const t = await createTryon( request, { signal: ctx.signal } );
		if ( ctx.live ) navigate( urls.tryon( t.id ) );

	} catch ( err ) {

		if ( ! ctx.live ) return;
		submit.disabled = false;
		submit.textContent = 'Try it on';
		if ( err instanceof ApiError && err.field === 'body_id' ) {

			forgetBody();
			formError.append( notice( 'error', 'We no longer have your body', 'It may have been deleted. Set it up again to try this on.', h( 'a', { class: 'button button--secondary', href: urls.body(), 'data-link': '' }, 'Set up your body' ) ) );

		} else if ( err instanceof ApiError && fieldErrors[ err.field ] ) {

			fieldErrors[ err.field ].textContent = err.message;

		} else {

			formError.append( errorNotice( err ) );

		}

	}

}
