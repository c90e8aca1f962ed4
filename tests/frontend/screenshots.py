"""Screenshots of every page at a desktop's (1440×900) and a phone's (390×844) size, into
docs/img/frontend-<page>-<desktop|phone>.png, against a running ``catwalk serve`` that serves
the built pages (the full catalogue):

    .venv/bin/catwalk serve --port 8000 &
    .venv/bin/python -m tests.frontend.screenshots [--url http://127.0.0.1:8000] [--garment dress]

It makes a body from measurements through the page, asks for two fast 2 s try-ons of the
garment (sizes S and M) through the API, and photographs the catalogue, the garment, your body,
a try-on's progress, the player, the fit map and the comparison. Not a test (pytest does not
collect it)."""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import httpx
from playwright.sync_api import sync_playwright

CHROMIUM = "/usr/bin/chromium"
ARGS = ["--use-angle=swiftshader", "--enable-unsafe-swiftshader", "--no-sandbox",
        "--disable-background-networking", "--disable-component-update", "--disable-sync",
        "--no-first-run"]
SIZES = {"desktop": {"width": 1440, "height": 900}, "phone": {"width": 390, "height": 844}}
OUT = Path(__file__).resolve().parents[2] / "docs" / "img"
THUMBS = """() => [...document.querySelectorAll('.card img')]
  .every(i => i.complete && i.naturalWidth > 0)"""


def settle(page, seconds=1.5):
    """Let a few frames draw (software WebGL is slow)."""
    page.wait_for_timeout(int(seconds * 1000))


def shoot(page, name, kind, full=True):
    path = OUT / f"frontend-{name}-{kind}.png"
    page.screenshot(path=str(path), full_page=full)
    print("wrote", path.relative_to(OUT.parents[1]))


def hold_player(page, t, count=1):
    page.wait_for_function(f"() => window.__catwalk && window.__catwalk.player && "
                           f"window.__catwalk.player.count === {count}", timeout=180_000)
    page.evaluate("__catwalk.player.pause()")
    page.evaluate(f"__catwalk.player.seek({t})")
    settle(page, 2.5)


def wait_thumbnails(http, timeout=900):
    """Until every thumbnail is rendered (meanwhile the API answers the flat pattern, not
    cached)."""
    t0 = time.monotonic()
    for g in http.get("/api/garments").json()["garments"]:
        while http.get(g["thumbnail_url"]).headers.get("cache-control") == "no-store":
            if time.monotonic() - t0 > timeout:
                raise SystemExit(f"the thumbnail of {g['id']} is not rendered after {timeout} s")
            time.sleep(2)


def wait_done(http, ids, timeout=900):
    t0 = time.monotonic()
    for i in ids:
        while True:
            s = http.get(f"/api/tryons/{i}").json()
            if s["status"] == "done":
                break
            if s["status"] in ("failed", "cancelled"):
                raise SystemExit(f"try-on {i} {s['status']}: {s.get('error')}")
            if time.monotonic() - t0 > timeout:
                raise SystemExit(f"try-on {i} not done after {timeout} s")
            time.sleep(1)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--url", default="http://127.0.0.1:8000")
    ap.add_argument("--garment", default="dress")
    ap.add_argument("--seconds", type=float, default=2.0)
    ap.add_argument("--preset", default="fast")
    a = ap.parse_args()
    OUT.mkdir(parents=True, exist_ok=True)
    http = httpx.Client(base_url=a.url, timeout=120)
    wait_thumbnails(http)

    with sync_playwright() as p:
        browser = p.chromium.launch(executable_path=CHROMIUM, args=ARGS, headless=True)
        pages = {}
        for kind, vp in SIZES.items():
            ctx = browser.new_context(viewport=vp, device_scale_factor=1,
                                      has_touch=kind == "phone")
            page = ctx.new_page()
            page.set_default_timeout(120_000)
            page.on("console", lambda m, k=kind: m.type == "error" and print(k, "console:", m.text))
            pages[kind] = page

        # the catalogue, and the body form, before there is a body
        for kind, page in pages.items():
            page.goto(a.url + "/")
            page.wait_for_function(THUMBS)
            shoot(page, "catalogue", kind)
            page.goto(a.url + "/body")
            page.wait_for_selector("form.measure-form")
            shoot(page, "body-form", kind)

        # a body through the page
        d = pages["desktop"]
        d.get_by_label("Height").fill("168")
        d.get_by_label("Bust / chest").fill("90")
        d.get_by_label("Waist").fill("72")
        d.get_by_label("Hips").fill("98")
        d.get_by_role("button", name="Make my body").click()
        d.wait_for_selector(".girths")
        body = d.evaluate("localStorage.getItem('catwalk.body')")
        pages["phone"].evaluate(f"localStorage.setItem('catwalk.body', '{body}')")

        for kind, page in pages.items():
            page.goto(a.url + "/body")
            page.wait_for_function("() => window.__catwalk && window.__catwalk.bodyView")
            settle(page)
            shoot(page, "body", kind)
            page.goto(f"{a.url}/garments/{a.garment}")
            page.wait_for_function("document.querySelector('.pattern__img').naturalWidth > 0")
            page.wait_for_function("() => window.__catwalk && window.__catwalk.dressed")
            settle(page, 1.5)
            shoot(page, "garment", kind)

        # two try-ons, S and M; the progress of the second while it runs
        req = {"body_id": body, "garment_id": a.garment, "seconds": a.seconds, "preset": a.preset}
        s = http.post("/api/tryons", json={**req, "size": "S"}).json()
        m = http.post("/api/tryons", json={**req, "size": "M"}).json()
        if http.get(f"/api/tryons/{m['id']}").json()["status"] != "done":
            for kind, page in pages.items():
                page.goto(f"{a.url}/tryon/{m['id']}")
                page.wait_for_selector(".progress")
                page.wait_for_function("parseFloat(document.querySelector('.tryon-box')"
                                       ".dataset.progress || '0') > 0.05", timeout=600_000)
                shoot(page, "progress", kind, full=False)
        wait_done(http, [s["id"], m["id"]])

        half = a.seconds / 2
        for kind, page in pages.items():
            page.goto(f"{a.url}/tryon/{m['id']}")
            hold_player(page, half)
            shoot(page, "tryon", kind)
            fit = page.get_by_role("button", name="Fit map", exact=True)
            if fit.is_enabled():
                fit.click()
                page.evaluate("window.scrollTo(0, 0)")
                settle(page, 2.5)
                shoot(page, "fitmap", kind)
            page.goto(f"{a.url}/compare?a={s['id']}&b={m['id']}")
            hold_player(page, half, count=2)
            shoot(page, "compare", kind)
        browser.close()


if __name__ == "__main__":
    main()
