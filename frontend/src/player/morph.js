// A garment chunk's shape at the shown time, on the CPU: morphed positions (base + Σ weight ×
// target) and, where the file has no NORMAL targets (the web copy), their normals. Pure.

/**
 * Morphed positions: base + Σ weight × target (relative targets, as glTF's), for the targets
 * whose weight is not 0. `targets[k]` may be null for a target not read yet (its weight must be 0).
 */
export function morphPositions( base, targets, weights, out = new Float32Array( base.length ) ) {

	out.set( base );
	for ( let k = 0; k < weights.length; k ++ ) {

		const w = weights[ k ];
		if ( w === 0 || ! targets[ k ] ) continue;
		const t = targets[ k ];
		for ( let i = 0; i < out.length; i ++ ) out[ i ] += w * t[ i ];

	}

	return out;

}

/**
 * Smooth vertex normals of a triangle list (area-weighted face normals, normalised).
 * `index`: triangle indices or null (non-indexed). Vertices of no triangle get (0, 1, 0).
 */
export function computeNormals( positions, index, out = new Float32Array( positions.length ) ) {

	out.fill( 0 );
	const n = positions.length / 3;
	const tris = index ? index.length / 3 : n / 3;
	for ( let t = 0; t < tris; t ++ ) {

		const a = 3 * ( index ? index[ 3 * t ] : 3 * t );
		const b = 3 * ( index ? index[ 3 * t + 1 ] : 3 * t + 1 );
		const c = 3 * ( index ? index[ 3 * t + 2 ] : 3 * t + 2 );
		const ux = positions[ b ] - positions[ a ], uy = positions[ b + 1 ] - positions[ a + 1 ], uz = positions[ b + 2 ] - positions[ a + 2 ];
		const vx = positions[ c ] - positions[ a ], vy = positions[ c + 1 ] - positions[ a + 1 ], vz = positions[ c + 2 ] - positions[ a + 2 ];
		const nx = uy * vz - uz * vy, ny = uz * vx - ux * vz, nz = ux * vy - uy * vx; // |n| = 2 × area
		out[ a ] += nx; out[ a + 1 ] += ny; out[ a + 2 ] += nz;
		out[ b ] += nx; out[ b + 1 ] += ny; out[ b + 2 ] += nz;
		out[ c ] += nx; out[ c + 1 ] += ny; out[ c + 2 ] += nz;

	}

	for ( let i = 0; i < out.length; i += 3 ) {

		const len = Math.hypot( out[ i ], out[ i + 1 ], out[ i + 2 ] );
		if ( len > 0 ) {

			out[ i ] /= len; out[ i + 1 ] /= len; out[ i + 2 ] /= len;

		} else {

			out[ i ] = 0; out[ i + 1 ] = 1; out[ i + 2 ] = 0;

		}

	}

	return out;

}
