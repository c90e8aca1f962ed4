// The pattern pieces in 2D (SVG), to scale on a centimetre grid, with pan and zoom: drag a
// piece to move it, drag the background to pan, the wheel (or + / −) to zoom; in seam mode,
// click vertices. Draws a scene from scene.js; reports what the person did through callbacks.

import { h } from '../ui/dom.js';

const SVGNS = 'http://www.w3.org/2000/svg';
const PX_PER_CM = 96 / 2.54; // CSS pixels in a centimetre ("actual size")

function s( tag, attrs = {}, ...children ) {

	const el = document.createElementNS( SVGNS, tag );
	for ( const [ k, v ] of Object.entries( attrs ) ) {

		if ( v === null || v === undefined || v === false ) continue;
		el.setAttribute( k, v === true ? '' : String( v ) );

	}

	for ( const c of children.flat() ) if ( c ) el.appendChild( c instanceof Node ? c : document.createTextNode( String( c ) ) );
	return el;

}

const f = ( x ) => Math.round( x * 100 ) / 100;

export class PatternView {

	/**
	 * `onSelect(name | null)`, `onMove(name, dx, dy)` (metres), `onVertex(panel, vertex, ghost)`,
	 * `onNudge(dx, dy)` (arrow keys on a selected piece, metres).
	 */
	constructor( { label = 'Pattern pieces', onSelect = () => {}, onMove = () => {}, onVertex = () => {}, onNudge = () => {} } = {} ) {

		this.cb = { onSelect, onMove, onVertex, onNudge };
		this.scale = 200; // px per metre (2 px a centimetre)
		this.centre = [ 0.5, 0.4 ];
		this.scene = null;
		this.state = {};
		this.fitted = false;
		this.svg = s( 'svg', { class: 'pattern-view__svg', tabindex: '0', role: 'application', 'aria-roledescription': 'pattern editor', 'aria-label': label } );
		const zoomIn = h( 'button', { type: 'button', class: 'seg', 'aria-label': 'Zoom in', onclick: () => this.zoom( 1.25 ) }, '+' );
		const zoomOut = h( 'button', { type: 'button', class: 'seg', 'aria-label': 'Zoom out', onclick: () => this.zoom( 0.8 ) }, '−' );
		const fit = h( 'button', { type: 'button', class: 'seg', onclick: () => this.fit() }, 'Fit' );
		const actual = h( 'button', { type: 'button', class: 'seg', title: '1 cm on the pattern is 1 cm on the screen', onclick: () => this.actualSize() }, '1:1' );
		this.scaleText = h( 'span', { class: 'pattern-view__scale muted small', 'aria-live': 'polite' } );
		this.el = h( 'div', { class: 'pattern-view' },
			this.svg,
			h( 'div', { class: 'pattern-view__tools' }, h( 'div', { class: 'segs', role: 'group', 'aria-label': 'Zoom' }, zoomOut, zoomIn, fit, actual ), this.scaleText ),
		);
		this.listen();
		this.resizeObserver = new ResizeObserver( () => this.draw() );
		this.resizeObserver.observe( this.svg );

	}

	dispose() {

		this.resizeObserver.disconnect();
		this.el.remove();

	}

	get size() {

		const r = this.svg.getBoundingClientRect();
		return [ Math.max( 1, r.width ), Math.max( 1, r.height ) ];

	}

	/** World metres → SVG px. */
	toScreen( p ) {

		const [ w, hgt ] = this.size;
		return [ ( p[ 0 ] - this.centre[ 0 ] ) * this.scale + w / 2, - ( p[ 1 ] - this.centre[ 1 ] ) * this.scale + hgt / 2 ];

	}

	/** Client px → world metres. */
	toWorld( clientX, clientY ) {

		const r = this.svg.getBoundingClientRect();
		return [ ( clientX - r.left - r.width / 2 ) / this.scale + this.centre[ 0 ], - ( clientY - r.top - r.height / 2 ) / this.scale + this.centre[ 1 ] ];

	}

	/** Show `scene` with `state`: { selected, mode: edit | seam, picks, draft, problems, highlight, textures }. */
	update( scene, state = {} ) {

		this.scene = scene;
		this.state = state;
		if ( ! this.fitted && scene && scene.order.length ) {

			const [ w ] = this.size;
			if ( w > 1 ) {

				this.fitted = true;
				this.fit();
				return;

			}

		}

		this.draw();

	}

