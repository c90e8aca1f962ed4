// The merchant editor's operations on a garment's JSON (docs/garment-format.md), as the
// backend's catwalk.garment.edit does them: move, rotate (about the centre of the panel's
// bounding box, all sizes together) and mirror a panel in every size, renumbering what refers
// to a mirrored panel's vertices (seams, the fold edge, anchor vertices of it and its copies) so
// the garment sews the same way; panel names, sizes, grain lines, folds; and the seams' sides
// as the pattern view shows them (mirrored copies and the mirrored halves of folded panels).
//
// The functions change the garment they are given (as the backend's do); nothing here touches
// the DOM.

import {
	flatten, bounds, mod, transformShape, transformPoint, moveMatrix, rotateMatrix, mirrorMatrix, determinant,
	segmentLengths, runLength, isStraightEdge,
} from './geometry.js';

// catwalk.garment.model
export const GARMENT_TYPES = [ 'dress', 'tshirt', 'shirt', 'blouse', 'top', 'bodice', 'skirt', 'trousers', 'shorts', 'jacket', 'coat', 'hoodie', 'jumpsuit', 'other' ];
export const PANEL_TYPES = [ 'front', 'back', 'sleeve', 'collar', 'cuff', 'waistband', 'skirt', 'leg', 'yoke', 'pocket', 'facing', 'hood', 'placket', 'neckband', 'other' ];
export const BODY_PARTS = [ 'torso', 'left_arm', 'right_arm', 'left_leg', 'right_leg', 'legs' ];
export const SIDES = [ 'front', 'back', 'left', 'right' ];
// catwalk.body.measure's landmarks (placement anchors)
export const LANDMARKS = [ 'neck_base', 'neck_side_left', 'neck_side_right', 'shoulder_left', 'shoulder_right', 'armpit_left', 'armpit_right', 'bust', 'underbust', 'waist', 'hips', 'crotch', 'elbow_left', 'elbow_right', 'wrist_left', 'wrist_right', 'knee_left', 'knee_right', 'ankle_left', 'ankle_right' ];
// catwalk.garment.check: seam partners within 2 % of each other's length, or the seam's ease
export const SEAM_LENGTH_TOLERANCE = 0.02;

export function findPanel( g, name ) {

	const p = g.panels.find( ( q ) => q.name === name );
	if ( ! p ) throw new Error( `no panel named ${ JSON.stringify( name ) }` );
	return p;

}

/** [the panel whose vertex numbers a seam on `panel` uses, whether they are mirrored]. */
export function sourceVertexMap( g, panel ) {

	const p = typeof panel === 'string' ? findPanel( g, panel ) : panel;
	if ( p.copy_of == null ) return [ p.name, false ];
	const [ base, mir ] = sourceVertexMap( g, p.copy_of );
	return [ base, mir !== Boolean( p.mirror ) ];

}

/** The panel's shape in `size` as the cutter sees it (a copy's comes from its source, mirrored x → −x). */
export function panelShape( g, panel, size ) {

	const p = typeof panel === 'string' ? findPanel( g, panel ) : panel;
	if ( p.copy_of != null ) {

		const src = panelShape( g, p.copy_of, size );
		return p.mirror ? transformShape( src, mirrorMatrix( 'x' ) ) : src;

	}

	const sh = p.shapes && p.shapes[ size ];
	if ( ! sh ) throw new Error( `panel ${ JSON.stringify( p.name ) } has no outline for size ${ JSON.stringify( size ) }` );
	return sh;

}

/** The fold edge of the panel as shown (a mirrored copy's is renumbered), or null. */
export function displayFold( g, panel ) {

	const p = typeof panel === 'string' ? findPanel( g, panel ) : panel;
	const base = findPanel( g, sourceVertexMap( g, p )[ 0 ] );
	const fold = p.fold ?? base.fold;
	if ( fold == null ) return null;
	const n = vertexCount( g, base );
	return sourceVertexMap( g, p )[ 1 ] ? mod( - fold - 1, n ) : fold;

}

export function vertexCount( g, panel ) {

	const p = typeof panel === 'string' ? findPanel( g, panel ) : panel;
	const base = findPanel( g, sourceVertexMap( g, p )[ 0 ] );
	return base.shapes[ panelSizes( g, base )[ 0 ] ].outline.length;

}

