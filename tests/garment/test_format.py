import json

import numpy as np
import pytest

from catwalk.errors import InputError
from catwalk.exchange.garment_json import (
    garment_from_dict,
    garment_to_dict,
    load_garment,
    save_garment,
)
from catwalk.garment.check import check_garment, require_valid
from catwalk.garment.geometry import (
    Segment,
    flatten,
    mirror_matrix,
    polygon_area,
    rotate_matrix,
    segment_lengths,
    transform_segments,
)
from catwalk.garment.model import Panel, Placement, Seam, SeamSide, Shape, cut_pieces

from .helpers import assert_only_input_errors, cli, rect, tube


def test_flatten_keeps_vertices_and_tolerance():
    segs = [Segment("line", np.array([0.0, 0.0])),
            Segment("cubic", np.array([1.0, 0.0]), [np.array([1.5, 0.5]), np.array([0.5, 1.0])]),
            Segment("quadratic", np.array([0.0, 1.0]), [np.array([-0.3, 0.5])])]
    coarse, fine = flatten(segs, 1e-2), flatten(segs, 1e-4)
    for f in (coarse, fine):
        np.testing.assert_allclose(f.points[f.vertex_index], [s.start for s in segs])
    assert len(fine.points) > len(coarse.points) > 3
    # every fine point is within the coarse tolerance of the coarse polyline
    a, b = coarse.points, np.roll(coarse.points, -1, axis=0)
    ab = b - a
    t = np.clip(np.einsum("pkd,kd->pk", fine.points[:, None] - a[None], ab)
                / np.einsum("kd,kd->k", ab, ab)[None], 0, 1)
    d = np.linalg.norm(fine.points[:, None] - (a[None] + t[..., None] * ab[None]), axis=2)
    assert d.min(axis=1).max() < 1e-2 * 1.01


def test_arc_bulge_half_circle_area_and_length():
    # a half disc of radius 1: the chord (2, 0) → (−1…) closed by a bulge-1 arc
    segs = [Segment("line", np.array([-1.0, 0.0])), Segment("arc", np.array([1.0, 0.0]), bulge=1.0)]
    f = flatten(segs, 1e-5)
    assert polygon_area(f.points) == pytest.approx(np.pi / 2, rel=1e-4)
    assert segment_lengths(segs)[1] == pytest.approx(np.pi, rel=1e-4)


def test_edits_move_rotate_mirror_keep_area_and_orientation():
    segs = rect(0.4, 0.6)
    a0 = polygon_area(flatten(segs).points)
    for m in (rotate_matrix(30, (0.2, 0.3)), mirror_matrix("x", 0.1), mirror_matrix("y")):
        out = transform_segments(segs, m)
        assert polygon_area(flatten(out).points) == pytest.approx(a0)   # still CCW
    mir = transform_segments(segs, mirror_matrix("x"))
    # vertex i of the mirror is the image of vertex (-i) mod n
    np.testing.assert_allclose(mir[1].start, [-segs[3].start[0], segs[3].start[1]])


def test_roundtrip_json(tmp_path):
    g = tube(sizes=("S", "M", "L"))
    g.panels[0].texture = {"image": "stripes.png", "size": [0.1, 0.1]}
    path = tmp_path / "g.json"
    save_garment(g, path)
    g2 = load_garment(path)
    assert garment_to_dict(g2) == garment_to_dict(g)
    assert g2.panels[0].placement.anchor == "bust"


def test_check_accepts_a_good_garment_and_reports_numbers():
    rep = check_garment(tube())
    assert rep.ok, rep.errors
    assert [r["area_m2"] for r in rep.panels] == [0.35, 0.35]
    assert all(r["difference"] == 0 for r in rep.seams)


def test_self_intersection_named():
    g = tube()
    bow = [Segment("line", np.array(p, float)) for p in [(0, 0), (0.5, 0.7), (0.5, 0), (0, 0.7)]]
    g.panels[0].shapes["M"] = Shape(bow)
    rep = check_garment(g)
    assert any("panel 'front' (size M): outline intersects itself: edges 0 and 2 cross" in e
               for e in rep.errors), rep.errors


