// Your body from a 3D scan: the body shape (or "work it out"), a drop zone and file input for an
// OBJ, PLY, STL or GLB file; the upload's progress with "Cancel", then the fitting
// (POST /api/bodies as a file), and why a scan could not be used.

import { uploadScan, ApiError } from '../api.js';
import { h, clear, nextId, icon } from '../ui/dom.js';
import { errorNotice, notice, progressBar } from '../ui/feedback.js';

export const SCAN_TYPES = [ 'obj', 'ply', 'stl', 'glb' ];

/** Whether a file's name says it is none of SCAN_TYPES (a name without an extension may be one). */
export function notAScan( name ) {

	const ext = ( name.split( '.' ).pop() || '' ).toLowerCase();
	return name.includes( '.' ) && ! SCAN_TYPES.includes( ext );

}

/** The scan's form: `onBody(body)` with the body fitted to the scan. */
export function scanForm( onBody, ctx ) {

	const inputId = nextId( 'scan' );
	const sexId = nextId( 'scan-sex' );
	const file = h( 'input', { type: 'file', id: inputId, class: 'visually-hidden', accept: SCAN_TYPES.map( ( t ) => `.${ t }` ).join( ',' ) } );
	const zone = h( 'label', { class: 'dropzone', for: inputId },
		icon( 'upload' ),
		h( 'span', { class: 'dropzone__title' }, 'Drop your scan here' ),
		h( 'span', { class: 'dropzone__text' }, 'or choose a file — OBJ, PLY, STL or GLB, up to 100 MB' ),
	);
	const sex = h( 'select', { id: sexId, name: 'scan-sex' },
		h( 'option', { value: '' }, 'Work it out from the scan' ),
		h( 'option', { value: 'female' }, 'Female' ),
		h( 'option', { value: 'male' }, 'Male' ),
	);
	const sexError = h( 'p', { class: 'field__error', 'aria-live': 'polite' } );
	const status = h( 'div', { class: 'upload-status', 'aria-live': 'polite' } );
	const scanError = h( 'div', { class: 'scan-error', 'aria-live': 'assertive' } );
	const form = h( 'form', { class: 'panel scan-form', novalidate: true, 'aria-labelledby': 'scan-title' },
		h( 'h2', { id: 'scan-title' }, 'Or upload a 3D scan' ),
		h( 'p', { class: 'muted' }, 'From a phone scanning app or a body scanner: one person standing, legs apart, arms away from the body. Any units.' ),
		h( 'div', { class: 'field' }, h( 'label', { for: sexId }, 'Body shape' ), sex, sexError ),
		file,
		zone,
		scanError,
		status,
	);

	const send = uploader( { file, zone, sex, sexError, status, scanError }, onBody, ctx );
	file.addEventListener( 'change', () => {

		if ( file.files && file.files[ 0 ] ) send( file.files[ 0 ] );

	} );
	dropZone( zone, file, send );
	return form;

}

/** `send(file)`: upload a scan, showing its progress in the form's `parts`; the upload is aborted when the page goes. */
function uploader( parts, onBody, ctx ) {

	const { file, zone, sex, sexError, status, scanError } = parts;
	let upload = null;
	ctx.onCleanup( () => upload && upload.abort() );

	const busy = ( on ) => {

		zone.classList.toggle( 'dropzone--busy', on );
		file.disabled = on;
		sex.disabled = on;

	};

	return async function send( f ) {

		clear( scanError );
		clear( status );
		sexError.textContent = '';
		if ( notAScan( f.name ) ) {

			scanError.append( notice( 'error', 'We can’t read that file', `“${ f.name }” is not an OBJ, PLY, STL or GLB file.` ) );
			return;

		}

		const bar = progressBar( 'Upload progress' );
		const label = h( 'p', { class: 'upload-status__label' }, `Uploading ${ f.name }…` );
		const cancel = h( 'button', { type: 'button', class: 'button button--secondary button--small' }, 'Cancel' );
		status.append( label, bar.el, cancel );
		busy( true );
		upload = uploadScan( f, {
			sex: sex.value,
			onProgress: ( x ) => {

				bar.set( x );
				label.textContent = `Uploading ${ f.name }… ${ Math.floor( x * 100 ) } %`;

			},
			onSent: () => {

				bar.indeterminate( true );
				label.textContent = 'Fitting your body to your scan’s surface (about 10 s)…';
				cancel.remove();

			},
		} );
		cancel.addEventListener( 'click', () => upload && upload.abort() );
		try {

			const body = await upload.promise;
			upload = null;
			onBody( body );

		} catch ( err ) {

			upload = null;
			if ( ! ctx.live ) return;
			busy( false );
			clear( status );
			file.value = '';
			refused( err, parts );

		}

	};

}

/** Why an upload did not give a body: cancelled, the body shape refused, the scan refused, or the network. */
function refused( err, { sexError, status, scanError } ) {

	if ( err && err.name === 'AbortError' ) {

		status.append( h( 'p', { class: 'muted' }, 'Upload cancelled.' ) );

	} else if ( err instanceof ApiError && err.field === 'sex' ) {

		sexError.textContent = err.message;

	} else if ( err instanceof ApiError ) {

		scanError.append( notice( 'error', 'We couldn’t use this scan', err.message ) );

	} else {

		scanError.append( errorNotice( err ) );

	}

}

/** A file dropped on the zone is sent (not while an upload runs); the zone lights up under a drag. */
function dropZone( zone, file, send ) {

	for ( const type of [ 'dragenter', 'dragover' ] ) {

		zone.addEventListener( type, ( e ) => {

			e.preventDefault();
			if ( ! file.disabled ) zone.classList.add( 'dropzone--over' );

		} );

	}

	for ( const type of [ 'dragleave', 'dragend' ] ) zone.addEventListener( type, () => zone.classList.remove( 'dropzone--over' ) );
	zone.addEventListener( 'drop', ( e ) => {

		e.preventDefault();
		zone.classList.remove( 'dropzone--over' );
		if ( file.disabled ) return;
		const f = e.dataTransfer && e.dataTransfer.files && e.dataTransfer.files[ 0 ];
		if ( f ) send( f );

	} );

}
