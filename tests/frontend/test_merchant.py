"""The merchant's garment editor (/merchant) in a real browser against a real ``catwalk serve``:
an API key made with ``catwalk merchant create``, a Gerber-style DXF of a two-piece skirt
imported, the pieces described, dragged, moved, mirrored and rotated (and undone), a save
refused with its problem shown on the pieces, two side seams sewn (by clicking vertices, and by
numbers), a custom fabric and a texture set, the garment saved and dressed on the sample body
(the preview's 3D view, fit map and report), published and found on the catalogue; a key
refused in the middle of an edit keeps the unsaved changes for after logging in again; a second
version keeps the texture it did not resend; logging out. The catalogue's pencil skirt (a fold,
a mirrored copy) opens in the editor and mirroring its back renumbers the seams exactly as
``catwalk garment edit`` does. The pages fit a phone.

Screenshots for docs/merchants.md: with ``CATWALK_TEST_SCREENSHOTS=1`` they are written to
docs/img/merchant-*.png (else into the test's temporary folder)."""

from __future__ import annotations

import os
import subprocess
import sys
import time
from pathlib import Path

import httpx
import pytest
from playwright.sync_api import expect

from service.helpers import REPO, Proc, free_port, service_env

from .conftest import FRONTEND, PHONE

DOCS_IMG = REPO / "docs" / "img"
W_MM, H_MM = 550.0, 600.0   # each piece: 55 cm wide (the skirt goes round the hips), 60 cm long
TEXTURE = REPO / "garments" / "textures" / "denim-twill.png"


def write_skirt_dxf(path: Path) -> Path:
    """A Gerber AccuMark-style DXF R12: one BLOCK per piece (boundary on layer 1 as two open
    POLYLINEs chained end to end, the second drawn backwards; grain line on layer 7; TEXTs
    'Piece Name:', 'Size:', 'Quantity:'), placed by INSERTs; file-level 'Units: METRIC' (mm)."""
    import ezdxf

    doc = ezdxf.new("R12")
    for i, name in enumerate(("FRONT", "BACK")):
        blk = doc.blocks.new(name=f"{name}_M")
        pts = [(0.0, 0.0), (W_MM, 0.0), (W_MM, H_MM), (0.0, H_MM), (0.0, 0.0)]
        blk.add_polyline2d(pts[:3], dxfattribs={"layer": "1"})
        blk.add_polyline2d(list(reversed(pts[2:])), dxfattribs={"layer": "1"})
        blk.add_line((W_MM / 2, 50.0), (W_MM / 2, H_MM - 100.0), dxfattribs={"layer": "7"})
        for k, (text, y) in enumerate(((f"Piece Name: {name}", 10), ("Size: M", 20),
                                       ("Quantity: 1", 30))):
            blk.add_text(text, dxfattribs={"layer": "1", "height": 5, "insert": (10, y + k)})
        doc.modelspace().add_blockref(f"{name}_M", (i * 700.0, 0.0))
    doc.modelspace().add_text("Style Name: WRAP01", dxfattribs={"layer": "1", "insert": (0, -40)})
    doc.modelspace().add_text("Units: METRIC", dxfattribs={"layer": "1", "insert": (0, -50)})
    doc.saveas(path)
    return path


@pytest.fixture(scope="module")
def fresh_dist(frontend_dist) -> Path:
    """frontend/dist, built again when a source file is newer (the merchant pages are new)."""
    built = (frontend_dist / "index.html").stat().st_mtime
    src = [p for p in (FRONTEND / "src").rglob("*") if p.is_file()] + [FRONTEND / "index.html"]
    if any(p.stat().st_mtime > built for p in src):
        r = subprocess.run(["npm", "run", "build"], cwd=FRONTEND, capture_output=True, text=True)
        assert r.returncode == 0, (r.stdout + r.stderr)[-3000:]
    return frontend_dist


