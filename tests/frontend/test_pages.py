"""The shopper's pages in a real browser against a real ``catwalk serve``: the catalogue's
thumbnails load, measurements make a body, a fast 1 s try-on shows its progress, the player
plays (time advances, the garment moves), the fit map toggles, the timeline scrubs — with no
console error anywhere."""

from __future__ import annotations

import math
import time

import httpx

from .conftest import PHONE

ALL_THUMBNAILS_LOADED = """() => {
  const imgs = [...document.querySelectorAll('.card img')];
  return imgs.length > 0 && imgs.every(i => i.complete && i.naturalWidth > 0);
}"""


def tryon_state(page) -> dict:
    return page.evaluate("""() => {
      const b = document.querySelector('.tryon-box');
      return b ? {stage: b.dataset.stage || null, progress: parseFloat(b.dataset.progress || 'NaN'),
                  status: b.dataset.status || null} : {};
    }""")


def wait_player(page) -> None:
    page.wait_for_function("() => window.__catwalk && window.__catwalk.player", timeout=90_000)


def check_fit_map(page) -> bool:
    """Toggle the fit map if this file can draw it; True when it did."""
    fit = page.get_by_role("button", name="Fit map", exact=True)
    if not page.evaluate("__catwalk.player.hasFitMap()"):
        assert fit.is_disabled()
        assert page.locator(".controls__note").is_visible()
        return False
    fit.click()
    assert fit.get_attribute("aria-pressed") == "true"
    assert page.locator(".legend").is_visible()
    page.evaluate("__catwalk.player.seek(0.5)")
    assert page.evaluate("__catwalk.player.fitMapOn()")
    assert page.evaluate("__catwalk.player.fitMapPeak()") > 0
    fit.click()
    assert page.locator(".legend").is_hidden()
    assert not page.evaluate("__catwalk.player.fitMapOn()")
    return True


def test_catalogue_body_tryon_and_player(site, page_factory, tmp_path):
    page, console = page_factory()
    garments = httpx.get(f"{site}/api/garments").json()["garments"]

    # the catalogue: every card's thumbnail loads
    page.goto(site + "/")
    page.wait_for_function(ALL_THUMBNAILS_LOADED, timeout=60_000)
    assert page.locator(".card").count() == len(garments)
    assert page.locator(".card__title").first.inner_text() == "Pencil skirt"

    # your body: ranges checked as you type, then the body from measurements
    page.get_by_role("link", name="Your body", exact=True).click()
    page.get_by_label("Height").fill("168")
    page.get_by_label("Bust / chest").fill("60")
    assert page.get_by_text("Bust must be between 74 and 140 cm.").is_visible()
    page.get_by_label("Bust / chest").fill("90")
    assert page.get_by_text("Bust must be between 74 and 140 cm.").is_hidden()
    page.get_by_label("Waist").fill("72")
    page.get_by_label("Hips").fill("98")
    page.get_by_role("button", name="Make my body").click()
    page.wait_for_selector(".girths", timeout=120_000)
    body_id = page.evaluate("localStorage.getItem('catwalk.body')")
    assert body_id and len(body_id) == 32
    assert page.locator(".girths").inner_text().count("cm") >= 8
    page.wait_for_function("() => window.__catwalk && window.__catwalk.bodyView",
                           timeout=60_000)

    # the garment page, then a fast 1 s try-on
    page.get_by_role("link", name="Catalogue", exact=True).click()
    page.locator(".card a").first.click()
    page.wait_for_selector(".tryon-form")
    page.wait_for_function("document.querySelector('.pattern__img').naturalWidth > 0")
    paths = httpx.get(f"{site}/openapi.json").json()["paths"]
    if any(p.endswith("/dressed.glb") for p in paths):     # the garment in 3D on its sample body
        page.wait_for_function("() => window.__catwalk && window.__catwalk.dressed",
                               timeout=90_000)
        assert page.locator(".garment-media__view canvas").is_visible()
    page.get_by_label("Walk length").select_option("1")
    page.get_by_label("Quality").select_option("fast")
    page.get_by_role("button", name="Try it on").click()
    page.wait_for_url("**/tryon/*")
    tryon_id = page.url.rsplit("/", 1)[1]

    # its progress advances (stage and fraction from the events) until it is done
    seen, t0 = [], time.monotonic()
    while time.monotonic() - t0 < 300:
        s = tryon_state(page)
        if s.get("status") == "done":
            break
        assert s.get("status") not in ("failed", "cancelled"), page.inner_text(".tryon-box")
        if s.get("stage") and (not seen or seen[-1] != (s["stage"], s["progress"])):
            seen.append((s["stage"], s["progress"]))
            assert page.get_by_role("progressbar").is_visible()
        time.sleep(0.1)
    else:
        raise AssertionError(f"the try-on did not finish: {seen}")
    fractions = [p for _, p in seen if not math.isnan(p)]
    assert len(set(fractions)) >= 3, seen
    assert fractions == sorted(fractions), seen          # never goes back
    assert len({st for st, _ in seen}) >= 3, seen        # several stages shown

    # the player plays: time advances, the garment's vertices move
    wait_player(page)
    t1 = page.evaluate("__catwalk.player.time()")
    page.wait_for_function(f"__catwalk.player.time() !== {t1}", timeout=30_000)
    assert page.evaluate("__catwalk.player.playing()")
    page.get_by_role("button", name="Pause").click()
    assert not page.evaluate("__catwalk.player.playing()")
    duration = page.evaluate("__catwalk.player.duration()")
    assert 0.8 <= duration <= 1.1, duration
    page.evaluate("__catwalk.player.seek(0.2)")
    a = page.evaluate("__catwalk.player.garmentVertex(0)")
    page.evaluate("__catwalk.player.seek(0.7)")
    b = page.evaluate("__catwalk.player.garmentVertex(0)")
    assert math.dist(a, b) > 0.01, (a, b)                # the garment walks with the body
    assert page.evaluate("__catwalk.player.visibleChunks()") == 1

    # speed, camera presets
    page.get_by_label("Speed").select_option("0.5")
    assert page.evaluate("__catwalk.player.speed()") == 0.5
    page.get_by_role("button", name="Side", exact=True).click()
    page.get_by_role("button", name="Follow", exact=True).click()

    # the fit map: on the web file when it carries the pattern, else on the plain file
    if not check_fit_map(page):
        page.evaluate(f"__catwalk.navigate('/tryon/{tryon_id}?compress=0')")
        page.wait_for_function("() => !window.__catwalk.player", timeout=10_000)
        wait_player(page)
        check_fit_map(page)
        page.get_by_role("button", name="Pause").click()

    # scrub with the timeline, then a screenshot
    page.get_by_label("Timeline").fill("600")
    t = page.evaluate("__catwalk.player.time()")
    assert abs(t - 0.6 * duration) < 0.01, (t, duration)
    assert not page.evaluate("__catwalk.player.playing()")
    shot = tmp_path / "player.png"
    page.screenshot(path=str(shot))
    assert shot.stat().st_size > 10_000

    # download link points at the result
    href = page.get_by_role("link", name="Download .glb").get_attribute("href")
    assert href.startswith(f"/api/tryons/{tryon_id}/result.glb")

    assert console.errors == []


