// The garment editor (the paper's: import a DXF; move, mirror, rotate; panel type; garment type
// and sizes; panel position; seam lines; texture per panel; save). Works on the garment's JSON
// (docs/garment-format.md) in memory; saves it with its textures as a new version.

import { h, clear, nextId } from '../ui/dom.js';
import { notice, errorNotice, spinner } from '../ui/feedback.js';
import { typeName } from '../format.js';
import { ApiError } from '../api.js';
import { saveGarment, getGarment, fetchFile, catalogueFabrics, isUnauthorised } from './api.js';
import { PatternView } from './pattern-view.js';
import { renderFabricForm, PRESET_FABRICS } from './fabric-form.js';
import { field, select, numberInput, num, keepFocus } from './form.js';
import { buildScene, sidePolyline, sideEnds, edgePolyline } from './scene.js';
import { createPreview } from './preview.js';
import { isBusy, versionOf } from './status.js';
import {
	GARMENT_TYPES, PANEL_TYPES, BODY_PARTS, SIDES, LANDMARKS, findPanel, editPanel, renamePanel, removePanel,
	layoutPanels, grainAngle, setGrainAngle, straightEdges, setFold, renameSize, removeSize, moveSize,
	texturePath, sideFromPicks, sideAsShown, storedReverse, shownReverse, seamLengths, runCrossesFold,
	cloneGarment, vertexCount, sourceVertexMap,
} from './garment-edit.js';
import { segmentLengths } from './geometry.js';

const cm = ( m ) => `${ ( m * 100 ).toFixed( 1 ) } cm`;
const pct = ( x ) => `${ ( x * 100 ).toFixed( 1 ) } %`;

/**
 * The editor for `garment` (its JSON). `id`/`item`: the saved garment it is a version of (null
 * for an import). `warnings`: the import's. `onBack()`: to the list; `onUnauthorised()`.
 */