@pytest.fixture(scope="module")
def shop(tmp_path_factory, one_garment_catalogue, fresh_dist):
    """``catwalk serve`` (one local worker) serving the pages, and a merchant's key made as an
    operator makes it: ``(base URL, key)``."""
    tmp = tmp_path_factory.mktemp("shop")
    env = service_env(tmp / "storage", one_garment_catalogue, frontend_dir=fresh_dist)
    port = free_port()
    proc = Proc(["serve", f"--port={port}", "--workers=1"], env, tmp / "serve.log")
    try:
        proc.wait_for('"api_ready"', timeout=180)
        out = subprocess.run([sys.executable, "-m", "catwalk.cli.main", "merchant", "create",
                              "atelier-test"], env=env, capture_output=True, text=True,
                             timeout=120, cwd=REPO)
        assert out.returncode == 0, out.stdout + out.stderr
        key = out.stdout.strip().splitlines()[-1]
        assert key.startswith("cwk_"), out.stdout
        yield f"http://127.0.0.1:{port}", key
    finally:
        proc.stop()


def shoot(page, name: str, tmp_path: Path, at=None) -> None:
    """docs/img/merchant-NAME.png (or the temporary folder): the whole page, or the window
    scrolled to the locator ``at`` (the editor's pattern view stays at the top of the window)."""
    folder = DOCS_IMG if os.environ.get("CATWALK_TEST_SCREENSHOTS") else tmp_path
    folder.mkdir(parents=True, exist_ok=True)
    path = folder / f"merchant-{name}.png"
    if at is None:
        page.screenshot(path=str(path), full_page=True)
    else:
        at.scroll_into_view_if_needed()
        page.evaluate("(y) => window.scrollTo(0, y)", at.evaluate(
            "(el) => el.getBoundingClientRect().top + window.scrollY - 12"))
        page.wait_for_timeout(300)
        page.screenshot(path=str(path))
    assert path.stat().st_size > 5_000


def editor_garment(page) -> dict:
    return page.evaluate("__catwalk.merchantEditor.garment()")


def back_v0(page) -> list[float]:
    """Vertex 0 of the back (size M) in the editor."""
    return editor_garment(page)["panels"][1]["shapes"]["M"]["outline"][0]["start"]


def outline(garment: dict, panel: str, size: str) -> list[dict]:
    return next(p for p in garment["panels"] if p["name"] == panel)["shapes"][size]["outline"]


def vertex(page, panel: str, v: int):
    return page.locator(f'circle.pv-vertex[data-panel="{panel}"][data-vertex="{v}"]'
                        ':not([data-ghost])')


def sew(page, a: str, a0: int, a1: int, b: str, b0: int, b1: int, name: str) -> str:
    """Click a's run a0 → a1 and b's run b0 → b1, flip the pairing, name it, add it; the
    lengths line shown before adding."""
    for panel, v in ((a, a0), (a, a1), (b, b0), (b, b1)):
        vertex(page, panel, v).click()
    diff = page.locator(".mp-diff").inner_text()
    page.get_by_role("button", name="Flip direction", exact=True).click()
    flip = page.get_by_role("button", name="Flip direction", exact=True)
    assert flip.get_attribute("aria-pressed") == "true"
    page.get_by_label("Seam name").fill(name)
    page.get_by_role("button", name="Add seam").click()
    return diff


def wait_dressed(page, timeout: float = 1500.0) -> str:
    """Until the preview's size is dressed (or failed); its status."""
    t0 = time.monotonic()
    while time.monotonic() - t0 < timeout:
        status = page.locator(".mp-preview__status").get_attribute("data-status")
        if status in ("dressed", "failed"):
            return status
        time.sleep(1.0)
    raise AssertionError(f"not dressed after {timeout:g} s: "
                         f"{page.locator('.mp-preview__status').inner_text()}")


