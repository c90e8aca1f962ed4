// The editor's pieces section: every piece (select one), and the selected piece's form: name
// and type, move / rotate / mirror, grain line and fold, position on the body, texture, remove.

import { h, clear } from '../ui/dom.js';
import { notice } from '../ui/feedback.js';
import { typeName } from '../format.js';
import { field, select, numberInput, num, keepFocus } from './form.js';
import { PANEL_TYPES, findPanel, editPanel, renamePanel, removePanel, grainAngle, setGrainAngle, straightEdges, setFold, panelSizes, importWarnings } from './garment-edit.js';
import { segmentLengths } from './geometry.js';
import { placementFields } from './piece-placement.js';
import { textureFields } from './piece-texture.js';
import { cm } from './units.js';

/** The pieces section of the editor in `state`: `{ el, render() }`. */
export function createPieceForm( state ) {

	const el = h( 'section', { class: 'panel mp-sec', 'aria-labelledby': 'mp-piece-title' } );
	const draw = () => {

		clear( el );
		el.append( h( 'h2', { id: 'mp-piece-title' }, 'Pieces' ) );
		if ( state.opError ) el.append( notice( 'error', null, state.opError, { label: 'OK', onClick: () => state.set( { opError: null } ) } ) );
		el.append( pieceList( state ) );
		if ( ! state.selected ) {

			el.append( h( 'p', { class: 'muted small' }, 'Select a piece (here or on the pattern) to move, rotate, mirror or describe it.' ) );
			return;

		}

		let p;
		try {

			p = findPanel( state.g, state.selected );

		} catch {

			state.selected = null;
			return;

		}

		el.append( pieceFields( state, p ) );

	};

	return { el, render: () => keepFocus( el, draw ) };

}

/** Mirror the selected piece; vertex numbers change, so a seam being picked starts again. */
function mirror( state, axis ) {

	if ( state.mutate( () => editPanel( state.g, state.selected, { mirror: axis } ) ) && state.picks.length ) state.set( { picks: [] } );

}

/** A button a piece, pressed when it is the selected one. */
function pieceList( state ) {

	const list = h( 'ul', { class: 'mp-pieces', 'aria-label': 'Pieces' } );
	for ( const p of state.g.panels ) {

		const bad = ! state.problemsStale && state.problems.some( ( x ) => x.panel === p.name );
		const told = safeList( () => importWarnings( state.g, p ) ).length;
		const absent = ! safeList( () => panelSizes( state.g, p ) ).includes( state.size );
		const classes = [ 'mp-piece', bad ? 'has-problem' : '', told ? 'has-warning' : '', absent ? 'is-absent' : '' ].filter( Boolean ).join( ' ' );
		list.append( h( 'li', {}, h( 'button', {
			type: 'button', class: classes, 'aria-pressed': String( state.selected === p.name ), 'data-key': `piece-${ p.name }`,
			title: [ told ? `The import repaired or assumed ${ told === 1 ? 'one thing' : `${ told } things` } on this piece` : '', absent ? `Not in size ${ state.size }` : '' ].filter( Boolean ).join( '; ' ) || null,
			onclick: () => state.set( { selected: state.selected === p.name ? null : p.name } ),
		}, told ? h( 'span', { class: 'mp-piece__mark', 'aria-label': 'with import warnings' }, '! ' ) : null, p.name,
		h( 'span', { class: 'muted small' }, ` ${ typeName( p.type || 'other' ) }${ p.copy_of != null ? `, copy of ${ p.copy_of }` : '' }${ absent ? `, not in ${ state.size }` : '' }` ) ) ) );

	}

	return list;

}

/** The form of the piece `p` (the selected one). */
function pieceFields( state, p ) {

	const form = h( 'div', { class: 'mp-piece-form' } );
	form.append( ...importNotes( state, p ) );
	form.append( nameAndType( state, p ) );
	if ( p.copy_of != null ) {

		form.append( h( 'p', { class: 'muted small' }, `A ${ p.mirror ? 'mirrored ' : '' }copy of ${ p.copy_of }: its shape follows ${ p.copy_of } (move, rotate or mirror that one).` ) );

	} else {

		form.append( ...transformFields( state ), ...grainAndFold( state, p ) );

	}

	form.append( placementFields( state, p ) );
	form.append( textureFields( state, p ) );
	form.append( h( 'div', { class: 'mp-actions' }, h( 'button', { type: 'button', class: 'button button--danger button--small', 'data-key': 'p-remove', onclick: () => remove( state, p.name ) }, 'Remove this piece' ) ) );
	return form;

}

/** What the import repaired or assumed on the piece, and the sizes it is in when not all. */
function importNotes( state, p ) {

	const out = [];
	const sizes = safeList( () => panelSizes( state.g, p ) );
	if ( sizes.length && sizes.length < state.g.sizes.length ) {

		out.push( h( 'p', { class: 'mp-piece-sizes small', 'data-key': 'p-sizes' }, `Cut in size${ sizes.length > 1 ? 's' : '' } ${ sizes.join( ', ' ) } only (not in ${ state.g.sizes.filter( ( s ) => ! sizes.includes( s ) ).join( ', ' ) }).` ) );

	}

	const told = safeList( () => importWarnings( state.g, p ) );
	if ( told.length ) {

		out.push( h( 'div', { class: 'notice notice--warn mp-piece-warnings', role: 'status', 'data-key': 'p-import-warnings' }, h( 'div', { class: 'notice__body' },
			h( 'p', { class: 'notice__title' }, p.copy_of != null ? `The import of ${ p.copy_of } says` : 'The import says' ),
			h( 'ul', {}, told.map( ( w ) => h( 'li', {}, w.message ) ) ) ) ) );

	}

	return out;

}

