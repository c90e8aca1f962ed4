import { describe, it, expect, vi, afterEach } from 'vitest';
import { errorFromResponse, ApiError, NetworkError, createBody, hasSizesRoute } from '../src/api.js';
import { adviceSummary } from '../src/advice.js';

afterEach( () => vi.unstubAllGlobals() );

describe( 'API errors', () => {

	it( 'keeps the API’s message and field', () => {

		const e = errorFromResponse( 422, { error: { code: 'invalid', message: 'height: Input should be less than or equal to 2.05', field: 'height' } } );
		expect( e ).toBeInstanceOf( ApiError );
		expect( e ).toMatchObject( { status: 422, code: 'invalid', field: 'height', message: 'height: Input should be less than or equal to 2.05' } );

	} );

	it( 'says something useful without a JSON body', () => {

		expect( errorFromResponse( 413, null ).message ).toMatch( /too large/ );
		expect( errorFromResponse( 502, null ).message ).toMatch( /problem \(502\)/ );

	} );

	it( 'turns a failed fetch into NetworkError', async () => {

		vi.stubGlobal( 'fetch', vi.fn().mockRejectedValue( new TypeError( 'Failed to fetch' ) ) );
		await expect( createBody( { sex: 'female' } ) ).rejects.toBeInstanceOf( NetworkError );

	} );

	it( 'sends measurements as JSON and reads the body', async () => {

		const fetch = vi.fn().mockResolvedValue( { ok: true, status: 201, text: async () => '{"id":"b1"}' } );
		vi.stubGlobal( 'fetch', fetch );
		const body = await createBody( { sex: 'female', height: 1.68, bust: 0.9, waist: 0.72, hips: 0.98 } );
		expect( body ).toEqual( { id: 'b1' } );
		const [ url, init ] = fetch.mock.calls[ 0 ];
		expect( url ).toBe( '/api/bodies' );
		expect( init.method ).toBe( 'POST' );
		expect( init.headers[ 'Content-Type' ] ).toBe( 'application/json' );
		expect( JSON.parse( init.body ).height ).toBe( 1.68 );

	} );

	it( 'throws the API error of a 4xx', async () => {

		vi.stubGlobal( 'fetch', vi.fn().mockResolvedValue( { ok: false, status: 422, text: async () => '{"error":{"code":"invalid","message":"waist 1.2 m is more than 12 cm above bust 0.8 m","field":"waist"}}' } ) );
		await expect( createBody( {} ) ).rejects.toMatchObject( { field: 'waist', status: 422 } );

	} );

} );

describe( 'size advice', () => {

	it( 'is asked for only when the server has the route', () => {

		expect( hasSizesRoute( new Set( [ '/api/garments/{garment_id}/sizes' ] ) ) ).toBe( true );
		expect( hasSizesRoute( new Set( [ '/api/garments/{garment_id}' ] ) ) ).toBe( false );

	} );

	it( 'reads the answer', () => {

		const s = adviceSummary( {
			garment_id: 'pencil-skirt', body_id: 'b', recommended: 'M',
			sizes: [
				{ size: 'S', chart: { waist: 0.70, hips: 0.96 }, ease: { waist: - 0.02, hips: - 0.02 }, fits: false },
				{ size: 'M', chart: { waist: 0.74, hips: 1.0 }, ease: { waist: 0.02, hips: 0.02 }, fits: true },
			],
		} );
		expect( s.recommended ).toBe( 'M' );
		expect( s.sizes[ 0 ].text ).toBe( 'tight at the waist and hips (room: waist −2 cm, hips −2 cm)' );
		expect( s.sizes[ 1 ] ).toMatchObject( { fits: true, text: 'fits (room: waist +2 cm, hips +2 cm)' } );
		expect( adviceSummary( null ) ).toBeNull();
		expect( adviceSummary( { sizes: [] } ) ).toBeNull();

	} );

} );

describe( 'size advice edge cases', () => {

	it( 'says when no size fits and when a size has no chart', () => {

		const s = adviceSummary( {
			recommended: 'L',
			sizes: [
				{ size: 'M', chart: null, ease: null, fits: null },
				{ size: 'L', chart: { bust: 1.0 }, ease: { bust: - 0.05 }, fits: false },
			],
		} );
		expect( s.recommendedFits ).toBe( false );
		expect( s.sizes[ 0 ] ).toMatchObject( { unknown: true, fits: false } );
		expect( s.sizes[ 1 ].text ).toBe( 'tight at the bust (room: bust −5 cm)' );

	} );

} );
