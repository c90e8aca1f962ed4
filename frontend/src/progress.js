// A try-on's progress: its events (server-sent, docs/api.md) folded into one state.

export const STAGE_LABELS = {
	queued: 'Waiting for a free tailor',
	starting: 'Starting',
	placing: 'Laying the pattern pieces round the body',
	sewing: 'Sewing the seams',
	settling: 'Letting the fabric settle',
	relief: 'Relaxing the fabric',
	gait: 'Making the walk',
	skinning: 'Posing the body',
	blending: 'Stepping off',
	walking: 'Simulating the walk',
	exporting: 'Saving the result',
	compressing: 'Packing it for your browser',
	preview: 'Drawing the preview',
	done: 'Ready',
	failed: 'Failed',
	cancelled: 'Cancelled',
};

export const FINAL = [ 'done', 'failed', 'cancelled' ];

export function stageLabel( stage ) {

	if ( ! stage ) return '';
	return STAGE_LABELS[ stage ] || stage.charAt( 0 ).toUpperCase() + stage.slice( 1 );

}

/** "42 %" */
export function formatPercent( fraction ) {

	const f = Math.min( 1, Math.max( 0, Number( fraction ) || 0 ) );
	return `${ Math.floor( f * 100 ) } %`;

}

export const initialProgress = () => ( { status: 'queued', progress: 0, stage: 'queued', ended: false, error: null, tryon: null } );

/**
 * Fold one event (`type`: progress | done | failed | cancelled, `data`: the try-on JSON) or a
 * polled try-on (`type` absent) into the state. The fraction never goes back; an ended state
 * never changes.
 */
export function reduceProgress( state, { type, data } ) {

	if ( state.ended || ! data || typeof data !== 'object' ) return state;
	let status = data.status || state.status;
	if ( type && FINAL.includes( type ) ) status = type;
	const ended = FINAL.includes( status );
	const progress = status === 'done' ? 1 : Math.max( state.progress, Number( data.progress ) || 0 );
	return {
		status,
		progress,
		stage: ended ? status : ( data.stage || state.stage ),
		ended,
		error: ended && status !== 'done' ? ( data.error || ( status === 'cancelled' ? 'cancelled' : 'the try-on failed' ) ) : null,
		tryon: { ...( state.tryon || {} ), ...data },
	};

}

/** Parse an SSE message's data; null when it is not JSON. */
export function parseEventData( text ) {

	try {

		return JSON.parse( text );

	} catch {

		return null;

	}

}

/**
 * Follow a try-on until it ends: its events (EventSource), and, if the stream breaks, polls
 * of `getTryon` until the stream can be opened again. `onUpdate(state)` on every change;
 * `onUnreachable(err)` when the server cannot be reached (polling goes on). Returns `stop()`.
 */
export function followTryon( id, { eventsUrl, getTryon, onUpdate, onUnreachable = () => {}, EventSourceImpl = globalThis.EventSource, pollMs = 1500, setTimer = setTimeout, clearTimer = clearTimeout } ) {

	let state = initialProgress();
	let source = null;
	let timer = null;
	let stopped = false;

	const push = ( ev ) => {

		const next = reduceProgress( state, ev );
		if ( next === state ) return;
		state = next;
		onUpdate( state );
		if ( state.ended ) stop();

	};

	const open = () => {

		if ( stopped ) return;
		source = new EventSourceImpl( eventsUrl );
		for ( const type of [ 'progress', ...FINAL ] ) {

			source.addEventListener( type, ( e ) => push( { type, data: parseEventData( e.data ) } ) );

		}

		source.onerror = () => {

			// The stream broke (or the server closed it): never let EventSource retry on its own.
			if ( source ) source.close();
			source = null;
			if ( ! stopped ) timer = setTimer( poll, pollMs );

		};

	};

	const poll = async () => {

		timer = null;
		if ( stopped ) return;
		try {

			const t = await getTryon( id );
			push( { data: t } );
			if ( ! stopped ) open();

		} catch ( err ) {

			if ( stopped ) return;
			if ( err && err.name === 'NetworkError' ) onUnreachable( err );
			else if ( err && err.status === 404 ) {

				push( { type: 'failed', data: { status: 'failed', error: err.message } } );
				return;

			}

			timer = setTimer( poll, pollMs * 2 );

		}

	};

	function stop() {

		stopped = true;
		if ( source ) source.close();
		source = null;
		if ( timer ) clearTimer( timer );
		timer = null;

	}

	open();
	return { stop, state: () => state };

}
