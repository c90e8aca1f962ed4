// Your body's measurements form: the body shape and four measurements in cm, each checked
// against its range as it is typed (and all of them when sent); "Make my body" asks the API for
// the body (POST /api/bodies).

import { createBody, ApiError } from '../api.js';
import { h, clear, nextId } from '../ui/dom.js';
import { errorNotice } from '../ui/feedback.js';
import { FIELDS, LABELS, HINTS, rangeCm, checkMeasurement, checkForm } from '../measurements.js';

/** The form: `onBody(body)` with the body made from it. */
export function measurementsForm( onBody, ctx ) {

	const form = h( 'form', { class: 'panel measure-form', novalidate: true, 'aria-labelledby': 'measure-title' } );
	const sex = sexField();
	const errors = { sex: sex.err }; // by field, and by the API's field name
	const inputs = {};
	const touched = new Set();
	const fields = FIELDS.map( ( key ) => {

		const f = measurementField( key, touched );
		inputs[ key ] = f.input;
		errors[ key ] = f.err;
		return f.wrap;

	} );

	const formError = h( 'div', { 'aria-live': 'assertive' } );
	const submit = h( 'button', { type: 'submit', class: 'button button--primary button--wide' }, 'Make my body' );
	form.append(
		h( 'h2', { id: 'measure-title' }, 'Type your measurements' ),
		h( 'p', { class: 'muted' }, 'A tape measure and two minutes. Measure over underwear, tape snug but not tight.' ),
		sex.wrap,
		h( 'div', { class: 'measure-grid' }, fields ),
		formError,
		submit,
	);

	form.addEventListener( 'submit', ( e ) => {

		e.preventDefault();
		send( { form, inputs, errors, formError, submit }, onBody, ctx );

	} );
	return form;

}

/** Female or male: two radio buttons named "sex". */
function sexField() {

	const sexId = nextId( 'sex' );
	const err = h( 'p', { class: 'field__error', id: `${ sexId }-err`, 'aria-live': 'polite' } );
	const wrap = h( 'fieldset', { class: 'field segmented-field' }, h( 'legend', {}, 'Body shape' ),
		h( 'div', { class: 'segmented' },
			[ [ 'female', 'Female' ], [ 'male', 'Male' ] ].map( ( [ v, label ], i ) => {

				const id = `${ sexId }-${ v }`;
				return h( 'span', { class: 'segmented__item' },
					h( 'input', { type: 'radio', name: 'sex', id, value: v, checked: i === 0 } ),
					h( 'label', { for: id }, label ) );

			} ),
		),
		err,
	);
	return { wrap, err };

}

/**
 * One measurement in cm, its range as placeholder and hint; its error shown as it is typed once
 * it has a value or has been left with one (`touched`: the keys left with a value).
 */
function measurementField( key, touched ) {

	const id = nextId( key );
	const [ lo, hi ] = rangeCm( key );
	const err = h( 'p', { class: 'field__error', id: `${ id }-err`, 'aria-live': 'polite' } );
	const input = h( 'input', {
		id, name: key, type: 'text', inputmode: 'decimal', autocomplete: 'off', spellcheck: false,
		placeholder: `${ lo }–${ hi }`, 'aria-describedby': `${ id }-hint ${ id }-err`,
	} );
	const check = ( force ) => {

		const r = checkMeasurement( key, input.value, { required: force } );
		const show = ! r.ok && ( force || touched.has( key ) || input.value.trim() !== '' );
		err.textContent = show ? r.message : '';
		input.setAttribute( 'aria-invalid', String( show ) );
		return r.ok;

	};

	input.addEventListener( 'input', () => check( false ) );
	input.addEventListener( 'blur', () => {

		if ( input.value.trim() !== '' ) touched.add( key );
		check( false );

	} );
	const wrap = h( 'div', { class: 'field' },
		h( 'label', { for: id }, LABELS[ key ] ),
		h( 'div', { class: 'input-unit' }, input, h( 'span', { class: 'input-unit__unit', 'aria-hidden': 'true' }, 'cm' ) ),
		h( 'p', { class: 'field__hint', id: `${ id }-hint` }, `${ HINTS[ key ] } ${ lo }–${ hi } cm.` ),
		err,
	);
	return { wrap, input, err };

}

/** Check every field; when they are right, make the body (the API's refusal shown at its field). */
async function send( { form, inputs, errors, formError, submit }, onBody, ctx ) {

	clear( formError );
	const values = { sex: ( form.querySelector( 'input[name=sex]:checked' ) || {} ).value };
	for ( const k of FIELDS ) values[ k ] = inputs[ k ].value;
	const checked = checkForm( values );
	for ( const k of Object.keys( errors ) ) {

		errors[ k ].textContent = checked.errors[ k ] || '';
		if ( inputs[ k ] ) inputs[ k ].setAttribute( 'aria-invalid', String( !! checked.errors[ k ] ) );

	}

	if ( ! checked.ok ) {

		const first = FIELDS.find( ( k ) => checked.errors[ k ] );
		if ( first ) inputs[ first ].focus();
		return;

	}

	submit.disabled = true;
	submit.replaceChildren( h( 'span', { class: 'spinner spinner--small', 'aria-hidden': 'true' } ), 'Making your body…' );
	try {

		const body = await createBody( checked.body, { signal: ctx.signal } );
		onBody( body );

	} catch ( err ) {

		if ( ! ctx.live ) return;
		submit.disabled = false;
		submit.textContent = 'Make my body';
		if ( err instanceof ApiError && err.field && errors[ err.field ] ) {

			errors[ err.field ].textContent = err.message;
			if ( inputs[ err.field ] ) {

				inputs[ err.field ].setAttribute( 'aria-invalid', 'true' );
				inputs[ err.field ].focus();

			}

		} else {

			formError.append( errorNotice( err ) );

		}

	}

}
