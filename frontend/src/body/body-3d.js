// Your body in 3D (its body.glb on a stage you can turn and zoom), or why it cannot be shown:
// no WebGL in this browser, or the file did not load ("Try again").

import { NetworkError } from '../api.js';
import { h, clear } from '../ui/dom.js';
import { spinner, notice } from '../ui/feedback.js';
import { hasWebGL, NO_WEBGL_MESSAGE } from '../viewer/webgl.js';
import { showBody } from '../viewer/body-view.js';

/**
 * The 3D view of `body`: `{ el, show() }`; `show()` once `el` is in the page (the stage takes
 * its size). `onViewer(viewer)` when the body is shown, `onRetry()` from "Try again".
 */
export function createBodyView( body, ctx, { onViewer, onRetry } ) {

	const view = h( 'div', { class: 'stage stage--body' } );
	const el = h( 'div', { class: 'body-layout__view' }, view, h( 'p', { class: 'muted small' }, 'Drag to turn, pinch or scroll to zoom.' ) );

	function show() {

		if ( ! hasWebGL() ) {

			view.classList.add( 'stage--none' );
			view.append( notice( 'warn', 'No 3D in this browser', NO_WEBGL_MESSAGE ) );
			return;

		}

		view.append( spinner( 'Loading your body in 3D…' ) );
		showBody( view, body.body_url, { signal: ctx.signal } ).then( ( v ) => {

			if ( ! v ) return;
			onViewer( v );
			const s = view.querySelector( '.loading' );
			if ( s ) s.remove();
			window.__catwalk = window.__catwalk || {};
			window.__catwalk.bodyView = v;

		} ).catch( ( err ) => {

			if ( ! ctx.live ) return;
			clear( view ).append( notice( 'error', 'Your body could not be shown', err instanceof NetworkError ? err.message : 'Its 3D file did not load.', { label: 'Try again', onClick: onRetry } ) );

		} );

	}

	return { el, show };

}
