// One try-on in a box: its progress while it runs (events, a bar, cancel), its failure reason,
// or, once done, the 3D player on a Stage (or the preview image where there is no WebGL).

import { getTryon, cancelTryon, tryonEventsUrl, resultUrl, previewUrl, thumbnailUrl, ApiError } from '../api.js';
import { followTryon, stageLabel, formatPercent } from '../progress.js';
import { urls } from '../router.js';
import { h, clear } from '../ui/dom.js';
import { errorNotice, notice, spinner, progressBar } from '../ui/feedback.js';
import { NO_WEBGL_MESSAGE } from '../viewer/webgl.js';
import { Stage } from '../viewer/stage.js';
import { loadGlb } from '../viewer/loader.js';
import { TryonPlayer } from './player.js';

/**
 * Mount try-on `id` into `box`. Callbacks: `onInfo(tryon)` whenever its JSON is known,
 * `onReady(player)` once the player is up, `onEnded(state)` for a failed or cancelled one.
 * Returns `{ dispose }`.
 */
export function mountTryon( box, id, { ctx, compress = true, label = 'The try-on', onInfo = () => {}, onReady = () => {}, onEnded = () => {} } ) {

	let follower = null;
	let stage = null;
	let prepared = null; // { view, stage }: made while the try-on runs, so the result shows sooner
	let player = null;
	let disposed = false;

	const dispose = () => {

		disposed = true;
		if ( follower ) follower.stop();
		if ( player ) player.dispose();
		if ( stage ) stage.dispose();
		if ( prepared && prepared.stage !== stage ) prepared.stage.dispose();
		follower = player = stage = prepared = null;

	};

	ctx.onCleanup( dispose );

	async function start() {

		clear( box ).append( spinner( 'Loading the try-on…' ) );
		let t;
		try {

			t = await getTryon( id, { signal: ctx.signal } );

		} catch ( err ) {

			if ( disposed || ! ctx.live ) return;
			clear( box ).append( errorNotice( err, err instanceof ApiError && err.status === 404 ? null : start ) );
			return;

		}

		if ( disposed ) return;
		onInfo( t );
		if ( t.status === 'done' ) showPlayer( t );
		else if ( t.status === 'failed' || t.status === 'cancelled' ) showEnded( { status: t.status, error: t.error, tryon: t } );
		else showProgress( t );

	}

	/** The player's stage made ahead (its WebGL context takes a while: ~0.25–0.6 s with
	 * software GL), while the simulation runs; none where WebGL 2 is missing. */
	function prepareStage() {

		if ( prepared || disposed || ! ( 'WebGL2RenderingContext' in window ) ) return;
		const view = h( 'div', { class: 'stage stage--player' } );
		try {

			prepared = { view, stage: new Stage( view, { label: `${ label }: the body walking in the garment. Drag to turn the view.` } ) };

		} catch {

			prepared = null;

		}

	}

	function showProgress( t ) {

		setTimeout( prepareStage, 0 ); // after the progress panel is drawn
		clear( box );
		const stageText = h( 'p', { class: 'progress__stage' } );
		const pct = h( 'span', { class: 'progress__pct' } );
		const bar = progressBar( `${ label }: simulation progress` );
		const contact = h( 'div', { class: 'progress__contact', 'aria-live': 'polite' } );
		const cancel = h( 'button', { type: 'button', class: 'button button--secondary' }, 'Cancel' );
		const panel = h( 'div', { class: 'progress', 'aria-live': 'polite' },
			h( 'div', { class: 'progress__main' },
				h( 'p', { class: 'progress__title' }, 'Sewing and simulating your try-on' ),
				h( 'div', { class: 'progress__line' }, stageText, pct ),
				bar.el,
				h( 'p', { class: 'muted small' }, 'The cloth is simulated frame by frame on our servers. You can leave this page and come back: the link keeps working.' ),
				contact,
				h( 'div', { class: 'progress__actions' }, cancel ),
			),
			t.garment_id ? h( 'img', { class: 'progress__img', src: thumbnailUrl( t.garment_id ), alt: '', width: 240, height: 360 } ) : null,
		);
		box.append( panel );

		const paint = ( s ) => {

			stageText.textContent = stageLabel( s.stage );
			pct.textContent = formatPercent( s.progress );
			bar.set( s.progress, `${ stageLabel( s.stage ) }, ${ formatPercent( s.progress ) }` );
			box.dataset.progress = String( s.progress );
			box.dataset.stage = s.stage;

		};

		paint( { stage: t.stage, progress: t.progress || 0 } );

		cancel.addEventListener( 'click', async () => {

			cancel.disabled = true;
			cancel.textContent = 'Cancelling…';
			try {

				await cancelTryon( id );

			} catch ( err ) {

				if ( ! ( err instanceof ApiError && err.code === 'finished' ) ) {

					cancel.disabled = false;
					cancel.textContent = 'Cancel';
					clear( contact ).append( errorNotice( err ) );

				}

			}

		} );

		follower = followTryon( id, {
			eventsUrl: tryonEventsUrl( id ),
			getTryon: ( x ) => getTryon( x ),
			onUnreachable: () => {

				clear( contact ).append( notice( 'warn', 'Lost contact with the server', 'Trying again…' ) );

			},
			onUpdate: ( s ) => {

				if ( disposed ) return;
				clear( contact );
				if ( s.tryon ) onInfo( s.tryon );
				paint( s );
				if ( ! s.ended ) return;
				follower = null;
				if ( s.status === 'done' ) showPlayer( s.tryon );
				else showEnded( s );

			},
		} );

	}

	function showEnded( s ) {

		clear( box );
		const t = s.tryon || {};
		const back = t.garment_id ? h( 'a', { class: 'button button--secondary', href: urls.garment( t.garment_id ), 'data-link': '' }, 'Back to the garment' ) : null;
		if ( s.status === 'cancelled' ) {

			box.append( notice( 'info', 'This try-on was cancelled', s.error && s.error !== 'cancelled' ? `(${ s.error })` : 'Nothing was kept.', back ) );

		} else {

			box.append( notice( 'error', 'This try-on failed', s.error || 'The simulation stopped without saying why.', back ) );

		}

		box.dataset.status = s.status;
		onEnded( s );

	}

	async function showPlayer( t ) {

		performance.mark( 'catwalk:result-ready' ); // the try-on is done: from here to the first frame
		clear( box );
		box.dataset.status = 'done';
		const noWebGL = () => {

			clear( box );
			box.append(
				notice( 'warn', 'No 3D in this browser', `${ NO_WEBGL_MESSAGE } Here are four moments of the walk instead.` ),
				h( 'img', { class: 'preview-img', src: previewUrl( id ), alt: 'Four moments of the walk, from the front and the side', width: 1440, height: 1080 } ),
			);

		};

		if ( ! ( 'WebGL2RenderingContext' in window ) ) return noWebGL();
		const view = prepared ? prepared.view : h( 'div', { class: 'stage stage--player' } );
		const loading = h( 'div', { class: 'stage__overlay' }, h( 'p', {}, 'Loading the 3D walk…' ) );
		const bar = progressBar( 'Download progress' );
		loading.append( bar.el );
		view.append( loading );
		box.append( view );
		// the download first: a WebGL context takes a while to make (software GL: ~0.25 s
		// each), so the file comes meanwhile; the stage itself tells whether WebGL 2 works
		const download = loadGlb( resultUrl( id, { compress } ), ( f ) => {

			if ( f === null ) bar.indeterminate( true );
			else bar.set( f );

		} );
		download.catch( () => {} ); // awaited below; no unhandled rejection meanwhile
		try {

			stage = prepared ? prepared.stage : new Stage( view, { label: `${ label }: the body walking in the garment. Drag to turn the view.` } );
			prepared = null;
			stage.resize();

		} catch {

			return noWebGL();

		}
		let gltf;
		try {

			gltf = await download;

		} catch ( err ) {

			if ( disposed ) return;
			loading.replaceChildren( notice( 'error', 'The 3D walk did not load', err && err.message ? err.message : String( err ), { label: 'Try again', onClick: () => {

				stage.dispose();
				stage = null;
				showPlayer( t );

			} } ) );
			return;

		}

		if ( disposed ) return;
		performance.mark( 'catwalk:result-loaded' );
		loading.remove();
		player = new TryonPlayer( stage, gltf );
		player.tryon = t;
		onReady( player, stage );

	}

	start();
	return { dispose };

}
