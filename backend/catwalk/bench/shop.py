"""A merchant's shop for the component (docs/embed.md) to be tried on: a merchant with a
published garment and its publishable key, and a plain product page that embeds
``<catwalk-tryon>``, served from another origin (another port on 127.0.0.1) than the service.
``catwalk bench player`` measures the component on it; ``tests/frontend/test_embed.py`` walks a
shopper through it.

The page is what a shop would write: its own fonts, a 62.5 % root font size and its own
button styles (none of which reach the component), a size select, and a listener for
``catwalk:size`` that picks the size and says so (``#chosen``), with every event the component
sent kept in ``window.shopEvents``.
"""

from __future__ import annotations

import html
import json
import threading
import time
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer
from pathlib import Path

import httpx

from catwalk.config import Config
from catwalk.service import merchants

SHOP_PAGE = """<!doctype html>
<html lang="en">
<head>
<meta charset="utf-8">
<meta name="viewport" content="width=device-width, initial-scale=1">
<link rel="icon" href="data:,">
<title>{title} — Atelier Nord</title>
<style>
  html {{ font-size: 62.5%; }}
  body {{ margin: 0; font: 1.6rem/1.45 Georgia, "Times New Roman", serif; color: #2b2620;
         background: #fffdf8; }}
  header {{ padding: 1.6rem 2.4rem; border-bottom: 1px solid #e7dfd2; font-size: 2.2rem;
           letter-spacing: .08em; text-transform: uppercase; }}
  main {{ display: grid; grid-template-columns: minmax(0, 1fr) minmax(0, 1.1fr); gap: 3.2rem;
         max-width: 112rem; margin: 0 auto; padding: 2.4rem; }}
  .photo {{ aspect-ratio: 3 / 4; border-radius: .4rem;
           background: linear-gradient(160deg, #d9cbb7, #a99377 60%, #6d5a45); }}
  h1 {{ font-weight: 400; font-size: 3.2rem; margin: 0 0 .4rem; }}
  .price {{ font-size: 2rem; margin: 0 0 2rem; }}
  label {{ display: block; margin-bottom: .6rem; }}
  select, button {{ font: inherit; font-size: 1.6rem; padding: 1rem 1.4rem; border-radius: 0; }}
  button {{ background: #2b2620; color: #fffdf8; border: 0; text-transform: uppercase;
           letter-spacing: .1em; }}
  .buy {{ display: flex; gap: 1.2rem; align-items: end; margin-bottom: 2.4rem; }}
  catwalk-tryon {{ margin: 0 0 2rem; }}
  #chosen {{ min-height: 2.4rem; font-style: italic; }}
  @media (max-width: 700px) {{ main {{ grid-template-columns: minmax(0, 1fr); padding: 1.6rem;
                                       gap: 1.6rem; }}
                              .photo {{ aspect-ratio: 4 / 3; }} }}
</style>
<script type="module" src="{service}/embed/v1/catwalk.js"></script>
</head>
<body>
<header>Atelier Nord</header>
<main>
  <div class="photo" role="img" aria-label="{title}, photographed"></div>
  <section>
    <h1>{title}</h1>
    <p class="price">€89</p>
    <div class="buy">
      <div><label for="size">Size</label>
        <select id="size">{options}</select></div>
      <button type="button">Add to cart</button>
    </div>
    <catwalk-tryon garment="{garment}" size="{size}" key="{key}"{extra}></catwalk-tryon>
    <p id="chosen" aria-live="polite"></p>
  </section>
</main>
<script>
  window.shopEvents = [];
  const tryon = document.querySelector('catwalk-tryon');
  const size = document.getElementById('size');
  for (const name of ['size', 'ready', 'body', 'error', 'forgotten']) {{
    tryon.addEventListener('catwalk:' + name,
                           (e) => window.shopEvents.push({{ type: e.type, detail: e.detail }}));
  }}
  tryon.addEventListener('catwalk:size', (e) => {{
    size.value = e.detail.size;
    document.getElementById('chosen').textContent =
      'Size ' + e.detail.size + ' chosen with the try-on';
  }});
  size.addEventListener('change', (e) => tryon.setAttribute('size', e.target.value));
</script>
</body>
</html>
"""


