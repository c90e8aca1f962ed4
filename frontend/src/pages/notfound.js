// Anything else.

import { h } from '../ui/dom.js';
import { urls } from '../router.js';

export function render( root, route ) {

	document.title = 'Not found — catwalk';
	root.append( h( 'section', { class: 'page-narrow' },
		h( 'h1', {}, 'This page isn’t here' ),
		h( 'p', { class: 'lead' }, route.reason || 'The link may be old, or mistyped.' ),
		h( 'p', {}, h( 'a', { class: 'button', href: urls.catalogue(), 'data-link': '' }, 'Go to the catalogue' ) ),
	) );

}