def test_unclosed_outline_named():
    d = garment_to_dict(tube())
    d["panels"][1]["shapes"]["M"]["outline"][2]["end"] = [0.0, 0.75]
    rep = check_garment(garment_from_dict(d))
    assert any("panel 'back' (size M): outline not closed: edge 2 ends at" in e
               for e in rep.errors), rep.errors


def test_seam_length_mismatch_named():
    g = tube()
    g.panels[1].shapes["M"] = Shape(rect(0.5, 0.68))
    rep = check_garment(g)
    assert any("seam 0 ('left') (size M): lengths differ by 2.9 %" in e for e in rep.errors)
    g.seams[0].ease = 0.05
    g.seams[1].ease = 0.05
    assert check_garment(g).ok


def test_unreachable_panel_and_missing_fabric_and_texture(tmp_path):
    g = tube()
    g.panels.append(Panel("pocket", "pocket", {"M": Shape(rect(0.1, 0.1))}))
    g.panels[0].fabric = "no-such-cloth"
    g.panels[1].texture = {"image": "missing.png"}
    rep = check_garment(g, tmp_path)
    text = "\n".join(rep.errors)
    assert "panel(s) 'pocket' not reachable" in text
    assert "panel 'front': fabric: unknown fabric 'no-such-cloth'" in text
    assert "panel 'back': texture image 'missing.png' not found" in text
    with pytest.raises(InputError, match="3 problem"):
        require_valid(g, tmp_path)


def test_custom_fabric():
    g = tube()
    g.fabric = {"base": "denim", "density": 0.35}
    g.panels[0].fabric = {"id": "x", "name": "x", "density": 0.2, "stretch_warp": 100,
                          "stretch_weft": 80, "shear": 10, "bend_warp": 1e-6, "bend_weft": 1e-6}
    assert check_garment(g).ok
    g.panels[1].fabric = {"base": "denim", "density": -1}
    assert any("panel 'back': fabric" in e for e in check_garment(g).errors)


def test_seam_outside_outline_and_overlap():
    g = tube()
    g.seams.append(Seam(SeamSide("front", 1, 7), SeamSide("back", 0, 1)))
    assert any("vertices 1→7 are outside the outline" in e for e in check_garment(g).errors)
    g = tube()
    g.seams.append(Seam(SeamSide("front", 1, 2), SeamSide("back", 2, 3), name="again"))
    assert any("both use edge" in e for e in check_garment(g).errors)


def test_fold_and_mirror_copy_cut_pieces():
    half = Panel("front", "front", {"M": Shape(rect(0.25, 0.7))}, fold=3)
    back = Panel("back", "back", {"M": Shape(rect(0.5, 0.7))})
    g = tube()
    g.panels = [half, back]
    g.seams = [Seam(SeamSide("front", 1, 2), SeamSide("back", 3, 0), reverse=True),
               Seam(SeamSide("front", 1, 2, "mirror"), SeamSide("back", 1, 2))]
    assert check_garment(g).ok, check_garment(g).errors
    pieces, seams = cut_pieces(g)
    pts = pieces[0].flat.points
    assert polygon_area(pts) == pytest.approx(0.35)
    np.testing.assert_allclose(pts.min(axis=0), [-0.25, 0.0])
    # the mirrored side runs from (-0.25, 0.7) down to (-0.25, 0): flipped, so reverse is set
    pa, sa, ea, pb, sb, eb, rev = seams[1]
    np.testing.assert_allclose(pts[sa], [-0.25, 0.7])
    np.testing.assert_allclose(pts[ea], [-0.25, 0.0])
    assert rev is True
    # the paired ends: a's start meets b's end (both at the top)
    np.testing.assert_allclose(pieces[pb].flat.points[eb], [0.5, 0.7])


