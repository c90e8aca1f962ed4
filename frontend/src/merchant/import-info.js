// What a DXF import said, above the editor: its warnings, and the pieces it read (name, size,
// quantity, area, perimeter).

import { h } from '../ui/dom.js';
import { cm } from './units.js';

/** The import's `warnings` and `pieces` (either may be empty: then nothing of it is shown). */
export function importInfo( warnings = [], pieces = null ) {

	const el = h( 'div', { class: 'mp-import' } );
	if ( warnings.length ) {

		el.append( h( 'div', { class: 'notice notice--warn mp-import__warnings', role: 'status' }, h( 'div', { class: 'notice__body' },
			h( 'p', { class: 'notice__title' }, 'The import says' ),
			h( 'ul', {}, warnings.map( ( w ) => h( 'li', {}, typeof w === 'string' ? w : w.message || JSON.stringify( w ) ) ) ) ) ) );

	}

	if ( pieces && pieces.length ) el.append( piecesTable( pieces ) );
	return el;

}

function piecesTable( pieces ) {

	return h( 'details', { class: 'panel mp-import__pieces' },
		h( 'summary', {}, `Imported ${ pieces.length === 1 ? 'one piece' : `${ pieces.length } pieces` } (${ [ ...new Set( pieces.map( ( p ) => p.size ) ) ].join( ', ' ) })` ),
		h( 'table', { class: 'table' },
			h( 'thead', {}, h( 'tr', {}, [ 'Piece', 'Size', 'Quantity', 'Area', 'Perimeter' ].map( ( t ) => h( 'th', { scope: 'col' }, t ) ) ) ),
			h( 'tbody', {}, pieces.map( ( p ) => h( 'tr', {},
				h( 'th', { scope: 'row' }, p.name ), h( 'td', {}, p.size ), h( 'td', {}, String( p.quantity ?? 1 ) ),
				h( 'td', {}, p.area_m2 != null ? `${ ( p.area_m2 * 1e4 ).toFixed( 0 ) } cm²` : '—' ),
				h( 'td', {}, p.perimeter_m != null ? cm( p.perimeter_m ) : '—' ) ) ) ),
		) );

}
