// The seam being sewn: the vertices picked on the pattern or by number (a run on one piece,
// then the run on the piece it is sewn to), the two sides they make, and the seam they add.

import { sideFromPicks, storedReverse } from './garment-edit.js';

/** A vertex clicked on the pattern (in seam mode): the first or last end of a run. */
export function pickVertex( state, panel, vertex, ghost ) {

	if ( state.mode !== 'seam' ) return;
	if ( state.picks.length >= 4 ) state.picks = [];
	const picks = state.picks;
	if ( picks.length === 1 || picks.length === 3 ) {

		const first = picks[ picks.length - 1 ];
		if ( first.panel !== panel || first.ghost !== ghost ) {

			// a run is on one piece (and one half of it): start again there
			state.picks = picks.slice( 0, picks.length - 1 );

		} else if ( first.vertex === vertex ) {

			state.set( { picks: picks.slice( 0, picks.length - 1 ) } );
			return;

		}

	}

	state.picks.push( { panel, vertex, ghost } );
	state.refresh( { garment: false } );

}

/** A run chosen by numbers as side `i` (0: the first, 2: the second), keeping the other side. */
export function pickRun( state, i, panel, from, to, ghost ) {

	const picks = state.picks;
	const next = picks.slice( 0, i );
	while ( next.length < i ) next.push( null );
	next[ i ] = { panel, vertex: from, ghost };
	next[ i + 1 ] = { panel, vertex: to, ghost };
	if ( i === 0 && picks.length === 4 ) next.push( picks[ 2 ], picks[ 3 ] );
	state.set( { picks: next.filter( Boolean ) } );

}

/** The sides picked so far: `{ a, b }`, each a side (`{ panel, start, end }`) or null. */
export function draftSides( state ) {

	const { g, picks } = state;
	const side = ( i ) => ( picks.length >= i + 2 ? sideFromPicks( g, picks[ i ].panel, picks[ i ].vertex, picks[ i + 1 ].vertex, picks[ i ].ghost ) : null );
	return { a: side( 0 ), b: side( 2 ) };

}

/** Side `i`'s run the other way round (its last vertex first). */
export function otherWay( state, i ) {

	const picks = state.picks;
	[ picks[ i ], picks[ i + 1 ] ] = [ picks[ i + 1 ], picks[ i ] ];
	state.refresh( { garment: false } );

}

/** The seam of the two sides picked, with the draft's name, ease and direction, added to the garment. */
export function addSeam( state ) {

	const { a, b } = draftSides( state );
	if ( ! a || ! b ) return;
	const draft = state.draft;
	const seam = { a, b, reverse: storedReverse( state.g, a, b, draft.reverse ) };
	if ( draft.name.trim() ) seam.name = draft.name.trim();
	if ( draft.ease ) seam.ease = Math.round( draft.ease * 1e4 ) / 1e4;
	if ( state.mutate( () => state.g.seams.push( seam ) ) ) {

		state.set( { picks: [], draft: { reverse: false, ease: 0, name: '' }, highlight: state.g.seams.length - 1 } );

	}

}
