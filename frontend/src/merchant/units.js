// Lengths and ratios as the merchant pages show them.

/** Metres as centimetres, one decimal: "12.5 cm". */
export const cm = ( m ) => `${ ( m * 100 ).toFixed( 1 ) } cm`;

/** A ratio as a percentage, one decimal: "2.0 %". */
export const pct = ( x ) => `${ ( x * 100 ).toFixed( 1 ) } %`;
