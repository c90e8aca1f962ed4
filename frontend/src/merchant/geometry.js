// Outline geometry of the garment format (docs/garment-format.md), as the backend's
// catwalk.garment.geometry computes it: segments (line, quadratic, cubic, arc with a DXF bulge),
// flattening within a chord tolerance, arc lengths, the editor's affine maps, picking.
//
// A point is [x, y] in metres (+y up). An outline is a closed loop of segments
// `{ type, start, controls?, bulge? }`: segment i runs from its start (vertex i) to the next
// segment's start. Nothing here touches the DOM.

export const KINDS = [ 'line', 'quadratic', 'cubic', 'arc' ];
const MAX_PIECES = 2000; // chords per segment, as the backend

const sub = ( a, b ) => [ a[ 0 ] - b[ 0 ], a[ 1 ] - b[ 1 ] ];
const norm = ( a ) => Math.hypot( a[ 0 ], a[ 1 ] );
export const dist = ( a, b ) => Math.hypot( a[ 0 ] - b[ 0 ], a[ 1 ] - b[ 1 ] );
export const mod = ( i, n ) => ( ( i % n ) + n ) % n;

function isStraight( seg ) {

	const kind = seg.type || 'line';
	return kind === 'line' || ( kind === 'arc' && Math.abs( seg.bulge || 0 ) < 1e-12 );

}

function piecesFor( bound, tolerance ) {

	// a curve with |B''| ≤ M cut into n equal parameter steps deviates ≤ M/(8 n²) from chords
	if ( bound <= 0 ) return 1;
	const n = Math.ceil( Math.sqrt( bound / ( 8 * tolerance ) ) );
	return Math.min( MAX_PIECES, Math.max( 1, n ) );

}

/** { centre, radius, a0, theta } of the bulge arc from p0 to p1 (theta signed, CCW > 0). */
export function arcGeometry( p0, p1, bulge ) {

	const theta = 4 * Math.atan( bulge );
	const chord = sub( p1, p0 );
	const c = norm( chord );
	if ( c === 0 ) return { centre: [ p0[ 0 ], p0[ 1 ] ], radius: 0, a0: 0, theta: 0 };
	const radius = c / ( 2 * Math.abs( Math.sin( theta / 2 ) ) );
	const mid = [ ( p0[ 0 ] + p1[ 0 ] ) / 2, ( p0[ 1 ] + p1[ 1 ] ) / 2 ];
	const normal = [ - chord[ 1 ] / c, chord[ 0 ] / c ]; // left of the chord
	const d = radius * Math.cos( theta / 2 ) * ( theta > 0 ? 1 : - 1 );
	const centre = [ mid[ 0 ] + normal[ 0 ] * d, mid[ 1 ] + normal[ 1 ] * d ];
	const a0 = Math.atan2( p0[ 1 ] - centre[ 1 ], p0[ 0 ] - centre[ 0 ] );
	return { centre, radius, a0, theta };

}

/** How many chords keep the segment (from its start to `end`) within `tolerance`. */
export function segmentPieces( seg, end, tolerance ) {

	const p0 = seg.start;
	if ( isStraight( seg ) ) return 1;
	if ( seg.type === 'quadratic' ) {

		const c = seg.controls[ 0 ];
		return piecesFor( 2 * norm( [ p0[ 0 ] - 2 * c[ 0 ] + end[ 0 ], p0[ 1 ] - 2 * c[ 1 ] + end[ 1 ] ] ), tolerance );

	}

	if ( seg.type === 'cubic' ) {

		const [ c1, c2 ] = seg.controls;
		const m1 = norm( [ p0[ 0 ] - 2 * c1[ 0 ] + c2[ 0 ], p0[ 1 ] - 2 * c1[ 1 ] + c2[ 1 ] ] );
		const m2 = norm( [ c1[ 0 ] - 2 * c2[ 0 ] + end[ 0 ], c1[ 1 ] - 2 * c2[ 1 ] + end[ 1 ] ] );
		return piecesFor( 6 * Math.max( m1, m2 ), tolerance );

	}

	if ( seg.type === 'arc' ) {

		const { radius, theta } = arcGeometry( p0, end, seg.bulge || 0 );
		if ( radius <= tolerance ) return 1;
		const step = 2 * Math.acos( Math.max( - 1, 1 - tolerance / radius ) );
		return Math.min( MAX_PIECES, Math.max( 1, Math.ceil( Math.abs( theta ) / Math.max( step, 1e-9 ) ) ) );

	}

	throw new Error( `unknown segment type ${ JSON.stringify( seg.type ) }` );

}

