// Your body (/body): measurements or a scan → the body in 3D, its girths, size advice per
// garment; the body id is remembered in localStorage, "Delete my body" forgets it.

import { createBody, uploadScan, getBody, deleteBody, listGarments, getSizeAdvice, apiPaths, hasSizesRoute, ApiError, NetworkError } from '../api.js';
import { urls } from '../router.js';
import { h, clear, nextId, icon } from '../ui/dom.js';
import { errorNotice, spinner, notice, progressBar } from '../ui/feedback.js';
import { FIELDS, LABELS, HINTS, GIRTHS, rangeCm, checkMeasurement, checkForm, formatCm } from '../measurements.js';
import { getBodyId, setBodyId, forgetBody } from '../store.js';
import { hasWebGL, NO_WEBGL_MESSAGE } from '../viewer/webgl.js';
import { showBody } from '../viewer/body-view.js';
import { shortName } from '../format.js';
import { adviceSummary } from '../advice.js';

const SCAN_TYPES = [ 'obj', 'ply', 'stl', 'glb' ];

export function render( root, route, ctx ) {

	document.title = 'Your body — catwalk';
	const page = h( 'div', { class: 'body-page' } );
	root.append( page );
	let viewer = null;
	ctx.onCleanup( () => viewer && viewer.dispose() );
	// a file dropped beside the drop zone must not make the browser leave the page
	const keepFiles = ( e ) => {

		if ( e.dataTransfer && [ ...e.dataTransfer.types ].includes( 'Files' ) ) e.preventDefault();

	};

	window.addEventListener( 'dragover', keepFiles );
	window.addEventListener( 'drop', keepFiles );
	ctx.onCleanup( () => {

		window.removeEventListener( 'dragover', keepFiles );
		window.removeEventListener( 'drop', keepFiles );

	} );

	async function start( message = null ) {

		if ( viewer ) {

			viewer.dispose();
			viewer = null;

		}

		const id = getBodyId();
		if ( ! id ) {

			showSetup( message );
			return;

		}

		clear( page ).append( spinner( 'Loading your body…' ) );
		try {

			const body = await getBody( id, { signal: ctx.signal } );
			if ( ctx.live ) showBodyPage( body );

		} catch ( err ) {

			if ( ! ctx.live ) return;
			if ( err instanceof ApiError && err.status === 404 ) {

				forgetBody();
				showSetup( notice( 'warn', 'We no longer have your body', 'It may have been deleted. Set it up again below.' ) );

			} else {

				clear( page ).append( errorNotice( err, () => start() ) );

			}

		}

	}

	// --- setting a body up --------------------------------------------------------------------

	function showSetup( message = null ) {

		clear( page );
		const previous = getBodyId();
		const onBody = ( body ) => {

			setBodyId( body.id );
			// one body per browser: the one it replaces is deleted (with its try-ons)
			if ( previous && previous !== body.id ) deleteBody( previous ).catch( () => {} );
			if ( ctx.live ) showBodyPage( body, true );

		};

		page.append(
			h( 'section', { class: 'intro' },
				h( 'h1', {}, 'Your body' ),
				h( 'p', { class: 'lead' }, 'We make a 3D body that walks like you from four measurements or from a 3D scan. It is kept under a private id that only this browser knows.' ),
				message,
				previous ? notice( 'info', 'This replaces your current body', 'When the new one is ready, the old one and its try-ons are deleted from our servers.', h( 'button', { type: 'button', class: 'button button--secondary', onclick: () => start() }, 'Keep my current body' ) ) : null,
			),
			h( 'div', { class: 'setup' },
				measurementsForm( onBody, ctx ),
				scanForm( onBody, ctx ),
			),
		);

	}

	// --- the body ----------------------------------------------------------------------------

	function showBodyPage( body, fresh = false ) {

		clear( page );
		const view = h( 'div', { class: 'stage stage--body' } );
		const scan = body.scan;
		const origin = body.source === 'scan'
			? `Made from your scan${ scan ? ` (${ scan.vertices.toLocaleString( 'en' ) } points, in ${ scan.units })` : '' }.`
			: 'Made from your measurements.';
		const distance = scan && scan.surface_distance_mm ? scan.surface_distance_mm.scan_to_body : null;
		const shapeNote = body.fit === 'surface' && distance
			? ` It takes your scan’s own shape: on average ${ distance.mean.toFixed( 1 ) } mm from its surface.`
			: '';
		const sexNote = body.sex_inferred ? ` We read the scan as a ${ body.sex } body shape.` : '';

		const deleteArea = h( 'div', { class: 'danger-zone' } );
		const deleteButton = h( 'button', { type: 'button', class: 'button button--danger' }, 'Delete my body' );
		deleteButton.addEventListener( 'click', () => confirmDelete( body, deleteArea, deleteButton ) );
		deleteArea.append( deleteButton );

		page.append(
			h( 'section', { class: 'intro' },
				h( 'h1', {}, 'Your body' ),
				fresh ? notice( 'info', 'Your body is ready', 'Pick a garment in the catalogue and press “Try it on”.', h( 'a', { class: 'button button--secondary', href: urls.catalogue(), 'data-link': '' }, 'Go to the catalogue' ) ) : null,
			),
			h( 'div', { class: 'body-layout' },
				h( 'div', { class: 'body-layout__view' }, view, h( 'p', { class: 'muted small' }, 'Drag to turn, pinch or scroll to zoom.' ) ),
				h( 'div', { class: 'body-layout__facts' },
					h( 'p', {}, origin + shapeNote + sexNote ),
					girthTable( body ),
					h( 'section', { class: 'advice-all', 'aria-labelledby': 'advice-title', hidden: true },
						h( 'h2', { id: 'advice-title' }, 'Your sizes' ),
						h( 'div', { class: 'advice-all__list' } ),
					),
					h( 'div', { class: 'body-actions' },
						h( 'a', { class: 'button button--primary', href: urls.catalogue(), 'data-link': '' }, 'Try something on' ),
						h( 'button', { type: 'button', class: 'button button--secondary', onclick: () => showSetup() }, 'Make a new body' ),
					),
					deleteArea,
				),
			),
		);

		if ( hasWebGL() ) {

			view.append( spinner( 'Loading your body in 3D…' ) );
			showBody( view, body.body_url, { signal: ctx.signal } ).then( ( v ) => {

				if ( ! v ) return;
				viewer = v;
				const s = view.querySelector( '.loading' );
				if ( s ) s.remove();
				window.__catwalk = window.__catwalk || {};
				window.__catwalk.bodyView = v;

			} ).catch( ( err ) => {

				if ( ! ctx.live ) return;
				clear( view ).append( notice( 'error', 'Your body could not be shown', err instanceof NetworkError ? err.message : 'Its 3D file did not load.', { label: 'Try again', onClick: () => start() } ) );

			} );

		} else {

			view.classList.add( 'stage--none' );
			view.append( notice( 'warn', 'No 3D in this browser', NO_WEBGL_MESSAGE ) );

		}

		showAllAdvice( body, page.querySelector( '.advice-all' ) );

	}

	async function showAllAdvice( body, section ) {

		try {

			if ( ! hasSizesRoute( await apiPaths() ) ) return;
			const garments = await listGarments( { signal: ctx.signal } );
			const list = section.querySelector( '.advice-all__list' );
			const rows = await Promise.all( garments.map( async ( g ) => [ g, adviceSummary( await getSizeAdvice( g.id, body.id, { signal: ctx.signal } ).catch( () => null ) ) ] ) );
			if ( ! ctx.live ) return;
			const table = h( 'table', { class: 'table' },
				h( 'thead', {}, h( 'tr', {}, h( 'th', { scope: 'col' }, 'Garment' ), h( 'th', { scope: 'col' }, 'Your size' ), h( 'th', { scope: 'col' }, 'Fit' ) ) ),
				h( 'tbody', {} ),
			);
			let any = false;
			for ( const [ g, s ] of rows ) {

				if ( ! s ) continue;
				any = true;
				const rec = s.sizes.find( ( x ) => x.size === s.recommended );
				table.tBodies[ 0 ].append( h( 'tr', {},
					h( 'th', { scope: 'row' }, h( 'a', { href: urls.garment( g.id ), 'data-link': '' }, shortName( g.name ) ) ),
					h( 'td', { class: 'size-cell' }, s.recommended || '—' ),
					h( 'td', {}, rec ? ( s.recommendedFits ? rec.text : `closest: ${ rec.text }` ) : 'no size advice' ),
				) );

			}

			if ( ! any ) return;
			list.append( table );
			section.hidden = false;

		} catch {

			// advice is optional: say nothing when it cannot be had

		}

	}

	function confirmDelete( body, area, button ) {

		button.hidden = true;
		const status = h( 'p', { class: 'field__error', 'aria-live': 'assertive' } );
		const yes = h( 'button', { type: 'button', class: 'button button--danger' }, 'Delete it' );
		const no = h( 'button', { type: 'button', class: 'button button--secondary' }, 'Keep it' );
		const box = h( 'div', { class: 'confirm', role: 'alertdialog', 'aria-label': 'Delete your body?' },
			h( 'p', {}, 'This deletes your body, your scan if you sent one, and every try-on made from it. It cannot be undone.' ),
			h( 'div', { class: 'confirm__actions' }, yes, no ),
			status,
		);
		no.addEventListener( 'click', () => {

			box.remove();
			button.hidden = false;
			button.focus();

		} );
		yes.addEventListener( 'click', async () => {

			yes.disabled = true;
			yes.textContent = 'Deleting…';
			try {

				await deleteBody( body.id );

			} catch ( err ) {

				if ( ! ( err instanceof ApiError && err.status === 404 ) ) {

					yes.disabled = false;
					yes.textContent = 'Delete it';
					status.textContent = err.message;
					return;

				}

			}

			forgetBody();
			if ( ctx.live ) start( notice( 'info', 'Your body has been deleted', 'Nothing of it is kept on our servers.' ) );

		} );
		area.append( box );
		yes.focus();

	}

	start();

}

