"""``catwalk bench player``: the try-on page in a real browser — how long until the first frame
is drawn, how large the file it downloads is, and whether the player's work per frame grows
with the try-on's length.

It starts ``catwalk serve`` (embedded default, a temporary storage folder, the repository's
catalogue and built pages), makes a body, and has the service make a fast try-on of the
catalogue dress for each ``--seconds`` (default 2 and 10 s: one and five garment chunks). Then,
in Debian's chromium driven by Playwright (WebGL through SwiftShader: the CPU draws, so frame
times are the machine's, not a GPU's), for each finished try-on it opens ``/tryon/{id}`` and
reports:

- ``ready_to_first_frame_s``: the page is opened as the try-on is asked for (as a shopper's
  is): from the page knowing the result is ready to the player's first drawn frame
  (``download_and_decode_s`` of it: fetching and decoding the .glb);
- ``web_bytes``: the .glb the page downloads (meshopt);
- ``frame_ms`` / ``frame_p95_ms``: the median and 95th percentile of the page's own work per
  frame (clock, mixer, CPU morph, fit map off, draw calls) over ``--frames`` frames of
  playback, and the same with the fit map on.

Then the shops' component (``embed``, docs/embed.md; ``--no-embed`` leaves it out): the gzip
size of its own files (``catwalk.js`` and its chunks) and of three.js's chunk; and the same
first frame on a shop's product page served from another origin (``catwalk.bench.shop``): a
merchant with the dress published, the page embedding ``<catwalk-tryon>`` with its
publishable key, a shopper typing the body's measurements and pressing "Try it on" for the
first ``--seconds`` walk — from the component knowing the result is ready to its first frame.

Needs the dev extras (``playwright``) and ``/usr/bin/chromium`` (``make test`` installs both).
"""

from __future__ import annotations

import gzip
import json
import os
import sys
import tempfile
from pathlib import Path

from catwalk.bench import cpu_model
from catwalk.bench.service import _start, _stop, free_port
from catwalk.bench.shop import ShopSite, open_shop, shop_page
from catwalk.config import Config, get_config
from catwalk.errors import InputError, SetupError
from catwalk.service.client import Client

CHROMIUM = os.environ.get("CATWALK_TEST_CHROMIUM", "/usr/bin/chromium")
ARGS = ["--use-angle=swiftshader", "--enable-unsafe-swiftshader", "--no-sandbox",
        "--disable-background-networking", "--disable-component-update", "--disable-sync",
        "--no-first-run"]
GARMENT = "dress"
BODY = {"sex": "female", "height": 1.68, "bust": 0.90, "waist": 0.72, "hips": 0.98}


def _frame_work(page, frames: int) -> dict:
    page.evaluate("__catwalk.player.play()")
    page.evaluate("__catwalk.player.resetFrameWork()")
    start = page.evaluate("__catwalk.player.frames()")
    page.wait_for_function(f"() => __catwalk.player.frames() >= {start + frames}",
                           timeout=600_000)
    return page.evaluate("__catwalk.player.frameWork()")


def _watched(browser):
    """A new page, its console errors and the sizes of the result files it downloaded."""
    page = browser.new_page(viewport={"width": 1280, "height": 800})
    errors: list[str] = []
    page.on("console", lambda m: errors.append(m.text) if m.type == "error" else None)
    sizes: list[int] = []
    page.on("response", lambda r: sizes.append(int(r.headers.get("content-length", 0)))
            if "/result.glb" in r.url else None)
    return page, errors, sizes


def _played(page, frames: int, errors: list[str], sizes: list[int]) -> dict:
    """Once the player drew its first frame: the time to it from the result being ready (the
    page's ``catwalk:`` marks), then the work per frame over ``frames`` frames, with and
    without the fit map."""
    page.wait_for_function("() => window.__catwalk && window.__catwalk.player && "
                           "window.__catwalk.player.frames() >= 1", timeout=1_800_000)
    marks = page.evaluate("""() => Object.fromEntries(performance.getEntriesByType('mark')
        .filter(m => m.name.startsWith('catwalk:')).map(m => [m.name.slice(8), m.startTime]))""")
    plain = _frame_work(page, frames)
    fit = None
    if page.evaluate("__catwalk.player.hasFitMap()"):
        page.get_by_role("button", name="Fit map").first.click()
        page.evaluate("__catwalk.player.frames()")
        fit = _frame_work(page, frames)
    ready, loaded, drawn = (marks.get(k) for k in ("result-ready", "result-loaded",
                                                   "first-frame"))
    info = {"ready_to_first_frame_s": round((drawn - ready) / 1e3, 3) if ready and drawn
            else None,
            "download_and_decode_s": round((loaded - ready) / 1e3, 3) if ready and loaded
            else None,
            "web_bytes": max(sizes) if sizes else None,
            "chunks": page.evaluate("__catwalk.player.chunks()"),
            "duration_s": round(page.evaluate("__catwalk.player.duration()"), 3),
            "frame_ms": round(plain["median"], 2), "frame_p95_ms": round(plain["p95"], 2),
            "frame_mean_ms": round(plain["mean"], 2),
            "frames_measured": plain["n"], "console_errors": errors}
    if fit is not None:
        info.update({"fit_map_frame_ms": round(fit["median"], 2),
                     "fit_map_frame_p95_ms": round(fit["p95"], 2)})
    page.close()
    return info


def _measure(browser, url: str, job_id: str, frames: int) -> dict:
    page, errors, sizes = _watched(browser)
    page.goto(f"{url}/tryon/{job_id}")
    return _played(page, frames, errors, sizes)