def test_merchant_editor_import_sew_save_dress_publish(shop, page_factory, tmp_path):
    site, key = shop
    page, console = page_factory()
    dxf = write_skirt_dxf(tmp_path / "wrap-skirt.dxf")

    # --- the login: a wrong key is refused, the right one kept in sessionStorage only
    page.goto(site + "/merchant")
    page.get_by_label("API key").fill("cwk_not-a-key")
    page.get_by_role("button", name="Log in").click()
    expect(page.get_by_text("key not accepted")).to_be_visible()
    shoot(page, "login", tmp_path)
    page.get_by_label("API key").fill(key)
    page.get_by_role("button", name="Log in").click()
    page.get_by_role("heading", name="Your garments").wait_for()
    page.get_by_text("No garments yet").wait_for()
    assert page.evaluate("sessionStorage.getItem('catwalk.merchantKey')") == key
    assert key not in page.evaluate("JSON.stringify(Object.assign({}, localStorage))")

    # --- import the DXF: two pieces, drawn side by side to scale
    page.get_by_label("DXF file").set_input_files(str(dxf))
    page.get_by_role("button", name="Import").click()
    page.wait_for_selector(".merchant-editor .pv-piece[data-panel='BACK']")
    assert page.locator(".pv-piece").count() == 2
    g = editor_garment(page)
    assert [p["name"] for p in g["panels"]] == ["FRONT", "BACK"]
    assert g["sizes"] == ["M"] and g["seams"] == [] and g["type"] == "other"
    front = [s["start"] for s in g["panels"][0]["shapes"]["M"]["outline"]]
    back = [s["start"] for s in g["panels"][1]["shapes"]["M"]["outline"]]
    # laid out: front from x = 5 cm, back 5 cm to its right, both standing on y = 0
    assert front[0] == pytest.approx([0.05, 0.0]) and front[2] == pytest.approx([0.6, 0.6])
    assert back[0] == pytest.approx([0.65, 0.0])

    # the garment: name and type
    page.get_by_label("Garment name").fill("Wrap skirt")
    page.get_by_label("Garment type").select_option("skirt")
    assert page.locator("h1.mp-title").inner_text() == "Wrap skirt"

    # the pieces: type, position on the body, a texture on the front
    for name, side in (("FRONT", "front"), ("BACK", "back")):
        page.locator(".mp-piece", has_text=name).click()
        page.get_by_label("Piece type").select_option("skirt")
        page.get_by_label("Body part").select_option("legs")
        page.get_by_label("Side", exact=True).select_option(side)
        page.get_by_label("Anchor landmark").fill("waist")
        page.get_by_label("Anchor landmark").press("Tab")
    page.locator(".mp-piece", has_text="FRONT").click()
    page.get_by_label("Image (PNG or JPEG)").set_input_files(str(TEXTURE))
    page.wait_for_selector(".mp-tex")
    page.get_by_label("One repeat, width (cm)").fill("5")
    page.get_by_label("One repeat, width (cm)").press("Tab")
    page.get_by_label("Height (cm)").fill("5")
    page.get_by_label("Height (cm)").press("Tab")

    # move the back by dragging it 80 px right, then back with the numbers (cm)
    scale = page.evaluate("__catwalk.merchantEditor.view.scale")     # px per metre
    box = page.locator(".pv-piece[data-panel='BACK'] .pv-outline").bounding_box()
    cx, cy = box["x"] + box["width"] / 2, box["y"] + box["height"] / 2
    page.mouse.move(cx, cy)
    page.mouse.down()
    page.mouse.move(cx + 40, cy, steps=4)
    page.mouse.move(cx + 80, cy, steps=4)
    page.mouse.up()
    moved = editor_garment(page)["panels"][1]["shapes"]["M"]["outline"][0]["start"]
    assert moved[0] == pytest.approx(0.65 + 80 / scale, abs=2e-3)
    assert moved[1] == pytest.approx(0.0, abs=1e-9)
    page.get_by_label("Right by").fill(str(-80 / scale * 100))
    page.get_by_role("button", name="Move", exact=True).click()
    back0 = editor_garment(page)["panels"][1]["shapes"]["M"]["outline"][0]["start"]
    assert back0 == pytest.approx([0.65, 0.0], abs=2e-3)
    # mirror and rotate, then undo both: the pieces are as imported
    page.get_by_role("button", name="Mirror left ↔ right").click()
    assert back_v0(page)[0] == pytest.approx(back0[0] + 0.55, abs=1e-6)
    page.get_by_label("Degrees, counter-clockwise").fill("90")
    page.get_by_role("button", name="Rotate", exact=True).click()
    page.get_by_role("button", name="Undo").click()
    page.get_by_role("button", name="Undo").click()
    assert back_v0(page) == pytest.approx(back0)

    # --- a save without seams is refused; the problem names the piece, drawn in red
    page.get_by_role("button", name="Save", exact=True).click()
    problems = page.locator(".mp-problems")
    problems.wait_for()
    assert "not reachable" in problems.inner_text()
    assert page.locator(".pv-piece.has-problem").count() >= 1
    shoot(page, "problems", tmp_path, at=page.locator(".mp-save"))

    # --- the side seams: front's right side (1 → 2) to the back's left (3 → 0), and front's
    # left (3 → 0) to the back's right (1 → 2); each pair flipped so hem meets hem
    page.get_by_role("button", name="Sew seams").first.click()
    diff = sew(page, "FRONT", 1, 2, "BACK", 3, 0, "side left")
    assert "60.0 cm and 60.0 cm, difference 0.0 %" in diff, diff
    # the other by numbers, as with the keyboard
    page.get_by_text("Or choose the vertices by number").click()
    first = page.locator(".mp-bynumber fieldset").nth(0)
    first.get_by_label("Piece").select_option("FRONT")
    first.get_by_label("First vertex").select_option("3")
    first.get_by_label("Last vertex").select_option("0")
    first.get_by_role("button", name="Set the first side").click()
    second = page.locator(".mp-bynumber fieldset").nth(1)
    second.get_by_label("Piece").select_option("BACK")
    second.get_by_label("First vertex").select_option("1")
    second.get_by_label("Last vertex").select_option("2")
    second.get_by_role("button", name="Set the second side").click()
    assert "60.0 cm and 60.0 cm" in page.locator(".mp-diff").inner_text()
    page.get_by_role("button", name="Flip direction", exact=True).click()
    page.get_by_label("Seam name").fill("side right")
    page.get_by_role("button", name="Add seam").click()
    g = editor_garment(page)
    assert [(s["a"], s["b"], s["reverse"]) for s in g["seams"]] == [
        ({"panel": "FRONT", "start": 1, "end": 2}, {"panel": "BACK", "start": 3, "end": 0}, True),
        ({"panel": "FRONT", "start": 3, "end": 0}, {"panel": "BACK", "start": 1, "end": 2}, True),
    ]
    assert g["seams"][0]["name"] == "side left"
    assert page.locator("table.mp-seams tbody tr").count() == 2
    assert page.locator(".pv-seam").count() == 4      # two runs a seam
    shoot(page, "seams", tmp_path, at=page.locator(".mp-layout"))

    # --- the fabric: a catalogue preset (denim: a stiff one that dresses this simple tube cleanly)
    page.get_by_label("Fabric of the garment").select_option("denim")
    assert editor_garment(page)["fabric"] == "denim"
    # … made custom: denim with its own density
    page.get_by_text("Custom", exact=True).click()
    assert editor_garment(page)["fabric"] == {"base": "denim"}
    page.get_by_label("Density (kg/m²)").fill("0.4")
    page.get_by_label("Density (kg/m²)").press("Tab")
    assert editor_garment(page)["fabric"] == {"base": "denim", "density": 0.4}
    page.get_by_role("button", name="Select & move").click()
    front_button = page.locator(".mp-piece", has_text="FRONT")
    if front_button.get_attribute("aria-pressed") != "true":
        front_button.click()
    assert page.locator(".pv-vertex-label").count() == 4               # its vertices, numbered
    shoot(page, "editor", tmp_path, at=page.locator(".mp-layout"))

    # --- save: version 1, then each size dressed on its sample body
    page.get_by_role("button", name="Save", exact=True).click()
    page.get_by_text("Saved: version 1").wait_for(timeout=120_000)
    assert page.locator(".mp-problems").count() == 0
    status = wait_dressed(page)
    report = page.locator(".mp-report").inner_text()
    assert status == "dressed", (page.locator(".mp-preview__status").inner_text(), report)
    page.wait_for_function("() => window.__catwalk && window.__catwalk.merchantPreview",
                           timeout=120_000)
    expect(page.locator(".mp-preview__view canvas")).to_be_visible()
    assert "Widest seam gap" in report and "Largest stretch" in report, report
    page.get_by_role("button", name="Fit map", exact=True).click()
    expect(page.locator(".mp-preview .legend")).to_be_visible()
    page.wait_for_timeout(1500)                       # a few frames (software WebGL)
    shoot(page, "preview", tmp_path, at=page.locator(".mp-preview"))

    # --- publish, then the garment is on the catalogue
    page.get_by_role("button", name="Publish version 1").click()
    page.get_by_text("Published version 1").wait_for()
    page.get_by_role("link", name="Open the catalogue").click()
    page.wait_for_url(site + "/")
    page.locator(".card__title", has_text="Wrap skirt").wait_for(timeout=60_000)
    items = httpx.get(f"{site}/api/garments").json()["garments"]
    gid = next(i["id"] for i in items if i["name"] == "Wrap skirt")

    # --- the list: version 1 published, its size dressed; open it again
    page.goto(site + "/merchant")
    row = page.locator(f"tr[data-id='{gid}']")
    row.wait_for()
    assert row.locator("td").nth(1).inner_text() == "1"
    assert row.locator("td").nth(2).inner_text() == "Version 1"
    assert row.locator("li[data-size='M']").get_attribute("data-status") == "dressed"
    shoot(page, "list", tmp_path)
    row.get_by_role("button", name="Open Wrap skirt").click()
    page.wait_for_selector(".merchant-editor .pv-piece[data-panel='BACK']")
    assert len(editor_garment(page)["seams"]) == 2
    # its texture, fetched with the key, fills the front
    page.wait_for_selector(".pv-piece[data-panel='FRONT'] .pv-outline[style*='url(']")

    # a second version without resending the texture keeps it (the list shows version 2)
    page.get_by_label("Description").fill("A wrap skirt in two pieces.")
    page.get_by_label("Description").press("Tab")
    # the key refused in the middle of editing (revoked, say): the login form, and after
    # logging in again the unsaved changes are offered back
    page.evaluate("sessionStorage.setItem('catwalk.merchantKey', 'cwk_revoked')")
    page.get_by_role("button", name="Save as a new version").click()
    page.get_by_label("API key").wait_for()
    expect(page.get_by_text("key not accepted")).to_be_visible()
    assert page.evaluate("sessionStorage.getItem('catwalk.merchantKey')") is None
    page.get_by_label("API key").fill(key)
    page.get_by_role("button", name="Log in").click()
    page.get_by_role("button", name="Back to the editor").click()
    assert page.get_by_label("Description").input_value() == "A wrap skirt in two pieces."
    page.get_by_role("button", name="Save as a new version").click()
    page.get_by_text("Saved: version 2").wait_for(timeout=120_000)
    auth = {"Authorization": f"Bearer {key}"}
    g2 = httpx.get(f"{site}/api/merchant/garments/{gid}", headers=auth).json()["garment"]
    tex = next(p["texture"]["image"] for p in g2["panels"] if p["name"] == "FRONT")
    got = httpx.get(f"{site}/api/merchant/garments/{gid}/versions/2/files/{tex}", headers=auth)
    assert got.status_code == 200 and got.content == TEXTURE.read_bytes()

    # --- a key the server does not accept when the page opens: back to the login form
    page.evaluate("sessionStorage.setItem('catwalk.merchantKey', 'cwk_revoked')")
    page.goto(site + "/merchant")
    page.get_by_label("API key").wait_for()
    expect(page.get_by_text("key not accepted")).to_be_visible()
    assert page.evaluate("sessionStorage.getItem('catwalk.merchantKey')") is None

    # --- log in again, log out
    page.get_by_label("API key").fill(key)
    page.get_by_role("button", name="Log in").click()
    page.get_by_role("button", name="Log out").click()
    page.get_by_label("API key").wait_for()
    assert page.evaluate("sessionStorage.getItem('catwalk.merchantKey')") is None

    # the refused key (401) and the refused save (422) are the only failed requests
    assert [e for e in console.errors
            if not ("Failed to load resource" in e and ("401" in e or "422" in e))] == []


