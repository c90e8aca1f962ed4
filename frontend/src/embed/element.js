// <catwalk-tryon garment="ID" size="M" key="pk_…">: catwalk's try-on on a merchant's shop page
// (docs/embed.md). In its own shadow root (the shop's styles stay out, its own stay in): a
// "Try it on" button; then the shopper's body (measurements or a scan, remembered on this shop
// under the shopper's own id: shopper.js), the try-on's progress, the player with the fit map
// and the size advice, and "Choose size M" → the `catwalk:size` event on the element, for the
// shop's page. It talks to the service it was loaded from, and nothing else.

import { configureApi, getGarment, getBody, deleteBody, createTryon, cancelTryon, getTryon, tryonEventsUrl, resultUrl, getSizeAdvice, ApiError } from '../api.js';
import { followTryon, stageLabel, formatPercent } from '../progress.js';
import { h, clear } from '../ui/dom.js';
import { notice, errorNotice, spinner, progressBar } from '../ui/feedback.js';
import { shortName } from '../format.js';
import pageCss from '../styles.css?inline';
import embedCss from './embed.css?inline';
import { toShadowCss } from './shadow-css.js';
import { shopperId, rememberedBody, rememberBody, forgetBody } from './shopper.js';
import { bodyStep } from './body-step.js';
import { sizePanel } from './size-panel.js';
import { setupMessage, isSetupError, attributeProblem } from './messages.js';

const SERVICE = new URL( import.meta.url ).origin;
const loadPlayer = () => import( './player-view.js' );
const PRESETS = [ 'fast', 'balanced', 'accurate' ];
let css = null;
let sheet = null;
let pageKey = null; // the publishable key the components on this page use

/** The walk's length and quality from the attributes (`seconds` 0.5–10, default 3; `preset`). */
export function walkOptions( el ) {

	const s = Number( el.getAttribute( 'seconds' ) );
	const preset = el.getAttribute( 'preset' );
	return {
		seconds: Number.isFinite( s ) && s >= 0.5 && s <= 10 ? s : 3,
		preset: PRESETS.includes( preset ) ? preset : 'fast',
	};

}

export class CatwalkTryon extends HTMLElement {

	static observedAttributes = [ 'garment', 'size', 'key' ];

	constructor() {

		super();
		this.attachShadow( { mode: 'open' } );
		this.garment = null;
		this.flow = null; // the open try-on: its requests, follower, player
		this.loading = null;
		this.pending = false;

	}

	connectedCallback() {

		this.soon();

	}

	disconnectedCallback() {

		this.stop();

	}

	attributeChangedCallback( name, was, now ) {

		if ( was !== now && this.isConnected && ! this.flow ) this.soon();

	}

	/** Back to the button once the attributes have settled (an element upgraded on a parsed
	 * page is told of each attribute, then connected: one start for all). */
	soon() {

		if ( this.pending ) return;
		this.pending = true;
		queueMicrotask( () => {

			this.pending = false;
			if ( this.isConnected ) this.idle();

		} );

	}

	get key() {

		return ( this.getAttribute( 'key' ) || '' ).trim();

	}

	emit( name, detail ) {

		this.dispatchEvent( new CustomEvent( `catwalk:${ name }`, { detail, bubbles: true, composed: true } ) );

	}

	step( name, ...content ) {

		this.dataset.step = name;
		const root = this.shadowRoot;
		clear( root );
		css ??= toShadowCss( pageCss ) + embedCss;
		// a constructed sheet (one for every component, and no inline style for a shop's
		// Content-Security-Policy to refuse); a <style> where the browser has none
		if ( 'adoptedStyleSheets' in root && 'replaceSync' in CSSStyleSheet.prototype ) {

			if ( ! sheet ) {

				sheet = new CSSStyleSheet();
				sheet.replaceSync( css );

			}

			root.adoptedStyleSheets = [ sheet ];

		} else {

			root.append( h( 'style', {}, css ) );

		}

		root.append( h( 'div', { class: 'cw', part: 'root' }, ...content ) );

	}

