// The merchant API client: the key (sessionStorage only), the Bearer header on every call,
// 401s, a save's multipart body, a 422's problems; and the dressing status words.
import { describe, it, expect, vi, beforeEach, afterEach } from 'vitest';
import {
	getKey, setKey, forgetKey, listGarments, importDxf, saveGarment, publishGarment, fetchDressed,
	isUnauthorised, garmentForm, dressedPath, filePath, catalogueFabrics,
} from '../src/merchant/api.js';
import { ApiError } from '../src/api.js';
import { parseRoute, urls } from '../src/router.js';
import { versionOf, sizeStatus, isBusy, anyBusy, reportRows, hasDressed } from '../src/merchant/status.js';

function memoryStorage() {

	const m = new Map();
	return { getItem: ( k ) => ( m.has( k ) ? m.get( k ) : null ), setItem: ( k, v ) => m.set( k, String( v ) ), removeItem: ( k ) => m.delete( k ), map: m };

}

const answer = ( status, body ) => ( { ok: status >= 200 && status < 300, status, text: async () => ( body == null ? '' : JSON.stringify( body ) ), blob: async () => new Blob( [ 'glb' ] ) } );

let session, local;
beforeEach( () => {

	session = memoryStorage();
	local = { getItem: vi.fn(), setItem: vi.fn(), removeItem: vi.fn() };
	vi.stubGlobal( 'sessionStorage', session );
	vi.stubGlobal( 'localStorage', local );

} );
afterEach( () => {

	forgetKey();
	vi.unstubAllGlobals();

} );

describe( 'the key', () => {

	it( 'lives in sessionStorage only and is forgotten on log out', () => {

		setKey( 'cwk_abc' );
		expect( getKey() ).toBe( 'cwk_abc' );
		expect( session.map.get( 'catwalk.merchantKey' ) ).toBe( 'cwk_abc' );
		forgetKey();
		expect( getKey() ).toBe( null );
		expect( session.map.size ).toBe( 0 );
		expect( local.setItem ).not.toHaveBeenCalled();

	} );

	it( 'is sent as a Bearer token on every call', async () => {

		setKey( 'cwk_k1' );
		const fetch = vi.fn().mockResolvedValue( answer( 200, { garments: [ { id: 'g1' } ] } ) );
		vi.stubGlobal( 'fetch', fetch );
		expect( await listGarments() ).toEqual( [ { id: 'g1' } ] );
		await publishGarment( 'g1', 2 );
		await fetchDressed( 'g1', 2, 'M' );
		for ( const [ , init ] of fetch.mock.calls ) expect( init.headers.Authorization ).toBe( 'Bearer cwk_k1' );
		expect( fetch.mock.calls[ 1 ][ 0 ] ).toBe( '/api/merchant/garments/g1/publish' );
		expect( JSON.parse( fetch.mock.calls[ 1 ][ 1 ].body ) ).toEqual( { version: 2 } );
		expect( fetch.mock.calls[ 2 ][ 0 ] ).toBe( '/api/merchant/garments/g1/versions/2/dressed/M.glb' );

	} );

	it( 'turns a 401 into "key not accepted"', async () => {

		vi.stubGlobal( 'fetch', vi.fn().mockResolvedValue( answer( 401, { error: { code: 'unauthorized', message: 'the API key is not valid (unknown or revoked)' } } ) ) );
		const err = await listGarments( { key: 'cwk_bad' } ).catch( ( e ) => e );
		expect( isUnauthorised( err ) ).toBe( true );
		vi.stubGlobal( 'fetch', vi.fn().mockResolvedValue( answer( 401, null ) ) );
		const bare = await listGarments( { key: 'cwk_bad' } ).catch( ( e ) => e );
		expect( bare.message ).toBe( 'key not accepted' );
		expect( isUnauthorised( new ApiError( 404, {} ) ) ).toBe( false );

	} );

} );

