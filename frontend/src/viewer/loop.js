// One animation loop: `fn(dt)` every frame (seconds since the last, capped) until stopped.

export function startLoop( fn ) {

	let last = performance.now();
	let id = 0;
	let running = true;
	const frame = ( now ) => {

		if ( ! running ) return;
		const dt = Math.min( 0.1, Math.max( 0, ( now - last ) / 1000 ) );
		last = now;
		try {

			fn( dt );

		} finally {

			if ( running ) id = requestAnimationFrame( frame );

		}

	};

	id = requestAnimationFrame( frame );
	return () => {

		running = false;
		cancelAnimationFrame( id );

	};

}