/** The segment's points from its start (included) to `end` (excluded). */
export function segmentPoints( seg, end, tolerance, pieces = null ) {

	const p0 = seg.start;
	if ( isStraight( seg ) ) {

		if ( pieces && pieces > 1 ) {

			const out = [];
			for ( let i = 0; i < pieces; i ++ ) {

				const t = i / pieces;
				out.push( [ p0[ 0 ] + t * ( end[ 0 ] - p0[ 0 ] ), p0[ 1 ] + t * ( end[ 1 ] - p0[ 1 ] ) ] );

			}

			return out;

		}

		return [ [ p0[ 0 ], p0[ 1 ] ] ];

	}

	const n = pieces || segmentPieces( seg, end, tolerance );
	const out = [];
	if ( seg.type === 'quadratic' ) {

		const c = seg.controls[ 0 ];
		for ( let i = 0; i < n; i ++ ) {

			const t = i / n, u = 1 - t;
			out.push( [ u * u * p0[ 0 ] + 2 * u * t * c[ 0 ] + t * t * end[ 0 ], u * u * p0[ 1 ] + 2 * u * t * c[ 1 ] + t * t * end[ 1 ] ] );

		}

		return out;

	}

	if ( seg.type === 'cubic' ) {

		const [ c1, c2 ] = seg.controls;
		for ( let i = 0; i < n; i ++ ) {

			const t = i / n, u = 1 - t;
			const a = u * u * u, b = 3 * u * u * t, c = 3 * u * t * t, d = t * t * t;
			out.push( [ a * p0[ 0 ] + b * c1[ 0 ] + c * c2[ 0 ] + d * end[ 0 ], a * p0[ 1 ] + b * c1[ 1 ] + c * c2[ 1 ] + d * end[ 1 ] ] );

		}

		return out;

	}

	const { centre, radius, a0, theta } = arcGeometry( p0, end, seg.bulge || 0 );
	for ( let i = 0; i < n; i ++ ) {

		const a = a0 + ( theta * i ) / n;
		out.push( [ centre[ 0 ] + radius * Math.cos( a ), centre[ 1 ] + radius * Math.sin( a ) ] );

	}

	return out;

}

/**
 * The closed outline as a polyline within `tolerance` metres (first point not repeated):
 * `{ points, vertexIndex, edgeSegment }` — vertex i is `points[vertexIndex[i]]`, polyline edge
 * k → k+1 belongs to segment `edgeSegment[k]`.
 */
export function flatten( outline, tolerance = 1e-3 ) {

	if ( ! ( tolerance > 0 ) ) throw new Error( 'flatten: tolerance must be positive' );
	const n = outline.length;
	const points = [], vertexIndex = [], edgeSegment = [];
	for ( let i = 0; i < n; i ++ ) {

		const end = outline[ ( i + 1 ) % n ].start;
		const pts = segmentPoints( outline[ i ], end, tolerance );
		vertexIndex.push( points.length );
		for ( const p of pts ) {

			points.push( p );
			edgeSegment.push( i );

		}

	}

	return { points, vertexIndex, edgeSegment };

}

/** Arc length of every segment (flattened within 10 µm, as the backend's checker measures). */
export function segmentLengths( outline, tolerance = 1e-5 ) {

	const { points, edgeSegment } = flatten( outline, tolerance );
	const out = new Array( outline.length ).fill( 0 );
	const m = points.length;
	for ( let k = 0; k < m; k ++ ) out[ edgeSegment[ k ] ] += dist( points[ k ], points[ ( k + 1 ) % m ] );
	return out;

}

/** Length of the run from vertex `start` forward (wrapping) to vertex `end` (the whole loop when equal). */
export function runLength( lengths, start, end ) {

	const n = lengths.length;
	let k = mod( end - start, n );
	if ( k === 0 ) k = n;
	let sum = 0;
	for ( let i = 0; i < k; i ++ ) sum += lengths[ mod( start + i, n ) ];
	return sum;

}

/** The segments of the run from vertex `start` forward to `end` (edge numbers). */
export function runEdges( n, start, end ) {

	let k = mod( end - start, n );
	if ( k === 0 ) k = n;
	const out = [];
	for ( let i = 0; i < k; i ++ ) out.push( mod( start + i, n ) );
	return out;

}

/** The polyline (open, both ends included) of the run from vertex `start` forward to `end`. */
export function runPolyline( outline, start, end, tolerance = 5e-4 ) {

	const n = outline.length;
	const out = [];
	for ( const e of runEdges( n, start, end ) ) {

		for ( const p of segmentPoints( outline[ e ], outline[ ( e + 1 ) % n ].start, tolerance ) ) out.push( p );

	}

	const last = outline[ mod( end, n ) ].start;
	out.push( [ last[ 0 ], last[ 1 ] ] );
	return out;

}

