"""Linear blend skinning with sparse 4-influence weights, and forward kinematics.

``skin`` runs a numba kernel over flat arrays: each vertex blends at most 4 joint matrices
(3×4, float32). ``joint_world_matrices`` composes local node transforms down the hierarchy,
vectorised over frames. ``body_frames`` turns a Body and a Motion into per-frame world-space
vertices and vertex velocities (central differences of the looping motion, m/s) — what the
cloth simulation needs.
"""

from __future__ import annotations

import numba
import numpy as np

from catwalk.body.types import Body, Motion, Skeleton
from catwalk.errors import Cancelled, InputError
from catwalk.geometry.quat import quat_to_mat


@numba.njit(cache=True, fastmath=True, nogil=True, boundscheck=False)
def _skin_one(rest, joints, weights, mats, out):
    """out[i] = Σ_k weights[i,k] · mats[joints[i,k]] · [rest[i], 1]; float32 throughout,
    zero-weight slots skipped."""
    n = rest.shape[0]
    for i in range(n):
        x = rest[i, 0]
        y = rest[i, 1]
        z = rest[i, 2]
        ox = np.float32(0.0)
        oy = np.float32(0.0)
        oz = np.float32(0.0)
        for k in range(4):
            w = weights[i, k]
            if w == 0.0:
                continue
            j = joints[i, k]
            ox += w * (mats[j, 0, 0] * x + mats[j, 0, 1] * y + mats[j, 0, 2] * z + mats[j, 0, 3])
            oy += w * (mats[j, 1, 0] * x + mats[j, 1, 1] * y + mats[j, 1, 2] * z + mats[j, 1, 3])
            oz += w * (mats[j, 2, 0] * x + mats[j, 2, 1] * y + mats[j, 2, 2] * z + mats[j, 2, 3])
        out[i, 0] = ox
        out[i, 1] = oy
        out[i, 2] = oz


@numba.njit(cache=True, fastmath=True, nogil=True)
def _skin_many(rest, joints, weights, mats, out):
    for f in range(mats.shape[0]):
        _skin_one(rest, joints, weights, mats[f], out[f])


class Skinner:
    """A body's skinning data converted once (float32 rest positions and weights, int32 joint
    indices), for skinning many frames one call at a time (the cloth simulation's loop)."""

    def __init__(self, rest_vertices: np.ndarray, skin_joints: np.ndarray,
                 skin_weights: np.ndarray, n_joints: int | None = None):
        self.rest = np.ascontiguousarray(rest_vertices, dtype=np.float32)
        self.joints = np.ascontiguousarray(skin_joints, dtype=np.int32)
        self.weights = np.ascontiguousarray(skin_weights, dtype=np.float32)
        n = self.rest.shape[0]
        if self.rest.ndim != 2 or self.rest.shape[1] != 3 or self.joints.shape != (n, 4) \
                or self.weights.shape != (n, 4):
            raise ValueError("skin: rest (N,3), joints (N,4), weights (N,4) expected")
        self.max_joint = int(self.joints.max()) if n else -1
        if n and self.joints.min() < 0:
            raise ValueError("skin: negative joint index")
        if n_joints is not None and self.max_joint >= n_joints:
            raise ValueError("skin: joint index out of range")

    def __call__(self, joint_matrices: np.ndarray, out: np.ndarray | None = None) -> np.ndarray:
        """(J,4,4) → (N,3), or (F,J,4,4) → (F,N,3), float32; ``out`` may be given."""
        mats = np.asarray(joint_matrices)
        if self.max_joint >= mats.shape[-3]:
            raise ValueError("skin: joint index out of range")
        m34 = mats[..., :3, :4]
        if m34.dtype != np.float32 or not m34.flags.c_contiguous:
            m34 = np.ascontiguousarray(m34, dtype=np.float32)
        shape = m34.shape[:-3] + self.rest.shape
        if out is None:
            out = np.empty(shape, dtype=np.float32)
        elif out.shape != shape or out.dtype != np.float32 or not out.flags.c_contiguous:
            raise ValueError(f"skin: out must be a C-contiguous float32 array {shape}")
        if m34.ndim == 3:
            _skin_one(self.rest, self.joints, self.weights, m34, out)
        else:
            _skin_many(self.rest, self.joints, self.weights, m34.reshape((-1,) + m34.shape[-3:]),
                       out.reshape((-1,) + self.rest.shape))
        return out


def skin(rest_vertices: np.ndarray, skin_joints: np.ndarray, skin_weights: np.ndarray,
         joint_matrices: np.ndarray) -> np.ndarray:
    """Skinned vertices, float32.

    ``joint_matrices`` are skinning matrices (joint world × inverse bind): (J, 4, 4) for one
    frame → (N, 3), or (F, J, 4, 4) for F frames → (F, N, 3). For many single-frame calls,
    build a :class:`Skinner` once instead.
    """
    return Skinner(rest_vertices, skin_joints, skin_weights)(joint_matrices)


def local_matrices(rotations: np.ndarray, translations: np.ndarray) -> np.ndarray:
    """(..., J, 4, 4) local transforms from quaternions (..., J, 4) and translations (..., J, 3)."""
    rotations = np.asarray(rotations, dtype=np.float64)
    out = np.zeros(rotations.shape[:-1] + (4, 4))
    out[..., :3, :3] = quat_to_mat(rotations)
    out[..., :3, 3] = translations
    out[..., 3, 3] = 1.0
    return out


