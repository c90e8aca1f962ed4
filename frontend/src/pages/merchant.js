// Merchants (/merchant): log in with an API key, list your garments, import a DXF, edit a
// garment (pieces, seams, fabric, textures), save versions, preview each size dressed, publish.
// The key is kept in sessionStorage only; every call sends it as a Bearer token.

import { h, clear } from '../ui/dom.js';
import { spinner, errorNotice } from '../ui/feedback.js';
import { getKey, setKey, forgetKey, listGarments, getGarment, isUnauthorised } from '../merchant/api.js';
import { createList } from '../merchant/garment-list.js';
import { createEditor } from '../merchant/editor.js';

export function render( root, route, ctx ) {

	document.title = 'Merchants — catwalk';
	const page = h( 'div', { class: 'merchant-page' } );
	root.append( page );
	let sub = null; // the shown view's AbortController
	let editor = null; // the shown editor
	let stash = null; // an editor's unsaved work when the key was refused (memory only)

	function view( fn ) {

		if ( sub ) sub.abort();
		sub = new AbortController();
		const signal = sub.signal;
		clear( page );
		fn( signal );
		window.scrollTo( 0, 0 );

	}

	ctx.onCleanup( () => {

		if ( sub ) sub.abort();

	} );

	function unauthorised() {

		if ( editor && editor.dirty() ) stash = editor.snapshot();
		forgetKey();
		showLogin( 'key not accepted' );

	}

	function logout() {

		stash = null;
		forgetKey();
		showLogin( null, 'You are logged out.' );

	}

	function showLogin( error = null, info = null ) {

		view( ( signal ) => {

			editor = null;
			document.title = 'Merchants — catwalk';
			const input = h( 'input', { type: 'password', id: 'merchant-key', name: 'key', autocomplete: 'off', spellcheck: 'false', required: true, 'aria-describedby': 'merchant-key-hint merchant-key-error' } );
			const err = h( 'p', { class: 'field__error', id: 'merchant-key-error', 'aria-live': 'assertive' }, error || '' );
			if ( error ) input.setAttribute( 'aria-invalid', 'true' );
			const submit = h( 'button', { type: 'submit', class: 'button button--primary button--wide' }, 'Log in' );
			const form = h( 'form', { class: 'panel merchant-login', novalidate: true },
				h( 'div', { class: 'field' },
					h( 'label', { for: input.id }, 'API key' ),
					input,
					h( 'p', { class: 'field__hint', id: 'merchant-key-hint' }, 'The key you were given (it starts with cwk_). It stays in this tab only and is forgotten when you close it.' ),
					err,
				),
				submit,
			);
			form.addEventListener( 'submit', async ( e ) => {

				e.preventDefault();
				const key = input.value.trim();
				if ( ! key ) {

					err.textContent = 'Enter your API key.';
					input.setAttribute( 'aria-invalid', 'true' );
					input.focus();
					return;

				}

				submit.disabled = true;
				submit.textContent = 'Checking…';
				err.textContent = '';
				try {

					await listGarments( { signal, key } );
					if ( signal.aborted ) return;
					setKey( key );
					showList();

				} catch ( ex ) {

					if ( ex && ex.name === 'AbortError' ) return;
					submit.disabled = false;
					submit.textContent = 'Log in';
					input.setAttribute( 'aria-invalid', 'true' );
					err.textContent = isUnauthorised( ex ) ? 'key not accepted' : ex.message;
					input.focus();

				}

			} );
			page.append( h( 'div', { class: 'page-narrow' },
				h( 'p', { class: 'eyebrow' }, 'Merchants' ),
				h( 'h1', {}, 'Your garments on catwalk' ),
				h( 'p', { class: 'lead' }, 'Import a pattern, sew its seams, choose the fabric, and see each size dressed on a sample body before you publish it to the catalogue.' ),
				info ? h( 'p', { class: 'muted', role: 'status' }, info ) : null,
				form,
			) );
			if ( error ) input.focus();

		} );

	}

	function showList() {

		view( ( signal ) => {

			editor = null;
			document.title = 'Your garments — catwalk';
			const list = createList( {
				signal,
				onOpen: openGarment,
				onImported: ( res, fileName ) => showEditor( { garment: res.garment, warnings: res.warnings || [], pieces: res.pieces || [], fileName } ),
				onUnauthorised: unauthorised,
				onLogout: logout,
			} );
			page.append( list.el );
			if ( stash ) {

				const kept = stash;
				list.notice( 'info', 'Your unsaved changes are kept', `“${ kept.garment.name || 'Untitled garment' }” was being edited when the key was refused.`,
					{ label: 'Back to the editor', onClick: () => {

						stash = null;
						showEditor( kept );

					} } );

			}

		} );

	}

	function openGarment( id ) {

		view( ( signal ) => {

			editor = null;
			page.append( spinner( 'Opening the garment…' ) );
			getGarment( id, { signal } ).then( ( item ) => {

				if ( signal.aborted ) return;
				const { garment, ...rest } = item;
				showEditor( { garment, id, item: { ...rest, default_size: garment && garment.default_size } } );

			} ).catch( ( err ) => {

				if ( err && err.name === 'AbortError' ) return;
				if ( isUnauthorised( err ) ) return unauthorised();
				clear( page ).append( errorNotice( err, () => openGarment( id ) ),
					h( 'button', { type: 'button', class: 'button button--secondary', onclick: showList }, 'All garments' ) );

			} );

		} );

	}

	function showEditor( { garment, id = null, item = null, warnings = [], pieces = null, fileName = null, textures = null, dirty = null } ) {

		view( ( signal ) => {

			if ( fileName && garment && ( ! garment.name || garment.name === 'garment' ) ) garment.name = fileName.replace( /\.dxf$/i, '' );
			document.title = `${ garment.name || 'Garment' } — catwalk merchants`;
			editor = createEditor( { garment, id, item, warnings, pieces, textures, dirty, signal, onBack: showList, onUnauthorised: unauthorised } );
			page.append( editor.el );

		} );

	}

	if ( getKey() ) showList();
	else showLogin();

}
