// The player's controls: play/pause, the timeline, speed, camera presets, follow, fit map,
// download. They drive a Transport (one clock) and any number of players (compare: two).

import { h, append, nextId, icon } from '../ui/dom.js';
import { SPEEDS, formatTime, scrubToTime, timeToScrub } from './timeline.js';
import { scaleGradientCss, STRAIN_LIMIT } from './stretch.js';

const STEPS = 1000;

/** The fit map's legend: the colour scale from 0 to the strain limit (hidden at first). */
export function fitLegend() {

	return h( 'div', { class: 'legend', hidden: true, 'aria-live': 'polite' },
		h( 'span', { class: 'legend__label' }, 'Stretch' ),
		h( 'span', { class: 'legend__scale', style: { background: scaleGradientCss() } } ),
		h( 'span', { class: 'legend__ticks' }, h( 'span', {}, '0 %' ), h( 'span', {}, `${ STRAIN_LIMIT * 50 } %` ), h( 'span', {}, `≥ ${ STRAIN_LIMIT * 100 } %` ) ),
		h( 'span', { class: 'legend__note' }, 'Warm colours: the fabric is stretched towards its limit there.' ),
	);

}

/** "Fit map" (a toggle) and its legend, for the `player` (one dressed view: the merchant's preview, a garment page). */
export function fitMapToggle( player ) {

	const legend = fitLegend();
	const toggle = h( 'button', { type: 'button', class: 'seg seg--toggle', 'aria-pressed': 'false' }, 'Fit map' );
	toggle.addEventListener( 'click', () => {

		const on = toggle.getAttribute( 'aria-pressed' ) !== 'true';
		toggle.setAttribute( 'aria-pressed', String( on ) );
		player.setFitMap( on );
		legend.hidden = ! on;

	} );
	return [ h( 'div', { class: 'segs' }, toggle ), legend ];

}

