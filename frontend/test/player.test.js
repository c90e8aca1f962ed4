// The player on a synthetic try-on with the browser layout (docs/tryon-format.md, NEW): a
// walker node, garment chunks with scale channels, LINEAR one-hot weights, _PATTERN.
import { describe, it, expect } from 'vitest';
import * as THREE from 'three';
import { TryonPlayer } from '../src/player/player.js';
import { describeTryon, parseGarmentNodeName } from '../src/player/tryon-file.js';

const FPS = 10;

function quad( frames, firstFrame ) {

	const g = new THREE.BufferGeometry();
	const base = [ 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0 ];
	g.setAttribute( 'position', new THREE.Float32BufferAttribute( base, 3 ) );
	g.setAttribute( '_pattern', new THREE.Float32BufferAttribute( [ 0, 0, 1, 0, 1, 1, 0, 1 ], 2 ) );
	g.setIndex( [ 0, 1, 2, 0, 2, 3 ] );
	// frame f: the quad scaled by 1 + 0.05 f in x and y (a relative target)
	g.morphAttributes.position = [];
	for ( let k = 0; k < frames; k ++ ) {

		const f = firstFrame + k;
		g.morphAttributes.position.push( new THREE.Float32BufferAttribute( base.map( ( v, i ) => ( i % 3 === 2 ? 0 : v * 0.05 * f ) ), 3 ) );

	}

	g.morphTargetsRelative = true;
	const m = new THREE.Mesh( g, new THREE.MeshStandardMaterial() );
	m.updateMorphTargets();
	return m;

}

function oneHot( n ) {

	const v = [];
	for ( let i = 0; i < n; i ++ ) for ( let j = 0; j < n; j ++ ) v.push( i === j ? 1 : 0 );
	return v;

}

/** Frames 0..3 at 10 fps in two chunks of 3 targets sharing frame 2. */
function syntheticTryon() {

	const root = new THREE.Group();
	const walker = new THREE.Object3D();
	walker.name = 'walker';
	const c0 = new THREE.Object3D();
	c0.name = 'garmentquad#0';
	const c1 = new THREE.Object3D();
	c1.name = 'garmentquad#1';
	const m0 = quad( 3, 0 );
	m0.name = 'garmentquad#0_1';
	const m1 = quad( 2, 2 );
	m1.name = 'garmentquad#1_1';
	c0.add( m0 );
	c1.add( m1 );
	walker.add( c0, c1 );
	root.add( walker );
	const t = ( ...frames ) => frames.map( ( f ) => f / FPS );
	const tracks = [
		new THREE.VectorKeyframeTrack( 'walker.position', t( 0, 1, 2, 3 ), [ 0, 0, 0, 0, 0, 0.1, 0, 0, 0.2, 0, 0, 0.3 ] ),
		new THREE.VectorKeyframeTrack( 'garmentquad#0.scale', t( 0, 2 ), [ 1, 1, 1, 0, 0, 0 ], THREE.InterpolateDiscrete ),
		new THREE.VectorKeyframeTrack( 'garmentquad#1.scale', t( 0, 2 ), [ 0, 0, 0, 1, 1, 1 ], THREE.InterpolateDiscrete ),
		new THREE.NumberKeyframeTrack( 'garmentquad#0_1.morphTargetInfluences', t( 0, 1, 2 ), oneHot( 3 ) ),
		new THREE.NumberKeyframeTrack( 'garmentquad#1_1.morphTargetInfluences', t( 2, 3 ), oneHot( 2 ) ),
	];
	const clip = new THREE.AnimationClip( 'walk', - 1, tracks );
	clip.userData = { catwalk: { fps: FPS } };
	const names = [ 'walker', 'garment:quad#0', 'garment:quad#1' ];
	const associations = new Map( [ [ walker, { nodes: 0 } ], [ c0, { nodes: 1 } ], [ c1, { nodes: 2 } ] ] );
	return { scene: root, animations: [ clip ], parser: { associations, json: { nodes: names.map( ( name ) => ( { name } ) ) } }, userData: { catwalk: { version: 2 } } };

}

function fakeStage() {

	return {
		scene: new THREE.Scene(),
		camera: new THREE.PerspectiveCamera( 35, 1, 0.05, 100 ),
		controls: { target: new THREE.Vector3(), update() {} },
		setRunway( z0, z1 ) {

			this.runway = [ z0, z1 ];

		},
		lightAt() {},
		frame( target ) {

			this.controls.target.copy( target );

		},
	};

}

