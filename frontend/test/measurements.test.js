import { describe, it, expect } from 'vitest';
import { RANGES, cmToM, mToCm, parseCm, checkMeasurement, checkForm, formatCm, formatSignedCm, rangeCm } from '../src/measurements.js';

describe( 'cm ↔ m', () => {

	it( 'converts both ways at the API precision', () => {

		expect( cmToM( 168 ) ).toBe( 1.68 );
		expect( cmToM( 168.5 ) ).toBe( 1.685 );
		expect( cmToM( 90.25 ) ).toBe( 0.9025 );
		expect( cmToM( 72.123 ) ).toBe( 0.7212 );
		expect( mToCm( 0.9205 ) ).toBe( 92.1 );
		expect( mToCm( 1.68 ) ).toBe( 168 );
		for ( const cm of [ 145, 150.5, 171.3, 205 ] ) expect( mToCm( cmToM( cm ) ) ).toBe( cm );

	} );

	it( 'shows the API ranges in cm', () => {

		expect( rangeCm( 'height' ) ).toEqual( [ 145, 205 ] );
		expect( rangeCm( 'bust' ) ).toEqual( [ 74, 140 ] );
		expect( rangeCm( 'waist' ) ).toEqual( [ 56, 130 ] );
		expect( rangeCm( 'hips' ) ).toEqual( [ 78, 145 ] );
		expect( RANGES.height ).toEqual( [ 1.45, 2.05 ] );

	} );

	it( 'formats lengths', () => {

		expect( formatCm( 0.9205 ) ).toBe( '92.1 cm' );
		expect( formatCm( 1.68 ) ).toBe( '168 cm' );
		expect( formatSignedCm( - 0.02 ) ).toBe( '−2 cm' );
		expect( formatSignedCm( 0.035 ) ).toBe( '+3.5 cm' );
		expect( formatSignedCm( 0 ) ).toBe( '0 cm' );

	} );

} );

describe( 'checking what is typed', () => {

	it( 'reads numbers as people type them', () => {

		expect( parseCm( '168' ) ).toBe( 168 );
		expect( parseCm( ' 168,5 ' ) ).toBe( 168.5 );
		expect( parseCm( '168 cm' ) ).toBe( 168 );
		expect( parseCm( '.5' ) ).toBe( 0.5 );
		expect( parseCm( '1e3' ) ).toBeNaN();
		expect( parseCm( 'tall' ) ).toBeNaN();
		expect( parseCm( '-3' ) ).toBeNaN();

	} );

	it( 'checks each range, inclusive', () => {

		expect( checkMeasurement( 'height', '145' ) ).toEqual( { ok: true, value: 1.45 } );
		expect( checkMeasurement( 'height', '205' ) ).toEqual( { ok: true, value: 2.05 } );
		expect( checkMeasurement( 'height', '144.9' ) ).toEqual( { ok: false, message: 'Height must be between 145 and 205 cm.' } );
		expect( checkMeasurement( 'bust', '60' ).message ).toBe( 'Bust must be between 74 and 140 cm.' );
		expect( checkMeasurement( 'waist', '131' ).ok ).toBe( false );
		expect( checkMeasurement( 'hips', '78' ).value ).toBe( 0.78 );
		expect( checkMeasurement( 'hips', 'abc' ).message ).toBe( 'Hips is a number of centimetres.' );

	} );

	it( 'lets an empty field wait until the form is sent', () => {

		expect( checkMeasurement( 'waist', '', { required: false } ) ).toEqual( { ok: true, empty: true } );
		expect( checkMeasurement( 'waist', '' ) ).toEqual( { ok: false, message: 'Enter your waist in cm.' } );

	} );

	it( 'turns a form into the API body, in metres', () => {

		expect( checkForm( { sex: 'female', height: '168', bust: '90', waist: '72', hips: '98' } ) ).toEqual( {
			ok: true, errors: {}, body: { sex: 'female', height: 1.68, bust: 0.9, waist: 0.72, hips: 0.98 },
		} );
		const bad = checkForm( { sex: 'robot', height: '300', bust: '90', waist: '', hips: '98' } );
		expect( bad.ok ).toBe( false );
		expect( Object.keys( bad.errors ).sort() ).toEqual( [ 'height', 'sex', 'waist' ] );
		expect( bad.body ).toBeUndefined();

	} );

} );
