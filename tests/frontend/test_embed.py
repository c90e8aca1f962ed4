"""The try-on on a merchant's own shop (docs/embed.md), in Chromium: a plain shop page served
from another origin (another port on 127.0.0.1) than ``catwalk serve`` embeds
``<catwalk-tryon>`` with the merchant's publishable key; a shopper makes a body, tries the
garment on, watches it walk with the fit map, picks a size — and the ``catwalk:size`` event
reaches the shop's page. The body is remembered on that shop and deleted from it; it is not
readable from another shop's origin. The same page on an origin the merchant does not allow
is refused with a clear message, and so is a page holding the merchant's secret key. The
component makes no request but to the shop and the service, keeps the shop's styles out and
fits a phone.

Screenshots for docs/embed.md: with ``CATWALK_TEST_SCREENSHOTS=1`` they are written to
docs/img/embed-*.png (else into the test's temporary folder)."""

from __future__ import annotations

import math
import os
import re
import time
from pathlib import Path

import httpx
import pytest

from catwalk.bench.shop import ShopSite, open_shop, shop_page, strict_policy
from service.helpers import REPO, Proc, free_port, make_config, service_env

from .conftest import DESKTOP, PHONE
from .test_pages import check_fit_map

DOCS_IMG = REPO / "docs" / "img"
STEP = "() => document.querySelector('catwalk-tryon').dataset.step"
FRAMES = "() => window.__catwalk && window.__catwalk.player && __catwalk.player.frames() >= {n}"


@pytest.fixture(scope="module")
def shops(tmp_path_factory, one_garment_catalogue, frontend_dist):
    """``catwalk serve`` (one local worker) with the built pages and component; merchant A
    with the pencil skirt published and its shop's origin allowed, merchant B (another shop,
    on another origin); the shop pages: A's product page on A's origin (and one holding A's
    secret key), and the same product page on B's origin, which A does not allow."""
    tmp = tmp_path_factory.mktemp("embed")
    env = service_env(tmp / "storage", one_garment_catalogue, frontend_dir=frontend_dist)
    port, a_port, b_port = free_port(), free_port(), free_port()
    proc = Proc(["serve", f"--port={port}", "--workers=1"], env, tmp / "serve.log")
    sites = []
    try:
        proc.wait_for('"api_ready"', timeout=180)
        service = f"http://127.0.0.1:{port}"
        a_origin, b_origin = f"http://127.0.0.1:{a_port}", f"http://127.0.0.1:{b_port}"
        config = make_config(env)
        a = open_shop(config, service, "atelier-nord", [a_origin],
                      REPO / "garments" / "pencil-skirt.json")
        from catwalk.service import merchants

        merchants.create(config, "other-shop")
        merchants.origins(config, "other-shop", replace=[b_origin])
        b_pk = merchants.publishable_key(config, "other-shop")
        page = shop_page(service, a["garment"], a["pk"], seconds=1)
        sites.append(ShopSite(a_port, {
            "/": page, "/secret": shop_page(service, a["garment"], a["key"], seconds=1),
            "/strict": (page, {"Content-Security-Policy": strict_policy(service)})}))
        sites.append(ShopSite(b_port, {"/": page}))
        yield {"service": service, "a": a, "a_origin": a_origin, "b_origin": b_origin,
               "b_pk": b_pk}
    finally:
        for s in sites:
            s.close()
        proc.stop()


def shoot(page, name: str, tmp_path: Path) -> None:
    folder = DOCS_IMG if os.environ.get("CATWALK_TEST_SCREENSHOTS") else tmp_path
    folder.mkdir(parents=True, exist_ok=True)
    path = folder / f"embed-{name}.png"
    page.screenshot(path=str(path), full_page=True)
    assert path.stat().st_size > 10_000


def requests_seen(page) -> list[str]:
    urls: list[str] = []
    page.on("request", lambda r: urls.append(r.url))
    return urls


def origins_of(urls: list[str]) -> set[str]:
    """The origins requests went to (the page's own blob: and data: URLs are no request)."""
    return {"/".join(u.split("/")[:3]) for u in urls if not u.startswith(("blob:", "data:"))}


