// What the body page says of your body: what it was made from (your measurements, or your scan:
// its points, units, how close the body lies to it, the body shape read from it) and its girths
// as you gave them and as the 3D body has them.

import { h } from '../ui/dom.js';
import { GIRTHS, formatCm } from '../measurements.js';

/** The sentence on what the body was made from (GET /api/bodies/{id}'s answer). */
export function bodyOrigin( body ) {

	const scan = body.scan;
	const origin = body.source === 'scan'
		? `Made from your scan${ scan ? ` (${ scan.vertices.toLocaleString( 'en' ) } points, in ${ scan.units })` : '' }.`
		: 'Made from your measurements.';
	const distance = scan && scan.surface_distance_mm ? scan.surface_distance_mm.scan_to_body : null;
	const shapeNote = body.fit === 'surface' && distance
		? ` It takes your scan’s own shape: on average ${ distance.mean.toFixed( 1 ) } mm from its surface.`
		: '';
	const sexNote = body.sex_inferred ? ` We read the scan as a ${ body.sex } body shape.` : '';
	return origin + shapeNote + sexNote;

}

/** The girths sent (or measured on the scan) beside the 3D body's. */
export function girthTable( body ) {

	const sent = body.measurements || {};
	const made = body.model_measurements || {};
	const firstHead = body.source === 'scan' ? 'Measured on your scan' : 'You told us';
	const rows = GIRTHS.filter( ( [ k ] ) => k in made || k in sent );
	return h( 'table', { class: 'table girths' },
		h( 'caption', {}, 'Measurements' ),
		h( 'thead', {}, h( 'tr', {}, h( 'th', { scope: 'col' }, '' ), h( 'th', { scope: 'col' }, firstHead ), h( 'th', { scope: 'col' }, 'Your 3D body' ) ) ),
		h( 'tbody', {}, rows.map( ( [ k, label ] ) => h( 'tr', {},
			h( 'th', { scope: 'row' }, label ),
			h( 'td', {}, k in sent ? formatCm( sent[ k ] ) : '—' ),
			h( 'td', {}, k in made ? formatCm( made[ k ] ) : '—' ),
		) ) ),
	);

}