def shop_page(service: str, garment: str, key: str, *, title: str = "Pencil skirt",
              sizes=("S", "M", "L"), size: str = "M", seconds: float | None = None,
              preset: str | None = None) -> str:
    """The product page embedding the component (the service's script at ``service``)."""
    esc = html.escape
    extra = (f' seconds="{seconds:g}"' if seconds is not None else "") + \
        (f' preset="{esc(preset)}"' if preset else "")
    options = "".join(f'<option{" selected" if s == size else ""}>{esc(s)}</option>'
                      for s in sizes)
    return SHOP_PAGE.format(title=esc(title), service=esc(service), garment=esc(garment),
                            size=esc(size), key=esc(key), extra=extra, options=options)


def strict_policy(service: str) -> str:
    """A shop's Content-Security-Policy that lets its page reach nothing but the service: what
    the component needs (its script and chunks, its requests, the result's textures as blobs,
    meshopt's WebAssembly) and the page's own inline script and style."""
    return (f"default-src 'none'; script-src {service} 'unsafe-inline' 'wasm-unsafe-eval'; "
            f"connect-src {service} blob:; img-src blob: data:; style-src 'unsafe-inline'")


class ShopSite:
    """Pages served on 127.0.0.1:``port`` in a thread (path → HTML, or (HTML, headers));
    ``url`` is its origin."""

    def __init__(self, port: int, pages: dict):
        site = self

        class Handler(BaseHTTPRequestHandler):
            def do_GET(self):  # noqa: N802 - http.server's name
                page = site.pages.get(self.path.split("?", 1)[0])
                text, headers = page if isinstance(page, tuple) else (page, {})
                data = (text or "not found").encode()
                self.send_response(200 if text else 404)
                self.send_header("Content-Type", "text/html; charset=utf-8")
                self.send_header("Content-Length", str(len(data)))
                for k, v in headers.items():
                    self.send_header(k, v)
                self.end_headers()
                self.wfile.write(data)

            def log_message(self, *args):   # quiet
                pass

        self.pages = dict(pages)
        self.server = ThreadingHTTPServer(("127.0.0.1", port), Handler)
        self.url = f"http://127.0.0.1:{port}"
        self.thread = threading.Thread(target=self.server.serve_forever, daemon=True)
        self.thread.start()

    def close(self) -> None:
        self.server.shutdown()
        self.server.server_close()


def open_shop(config: Config, url: str, name: str, origins: list[str], garment: Path,
              timeout: float = 900.0) -> dict:
    """A merchant ``name`` on the service at ``url`` (its database: ``config``'s), its
    origins allowed, ``garment`` (a catalogue garment JSON, its textures beside it) uploaded
    over the API, dressed by the check and published: ``{"key", "pk", "garment", "sizes"}``."""
    key = merchants.create(config, name)
    merchants.origins(config, name, replace=origins)
    g = json.loads(garment.read_text())
    names = sorted({p["texture"]["image"] for p in g["panels"] if p.get("texture")})
    parts = [("garment", ("garment.json", json.dumps(g).encode(), "application/json"))]
    parts += [("files", (n, (garment.parent / n).read_bytes(), "image/png")) for n in names
              if (garment.parent / n).is_file()]
    auth = {"Authorization": f"Bearer {key}"}
    with httpx.Client(base_url=url, headers=auth, timeout=120) as api:
        r = api.post("/api/merchant/garments", files=parts)
        r.raise_for_status()
        gid = r.json()["id"]
        t0 = time.monotonic()
        while (item := api.get(f"/api/merchant/garments/{gid}").json())["versions"][0][
                "check_status"] != "done":   # the latest version first
            if time.monotonic() - t0 > timeout:
                raise TimeoutError(f"the dressing check of {gid} did not end in {timeout:g} s")
            time.sleep(0.5)
        api.post(f"/api/merchant/garments/{gid}/publish").raise_for_status()
    return {"key": key, "pk": merchants.publishable_key(config, name), "garment": gid,
            "sizes": item["sizes"]}