def test_merchant_editor_mirrors_a_catalogue_garment_as_the_backend_does(shop, page_factory):
    """The pencil skirt (a front cut on the fold, a back and its mirrored copy, darts) uploaded
    over the API opens in the editor with the fold's mirrored half and the copy drawn and its
    side seams joining hem to hem; mirroring the back in the editor renumbers the seams exactly
    as ``catwalk garment edit --mirror x`` does, and the server accepts the result."""
    import json

    from catwalk.exchange.garment_json import garment_from_dict, garment_to_dict
    from catwalk.garment.edit import edit

    site, key = shop
    auth = {"Authorization": f"Bearer {key}"}
    skirt = json.loads((REPO / "garments" / "pencil-skirt.json").read_text())
    skirt["name"] = "Pencil skirt (editor test)"
    tex = REPO / "garments" / "textures" / "suiting-check.png"
    res = httpx.post(f"{site}/api/merchant/garments", headers=auth, timeout=120, files=[
        ("garment", ("garment.json", json.dumps(skirt).encode(), "application/json")),
        ("files", ("textures/suiting-check.png", tex.read_bytes(), "image/png"))])
    assert res.status_code == 201, res.text
    gid = res.json()["id"]

    page, console = page_factory()
    page.goto(site + "/merchant")
    page.get_by_label("API key").fill(key)
    page.get_by_role("button", name="Log in").click()
    page.get_by_role("button", name="Open Pencil skirt (editor test)").click()
    page.wait_for_selector(".merchant-editor .pv-piece[data-panel='back_left']")
    assert page.locator(".pv-ghost").count() == 1                  # the front's other half
    assert page.locator(".pv-piece.is-copy").count() == 1          # back_left
    assert page.locator("table.mp-seams tbody tr").count() == 11
    # every link of the side seams joins two points at one height (hem to hem, waist to waist)
    links = page.evaluate("""() => __catwalk.merchantEditor.view.scene.seams
        .filter(s => s.index === 8 || s.index === 9).flatMap(s => s.links)""")
    assert len(links) == 4
    for p, q in links:
        assert p[1] == pytest.approx(q[1], abs=0.01), links

    # mirror the back left ↔ right: the seams as the backend's edit renumbers them
    page.locator(".mp-piece[data-key='piece-back_right']").click()
    page.get_by_role("button", name="Mirror left ↔ right").click()
    mine = page.evaluate("__catwalk.merchantEditor.garment()")
    g = garment_from_dict(json.loads(json.dumps(skirt)))
    theirs = garment_to_dict(edit(g, "back_right", mirror="x"))
    assert [(s["a"], s["b"], s["reverse"]) for s in mine["seams"]] == \
        [(s["a"], s["b"], s["reverse"]) for s in theirs["seams"]]
    for size in skirt["sizes"]:
        a = outline(mine, "back_right", size)
        b = outline(theirs, "back_right", size)
        assert [s["type"] for s in a] == [s["type"] for s in b]
        for sa, sb in zip(a, b, strict=True):
            assert sa["start"] == pytest.approx(sb["start"], abs=1e-6)
            flat = [x for c in sa.get("controls", []) for x in c]
            assert flat == pytest.approx([x for c in sb.get("controls", []) for x in c], abs=1e-6)

    # the checker agrees: version 2 is accepted (the texture kept from version 1)
    page.get_by_role("button", name="Save as a new version").click()
    page.get_by_text("Saved: version 2").wait_for(timeout=120_000)
    assert page.locator(".mp-problems").count() == 0
    assert httpx.get(f"{site}/api/merchant/garments/{gid}/versions/2/files/"
                     "textures/suiting-check.png", headers=auth).status_code == 200
    assert console.errors == []


