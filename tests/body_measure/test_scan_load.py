"""load_scan: OBJ/PLY/STL/GLB round trips, unit and axis detection, topology report."""

import numpy as np
import pytest
import trimesh
from scipy.spatial import cKDTree

from catwalk.exchange.scan import load_scan


def _centred(v):
    lo, hi = v.min(axis=0), v.max(axis=0)
    return v - [(lo[0] + hi[0]) / 2, lo[1], (lo[2] + hi[2]) / 2]


def _same_points(a, b, tol):
    assert len(a) == len(b)
    d, _ = cKDTree(b).query(a)
    assert d.max() < tol, d.max()


# file axes from glTF axes: (name, function, expected up, expected forward)
AXES = {
    "yup": (lambda v: v, "+Y", "+Z"),
    "zup": (lambda v: np.stack([v[:, 0], -v[:, 2], v[:, 1]], axis=1), "+Z", "-Y"),
    "upside_down": (lambda v: np.stack([v[:, 0], -v[:, 1], -v[:, 2]], axis=1), "-Y", "-Z"),
    "facing_x": (lambda v: np.stack([v[:, 2], v[:, 1], -v[:, 0]], axis=1), "+Y", "+X"),
}


@pytest.mark.parametrize("ext,unit,scale,axes", [
    ("obj", "m", 1.0, "yup"),
    ("ply", "cm", 100.0, "zup"),
    ("stl", "mm", 1000.0, "zup"),
    ("glb", "m", 1.0, "upside_down"),   # glTF is metres: a GLB is never rescaled
    ("ply", "mm", 1000.0, "facing_x"),
])
def test_round_trip(ext, unit, scale, axes, bodies, body_faces, tmp_path):
    v = bodies["female"]
    to_file, up, fwd = AXES[axes]
    p = tmp_path / f"body.{ext}"
    trimesh.Trimesh(to_file(v) * scale, body_faces, process=False).export(p)
    scan = load_scan(p)
    assert (scan.units, scan.up, scan.forward, scan.forward_detected) == (unit, up, fwd, True)
    assert len(scan.faces) == len(body_faces)
    assert scan.watertight and scan.holes == 0 and scan.components == 1
    assert scan.vertices[:, 1].min() == pytest.approx(0.0, abs=1e-9)
    assert scan.height == pytest.approx(1.590, abs=0.002)
    tol = 1e-4 if ext == "stl" else 1e-6  # STL stores float32
    _same_points(scan.vertices, _centred(v), tol)
    # the transform maps the file's coordinates onto the output
    fv = to_file(v) * scale
    mapped = fv @ scan.transform[:3, :3].T + scan.transform[:3, 3]
    _same_points(mapped, scan.vertices, tol)
    assert np.linalg.det(scan.transform[:3, :3]) > 0  # a rotation, never a mirror
    info = scan.info()
    assert info["faces"] == len(body_faces) and info["units"] == unit


def test_stray_points_on_no_triangle_are_ignored(bodies, body_faces, tmp_path):
    """Vertices no face uses (a scanner's stray points) neither tilt the axes nor the size."""
    v = AXES["zup"][0](bodies["female"]) * 1000.0
    stray = np.random.default_rng(0).uniform(-900, 900, size=(20, 3))
    p = tmp_path / "stray.ply"
    trimesh.Trimesh(np.vstack([v, stray]), body_faces, process=False).export(p)
    scan = load_scan(p)
    assert (scan.units, scan.up, scan.forward) == ("mm", "+Z", "-Y")
    assert len(scan.vertices) == len(v) and scan.height == pytest.approx(1.590, abs=0.002)


def test_glb_merges_primitives_with_node_transforms(bodies, body_faces, tmp_path):
    """Two halves of the body as separate meshes under transformed nodes: the loader applies
    the world transforms and merges them."""
    v = bodies["male"]
    left = np.nonzero(v[body_faces].mean(axis=1)[:, 0] >= 0)[0]
    right = np.nonzero(v[body_faces].mean(axis=1)[:, 0] < 0)[0]
    scene = trimesh.Scene()
    for name, sel, shift in (("left", left, [0.0, 2.0, 0.0]), ("right", right, [5.0, 0.0, 1.0])):
        part = trimesh.Trimesh(v, body_faces[sel], process=False)
        part.remove_unreferenced_vertices()
        T = trimesh.transformations.translation_matrix(shift)
        part.apply_transform(np.linalg.inv(T))  # the node transform puts it back
        scene.add_geometry(part, geom_name=name, node_name=name, transform=T)
    p = tmp_path / "halves.glb"
    scene.export(p)
    scan = load_scan(p)
    assert len(scan.faces) == len(body_faces)
    assert scan.components == 1 and scan.holes == 0  # welded along the seam
    assert (scan.units, scan.up, scan.forward) == ("m", "+Y", "+Z")
    _same_points(scan.vertices, _centred(v), 1e-5)


def test_holes_and_components_reported(bodies, body_faces, tmp_path):
    v = bodies["female"]
    # cut two separate holes (the faces around two far-apart vertices) and add a stray cube
    drop = np.zeros(len(body_faces), bool)
    for vid in (100, 9000):
        drop |= (body_faces == vid).any(axis=1)
    faces = body_faces[~drop]
    cube = trimesh.creation.box(extents=[0.05, 0.05, 0.05])
    verts = np.concatenate([v, cube.vertices + [0.0, 0.05, 0.6]])
    faces = np.concatenate([faces, cube.faces + len(v)])
    p = tmp_path / "holes.ply"
    trimesh.Trimesh(verts, faces, process=False).export(p)
    scan = load_scan(p)
    assert scan.holes == 2
    assert scan.components == 2
    assert not scan.watertight


def test_makehuman_obj_in_decimetres(mpfb2):
    """MakeHuman's own base.obj (decimetres, helpers included) loads as a 1.66 m body."""
    scan = load_scan(mpfb2 / "3dobjs" / "base.obj")
    assert scan.units == "dm"
    assert scan.up == "+Y" and scan.forward == "+Z"
    assert scan.height == pytest.approx(1.75, abs=0.12)  # helper geometry (hair) adds height
