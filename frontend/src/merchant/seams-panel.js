// The editor's seams section: the seam being sewn (its two runs, picked on the pattern or by
// number, their lengths and difference, name, ease, direction) and every seam of the garment
// (lengths in the size shown, ease, show, flip, delete).

import { h, clear } from '../ui/dom.js';
import { field, select, numberInput, num, keepFocus } from './form.js';
import { findPanel, sideAsShown, shownReverse, seamLengths, runCrossesFold, vertexCount, sourceVertexMap, panelSizes } from './garment-edit.js';
import { draftSides, otherWay, addSeam, pickRun } from './seam-picks.js';
import { cm, pct } from './units.js';

/** The seams section of the editor in `state`: `{ el, render() }`. */
export function createSeamsPanel( state ) {

	const el = h( 'section', { class: 'panel mp-sec', 'aria-labelledby': 'mp-seams-title' } );
	const draw = () => {

		clear( el );
		el.append( h( 'h2', { id: 'mp-seams-title' }, 'Seams' ), draftBox( state ) );
		if ( ! state.g.seams.length ) {

			el.append( h( 'p', { class: 'muted small' }, 'No seams yet: every piece must be sewn to the rest.' ) );
			return;

		}

		el.append( seamTable( state ) );

	};

	return { el, render: () => keepFocus( el, draw ) };

}

/** The seam being sewn (in seam mode; else how to start one). */
function draftBox( state ) {

	const box = h( 'div', { class: 'mp-draft' } );
	if ( state.mode !== 'seam' ) {

		box.append( h( 'p', { class: 'muted small' }, 'To sew a seam, choose “Sew seams” above the pattern and click the vertices of the two runs.' ),
			h( 'button', { type: 'button', class: 'button button--secondary button--small', 'data-key': 'to-seam', onclick: () => state.set( { mode: 'seam' } ) }, 'Sew seams' ) );
		return box;

	}

	const { a, b } = draftSides( state );
	box.append( draftSide( state, 'First side', a, 0 ), draftSide( state, 'Second side', b, 2 ), byNumber( state ) );
	if ( a && b ) {

		const size = state.size;
		const m = safe( () => seamLengths( state.g, { a, b, ease: state.draft.ease }, size ) );
		if ( m ) box.append( h( 'p', { class: `mp-diff ${ m.ok ? 'is-good' : 'is-bad' }`, 'aria-live': 'polite' }, `Size ${ size }: ${ cm( m.a ) } and ${ cm( m.b ) }, difference ${ pct( m.difference ) } (limit ${ pct( m.limit ) })` ) );

	}

	box.append( ...draftControls( state, a && b ) );
	return box;

}

/** A side of the seam being sewn: its run and length, or what to click next. */
function draftSide( state, label, side, i ) {

	const { g, picks } = state;
	let text;
	if ( side ) {

		const len = safe( () => seamLengths( g, { a: side, b: side }, state.size ).a );
		text = `${ sideText( g, side ) }${ len != null ? `: ${ cm( len ) }` : '' }`;

	} else if ( picks.length === i + 1 ) text = `${ picks[ i ].panel }, from vertex ${ picks[ i ].vertex } — now click the last vertex`;
	else text = picks.length >= i ? 'click its first vertex' : '—';
	return h( 'div', { class: 'mp-draft__side' }, h( 'span', { class: 'mp-draft__label' }, label ), h( 'span', { 'data-side': label }, text ),
		side ? h( 'button', { type: 'button', class: 'button button--secondary button--small', 'data-key': `other-${ i }`, onclick: () => otherWay( state, i ) }, 'Other way round' ) : null,
		side && runCrossesFold( g, side ) ? h( 'span', { class: 'field__error' }, 'This run crosses the fold edge.' ) : null,
	);

}

