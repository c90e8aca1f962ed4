// The merchant API (/api/merchant/…): every call sends `Authorization: Bearer KEY`. Errors are
// the shopper API's ApiError / NetworkError; a 401 is an ApiError with status 401 (the page
// forgets the key and asks again). The key lives in sessionStorage only (gone with the tab).

import { ApiError, errorFromResponse, fetchOrThrow, parseJson, readBlob, readText } from '../api.js';

const KEY = 'catwalk.merchantKey';
const enc = encodeURIComponent;

function store() {

	try {

		return globalThis.sessionStorage || null;

	} catch {

		return null; // storage blocked

	}

}

let memoryKey = null; // where sessionStorage cannot be used

export function getKey() {

	const s = store();
	try {

		return ( s && s.getItem( KEY ) ) || memoryKey;

	} catch {

		return memoryKey;

	}

}

export function setKey( key ) {

	memoryKey = key;
	const s = store();
	try {

		if ( s ) s.setItem( KEY, key );

	} catch {

		// kept in memory only

	}

}

export function forgetKey() {

	memoryKey = null;
	const s = store();
	try {

		if ( s ) s.removeItem( KEY );

	} catch {

		// nothing stored

	}

}

export const isUnauthorised = ( err ) => err instanceof ApiError && err.status === 401;

/** The ApiError of a failed answer, keeping the error's `problems` (a 422 of a garment). */
function failure( status, data ) {

	const err = errorFromResponse( status, data );
	const e = data && data.error && typeof data.error === 'object' ? data.error : null;
	err.problems = e && Array.isArray( e.problems ) ? e.problems : [];
	if ( status === 401 && ! ( e && e.message ) ) err.message = 'key not accepted';
	return err;

}

async function send( method, path, { json, form, signal, key = getKey(), accept = 'application/json' } = {} ) {

	const headers = { Accept: accept };
	if ( key ) headers.Authorization = `Bearer ${ key }`;
	const init = { method, headers, signal };
	if ( json !== undefined ) {

		headers[ 'Content-Type' ] = 'application/json';
		init.body = JSON.stringify( json );

	} else if ( form !== undefined ) {

		init.body = form; // the browser sets the multipart boundary

	}

	return fetchOrThrow( path, init );

}

async function request( method, path, opts = {} ) {

	const res = await send( method, path, opts );
	const data = parseJson( await readText( res ) );
	if ( ! res.ok ) throw failure( res.status, data );
	return data;

}

async function binary( path, opts = {} ) {

	const res = await send( 'GET', path, { ...opts, accept: '*/*' } );
	if ( ! res.ok ) throw failure( res.status, parseJson( await readText( res ).catch( () => '' ) ) );
	return readBlob( res );

}

/** The multipart body of a save: `garment` (garment.json) and each texture as a `files` part named by its path. */
export function garmentForm( garment, textures = new Map() ) {

	const form = new FormData();
	form.append( 'garment', new Blob( [ JSON.stringify( garment ) ], { type: 'application/json' } ), 'garment.json' );
	for ( const [ path, blob ] of textures ) form.append( 'files', blob, path );
	return form;

}

// --- the routes -----------------------------------------------------------------------------

export const listGarments = ( opts ) => request( 'GET', '/api/merchant/garments', opts ).then( ( d ) => ( d && d.garments ) || [] );
export const getGarment = ( id, opts ) => request( 'GET', `/api/merchant/garments/${ enc( id ) }`, opts );

/** Import a DXF: { garment, pieces, warnings }. `units`: in | mm | cm | m, or '' for the file's own. */
export function importDxf( file, { units = '', ...opts } = {} ) {

	const form = new FormData();
	form.append( 'dxf', file, file.name || 'pattern.dxf' );
	if ( units ) form.append( 'units', units );
	return request( 'POST', '/api/merchant/import', { ...opts, form } );

}

/** Save: a new garment (no id: POST) or a new version of garment `id` (PUT). `textures`: Map path → Blob. */
export function saveGarment( id, garment, textures, opts ) {

	const form = garmentForm( garment, textures );
	return id ? request( 'PUT', `/api/merchant/garments/${ enc( id ) }`, { ...opts, form } ) : request( 'POST', '/api/merchant/garments', { ...opts, form } );

}

export const publishGarment = ( id, version = null, opts ) => request( 'POST', `/api/merchant/garments/${ enc( id ) }/publish`, { ...opts, json: version == null ? {} : { version } } );

export const dressedPath = ( id, version, size ) => `/api/merchant/garments/${ enc( id ) }/versions/${ enc( version ) }/dressed/${ enc( size ) }.glb`;
export const filePath = ( id, version, path ) => `/api/merchant/garments/${ enc( id ) }/versions/${ enc( version ) }/files/${ String( path ).split( '/' ).map( enc ).join( '/' ) }`;

/** The dressed preview of a size (a .glb, fetched with the key). */
export const fetchDressed = ( id, version, size, opts ) => binary( dressedPath( id, version, size ), opts );
/** A file of a saved version (a texture image), fetched with the key. */
export const fetchFile = ( id, version, path, opts ) => binary( filePath( id, version, path ), opts );

/** The fabric names the catalogue offers (every garment's `fabrics`), presets first as listed. */
export async function catalogueFabrics( opts ) {

	const d = await request( 'GET', '/api/garments', { ...opts, key: null } );
	const names = [];
	for ( const g of ( d && d.garments ) || [] ) for ( const f of g.fabrics || [] ) if ( ! names.includes( f ) ) names.push( f );
	return names;

}

/** The merchant: name, its publishable key (pk_…) and the origins its shop's pages are on. */
export const getMe = ( opts ) => request( 'GET', '/api/merchant/me', opts );
/** Replace the origins the publishable key may be used from; the merchant as it is then. */
export const setOrigins = ( origins, opts ) => request( 'PUT', '/api/merchant/origins', { ...opts, json: { origins } } );