export function createControls( { transport, players, fps = 30, downloads = [], fitMapNote = null } ) {

	const fitMapAvailable = players.length > 0 && players.every( ( p ) => p.fitMap );
	const root = h( 'div', { class: 'controls', role: 'group', 'aria-label': 'Player controls' } );

	// play / pause
	const play = h( 'button', { type: 'button', class: 'icon-button icon-button--play', 'aria-label': 'Play' } );
	play.addEventListener( 'click', () => transport.toggle() );

	// timeline
	const scrubId = nextId( 'scrub' );
	const scrub = h( 'input', { type: 'range', id: scrubId, class: 'timeline', min: 0, max: STEPS, step: 1, value: 0, 'aria-label': 'Timeline' } );
	let wasPlaying = false;
	let dragging = false;
	scrub.addEventListener( 'pointerdown', () => {

		dragging = true;
		wasPlaying = transport.playing;
		transport.pause();

	} );
	const endDrag = () => {

		if ( ! dragging ) return;
		dragging = false;
		if ( wasPlaying ) transport.play();

	};

	scrub.addEventListener( 'pointerup', endDrag );
	scrub.addEventListener( 'pointercancel', endDrag );
	scrub.addEventListener( 'input', () => {

		if ( ! dragging ) transport.pause();
		transport.seek( scrubToTime( scrub.value, STEPS, transport.duration ) );

	} );
	const clock = h( 'span', { class: 'clock', 'aria-hidden': 'true' } );

	// speed
	const speedId = nextId( 'speed' );
	const speed = h( 'select', { id: speedId, class: 'speed' } );
	for ( const s of SPEEDS ) speed.append( h( 'option', { value: String( s ), selected: s === 1 }, `${ s }×` ) );
	speed.addEventListener( 'change', () => transport.setSpeed( Number( speed.value ) ) );

	// camera
	const viewButtons = [ 'front', 'side', 'back' ].map( ( v ) => {

		const b = h( 'button', { type: 'button', class: 'seg', 'aria-pressed': String( v === 'front' ), 'data-view': v }, v[ 0 ].toUpperCase() + v.slice( 1 ) );
		b.addEventListener( 'click', () => {

			for ( const o of viewButtons ) o.setAttribute( 'aria-pressed', String( o === b ) );
			for ( const p of players ) p.setView( v );

		} );
		return b;

	} );
	const follow = h( 'button', { type: 'button', class: 'seg seg--toggle', 'aria-pressed': 'true', title: 'Keep the camera on the walker' }, 'Follow' );
	follow.addEventListener( 'click', () => {

		const on = follow.getAttribute( 'aria-pressed' ) !== 'true';
		follow.setAttribute( 'aria-pressed', String( on ) );
		for ( const p of players ) p.setFollow( on );

	} );

	// fit map
	const legend = fitLegend();
	const fit = h( 'button', { type: 'button', class: 'seg seg--toggle', 'aria-pressed': 'false', disabled: ! fitMapAvailable, 'aria-describedby': null }, 'Fit map' );
	const fitNote = fitMapAvailable ? null : h( 'p', { class: 'controls__note', id: nextId( 'fitnote' ) }, fitMapNote || 'The fit map needs a newer try-on file (one with its pattern coordinates); this one has none.' );
	if ( fitNote ) fit.setAttribute( 'aria-describedby', fitNote.id );
	fit.addEventListener( 'click', () => {

		const on = fit.getAttribute( 'aria-pressed' ) !== 'true';
		fit.setAttribute( 'aria-pressed', String( on ) );
		for ( const p of players ) p.setFitMap( on );
		legend.hidden = ! on;

	} );

	append( root, [
		h( 'div', { class: 'controls__row controls__row--time' }, play, scrub, clock ),
		h( 'div', { class: 'controls__row controls__row--options' },
			h( 'div', { class: 'control' }, h( 'label', { for: speedId, class: 'control__label' }, 'Speed' ), speed ),
			h( 'div', { class: 'control' }, h( 'span', { class: 'control__label', id: `${ speedId }-cam` }, 'Camera' ),
				h( 'div', { class: 'control__group' },
					h( 'div', { class: 'segs', role: 'group', 'aria-labelledby': `${ speedId }-cam` }, viewButtons ),
					h( 'div', { class: 'segs' }, follow ) ) ),
			h( 'div', { class: 'control' }, h( 'span', { class: 'control__label' }, 'Fit' ), h( 'div', { class: 'segs' }, fit ) ),
			downloads.length ? h( 'div', { class: 'control control--downloads' }, downloads.map( ( d ) => h( 'a', { class: 'button button--secondary button--small', href: d.href, download: d.filename || '' }, icon( 'download' ), d.label ) ) ) : null,
		),
		fitNote,
		legend,
	] );

	const update = () => {

		const playing = transport.playing;
		play.innerHTML = '';
		play.append( icon( playing ? 'pause' : 'play' ) );
		play.setAttribute( 'aria-label', playing ? 'Pause' : 'Play' );
		if ( ! dragging ) scrub.value = String( timeToScrub( transport.time, STEPS, transport.duration ) );
		const frame = Math.floor( transport.shownTime() * fps + 1e-6 );
		scrub.setAttribute( 'aria-valuetext', `${ transport.shownTime().toFixed( 2 ) } seconds of ${ transport.duration.toFixed( 2 ) }, frame ${ frame }` );
		clock.textContent = `${ formatTime( transport.shownTime() ) } / ${ formatTime( transport.duration ) }`;

	};

	let lastPlaying = null;
	let lastShown = - 1;
	const off = transport.on( () => {

		// the clock text every change; the button only when it flips
		if ( lastPlaying !== transport.playing ) {

			lastPlaying = transport.playing;
			update();

		} else if ( Math.abs( transport.time - lastShown ) > 0.005 ) {

			lastShown = transport.time;
			if ( ! dragging ) scrub.value = String( timeToScrub( transport.time, STEPS, transport.duration ) );
			clock.textContent = `${ formatTime( transport.shownTime() ) } / ${ formatTime( transport.duration ) }`;

		}

	} );
	update();

	// keyboard: space plays/pauses, arrows step a frame
	const onKey = ( e ) => {

		if ( e.target.closest && e.target.closest( 'select, input[type=text], textarea' ) ) return;
		if ( e.key === ' ' || e.key === 'k' ) {

			if ( e.target.tagName === 'BUTTON' && e.key === ' ' ) return; // the button's own click
			e.preventDefault();
			transport.toggle();

		} else if ( ( e.key === 'ArrowLeft' || e.key === 'ArrowRight' ) && e.target !== scrub ) {

			e.preventDefault();
			transport.pause();
			transport.seek( transport.time + ( e.key === 'ArrowLeft' ? - 1 : 1 ) / fps );

		}

	};

	return {
		el: root,
		legend,
		onKey,
		update,
		dispose: () => off(),
	};

}
