// "Your sizes" on the body page: for every garment in the catalogue, the size advised for your
// body and how it fits (GET /api/garments/{id}/sizes?body_id=…). Hidden when the API has no
// size advice or none of the garments has any.

import { listGarments, getSizeAdvice, apiPaths, hasSizesRoute } from '../api.js';
import { urls } from '../router.js';
import { h } from '../ui/dom.js';
import { shortName } from '../format.js';
import { adviceSummary } from '../advice.js';

/** The fit of the advised size in words, from an adviceSummary. */
export function advisedFit( s ) {

	const rec = s.sizes.find( ( x ) => x.size === s.recommended );
	return rec ? ( s.recommendedFits ? rec.text : `closest: ${ rec.text }` ) : 'no size advice';

}

/** The section, hidden: `{ el, load() }`; `load()` asks for the advice and shows the section when there is some. */
export function createSizesPanel( body, ctx ) {

	const list = h( 'div', { class: 'advice-all__list' } );
	const el = h( 'section', { class: 'advice-all', 'aria-labelledby': 'advice-title', hidden: true },
		h( 'h2', { id: 'advice-title' }, 'Your sizes' ),
		list,
	);

	async function load() {

		try {

			if ( ! hasSizesRoute( await apiPaths() ) ) return;
			const garments = await listGarments( { signal: ctx.signal } );
			const rows = await Promise.all( garments.map( async ( g ) => [ g, adviceSummary( await getSizeAdvice( g.id, body.id, { signal: ctx.signal } ).catch( () => null ) ) ] ) );
			if ( ! ctx.live ) return;
			const advised = rows.filter( ( [ , s ] ) => s );
			if ( ! advised.length ) return;
			list.append( sizesTable( advised ) );
			el.hidden = false;

		} catch {

			// advice is optional: say nothing when it cannot be had

		}

	}

	return { el, load };

}

/** A row a garment: its name (a link to it), the advised size, the fit. */
function sizesTable( rows ) {

	return h( 'table', { class: 'table' },
		h( 'thead', {}, h( 'tr', {}, h( 'th', { scope: 'col' }, 'Garment' ), h( 'th', { scope: 'col' }, 'Your size' ), h( 'th', { scope: 'col' }, 'Fit' ) ) ),
		h( 'tbody', {}, rows.map( ( [ g, s ] ) => h( 'tr', {},
			h( 'th', { scope: 'row' }, h( 'a', { href: urls.garment( g.id ), 'data-link': '' }, shortName( g.name ) ) ),
			h( 'td', { class: 'size-cell' }, s.recommended || '—' ),
			h( 'td', {}, advisedFit( s ) ),
		) ) ),
	);

}
