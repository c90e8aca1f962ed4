// The try-on player: one loaded try-on on a Stage, driven to any time by the AnimationMixer
// (body bones and garment morph weights from one clip), chunk visibility, camera presets that
// can follow the walker, and the fit map.

import * as THREE from 'three';
import { describeTryon } from './tryon-file.js';
import { clampTime } from './timeline.js';
import { chunkAt, splitByChunk } from './chunk-clips.js';
import { FitMap } from './fitmap.js';
import { GarmentMesh } from './garment-mesh.js';

/** Least-squares line through (t, v): `{ a, b }` with v ≈ a + b t. */
export function fitLine( ts, vs ) {

	const n = ts.length;
	if ( n === 0 ) return { a: 0, b: 0 };
	let st = 0, sv = 0, stt = 0, stv = 0;
	for ( let i = 0; i < n; i ++ ) {

		st += ts[ i ];
		sv += vs[ i ];
		stt += ts[ i ] * ts[ i ];
		stv += ts[ i ] * vs[ i ];

	}

	const d = n * stt - st * st;
	if ( Math.abs( d ) < 1e-12 ) return { a: sv / n, b: 0 };
	const b = ( n * stv - st * sv ) / d;
	return { a: ( sv - b * st ) / n, b };

}

export const VIEWS = {
	front: new THREE.Vector3( 0.12, 0.1, 1 ),
	side: new THREE.Vector3( 1, 0.1, 0.04 ),
	back: new THREE.Vector3( - 0.12, 0.1, - 1 ),
};

const _p = new THREE.Vector3();
const _q = new THREE.Vector3();
const _box = new THREE.Box3();

export class TryonPlayer {

	constructor( stage, gltf ) {

		this.stage = stage;
		this.gltf = gltf;
		const file = describeTryon( gltf );
		this.file = file;
		stage.scene.add( file.root );

		// The skinned body's bounds are computed once at the bind pose: draw it wherever it walks.
		for ( const b of file.bodies ) {

			b.frustumCulled = false;
			b.castShadow = true;
			b.receiveShadow = true;

		}

		for ( const m of file.garmentMeshes ) {

			m.frustumCulled = false;
			m.castShadow = true;

		}

		file.root.updateMatrixWorld( true );
		_box.makeEmpty();
		for ( const b of file.bodies ) _box.expandByObject( b );
		this.height = _box.isEmpty() ? 1.7 : Math.min( 2.3, Math.max( 1.2, _box.max.y - Math.max( 0, _box.min.y ) ) );

		// the body's tracks in one action, each garment chunk's in its own, enabled only while
		// the chunk is on show (the mixer then skips the others: a frame's cost does not grow
		// with the try-on's length)
		this.mixer = new THREE.AnimationMixer( file.root );
		this.action = null;
		this.chunkPlay = []; // per garment: { nodes, starts, actions }
		if ( file.clip ) {

			const nodes = file.chunkNodes;
			const { base, chunks } = splitByChunk( file.clip, nodes );
			this.action = this.mixer.clipAction( base );
			this.action.play();
			let i = 0;
			for ( const g of file.garments ) {

				const own = chunks.slice( i, i + g.chunks.length );
				const actions = own.map( ( c ) => this.mixer.clipAction( c.clip ).play() );
				this.chunkPlay.push( { nodes: g.chunks.map( ( c ) => c.node ), starts: own.map( ( c ) => c.start ), actions } );
				i += g.chunks.length;

			}

		}
		this.fitMap = file.hasPattern ? new FitMap( file.garmentMeshes ) : null;
		this.states = new Map(); // garment mesh → GarmentMesh, made when first shown
		this.time = 0;
		this.view = 'front';
		this.follow = true;
		this.lastWalker = new THREE.Vector3();

		// The walk's path: for the runway, the fixed views, and a steady line for the camera to
		// follow (the pelvis sways and bobs; a camera on it would too).
		this.path = new THREE.Box3();
		const n = 48;
		const ts = [], xs = [], zs = [];
		for ( let i = 0; i <= n; i ++ ) {

			const t = ( i / n ) * file.duration;
			this.applyTime( t );
			const p = this.walkerPosition( _p );
			this.path.expandByPoint( p );
			ts.push( t );
			xs.push( p.x );
			zs.push( p.z );

		}

		this.line = { x: fitLine( ts, xs ), z: fitLine( ts, zs ) };
		stage.setRunway( this.path.min.z, this.path.max.z );
		this.setTime( 0 );
		this.setView( 'front' );

	}

	get duration() {

		return this.file.duration;

	}

	get fps() {

		return this.file.fps;

	}

