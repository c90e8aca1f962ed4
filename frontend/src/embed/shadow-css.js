// The pages' stylesheet (src/styles.css) made fit for the component's shadow root: its
// variables on the host instead of the document's root, rem (the shop's root font size, which
// may be anything) as the pages' 16 px, and its narrow-screen rules asked of the component's
// own width (a container query) rather than the window's: on a shop the component may sit in
// a narrow column of a wide screen.

export const ROOT_FONT_PX = 16;

export function toShadowCss( css ) {

	return css
		.replace( /:root\b/g, ':host' )
		.replace( /(-?\d*\.?\d+)rem\b/g, ( _, n ) => `${ +( Number( n ) * ROOT_FONT_PX ).toFixed( 3 ) }px` )
		.replace( /@media\s*\(\s*max-width\s*:\s*([\d.]+px)\s*\)/g, '@container catwalk (max-width: $1)' );

}