	zoom( by, about = null ) {

		const next = Math.min( 20000, Math.max( 20, this.scale * by ) );
		if ( about ) {

			// keep the world point under the pointer where it is
			const k = this.scale / next;
			this.centre = [ about[ 0 ] + ( this.centre[ 0 ] - about[ 0 ] ) * k, about[ 1 ] + ( this.centre[ 1 ] - about[ 1 ] ) * k ];

		}

		this.scale = next;
		this.draw();

	}

	actualSize() {

		this.scale = PX_PER_CM * 100;
		this.draw();

	}

	/** Every piece in view. */
	fit() {

		const box = this.sceneBounds();
		if ( ! box ) return;
		const [ w, hgt ] = this.size;
		const bw = Math.max( 0.05, box.max[ 0 ] - box.min[ 0 ] ), bh = Math.max( 0.05, box.max[ 1 ] - box.min[ 1 ] );
		this.scale = Math.min( 20000, Math.max( 20, 0.88 * Math.min( w / bw, hgt / bh ) ) );
		this.centre = [ ( box.min[ 0 ] + box.max[ 0 ] ) / 2, ( box.min[ 1 ] + box.max[ 1 ] ) / 2 ];
		this.draw();

	}

	sceneBounds() {

		if ( ! this.scene ) return null;
		const min = [ Infinity, Infinity ], max = [ - Infinity, - Infinity ];
		for ( const name of this.scene.order ) {

			const piece = this.scene.pieces[ name ];
			for ( const pts of [ piece.points, piece.ghost || [] ] ) {

				for ( const p of pts ) {

					min[ 0 ] = Math.min( min[ 0 ], p[ 0 ] );
					min[ 1 ] = Math.min( min[ 1 ], p[ 1 ] );
					max[ 0 ] = Math.max( max[ 0 ], p[ 0 ] );
					max[ 1 ] = Math.max( max[ 1 ], p[ 1 ] );

				}

			}

		}

		return Number.isFinite( min[ 0 ] ) ? { min, max } : null;

	}

	path( points, closed = true ) {

		if ( ! points.length ) return '';
		const parts = points.map( ( p, i ) => {

			const [ x, y ] = this.toScreen( p );
			return `${ i ? 'L' : 'M' }${ f( x ) } ${ f( y ) }`;

		} );
		return parts.join( '' ) + ( closed ? 'Z' : '' );

	}

	// --- drawing ------------------------------------------------------------------------------

	draw() {

		const svg = this.svg;
		while ( svg.firstChild ) svg.removeChild( svg.firstChild );
		const [ w, hgt ] = this.size;
		svg.setAttribute( 'viewBox', `0 0 ${ f( w ) } ${ f( hgt ) }` );
		const cmPx = this.scale / 100;
		this.scaleText.textContent = `1 cm = ${ cmPx.toFixed( 1 ) } px · grid: ${ cmPx >= 6 ? '1 cm and 10 cm' : cmPx * 10 >= 6 ? '10 cm' : '1 m' }`;
		const defs = s( 'defs', {},
			s( 'marker', { id: 'pv-arrow', viewBox: '0 0 10 10', refX: '9', refY: '5', markerWidth: '7', markerHeight: '7', orient: 'auto-start-reverse' },
				s( 'path', { d: 'M0 0L10 5L0 10z', class: 'pv-arrowhead' } ) ),
		);
		svg.append( defs, this.grid( w, hgt ) );
		if ( ! this.scene ) return;
		const st = this.state;
		const textures = st.textures || new Map();
		const problems = st.problems || { panels: new Set(), edges: [] };
		const pieces = s( 'g', { class: 'pv-pieces' } );
		const overlay = s( 'g', { class: 'pv-overlay' } );
		const seamMode = st.mode === 'seam';
		for ( const name of this.scene.order ) {

			const selected = st.selected === name;
			const piece = this.scene.pieces[ name ];
			pieces.append( this.pieceGroup( name, { selected, defs, texture: textures.get( name ), problem: problems.panels.has( name ) } ) );
			if ( seamMode || selected ) this.vertices( overlay, piece, false, selected );
			if ( seamMode && piece.ghost ) this.vertices( overlay, piece, true, false );

		}

		svg.append( pieces );
		svg.append( this.seamLines( seamMode ) );
		if ( st.draft ) {

			for ( const run of st.draft.runs || [] ) svg.append( s( 'path', { class: 'pv-draft', d: this.path( run, false ) } ) );
			for ( const [ p, q ] of st.draft.links || [] ) svg.append( s( 'path', { class: 'pv-link pv-link--draft', d: this.path( [ p, q ], false ) } ) );

		}

		for ( const e of problems.edges ) svg.append( s( 'path', { class: 'pv-problem-edge', d: this.path( e.points, false ) } ) );
		svg.append( overlay );

	}