/** Signed area (positive counter-clockwise) of a closed polygon. */
export function polygonArea( points ) {

	let s = 0;
	const m = points.length;
	for ( let i = 0; i < m; i ++ ) {

		const a = points[ i ], b = points[ ( i + 1 ) % m ];
		s += a[ 0 ] * b[ 1 ] - b[ 0 ] * a[ 1 ];

	}

	return s / 2;

}

export function perimeter( outline ) {

	return segmentLengths( outline ).reduce( ( a, b ) => a + b, 0 );

}

/** { min: [x, y], max: [x, y] } of points. */
export function bounds( points ) {

	const min = [ Infinity, Infinity ], max = [ - Infinity, - Infinity ];
	for ( const p of points ) {

		if ( p[ 0 ] < min[ 0 ] ) min[ 0 ] = p[ 0 ];
		if ( p[ 1 ] < min[ 1 ] ) min[ 1 ] = p[ 1 ];
		if ( p[ 0 ] > max[ 0 ] ) max[ 0 ] = p[ 0 ];
		if ( p[ 1 ] > max[ 1 ] ) max[ 1 ] = p[ 1 ];

	}

	return { min, max };

}

/** Whether `p` is inside the closed polygon `points` (even-odd). */
export function pointInPolygon( p, points ) {

	let inside = false;
	const m = points.length;
	for ( let i = 0, j = m - 1; i < m; j = i ++ ) {

		const a = points[ i ], b = points[ j ];
		if ( ( a[ 1 ] > p[ 1 ] ) !== ( b[ 1 ] > p[ 1 ] ) && p[ 0 ] < ( ( b[ 0 ] - a[ 0 ] ) * ( p[ 1 ] - a[ 1 ] ) ) / ( b[ 1 ] - a[ 1 ] ) + a[ 0 ] ) inside = ! inside;

	}

	return inside;

}

/** The outline vertex nearest `p` within `radius` (metres), or -1. */
export function pickVertex( outline, p, radius ) {

	let best = - 1, bestD = radius;
	outline.forEach( ( seg, i ) => {

		const d = dist( seg.start, p );
		if ( d <= bestD ) {

			best = i;
			bestD = d;

		}

	} );
	return best;

}

/** Distance from `p` to the segment a–b. */
export function pointSegmentDistance( p, a, b ) {

	const d = sub( b, a );
	const len2 = d[ 0 ] * d[ 0 ] + d[ 1 ] * d[ 1 ];
	const t = len2 > 0 ? Math.min( 1, Math.max( 0, ( ( p[ 0 ] - a[ 0 ] ) * d[ 0 ] + ( p[ 1 ] - a[ 1 ] ) * d[ 1 ] ) / len2 ) ) : 0;
	return dist( p, [ a[ 0 ] + t * d[ 0 ], a[ 1 ] + t * d[ 1 ] ] );

}

/** The outline edge (segment number) nearest `p` within `radius`, or -1. */
export function pickEdge( outline, p, radius, tolerance = 1e-3 ) {

	const { points, edgeSegment } = flatten( outline, tolerance );
	let best = - 1, bestD = radius;
	const m = points.length;
	for ( let k = 0; k < m; k ++ ) {

		const d = pointSegmentDistance( p, points[ k ], points[ ( k + 1 ) % m ] );
		if ( d <= bestD ) {

			best = edgeSegment[ k ];
			bestD = d;

		}

	}

	return best;

}

// --- affine maps (2×3: [[a, b, tx], [c, d, ty]]), as catwalk.garment.geometry ---------------------

export function moveMatrix( dx, dy ) {

	return [ [ 1, 0, dx ], [ 0, 1, dy ] ];

}

/** Counter-clockwise by `degrees` about `centre`. */
export function rotateMatrix( degrees, centre = [ 0, 0 ] ) {

	const a = ( degrees * Math.PI ) / 180;
	const c = Math.cos( a ), s = Math.sin( a );
	const [ cx, cy ] = centre;
	return [ [ c, - s, cx - c * cx + s * cy ], [ s, c, cy - s * cx - c * cy ] ];

}

/** Mirror across the vertical line x = at (axis "x": x → 2at − x) or the horizontal y = at ("y"). */
export function mirrorMatrix( axis = 'x', at = 0 ) {

	if ( axis === 'x' ) return [ [ - 1, 0, 2 * at ], [ 0, 1, 0 ] ];
	if ( axis === 'y' ) return [ [ 1, 0, 0 ], [ 0, - 1, 2 * at ] ];
	throw new Error( `mirror axis must be 'x' or 'y', not ${ JSON.stringify( axis ) }` );

}

