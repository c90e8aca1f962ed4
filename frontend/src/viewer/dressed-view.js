// A garment dressed on its sample body, standing (GET /api/garments/{id}/dressed.glb: a
// one-frame try-on file), on a Stage with orbit controls; the fit map can be shown on it.

import { Stage } from './stage.js';
import { loadGlb } from './loader.js';
import { startLoop } from './loop.js';
import { TryonPlayer } from '../player/player.js';

export async function showDressed( container, url, { signal, label = 'The garment on a sample body; drag to turn it' } = {} ) {

	const stage = new Stage( container, { runway: false, label } );
	const stop = startLoop( () => stage.render() );
	let player = null;
	const dispose = () => {

		stop();
		if ( player ) player.dispose();
		stage.dispose();

	};

	signal?.addEventListener( 'abort', dispose, { once: true } );
	let gltf;
	try {

		gltf = await loadGlb( url );

	} catch ( err ) {

		dispose();
		throw err;

	}

	if ( signal?.aborted ) return null;
	player = new TryonPlayer( stage, gltf );
	player.setTime( 0 );
	return { stage, player, dispose };

}