def test_merchant_editor_shows_what_a_real_exports_import_repaired(shop, page_factory,
                                                                    tmp_path):
    """A CLO export with every class of issue 46 (cm under 'Units: METRIC', the sample size's
    'Quantity: 0', a pocket of sizes M and L, repeated points, small loops) imported in the
    editor: every repair and assumption listed above the pattern and on its piece (also once
    uploaded with its markup and opened again); the pocket not drawn in size S."""
    import json

    from garment.dxf_fixtures import real_export_markup, write_real_export

    site, key = shop
    dxf = write_real_export(tmp_path / "real-export.dxf")
    page, console = page_factory()
    page.goto(site + "/merchant")
    page.get_by_label("API key").fill(key)
    page.get_by_role("button", name="Log in").click()
    page.get_by_role("heading", name="Your garments").wait_for()
    page.get_by_label("DXF file").set_input_files(str(dxf))
    page.get_by_role("button", name="Import").click()
    page.wait_for_selector(".merchant-editor .pv-piece[data-panel='POCKET']")
    told = page.locator(".mp-import__warnings li").all_inner_texts()
    assert len(told) == 12 and sum("crossed itself in a small loop" in t for t in told) == 6
    assert any("read in centimetres instead" in t for t in told)
    g = editor_garment(page)
    assert g["sizes"] == ["S", "M", "L"] and sorted(g["panels"][2]["shapes"]) == ["L", "M"]
    # the pieces that were repaired are marked; the pocket says what was assumed, and its sizes
    assert page.locator(".mp-piece.has-warning").count() == 3
    page.locator(".mp-piece[data-key='piece-POCKET']").click()
    on_piece = page.locator("[data-key='p-import-warnings'] li").all_inner_texts()
    assert on_piece == [
        "size M: 'Quantity: 0' read as 1, as in size L (no 'Quantity:' text there): an "
        "export's mark on its sample size, not 'do not cut'",
        "in sizes M, L only (not in size S): imported in those sizes"]
    assert page.locator("[data-key='p-sizes']").inner_text() == \
        "Cut in sizes M, L only (not in S)."
    page.locator(".mp-piece[data-key='piece-BACK']").click()
    on_piece = page.locator("[data-key='p-import-warnings'] li").all_inner_texts()
    assert "size M: 2 repeated boundary point(s) dropped (the same point twice in a row, " \
           "within 0.05 mm: an edge of no length)" in on_piece
    shoot(page, "import-warnings", tmp_path, at=page.locator("#mp-piece-title"))
    page.get_by_label("Pieces of size").select_option("S")
    expect(page.locator(".pv-piece[data-panel='POCKET']")).to_have_count(0)
    assert "not in S" in page.locator(".mp-piece[data-key='piece-POCKET']").inner_text()
    page.get_by_label("Pieces of size").select_option("M")

    # uploaded with its markup over the API (201, its warnings), opened again: still on the pieces
    auth = {"Authorization": f"Bearer {key}"}
    res = httpx.post(f"{site}/api/merchant/garments", headers=auth, timeout=120, files=[
        ("dxf", (dxf.name, dxf.read_bytes(), "application/dxf")),
        ("markup", ("markup.json", json.dumps(real_export_markup()).encode(),
                    "application/json"))])
    assert res.status_code == 201, res.text
    assert {w["code"] for w in res.json()["warnings"]} >= {"units", "loop-removed", "sizes"}
    page.once("dialog", lambda d: d.accept())   # leave the unsaved import
    page.get_by_role("link", name="‹ All garments").click()
    page.get_by_role("button", name="Open Real export skirt").click()
    page.wait_for_selector(".merchant-editor .pv-piece[data-panel='pocket']")
    page.locator(".mp-piece[data-key='piece-back_right']").click()   # a copy: its source's
    assert page.locator("[data-key='p-import-warnings'] .notice__title").inner_text() == \
        "The import of back_left says"
    assert len(page.locator("[data-key='p-import-warnings'] li").all_inner_texts()) == 5
    page.get_by_label("Pieces of size").select_option("S")   # the pocket's seam: not in S
    assert "not sewn in S (no pocket)" in page.locator("tr[data-seam='3']").inner_text()
    assert console.errors == []


