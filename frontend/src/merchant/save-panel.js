// The editor's save section: "Save" (a new version, with the textures not yet on the server),
// a refused save's problems (each naming its piece, edge, seam or size), the saved version's
// warnings; after a save the garment is polled while its sizes are being dressed.

import { h, clear } from '../ui/dom.js';
import { notice, errorNotice, spinner } from '../ui/feedback.js';
import { ApiError } from '../api.js';
import { saveGarment, getGarment, isUnauthorised } from './api.js';
import { keepFocus } from './form.js';
import { isBusy } from './status.js';

/**
 * The save section of the editor in `state`: `{ el, render(), poll() }`. `onItem(item)`: the
 * saved garment (with its versions and their dressing), after a save and at every poll.
 */
export function createSavePanel( state, { signal, onItem, onUnauthorised } ) {

	const el = h( 'section', { class: 'panel mp-sec mp-save', 'aria-labelledby': 'mp-save-title' } );
	const status = h( 'div', { class: 'mp-save__status', 'aria-live': 'polite' } );
	let warnings = []; // of the last save
	let saving = false;
	const poll = poller( state, { signal, onItem, onUnauthorised } );

	const draw = () => {

		clear( el );
		el.append( h( 'h2', { id: 'mp-save-title' }, 'Save' ),
			h( 'button', { type: 'button', class: 'button button--primary button--wide', 'data-key': 'save', onclick: save }, state.savedId ? 'Save as a new version' : 'Save' ),
			status );
		if ( state.problems.length ) el.append( problemsNotice( state ) );
		if ( warnings.length ) {

			el.append( h( 'div', { class: 'notice notice--warn', role: 'status' }, h( 'div', { class: 'notice__body' },
				h( 'p', { class: 'notice__title' }, 'Warnings' ),
				h( 'ul', {}, warnings.map( ( w ) => h( 'li', {}, typeof w === 'string' ? w : w.message || JSON.stringify( w ) ) ) ) ) ) );

		}

	};

	async function save() {

		if ( saving ) return;
		saving = true;
		clear( status ).append( spinner( 'Saving…' ) );
		try {

			const res = await saveGarment( state.savedId, state.g, unsavedTextures( state ), { signal } );
			if ( signal.aborted ) return;
			warnings = ( res && res.warnings ) || [];
			saved( state, res );
			clear( status ).append( notice( 'info', `Saved: version ${ res.version }`, 'Each size is being dressed on its sample body; the preview below follows.' ) );
			onItem( state.savedItem );
			state.refresh( { garment: false } );
			poll();

		} catch ( err ) {

			if ( err && err.name === 'AbortError' ) return;
			if ( isUnauthorised( err ) ) return onUnauthorised();
			refused( state, err, status );

		} finally {

			saving = false;

		}

	}

	return { el, render: () => keepFocus( el, draw ), poll };

}

/** Poll the saved garment every 2 s while a size is queued or being dressed: `poll()` starts it. */
function poller( state, { signal, onItem, onUnauthorised } ) {

	let timer = null;
	signal.addEventListener( 'abort', () => clearTimeout( timer ), { once: true } );
	return function poll() {

		clearTimeout( timer );
		if ( ! state.savedId || signal.aborted ) return;
		timer = setTimeout( async () => {

			try {

				const it = await getGarment( state.savedId, { signal } );
				if ( signal.aborted ) return;
				state.savedItem = it;
				onItem( it );
				if ( isBusy( it ) ) poll();

			} catch ( err ) {

				if ( err && err.name === 'AbortError' ) return;
				if ( isUnauthorised( err ) ) return onUnauthorised();
				poll(); // try again

			}

		}, 2000 );

	};

}

/** The textures to send: the images chosen since the last save (path → blob). */
function unsavedTextures( state ) {

	const files = new Map();
	for ( const p of state.g.panels ) {

		const t = state.textures.get( p.name );
		if ( p.texture && t && t.blob && t.path === p.texture.image ) files.set( t.path, t.blob );

	}

	return files;

}

/** The state after the save answered `res`: saved, no problems, the textures kept on the server. */
function saved( state, res ) {

	state.problems = [];
	state.savedId = res.id;
	state.dirty = false;
	for ( const t of state.textures.values() ) t.blob = null; // kept on the server from now on
	state.savedItem = mergeSaved( state.savedItem, res, state.g );

}

/** A save refused: its problems listed (the first piece named selected), or the error in `status`. */
function refused( state, err, status ) {

	if ( err instanceof ApiError && err.problems && err.problems.length ) {

		state.problems = err.problems;
		state.problemsStale = false;
		clear( status );
		const firstPanel = state.problems.find( ( p ) => p.panel && state.g.panels.some( ( q ) => q.name === p.panel ) );
		if ( firstPanel ) state.selected = firstPanel.panel;
		state.refresh( { garment: false } );

	} else {

		state.problems = [];
		clear( status ).append( errorNotice( err ) );
		state.refresh( { garment: false } );

	}

}

/** The last refused save's problems; a piece named shows it (selected, its seam and size). */
function problemsNotice( state ) {

	const problems = state.problems;
	const show = ( p ) => {

		const g = state.g;
		if ( g.panels.some( ( q ) => q.name === p.panel ) ) state.selected = p.panel;
		if ( Number.isInteger( p.seam ) ) state.highlight = p.seam;
		if ( p.size && g.sizes.includes( p.size ) ) state.size = p.size;
		state.set( { mode: 'edit' } );

	};

	return h( 'div', { class: 'notice notice--error mp-problems', role: 'alert' },
		h( 'div', { class: 'notice__body' },
			h( 'p', { class: 'notice__title' }, `The last save was refused: ${ problems.length === 1 ? 'a problem' : `${ problems.length } problems` }` ),
			state.problemsStale ? h( 'p', { class: 'notice__text' }, 'You have changed the garment since; save again to check it.' ) : null,
			h( 'ul', {}, problems.map( ( p ) => h( 'li', { 'data-panel': p.panel || null, 'data-edge': p.edge ?? null },
				p.panel ? h( 'button', { type: 'button', class: 'mp-link', onclick: () => show( p ) }, p.panel ) : null,
				p.panel ? ( p.edge != null ? `, edge ${ p.edge }: ` : ': ' ) : null,
				p.message ) ) ),
		) );

}

/** The merchant garment after a save answered `res` ({ id, version, sizes, warnings, dressing }). */
function mergeSaved( item, res, g ) {

	const entry = { version: res.version, created_at: new Date().toISOString(), warnings: res.warnings || [], dressing: res.dressing || {} };
	const base = item && item.id === res.id ? item : { id: res.id, name: g.name, type: g.type, published_version: null, versions: [] };
	return {
		...base,
		name: g.name, type: g.type, sizes: res.sizes || g.sizes, default_size: g.default_size, version: res.version,
		versions: [ ...( base.versions || [] ).filter( ( v ) => v.version !== res.version ), entry ],
	};

}
