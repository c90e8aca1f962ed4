// A saved version dressed on each size's sample body: the status of every size, the chosen
// size in 3D with the fit map (the .glb is fetched with the merchant's key and handed to the
// viewer as an object URL), the dressing report's numbers, and "Publish".

import { h, clear, nextId } from '../ui/dom.js';
import { spinner, notice, errorNotice } from '../ui/feedback.js';
import { hasWebGL } from '../viewer/webgl.js';
import { showDressed } from '../viewer/dressed-view.js';
import { fitLegend } from '../player/controls.js';
import { urls } from '../router.js';
import { fetchDressed, publishGarment, isUnauthorised } from './api.js';
import { versionOf, sizeStatus, reportRows, hasDressed } from './status.js';

export function createPreview( { signal, onUnauthorised = () => {}, onPublished = () => {} } ) {

	const sizesEl = h( 'div', { class: 'size-options', role: 'radiogroup', 'aria-label': 'Size to preview' } );
	const statusEl = h( 'p', { class: 'mp-preview__status', 'aria-live': 'polite' } );
	const view = h( 'div', { class: 'mp-preview__view stage', hidden: true } );
	const extras = h( 'div', { class: 'mp-preview__extras' } );
	const report = h( 'dl', { class: 'facts mp-report' } );
	const publishMsg = h( 'div', { 'aria-live': 'polite' } );
	const publishBtn = h( 'button', { type: 'button', class: 'button button--primary', disabled: true }, 'Publish' );
	const empty = h( 'div', { class: 'mp-preview__empty muted' }, 'The 3D view of a size appears here once it is dressed.' );
	const el = h( 'section', { class: 'panel mp-preview', 'aria-labelledby': 'mp-preview-title' },
		h( 'h2', { id: 'mp-preview-title' }, 'Preview' ),
		h( 'p', { class: 'muted small' }, 'After every save each size is dressed on its sample body on our servers. Choose a size to see it in 3D.' ),
		h( 'div', { class: 'mp-preview__grid' },
			h( 'div', { class: 'mp-preview__stage' }, empty, view, extras ),
			h( 'div', { class: 'mp-preview__info' },
				sizesEl, statusEl, report,
				h( 'div', { class: 'mp-actions' }, publishBtn ), publishMsg ),
		),
	);
	new MutationObserver( () => {

		empty.hidden = ! view.hidden;

	} ).observe( view, { attributes: true, attributeFilter: [ 'hidden' ] } );

	let item = null; // the merchant garment (with versions)
	let size = null;
	let shown = null; // { key, dispose, player }
	let loading = null; // key being loaded
	const name = nextId( 'pv-size' );

	const disposeShown = () => {

		if ( shown ) shown.dispose();
		shown = null;
		loading = null;
		clear( extras );
		view.hidden = true;
		clear( view );

	};

	signal.addEventListener( 'abort', disposeShown, { once: true } );

	publishBtn.addEventListener( 'click', async () => {

		if ( ! item ) return;
		publishBtn.disabled = true;
		clear( publishMsg ).append( spinner( 'Publishing…' ) );
		try {

			const res = await publishGarment( item.id, item.version, { signal } );
			const gid = ( res && ( res.catalogue_id || res.garment_id ) ) || item.id;
			item.published_version = ( res && res.published_version ) ?? item.version;
			clear( publishMsg ).append( notice( 'info', `Published version ${ item.published_version }`, 'Shoppers can now find it in the catalogue.',
				h( 'span', { class: 'mp-actions' },
					h( 'a', { class: 'button button--secondary', href: urls.catalogue(), 'data-link': '' }, 'Open the catalogue' ),
					h( 'a', { class: 'button button--secondary', href: urls.garment( gid ), 'data-link': '' }, 'Its catalogue page' ),
				) ) );
			onPublished( res );

		} catch ( err ) {

			if ( err && err.name === 'AbortError' ) return;
			if ( isUnauthorised( err ) ) return onUnauthorised();
			clear( publishMsg ).append( errorNotice( err ) );

		} finally {

			refreshPublish();

		}

	} );

	function refreshPublish() {

		const v = item && versionOf( item );
		publishBtn.disabled = ! v;
		publishBtn.textContent = item && item.published_version === item.version ? `Version ${ item.version } is published` : v ? `Publish version ${ v.version }` : 'Publish';
		if ( item && item.published_version === item.version ) publishBtn.disabled = true;

	}

	/** Show the garment `it` (its latest version). */
	function update( it ) {

		item = it;
		const v = versionOf( item );
		const sizes = ( item && item.sizes ) || [];
		const def = item && ( item.default_size || ( item.garment && item.garment.default_size ) );
		if ( ! size || ! sizes.includes( size ) ) size = def && sizes.includes( def ) ? def : sizes[ Math.floor( sizes.length / 2 ) ] || null;
		clear( sizesEl );
		for ( const s of sizes ) {

			const id = nextId( 'pv' );
			const st = sizeStatus( v && v.dressing && v.dressing[ s ] );
			sizesEl.append( h( 'span', { class: 'size-option' },
				h( 'input', { type: 'radio', name, id, value: s, checked: s === size, onchange: () => {

					size = s;
					update( item );

				} } ),
				h( 'label', { for: id }, s, h( 'span', { class: `mp-dot mp-dot--${ st.kind }`, 'aria-hidden': 'true' } ), h( 'span', { class: 'visually-hidden' }, `: ${ st.text }` ) ),
			) );

		}

		refreshPublish();
		const entry = v && v.dressing && size ? v.dressing[ size ] : null;
		const st = sizeStatus( entry );
		clear( statusEl );
		if ( ! v ) {

			statusEl.append( 'Save the garment to dress it.' );
			disposeShown();
			clear( report );
			return;

		}

		statusEl.dataset.status = ( entry && entry.status ) || 'none';
		statusEl.append( st.kind === 'busy' ? h( 'span', { class: 'loading loading--inline' }, h( 'span', { class: 'spinner', 'aria-hidden': 'true' } ), `Size ${ size }, version ${ v.version }: ${ st.text }` ) : `Size ${ size }, version ${ v.version }: ${ st.text }` );
		clear( report );
		for ( const [ label, text, good ] of reportRows( entry ) ) {

			const cls = [ good === false && 'is-bad', good === true && 'is-good', ( label === 'Note' || label === 'Problem' ) && 'mp-report__note' ].filter( Boolean ).join( ' ' );
			report.append( h( 'div', { class: cls || null }, h( 'dt', {}, label ), h( 'dd', {}, text ) ) );

		}
		const key = `${ item.id }/${ v.version }/${ size }`;
		if ( hasDressed( entry ) ) {

			if ( ( shown && shown.key === key ) || loading === key ) return;
			show3d( key, item.id, v.version, size );

		} else {

			disposeShown();

		}

	}

	async function show3d( key, id, version, s ) {

		disposeShown();
		if ( ! hasWebGL() ) {

			statusEl.append( ' (this browser cannot show 3D)' );
			return;

		}

		loading = key;
		view.hidden = false;
		view.append( spinner( 'Loading the 3D view…' ) );
		let url = null;
		try {

			const blob = await fetchDressed( id, version, s, { signal } );
			if ( loading !== key || signal.aborted ) return;
			url = URL.createObjectURL( blob );
			clear( view );
			const got = await showDressed( view, url, { signal, label: `Size ${ s } on its sample body, in 3D; drag to turn it` } );
			if ( ! got || loading !== key ) {

				if ( got ) got.dispose();
				return;

			}

			shown = { key, player: got.player, dispose: got.dispose };
			view.dataset.shown = key;
			if ( got.player.fitMap ) {

				const legend = fitLegend();
				const toggle = h( 'button', { type: 'button', class: 'seg seg--toggle', 'aria-pressed': 'false' }, 'Fit map' );
				toggle.addEventListener( 'click', () => {

					const on = toggle.getAttribute( 'aria-pressed' ) !== 'true';
					toggle.setAttribute( 'aria-pressed', String( on ) );
					got.player.setFitMap( on );
					legend.hidden = ! on;

				} );
				extras.append( h( 'div', { class: 'segs' }, toggle ), legend );

			}

			window.__catwalk = window.__catwalk || {};
			window.__catwalk.merchantPreview = got.player;

		} catch ( err ) {

			if ( err && err.name === 'AbortError' ) return;
			if ( isUnauthorised( err ) ) return onUnauthorised();
			clear( view ).append( errorNotice( err ) );

		} finally {

			if ( url ) URL.revokeObjectURL( url );
			if ( loading === key ) loading = null;

		}

	}

	return { el, update, dispose: disposeShown };

}