def make_body(page) -> None:
    page.get_by_role("button", name="Try it on").click()
    page.wait_for_function(f"({STEP})() === 'body'")
    page.get_by_label("Height").fill("168")
    page.get_by_label("Bust / chest").fill("90")
    page.get_by_label("Waist").fill("72")
    page.get_by_label("Hips").fill("98")
    page.get_by_role("button", name="Make my body").click()


def follow_progress(page, timeout: float = 300.0) -> list[float]:
    """The fractions the component showed until its player came."""
    seen, t0 = [], time.monotonic()
    while time.monotonic() - t0 < timeout:
        step, progress = page.evaluate("""() => { const e = document.querySelector(
            'catwalk-tryon'); return [e.dataset.step, parseFloat(e.dataset.progress)]; }""")
        if step == "player":
            return seen
        assert step not in ("ended", "refused"), page.locator("catwalk-tryon .cw").inner_text()
        if progress == progress and (not seen or seen[-1] != progress):
            seen.append(progress)
        time.sleep(0.1)
    raise AssertionError(f"no player in {timeout:g} s: {seen}")


def test_a_shopper_tries_it_on_and_picks_a_size(shops, page_factory, tmp_path):
    page, console = page_factory(DESKTOP)
    urls = requests_seen(page)
    page.goto(shops["a_origin"] + "/")
    tryon = page.locator("catwalk-tryon")
    button = page.get_by_role("button", name="Try it on")
    page.wait_for_function("() => { const b = document.querySelector('catwalk-tryon')"
                           ".shadowRoot.querySelector('.cw-open'); return b && !b.disabled; }")
    # the shop's styles stay out (its serif font, its upper-case buttons, its 10 px rem)
    style = button.evaluate("(b) => { const s = getComputedStyle(b); return [s.fontFamily, "
                            "s.textTransform, s.fontSize]; }")
    assert "Georgia" not in style[0] and style[1] == "none" and style[2] == "16px", style
    assert page.locator("header").evaluate("(h) => getComputedStyle(h).fontFamily") \
        .startswith("Georgia")                                 # and its own stay its own

    # the body, the try-on's progress (it never goes back), the player
    make_body(page)
    fractions = follow_progress(page)
    assert fractions == sorted(fractions) and len(set(fractions)) >= 2, fractions
    page.wait_for_function(FRAMES.format(n=30), timeout=90_000)
    t1 = page.evaluate("__catwalk.player.time()")
    page.wait_for_function(f"__catwalk.player.time() !== {t1}", timeout=30_000)
    page.get_by_role("button", name="Pause").click()
    page.evaluate("__catwalk.player.seek(0.2)")
    v1 = page.evaluate("__catwalk.player.garmentVertex(0)")
    page.evaluate("__catwalk.player.seek(0.7)")
    assert math.dist(v1, page.evaluate("__catwalk.player.garmentVertex(0)")) > 0.01
    assert check_fit_map(page)                                  # the web file carries it
    marks = page.evaluate("""() => Object.fromEntries(performance.getEntriesByType('mark')
        .filter(m => m.name.startsWith('catwalk:')).map(m => [m.name.slice(8), m.startTime]))""")
    assert 0 < marks["first-frame"] - marks["result-ready"] < 5_000, marks

    # the size advice, then a size chosen: the event reaches the shop's page
    advice = page.locator("catwalk-tryon .advice")
    advice.get_by_text("We suggest size").wait_for()
    assert advice.locator("li").count() == 3
    page.get_by_role("button", name="Choose size M").click()
    assert page.locator("#chosen").inner_text() == "Size M chosen with the try-on"
    assert page.locator("#size").input_value() == "M"
    events = page.evaluate("window.shopEvents")
    chosen = [e["detail"] for e in events if e["type"] == "catwalk:size"]
    assert len(chosen) == 1 and chosen[0]["size"] == "M", events
    assert chosen[0]["garment"] == shops["a"]["garment"] and chosen[0]["recommended"]
    assert [e["type"] for e in events][:2] == ["catwalk:body", "catwalk:ready"], events
    page.get_by_role("button", name="Play").click()
    page.wait_for_timeout(600)
    shoot(page, "shop-desktop", tmp_path)

    # another size: tried on, then chosen
    page.locator("catwalk-tryon").get_by_role("button", name="Try on size L").click()
    follow_progress(page)
    page.wait_for_function(FRAMES.format(n=5), timeout=90_000)
    page.get_by_role("button", name="Choose size L").click()
    assert page.locator("#chosen").inner_text() == "Size L chosen with the try-on"
    assert origins_of(urls) == {shops["a_origin"], shops["service"]}, origins_of(urls)
    assert console.errors == []
    assert tryon.get_attribute("data-step") == "player"


