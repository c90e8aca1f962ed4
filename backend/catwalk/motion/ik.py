"""Two-bone inverse kinematics (thigh + shank, upper arm + forearm), vectorised over frames."""

from __future__ import annotations

import numpy as np

from catwalk.geometry.quat import frame_from, orthonormalize


def two_bone_ik(root: np.ndarray, target: np.ndarray, pole: np.ndarray, l1: float, l2: float,
                min_bend_deg: float = 0.5):
    """Middle-joint positions (knee/elbow) for chains root → mid → end reaching ``target``.

    ``root``, ``target``, ``pole`` are (F, 3); the middle joint bends towards ``pole`` (a
    direction, e.g. forward for a knee). A target out of reach is pulled in along the line from
    the root, so the chain never fully straightens (``min_bend_deg``) or folds past itself.
    Returns ``(mid (F,3), end (F,3))`` where ``end`` is the (possibly clamped) reached point.
    """
    root = np.asarray(root, dtype=np.float64)
    d = np.asarray(target, dtype=np.float64) - root
    dist = np.linalg.norm(d, axis=-1)
    u = d / np.maximum(dist, 1e-12)[..., None]
    bend = np.radians(min_bend_deg)
    dmax = np.sqrt(l1 * l1 + l2 * l2 + 2 * l1 * l2 * np.cos(bend))
    dmin = abs(l1 - l2) + 1e-6
    dist_c = np.clip(dist, dmin, dmax)
    cos_a = np.clip((l1 * l1 + dist_c * dist_c - l2 * l2) / (2 * l1 * dist_c), -1.0, 1.0)
    sin_a = np.sqrt(1.0 - cos_a * cos_a)
    w = orthonormalize(np.broadcast_to(pole, d.shape), u)
    mid = root + l1 * (cos_a[..., None] * u + sin_a[..., None] * w)
    end = root + dist_c[..., None] * u
    return mid, end


def bone_delta(rest_dir: np.ndarray, rest_side: np.ndarray, new_dir: np.ndarray,
               new_side: np.ndarray) -> np.ndarray:
    """World-space rotations (F, 3, 3) taking a bone's rest (direction, side axis) frame to the
    new one: the bone points along ``new_dir`` with its side axis as close to ``new_side`` as the
    direction allows (no twist beyond what the side axes ask)."""
    f_rest = frame_from(np.broadcast_to(rest_dir, np.shape(new_dir)),
                        np.broadcast_to(rest_side, np.shape(new_dir)))
    f_new = frame_from(new_dir, new_side)
    return f_new @ np.swapaxes(f_rest, -1, -2)
