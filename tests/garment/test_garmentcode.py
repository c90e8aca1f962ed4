from pathlib import Path

import numpy as np

from catwalk.exchange.garmentcode import euler_xyz, load_garmentcode
from catwalk.garment.check import check_garment
from catwalk.garment.model import cut_pieces

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
