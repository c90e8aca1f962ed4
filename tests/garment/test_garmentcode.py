import json
import math
from pathlib import Path

import numpy as np
import pytest

from catwalk.exchange.garmentcode import euler_xyz, garmentcode_to_garment, load_garmentcode
from catwalk.garment.check import check_garment
from catwalk.garment.model import cut_pieces
from catwalk.garment.place import place_panels

ROOT = Path(__file__).resolve().parents[2]
SPECS = ROOT / "garments" / "garmentcode"


def _spec(name):
    p = SPECS / f"{name}_specification.json"
    assert p.is_file(), f"{p} missing (the GarmentCode specifications are committed)"
    return p


def test_euler_matches_rz_ry_rx():
    r = euler_xyz([0, 0, 90])
    np.testing.assert_allclose(r @ [1, 0, 0], [0, 1, 0], atol=1e-12)


def test_shirt_converts_and_checks():
    g = load_garmentcode(_spec("shirt_mean"))
    rep = check_garment(g)
    assert rep.ok, rep.errors
    assert len(g.panels) == 8 and len(g.seams) == 18 and g.type == "shirt"
    sleeve = g.panel("left_sleeve_f")
    assert sleeve.type == "sleeve" and sleeve.placement.part == "left_arm"
    assert g.panel("right_btorso").placement.side == "back"
    # cm → m: the torso panels are ~0.1 m² each
    areas = {r["panel"]: r["area_m2"] for r in rep.panels}
    assert 0.08 < areas["left_ftorso"] < 0.13
    # stitched edges meet in 3D at the ends the direction says
    pieces, seams = cut_pieces(g)
    assert all(max(s[1], s[2]) < len(pieces[s[0]].flat.points) for s in seams)


def test_dress_gathers_declared():
    g = load_garmentcode(_spec("dress_pencil"))
    rep = check_garment(g)
    assert rep.ok, rep.errors
    gathers = [s for s in g.seams if s.kind == "gather"]
    assert len(gathers) == 9 and all(0.23 < s.ease < 0.26 for s in gathers)
    darts = [s for s in g.seams if s.kind == "dart"]
    assert len(darts) == 4 and all(s.reverse for s in darts)   # dart sides meet tip to tip


# female-M's landmarks (bodies/recipes.json, rigged: with its shoulder and hip joints)
FEMALE_M = {
    "neck_base": [0.0, 1.432, 0.039], "neck_side_left": [0.061, 1.432, 0.039],
    "neck_side_right": [-0.061, 1.432, 0.039], "bust": [0.0, 1.238, 0.056],
    "waist": [0.0, 1.112, 0.066], "hips": [0.0, 0.872, 0.019], "crotch": [0.0, 0.787, 0.037],
    "shoulder_left": [0.201, 1.375, 0.016], "shoulder_right": [-0.201, 1.375, 0.016],
    "arm_root_left": [0.161, 1.34, 0.021], "arm_root_right": [-0.161, 1.34, 0.021],
    "armpit_left": [0.165, 1.259, 0.032], "armpit_right": [-0.165, 1.259, 0.032],
    "elbow_left": [0.334, 1.146, 0.036], "elbow_right": [-0.334, 1.146, 0.036],
    "wrist_left": [0.442, 1.032, 0.166], "wrist_right": [-0.442, 1.032, 0.166],
    "leg_root_left": [0.099, 0.87, 0.018], "leg_root_right": [-0.099, 0.87, 0.018],
    "knee_left": [0.137, 0.474, 0.047], "knee_right": [-0.137, 0.474, 0.047],
    "ankle_left": [0.175, 0.071, 0.025], "ankle_right": [-0.175, 0.071, 0.025]}
GIRTHS = {"bust": 0.98, "waist": 0.80, "hips": 1.06}


def _inside(poly: np.ndarray, step: float = 0.01) -> np.ndarray:
    """Grid points (``step`` apart) inside the polygon (even-odd rule)."""
    lo, hi = poly.min(axis=0), poly.max(axis=0)
    gx, gy = np.meshgrid(np.arange(lo[0], hi[0], step), np.arange(lo[1], hi[1], step))
    p = np.stack([gx.ravel(), gy.ravel()], axis=1)
    a, b = poly, np.roll(poly, -1, axis=0)
    cross = ((a[:, 1] > p[:, 1, None]) != (b[:, 1] > p[:, 1, None])) & (
        p[:, 0, None] < a[:, 0] + (p[:, 1, None] - a[:, 1]) * (b[:, 0] - a[:, 0])
        / np.where(b[:, 1] == a[:, 1], 1.0, b[:, 1] - a[:, 1]))
    return p[cross.sum(axis=1) % 2 == 1]


