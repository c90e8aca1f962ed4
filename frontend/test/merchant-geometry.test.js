// The editor's outline geometry against numbers from the backend (catwalk.garment.geometry on
// the catalogue's pencil skirt and hand-made segments).
import { describe, it, expect } from 'vitest';
import { readFileSync } from 'node:fs';
import {
	flatten, segmentLengths, runLength, runEdges, runPolyline, polygonArea, arcGeometry,
	moveMatrix, rotateMatrix, mirrorMatrix, lineMirrorMatrix, transformPoint, transformSegments,
	reverseSegments, transformShape, pickVertex, pickEdge, pointInPolygon, bounds, segmentPieces,
} from '../src/merchant/geometry.js';

const skirt = () => JSON.parse( readFileSync( new URL( '../../garments/pencil-skirt.json', import.meta.url ), 'utf8' ) );
const backRightM = () => skirt().panels.find( ( p ) => p.name === 'back_right' ).shapes.M;

// a 40 cm line, an arc of bulge 0.25 (θ = 4·atan 0.25) and a quadratic
const MIXED = [
	{ type: 'line', start: [ 0, 0 ] },
	{ type: 'arc', start: [ 0.4, 0 ], bulge: 0.25 },
	{ type: 'quadratic', start: [ 0.4, 0.3 ], controls: [ [ 0.2, 0.5 ] ] },
];

describe( 'flattening and lengths', () => {

	it( 'measures line, arc and quadratic segments as the backend does', () => {

		const L = segmentLengths( MIXED );
		expect( L[ 0 ] ).toBeCloseTo( 0.4, 12 );
		expect( L[ 1 ] ).toBeCloseTo( 0.3123445444717645, 9 );
		expect( L[ 2 ] ).toBeCloseTo( 0.6099531379642305, 9 );
		// the arc: chord 0.3, θ = 4 atan(0.25) → r = 0.3 / (2 sin(θ/2)), length r·θ
		const theta = 4 * Math.atan( 0.25 );
		expect( L[ 1 ] ).toBeCloseTo( ( 0.3 / ( 2 * Math.sin( theta / 2 ) ) ) * theta, 5 ); // chords within 10 µm
		expect( flatten( MIXED, 1e-3 ).points.length ).toBe( 22 );

	} );

	it( 'measures cubic runs of the pencil skirt like catwalk garment check', () => {

		const L = segmentLengths( backRightM().outline );
		const expected = [ 0.35454, 0.040050528, 0.25524, 0.012762, 0.02832, 0.2832, 0.012762, 0.3781, 0.278590472, 0.089897499, 0.10462378, 0.104623408, 0.012268571, 0.130493782, 0.130491832, 0.107380481 ];
		L.forEach( ( l, i ) => expect( l ).toBeCloseTo( expected[ i ], 8 ) );
		expect( runLength( L, 6, 9 ) ).toBeCloseTo( 0.66945, 5 ); // the side seam's back run
		expect( runLength( L, 10, 11 ) ).toBeCloseTo( 0.10462, 5 );
		expect( runLength( L, 15, 1 ) ).toBeCloseTo( 0.107380481 + 0.35454, 8 ); // wraps
		expect( runLength( L, 3, 3 ) ).toBeCloseTo( L.reduce( ( a, b ) => a + b ), 12 ); // the whole loop
		expect( flatten( backRightM().outline, 1e-3 ).points.length ).toBe( 71 );

	} );

	it( 'lists run edges and draws run polylines from vertex to vertex', () => {

		expect( runEdges( 5, 3, 1 ) ).toEqual( [ 3, 4, 0 ] );
		const square = [ [ 0, 0 ], [ 1, 0 ], [ 1, 1 ], [ 0, 1 ] ].map( ( start ) => ( { type: 'line', start } ) );
		expect( runPolyline( square, 3, 1 ) ).toEqual( [ [ 0, 1 ], [ 0, 0 ], [ 1, 0 ] ] );
		expect( polygonArea( square.map( ( s ) => s.start ) ) ).toBe( 1 );
		const arc = runPolyline( MIXED, 1, 2, 1e-3 );
		expect( arc[ 0 ][ 0 ] ).toBeCloseTo( 0.4, 12 );
		expect( arc[ 0 ][ 1 ] ).toBeCloseTo( 0, 12 );
		expect( arc.at( - 1 ) ).toEqual( [ 0.4, 0.3 ] );
		expect( arc.length ).toBe( segmentPieces( MIXED[ 1 ], [ 0.4, 0.3 ], 1e-3 ) + 1 );

	} );

	it( 'finds the arc centre: a bulge-1 half circle', () => {

		const a = arcGeometry( [ 0, 0 ], [ 2, 0 ], 1 );
		expect( a.radius ).toBeCloseTo( 1, 12 );
		expect( a.centre[ 0 ] ).toBeCloseTo( 1, 12 );
		expect( a.centre[ 1 ] ).toBeCloseTo( 0, 12 );
		expect( a.theta ).toBeCloseTo( Math.PI, 12 );

	} );

} );

