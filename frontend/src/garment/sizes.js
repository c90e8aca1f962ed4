// The garment's sizes: a radio button a size, and under them the size advice for your body
// (GET /api/garments/{id}/sizes?body_id=…): the advised size is picked, every size's fit listed.

import { getSizeAdvice } from '../api.js';
import { h, nextId } from '../ui/dom.js';
import { adviceSummary } from '../advice.js';

/**
 * The "Size" fieldset, `size` picked: `{ el, advice, error, check(s) }`; `onPick(s)` when a size
 * is picked, `check(s)` shows `s` as picked; `advice` is where the size advice goes, `error`
 * the field's error.
 */
export function sizePicker( g, size, onPick ) {

	const sizeName = nextId( 'size' );
	const el = h( 'fieldset', { class: 'field sizes' }, h( 'legend', {}, 'Size' ) );
	const row = h( 'div', { class: 'size-options' } );
	const error = h( 'p', { class: 'field__error', 'aria-live': 'polite' } );
	const advice = h( 'div', { class: 'advice', 'aria-live': 'polite' } );
	for ( const s of g.sizes ) {

		const id = nextId( 'size' );
		row.append( h( 'span', { class: 'size-option' },
			h( 'input', { type: 'radio', name: sizeName, id, value: s, checked: s === size, onchange: () => onPick( s ) } ),
			h( 'label', { for: id }, s ),
		) );

	}

	el.append( row, advice, error );
	const check = ( s ) => {

		for ( const input of row.querySelectorAll( 'input' ) ) input.checked = input.value === s;

	};

	return { el, advice, error, check };

}

/** The size advice for the body into `el`; the advised size picked with `pick(s)`. Nothing when there is none. */
export async function showSizeAdvice( g, bodyId, el, pick, ctx ) {

	let advice;
	try {

		advice = await getSizeAdvice( g.id, bodyId, { signal: ctx.signal } );

	} catch {

		return; // advice is a help, not a must: say nothing

	}

	if ( ! ctx.live || ! advice ) return;
	const summary = adviceSummary( advice );
	if ( ! summary ) return;
	if ( summary.recommended && g.sizes.includes( summary.recommended ) ) pick( summary.recommended );
	el.append(
		h( 'p', { class: 'advice__main' }, adviceHeadline( summary ) ),
		h( 'ul', { class: 'advice__list' }, summary.sizes.map( ( s ) => h( 'li', { class: s.fits ? 'fits' : 'tight' }, h( 'strong', {}, s.size ), ' ', s.text ) ) ),
	);

}

/** The advice in one sentence, from an adviceSummary. */
export function adviceHeadline( s ) {

	if ( ! s.recommended ) return 'We have no size advice for this garment.';
	if ( ! s.recommendedFits ) return `No size has room for all your measurements; ${ s.recommended } is the closest.`;
	return `We suggest size ${ s.recommended } for your body.`;

}
