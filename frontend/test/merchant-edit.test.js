// The editor's garment operations against catwalk.garment.edit on the catalogue's pencil skirt
// (numbers from `edit(g, panel, mirror=…|rotate=…|move=…)` and garment_to_dict).
import { describe, it, expect } from 'vitest';
import { readFileSync } from 'node:fs';
import {
	editPanel, panelCentre, findPanel, renamePanel, removePanel, layoutPanels, grainAngle, setGrainAngle,
	renameSize, removeSize, moveSize, texturePath, sideFromPicks, sideAsShown, storedReverse, shownReverse,
	seamLengths, sideLength, runCrossesFold, shownEdge, panelShape, displayFold, straightEdges, setFold,
	PANEL_TYPES, GARMENT_TYPES, transformPanel, panelSizes, importWarnings, vertexCount,
} from '../src/merchant/garment-edit.js';
import { flatten, bounds } from '../src/merchant/geometry.js';
import { buildScene, sideEnds } from '../src/merchant/scene.js';

const skirt = () => JSON.parse( readFileSync( new URL( '../../garments/pencil-skirt.json', import.meta.url ), 'utf8' ) );
const close = ( a, b, digits = 6 ) => a.forEach( ( x, i ) => expect( x ).toBeCloseTo( b[ i ], digits ) );
const seamSides = ( g ) => g.seams.map( ( s ) => [ s.a.start, s.a.end, s.b.start, s.b.end, s.reverse ] );

describe( 'move, rotate, mirror as catwalk garment edit', () => {

	it( 'centres on the bounding box of every size', () => {

		const g = skirt();
		close( panelCentre( findPanel( g, 'back_right' ) ), [ 0.137295, - 0.3179685 ] );
		close( panelCentre( findPanel( g, 'front' ) ), [ 0.14385, - 0.3179685 ] );

	} );

	it( 'mirrors a panel left ↔ right: points, controls, vertex numbers and its copy’s seams', () => {

		const g = skirt();
		editPanel( g, 'back_right', { mirror: 'x' } );
		const out = findPanel( g, 'back_right' ).shapes.M.outline;
		expect( out[ 0 ].type ).toBe( 'cubic' );
		close( out[ 0 ].start, [ 0.27459, 0 ] );
		close( out[ 0 ].controls.flat(), [ 0.235774, 0, 0.167389, 0.000782 ] );
		close( out[ 1 ].start, [ 0.167213, 0.000801 ] );
		close( out[ 1 ].controls.flat(), [ 0.164346, - 0.025134, 0.156161, - 0.076979 ] );
		close( out[ 2 ].start, [ 0.152879, - 0.128876 ] );
		close( findPanel( g, 'back_right' ).shapes.M.grain.flat(), [ 0.27459, 0, 0.27459, 1 ] );
		// seams 4–10 as the backend renumbers them (back_left is a mirrored copy of back_right)
		expect( seamSides( g ).slice( 4 ) ).toEqual( [
			[ 5, 6, 4, 5, true ], [ 2, 3, 1, 2, true ], [ 5, 6, 4, 5, true ], [ 2, 3, 1, 2, true ],
			[ 2, 5, 7, 10, true ], [ 2, 5, 7, 10, true ], [ 15, 0, 15, 0, false ],
		] );
		expect( g.seams[ 9 ].a.half ).toBe( 'mirror' );
		expect( findPanel( g, 'back_left' ).placement.anchor_vertex ).toBe( 0 );
		// lengths are kept: the side seam's back run is still 0.66945 m
		expect( sideLength( g, g.seams[ 8 ].b, 'M' ) ).toBeCloseTo( 0.66945, 5 );

	} );

	it( 'mirrors a folded panel up ↔ down: its fold edge and darts renumbered', () => {

		const g = skirt();
		editPanel( g, 'front', { mirror: 'y' } );
		const p = findPanel( g, 'front' );
		expect( p.fold ).toBe( 11 );
		expect( seamSides( g ).slice( 0, 3 ) ).toEqual( [ [ 5, 6, 4, 5, true ], [ 2, 3, 1, 2, true ], [ 5, 6, 4, 5, true ] ] );
		close( p.shapes.M.outline[ 0 ].start, [ 0, - 0.635937 ] );
		close( p.shapes.M.outline[ 0 ].controls.flat(), [ 0.036899, - 0.635937, 0.102958, - 0.637078 ] );
		close( p.shapes.M.outline[ 1 ].start, [ 0.103125, - 0.637096 ] );
		// mirroring twice gives the garment back
		editPanel( g, 'front', { mirror: 'y' } );
		expect( seamSides( g ) ).toEqual( seamSides( skirt() ) );
		expect( findPanel( g, 'front' ).fold ).toBe( 0 );
		close( findPanel( g, 'front' ).shapes.S.outline[ 3 ].start, findPanel( skirt(), 'front' ).shapes.S.outline[ 3 ].start, 9 );

	} );

	it( 'rotates about the centre, then moves', () => {

		const g = skirt();
		editPanel( g, 'front', { rotate: 30, move: [ 0.1, - 0.05 ] } );
		const sh = findPanel( g, 'front' ).shapes.M;
		close( sh.outline[ 0 ].start, [ - 0.039712, - 0.164525 ] );
		close( sh.outline[ 1 ].start, [ 0.285719, - 0.728188 ] );
		close( sh.grain.flat(), [ - 0.039712, - 0.164525, - 0.539712, 0.701501 ] );
		expect( grainAngle( sh ) ).toBeCloseTo( 30, 9 );
		expect( seamSides( g ) ).toEqual( seamSides( skirt() ) ); // no renumbering

	} );

	it( 'refuses to move a copy', () => {

		expect( () => editPanel( skirt(), 'back_left', { move: [ 0.1, 0 ] } ) ).toThrow( /copy of "back_right"/ );

	} );

} );

