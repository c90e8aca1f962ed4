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

Needs the dev extras (``playwright``) and ``/usr/bin/chromium`` (``make test`` installs both).
"""

from __future__ import annotations

import json
import os
import sys
import tempfile
from pathlib import Path

from catwalk.bench import cpu_model
from catwalk.bench.service import _start, _stop, free_port
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


def _measure(browser, url: str, job_id: str, frames: int) -> dict:
    page = browser.new_page(viewport={"width": 1280, "height": 800})
    errors: list[str] = []
    page.on("console", lambda m: errors.append(m.text) if m.type == "error" else None)
    sizes: list[int] = []
    page.on("response", lambda r: sizes.append(int(r.headers.get("content-length", 0)))
            if "/result.glb" in r.url else None)
    page.goto(f"{url}/tryon/{job_id}")
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


def run(seconds: list[float], frames: int = 240, log=None) -> dict:
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
    r = run(args.seconds, args.frames, log)
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
    return 0
