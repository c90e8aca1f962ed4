// Words and numbers for a merchant garment's versions and their dressing (each size dressed
// on its sample body after every save). No DOM.

export const BUSY = new Set( [ 'queued', 'running' ] );

/** The version entry of `item` numbered `version` (default: its latest), or null. */
export function versionOf( item, version = null ) {

	const versions = ( item && item.versions ) || [];
	const want = version == null ? item && item.version : version;
	return versions.find( ( v ) => v.version === want ) || ( version == null ? versions[ versions.length - 1 ] : null ) || null;

}

/** { kind: busy | ok | failed | none, text } for one size's dressing entry. */
export function sizeStatus( entry ) {

	const status = entry && entry.status;
	if ( status === 'queued' ) return { kind: 'busy', text: 'Queued…' };
	if ( status === 'running' ) return { kind: 'busy', text: 'Dressing…' };
	if ( status === 'dressed' ) {

		if ( entry.ok === false ) return { kind: 'warn', text: entry.message ? `Dressed: ${ entry.message }` : 'Dressed, with problems' };
		return { kind: 'ok', text: 'Dressed' };

	}

	if ( status === 'failed' ) return { kind: 'failed', text: entry.message || 'Failed' };
	if ( ! status ) return { kind: 'none', text: 'Not dressed' };
	return { kind: 'none', text: String( status ) };

}

/** Whether any size of the item's latest version is still queued or being dressed. */
export function isBusy( item ) {

	const v = versionOf( item );
	if ( ! v || ! v.dressing ) return false;
	return Object.values( v.dressing ).some( ( e ) => e && BUSY.has( e.status ) );

}

export const anyBusy = ( items ) => items.some( isBusy );

const mm = ( x ) => `${ Number( x ).toFixed( 1 ) } mm`;
const pct = ( x ) => `${ ( Number( x ) * 100 ).toFixed( 1 ) } %`;
const num = ( x ) => typeof x === 'number' && Number.isFinite( x );

/** The dressing report's numbers as [label, text, good?] rows (what the entry has; good: null when unknown). */
export function reportRows( entry ) {

	if ( ! entry ) return [];
	const rows = [];
	const limits = entry.limits || {};
	const checks = entry.checks || {};
	const verdict = ( v ) => ( v === true || v === false ? v : null );
	if ( entry.sample ) rows.push( [ 'Sample body', String( entry.sample ), null ] );
	if ( num( entry.seam_gap_mm ) ) {

		const worst = entry.seam_gap_mm > 0 && entry.worst_seam != null && entry.worst_seam !== '' ? `, at ${ seamName( entry.worst_seam ) }` : '';
		const limit = num( limits.seam_gap_mm ) ? ` (limit ${ mm( limits.seam_gap_mm ) })` : '';
		rows.push( [ 'Widest seam gap', `${ mm( entry.seam_gap_mm ) }${ worst }${ limit }`, verdict( checks.seams_welded ) ] );

	} else if ( entry.worst_seam != null ) rows.push( [ 'Worst seam', seamName( entry.worst_seam ), null ] );
	if ( num( entry.max_penetration_mm ) ) {

		const limit = num( limits.penetration_mm ) ? ` (limit ${ mm( limits.penetration_mm ) })` : '';
		rows.push( [ 'Deepest into the body', `${ mm( entry.max_penetration_mm ) }${ limit }`, verdict( checks.no_penetration ) ] );

	}

	if ( num( entry.max_strain ) ) {

		const limit = num( entry.strain_limit ) ? entry.strain_limit : num( limits.strain ) ? limits.strain : null;
		const good = verdict( checks.strain_within_limit ) ?? ( limit == null ? null : entry.max_strain <= limit );
		rows.push( [ 'Largest stretch', limit == null ? pct( entry.max_strain ) : `${ pct( entry.max_strain ) } (fabric limit ${ pct( limit ) })`, good ] );

	}

	if ( entry.message ) rows.push( [ entry.status === 'failed' ? 'Problem' : 'Note', String( entry.message ), entry.status === 'failed' || entry.ok === false ? false : null ] );
	return rows;

}

/** Whether the size has a dressed .glb to show (a failed size may have one too). */
export function hasDressed( entry ) {

	return Boolean( entry && ( entry.status === 'dressed' || ( entry.status === 'failed' && entry.glb_url ) ) );

}

function seamName( s ) {

	return typeof s === 'number' ? `seam ${ s }` : String( s );

}

/** "v3" / "v3 (published)" style words for the list. */
export function publishedText( item ) {

	return item.published_version == null ? 'Not published' : `Version ${ item.published_version }`;

}
