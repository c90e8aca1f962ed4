import json
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest

from catwalk.catalogue.garments import build_catalogue, catalogue_files
from catwalk.exchange.freesewing import ops_to_segments
from catwalk.exchange.garment_json import load_garment
from catwalk.garment.check import check_garment
from catwalk.garment.geometry import polygon_area, segment_lengths
from catwalk.garment.model import cut_pieces
from catwalk.garment.place import place_panels

from .helpers import cli

ROOT = Path(__file__).resolve().parents[2] / "garments"
LANDMARKS = {"neck_base": [0, 1.45, 0.0],
             "waist": [0, 1.05, 0.0], "shoulder_left": [0.19, 1.42, 0.0],
             "shoulder_right": [-0.19, 1.42, 0.0], "wrist_left": [0.25, 0.85, 0.0],
             "wrist_right": [-0.25, 0.85, 0.0]}


def test_catalogue_garments_check_in_every_size():
    files = catalogue_files(ROOT)
    names = {f.stem for f in files}
    assert {"dress", "tshirt", "pencil-skirt", "trousers", "bodice", "gc-shirt"} <= names
    for f in files:
        g = load_garment(f)
        rep = check_garment(g)
        assert rep.ok, (f.name, rep.errors)
        assert len(g.sizes) >= 3
        assert set(g.fit) == set(g.sizes)   # which sample body each size is for
        assert all(p.texture for p in g.panels)
        assert len(g.seams) >= len(g.panels) - 1
    # the paper's dress: front, back, two sleeves
    dress = load_garment(ROOT / "dress.json")
    assert sorted(p.type for p in dress.panels) == ["back", "front", "sleeve", "sleeve"]


def test_catalogue_is_graded():
    g = load_garment(ROOT / "tshirt.json")
    rep = check_garment(g)
    front = {r["size"]: r["area_m2"] for r in rep.panels if r["panel"] == "front"}
    assert front["S"] < front["M"] < front["L"]
    # a chest of 0.98 m with ~15 % ease: front + back widths at the hem ≈ 0.57 m per half
    assert 0.13 < front["M"] < 0.17


def test_catalogue_rebuild_is_reproducible(tmp_path):
    root = tmp_path / "garments"
    shutil.copytree(ROOT, root, ignore=shutil.ignore_patterns("node_modules", "*.json.tmp"))
    for f in root.glob("*.json"):
        f.unlink()
    build_catalogue(root)
    for f in catalogue_files(ROOT):
        assert json.loads((root / f.name).read_text()) == json.loads(f.read_text()), f.name


def test_freesewing_ops_are_flipped_and_counter_clockwise():
    # a 100 × 50 mm rectangle drawn clockwise in FreeSewing's axes (+y down)
    ops = [["M", 0, 0], ["L", 100, 0], ["L", 100, 50], ["L", 0, 50], ["Z"]]
    segs = ops_to_segments(ops, "test")
    from catwalk.garment.geometry import flatten
    pts = flatten(segs).points
    assert polygon_area(pts) == pytest.approx(0.005)
    assert pts[:, 1].max() == pytest.approx(0.0) and pts[:, 1].min() == pytest.approx(-0.05)
    np.testing.assert_allclose(segment_lengths(segs).sum(), 0.3)


def test_from_freesewing_cli_describe_and_markup(tmp_path, capsys):
    draft = ROOT / "freesewing" / "drafts" / "tshirt.json"
    code, out, _ = cli(["garment", "from-freesewing", str(draft), "--describe"], capsys)
    assert code == 0 and "teagan.front (fold edge 6)" in out
    bad = tmp_path / "m.json"
    m = json.loads((ROOT / "freesewing" / "markup" / "tshirt.json").read_text())
    m["seams"][0]["b"]["end"] = 3   # side seam to the armhole: far too long
    bad.write_text(json.dumps(m))
    code, _, err = cli(["garment", "from-freesewing", str(draft), "--markup", str(bad), "-o",
                        str(tmp_path / "t.json")], capsys)
    assert code == 2 and "seam 0 ('side left')" in err and not (tmp_path / "t.json").exists()


