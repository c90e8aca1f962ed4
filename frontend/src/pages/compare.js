// Compare (/compare?a=…&b=…): two try-ons side by side on one clock.

import { getGarment } from '../api.js';
import { urls } from '../router.js';
import { h, icon } from '../ui/dom.js';
import { fabricName, shortName } from '../format.js';
import { mountTryon } from '../player/tryon-view.js';
import { startSession } from '../player/session.js';
import { startLoop } from '../viewer/loop.js';

export function render( root, route, ctx ) {

	document.title = 'Compare — catwalk';
	const title = h( 'h1', {}, 'Side by side' );
	const crumbs = h( 'p', { class: 'crumbs' }, h( 'a', { href: urls.catalogue(), 'data-link': '' }, icon( 'back' ), 'Catalogue' ) );
	const ids = [ route.a, route.b ];
	const heads = ids.map( () => h( 'h2', { class: 'compare__label' }, '…' ) );
	const boxes = ids.map( ( id ) => h( 'div', { class: 'tryon-box', 'data-tryon': id } ) );
	const controlsBox = h( 'div', { class: 'tryon-controls' } );
	const wrap = h( 'div', { class: 'player player--compare', tabindex: '-1' },
		h( 'div', { class: 'compare' }, ids.map( ( id, k ) => h( 'section', { class: 'compare__side', 'aria-label': `Try-on ${ k + 1 }` },
			h( 'div', { class: 'compare__head' }, heads[ k ], h( 'a', { class: 'small', href: urls.tryon( id ), 'data-link': '' }, 'Open alone' ) ),
			boxes[ k ],
		) ) ),
		controlsBox,
	);
	root.append( crumbs, h( 'header', { class: 'tryon-head' }, title, h( 'p', { class: 'muted' }, 'Both walks play on one clock: pause, scrub and change speed for both at once.' ) ), wrap );

	const ready = [ null, null ];
	let session = null;
	let named = false;
	ctx.onCleanup( () => session && session.dispose() );

	ids.forEach( ( id, k ) => {

		mountTryon( boxes[ k ], id, {
			ctx,
			label: `Try-on ${ k + 1 }`,
			onInfo: async ( t ) => {

				heads[ k ].textContent = `Size ${ t.size }${ t.fabric ? `, ${ fabricName( t.fabric ) }` : '' }`;
				if ( ! named && t.garment_id ) {

					named = true;
					crumbs.replaceChildren( h( 'a', { href: urls.garment( t.garment_id ), 'data-link': '' }, icon( 'back' ), 'The garment' ) );
					try {

						const g = await getGarment( t.garment_id, { signal: ctx.signal } );
						if ( ctx.live ) {

							title.textContent = `${ shortName( g.name ) }, side by side`;
							document.title = `${ shortName( g.name ) }: compare — catwalk`;

						}

					} catch { /* keep the generic title */ }

				}

			},
			onReady: ( player, stage ) => {

				// until the other one is ready too, this one stands still (and can be turned)
				const waiting = startLoop( () => stage.render() );
				ready[ k ] = { player, stage, waiting };
				ctx.onCleanup( waiting );
				if ( ready.every( Boolean ) && ! session && ctx.live ) {

					for ( const r of ready ) r.waiting();

					const fps = ( ready[ 0 ].player.tryon.metrics && ready[ 0 ].player.tryon.metrics.fps ) || ready[ 0 ].player.fps;
					session = startSession( {
						players: ready.map( ( r ) => r.player ),
						stages: ready.map( ( r ) => r.stage ),
						controlsBox,
						keyTarget: wrap,
						fps,
					} );

				}

			},
		} );

	} );

}