function girthTable( body ) {

	const sent = body.measurements || {};
	const made = body.model_measurements || {};
	const firstHead = body.source === 'scan' ? 'Measured on your scan' : 'You told us';
	const rows = GIRTHS.filter( ( [ k ] ) => k in made || k in sent );
	return h( 'table', { class: 'table girths' },
		h( 'caption', {}, 'Measurements' ),
		h( 'thead', {}, h( 'tr', {}, h( 'th', { scope: 'col' }, '' ), h( 'th', { scope: 'col' }, firstHead ), h( 'th', { scope: 'col' }, 'Your 3D body' ) ) ),
		h( 'tbody', {}, rows.map( ( [ k, label ] ) => h( 'tr', {},
			h( 'th', { scope: 'row' }, label ),
			h( 'td', {}, k in sent ? formatCm( sent[ k ] ) : '—' ),
			h( 'td', {}, k in made ? formatCm( made[ k ] ) : '—' ),
		) ) ),
	);

}

// --- the measurements form ---------------------------------------------------------------------

function measurementsForm( onBody, ctx ) {

	const form = h( 'form', { class: 'panel measure-form', novalidate: true, 'aria-labelledby': 'measure-title' } );
	const errors = {};
	const inputs = {};
	const touched = new Set();

	const sexId = nextId( 'sex' );
	const sexError = h( 'p', { class: 'field__error', id: `${ sexId }-err`, 'aria-live': 'polite' } );
	errors.sex = sexError;
	const sexGroup = h( 'fieldset', { class: 'field segmented-field' }, h( 'legend', {}, 'Body shape' ),
		h( 'div', { class: 'segmented' },
			[ [ 'female', 'Female' ], [ 'male', 'Male' ] ].map( ( [ v, label ], i ) => {

				const id = `${ sexId }-${ v }`;
				return h( 'span', { class: 'segmented__item' },
					h( 'input', { type: 'radio', name: 'sex', id, value: v, checked: i === 0 } ),
					h( 'label', { for: id }, label ) );

			} ),
		),
		sexError,
	);

	const fields = FIELDS.map( ( key ) => {

		const id = nextId( key );
		const [ lo, hi ] = rangeCm( key );
		const err = h( 'p', { class: 'field__error', id: `${ id }-err`, 'aria-live': 'polite' } );
		const input = h( 'input', {
			id, name: key, type: 'text', inputmode: 'decimal', autocomplete: 'off', spellcheck: false,
			placeholder: `${ lo }–${ hi }`, 'aria-describedby': `${ id }-hint ${ id }-err`,
		} );
		inputs[ key ] = input;
		errors[ key ] = err;
		const check = ( force ) => {

			const r = checkMeasurement( key, input.value, { required: force } );
			const show = ! r.ok && ( force || touched.has( key ) || input.value.trim() !== '' );
			err.textContent = show ? r.message : '';
			input.setAttribute( 'aria-invalid', String( show ) );
			return r.ok;

		};

		input.addEventListener( 'input', () => check( false ) );
		input.addEventListener( 'blur', () => {

			if ( input.value.trim() !== '' ) touched.add( key );
			check( false );

		} );
		return h( 'div', { class: 'field' },
			h( 'label', { for: id }, LABELS[ key ] ),
			h( 'div', { class: 'input-unit' }, input, h( 'span', { class: 'input-unit__unit', 'aria-hidden': 'true' }, 'cm' ) ),
			h( 'p', { class: 'field__hint', id: `${ id }-hint` }, `${ HINTS[ key ] } ${ lo }–${ hi } cm.` ),
			err,
		);

	} );

	const formError = h( 'div', { 'aria-live': 'assertive' } );
	const submit = h( 'button', { type: 'submit', class: 'button button--primary button--wide' }, 'Make my body' );
	form.append(
		h( 'h2', { id: 'measure-title' }, 'Type your measurements' ),
		h( 'p', { class: 'muted' }, 'A tape measure and two minutes. Measure over underwear, tape snug but not tight.' ),
		sexGroup,
		h( 'div', { class: 'measure-grid' }, fields ),
		formError,
		submit,
	);

	form.addEventListener( 'submit', async ( e ) => {

		e.preventDefault();
		clear( formError );
		const values = { sex: ( form.querySelector( 'input[name=sex]:checked' ) || {} ).value };
		for ( const k of FIELDS ) values[ k ] = inputs[ k ].value;
		const checked = checkForm( values );
		for ( const k of Object.keys( errors ) ) {

			errors[ k ].textContent = checked.errors[ k ] || '';
			if ( inputs[ k ] ) inputs[ k ].setAttribute( 'aria-invalid', String( !! checked.errors[ k ] ) );

		}

		if ( ! checked.ok ) {

			const first = FIELDS.find( ( k ) => checked.errors[ k ] );
			if ( first ) inputs[ first ].focus();
			return;

		}

		submit.disabled = true;
		submit.replaceChildren( h( 'span', { class: 'spinner spinner--small', 'aria-hidden': 'true' } ), 'Making your body…' );
		try {

			const body = await createBody( checked.body, { signal: ctx.signal } );
			onBody( body );

		} catch ( err ) {

			if ( ! ctx.live ) return;
			submit.disabled = false;
			submit.textContent = 'Make my body';
			if ( err instanceof ApiError && err.field && errors[ err.field ] ) {

				errors[ err.field ].textContent = err.message;
				if ( inputs[ err.field ] ) {

					inputs[ err.field ].setAttribute( 'aria-invalid', 'true' );
					inputs[ err.field ].focus();

				}

			} else {

				formError.append( errorNotice( err ) );

			}

		}

	} );
	return form;

}

// --- the scan upload ---------------------------------------------------------------------------

function scanForm( onBody, ctx ) {

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

	let upload = null;
	ctx.onCleanup( () => upload && upload.abort() );

	const busy = ( on ) => {

		zone.classList.toggle( 'dropzone--busy', on );
		file.disabled = on;
		sex.disabled = on;

	};

	async function send( f ) {

		clear( scanError );
		clear( status );
		sexError.textContent = '';
		const ext = ( f.name.split( '.' ).pop() || '' ).toLowerCase();
		if ( f.name.includes( '.' ) && ! SCAN_TYPES.includes( ext ) ) {

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

	}

	file.addEventListener( 'change', () => {

		if ( file.files && file.files[ 0 ] ) send( file.files[ 0 ] );

	} );
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
	return form;

}