/** The seam being sewn: name, ease, flip direction; add it, or clear the picks. */
function draftControls( state, complete ) {

	const draft = state.draft;
	const name = h( 'input', { type: 'text', value: draft.name, 'data-key': 'd-name', placeholder: 'e.g. side left' } );
	name.addEventListener( 'input', () => {

		state.draft.name = name.value;

	} );
	const ease = numberInput( Math.round( draft.ease * 1000 ) / 10, { min: 0, 'data-key': 'd-ease' } );
	ease.addEventListener( 'change', () => {

		state.draft.ease = Math.max( 0, num( ease.value ) || 0 ) / 100;
		state.refresh( { garment: false } );

	} );
	const flip = h( 'button', { type: 'button', class: 'seg seg--toggle', 'aria-pressed': String( draft.reverse ), 'data-key': 'd-flip', onclick: () => {

		state.draft.reverse = ! state.draft.reverse;
		state.refresh( { garment: false } );

	} }, 'Flip direction' );
	return [
		h( 'div', { class: 'field-row--2' }, field( 'Seam name', name ), field( 'Ease (%)', ease, 'Length difference eased or gathered in.' ) ),
		h( 'div', { class: 'mp-actions' },
			h( 'div', { class: 'segs' }, flip ),
			h( 'button', { type: 'button', class: 'button button--primary button--small', disabled: ! complete, 'data-key': 'd-add', onclick: () => addSeam( state ) }, 'Add seam' ),
			h( 'button', { type: 'button', class: 'button button--secondary button--small', disabled: ! state.picks.length, 'data-key': 'd-clear', onclick: () => state.set( { picks: [] } ) }, 'Clear' ),
		),
	];

}

/** Picking by numbers (for the keyboard): a piece, its first and last vertex, which half. */
function byNumber( state ) {

	const wrap = h( 'details', { class: 'mp-bynumber' }, h( 'summary', {}, 'Or choose the vertices by number' ) );
	wrap.append( byNumberRow( state, 'first side', 0 ) );
	if ( state.picks.length >= 2 ) wrap.append( byNumberRow( state, 'second side', 2 ) );
	wrap.open = state.byNumberOpen;
	wrap.addEventListener( 'toggle', () => {

		state.byNumberOpen = wrap.open;

	} );
	return wrap;

}

/** One side by numbers (`i`: 0 the first, 2 the second). */
function byNumberRow( state, label, i ) {

	const { g, picks } = state;
	const cur = picks[ i ] && picks[ i + 1 ] ? picks[ i ] : null;
	const panelSel = select( g.panels.map( ( p ) => [ p.name, p.name ] ), cur ? cur.panel : ( state.selected || g.panels[ 0 ].name ), { 'data-key': `bn-panel-${ i }` } );
	const n = () => vertexCount( state.g, panelSel.value );
	const vsel = ( key, value ) => select( Array.from( { length: n() }, ( _, v ) => [ String( v ), String( v ) ] ), value, { 'data-key': key } );
	let from = vsel( `bn-from-${ i }`, cur ? cur.vertex : 0 );
	let to = vsel( `bn-to-${ i }`, cur ? picks[ i + 1 ].vertex : 1 );
	const folded = () => findPanel( state.g, sourceVertexMap( state.g, panelSel.value )[ 0 ] ).fold != null;
	const half = select( [ [ '', 'as drawn' ], [ 'ghost', 'mirrored half' ] ], cur && cur.ghost ? 'ghost' : '', { 'data-key': `bn-half-${ i }` } );
	const halfField = field( 'Half', half );
	halfField.hidden = ! folded();
	const fromField = field( 'First vertex', from ), toField = field( 'Last vertex', to );
	panelSel.addEventListener( 'change', () => {

		const f2 = vsel( `bn-from-${ i }`, 0 ), t2 = vsel( `bn-to-${ i }`, 1 );
		f2.id = from.id;
		t2.id = to.id;
		from.replaceWith( f2 );
		to.replaceWith( t2 );
		from = f2;
		to = t2;
		halfField.hidden = ! folded();

	} );
	const set = h( 'button', { type: 'button', class: 'button button--secondary button--small', 'data-key': `bn-set-${ i }`, onclick: () => {

		pickRun( state, i, panelSel.value, Number( from.value ), Number( to.value ), folded() && half.value === 'ghost' );

	} }, `Set the ${ label }` );
	return h( 'fieldset', { class: 'field mp-ops' }, h( 'legend', {}, label.charAt( 0 ).toUpperCase() + label.slice( 1 ) ),
		h( 'div', { class: 'mp-inline' }, field( 'Piece', panelSel ), fromField, toField, halfField, set ) );

}

