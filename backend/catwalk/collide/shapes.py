"""Analytic test bodies: UV spheres, (tapered, elliptic) capsules, and a capsule *mannequin*
with the body's part labels (0 torso+head, 1 left arm, 2 right arm, 3 left leg, 4 right leg) in
glTF axes (+Y up, faces +Z, feet on y = 0; the body's left is +X), posable, with a simple walk.

The mannequin is a union of closed capsules (they overlap at the joints, they are not welded):
enough for colliders, which only need closed surfaces per part. ``resolution`` scales the
triangle count (1.0 ≈ 5.3k triangles; 2.25 ≈ 26.7k, the MakeHuman body's count).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from catwalk.body.types import (
    PART_LEFT_ARM,
    PART_LEFT_LEG,
    PART_RIGHT_ARM,
    PART_RIGHT_LEG,
    PART_TORSO,
)


def _frame(axis):
    """Two unit vectors orthogonal to ``axis`` (unit), right-handed (e1, e2, axis)."""
    a = np.asarray(axis, dtype=np.float64)
    helper = np.array([0.0, 0.0, 1.0]) if abs(a[2]) < 0.9 else np.array([1.0, 0.0, 0.0])
    e1 = np.cross(helper, a)
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(a, e1)
    return e1, e2


def capsule(a, b, r0, r1=None, n_around=24, n_cap=6, n_body=6, squash=1.0, squash_dir=None):
    """A closed capsule from ``a`` to ``b`` (radius ``r0`` at a, ``r1`` at b), outward faces.

    ``squash`` scales the cross-section along ``squash_dir`` (made orthogonal to the axis):
    an elliptic capsule (a torso). Returns (vertices (N,3), faces (M,3) int32).
    """
    a = np.asarray(a, dtype=np.float64)
    b = np.asarray(b, dtype=np.float64)
    r1 = r0 if r1 is None else r1
    axis = b - a
    length = float(np.linalg.norm(axis))
    if length < 1e-12:
        axis = np.array([0.0, 1.0, 0.0])
    else:
        axis = axis / length
    e1, e2 = _frame(axis)
    if squash_dir is not None and squash != 1.0:
        d = np.asarray(squash_dir, dtype=np.float64)
        d = d - axis * (d @ axis)
        d /= np.linalg.norm(d)
        e1, e2 = d, np.cross(axis, d)
    # profile: (offset along axis, radius) from the pole at a to the pole at b
    prof = []
    for k in range(1, n_cap + 1):  # cap at a, from near the pole to the equator
        t = (math.pi / 2) * k / n_cap
        prof.append((a, -math.cos(t) * r0, math.sin(t) * r0))
    for k in range(1, n_body):
        s = k / n_body
        prof.append((a + s * (b - a), 0.0, (1 - s) * r0 + s * r1))
    for k in range(n_cap if length >= 1e-12 else n_cap - 1, 0, -1):  # a sphere: one equator
        t = (math.pi / 2) * k / n_cap
        prof.append((b, math.cos(t) * r1, math.sin(t) * r1))
    phi = np.linspace(0.0, 2 * math.pi, n_around, endpoint=False)
    ring = np.cos(phi)[:, None] * e1 * squash + np.sin(phi)[:, None] * e2
    verts = [a - axis * r0]
    for c, off, rad in prof:
        verts.extend(c + axis * off + rad * ring)
    verts.append(b + axis * r1)
    v = np.array(verts)
    nr = len(prof)
    faces = []
    ring_idx = lambda k, j: 1 + k * n_around + (j % n_around)  # noqa: E731
    for j in range(n_around):  # fan at a: normal must point along -axis
        faces.append((0, ring_idx(0, j + 1), ring_idx(0, j)))
    for k in range(nr - 1):
        for j in range(n_around):
            p, q = ring_idx(k, j), ring_idx(k, j + 1)
            s, t = ring_idx(k + 1, j), ring_idx(k + 1, j + 1)
            faces.append((p, q, t))
            faces.append((p, t, s))
    last = len(v) - 1
    for j in range(n_around):
        faces.append((last, ring_idx(nr - 1, j), ring_idx(nr - 1, j + 1)))
    f = np.array(faces, dtype=np.int32)
    return v, f


def sphere(centre=(0.0, 0.0, 0.0), radius=0.1, n_around=48, n_rings=24):
    """A UV sphere (a capsule of zero length). Returns (vertices, faces)."""
    c = np.asarray(centre, dtype=np.float64)
    return capsule(c, c, radius, n_around=n_around, n_cap=max(n_rings // 2, 2), n_body=1)


def notched_prism(half=0.05, depth=0.03, half_width=0.005, length=0.1, rings=21):
    """A square prism along Z (side ``2·half``, ``length`` long, centred on the origin) with a
    V notch ``depth`` deep and ``2·half_width`` wide cut along the middle of its top face (a
    fold of one part onto itself, like the skinned arm's under the armpit), outward faces,
    ``rings`` rings along Z. Flat shaded: each triangle has its own three vertices, so its
    normal is the face's up to the notch's bottom. Returns (vertices, faces)."""
    a, d, w = half, depth, half_width
    poly = np.array([(-a, -a), (a, -a), (a, a), (w, a), (0.0, a - d), (-w, a), (-a, a)])
    n = len(poly)   # counter-clockwise seen from +Z
    zs = np.linspace(-length / 2, length / 2, rings)
    v = np.r_[np.concatenate([np.c_[poly, np.full(n, z)] for z in zs]),
              [[0.0, -a / 2, zs[0]], [0.0, -a / 2, zs[-1]]]]
    c0, c1, last = rings * n, rings * n + 1, (rings - 1) * n
    faces = []
    for i in range(n):
        j = (i + 1) % n
        for r in range(rings - 1):
            p, q = r * n, (r + 1) * n
            faces += [(p + i, p + j, q + j), (p + i, q + j, q + i)]
        faces += [(c0, j, i), (c1, last + i, last + j)]   # the end caps (fans)
    f = np.array(faces)
    return v[f].reshape(-1, 3), np.arange(3 * len(f), dtype=np.int32).reshape(-1, 3)


def notched_prism_depth(points, half=0.05, depth=0.03, half_width=0.005, length=0.1):
    """How deep each point is inside :func:`notched_prism` of the same sizes (0 outside), for
    points near its notch (within the prism's length)."""
    a, d, w = half, depth, half_width
    x, y, z = np.asarray(points, dtype=np.float64).T
    beta = math.atan2(w, d)   # the notch's half angle
    # signed distances to the notch's two faces' planes, positive on the notch's side
    da = x * math.cos(beta) + (y - (a - d)) * math.sin(beta)
    db = -x * math.cos(beta) + (y - (a - d)) * math.sin(beta)
    inside = (np.abs(x) < a) & (np.abs(y) < a) & (np.abs(z) < length / 2) & (
        (da < 0) | (db < 0))
    return np.where(inside, np.maximum(-da, -db), 0.0)


def merge(meshes):
    """Concatenate (vertices, faces) pairs into one mesh."""
    vs, fs, off = [], [], 0
    for v, f in meshes:
        vs.append(v)
        fs.append(f + off)
        off += len(v)
    return np.vstack(vs), np.vstack(fs).astype(np.int32)


def _rot_x(deg):
    t = math.radians(deg)
    c, s = math.cos(t), math.sin(t)
    return np.array([[1, 0, 0], [0, c, -s], [0, s, c]])


def _rot_z(deg):
    t = math.radians(deg)
    c, s = math.cos(t), math.sin(t)
    return np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])


