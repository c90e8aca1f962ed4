"""measure_body on the MakeHuman default bodies: plausible numbers, landmarks, invariance to
remeshing / noise / units / axes (the acceptance test), smoothness, determinism, bad input."""

import numpy as np
import pytest
import trimesh

from catwalk.body.measure import measure_body
from catwalk.errors import InputError

GIRTHS = ("bust", "underbust", "waist", "hips", "neck_girth")
LANDMARKS = (
    "neck_base", "shoulder_left", "shoulder_right", "armpit_left", "armpit_right", "bust",
    "waist", "hips", "crotch", "elbow_left", "elbow_right", "wrist_left", "wrist_right",
    "knee_left", "knee_right", "ankle_left", "ankle_right",
)


def test_heights_match_makehuman(measured):
    assert measured["female"]["height"] == pytest.approx(1.590, abs=0.002)
    assert measured["neutral"]["height"] == pytest.approx(1.659, abs=0.002)
    assert measured["male"]["height"] == pytest.approx(1.730, abs=0.002)


def test_female_measurements_plausible(measured):
    m = measured["female"]
    assert m["bust"] == m["chest"]
    assert 0.80 < m["bust"] < 0.95
    assert 0.65 < m["underbust"] < m["bust"] - 0.08  # a cup, not a barrel
    assert 0.60 < m["waist"] < 0.75
    assert 0.85 < m["hips"] < 1.00
    assert m["waist"] < m["underbust"] < m["bust"]
    assert 0.44 * m["height"] < m["inseam"] < 0.49 * m["height"]
    assert 0.36 < m["shoulder_width"] < 0.48
    assert 0.40 < m["arm_length"] < 0.60
    assert 0.27 < m["neck_girth"] < 0.34
    assert 0.22 < m["upper_arm_girth"] < 0.36
    # the bust points: forward of the bust loop's centre, one each side, 14-26 cm apart
    bl, br, c = (np.array(m["landmarks"][k]) for k in ("bust_point_left", "bust_point_right",
                                                       "bust"))
    assert 0.14 < m["bust_span"] < 0.26
    assert m["bust_span"] == pytest.approx(bl[0] - br[0], abs=1e-12)
    assert bl[0] > c[0] > br[0] and min(bl[2], br[2]) > c[2] + 0.05
    np.testing.assert_allclose(bl * [-1, 1, 1], br, atol=0.01)


def test_male_measurements_plausible(measured):
    m, f = measured["male"], measured["female"]
    assert "underbust" not in m and "underbust" not in m["landmarks"]
    assert "bust_span" not in m and "bust_point_left" not in m["landmarks"]
    assert m["bust"] == m["chest"]
    assert 0.90 < m["chest"] < 1.05
    assert 0.68 < m["waist"] < 0.82
    assert 0.85 < m["hips"] < 1.00
    assert m["waist"] < m["hips"] and m["waist"] < m["chest"]
    # men: broader shoulders, thicker neck, longer arms and legs than the women
    for k in ("shoulder_width", "neck_girth", "arm_length", "inseam", "chest",
              "upper_arm_girth"):
        assert m[k] > f[k] + 0.01, k


def test_landmarks_complete_symmetric_and_ordered(measured):
    for name, m in measured.items():
        lm = m["landmarks"]
        for k in LANDMARKS:
            assert k in lm, (name, k)
            assert np.all(np.isfinite(lm[k])) and len(lm[k]) == 3
        for part in ("shoulder", "armpit", "elbow", "wrist", "knee", "ankle"):
            left, right = np.array(lm[f"{part}_left"]), np.array(lm[f"{part}_right"])
            assert left[0] > 0.05 > -0.05 > right[0], (name, part)  # body's left is +x
            np.testing.assert_allclose(left * [-1, 1, 1], right, atol=0.005)
        y = {k: lm[k][1] for k in lm}
        chain = ["ankle_left", "knee_left", "crotch", "hips", "waist", "bust", "armpit_left",
                 "shoulder_left", "neck_base", "top_of_head"]
        ys = [y[k] for k in chain]
        assert ys == sorted(ys), (name, dict(zip(chain, ys, strict=True)))
        assert y["wrist_left"] < y["elbow_left"] < y["shoulder_left"]
        assert lm["crotch"][1] == pytest.approx(m["inseam"], abs=1e-9)


def test_landmarks_near_makehuman_rig_joints(measured):
    """The neutral body's landmarks lie near the joints of MakeHuman's default rig (which are
    defined on the same mesh): knee, ankle, wrist, elbow, neck."""
    from catwalk.body.makehuman import BODY_VERTEX_COUNT, load_base_mesh, load_json

    rig = load_json("rigs/standard/rig.default.json")
    off = -load_base_mesh().vertices[:BODY_VERTEX_COUNT, 1].min() * 0.1

    def joint(name):  # Blender (x, y, z) -> glTF (x, z, -y), feet on y = 0
        x, y, z = rig[name]["head"]["default_position"]
        return np.array([x, z + off, -y])

    lm = measured["neutral"]["landmarks"]
    for mark, bone, tol in (("knee_left", "lowerleg01.L", 0.02), ("wrist_left", "wrist.L", 0.02),
                            ("ankle_left", "foot.L", 0.03), ("elbow_left", "lowerarm01.L", 0.045),
                            ("neck_base", "neck01", 0.03)):
        d = np.linalg.norm(np.array(lm[mark]) - joint(bone))
        assert d < tol, (mark, bone, d)


