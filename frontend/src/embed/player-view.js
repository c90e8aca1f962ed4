// The component's player, loaded (with three.js) only once a try-on is asked for: the same
// Stage, TryonPlayer and controls as catwalk's try-on page (fit map, camera, speed, timeline).
// Its stage is made while the try-on is simulated (a WebGL context takes a while), so the walk
// shows soon after the result is ready (`catwalk bench player`).

import { Stage } from '../viewer/stage.js';
import { loadGlb } from '../viewer/loader.js';
import { TryonPlayer } from '../player/player.js';
import { startSession } from '../player/session.js';

export const hasWebGL2 = () => 'WebGL2RenderingContext' in window;

/** A Stage in `view` (a sized element), made ahead of the result; null without WebGL 2. */
export function prepareStage( view, label ) {

	if ( ! hasWebGL2() ) return null;
	try {

		return new Stage( view, { label } );

	} catch {

		return null;

	}

}

/**
 * The walk from `url` on `stage` (made now if none was prepared in `view`), with its controls
 * in `controlsBox`; `onProgress(fraction | null)` while the file downloads. Resolves to
 * `{ player, stage, dispose }`.
 */
export async function playTryon( { view, stage, url, label, controlsBox, keyTarget, tryon, onProgress } ) {

	const download = loadGlb( url, onProgress ); // the file comes while the stage is made
	download.catch( () => {} );
	let own = stage || new Stage( view, { label } );
	own.resize();
	let gltf;
	try {

		gltf = await download;

	} catch ( err ) {

		own.dispose();
		own = null;
		throw err;

	}

	performance.mark( 'catwalk:result-loaded' );
	const player = new TryonPlayer( own, gltf );
	player.tryon = tryon;
	const fps = ( tryon.metrics && tryon.metrics.fps ) || player.fps;
	const session = startSession( { players: [ player ], stages: [ own ], controlsBox, keyTarget, fps } );
	return {
		player,
		stage: own,
		dispose() {

			session.dispose();
			player.dispose();
			own.dispose();

		},
	};

}
