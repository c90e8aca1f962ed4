// Client-side routes on location.pathname: one index.html, links use history.pushState.
//
//   /                       catalogue (?type= filters)
//   /garments/{id}          a garment
//   /body                   your body
//   /tryon/{id}             a try-on (progress, then the player; ?compress=0 plays the plain file)
//   /compare?a={id}&b={id}  two try-ons side by side
//   /merchant               merchants: their garments, the garment editor (an API key)

function decode( part ) {

	try {

		return decodeURIComponent( part );

	} catch {

		return null;

	}

}

/** The route a URL names: `{ name, ...params }`; `name` is `notfound` for anything else. */
export function parseRoute( pathname, search = '' ) {

	const query = new URLSearchParams( search );
	let path = pathname || '/';
	if ( path.length > 1 ) path = path.replace( /\/+$/, '' ); // "/body/" is "/body"
	const parts = path.split( '/' ).filter( Boolean ).map( decode );
	if ( parts.some( ( p ) => p === null || p === '' ) ) return { name: 'notfound', path };

	if ( parts.length === 0 ) return { name: 'catalogue', type: query.get( 'type' ) || null };
	if ( parts.length === 1 && parts[ 0 ] === 'body' ) return { name: 'body' };
	if ( parts.length === 1 && parts[ 0 ] === 'merchant' ) return { name: 'merchant' };
	if ( parts.length === 2 && parts[ 0 ] === 'garments' ) return { name: 'garment', id: parts[ 1 ] };
	if ( parts.length === 2 && parts[ 0 ] === 'tryon' ) {

		return { name: 'tryon', id: parts[ 1 ], compress: query.get( 'compress' ) !== '0' };

	}

	if ( parts.length === 1 && parts[ 0 ] === 'compare' ) {

		const a = query.get( 'a' );
		const b = query.get( 'b' );
		if ( a && b ) return { name: 'compare', a, b };
		return { name: 'notfound', path, reason: 'compare needs two try-ons: /compare?a=…&b=…' };

	}

	return { name: 'notfound', path };

}

/** URLs of the pages. */
export const urls = {
	catalogue: ( type = null ) => ( type ? `/?type=${ encodeURIComponent( type ) }` : '/' ),
	garment: ( id ) => `/garments/${ encodeURIComponent( id ) }`,
	body: () => '/body',
	tryon: ( id, { compress = true } = {} ) => `/tryon/${ encodeURIComponent( id ) }${ compress ? '' : '?compress=0' }`,
	compare: ( a, b ) => `/compare?a=${ encodeURIComponent( a ) }&b=${ encodeURIComponent( b ) }`,
	merchant: () => '/merchant',
};

/** Whether a click on this anchor is one the router should take (same origin, plain left click). */
export function isRouterClick( event, anchor, origin ) {

	if ( ! anchor || event.defaultPrevented || event.button !== 0 ) return false;
	if ( event.metaKey || event.ctrlKey || event.shiftKey || event.altKey ) return false;
	if ( anchor.target && anchor.target !== '_self' ) return false;
	if ( anchor.hasAttribute( 'download' ) ) return false;
	let url;
	try {

		url = new URL( anchor.href, origin );

	} catch {

		return false;

	}

	if ( url.origin !== origin ) return false;
	if ( url.pathname.startsWith( '/api/' ) || url.pathname === '/docs' ) return false;
	return true;

}

let onChange = null;

/** Go to `url` inside the app (pushState, or replaceState with `replace`). */
export function navigate( url, { replace = false } = {} ) {

	if ( replace ) history.replaceState( null, '', url );
	else history.pushState( null, '', url );
	if ( onChange ) onChange( { scroll: ! replace } );

}

/** Start routing: `render(route)` now and on every navigation. */
export function startRouter( render ) {

	const current = () => parseRoute( location.pathname, location.search );
	onChange = ( { scroll = true } = {} ) => {

		render( current() );
		if ( scroll ) window.scrollTo( 0, 0 );

	};

	document.addEventListener( 'click', ( event ) => {

		const anchor = event.target.closest ? event.target.closest( 'a[href]' ) : null;
		if ( ! isRouterClick( event, anchor, location.origin ) ) return;
		event.preventDefault();
		const url = new URL( anchor.href, location.origin );
		if ( url.pathname + url.search === location.pathname + location.search ) return;
		navigate( url.pathname + url.search + url.hash );

	} );
	window.addEventListener( 'popstate', () => onChange( { scroll: false } ) );
	render( current() );

}
