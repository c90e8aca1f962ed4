// What a try-on .glb holds, found in the loaded glTF (docs/tryon-format.md): the skinned body,
// each garment's chunk nodes (`garment:<id>#<k>`, or one `garment:<id>` in older files), the
// `walker` node (if any), the clip `walk`, its fps and duration, and whether the fit map can be
// drawn (the pattern coordinates: TEXCOORD_1, or `_PATTERN` in early version-2 files).

import { fpsFromTimes } from './timeline.js';
import { patternAttribute } from './garment-mesh.js';

/** `garment:dress#2` → { garment: 'dress', chunk: 2 }; `garment:dress` → chunk 0; else null. */
export function parseGarmentNodeName( name ) {

	const m = /^garment:(.+?)(?:#(\d+))?$/.exec( name || '' );
	if ( ! m ) return null;
	return { garment: m[ 1 ], chunk: m[ 2 ] === undefined ? 0 : Number( m[ 2 ] ), chunked: m[ 2 ] !== undefined };

}

/** The glTF node name an object was loaded from (three.js sanitises object names). */
function gltfName( gltf, object ) {

	const assoc = gltf.parser && gltf.parser.associations ? gltf.parser.associations.get( object ) : null;
	if ( assoc && assoc.nodes !== undefined ) {

		const def = gltf.parser.json.nodes[ assoc.nodes ];
		return def && def.name ? def.name : null;

	}

	return null;

}

export function describeTryon( gltf ) {

	const root = gltf.scene;
	const clip = gltf.animations.find( ( a ) => a.name === 'walk' ) || gltf.animations[ 0 ] || null;

	const bodies = [];
	const byGarment = new Map();
	let walker = null;
	root.traverse( ( o ) => {

		if ( o.isSkinnedMesh ) bodies.push( o );
		const name = gltfName( gltf, o );
		if ( name === 'walker' ) walker = o;
		const g = name ? parseGarmentNodeName( name ) : null;
		if ( ! g ) return;
		if ( ! byGarment.has( g.garment ) ) byGarment.set( g.garment, { id: g.garment, chunks: [] } );
		byGarment.get( g.garment ).chunks.push( { index: g.chunk, node: o, meshes: [] } );

	} );

	const garments = [ ...byGarment.values() ];
	for ( const g of garments ) {

		g.chunks.sort( ( a, b ) => a.index - b.index );
		for ( const c of g.chunks ) {

			c.node.traverse( ( o ) => {

				if ( o.isMesh && ! o.isSkinnedMesh ) c.meshes.push( o );

			} );

		}

	}

	// fps: the clip's extras, a garment mesh's extras, else the keyframe times.
	let fps = clip && clip.userData && clip.userData.catwalk && clip.userData.catwalk.fps;
	if ( ! fps ) {

		for ( const g of garments ) for ( const c of g.chunks ) for ( const m of c.meshes ) {

			const e = m.userData && m.userData.catwalk;
			if ( ! fps && e && e.fps ) fps = e.fps;

		}

	}

	if ( ! fps && clip ) {

		const track = clip.tracks.find( ( t ) => t.name.endsWith( '.morphTargetInfluences' ) ) || clip.tracks[ 0 ];
		fps = track ? fpsFromTimes( track.times ) : 30;

	}

	const garmentMeshes = garments.flatMap( ( g ) => g.chunks.flatMap( ( c ) => c.meshes ) );
	const hasPattern = garmentMeshes.length > 0 && garmentMeshes.every( ( m ) => !! patternAttribute( m.geometry ) );
	const duration = clip ? clip.duration : 0;
	const frames = garmentMeshes.length ? Math.round( duration * ( fps || 30 ) ) + 1 : 0;

	return {
		root,
		clip,
		duration,
		fps: fps || 30,
		frames,
		bodies,
		walker,
		garments,
		chunkNodes: garments.flatMap( ( g ) => g.chunks.map( ( c ) => c.node ) ),
		garmentMeshes,
		hasPattern,
		version: gltf.userData && gltf.userData.catwalk ? gltf.userData.catwalk.version : null,
	};

}
