import { describe, it, expect, vi } from 'vitest';
import { reduceProgress, initialProgress, followTryon, stageLabel, formatPercent, parseEventData } from '../src/progress.js';

const ev = ( type, data ) => ( { type, data } );

describe( 'reduceProgress', () => {

	it( 'follows the stages and never goes back', () => {

		let s = initialProgress();
		s = reduceProgress( s, ev( 'progress', { status: 'running', progress: 0.2, stage: 'settling' } ) );
		expect( s ).toMatchObject( { status: 'running', progress: 0.2, stage: 'settling', ended: false } );
		s = reduceProgress( s, ev( 'progress', { status: 'queued', progress: 0, stage: 'queued' } ) ); // a retried job
		expect( s.progress ).toBe( 0.2 );
		expect( s.stage ).toBe( 'queued' );
		s = reduceProgress( s, ev( 'progress', { status: 'running', progress: 0.75, stage: 'compressing' } ) );
		expect( s.progress ).toBe( 0.75 );

	} );

	it( 'ends on done with progress 1 and keeps the try-on', () => {

		let s = reduceProgress( initialProgress(), ev( 'progress', { status: 'running', progress: 0.8, stage: 'preview' } ) );
		s = reduceProgress( s, ev( 'done', { id: 'x', status: 'done', progress: 1, stage: 'done', result_url: '/api/tryons/x/result.glb' } ) );
		expect( s ).toMatchObject( { status: 'done', progress: 1, ended: true, error: null } );
		expect( s.tryon.result_url ).toBe( '/api/tryons/x/result.glb' );
		expect( reduceProgress( s, ev( 'progress', { status: 'running', progress: 0.1 } ) ) ).toBe( s ); // ended: frozen

	} );

	it( 'keeps the failure reason', () => {

		const s = reduceProgress( initialProgress(), ev( 'failed', { status: 'failed', progress: 0.3, error: 'the seam front/back would not close' } ) );
		expect( s ).toMatchObject( { status: 'failed', stage: 'failed', ended: true, error: 'the seam front/back would not close', progress: 0.3 } );
		const c = reduceProgress( initialProgress(), ev( 'cancelled', { status: 'cancelled', error: 'cancelled' } ) );
		expect( c ).toMatchObject( { status: 'cancelled', ended: true, error: 'cancelled' } );
		// the event type wins over a stale status
		const d = reduceProgress( initialProgress(), ev( 'failed', { id: 'x', status: 'failed', error: 'the try-on was deleted' } ) );
		expect( d.error ).toBe( 'the try-on was deleted' );

	} );

	it( 'ignores events without data', () => {

		const s = initialProgress();
		expect( reduceProgress( s, ev( 'progress', null ) ) ).toBe( s );
		expect( parseEventData( 'not json' ) ).toBeNull();

	} );

	it( 'words', () => {

		expect( stageLabel( 'walking' ) ).toBe( 'Simulating the walk' );
		expect( stageLabel( 'warping' ) ).toBe( 'Warping' );
		expect( formatPercent( 0.4594 ) ).toBe( '45 %' );
		expect( formatPercent( 2 ) ).toBe( '100 %' );

	} );

} );

class FakeEventSource {

	static last = null;
	constructor( url ) {

		this.url = url;
		this.listeners = {};
		this.closed = false;
		FakeEventSource.last = this;

	}

	addEventListener( type, fn ) {

		( this.listeners[ type ] ||= [] ).push( fn );

	}

	emit( type, data ) {

		for ( const fn of this.listeners[ type ] || [] ) fn( { data: JSON.stringify( data ) } );

	}

	close() {

		this.closed = true;

	}

}

describe( 'followTryon', () => {

	it( 'folds the events and closes the stream at the end', () => {

		const updates = [];
		const f = followTryon( 'x', { eventsUrl: '/api/tryons/x/events', getTryon: vi.fn(), onUpdate: ( s ) => updates.push( s ), EventSourceImpl: FakeEventSource } );
		const es = FakeEventSource.last;
		expect( es.url ).toBe( '/api/tryons/x/events' );
		es.emit( 'progress', { status: 'running', progress: 0.1, stage: 'placing' } );
		es.emit( 'progress', { status: 'running', progress: 0.5, stage: 'walking' } );
		es.emit( 'done', { status: 'done', progress: 1, stage: 'done' } );
		expect( updates.map( ( s ) => s.stage ) ).toEqual( [ 'placing', 'walking', 'done' ] );
		expect( es.closed ).toBe( true );
		expect( f.state().ended ).toBe( true );

	} );

	it( 'polls when the stream breaks, then opens it again', async () => {

		const timers = [];
		const updates = [];
		const getTryon = vi.fn().mockResolvedValue( { status: 'running', progress: 0.6, stage: 'walking' } );
		followTryon( 'x', {
			eventsUrl: 'e', getTryon, onUpdate: ( s ) => updates.push( s ), EventSourceImpl: FakeEventSource,
			setTimer: ( fn ) => timers.push( fn ), clearTimer: () => {},
		} );
		const first = FakeEventSource.last;
		first.onerror();
		expect( first.closed ).toBe( true );
		expect( timers.length ).toBe( 1 );
		await timers[ 0 ]();
		expect( getTryon ).toHaveBeenCalledWith( 'x' );
		expect( updates.at( - 1 ).progress ).toBe( 0.6 );
		expect( FakeEventSource.last ).not.toBe( first ); // reopened

	} );

	it( 'says when the server cannot be reached, and keeps trying', async () => {

		const timers = [];
		const err = Object.assign( new Error( 'unreachable' ), { name: 'NetworkError' } );
		const onUnreachable = vi.fn();
		followTryon( 'x', {
			eventsUrl: 'e', getTryon: vi.fn().mockRejectedValue( err ), onUpdate: () => {}, onUnreachable, EventSourceImpl: FakeEventSource,
			setTimer: ( fn ) => timers.push( fn ), clearTimer: () => {},
		} );
		FakeEventSource.last.onerror();
		await timers[ 0 ]();
		expect( onUnreachable ).toHaveBeenCalledOnce();
		expect( timers.length ).toBe( 2 );

	} );

} );
