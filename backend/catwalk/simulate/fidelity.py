"""How near a walk stays to a reference walk of the same dressed cloth.

Both walks record the same points (the same dressed garment, so the same pattern points in
the same order) on the same frames; what is compared:

- :func:`vertex_rms`: the per-vertex RMS distance over every recorded frame (m);
- :func:`hem_swing`: how far the hem swings — the RMS, over the hem's points, of each point's
  horizontal spread over the walk (the standard deviation of its x and z) about the cloth's
  centroid of each frame (so the body's own travel along the catwalk is taken out); the
  ratio of two walks' swings says whether the faster one damps or exaggerates the motion.
  The hem (:func:`hem_points`) is the points within ``band`` of the lowest one in the first
  recorded frame.

The cloth is chaotic: two walks whose drapes differ by a hair part by centimetres where folds
form. :func:`nudged` gives the dressed garment moved 0.1 mm, whose walk against the
unmoved one's is the noise floor a distance must clear to mean anything (``bench paper``,
``bench pareto``).
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from catwalk.errors import InputError


def _frames(positions) -> np.ndarray:
    p = np.asarray(positions, dtype=np.float64)
    if p.ndim != 3 or p.shape[2] != 3 or p.shape[0] < 1 or p.shape[1] < 1:
        raise InputError(f"need recorded positions of shape (frames, points, 3), got "
                         f"{p.shape}")
    return p


NUDGE = 1e-4   # m: the noise floor's move of the drape


def nudged(dressed, metres: float = NUDGE):
    """A copy of ``dressed`` (a :class:`~catwalk.simulate.dressing.Dressed`) with its cloth
    moved ``metres`` along x."""
    state = dressed.state.copy()
    state.positions[:, 0] += metres
    return replace(dressed, state=state)


def vertex_rms(a, b) -> float:
    """RMS distance (m) between the same points of two walks over their common frames."""
    a, b = _frames(a), _frames(b)
    if a.shape[1] != b.shape[1]:
        raise InputError(f"the walks record different points ({a.shape[1]} against "
                         f"{b.shape[1]}): not the same dressed cloth")
    n = min(len(a), len(b))
    d = a[:n] - b[:n]
    return float(np.sqrt(np.mean(np.sum(d * d, axis=2))))


def hem_points(positions, band: float = 0.03) -> np.ndarray:
    """Indices of the points within ``band`` metres of the lowest point in the first frame."""
    y = _frames(positions)[0, :, 1]
    return np.flatnonzero(y <= y.min() + band)


def hem_swing(positions, hem: np.ndarray) -> float:
    """The hem's swing (m): RMS over the points ``hem`` of the standard deviation of their
    horizontal offset from the cloth's centroid, over the recorded frames."""
    p = _frames(positions)
    rel = p[:, hem][:, :, (0, 2)] - p.mean(axis=1)[:, None, (0, 2)]
    return float(np.sqrt(np.mean(np.sum(rel.var(axis=0), axis=1))))
