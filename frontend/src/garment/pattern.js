// The garment's pattern pieces: the cutting pattern of the size picked, laid flat
// (GET /api/garments/{id}/pattern.png?size=…), how many pieces and seams it has, and their names.

import { patternUrl } from '../api.js';
import { h } from '../ui/dom.js';
import { shortName } from '../format.js';

/** The section, showing `size`: `{ el, setSize(s) }`. */
export function patternPanel( g, size ) {

	const img = h( 'img', { class: 'pattern__img', src: patternUrl( g.id, size ), alt: patternAlt( g, size ), width: 480, height: 360 } );
	const caption = h( 'figcaption', { class: 'muted' } );
	const setCaption = ( s ) => {

		caption.textContent = `Size ${ s }: ${ g.panels.length } pieces, ${ g.seams } seams, laid flat.`;

	};

	setCaption( size );
	const el = h( 'section', { class: 'pattern', 'aria-labelledby': 'pattern-title' },
		h( 'h2', { id: 'pattern-title' }, 'Pattern pieces' ),
		h( 'figure', { class: 'pattern__figure' }, img, caption ),
		h( 'ul', { class: 'pieces' }, g.panels.map( ( p ) => h( 'li', {}, pieceName( p.name ) ) ) ),
	);
	const setSize = ( s ) => {

		img.src = patternUrl( g.id, s );
		img.alt = patternAlt( g, s );
		setCaption( s );

	};

	return { el, setSize };

}

const patternAlt = ( g, size ) => `Cutting pattern of ${ shortName( g.name ) }, size ${ size }`;

/** A piece's name as words: "back_right" → "Back right". */
export function pieceName( name ) {

	const s = String( name ).replace( /[_-]+/g, ' ' );
	return s.charAt( 0 ).toUpperCase() + s.slice( 1 );

}
