// What the component remembers on the shop (the shop's own localStorage, so on that shop
// only): the shopper's own id, made here at random and sent with each request that reaches a
// body (X-Catwalk-Shopper), and the id of the shopper's body made on this shop, per key.
// Nothing else: measurements stay on the server, reached by these two.

const SHOPPER = 'catwalk:shopper';
const BODY = 'catwalk:body:';
const ID = /^[A-Za-z0-9_-]{16,64}$/;
const memory = new Map(); // storage turned off (private mode): for as long as the page lasts

function storage() {

	try {

		const s = globalThis.localStorage;
		return s || null;

	} catch {

		return null;

	}

}

function read( name, store ) {

	try {

		return store ? store.getItem( name ) : ( memory.get( name ) ?? null );

	} catch {

		return memory.get( name ) ?? null;

	}

}

function write( name, value, store ) {

	if ( value === null ) memory.delete( name );
	else memory.set( name, value );
	try {

		if ( store && value === null ) store.removeItem( name );
		else if ( store ) store.setItem( name, value );

	} catch { /* full or refused: the page's memory keeps it */ }

}

/** 24 random bytes as 32 URL-safe characters. */
export function newShopperId( random = globalThis.crypto ) {

	const bytes = random.getRandomValues( new Uint8Array( 24 ) );
	let text = '';
	for ( const b of bytes ) text += String.fromCharCode( b );
	return btoa( text ).replace( /\+/g, '-' ).replace( /\//g, '_' ).replace( /=+$/, '' );

}

/** The shopper's own id on this shop: the one kept, or a new one kept from now on. */
export function shopperId( store = storage() ) {

	const kept = read( SHOPPER, store );
	if ( kept && ID.test( kept ) ) return kept;
	const id = newShopperId();
	write( SHOPPER, id, store );
	return id;

}

/** The id of the shopper's body made with this shop's key, or null. */
export const rememberedBody = ( key, store = storage() ) => read( BODY + key, store );

export const rememberBody = ( key, id, store = storage() ) => write( BODY + key, id, store );

export const forgetBody = ( key, store = storage() ) => write( BODY + key, null, store );
