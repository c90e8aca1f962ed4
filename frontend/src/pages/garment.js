// A garment (/garments/{id}): its sizes, fabrics and pattern pieces, a view of it dressed on a
// sample body, size advice for your body, and "Try it on".
//
// The panels are in garment/: the dressed view, the size picker and its advice, the order form,
// the pattern pieces; this page loads the garment, keeps the size picked and lays them out.

import { getGarment, ApiError } from '../api.js';
import { urls } from '../router.js';
import { h, clear, icon } from '../ui/dom.js';
import { errorNotice, spinner } from '../ui/feedback.js';
import { fabricName, typeName, shortName, nameSource } from '../format.js';
import { getBodyId } from '../store.js';
import { garmentMedia } from '../garment/media.js';
import { sizePicker, showSizeAdvice } from '../garment/sizes.js';
import { tryonForm } from '../garment/tryon-form.js';
import { patternPanel } from '../garment/pattern.js';

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
		show( page, g, ctx );

	}

	load();

}

/** The garment's page: the size picked is the default until advice or the shopper picks another. */
function show( page, g, ctx ) {

	document.title = `${ shortName( g.name ) } — catwalk`;
	clear( page );
	const bodyId = getBodyId();
	let size = g.default_size;
	const media = garmentMedia( g, ctx );
	const sizes = sizePicker( g, size, setSize );
	const form = tryonForm( g, ctx, { sizes, size: () => size, bodyId } );
	const pattern = patternPanel( g, size );

	function setSize( s ) {

		size = s;
		pattern.setSize( s );
		sizes.check( s );

	}

	page.append(
		h( 'div', { class: 'garment-layout' },
			media,
			h( 'div', { class: 'garment-info' }, ...details( g ), form ),
		),
		pattern.el,
	);

	if ( bodyId ) showSizeAdvice( g, bodyId, sizes.advice, setSize, ctx );

}

/** Its type, name, pattern's source, description and facts. */
function details( g ) {

	const source = nameSource( g.name );
	return [
		h( 'p', { class: 'eyebrow' }, typeName( g.type ) ),
		h( 'h1', {}, shortName( g.name ) ),
		source ? h( 'p', { class: 'muted' }, `Pattern: ${ source }` ) : null,
		g.description ? h( 'p', { class: 'lead' }, g.description ) : null,
		h( 'dl', { class: 'facts' },
			h( 'div', {}, h( 'dt', {}, 'Sizes' ), h( 'dd', {}, g.sizes.join( ' · ' ) ) ),
			h( 'div', {}, h( 'dt', {}, 'Fabric' ), h( 'dd', {}, fabricName( g.fabric ) ) ),
			h( 'div', {}, h( 'dt', {}, 'Other fabrics' ), h( 'dd', {}, `${ g.fabrics.length - 1 } to choose from` ) ),
		),
	];

}
