import { describe, it, expect } from 'vitest';
import { advance, clampSpeed, clampTime, scrubToTime, timeToScrub, frameAt, fpsFromTimes, formatTime, chunkForFrame, Transport, END_EPSILON } from '../src/player/timeline.js';

describe( 'time math', () => {

	it( 'scrubber ↔ time', () => {

		expect( scrubToTime( 0, 1000, 4 ) ).toBe( 0 );
		expect( scrubToTime( 500, 1000, 4 ) ).toBe( 2 );
		expect( scrubToTime( 1000, 1000, 4 ) ).toBe( 4 );
		expect( scrubToTime( 2000, 1000, 4 ) ).toBe( 4 );
		expect( timeToScrub( 2, 1000, 4 ) ).toBe( 500 );
		expect( timeToScrub( 0.9, 1000, 0.9 ) ).toBe( 1000 );
		for ( const v of [ 0, 1, 333, 999, 1000 ] ) expect( timeToScrub( scrubToTime( v, 1000, 3.7 ), 1000, 3.7 ) ).toBe( v );
		expect( timeToScrub( 1, 1000, 0 ) ).toBe( 0 );

	} );

	it( 'speed scales the clock, 0.25× to 2×', () => {

		expect( advance( 0, 0.1, 1, 4 ) ).toBeCloseTo( 0.1 );
		expect( advance( 0, 0.1, 2, 4 ) ).toBeCloseTo( 0.2 );
		expect( advance( 0, 0.1, 0.25, 4 ) ).toBeCloseTo( 0.025 );
		expect( clampSpeed( 8 ) ).toBe( 2 );
		expect( clampSpeed( 0.01 ) ).toBe( 0.25 );
		expect( clampSpeed( 'x' ) ).toBe( 1 );

	} );

	it( 'loops round, or stops at the end', () => {

		expect( advance( 3.9, 0.2, 1, 4 ) ).toBeCloseTo( 0.1 );
		expect( advance( 3.9, 0.2, 1, 4, false ) ).toBe( 4 );
		expect( advance( 1, 0.1, 1, 0 ) ).toBe( 0 );

	} );

	it( 'clamps into the clip (the last frame stays shown at the end)', () => {

		expect( clampTime( - 1, 4 ) ).toBe( 0 );
		expect( clampTime( 5, 4 ) ).toBe( 4 - END_EPSILON );
		expect( clampTime( NaN, 4 ) ).toBe( 0 );

	} );

	it( 'frame i is at i / fps', () => {

		expect( frameAt( 0, 30 ) ).toBe( 0 );
		expect( frameAt( 1 / 30, 30 ) ).toBe( 1 );
		expect( frameAt( 0.0333333, 30 ) ).toBe( 1 ); // float32 keyframe times rounded down
		expect( frameAt( 0.9, 30, 28 ) ).toBe( 27 );
		expect( frameAt( 5, 30, 28 ) ).toBe( 27 );
		expect( fpsFromTimes( Float32Array.from( [ 0, 1 / 30, 2 / 30, 3 / 30 ] ) ) ).toBe( 30 );
		expect( fpsFromTimes( [ 0 ] ) ).toBe( 30 );
		expect( formatTime( 1.25 ) ).toBe( '0:01.25' );
		expect( formatTime( 61.5 ) ).toBe( '1:01.50' );

	} );

} );

describe( 'chunks', () => {

	it( 'chooses the chunk that holds a frame (64 targets, one frame shared)', () => {

		expect( chunkForFrame( 0, 28 ) ).toBe( 0 );
		expect( chunkForFrame( 27, 28 ) ).toBe( 0 );
		expect( chunkForFrame( 62, 121 ) ).toBe( 0 );
		expect( chunkForFrame( 63, 121 ) ).toBe( 1 ); // the shared frame: the later chunk
		expect( chunkForFrame( 120, 121 ) ).toBe( 1 );
		expect( chunkForFrame( 126, 127 ) ).toBe( 1 ); // 127 frames: chunk 1 ends exactly on 126
		expect( chunkForFrame( 126, 128 ) ).toBe( 2 );
		expect( chunkForFrame( 999, 128 ) ).toBe( 2 );

	} );

} );

describe( 'Transport', () => {

	it( 'plays, pauses, seeks and ticks at its speed', () => {

		const t = new Transport( 2 );
		const seen = [];
		t.on( ( x ) => seen.push( x.time ) );
		expect( t.tick( 0.5 ) ).toBe( false ); // paused: nothing moves
		t.play();
		t.tick( 0.5 );
		expect( t.time ).toBeCloseTo( 0.5 );
		t.setSpeed( 2 );
		t.tick( 0.25 );
		expect( t.time ).toBeCloseTo( 1.0 );
		t.tick( 0.6 );
		expect( t.time ).toBeCloseTo( 0.2 ); // looped
		t.pause();
		t.seek( 5 );
		expect( t.time ).toBe( 2 - END_EPSILON );
		expect( t.shownTime() ).toBe( 2 - END_EPSILON );
		expect( seen.length ).toBeGreaterThan( 4 );

	} );

} );
