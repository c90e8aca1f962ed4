// The toolbar above the pattern: the size whose pieces are shown, the mode (select & move, or
// sew seams), "Lay out side by side", "Undo"; and the hint of the mode below it.

import { h, clear, nextId } from '../ui/dom.js';

const HINTS = {
	seam: 'Click the first and then the last vertex of a run on one piece, then on the piece it is sewn to. A run goes counter-clockwise from its first vertex to its last; the dashed lines join the ends that meet.',
	edit: 'Click a piece to select it; drag it to move it (arrow keys: 1 mm, with Shift 1 cm). Drag the background to pan; wheel, + and − to zoom.',
};

/** The toolbar of the editor in `state`: `{ el, hint, render() }`. `onLayout()`: lay the pieces out. */
export function createToolbar( state, { onLayout } ) {

	const sizeSel = h( 'select', { id: nextId( 'size' ), 'data-key': 'view-size' } );
	const modeEdit = h( 'button', { type: 'button', class: 'seg', 'aria-pressed': 'true' }, 'Select & move' );
	const modeSeam = h( 'button', { type: 'button', class: 'seg', 'aria-pressed': 'false' }, 'Sew seams' );
	const undoBtn = h( 'button', { type: 'button', class: 'button button--secondary button--small', disabled: true }, 'Undo' );
	const layoutBtn = h( 'button', { type: 'button', class: 'button button--secondary button--small' }, 'Lay out side by side' );
	const hint = h( 'p', { class: 'muted small mp-hint', 'aria-live': 'polite' } );
	const el = h( 'div', { class: 'mp-toolbar' },
		h( 'div', { class: 'control' }, h( 'label', { class: 'control__label', for: sizeSel.id }, 'Pieces of size' ), sizeSel ),
		h( 'div', { class: 'segs', role: 'group', 'aria-label': 'Mode' }, modeEdit, modeSeam ),
		layoutBtn, undoBtn,
	);
	sizeSel.addEventListener( 'change', () => state.set( { size: sizeSel.value } ) );
	modeEdit.addEventListener( 'click', () => state.set( { mode: 'edit' } ) );
	modeSeam.addEventListener( 'click', () => state.set( { mode: 'seam' } ) );
	undoBtn.addEventListener( 'click', () => state.undo() );
	layoutBtn.addEventListener( 'click', onLayout );

	function render() {

		undoBtn.disabled = ! state.canUndo();
		clear( sizeSel );
		for ( const s of state.g.sizes ) sizeSel.append( h( 'option', { value: s, selected: s === state.size }, s ) );
		modeEdit.setAttribute( 'aria-pressed', String( state.mode === 'edit' ) );
		modeSeam.setAttribute( 'aria-pressed', String( state.mode === 'seam' ) );
		hint.textContent = state.mode === 'seam' ? HINTS.seam : HINTS.edit;

	}

	return { el, hint, render };

}
