// Players on one clock: a Transport, the animation loop, the controls, and the debug hook
// (`window.__catwalk.player`: time(), garmentVertex(i), … — for tests).

import { Transport } from './timeline.js';
import { createControls } from './controls.js';
import { startLoop } from '../viewer/loop.js';

export function startSession( { players, stages, controlsBox, keyTarget, fps = 30, downloads = [], fitMapNote = null, autoplay = true } ) {

	const duration = Math.max( ...players.map( ( p ) => p.duration ) );
	const transport = new Transport( duration );
	const controls = createControls( { transport, players, fps, downloads, fitMapNote } );
	controlsBox.append( controls.el );
	keyTarget.addEventListener( 'keydown', controls.onKey );

	let shown = - 1;
	let frames = 0;
	const show = () => {

		const t = transport.shownTime();
		if ( t === shown ) return;
		shown = t;
		for ( const p of players ) p.setTime( Math.min( t, p.duration ) );

	};

	const work = []; // ms of the page's own work per frame (clock, morphs, fit map, draw calls)
	const stop = startLoop( ( dt ) => {

		const t0 = performance.now();
		transport.tick( dt );
		show();
		for ( const s of stages ) s.render();
		frames ++;
		if ( frames === 1 ) performance.mark( 'catwalk:first-frame' );
		work.push( performance.now() - t0 );
		if ( work.length > 600 ) work.shift();

	} );
	show();
	if ( autoplay ) transport.play();

	const hook = {
		time: () => transport.shownTime(),
		duration: () => transport.duration,
		playing: () => transport.playing,
		frames: () => frames,
		// the page's work per frame over the last (up to) 600 frames: { n, mean, median, p95 } in ms
		resetFrameWork: () => {

			work.length = 0;

		},
		frameWork: () => {

			const w = [ ...work ].sort( ( x, y ) => x - y );
			const n = w.length;
			const at = ( q ) => ( n ? w[ Math.floor( q * ( n - 1 ) ) ] : 0 );
			return { n, mean: n ? w.reduce( ( a, b ) => a + b, 0 ) / n : 0, median: at( 0.5 ), p95: at( 0.95 ) };

		},
		play: () => transport.play(),
		pause: () => transport.pause(),
		seek: ( t ) => {

			transport.seek( t );
			show();

		},
		setSpeed: ( s ) => transport.setSpeed( s ),
		speed: () => transport.speed,
		garmentVertex: ( i = 0, k = 0 ) => players[ k ].garmentVertex( i ),
		hasFitMap: () => players.every( ( p ) => !! p.fitMap ),
		fitMapOn: () => players.every( ( p ) => p.fitMap && p.fitMap.enabled ),
		fitMapPeak: ( k = 0 ) => ( players[ k ].fitMap ? players[ k ].fitMap.peak : null ),
		visibleChunks: ( k = 0 ) => players[ k ].file.chunkNodes.filter( ( n ) => n.visible ).length,
		chunks: ( k = 0 ) => players[ k ].file.chunkNodes.length,
		fileVersion: ( k = 0 ) => players[ k ].file.version,
		count: players.length,
	};
	window.__catwalk = window.__catwalk || {};
	window.__catwalk.player = hook;

	return {
		transport,
		dispose() {

			stop();
			controls.dispose();
			keyTarget.removeEventListener( 'keydown', controls.onKey );
			if ( window.__catwalk && window.__catwalk.player === hook ) delete window.__catwalk.player;

		},
	};

}