def _placed(g):
    """Pieces, seams, each piece's outline as placed on female-M, and its inside (1 cm grid)."""
    pieces, seams = cut_pieces(g)
    pls = place_panels(g, FEMALE_M, g.default_size, GIRTHS)
    world = {pc.name: pl.to_world(pc.flat.points) for pc, pl in zip(pieces, pls, strict=True)}
    inner = {pc.name: pl.to_world(_inside(pc.flat.points))
             for pc, pl in zip(pieces, pls, strict=True)}
    return pieces, seams, world, inner


def _seam_end_gaps(pieces, seams, world, g, names, dims=(0, 1, 2)):
    """The distance between the two sides' ends of each named seam as placed (m; in world
    coordinates ``dims``)."""
    out = {}
    for s, (pa, sa, ea, pb, sb, eb, rev) in zip(g.seams, seams, strict=True):
        if s.name in names:
            a = world[pieces[pa].name][[sa, ea]][:, dims]
            b = world[pieces[pb].name][[eb, sb] if rev else [sb, eb]][:, dims]
            out[s.name] = float(np.linalg.norm(a - b, axis=1).max())
    return out


@pytest.mark.parametrize("side", ["left", "right"])
def test_mean_shirt_sleeves_are_placed_round_our_arm(side):
    """GarmentCode places its sleeve halves flat, 15 cm in front of and behind its own body's
    arm at 50° from vertical; they are re-placed round our arm (42° here): round its axis at
    the radius that closes them, the cap at the shoulder, front half in front."""
    g = load_garmentcode(_spec("shirt_mean"))
    pieces, seams, world, inner = _placed(g)
    root, elbow = (np.array(FEMALE_M[f"{k}_{side}"]) for k in ("arm_root", "elbow"))
    down = (elbow - root) / np.linalg.norm(elbow - root)
    radius = 2 * 0.2126 / (2 * math.pi)          # two halves 21.26 cm wide
    for half in ("f", "b"):
        pts = inner[f"{side}_sleeve_{half}"]
        t = (pts - root) @ down
        upper = pts[(t > 0.0) & (t < 0.8 * np.linalg.norm(elbow - root))]   # clear of the elbow
        assert len(upper) > 20
        rel = upper - root - np.outer((upper - root) @ down, down)
        np.testing.assert_allclose(np.linalg.norm(rel, axis=1), radius, atol=0.005)
        # front half in front of the arm's axis, back half behind
        z = rel[:, 2]
        assert (z > -0.01).all() if half == "f" else (z < 0.01).all()
        assert np.median(np.abs(z)) > 0.03
        # from the shoulder joint down the arm: the cap 0–2 cm above it, the cuff past the elbow
        assert abs(t.min()) < 0.02 and t.max() > np.linalg.norm(elbow - root)
    # the cap's top (where the two halves' top seam meets the armhole) near the shoulder
    f = next(pc for pc in pieces if pc.name == f"{side}_sleeve_f")
    cap_top = world[f.name][f.flat.vertex_index[1 if side == "left" else 3]]
    assert np.linalg.norm(cap_top - FEMALE_M[f"shoulder_{side}"]) < 0.03
    # the halves' top and underarm seams start closed (GarmentCode's placement on our body
    # left the top seam's sides 113° apart round the arm once they wrapped onto it)
    tube = [s.name for s in g.seams if {s.a.panel, s.b.panel} == {f"{side}_sleeve_f",
                                                                   f"{side}_sleeve_b"}]
    gaps = _seam_end_gaps(pieces, seams, world, g, tube)
    assert len(gaps) == 2 and max(gaps.values()) < 0.005, gaps