def test_mirror_copy_seam_indices():
    g = tube()
    g.panels.append(Panel("sleeve_l", "sleeve", {"M": Shape(rect(0.3, 0.2))},
                          placement=Placement(part="left_arm", side="left")))
    g.panels.append(Panel("sleeve_r", "sleeve", copy_of="sleeve_l", mirror=True,
                          placement=Placement(part="right_arm", side="right")))
    g.seams += [Seam(SeamSide("sleeve_l", 3, 0), SeamSide("front", 2, 3)),
                Seam(SeamSide("sleeve_r", 3, 0), SeamSide("back", 2, 3))]
    g.panels[0].shapes["M"] = Shape(rect(0.2, 0.2))  # top edges 0.2 m like the sleeve ends
    g.panels[1].shapes["M"] = Shape(rect(0.2, 0.2))
    assert check_garment(g).ok, check_garment(g).errors
    pieces, seams = cut_pieces(g)
    r = pieces[3].flat.points
    pa, sa, ea, *_ = seams[3]
    # sleeve_l run 3→0 is its left edge x=0 from y=0.2 down to 0; in the mirror it is x=0 too
    np.testing.assert_allclose(r[[sa, ea]][:, 0], [0.0, 0.0])
    assert seams[3][-1] is True  # walking backwards in the copy flips the pairing


def test_cli_check(tmp_path, capsys):
    path = tmp_path / "tube.json"
    save_garment(tube(), path)
    code, out, _ = cli(["garment", "check", str(path)], capsys)
    assert code == 0 and "ok" in out
    d = json.loads(path.read_text())
    d["seams"][0]["b"]["panel"] = "nope"
    path.write_text(json.dumps(d))
    code, _, err = cli(["garment", "check", str(path)], capsys)
    assert code == 2 and "seam 0, side b: no panel named 'nope'" in err
    path.write_text("{not json")
    code, _, err = cli(["garment", "check", str(path)], capsys)
    assert code == 2 and "not readable JSON" in err


def test_unfolded_curved_panel_is_symmetric_and_double():
    from pathlib import Path

    g = load_garment(Path(__file__).resolve().parents[2] / "garments" / "tshirt.json")
    pieces, _ = cut_pieces(g, "M", tolerance=1e-4)
    front = pieces[0]
    half = abs(polygon_area(flatten(g.panel("front").shapes["M"].outline, 1e-4).points))
    assert abs(polygon_area(front.flat.points)) == pytest.approx(2 * half, rel=1e-6)
    pts = front.flat.points
    mirrored = pts * [-1, 1]
    d = np.linalg.norm(pts[:, None] - mirrored[None], axis=2).min(axis=1)
    assert d.max() < 1e-9


def test_fold_half_crossing_the_fold_is_caught():
    g = tube()
    # a half whose top-left corner pokes across the fold line x = 0
    segs = [Segment("line", np.array(p, float)) for p in
            [(0, 0), (0.25, 0), (0.25, 0.7), (-0.05, 0.7), (0, 0.35)]]
    g.panels[0] = Panel("front", "front", {"M": Shape(segs)}, fold=4)
    rep = check_garment(g)
    assert any("opened on its fold: outline intersects itself" in e for e in rep.errors), \
        rep.errors


def test_cut_pieces_turn_grain_to_y():
    g = tube()
    g.panels[0].shapes["M"].grain = np.array([[0.1, 0.1], [0.2, 0.4]])   # 18.4° off +y
    pieces, _ = cut_pieces(g)
    assert pieces[0].grain_rotation == pytest.approx(np.degrees(np.arctan2(0.1, 0.3)))
    gr = pieces[0].shape.grain
    assert abs(gr[1, 0] - gr[0, 0]) < 1e-12 and gr[1, 1] > gr[0, 1]
    assert abs(polygon_area(pieces[0].flat.points)) == pytest.approx(0.35)
    g.panels[0].shapes["M"].grain = np.array([[0.1, 0.4], [0.1, 0.1]])   # pointing down: kept
    assert cut_pieces(g)[0][0].grain_rotation == 0.0


