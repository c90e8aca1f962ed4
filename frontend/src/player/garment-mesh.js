// One garment mesh (a panel of a chunk) as the player keeps it on the CPU: its morphed
// positions at the shown time, and its normals when the file carries no NORMAL targets.

import * as THREE from 'three';
import { morphPositions, computeNormals } from './morph.js';

/** The pattern coordinates (metres, the rest shape): `TEXCOORD_1` (three.js `uv1`), or `_PATTERN`. */
export function patternAttribute( geometry ) {

	return geometry.attributes._pattern || geometry.attributes.uv1 || null;

}

export function readVec( attr, size ) {

	const n = attr.count;
	const out = new Float32Array( n * size );
	for ( let i = 0; i < n; i ++ ) {

		out[ size * i ] = attr.getX( i );
		out[ size * i + 1 ] = attr.getY( i );
		if ( size > 2 ) out[ size * i + 2 ] = attr.getZ( i );

	}

	return out;

}

export class GarmentMesh {

	constructor( mesh ) {

		const g = mesh.geometry;
		this.mesh = mesh;
		this.count = g.attributes.position.count;
		this.index = g.index ? g.index.array : null;
		this.base = readVec( g.attributes.position, 3 );
		this.morph = ( g.morphAttributes && g.morphAttributes.position ) || [];
		this.targets = new Array( this.morph.length ).fill( null );
		this.local = new Float32Array( this.count * 3 );
		this.stamp = null;
		// Without NORMAL targets three.js would light every frame with the first one's normals.
		const hasNormalTargets = !! ( g.morphAttributes && g.morphAttributes.normal && g.morphAttributes.normal.length );
		this.ownNormals = this.morph.length > 1 && ! hasNormalTargets;
		if ( this.ownNormals ) {

			this.normals = new THREE.BufferAttribute( new Float32Array( this.count * 3 ), 3 );
			this.normals.setUsage( THREE.DynamicDrawUsage );
			g.setAttribute( 'normal', this.normals );

		}

	}

	/** Morph on the CPU for the mesh's current influences (once per distinct set). */
	update() {

		const weights = this.mesh.morphTargetInfluences || [];
		let stamp = '';
		for ( let k = 0; k < weights.length; k ++ ) {

			if ( weights[ k ] === 0 ) continue;
			stamp += `${ k }:${ weights[ k ] };`;
			if ( ! this.targets[ k ] && this.morph[ k ] ) this.targets[ k ] = readVec( this.morph[ k ], 3 );

		}

		if ( stamp === this.stamp ) return false;
		this.stamp = stamp;
		morphPositions( this.base, this.targets, weights, this.local );
		if ( this.ownNormals ) {

			computeNormals( this.local, this.index, this.normals.array );
			this.normals.needsUpdate = true;

		}

		return true;

	}

}
