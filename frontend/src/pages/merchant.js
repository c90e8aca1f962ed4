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
	// the page, the shown view's AbortController, the shown editor, and an editor's unsaved
	// work when the key was refused (memory only)
	const m = { page, sub: null, editor: null, stash: null };
	ctx.onCleanup( () => {

		if ( m.sub ) m.sub.abort();

	} );
	if ( getKey() ) showList( m );
	else showLogin( m );

}

/** Show a view: `fn(signal)` fills the page (the view before it aborted). */
function view( m, fn ) {

	if ( m.sub ) m.sub.abort();
	m.sub = new AbortController();
	const signal = m.sub.signal;
	clear( m.page );
	fn( signal );
	window.scrollTo( 0, 0 );

}

/** The key was refused: keep the editor's unsaved work, forget the key, log in again. */
function unauthorised( m ) {

	if ( m.editor && m.editor.dirty() ) m.stash = m.editor.snapshot();
	forgetKey();
	showLogin( m, 'key not accepted' );

}

function logout( m ) {

	m.stash = null;
	forgetKey();
	showLogin( m, null, 'You are logged out.' );

}

function showLogin( m, error = null, info = null ) {

	view( m, ( signal ) => {

		m.editor = null;
		document.title = 'Merchants — catwalk';
		const { form, input } = loginForm( { signal, error, onLoggedIn: () => showList( m ) } );
		m.page.append( h( 'div', { class: 'page-narrow' },
			h( 'p', { class: 'eyebrow' }, 'Merchants' ),
			h( 'h1', {}, 'Your garments on catwalk' ),
			h( 'p', { class: 'lead' }, 'Import a pattern, sew its seams, choose the fabric, and see each size dressed on a sample body before you publish it to the catalogue.' ),
			info ? h( 'p', { class: 'muted', role: 'status' }, info ) : null,
			form,
		) );
		if ( error ) input.focus();

	} );

}

/** The API key's form: the key is tried (listing the garments) before it is kept; `onLoggedIn()`. */
function loginForm( { signal, error, onLoggedIn } ) {

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
	const refuse = ( text ) => {

		input.setAttribute( 'aria-invalid', 'true' );
		err.textContent = text;
		input.focus();

	};

	form.addEventListener( 'submit', async ( e ) => {

		e.preventDefault();
		const key = input.value.trim();
		if ( ! key ) return refuse( 'Enter your API key.' );
		submit.disabled = true;
		submit.textContent = 'Checking…';
		err.textContent = '';
		try {

			await listGarments( { signal, key } );
			if ( signal.aborted ) return;
			setKey( key );
			onLoggedIn();

		} catch ( ex ) {

			if ( ex && ex.name === 'AbortError' ) return;
			submit.disabled = false;
			submit.textContent = 'Log in';
			refuse( isUnauthorised( ex ) ? 'key not accepted' : ex.message );

		}

	} );
	return { form, input };

}

function showList( m ) {

	view( m, ( signal ) => {

		m.editor = null;
		document.title = 'Your garments — catwalk';
		const list = createList( {
			signal,
			onOpen: ( id ) => openGarment( m, id ),
			onImported: ( res, fileName ) => showEditor( m, { garment: res.garment, warnings: res.warnings || [], pieces: res.pieces || [], fileName } ),
			onUnauthorised: () => unauthorised( m ),
			onLogout: () => logout( m ),
		} );
		m.page.append( list.el );
		if ( m.stash ) {

			const kept = m.stash;
			list.notice( 'info', 'Your unsaved changes are kept', `“${ kept.garment.name || 'Untitled garment' }” was being edited when the key was refused.`,
				{ label: 'Back to the editor', onClick: () => {

					m.stash = null;
					showEditor( m, kept );

				} } );

		}

	} );

}

function openGarment( m, id ) {

	view( m, ( signal ) => {

		m.editor = null;
		m.page.append( spinner( 'Opening the garment…' ) );
		getGarment( id, { signal } ).then( ( item ) => {

			if ( signal.aborted ) return;
			const { garment, ...rest } = item;
			showEditor( m, { garment, id, item: { ...rest, default_size: garment && garment.default_size } } );

		} ).catch( ( err ) => {

			if ( err && err.name === 'AbortError' ) return;
			if ( isUnauthorised( err ) ) return unauthorised( m );
			clear( m.page ).append( errorNotice( err, () => openGarment( m, id ) ),
				h( 'button', { type: 'button', class: 'button button--secondary', onclick: () => showList( m ) }, 'All garments' ) );

		} );

	} );

}

function showEditor( m, { garment, id = null, item = null, warnings = [], pieces = null, fileName = null, textures = null, dirty = null } ) {

	view( m, ( signal ) => {

		if ( fileName && garment && ( ! garment.name || garment.name === 'garment' ) ) garment.name = fileName.replace( /\.dxf$/i, '' );
		document.title = `${ garment.name || 'Garment' } — catwalk merchants`;
		m.editor = createEditor( { garment, id, item, warnings, pieces, textures, dirty, signal, onBack: () => showList( m ), onUnauthorised: () => unauthorised( m ) } );
		m.page.append( m.editor.el );

	} );

}
