// The merchant's garments: name, id, latest and published version, and each size's dressing
// (polled every 2 s while a size is queued or being dressed); "Open" and a DXF import; the
// try-on on the merchant's own shop (its publishable key and origins: shop-panel.js).

import { h, clear, nextId, icon } from '../ui/dom.js';
import { spinner, errorNotice, notice } from '../ui/feedback.js';
import { typeName } from '../format.js';
import { urls } from '../router.js';
import { listGarments, importDxf, isUnauthorised } from './api.js';
import { versionOf, sizeStatus, anyBusy, publishedText } from './status.js';
import { shopPanel } from './shop-panel.js';

export function createList( { signal, onOpen, onImported, onUnauthorised, onLogout } ) {

	const tableBox = h( 'div', { class: 'mp-list', 'aria-live': 'polite', 'aria-busy': 'true' }, spinner( 'Loading your garments…' ) );
	const importBox = importForm( { signal, onImported, onUnauthorised } );
	const el = h( 'div', { class: 'merchant-list' },
		h( 'div', { class: 'mp-head' },
			h( 'div', {}, h( 'p', { class: 'eyebrow' }, 'Merchants' ), h( 'h1', {}, 'Your garments' ) ),
			h( 'button', { type: 'button', class: 'button button--secondary', onclick: onLogout }, 'Log out' ),
		),
		importBox,
		h( 'section', { 'aria-labelledby': 'mp-list-title' }, h( 'h2', { id: 'mp-list-title' }, 'Saved garments' ), tableBox ),
		shopPanel( { signal, onUnauthorised } ),
	);
	let timer = null;
	signal.addEventListener( 'abort', () => clearTimeout( timer ), { once: true } );

	async function load( first = false ) {

		try {

			const items = await listGarments( { signal } );
			if ( signal.aborted ) return;
			showGarments( tableBox, items, onOpen );
			if ( anyBusy( items ) ) timer = setTimeout( load, 2000 );

		} catch ( err ) {

			if ( err && err.name === 'AbortError' ) return;
			if ( isUnauthorised( err ) ) return onUnauthorised();
			if ( first ) clear( tableBox ).append( errorNotice( err, () => load( true ) ) );
			else timer = setTimeout( load, 2000 ); // a blip while polling: try again

		}

	}

	load( true );
	return { el, notice: ( kind, title, text, action = null ) => el.insertBefore( notice( kind, title, text, action ), importBox ) };

}

/** "Import a pattern (DXF)": the file and its units; `onImported(res, fileName)` with what the import read. */
function importForm( { signal, onImported, onUnauthorised } ) {

	const file = h( 'input', { type: 'file', id: nextId( 'dxf' ), accept: '.dxf,application/dxf,image/vnd.dxf', required: true } );
	const units = h( 'select', { id: nextId( 'units' ) },
		h( 'option', { value: '' }, 'As the file says' ),
		h( 'option', { value: 'mm' }, 'Millimetres' ),
		h( 'option', { value: 'cm' }, 'Centimetres' ),
		h( 'option', { value: 'm' }, 'Metres' ),
		h( 'option', { value: 'in' }, 'Inches' ),
	);
	const status = h( 'div', { class: 'mp-import__status', 'aria-live': 'polite' } );
	const submit = h( 'button', { type: 'submit', class: 'button button--primary' }, icon( 'upload' ), 'Import' );
	const form = h( 'form', { class: 'panel mp-import-form', novalidate: true },
		h( 'h2', {}, 'Import a pattern (DXF)' ),
		h( 'p', { class: 'muted small' }, 'An AAMA/ASTM DXF as Gerber, Lectra or CLO export it (one block per piece and size), or a plain DXF of closed polylines.' ),
		h( 'div', { class: 'field-row--2' },
			h( 'div', { class: 'field' }, h( 'label', { for: file.id }, 'DXF file' ), file ),
			h( 'div', { class: 'field' }, h( 'label', { for: units.id }, 'Units' ), units ),
		),
		h( 'div', { class: 'mp-actions' }, submit ),
		status,
	);
	form.addEventListener( 'submit', async ( e ) => {

		e.preventDefault();
		const f = file.files && file.files[ 0 ];
		if ( ! f ) {

			clear( status ).append( h( 'p', { class: 'field__error' }, 'Choose a DXF file first.' ) );
			file.focus();
			return;

		}

		submit.disabled = true;
		clear( status ).append( spinner( 'Reading the pattern…' ) );
		try {

			const res = await importDxf( f, { units: units.value, signal } );
			if ( signal.aborted ) return;
			onImported( res, f.name );

		} catch ( err ) {

			if ( err && err.name === 'AbortError' ) return;
			if ( isUnauthorised( err ) ) return onUnauthorised();
			clear( status ).append( errorNotice( err ) );
			submit.disabled = false;

		}

	} );
	return form;

}

/** The garments `items` into `box`: a row each, "Open" calling `onOpen(id)`. */
function showGarments( box, items, onOpen ) {

	box.setAttribute( 'aria-busy', 'false' );
	clear( box );
	if ( ! items.length ) {

		box.append( h( 'p', { class: 'empty' }, 'No garments yet: import a DXF above to make the first.' ) );
		return;

	}

	box.append( h( 'div', { class: 'mp-table-wrap' }, h( 'table', { class: 'table mp-garments' },
		h( 'thead', {}, h( 'tr', {}, [ 'Garment', 'Id', 'Latest version', 'Published', 'Dressing (latest version)', '' ].map( ( t, i ) => h( 'th', { scope: 'col' }, i === 5 ? h( 'span', { class: 'visually-hidden' }, 'Actions' ) : t ) ) ) ),
		h( 'tbody', {}, items.map( ( it ) => garmentRow( it, onOpen ) ) ),
	) ) );

}

function garmentRow( it, onOpen ) {

	return h( 'tr', { 'data-id': it.id },
		h( 'th', { scope: 'row' }, it.name, h( 'br' ), h( 'span', { class: 'muted small' }, typeName( it.type || 'other' ) ) ),
		h( 'td', {}, h( 'code', {}, it.id ) ),
		h( 'td', {}, String( it.version ?? '—' ) ),
		h( 'td', {}, it.published_version == null ? publishedText( it ) : h( 'a', { href: urls.garment( it.id ), 'data-link': '' }, publishedText( it ) ) ),
		dressingCell( it ),
		h( 'td', {}, h( 'button', { type: 'button', class: 'button button--secondary button--small', 'aria-label': `Open ${ it.name }`, onclick: () => onOpen( it.id ) }, 'Open' ) ),
	);

}

/** Each size of the latest version: a dot (or a spinner) and its dressing status. */
function dressingCell( item ) {

	const v = versionOf( item );
	if ( ! v || ! v.dressing || ! Object.keys( v.dressing ).length ) return h( 'td', { class: 'muted' }, '—' );
	const ul = h( 'ul', { class: 'mp-dressing' } );
	for ( const size of item.sizes || Object.keys( v.dressing ) ) {

		const st = sizeStatus( v.dressing[ size ] );
		ul.append( h( 'li', { class: `mp-dressing__${ st.kind }`, 'data-size': size, 'data-status': ( v.dressing[ size ] && v.dressing[ size ].status ) || 'none' },
			st.kind === 'busy' ? h( 'span', { class: 'spinner spinner--tiny', 'aria-hidden': 'true' } ) : h( 'span', { class: `mp-dot mp-dot--${ st.kind }`, 'aria-hidden': 'true' } ),
			h( 'strong', {}, size ), ' ', st.text ) );

	}

	return h( 'td', {}, ul );

}