	/** The piece `name`: outline (filled with its `texture`), mirrored half, fold, grain line, name. */
	pieceGroup( name, { selected, defs, texture, problem } ) {

		const piece = this.scene.pieces[ name ];
		const cls = [ 'pv-piece', selected && 'is-selected', piece.isCopy && 'is-copy', problem && 'has-problem' ].filter( Boolean ).join( ' ' );
		const g = s( 'g', { class: cls, 'data-panel': name } );
		let fill = null;
		if ( texture && texture.url && piece.texture && piece.texture.size ) {

			const id = `pv-tex-${ this.scene.order.indexOf( name ) }`;
			const [ tw, th ] = piece.texture.size.map( ( x ) => Math.max( 1, x * this.scale ) );
			const [ ox, oy ] = this.toScreen( [ 0, 0 ] );
			defs.append( s( 'pattern', { id, patternUnits: 'userSpaceOnUse', x: f( ox ), y: f( oy - th ), width: f( tw ), height: f( th ) },
				s( 'image', { href: texture.url, x: 0, y: 0, width: f( tw ), height: f( th ), preserveAspectRatio: 'none' } ) ) );
			fill = `url(#${ id })`;

		}

		if ( piece.ghost ) g.append( s( 'path', { class: 'pv-ghost', d: this.path( piece.ghost ) } ) );
		g.append( s( 'path', { class: 'pv-outline', d: this.path( piece.points ), style: fill ? `fill:${ fill }` : null } ) );
		if ( piece.fold != null ) {

			const n = piece.outline.length;
			g.append( s( 'path', { class: 'pv-fold', d: this.path( [ piece.outline[ piece.fold ].start, piece.outline[ ( piece.fold + 1 ) % n ].start ], false ) } ) );

		}

		if ( piece.grain ) {

			const [ a, b ] = piece.grain.map( ( p ) => this.toScreen( p ) );
			g.append( s( 'line', { class: 'pv-grain', x1: f( a[ 0 ] ), y1: f( a[ 1 ] ), x2: f( b[ 0 ] ), y2: f( b[ 1 ] ), 'marker-end': 'url(#pv-arrow)', 'marker-start': 'url(#pv-arrow)' } ) );

		}

		const box = bbox( piece.points );
		const [ lx, ly ] = this.toScreen( [ ( box.min[ 0 ] + box.max[ 0 ] ) / 2, ( box.min[ 1 ] + box.max[ 1 ] ) / 2 ] );
		g.append( s( 'text', { class: 'pv-label', x: f( lx ), y: f( ly ), 'text-anchor': 'middle' }, name ) );
		return g;

	}

	/** The seams: runs in the seam's colour, dashed lines between the ends that meet (highlighted or in seam mode). */
	seamLines( seamMode ) {

		const st = this.state;
		const seams = s( 'g', { class: 'pv-seams' } );
		for ( const seam of this.scene.seams ) {

			const hl = st.highlight === seam.index;
			const cls = `pv-seam pv-seam--${ seam.index % 6 }${ hl ? ' is-highlighted' : '' }`;
			seams.append( s( 'path', { class: cls, d: this.path( seam.a, false ), 'data-seam': seam.index } ) );
			seams.append( s( 'path', { class: cls, d: this.path( seam.b, false ), 'data-seam': seam.index } ) );
			if ( hl || seamMode ) for ( const [ p, q ] of seam.links ) seams.append( s( 'path', { class: `pv-link pv-seam--${ seam.index % 6 }`, d: this.path( [ p, q ], false ) } ) );

		}

		return seams;

	}

	vertices( into, piece, ghost, numbered ) {

		const picks = this.state.picks || [];
		piece.outline.forEach( ( seg, v ) => {

			const p = ghost && piece.ghostMatrix ? apply( seg.start, piece.ghostMatrix ) : seg.start;
			const [ x, y ] = this.toScreen( p );
			const picked = picks.some( ( k ) => k.panel === piece.name && k.vertex === v && Boolean( k.ghost ) === ghost );
			into.append( s( 'circle', {
				class: `pv-vertex${ ghost ? ' pv-vertex--ghost' : '' }${ picked ? ' is-picked' : '' }`,
				cx: f( x ), cy: f( y ), r: picked ? 7 : 5,
				'data-panel': piece.name, 'data-vertex': v, 'data-ghost': ghost ? '1' : null,
			}, s( 'title', {}, `${ piece.name }${ ghost ? ' (mirrored half)' : '' }: vertex ${ v }` ) ) );
			if ( numbered ) into.append( s( 'text', { class: 'pv-vertex-label', x: f( x + 8 ), y: f( y - 6 ) }, String( v ) ) );

		} );

	}