def _small_doc() -> dict:
    g = tube(sizes=("S", "M"))
    g.panels[0].fold = 3
    g.panels[0].texture = {"image": "none.png", "size": [0.1, 0.1]}
    g.panels.append(Panel("sleeve_l", "sleeve",
                          {s: Shape([Segment("line", np.array([0.0, 0.0])),
                                     Segment("cubic", np.array([0.3, 0.0]),
                                             [np.array([0.3, 0.1]), np.array([0.2, 0.2])]),
                                     Segment("arc", np.array([0.0, 0.2]), bulge=0.1)],
                                    np.array([[0.0, 0.0], [0.0, 1.0]]), np.array([[0.1, 0.0]]),
                                    {0: "hem"}) for s in ("S", "M")},
                          placement=Placement(part="left_arm", anchor="shoulder_left",
                                              anchor_vertex=2)))
    g.panels.append(Panel("sleeve_r", "sleeve", copy_of="sleeve_l", mirror=True))
    g.seams.append(Seam(SeamSide("sleeve_l", 0, 1), SeamSide("sleeve_r", 0, 1), ease=0.1))
    g.fit = {"S": "female-S", "M": "female-M"}
    return garment_to_dict(g)


def test_malformed_files_raise_input_errors_only():
    """Any field replaced by a value of the wrong type gives an InputError (exit 2), never
    another exception (a traceback)."""

    base = _small_doc()
    garment_from_dict(base)

    def use(doc):
        g = garment_from_dict(doc)
        check_garment(g)
        cut_pieces(g)

    tried = assert_only_input_errors(base, use)
    assert tried > 300


def test_edit_mirror_keeps_the_garment_sewing_the_same(tmp_path, capsys):
    import shutil
    from pathlib import Path

    src = Path(__file__).resolve().parents[2] / "garments" / "bodice.json"
    shutil.copytree(src.parent / "textures", tmp_path / "textures")
    g0 = load_garment(src)
    pieces0, seams0 = cut_pieces(g0, "M", tolerance=1e-4)
    out = tmp_path / "b.json"
    code, _, err = cli(["garment", "edit", str(src), "--panel", "back_right", "--mirror", "x",
                        "--rotate", "30", "--move", "0.1", "0.2", "--type", "back",
                        "-o", str(out)], capsys)
    assert code == 0, err
    g1 = load_garment(out)
    assert check_garment(g1, src.parent).ok
    pieces1, seams1 = cut_pieces(g1, "M", tolerance=1e-4)
    # every seam joins runs of the same lengths as before, in the same pairing
    for s0, s1 in zip(seams0, seams1, strict=True):
        for (p0, a0, b0), (p1, a1, b1) in (((s0[0], s0[1], s0[2]), (s1[0], s1[1], s1[2])),
                                           ((s0[3], s0[4], s0[5]), (s1[3], s1[4], s1[5]))):
            pts0, pts1 = pieces0[p0].flat.points, pieces1[p1].flat.points

            def run(pts, a, b):
                n = len(pts)
                idx = [(a + k) % n for k in range((b - a) % n + 1)]
                return np.linalg.norm(np.diff(pts[idx], axis=0), axis=1).sum()
            assert run(pts1, a1, b1) == pytest.approx(run(pts0, a0, b0), rel=1e-3)
    back0 = g0.panel("back_right").placement.anchor_vertex
    assert g1.panel("back_right").placement.anchor_vertex == (-back0) % 11
    code, _, err = cli(["garment", "edit", str(src), "--panel", "back_left", "--rotate", "5",
                        "-o", str(tmp_path / "c.json")], capsys)
    assert code == 2 and "is a copy of 'back_right'" in err