/** The sizes the panel is cut in, in grading order (a panel of some sizes only, such as a pocket of the larger ones, has outlines in those; a copy follows its source). */
export function panelSizes( g, panel ) {

	const p = typeof panel === 'string' ? findPanel( g, panel ) : panel;
	const base = findPanel( g, sourceVertexMap( g, p )[ 0 ] );
	return g.sizes.filter( ( s ) => base.shapes && base.shapes[ s ] );

}

/** What importing the panel's piece repaired or assumed (`meta.import_warnings`: { code, message, size? }; a copy: its source's). */
export function importWarnings( g, panel ) {

	const p = typeof panel === 'string' ? findPanel( g, panel ) : panel;
	const base = findPanel( g, sourceVertexMap( g, p )[ 0 ] );
	const list = base.meta && base.meta.import_warnings;
	return Array.isArray( list ) ? list.filter( ( w ) => w && typeof w.message === 'string' ) : [];

}

/** The centre of the panel's bounding box over every size (outlines flattened within 1 mm). */
export function panelCentre( panel ) {

	const pts = [];
	for ( const sh of Object.values( panel.shapes ) ) for ( const p of flatten( sh.outline, 1e-3 ).points ) pts.push( p );
	const { min, max } = bounds( pts );
	return [ 0.5 * ( min[ 0 ] + max[ 0 ] ), 0.5 * ( min[ 1 ] + max[ 1 ] ) ];

}

/** Apply the 2×3 affine `matrix` to panel `name` in every size (catwalk.garment.edit.transform_panel). */
export function transformPanel( g, name, matrix ) {

	const p = findPanel( g, name );
	if ( p.copy_of != null ) throw new Error( `panel ${ JSON.stringify( name ) } is a copy of ${ JSON.stringify( p.copy_of ) }: edit ${ JSON.stringify( p.copy_of ) }` );
	const reflect = determinant( matrix ) < 0;
	const n = Object.values( p.shapes )[ 0 ].outline.length;
	for ( const s of Object.keys( p.shapes ) ) p.shapes[ s ] = transformShape( p.shapes[ s ], matrix );
	const users = new Set( [ p.name ] );
	for ( const q of g.panels ) if ( sourceVertexMap( g, q )[ 0 ] === p.name ) users.add( q.name );
	// a placement's anchor point is in the panel's pattern coordinates
	for ( const q of g.panels ) {

		if ( users.has( q.name ) && q.placement && q.placement.anchor_point != null ) q.placement.anchor_point = transformPoint( q.placement.anchor_point, matrix );

	}

	if ( ! reflect ) return g;
	// vertex v → (−v) mod n for the panel and every copy that uses its numbering
	if ( p.fold != null ) p.fold = mod( - p.fold - 1, n );
	for ( const q of g.panels ) {

		if ( users.has( q.name ) && q.placement && q.placement.anchor_vertex != null ) q.placement.anchor_vertex = mod( - q.placement.anchor_vertex, n );

	}

	for ( const s of g.seams || [] ) {

		let flip = false;
		for ( const side of [ s.a, s.b ] ) {

			if ( users.has( side.panel ) ) {

				const start = side.start;
				side.start = mod( - side.end, n );
				side.end = mod( - start, n );
				flip = ! flip;

			}

		}

		if ( flip ) s.reverse = ! s.reverse;

	}

	return g;

}

/**
 * The editor's geometric operations on one panel (catwalk.garment.edit.edit): mirror ("x":
 * left ↔ right, "y": up ↔ down) and rotate (degrees, counter-clockwise) about the centre of the
 * panel's bounding box, then move by [dx, dy] metres.
 */
export function editPanel( g, name, { move = null, rotate = null, mirror = null } = {} ) {

	const p = findPanel( g, name );
	if ( p.copy_of != null ) throw new Error( `panel ${ JSON.stringify( name ) } is a copy of ${ JSON.stringify( p.copy_of ) }: edit ${ JSON.stringify( p.copy_of ) }` );
	if ( mirror != null ) {

		if ( mirror !== 'x' && mirror !== 'y' ) throw new Error( `mirror ${ JSON.stringify( mirror ) }: use x (left ↔ right) or y (up ↔ down)` );
		const c = panelCentre( p );
		transformPanel( g, name, mirrorMatrix( mirror, mirror === 'x' ? c[ 0 ] : c[ 1 ] ) );

	}

	if ( rotate ) transformPanel( g, name, rotateMatrix( Number( rotate ), panelCentre( p ) ) );
	if ( move != null ) transformPanel( g, name, moveMatrix( Number( move[ 0 ] ), Number( move[ 1 ] ) ) );
	return g;

}

