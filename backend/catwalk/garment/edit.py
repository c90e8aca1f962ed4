"""The paper's editor operations on a garment: move, rotate, mirror a panel; set its type,
texture and fabric (``catwalk garment edit``).

A geometric edit applies to the panel's shape in every size (outline, grain line, notches) and
to its placement's anchor point. A
mirror reverses the loop's direction to keep its orientation, so vertex ``i`` becomes vertex
``−i mod n``: seams, the fold edge and the anchor vertex that refer to the panel (or to copies
of it, which use its numbering) are renumbered, and each seam's pairing follows the image, so the
garment still sews the same way.
"""

from __future__ import annotations

import numpy as np

from catwalk.errors import InputError
from catwalk.garment.geometry import flatten, mirror_matrix, move_matrix, rotate_matrix
from catwalk.garment.model import PANEL_TYPES, Garment, Panel


def _centre(p: Panel) -> np.ndarray:
    pts = np.concatenate([flatten(sh.outline, 1e-3).points for sh in p.shapes.values()])
    return 0.5 * (pts.min(axis=0) + pts.max(axis=0))


def transform_panel(g: Garment, name: str, matrix: np.ndarray) -> None:
    """Apply the 2×3 affine ``matrix`` to panel ``name`` in every size (in place)."""
    p = g.panel(name)
    if p.copy_of is not None:
        raise InputError(f"panel {name!r} is a copy of {p.copy_of!r}: edit {p.copy_of!r}")
    reflect = float(np.linalg.det(matrix[:, :2])) < 0
    n = len(next(iter(p.shapes.values())).outline)
    p.shapes = {s: sh.transformed(matrix) for s, sh in p.shapes.items()}
    users = {p.name} | {q.name for q in g.panels if g.source_vertex_map(q)[0] == p.name}
    for q in g.panels:   # a placement's anchor point is in the panel's pattern coordinates
        if q.name in users and q.placement is not None and q.placement.anchor_point is not None:
            q.placement.anchor_point = [float(x) for x in
                                        matrix[:, :2] @ np.asarray(q.placement.anchor_point,
                                                                   dtype=float) + matrix[:, 2]]
    if not reflect:
        return
    # vertex v → (−v) mod n for the panel and every copy that uses its numbering
    if p.fold is not None:
        p.fold = (-p.fold - 1) % n
    for q in g.panels:
        if q.name in users and q.placement is not None and q.placement.anchor_vertex is not None:
            q.placement.anchor_vertex = (-q.placement.anchor_vertex) % n
    for s in g.seams:
        flip = False
        for side in (s.a, s.b):
            if side.panel in users:
                side.start, side.end = (-side.end) % n, (-side.start) % n
                flip = not flip
        if flip:
            s.reverse = not s.reverse


def edit(g: Garment, panel: str, *, move=None, rotate: float | None = None,
         mirror: str | None = None, ptype: str | None = None, texture: str | None = None,
         texture_size=None, fabric: str | None = None) -> Garment:
    """The editor's operations on one panel; rotation and mirroring are about the centre of
    the panel's bounding box (all sizes together)."""
    p = g.panel(panel)
    if p.copy_of is not None and (mirror or rotate or move is not None):
        raise InputError(f"panel {panel!r} is a copy of {p.copy_of!r}: edit {p.copy_of!r}")
    if mirror is not None:
        if mirror not in ("x", "y"):
            raise InputError(f"mirror {mirror!r}: use x (left ↔ right) or y (up ↔ down)")
        c = _centre(p)
        transform_panel(g, panel, mirror_matrix(mirror, c[0] if mirror == "x" else c[1]))
    if rotate:
        transform_panel(g, panel, rotate_matrix(float(rotate), tuple(_centre(p))))
    if move is not None:
        transform_panel(g, panel, move_matrix(float(move[0]), float(move[1])))
    if ptype is not None:
        if ptype not in PANEL_TYPES:
            raise InputError(f"panel type {ptype!r} is not one of {', '.join(PANEL_TYPES)}")
        p.type = ptype
    if texture is not None:
        p.texture = {"image": texture, "size": list(texture_size or (0.1, 0.1))}
    if fabric is not None:
        p.fabric = fabric
    return g