	/** The button, once the garment is known; the reason when the set-up is refused. */
	async idle() {

		this.stop();
		const open = h( 'button', { type: 'button', class: 'button button--primary cw-open', disabled: true }, 'Try it on' );
		open.addEventListener( 'click', () => this.open() );
		this.step( 'idle', h( 'div', { class: 'cw-bar' }, open, h( 'p', { class: 'cw-note' }, 'See it walk on your own body' ) ) );
		try {

			this.garment = await this.loadGarment();

		} catch ( err ) {

			this.refused( err );
			return;

		}

		if ( this.dataset.step !== 'idle' ) return;
		open.disabled = false;
		open.setAttribute( 'aria-label', `Try it on: ${ shortName( this.garment.name ) }` );

	}

	loadGarment() {

		const garment = ( this.getAttribute( 'garment' ) || '' ).trim();
		const problem = attributeProblem( { garment, key: this.key } );
		if ( problem ) return Promise.reject( new ApiError( 400, { code: 'attributes', message: problem } ) );
		if ( pageKey && pageKey !== this.key ) {

			return Promise.reject( new ApiError( 400, { code: 'attributes', message: 'Every catwalk try-on on a page uses the same key; this one names another.' } ) );

		}

		pageKey = this.key;
		configureApi( { base: SERVICE, key: this.key, headers: { 'X-Catwalk-Shopper': shopperId() } } );
		// a plain request (no header of ours, so no preflight): a refusal can be read and shown
		return ( this.loading ??= getGarment( garment, { plain: true } ).finally( () => {

			this.loading = null;

		} ) );

	}

	refused( err ) {

		const { title, text } = setupMessage( err );
		this.step( 'refused', notice( 'error', title, text ) );
		this.emit( 'error', { code: err.code || err.name, status: err.status || null, message: text } );
		if ( isSetupError( err ) || err.code === 'attributes' ) console.warn( `catwalk: ${ text }` );

	}

	/** The flow's frame: a title, the step, a line about the body kept; `ctx` for its requests. */
	frame( title ) {

		this.stop();
		const controller = new AbortController();
		const cleanups = [];
		const ctx = {
			signal: controller.signal,
			get live() {

				return ! controller.signal.aborted;

			},
			onCleanup: ( fn ) => cleanups.push( fn ),
		};
		const body = h( 'div', { class: 'cw-step' } );
		const close = h( 'button', { type: 'button', class: 'icon-button cw-close', 'aria-label': 'Close the try-on' }, '×' );
		close.addEventListener( 'click', () => this.idle() );
		const heading = h( 'p', { class: 'cw-title' }, title );
		const foot = h( 'div', { class: 'cw-foot' } );
		this.flow = { controller, cleanups, ctx, body, heading, foot };
		this.step( 'open', h( 'section', { class: 'cw-panel', 'aria-label': `Try-on: ${ shortName( this.garment.name ) }` },
			h( 'header', { class: 'cw-head' }, heading, close ), body, foot ) );
		return this.flow;

	}

	stop() {

		const f = this.flow;
		this.flow = null;
		if ( ! f ) return;
		f.controller.abort();
		for ( const fn of f.cleanups.reverse() ) {

			try {

				fn();

			} catch ( err ) {

				console.warn( 'catwalk: cleanup failed', err );

			}

		}

	}

	/** "Try it on": the shopper's body kept on this shop, else the body step. */
	async open() {

		const f = this.frame( shortName( this.garment.name ) );
		const kept = rememberedBody( this.key );
		if ( ! kept ) return this.askBody( f );
		f.body.append( spinner( 'Finding your body…' ) );
		try {

			const body = await getBody( kept, { signal: f.ctx.signal } );
			if ( f.ctx.live ) this.tryOn( body, this.getAttribute( 'size' ) );

		} catch ( err ) {

			if ( ! f.ctx.live ) return;
			if ( err instanceof ApiError && err.status === 404 ) {

				forgetBody( this.key );
				this.askBody( f, notice( 'warn', 'Your body is no longer kept here', 'Give it again below.' ) );

			} else {

				clear( f.body ).append( errorNotice( err, () => this.open() ) );

			}

		}

	}