def _rot_y(deg):
    t = math.radians(deg)
    c, s = math.cos(t), math.sin(t)
    return np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]])


@dataclass
class Pose:
    """Joint angles in degrees. Arm/leg *swing* rotates the limb forwards (+Z) about the
    shoulder/hip; *abduct* outwards (away from the body's mid-plane); ``elbow``/``knee`` flex;
    ``forearm_in`` turns the forearm inwards (towards the mid-plane, about the vertical) after
    the elbow flexes; ``offset`` translates the whole body."""

    l_arm_swing: float = 0.0
    r_arm_swing: float = 0.0
    l_arm_abduct: float = 6.0
    r_arm_abduct: float = 6.0
    l_elbow: float = 10.0
    r_elbow: float = 10.0
    l_forearm_in: float = 0.0
    r_forearm_in: float = 0.0
    l_leg_swing: float = 0.0
    r_leg_swing: float = 0.0
    l_knee: float = 5.0
    r_knee: float = 5.0
    offset: tuple = (0.0, 0.0, 0.0)


# dimensions (metres) of a ≈1.72 m mannequin
SHOULDER_Y, SHOULDER_X = 1.42, 0.20
HIP_Y, HIP_X = 0.93, 0.09
UPPER_ARM, FOREARM, THIGH, SHIN = 0.29, 0.26, 0.44, 0.43


