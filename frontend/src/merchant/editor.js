// The garment editor (the paper's: import a DXF; move, mirror, rotate; panel type; garment type
// and sizes; panel position; seam lines; texture per panel; save). Works on the garment's JSON
// (docs/garment-format.md) in memory; saves it with its textures as a new version.
//
// This module composes the editor: its state (editor-state.js), the pattern view with its
// toolbar, and the sections beside it (garment, pieces, seams, fabric, save), each a module
// that builds its DOM from the state and redraws it when the state changes.

import { h } from '../ui/dom.js';
import { catalogueFabrics } from './api.js';
import { PatternView } from './pattern-view.js';
import { createFabricPanel, PRESET_FABRICS } from './fabric-form.js';
import { createPreview } from './preview.js';
import { isBusy } from './status.js';
import { editPanel, layoutPanels, cloneGarment, sourceVertexMap } from './garment-edit.js';
import { EditorState } from './editor-state.js';
import { createToolbar } from './editor-toolbar.js';
import { drawPattern } from './pattern-draw.js';
import { pickVertex } from './seam-picks.js';
import { createGarmentForm } from './garment-form.js';
import { createPieceForm } from './piece-form.js';
import { createSeamsPanel } from './seams-panel.js';
import { createSavePanel } from './save-panel.js';
import { loadSavedTextures } from './piece-texture.js';
import { importInfo } from './import-info.js';

/**
 * The editor for `garment` (its JSON). `id`/`item`: the saved garment it is a version of (null
 * for an import). `warnings`: the import's. `onBack()`: to the list; `onUnauthorised()`.
 */
export function createEditor( { garment, id = null, item = null, warnings = [], pieces = null, textures = null, dirty = null, signal, onBack, onUnauthorised } ) {

	const state = new EditorState( { garment, id, item, textures, dirty } );
	const view = patternView( state );
	const toolbar = createToolbar( state, { onLayout: () => {

		if ( state.mutate( () => layoutPanels( state.g ) ) ) view.fit();

	} } );
	const preview = createPreview( { signal, onUnauthorised } );
	const garmentForm = createGarmentForm( state );
	const pieceForm = createPieceForm( state );
	const seams = createSeamsPanel( state );
	const fabric = createFabricPanel( state );
	const save = createSavePanel( state, { signal, onUnauthorised, onItem: ( it ) => preview.update( it ) } );
	const title = h( 'h1', { class: 'mp-title' } );
	const dirtyEl = h( 'span', { class: 'mp-dirty muted small', 'aria-live': 'polite' } );
	const back = () => {

		if ( state.dirty && ! window.confirm( 'Leave the editor? Your changes are not saved.' ) ) return;
		onBack();

	};

	const el = editorLayout( { back, head: [ title, dirtyEl ], info: importInfo( warnings, pieces ), toolbar, view,
		sections: [ garmentForm.el, pieceForm.el, seams.el, fabric.el, save.el ], preview } );
	undoKeys( el, state );

	state.onRender( ( { garment: all = true } = {} ) => {

		title.textContent = state.g.name || 'Untitled garment';
		dirtyEl.textContent = state.dirty ? ( state.savedId ? 'Unsaved changes' : 'Not saved yet' ) : `Saved as version ${ state.savedItem ? state.savedItem.version : '' }`;
		toolbar.render();
		if ( all ) garmentForm.render();
		pieceForm.render();
		seams.render();
		if ( all ) fabric.render();
		save.render();
		drawPattern( view, state );

	} );

	guardUnload( state, signal );
	signal.addEventListener( 'abort', () => {

		view.dispose();
		for ( const t of state.textures.values() ) if ( t.url ) URL.revokeObjectURL( t.url );

	}, { once: true } );
	catalogueFabrics( { signal } ).then( ( names ) => {

		if ( signal.aborted || ! names.length ) return;
		state.fabricNames = [ ...new Set( [ ...names, ...PRESET_FABRICS ] ) ];
		fabric.render();

	} ).catch( () => {} );

	if ( ! id && ! textures ) layOutImport( state.g );
	preview.update( state.savedItem );
	state.refresh();
	loadSavedTextures( state, { signal, onUnauthorised } );
	if ( state.savedItem && isBusy( state.savedItem ) ) save.poll();

	// a hook for tests and debugging
	window.__catwalk = window.__catwalk || {};
	window.__catwalk.merchantEditor = { garment: () => cloneGarment( state.g ), view, sourceVertexMap: ( p ) => sourceVertexMap( state.g, p ) };

	return { el, dirty: () => state.dirty, snapshot: () => state.snapshot() };

}

/** The pattern view, reporting selection, drags, nudges and vertex clicks to `state`. */
function patternView( state ) {

	return new PatternView( {
		label: 'Pattern pieces to scale; drag a piece to move it, drag the background to pan, the wheel or + and − to zoom',
		onSelect: ( name ) => state.set( { selected: name } ),
		onMove: ( name, dx, dy ) => state.mutate( () => editPanel( state.g, name, { move: [ dx, dy ] } ) ),
		onNudge: ( dx, dy ) => state.mutate( () => editPanel( state.g, state.selected, { move: [ dx, dy ] } ) ),
		onVertex: ( panel, vertex, ghost ) => pickVertex( state, panel, vertex, ghost ),
	} );

}

/** The editor's page: crumbs, title, the import's report, the pattern with the sections beside it, the preview. */
function editorLayout( { back, head, info, toolbar, view, sections, preview } ) {

	return h( 'div', { class: 'merchant-editor' },
		h( 'p', { class: 'crumbs' }, h( 'a', { href: '/merchant', onclick: ( e ) => {

			e.preventDefault();
			back();

		} }, '‹ All garments' ) ),
		h( 'div', { class: 'mp-head' }, ...head ),
		info,
		h( 'div', { class: 'mp-layout' },
			h( 'div', { class: 'mp-canvas' }, toolbar.el, toolbar.hint, view.el ),
			h( 'div', { class: 'mp-side' }, ...sections ),
		),
		preview.el,
	);

}

/** Ctrl+Z (⌘Z) outside a text field: undo. */
function undoKeys( el, state ) {

	el.addEventListener( 'keydown', ( e ) => {

		if ( ( e.ctrlKey || e.metaKey ) && ! e.shiftKey && e.key === 'z' && ! /^(INPUT|TEXTAREA|SELECT)$/.test( e.target.tagName ) ) {

			e.preventDefault();
			state.undo();

		}

	} );

}

/** Ask before leaving the page with unsaved changes (until `signal` aborts). */
function guardUnload( state, signal ) {

	const beforeUnload = ( e ) => {

		if ( ! state.dirty ) return;
		e.preventDefault();
		e.returnValue = '';

	};

	window.addEventListener( 'beforeunload', beforeUnload );
	signal.addEventListener( 'abort', () => window.removeEventListener( 'beforeunload', beforeUnload ), { once: true } );

}

/** An import: its pieces all start at the origin; lay them out side by side. */
function layOutImport( g ) {

	try {

		layoutPanels( g );

	} catch ( err ) {

		console.warn( 'layout', err );

	}

}
