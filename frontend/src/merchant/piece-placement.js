// A piece's position on the body (its placement hint): the body part, the side it faces, the
// landmark it is anchored at, the point of the piece at the anchor, its distance, wrapping.

import { h, nextId } from '../ui/dom.js';
import { field, select, numberInput, num } from './form.js';
import { BODY_PARTS, SIDES, LANDMARKS, findPanel, vertexCount } from './garment-edit.js';

/** The "Position on the body" fieldset of the piece `p` (the selected one). */
export function placementFields( state, p ) {

	const pl = p.placement || null;
	const part = select( [ [ '', 'No hint' ], ...BODY_PARTS.map( ( x ) => [ x, x.replace( /_/g, ' ' ) ] ) ], pl ? pl.part || 'torso' : '', { 'data-key': 'pl-part' } );
	part.addEventListener( 'change', () => {

		if ( part.value === '' ) state.mutate( () => {

			delete findPanel( state.g, state.selected ).placement;

		} );
		else setPlacement( state, ( x ) => {

			x.part = part.value;

		} );

	} );
	const fs = h( 'fieldset', { class: 'field mp-ops' }, h( 'legend', {}, 'Position on the body' ), field( 'Body part', part ) );
	if ( ! pl ) {

		fs.append( h( 'p', { class: 'field__hint' }, 'Without a hint the piece is placed by its type; the checker warns.' ) );
		return fs;

	}

	fs.append( ...hintFields( state, p, pl ) );
	return fs;

}

/** Change the selected piece's placement with `fn(placement)` (a torso front one when it had none). */
function setPlacement( state, fn ) {

	return state.mutate( () => {

		const q = findPanel( state.g, state.selected );
		q.placement = q.placement || { part: 'torso', side: 'front' };
		fn( q.placement );

	} );

}

/** Side, anchor landmark, the point at the anchor, distance, wrap: of the placement `pl` of `p`. */
function hintFields( state, p, pl ) {

	const set = ( fn ) => setPlacement( state, fn );
	const side = select( SIDES.map( ( x ) => [ x, x ] ), pl.side || 'front', { 'data-key': 'pl-side' } );
	side.addEventListener( 'change', () => set( ( x ) => {

		x.side = side.value;

	} ) );
	const listId = nextId( 'landmarks' );
	const anchor = h( 'input', { type: 'text', value: pl.anchor || '', list: listId, 'data-key': 'pl-anchor', placeholder: 'e.g. waist' } );
	anchor.setAttribute( 'list', listId );
	anchor.addEventListener( 'change', () => set( ( x ) => {

		if ( anchor.value.trim() ) x.anchor = anchor.value.trim();
		else delete x.anchor;

	} ) );
	const n = vertexCount( state.g, p );
	const av = select( [ [ '', 'Top centre (default)' ], ...Array.from( { length: n }, ( _, i ) => [ String( i ), `Vertex ${ i }` ] ) ], pl.anchor_vertex ?? '', { 'data-key': 'pl-av' } );
	av.addEventListener( 'change', () => set( ( x ) => {

		if ( av.value === '' ) delete x.anchor_vertex;
		else x.anchor_vertex = Number( av.value );

	} ) );
	const distance = numberInput( pl.distance != null ? Math.round( pl.distance * 1000 ) / 10 : 3, { 'data-key': 'pl-dist', min: 0 } );
	distance.addEventListener( 'change', () => {

		const d = num( distance.value );
		if ( Number.isFinite( d ) && d >= 0 ) set( ( x ) => {

			x.distance = d / 100;

		} );

	} );
	const wrap = h( 'input', { type: 'checkbox', checked: pl.wrap !== false, 'data-key': 'pl-wrap', id: nextId( 'wrap' ) } );
	wrap.addEventListener( 'change', () => set( ( x ) => {

		x.wrap = wrap.checked;

	} ) );
	return [
		h( 'div', { class: 'field-row--2' }, field( 'Side', side ), field( 'Anchor landmark', anchor ) ),
		h( 'datalist', { id: listId }, LANDMARKS.map( ( l ) => h( 'option', { value: l } ) ) ),
		h( 'div', { class: 'field-row--2' }, field( 'Point at the anchor', av ), field( 'Distance from the body (cm)', distance ) ),
		h( 'div', { class: 'mp-check' }, wrap, h( 'label', { for: wrap.id }, 'Wrap round the body part' ) ),
	];

}
