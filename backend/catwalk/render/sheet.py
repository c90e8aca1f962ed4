"""A contact sheet of a scene: frames at several times (columns) from several views (rows), the
camera's scale fixed over the whole walk (``catwalk render`` and the workers' previews)."""

from __future__ import annotations

import numpy as np

from catwalk.errors import Cancelled
from catwalk.render.preview import render_meshes


def render_sheet(scene, times, views, size, cancel=None) -> np.ndarray:
    """Images of ``scene`` at ``times`` (columns) from ``views`` (rows). Every cell has the
    same scale — a box as large as the largest frame's — centred on its own frame, so a body
    walking metres down the catwalk stays the same size and in view. ``cancel()`` is asked
    before each cell (:class:`~catwalk.errors.Cancelled`)."""
    frames = {t: [(v, f, rgb) for _, v, f, rgb in scene.meshes_at(t)] for t in times}
    boxes = {}
    for t, ms in frames.items():
        v = np.concatenate([m[0] for m in ms])
        lo, hi = v.min(axis=0), v.max(axis=0)
        lo[1] = min(lo[1], 0.0)
        boxes[t] = (lo, hi)
    extent = np.max([hi - lo for lo, hi in boxes.values()], axis=0)
    rows = []
    for view in views:
        cells = []
        for t in times:
            lo, hi = boxes[t]
            mid = 0.5 * (lo + hi)
            box = (mid - 0.5 * extent, mid + 0.5 * extent)
            box[0][1], box[1][1] = lo[1], lo[1] + extent[1]
            bbox = None if len(times) == 1 else box
            if cancel is not None and cancel():
                raise Cancelled("try-on cancelled")
            cells.append(render_meshes(frames[t], view=view, size=size, bbox=bbox))
        rows.append(np.concatenate(cells, axis=1))
    return np.concatenate(rows, axis=0)