describe( 'names, sizes, layout, grain, fold', () => {

	it( 'renames a panel everywhere and removes one with its copies and seams', () => {

		const g = skirt();
		renamePanel( g, 'back_right', 'back' );
		expect( findPanel( g, 'back_left' ).copy_of ).toBe( 'back' );
		expect( g.seams[ 10 ].a.panel ).toBe( 'back' );
		expect( () => renamePanel( g, 'back', 'front' ) ).toThrow( /already/ );
		expect( removePanel( g, 'back' ).sort() ).toEqual( [ 'back', 'back_left' ] );
		expect( g.panels.map( ( p ) => p.name ) ).toEqual( [ 'front' ] );
		expect( g.seams.map( ( s ) => s.name ) ).toEqual( [ 'front dart 1', 'front dart 2', 'front dart 1 (mirror)', 'front dart 2 (mirror)' ] );

	} );

	it( 'lays panels side by side, bottoms on y = 0, keeping seams', () => {

		const g = skirt();
		layoutPanels( g, 0.05 );
		const box = ( name ) => bounds( Object.values( findPanel( g, name ).shapes ).flatMap( ( s ) => flatten( s.outline ).points ) );
		const br = box( 'back_right' ), fr = box( 'front' );
		expect( br.min[ 0 ] ).toBeCloseTo( 0.05, 9 );
		expect( br.min[ 1 ] ).toBeCloseTo( 0, 9 );
		expect( fr.min[ 0 ] ).toBeCloseTo( br.max[ 0 ] + 0.05, 9 );
		expect( fr.min[ 1 ] ).toBeCloseTo( 0, 9 );
		expect( seamSides( g ) ).toEqual( seamSides( skirt() ) );

	} );

	it( 'sets the grain line of every size at an angle', () => {

		const p = findPanel( skirt(), 'front' );
		setGrainAngle( p, - 45 );
		for ( const sh of Object.values( p.shapes ) ) expect( grainAngle( sh ) ).toBeCloseTo( - 45, 3 );
		const [ a, b ] = p.shapes.M.grain;
		expect( b[ 0 ] - a[ 0 ] ).toBeGreaterThan( 0 ); // −45°: towards +x
		expect( grainAngle( { outline: [] } ) ).toBe( 0 );

	} );

	it( 'offers straight edges for the fold', () => {

		const p = findPanel( skirt(), 'front' );
		expect( straightEdges( p, 'M' ) ).toEqual( [ 0, 1 ] ); // the centre front (the fold) and the hem; the rest are cubic
		setFold( p, null );
		expect( 'fold' in p ).toBe( false );
		setFold( p, '4' );
		expect( p.fold ).toBe( 4 );

	} );

	it( 'renames, removes and reorders sizes', () => {

		const g = skirt();
		renameSize( g, 'M', 'Medium' );
		expect( g.sizes ).toEqual( [ 'S', 'Medium', 'L' ] );
		expect( g.default_size ).toBe( 'Medium' );
		expect( g.fit.Medium ).toBe( 'female-M' );
		expect( Object.keys( findPanel( g, 'front' ).shapes ) ).toEqual( [ 'S', 'Medium', 'L' ] );
		removeSize( g, 'Medium' );
		expect( g.sizes ).toEqual( [ 'S', 'L' ] );
		expect( g.default_size ).toBe( 'L' );
		moveSize( g, 'L', - 1 );
		expect( g.sizes ).toEqual( [ 'L', 'S' ] );
		removeSize( g, 'L' );
		expect( () => removeSize( g, 'S' ) ).toThrow( /at least one size/ );

	} );

	it( 'knows a piece of some sizes only: its sizes, its vertex count, not drawn in the others, not left without a size', () => {

		const g = skirt();
		const back = findPanel( g, 'back_right' );
		delete back.shapes.S;   // a piece of sizes M and L only, as a DXF import makes it
		back.meta = { import_warnings: [ { code: 'sizes', message: 'in sizes M, L only (not in size S): imported in those sizes' } ] };
		expect( panelSizes( g, 'back_right' ) ).toEqual( [ 'M', 'L' ] );
		expect( panelSizes( g, 'back_left' ) ).toEqual( [ 'M', 'L' ] );   // its mirrored copy
		expect( vertexCount( g, 'back_right' ) ).toBe( back.shapes.M.outline.length );
		expect( importWarnings( g, 'back_left' ).map( ( w ) => w.code ) ).toEqual( [ 'sizes' ] );
		expect( importWarnings( g, 'front' ) ).toEqual( [] );
		expect( Object.keys( buildScene( g, 'S' ).pieces ) ).toEqual( [ 'front' ] );
		expect( straightEdges( back, 'S' ) ).toEqual( straightEdges( back, 'M' ) );
		delete back.shapes.L;
		expect( () => removeSize( g, 'M' ) ).toThrow( /only size of back_right: remove that piece first/ );
		removeSize( g, 'L' );
		expect( g.sizes ).toEqual( [ 'S', 'M' ] );

	} );

	it( 'names texture files after the panel', () => {

		expect( texturePath( 'FRONT (2)', { type: 'image/png', name: 'a.png' } ) ).toBe( 'textures/front-2.png' );
		expect( texturePath( 'back', { type: 'image/jpeg', name: 'x.JPG' } ) ).toBe( 'textures/back.jpg' );
		expect( texturePath( '_Ärmel links_', { type: 'image/png' } ) ).toBe( 'textures/rmel-links.png' );
		expect( texturePath( '***' ) ).toBe( 'textures/panel.png' );
		expect( PANEL_TYPES ).toContain( 'waistband' );
		expect( GARMENT_TYPES.at( - 1 ) ).toBe( 'other' );

	} );

} );