	grid( w, hgt ) {

		const g = s( 'g', { class: 'pv-grid', 'aria-hidden': 'true' } );
		const a = this.toWorld( this.svg.getBoundingClientRect().left, this.svg.getBoundingClientRect().top );
		const [ x0, y1 ] = a;
		const x1 = x0 + w / this.scale, y0 = y1 - hgt / this.scale;
		const cm = this.scale / 100;
		const steps = [];
		if ( cm >= 6 ) steps.push( [ 0.01, 'pv-grid__minor' ] );
		if ( cm * 10 >= 6 ) steps.push( [ 0.1, 'pv-grid__major' ] );
		else steps.push( [ 1, 'pv-grid__major' ] );
		let d = {};
		for ( const [ step, cls ] of steps ) {

			d[ cls ] = '';
			for ( let i = Math.ceil( x0 / step ); i * step <= x1; i ++ ) {

				const x = f( this.toScreen( [ i * step, 0 ] )[ 0 ] );
				d[ cls ] += `M${ x } 0V${ f( hgt ) }`;

			}

			for ( let j = Math.ceil( y0 / step ); j * step <= y1; j ++ ) {

				const y = f( this.toScreen( [ 0, j * step ] )[ 1 ] );
				d[ cls ] += `M0 ${ y }H${ f( w ) }`;

			}

		}

		for ( const [ cls, path ] of Object.entries( d ) ) g.append( s( 'path', { class: cls, d: path } ) );
		const [ ox, oy ] = this.toScreen( [ 0, 0 ] );
		g.append( s( 'path', { class: 'pv-grid__axis', d: `M${ f( ox ) } 0V${ f( hgt ) }M0 ${ f( oy ) }H${ f( w ) }` } ) );
		// labels every 10 cm (or every metre when far out) along the top and left edges
		const step = cm * 10 >= 28 ? 0.1 : cm * 100 >= 28 ? 1 : null;
		if ( step ) {

			for ( let i = Math.ceil( x0 / step ); i * step <= x1; i ++ ) {

				const x = this.toScreen( [ i * step, 0 ] )[ 0 ];
				g.append( s( 'text', { class: 'pv-grid__label', x: f( x + 3 ), y: 12 }, `${ Math.round( i * step * 100 ) }` ) );

			}

			for ( let j = Math.ceil( y0 / step ); j * step <= y1; j ++ ) {

				const y = this.toScreen( [ 0, j * step ] )[ 1 ];
				g.append( s( 'text', { class: 'pv-grid__label', x: 3, y: f( y - 3 ) }, `${ Math.round( j * step * 100 ) }` ) );

			}

		}

		return g;

	}

	// --- input --------------------------------------------------------------------------------

	listen() {

		const svg = this.svg;
		this.drag = null; // { kind: pan | piece, x, y, name, moved, group, centre, deselect }
		svg.addEventListener( 'pointerdown', ( e ) => this.pointerDown( e ) );
		svg.addEventListener( 'pointermove', ( e ) => this.pointerMove( e ) );
		const end = ( e ) => this.pointerEnd( e );
		svg.addEventListener( 'pointerup', end );
		svg.addEventListener( 'pointercancel', end );
		svg.addEventListener( 'wheel', ( e ) => {

			e.preventDefault();
			this.zoom( Math.exp( - e.deltaY * 0.0015 ), this.toWorld( e.clientX, e.clientY ) );

		}, { passive: false } );
		svg.addEventListener( 'keydown', ( e ) => this.keyDown( e ) );

	}

	/** A vertex clicked (seam mode), or a drag starting: of a piece (edit mode), else of the background. */
	pointerDown( e ) {

		const svg = this.svg;
		if ( e.button !== 0 ) return;
		const vertex = e.target.closest && e.target.closest( '.pv-vertex' );
		if ( vertex && this.state.mode === 'seam' ) {

			e.preventDefault();
			this.cb.onVertex( vertex.dataset.panel, Number( vertex.dataset.vertex ), vertex.dataset.ghost === '1' );
			return;

		}

		const pieceEl = e.target.closest && e.target.closest( '.pv-piece' );
		svg.setPointerCapture( e.pointerId );
		if ( pieceEl && this.state.mode !== 'seam' ) {

			const name = pieceEl.dataset.panel;
			if ( this.state.selected !== name ) this.cb.onSelect( name );
			const group = svg.querySelector( `.pv-piece[data-panel="${ cssEscape( name ) }"]` );
			this.drag = { kind: this.scene.pieces[ name ] && ! this.scene.pieces[ name ].isCopy ? 'piece' : 'pan', x: e.clientX, y: e.clientY, name, moved: false, group };

		} else {

			this.drag = { kind: 'pan', x: e.clientX, y: e.clientY, moved: false, centre: this.centre.slice() };
			if ( ! pieceEl && this.state.mode !== 'seam' ) this.drag.deselect = true;

		}

	}

