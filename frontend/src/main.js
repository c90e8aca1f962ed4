// catwalk's shopper pages: one index.html, a page per route, each page one module.

import './styles.css';
import { startRouter, navigate } from './router.js';
import { getBodyId, onBodyChange } from './store.js';
import { setBanner } from './ui/feedback.js';
import { clear } from './ui/dom.js';
import * as catalogue from './pages/catalogue.js';
import * as garment from './pages/garment.js';
import * as body from './pages/body.js';
import * as tryon from './pages/tryon.js';
import * as compare from './pages/compare.js';
import * as merchant from './pages/merchant.js';
import * as notfound from './pages/notfound.js';

const PAGES = { catalogue, garment, body, tryon, compare, merchant, notfound };
const main = document.getElementById( 'main' );

let current = null; // { controller, cleanups }

function markNav( name ) {

	for ( const a of document.querySelectorAll( '[data-nav]' ) ) {

		const current = a.dataset.nav === name || ( name === 'garment' && a.dataset.nav === 'catalogue' );
		if ( current ) a.setAttribute( 'aria-current', 'page' );
		else a.removeAttribute( 'aria-current' );

	}

}

function markBody( id ) {

	const dot = document.querySelector( '.nav-dot' );
	if ( dot ) dot.hidden = ! id;

}

/** Leave the shown page: abort its requests, run what it registered with onCleanup. */
function leave() {

	if ( ! current ) return;
	current.controller.abort();
	for ( const fn of current.cleanups.reverse() ) {

		try {

			fn();

		} catch ( err ) {

			console.warn( 'page cleanup failed', err );

		}

	}

	current = null;

}

function render( route ) {

	leave();
	setBanner( null );
	clear( main );
	markNav( route.name );
	const page = PAGES[ route.name ] || notfound;
	main.dataset.page = route.name;
	const controller = new AbortController();
	const cleanups = [];
	current = { controller, cleanups };
	const ctx = {
		signal: controller.signal,
		get live() {

			return ! controller.signal.aborted;

		},
		onCleanup: ( fn ) => {

			if ( controller.signal.aborted ) fn();
			else cleanups.push( fn );

		},
	};
	Promise.resolve()
		.then( () => page.render( main, route, ctx ) )
		.catch( ( err ) => {

			if ( err && err.name === 'AbortError' ) return;
			console.error( err );

		} );
	if ( route.name !== 'catalogue' ) main.focus( { preventScroll: true } );

}

markBody( getBodyId() );
onBodyChange( markBody );
startRouter( render );

// A small hook for tests and debugging (no secrets: what the page already shows).
window.__catwalk = window.__catwalk || {};
window.__catwalk.navigate = navigate;
