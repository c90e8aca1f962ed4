import { describe, it, expect } from 'vitest';
import { parseRoute, urls, isRouterClick } from '../src/router.js';

describe( 'parseRoute', () => {

	it( 'names each page', () => {

		expect( parseRoute( '/' ) ).toEqual( { name: 'catalogue', type: null } );
		expect( parseRoute( '/', '?type=skirt' ) ).toEqual( { name: 'catalogue', type: 'skirt' } );
		expect( parseRoute( '/garments/pencil-skirt' ) ).toEqual( { name: 'garment', id: 'pencil-skirt' } );
		expect( parseRoute( '/body' ) ).toEqual( { name: 'body' } );
		expect( parseRoute( '/body/' ) ).toEqual( { name: 'body' } );
		expect( parseRoute( '/tryon/0jlJlyj6oRM1cobWU4gtNL60boCTRsHc' ) ).toEqual( { name: 'tryon', id: '0jlJlyj6oRM1cobWU4gtNL60boCTRsHc', compress: true } );
		expect( parseRoute( '/tryon/abc', '?compress=0' ) ).toEqual( { name: 'tryon', id: 'abc', compress: false } );
		expect( parseRoute( '/compare', '?a=x&b=y' ) ).toEqual( { name: 'compare', a: 'x', b: 'y' } );

	} );

	it( 'decodes ids and keeps URL-safe characters', () => {

		expect( parseRoute( '/tryon/kkEt-UrQb65L1P42sZ6TdKPvNvA07BB-' ).id ).toBe( 'kkEt-UrQb65L1P42sZ6TdKPvNvA07BB-' );
		expect( parseRoute( '/garments/a%20b' ).id ).toBe( 'a b' );
		expect( parseRoute( urls.garment( 'gc dress/x' ) ) ).toEqual( { name: 'garment', id: 'gc dress/x' } );

	} );

	it( 'refuses what is not a page', () => {

		expect( parseRoute( '/nope' ).name ).toBe( 'notfound' );
		expect( parseRoute( '/garments' ).name ).toBe( 'notfound' );
		expect( parseRoute( '/garments/a/b' ).name ).toBe( 'notfound' );
		expect( parseRoute( '/compare', '?a=x' ).name ).toBe( 'notfound' );
		expect( parseRoute( '/garments/%E0%A4%A' ).name ).toBe( 'notfound' ); // bad escape

	} );

	it( 'round-trips its own URLs', () => {

		const split = ( u ) => {

			const url = new URL( u, 'http://x' );
			return parseRoute( url.pathname, url.search );

		};

		expect( split( urls.catalogue() ) ).toEqual( { name: 'catalogue', type: null } );
		expect( split( urls.catalogue( 'dress' ) ) ).toEqual( { name: 'catalogue', type: 'dress' } );
		expect( split( urls.body() ) ).toEqual( { name: 'body' } );
		expect( split( urls.tryon( 'a-b_c' ) ) ).toEqual( { name: 'tryon', id: 'a-b_c', compress: true } );
		expect( split( urls.tryon( 'a', { compress: false } ) ) ).toEqual( { name: 'tryon', id: 'a', compress: false } );
		expect( split( urls.compare( 'a&1', 'b=2' ) ) ).toEqual( { name: 'compare', a: 'a&1', b: 'b=2' } );

	} );

} );

describe( 'isRouterClick', () => {

	const origin = 'http://127.0.0.1:8000';
	const anchor = ( href, attrs = {} ) => ( {
		href: new URL( href, origin ).href,
		target: attrs.target || '',
		hasAttribute: ( k ) => k in attrs,
	} );
	const click = ( extra = {} ) => ( { defaultPrevented: false, button: 0, metaKey: false, ctrlKey: false, shiftKey: false, altKey: false, ...extra } );

	it( 'takes plain same-origin page links', () => {

		expect( isRouterClick( click(), anchor( '/body' ), origin ) ).toBe( true );
		expect( isRouterClick( click(), anchor( '/garments/dress' ), origin ) ).toBe( true );

	} );

	it( 'leaves downloads, API files, other sites, new tabs and modified clicks to the browser', () => {

		expect( isRouterClick( click(), anchor( '/api/tryons/x/result.glb' ), origin ) ).toBe( false );
		expect( isRouterClick( click(), anchor( '/x.glb', { download: '' } ), origin ) ).toBe( false );
		expect( isRouterClick( click(), anchor( 'https://example.org/' ), origin ) ).toBe( false );
		expect( isRouterClick( click(), anchor( '/body', { target: '_blank' } ), origin ) ).toBe( false );
		expect( isRouterClick( click( { ctrlKey: true } ), anchor( '/body' ), origin ) ).toBe( false );
		expect( isRouterClick( click( { button: 1 } ), anchor( '/body' ), origin ) ).toBe( false );
		expect( isRouterClick( click(), null, origin ) ).toBe( false );

	} );

} );
