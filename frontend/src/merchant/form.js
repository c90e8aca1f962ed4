// Small form pieces of the merchant pages: a labelled field, a select, a number input, and a
// re-render that keeps the keyboard focus where it was.

import { h, nextId } from '../ui/dom.js';

/** A number from an input's value (NaN when empty). */
export const num = ( v ) => ( v === '' || v == null ? NaN : Number( v ) );

export function field( label, control, hint = null ) {

	const id = control.id || nextId( 'f' );
	control.id = id;
	return h( 'div', { class: 'field' }, h( 'label', { for: id }, label ), control, hint ? h( 'p', { class: 'field__hint' }, hint ) : null );

}

export function select( options, value, attrs = {} ) {

	const el = h( 'select', attrs );
	for ( const [ v, text ] of options ) el.append( h( 'option', { value: v, selected: String( v ) === String( value ) }, text ) );
	return el;

}

export function numberInput( value, attrs = {} ) {

	return h( 'input', { type: 'number', inputmode: 'decimal', step: 'any', value: value == null || Number.isNaN( value ) ? '' : String( value ), ...attrs } );

}

/** Re-render `section` with `fn`, putting the focus back on the control with the same data-key. */
export function keepFocus( section, fn ) {

	const active = document.activeElement;
	const key = active && section.contains( active ) ? active.dataset.key : null;
	fn();
	if ( key ) {

		const again = section.querySelector( `[data-key="${ window.CSS && CSS.escape ? CSS.escape( key ) : key }"]` );
		if ( again ) again.focus( { preventScroll: true } );

	}

}