def _retriangulated_noisy_mm_zup_stl(v, faces, path, noise=0.001, seed=0):
    """A copy of the body with the given (other) triangulation, ±noise, in millimetres,
    Z up (file axes), as binary STL."""
    vs, fs = v, faces
    rng = np.random.default_rng(seed)
    vs = vs + rng.uniform(-noise, noise, vs.shape)
    zup = np.stack([vs[:, 0], -vs[:, 2], vs[:, 1]], axis=1) * 1000.0  # glTF -> Z-up, mm
    trimesh.Trimesh(zup, fs, process=False).export(path)
    return path


@pytest.mark.parametrize("copy", ["retriangulated", "subdivided", "loop_subdivided", "noisy",
                                  "mm_zup_scan", "all_at_once"])
def test_girths_invariant_to_remesh_noise_units_axes(copy, bodies, body_faces,
                                                     quad_flipped_faces, measured, tmp_path):
    """Acceptance: measure() on a remeshed, noisy (±1 mm), millimetre, Z-up copy of a body
    gives the same girths within 1.5 cm."""
    from catwalk.exchange.scan import load_scan

    v = bodies["female"]
    ref = measured["female"]
    rng = np.random.default_rng(1)
    if copy == "retriangulated":
        m = measure_body(v, quad_flipped_faces, sex="female")
    elif copy == "subdivided":
        m = measure_body(*trimesh.remesh.subdivide(v, body_faces), sex="female")
    elif copy == "loop_subdivided":  # smooths the surface: a real remesh
        m = measure_body(*trimesh.remesh.subdivide_loop(v, body_faces), sex="female")
    elif copy == "noisy":
        m = measure_body(v + rng.uniform(-0.001, 0.001, v.shape), body_faces, sex="female")
    elif copy == "mm_zup_scan":
        p = tmp_path / "body_mm_zup.stl"
        zup = np.stack([v[:, 0], -v[:, 2], v[:, 1]], axis=1) * 1000.0
        trimesh.Trimesh(zup, body_faces, process=False).export(p)
        scan = load_scan(p)
        assert (scan.units, scan.up, scan.forward) == ("mm", "+Z", "-Y")
        m = measure_body(scan.vertices, scan.faces, sex="female")
    else:
        p = _retriangulated_noisy_mm_zup_stl(v, quad_flipped_faces, tmp_path / "all.stl")
        scan = load_scan(p)
        assert (scan.units, scan.up, scan.forward) == ("mm", "+Z", "-Y")
        m = measure_body(scan.vertices, scan.faces, sex="female")
    for k in GIRTHS + ("height", "inseam", "upper_arm_girth", "bust_span"):
        assert abs(m[k] - ref[k]) < 0.015, (copy, k, m[k], ref[k])
    # the same body gives nearly the same numbers, not just within tolerance (loop
    # subdivision smooths the surface and shrinks girths by a few millimetres)
    assert abs(m["waist"] - ref["waist"]) < 0.008
    assert abs(m["hips"] - ref["hips"]) < 0.008


def test_male_invariant_too(bodies, quad_flipped_faces, measured, tmp_path):
    from catwalk.exchange.scan import load_scan

    p = _retriangulated_noisy_mm_zup_stl(bodies["male"], quad_flipped_faces, tmp_path / "m.stl",
                                         seed=3)
    scan = load_scan(p)
    m = measure_body(scan.vertices, scan.faces, sex="male")
    for k in ("chest", "waist", "hips", "neck_girth", "shoulder_width", "arm_length"):
        assert abs(m[k] - measured["male"][k]) < 0.015, k


def test_deterministic(bodies, body_faces):
    a = measure_body(bodies["male"], body_faces)
    b = measure_body(bodies["male"].copy(), body_faces.copy())
    assert a == b


def test_smooth_in_the_shape(mpfb2, body_faces):
    """The fitter takes finite differences: equal slider steps give nearly equal changes."""
    from catwalk.body.makehuman import (
        BODY_VERTEX_COUNT,
        MacroSliders,
        apply_targets,
        macro_weights,
        obj_to_gltf,
    )

    rows = []
    for w in np.linspace(0.30, 0.34, 5):
        v = obj_to_gltf(apply_targets(macro_weights(MacroSliders(weight=w))))[:BODY_VERTEX_COUNT]
        v = v - [0.0, v[:, 1].min(), 0.0]
        m = measure_body(v, body_faces, sex="female")
        rows.append([m[k] for k in ("bust", "underbust", "waist", "hips", "neck_girth")])
    d = np.diff(np.array(rows), axis=0)
    assert np.all(d[:, :4] > 0)  # heavier: every torso girth grows
    assert np.abs(np.diff(d, axis=0)).max() < 0.0005  # and steadily (< 0.5 mm wobble)