	askBody( f = this.frame( shortName( this.garment.name ) ), note = null ) {

		this.dataset.step = 'body';
		const previous = rememberedBody( this.key );
		clear( f.body ).append( bodyStep( ( body ) => {

			rememberBody( this.key, body.id );
			this.emit( 'body', { source: body.source } );
			// a new body replaces the one kept before: that one is deleted
			if ( previous && previous !== body.id ) deleteBody( previous ).catch( () => {} );
			this.tryOn( body, this.getAttribute( 'size' ) );

		}, f.ctx, note ) );

	}

	/** The body kept: its line under the step (change it, or delete it). */
	bodyLine( f, body ) {

		const m = body.measurements || {};
		const told = body.source === 'scan' ? 'from your scan' : `${ Math.round( ( m.height || 0 ) * 100 ) } cm tall`;
		const change = h( 'button', { type: 'button', class: 'link-button' }, 'Change' );
		const forget = h( 'button', { type: 'button', class: 'link-button' }, 'Delete my body' );
		change.addEventListener( 'click', () => this.askBody() );
		forget.addEventListener( 'click', async () => {

			forget.disabled = true;
			try {

				await deleteBody( body.id );

			} catch ( err ) {

				if ( ! ( err instanceof ApiError && err.status === 404 ) ) {

					forget.disabled = false;
					f.foot.append( errorNotice( err ) );
					return;

				}

			}

			forgetBody( this.key );
			this.emit( 'forgotten', {} );
			this.idle();

		} );
		clear( f.foot ).append( h( 'p', { class: 'cw-kept' }, `Your body (${ told }) is kept for this shop only. `, change, ' · ', forget ) );

	}

	/** Ask for the try-on in `size` (none: the size advised for the body), then follow it. */
	async tryOn( body, size = null ) {

		const f = this.frame( shortName( this.garment.name ) );
		this.dataset.step = 'progress';
		this.bodyLine( f, body );
		f.body.append( spinner( 'Asking for your try-on…' ) );
		try {

			if ( ! size || ! this.garment.sizes.includes( size ) ) {

				const advice = await getSizeAdvice( this.garment.id, body.id, { signal: f.ctx.signal } ).catch( () => null );
				size = ( advice && advice.recommended ) || this.garment.default_size;

			}

			f.heading.textContent = `${ shortName( this.garment.name ) } · size ${ size }`;
			const t = await createTryon( { body_id: body.id, garment_id: this.garment.id, size, ...walkOptions( this ) }, { signal: f.ctx.signal } );
			if ( f.ctx.live ) this.follow( f, body, t );

		} catch ( err ) {

			if ( ! f.ctx.live ) return;
			clear( f.body ).append( errorNotice( err, () => this.tryOn( body, size ) ) );
			if ( err instanceof ApiError && err.field === 'body_id' ) forgetBody( this.key );

		}

	}

