// What the pattern view shows of the editor's state: the pieces of the size shown, the seam
// being sewn (its runs, and dashed lines joining the ends that meet) and the last refused
// save's problems (pieces and edges in red, until the garment changes).

import { buildScene, sidePolyline, sideEnds, edgePolyline } from './scene.js';
import { vertexCount } from './garment-edit.js';
import { draftSides } from './seam-picks.js';

/** Draw the editor's `state` in the PatternView `view`. */
export function drawPattern( view, state ) {

	const { g, size } = state;
	let scene;
	try {

		scene = buildScene( g, size );

	} catch ( err ) {

		console.warn( 'pattern view', err );
		return;

	}

	view.update( scene, {
		selected: state.selected, mode: state.mode, picks: state.picks, highlight: state.highlight,
		draft: draftLines( state, scene ),
		problems: problemMarks( state, scene ),
		textures: state.textures,
	} );

}

/** The runs picked and the links between their ends: `{ runs, links }`, or null when none. */
function draftLines( state, scene ) {

	const g = state.g;
	const { a, b } = draftSides( state );
	const runs = [];
	const links = [];
	for ( const side of [ a, b ] ) if ( side && scene.pieces[ side.panel ] ) runs.push( sidePolyline( g, scene.pieces[ side.panel ], side ) );
	if ( a && b ) {

		const [ a0, a1 ] = sideEnds( g, scene.pieces[ a.panel ], a );
		const [ b0, b1 ] = sideEnds( g, scene.pieces[ b.panel ], b );
		links.push( ...( state.draft.reverse ? [ [ a0, b1 ], [ a1, b0 ] ] : [ [ a0, b0 ], [ a1, b1 ] ] ) );

	}

	return runs.length ? { runs, links } : null;

}

/** The pieces and edges the last refused save names: `{ panels, edges }`. */
function problemMarks( state, scene ) {

	const g = state.g;
	const panels = new Set();
	const edges = [];
	for ( const p of state.problemsStale ? [] : state.problems ) {

		if ( ! p.panel || ! scene.pieces[ p.panel ] ) continue;
		panels.add( p.panel );
		if ( Number.isInteger( p.edge ) && p.edge >= 0 && p.edge < vertexCount( g, p.panel ) ) edges.push( { panel: p.panel, points: edgePolyline( g, scene.pieces[ p.panel ], p.panel, p.edge ) } );

	}

	return { panels, edges };

}
