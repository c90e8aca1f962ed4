"""Scenes for collider tests and ``catwalk bench collide``: a walking body (the capsule
mannequin, or a MakeHuman body when :mod:`catwalk.body` / :mod:`catwalk.motion` provide one)
and cloth points *bound* to it (a synthetic dress: each point rides on a body triangle at a
fixed barycentric position and normal offset, so it follows the body the way a settled garment
does, and is jittered each substep so that some points end up inside).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from catwalk.body.make import make_body
from catwalk.body.skinning import body_frames
from catwalk.collide.collider import face_parts
from catwalk.collide.shapes import Mannequin, walk_frames
from catwalk.geometry.raster import vertex_normals
from catwalk.motion.gait import walk_motion


@dataclass
class WalkingBody:
    """Frames of a walking body: ``vertices``/``velocities`` (T,N,3), ``faces`` (M,3),
    ``parts`` (N,), ``fps``, ``source`` (what made it)."""

    vertices: np.ndarray
    velocities: np.ndarray
    faces: np.ndarray
    parts: np.ndarray
    fps: float
    source: str


def mannequin_walk(n_frames=30, fps=30.0, resolution=2.25, t0=0.0, speed=1.2) -> WalkingBody:
    """The capsule mannequin walking (arms and legs swinging, moving along +Z at ``speed``);
    ``resolution`` 2.25 ≈ the MakeHuman body's 26.7k triangles."""
    m = Mannequin(resolution)
    times = t0 + np.arange(n_frames) / fps
    v, w = walk_frames(m, times, speed=speed)
    return WalkingBody(v, w, m.faces, m.parts, fps,
                       f"capsule mannequin, resolution {resolution}, {len(m.faces)} triangles")


def makehuman_walk(n_frames=30, fps=30.0, speed=1.2, style="catwalk", sex="female",
                   height=1.68, bust=0.90, waist=0.72, hips=0.98) -> WalkingBody:
    """A MakeHuman body from measurements (:func:`catwalk.body.make.make_body`) walking
    (:func:`catwalk.motion.gait.walk_motion`, skinned by
    :func:`catwalk.body.skinning.body_frames`): the first ``n_frames`` frames of a looping
    walk. Needs the MakeHuman assets (fetched on first use)."""
    body = make_body(sex, height, bust=bust, waist=waist, hips=hips)
    seconds = max(n_frames / fps, 1.0)
    motion = walk_motion(body, seconds, speed=speed, style=style, fps=fps)
    v, w = body_frames(body, motion)
    reps = -(-n_frames // len(v))
    if reps > 1:  # a loop: continue it, shifted by the distance walked per loop
        off = np.asarray(motion.meta.get("loop_offset", (0.0, 0.0, 0.0)))
        v = np.concatenate([v + k * off for k in range(reps)])
        w = np.concatenate([w] * reps)
    return WalkingBody(np.asarray(v[:n_frames], np.float64), np.asarray(w[:n_frames], np.float64),
                       np.asarray(body.faces), np.asarray(body.parts), fps,
                       f"MakeHuman {sex} {height} m (bust {bust}, waist {waist}, hips {hips}), "
                       f"{style} walk at {speed} m/s, {len(body.faces)} triangles")


@dataclass
class BoundCloth:
    """Cloth points riding on body triangles: ``tri`` (P,), ``bary`` (P,3), ``offset`` (P,)
    along the interpolated normal (m)."""

    tri: np.ndarray
    bary: np.ndarray
    offset: np.ndarray

    def positions(self, vertices, faces, normals=None) -> np.ndarray:
        f = faces[self.tri]
        p = np.einsum("pk,pkj->pj", self.bary, vertices[f])
        if normals is None:
            normals = vertex_normals(vertices, faces)
        n = np.einsum("pk,pkj->pj", self.bary, normals[f])
        n /= np.linalg.norm(n, axis=1, keepdims=True)
        return p + self.offset[:, None] * n


def dress(body_vertices, faces, parts, n_points=3400, thickness=0.004, seed=0,
          y_range=(0.55, 0.80), skirt=True) -> BoundCloth:
    """A synthetic dress of ``n_points``: 60 % on the torso, 20 % on the upper arms (sleeves),
    20 % on the thighs (a skirt's lining); all between ``y_range`` (fractions of the body's
    height: hem to shoulder). Offsets: −1 mm … thickness + 2 mm (touching), a quarter of the
    skirt points 1–6 cm away (hanging). ``skirt=False``: a top, the skirt's share on the
    torso (nothing on the legs)."""
    rng = np.random.default_rng(seed)
    v = np.asarray(body_vertices, dtype=np.float64)
    fp = face_parts(faces, parts)
    height = v[:, 1].max() - v[:, 1].min()
    cy = v[faces].mean(axis=1)[:, 1] - v[:, 1].min()
    band = (cy > y_range[0] * height) & (cy < y_range[1] * height)
    area = 0.5 * np.linalg.norm(np.cross(v[faces[:, 1]] - v[faces[:, 0]],
                                         v[faces[:, 2]] - v[faces[:, 0]]), axis=1)
    groups = [(np.isin(fp, [0]) & band, 0.6 if skirt else 0.8),
              (np.isin(fp, [1, 2]) & band, 0.2), (np.isin(fp, [3, 4]) & band, 0.2 if skirt else 0)]
    tris, offs = [], []
    for mask, share in groups:
        ids = np.nonzero(mask)[0]
        k = int(round(share * n_points)) if (mask is not groups[-1][0] or not skirt) else \
            n_points - sum(len(t) for t in tris)
        if len(ids) == 0 or k <= 0:
            continue
        pick = rng.choice(ids, size=k, p=area[ids] / area[ids].sum())
        tris.append(pick)
        off = rng.uniform(-0.001, thickness + 0.002, k)
        if mask is groups[2][0]:
            far = rng.random(k) < 0.25
            off[far] = rng.uniform(0.01, 0.06, far.sum())
        offs.append(off)
    tri = np.concatenate(tris)
    off = np.concatenate(offs)
    r = rng.random((len(tri), 2))
    flip = r.sum(axis=1) > 1
    r[flip] = 1 - r[flip]
    bary = np.c_[1 - r.sum(axis=1), r]
    # a real garment's points come panel by panel, row by row: neighbours in memory are
    # neighbours in space. Mimic that with a Morton (Z-order) sort of the points.
    order = np.argsort(morton(np.einsum("pk,pkj->pj", bary, v[faces[tri]])), kind="stable")
    return BoundCloth(tri[order], bary[order], off[order])


def morton(points, bits=10) -> np.ndarray:
    """Z-order codes of points (in their bounding box, ``bits`` per axis)."""
    p = np.asarray(points, dtype=np.float64)
    lo = p.min(axis=0)
    span = np.maximum(p.max(axis=0) - lo, 1e-12)
    q = ((p - lo) / span * ((1 << bits) - 1)).astype(np.int64)
    code = np.zeros(len(p), np.int64)
    for b in range(bits):
        for a in range(3):
            code |= ((q[:, a] >> b) & 1) << (3 * b + a)
    return code