export function createEditor( { garment, id = null, item = null, warnings = [], pieces = null, textures: given = null, dirty: givenDirty = null, signal, onBack, onUnauthorised } ) {

	let g = cloneGarment( garment );
	g.seams = g.seams || [];
	g.sizes = g.sizes || [];
	if ( ! g.default_size || ! g.sizes.includes( g.default_size ) ) g.default_size = g.sizes[ Math.floor( g.sizes.length / 2 ) ];
	let savedId = id;
	let savedItem = item;
	let size = g.default_size;
	let selected = null;
	let mode = 'edit';
	let picks = []; // [{ panel, vertex, ghost }] — up to four: a's two ends, b's two ends
	let draft = { reverse: false, ease: 0, name: '' };
	let problems = []; // of the last refused save
	let problemsStale = false; // the garment changed since: listed, no longer drawn
	let highlight = null;
	let byNumberOpen = false;
	let dirty = givenDirty ?? ! id;
	const history = [];
	const textures = new Map(); // panel name → { path, blob | null, url | null }
	let pollTimer = null;
	let fabricNames = PRESET_FABRICS.slice();

	// textures the garment names: shown once fetched from the saved version
	for ( const [ name, t ] of given || [] ) textures.set( name, { path: t.path, blob: t.blob, url: t.blob ? URL.createObjectURL( t.blob ) : null } );
	for ( const p of g.panels ) if ( p.texture && p.texture.image && ! textures.has( p.name ) ) textures.set( p.name, { path: p.texture.image, blob: null, url: null } );

	const view = new PatternView( {
		label: 'Pattern pieces to scale; drag a piece to move it, drag the background to pan, the wheel or + and − to zoom',
		onSelect: ( name ) => {

			selected = name;
			refresh( { garment: false } );

		},
		onMove: ( name, dx, dy ) => mutate( () => editPanel( g, name, { move: [ dx, dy ] } ) ),
		onNudge: ( dx, dy ) => mutate( () => editPanel( g, selected, { move: [ dx, dy ] } ) ),
		onVertex: pickVertex,
	} );

	// --- the layout ------------------------------------------------------------------------------
	const title = h( 'h1', { class: 'mp-title' } );
	const dirtyEl = h( 'span', { class: 'mp-dirty muted small', 'aria-live': 'polite' } );
	const sizeSel = h( 'select', { id: nextId( 'size' ), 'data-key': 'view-size' } );
	const modeEdit = h( 'button', { type: 'button', class: 'seg', 'aria-pressed': 'true' }, 'Select & move' );
	const modeSeam = h( 'button', { type: 'button', class: 'seg', 'aria-pressed': 'false' }, 'Sew seams' );
	const undoBtn = h( 'button', { type: 'button', class: 'button button--secondary button--small', disabled: true }, 'Undo' );
	const layoutBtn = h( 'button', { type: 'button', class: 'button button--secondary button--small' }, 'Lay out side by side' );
	const modeHint = h( 'p', { class: 'muted small mp-hint', 'aria-live': 'polite' } );
	const garmentSec = h( 'section', { class: 'panel mp-sec', 'aria-labelledby': 'mp-garment-title' } );
	const pieceSec = h( 'section', { class: 'panel mp-sec', 'aria-labelledby': 'mp-piece-title' } );
	const seamSec = h( 'section', { class: 'panel mp-sec', 'aria-labelledby': 'mp-seams-title' } );
	const fabricSec = h( 'section', { class: 'panel mp-sec', 'aria-labelledby': 'mp-fabric-title' } );
	const saveSec = h( 'section', { class: 'panel mp-sec mp-save', 'aria-labelledby': 'mp-save-title' } );
	const preview = createPreview( { signal, onUnauthorised } );
	const importInfo = h( 'div', { class: 'mp-import' } );

	const el = h( 'div', { class: 'merchant-editor' },
		h( 'p', { class: 'crumbs' }, h( 'a', { href: '/merchant', onclick: ( e ) => {

			e.preventDefault();
			back();

		} }, '‹ All garments' ) ),
		h( 'div', { class: 'mp-head' }, title, dirtyEl ),
		importInfo,
		h( 'div', { class: 'mp-layout' },
			h( 'div', { class: 'mp-canvas' },
				h( 'div', { class: 'mp-toolbar' },
					h( 'div', { class: 'control' }, h( 'label', { class: 'control__label', for: sizeSel.id }, 'Pieces of size' ), sizeSel ),
					h( 'div', { class: 'segs', role: 'group', 'aria-label': 'Mode' }, modeEdit, modeSeam ),
					layoutBtn, undoBtn,
				),
				modeHint,
				view.el,
			),
			h( 'div', { class: 'mp-side' }, garmentSec, pieceSec, seamSec, fabricSec, saveSec ),
		),
		preview.el,
	);

	sizeSel.addEventListener( 'change', () => {

		size = sizeSel.value;
		refresh( { garment: false } );

	} );
	modeEdit.addEventListener( 'click', () => setMode( 'edit' ) );
	modeSeam.addEventListener( 'click', () => setMode( 'seam' ) );
	undoBtn.addEventListener( 'click', undo );
	layoutBtn.addEventListener( 'click', () => mutate( () => layoutPanels( g ), { fit: true } ) );
	el.addEventListener( 'keydown', ( e ) => {

		if ( ( e.ctrlKey || e.metaKey ) && ! e.shiftKey && e.key === 'z' && ! /^(INPUT|TEXTAREA|SELECT)$/.test( e.target.tagName ) ) {

			e.preventDefault();
			undo();

		}

	} );

	function setMode( m ) {

		mode = m;
		modeEdit.setAttribute( 'aria-pressed', String( m === 'edit' ) );
		modeSeam.setAttribute( 'aria-pressed', String( m === 'seam' ) );
		refresh( { garment: false } );

	}

	function back() {

		if ( dirty && ! window.confirm( 'Leave the editor? Your changes are not saved.' ) ) return;
		onBack();

	}

	/** Change the garment (undoable), then redraw. */
	function mutate( fn, { fit = false } = {} ) {

		const before = cloneGarment( g );
		try {

			fn();

		} catch ( err ) {

			g = before;
			showOpError( err );
			return false;

		}

		history.push( before );
		if ( history.length > 50 ) history.shift();
		dirty = true;
		problemsStale = problems.length > 0;
		refresh();
		if ( fit ) view.fit();
		return true;

	}

	/** Mirror the selected piece; vertex numbers change, so a seam being picked starts again. */
	function mirror( axis ) {

		if ( mutate( () => editPanel( g, selected, { mirror: axis } ) ) && picks.length ) {

			picks = [];
			refresh( { garment: false } );

		}

	}

	function undo() {

		if ( ! history.length ) return;
		g = history.pop();
		picks = [];
		if ( selected && ! g.panels.some( ( p ) => p.name === selected ) ) selected = null;
		if ( ! g.sizes.includes( size ) ) size = g.default_size;
		dirty = true;
		refresh();

	}

	let opError = null;
	function showOpError( err ) {

		opError = err && err.message ? err.message : String( err );
		refresh( { garment: false } );

	}

	// --- seams: picking -----------------------------------------------------------------------

	function pickVertex( panel, vertex, ghost ) {

		if ( mode !== 'seam' ) return;
		if ( picks.length >= 4 ) picks = [];
		if ( picks.length === 1 || picks.length === 3 ) {

			const first = picks[ picks.length - 1 ];
			if ( first.panel !== panel || first.ghost !== ghost ) {

				// a run is on one piece (and one half of it): start again there
				picks = picks.slice( 0, picks.length - 1 );

			} else if ( first.vertex === vertex ) {

				picks = picks.slice( 0, picks.length - 1 );
				refresh( { garment: false } );
				return;

			}

		}

		picks.push( { panel, vertex, ghost } );
		refresh( { garment: false } );

	}

	function draftSides() {

		const side = ( i ) => ( picks.length >= i + 2 ? sideFromPicks( g, picks[ i ].panel, picks[ i ].vertex, picks[ i + 1 ].vertex, picks[ i ].ghost ) : null );
		return { a: side( 0 ), b: side( 2 ) };

	}

	function otherWay( i ) {

		[ picks[ i ], picks[ i + 1 ] ] = [ picks[ i + 1 ], picks[ i ] ];
		refresh( { garment: false } );

	}

	function addSeam() {

		const { a, b } = draftSides();
		if ( ! a || ! b ) return;
		const seam = { a, b, reverse: storedReverse( g, a, b, draft.reverse ) };
		if ( draft.name.trim() ) seam.name = draft.name.trim();
		if ( draft.ease ) seam.ease = Math.round( draft.ease * 1e4 ) / 1e4;
		if ( mutate( () => g.seams.push( seam ) ) ) {

			picks = [];
			draft = { reverse: false, ease: 0, name: '' };
			highlight = g.seams.length - 1;
			refresh( { garment: false } );

		}

	}

	// --- rendering ----------------------------------------------------------------------------

	// A re-render removes controls; a focused one with an edit not yet committed then fires
	// its change event (blur) in the middle of it: that change re-renders once this one ends.
	let rendering = false;
	let again = null;
	function refresh( opts = {} ) {

		if ( rendering ) {

			again = { garment: Boolean( ( again && again.garment ) || opts.garment !== false ) };
			return;

		}

		rendering = true;
		try {

			render( opts );

		} finally {

			rendering = false;

		}

		if ( again ) {

			const next = again;
			again = null;
			refresh( next );

		}

	}

	function render( { garment = true } = {} ) {

		title.textContent = g.name || 'Untitled garment';
		dirtyEl.textContent = dirty ? ( savedId ? 'Unsaved changes' : 'Not saved yet' ) : `Saved as version ${ savedItem ? savedItem.version : '' }`;
		undoBtn.disabled = ! history.length;
		clear( sizeSel );
		for ( const s of g.sizes ) sizeSel.append( h( 'option', { value: s, selected: s === size }, s ) );
		modeHint.textContent = mode === 'seam'
			? 'Click the first and then the last vertex of a run on one piece, then on the piece it is sewn to. A run goes counter-clockwise from its first vertex to its last; the dashed lines join the ends that meet.'
			: 'Click a piece to select it; drag it to move it (arrow keys: 1 mm, with Shift 1 cm). Drag the background to pan; wheel, + and − to zoom.';
		if ( garment ) keepFocus( garmentSec, renderGarment );
		keepFocus( pieceSec, renderPiece );
		keepFocus( seamSec, renderSeams );
		if ( garment ) keepFocus( fabricSec, renderFabric );
		keepFocus( saveSec, renderSave );
		drawView();

	}

	function drawView() {

		let scene;
		try {

			scene = buildScene( g, size );

		} catch ( err ) {

			console.warn( 'pattern view', err );
			return;

		}

		const { a, b } = draftSides();
		const runs = [];
		const links = [];
		for ( const side of [ a, b ] ) if ( side && scene.pieces[ side.panel ] ) runs.push( sidePolyline( g, scene.pieces[ side.panel ], side ) );
		if ( a && b ) {

			const [ a0, a1 ] = sideEnds( g, scene.pieces[ a.panel ], a );
			const [ b0, b1 ] = sideEnds( g, scene.pieces[ b.panel ], b );
			links.push( ...( draft.reverse ? [ [ a0, b1 ], [ a1, b0 ] ] : [ [ a0, b0 ], [ a1, b1 ] ] ) );

		}

		const probPanels = new Set();
		const probEdges = [];
		for ( const p of problemsStale ? [] : problems ) {

			if ( ! p.panel || ! scene.pieces[ p.panel ] ) continue;
			probPanels.add( p.panel );
			if ( Number.isInteger( p.edge ) && p.edge >= 0 && p.edge < vertexCount( g, p.panel ) ) probEdges.push( { panel: p.panel, points: edgePolyline( g, scene.pieces[ p.panel ], p.panel, p.edge ) } );

		}

		view.update( scene, {
			selected, mode, picks, highlight,
			draft: runs.length ? { runs, links } : null,
			problems: { panels: probPanels, edges: probEdges },
			textures,
		} );

	}

	function renderGarment() {

		clear( garmentSec );
		const name = h( 'input', { type: 'text', value: g.name || '', 'data-key': 'g-name', maxlength: 200, required: true } );
		name.addEventListener( 'change', () => mutate( () => {

			g.name = name.value.trim() || g.name;

		} ) );
		const type = select( GARMENT_TYPES.map( ( t ) => [ t, typeName( t ) ] ), g.type || 'other', { 'data-key': 'g-type' } );
		type.addEventListener( 'change', () => mutate( () => {

			g.type = type.value;

		} ) );
		const desc = h( 'textarea', { rows: 2, 'data-key': 'g-desc', class: 'mp-textarea' } );
		desc.value = g.description || '';
		desc.addEventListener( 'change', () => mutate( () => {

			if ( desc.value.trim() ) g.description = desc.value.trim();
			else delete g.description;

		} ) );
		const def = select( g.sizes.map( ( s ) => [ s, s ] ), g.default_size, { 'data-key': 'g-default' } );
		def.addEventListener( 'change', () => mutate( () => {

			g.default_size = def.value;

		} ) );
		const sizes = h( 'ul', { class: 'mp-sizes' } );
		g.sizes.forEach( ( s, i ) => {

			const input = h( 'input', { type: 'text', value: s, 'aria-label': `Name of size ${ s }`, 'data-key': `size-${ i }`, maxlength: 200 } );
			input.addEventListener( 'change', () => {

				const to = input.value.trim();
				if ( mutate( () => renameSize( g, s, to ) ) && size === s ) {

					size = to;
					refresh();

				}

			} );
			sizes.append( h( 'li', {},
				input,
				h( 'button', { type: 'button', class: 'button button--secondary button--small', 'aria-label': `Move size ${ s } earlier`, 'data-key': `size-up-${ i }`, disabled: i === 0, onclick: () => mutate( () => moveSize( g, s, - 1 ) ) }, '↑' ),
				h( 'button', { type: 'button', class: 'button button--secondary button--small', 'aria-label': `Move size ${ s } later`, 'data-key': `size-down-${ i }`, disabled: i === g.sizes.length - 1, onclick: () => mutate( () => moveSize( g, s, 1 ) ) }, '↓' ),
				h( 'button', { type: 'button', class: 'button button--danger button--small', 'aria-label': `Remove size ${ s }`, 'data-key': `size-rm-${ i }`, disabled: g.sizes.length <= 1, onclick: () => {

					if ( mutate( () => removeSize( g, s ) ) && ! g.sizes.includes( size ) ) {

						size = g.default_size;
						refresh();

					}

				} }, 'Remove' ),
			) );

		} );
		garmentSec.append(
			h( 'h2', { id: 'mp-garment-title' }, 'Garment' ),
			field( 'Garment name', name ),
			h( 'div', { class: 'field-row--2' }, field( 'Garment type', type ), field( 'Default size', def ) ),
			field( 'Description', desc ),
			h( 'fieldset', { class: 'field' }, h( 'legend', {}, 'Sizes, in grading order' ), sizes,
				h( 'p', { class: 'field__hint' }, 'Each size is dressed on the sample body of that size after saving.' ) ),
		);

	}

	function renderPiece() {

		clear( pieceSec );
		pieceSec.append( h( 'h2', { id: 'mp-piece-title' }, 'Pieces' ) );
		if ( opError ) {

			pieceSec.append( notice( 'error', null, opError, { label: 'OK', onClick: () => {

				opError = null;
				refresh( { garment: false } );

			} } ) );

		}

		const list = h( 'ul', { class: 'mp-pieces', 'aria-label': 'Pieces' } );
		for ( const p of g.panels ) {

			const bad = ! problemsStale && problems.some( ( x ) => x.panel === p.name );
			list.append( h( 'li', {}, h( 'button', {
				type: 'button', class: `mp-piece${ bad ? ' has-problem' : '' }`, 'aria-pressed': String( selected === p.name ), 'data-key': `piece-${ p.name }`,
				onclick: () => {

					selected = selected === p.name ? null : p.name;
					refresh( { garment: false } );

				},
			}, p.name, h( 'span', { class: 'muted small' }, ` ${ typeName( p.type || 'other' ) }${ p.copy_of != null ? `, copy of ${ p.copy_of }` : '' }` ) ) ) );

		}

		pieceSec.append( list );
		if ( ! selected ) {

			pieceSec.append( h( 'p', { class: 'muted small' }, 'Select a piece (here or on the pattern) to move, rotate, mirror or describe it.' ) );
			return;

		}

		let p;
		try {

			p = findPanel( g, selected );

		} catch {

			selected = null;
			return;

		}

		const form = h( 'div', { class: 'mp-piece-form' } );
		const name = h( 'input', { type: 'text', value: p.name, 'data-key': 'p-name', maxlength: 200 } );
		name.addEventListener( 'change', () => {

			const from = p.name, to = name.value.trim();
			if ( mutate( () => renamePanel( g, from, to ) ) ) {

				if ( textures.has( from ) ) {

					textures.set( to, textures.get( from ) );
					textures.delete( from );

				}

				picks = picks.map( ( k ) => ( k.panel === from ? { ...k, panel: to } : k ) );
				selected = to;
				refresh( { garment: false } );

			}

		} );
		const type = select( PANEL_TYPES.map( ( t ) => [ t, typeName( t ) ] ), p.type || 'other', { 'data-key': 'p-type' } );
		type.addEventListener( 'change', () => mutate( () => {

			p = findPanel( g, selected );
			p.type = type.value;

		} ) );
		form.append( h( 'div', { class: 'field-row--2' }, field( 'Piece name', name ), field( 'Piece type', type ) ) );

		if ( p.copy_of != null ) {

			form.append( h( 'p', { class: 'muted small' }, `A ${ p.mirror ? 'mirrored ' : '' }copy of ${ p.copy_of }: its shape follows ${ p.copy_of } (move, rotate or mirror that one).` ) );

		} else {

			// move, rotate, mirror
			const dx = numberInput( 0, { 'data-key': 'p-dx' } ), dy = numberInput( 0, { 'data-key': 'p-dy' } );
			const moveBtn = h( 'button', { type: 'button', class: 'button button--secondary button--small', 'data-key': 'p-move' }, 'Move' );
			moveBtn.addEventListener( 'click', () => {

				const x = num( dx.value ) || 0, y = num( dy.value ) || 0;
				if ( x || y ) mutate( () => editPanel( g, selected, { move: [ x / 100, y / 100 ] } ) );

			} );
			const deg = numberInput( 90, { 'data-key': 'p-deg' } );
			const rotBtn = h( 'button', { type: 'button', class: 'button button--secondary button--small', 'data-key': 'p-rotate' }, 'Rotate' );
			rotBtn.addEventListener( 'click', () => {

				const d = num( deg.value );
				if ( d ) mutate( () => editPanel( g, selected, { rotate: d } ) );

			} );
			form.append(
				h( 'fieldset', { class: 'field mp-ops' }, h( 'legend', {}, 'Move (cm)' ),
					h( 'div', { class: 'mp-inline' }, field( 'Right by', dx ), field( 'Up by', dy ), moveBtn ) ),
				h( 'fieldset', { class: 'field mp-ops' }, h( 'legend', {}, 'Rotate and mirror' ),
					h( 'div', { class: 'mp-inline' }, field( 'Degrees, counter-clockwise', deg ), rotBtn ),
					h( 'div', { class: 'mp-inline' },
						h( 'button', { type: 'button', class: 'button button--secondary button--small', 'data-key': 'p-mirror-x', onclick: () => mirror( 'x' ) }, 'Mirror left ↔ right' ),
						h( 'button', { type: 'button', class: 'button button--secondary button--small', 'data-key': 'p-mirror-y', onclick: () => mirror( 'y' ) }, 'Mirror up ↔ down' ),
					),
					h( 'p', { class: 'field__hint' }, 'In every size, about the centre of the piece; seams on it are renumbered so the garment sews the same way.' ) ),
			);

			// grain and fold
			const shape = p.shapes[ size ] || Object.values( p.shapes )[ 0 ];
			const grain = numberInput( Math.round( grainAngle( shape ) * 10 ) / 10, { 'data-key': 'p-grain' } );
			const grainBtn = h( 'button', { type: 'button', class: 'button button--secondary button--small', 'data-key': 'p-grain-set' }, 'Set grain line' );
			grainBtn.addEventListener( 'click', () => {

				const d = num( grain.value );
				if ( Number.isFinite( d ) ) mutate( () => setGrainAngle( findPanel( g, selected ), d ) );

			} );
			const lengths = segmentLengths( shape.outline );
			const fold = select( [ [ '', 'Not cut on the fold' ], ...straightEdges( p, size ).map( ( k ) => [ String( k ), `Edge ${ k } (vertices ${ k }→${ ( k + 1 ) % shape.outline.length }, ${ cm( lengths[ k ] ) })` ] ) ], p.fold ?? '', { 'data-key': 'p-fold' } );
			fold.addEventListener( 'change', () => mutate( () => setFold( findPanel( g, selected ), fold.value === '' ? null : Number( fold.value ) ) ) );
			form.append(
				h( 'fieldset', { class: 'field mp-ops' }, h( 'legend', {}, 'Grain line' ),
					h( 'div', { class: 'mp-inline' }, field( 'Degrees from vertical', grain, '0: the warp runs up the piece; positive turns it counter-clockwise.' ), grainBtn ) ),
				field( 'Cut on the fold along', fold, 'The piece is half of the cut one, mirrored across this straight edge.' ),
			);

		}

		// placement
		form.append( placementFields( p ) );
		// texture
		form.append( textureFields( p ) );
		form.append( h( 'div', { class: 'mp-actions' }, h( 'button', { type: 'button', class: 'button button--danger button--small', 'data-key': 'p-remove', onclick: () => {

			const gone = p.name;
			if ( ! window.confirm( `Remove the piece ${ gone }${ g.panels.some( ( q ) => q.copy_of === gone ) ? ' and its copies' : '' }, and the seams on it?` ) ) return;
			if ( mutate( () => {

				for ( const n of removePanel( g, gone ) ) textures.delete( n );

			} ) ) {

				selected = null;
				picks = [];
				refresh();

			}

		} }, 'Remove this piece' ) ) );
		pieceSec.append( form );

	}

	function placementFields( p ) {

		const pl = p.placement || null;
		const set = ( fn ) => mutate( () => {

			const q = findPanel( g, selected );
			q.placement = q.placement || { part: 'torso', side: 'front' };
			fn( q.placement );

		} );
		const part = select( [ [ '', 'No hint' ], ...BODY_PARTS.map( ( x ) => [ x, x.replace( /_/g, ' ' ) ] ) ], pl ? pl.part || 'torso' : '', { 'data-key': 'pl-part' } );
		part.addEventListener( 'change', () => {

			if ( part.value === '' ) mutate( () => {

				delete findPanel( g, selected ).placement;

			} );
			else set( ( x ) => {

				x.part = part.value;

			} );

		} );
		const fs = h( 'fieldset', { class: 'field mp-ops' }, h( 'legend', {}, 'Position on the body' ), field( 'Body part', part ) );
		if ( ! pl ) {

			fs.append( h( 'p', { class: 'field__hint' }, 'Without a hint the piece is placed by its type; the checker warns.' ) );
			return fs;

		}

		const side = select( SIDES.map( ( x ) => [ x, x ] ), pl.side || 'front', { 'data-key': 'pl-side' } );
		side.addEventListener( 'change', () => set( ( x ) => {

			x.side = side.value;

		} ) );
		const listId = nextId( 'landmarks' );
		const anchor = h( 'input', { type: 'text', value: pl.anchor || '', list: listId, 'data-key': 'pl-anchor', placeholder: 'e.g. waist' } );
		anchor.setAttribute( 'list', listId );
		anchor.addEventListener( 'change', () => set( ( x ) => {

			if ( anchor.value.trim() ) x.anchor = anchor.value.trim();
			else delete x.anchor;

		} ) );
		const n = vertexCount( g, p );
		const av = select( [ [ '', 'Top centre (default)' ], ...Array.from( { length: n }, ( _, i ) => [ String( i ), `Vertex ${ i }` ] ) ], pl.anchor_vertex ?? '', { 'data-key': 'pl-av' } );
		av.addEventListener( 'change', () => set( ( x ) => {

			if ( av.value === '' ) delete x.anchor_vertex;
			else x.anchor_vertex = Number( av.value );

		} ) );
		const distance = numberInput( pl.distance != null ? Math.round( pl.distance * 1000 ) / 10 : 3, { 'data-key': 'pl-dist', min: 0 } );
		distance.addEventListener( 'change', () => {

			const d = num( distance.value );
			if ( Number.isFinite( d ) && d >= 0 ) set( ( x ) => {

				x.distance = d / 100;

			} );

		} );
		const wrap = h( 'input', { type: 'checkbox', checked: pl.wrap !== false, 'data-key': 'pl-wrap', id: nextId( 'wrap' ) } );
		wrap.addEventListener( 'change', () => set( ( x ) => {

			x.wrap = wrap.checked;

		} ) );
		fs.append(
			h( 'div', { class: 'field-row--2' }, field( 'Side', side ), field( 'Anchor landmark', anchor ) ),
			h( 'datalist', { id: listId }, LANDMARKS.map( ( l ) => h( 'option', { value: l } ) ) ),
			h( 'div', { class: 'field-row--2' }, field( 'Point at the anchor', av ), field( 'Distance from the body (cm)', distance ) ),
			h( 'div', { class: 'mp-check' }, wrap, h( 'label', { for: wrap.id }, 'Wrap round the body part' ) ),
		);
		return fs;

	}

	function textureFields( p ) {

		const fs = h( 'fieldset', { class: 'field mp-ops' }, h( 'legend', {}, 'Texture' ) );
		const tex = textures.get( p.name );
		const file = h( 'input', { type: 'file', accept: 'image/png,image/jpeg', 'data-key': 'tex-file' } );
		file.addEventListener( 'change', () => {

			const f = file.files && file.files[ 0 ];
			if ( ! f ) return;
			let path = texturePath( p.name, f );
			const taken = new Set( g.panels.filter( ( q ) => q.name !== p.name && q.texture ).map( ( q ) => q.texture.image ) );
			for ( let k = 2; taken.has( path ); k ++ ) path = texturePath( p.name, f ).replace( /(\.\w+)$/, `-${ k }$1` );
			const old = textures.get( p.name );
			if ( old && old.url ) URL.revokeObjectURL( old.url );
			textures.set( p.name, { path, blob: f, url: URL.createObjectURL( f ) } );
			mutate( () => {

				const q = findPanel( g, selected );
				q.texture = { image: path, size: ( q.texture && q.texture.size ) || [ 0.1, 0.1 ] };

			} );

		} );
		fs.append( field( 'Image (PNG or JPEG)', file, tex ? `Now: ${ tex.path }${ tex.blob ? '' : ' (kept from the saved version)' }` : 'None: the fabric’s colour.' ) );
		if ( p.texture ) {

			if ( tex && tex.url ) fs.append( h( 'img', { class: 'mp-tex', src: tex.url, alt: `Texture of ${ p.name }`, width: 64, height: 64 } ) );
			const [ w, hgt ] = p.texture.size || [ 0.1, 0.1 ];
			const tw = numberInput( Math.round( w * 1000 ) / 10, { min: 0.1, 'data-key': 'tex-w' } );
			const th = numberInput( Math.round( hgt * 1000 ) / 10, { min: 0.1, 'data-key': 'tex-h' } );
			const setSize = () => {

				const a = num( tw.value ), b = num( th.value );
				if ( a > 0 && b > 0 ) mutate( () => {

					findPanel( g, selected ).texture.size = [ a / 100, b / 100 ];

				} );

			};

			tw.addEventListener( 'change', setSize );
			th.addEventListener( 'change', setSize );
			fs.append(
				h( 'div', { class: 'field-row--2' }, field( 'One repeat, width (cm)', tw ), field( 'Height (cm)', th ) ),
				h( 'button', { type: 'button', class: 'button button--secondary button--small', 'data-key': 'tex-rm', onclick: () => {

					const old = textures.get( p.name );
					if ( old && old.url ) URL.revokeObjectURL( old.url );
					textures.delete( p.name );
					mutate( () => {

						delete findPanel( g, selected ).texture;

					} );

				} }, 'Remove texture' ),
			);

		}

		return fs;

	}

	function sideText( side, short = false ) {

		const s = sideAsShown( g, side );
		if ( short ) return `${ side.panel }${ s.ghost ? ' (mirrored half)' : '' } ${ s.first }→${ s.last }`;
		return `${ side.panel }${ s.ghost ? ' (mirrored half)' : '' }, vertices ${ s.first } → ${ s.last }`;

	}

	function renderSeams() {

		clear( seamSec );
		seamSec.append( h( 'h2', { id: 'mp-seams-title' }, 'Seams' ) );
		const { a, b } = draftSides();
		const box = h( 'div', { class: 'mp-draft' } );
		if ( mode !== 'seam' ) {

			box.append( h( 'p', { class: 'muted small' }, 'To sew a seam, choose “Sew seams” above the pattern and click the vertices of the two runs.' ),
				h( 'button', { type: 'button', class: 'button button--secondary button--small', 'data-key': 'to-seam', onclick: () => setMode( 'seam' ) }, 'Sew seams' ) );

		} else {

			const line = ( label, side, i ) => {

				let text;
				if ( side ) {

					const len = safe( () => seamLengthOf( side ) );
					text = `${ sideText( side ) }${ len != null ? `: ${ cm( len ) }` : '' }`;

				} else if ( picks.length === i + 1 ) text = `${ picks[ i ].panel }, from vertex ${ picks[ i ].vertex } — now click the last vertex`;
				else text = picks.length >= i ? 'click its first vertex' : '—';
				return h( 'div', { class: 'mp-draft__side' }, h( 'span', { class: 'mp-draft__label' }, label ), h( 'span', { 'data-side': label }, text ),
					side ? h( 'button', { type: 'button', class: 'button button--secondary button--small', 'data-key': `other-${ i }`, onclick: () => otherWay( i ) }, 'Other way round' ) : null,
					side && runCrossesFold( g, side ) ? h( 'span', { class: 'field__error' }, 'This run crosses the fold edge.' ) : null,
				);

			};

			box.append( line( 'First side', a, 0 ), line( 'Second side', b, 2 ), byNumber() );
			if ( a && b ) {

				const m = safe( () => seamLengths( g, { a, b, ease: draft.ease }, size ) );
				if ( m ) box.append( h( 'p', { class: `mp-diff ${ m.ok ? 'is-good' : 'is-bad' }`, 'aria-live': 'polite' }, `Size ${ size }: ${ cm( m.a ) } and ${ cm( m.b ) }, difference ${ pct( m.difference ) } (limit ${ pct( m.limit ) })` ) );

			}

			const name = h( 'input', { type: 'text', value: draft.name, 'data-key': 'd-name', placeholder: 'e.g. side left' } );
			name.addEventListener( 'input', () => {

				draft.name = name.value;

			} );
			const ease = numberInput( Math.round( draft.ease * 1000 ) / 10, { min: 0, 'data-key': 'd-ease' } );
			ease.addEventListener( 'change', () => {

				draft.ease = Math.max( 0, num( ease.value ) || 0 ) / 100;
				refresh( { garment: false } );

			} );
			const flip = h( 'button', { type: 'button', class: 'seg seg--toggle', 'aria-pressed': String( draft.reverse ), 'data-key': 'd-flip', onclick: () => {

				draft.reverse = ! draft.reverse;
				refresh( { garment: false } );

			} }, 'Flip direction' );
			box.append(
				h( 'div', { class: 'field-row--2' }, field( 'Seam name', name ), field( 'Ease (%)', ease, 'Length difference eased or gathered in.' ) ),
				h( 'div', { class: 'mp-actions' },
					h( 'div', { class: 'segs' }, flip ),
					h( 'button', { type: 'button', class: 'button button--primary button--small', disabled: ! ( a && b ), 'data-key': 'd-add', onclick: addSeam }, 'Add seam' ),
					h( 'button', { type: 'button', class: 'button button--secondary button--small', disabled: ! picks.length, 'data-key': 'd-clear', onclick: () => {

						picks = [];
						refresh( { garment: false } );

					} }, 'Clear' ),
				),
			);

		}

		seamSec.append( box );
		if ( ! g.seams.length ) {

			seamSec.append( h( 'p', { class: 'muted small' }, 'No seams yet: every piece must be sewn to the rest.' ) );
			return;

		}

		const rows = g.seams.map( ( s, i ) => {

			const m = safe( () => seamLengths( g, s, size ) );
			const bad = ! problemsStale && problems.some( ( p ) => p.seam === i );
			const easeIn = numberInput( Math.round( ( Number( s.ease ) || 0 ) * 1000 ) / 10, { min: 0, class: 'mp-num', 'aria-label': `Ease of seam ${ i } (%)`, 'data-key': `s-ease-${ i }` } );
			easeIn.addEventListener( 'change', () => mutate( () => {

				const e = Math.max( 0, num( easeIn.value ) || 0 ) / 100;
				if ( e ) g.seams[ i ].ease = Math.round( e * 1e4 ) / 1e4;
				else delete g.seams[ i ].ease;

			} ) );
			return h( 'tr', { class: [ highlight === i && 'is-highlighted', bad && 'has-problem' ].filter( Boolean ).join( ' ' ) || null, 'data-seam': i },
				h( 'th', { scope: 'row' }, s.name || `Seam ${ i }` ),
				h( 'td', { class: 'mp-runs' }, sideText( s.a, true ), h( 'br' ), sideText( s.b, true ) ),
				h( 'td', { class: m && ! m.ok ? 'is-bad' : null }, m ? `${ cm( m.a ) } / ${ cm( m.b ) }, ${ pct( m.difference ) }` : '—' ),
				h( 'td', {}, easeIn ),
				h( 'td', { class: 'mp-row-actions' },
					h( 'button', { type: 'button', class: 'button button--secondary button--small', 'aria-pressed': String( highlight === i ), 'aria-label': `Show seam ${ s.name || i }`, 'data-key': `s-show-${ i }`, onclick: () => {

						highlight = highlight === i ? null : i;
						refresh( { garment: false } );

					} }, 'Show' ),
					h( 'button', { type: 'button', class: 'button button--secondary button--small', 'aria-pressed': String( shownReverse( g, s ) ), 'aria-label': `Flip direction of seam ${ s.name || i }`, 'data-key': `s-flip-${ i }`, onclick: () => mutate( () => {

						g.seams[ i ].reverse = ! g.seams[ i ].reverse;
						highlight = i;

					} ) }, 'Flip' ),
					h( 'button', { type: 'button', class: 'button button--danger button--small', 'aria-label': `Delete seam ${ s.name || i }`, 'data-key': `s-del-${ i }`, onclick: () => mutate( () => {

						g.seams.splice( i, 1 );
						highlight = null;
						problems = problems.filter( ( p ) => p.seam == null );

					} ) }, 'Delete' ),
				),
			);

		} );
		seamSec.append( h( 'div', { class: 'mp-table-wrap' }, h( 'table', { class: 'table mp-seams' },
			h( 'caption', { class: 'visually-hidden' }, `Seams, lengths in size ${ size }` ),
			h( 'thead', {}, h( 'tr', {}, h( 'th', { scope: 'col' }, 'Seam' ), h( 'th', { scope: 'col' }, 'Runs' ), h( 'th', { scope: 'col' }, `Lengths (${ size })` ), h( 'th', { scope: 'col' }, 'Ease %' ), h( 'th', { scope: 'col' }, h( 'span', { class: 'visually-hidden' }, 'Actions' ) ) ) ),
			h( 'tbody', {}, rows ),
		) ) );

	}

	/** Picking by numbers (for the keyboard): a piece, its first and last vertex, which half. */
	function byNumber() {

		const wrap = h( 'details', { class: 'mp-bynumber' }, h( 'summary', {}, 'Or choose the vertices by number' ) );
		const row = ( label, i ) => {

			const cur = picks[ i ] && picks[ i + 1 ] ? picks[ i ] : null;
			const panelSel = select( g.panels.map( ( p ) => [ p.name, p.name ] ), cur ? cur.panel : ( selected || g.panels[ 0 ].name ), { 'data-key': `bn-panel-${ i }` } );
			const n = () => vertexCount( g, panelSel.value );
			const vsel = ( key, value ) => select( Array.from( { length: n() }, ( _, v ) => [ String( v ), String( v ) ] ), value, { 'data-key': key } );
			let from = vsel( `bn-from-${ i }`, cur ? cur.vertex : 0 );
			let to = vsel( `bn-to-${ i }`, cur ? picks[ i + 1 ].vertex : 1 );
			const folded = () => findPanel( g, sourceVertexMap( g, panelSel.value )[ 0 ] ).fold != null;
			const half = select( [ [ '', 'as drawn' ], [ 'ghost', 'mirrored half' ] ], cur && cur.ghost ? 'ghost' : '', { 'data-key': `bn-half-${ i }` } );
			const halfField = field( 'Half', half );
			halfField.hidden = ! folded();
			const fromField = field( 'First vertex', from ), toField = field( 'Last vertex', to );
			panelSel.addEventListener( 'change', () => {

				const f2 = vsel( `bn-from-${ i }`, 0 ), t2 = vsel( `bn-to-${ i }`, 1 );
				f2.id = from.id;
				t2.id = to.id;
				from.replaceWith( f2 );
				to.replaceWith( t2 );
				from = f2;
				to = t2;
				halfField.hidden = ! folded();

			} );
			const set = h( 'button', { type: 'button', class: 'button button--secondary button--small', 'data-key': `bn-set-${ i }`, onclick: () => {

				const ghost = folded() && half.value === 'ghost';
				const next = picks.slice( 0, i );
				while ( next.length < i ) next.push( null );
				next[ i ] = { panel: panelSel.value, vertex: Number( from.value ), ghost };
				next[ i + 1 ] = { panel: panelSel.value, vertex: Number( to.value ), ghost };
				if ( i === 0 && picks.length === 4 ) next.push( picks[ 2 ], picks[ 3 ] );
				picks = next.filter( Boolean );
				refresh( { garment: false } );

			} }, `Set the ${ label }` );
			return h( 'fieldset', { class: 'field mp-ops' }, h( 'legend', {}, label.charAt( 0 ).toUpperCase() + label.slice( 1 ) ),
				h( 'div', { class: 'mp-inline' }, field( 'Piece', panelSel ), fromField, toField, halfField, set ) );

		};

		wrap.append( row( 'first side', 0 ) );
		if ( picks.length >= 2 ) wrap.append( row( 'second side', 2 ) );
		wrap.open = byNumberOpen;
		wrap.addEventListener( 'toggle', () => {

			byNumberOpen = wrap.open;

		} );
		return wrap;

	}

	function seamLengthOf( side ) {

		return seamLengths( g, { a: side, b: side }, size ).a;

	}

	function renderFabric() {

		renderFabricForm( fabricSec, { fabric: g.fabric, names: fabricNames, change: ( fn ) => mutate( () => {

			g.fabric = fn( g.fabric );

		} ) } );

	}

	function renderSave() {

		clear( saveSec );
		const btn = h( 'button', { type: 'button', class: 'button button--primary button--wide', 'data-key': 'save', onclick: save }, savedId ? 'Save as a new version' : 'Save' );
		saveSec.append( h( 'h2', { id: 'mp-save-title' }, 'Save' ), btn, saveStatus );
		if ( problems.length ) {

			saveSec.append( h( 'div', { class: 'notice notice--error mp-problems', role: 'alert' },
				h( 'div', { class: 'notice__body' },
					h( 'p', { class: 'notice__title' }, `The last save was refused: ${ problems.length === 1 ? 'a problem' : `${ problems.length } problems` }` ),
					problemsStale ? h( 'p', { class: 'notice__text' }, 'You have changed the garment since; save again to check it.' ) : null,
					h( 'ul', {}, problems.map( ( p ) => h( 'li', { 'data-panel': p.panel || null, 'data-edge': p.edge ?? null },
						p.panel ? h( 'button', { type: 'button', class: 'mp-link', onclick: () => {

							if ( g.panels.some( ( q ) => q.name === p.panel ) ) selected = p.panel;
							if ( Number.isInteger( p.seam ) ) highlight = p.seam;
							if ( p.size && g.sizes.includes( p.size ) ) size = p.size;
							setMode( 'edit' );

						} }, p.panel ) : null,
						p.panel ? ( p.edge != null ? `, edge ${ p.edge }: ` : ': ' ) : null,
						p.message ) ) ),
				) ) );

		}

		if ( lastWarnings.length ) {

			saveSec.append( h( 'div', { class: 'notice notice--warn', role: 'status' }, h( 'div', { class: 'notice__body' },
				h( 'p', { class: 'notice__title' }, 'Warnings' ),
				h( 'ul', {}, lastWarnings.map( ( w ) => h( 'li', {}, typeof w === 'string' ? w : w.message || JSON.stringify( w ) ) ) ) ) ) );

		}

	}

	const saveStatus = h( 'div', { class: 'mp-save__status', 'aria-live': 'polite' } );
	let lastWarnings = [];
	let saving = false;

	async function save() {

		if ( saving ) return;
		saving = true;
		clear( saveStatus ).append( spinner( 'Saving…' ) );
		const files = new Map();
		for ( const p of g.panels ) {

			const t = textures.get( p.name );
			if ( p.texture && t && t.blob && t.path === p.texture.image ) files.set( t.path, t.blob );

		}

		try {

			const res = await saveGarment( savedId, g, files, { signal } );
			if ( signal.aborted ) return;
			problems = [];
			lastWarnings = ( res && res.warnings ) || [];
			savedId = res.id;
			dirty = false;
			for ( const t of textures.values() ) t.blob = null; // kept on the server from now on
			clear( saveStatus ).append( notice( 'info', `Saved: version ${ res.version }`, 'Each size is being dressed on its sample body; the preview below follows.' ) );
			savedItem = mergeSaved( savedItem, res, g );
			preview.update( savedItem );
			refresh( { garment: false } );
			poll();

		} catch ( err ) {

			if ( err && err.name === 'AbortError' ) return;
			if ( isUnauthorised( err ) ) return onUnauthorised();
			if ( err instanceof ApiError && err.problems && err.problems.length ) {

				problems = err.problems;
				problemsStale = false;
				clear( saveStatus );
				const firstPanel = problems.find( ( p ) => p.panel && g.panels.some( ( q ) => q.name === p.panel ) );
				if ( firstPanel ) selected = firstPanel.panel;
				refresh( { garment: false } );

			} else {

				problems = [];
				clear( saveStatus ).append( errorNotice( err ) );
				refresh( { garment: false } );

			}

		} finally {

			saving = false;

		}

	}

	/** Poll the saved garment every 2 s while a size is queued or being dressed. */
	function poll() {

		clearTimeout( pollTimer );
		if ( ! savedId || signal.aborted ) return;
		pollTimer = setTimeout( async () => {

			try {

				const it = await getGarment( savedId, { signal } );
				if ( signal.aborted ) return;
				savedItem = it;
				preview.update( it );
				if ( isBusy( it ) ) poll();

			} catch ( err ) {

				if ( err && err.name === 'AbortError' ) return;
				if ( isUnauthorised( err ) ) return onUnauthorised();
				poll(); // try again

			}

		}, 2000 );

	}

	const beforeUnload = ( e ) => {

		if ( ! dirty ) return;
		e.preventDefault();
		e.returnValue = '';

	};

	window.addEventListener( 'beforeunload', beforeUnload );
	signal.addEventListener( 'abort', () => {

		window.removeEventListener( 'beforeunload', beforeUnload );
		clearTimeout( pollTimer );
		view.dispose();
		for ( const t of textures.values() ) if ( t.url ) URL.revokeObjectURL( t.url );

	}, { once: true } );

	// the textures of a saved version, to show them on the pieces
	async function loadTextures() {

		const v = savedItem && versionOf( savedItem );
		if ( ! savedId || ! v ) return;
		for ( const [ name, t ] of textures ) {

			if ( t.url || t.blob ) continue;
			try {

				const blob = await fetchFile( savedId, v.version, t.path, { signal } );
				if ( signal.aborted ) return;
				if ( textures.get( name ) === t && ! t.url ) t.url = URL.createObjectURL( blob );

			} catch ( err ) {

				if ( err && err.name === 'AbortError' ) return;
				if ( isUnauthorised( err ) ) return onUnauthorised();
				// not there: drawn without it

			}

		}

		refresh( { garment: false } );

	}

	catalogueFabrics( { signal } ).then( ( names ) => {

		if ( signal.aborted || ! names.length ) return;
		fabricNames = [ ...new Set( [ ...names, ...PRESET_FABRICS ] ) ];
		keepFocus( fabricSec, renderFabric );

	} ).catch( () => {} );

	// --- start ------------------------------------------------------------------------------------
	if ( warnings.length ) {

		importInfo.append( h( 'div', { class: 'notice notice--warn mp-import__warnings', role: 'status' }, h( 'div', { class: 'notice__body' },
			h( 'p', { class: 'notice__title' }, 'The import says' ),
			h( 'ul', {}, warnings.map( ( w ) => h( 'li', {}, typeof w === 'string' ? w : w.message || JSON.stringify( w ) ) ) ) ) ) );

	}

	if ( pieces && pieces.length ) {

		importInfo.append( h( 'details', { class: 'panel mp-import__pieces' },
			h( 'summary', {}, `Imported ${ pieces.length === 1 ? 'one piece' : `${ pieces.length } pieces` } (${ [ ...new Set( pieces.map( ( p ) => p.size ) ) ].join( ', ' ) })` ),
			h( 'table', { class: 'table' },
				h( 'thead', {}, h( 'tr', {}, [ 'Piece', 'Size', 'Quantity', 'Area', 'Perimeter' ].map( ( t ) => h( 'th', { scope: 'col' }, t ) ) ) ),
				h( 'tbody', {}, pieces.map( ( p ) => h( 'tr', {},
					h( 'th', { scope: 'row' }, p.name ), h( 'td', {}, p.size ), h( 'td', {}, String( p.quantity ?? 1 ) ),
					h( 'td', {}, p.area_m2 != null ? `${ ( p.area_m2 * 1e4 ).toFixed( 0 ) } cm²` : '—' ),
					h( 'td', {}, p.perimeter_m != null ? cm( p.perimeter_m ) : '—' ) ) ) ),
			) ) );

	}

	if ( ! id && ! given ) {

		// an import: pieces all start at the origin; lay them out side by side
		try {

			layoutPanels( g );

		} catch ( err ) {

			console.warn( 'layout', err );

		}

	}

	preview.update( savedItem );
	refresh();
	loadTextures();
	if ( savedItem && isBusy( savedItem ) ) poll();

	// a hook for tests and debugging
	window.__catwalk = window.__catwalk || {};
	window.__catwalk.merchantEditor = { garment: () => cloneGarment( g ), view, sourceVertexMap: ( p ) => sourceVertexMap( g, p ) };

	return {
		el,
		dirty: () => dirty,
		/** What is needed to open the editor again as it is (after logging in again). */
		snapshot: () => ( {
			garment: cloneGarment( g ), id: savedId, item: savedItem, dirty,
			textures: new Map( [ ...textures ].map( ( [ name, t ] ) => [ name, { path: t.path, blob: t.blob } ] ) ),
		} ),
	};

}

function safe( fn ) {

	try {

		return fn();

	} catch {

		return null;

	}

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