/** Rename a panel and every reference to it (seams, copies). */
export function renamePanel( g, from, to ) {

	to = String( to ).trim();
	if ( ! to ) throw new Error( 'a panel needs a name' );
	if ( to.length > 200 ) throw new Error( 'a panel name has at most 200 characters' );
	if ( to === from ) return g;
	if ( g.panels.some( ( q ) => q.name === to ) ) throw new Error( `there is a panel named ${ JSON.stringify( to ) } already` );
	findPanel( g, from ).name = to;
	for ( const q of g.panels ) if ( q.copy_of === from ) q.copy_of = to;
	for ( const s of g.seams || [] ) for ( const side of [ s.a, s.b ] ) if ( side.panel === from ) side.panel = to;
	return g;

}

/** Remove a panel, its copies and the seams that use them. Returns the names removed. */
export function removePanel( g, name ) {

	findPanel( g, name );
	const gone = new Set( [ name ] );
	let grew = true;
	while ( grew ) {

		grew = false;
		for ( const q of g.panels ) {

			if ( q.copy_of != null && gone.has( q.copy_of ) && ! gone.has( q.name ) ) {

				gone.add( q.name );
				grew = true;

			}

		}

	}

	g.panels = g.panels.filter( ( q ) => ! gone.has( q.name ) );
	g.seams = ( g.seams || [] ).filter( ( s ) => ! gone.has( s.a.panel ) && ! gone.has( s.b.panel ) );
	return [ ...gone ];

}

/** Lay the panels (those with shapes) side by side along +x, `gap` metres apart, bottoms on y = 0; mirrored copies follow as images across x = 0. */
export function layoutPanels( g, gap = 0.05 ) {

	let x = gap;
	for ( const p of g.panels ) {

		if ( p.copy_of != null ) continue;
		const pts = [];
		for ( const sh of Object.values( p.shapes ) ) for ( const q of flatten( sh.outline, 1e-3 ).points ) pts.push( q );
		const { min, max } = bounds( pts );
		const dx = x - min[ 0 ], dy = - min[ 1 ];
		if ( Math.abs( dx ) > 1e-9 || Math.abs( dy ) > 1e-9 ) transformPanel( g, p.name, moveMatrix( dx, dy ) );
		x += max[ 0 ] - min[ 0 ] + gap;

	}

	return g;

}

/** Grain direction in degrees from +y, counter-clockwise positive (0 when the shape has none: warp along +y). */
export function grainAngle( shape ) {

	if ( ! shape.grain ) return 0;
	const [ a, b ] = shape.grain;
	const dx = b[ 0 ] - a[ 0 ], dy = b[ 1 ] - a[ 1 ];
	if ( dx === 0 && dy === 0 ) return 0;
	return ( Math.atan2( - dx, dy ) * 180 ) / Math.PI;

}

/** Set the grain line of every size: through the centre of the shape, `degrees` from +y (counter-clockwise), 40 % of its height long. */
export function setGrainAngle( panel, degrees ) {

	const a = ( Number( degrees ) * Math.PI ) / 180;
	const d = [ - Math.sin( a ), Math.cos( a ) ];
	for ( const sh of Object.values( panel.shapes ) ) {

		const { min, max } = bounds( flatten( sh.outline, 1e-3 ).points );
		const c = [ 0.5 * ( min[ 0 ] + max[ 0 ] ), 0.5 * ( min[ 1 ] + max[ 1 ] ) ];
		const half = Math.max( 0.025, 0.2 * ( max[ 1 ] - min[ 1 ] ) );
		const r = ( v ) => Math.round( v * 1e6 ) / 1e6;
		sh.grain = [ [ r( c[ 0 ] - half * d[ 0 ] ), r( c[ 1 ] - half * d[ 1 ] ) ], [ r( c[ 0 ] + half * d[ 0 ] ), r( c[ 1 ] + half * d[ 1 ] ) ] ];

	}

	return panel;

}

