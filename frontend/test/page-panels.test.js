// The words of the body and garment pages' panels (src/body/, src/garment/): what a body was
// made from, the advised sizes, the pattern's pieces, which scan files are refused.
import { describe, it, expect } from 'vitest';
import { bodyOrigin } from '../src/body/body-facts.js';
import { advisedFit } from '../src/body/sizes-panel.js';
import { notAScan } from '../src/body/scan-form.js';
import { adviceHeadline } from '../src/garment/sizes.js';
import { pieceName } from '../src/garment/pattern.js';
import { adviceSummary } from '../src/advice.js';

const ease = ( cm ) => ( { waist: cm / 100, hips: cm / 100 } );
const advice = ( recommended, fits ) => adviceSummary( {
	recommended,
	sizes: [
		{ size: 'S', chart: {}, ease: ease( fits ? 0 : - 4 ), fits },
		{ size: 'M', chart: {}, ease: ease( 8 ), fits: true },
	],
} );

describe( 'the body page', () => {

	it( 'says what the body was made from', () => {

		expect( bodyOrigin( { source: 'measurements' } ) ).toBe( 'Made from your measurements.' );
		expect( bodyOrigin( { source: 'scan' } ) ).toBe( 'Made from your scan.' );
		expect( bodyOrigin( {
			source: 'scan', fit: 'surface', sex: 'female', sex_inferred: true,
			scan: { vertices: 123456, units: 'mm', surface_distance_mm: { scan_to_body: { mean: 0.84 } } },
		} ) ).toBe( 'Made from your scan (123,456 points, in mm). It takes your scan’s own shape: on average 0.8 mm from its surface. We read the scan as a female body shape.' );
		// a body not fitted to the scan's surface says nothing of the distance
		expect( bodyOrigin( { source: 'scan', fit: 'measurements', sex: 'male', scan: { vertices: 10, units: 'm', surface_distance_mm: { scan_to_body: { mean: 3 } } } } ) )
			.toBe( 'Made from your scan (10 points, in m).' );

	} );

	it( 'gives each garment’s advised size with its fit, or the closest', () => {

		expect( advisedFit( advice( 'S', true ) ) ).toBe( 'fits (room: waist 0 cm, hips 0 cm)' );
		expect( advisedFit( advice( 'S', false ) ) ).toBe( 'closest: tight at the waist and hips (room: waist −4 cm, hips −4 cm)' );
		expect( advisedFit( advice( null, true ) ) ).toBe( 'no size advice' );

	} );

	it( 'refuses files that are not scans by their extension', () => {

		for ( const name of [ 'me.obj', 'ME.PLY', 'scan.v2.stl', 'body.glb', 'noextension' ] ) expect( notAScan( name ) ).toBe( false );
		for ( const name of [ 'me.jpg', 'scan.obj.zip', 'body.gltf', 'dot.' ] ) expect( notAScan( name ) ).toBe( true );

	} );

} );

describe( 'the garment page', () => {

	it( 'heads the size advice', () => {

		expect( adviceHeadline( advice( 'S', true ) ) ).toBe( 'We suggest size S for your body.' );
		expect( adviceHeadline( advice( 'S', false ) ) ).toBe( 'No size has room for all your measurements; S is the closest.' );
		expect( adviceHeadline( advice( null, true ) ) ).toBe( 'We have no size advice for this garment.' );

	} );

	it( 'names the pattern pieces in words', () => {

		expect( pieceName( 'back_right' ) ).toBe( 'Back right' );
		expect( pieceName( 'sleeve--left' ) ).toBe( 'Sleeve left' );
		expect( pieceName( 'front' ) ).toBe( 'Front' );

	} );

} );
