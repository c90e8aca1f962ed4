// A 3D stage: renderer, camera, orbit controls, soft lighting and a floor with a runway.

import * as THREE from 'three';
import { OrbitControls } from 'three/examples/jsm/controls/OrbitControls.js';

const BACKGROUND = 0xefedea;

export class Stage {

	/** `container`: the element the canvas fills (it sizes the canvas). */
	constructor( container, { shadows = true, runway = true, label = '3D view' } = {} ) {

		this.container = container;
		const renderer = new THREE.WebGLRenderer( { antialias: true, powerPreference: 'high-performance', preserveDrawingBuffer: false } );
		renderer.setPixelRatio( Math.min( window.devicePixelRatio || 1, 2 ) );
		renderer.outputColorSpace = THREE.SRGBColorSpace;
		renderer.toneMapping = THREE.NeutralToneMapping;
		renderer.toneMappingExposure = 1.0;
		renderer.shadowMap.enabled = shadows;
		renderer.shadowMap.type = THREE.PCFShadowMap;
		renderer.domElement.className = 'stage__canvas';
		renderer.domElement.setAttribute( 'role', 'img' );
		renderer.domElement.setAttribute( 'aria-label', label );
		container.appendChild( renderer.domElement );
		this.renderer = renderer;

		const scene = new THREE.Scene();
		scene.background = new THREE.Color( BACKGROUND );
		scene.fog = new THREE.Fog( BACKGROUND, 5, 18 );
		this.scene = scene;

		this.camera = new THREE.PerspectiveCamera( 35, 1, 0.05, 100 );
		this.camera.position.set( 1.4, 1.4, 3.6 );

		const controls = new OrbitControls( this.camera, renderer.domElement );
		controls.target.set( 0, 0.95, 0 );
		controls.enableDamping = true;
		controls.dampingFactor = 0.12;
		controls.minDistance = 0.6;
		controls.maxDistance = 14;
		controls.maxPolarAngle = Math.PI * 0.495; // never under the floor
		controls.update();
		this.controls = controls;

		// Soft light: sky/ground hemisphere + one key light with soft shadows that follows the subject.
		const hemi = new THREE.HemisphereLight( 0xffffff, 0xb8b0a6, 1.7 );
		scene.add( hemi );
		const key = new THREE.DirectionalLight( 0xffffff, 2.0 );
		key.position.set( 2.5, 5, 3.5 );
		key.castShadow = shadows;
		key.shadow.mapSize.set( 1024, 1024 );
		key.shadow.camera.left = - 1.6;
		key.shadow.camera.right = 1.6;
		key.shadow.camera.top = 2.2;
		key.shadow.camera.bottom = - 0.6;
		key.shadow.camera.near = 0.5;
		key.shadow.camera.far = 14;
		key.shadow.bias = - 0.0004;
		key.shadow.normalBias = 0.02;
		key.shadow.radius = 4;
		scene.add( key );
		scene.add( key.target );
		this.key = key;
		this.keyOffset = key.position.clone();
		const fill = new THREE.DirectionalLight( 0xfff4ea, 0.6 );
		fill.position.set( - 3, 2.5, - 2 );
		scene.add( fill );

		const floor = new THREE.Mesh(
			new THREE.CircleGeometry( 30, 64 ),
			new THREE.MeshStandardMaterial( { color: 0xe4e0da, roughness: 1, metalness: 0 } ),
		);
		floor.rotation.x = - Math.PI / 2;
		floor.receiveShadow = shadows;
		floor.name = 'floor';
		scene.add( floor );
		this.floor = floor;

		if ( runway ) {

			const strip = new THREE.Mesh(
				new THREE.PlaneGeometry( 1.5, 1 ),
				new THREE.MeshStandardMaterial( { color: 0xf8f6f2, roughness: 0.9, metalness: 0 } ),
			);
			strip.rotation.x = - Math.PI / 2;
			strip.position.y = 0.001;
			strip.receiveShadow = shadows;
			strip.name = 'runway';
			scene.add( strip );
			this.runway = strip;
			this.setRunway( - 1, 6 );

		}

		this.resizeObserver = new ResizeObserver( () => this.resize() );
		this.resizeObserver.observe( container );
		this.resize();
		this.disposed = false;

	}

	/** Lay the runway from z0 to z1 (metres), two metres beyond each end. */
	setRunway( z0, z1 ) {

		if ( ! this.runway ) return;
		const len = Math.max( 2, z1 - z0 + 4 );
		this.runway.scale.set( 1, len, 1 );
		this.runway.position.z = ( z0 + z1 ) / 2;

	}

	/** Keep the key light (and its shadow camera) over `point`. */
	lightAt( point ) {

		this.key.position.copy( point ).add( this.keyOffset );
		this.key.target.position.copy( point );
		this.key.target.updateMatrixWorld();

	}

	resize() {

		const w = Math.max( 1, this.container.clientWidth );
		const h = Math.max( 1, this.container.clientHeight );
		if ( w === this.width && h === this.height ) return;
		this.width = w;
		this.height = h;
		this.renderer.setSize( w, h, true );
		this.camera.aspect = w / h;
		this.camera.updateProjectionMatrix();

	}

	render() {

		if ( this.disposed ) return;
		this.controls.update();
		this.renderer.render( this.scene, this.camera );

	}

	/** Point the camera at `target` from `direction` (unit-ish vector) so a box of `height` fits. */
	frame( target, direction, height = 1.9, margin = 1.15 ) {

		const fov = THREE.MathUtils.degToRad( this.camera.fov );
		const aspect = Math.max( 0.3, this.camera.aspect );
		const fitH = ( height * margin ) / 2 / Math.tan( fov / 2 );
		const fitW = ( height * 0.55 * margin ) / 2 / ( Math.tan( fov / 2 ) * aspect );
		const dist = Math.max( fitH, fitW, 1.2 );
		const dir = direction.clone().normalize();
		this.controls.target.copy( target );
		this.camera.position.copy( target ).addScaledVector( dir, dist );
		this.controls.update();

	}

	dispose() {

		if ( this.disposed ) return;
		this.disposed = true;
		this.resizeObserver.disconnect();
		this.controls.dispose();
		this.scene.traverse( ( o ) => {

			if ( o.geometry ) o.geometry.dispose();
			const mats = Array.isArray( o.material ) ? o.material : o.material ? [ o.material ] : [];
			for ( const m of mats ) {

				for ( const v of Object.values( m ) ) if ( v && v.isTexture ) v.dispose();
				m.dispose();

			}

		} );
		this.renderer.setAnimationLoop( null );
		this.renderer.dispose();
		this.renderer.forceContextLoss(); // browsers keep only a few live contexts
		this.renderer.domElement.remove();

	}

}
