// The garment dressed on the sample body of its default size: its picture (the thumbnail) at
// first, in 3D (dressed.glb, turned by dragging) once it loads where the browser and the API
// allow, with a "Fit map" toggle when the file carries the fit.

import { thumbnailUrl, dressedUrl, apiPaths, hasDressedRoute } from '../api.js';
import { h } from '../ui/dom.js';
import { shortName } from '../format.js';
import { hasWebGL } from '../viewer/webgl.js';
import { showDressed } from '../viewer/dressed-view.js';
import { fitMapToggle } from '../player/controls.js';

/** The figure; its 3D view is asked for at once (the picture stays where there is none). */
export function garmentMedia( g, ctx ) {

	const picture = h( 'img', { src: thumbnailUrl( g.id ), alt: `${ shortName( g.name ) } dressed on a sample body`, width: 240, height: 360, class: 'garment-media__img' } );
	const view = h( 'div', { class: 'garment-media__view', hidden: true } );
	const caption = h( 'figcaption', { class: 'muted' }, `Simulated on our size ${ g.default_size } sample body.` );
	const extras = h( 'div', { class: 'garment-media__extras', hidden: true } );
	const media = h( 'figure', { class: 'garment-media' }, picture, view, caption, extras );
	show3d( g, ctx, { picture, view, caption, extras } );
	return media;

}

async function show3d( g, ctx, { picture, view, caption, extras } ) {

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

		extras.append( ...fitMapToggle( shown.player ) );
		extras.hidden = false;

	}

	window.__catwalk = window.__catwalk || {};
	window.__catwalk.dressed = shown.player;

}
