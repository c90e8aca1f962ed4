// A body in 3D: body.glb on a Stage, orbit controls, framed from the front.

import * as THREE from 'three';
import { Stage } from './stage.js';
import { loadGlb } from './loader.js';
import { startLoop } from './loop.js';

export async function showBody( container, url, { signal } = {} ) {

	const stage = new Stage( container, { runway: false, label: 'Your body in 3D; drag to turn it' } );
	const stop = startLoop( () => stage.render() );
	const dispose = () => {

		stop();
		stage.dispose();

	};

	signal?.addEventListener( 'abort', dispose, { once: true } );
	const gltf = await loadGlb( url );
	if ( signal?.aborted ) return null;
	const root = gltf.scene;
	root.traverse( ( o ) => {

		if ( o.isMesh ) {

			o.frustumCulled = false;
			o.castShadow = true;
			o.receiveShadow = true;

		}

	} );
	stage.scene.add( root );
	root.updateMatrixWorld( true );
	const box = new THREE.Box3().setFromObject( root );
	const height = box.isEmpty() ? 1.7 : box.max.y - Math.max( 0, box.min.y );
	const centre = box.getCenter( new THREE.Vector3() );
	stage.lightAt( new THREE.Vector3( centre.x, 0, centre.z ) );
	stage.frame( new THREE.Vector3( centre.x, height * 0.5, centre.z ), new THREE.Vector3( 0.35, 0.08, 1 ), height * 1.05 );
	return { stage, height, dispose };

}