def test_the_body_is_kept_on_that_shop_only_and_deleted(shops, page_factory):
    page, console = page_factory(DESKTOP)
    page.goto(shops["a_origin"] + "/")
    make_body(page)
    follow_progress(page)
    pk = shops["a"]["pk"]
    body_id = page.evaluate(f"localStorage.getItem('catwalk:body:{pk}')")
    shopper = page.evaluate("localStorage.getItem('catwalk:shopper')")
    assert body_id and len(body_id) == 32 and shopper and len(shopper) == 32

    # another visit: the body kept on this shop is used at once
    page.reload()
    page.get_by_role("button", name="Try it on").click()
    follow_progress(page)
    kept = page.locator("catwalk-tryon .cw-kept")
    assert "kept for this shop only" in kept.inner_text()

    # from another shop's page (its own key, its own allowed origin), with the same shopper's
    # id: the body is not there; with this shop's key that origin is refused
    other = page.context.new_page()
    other.goto(shops["b_origin"] + "/")
    ask = """async ([url, shopper]) => { const r = await fetch(url, {headers:
        {'X-Catwalk-Shopper': shopper}}); return [r.status, (await r.json()).error]; }"""
    base = f"{shops['service']}/api/bodies/{body_id}"
    status, error = other.evaluate(ask, [f"{base}?key={shops['b_pk']}", shopper])
    assert status == 404 and error["code"] == "not_found", (status, error)
    assert httpx.get(base).status_code == 404                 # nor on catwalk's own pages
    other.close()

    # the shopper deletes it: gone from the server and the shop's storage
    kept.get_by_role("button", name="Delete my body").click()
    page.wait_for_function(f"({STEP})() === 'idle'")
    assert page.evaluate(f"localStorage.getItem('catwalk:body:{pk}')") is None
    r = httpx.get(f"{base}?key={pk}", headers={"Origin": shops["a_origin"],
                                               "X-Catwalk-Shopper": shopper})
    assert r.status_code == 404, r.text
    assert [e["type"] for e in page.evaluate("window.shopEvents")][-1] == "catwalk:forgotten"
    assert console.errors == []


def test_a_scan_in_the_component(shops, page_factory, tmp_path):
    from catwalk.body import synthetic as sy

    v, f = sy.scan_of(sy.true_body(sy.case("hip")), faces=30_000, seed=5)
    scan = tmp_path / "scan.ply"
    sy.write_scan(scan, v, f)
    page, console = page_factory(DESKTOP)
    page.goto(shops["a_origin"] + "/")
    page.get_by_role("button", name="Try it on").click()
    page.get_by_role("tab", name="A 3D scan").click()
    page.locator("catwalk-tryon input[type=file]").set_input_files(str(scan))
    page.wait_for_function(f"['progress', 'player'].includes(({STEP})())", timeout=180_000)
    assert "from your scan" in page.locator("catwalk-tryon .cw-kept").inner_text()
    page.get_by_role("button", name="Close the try-on").click()
    assert console.errors == []


def test_at_a_phone_size(shops, page_factory, tmp_path):
    page, console = page_factory(PHONE)
    page.goto(shops["a_origin"] + "/")
    make_body(page)
    follow_progress(page)
    page.wait_for_function(FRAMES.format(n=10), timeout=90_000)
    assert page.evaluate("document.documentElement.scrollWidth") <= PHONE["width"]
    for name in ("Choose size M", "Try on size L", "Pause", "Fit map"):
        box = page.get_by_role("button", name=name).bounding_box()
        assert box["height"] >= 38 and box["x"] >= 0 and box["x"] + box["width"] <= 390, name
    stage = page.locator("catwalk-tryon .cw-stage").bounding_box()
    assert stage["width"] > 300 and stage["height"] > 300, stage
    page.get_by_role("button", name="Choose size M").click()
    assert page.locator("#chosen").inner_text() == "Size M chosen with the try-on"
    shoot(page, "shop-phone", tmp_path)
    assert console.errors == []


