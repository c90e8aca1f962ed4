// The editor's garment section: the garment's name, type, description, default size, and its
// sizes in grading order (renamed, moved, removed).

import { h, clear } from '../ui/dom.js';
import { typeName } from '../format.js';
import { field, select, keepFocus } from './form.js';
import { GARMENT_TYPES, renameSize, removeSize, moveSize } from './garment-edit.js';

/** The garment section of the editor in `state`: `{ el, render() }`. */
export function createGarmentForm( state ) {

	const el = h( 'section', { class: 'panel mp-sec', 'aria-labelledby': 'mp-garment-title' } );
	const draw = () => {

		clear( el );
		el.append(
			h( 'h2', { id: 'mp-garment-title' }, 'Garment' ),
			...describeFields( state ),
			h( 'fieldset', { class: 'field' }, h( 'legend', {}, 'Sizes, in grading order' ), sizeList( state ),
				h( 'p', { class: 'field__hint' }, 'Each size is dressed on the sample body of that size after saving.' ) ),
		);

	};

	return { el, render: () => keepFocus( el, draw ) };

}

/** Name; type and default size; description. */
function describeFields( state ) {

	const g = state.g;
	const name = h( 'input', { type: 'text', value: g.name || '', 'data-key': 'g-name', maxlength: 200, required: true } );
	name.addEventListener( 'change', () => state.mutate( () => {

		state.g.name = name.value.trim() || state.g.name;

	} ) );
	const type = select( GARMENT_TYPES.map( ( t ) => [ t, typeName( t ) ] ), g.type || 'other', { 'data-key': 'g-type' } );
	type.addEventListener( 'change', () => state.mutate( () => {

		state.g.type = type.value;

	} ) );
	const desc = h( 'textarea', { rows: 2, 'data-key': 'g-desc', class: 'mp-textarea' } );
	desc.value = g.description || '';
	desc.addEventListener( 'change', () => state.mutate( () => {

		if ( desc.value.trim() ) state.g.description = desc.value.trim();
		else delete state.g.description;

	} ) );
	const def = select( g.sizes.map( ( s ) => [ s, s ] ), g.default_size, { 'data-key': 'g-default' } );
	def.addEventListener( 'change', () => state.mutate( () => {

		state.g.default_size = def.value;

	} ) );
	return [
		field( 'Garment name', name ),
		h( 'div', { class: 'field-row--2' }, field( 'Garment type', type ), field( 'Default size', def ) ),
		field( 'Description', desc ),
	];

}

/** Every size: its name, earlier, later, remove. */
function sizeList( state ) {

	const sizes = h( 'ul', { class: 'mp-sizes' } );
	const count = state.g.sizes.length;
	state.g.sizes.forEach( ( s, i ) => {

		const input = h( 'input', { type: 'text', value: s, 'aria-label': `Name of size ${ s }`, 'data-key': `size-${ i }`, maxlength: 200 } );
		input.addEventListener( 'change', () => {

			const to = input.value.trim();
			if ( state.mutate( () => renameSize( state.g, s, to ) ) && state.size === s ) {

				state.size = to;
				state.refresh();

			}

		} );
		const button = ( cls, label, key, disabled, onclick, text ) => h( 'button', { type: 'button', class: `button ${ cls } button--small`, 'aria-label': label, 'data-key': key, disabled, onclick }, text );
		sizes.append( h( 'li', {},
			input,
			button( 'button--secondary', `Move size ${ s } earlier`, `size-up-${ i }`, i === 0, () => state.mutate( () => moveSize( state.g, s, - 1 ) ), '↑' ),
			button( 'button--secondary', `Move size ${ s } later`, `size-down-${ i }`, i === count - 1, () => state.mutate( () => moveSize( state.g, s, 1 ) ), '↓' ),
			button( 'button--danger', `Remove size ${ s }`, `size-rm-${ i }`, count <= 1, () => {

				if ( state.mutate( () => removeSize( state.g, s ) ) && ! state.g.sizes.includes( state.size ) ) {

					state.size = state.g.default_size;
					state.refresh();

				}

			}, 'Remove' ),
		) );

	} );
	return sizes;

}
