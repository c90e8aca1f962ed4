// What the component says when the service refuses the shop's set-up (docs/embed.md): the
// key, the page's origin, a secret key in the page. A shopper sees a short line; the
// merchant, reading the same notice, the service's own reason beside it.

import { ApiError, NetworkError } from '../api.js';

/** Refusals that are the shop's set-up, not the shopper's doing. */
export const SETUP_CODES = [ 'origin_not_allowed', 'secret_key_exposed', 'unauthorized', 'key_not_allowed' ];

export function isSetupError( err ) {

	return err instanceof ApiError && SETUP_CODES.includes( err.code );

}

/** `{ title, text }` for an error met while starting up. */
export function setupMessage( err ) {

	if ( err instanceof NetworkError ) {

		return { title: 'The try-on cannot start', text: 'The catwalk server cannot be reached from this page. Check the connection, then reload.' };

	}

	if ( err instanceof ApiError && err.code === 'secret_key_exposed' ) {

		return { title: 'This page holds a secret key', text: `The try-on was refused: ${ err.message }` };

	}

	if ( err instanceof ApiError && err.code === 'origin_not_allowed' ) {

		return { title: 'The try-on is not allowed on this site', text: err.message };

	}

	if ( err instanceof ApiError && err.code === 'unauthorized' ) {

		return { title: 'The try-on’s key is not valid', text: err.message };

	}

	if ( err instanceof ApiError && err.status === 404 ) {

		return { title: 'This garment cannot be tried on', text: `${ err.message } (a garment this shop has published on catwalk).` };

	}

	if ( err instanceof ApiError && err.code === 'rate_limited' ) {

		return { title: 'Too many try-ons just now', text: err.message };

	}

	return { title: 'The try-on cannot start', text: err && err.message ? err.message : String( err ) };

}

/** The attributes' own mistakes, found before any request: null when they look right. */
export function attributeProblem( { garment, key } ) {

	if ( ! key ) return 'The key attribute is missing: give the shop’s publishable key (pk_…).';
	if ( key.startsWith( 'cwk_' ) ) return null; // sent, so that the service refuses it and says why
	if ( ! key.startsWith( 'pk_' ) ) return 'The key attribute is not a publishable key (pk_…).';
	if ( ! garment ) return 'The garment attribute is missing: give the garment’s catwalk id.';
	return null;

}
