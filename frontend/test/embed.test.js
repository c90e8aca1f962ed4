import { describe, it, expect, vi, afterEach } from 'vitest';
import { configureApi, apiUrl, getGarment, createBody, resultUrl, tryonEventsUrl, ApiError, NetworkError } from '../src/api.js';
import { toShadowCss } from '../src/embed/shadow-css.js';
import { shopperId, newShopperId, rememberedBody, rememberBody, forgetBody } from '../src/embed/shopper.js';
import { attributeProblem, setupMessage, isSetupError } from '../src/embed/messages.js';

afterEach( () => {

	vi.unstubAllGlobals();
	configureApi(); // back to the pages' own: same origin, no key

} );

function fakeStorage() {

	const m = new Map();
	return { getItem: ( k ) => ( m.has( k ) ? m.get( k ) : null ), setItem: ( k, v ) => m.set( k, String( v ) ), removeItem: ( k ) => m.delete( k ), map: m };

}

describe( 'the API from a shop’s page', () => {

	it( 'names the service, the key on every URL, the shopper on the requests that reach a body', async () => {

		configureApi( { base: 'https://catwalk.example/', key: 'pk_abc', headers: { 'X-Catwalk-Shopper': 's'.repeat( 32 ) } } );
		expect( apiUrl( '/api/bodies' ) ).toBe( 'https://catwalk.example/api/bodies?key=pk_abc' );
		expect( resultUrl( 't1', { compress: false } ) ).toBe( 'https://catwalk.example/api/tryons/t1/result.glb?compress=0&key=pk_abc' );
		expect( tryonEventsUrl( 't1' ) ).toBe( 'https://catwalk.example/api/tryons/t1/events?key=pk_abc' );
		const fetch = vi.fn().mockResolvedValue( { ok: true, status: 201, text: async () => '{"id":"b1"}' } );
		vi.stubGlobal( 'fetch', fetch );
		await createBody( { sex: 'female' } );
		expect( fetch.mock.calls[ 0 ][ 0 ] ).toBe( 'https://catwalk.example/api/bodies?key=pk_abc' );
		expect( fetch.mock.calls[ 0 ][ 1 ].headers[ 'X-Catwalk-Shopper' ] ).toBe( 's'.repeat( 32 ) );
		// the first request is plain (no header of ours: no preflight), so a refusal can be read
		await getGarment( 'skirt', { plain: true } );
		expect( fetch.mock.calls[ 1 ][ 1 ].headers ).toEqual( { Accept: 'application/json' } );

	} );

	it( 'is the page’s own origin with nothing added by default', () => {

		expect( apiUrl( '/api/tryons/x' ) ).toBe( '/api/tryons/x' );
		expect( resultUrl( 'x' ) ).toBe( '/api/tryons/x/result.glb' );

	} );

} );

describe( 'the shadow root’s stylesheet', () => {

	it( 'puts the variables on the host, rem in the pages’ pixels, narrow screens as container queries', () => {

		const css = toShadowCss( ':root{--x:1}h1{font-size:clamp(1.75rem,1.3rem + 1.6vw,2.6rem);margin:.5rem}@media (max-width: 600px){.a{b:c}}@media (prefers-reduced-motion: reduce){.a{d:e}}' );
		expect( css ).toContain( ':host{--x:1}' );
		expect( css ).toContain( 'clamp(28px,20.8px + 1.6vw,41.6px)' );
		expect( css ).toContain( 'margin:8px' );
		expect( css ).toContain( '@container catwalk (max-width: 600px){.a{b:c}}' );
		expect( css ).toContain( '@media (prefers-reduced-motion: reduce)' );
		expect( css ).not.toMatch( /\drem/ );

	} );

} );

describe( 'what the component remembers on the shop', () => {

	it( 'keeps one shopper id, 32 URL-safe characters', () => {

		const store = fakeStorage();
		const id = shopperId( store );
		expect( id ).toMatch( /^[A-Za-z0-9_-]{32}$/ );
		expect( shopperId( store ) ).toBe( id );
		expect( newShopperId() ).not.toBe( id );
		store.setItem( 'catwalk:shopper', 'not valid!' );
		expect( shopperId( store ) ).not.toBe( 'not valid!' );

	} );

	it( 'keeps the body per key, and forgets it', () => {

		const store = fakeStorage();
		expect( rememberedBody( 'pk_a', store ) ).toBeNull();
		rememberBody( 'pk_a', 'body1', store );
		expect( rememberedBody( 'pk_a', store ) ).toBe( 'body1' );
		expect( rememberedBody( 'pk_b', store ) ).toBeNull();
		forgetBody( 'pk_a', store );
		expect( rememberedBody( 'pk_a', store ) ).toBeNull();
		expect( [ ...store.map.keys() ] ).toEqual( [] );

	} );

	it( 'lasts the page without storage', () => {

		rememberBody( 'pk_c', 'body2', null );
		expect( rememberedBody( 'pk_c', null ) ).toBe( 'body2' );
		forgetBody( 'pk_c', null );
		expect( rememberedBody( 'pk_c', null ) ).toBeNull();

	} );

} );

describe( 'the component’s messages', () => {

	it( 'finds the attributes’ own mistakes', () => {

		expect( attributeProblem( { garment: 'g', key: '' } ) ).toMatch( /key attribute is missing/ );
		expect( attributeProblem( { garment: 'g', key: 'abc' } ) ).toMatch( /not a publishable key/ );
		expect( attributeProblem( { garment: '', key: 'pk_x' } ) ).toMatch( /garment attribute/ );
		expect( attributeProblem( { garment: 'g', key: 'cwk_x' } ) ).toBeNull(); // the service refuses it, saying why
		expect( attributeProblem( { garment: 'g', key: 'pk_x' } ) ).toBeNull();

	} );

	it( 'tells a refused set-up from the rest', () => {

		const origin = new ApiError( 403, { code: 'origin_not_allowed', message: 'the page’s origin https://x is not …' } );
		expect( isSetupError( origin ) ).toBe( true );
		expect( setupMessage( origin ) ).toEqual( { title: 'The try-on is not allowed on this site', text: 'the page’s origin https://x is not …' } );
		expect( setupMessage( new ApiError( 403, { code: 'secret_key_exposed', message: 'never in a page' } ) ).title ).toMatch( /secret key/ );
		expect( setupMessage( new NetworkError() ).text ).toMatch( /cannot be reached/ );
		expect( isSetupError( new ApiError( 404, { code: 'not_found' } ) ) ).toBe( false );

	} );

} );