/** Every seam of the garment, lengths in the size shown. */
function seamTable( state ) {

	const size = state.size;
	return h( 'div', { class: 'mp-table-wrap' }, h( 'table', { class: 'table mp-seams' },
		h( 'caption', { class: 'visually-hidden' }, `Seams, lengths in size ${ size }` ),
		h( 'thead', {}, h( 'tr', {}, h( 'th', { scope: 'col' }, 'Seam' ), h( 'th', { scope: 'col' }, 'Runs' ), h( 'th', { scope: 'col' }, `Lengths (${ size })` ), h( 'th', { scope: 'col' }, 'Ease %' ), h( 'th', { scope: 'col' }, h( 'span', { class: 'visually-hidden' }, 'Actions' ) ) ) ),
		h( 'tbody', {}, state.g.seams.map( ( s, i ) => seamRow( state, s, i ) ) ),
	) );

}

/** Why a seam has no lengths in `size`: a piece of it not in that size (it is not sewn there), or '—'. */
function notSewn( g, s, size ) {

	const absent = [ s.a.panel, s.b.panel ].filter( ( p ) => ! safe( () => panelSizes( g, p ).includes( size ) ) );
	return absent.length ? `not sewn in ${ size } (no ${ absent.join( ', ' ) })` : '—';

}

/** The seam `s` (number `i`): name, runs, lengths, ease; show, flip, delete. */
function seamRow( state, s, i ) {

	const { g, highlight } = state;
	const m = safe( () => seamLengths( g, s, state.size ) );
	const bad = ! state.problemsStale && state.problems.some( ( p ) => p.seam === i );
	const easeIn = numberInput( Math.round( ( Number( s.ease ) || 0 ) * 1000 ) / 10, { min: 0, class: 'mp-num', 'aria-label': `Ease of seam ${ i } (%)`, 'data-key': `s-ease-${ i }` } );
	easeIn.addEventListener( 'change', () => state.mutate( () => {

		const e = Math.max( 0, num( easeIn.value ) || 0 ) / 100;
		if ( e ) state.g.seams[ i ].ease = Math.round( e * 1e4 ) / 1e4;
		else delete state.g.seams[ i ].ease;

	} ) );
	const button = ( cls, attrs, onclick, text ) => h( 'button', { type: 'button', class: `button ${ cls } button--small`, ...attrs, onclick }, text );
	return h( 'tr', { class: [ highlight === i && 'is-highlighted', bad && 'has-problem' ].filter( Boolean ).join( ' ' ) || null, 'data-seam': i },
		h( 'th', { scope: 'row' }, s.name || `Seam ${ i }` ),
		h( 'td', { class: 'mp-runs' }, sideText( g, s.a, true ), h( 'br' ), sideText( g, s.b, true ) ),
		h( 'td', { class: m && ! m.ok ? 'is-bad' : null }, m ? `${ cm( m.a ) } / ${ cm( m.b ) }, ${ pct( m.difference ) }` : notSewn( g, s, state.size ) ),
		h( 'td', {}, easeIn ),
		h( 'td', { class: 'mp-row-actions' },
			button( 'button--secondary', { 'aria-pressed': String( highlight === i ), 'aria-label': `Show seam ${ s.name || i }`, 'data-key': `s-show-${ i }` },
				() => state.set( { highlight: state.highlight === i ? null : i } ), 'Show' ),
			button( 'button--secondary', { 'aria-pressed': String( shownReverse( g, s ) ), 'aria-label': `Flip direction of seam ${ s.name || i }`, 'data-key': `s-flip-${ i }` }, () => state.mutate( () => {

				state.g.seams[ i ].reverse = ! state.g.seams[ i ].reverse;
				state.highlight = i;

			} ), 'Flip' ),
			button( 'button--danger', { 'aria-label': `Delete seam ${ s.name || i }`, 'data-key': `s-del-${ i }` }, () => state.mutate( () => {

				state.g.seams.splice( i, 1 );
				state.highlight = null;
				state.problems = state.problems.filter( ( p ) => p.seam == null );

			} ), 'Delete' ),
		),
	);

}

/** A side as the pattern shows it: "FRONT, vertices 1 → 2" (short: "FRONT 1→2"). */
function sideText( g, side, short = false ) {

	const s = sideAsShown( g, side );
	if ( short ) return `${ side.panel }${ s.ghost ? ' (mirrored half)' : '' } ${ s.first }→${ s.last }`;
	return `${ side.panel }${ s.ghost ? ' (mirrored half)' : '' }, vertices ${ s.first } → ${ s.last }`;

}

function safe( fn ) {

	try {

		return fn();

	} catch {

		return null;

	}

}