describe( 'uploads', () => {

	it( 'sends the garment as garment.json and textures named by their paths', async () => {

		setKey( 'cwk_k' );
		const fetch = vi.fn().mockResolvedValue( answer( 201, { id: 'skirt-1', version: 1, sizes: [ 'M' ], warnings: [], dressing: { M: { status: 'queued' } } } ) );
		vi.stubGlobal( 'fetch', fetch );
		const png = new Blob( [ new Uint8Array( [ 137, 80, 78, 71 ] ) ], { type: 'image/png' } );
		const res = await saveGarment( null, { name: 'Skirt', panels: [] }, new Map( [ [ 'textures/front.png', png ] ] ) );
		expect( res.version ).toBe( 1 );
		const [ url, init ] = fetch.mock.calls[ 0 ];
		expect( url ).toBe( '/api/merchant/garments' );
		expect( init.method ).toBe( 'POST' );
		expect( init.headers[ 'Content-Type' ] ).toBeUndefined(); // the browser's multipart boundary
		const garment = init.body.get( 'garment' );
		expect( garment.name ).toBe( 'garment.json' );
		expect( garment.type ).toBe( 'application/json' );
		expect( JSON.parse( await garment.text() ) ).toEqual( { name: 'Skirt', panels: [] } );
		const files = init.body.getAll( 'files' );
		expect( files.map( ( f ) => f.name ) ).toEqual( [ 'textures/front.png' ] );
		// a new version of a saved garment is a PUT
		await saveGarment( 'skirt-1', { name: 'Skirt' }, new Map() );
		expect( fetch.mock.calls[ 1 ][ 0 ] ).toBe( '/api/merchant/garments/skirt-1' );
		expect( fetch.mock.calls[ 1 ][ 1 ].method ).toBe( 'PUT' );
		expect( fetch.mock.calls[ 1 ][ 1 ].body.getAll( 'files' ) ).toEqual( [] );

	} );

	it( 'keeps the problems of a 422', async () => {

		const problems = [ { panel: 'FRONT', edge: 2, message: "panel 'FRONT' (size M): …" }, { message: 'seam 0 …', seam: 0 } ];
		vi.stubGlobal( 'fetch', vi.fn().mockResolvedValue( answer( 422, { error: { code: 'invalid_garment', message: 'the garment has 2 problems', problems } } ) ) );
		const err = await saveGarment( null, {}, new Map() ).catch( ( e ) => e );
		expect( err.code ).toBe( 'invalid_garment' );
		expect( err.problems ).toEqual( problems );

	} );

	it( 'imports a DXF as the part "dxf" with its units', async () => {

		const fetch = vi.fn().mockResolvedValue( answer( 200, { garment: {}, pieces: [], warnings: [] } ) );
		vi.stubGlobal( 'fetch', fetch );
		await importDxf( new File( [ '0\nEOF\n' ], 'skirt.dxf' ), { units: 'mm' } );
		const form = fetch.mock.calls[ 0 ][ 1 ].body;
		expect( form.get( 'dxf' ).name ).toBe( 'skirt.dxf' );
		expect( form.get( 'units' ) ).toBe( 'mm' );
		expect( fetch.mock.calls[ 0 ][ 0 ] ).toBe( '/api/merchant/import' );

	} );

	it( 'builds paths with escaped parts and lists the catalogue’s fabrics without the key', async () => {

		expect( dressedPath( 'a b', 3, 'X/L' ) ).toBe( '/api/merchant/garments/a%20b/versions/3/dressed/X%2FL.glb' );
		expect( filePath( 'g', 1, 'textures/front 1.png' ) ).toBe( '/api/merchant/garments/g/versions/1/files/textures/front%201.png' );
		expect( garmentForm( {} ).getAll( 'files' ) ).toEqual( [] );
		setKey( 'cwk_k' );
		const fetch = vi.fn().mockResolvedValue( answer( 200, { garments: [ { fabrics: [ 'denim', 'm1' ] }, { fabrics: [ 'm1', 'm2' ] } ] } ) );
		vi.stubGlobal( 'fetch', fetch );
		expect( await catalogueFabrics() ).toEqual( [ 'denim', 'm1', 'm2' ] );
		expect( fetch.mock.calls[ 0 ][ 1 ].headers.Authorization ).toBeUndefined();

	} );

} );

describe( 'dressing status', () => {

	const item = {
		id: 'g', version: 2, sizes: [ 'S', 'M' ],
		versions: [
			{ version: 2, dressing: { S: { status: 'running' }, M: { status: 'queued' } } },
			{ version: 1, dressing: { S: { status: 'dressed', ok: true }, M: { status: 'failed', ok: false, message: 'could not be dressed: seams open' } } },
		],
	};

	it( 'reads the latest version and whether to poll', () => {

		expect( versionOf( item ).version ).toBe( 2 );
		expect( versionOf( item, 1 ).version ).toBe( 1 );
		expect( versionOf( item, 7 ) ).toBe( null );
		expect( isBusy( item ) ).toBe( true );
		expect( anyBusy( [ { ...item, version: 1 } ] ) ).toBe( false );

	} );

	it( 'words each size', () => {

		expect( sizeStatus( { status: 'queued' } ) ).toEqual( { kind: 'busy', text: 'Queued…' } );
		expect( sizeStatus( { status: 'running' } ).kind ).toBe( 'busy' );
		expect( sizeStatus( { status: 'dressed', ok: true } ) ).toEqual( { kind: 'ok', text: 'Dressed' } );
		expect( sizeStatus( item.versions[ 1 ].dressing.M ) ).toEqual( { kind: 'failed', text: 'could not be dressed: seams open' } );
		expect( sizeStatus( null ).kind ).toBe( 'none' );

	} );

	it( 'lists the report’s numbers against their limits', () => {

		const rows = reportRows( {
			status: 'dressed', ok: true, sample: 'female-M', seam_gap_mm: 1.24, worst_seam: 'side left', max_penetration_mm: 2.5,
			max_strain: 0.031, strain_limit: 0.04, limits: { seam_gap_mm: 5, penetration_mm: 6 }, checks: { seams_welded: true, no_penetration: true, strain_within_limit: true }, message: '',
		} );
		expect( rows ).toEqual( [
			[ 'Sample body', 'female-M', null ],
			[ 'Widest seam gap', '1.2 mm, at side left (limit 5.0 mm)', true ],
			[ 'Deepest into the body', '2.5 mm (limit 6.0 mm)', true ],
			[ 'Largest stretch', '3.1 % (fabric limit 4.0 %)', true ],
		] );
		const bad = reportRows( { status: 'failed', max_strain: 0.2, strain_limit: 0.1, message: 'too tight' } );
		expect( bad ).toEqual( [ [ 'Largest stretch', '20.0 % (fabric limit 10.0 %)', false ], [ 'Problem', 'too tight', false ] ] );
		expect( hasDressed( { status: 'dressed' } ) ).toBe( true );
		expect( hasDressed( { status: 'failed', glb_url: '/x.glb' } ) ).toBe( true );
		expect( hasDressed( { status: 'failed' } ) ).toBe( false );

	} );

} );

describe( 'the route', () => {

	it( 'is /merchant', () => {

		expect( parseRoute( '/merchant' ) ).toEqual( { name: 'merchant' } );
		expect( parseRoute( '/merchant/' ) ).toEqual( { name: 'merchant' } );
		expect( parseRoute( '/merchant/x' ).name ).toBe( 'notfound' );
		expect( urls.merchant() ).toBe( '/merchant' );

	} );

} );
