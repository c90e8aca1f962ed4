import { describe, expect, it } from 'vitest';
import * as THREE from 'three';
import { chunkAt, splitByChunk } from '../src/player/chunk-clips.js';

function chunkNode( name ) {

	const group = new THREE.Group();
	group.name = name;
	const mesh = new THREE.Mesh();
	mesh.name = `${ name }_0`;
	group.add( mesh );
	return group;

}

describe( 'one clip per chunk', () => {

	it( 'keeps the body in the base clip and each chunk\'s weights in its own, without scales', () => {

		const nodes = [ chunkNode( 'garmentdress0' ), chunkNode( 'garmentdress1' ) ];
		const clip = new THREE.AnimationClip( 'walk', 4, [
			new THREE.QuaternionKeyframeTrack( 'pelvis.quaternion', [ 0, 4 ], [ 0, 0, 0, 1, 0, 0, 0, 1 ] ),
			new THREE.NumberKeyframeTrack( 'garmentdress0_0.morphTargetInfluences', [ 0, 2.1 ], [ 1, 0, 0, 1 ] ),
			new THREE.VectorKeyframeTrack( 'garmentdress0.scale', [ 0, 2.1 ], [ 1, 1, 1, 0, 0, 0 ] ),
			new THREE.NumberKeyframeTrack( 'garmentdress1_0.morphTargetInfluences', [ 2.1, 4 ], [ 1, 0, 0, 1 ] ),
			new THREE.VectorKeyframeTrack( 'garmentdress1.scale', [ 0, 2.1 ], [ 0, 0, 0, 1, 1, 1 ] ),
		] );
		const { base, chunks } = splitByChunk( clip, nodes );
		expect( base.tracks.map( ( t ) => t.name ) ).toEqual( [ 'pelvis.quaternion' ] );
		expect( chunks.map( ( c ) => c.clip.tracks.map( ( t ) => t.name ) ) ).toEqual( [
			[ 'garmentdress0_0.morphTargetInfluences' ], [ 'garmentdress1_0.morphTargetInfluences' ] ] );
		expect( chunks.map( ( c ) => c.start ) ).toEqual( [ 0, Math.fround( 2.1 ) ] ); // key times are float32
		expect( chunks.every( ( c ) => c.clip.duration === 4 ) ).toBe( true );

	} );

	it( 'shows the last chunk starting at or before the time', () => {

		const starts = [ 0, 2.1, 4.2 ];
		expect( chunkAt( starts, 0 ) ).toBe( 0 );
		expect( chunkAt( starts, 2.0999 ) ).toBe( 0 );
		expect( chunkAt( starts, 2.1 ) ).toBe( 1 );
		expect( chunkAt( starts, 9 ) ).toBe( 2 );
		expect( chunkAt( [ 0 ], 5 ) ).toBe( 0 );

	} );

} );