describe( 'a try-on file', () => {

	it( 'names its garments and chunks', () => {

		expect( parseGarmentNodeName( 'garment:dress#2' ) ).toEqual( { garment: 'dress', chunk: 2, chunked: true } );
		expect( parseGarmentNodeName( 'garment:pencil-skirt' ) ).toEqual( { garment: 'pencil-skirt', chunk: 0, chunked: false } );
		expect( parseGarmentNodeName( 'body' ) ).toBeNull();

	} );

	it( 'is described: walker, chunks in order, fps, duration, pattern', () => {

		const f = describeTryon( syntheticTryon() );
		expect( f.walker.name ).toBe( 'walker' );
		expect( f.garments.map( ( g ) => g.id ) ).toEqual( [ 'quad' ] );
		expect( f.garments[ 0 ].chunks.map( ( c ) => c.index ) ).toEqual( [ 0, 1 ] );
		expect( f.fps ).toBe( FPS );
		expect( f.duration ).toBeCloseTo( 0.3 );
		expect( f.frames ).toBe( 4 );
		expect( f.hasPattern ).toBe( true );
		expect( f.version ).toBe( 2 );

	} );

} );

describe( 'the player', () => {

	it( 'shows one chunk at a time, interpolating between frames', () => {

		const stage = fakeStage();
		const p = new TryonPlayer( stage, syntheticTryon() );
		expect( stage.runway[ 0 ] ).toBeCloseTo( 0 );
		expect( stage.runway[ 1 ] ).toBeCloseTo( 0.3 );

		p.setTime( 0.05 ); // halfway between frames 0 and 1, chunk 0
		expect( p.file.chunkNodes.map( ( n ) => n.visible ) ).toEqual( [ true, false ] );
		let v = p.garmentVertex( 2 ); // (1, 1) at scale 1.025, the walker at z 0.05
		expect( v[ 0 ] ).toBeCloseTo( 1.025, 5 );
		expect( v[ 1 ] ).toBeCloseTo( 1.025, 5 );
		expect( v[ 2 ] ).toBeCloseTo( 0.05, 5 );

		p.setTime( 0.25 ); // between frames 2 and 3: chunk 1
		expect( p.file.chunkNodes.map( ( n ) => n.visible ) ).toEqual( [ false, true ] );
		v = p.garmentVertex( 2 );
		expect( v[ 0 ] ).toBeCloseTo( 1.125, 5 );
		expect( v[ 2 ] ).toBeCloseTo( 0.25, 5 );

	} );

	it( 'follows the walker with the camera', () => {

		const stage = fakeStage();
		const p = new TryonPlayer( stage, syntheticTryon() );
		p.setTime( 0 );
		const z0 = stage.camera.position.z;
		p.setTime( 0.2 );
		expect( stage.camera.position.z - z0 ).toBeCloseTo( 0.2, 4 ); // along the walk's fitted line
		p.setFollow( false );
		p.setTime( 0.1 );
		const z1 = stage.camera.position.z;
		p.setTime( 0.2 );
		expect( stage.camera.position.z ).toBe( z1 );

	} );

	it( 'draws the fit map from the shown chunk’s stretch', () => {

		const p = new TryonPlayer( fakeStage(), syntheticTryon() );
		expect( p.setFitMap( true ) ).toBe( true );
		// just past frame 2 (float32 key times round 0.2 up here; catwalk's files round down)
		p.setTime( 0.2001 ); // scaled 1.10 → 10 % everywhere, in chunk 1
		expect( p.file.chunkNodes.map( ( n ) => n.visible ) ).toEqual( [ false, true ] );
		expect( p.fitMap.peak ).toBeCloseTo( 0.10, 3 );
		const mesh = p.file.garments[ 0 ].chunks[ 1 ].meshes[ 0 ];
		expect( mesh.material ).toBe( p.fitMap.material );
		const col = mesh.geometry.attributes.color;
		expect( col.getX( 0 ) ).toBeGreaterThan( col.getZ( 0 ) ); // warm: red over blue
		p.setTime( 0 ); // frame 0: unstretched
		expect( p.fitMap.peak ).toBeCloseTo( 0, 6 );
		p.setFitMap( false );
		expect( mesh.material ).not.toBe( p.fitMap.material );

	} );

	it( 'has no fit map without _PATTERN', () => {

		const gltf = syntheticTryon();
		gltf.scene.traverse( ( o ) => o.isMesh && o.geometry.deleteAttribute( '_pattern' ) );
		const p = new TryonPlayer( fakeStage(), gltf );
		expect( p.fitMap ).toBeNull();
		expect( p.setFitMap( true ) ).toBe( false );

	} );

	it( 'reads the pattern from TEXCOORD_1 (uv1) too, and lights each frame with its own normals', () => {

		const gltf = syntheticTryon();
		gltf.scene.traverse( ( o ) => {

			if ( ! o.isMesh ) return;
			o.geometry.setAttribute( 'uv1', o.geometry.attributes._pattern );
			o.geometry.deleteAttribute( '_pattern' );

		} );
		const p = new TryonPlayer( fakeStage(), gltf );
		expect( p.fitMap ).not.toBeNull();
		p.setFitMap( true );
		p.setTime( 0.1 ); // frame 1: 5 %
		expect( p.fitMap.peak ).toBeCloseTo( 0.05, 4 );
		const mesh = p.file.garments[ 0 ].chunks[ 0 ].meshes[ 0 ];
		const normal = mesh.geometry.attributes.normal;
		expect( normal.getZ( 0 ) ).toBeCloseTo( 1, 6 ); // the flat quad faces +z

	} );

} );