	/** Where the walker is on the floor (y = 0): the `walker` node, else the pelvis. */
	walkerPosition( out ) {

		const f = this.file;
		if ( f.walker ) f.walker.getWorldPosition( out );
		else {

			const body = f.bodies[ 0 ];
			const bone = body && body.skeleton ? ( body.skeleton.getBoneByName( 'pelvis' ) || body.skeleton.bones[ 0 ] ) : null;
			if ( bone ) bone.getWorldPosition( out );
			else out.set( 0, 0, 0 );

		}

		out.y = 0;
		return out;

	}

	/** The point the camera follows at time `t`: the walk's straight line. */
	followPoint( t, out ) {

		const { x, z } = this.line;
		return out.set( x.a + x.b * t, 0, z.a + z.b * t );

	}

	/** The shown garment meshes, morphed on the CPU when something needs their shape. */
	shownStates() {

		const needShape = this.fitMap && this.fitMap.enabled;
		const out = [];
		for ( const g of this.file.garments ) {

			for ( const c of g.chunks ) {

				if ( ! c.node.visible ) continue;
				for ( const m of c.meshes ) {

					let s = this.states.get( m );
					if ( ! s ) {

						s = new GarmentMesh( m );
						this.states.set( m, s );

					}

					if ( needShape || s.ownNormals ) s.update();
					out.push( s );

				}

			}

		}

		return out;

	}

	applyTime( t ) {

		this.time = clampTime( t, this.file.duration );
		for ( const g of this.chunkPlay ) {

			const on = chunkAt( g.starts, this.time );
			g.actions.forEach( ( a, k ) => {

				a.enabled = k === on;

			} );
			g.nodes.forEach( ( n, k ) => {

				n.visible = k === on;
				n.scale.setScalar( 1 );

			} );

		}

		if ( this.action ) this.mixer.setTime( this.time );
		this.file.root.updateMatrixWorld( true );

	}

	/** Show the try-on at time `t` (seconds). */
	setTime( t ) {

		this.applyTime( t );
		const states = this.shownStates();
		if ( this.fitMap ) this.fitMap.update( states );
		const p = this.followPoint( this.time, _p );
		if ( this.follow ) {

			_q.subVectors( p, this.lastWalker );
			this.stage.camera.position.add( _q );
			this.stage.controls.target.add( _q );

		}

		this.lastWalker.copy( p );
		this.stage.lightAt( p );

	}

	/** Camera preset: `front`, `side` or `back`; following the walker or framing the whole walk. */
	setView( view = this.view ) {

		this.view = view;
		const dir = VIEWS[ view ] || VIEWS.front;
		const h = this.height;
		if ( this.follow ) {

			const p = this.followPoint( this.time, _p );
			this.stage.frame( _q.set( p.x, h * 0.52, p.z ), dir, h * 1.08 );

		} else {

			const c = this.path.getCenter( _p );
			const along = Math.max( 0.5, this.path.max.z - this.path.min.z );
			// side: the whole walk across the view; front/back: the far end of the runway
			const span = view === 'side' ? along + 1.0 : 1.0;
			const target = _q.set( c.x, h * 0.5, c.z );
			this.stage.frame( target, dir, Math.max( h * 1.1, span / Math.max( 0.5, this.stage.camera.aspect ) ), 1.1 );
			if ( view !== 'side' ) {

				// keep the walker whole at the near end too
				const d = this.stage.camera.position.distanceTo( target );
				this.stage.camera.position.copy( target ).addScaledVector( dir.clone().normalize(), d + along / 2 );
				this.stage.controls.update();

			}

		}

	}

	setFollow( on ) {

		this.follow = on;
		this.setView( this.view );

	}

	setFitMap( on ) {

		if ( ! this.fitMap ) return false;
		this.fitMap.setEnabled( on );
		this.fitMap.update( this.shownStates() );
		return true;

	}

	/** For tests: vertex `i` of the first shown garment mesh, in world space, at the current time. */
	garmentVertex( i = 0 ) {

		for ( const c of this.file.garments.flatMap( ( g ) => g.chunks ) ) {

			if ( ! c.node.visible || ! c.meshes.length ) continue;
			const m = c.meshes[ 0 ];
			m.getVertexPosition( i, _p );
			m.localToWorld( _p );
			return [ _p.x, _p.y, _p.z ];

		}

		return null;

	}

	dispose() {

		this.mixer.stopAllAction();
		if ( this.file.clip ) this.mixer.uncacheClip( this.file.clip );
		if ( this.fitMap ) this.fitMap.dispose();
		this.stage.scene.remove( this.file.root );

	}

}
