// The catwalk HTTP API (docs/api.md), same origin. Errors are thrown as ApiError (the API's
// JSON error: code, message, field) or NetworkError (the server could not be reached).
// A shop's component (src/embed/, docs/embed.md) points it at the service's origin with the
// shop's publishable key (a query parameter, so that a preflight carries it too) and the
// shopper's own id (a header): configureApi().

const target = { base: '', key: null, headers: {} };

/** Where the API is (`base`: an origin; '' the page's own), the publishable key every request
 * names (`key`) and the headers each carries (`headers`). */
export function configureApi( { base = '', key = null, headers = {} } = {} ) {

	target.base = base.replace( /\/+$/, '' );
	target.key = key;
	target.headers = { ...headers };

}

/** The URL of an API path (`/api/…`, with its query) as configured. */
export function apiUrl( path ) {

	if ( ! target.key ) return target.base + path;
	return `${ target.base }${ path }${ path.includes( '?' ) ? '&' : '?' }key=${ encodeURIComponent( target.key ) }`;

}

export class ApiError extends Error {

	constructor( status, { code = 'error', message, field = null, details = null } = {} ) {

		super( message || `the server answered ${ status }` );
		this.name = 'ApiError';
		this.status = status;
		this.code = code;
		this.field = field;
		this.details = details;

	}

}

export class NetworkError extends Error {

	constructor( cause ) {

		super( 'The catwalk server could not be reached. Check your connection, then try again.' );
		this.name = 'NetworkError';
		this.cause = cause;

	}

}

/** The ApiError for a non-2xx answer whose body parsed as `data` (or null). */
export function errorFromResponse( status, data ) {

	const e = data && typeof data === 'object' && data.error && typeof data.error === 'object' ? data.error : null;
	if ( e ) return new ApiError( status, e );
	if ( status === 413 ) return new ApiError( status, { code: 'too_large', message: 'The file is too large to upload.' } );
	if ( status >= 500 ) return new ApiError( status, { code: 'server', message: `The server had a problem (${ status }). Please try again in a moment.` } );
	return new ApiError( status, { message: `The server answered ${ status }.` } );

}

export function parseJson( text ) {

	if ( ! text ) return null;
	try {

		return JSON.parse( text );

	} catch {

		return null;

	}

}

/** `plain`: without the configured headers (a cross-origin request without a preflight). */
async function request( method, path, { json, signal, plain = false } = {} ) {

	const init = { method, signal, headers: { Accept: 'application/json', ...( plain ? {} : target.headers ) } };
	if ( json !== undefined ) {

		init.headers[ 'Content-Type' ] = 'application/json';
		init.body = JSON.stringify( json );

	}

	const res = await fetchOrThrow( apiUrl( path ), init );
	const data = parseJson( await readText( res ) );
	if ( ! res.ok ) throw errorFromResponse( res.status, data );
	return data;

}

function network( err ) {

	if ( err && err.name === 'AbortError' ) return err;
	return new NetworkError( err );

}

/** `fetch( path, init )`; a failure to reach the server is thrown as NetworkError (an abort as itself). */
export async function fetchOrThrow( path, init ) {

	try {

		return await fetch( path, init );

	} catch ( err ) {

		throw network( err );

	}

}

/** The answer's body as text; a connection broken meanwhile is thrown as NetworkError. */
export async function readText( res ) {

	try {

		return await res.text();

	} catch ( err ) {

		throw network( err );

	}

}

/** The answer's body as a Blob; a connection broken meanwhile is thrown as NetworkError. */
export async function readBlob( res ) {

	try {

		return await res.blob();

	} catch ( err ) {

		throw network( err );

	}

}

const enc = encodeURIComponent;

// --- garments ---------------------------------------------------------------------------

export const listGarments = ( opts ) => request( 'GET', '/api/garments', opts ).then( ( d ) => d.garments );
export const getGarment = ( id, opts ) => request( 'GET', `/api/garments/${ enc( id ) }`, opts );
export const thumbnailUrl = ( id ) => apiUrl( `/api/garments/${ enc( id ) }/thumbnail.png` );
export const dressedUrl = ( id ) => apiUrl( `/api/garments/${ enc( id ) }/dressed.glb` );
export const patternUrl = ( id, size ) => apiUrl( `/api/garments/${ enc( id ) }/pattern.png${ size ? `?size=${ enc( size ) }` : '' }` );

// --- optional routes ------------------------------------------------------------------------
// Size advice (`GET /api/garments/{id}/sizes`) is newer than the rest of the API: ask the
// OpenAPI document whether this server has it, so an older server is never asked (no 404s).