/** The straight edges of a panel (fold candidates) in `size` (or in its first size, when it is not cut in that one). */
export function straightEdges( panel, size ) {

	const outline = ( panel.shapes[ size ] || Object.values( panel.shapes )[ 0 ] ).outline;
	return outline.map( ( _, k ) => k ).filter( ( k ) => isStraightEdge( outline, k ) );

}

/** Cut the panel on the fold along edge `k` (null: not on fold). */
export function setFold( panel, k ) {

	if ( k == null || k === '' ) delete panel.fold;
	else panel.fold = Number( k );
	return panel;

}

/** Rename size `from` everywhere (panel shapes, default size, fit). */
export function renameSize( g, from, to ) {

	to = String( to ).trim();
	if ( ! to ) throw new Error( 'a size needs a name' );
	if ( to.length > 200 ) throw new Error( 'a size name has at most 200 characters' );
	if ( to === from ) return g;
	if ( g.sizes.includes( to ) ) throw new Error( `there is a size ${ JSON.stringify( to ) } already` );
	const i = g.sizes.indexOf( from );
	if ( i < 0 ) throw new Error( `no size ${ JSON.stringify( from ) }` );
	g.sizes[ i ] = to;
	for ( const p of g.panels ) {

		if ( ! p.shapes || ! ( from in p.shapes ) ) continue;
		const shapes = {};
		for ( const [ k, v ] of Object.entries( p.shapes ) ) shapes[ k === from ? to : k ] = v;
		p.shapes = shapes;

	}

	if ( g.default_size === from ) g.default_size = to;
	if ( g.fit && from in g.fit ) {

		g.fit[ to ] = g.fit[ from ];
		delete g.fit[ from ];

	}

	return g;

}

/** Remove a size (not the last one, nor the only size of a piece). */
export function removeSize( g, size ) {

	if ( g.sizes.length <= 1 ) throw new Error( 'a garment needs at least one size' );
	if ( ! g.sizes.includes( size ) ) throw new Error( `no size ${ JSON.stringify( size ) }` );
	const only = g.panels.filter( ( p ) => p.copy_of == null && p.shapes && p.shapes[ size ] && panelSizes( g, p ).length === 1 );
	if ( only.length ) throw new Error( `size ${ size } is the only size of ${ only.map( ( p ) => p.name ).join( ', ' ) }: remove ${ only.length === 1 ? 'that piece' : 'those pieces' } first` );
	g.sizes = g.sizes.filter( ( s ) => s !== size );
	for ( const p of g.panels ) if ( p.shapes ) delete p.shapes[ size ];
	if ( g.default_size === size ) g.default_size = g.sizes[ Math.floor( g.sizes.length / 2 ) ];
	if ( g.fit ) delete g.fit[ size ];
	return g;

}

/** Move a size one place earlier (-1) or later (+1) in the grading order. */
export function moveSize( g, size, by ) {

	const i = g.sizes.indexOf( size );
	const j = i + by;
	if ( i < 0 || j < 0 || j >= g.sizes.length ) return g;
	[ g.sizes[ i ], g.sizes[ j ] ] = [ g.sizes[ j ], g.sizes[ i ] ];
	return g;

}

/** A texture path for a panel's image: textures/<panel>.<png|jpg> (as the server's file names allow). */
export function texturePath( panelName, file = null ) {

	// the server takes letters, digits, '.', '_', '-', starting with a letter or digit
	const slug = String( panelName ).toLowerCase().replace( /[^a-z0-9_-]+/g, '-' ).replace( /^[^a-z0-9]+|[-_]+$/g, '' ).slice( 0, 90 ) || 'panel';
	const type = file && file.type ? file.type : '';
	const name = file && file.name ? file.name.toLowerCase() : '';
	const ext = type === 'image/jpeg' || /\.jpe?g$/.test( name ) ? 'jpg' : 'png';
	return `textures/${ slug }.${ ext }`;

}

// --- seams: sides as the pattern view shows them ----------------------------------------------------
//
// The view shows each panel as cut: a mirrored copy as its source's image (its vertex i is the
// image of the source's vertex −i), a panel cut on the fold as its stored half plus the mirrored
// half (the "ghost"; ghost vertex v is the image of stored vertex v across the fold line). A
// side picked there — first vertex p1, then p2, the run going forward along the cut piece's
// outline (counter-clockwise) — is stored in the source's numbering, forward from `start` to
// `end`; on a mirrored copy or on the mirrored half the stored run walks the shown one
// backwards, so the side is "flipped" and the seam's stored `reverse` is the shown pairing's
// XOR the sides' flips (as catwalk.garment.model.side_vertices and cut_pieces undo it).

