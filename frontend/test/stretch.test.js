import { describe, it, expect } from 'vitest';
import { buildEdges, computeStretch, stretchColour, scaleGradientCss, STRAIN_LIMIT } from '../src/player/stretch.js';
import { morphPositions, computeNormals } from '../src/player/morph.js';

// a unit quad in the pattern: 0 (0,0), 1 (1,0), 2 (1,1), 3 (0,1); two triangles
const pattern = Float32Array.from( [ 0, 0, 1, 0, 1, 1, 0, 1 ] );
const index = Uint32Array.from( [ 0, 1, 2, 0, 2, 3 ] );
const flat = ( sx, sy = sx ) => Float32Array.from( [ 0, 0, 0, sx, 0, 0, sx, sy, 0, 0, sy, 0 ] );

describe( 'stretch', () => {

	it( 'finds each edge once, with its pattern length', () => {

		const e = buildEdges( index, 4, pattern );
		expect( e.rest.length ).toBe( 5 ); // four sides and the diagonal
		const diag = [ ...e.rest ].filter( ( r ) => Math.abs( r - Math.SQRT2 ) < 1e-6 );
		expect( diag.length ).toBe( 1 );

	} );

	it( 'a flat quad stretched 10 % gives 0.10', () => {

		const s = computeStretch( flat( 1.1 ), buildEdges( index, 4, pattern ) );
		for ( const v of s ) expect( v ).toBeCloseTo( 0.10, 5 );

	} );

	it( 'takes the largest edge at each vertex, and no compression', () => {

		const s = computeStretch( flat( 1.1, 1.0 ), buildEdges( index, 4, pattern ) );
		for ( const v of s ) expect( v ).toBeCloseTo( 0.10, 5 ); // every vertex has a horizontal edge
		const squeezed = computeStretch( flat( 0.8 ), buildEdges( index, 4, pattern ) );
		for ( const v of squeezed ) expect( v ).toBe( 0 );

	} );

	it( 'is the same for a moved, turned garment', () => {

		const p = flat( 1.05 );
		const c = Math.cos( 0.7 ), sn = Math.sin( 0.7 );
		const q = new Float32Array( 12 );
		for ( let i = 0; i < 4; i ++ ) {

			const x = p[ 3 * i ], y = p[ 3 * i + 1 ];
			q[ 3 * i ] = c * x + 3;
			q[ 3 * i + 1 ] = y - 1;
			q[ 3 * i + 2 ] = sn * x + 2;

		}

		const s = computeStretch( q, buildEdges( index, 4, pattern ) );
		for ( const v of s ) expect( v ).toBeCloseTo( 0.05, 5 );

	} );

	it( 'works on non-indexed triangles and drops zero-length pattern edges', () => {

		const pat = Float32Array.from( [ 0, 0, 1, 0, 0, 1 ] );
		const e = buildEdges( null, 3, pat );
		expect( e.rest.length ).toBe( 3 );
		const degenerate = buildEdges( null, 3, Float32Array.from( [ 0, 0, 0, 0, 0, 1 ] ) );
		expect( degenerate.rest.length ).toBe( 2 );

	} );

	it( 'morphs positions from the base and the weighted targets', () => {

		const base = Float32Array.from( [ 0, 0, 0, 1, 0, 0 ] );
		const t1 = Float32Array.from( [ 0, 0, 0, 0.2, 0, 0 ] );
		const t2 = Float32Array.from( [ 0, 1, 0, 0, 1, 0 ] );
		const out = morphPositions( base, [ null, t1, t2 ], [ 0, 0.5, 0.5 ] );
		[ 0, 0.5, 0, 1.1, 0.5, 0 ].forEach( ( v, i ) => expect( out[ i ] ).toBeCloseTo( v, 6 ) );

	} );

	it( 'computes the normals of the morphed shape', () => {

		// the quad in the xy plane faces +z; folded up along x = 1 its far corner tilts
		const n = computeNormals( flat( 1 ), index );
		for ( let i = 0; i < 4; i ++ ) expect( [ n[ 3 * i ], n[ 3 * i + 1 ], n[ 3 * i + 2 ] ] ).toEqual( [ 0, 0, 1 ] );
		const tilted = Float32Array.from( [ 0, 0, 0, 1, 0, 0, 1, 1, 1, 0, 1, 1 ] ); // rotated 45° about x
		const m = computeNormals( tilted, index );
		expect( m[ 1 ] ).toBeCloseTo( - Math.SQRT1_2, 6 );
		expect( m[ 2 ] ).toBeCloseTo( Math.SQRT1_2, 6 );
		const lonely = computeNormals( Float32Array.from( [ 0, 0, 0 ] ), Uint32Array.from( [] ) );
		expect( [ ...lonely ] ).toEqual( [ 0, 1, 0 ] );

	} );

} );

describe( 'colour scale', () => {

	it( 'runs from cool at 0 to red at the strain limit, clamped', () => {

		expect( STRAIN_LIMIT ).toBe( 0.10 );
		const cool = stretchColour( 0 );
		const hot = stretchColour( 0.10 );
		expect( cool[ 2 ] ).toBeGreaterThan( cool[ 0 ] ); // blue over red
		expect( hot[ 0 ] ).toBeGreaterThan( 0.8 );
		expect( hot[ 1 ] ).toBeLessThan( 0.3 );
		expect( stretchColour( 0.5 ) ).toEqual( hot );
		expect( stretchColour( - 1 ) ).toEqual( cool );
		expect( stretchColour( NaN ) ).toEqual( cool );

	} );

	it( 'warms steadily', () => {

		let last = - 1;
		for ( let s = 0; s <= 0.1; s += 0.01 ) {

			const [ r, g, b ] = stretchColour( s );
			const warmth = r - b;
			expect( warmth ).toBeGreaterThanOrEqual( last - 1e-9 );
			last = warmth;
			for ( const x of [ r, g, b ] ) {

				expect( x ).toBeGreaterThanOrEqual( 0 );
				expect( x ).toBeLessThanOrEqual( 1 );

			}

		}

		expect( scaleGradientCss() ).toMatch( /^linear-gradient\(to right, rgb\(/ );

	} );

} );
