// Your body (/body): measurements or a scan → the body in 3D, its girths, size advice per
// garment; the body id is remembered in localStorage, "Delete my body" forgets it.
//
// The panels are in body/: the measurements form, the scan upload, the 3D view, the facts, the
// sizes for every garment, the danger zone; this page chooses between setting a body up and
// showing it, and lays the panels out.

import { getBody, deleteBody, ApiError } from '../api.js';
import { urls } from '../router.js';
import { h, clear } from '../ui/dom.js';
import { errorNotice, spinner, notice } from '../ui/feedback.js';
import { getBodyId, setBodyId, forgetBody } from '../store.js';
import { measurementsForm } from '../body/measurements-form.js';
import { scanForm } from '../body/scan-form.js';
import { createBodyView } from '../body/body-3d.js';
import { bodyOrigin, girthTable } from '../body/body-facts.js';
import { createSizesPanel } from '../body/sizes-panel.js';
import { createDeletePanel } from '../body/delete-panel.js';

export function render( root, route, ctx ) {

	document.title = 'Your body — catwalk';
	const page = h( 'div', { class: 'body-page' } );
	root.append( page );
	// the page, its context, and the 3D view of the body shown
	const b = { page, ctx, viewer: null };
	ctx.onCleanup( () => b.viewer && b.viewer.dispose() );
	keepDroppedFiles( ctx );
	start( b );

}

/** The body remembered, loaded and shown; else (or when it is gone) the setup, `message` above it. */
async function start( b, message = null ) {

	const { page, ctx } = b;
	dropViewer( b );
	const id = getBodyId();
	if ( ! id ) {

		showSetup( b, message );
		return;

	}

	clear( page ).append( spinner( 'Loading your body…' ) );
	try {

		const body = await getBody( id, { signal: ctx.signal } );
		if ( ctx.live ) showBodyPage( b, body );

	} catch ( err ) {

		if ( ! ctx.live ) return;
		if ( err instanceof ApiError && err.status === 404 ) {

			forgetBody();
			showSetup( b, notice( 'warn', 'We no longer have your body', 'It may have been deleted. Set it up again below.' ) );

		} else {

			clear( page ).append( errorNotice( err, () => start( b ) ) );

		}

	}

}

/** The 3D view shown (if any) stopped and let go: its render loop and WebGL context with it. */
function dropViewer( b ) {

	if ( b.viewer ) {

		b.viewer.dispose();
		b.viewer = null;

	}

}

// --- setting a body up ------------------------------------------------------------------------

function showSetup( b, message = null ) {

	const { page, ctx } = b;
	dropViewer( b );
	clear( page );
	const previous = getBodyId();
	const onBody = ( body ) => {

		setBodyId( body.id );
		// one body per browser: the one it replaces is deleted (with its try-ons)
		if ( previous && previous !== body.id ) deleteBody( previous ).catch( () => {} );
		if ( ctx.live ) showBodyPage( b, body, true );

	};

	page.append(
		h( 'section', { class: 'intro' },
			h( 'h1', {}, 'Your body' ),
			h( 'p', { class: 'lead' }, 'We make a 3D body that walks like you from four measurements or from a 3D scan. It is kept under a private id that only this browser knows.' ),
			message,
			previous ? notice( 'info', 'This replaces your current body', 'When the new one is ready, the old one and its try-ons are deleted from our servers.', h( 'button', { type: 'button', class: 'button button--secondary', onclick: () => start( b ) }, 'Keep my current body' ) ) : null,
		),
		h( 'div', { class: 'setup' },
			measurementsForm( onBody, ctx ),
			scanForm( onBody, ctx ),
		),
	);

}

// --- the body ----------------------------------------------------------------------------------

function showBodyPage( b, body, fresh = false ) {

	const { page, ctx } = b;
	dropViewer( b );
	clear( page );
	const view = createBodyView( body, ctx, { onViewer: ( v ) => ( b.viewer = v ), onRetry: () => start( b ) } );
	const sizes = createSizesPanel( body, ctx );
	page.append(
		h( 'section', { class: 'intro' },
			h( 'h1', {}, 'Your body' ),
			fresh ? notice( 'info', 'Your body is ready', 'Pick a garment in the catalogue and press “Try it on”.', h( 'a', { class: 'button button--secondary', href: urls.catalogue(), 'data-link': '' }, 'Go to the catalogue' ) ) : null,
		),
		h( 'div', { class: 'body-layout' },
			view.el,
			h( 'div', { class: 'body-layout__facts' },
				h( 'p', {}, bodyOrigin( body ) ),
				girthTable( body ),
				sizes.el,
				h( 'div', { class: 'body-actions' },
					h( 'a', { class: 'button button--primary', href: urls.catalogue(), 'data-link': '' }, 'Try something on' ),
					h( 'button', { type: 'button', class: 'button button--secondary', onclick: () => showSetup( b ) }, 'Make a new body' ),
				),
				createDeletePanel( body, ctx, () => start( b, notice( 'info', 'Your body has been deleted', 'Nothing of it is kept on our servers.' ) ) ),
			),
		),
	);
	view.show();
	sizes.load();

}

/** A file dropped beside the drop zone must not make the browser leave the page. */
function keepDroppedFiles( ctx ) {

	const keepFiles = ( e ) => {

		if ( e.dataTransfer && [ ...e.dataTransfer.types ].includes( 'Files' ) ) e.preventDefault();

	};

	window.addEventListener( 'dragover', keepFiles );
	window.addEventListener( 'drop', keepFiles );
	ctx.onCleanup( () => {

		window.removeEventListener( 'dragover', keepFiles );
		window.removeEventListener( 'drop', keepFiles );

	} );

}
