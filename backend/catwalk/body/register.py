"""Registering the MakeHuman template to a scan's surface: similarity ICP, the arms' pose, then
non-rigid ICP with a stiffness schedule.

The template keeps its topology (so its rig, skin weights, parts and landmarks' definitions
stay valid) and takes the scan's shape. Each non-rigid iteration finds correspondences both
ways — every template vertex to its closest point on the scan, and a sample of scan points to
their closest points on the template (barycentric, so they pull on a triangle's three
vertices) — drops those that are far, whose normals disagree, or that land on a hole's rim (the
template fills the holes), and solves one sparse linear system for the displacements: the
correspondence terms plus a membrane term ``stiffness · Σ_edges |d_i − d_j|²`` over the
template's edges. The stiffness goes from stiff (the template moves almost as a whole) to
supple (it follows the scan's detail), like Amberg et al. (2007)'s optimal-step NICP, with
displacements rather than per-vertex affine transforms: the start is already close (the
measurement fit, the similarity and the arms' pose), which is what affine transforms are for.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
from scipy.optimize import minimize
from scipy.sparse.linalg import factorized
from scipy.spatial import cKDTree

from catwalk.body.limbs import ARM_PARAMETERS, pose_arms
from catwalk.errors import Cancelled
from catwalk.geometry.mesh import compact, edge_keys, folds, smooth_pairs, unique_edges
from catwalk.geometry.quat import axis_angle
from catwalk.geometry.raster import vertex_normals
from catwalk.geometry.surface import BodySurface

# (stiffness, iterations, reject beyond (m)): stiff to supple
SCHEDULE = ((200.0, 3, 0.05), (50.0, 3, 0.03), (15.0, 3, 0.02), (5.0, 3, 0.015),
            (2.0, 3, 0.01), (1.0, 2, 0.01), (0.5, 2, 0.008))
RIM_EPS = 1e-9              # a barycentric coordinate this small: the point is on that side
NORMAL_AGREEMENT = 0.5      # cosine: correspondences whose normals differ more are dropped
SCAN_SAMPLE = 25_000        # scan points pulling on the template per iteration
BACK_REJECT = 0.03          # m: scan points pull on the template from this far in every stage
FOCUS_REACH = 0.02          # m: scan points this near the hands all pull on the template
ARM_REACH = 0.25            # m: how far a posed arm may move out of its rest box


@dataclass
class Target:
    """The scan as a registration target (glTF metres), its triangles facing out."""
    vertices: np.ndarray
    faces: np.ndarray
    normals: np.ndarray
    tree: cKDTree
    surface: BodySurface
    rim_side: np.ndarray     # (F, 3) bool: the triangle's side k (vertex k to k + 1) is a boundary
    rim_vertex: np.ndarray   # (V,) bool: the vertex is on a boundary
    sample: np.ndarray       # indices of scan vertices used as points pulling on the template
    turned_out: bool = False  # the file's triangles faced in and were turned

    @classmethod
    def of(cls, vertices: np.ndarray, faces: np.ndarray, seed: int = 0) -> Target:
        v, f = compact(np.asarray(vertices, dtype=np.float64), faces)   # (no surface there)
        v, f = np.ascontiguousarray(v), np.ascontiguousarray(f)
        # a scan whose triangles wind inwards encloses a negative volume: turn them
        c = v.mean(axis=0)
        a, b, d = v[f[:, 0]] - c, v[f[:, 1]] - c, v[f[:, 2]] - c
        turned = float(np.sum(a * np.cross(b, d))) < 0.0
        if turned:
            f = np.ascontiguousarray(f[:, ::-1])
        keys = edge_keys(f, len(v))
        key, count = np.unique(keys, return_counts=True)
        once = key[count == 1]              # boundary sides: on one triangle only
        rim_side = np.isin(keys, once).reshape(-1, 3)
        rim_vertex = np.zeros(len(v), dtype=bool)
        rim_vertex[once // len(v)] = True
        rim_vertex[once % len(v)] = True
        rng = np.random.default_rng(seed)
        sample = rng.choice(len(v), size=min(SCAN_SAMPLE, len(v)), replace=False)
        return cls(v, f, vertex_normals(v, f), cKDTree(v), BodySurface(f, len(v)), rim_side,
                   rim_vertex, np.sort(sample), turned)

    def closest(self, points: np.ndarray):
        """(closest points on the scan, distances, normals there, on a hole's rim).

        On the rim: the closest point lies on a boundary side or at a boundary vertex — the
        scan has no surface beyond it, so the point is over a hole (a triangle merely touching
        a hole's edge is still the scan's surface)."""
        q, d, t, bary = self.surface.closest(self.vertices, points, tree=self.tree,
                                             normals=self.normals)
        n = self.normals[self.faces[t]].sum(axis=1)
        n /= np.linalg.norm(n, axis=1, keepdims=True) + 1e-30
        zero = bary < RIM_EPS                           # (s, u, w) for vertices (0, 1, 2)
        sides = self.rim_side[t]
        rim = (sides[:, 0] & zero[:, 2]) | (sides[:, 1] & zero[:, 0]) | (sides[:, 2] & zero[:, 1])
        at_vertex = np.sum(zero, axis=1) >= 2
        corner = self.faces[t, np.argmax(bary, axis=1)]
        rim |= at_vertex & self.rim_vertex[corner]
        return q, np.abs(d), n, rim


def _similarity_step(x: np.ndarray, q: np.ndarray, n: np.ndarray, w: np.ndarray):
    """One point-to-plane step: the small scale δ, rotation ω and move t minimising
    Σ w (n · ((1 + δ)(x − c) + ω × (x − c) + c + t − q))² (c: the weighted centroid).
    Returns (s, R, t) with x' = s R (x − c) + c + t, i.e. s R x + (c + t − s R c)."""
    c = (w @ x) / w.sum()
    r = x - c
    a = np.concatenate([np.sum(n * r, 1)[:, None], np.cross(r, n), n], axis=1)   # (N, 7)
    b = np.sum(n * (q - x), 1)
    sw = np.sqrt(w)
    sol = np.linalg.lstsq(a * sw[:, None], b * sw, rcond=None)[0]
    delta, omega, t = sol[0], sol[1:4], sol[4:7]
    angle = float(np.linalg.norm(omega))
    rot = axis_angle(omega / angle, angle) if angle > 1e-12 else np.eye(3)
    s = 1.0 + float(delta)
    return s, rot, c + t - s * rot @ c


def similarity(v: np.ndarray, use: np.ndarray, target: Target, iterations: int = 10):
    """Scale, turn and move the template (its ``use`` vertices' closest points, point to
    plane) onto the scan. Returns (moved vertices, scale, rotation, translation) of the
    whole: moved = scale · v @ rotationᵀ + translation."""
    # start centred as the scan's loader centres a scan: its box's middle on x = z = 0
    t_all = np.zeros(3)
    t_all[[0, 2]] = -0.5 * (v.min(axis=0) + v.max(axis=0))[[0, 2]]
    s_all, r_all = 1.0, np.eye(3)
    x = v + t_all
    for _ in range(iterations):
        q, d, qn, rim = target.closest(x[use])
        cut = max(0.01, float(np.percentile(d, 90)))
        w = ((d < cut) & ~rim).astype(np.float64)
        s, rot, t = _similarity_step(x[use], q, qn, w)
        x = s * x @ rot.T + t
        s_all, r_all, t_all = s * s_all, rot @ r_all, s * rot @ t_all + t
        turn = float(np.arccos(np.clip(0.5 * (np.trace(rot) - 1.0), -1.0, 1.0)))
        if abs(s - 1.0) < 1e-4 and np.linalg.norm(t) < 1e-4 and turn < 1e-4:
            break                   # a tenth of a millimetre over a body's height
    return x, s_all, r_all, t_all


def fit_arms(v: np.ndarray, skeleton, joints, weights, parts, target: Target,
             start: dict | None = None):
    """Each arm's pose (:data:`catwalk.body.limbs.ARM_PARAMETERS`, radians) that brings the
    template's arm onto the scan's: the shoulder first (a coarse grid, then Nelder–Mead), then
    shoulder, elbow and wrist together. Returns (posed vertices, side -> parameters)."""
    angles = {}
    world = skeleton.rest_world          # once: the cost below is evaluated hundreds of times
    for side, part in (("l", 1), ("r", 2)):
        arm = np.flatnonzero(parts == part)
        va, ja, wa = v[arm], joints[arm], weights[arm]
        # the scan's points within reach of the arm: a small tree, queried hundreds of times
        near = np.all((target.vertices > va.min(axis=0) - ARM_REACH)
                      & (target.vertices < va.max(axis=0) + ARM_REACH), axis=1)
        tree = cKDTree(target.vertices[near])

        def cost(a, side=side, va=va, ja=ja, wa=wa, tree=tree):
            x = pose_arms(va, skeleton, ja, wa, {side: a}, world=world)
            d, _ = tree.query(x, distance_upper_bound=0.05)
            return float(np.mean(np.minimum(d, 0.05)))

        if start is None:
            a0 = min(((a, f) for a in np.radians([-20, -10, 0, 10, 20])
                      for f in np.radians([-10, 0, 10])), key=lambda af: cost(np.array(af)))
            a0 = minimize(cost, np.array(a0), method="Nelder-Mead",
                          options={"xatol": 2e-3, "fatol": 1e-6, "maxfev": 60}).x
        else:
            a0 = np.asarray(start[side][:2])
        a0 = np.concatenate([a0, np.zeros(len(ARM_PARAMETERS) - 2)])
        res = minimize(cost, a0, method="Nelder-Mead",
                       options={"xatol": 2e-3, "fatol": 1e-6, "maxfev": 200,
                                "initial_simplex": a0 + np.vstack([np.zeros(5),
                                                                   0.05 * np.eye(5)])})
        angles[side] = [float(x) for x in res.x]
    return pose_arms(v, skeleton, joints, weights, angles, world=world), angles


def _membrane(faces: np.ndarray, n: int) -> sp.csr_matrix:
    """MᵀM for the template's edge incidence M: Σ_edges |d_i − d_j|² = dᵀ MᵀM d."""
    e = unique_edges(faces, n)
    rows = np.repeat(np.arange(len(e)), 2)
    m = sp.csr_matrix((np.tile([1.0, -1.0], len(e)), (rows, e.ravel())), shape=(len(e), n))
    return (m.T @ m).tocsc()


def unfold(x: np.ndarray, v0: np.ndarray, faces: np.ndarray, rounds: int = 20) -> np.ndarray:
    """Noise folds out: where two triangles that were smooth in the template ``v0`` fold over
    in ``x``, their vertices and the ring around them take their neighbours' mean
    displacement, round after round until none is folded (a few hundred of 13,380 vertices
    move, by a millimetre or so)."""
    n = len(x)
    e = unique_edges(faces, n)
    adj = sp.csr_matrix((np.ones(2 * len(e)), (e.ravel(), e[:, ::-1].ravel())), shape=(n, n))
    mean = sp.diags(1.0 / np.maximum(np.asarray(adj.sum(axis=1)).ravel(), 1.0)) @ adj
    smooth = smooth_pairs(v0, faces)
    x = x.copy()
    for _ in range(rounds):
        bad = folds(x, v0, faces, smooth)
        if not len(bad):
            break
        near = np.zeros(n, dtype=bool)
        near[faces[bad.ravel()].ravel()] = True
        near |= (adj @ near.astype(float)) > 0
        d = x - v0
        x[near] = v0[near] + (mean @ d)[near]
    return x


def nonrigid(v0: np.ndarray, faces: np.ndarray, target: Target, schedule=SCHEDULE,
             focus: np.ndarray | None = None, cancel=None) -> np.ndarray:
    """Non-rigid ICP of the template ``v0`` onto ``target`` (see the module's text).

    ``focus``: template vertices with fine detail (the hands): every scan point within 2 cm of
    them pulls on the template, besides the random sample (fingertips are few of its points).
    ``cancel()`` is asked before every round (:class:`~catwalk.errors.Cancelled`)."""
    n = len(v0)
    faces = np.ascontiguousarray(faces, dtype=np.int64)
    reg = _membrane(faces, n)
    own = BodySurface(faces, n)
    sample = target.sample
    if focus is not None and len(focus):
        d, _ = cKDTree(v0[focus]).query(target.vertices, distance_upper_bound=FOCUS_REACH)
        sample = np.union1d(sample, np.flatnonzero(np.isfinite(d)))
    pts = target.vertices[sample]
    pts_n = target.normals[sample]
    back_w = n / max(1, len(pts))
    x = v0.copy()
    for stiff, iters, reject in schedule:
        for _ in range(iters):
            if cancel is not None and cancel():
                raise Cancelled("registration cancelled")
            nrm = vertex_normals(x, faces)
            # template → scan
            q, d, qn, rim = target.closest(x)
            wf = ((d < reject) & ~rim & (np.sum(qn * nrm, 1) > NORMAL_AGREEMENT)).astype(float)
            # scan → template (barycentric rows)
            c, dc, tri, bary = own.closest(x, pts, normals=nrm)
            tv = faces[tri]
            tn = nrm[tv].sum(axis=1)
            tn /= np.linalg.norm(tn, axis=1, keepdims=True) + 1e-30
            wb = ((np.abs(dc) < max(reject, BACK_REJECT))
                  & (np.sum(tn * pts_n, 1) > NORMAL_AGREEMENT)) * back_w
            rows = np.repeat(np.arange(len(pts)), 3)
            b = sp.csr_matrix((bary.ravel(), (rows, tv.ravel())), shape=(len(pts), n))
            bw = b.multiply(wb[:, None]).tocsr()
            k = sp.diags(wf) + (b.T @ bw) + stiff * reg
            rhs = wf[:, None] * (q - x) + bw.T @ (pts - c)
            solve = factorized(k.tocsc())
            x = x + np.stack([solve(np.ascontiguousarray(rhs[:, j])) for j in range(3)], 1)
    return x
