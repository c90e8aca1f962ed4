// The garment editor's state: the garment being edited (its JSON) with its undo history, and
// what the editor shows of it (size, selected piece, mode, the seam being picked, the last
// refused save's problems). The sections read its fields; they change the garment through
// mutate() (undoable) and what is shown through set() (or assign, then refresh()): both redraw.

import { PRESET_FABRICS } from './fabric-form.js';
import { cloneGarment } from './garment-edit.js';

const HISTORY = 50; // undo steps kept

/**
 * The state of the editor of `garment`; `id`/`item`: the saved garment it is a version of (null
 * for an import); `textures`: a panel's texture (name → { path, blob }) when opened again;
 * `dirty`: unsaved changes (by default: an import has them).
 */
export class EditorState {

	constructor( { garment, id = null, item = null, textures = null, dirty = null } ) {

		const g = cloneGarment( garment );
		g.seams = g.seams || [];
		g.sizes = g.sizes || [];
		if ( ! g.default_size || ! g.sizes.includes( g.default_size ) ) g.default_size = g.sizes[ Math.floor( g.sizes.length / 2 ) ];
		this.g = g;
		this.savedId = id;
		this.savedItem = item;
		this.dirty = dirty ?? ! id;
		this.size = g.default_size;
		this.selected = null;
		this.mode = 'edit'; // edit | seam
		this.picks = []; // [{ panel, vertex, ghost }] — up to four: a's two ends, b's two ends
		this.draft = { reverse: false, ease: 0, name: '' }; // of the seam being picked
		this.problems = []; // of the last refused save
		this.problemsStale = false; // the garment changed since: listed, no longer drawn
		this.highlight = null; // a seam's index
		this.opError = null; // the message of an edit that failed
		this.byNumberOpen = false;
		this.textures = texturesOf( g, textures ); // panel name → { path, blob | null, url | null }
		this.fabricNames = PRESET_FABRICS.slice();
		this.history = [];
		this.renderer = () => {};
		// A re-render removes controls; a focused one with an edit not yet committed then fires
		// its change event (blur) in the middle of it: that change re-renders once this one ends.
		this.rendering = false;
		this.again = null;

	}

	/** `fn` draws the editor (`{ garment }`: false when only the view state changed). */
	onRender( fn ) {

		this.renderer = fn;

	}

	/** Draw the editor again (once the draw under way ends, when called during one). */
	refresh( opts = {} ) {

		if ( this.rendering ) {

			this.again = { garment: Boolean( ( this.again && this.again.garment ) || opts.garment !== false ) };
			return;

		}

		this.rendering = true;
		try {

			this.renderer( opts );

		} finally {

			this.rendering = false;

		}

		if ( this.again ) {

			const next = this.again;
			this.again = null;
			this.refresh( next );

		}

	}

	/** Change what is shown, not the garment (`patch`: fields of the state), then redraw. */
	set( patch ) {

		Object.assign( this, patch );
		this.refresh( { garment: false } );

	}

	/** Change the garment with `fn` (undoable), then redraw; false when `fn` threw (the garment as it was). */
	mutate( fn ) {

		const before = cloneGarment( this.g );
		try {

			fn();

		} catch ( err ) {

			this.g = before;
			this.fail( err );
			return false;

		}

		this.history.push( before );
		if ( this.history.length > HISTORY ) this.history.shift();
		this.dirty = true;
		this.problemsStale = this.problems.length > 0;
		this.refresh();
		return true;

	}

	canUndo() {

		return this.history.length > 0;

	}

	/** The garment before the last change. */
	undo() {

		if ( ! this.history.length ) return;
		this.g = this.history.pop();
		this.picks = [];
		if ( this.selected && ! this.g.panels.some( ( p ) => p.name === this.selected ) ) this.selected = null;
		if ( ! this.g.sizes.includes( this.size ) ) this.size = this.g.default_size;
		this.dirty = true;
		this.refresh();

	}

	/** Show the error of an edit. */
	fail( err ) {

		this.opError = err && err.message ? err.message : String( err );
		this.refresh( { garment: false } );

	}

	/** What is needed to open the editor again as it is (after logging in again). */
	snapshot() {

		return {
			garment: cloneGarment( this.g ), id: this.savedId, item: this.savedItem, dirty: this.dirty,
			textures: new Map( [ ...this.textures ].map( ( [ name, t ] ) => [ name, { path: t.path, blob: t.blob } ] ) ),
		};

	}

}

/** The textures the garment names: `given` ones (with their images), the rest fetched once saved. */
function texturesOf( g, given ) {

	const textures = new Map();
	for ( const [ name, t ] of given || [] ) textures.set( name, { path: t.path, blob: t.blob, url: t.blob ? URL.createObjectURL( t.blob ) : null } );
	for ( const p of g.panels ) if ( p.texture && p.texture.image && ! textures.has( p.name ) ) textures.set( p.name, { path: p.texture.image, blob: null, url: null } );
	return textures;

}