def test_every_problem_at_once_as_structured_problems(tmp_path):
    """An outline error on one panel does not hide a seam's problem between two others; the
    reader, told to, lists a seam naming no panel instead of stopping at it; each problem
    names its panel, edge, seam and size."""
    g = tube()
    g.panels.append(Panel("pocket", "pocket", {"M": Shape(rect(0.1, 0.1))}))
    g.panels.append(Panel("flap", "pocket", {"M": Shape(rect(0.1, 0.12))}))
    g.seams.append(Seam(SeamSide("pocket", 0, 1), SeamSide("flap", 2, 3), name="flap seam"))
    g.seams.append(Seam(SeamSide("pocket", 1, 2), SeamSide("front", 2, 3), name="pocket top"))
    d = garment_to_dict(g)
    d["panels"][1]["shapes"]["M"]["outline"][2]["end"] = [0.0, 0.75]   # back: not closed
    d["panels"][2]["shapes"]["M"]["outline"][3] = {"type": "line", "start": [0.0, 0.1]}
    d["seams"].append({"name": "ghost", "a": {"panel": "sleeve", "start": 0, "end": 1},
                       "b": {"panel": "front", "start": 0, "end": 1}})
    with pytest.raises(InputError, match="no panel named 'sleeve'"):
        garment_from_dict(d)
    problems: list[str] = []
    g2 = garment_from_dict(d, problems=problems)
    assert problems == ["garment: seam 4, side a: no panel named 'sleeve'"]
    rep = check_garment(g2, tmp_path)
    got = rep.problems()
    unclosed = next(p for p in got if "not closed" in p["message"])
    assert {k: unclosed[k] for k in ("panel", "edge", "size")} == \
        {"panel": "back", "edge": 2, "size": "M"}
    # the seams between sound panels are still checked: the pocket's top (0.1 m) against
    # the front's (0.5 m)
    top = next(p for p in got if "lengths differ" in p["message"])
    assert top["seam"] == 3 and top["panel"] == "pocket" and top["edge"] == 1
    assert all(p["message"] in rep.errors for p in got)


def test_edits_move_a_placement_anchor_point_with_the_panel():
    from catwalk.garment.edit import edit

    g = tube()
    g.panels[0].placement.anchor_point = [0.1, 0.2]
    edit(g, "front", move=(0.05, -0.02))
    assert g.panels[0].placement.anchor_point == pytest.approx([0.15, 0.18])
    edit(g, "front", mirror="x")   # about the bounding box's centre, x = 0.30
    assert g.panels[0].placement.anchor_point == pytest.approx([0.45, 0.18])


def test_a_texture_too_large_is_refused(tmp_path):
    from PIL import Image

    Image.new("RGB", (4097, 4096)).save(tmp_path / "huge.png")
    Image.new("RGB", (64, 64)).save(tmp_path / "small.png")
    g = tube()
    g.panels[0].texture = {"image": "huge.png"}
    g.panels[1].texture = {"image": "small.png"}
    errors = check_garment(g, tmp_path).errors
    assert errors == ["panel 'front': texture image 'huge.png' is 4097 × 4096 pixels; at most "
                      "16,777,216 (4096 × 4096)"]


def test_a_panel_of_some_sizes_only(tmp_path):
    """A pocket in size L only: read and written as it is, cut in L alone, its seam sewn in
    L; unsewn, it is named for the sizes that have it; a panel in no size, or a size without
    panels, is refused."""
    g = tube(sizes=("M", "L"))
    g.panels.append(Panel("pocket", "pocket", {"L": Shape(rect(0.15, 0.2))},
                          placement=Placement(side="front", anchor="bust")))
    d = garment_to_dict(g)
    assert list(d["panels"][2]["shapes"]) == ["L"]
    g2 = garment_from_dict(d)
    assert g2.panel_sizes("pocket") == ["L"] and not g2.cut_in("pocket", "M")
    assert [p.name for p in cut_pieces(g2, "M")[0]] == ["front", "back"]
    rep = check_garment(g2)
    assert rep.errors == ["panel(s) 'pocket' not reachable from panel 'front' through seams "
                          "(size L) (every panel must be sewn to the rest)"]
    g2.seams.append(Seam(SeamSide("pocket", 0, 1), SeamSide("front", 0, 1), ease=0.8))
    rep = check_garment(g2)
    assert rep.ok, rep.errors
    assert [(r["seam"], r["size"]) for r in rep.seams] == [(0, "M"), (1, "M"), (0, "L"),
                                                            (1, "L"), (2, "L")]
    pieces, seams = cut_pieces(g2, "L")
    assert [p.name for p in pieces] == ["front", "back", "pocket"] and len(seams) == 3
    assert len(cut_pieces(g2, "M")[1]) == 2
    bad = garment_to_dict(g2)
    bad["panels"][2]["shapes"] = {}
    with pytest.raises(InputError, match="panel 'pocket': no outline in any size"):
        garment_from_dict(bad)
    bad = garment_to_dict(g2)
    bad["sizes"].append("XL")
    with pytest.raises(InputError, match="size XL: no panel has an outline in this size"):
        garment_from_dict(bad)
