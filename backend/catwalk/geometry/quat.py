"""Rotation helpers, vectorised over leading axes. Quaternions are (x, y, z, w) as in glTF."""

from __future__ import annotations

import numpy as np


def axis_angle(axis, angle) -> np.ndarray:
    """Rotation matrices (..., 3, 3) for unit ``axis`` (..., 3) and ``angle`` (...) radians."""
    axis = np.asarray(axis, dtype=np.float64)
    angle = np.asarray(angle, dtype=np.float64)
    axis, angle = np.broadcast_arrays(axis, angle[..., None])
    angle = angle[..., 0]
    x, y, z = axis[..., 0], axis[..., 1], axis[..., 2]
    c, s = np.cos(angle), np.sin(angle)
    t = 1.0 - c
    out = np.empty(angle.shape + (3, 3))
    out[..., 0, 0] = t * x * x + c
    out[..., 0, 1] = t * x * y - s * z
    out[..., 0, 2] = t * x * z + s * y
    out[..., 1, 0] = t * x * y + s * z
    out[..., 1, 1] = t * y * y + c
    out[..., 1, 2] = t * y * z - s * x
    out[..., 2, 0] = t * x * z - s * y
    out[..., 2, 1] = t * y * z + s * x
    out[..., 2, 2] = t * z * z + c
    return out


def rot_x(angle) -> np.ndarray:
    return axis_angle([1.0, 0.0, 0.0], angle)


def rot_y(angle) -> np.ndarray:
    return axis_angle([0.0, 1.0, 0.0], angle)


def rot_z(angle) -> np.ndarray:
    return axis_angle([0.0, 0.0, 1.0], angle)


def mat_to_quat(m: np.ndarray) -> np.ndarray:
    """(..., 3, 3) rotation matrices → (..., 4) unit quaternions (x, y, z, w), w ≥ 0 not
    enforced (use :func:`make_continuous` for animation tracks)."""
    m = np.asarray(m, dtype=np.float64)
    shape = m.shape[:-2]
    m = m.reshape(-1, 3, 3)
    q = np.empty((m.shape[0], 4))
    tr = m[:, 0, 0] + m[:, 1, 1] + m[:, 2, 2]
    # four candidate formulas; pick the numerically best per matrix
    cand = np.stack([tr, m[:, 0, 0], m[:, 1, 1], m[:, 2, 2]], axis=1)
    k = np.argmax(cand, axis=1)
    for case in range(4):
        sel = k == case
        if not np.any(sel):
            continue
        a = m[sel]
        if case == 0:
            s = np.sqrt(np.maximum(tr[sel] + 1.0, 1e-300)) * 2.0
            q[sel, 3] = 0.25 * s
            q[sel, 0] = (a[:, 2, 1] - a[:, 1, 2]) / s
            q[sel, 1] = (a[:, 0, 2] - a[:, 2, 0]) / s
            q[sel, 2] = (a[:, 1, 0] - a[:, 0, 1]) / s
        elif case == 1:
            s = np.sqrt(np.maximum(1.0 + a[:, 0, 0] - a[:, 1, 1] - a[:, 2, 2], 1e-300)) * 2.0
            q[sel, 3] = (a[:, 2, 1] - a[:, 1, 2]) / s
            q[sel, 0] = 0.25 * s
            q[sel, 1] = (a[:, 0, 1] + a[:, 1, 0]) / s
            q[sel, 2] = (a[:, 0, 2] + a[:, 2, 0]) / s
        elif case == 2:
            s = np.sqrt(np.maximum(1.0 + a[:, 1, 1] - a[:, 0, 0] - a[:, 2, 2], 1e-300)) * 2.0
            q[sel, 3] = (a[:, 0, 2] - a[:, 2, 0]) / s
            q[sel, 0] = (a[:, 0, 1] + a[:, 1, 0]) / s
            q[sel, 1] = 0.25 * s
            q[sel, 2] = (a[:, 1, 2] + a[:, 2, 1]) / s
        else:
            s = np.sqrt(np.maximum(1.0 + a[:, 2, 2] - a[:, 0, 0] - a[:, 1, 1], 1e-300)) * 2.0
            q[sel, 3] = (a[:, 1, 0] - a[:, 0, 1]) / s
            q[sel, 0] = (a[:, 0, 2] + a[:, 2, 0]) / s
            q[sel, 1] = (a[:, 1, 2] + a[:, 2, 1]) / s
            q[sel, 2] = 0.25 * s
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    return q.reshape(shape + (4,))


def quat_to_mat(q: np.ndarray) -> np.ndarray:
    """(..., 4) quaternions (x, y, z, w) → (..., 3, 3) rotation matrices."""
    q = np.asarray(q, dtype=np.float64)
    q = q / np.linalg.norm(q, axis=-1, keepdims=True)
    x, y, z, w = q[..., 0], q[..., 1], q[..., 2], q[..., 3]
    out = np.empty(q.shape[:-1] + (3, 3))
    out[..., 0, 0] = 1 - 2 * (y * y + z * z)
    out[..., 0, 1] = 2 * (x * y - z * w)
    out[..., 0, 2] = 2 * (x * z + y * w)
    out[..., 1, 0] = 2 * (x * y + z * w)
    out[..., 1, 1] = 1 - 2 * (x * x + z * z)
    out[..., 1, 2] = 2 * (y * z - x * w)
    out[..., 2, 0] = 2 * (x * z - y * w)
    out[..., 2, 1] = 2 * (y * z + x * w)
    out[..., 2, 2] = 1 - 2 * (x * x + y * y)
    return out


def make_continuous(q: np.ndarray) -> np.ndarray:
    """Flip signs along axis 0 (frames) so consecutive quaternions lie in the same hemisphere
    (their dot product is ≥ 0), starting from w ≥ 0 on the first frame."""
    q = np.array(q, dtype=np.float64, copy=True)
    first = q[0]
    flip0 = first[..., 3] < 0
    q[0][flip0] *= -1
    for f in range(1, q.shape[0]):
        d = np.sum(q[f] * q[f - 1], axis=-1)
        q[f][d < 0] *= -1
    return q


def orthonormalize(v: np.ndarray, against: np.ndarray) -> np.ndarray:
    """Unit part of ``v`` perpendicular to unit ``against`` (both (..., 3))."""
    w = v - np.sum(v * against, axis=-1, keepdims=True) * against
    return w / np.linalg.norm(w, axis=-1, keepdims=True)


def frame_from(d: np.ndarray, n: np.ndarray) -> np.ndarray:
    """Orthonormal frames (..., 3, 3) with columns (d, n⊥, d × n⊥) from directions d and n."""
    d = d / np.linalg.norm(d, axis=-1, keepdims=True)
    n = orthonormalize(n, d)
    return np.stack([d, n, np.cross(d, n)], axis=-1)
