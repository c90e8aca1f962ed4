// A saved version dressed on each size's sample body: the status of every size, the chosen
// size in 3D with the fit map (the .glb is fetched with the merchant's key and handed to the
// viewer as an object URL), the dressing report's numbers, and "Publish".

import { h, clear, nextId } from '../ui/dom.js';
import { spinner, notice, errorNotice } from '../ui/feedback.js';
import { hasWebGL } from '../viewer/webgl.js';
import { showDressed } from '../viewer/dressed-view.js';
import { fitMapToggle } from '../player/controls.js';
import { urls } from '../router.js';
import { fetchDressed, publishGarment, isUnauthorised } from './api.js';
import { versionOf, sizeStatus, reportRows, hasDressed } from './status.js';

export function createPreview( { signal, onUnauthorised = () => {}, onPublished = () => {} } ) {

	// the parts, and what is shown: the merchant garment (with versions), the size, the 3D view
	// ({ key, dispose, player }) and the key being loaded
	const pv = { ...previewParts(), signal, onUnauthorised, item: null, size: null, shown: null, loading: null, name: nextId( 'pv-size' ) };
	const dispose = () => disposeShown( pv );
	signal.addEventListener( 'abort', dispose, { once: true } );
	pv.publishBtn.addEventListener( 'click', () => publish( pv, onPublished ) );

	/** Show the garment `it` (its latest version). */
	function update( it ) {

		pv.item = it;
		const v = versionOf( it );
		const sizes = ( it && it.sizes ) || [];
		const def = it && ( it.default_size || ( it.garment && it.garment.default_size ) );
		if ( ! pv.size || ! sizes.includes( pv.size ) ) pv.size = def && sizes.includes( def ) ? def : sizes[ Math.floor( sizes.length / 2 ) ] || null;
		sizeOptions( pv, sizes, v, ( s ) => {

			pv.size = s;
			update( pv.item );

		} );
		refreshPublish( pv );
		const entry = v && v.dressing && pv.size ? v.dressing[ pv.size ] : null;
		clear( pv.statusEl );
		if ( ! v ) {

			pv.statusEl.append( 'Save the garment to dress it.' );
			disposeShown( pv );
			clear( pv.report );
			return;

		}

		showStatus( pv, v, entry );
		const key = `${ it.id }/${ v.version }/${ pv.size }`;
		if ( hasDressed( entry ) ) {

			if ( ( pv.shown && pv.shown.key === key ) || pv.loading === key ) return;
			show3d( pv, key, it.id, v.version, pv.size );

		} else {

			disposeShown( pv );

		}

	}

	return { el: pv.el, update, dispose };

}

/** The section and its parts (the 3D view's placeholder shown while the view is hidden). */
function previewParts() {

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
	return { el, sizesEl, statusEl, view, extras, report, publishMsg, publishBtn };

}

function disposeShown( pv ) {

	if ( pv.shown ) pv.shown.dispose();
	pv.shown = null;
	pv.loading = null;
	clear( pv.extras );
	pv.view.hidden = true;
	clear( pv.view );

}

/** A radio a size of the version `v` (with its dressing status); `onPick(size)`. */
function sizeOptions( pv, sizes, v, onPick ) {

	clear( pv.sizesEl );
	for ( const s of sizes ) {

		const id = nextId( 'pv' );
		const st = sizeStatus( v && v.dressing && v.dressing[ s ] );
		pv.sizesEl.append( h( 'span', { class: 'size-option' },
			h( 'input', { type: 'radio', name: pv.name, id, value: s, checked: s === pv.size, onchange: () => onPick( s ) } ),
			h( 'label', { for: id }, s, h( 'span', { class: `mp-dot mp-dot--${ st.kind }`, 'aria-hidden': 'true' } ), h( 'span', { class: 'visually-hidden' }, `: ${ st.text }` ) ),
		) );

	}

}

/** The chosen size's status (`entry`: its dressing in version `v`) and its report's numbers. */
function showStatus( pv, v, entry ) {

	const st = sizeStatus( entry );
	const text = `Size ${ pv.size }, version ${ v.version }: ${ st.text }`;
	pv.statusEl.dataset.status = ( entry && entry.status ) || 'none';
	pv.statusEl.append( st.kind === 'busy' ? h( 'span', { class: 'loading loading--inline' }, h( 'span', { class: 'spinner', 'aria-hidden': 'true' } ), text ) : text );
	clear( pv.report );
	for ( const [ label, value, good ] of reportRows( entry ) ) {

		const cls = [ good === false && 'is-bad', good === true && 'is-good', ( label === 'Note' || label === 'Problem' ) && 'mp-report__note' ].filter( Boolean ).join( ' ' );
		pv.report.append( h( 'div', { class: cls || null }, h( 'dt', {}, label ), h( 'dd', {}, value ) ) );

	}

}

function refreshPublish( pv ) {

	const { item, publishBtn } = pv;
	const v = item && versionOf( item );
	publishBtn.disabled = ! v;
	publishBtn.textContent = item && item.published_version === item.version ? `Version ${ item.version } is published` : v ? `Publish version ${ v.version }` : 'Publish';
	if ( item && item.published_version === item.version ) publishBtn.disabled = true;

}

/** Publish the garment's latest version; then links to the catalogue. */
async function publish( pv, onPublished ) {

	const { signal, publishMsg } = pv;
	if ( ! pv.item ) return;
	pv.publishBtn.disabled = true;
	clear( publishMsg ).append( spinner( 'Publishing…' ) );
	try {

		const res = await publishGarment( pv.item.id, pv.item.version, { signal } );
		const item = pv.item; // (the garment as polled meanwhile)
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
		if ( isUnauthorised( err ) ) return pv.onUnauthorised();
		clear( publishMsg ).append( errorNotice( err ) );

	} finally {

		refreshPublish( pv );

	}

}

/** Size `s` of version `version` dressed, in 3D (the .glb fetched with the key), under `key`. */
async function show3d( pv, key, id, version, s ) {

	const { view, signal } = pv;
	disposeShown( pv );
	if ( ! hasWebGL() ) {

		pv.statusEl.append( ' (this browser cannot show 3D)' );
		return;

	}

	pv.loading = key;
	view.hidden = false;
	view.append( spinner( 'Loading the 3D view…' ) );
	let url = null;
	try {

		const blob = await fetchDressed( id, version, s, { signal } );
		if ( pv.loading !== key || signal.aborted ) return;
		url = URL.createObjectURL( blob );
		clear( view );
		const got = await showDressed( view, url, { signal, label: `Size ${ s } on its sample body, in 3D; drag to turn it` } );
		if ( ! got || pv.loading !== key ) {

			if ( got ) got.dispose();
			return;

		}

		pv.shown = { key, player: got.player, dispose: got.dispose };
		view.dataset.shown = key;
		if ( got.player.fitMap ) pv.extras.append( ...fitMapToggle( got.player ) );
		window.__catwalk = window.__catwalk || {};
		window.__catwalk.merchantPreview = got.player;

	} catch ( err ) {

		if ( err && err.name === 'AbortError' ) return;
		if ( isUnauthorised( err ) ) return pv.onUnauthorised();
		clear( view ).append( errorNotice( err ) );

	} finally {

		if ( url ) URL.revokeObjectURL( url );
		if ( pv.loading === key ) pv.loading = null;

	}

}