def test_under_a_strict_content_security_policy(shops, page_factory):
    """A shop whose pages may reach nothing but the service (strict_policy): the component
    works, and nothing it does is refused by the policy (no other origin, no inline style)."""
    page, console = page_factory(DESKTOP)
    page.goto(shops["a_origin"] + "/strict")
    make_body(page)
    follow_progress(page)
    page.wait_for_function(FRAMES.format(n=10), timeout=90_000)
    assert page.evaluate("__catwalk.player.hasFitMap()")
    assert console.errors == []


def test_an_origin_not_allowed_is_refused_clearly(shops, page_factory, tmp_path):
    page, _ = page_factory(DESKTOP)
    page.goto(shops["b_origin"] + "/")
    page.wait_for_function(f"({STEP})() === 'refused'")
    text = page.locator("catwalk-tryon .notice").inner_text()
    assert "not allowed on this site" in text and shops["b_origin"] in text, text
    assert "catwalk merchant origins" in text
    assert page.get_by_role("button", name="Try it on").count() == 0
    events = page.evaluate("window.shopEvents")
    assert [e["detail"]["code"] for e in events] == ["origin_not_allowed"], events
    shoot(page, "refused", tmp_path)


def test_a_secret_key_in_the_page_is_refused(shops, page_factory):
    page, _ = page_factory(DESKTOP)
    answers = []
    page.on("response", lambda r: answers.append((r.status, r.url)))
    page.goto(shops["a_origin"] + "/secret")
    page.wait_for_function(f"({STEP})() === 'refused'")
    text = page.locator("catwalk-tryon .notice").inner_text()
    assert "secret key" in text and "publishable key" in text, text
    refused = [s for s, u in answers if "/api/" in u]
    assert refused == [403], answers
    events = page.evaluate("window.shopEvents")
    assert [e["detail"]["code"] for e in events] == ["secret_key_exposed"], events


def test_the_editor_shows_the_key_and_sets_the_origins(shops, page_factory, tmp_path):
    """The merchant's editor (on the service's own origin, with the secret key) shows the
    publishable key and the snippet, and saves the origins (checked by the service)."""
    page, console = page_factory(DESKTOP)
    page.goto(shops["service"] + "/merchant")
    page.get_by_label("API key").fill(shops["a"]["key"])
    page.get_by_role("button", name="Log in").click()
    panel = page.locator(".mp-shop")
    panel.locator(".mp-pk").get_by_text(shops["a"]["pk"]).wait_for()
    snippet = panel.locator(".mp-snippet").inner_text()
    assert f'{shops["service"]}/embed/v1/catwalk.js' in snippet and shops["a"]["pk"] in snippet
    area = panel.get_by_label("Your shop’s addresses (origins), one a line")
    assert area.input_value() == shops["a_origin"]
    area.fill(f"{shops['a_origin']}\nhttps://Shop.Example/")
    panel.get_by_role("button", name="Save the addresses").click()
    panel.get_by_text("Saved: the key works from these 2 addresses.").wait_for()
    assert area.input_value() == f"{shops['a_origin']}\nhttps://shop.example"
    area.fill("https://shop.example/cart")
    panel.get_by_role("button", name="Save the addresses").click()
    panel.get_by_text("an origin is the scheme, host and port only").wait_for()
    area.fill(shops["a_origin"])
    panel.get_by_role("button", name="Save the addresses").click()
    panel.get_by_text("Saved: the key works from this address.").wait_for()
    panel.scroll_into_view_if_needed()
    shoot(page, "editor", tmp_path)
    assert [e for e in console.errors if "422" not in e] == []


def test_the_component_is_small_besides_three(frontend_dist):
    """Its own files (the entry and the player's chunk) gzip to at most 200 kB; three.js is a
    chunk of its own, fetched only once a try-on is asked for (the entry does not import it)."""
    from catwalk.bench.player import embed_sizes

    built = frontend_dist / "embed" / "v1"
    sizes = embed_sizes(built)
    assert sizes["own_gzip_bytes"] <= 200_000, sizes
    assert sizes["three_gzip_bytes"] > 100_000, sizes                 # three.js is there
    entry = (built / "catwalk.js").read_text()
    three = next(p.name for p in (built / "chunks").glob("three-*.js"))
    assert three not in entry and re.search(r"import\([`'\"]\./chunks/player-view-", entry)
