"""Scans this project makes, with their truth: for the scan-registration tests and
``catwalk bench scan``.

A *true body* is a MakeHuman body the registration never fitted to: a macro mix of its own
(age, muscle, weight, proportions, race), local changes (a belly, broad shoulders, a left hip
raised by a smooth bump) and, for one case, arms lowered from MakeHuman's A-pose. Its *scan* is
what a scanner would hand over:

- **remeshed**: the surface subdivided to the requested face count, then every vertex slid
  along the surface by up to a third of an edge and put back on the true surface (so no scan
  vertex sits where a MakeHuman vertex does);
- **noisy**: each vertex moved along the surface normal by Gaussian noise (σ = 1 mm);
- **holed**: open at the crown (the top 2.5 cm), the soles and both armpits (3 cm around them);
- **in a scanner's frame**: millimetres, Z up, facing −Y.

The truth stays in glTF metres (feet on y = 0, facing +Z); :data:`FILE_FROM_GLTF` maps it to
the file's frame.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from catwalk.body import makehuman as mh
from catwalk.body.limbs import pose_arms
from catwalk.body.rig import build_rig
from catwalk.geometry.mesh import compact, face_normals
from catwalk.geometry.raster import vertex_normals
from catwalk.geometry.surface import BodySurface

# glTF metres (+Y up, facing +Z) → a scanner's file: millimetres, +Z up, facing −Y (a rotation)
FILE_FROM_GLTF = np.array([[1.0, 0.0, 0.0, 0.0],
                           [0.0, 0.0, -1.0, 0.0],
                           [0.0, 1.0, 0.0, 0.0],
                           [0.0, 0.0, 0.0, 1.0]]) @ np.diag([1000.0, 1000.0, 1000.0, 1.0])
NOISE_M = 0.001


@dataclass(frozen=True)
class ScanCase:
    name: str
    sex: str
    sliders: dict                       # MacroSliders fields
    modifiers: dict = field(default_factory=dict)   # two-sided MakeHuman modifiers
    hip_raise_m: float = 0.0            # the left hip lifted by a smooth bump
    arms_deg: tuple = (0.0, 0.0)        # (abduction, flexion) of both arms from the A-pose


CASES = (
    ScanCase("belly", "male",
             {"gender": 0.9, "age": 0.75, "muscle": 0.4, "weight": 0.75, "height": 0.6,
              "proportions": 0.3, "african": 0.2, "asian": 0.2, "caucasian": 0.6},
             {"stomach/stomach-pregnant": 0.45}),
    ScanCase("shoulders", "female",
             {"gender": 0.1, "age": 0.45, "muscle": 0.7, "weight": 0.4, "height": 0.4,
              "proportions": 0.7, "african": 0.6, "asian": 0.2, "caucasian": 0.2},
             {"torso/measure-shoulder-dist": 0.8, "torso/torso-vshape": 0.4}),
    ScanCase("hip", "female",
             {"gender": 0.0, "age": 0.6, "muscle": 0.5, "weight": 0.65, "height": 0.55,
              "proportions": 0.5, "african": 0.1, "asian": 0.6, "caucasian": 0.3},
             {"hip/hip-scale-horiz": 0.3}, hip_raise_m=0.015, arms_deg=(10.0, 5.0)),
)


def case(name: str) -> ScanCase:
    for c in CASES:
        if c.name == name:
            return c
    raise KeyError(name)


@dataclass
class TrueBody:
    vertices: np.ndarray     # (13380, 3) glTF metres, feet on y = 0
    faces: np.ndarray        # (26756, 3)
    parts: np.ndarray        # (13380,) body part per vertex
    case: ScanCase


def true_body(c: ScanCase) -> TrueBody:
    """The case's MakeHuman body, shaped and posed (see the module's text)."""
    weights = mh.macro_weights(mh.MacroSliders(**c.sliders))
    weights.update(mh.modifier_weights(c.modifiers))
    full = mh.obj_to_gltf(mh.apply_targets(weights))
    full[:, 1] -= full[: mh.BODY_VERTEX_COUNT, 1].min()
    skeleton, joints, sw, parts = build_rig(full)
    v = full[: mh.BODY_VERTEX_COUNT].copy()
    if c.hip_raise_m:
        # a smooth bump lifting the left hip (x > 0) around the greater trochanter's height
        hip_y = 0.53 * float(v[:, 1].max())
        x0 = 0.5 * float(v[parts == 3, 0].mean() + v[parts == 0, 0].max())
        r2 = ((v[:, 1] - hip_y) / 0.12) ** 2 + ((v[:, 0] - x0) / 0.12) ** 2
        v[:, 1] += c.hip_raise_m * np.exp(-r2) * (parts != 1) * (parts != 2)
    if any(c.arms_deg):
        a = np.radians(c.arms_deg)
        v = pose_arms(v, skeleton, joints, sw, {s: (a[0], a[1]) for s in ("l", "r")})
    return TrueBody(v, mh.load_base_mesh().body_triangles.copy(), parts, c)


def _subdivide(v, f, faces_wanted):
    """Midpoint subdivision of the longest edges until about ``faces_wanted`` faces."""
    import trimesh  # deferred: trimesh loads in ≈ 0.4 s; only scan files need it

    area = float(trimesh.Trimesh(v, f, process=False).area)
    edge = np.sqrt(4.0 * area / (np.sqrt(3.0) * faces_wanted)) * 1.68
    return trimesh.remesh.subdivide_to_size(v, f, max_edge=edge, max_iter=12)


def _holes(v, f, truth: TrueBody):
    """Faces kept: open at the crown, the soles and both armpits."""
    cent = v[f].mean(axis=1)
    top = float(truth.vertices[:, 1].max())
    n = face_normals(v, f)
    keep = cent[:, 1] < top - 0.025
    keep &= ~((cent[:, 1] < 0.012) & (n[:, 1] < -0.5))
    tv, tf, parts = truth.vertices, truth.faces, truth.parts
    for arm in (1, 2):
        fp = parts[tf]
        seam = tf[np.any(fp == arm, axis=1) & np.any(fp == 0, axis=1)].ravel()
        seam = seam[parts[seam] == arm]
        pit = tv[seam[np.argmin(tv[seam, 1])]]
        keep &= np.linalg.norm(cent - pit, axis=1) > 0.03
    return f[keep]


def scan_of(truth: TrueBody, faces: int = 300_000, noise_m: float = NOISE_M,
            holes: bool = True, seed: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """(vertices, faces) of a scan of ``truth`` in glTF metres (see the module's text)."""
    from scipy.spatial import cKDTree  # deferred: scipy loads in ≈ 0.3 s; only this path needs it


    rng = np.random.default_rng(seed)
    v, f = _subdivide(truth.vertices, truth.faces, faces)
    nrm = vertex_normals(v, f)
    e = v[f[:, 1]] - v[f[:, 0]]
    step = float(np.mean(np.linalg.norm(e, axis=1))) / 3.0
    slide = rng.normal(size=v.shape)
    slide -= np.sum(slide * nrm, axis=1, keepdims=True) * nrm
    slide *= step / (np.linalg.norm(slide, axis=1, keepdims=True) + 1e-30)
    surface = BodySurface(truth.faces, len(truth.vertices), k=12)
    on, _, tri, _ = surface.closest(truth.vertices, v + slide,
                                    tree=cKDTree(truth.vertices))
    tn = vertex_normals(truth.vertices, truth.faces)[truth.faces[tri]].mean(axis=1)
    tn /= np.linalg.norm(tn, axis=1, keepdims=True)
    v = on + rng.normal(scale=noise_m, size=(len(v), 1)) * tn if noise_m else on
    if holes:
        v, f = compact(v, _holes(v, f, truth))
    return v, f.astype(np.int32)


def to_file_frame(v: np.ndarray) -> np.ndarray:
    """glTF metres → the scanner's millimetres, Z up, facing −Y."""
    return v @ FILE_FROM_GLTF[:3, :3].T + FILE_FROM_GLTF[:3, 3]


def write_scan(path, v_gltf: np.ndarray, f: np.ndarray) -> None:
    """The scan as a binary PLY in the scanner's frame."""
    import trimesh  # deferred: trimesh loads in ≈ 0.4 s; only scan files need it

    trimesh.Trimesh(to_file_frame(v_gltf), f, process=False).export(str(path))


def truth_in_scan_frame(truth: TrueBody, scan, report: dict | None = None) -> np.ndarray:
    """The true vertices where the registered body is: the scan's file (written by
    :func:`write_scan`) as :func:`catwalk.exchange.scan.load_scan` aligned it, then moved as
    the registration moved the scan after tidying it (``report["registration"]["moved_m"]``
    of :func:`catwalk.body.from_scan.body_from_scan`)."""
    m = scan.transform @ FILE_FROM_GLTF
    moved = (report or {}).get("registration", {}).get("moved_m", (0.0, 0.0, 0.0))
    return truth.vertices @ m[:3, :3].T + m[:3, 3] + np.asarray(moved)


def distance_to_truth(truth_v: np.ndarray, faces: np.ndarray, body_v: np.ndarray,
                      body_faces: np.ndarray) -> dict:
    """Surface distance between a registered body and the true surface, both directions
    together (every body vertex to the truth, every true vertex to the body), mm."""
    d1 = BodySurface(faces, len(truth_v)).signed_distance(truth_v, body_v)
    d2 = BodySurface(body_faces, len(body_v)).signed_distance(body_v, truth_v)
    d = np.abs(np.concatenate([d1, d2])) * 1000.0
    return {"mean_mm": round(float(d.mean()), 3), "p99_mm": round(float(np.percentile(d, 99)), 3),
            "max_mm": round(float(d.max()), 3)}
