// glTF loading: try-on files are meshopt-compressed (EXT_meshopt_compression +
// KHR_mesh_quantization), bodies are plain glTF.

import { GLTFLoader } from 'three/examples/jsm/loaders/GLTFLoader.js';
import { MeshoptDecoder } from 'three/examples/jsm/libs/meshopt_decoder.module.js';

let loader = null;

export function gltfLoader() {

	if ( ! loader ) {

		loader = new GLTFLoader();
		loader.setMeshoptDecoder( MeshoptDecoder );

	}

	return loader;

}

/** Load a .glb; `onProgress(fraction | null)` while it downloads. */
export function loadGlb( url, onProgress = () => {} ) {

	return gltfLoader().loadAsync( url, ( e ) => {

		onProgress( e.lengthComputable && e.total > 0 ? e.loaded / e.total : null );

	} );

}
