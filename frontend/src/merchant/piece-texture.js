// A piece's texture: the image chosen for it (kept in the editor's state until it is saved) and
// the size of one repeat; and the textures of a saved version, fetched to show on the pieces.

import { h } from '../ui/dom.js';
import { fetchFile, isUnauthorised } from './api.js';
import { field, numberInput, num } from './form.js';
import { findPanel, texturePath } from './garment-edit.js';
import { versionOf } from './status.js';

/** The "Texture" fieldset of the piece `p` (the selected one). */
export function textureFields( state, p ) {

	const fs = h( 'fieldset', { class: 'field mp-ops' }, h( 'legend', {}, 'Texture' ) );
	const tex = state.textures.get( p.name );
	const file = h( 'input', { type: 'file', accept: 'image/png,image/jpeg', 'data-key': 'tex-file' } );
	file.addEventListener( 'change', () => {

		const f = file.files && file.files[ 0 ];
		if ( f ) setImage( state, p.name, f );

	} );
	fs.append( field( 'Image (PNG or JPEG)', file, tex ? `Now: ${ tex.path }${ tex.blob ? '' : ' (kept from the saved version)' }` : 'None: the fabric’s colour.' ) );
	if ( p.texture ) {

		if ( tex && tex.url ) fs.append( h( 'img', { class: 'mp-tex', src: tex.url, alt: `Texture of ${ p.name }`, width: 64, height: 64 } ) );
		fs.append( ...repeatFields( state, p ) );

	}

	return fs;

}

/** The image `f` as the texture of the piece `name`, under a path no other piece's texture has. */
function setImage( state, name, f ) {

	let path = texturePath( name, f );
	const taken = new Set( state.g.panels.filter( ( q ) => q.name !== name && q.texture ).map( ( q ) => q.texture.image ) );
	for ( let k = 2; taken.has( path ); k ++ ) path = texturePath( name, f ).replace( /(\.\w+)$/, `-${ k }$1` );
	forget( state, name );
	state.textures.set( name, { path, blob: f, url: URL.createObjectURL( f ) } );
	state.mutate( () => {

		const q = findPanel( state.g, state.selected );
		q.texture = { image: path, size: ( q.texture && q.texture.size ) || [ 0.1, 0.1 ] };

	} );

}

/** One repeat's width and height (cm), and "Remove texture". */
function repeatFields( state, p ) {

	const [ w, hgt ] = p.texture.size || [ 0.1, 0.1 ];
	const tw = numberInput( Math.round( w * 1000 ) / 10, { min: 0.1, 'data-key': 'tex-w' } );
	const th = numberInput( Math.round( hgt * 1000 ) / 10, { min: 0.1, 'data-key': 'tex-h' } );
	const setSize = () => {

		const a = num( tw.value ), b = num( th.value );
		if ( a > 0 && b > 0 ) state.mutate( () => {

			findPanel( state.g, state.selected ).texture.size = [ a / 100, b / 100 ];

		} );

	};

	tw.addEventListener( 'change', setSize );
	th.addEventListener( 'change', setSize );
	return [
		h( 'div', { class: 'field-row--2' }, field( 'One repeat, width (cm)', tw ), field( 'Height (cm)', th ) ),
		h( 'button', { type: 'button', class: 'button button--secondary button--small', 'data-key': 'tex-rm', onclick: () => {

			forget( state, p.name );
			state.textures.delete( p.name );
			state.mutate( () => {

				delete findPanel( state.g, state.selected ).texture;

			} );

		} }, 'Remove texture' ),
	];

}

/** Let go of the image shown for the piece `name`. */
function forget( state, name ) {

	const old = state.textures.get( name );
	if ( old && old.url ) URL.revokeObjectURL( old.url );

}

/** Fetch the saved version's textures (with the merchant's key) to show them on the pieces, then redraw. */
export async function loadSavedTextures( state, { signal, onUnauthorised } ) {

	const v = state.savedItem && versionOf( state.savedItem );
	if ( ! state.savedId || ! v ) return;
	for ( const [ name, t ] of state.textures ) {

		if ( t.url || t.blob ) continue;
		try {

			const blob = await fetchFile( state.savedId, v.version, t.path, { signal } );
			if ( signal.aborted ) return;
			if ( state.textures.get( name ) === t && ! t.url ) t.url = URL.createObjectURL( blob );

		} catch ( err ) {

			if ( err && err.name === 'AbortError' ) return;
			if ( isUnauthorised( err ) ) return onUnauthorised();
			// not there: drawn without it

		}

	}

	state.refresh( { garment: false } );

}
