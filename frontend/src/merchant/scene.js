// What the pattern view draws for a garment in one size, as plain data (no DOM): each piece
// as cut (mirrored copies as their source's image, folded panels with their mirrored half), the
// seams' runs and which ends meet, a seam being drawn, problems to point at.

import { flatten, foldMatrix, transformPoint, runPolyline, mod } from './geometry.js';
import { panelShape, displayFold, sourceVertexMap, sideAsShown, shownRun, shownReverse, shownEdge, vertexCount } from './garment-edit.js';

const FLAT = 5e-4; // 0.5 mm chords for drawing

/** The points of vertex `v` of a shown piece (on its mirrored half when `ghost`). */
export function shownVertex( piece, v, ghost = false ) {

	const p = piece.outline[ mod( v, piece.outline.length ) ].start;
	return ghost && piece.ghostMatrix ? transformPoint( p, piece.ghostMatrix ) : p;

}

/** One piece as drawn. */
export function pieceOf( g, panel, size ) {

	const shape = panelShape( g, panel, size );
	const fold = displayFold( g, panel );
	const ghostMatrix = fold == null ? null : foldMatrix( shape.outline, fold );
	const points = flatten( shape.outline, FLAT ).points;
	return {
		name: panel.name,
		type: panel.type || 'other',
		isCopy: panel.copy_of != null,
		copyOf: panel.copy_of ?? null,
		mirrored: sourceVertexMap( g, panel )[ 1 ],
		outline: shape.outline,
		points,
		ghost: ghostMatrix ? points.map( ( p ) => transformPoint( p, ghostMatrix ) ) : null,
		ghostMatrix,
		fold,
		grain: shape.grain || null,
		texture: panel.texture || null,
	};

}

/** The polyline of a side's run as shown. */
export function sidePolyline( g, piece, side ) {

	const run = shownRun( g, side );
	const pts = runPolyline( piece.outline, run.start, run.end, FLAT );
	return side.half === 'mirror' && piece.ghostMatrix ? pts.map( ( p ) => transformPoint( p, piece.ghostMatrix ) ) : pts;

}

/** [first, last] points of a side as shown (first: where the seam starts). */
export function sideEnds( g, piece, side ) {

	const s = sideAsShown( g, side );
	return [ shownVertex( piece, s.first, s.ghost ), shownVertex( piece, s.last, s.ghost ) ];

}

/** The pairs of points a seam joins: [[a first, b's matching end], [a last, b's other end]]. */
export function seamLinks( g, pieces, seam ) {

	const [ a0, a1 ] = sideEnds( g, pieces[ seam.a.panel ], seam.a );
	const [ b0, b1 ] = sideEnds( g, pieces[ seam.b.panel ], seam.b );
	return shownReverse( g, seam ) ? [ [ a0, b1 ], [ a1, b0 ] ] : [ [ a0, b0 ], [ a1, b1 ] ];

}

/**
 * The scene of `size`: { pieces: {name: piece}, order: [names], seams: [{index, a, b, links}] }
 * (a and b: run polylines). Seams naming a missing panel are left out.
 */
export function buildScene( g, size ) {

	const pieces = {};
	const order = [];
	for ( const p of g.panels ) {

		try {

			pieces[ p.name ] = pieceOf( g, p, size );
			order.push( p.name );

		} catch {

			// a panel without this size (the checker will say so): not drawn

		}

	}

	const seams = [];
	( g.seams || [] ).forEach( ( s, index ) => {

		if ( ! pieces[ s.a.panel ] || ! pieces[ s.b.panel ] ) return;
		try {

			seams.push( { index, a: sidePolyline( g, pieces[ s.a.panel ], s.a ), b: sidePolyline( g, pieces[ s.b.panel ], s.b ), links: seamLinks( g, pieces, s ) } );

		} catch {

			// vertices out of range: the checker names them

		}

	} );
	return { pieces, order, seams };

}

/** The polyline of edge `edge` (stored numbering) of a piece as shown. */
export function edgePolyline( g, piece, panelName, edge ) {

	const n = vertexCount( g, panelName );
	const e = shownEdge( g, panelName, mod( edge, n ) );
	return runPolyline( piece.outline, e, e + 1, FLAT );

}