/** Whether the side's stored run walks the shown one backwards. */
export function sideFlipped( g, side ) {

	return sourceVertexMap( g, side.panel )[ 1 ] !== ( side.half === 'mirror' );

}

/** The side picked on the view: vertices p1 → p2 of panel `panel` as shown (on its mirrored half when `ghost`). */
export function sideFromPicks( g, panel, p1, p2, ghost = false ) {

	const n = vertexCount( g, panel );
	const mirrored = sourceVertexMap( g, panel )[ 1 ];
	const stored = ( v ) => ( mirrored ? mod( - v, n ) : mod( v, n ) );
	const side = { panel, start: stored( p1 ), end: stored( p2 ) };
	if ( ghost ) side.half = 'mirror';
	if ( mirrored !== ghost ) [ side.start, side.end ] = [ side.end, side.start ];
	return side;

}

/** The side as shown: { panel, first, last, ghost } — the run goes from vertex `first` to `last` along the shown piece (`first` is where the seam starts). */
export function sideAsShown( g, side ) {

	const n = vertexCount( g, side.panel );
	const mirrored = sourceVertexMap( g, side.panel )[ 1 ];
	const ghost = side.half === 'mirror';
	const shown = ( v ) => ( mirrored ? mod( - v, n ) : mod( v, n ) );
	let first = shown( side.start ), last = shown( side.end );
	if ( mirrored !== ghost ) [ first, last ] = [ last, first ];
	return { panel: side.panel, first, last, ghost };

}

/** The run as vertex numbers of the shown half, forward from `start` to `end` (the ghost's run is the image of this one). */
export function shownRun( g, side ) {

	const n = vertexCount( g, side.panel );
	const mirrored = sourceVertexMap( g, side.panel )[ 1 ];
	return mirrored ? { start: mod( - side.end, n ), end: mod( - side.start, n ) } : { start: side.start, end: side.end };

}

/** The seam's stored `reverse` for a shown pairing (`shownReverse`: a's first vertex meets b's last). */
export function storedReverse( g, a, b, shownReverse ) {

	return Boolean( shownReverse ) !== sideFlipped( g, a ) !== sideFlipped( g, b );

}

/** Whether, as shown, a's first vertex meets b's last (the seam's `reverse` in the view's terms). */
export function shownReverse( g, seam ) {

	return Boolean( seam.reverse ) !== sideFlipped( g, seam.a ) !== sideFlipped( g, seam.b );

}

/** Length (metres) of a side's run in `size`, along the outline (curves included). */
export function sideLength( g, side, size ) {

	const base = findPanel( g, sourceVertexMap( g, side.panel )[ 0 ] );
	return runLength( segmentLengths( base.shapes[ size ].outline ), side.start, side.end );

}

/** { a, b, difference, limit, ok }: the two runs' lengths (m) in `size` and their relative difference, as the checker measures them. */
export function seamLengths( g, seam, size ) {

	const a = sideLength( g, seam.a, size );
	const b = sideLength( g, seam.b, size );
	const difference = Math.abs( a - b ) / Math.max( a, b );
	const limit = Math.max( SEAM_LENGTH_TOLERANCE, Number( seam.ease ) || 0 );
	return { a, b, difference, limit, ok: difference <= limit };

}

/** Whether the side's run crosses its panel's fold edge (the checker refuses that). */
export function runCrossesFold( g, side ) {

	const base = findPanel( g, sourceVertexMap( g, side.panel )[ 0 ] );
	if ( base.fold == null ) return false;
	const n = vertexCount( g, base );
	const k = mod( side.end - side.start, n );
	for ( let t = 0; t < k; t ++ ) if ( mod( side.start + t, n ) === base.fold ) return true;
	return false;

}

/** The stored edge `edge` of `panel` as numbered on the shown piece (mirrored copies walk the other way). */
export function shownEdge( g, panel, edge ) {

	const n = vertexCount( g, panel );
	return sourceVertexMap( g, panel )[ 1 ] ? mod( - edge - 1, n ) : edge;

}

/** A deep copy of a garment JSON. */
export const cloneGarment = ( g ) => JSON.parse( JSON.stringify( g ) );
