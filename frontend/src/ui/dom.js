// A small element builder: h('div', { class: 'x', onclick }, child, 'text', [more]).

export function h( tag, attrs = {}, ...children ) {

	const el = document.createElement( tag );
	for ( const [ k, v ] of Object.entries( attrs || {} ) ) {

		if ( v === null || v === undefined || v === false ) continue;
		if ( k === 'class' ) el.className = v;
		else if ( k === 'dataset' ) Object.assign( el.dataset, v );
		else if ( k === 'style' && typeof v === 'object' ) Object.assign( el.style, v );
		else if ( k.startsWith( 'on' ) && typeof v === 'function' ) el.addEventListener( k.slice( 2 ), v );
		else if ( k === 'html' ) el.innerHTML = v; // only ever our own static SVG
		else if ( v === true ) el.setAttribute( k, '' );
		else if ( k in el && ! k.includes( '-' ) && k !== 'list' && k !== 'form' ) el[ k ] = v;
		else el.setAttribute( k, v );

	}

	append( el, children );
	return el;

}

export function append( el, children ) {

	for ( const c of children.flat( Infinity ) ) {

		if ( c === null || c === undefined || c === false ) continue;
		el.appendChild( c instanceof Node ? c : document.createTextNode( String( c ) ) );

	}

	return el;

}

export function clear( el ) {

	while ( el.firstChild ) el.removeChild( el.firstChild );
	return el;

}

let uid = 0;
export const nextId = ( prefix = 'id' ) => `${ prefix }-${ ++ uid }`;

/** Inline icons (decorative: the buttons carry their own labels). */
export const ICONS = {
	play: '<svg viewBox="0 0 24 24" aria-hidden="true"><path d="M8 5.5v13l10.5-6.5z" fill="currentColor"/></svg>',
	pause: '<svg viewBox="0 0 24 24" aria-hidden="true"><path d="M7 5h3.5v14H7zM13.5 5H17v14h-3.5z" fill="currentColor"/></svg>',
	download: '<svg viewBox="0 0 24 24" aria-hidden="true"><path d="M12 4v10m0 0-4-4m4 4 4-4M5 19h14" fill="none" stroke="currentColor" stroke-width="2" stroke-linecap="round" stroke-linejoin="round"/></svg>',
	upload: '<svg viewBox="0 0 24 24" aria-hidden="true"><path d="M12 16V5m0 0L8 9m4-4 4 4M5 19h14" fill="none" stroke="currentColor" stroke-width="2" stroke-linecap="round" stroke-linejoin="round"/></svg>',
	back: '<svg viewBox="0 0 24 24" aria-hidden="true"><path d="M15 5l-7 7 7 7" fill="none" stroke="currentColor" stroke-width="2" stroke-linecap="round" stroke-linejoin="round"/></svg>',
};

export function icon( name ) {

	return h( 'span', { class: 'icon', html: ICONS[ name ] } );

}
