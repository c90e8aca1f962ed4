// One clip per garment chunk: the mixer evaluates only the chunk on show, so a frame costs the
// same whatever the try-on's length (the file's clip holds every chunk's morph-weight tracks:
// 5 chunks for 10 s, each track 64 weights wide).

import * as THREE from 'three';

/** The names a track can bind to, for every object under `node` (three.js binds a track to an
 * object by name, or by uuid when it has none). */
function bindNames( node ) {

	const names = new Set();
	node.traverse( ( o ) => {

		if ( o.name ) names.add( o.name );
		names.add( o.uuid );

	} );
	return names;

}

/**
 * Split `clip` into `{ base, chunks: [{ clip, start }] }`: `base` the tracks of everything but
 * the garment chunks (the body's bones), one clip per chunk with its morph-weight tracks
 * (its scale tracks dropped: the player shows the chunk whose window holds the time), and each
 * chunk's `start`: its first key's time.
 */
export function splitByChunk( clip, chunkNodes ) {

	const owners = chunkNodes.map( bindNames );
	const base = [];
	const per = chunkNodes.map( () => [] );
	for ( const track of clip.tracks ) {

		const { nodeName, propertyName } = THREE.PropertyBinding.parseTrackName( track.name );
		const k = owners.findIndex( ( names ) => names.has( nodeName ) );
		if ( k < 0 ) base.push( track );
		else if ( propertyName !== 'scale' ) per[ k ].push( track );

	}

	const chunks = per.map( ( tracks, k ) => ( {
		clip: new THREE.AnimationClip( `${ clip.name }#${ k }`, clip.duration, tracks ),
		start: tracks.length ? tracks[ 0 ].times[ 0 ] : 0,
	} ) );
	return { base: new THREE.AnimationClip( clip.name, clip.duration, base ), chunks };

}

/** The chunk on show at `t`: the last one (of one garment, in order) starting at or before `t`. */
export function chunkAt( starts, t ) {

	let k = 0;
	for ( let i = 1; i < starts.length; i ++ ) if ( starts[ i ] <= t ) k = i;
	return k;

}