/** Reflection across the line through p and q. */
export function lineMirrorMatrix( p, q ) {

	const d0 = sub( q, p );
	const l = norm( d0 );
	const d = [ d0[ 0 ] / l, d0[ 1 ] / l ];
	const r = [ [ 2 * d[ 0 ] * d[ 0 ] - 1, 2 * d[ 0 ] * d[ 1 ] ], [ 2 * d[ 1 ] * d[ 0 ], 2 * d[ 1 ] * d[ 1 ] - 1 ] ];
	const t = [ p[ 0 ] - ( r[ 0 ][ 0 ] * p[ 0 ] + r[ 0 ][ 1 ] * p[ 1 ] ), p[ 1 ] - ( r[ 1 ][ 0 ] * p[ 0 ] + r[ 1 ][ 1 ] * p[ 1 ] ) ];
	return [ [ r[ 0 ][ 0 ], r[ 0 ][ 1 ], t[ 0 ] ], [ r[ 1 ][ 0 ], r[ 1 ][ 1 ], t[ 1 ] ] ];

}

export const determinant = ( m ) => m[ 0 ][ 0 ] * m[ 1 ][ 1 ] - m[ 0 ][ 1 ] * m[ 1 ][ 0 ];

export function transformPoint( p, m ) {

	return [ m[ 0 ][ 0 ] * p[ 0 ] + m[ 0 ][ 1 ] * p[ 1 ] + m[ 0 ][ 2 ], m[ 1 ][ 0 ] * p[ 0 ] + m[ 1 ][ 1 ] * p[ 1 ] + m[ 1 ][ 2 ] ];

}

function segment( type, start, controls, bulge ) {

	const s = { type, start };
	if ( controls.length ) s.controls = controls;
	if ( type === 'arc' ) s.bulge = bulge;
	return s;

}

/**
 * The same loop walked the other way: vertex i of the result is vertex (−i) mod n of the input;
 * segment i of the result is input segment (−i − 1) mod n reversed.
 */
export function reverseSegments( outline ) {

	const n = outline.length;
	const out = [];
	for ( let i = 0; i < n; i ++ ) {

		const src = outline[ mod( - i - 1, n ) ];
		const start = outline[ mod( - i, n ) ].start; // the end of src
		out.push( segment( src.type || 'line', [ start[ 0 ], start[ 1 ] ], ( src.controls || [] ).slice().reverse().map( ( c ) => [ c[ 0 ], c[ 1 ] ] ), - ( src.bulge || 0 ) ) );

	}

	return out;

}

/**
 * Segments under an affine map; a reflection (det < 0) reverses the loop so that it keeps its
 * orientation, and vertex i of the result is the image of vertex (−i) mod n. A stated `end` is
 * dropped (the next start is the end).
 */
export function transformSegments( outline, m ) {

	const det = determinant( m );
	const out = outline.map( ( s ) => segment( s.type || 'line', transformPoint( s.start, m ), ( s.controls || [] ).map( ( c ) => transformPoint( c, m ) ), det > 0 ? ( s.bulge || 0 ) : - ( s.bulge || 0 ) ) );
	if ( det > 0 || ! out.length ) return out;
	return reverseSegments( out );

}

/** A shape (one size) under an affine map: outline, grain line, notches, labels renumbered. */
export function transformShape( shape, m ) {

	const det = determinant( m );
	const n = shape.outline.length;
	const out = { ...shape, outline: transformSegments( shape.outline, m ) };
	if ( shape.grain ) out.grain = shape.grain.map( ( p ) => transformPoint( p, m ) );
	if ( shape.notches ) out.notches = shape.notches.map( ( p ) => transformPoint( p, m ) );
	if ( shape.labels ) {

		if ( det > 0 ) out.labels = { ...shape.labels };
		else {

			out.labels = {};
			for ( const [ v, name ] of Object.entries( shape.labels ) ) out.labels[ String( mod( - Number( v ), n ) ) ] = name;

		}

	}

	return out;

}

/**
 * Open a half cut on fold along segment `k`: the mirrored half's points, as
 * catwalk.garment.model.unfold makes the cut piece (the stored half plus its image across the
 * fold line). Returns the reflection matrix; the image of stored vertex v is
 * `transformPoint(outline[v].start, matrix)`.
 */
export function foldMatrix( outline, k ) {

	const n = outline.length;
	return lineMirrorMatrix( outline[ mod( k, n ) ].start, outline[ mod( k + 1, n ) ].start );

}

/** Whether segment `k` is straight (a fold edge must be). */
export function isStraightEdge( outline, k ) {

	return isStraight( outline[ k ] );

}
