// The shops' script (docs/embed.md): `<script type="module" src="https://catwalk…/embed/v1/
// catwalk.js">` defines <catwalk-tryon>. Built on its own (vite.embed.config.js) into
// dist/embed/v1/; the player and three.js come from beside it when a try-on is asked for.

import { defineTryonElement } from './element.js';

defineTryonElement();