def test_place_panels_puts_pieces_round_the_body():
    g = load_garment(ROOT / "tshirt.json")
    pieces, seams = cut_pieces(g, "M")
    pls = place_panels(g, LANDMARKS, "M")
    world = {pc.name: pl.to_world(pc.flat.points) for pc, pl in zip(pieces, pls, strict=True)}
    assert world["front"][:, 2].min() > 0 and world["back"][:, 2].max() < 0
    assert world["sleeve_right"][:, 0].max() < -0.1 and world["sleeve_left"][:, 0].min() > 0.1
    # front and back hang from their high shoulder points at the neck's height (their
    # centre necks differ by 6 cm), so the shoulder seams start level
    assert world["front"][:, 1].max() == pytest.approx(1.45, abs=0.005)
    assert world["back"][:, 1].max() == pytest.approx(1.45, abs=0.005)
    with_sides = dict(LANDMARKS, neck_side_left=[0.06, 1.43, 0.0])
    pls2 = place_panels(g, with_sides, "M")
    front = next(i for i, p in enumerate(pieces) if p.name == "front")
    top = pls2[front].to_world(pieces[front].flat.points)[:, 1].max()
    assert top == pytest.approx(1.43, abs=0.005)
    # wrapping keeps lengths along the pattern's u (a cylinder is developable)
    for pc, pl in zip(pieces, pls, strict=True):
        lo, hi = pc.flat.points.min(axis=0), pc.flat.points.max(axis=0)
        u = np.linspace(lo[0], hi[0], 2001)
        line = pl.to_world(np.stack([u, np.full_like(u, 0.5 * (lo[1] + hi[1]))], axis=1))
        assert np.linalg.norm(np.diff(line, axis=0), axis=1).sum() == pytest.approx(
            hi[0] - lo[0], rel=1e-3)
        centre, d, radius = pl.cylinder
        rel = line - centre
        radial = rel - np.outer(rel @ d, d)
        np.testing.assert_allclose(np.linalg.norm(radial, axis=1), radius, rtol=1e-9)
    # sleeves close: the underarm seam ends meet after wrapping
    for pa, sa, ea, pb, sb, eb, rev in seams:
        if pieces[pa].name == pieces[pb].name == "sleeve_right":
            a = world["sleeve_right"][[sa, ea]]
            b = world["sleeve_right"][[eb, sb] if rev else [sb, eb]]
            assert np.linalg.norm(a - b, axis=1).max() < 1e-6


def test_node_draft_reproduces_committed_drafts(tmp_path):
    assert shutil.which("node") is not None, "node is not installed (make install)"
    assert (ROOT / "freesewing" / "node_modules").is_dir(), \
        "the FreeSewing packages are not installed (make install: npm ci in garments/freesewing)"
    res = subprocess.run(["node", str(ROOT / "freesewing" / "draft.mjs"), "--out", str(tmp_path),
                          "tshirt", "pencil-skirt"], capture_output=True, text=True, timeout=60)
    assert res.returncode == 0, res.stderr
    for gid in ("tshirt", "pencil-skirt"):
        assert (json.loads((tmp_path / f"{gid}.json").read_text())
                == json.loads((ROOT / "freesewing" / "drafts" / f"{gid}.json").read_text()))


@pytest.mark.parametrize("name", ["dress", "tshirt", "pencil-skirt", "trousers", "bodice",
                                  "gc-shirt"])
def test_seam_pairing_agrees_with_placement(name):
    """Each seam's ends meet the partner ends that the placed panels put nearer, not the
    opposite ones (catches a wrong ``reverse`` or ``half`` in the markup)."""
    g = load_garment(ROOT / f"{name}.json")
    pieces, seams = cut_pieces(g, "M")
    pls = place_panels(g, LANDMARKS, "M")
    world = [pl.to_world(pc.flat.points) for pc, pl in zip(pieces, pls, strict=True)]
    for i, (pa, sa, ea, pb, sb, eb, rev) in enumerate(seams):
        a, b = world[pa][[sa, ea]], world[pb][[sb, eb]]
        kept = np.linalg.norm(a - (b[::-1] if rev else b), axis=1).sum()
        flipped = np.linalg.norm(a - (b if rev else b[::-1]), axis=1).sum()
        assert kept <= flipped + 1e-9, (g.seams[i].name, kept, flipped)


def test_freesewing_lengths_are_our_bodies_and_up_to_date(tmp_path):
    """The lengths the FreeSewing drafts use are measured on our sample bodies (as committed
    in lengths.json) and are plausible for them."""
    from catwalk.catalogue.bodies import load_recipes
    from catwalk.catalogue.lengths import BODY_LENGTHS, freesewing_lengths

    committed = json.loads((ROOT / "freesewing" / "lengths.json").read_text())["bodies"]
    assert set(committed) == {r["name"] for r in load_recipes()}
    recipe = next(r for r in load_recipes() if r["name"] == "female-M")
    got = freesewing_lengths([recipe])["female-M"]
    assert set(got) == set(BODY_LENGTHS)  # a woman: every one, bustSpan too
    for k in BODY_LENGTHS:
        assert got[k] == pytest.approx(committed["female-M"][k], abs=1.0), k
    assert 0.6 * recipe["height"] * 1000 < got["waistToFloor"] < 0.7 * recipe["height"] * 1000
    assert got["inseam"] < got["waistToFloor"] and got["waistToKnee"] < got["waistToFloor"]
    assert 400 < got["shoulderToWrist"] < 650
    assert 220 < got["biceps"] < 400 and 150 < got["bustSpan"] < 260
    male = next(r for r in load_recipes() if r["name"] == "male-M")
    assert "bustSpan" not in freesewing_lengths([male])["male-M"]


def test_freesewing_lengths_cli_refuses_an_unwritable_output_at_once(tmp_path, capsys):
    blocker = tmp_path / "a-file"
    blocker.write_text("not a folder")
    code, _, err = cli(["garment", "freesewing-lengths", "-o", str(blocker / "lengths.json")],
                       capsys)
    assert code == 2 and "not a writable folder" in err
    assert blocker.read_text() == "not a folder" and list(tmp_path.iterdir()) == [blocker]
