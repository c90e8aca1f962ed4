// A try-on (/tryon/{id}): its progress, then the player; a failed one's reason.

import { getGarment, createTryon, resultUrl, previewUrl, ApiError } from '../api.js';
import { urls, navigate } from '../router.js';
import { h, clear, icon, nextId } from '../ui/dom.js';
import { errorNotice } from '../ui/feedback.js';
import { fabricName, presetName, shortName } from '../format.js';
import { getBodyId, forgetBody } from '../store.js';
import { mountTryon } from '../player/tryon-view.js';
import { startSession } from '../player/session.js';

export function render( root, route, ctx ) {

	document.title = 'Try-on — catwalk';
	const crumbs = h( 'p', { class: 'crumbs' }, h( 'a', { href: urls.catalogue(), 'data-link': '' }, icon( 'back' ), 'Catalogue' ) );
	const title = h( 'h1', { class: 'tryon-title' }, 'Your try-on' );
	const meta = h( 'p', { class: 'tryon-meta muted' } );
	const box = h( 'div', { class: 'tryon-box', 'data-tryon': route.id } );
	const controlsBox = h( 'div', { class: 'tryon-controls' } );
	const extra = h( 'div', { class: 'tryon-extra' } );
	const wrap = h( 'div', { class: 'player', tabindex: '-1' }, box, controlsBox );
	root.append(
		crumbs,
		h( 'header', { class: 'tryon-head' }, title, meta ),
		wrap,
		extra,
	);

	let garment = null;
	let info = null;
	let session = null;
	ctx.onCleanup( () => session && session.dispose() );

	const describe = ( t ) => {

		const fabric = t.fabric || ( garment && garment.fabric );
		meta.textContent = [ `Size ${ t.size }`, fabric ? fabricName( fabric ) : null, `${ t.seconds } s walk`, `${ presetName( t.preset ) } quality` ].filter( Boolean ).join( ' · ' );

	};

	const setInfo = async ( t ) => {

		info = t;
		describe( t );
		if ( garment || ! t.garment_id ) return;
		garment = { id: t.garment_id }; // asked once
		crumbs.replaceChildren( h( 'a', { href: urls.garment( t.garment_id ), 'data-link': '' }, icon( 'back' ), 'The garment' ) );
		try {

			garment = await getGarment( t.garment_id, { signal: ctx.signal } );
			if ( ! ctx.live ) return;
			title.textContent = shortName( garment.name );
			document.title = `${ shortName( garment.name ) }, size ${ t.size } — catwalk`;
			describe( info );

		} catch { /* the title stays generic */ }

	};

	mountTryon( box, route.id, {
		ctx,
		compress: route.compress,
		label: 'Your try-on',
		onInfo: setInfo,
		onReady: ( player, stage ) => {

			const t = player.tryon;
			const fps = ( t.metrics && t.metrics.fps ) || player.fps;
			session = startSession( {
				players: [ player ],
				stages: [ stage ],
				controlsBox,
				keyTarget: wrap,
				fps,
				downloads: [
					{ href: resultUrl( route.id, { compress: route.compress } ), label: 'Download .glb', filename: `tryon-${ route.id.slice( 0, 8 ) }.glb` },
					{ href: previewUrl( route.id ), label: 'Preview image', filename: `tryon-${ route.id.slice( 0, 8 ) }.png` },
				],
				fitMapNote: route.compress ? 'This try-on’s web file has no pattern coordinates, so the fit map cannot be drawn for it.' : null,
			} );
			showExtra( t );

		},
	} );

	function showExtra( t ) {

		clear( extra );
		const m = t.metrics || {};
		const facts = [];
		if ( m.frames ) facts.push( [ 'Frames', `${ m.frames } at ${ m.fps || 30 } per second` ] );
		if ( m.points ) facts.push( [ 'Cloth points', m.points.toLocaleString( 'en' ) ] );
		if ( typeof m.p99_strain === 'number' ) facts.push( [ 'Stretch (99 % of the cloth under)', `${ ( m.p99_strain * 100 ).toFixed( 1 ) } %` ] );
		if ( typeof m.max_penetration_mm === 'number' ) facts.push( [ 'Deepest dip into the body', `${ m.max_penetration_mm.toFixed( 1 ) } mm` ] );
		if ( t.cached ) facts.push( [ 'From', 'an identical try-on made before' ] );

		const sections = [];
		const body = getBodyId();
		const sizes = garment && garment.sizes ? garment.sizes.filter( ( s ) => s !== t.size ) : [];
		if ( body && sizes.length ) sections.push( compareForm( t, sizes, body ) );
		if ( facts.length ) {

			sections.push( h( 'details', { class: 'panel about' },
				h( 'summary', {}, 'About this simulation' ),
				h( 'dl', { class: 'facts' }, facts.map( ( [ k, v ] ) => h( 'div', {}, h( 'dt', {}, k ), h( 'dd', {}, v ) ) ) ),
			) );

		}

		extra.append( ...sections );

	}

	function compareForm( t, sizes, bodyId ) {

		const id = nextId( 'other' );
		const select = h( 'select', { id }, sizes.map( ( s ) => h( 'option', { value: s }, `Size ${ s }` ) ) );
		const status = h( 'div', { 'aria-live': 'polite' } );
		const go = h( 'button', { type: 'submit', class: 'button button--secondary' }, 'Compare side by side' );
		const form = h( 'form', { class: 'panel compare-form' },
			h( 'h2', {}, 'Not sure about the size?' ),
			h( 'p', { class: 'muted' }, 'Walk in another size next to this one, in step.' ),
			h( 'div', { class: 'inline-form' }, h( 'label', { for: id, class: 'visually-hidden' }, 'Other size' ), select, go ),
			status,
		);
		form.addEventListener( 'submit', async ( e ) => {

			e.preventDefault();
			go.disabled = true;
			clear( status );
			try {

				const other = await createTryon( {
					body_id: bodyId, garment_id: t.garment_id, size: select.value, fabric: t.fabric || null, seconds: t.seconds, preset: t.preset,
				}, { signal: ctx.signal } );
				if ( ctx.live ) navigate( urls.compare( route.id, other.id ) );

			} catch ( err ) {

				if ( ! ctx.live ) return;
				go.disabled = false;
				if ( err instanceof ApiError && err.field === 'body_id' ) forgetBody();
				status.append( errorNotice( err ) );

			}

		} );
		return form;

	}

}