def test_pages_at_a_phone_size(site, page_factory):
    """The catalogue and the body form fit a 390 px wide phone: nothing wider than the screen."""
    page, console = page_factory(PHONE)
    page.goto(site + "/")
    page.wait_for_function(ALL_THUMBNAILS_LOADED, timeout=60_000)
    assert page.evaluate("document.documentElement.scrollWidth") <= PHONE["width"]
    page.goto(site + "/body")                  # the server answers pages with index.html
    page.evaluate("localStorage.removeItem('catwalk.body')")
    page.reload()
    page.wait_for_selector("form.measure-form")
    assert page.evaluate("document.documentElement.scrollWidth") <= PHONE["width"]
    box = page.get_by_role("button", name="Make my body").bounding_box()
    assert box["height"] >= 44                  # touch-sized
    page.goto(site + "/no/such/page")
    assert page.get_by_role("heading", name="This page isn’t here").is_visible()
    assert console.errors == []


def test_a_scan_becomes_the_shoppers_body(site, page_factory, tmp_path):
    """A shopper drops a scan (millimetres, Z up, noisy, with holes): the page says it is
    being fitted, then shows the body with how close it lies to the scan, and draws it."""
    from catwalk.body import synthetic as sy

    truth = sy.true_body(sy.case("hip"))
    v, f = sy.scan_of(truth, faces=40_000, seed=3)
    scan = tmp_path / "my-scan.ply"
    sy.write_scan(scan, v, f)

    page, console = page_factory()
    page.goto(site + "/body")
    page.locator("input[type=file]").set_input_files(str(scan))
    page.wait_for_selector(".girths", timeout=120_000)
    text = page.locator(".body-layout__facts").inner_text()
    assert "Made from your scan" in text and "mm from its surface" in text, text
    assert "We read the scan as a female body shape" in text
    body_id = page.evaluate("localStorage.getItem('catwalk.body')")
    got = httpx.get(f"{site}/api/bodies/{body_id}").json()
    assert got["fit"] == "surface" and got["source"] == "scan"
    assert got["scan"]["surface_distance_mm"]["scan_to_body"]["mean"] < 1.5
    page.wait_for_function("() => window.__catwalk && window.__catwalk.bodyView",
                           timeout=60_000)
    shot = tmp_path / "scan-body.png"
    page.screenshot(path=str(shot))
    assert shot.stat().st_size > 10_000
    assert console.errors == []