	/** The progress (the player's code fetched and its stage made meanwhile), then the walk. */
	follow( f, body, t ) {

		const view = h( 'div', { class: 'stage stage--player cw-stage' } );
		const label = `${ shortName( this.garment.name ) } in size ${ t.size }: your body walking in it. Drag to turn the view.`;
		const ahead = loadPlayer().then( ( mod ) => ( { mod, stage: f.ctx.live ? mod.prepareStage( view, label ) : null } ) );
		ahead.catch( () => {} );
		f.cleanups.push( () => ahead.then( ( a ) => a.stage && ! f.player && a.stage.dispose() ).catch( () => {} ) );
		if ( t.status === 'done' ) return this.play( f, body, t, view, ahead, label );

		const stageText = h( 'p', { class: 'progress__stage' } );
		const pct = h( 'span', { class: 'progress__pct' } );
		const bar = progressBar( 'Try-on progress' );
		const cancel = h( 'button', { type: 'button', class: 'button button--secondary button--small' }, 'Cancel' );
		cancel.addEventListener( 'click', () => cancelTryon( t.id ).catch( () => {} ) );
		clear( f.body ).append( h( 'div', { class: 'progress cw-progress', 'aria-live': 'polite' },
			h( 'div', { class: 'progress__main' },
				h( 'p', { class: 'progress__title' }, 'Sewing and simulating your try-on' ),
				h( 'div', { class: 'progress__line' }, stageText, pct ), bar.el,
				h( 'div', { class: 'progress__actions' }, cancel ) ) ) );
		const paint = ( s ) => {

			stageText.textContent = stageLabel( s.stage );
			pct.textContent = formatPercent( s.progress );
			bar.set( s.progress, `${ stageLabel( s.stage ) }, ${ formatPercent( s.progress ) }` );
			this.dataset.progress = String( s.progress );

		};

		paint( t );
		const follower = followTryon( t.id, {
			eventsUrl: tryonEventsUrl( t.id ),
			getTryon: ( id ) => getTryon( id ),
			onUpdate: ( s ) => {

				if ( ! f.ctx.live ) return;
				paint( s );
				if ( ! s.ended ) return;
				if ( s.status === 'done' ) this.play( f, body, s.tryon, view, ahead, label );
				else this.ended( f, body, s );

			},
		} );
		f.cleanups.push( () => follower.stop() );

	}

	ended( f, body, s ) {

		this.dataset.step = 'ended';
		const again = { label: 'Try again', onClick: () => this.tryOn( body, s.tryon && s.tryon.size ) };
		clear( f.body ).append( s.status === 'cancelled'
			? notice( 'info', 'The try-on was cancelled', null, again )
			: notice( 'error', 'This try-on failed', s.error || 'The simulation stopped without saying why.', again ) );

	}

	/** The result is ready: the walk on the stage made ahead, its controls, the sizes. */
	async play( f, body, t, view, ahead, label ) {

		performance.mark( 'catwalk:result-ready' );
		this.dataset.step = 'player';
		const controlsBox = h( 'div', { class: 'tryon-controls' } );
		const wrap = h( 'div', { class: 'player cw-player', tabindex: '-1' }, view, controlsBox );
		const loading = h( 'div', { class: 'stage__overlay' }, h( 'p', {}, 'Loading the 3D walk…' ) );
		const bar = progressBar( 'Download progress' );
		loading.append( bar.el );
		view.append( loading );
		const sizes = sizePanel( {
			garment: this.garment, size: t.size, bodyId: body.id, ctx: f.ctx,
			onChoose: ( size, summary ) => {

				sizes.chosen( size );
				this.emit( 'size', { garment: this.garment.id, size, recommended: summary ? summary.recommended : null, fits: summary ? !! ( summary.sizes.find( ( x ) => x.size === size ) || {} ).fits : null, tryon: t.id } );

			},
			onTry: ( size ) => this.tryOn( body, size ),
		} );
		clear( f.body ).append( wrap, sizes.el );
		try {

			const { mod, stage } = await ahead;
			if ( ! f.ctx.live ) return;
			if ( ! mod.hasWebGL2() ) throw new Error( 'This browser cannot show 3D (WebGL 2 is off or missing).' );
			f.player = await mod.playTryon( { view, stage, url: resultUrl( t.id ), label, controlsBox, keyTarget: wrap, tryon: t, onProgress: ( x ) => ( x === null ? bar.indeterminate( true ) : bar.set( x ) ) } );
			if ( ! f.ctx.live ) return f.player.dispose();
			f.cleanups.push( () => f.player.dispose() );
			loading.remove();
			this.emit( 'ready', { garment: this.garment.id, size: t.size, tryon: t.id } );

		} catch ( err ) {

			if ( f.ctx.live ) loading.replaceChildren( notice( 'error', 'The 3D walk did not load', err && err.message ? err.message : String( err ) ) );

		}

	}

}

export function defineTryonElement( name = 'catwalk-tryon' ) {

	if ( ! customElements.get( name ) ) customElements.define( name, CatwalkTryon );

}
