// A garment (/garments/{id}): its sizes, fabrics and pattern pieces, a view of it dressed on a
// sample body, size advice for your body, and "Try it on".

import { getGarment, thumbnailUrl, patternUrl, dressedUrl, createTryon, getSizeAdvice, apiPaths, hasDressedRoute, ApiError } from '../api.js';
import { urls, navigate } from '../router.js';
import { h, clear, nextId, icon } from '../ui/dom.js';
import { errorNotice, spinner, notice } from '../ui/feedback.js';
import { fabricName, typeName, shortName, nameSource, PRESETS, WALK_LENGTHS } from '../format.js';
import { getBodyId, forgetBody } from '../store.js';
import { adviceSummary } from '../advice.js';
import { hasWebGL } from '../viewer/webgl.js';
import { showDressed } from '../viewer/dressed-view.js';
import { fitLegend } from '../player/controls.js';

export function render( root, route, ctx ) {

	document.title = 'Garment — catwalk';
	const page = h( 'div', { class: 'garment-page' } );
	root.append(
		h( 'p', { class: 'crumbs' }, h( 'a', { href: urls.catalogue(), 'data-link': '' }, icon( 'back' ), 'Catalogue' ) ),
		page,
	);

	async function load() {

		clear( page ).append( spinner( 'Loading the garment…' ) );
		let g;
		try {

			g = await getGarment( route.id, { signal: ctx.signal } );

		} catch ( err ) {

			if ( ! ctx.live ) return;
			clear( page ).append( errorNotice( err, err instanceof ApiError && err.status === 404 ? null : load ) );
			return;

		}

		if ( ! ctx.live ) return;
		show( g );

	}

	function show( g ) {

		document.title = `${ shortName( g.name ) } — catwalk`;
		clear( page );
		const bodyId = getBodyId();
		let size = g.default_size;

		// --- dressed on the sample body of its default size: in 3D (dressed.glb), the picture
		// (the thumbnail) until then, or where there is no 3D ---
		const picture = h( 'img', { src: thumbnailUrl( g.id ), alt: `${ shortName( g.name ) } dressed on a sample body`, width: 240, height: 360, class: 'garment-media__img' } );
		const view = h( 'div', { class: 'garment-media__view', hidden: true } );
		const caption = h( 'figcaption', { class: 'muted' }, `Simulated on our size ${ g.default_size } sample body.` );
		const extras = h( 'div', { class: 'garment-media__extras', hidden: true } );
		const media = h( 'figure', { class: 'garment-media' }, picture, view, caption, extras );
		show3d( g, { picture, view, caption, extras } );

		// --- the order form ---
		const form = h( 'form', { class: 'tryon-form', novalidate: true } );
		const sizeName = nextId( 'size' );
		const sizeGroup = h( 'fieldset', { class: 'field sizes' }, h( 'legend', {}, 'Size' ) );
		const sizeRow = h( 'div', { class: 'size-options' } );
		const sizeError = h( 'p', { class: 'field__error', 'aria-live': 'polite' } );
		const adviceEl = h( 'div', { class: 'advice', 'aria-live': 'polite' } );
		for ( const s of g.sizes ) {

			const id = nextId( 'size' );
			sizeRow.append( h( 'span', { class: 'size-option' },
				h( 'input', { type: 'radio', name: sizeName, id, value: s, checked: s === size, onchange: () => setSize( s ) } ),
				h( 'label', { for: id }, s ),
			) );

		}

		sizeGroup.append( sizeRow, adviceEl, sizeError );

		const select = ( label, options, value, hint = null ) => {

			const id = nextId( 'sel' );
			const el = h( 'select', { id, name: label } );
			for ( const [ v, text ] of options ) el.append( h( 'option', { value: v, selected: v === value }, text ) );
			const err = h( 'p', { class: 'field__error', 'aria-live': 'polite' } );
			const wrap = h( 'div', { class: 'field' }, h( 'label', { for: id }, label ), el, hint ? h( 'p', { class: 'field__hint' }, hint ) : null, err );
			return { wrap, el, err };

		};

		const fabric = select( 'Fabric', g.fabrics.map( ( f, i ) => [ f, i === 0 ? `${ fabricName( f ) } (as designed)` : fabricName( f ) ] ), g.fabric );
		const seconds = select( 'Walk length', WALK_LENGTHS.map( ( s ) => [ String( s ), `${ s } seconds` ] ), '4' );
		const preset = select( 'Quality', PRESETS.map( ( [ v, name, hint ] ) => [ v, `${ name } — ${ hint }` ] ), 'balanced' );
		const formError = h( 'div', { class: 'form-error', 'aria-live': 'assertive' } );
		const submit = h( 'button', { type: 'submit', class: 'button button--primary button--wide' }, 'Try it on' );
		const needBody = h( 'div', { class: 'need-body' },
			h( 'p', {}, 'To try it on we need your body: a few measurements or a 3D scan.' ),
			h( 'a', { class: 'button button--primary button--wide', href: urls.body(), 'data-link': '' }, 'Set up your body' ),
		);
		form.append(
			sizeGroup,
			h( 'div', { class: 'field-row' }, fabric.wrap ),
			h( 'div', { class: 'field-row field-row--2' }, seconds.wrap, preset.wrap ),
			formError,
			bodyId ? submit : needBody,
		);
		const fieldErrors = { size: sizeError, fabric: fabric.err, seconds: seconds.err, preset: preset.err };

		form.addEventListener( 'submit', async ( e ) => {

			e.preventDefault();
			for ( const el of Object.values( fieldErrors ) ) el.textContent = '';
			clear( formError );
			const body = getBodyId();
			if ( ! body ) return;
			submit.disabled = true;
			submit.textContent = 'Starting…';
			try {

				const t = await createTryon( {
					body_id: body,
					garment_id: g.id,
					size,
					fabric: fabric.el.value === g.fabric ? null : fabric.el.value,
					seconds: Number( seconds.el.value ),
					preset: preset.el.value,
				}, { signal: ctx.signal } );
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

		} );

		// --- the pattern pieces ---
		const patternImg = h( 'img', { class: 'pattern__img', src: patternUrl( g.id, size ), alt: `Cutting pattern of ${ shortName( g.name ) }, size ${ size }`, width: 480, height: 360 } );
		const patternCaption = h( 'figcaption', { class: 'muted' } );
		const setCaption = () => {

			patternCaption.textContent = `Size ${ size }: ${ g.panels.length } pieces, ${ g.seams } seams, laid flat.`;

		};

		setCaption();

		function setSize( s ) {

			size = s;
			patternImg.src = patternUrl( g.id, s );
			patternImg.alt = `Cutting pattern of ${ shortName( g.name ) }, size ${ s }`;
			setCaption();
			for ( const input of sizeRow.querySelectorAll( 'input' ) ) input.checked = input.value === s;

		}

		const source = nameSource( g.name );
		page.append(
			h( 'div', { class: 'garment-layout' },
				media,
				h( 'div', { class: 'garment-info' },
					h( 'p', { class: 'eyebrow' }, typeName( g.type ) ),
					h( 'h1', {}, shortName( g.name ) ),
					source ? h( 'p', { class: 'muted' }, `Pattern: ${ source }` ) : null,
					g.description ? h( 'p', { class: 'lead' }, g.description ) : null,
					h( 'dl', { class: 'facts' },
						h( 'div', {}, h( 'dt', {}, 'Sizes' ), h( 'dd', {}, g.sizes.join( ' · ' ) ) ),
						h( 'div', {}, h( 'dt', {}, 'Fabric' ), h( 'dd', {}, fabricName( g.fabric ) ) ),
						h( 'div', {}, h( 'dt', {}, 'Other fabrics' ), h( 'dd', {}, `${ g.fabrics.length - 1 } to choose from` ) ),
					),
					form,
				),
			),
			h( 'section', { class: 'pattern', 'aria-labelledby': 'pattern-title' },
				h( 'h2', { id: 'pattern-title' }, 'Pattern pieces' ),
				h( 'figure', { class: 'pattern__figure' }, patternImg, patternCaption ),
				h( 'ul', { class: 'pieces' }, g.panels.map( ( p ) => h( 'li', {}, pieceName( p.name ) ) ) ),
			),
		);

		if ( bodyId ) showAdvice( g, bodyId, adviceEl, setSize );

	}

	async function show3d( g, { picture, view, caption, extras } ) {

		if ( ! hasWebGL() ) return;
		try {

			if ( ! hasDressedRoute( await apiPaths() ) ) return;

		} catch {

			return;

		}

		if ( ! ctx.live ) return;
		view.hidden = false;
		view.classList.add( 'garment-media__view--loading' );
		let shown;
		try {

			shown = await showDressed( view, dressedUrl( g.id ), { signal: ctx.signal, label: `${ shortName( g.name ) } on a sample body, in 3D; drag to turn it` } );

		} catch {

			view.hidden = true; // not made yet, or it failed: the picture stays
			return;

		}

		if ( ! shown || ! ctx.live ) return;
		ctx.onCleanup( shown.dispose );
		view.classList.remove( 'garment-media__view--loading' );
		picture.hidden = true;
		caption.textContent = `Simulated on our size ${ g.default_size } sample body. Drag to turn it.`;
		if ( shown.player.fitMap ) {

			const legend = fitLegend();
			const toggle = h( 'button', { type: 'button', class: 'seg seg--toggle', 'aria-pressed': 'false' }, 'Fit map' );
			toggle.addEventListener( 'click', () => {

				const on = toggle.getAttribute( 'aria-pressed' ) !== 'true';
				toggle.setAttribute( 'aria-pressed', String( on ) );
				shown.player.setFitMap( on );
				legend.hidden = ! on;

			} );
			extras.append( h( 'div', { class: 'segs' }, toggle ), legend );
			extras.hidden = false;

		}

		window.__catwalk = window.__catwalk || {};
		window.__catwalk.dressed = shown.player;

	}

	async function showAdvice( g, bodyId, el, setSize ) {

		let advice;
		try {

			advice = await getSizeAdvice( g.id, bodyId, { signal: ctx.signal } );

		} catch {

			return; // advice is a help, not a must: say nothing

		}

		if ( ! ctx.live || ! advice ) return;
		const summary = adviceSummary( advice );
		if ( ! summary ) return;
		if ( summary.recommended && g.sizes.includes( summary.recommended ) ) setSize( summary.recommended );
		el.append(
			h( 'p', { class: 'advice__main' }, adviceHeadline( summary ) ),
			h( 'ul', { class: 'advice__list' }, summary.sizes.map( ( s ) => h( 'li', { class: s.fits ? 'fits' : 'tight' }, h( 'strong', {}, s.size ), ' ', s.text ) ) ),
		);

	}

	load();

}

function adviceHeadline( s ) {

	if ( ! s.recommended ) return 'We have no size advice for this garment.';
	if ( ! s.recommendedFits ) return `No size has room for all your measurements; ${ s.recommended } is the closest.`;
	return `We suggest size ${ s.recommended } for your body.`;

}

function pieceName( name ) {

	const s = String( name ).replace( /[_-]+/g, ' ' );
	return s.charAt( 0 ).toUpperCase() + s.slice( 1 );

}