let routesPromise = null;

/** The set of API paths (OpenAPI templates) this server answers; empty when unknown. */
export function apiPaths() {

	if ( ! routesPromise ) {

		routesPromise = request( 'GET', '/openapi.json' )
			.then( ( doc ) => new Set( Object.keys( ( doc && doc.paths ) || {} ) ) )
			.catch( ( err ) => {

				routesPromise = null; // ask again next time
				if ( err instanceof NetworkError ) throw err;
				return new Set();

			} );

	}

	return routesPromise;

}

export function hasDressedRoute( paths ) {

	for ( const p of paths ) if ( /^\/api\/garments\/\{[^}]+\}\/dressed\.glb$/.test( p ) ) return true;
	return false;

}

export function hasSizesRoute( paths ) {

	for ( const p of paths ) if ( /^\/api\/garments\/\{[^}]+\}\/sizes$/.test( p ) ) return true;
	return false;

}

/** Size advice for a garment on a body, or null when the server has none to give. */
export async function getSizeAdvice( garmentId, bodyId, opts ) {

	// a shop's key opens no OpenAPI document; the service a shop's component comes from has it
	const paths = target.key ? null : await apiPaths();
	if ( paths && ! hasSizesRoute( paths ) ) return null;
	try {

		return await request( 'GET', `/api/garments/${ enc( garmentId ) }/sizes?body_id=${ enc( bodyId ) }`, opts );

	} catch ( err ) {

		if ( err instanceof ApiError && ( err.status === 404 || err.status === 405 ) ) return null;
		throw err;

	}

}

// --- bodies -------------------------------------------------------------------------------

export const createBody = ( measurements, opts ) => request( 'POST', '/api/bodies', { ...opts, json: measurements } );
export const getBody = ( id, opts ) => request( 'GET', `/api/bodies/${ enc( id ) }`, opts );
export const deleteBody = ( id, opts ) => request( 'DELETE', `/api/bodies/${ enc( id ) }`, opts );

/**
 * Upload a scan (multipart, part `scan`, optional `sex`) with XMLHttpRequest so the upload's
 * progress can be shown: `onProgress(fraction)` while sending, then `onSent()` while the
 * server makes the body. Resolves to the Body; rejects with ApiError / NetworkError.
 * Returns `{ promise, abort }`.
 */
export function uploadScan( file, { sex = '', onProgress = () => {}, onSent = () => {} } = {} ) {

	const xhr = new XMLHttpRequest();
	const promise = new Promise( ( resolve, reject ) => {

		const form = new FormData();
		form.append( 'scan', file, file.name );
		if ( sex ) form.append( 'sex', sex );
		xhr.open( 'POST', apiUrl( '/api/bodies' ) );
		xhr.setRequestHeader( 'Accept', 'application/json' );
		for ( const [ k, v ] of Object.entries( target.headers ) ) xhr.setRequestHeader( k, v );
		xhr.upload.addEventListener( 'progress', ( e ) => {

			if ( e.lengthComputable && e.total > 0 ) onProgress( e.loaded / e.total );

		} );
		xhr.upload.addEventListener( 'load', () => {

			onProgress( 1 );
			onSent();

		} );
		xhr.addEventListener( 'load', () => {

			const data = parseJson( xhr.responseText );
			if ( xhr.status >= 200 && xhr.status < 300 ) resolve( data );
			else reject( errorFromResponse( xhr.status, data ) );

		} );
		xhr.addEventListener( 'error', () => reject( new NetworkError() ) );
		xhr.addEventListener( 'abort', () => reject( new DOMException( 'upload cancelled', 'AbortError' ) ) );
		xhr.send( form );

	} );
	return { promise, abort: () => xhr.abort() };

}

// --- try-ons ------------------------------------------------------------------------------

export const createTryon = ( req, opts ) => request( 'POST', '/api/tryons', { ...opts, json: req } );
export const getTryon = ( id, opts ) => request( 'GET', `/api/tryons/${ enc( id ) }`, opts );
export const cancelTryon = ( id, opts ) => request( 'DELETE', `/api/tryons/${ enc( id ) }`, opts );
export const tryonEventsUrl = ( id ) => apiUrl( `/api/tryons/${ enc( id ) }/events` );
export const resultUrl = ( id, { compress = true } = {} ) => apiUrl( `/api/tryons/${ enc( id ) }/result.glb${ compress ? '' : '?compress=0' }` );
export const previewUrl = ( id ) => apiUrl( `/api/tryons/${ enc( id ) }/preview.png` );
