// The fit map on the garment: for every shown frame, each vertex's stretch against the flat
// pattern (TEXCOORD_1 / _PATTERN, metres), from the morphed positions of the shown chunk, as
// vertex colours on a plain material.

import * as THREE from 'three';
import { buildEdges, computeStretch, stretchColour, STRAIN_LIMIT } from './stretch.js';
import { patternAttribute, readVec } from './garment-mesh.js';

const LUT_SIZE = 256;

function colourTable( limit ) {

	// linear-space colours for stretch 0 … limit (the renderer works in linear, outputs sRGB)
	const lut = new Float32Array( LUT_SIZE * 3 );
	const c = new THREE.Color();
	const rgb = [ 0, 0, 0 ];
	for ( let i = 0; i < LUT_SIZE; i ++ ) {

		stretchColour( ( i / ( LUT_SIZE - 1 ) ) * limit, limit, rgb );
		c.setRGB( rgb[ 0 ], rgb[ 1 ], rgb[ 2 ], THREE.SRGBColorSpace );
		lut[ 3 * i ] = c.r;
		lut[ 3 * i + 1 ] = c.g;
		lut[ 3 * i + 2 ] = c.b;

	}

	return lut;

}

/** One garment mesh's stretch, kept between frames. */
class MeshStretch {

	constructor( state ) {

		const g = state.mesh.geometry;
		this.state = state;
		this.edges = buildEdges( state.index, state.count, readVec( patternAttribute( g ), 2 ) );
		this.world = new Float32Array( state.count * 3 );
		this.stretch = new Float32Array( state.count );
		this.colors = new THREE.BufferAttribute( new Float32Array( state.count * 3 ), 3 );
		this.colors.setUsage( THREE.DynamicDrawUsage );
		g.setAttribute( 'color', this.colors );
		this.peak = 0;

	}

	update( lut, limit ) {

		const { mesh, local } = this.state;
		// to world metres: quantised files carry a dequantising scale on the node
		const e = mesh.matrixWorld.elements;
		const W = this.world;
		for ( let i = 0; i < local.length; i += 3 ) {

			const x = local[ i ], y = local[ i + 1 ], z = local[ i + 2 ];
			W[ i ] = e[ 0 ] * x + e[ 4 ] * y + e[ 8 ] * z + e[ 12 ];
			W[ i + 1 ] = e[ 1 ] * x + e[ 5 ] * y + e[ 9 ] * z + e[ 13 ];
			W[ i + 2 ] = e[ 2 ] * x + e[ 6 ] * y + e[ 10 ] * z + e[ 14 ];

		}

		computeStretch( W, this.edges, this.stretch );
		const col = this.colors.array;
		let peak = 0;
		for ( let i = 0; i < this.stretch.length; i ++ ) {

			const s = this.stretch[ i ];
			if ( s > peak ) peak = s;
			const j = 3 * Math.min( LUT_SIZE - 1, Math.round( ( s / limit ) * ( LUT_SIZE - 1 ) ) );
			col[ 3 * i ] = lut[ j ];
			col[ 3 * i + 1 ] = lut[ j + 1 ];
			col[ 3 * i + 2 ] = lut[ j + 2 ];

		}

		this.peak = peak;
		this.colors.needsUpdate = true;

	}

}

export class FitMap {

	/** `meshes`: every garment mesh of the file. */
	constructor( meshes, { limit = STRAIN_LIMIT } = {} ) {

		this.meshes = meshes;
		this.limit = limit;
		this.lut = colourTable( limit );
		this.enabled = false;
		this.peak = 0;
		this.cache = new Map(); // GarmentMesh → MeshStretch (made the first time it is shown)
		this.material = new THREE.MeshStandardMaterial( {
			vertexColors: true, side: THREE.DoubleSide, roughness: 0.85, metalness: 0, name: 'fit-map',
		} );

	}

	setEnabled( on ) {

		this.enabled = on;
		for ( const m of this.meshes ) {

			if ( on ) {

				if ( ! m.userData.ownMaterial ) m.userData.ownMaterial = m.material;
				m.material = this.material;

			} else if ( m.userData.ownMaterial ) {

				m.material = m.userData.ownMaterial;

			}

		}

	}

	/** Recolour the shown meshes (`states`: their GarmentMesh, morphed for this time). */
	update( states ) {

		if ( ! this.enabled ) return;
		let peak = 0;
		for ( const state of states ) {

			let s = this.cache.get( state );
			if ( ! s ) {

				s = new MeshStretch( state );
				this.cache.set( state, s );

			}

			s.update( this.lut, this.limit );
			peak = Math.max( peak, s.peak );

		}

		this.peak = peak;

	}

	dispose() {

		this.material.dispose();

	}

}
