// The garment's fabric: a catalogue fabric (a preset of catwalk.cloth.fabrics or one Petrak et
// al. measured) or a custom one (docs/garment-format.md: a preset with overrides, or every
// Fabric field); the editor's fabric section, that form on the garment being edited.

import { h, clear, nextId } from '../ui/dom.js';
import { fabricName } from '../format.js';
import { field, select, numberInput, num, keepFocus } from './form.js';

export const PRESET_FABRICS = [ 'cotton-jersey', 'denim', 'silk-charmeuse', 'wool-suiting', 'm1', 'm2', 'm3', 'm4', 'm5', 'm6' ];
// the custom fabric's fields (catwalk.cloth.fabrics.Fabric), SI units
const FABRIC_FIELDS = [
	[ 'density', 'Density', 'kg/m²' ],
	[ 'stretch_warp', 'Stretch, warp', 'N/m' ],
	[ 'stretch_weft', 'Stretch, weft', 'N/m' ],
	[ 'shear', 'Shear', 'N/m' ],
	[ 'bend_warp', 'Bending, warp', 'N·m' ],
	[ 'bend_weft', 'Bending, weft', 'N·m' ],
	[ 'damping', 'Damping', '' ],
	[ 'air', 'Air drag', '' ],
	[ 'friction', 'Friction', '' ],
	[ 'tau', 'Strain limit', '' ],
];
const REQUIRED_FABRIC = [ 'density', 'stretch_warp', 'stretch_weft', 'shear', 'bend_warp', 'bend_weft' ];

/**
 * The fabric section into `section`: a catalogue fabric (`names`: the presets and measured
 * fabrics the catalogue offers) or a custom one (a preset with overrides, or every value).
 * `change(fn)`: the garment's fabric becomes `fn(fabric)`.
 */
export function renderFabricForm( section, { fabric, names: offered, change } ) {

	clear( section );
	const custom = typeof fabric === 'object' && fabric !== null;
	const fabricId = nextId( 'fabric' );
	const presetRadio = h( 'input', { type: 'radio', name: fabricId, id: `${ fabricId }-p`, checked: ! custom, 'data-key': 'fab-preset' } );
	const customRadio = h( 'input', { type: 'radio', name: fabricId, id: `${ fabricId }-c`, checked: custom, 'data-key': 'fab-custom' } );
	const names = offered.slice();
	if ( ! custom && fabric && ! names.includes( fabric ) ) names.unshift( fabric );
	presetRadio.addEventListener( 'change', () => change( ( f ) => ( typeof f === 'object' && f && f.base ? f.base : 'cotton-jersey' ) ) );
	customRadio.addEventListener( 'change', () => change( ( f ) => ( { base: typeof f === 'string' && PRESET_FABRICS.includes( f ) ? f : 'cotton-jersey' } ) ) );
	section.append( h( 'h2', { id: 'mp-fabric-title' }, 'Fabric' ),
		h( 'div', { class: 'segmented', role: 'radiogroup', 'aria-label': 'Fabric' },
			h( 'span', { class: 'segmented__item' }, presetRadio, h( 'label', { for: presetRadio.id }, 'A catalogue fabric' ) ),
			h( 'span', { class: 'segmented__item' }, customRadio, h( 'label', { for: customRadio.id }, 'Custom' ) ) ) );
	if ( ! custom ) {

		const sel = select( names.map( ( n ) => [ n, fabricName( n ) ] ), fabric || 'cotton-jersey', { 'data-key': 'fab-name' } );
		sel.addEventListener( 'change', () => change( () => sel.value ) );
		section.append( field( 'Fabric of the garment', sel, 'Presets and fabrics measured by Petrak et al. (m1–m6).' ) );
		return;

	}

	const spec = fabric;
	const base = select( [ [ '', 'None: give every value' ], ...PRESET_FABRICS.map( ( n ) => [ n, fabricName( n ) ] ) ], spec.base || '', { 'data-key': 'fab-base' } );
	base.addEventListener( 'change', () => change( ( f ) => {

		const next = { ...f };
		if ( base.value ) next.base = base.value;
		else {

			delete next.base;
			next.id = next.id || 'custom';
			next.name = next.name || 'custom fabric';

		}

		return next;

	} ) );
	const grid = h( 'div', { class: 'measure-grid' } );
	for ( const [ key, label, unit ] of FABRIC_FIELDS ) {

		const input = numberInput( spec[ key ], { 'data-key': `fab-${ key }`, min: 0, placeholder: spec.base ? 'as the base' : REQUIRED_FABRIC.includes( key ) ? 'required' : 'default' } );
		input.addEventListener( 'change', () => change( ( f ) => {

			const next = { ...f };
			const v = num( input.value );
			if ( Number.isFinite( v ) ) next[ key ] = v;
			else delete next[ key ];
			return next;

		} ) );
		grid.append( field( unit ? `${ label } (${ unit })` : label, input ) );

	}

	section.append( field( 'Based on', base, 'Values left empty are the base fabric’s.' ), grid );

}

/** The fabric section of the editor in `state` (editor-state.js): `{ el, render() }`. */
export function createFabricPanel( state ) {

	const el = h( 'section', { class: 'panel mp-sec', 'aria-labelledby': 'mp-fabric-title' } );
	const draw = () => renderFabricForm( el, { fabric: state.g.fabric, names: state.fabricNames, change: ( fn ) => state.mutate( () => {

		state.g.fabric = fn( state.g.fabric );

	} ) } );
	return { el, render: () => keepFocus( el, draw ) };

}