def joint_world_matrices(skeleton: Skeleton, rotations: np.ndarray,
                         translations: np.ndarray) -> np.ndarray:
    """Forward kinematics: world matrices (..., J, 4, 4) from local rotations (..., J, 4)
    (x, y, z, w) and translations (..., J, 3); leading axes (frames) are vectorised."""
    local = local_matrices(rotations, translations)
    world = np.empty_like(local)
    for j, p in enumerate(skeleton.parents):
        world[..., j, :, :] = local[..., j, :, :] if p < 0 else \
            world[..., p, :, :] @ local[..., j, :, :]
    return world


def skinning_matrices(skeleton: Skeleton, world: np.ndarray) -> np.ndarray:
    return world @ skeleton.inverse_bind


def motion_matrices(body: Body, motion: Motion) -> np.ndarray:
    """The skinning matrices (F, J, 4, 4) of ``motion``'s frames on ``body``'s rig."""
    sk = body.skeleton
    return skinning_matrices(sk, joint_world_matrices(sk, motion.rotations, motion.translations))


def blended_matrices(body: Body, mats: np.ndarray, vertices: np.ndarray) -> np.ndarray:
    """Each of ``vertices``' blended skinning transform (P, 4, 4), Σ wₖ·Mₖ over its joints,
    at one frame's skinning matrices ``mats`` (J, 4, 4)."""
    j = body.skin_joints[vertices].astype(np.int64)
    return np.einsum("pk,pkij->pij", body.skin_weights[vertices].astype(np.float64), mats[j])


def rigid_deviation(body: Body, mats: np.ndarray, verts: np.ndarray) -> np.ndarray:
    """Per vertex, the farthest (m) its skinned position ``verts`` (F, N, 3) over F frames of
    skinning matrices ``mats`` (F, J, 4, 4, :func:`motion_matrices`) strays from where its
    dominant joint's transform alone carries it (0: the vertex moves rigidly with one bone,
    as a distance field in that bone's frame would)."""
    dom = body.skin_joints[np.arange(len(body.vertices)), np.argmax(body.skin_weights, axis=1)]
    rest = np.c_[body.vertices, np.ones(len(body.vertices))]
    out = np.zeros(len(body.vertices))
    for f in range(len(mats)):   # a frame at a time: (N, 3, 4) gathered, not (F, N, 3, 4)
        carried = np.einsum("vij,vj->vi", mats[f, dom, :3, :], rest)
        np.maximum(out, np.linalg.norm(carried - verts[f], axis=1), out=out)
    return out


def body_frames(body: Body, motion: Motion, *, cancel=None, progress=None,
                chunk: int = 16) -> tuple[np.ndarray, np.ndarray]:
    """Per-frame world-space vertices (F, N, 3) float32 and velocities (F, N, 3) float32 (m/s).

    Velocities are central differences; a looping motion wraps around, its last frame followed
    by the first shifted by ``motion.meta["loop_offset"]`` (the distance walked per loop).
    The frames are skinned ``chunk`` at a time; between two chunks ``cancel()`` is asked
    (:class:`~catwalk.errors.Cancelled`) and ``progress("skinning", done, frames)`` told
    (:mod:`catwalk.progress`).
    """
    if body.skeleton is None or body.skin_joints is None or body.skin_weights is None:
        raise InputError("this body has no rig (skeleton and skin weights); cannot animate it")
    sk = body.skeleton
    if motion.rotations.shape[1] != len(sk.names):
        raise InputError(f"motion has {motion.rotations.shape[1]} joints, the body's rig "
                           f"has {len(sk.names)}")
    mats = motion_matrices(body, motion)
    skinner = Skinner(body.vertices, body.skin_joints, body.skin_weights)
    parts = []
    for a in range(0, max(len(mats), 1), chunk):
        if cancel is not None and cancel():
            raise Cancelled("try-on cancelled")
        parts.append(skinner(mats[a:a + chunk]))
        if progress is not None:
            progress("skinning", min(a + chunk, len(mats)), len(mats))
    verts = np.concatenate(parts) if len(parts) > 1 else parts[0]
    nf = verts.shape[0]
    vel = np.empty_like(verts)
    dt = 1.0 / float(motion.fps)
    if nf == 1:
        vel[:] = 0.0
        return verts, vel
    if motion.loop:
        offset = np.asarray(motion.meta.get("loop_offset", (0.0, 0.0, 0.0)), dtype=np.float32)
        if nf >= 3:
            vel[1:-1] = (verts[2:] - verts[:-2]) / (2 * dt)
        vel[0] = (verts[1] - (verts[-1] - offset)) / (2 * dt)
        vel[-1] = ((verts[0] + offset) - verts[-2]) / (2 * dt)
    else:
        if nf >= 3:
            vel[1:-1] = (verts[2:] - verts[:-2]) / (2 * dt)
        vel[0] = (verts[1] - verts[0]) / dt
        vel[-1] = (verts[-1] - verts[-2]) / dt
    return verts, vel
