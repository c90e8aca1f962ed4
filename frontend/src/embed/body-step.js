// The component's body step: the shopper's measurements or a 3D scan, the same forms as
// catwalk's own body page (body/measurements-form.js, body/scan-form.js), one shown at a time.

import { h, nextId } from '../ui/dom.js';
import { measurementsForm } from '../body/measurements-form.js';
import { scanForm } from '../body/scan-form.js';

/** The step: `onBody(body)` once a body is made from either form. */
export function bodyStep( onBody, ctx, note = null ) {

	const tabs = [ [ 'measure', 'My measurements', measurementsForm ], [ 'scan', 'A 3D scan', scanForm ] ];
	const group = nextId( 'bodytabs' );
	const panes = {};
	const buttons = tabs.map( ( [ name, label, form ], i ) => {

		const pane = h( 'div', { class: 'cw-pane', role: 'tabpanel', id: `${ group }-${ name }`, hidden: i !== 0 }, form( onBody, ctx ) );
		panes[ name ] = pane;
		return h( 'button', { type: 'button', class: 'seg', role: 'tab', 'aria-selected': String( i === 0 ), 'aria-controls': pane.id, 'data-tab': name }, label );

	} );
	for ( const b of buttons ) {

		b.addEventListener( 'click', () => {

			for ( const o of buttons ) {

				o.setAttribute( 'aria-selected', String( o === b ) );
				panes[ o.dataset.tab ].hidden = o !== b;

			}

		} );

	}

	return h( 'div', { class: 'cw-body' },
		note,
		h( 'p', { class: 'cw-lead' }, 'Your body, once: it is kept for this shop only, and you can delete it at any time.' ),
		h( 'div', { class: 'segs cw-tabs', role: 'tablist', 'aria-label': 'How to give your body' }, buttons ),
		Object.values( panes ),
	);

}