def test_feet_need_not_be_at_zero(bodies, body_faces, measured):
    m = measure_body(bodies["female"] + [0.3, 0.5, -0.2], body_faces, sex="female")
    for k in GIRTHS + ("height", "inseam", "shoulder_width", "arm_length"):
        assert m[k] == pytest.approx(measured["female"][k], abs=1e-4)  # rounding only
    assert m["landmarks"]["crotch"][1] == pytest.approx(measured["female"]["inseam"] + 0.5)


def test_bad_input_raises(bodies, body_faces):
    v = bodies["female"]
    bad = v.copy()
    bad[5, 1] = np.nan
    with pytest.raises(InputError, match="NaN"):
        measure_body(bad, body_faces)
    with pytest.raises(InputError, match="tall"):
        measure_body(v * 1000.0, body_faces)  # millimetres: load_scan converts, measure doesn't
    with pytest.raises(InputError, match="sex"):
        measure_body(v, body_faces, sex="other")
    with pytest.raises(InputError):
        measure_body(v[:, :2], body_faces)
    lying = np.stack([v[:, 1], -v[:, 0], v[:, 2]], axis=1)  # on its side
    with pytest.raises(InputError):
        measure_body(lying, body_faces)


def _lower_arms(v_full, deg):
    """Rotate both arms about their shoulder joints towards the body in the frontal plane,
    blended by MakeHuman's skinning weights of the arm bones (linear-blend skinning)."""
    from catwalk.body.makehuman import BODY_VERTEX_COUNT, load_base_mesh, load_json

    base = load_base_mesh()
    weights = load_json("rigs/standard/weights.default.json")["weights"]
    n = BODY_VERTEX_COUNT
    total = np.zeros(n)
    arm = {"L": np.zeros(n), "R": np.zeros(n)}
    prefixes = ("upperarm", "lowerarm", "wrist", "finger", "metacarpal")
    for bone, pairs in weights.items():
        if not pairs:
            continue
        a = np.asarray(pairs, dtype=np.float64)
        idx, w = a[:, 0].astype(int), a[:, 1]
        keep = idx < n
        np.add.at(total, idx[keep], w[keep])
        side = bone[-1]
        if bone[-2:] in (".L", ".R") and bone.startswith(prefixes):
            np.add.at(arm[side], idx[keep], w[keep])
    v = v_full[:n].copy()
    for side, sgn in (("L", 1.0), ("R", -1.0)):
        c = v_full[base.group_vertices[f"joint-{side.lower()}-shoulder"]].mean(axis=0)
        w = arm[side] / np.maximum(total, 1e-12)
        th = np.radians(deg) * sgn
        R = np.array([[np.cos(th), np.sin(th), 0.0], [-np.sin(th), np.cos(th), 0.0],
                      [0.0, 0.0, 1.0]])
        rel = v - c
        v = v + w[:, None] * (rel @ R.T - rel)
    return v - [0.0, v[:, 1].min(), 0.0]


def test_arms_closer_to_the_body(mpfb2, body_faces, measured):
    """Arms lowered by 30 degrees (from MakeHuman's A-pose to nearly hanging): still measured,
    torso girths unchanged but for the skinning's deformation near the armpit."""
    from catwalk.body.makehuman import MacroSliders, apply_targets, macro_weights, obj_to_gltf

    v_full = obj_to_gltf(apply_targets(macro_weights(MacroSliders(gender=0.0))))
    m = measure_body(_lower_arms(v_full, 30.0), body_faces, sex="female")
    ref = measured["female"]
    for k in ("underbust", "waist", "hips", "neck_girth", "height", "inseam"):
        assert abs(m[k] - ref[k]) < 0.003, k
    assert abs(m["bust"] - ref["bust"]) < 0.01
    wl, wr = m["landmarks"]["wrist_left"], ref["landmarks"]["wrist_left"]
    assert wl[0] < wr[0] - 0.1  # the wrist came in towards the hip
    assert abs(m["arm_length"] - ref["arm_length"]) < 0.015  # the shoulder deforms


def test_holes_are_bridged(bodies, body_faces, measured):
    """Scans have holes: 5 % of the triangles missing at random, and the top of the head and
    the soles cut away, change no girth by more than a millimetre."""
    v = bodies["female"]
    c = v[body_faces].mean(axis=1)
    keep = np.random.default_rng(7).random(len(body_faces)) > 0.05
    keep &= (c[:, 1] < 1.56) & (c[:, 1] > 0.01)
    m = measure_body(v, body_faces[keep], sex="female")
    for k in GIRTHS + ("shoulder_width", "arm_length"):
        assert abs(m[k] - measured["female"][k]) < 0.001, k
    assert abs(m["inseam"] - measured["female"]["inseam"]) < 0.01  # the soles are gone