describe( 'seams as the view shows them', () => {

	it( 'stores a side picked on a plain panel as is', () => {

		const g = skirt();
		expect( sideFromPicks( g, 'back_right', 6, 9 ) ).toEqual( { panel: 'back_right', start: 6, end: 9 } );
		expect( sideAsShown( g, { panel: 'back_right', start: 6, end: 9 } ) ).toEqual( { panel: 'back_right', first: 6, last: 9, ghost: false } );

	} );

	it( 'stores a side picked on a mirrored copy in its source’s numbers, walked the other way', () => {

		const g = skirt();
		// the copy's shown vertex v is the source's vertex −v (16 vertices)
		const side = sideFromPicks( g, 'back_left', 7, 10 );
		expect( side ).toEqual( { panel: 'back_left', start: 6, end: 9 } );
		expect( sideAsShown( g, side ) ).toEqual( { panel: 'back_left', first: 7, last: 10, ghost: false } );
		// the catalogue's "side left": front 2→5 with back_left 6→9, reverse false; shown, the
		// copy's run walks backwards, so the shown pairing is the other way round
		expect( shownReverse( g, g.seams[ 8 ] ) ).toBe( true );
		expect( storedReverse( g, g.seams[ 8 ].a, g.seams[ 8 ].b, true ) ).toBe( false );

	} );

	it( 'stores a side picked on the mirrored half of a folded panel as half "mirror"', () => {

		const g = skirt();
		const side = sideFromPicks( g, 'front', 5, 2, true );
		expect( side ).toEqual( { panel: 'front', start: 2, end: 5, half: 'mirror' } );
		expect( sideAsShown( g, side ) ).toEqual( { panel: 'front', first: 5, last: 2, ghost: true } );
		// "side right": front's mirrored half 2→5 with back_right 6→9, reverse false; the mirrored
		// half's run walks the shown one backwards, back_right's does not: shown, reversed
		expect( shownReverse( g, g.seams[ 9 ] ) ).toBe( true );

	} );

	it( 'draws the catalogue’s side seams joining hem to hem and waist to waist', () => {

		const g = skirt();
		const scene = buildScene( g, 'M' );
		for ( const i of [ 8, 9 ] ) {

			const s = scene.seams.find( ( x ) => x.index === i );
			// each link joins two points at the same height (the panels stand side by side)
			for ( const [ p, q ] of s.links ) expect( p[ 1 ] ).toBeCloseTo( q[ 1 ], 2 );

		}

		const [ first, last ] = sideEnds( g, scene.pieces.front, g.seams[ 9 ].a );
		// on the mirrored half, across the fold line x = 0
		expect( first[ 0 ] ).toBeLessThan( 0 );
		expect( last[ 0 ] ).toBeLessThan( 0 );
		expect( scene.pieces.front.ghost ).not.toBeNull();
		expect( displayFold( g, 'back_left' ) ).toBe( null );

	} );

	it( 'measures both runs of a seam and their difference in the current size', () => {

		const g = skirt();
		const m = seamLengths( g, g.seams[ 8 ], 'M' );
		expect( m.a ).toBeCloseTo( 0.66912, 5 );
		expect( m.b ).toBeCloseTo( 0.66945, 5 );
		expect( m.difference ).toBeCloseTo( 0.0005, 4 );
		expect( m.ok ).toBe( true );
		const s = seamLengths( g, { a: { panel: 'front', start: 2, end: 5 }, b: { panel: 'back_right', start: 0, end: 1 } }, 'S' );
		expect( s.difference ).toBeGreaterThan( 0.02 );
		expect( s.ok ).toBe( false );
		expect( seamLengths( g, { a: { panel: 'front', start: 2, end: 5 }, b: { panel: 'back_right', start: 0, end: 1 }, ease: 0.9 }, 'S' ).ok ).toBe( true );

	} );

	it( 'knows runs over the fold and mirrored edge numbers', () => {

		const g = skirt();
		expect( runCrossesFold( g, { panel: 'front', start: 11, end: 1 } ) ).toBe( true );
		expect( runCrossesFold( g, { panel: 'front', start: 2, end: 5 } ) ).toBe( false );
		expect( shownEdge( g, 'back_left', 0 ) ).toBe( 15 );
		expect( shownEdge( g, 'back_right', 0 ) ).toBe( 0 );
		// a mirrored copy's shape is its source's image: shown vertex 1 is the image of vertex 15
		const src = findPanel( g, 'back_right' ).shapes.M.outline;
		const copy = panelShape( g, 'back_left', 'M' ).outline;
		expect( copy[ 1 ].start[ 0 ] ).toBeCloseTo( - src[ 15 ].start[ 0 ], 12 );
		expect( copy[ 1 ].start[ 1 ] ).toBeCloseTo( src[ 15 ].start[ 1 ], 12 );

	} );

	it( 'moves a placement anchor point with its panel (as catwalk.garment.edit does)', () => {

		const g = skirt();
		const front = findPanel( g, 'front' );
		front.placement.anchor_point = [ 0.1, 0.2 ];
		transformPanel( g, 'front', [ [ 1, 0, 0.05 ], [ 0, 1, - 0.02 ] ] );
		expect( front.placement.anchor_point[ 0 ] ).toBeCloseTo( 0.15, 12 );
		expect( front.placement.anchor_point[ 1 ] ).toBeCloseTo( 0.18, 12 );
		transformPanel( g, 'front', [ [ - 1, 0, 0 ], [ 0, 1, 0 ] ] );   // mirrored about x = 0
		expect( front.placement.anchor_point[ 0 ] ).toBeCloseTo( - 0.15, 12 );

	} );

} );
