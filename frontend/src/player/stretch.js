// The fit map's numbers: per-vertex stretch of the garment against its flat cutting pattern,
// and the colour scale. Pure (typed arrays in, typed arrays out), so it is tested alone.

/** The fabric's strain limit the scale's warm end stands for (10 %). */
export const STRAIN_LIMIT = 0.10;

/**
 * The unique edges of a triangle list, with their rest length in the flat pattern.
 * `index`: triangle vertex indices (or null: non-indexed, 3 vertices per triangle);
 * `pattern`: Float32Array of (u, v) metres per vertex. Edges of zero rest length are dropped.
 */
export function buildEdges( index, vertexCount, pattern ) {

	const triCount = index ? Math.floor( index.length / 3 ) : Math.floor( vertexCount / 3 );
	const seen = new Set();
	const a = [];
	const b = [];
	const rest = [];
	const at = ( i ) => ( index ? index[ i ] : i );
	for ( let t = 0; t < triCount; t ++ ) {

		for ( let k = 0; k < 3; k ++ ) {

			let i = at( 3 * t + k );
			let j = at( 3 * t + ( k + 1 ) % 3 );
			if ( i === j ) continue;
			if ( i > j ) [ i, j ] = [ j, i ];
			const key = i * vertexCount + j;
			if ( seen.has( key ) ) continue;
			seen.add( key );
			const du = pattern[ 2 * i ] - pattern[ 2 * j ];
			const dv = pattern[ 2 * i + 1 ] - pattern[ 2 * j + 1 ];
			const len = Math.hypot( du, dv );
			if ( ! ( len > 1e-9 ) ) continue;
			a.push( i );
			b.push( j );
			rest.push( len );

		}

	}

	return { a: Uint32Array.from( a ), b: Uint32Array.from( b ), rest: Float32Array.from( rest ), vertexCount };

}

/**
 * Per-vertex stretch: the largest (3D length / pattern length − 1) over the edges at each
 * vertex, clamped at 0. `positions`: Float32Array xyz per vertex (metres).
 */
export function computeStretch( positions, edges, out = new Float32Array( edges.vertexCount ) ) {

	out.fill( 0 );
	const { a, b, rest } = edges;
	for ( let e = 0; e < rest.length; e ++ ) {

		const i = 3 * a[ e ];
		const j = 3 * b[ e ];
		const dx = positions[ i ] - positions[ j ];
		const dy = positions[ i + 1 ] - positions[ j + 1 ];
		const dz = positions[ i + 2 ] - positions[ j + 2 ];
		const s = Math.sqrt( dx * dx + dy * dy + dz * dz ) / rest[ e ] - 1;
		if ( s > out[ a[ e ] ] ) out[ a[ e ] ] = s;
		if ( s > out[ b[ e ] ] ) out[ b[ e ] ] = s;

	}

	return out;

}

/** The colour scale's stops (sRGB 0..1): a cool neutral at 0, warm red at the strain limit. */
export const SCALE_STOPS = [
	[ 0.0, [ 0.62, 0.72, 0.84 ] ], // cool grey-blue: relaxed
	[ 0.35, [ 0.88, 0.87, 0.80 ] ], // warm neutral: some ease taken up
	[ 0.65, [ 0.98, 0.72, 0.30 ] ], // amber
	[ 1.0, [ 0.84, 0.17, 0.13 ] ], // red: at the fabric's limit
];

/** The colour (sRGB 0..1) of a stretch `s` on the scale 0 … `limit` (clamped). */
export function stretchColour( s, limit = STRAIN_LIMIT, out = [ 0, 0, 0 ] ) {

	const f = Math.min( 1, Math.max( 0, ( Number( s ) || 0 ) / limit ) );
	for ( let k = 1; k < SCALE_STOPS.length; k ++ ) {

		const [ f1, c1 ] = SCALE_STOPS[ k ];
		if ( f <= f1 || k === SCALE_STOPS.length - 1 ) {

			const [ f0, c0 ] = SCALE_STOPS[ k - 1 ];
			const u = f1 > f0 ? Math.min( 1, Math.max( 0, ( f - f0 ) / ( f1 - f0 ) ) ) : 1;
			out[ 0 ] = c0[ 0 ] + ( c1[ 0 ] - c0[ 0 ] ) * u;
			out[ 1 ] = c0[ 1 ] + ( c1[ 1 ] - c0[ 1 ] ) * u;
			out[ 2 ] = c0[ 2 ] + ( c1[ 2 ] - c0[ 2 ] ) * u;
			return out;

		}

	}

	return out;

}

/** A CSS linear-gradient of the scale, for the legend. */
export function scaleGradientCss() {

	const stops = SCALE_STOPS.map( ( [ f, c ] ) => `rgb(${ c.map( ( x ) => Math.round( x * 255 ) ).join( ' ' ) }) ${ Math.round( f * 100 ) }%` );
	return `linear-gradient(to right, ${ stops.join( ', ' ) })`;

}
