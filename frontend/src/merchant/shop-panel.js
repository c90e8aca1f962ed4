// "The try-on on your shop": the merchant's publishable key, the snippet for its product pages
// (docs/embed.md), and the origins those pages are on — the only ones the key works from.

import { h, clear, nextId } from '../ui/dom.js';
import { spinner, errorNotice, notice } from '../ui/feedback.js';
import { getMe, setOrigins, isUnauthorised } from './api.js';

/** The snippet a shop's product page carries, for the service at `service`. */
export function embedSnippet( service, key, garment = 'GARMENT-ID', size = 'M' ) {

	return `<script type="module" src="${ service }/embed/v1/catwalk.js"></script>\n<catwalk-tryon garment="${ garment }" size="${ size }" key="${ key }"></catwalk-tryon>`;

}

/** The origins typed one a line (or separated by spaces or commas), blanks dropped. */
export function parseOrigins( text ) {

	return String( text || '' ).split( /[\s,]+/ ).map( ( s ) => s.trim() ).filter( Boolean );

}

export function shopPanel( { signal, onUnauthorised } ) {

	const body = h( 'div', { 'aria-live': 'polite' }, spinner( 'Loading your shop’s key…' ) );
	const el = h( 'section', { class: 'panel mp-shop', 'aria-labelledby': 'mp-shop-title' },
		h( 'h2', { id: 'mp-shop-title' }, 'The try-on on your shop' ),
		h( 'p', { class: 'muted small' }, 'Put this on a product page of your shop: your shoppers try the garment on there. The publishable key only opens their try-ons, and only from the addresses below; your API key (cwk_…) never goes into a page.' ),
		body,
	);

	const failed = ( err ) => {

		if ( err && err.name === 'AbortError' ) return true;
		if ( isUnauthorised( err ) ) {

			onUnauthorised();
			return true;

		}

		return false;

	};

	getMe( { signal } ).then( ( me ) => {

		if ( ! signal.aborted ) show( body, me, signal, failed );

	} ).catch( ( err ) => {

		if ( ! failed( err ) ) clear( body ).append( errorNotice( err ) );

	} );
	return el;

}

function show( body, me, signal, failed ) {

	const areaId = nextId( 'origins' );
	const area = h( 'textarea', { id: areaId, rows: 3, spellcheck: false, class: 'mp-textarea', placeholder: 'https://shop.example' } );
	area.value = ( me.origins || [] ).join( '\n' );
	const status = h( 'div', { 'aria-live': 'polite' } );
	const save = h( 'button', { type: 'submit', class: 'button button--secondary' }, 'Save the addresses' );
	const form = h( 'form', { class: 'mp-origins-form', novalidate: true },
		h( 'div', { class: 'field' },
			h( 'label', { for: areaId }, 'Your shop’s addresses (origins), one a line' ),
			area,
			h( 'p', { class: 'field__hint' }, 'As the browser shows them, without a path: https://shop.example, https://www.shop.example.' ) ),
		h( 'div', { class: 'mp-actions' }, save ),
		status,
	);
	form.addEventListener( 'submit', async ( e ) => {

		e.preventDefault();
		save.disabled = true;
		clear( status );
		try {

			const now = await setOrigins( parseOrigins( area.value ), { signal } );
			area.value = now.origins.join( '\n' );
			status.append( notice( 'info', null, now.origins.length ? `Saved: the key works from ${ now.origins.length === 1 ? 'this address' : `these ${ now.origins.length } addresses` }.` : 'Saved: no address yet, so the key works nowhere.' ) );

		} catch ( err ) {

			if ( ! failed( err ) ) status.append( errorNotice( err ) );

		} finally {

			save.disabled = false;

		}

	} );
	clear( body ).append(
		h( 'p', {}, 'Publishable key: ', h( 'code', { class: 'mp-pk' }, me.publishable_key || '—' ) ),
		h( 'pre', { class: 'mp-snippet' }, h( 'code', {}, embedSnippet( window.location.origin, me.publishable_key || 'pk_…' ) ) ),
		form,
	);

}