describe( 'affine maps', () => {

	it( 'rotates counter-clockwise about a centre and mirrors across lines', () => {

		const r = transformPoint( [ 2, 1 ], rotateMatrix( 90, [ 1, 1 ] ) );
		expect( r[ 0 ] ).toBeCloseTo( 1, 12 );
		expect( r[ 1 ] ).toBeCloseTo( 2, 12 );
		expect( transformPoint( [ 0.3, 0.2 ], mirrorMatrix( 'x', 0.5 ) ) ).toEqual( [ 0.7, 0.2 ] );
		expect( transformPoint( [ 0.3, 0.2 ], mirrorMatrix( 'y', 1 ) ) ).toEqual( [ 0.3, 1.8 ] );
		expect( transformPoint( [ 0.3, 0.2 ], moveMatrix( 0.1, - 0.2 ) ) ).toEqual( [ 0.4, 0 ] );
		const m = transformPoint( [ 1, 0 ], lineMirrorMatrix( [ 0, 0 ], [ 1, 1 ] ) );
		expect( m[ 0 ] ).toBeCloseTo( 0, 12 );
		expect( m[ 1 ] ).toBeCloseTo( 1, 12 );

	} );

	it( 'reverses a mirrored loop so vertex i is the image of vertex −i, controls and bulges included', () => {

		const out = transformSegments( MIXED, mirrorMatrix( 'x', 0 ) );
		// vertex 0 ← vertex 0, vertex 1 ← vertex 2, vertex 2 ← vertex 1
		expect( out.map( ( s ) => s.start ) ).toEqual( [ [ 0, 0 ], [ - 0.4, 0.3 ], [ - 0.4, 0 ] ] );
		// segment i is input segment (−i − 1) mod n reversed: 0 ← quadratic, 1 ← arc, 2 ← line
		expect( out.map( ( s ) => s.type ) ).toEqual( [ 'quadratic', 'arc', 'line' ] );
		expect( out[ 0 ].controls ).toEqual( [ [ - 0.2, 0.5 ] ] );
		expect( out[ 1 ].bulge ).toBe( 0.25 ); // reflected (−) and walked backwards (−)
		expect( polygonArea( flatten( out ).points ) ).toBeCloseTo( polygonArea( flatten( MIXED ).points ), 9 ); // still counter-clockwise
		const L = segmentLengths( out );
		expect( L[ 1 ] ).toBeCloseTo( 0.3123445444717645, 9 );
		expect( L[ 0 ] ).toBeCloseTo( 0.6099531379642305, 9 );
		// cubic controls swap order when walked backwards
		const cubic = [ { type: 'cubic', start: [ 0, 0 ], controls: [ [ 1, 0 ], [ 1, 1 ] ] }, { type: 'line', start: [ 0, 1 ] } ];
		expect( reverseSegments( cubic ) ).toEqual( [ { type: 'line', start: [ 0, 0 ] }, { type: 'cubic', start: [ 0, 1 ], controls: [ [ 1, 1 ], [ 1, 0 ] ] } ] );

	} );

	it( 'renumbers labels of a mirrored shape and moves its grain line', () => {

		const sh = { outline: MIXED, grain: [ [ 0, 0 ], [ 0, 1 ] ], notches: [ [ 0.1, 0 ] ], labels: { 1: 'corner' } };
		const out = transformShape( sh, mirrorMatrix( 'x', 0.2 ) );
		expect( out.labels ).toEqual( { 2: 'corner' } );
		expect( out.grain ).toEqual( [ [ 0.4, 0 ], [ 0.4, 1 ] ] );
		expect( out.notches[ 0 ][ 0 ] ).toBeCloseTo( 0.3, 12 );
		expect( sh.outline[ 1 ].start ).toEqual( [ 0.4, 0 ] ); // the input is left alone

	} );

} );

describe( 'picking', () => {

	const square = [ [ 0, 0 ], [ 0.5, 0 ], [ 0.5, 0.5 ], [ 0, 0.5 ] ].map( ( start ) => ( { type: 'line', start } ) );

	it( 'picks the nearest vertex within the radius', () => {

		expect( pickVertex( square, [ 0.49, 0.02 ], 0.05 ) ).toBe( 1 );
		expect( pickVertex( square, [ 0.25, 0.25 ], 0.05 ) ).toBe( - 1 );
		expect( pickVertex( square, [ 0.02, 0.47 ], 0.05 ) ).toBe( 3 );

	} );

	it( 'picks edges and points inside', () => {

		expect( pickEdge( square, [ 0.51, 0.25 ], 0.02 ) ).toBe( 1 );
		expect( pickEdge( square, [ 0.25, 0.25 ], 0.02 ) ).toBe( - 1 );
		expect( pickEdge( MIXED, [ 0.437, 0.15 ], 0.002 ) ).toBe( 1 ); // on the arc's bulge (sagitta 3.75 cm)
		expect( pointInPolygon( [ 0.25, 0.25 ], square.map( ( s ) => s.start ) ) ).toBe( true );
		expect( pointInPolygon( [ 0.75, 0.25 ], square.map( ( s ) => s.start ) ) ).toBe( false );
		const theta = 4 * Math.atan( 0.25 ), r = 0.3 / ( 2 * Math.sin( theta / 2 ) );
		expect( bounds( flatten( MIXED, 1e-7 ).points ).max[ 0 ] ).toBeCloseTo( 0.4 + r * ( 1 - Math.cos( theta / 2 ) ), 6 ); // the sagitta

	} );

} );
