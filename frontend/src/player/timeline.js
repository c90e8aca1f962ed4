// The player's clock: pure time math (no three.js), shared by one player or two in sync.

export const SPEEDS = [ 0.25, 0.5, 1, 1.5, 2 ];
export const MIN_SPEED = 0.25;
export const MAX_SPEED = 2;

/** The last moment that still shows the clip's last frame (a looping mixer wraps at `duration`). */
export const END_EPSILON = 1e-4;

export function clampSpeed( speed ) {

	const s = Number( speed );
	if ( ! Number.isFinite( s ) ) return 1;
	return Math.min( MAX_SPEED, Math.max( MIN_SPEED, s ) );

}

/** Clamp a time into [0, duration − ε] (what the mixer is asked to show). */
export function clampTime( t, duration ) {

	if ( ! ( duration > 0 ) ) return 0;
	if ( ! Number.isFinite( t ) || t < 0 ) return 0;
	return Math.min( t, Math.max( 0, duration - END_EPSILON ) );

}

/** The time after `dt` seconds of wall clock at `speed`: wraps round when `loop`, else stops at the end. */
export function advance( t, dt, speed, duration, loop = true ) {

	if ( ! ( duration > 0 ) ) return 0;
	const next = t + Math.max( 0, dt ) * clampSpeed( speed );
	if ( next < duration ) return next;
	if ( ! loop ) return duration;
	return next % duration;

}

/** Scrubber position (0..steps) → time; time → scrubber position. */
export function scrubToTime( value, steps, duration ) {

	if ( ! ( steps > 0 ) ) return 0;
	const f = Math.min( 1, Math.max( 0, Number( value ) / steps ) );
	return f * duration;

}

export function timeToScrub( t, steps, duration ) {

	if ( ! ( duration > 0 ) ) return 0;
	const f = Math.min( 1, Math.max( 0, t / duration ) );
	return Math.round( f * steps );

}

/** The frame shown at time `t` (frame i is at i / fps) — the last whose time ≤ t. */
export function frameAt( t, fps, frames = Infinity ) {

	const i = Math.floor( t * fps + 1e-6 );
	return Math.max( 0, Math.min( frames - 1, i ) );

}

/** fps from keyframe times (the median step), when the file does not say it. */
export function fpsFromTimes( times ) {

	if ( ! times || times.length < 2 ) return 30;
	const steps = [];
	for ( let i = 1; i < times.length; i ++ ) steps.push( times[ i ] - times[ i - 1 ] );
	steps.sort( ( a, b ) => a - b );
	const dt = steps[ Math.floor( steps.length / 2 ) ];
	if ( ! ( dt > 0 ) ) return 30;
	return Math.round( 1000 / dt ) / 1000; // 29.99999 → 30
}

/** "0:01.25" */
export function formatTime( t ) {

	const s = Math.max( 0, t );
	const m = Math.floor( s / 60 );
	const rest = s - m * 60;
	return `${ m }:${ rest.toFixed( 2 ).padStart( 5, '0' ) }`;

}

/**
 * Chunks of a garment's frames (at most `size` morph targets each, consecutive chunks sharing
 * one frame): chunk k holds frames [k·(size−1), k·(size−1) + size − 1]. The chunk that shows
 * frame `frame` (a frame shared by two chunks: the later one, which then keeps on showing).
 */
export function chunkForFrame( frame, frames, size = 64 ) {

	if ( frames <= size ) return 0;
	const step = size - 1;
	const last = Math.ceil( ( frames - 1 ) / step ) - 1;
	return Math.max( 0, Math.min( last, Math.floor( frame / step ) ) );

}

/**
 * One clock for one or several players: time, playing, speed; `tick(dt)` moves it on.
 * Listeners get the clock after every change.
 */
export class Transport {

	constructor( duration = 0 ) {

		this.duration = duration;
		this.time = 0;
		this.playing = false;
		this.speed = 1;
		this.loop = true;
		this.listeners = new Set();

	}

	on( fn ) {

		this.listeners.add( fn );
		return () => this.listeners.delete( fn );

	}

	emit() {

		for ( const fn of this.listeners ) fn( this );

	}

	setDuration( d ) {

		this.duration = Math.max( 0, d );
		this.time = clampTime( this.time, this.duration );
		this.emit();

	}

	play() {

		if ( this.time >= this.duration - END_EPSILON && ! this.loop ) this.time = 0;
		this.playing = true;
		this.emit();

	}

	pause() {

		this.playing = false;
		this.emit();

	}

	toggle() {

		if ( this.playing ) this.pause();
		else this.play();

	}

	seek( t ) {

		this.time = clampTime( t, this.duration );
		this.emit();

	}

	setSpeed( s ) {

		this.speed = clampSpeed( s );
		this.emit();

	}

	/** The shown time (clamped for the mixer). */
	shownTime() {

		return clampTime( this.time, this.duration );

	}

	tick( dt ) {

		if ( ! this.playing ) return false;
		this.time = advance( this.time, dt, this.speed, this.duration, this.loop );
		if ( ! this.loop && this.time >= this.duration ) this.playing = false;
		this.emit();
		return true;

	}

}
