import { defineConfig } from 'vite';

// The shops' component (src/embed/, docs/embed.md), built on its own into dist/embed/v1/:
// `catwalk.js` (the element, the body step, the progress; its styles inline for its shadow
// root) and, fetched from beside it when a try-on is asked for, the player and three.js in
// chunks/. Paths are relative to the script (`base: './'`, no modulepreload links put into
// the shop's document), so the chunks come from the service, whatever page loads it.
export default defineConfig( {
	base: './',
	publicDir: false,
	build: {
		outDir: 'dist/embed/v1',
		emptyOutDir: true,
		sourcemap: false,
		modulePreload: false,
		chunkSizeWarningLimit: 900, // three.js
		lib: false,
		rolldownOptions: {
			input: { catwalk: 'src/embed/catwalk.js' },
			preserveEntrySignatures: 'exports-only',
			output: {
				format: 'es',
				entryFileNames: '[name].js',
				chunkFileNames: 'chunks/[name]-[hash].js',
				assetFileNames: 'chunks/[name]-[hash][extname]',
				codeSplitting: { groups: [ { name: 'three', test: /node_modules[\\/]three[\\/]/ } ] },
			},
		},
	},
} );
