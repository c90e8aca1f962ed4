// Body measurements: the API takes metres, the form shows centimetres.

/** The API's accepted ranges, metres (docs/api.md, POST /api/bodies). */
export const RANGES = {
	height: [ 1.45, 2.05 ],
	bust: [ 0.74, 1.40 ],
	waist: [ 0.56, 1.30 ],
	hips: [ 0.78, 1.45 ],
};

export const FIELDS = [ 'height', 'bust', 'waist', 'hips' ];

export const LABELS = {
	height: 'Height',
	bust: 'Bust / chest',
	waist: 'Waist',
	hips: 'Hips',
};

export const HINTS = {
	height: 'Standing, without shoes.',
	bust: 'Around the fullest part of the chest.',
	waist: 'Around the narrowest part, above the navel.',
	hips: 'Around the fullest part of the seat.',
};

/** The girths a body's model_measurements holds, in the order they are shown. */
export const GIRTHS = [
	[ 'height', 'Height' ],
	[ 'bust', 'Bust' ],
	[ 'underbust', 'Underbust' ],
	[ 'waist', 'Waist' ],
	[ 'hips', 'Hips' ],
	[ 'inseam', 'Inseam' ],
	[ 'shoulder_width', 'Shoulder width' ],
	[ 'arm_length', 'Arm length' ],
	[ 'upper_arm_girth', 'Upper arm' ],
	[ 'neck_girth', 'Neck' ],
];

/** Centimetres to metres, to 0.1 mm (4 decimals), as the API rounds. */
export function cmToM( cm ) {

	return Math.round( cm * 100 ) / 10000;

}

/** Metres to centimetres, to 0.1 cm. */
export function mToCm( m ) {

	return Math.round( m * 1000 ) / 10;

}

/** "68.5 cm" */
export function formatCm( m ) {

	const cm = mToCm( m );
	return `${ Number.isInteger( cm ) ? cm.toFixed( 0 ) : cm.toFixed( 1 ) } cm`;

}

/** A signed difference in cm: "+2 cm", "−1.5 cm". */
export function formatSignedCm( m ) {

	const cm = mToCm( m );
	const abs = Math.abs( cm );
	const text = Number.isInteger( abs ) ? abs.toFixed( 0 ) : abs.toFixed( 1 );
	if ( cm === 0 ) return '0 cm';
	return `${ cm > 0 ? '+' : '−' }${ text } cm`;

}

export function rangeCm( key ) {

	const [ lo, hi ] = RANGES[ key ];
	return [ mToCm( lo ), mToCm( hi ) ];

}

/** Parse what a person typed as centimetres ("168", "168.5", "168,5", " 168 cm"). NaN if not a number. */
export function parseCm( text ) {

	if ( typeof text === 'number' ) return text;
	const t = String( text ?? '' ).trim().replace( /\s*cm$/i, '' ).replace( ',', '.' );
	if ( ! /^[0-9]+(\.[0-9]*)?$|^\.[0-9]+$/.test( t ) ) return NaN;
	return Number( t );

}

/**
 * Check one measurement typed in cm. `{ ok, value }` (value in metres) or `{ ok: false, message }`.
 * `required: false` lets an empty field pass as "not yet typed" (`empty: true`).
 */
export function checkMeasurement( key, text, { required = true } = {} ) {

	const label = LABELS[ key ].split( ' /' )[ 0 ];
	const [ lo, hi ] = rangeCm( key );
	if ( String( text ?? '' ).trim() === '' ) {

		return required ? { ok: false, message: `Enter your ${ label.toLowerCase() } in cm.` } : { ok: true, empty: true };

	}

	const cm = parseCm( text );
	if ( ! Number.isFinite( cm ) ) return { ok: false, message: `${ label } is a number of centimetres.` };
	if ( cm < lo || cm > hi ) return { ok: false, message: `${ label } must be between ${ lo } and ${ hi } cm.` };
	return { ok: true, value: cmToM( cm ) };

}

/** Check the whole form `{ sex, height, bust, waist, hips }` (cm as typed). */
export function checkForm( values ) {

	const errors = {};
	const body = {};
	if ( values.sex !== 'female' && values.sex !== 'male' ) errors.sex = 'Choose the body shape to start from.';
	else body.sex = values.sex;
	for ( const key of FIELDS ) {

		const r = checkMeasurement( key, values[ key ] );
		if ( r.ok ) body[ key ] = r.value;
		else errors[ key ] = r.message;

	}

	const ok = Object.keys( errors ).length === 0;
	return ok ? { ok, body, errors } : { ok, errors };

}