def test_merchant_pages_at_a_phone_size(shop, page_factory):
    """The login, the list and the editor (the pencil skirt uploaded by the test before, or
    any garment) fit a 390 px wide phone: nothing wider than the screen."""
    site, key = shop
    auth = {"Authorization": f"Bearer {key}"}
    if not httpx.get(f"{site}/api/merchant/garments", headers=auth).json()["garments"]:
        skirt = (REPO / "garments" / "pencil-skirt.json").read_bytes()
        tex = (REPO / "garments" / "textures" / "suiting-check.png").read_bytes()
        res = httpx.post(f"{site}/api/merchant/garments", headers=auth, timeout=120, files=[
            ("garment", ("garment.json", skirt, "application/json")),
            ("files", ("textures/suiting-check.png", tex, "image/png"))])
        assert res.status_code == 201, res.text
    page, console = page_factory(PHONE)
    page.goto(site + "/merchant")
    page.get_by_label("API key").wait_for()
    assert page.evaluate("document.documentElement.scrollWidth") <= PHONE["width"]
    page.get_by_label("API key").fill(key)
    page.get_by_role("button", name="Log in").click()
    page.locator("tr[data-id]").first.wait_for()
    assert page.evaluate("document.documentElement.scrollWidth") <= PHONE["width"]
    page.locator("tr[data-id] button").first.click()
    page.wait_for_selector(".merchant-editor .pv-piece")
    assert page.evaluate("document.documentElement.scrollWidth") <= PHONE["width"]
    box = page.get_by_role("button", name="Sew seams").first.bounding_box()
    assert box["height"] >= 38
    assert console.errors == []