def embed_sizes(folder: Path) -> dict:
    """The component's files (``dist/embed/v1``) gzipped (level 9, as a server would send
    them): its own — the entry and every chunk but three.js's — and three.js's chunk."""
    own, three, files = 0, 0, {}
    for path in sorted(folder.rglob("*.js")):
        n = len(gzip.compress(path.read_bytes(), 9))
        files[str(path.relative_to(folder))] = n
        if path.parent.name == "chunks" and path.name.startswith("three-"):
            three += n
        else:
            own += n
    return {"own_gzip_bytes": own, "three_gzip_bytes": three, "files_gzip_bytes": files}


def _measure_embed(browser, url: str, config: Config, seconds: float, frames: int,
                   say) -> dict:
    """The component on a shop's page of another origin: a shopper's body typed, "Try it on",
    the first frame once the result is ready."""
    port = free_port()
    shop = f"http://127.0.0.1:{port}"
    say(f"a merchant publishes the {GARMENT} (its dressing check) …")
    s = open_shop(config, url, "bench-shop", [shop], config.catalogue_dir / f"{GARMENT}.json")
    site = ShopSite(port, {"/": shop_page(url, s["garment"], s["pk"], title="Dress",
                                          sizes=s["sizes"], size="M", seconds=seconds)})
    try:
        say(f"a fast {seconds:g} s try-on in the component on a shop's page ({shop}) …")
        page, errors, sizes = _watched(browser)
        page.goto(f"{shop}/")
        page.get_by_role("button", name="Try it on").click()
        for label, key in (("Height", "height"), ("Bust / chest", "bust"), ("Waist", "waist"),
                           ("Hips", "hips")):
            page.get_by_label(label).fill(f"{BODY[key] * 100:g}")
        page.get_by_role("button", name="Make my body").click()
        return {"seconds": seconds, "shop": shop, **_played(page, frames, errors, sizes)}
    finally:
        site.close()


def run(seconds: list[float], frames: int = 240, log=None, embed: bool = True) -> dict:
    from playwright.sync_api import (
        sync_playwright,  # deferred: playwright: only the browser benchmark needs it
    )


    say = log or (lambda m: None)
    tmp = Path(tempfile.mkdtemp(prefix="catwalk-bench-player-"))
    port = free_port()
    url = f"http://127.0.0.1:{port}"
    proc, logf = _start(port, 1, tmp / "storage")
    out = {"garment": GARMENT, "preset": "fast", "machine": cpu_model(), "runs": []}
    try:
        with Client(url, timeout=300) as api, sync_playwright() as pw:
            api.wait_ready(timeout=300)
            body = api.create_body(**BODY)
            browser = pw.chromium.launch(executable_path=CHROMIUM, args=ARGS, headless=True)
            try:
                for s in seconds:
                    # as a shopper does: the page is open while the try-on is made
                    say(f"a fast {s:g} s try-on of the {GARMENT}, followed in chromium …")
                    job = api.create_tryon(body_id=body["id"], garment_id=GARMENT,
                                           preset="fast", seconds=s)
                    out["runs"].append({"seconds": s,
                                        **_measure(browser, url, job["id"], frames)})
                if embed:
                    built = get_config().frontend_dir / "embed" / "v1"
                    # the service's own database: embedded, in its storage folder
                    theirs = Config(storage_dir=tmp / "storage", database_url=None,
                                    broker_url=None, catalogue_dir=get_config().catalogue_dir)
                    out["embed"] = {**embed_sizes(built), **_measure_embed(
                        browser, url, theirs, seconds[0], frames, say)}
            finally:
                browser.close()
    finally:
        _stop(proc)
        logf.close()
        import shutil

        shutil.rmtree(tmp, ignore_errors=True)
    return out


def main(args) -> int:
    if not Path(CHROMIUM).is_file():
        raise SetupError(f"{CHROMIUM} is missing: `make test` installs Debian's chromium")
    try:
        import playwright  # noqa: F401
    except ImportError:
        raise SetupError("playwright is not installed: pip install -e '.[dev]'") from None
    if not args.seconds or any(not 0.5 <= s <= 10 for s in args.seconds):
        raise InputError(f"--seconds must be within 0.5–10, got {args.seconds}")
    if args.frames < 30:
        raise InputError(f"--frames must be at least 30, got {args.frames}")
    log = None if args.json else (lambda m: print(f"bench player: {m}", file=sys.stderr))
    r = run(args.seconds, args.frames, log, embed=not args.no_embed)
    if args.json:
        print(json.dumps(r, indent=2))
        return 0
    print(f"catwalk bench player: the {r['garment']} (fast), chromium + SwiftShader "
          f"({r['machine']})")
    for run_ in r["runs"]:
        fit = (f", fit map {run_['fit_map_frame_ms']:.1f} ms" if "fit_map_frame_ms" in run_
               else "")
        print(f"  {run_['seconds']:g} s walk ({run_['chunks']} chunks, "
              f"{(run_['web_bytes'] or 0) / 1e6:.2f} MB): result ready → first frame "
              f"{run_['ready_to_first_frame_s']} s; work per frame {run_['frame_ms']:.1f} ms "
              f"(p95 {run_['frame_p95_ms']:.1f})"
              f"{fit}; console errors: {len(run_['console_errors'])}")
    e = r.get("embed")
    if e:
        print(f"  the shops' component: {e['own_gzip_bytes'] / 1e3:.1f} kB gzip of its own "
              f"(three.js {e['three_gzip_bytes'] / 1e3:.1f} kB besides); on a shop's page, "
              f"{e['seconds']:g} s walk: result ready → first frame "
              f"{e['ready_to_first_frame_s']} s; work per frame {e['frame_ms']:.1f} ms "
              f"(p95 {e['frame_p95_ms']:.1f}); console errors: {len(e['console_errors'])}")
    return 0
