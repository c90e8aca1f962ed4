"""Checks of a walk (the tests and ``catwalk bench gait``): the planted foot's sliding, the
folds and inverted triangles of the skinned body, the sagittal joint angles against the
curves, the faces under the armpits."""

from __future__ import annotations

import numpy as np

from catwalk.body.rig import armpit_seam
from catwalk.body.skinning import joint_world_matrices, skinning_matrices
from catwalk.body.types import Body, Motion
from catwalk.geometry.mesh import face_normals, folds, smooth_pairs
from catwalk.motion.gait import PELVIC_TILT_MEAN_DEG, STANCE_END


def foot_vertices(body: Body, side: str) -> np.ndarray:
    """Indices of the vertices that the foot and toe bones of ``side`` ('l'/'r') carry."""
    sk = body.skeleton
    w = np.zeros(len(body.vertices))
    for name in (f"foot_{side}", f"ball_{side}"):
        w += (body.skin_weights * (body.skin_joints == sk.index(name))).sum(axis=1)
    return np.flatnonzero(w > 0.3)


def foot_sliding(body: Body, motion: Motion, verts: np.ndarray, contact: float = 0.004):
    """Accumulated horizontal motion (m) of the stance foot's floor-contact vertices, one value
    per step: for each pair of consecutive stance frames, the mean horizontal displacement of
    the foot's vertices lower than ``contact`` in both, summed over the stance phase."""
    period = motion.meta["cycle_s"]
    t = np.arange(motion.frames) / motion.fps
    out = []
    for side, phase0 in (("l", 0.0), ("r", 0.5)):
        fv = foot_vertices(body, side)
        tau = t / period - phase0
        ph, step = tau % 1.0, np.floor(tau)
        for k in np.unique(step):
            frames = np.flatnonzero((step == k) & (ph < STANCE_END))
            total = 0.0
            for a, c in zip(frames[:-1], frames[1:], strict=True):
                va, vc = verts[a, fv], verts[c, fv]
                touch = (va[:, 1] < contact) & (vc[:, 1] < contact)
                if touch.any():
                    total += float(np.linalg.norm((vc - va)[touch][:, [0, 2]], axis=1).mean())
            if len(frames) >= 2:
                out.append(total)
    return np.array(out)


def walk_folds(body: Body, verts: np.ndarray, every: int = 2) -> int:
    """The most triangle pairs folded over (normals more than 90° apart) in any of the walk's
    frames (every ``every``-th) that were smooth (under 60°) at rest: the skinning's creases."""
    smooth = smooth_pairs(body.vertices, body.faces)
    return max(len(folds(np.asarray(verts[i], np.float64), body.vertices, body.faces, smooth))
               for i in range(0, len(verts), every))


def sagittal_angles(body: Body, motion: Motion, side: str = "l"):
    """(phase, hip, knee, ankle) in degrees over the frames of a walk, measured from the joint
    positions in the sagittal (y, z) plane the way the tables define them: hip flexion of the
    thigh against the pelvis (lab convention: thigh angle to the vertical + the mean anterior
    tilt), knee flexion, ankle dorsiflexion; the rest pose reads 0 for the knee and ankle."""
    sk = body.skeleton
    names = [f"thigh_{side}", f"calf_{side}", f"foot_{side}", f"ball_{side}"]
    js = [sk.index(n) for n in names]
    world = joint_world_matrices(sk, motion.rotations, motion.translations)[..., :3, 3]
    rest = sk.rest_world[:, :3, 3]

    def seg(p, a, b):
        v = p[..., b, :] - p[..., a, :]
        return np.degrees(np.arctan2(v[..., 2], -v[..., 1]))   # + = distal end forward

    def foot(p):
        v = p[..., js[3], :] - p[..., js[2], :]
        return np.degrees(np.arctan2(v[..., 1], v[..., 2]))    # + = toes up

    thigh, shank, ft = seg(world, js[0], js[1]), seg(world, js[1], js[2]), foot(world)
    thigh0, shank0, ft0 = seg(rest, js[0], js[1]), seg(rest, js[1], js[2]), foot(rest)
    hip = thigh - thigh0 + PELVIC_TILT_MEAN_DEG
    knee = (thigh - thigh0) - (shank - shank0)
    ankle = (ft - ft0) - (shank - shank0)
    phase0 = 0.0 if side == "l" else 0.5
    phase = (np.arange(motion.frames) / motion.fps / motion.meta["cycle_s"] - phase0) % 1.0
    return phase, hip, knee, ankle


def armpit_faces(body: Body, reach: float = 0.06) -> np.ndarray:
    """Indices of the body's triangles with a corner within ``reach`` (m, at rest) of a seam
    between the torso and an arm: the armpits and the tops of the shoulders."""
    from scipy.spatial import cKDTree  # deferred: scipy loads in ≈ 0.3 s; only this path needs it


    v = np.asarray(body.vertices, np.float64)
    tri = np.asarray(body.faces, np.int64)
    seam = v[armpit_seam(tri, body.parts)]
    d, _ = cKDTree(seam).query(v, distance_upper_bound=reach)
    return np.flatnonzero(np.isfinite(d)[tri].any(axis=1))


def inverted_triangles(body: Body, motion: Motion, verts: np.ndarray,
                       faces: np.ndarray | None = None) -> np.ndarray:
    """Per frame, how many of ``faces`` (default: all the body's) the skinning turns inside out:
    the posed triangle's normal points away from its rest normal carried by the blended
    rotation of its corners (the skinning's own frame there). A smooth rig has none; linear
    blend skinning folds a joint's crease over itself where the weights change too abruptly
    (the armpit with MakeHuman's weights, :mod:`catwalk.body.rig`)."""
    tri = np.asarray(body.faces if faces is None else faces, dtype=np.int64)
    corners = np.unique(tri)
    local = np.searchsorted(corners, tri)
    joints = body.skin_joints[corners].astype(np.int64)
    weights = body.skin_weights[corners].astype(np.float64)
    rest = face_normals(np.asarray(body.vertices, np.float64), tri)
    mats = skinning_matrices(body.skeleton, joint_world_matrices(
        body.skeleton, motion.rotations, motion.translations))[..., :3, :3]
    out = np.zeros(len(verts), dtype=np.int64)
    for f in range(len(verts)):
        rot = np.einsum("vk,vkij->vij", weights, mats[f][joints])[local].sum(axis=1)
        carried = np.einsum("tij,tj->ti", rot, rest)
        posed = face_normals(np.asarray(verts[f], np.float64), tri)
        out[f] = int((np.einsum("ti,ti->t", carried, posed) < 0).sum())
    return out
