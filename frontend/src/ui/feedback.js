// Messages a person can act on: the server unreachable (with a retry), an API error, a spinner.

import { h, clear } from './dom.js';
import { NetworkError } from '../api.js';

/** A notice block. `kind`: info | error | warn. `action`: { label, onClick } or an element. */
export function notice( kind, title, text, action = null ) {

	return h( 'div', { class: `notice notice--${ kind }`, role: kind === 'error' ? 'alert' : 'status' },
		h( 'div', { class: 'notice__body' },
			title ? h( 'p', { class: 'notice__title' }, title ) : null,
			text ? h( 'p', { class: 'notice__text' }, text ) : null,
		),
		action ? ( action instanceof Node ? action : h( 'button', { class: 'button button--secondary', type: 'button', onclick: action.onClick }, action.label ) ) : null,
	);

}

/** The notice for an error thrown by api.js; `retry` re-runs what failed. */
export function errorNotice( err, retry = null ) {

	if ( err instanceof NetworkError ) {

		return notice( 'error', 'We can’t reach the catwalk server', 'Check your connection; the server may also be restarting.', retry ? { label: 'Try again', onClick: retry } : null );

	}

	const title = err && err.status === 404 ? 'Not found' : 'Something went wrong';
	return notice( 'error', title, err && err.message ? err.message : String( err ), retry ? { label: 'Try again', onClick: retry } : null );

}

/** Show (or, with null, hide) the page-wide banner above the content. */
export function setBanner( el ) {

	const slot = document.getElementById( 'banner' );
	if ( ! slot ) return;
	clear( slot );
	if ( el ) slot.appendChild( el );

}

export function spinner( label = 'Loading…' ) {

	return h( 'div', { class: 'loading', role: 'status' }, h( 'span', { class: 'spinner', 'aria-hidden': 'true' } ), h( 'span', {}, label ) );

}

/** A determinate progress bar: returns { el, set(fraction, text) }. */
export function progressBar( label ) {

	const fill = h( 'div', { class: 'bar__fill' } );
	const bar = h( 'div', { class: 'bar', role: 'progressbar', 'aria-label': label, 'aria-valuemin': '0', 'aria-valuemax': '100', 'aria-valuenow': '0' }, fill );
	return {
		el: bar,
		set( fraction, text = null ) {

			const pct = Math.round( Math.min( 1, Math.max( 0, fraction ) ) * 1000 ) / 10;
			fill.style.width = `${ pct }%`;
			bar.setAttribute( 'aria-valuenow', String( Math.floor( pct ) ) );
			if ( text ) bar.setAttribute( 'aria-valuetext', text );

		},
		indeterminate( on ) {

			bar.classList.toggle( 'bar--indeterminate', on );

		},
	};

}