def test_jumpsuit_converts_and_its_legs_are_placed_round_ours():
    g = load_garmentcode(_spec("js_mean_all"))
    rep = check_garment(g)
    assert rep.ok, rep.errors
    assert len(g.panels) == 12 and len(g.seams) == 57 and g.type == "jumpsuit"
    assert g.panel("pant_f_l").placement.part == "left_leg"
    pieces, seams, world, inner = _placed(g)
    for side, sign in (("l", 1.0), ("r", -1.0)):
        knee = np.array(FEMALE_M[f"knee_{'left' if side == 'l' else 'right'}"])
        for half in ("f", "b"):
            pts = inner[f"pant_{half}_{side}"]
            near = pts[np.abs(pts[:, 1] - knee[1]) < 0.05]    # round the knee
            dz = (near[:, 2] - knee[2]) * (1.0 if half == "f" else -1.0)
            # (the back half, 35 cm of the leg's 65, reaches 2 cm round the inseam)
            assert (dz > -0.025).all() and np.median(dz) > 0.05
            assert (sign * (near[:, 0] - knee[0])).max() > 0.08   # the outseam outside
        # the hem is above the foot, the top where the bodice ends
        assert pts[:, 1].min() > FEMALE_M["ankle_left"][1]
    legs = [s.name for s in g.seams if g.panel(s.a.panel).type == g.panel(s.b.panel).type
            == "leg" and s.a.panel[-1] == s.b.panel[-1] and s.a.panel != s.b.panel]
    gaps = _seam_end_gaps(pieces, seams, world, g, legs)
    # in- and outseams (GarmentCode's placement: 45 cm apart on our body; now the halves'
    # different widths and waist heights leave 3–8 cm)
    assert len(gaps) == 6 and max(gaps.values()) < 0.1, gaps
    waist = [s.name for s in g.seams if {g.panel(s.a.panel).type, g.panel(s.b.panel).type}
             in ({"leg", "front"}, {"leg", "back"})]
    # the trouser halves' waist at the height of the bodice's bottom (their seams' ends
    # 3–14 cm apart, the bodice round a wider cylinder; GarmentCode's placement: 7–32 cm)
    heights = _seam_end_gaps(pieces, seams, world, g, waist, dims=[1])
    assert len(heights) == 15 and max(heights.values()) < 0.04, heights


def test_cuff_is_placed_past_its_sleeve():
    """A cuff (sewn only to its sleeve) is placed after it, where its seam to the sleeve is
    along the arm, and on the sleeve's limb."""
    spec = json.loads(_spec("shirt_mean").read_text())
    panels, stitches = spec["pattern"]["panels"], spec["pattern"]["stitches"]
    w = 21.259007137519678
    for fb, verts, cuff_edge, sleeve_edge, under, top in (
            ("f", [[0, 0], [0, -w], [5, -w], [5, 0]], 0, 3, 1, 3),
            ("b", [[0, 0], [5, 0], [5, -w], [0, -w]], 3, 0, 2, 0)):
        sl = panels[f"left_sleeve_{fb}"]
        panels[f"left_cuff_{fb}"] = {
            "translation": sl["translation"], "rotation": sl["rotation"], "vertices": verts,
            "edges": [{"endpoints": [k, (k + 1) % 4]} for k in range(4)]}
        stitches.append([{"panel": f"left_sleeve_{fb}", "edge": sleeve_edge},
                         {"panel": f"left_cuff_{fb}", "edge": cuff_edge}])
        if fb == "b":
            stitches += [[{"panel": "left_cuff_f", "edge": 1}, {"panel": "left_cuff_b",
                                                                 "edge": under}],
                         [{"panel": "left_cuff_f", "edge": 3}, {"panel": "left_cuff_b",
                                                                 "edge": top}]]
    spec["pattern"].pop("panel_order", None)
    g = garmentcode_to_garment(spec)
    assert g.panel("left_cuff_b").type == "cuff" and g.panel("left_cuff_b").placement.part \
        == "left_arm"
    pieces, seams, world, inner = _placed(g)
    root, wrist = np.array(FEMALE_M["arm_root_left"]), np.array(FEMALE_M["wrist_left"])
    for fb in ("f", "b"):   # down the arm from the sleeve, short of the wrist
        cuff = np.linalg.norm(inner[f"left_cuff_{fb}"].mean(axis=0) - root)
        sleeve = np.linalg.norm(inner[f"left_sleeve_{fb}"].mean(axis=0) - root)
        assert sleeve + 0.1 < cuff < np.linalg.norm(wrist - root)
    gaps = _seam_end_gaps(pieces, seams, world, g, [s.name for s in g.seams
                                                    if "cuff" in s.name])
    assert len(gaps) == 4 and max(gaps.values()) < 0.01, gaps


def test_mean_shirt_dresses_in_its_own_fabric():
    """The mean shirt as imported (cotton jersey) on female-M: every seam welded (its
    sleeves, placed as GarmentCode placed them, stayed open by 8 cm)."""
    from catwalk.catalogue.bodies import sample_body
    from catwalk.simulate.fitcheck import dressing_check

    g = load_garmentcode(_spec("shirt_mean"))
    assert g.fabric == "cotton-jersey"
    rep, _ = dressing_check(sample_body("female-M"), g, "M")
    assert rep["ok"], rep["message"]
    assert rep["seam_gap_mm"] == 0.0 and not rep["open_seams"]
