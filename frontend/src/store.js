// What the browser remembers: the shopper's body id (localStorage), nothing else.

const KEY = 'catwalk.body';
const listeners = new Set();

function storage() {

	try {

		return window.localStorage;

	} catch {

		return null; // storage disabled: the body lasts as long as the page

	}

}

let memory = null;

export function getBodyId() {

	const s = storage();
	if ( ! s ) return memory;
	try {

		return s.getItem( KEY );

	} catch {

		return memory;

	}

}

export function setBodyId( id ) {

	memory = id;
	const s = storage();
	try {

		if ( s ) {

			if ( id ) s.setItem( KEY, id );
			else s.removeItem( KEY );

		}

	} catch { /* private mode: memory only */ }

	for ( const fn of listeners ) fn( id );

}

export const forgetBody = () => setBodyId( null );

export function onBodyChange( fn ) {

	listeners.add( fn );
	return () => listeners.delete( fn );

}
