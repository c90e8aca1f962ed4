// Under the player: the size advice for the shopper's body (each size against its chart, as
// on catwalk's garment page), "Choose size M" for the size shown — the `catwalk:size` event
// the shop's page listens to — and "Try on size S" for the others.

import { getSizeAdvice } from '../api.js';
import { h, clear } from '../ui/dom.js';
import { adviceSummary } from '../advice.js';
import { adviceHeadline } from '../garment/sizes.js';

/**
 * The panel for the try-on shown in `size` of `garment`: `onChoose(size, summary)` when the
 * shopper picks it, `onTry(size)` for another size. Returns `{ el, chosen(size) }`.
 */
export function sizePanel( { garment, size, bodyId, ctx, onChoose, onTry } ) {

	const advice = h( 'div', { class: 'advice', 'aria-live': 'polite' } );
	const done = h( 'p', { class: 'cw-chosen', 'aria-live': 'polite' } );
	const choose = h( 'button', { type: 'button', class: 'button button--primary cw-choose' }, `Choose size ${ size }` );
	const others = h( 'div', { class: 'cw-others' } );
	let summary = null;
	choose.addEventListener( 'click', () => onChoose( size, summary ) );
	const el = h( 'section', { class: 'cw-sizes', 'aria-label': 'Sizes' },
		advice,
		h( 'div', { class: 'cw-size-actions' }, choose, others ),
		done,
	);

	const tryButtons = ( recommended ) => {

		clear( others );
		for ( const s of garment.sizes.filter( ( x ) => x !== size ) ) {

			const label = s === recommended ? `Try on size ${ s } (suggested)` : `Try on size ${ s }`;
			others.append( h( 'button', { type: 'button', class: 'button button--secondary button--small', 'data-size': s, onclick: () => onTry( s ) }, label ) );

		}

	};

	tryButtons( null );
	getSizeAdvice( garment.id, bodyId, { signal: ctx.signal } ).then( ( answer ) => {

		summary = adviceSummary( answer );
		if ( ! ctx.live || ! summary ) return;
		tryButtons( summary.recommended );
		advice.append(
			h( 'p', { class: 'advice__main' }, adviceHeadline( summary ) ),
			h( 'ul', { class: 'advice__list' }, summary.sizes.map( ( s ) => h( 'li', { class: s.fits ? 'fits' : 'tight', 'data-size': s.size }, h( 'strong', {}, s.size ), ' ', s.text, s.size === size ? ' — shown' : '' ) ) ),
		);

	} ).catch( () => { /* advice is a help: without it the sizes can still be chosen */ } );

	return {
		el,
		chosen( s ) {

			done.textContent = `Size ${ s } chosen.`;
			choose.setAttribute( 'aria-pressed', 'true' );

		},
	};

}
