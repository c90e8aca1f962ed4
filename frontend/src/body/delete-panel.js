// "Delete my body": asks first (what goes with it, that it cannot be undone), then deletes the
// body (DELETE /api/bodies/{id}) and forgets it in this browser; a body already gone counts as
// deleted.

import { deleteBody, ApiError } from '../api.js';
import { h } from '../ui/dom.js';
import { forgetBody } from '../store.js';

/** The danger zone of the body page; `onDeleted()` once the body is deleted and forgotten (while the page is shown). */
export function createDeletePanel( body, ctx, onDeleted ) {

	const area = h( 'div', { class: 'danger-zone' } );
	const button = h( 'button', { type: 'button', class: 'button button--danger' }, 'Delete my body' );
	button.addEventListener( 'click', () => confirmDelete( body, { area, button }, () => {

		forgetBody();
		if ( ctx.live ) onDeleted();

	} ) );
	area.append( button );
	return area;

}

function confirmDelete( body, { area, button }, deleted ) {

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

		deleted();

	} );
	area.append( box );
	yes.focus();

}