@dataclass
class Mannequin:
    """A posable capsule body: ``faces`` (M,3) int32 and ``parts`` (N,) int8 fixed;
    :meth:`vertices` (N,3) for a :class:`Pose`."""

    resolution: float = 1.0

    def __post_init__(self):
        v, f, p = self._build(Pose())
        self.faces = f
        self.parts = p
        self.rest = v

    def _res(self, n):
        return max(int(round(n * math.sqrt(self.resolution))), 3)

    def _build(self, pose: Pose):
        R = self._res
        meshes, parts = [], []

        def add(mesh, part):
            meshes.append(mesh)
            parts.append(np.full(len(mesh[0]), part, np.int8))

        # torso + head (part 0): elliptic torso, pelvis, neck, head
        add(capsule((0, 1.02, 0), (0, 1.33, 0), 0.15, 0.17, n_around=R(40), n_cap=R(8),
                    n_body=R(10), squash=0.68, squash_dir=(0, 0, 1)), PART_TORSO)
        add(capsule((-0.06, 0.93, 0), (0.06, 0.93, 0), 0.11, n_around=R(28), n_cap=R(6),
                    n_body=R(4)), PART_TORSO)
        add(capsule((0, 1.38, 0), (0, 1.52, 0), 0.055, n_around=R(20), n_cap=R(4),
                    n_body=R(3)), PART_TORSO)
        add(capsule((0, 1.58, 0.01), (0, 1.64, 0.0), 0.095, n_around=R(32), n_cap=R(8),
                    n_body=R(3)), PART_TORSO)
        for side, part in ((1.0, PART_LEFT_ARM), (-1.0, PART_RIGHT_ARM)):
            pre = "l" if side > 0 else "r"
            swing = getattr(pose, f"{pre}_arm_swing")
            abduct = getattr(pose, f"{pre}_arm_abduct")
            elbow = getattr(pose, f"{pre}_elbow")
            fin = getattr(pose, f"{pre}_forearm_in")
            sh = np.array([side * SHOULDER_X, SHOULDER_Y, 0.0])
            rot = _rot_x(-swing) @ _rot_z(side * abduct)
            down = np.array([0.0, -1.0, 0.0])
            el = sh + rot @ (down * UPPER_ARM)
            frot = rot @ _rot_x(-elbow)
            fdir = _rot_y(-side * fin) @ (frot @ down)
            wr = el + fdir * FOREARM
            hand = wr + fdir * 0.08
            add(capsule(sh, el, 0.05, 0.04, n_around=R(24), n_cap=R(5), n_body=R(8)), part)
            add(capsule(el, wr, 0.04, 0.03, n_around=R(24), n_cap=R(5), n_body=R(8)), part)
            add(capsule(wr, hand, 0.03, 0.025, n_around=R(16), n_cap=R(4), n_body=R(3)),
                part)
        for side, part in ((1.0, PART_LEFT_LEG), (-1.0, PART_RIGHT_LEG)):
            pre = "l" if side > 0 else "r"
            swing = getattr(pose, f"{pre}_leg_swing")
            knee = getattr(pose, f"{pre}_knee")
            hp = np.array([side * HIP_X, HIP_Y, 0.0])
            rot = _rot_x(-swing)
            down = np.array([0.0, -1.0, 0.0])
            kn = hp + rot @ (down * THIGH)
            srot = rot @ _rot_x(knee)
            an = kn + srot @ (down * SHIN)
            toe = an + srot @ np.array([0.0, -0.02, 0.16])
            add(capsule(hp, kn, 0.075, 0.05, n_around=R(28), n_cap=R(5), n_body=R(10)), part)
            add(capsule(kn, an, 0.05, 0.035, n_around=R(24), n_cap=R(5), n_body=R(10)), part)
            add(capsule(an, toe, 0.035, 0.03, n_around=R(16), n_cap=R(4), n_body=R(4)), part)
        v, f = merge(meshes)
        v = v + np.asarray(pose.offset, dtype=np.float64)
        return v, f, np.concatenate(parts)

    def vertices(self, pose: Pose) -> np.ndarray:
        return self._build(pose)[0]


def walk_pose(t: float, period: float = 1.1, speed: float = 0.0, arm_amp: float = 22.0,
              leg_amp: float = 25.0) -> Pose:
    """A simple sinusoidal walk at time ``t`` (s): legs and opposite arms swing; ``speed``
    (m/s) moves the body along +Z."""
    ph = 2 * math.pi * t / period
    s = math.sin(ph)
    return Pose(
        l_arm_swing=-arm_amp * s, r_arm_swing=arm_amp * s,
        l_elbow=15 + 10 * max(-s, 0), r_elbow=15 + 10 * max(s, 0),
        l_leg_swing=leg_amp * s, r_leg_swing=-leg_amp * s,
        l_knee=5 + 30 * max(math.sin(ph + 1.2), 0), r_knee=5 + 30 * max(-math.sin(ph + 1.2), 0),
        offset=(0.0, 0.0, speed * t),
    )


def figure10_pose() -> Pose:
    """The paper's figure-10 case: the right arm swung forward, elbow bent, the forearm across
    the front of the torso."""
    return Pose(r_arm_swing=20.0, r_elbow=80.0, r_forearm_in=75.0, r_arm_abduct=4.0,
                l_arm_swing=-15.0, l_leg_swing=-12.0, r_leg_swing=12.0)


def walk_frames(mannequin: Mannequin, times, **walk_kw):
    """Vertices and velocities (central differences) of the walk at ``times``:
    (T,N,3), (T,N,3)."""
    times = np.asarray(times, dtype=np.float64)
    h = 1e-3
    vs, vels = [], []
    for t in times:
        v = mannequin.vertices(walk_pose(t, **walk_kw))
        vp = mannequin.vertices(walk_pose(t + h, **walk_kw))
        vm = mannequin.vertices(walk_pose(t - h, **walk_kw))
        vs.append(v)
        vels.append((vp - vm) / (2 * h))
    return np.array(vs), np.array(vels)
