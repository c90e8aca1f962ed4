import { defineConfig } from 'vite';

// The service (`catwalk serve`) answers the API; the dev server forwards to it.
const SERVICE = process.env.CATWALK_SERVICE_URL || 'http://127.0.0.1:8000';
const proxy = Object.fromEntries(
	[ '/api', '/healthz', '/readyz', '/openapi.json' ].map( ( p ) => [ p, { target: SERVICE, changeOrigin: false } ] ),
);

export default defineConfig( {
	base: '/',
	appType: 'spa', // one index.html, client-side routes (the service answers them with a history fallback)
	server: { host: '127.0.0.1', port: 5173, proxy },
	preview: { host: '127.0.0.1', port: 4173, proxy },
	build: {
		outDir: 'dist',
		assetsDir: 'assets',
		sourcemap: false,
		chunkSizeWarningLimit: 900, // three.js is most of it
	},
	test: {
		include: [ 'test/**/*.test.js' ],
		environment: 'node',
	},
} );
