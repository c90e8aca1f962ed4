// Size advice (GET /api/garments/{id}/sizes?body_id=…) in words.

import { formatSignedCm } from './measurements.js';

const GIRTH_WORDS = { bust: 'bust', waist: 'waist', hips: 'hips' };

/**
 * `{ recommended, recommendedFits, sizes: [{ size, fits, text }] }` from the API's answer, or
 * null when it has nothing to say (the API recommends the largest size when none fits). Ease = the size chart's girth − the body's (metres): negative is tight.
 */
export function adviceSummary( advice ) {

	if ( ! advice || ! Array.isArray( advice.sizes ) || ! advice.sizes.length ) return null;
	const sizes = advice.sizes.map( ( s ) => {

		if ( ! s.chart && ! s.ease ) return { size: s.size, fits: false, unknown: true, ease: {}, text: 'no size chart for this size' };
		const ease = s.ease || {};
		const parts = Object.keys( ease ).filter( ( k ) => typeof ease[ k ] === 'number' ).map( ( k ) => `${ GIRTH_WORDS[ k ] || k.replace( /_/g, ' ' ) } ${ formatSignedCm( ease[ k ] ) }` );
		const tight = Object.entries( ease ).filter( ( [ , v ] ) => typeof v === 'number' && v < 0 ).map( ( [ k ] ) => GIRTH_WORDS[ k ] || k );
		let verdict = s.fits ? 'fits' : 'too tight';
		if ( ! s.fits && tight.length ) verdict = `tight at the ${ tight.join( ' and ' ) }`;
		else if ( ! s.fits ) verdict = 'does not fit';
		return { size: s.size, fits: !! s.fits, ease, text: parts.length ? `${ verdict } (room: ${ parts.join( ', ' ) })` : verdict };

	} );
	const recommended = advice.recommended || null;
	const rec = sizes.find( ( x ) => x.size === recommended );
	return { recommended, recommendedFits: !! ( rec && rec.fits ), sizes };

}