	/** Pan, or move the dragged piece's drawing (the piece itself moves when the drag ends). */
	pointerMove( e ) {

		const drag = this.drag;
		if ( ! drag ) return;
		const dx = e.clientX - drag.x, dy = e.clientY - drag.y;
		if ( ! drag.moved && Math.hypot( dx, dy ) < 3 ) return;
		drag.moved = true;
		if ( drag.kind === 'pan' ) {

			if ( ! drag.centre ) drag.centre = this.centre.slice();
			this.centre = [ drag.centre[ 0 ] - dx / this.scale, drag.centre[ 1 ] + dy / this.scale ];
			this.draw();

		} else {

			const group = this.svg.querySelector( `.pv-piece[data-panel="${ cssEscape( drag.name ) }"]` );
			if ( group ) group.setAttribute( 'transform', `translate(${ f( dx ) } ${ f( dy ) })` );
			this.svg.classList.add( 'is-dragging' );

		}

	}

	/** A drag ended (pointerup) or was cancelled: the piece moved, or a click on the background deselects. */
	pointerEnd( e ) {

		const svg = this.svg;
		if ( ! this.drag ) return;
		const d = this.drag;
		this.drag = null;
		svg.classList.remove( 'is-dragging' );
		if ( svg.hasPointerCapture( e.pointerId ) ) svg.releasePointerCapture( e.pointerId );
		if ( d.kind === 'piece' && d.moved && e.type === 'pointerup' ) {

			this.cb.onMove( d.name, ( e.clientX - d.x ) / this.scale, - ( e.clientY - d.y ) / this.scale );

		} else if ( d.kind === 'piece' && d.moved ) {

			this.draw();

		} else if ( d.deselect && ! d.moved ) {

			this.cb.onSelect( null );

		}

	}

	/** + − 0 zoom and fit; Escape deselects; the arrows nudge the selected piece, or pan. */
	keyDown( e ) {

		const arrows = { ArrowLeft: [ - 1, 0 ], ArrowRight: [ 1, 0 ], ArrowUp: [ 0, 1 ], ArrowDown: [ 0, - 1 ] };
		if ( e.key === '+' || e.key === '=' ) this.zoom( 1.25 );
		else if ( e.key === '-' ) this.zoom( 0.8 );
		else if ( e.key === '0' ) this.fit();
		else if ( e.key === 'Escape' ) this.cb.onSelect( null );
		else if ( arrows[ e.key ] ) {

			const [ ax, ay ] = arrows[ e.key ];
			const piece = this.state.selected && this.scene && this.scene.pieces[ this.state.selected ];
			if ( piece && ! piece.isCopy && this.state.mode !== 'seam' ) {

				const step = e.shiftKey ? 0.01 : 0.001; // 1 cm, or 1 mm
				this.cb.onNudge( ax * step, ay * step );

			} else {

				const step = 40 / this.scale;
				this.centre = [ this.centre[ 0 ] + ax * step, this.centre[ 1 ] + ay * step ];
				this.draw();

			}

		} else return;
		e.preventDefault();

	}

}

function apply( p, m ) {

	return [ m[ 0 ][ 0 ] * p[ 0 ] + m[ 0 ][ 1 ] * p[ 1 ] + m[ 0 ][ 2 ], m[ 1 ][ 0 ] * p[ 0 ] + m[ 1 ][ 1 ] * p[ 1 ] + m[ 1 ][ 2 ] ];

}

function bbox( points ) {

	const min = [ Infinity, Infinity ], max = [ - Infinity, - Infinity ];
	for ( const p of points ) {

		min[ 0 ] = Math.min( min[ 0 ], p[ 0 ] );
		min[ 1 ] = Math.min( min[ 1 ], p[ 1 ] );
		max[ 0 ] = Math.max( max[ 0 ], p[ 0 ] );
		max[ 1 ] = Math.max( max[ 1 ], p[ 1 ] );

	}

	return { min, max };

}

function cssEscape( s ) {

	return window.CSS && CSS.escape ? CSS.escape( s ) : String( s ).replace( /["\\]/g, '\\$&' );

}
