// Can this browser draw 3D? (WebGL 2, which three.js needs.)

let answer = null;

export function hasWebGL() {

	if ( answer !== null ) return answer;
	try {

		const canvas = document.createElement( 'canvas' );
		const gl = canvas.getContext( 'webgl2' );
		answer = !! gl;
		if ( gl ) {

			const lose = gl.getExtension( 'WEBGL_lose_context' );
			if ( lose ) lose.loseContext();

		}

	} catch {

		answer = false;

	}

	return answer;

}

export const NO_WEBGL_MESSAGE = 'Your browser cannot show 3D here: WebGL 2 is turned off or not supported. Turn on hardware acceleration, or try a recent Chrome, Firefox, Safari or Edge.';
