// The catalogue (/): every garment as a card, filtered by type.

import { listGarments, thumbnailUrl } from '../api.js';
import { urls } from '../router.js';
import { h, clear } from '../ui/dom.js';
import { errorNotice, spinner } from '../ui/feedback.js';
import { fabricName, typeName, shortName, nameSource } from '../format.js';
import { getBodyId } from '../store.js';

export function render( root, route, ctx ) {

	document.title = 'Catalogue — catwalk';
	const list = h( 'div', { class: 'catalogue' } );
	root.append(
		h( 'section', { class: 'hero' },
			h( 'h1', {}, 'See it move on you' ),
			h( 'p', { class: 'lead' }, 'Pick a garment, give us your measurements or a body scan, and watch yourself walk in it — the fabric simulated stitch by stitch.' ),
			getBodyId() ? null : h( 'p', {}, h( 'a', { class: 'button button--secondary', href: urls.body(), 'data-link': '' }, 'Set up your body first' ) ),
		),
		list,
	);

	async function load() {

		clear( list ).append( spinner( 'Loading the catalogue…' ) );
		let garments;
		try {

			garments = await listGarments( { signal: ctx.signal } );

		} catch ( err ) {

			if ( ! ctx.live ) return;
			clear( list ).append( errorNotice( err, load ) );
			return;

		}

		if ( ! ctx.live ) return;
		show( garments );

	}

	function show( garments ) {

		clear( list );
		const types = [ ...new Set( garments.map( ( g ) => g.type ) ) ].sort();
		const active = route.type && types.includes( route.type ) ? route.type : null;
		const grid = h( 'ul', { class: 'cards', 'aria-label': 'Garments' } );
		const count = h( 'p', { class: 'muted count', 'aria-live': 'polite' } );

		const filters = h( 'div', { class: 'chips', role: 'group', 'aria-label': 'Filter by type' } );
		const chip = ( type, label, n ) => h( 'button', {
			type: 'button', class: 'chip', 'aria-pressed': String( type === active ), 'data-type': type || '',
			onclick: () => {

				// filter in place: the URL says which, the list is not fetched again
				history.replaceState( null, '', urls.catalogue( type ) );
				route = { ...route, type };
				show( garments );
				const again = list.querySelector( `.chip[data-type="${ type || '' }"]` );
				if ( again ) again.focus();

			},
		}, label, h( 'span', { class: 'chip__count' }, String( n ) ) );
		filters.append( chip( null, 'All', garments.length ) );
		for ( const t of types ) filters.append( chip( t, typeName( t ), garments.filter( ( g ) => g.type === t ).length ) );

		const shown = active ? garments.filter( ( g ) => g.type === active ) : garments;
		count.textContent = shown.length === 1 ? '1 garment' : `${ shown.length } garments`;
		for ( const g of shown ) grid.append( card( g ) );
		if ( ! garments.length ) {

			list.append( h( 'p', { class: 'empty' }, 'The catalogue is empty for now.' ) );
			return;

		}

		list.append( h( 'div', { class: 'catalogue__bar' }, filters, count ), grid );

	}

	load();

}

function card( g ) {

	const source = nameSource( g.name );
	return h( 'li', { class: 'card' },
		h( 'a', { class: 'card__link', href: urls.garment( g.id ), 'data-link': '', 'aria-label': `${ shortName( g.name ) }, ${ typeName( g.type ) }` },
			h( 'div', { class: 'card__media' },
				h( 'img', { class: 'card__img', src: thumbnailUrl( g.id ), alt: `${ shortName( g.name ) } on a sample body`, width: 240, height: 360, loading: 'lazy', decoding: 'async' } ),
			),
			h( 'div', { class: 'card__body' },
				h( 'p', { class: 'card__type' }, typeName( g.type ) ),
				h( 'h2', { class: 'card__title' }, shortName( g.name ) ),
				source ? h( 'p', { class: 'card__source muted' }, source ) : null,
				h( 'dl', { class: 'card__facts' },
					h( 'div', {}, h( 'dt', {}, 'Sizes' ), h( 'dd', {}, g.sizes.join( ' · ' ) ) ),
					h( 'div', {}, h( 'dt', {}, 'Fabric' ), h( 'dd', {}, fabricName( g.fabric ) ) ),
				),
			),
		),
	);

}
