// Words for what the API names by id: fabrics, garment types, presets.

const FABRICS = {
	'cotton-jersey': 'Cotton jersey',
	denim: 'Denim',
	'silk-charmeuse': 'Silk charmeuse',
	'wool-suiting': 'Wool suiting',
	m1: 'Polyester twill',
	m2: 'Polyester plain weave',
	m3: 'Wool-blend stretch twill',
	m4: 'Poly-viscose stretch twill',
	m5: 'Stretch plain weave',
	m6: 'Cotton stretch twill',
	custom: 'Its own fabric',
};

const TYPES = {
	tshirt: 'T-shirt',
	trousers: 'Trousers',
};

function humanise( id ) {

	const s = String( id ).replace( /[-_]+/g, ' ' ).trim();
	return s.charAt( 0 ).toUpperCase() + s.slice( 1 );

}

export const fabricName = ( id ) => FABRICS[ id ] || humanise( id );
export const typeName = ( type ) => TYPES[ type ] || humanise( type );

/** A garment's display name without the pattern's provenance: "Pencil skirt (FreeSewing Penelope)" → "Pencil skirt". */
export function shortName( name ) {

	const s = String( name || '' ).replace( /\s*\([^)]*\)\s*$/, '' ).replace( /_/g, ' ' ).trim();
	return s ? s.charAt( 0 ).toUpperCase() + s.slice( 1 ) : String( name || '' );

}

/** The provenance in a garment's name: "FreeSewing Penelope", or null. */
export function nameSource( name ) {

	const m = /\(([^)]*)\)\s*$/.exec( String( name || '' ) );
	return m ? m[ 1 ] : null;

}

export const PRESETS = [
	[ 'fast', 'Quick look', 'Fastest; a rougher drape' ],
	[ 'balanced', 'Standard', 'The usual quality' ],
	[ 'accurate', 'Finest', 'Slowest; the most faithful drape' ],
];

export const presetName = ( id ) => ( PRESETS.find( ( p ) => p[ 0 ] === id ) || [ id, humanise( id ) ] )[ 1 ];

export const WALK_LENGTHS = [ 1, 2, 4, 6, 10 ];

export function plural( n, one, many = `${ one }s` ) {

	return `${ n } ${ n === 1 ? one : many }`;

}