/** `fn()`'s list, or an empty one when it throws (a garment being edited may be half-made). */
function safeList( fn ) {

	try {

		return fn();

	} catch {

		return [];

	}

}

function nameAndType( state, p ) {

	const name = h( 'input', { type: 'text', value: p.name, 'data-key': 'p-name', maxlength: 200 } );
	name.addEventListener( 'change', () => {

		const from = p.name, to = name.value.trim();
		if ( state.mutate( () => renamePanel( state.g, from, to ) ) ) {

			const textures = state.textures;
			if ( textures.has( from ) ) {

				textures.set( to, textures.get( from ) );
				textures.delete( from );

			}

			state.set( { picks: state.picks.map( ( k ) => ( k.panel === from ? { ...k, panel: to } : k ) ), selected: to } );

		}

	} );
	const type = select( PANEL_TYPES.map( ( t ) => [ t, typeName( t ) ] ), p.type || 'other', { 'data-key': 'p-type' } );
	type.addEventListener( 'change', () => state.mutate( () => {

		findPanel( state.g, state.selected ).type = type.value;

	} ) );
	return h( 'div', { class: 'field-row--2' }, field( 'Piece name', name ), field( 'Piece type', type ) );

}

/** Move (cm), rotate (degrees) and mirror the selected piece. */
function transformFields( state ) {

	const edit = ( how ) => state.mutate( () => editPanel( state.g, state.selected, how ) );
	const dx = numberInput( 0, { 'data-key': 'p-dx' } ), dy = numberInput( 0, { 'data-key': 'p-dy' } );
	const moveBtn = h( 'button', { type: 'button', class: 'button button--secondary button--small', 'data-key': 'p-move' }, 'Move' );
	moveBtn.addEventListener( 'click', () => {

		const x = num( dx.value ) || 0, y = num( dy.value ) || 0;
		if ( x || y ) edit( { move: [ x / 100, y / 100 ] } );

	} );
	const deg = numberInput( 90, { 'data-key': 'p-deg' } );
	const rotBtn = h( 'button', { type: 'button', class: 'button button--secondary button--small', 'data-key': 'p-rotate' }, 'Rotate' );
	rotBtn.addEventListener( 'click', () => {

		const d = num( deg.value );
		if ( d ) edit( { rotate: d } );

	} );
	return [
		h( 'fieldset', { class: 'field mp-ops' }, h( 'legend', {}, 'Move (cm)' ),
			h( 'div', { class: 'mp-inline' }, field( 'Right by', dx ), field( 'Up by', dy ), moveBtn ) ),
		h( 'fieldset', { class: 'field mp-ops' }, h( 'legend', {}, 'Rotate and mirror' ),
			h( 'div', { class: 'mp-inline' }, field( 'Degrees, counter-clockwise', deg ), rotBtn ),
			h( 'div', { class: 'mp-inline' },
				h( 'button', { type: 'button', class: 'button button--secondary button--small', 'data-key': 'p-mirror-x', onclick: () => mirror( state, 'x' ) }, 'Mirror left ↔ right' ),
				h( 'button', { type: 'button', class: 'button button--secondary button--small', 'data-key': 'p-mirror-y', onclick: () => mirror( state, 'y' ) }, 'Mirror up ↔ down' ),
			),
			h( 'p', { class: 'field__hint' }, 'In every size, about the centre of the piece; seams on it are renumbered so the garment sews the same way.' ) ),
	];

}

/** The grain line's angle and the edge the piece is cut on the fold along (in the size shown). */
function grainAndFold( state, p ) {

	const size = state.size;
	const shape = p.shapes[ size ] || Object.values( p.shapes )[ 0 ];
	const grain = numberInput( Math.round( grainAngle( shape ) * 10 ) / 10, { 'data-key': 'p-grain' } );
	const grainBtn = h( 'button', { type: 'button', class: 'button button--secondary button--small', 'data-key': 'p-grain-set' }, 'Set grain line' );
	grainBtn.addEventListener( 'click', () => {

		const d = num( grain.value );
		if ( Number.isFinite( d ) ) state.mutate( () => setGrainAngle( findPanel( state.g, state.selected ), d ) );

	} );
	const lengths = segmentLengths( shape.outline );
	const fold = select( [ [ '', 'Not cut on the fold' ], ...straightEdges( p, size ).map( ( k ) => [ String( k ), `Edge ${ k } (vertices ${ k }→${ ( k + 1 ) % shape.outline.length }, ${ cm( lengths[ k ] ) })` ] ) ], p.fold ?? '', { 'data-key': 'p-fold' } );
	fold.addEventListener( 'change', () => state.mutate( () => setFold( findPanel( state.g, state.selected ), fold.value === '' ? null : Number( fold.value ) ) ) );
	return [
		h( 'fieldset', { class: 'field mp-ops' }, h( 'legend', {}, 'Grain line' ),
			h( 'div', { class: 'mp-inline' }, field( 'Degrees from vertical', grain, '0: the warp runs up the piece; positive turns it counter-clockwise.' ), grainBtn ) ),
		field( 'Cut on the fold along', fold, 'The piece is half of the cut one, mirrored across this straight edge.' ),
	];

}

/** Remove the piece `gone` (after asking), its copies, the seams on it and their textures. */
function remove( state, gone ) {

	const g = state.g;
	if ( ! window.confirm( `Remove the piece ${ gone }${ g.panels.some( ( q ) => q.copy_of === gone ) ? ' and its copies' : '' }, and the seams on it?` ) ) return;
	if ( state.mutate( () => {

		for ( const n of removePanel( state.g, gone ) ) state.textures.delete( n );

	} ) ) {

		state.selected = null;
		state.picks = [];
		state.refresh();

	}

}
