"""A garment (catwalk.garment) as a cloth model (catwalk.cloth) placed round a body.

:func:`garment_cloth` cuts the garment in one size, places each piece round the body from its
landmarks (:func:`catwalk.garment.place.place_panels`), and builds one
:class:`~catwalk.cloth.model.ClothModel` whose seams are the garment's. :func:`weld` turns closed
seams into shared points: partner points become one particle (masses added, springs and
triangles re-indexed), so that a sewn garment needs no seam forces during the walk; ``rep``
maps every original point to its particle, which is how the output keeps one vertex per
pattern point (each panel keeps its own UVs).
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components

from catwalk.cloth.builder import Panel, Seam, adjacency, build_cloth
from catwalk.cloth.fabrics import Fabric, resolve_fabric
from catwalk.cloth.model import ClothModel
from catwalk.errors import InputError
from catwalk.garment.model import Garment, cut_pieces
from catwalk.garment.place import place_panels

# colour per panel type when a panel has no texture (linear RGBA)
_TYPE_COLOURS = {"front": (0.55, 0.12, 0.15, 1.0), "back": (0.50, 0.10, 0.13, 1.0),
                 "sleeve": (0.60, 0.15, 0.18, 1.0)}
_DEFAULT_COLOUR = (0.45, 0.15, 0.20, 1.0)


@dataclass
class GarmentCloth:
    garment: Garment
    size: str
    model: ClothModel
    fabric: Fabric
    textures: list            # per panel: (image path, (w, h)) or None
    colors: list              # per panel RGBA


def body_girths(body) -> dict:
    """The body's bust/waist/hips girths (m) from its metadata, if it has them."""
    meas = body.meta.get("measured") or {}
    if not isinstance(meas, dict):
        return {}
    out = {}
    for k in ("bust", "waist", "hips"):
        v = meas.get(k)
        if isinstance(v, (int, float)) and v > 0:
            out[k] = float(v)
    return out


def placement_landmarks(body) -> dict:
    """The body's landmarks plus, for a rigged body, ``arm_root_left``/``arm_root_right`` and
    ``leg_root_left``/``leg_root_right``: the shoulder and hip joints (a sleeve's or a trouser
    leg's axis starts there, not at the body's surface)."""
    lm = dict(body.landmarks)
    sk = body.skeleton
    if sk is not None:
        world = sk.rest_world
        for key, names in (("arm_root_left", ("upperarm_l", "upperarm.L", "upper_arm.L")),
                           ("arm_root_right", ("upperarm_r", "upperarm.R", "upper_arm.R")),
                           ("leg_root_left", ("thigh_l", "upperleg01.L", "thigh.L")),
                           ("leg_root_right", ("thigh_r", "upperleg01.R", "thigh.R"))):
            for n in names:
                if n in sk.names:
                    lm[key] = world[sk.names.index(n)][:3, 3].tolist()
                    break
    return lm


FEET_CLEARANCE = 0.05   # m above the ankles that a placed garment's lowest point must be


def _lift_over_feet(model: ClothModel, body) -> float:
    """How far to lift a garment placed down to the floor so that no piece starts round the
    feet (a straight tube cannot clear them: the collider would push hem points to both sides
    of a foot and sewing could not close the hem ends). Gravity takes it down again while it
    settles; the waist lands where the body holds it."""
    ankles = [body.landmarks[k][1] for k in ("ankle_left", "ankle_right") if k in body.landmarks]
    if not ankles:
        return 0.0
    low = float(model.rest_positions[:, 1].min())
    return max(0.0, max(ankles) + FEET_CLEARANCE - low)


def garment_cloth(garment: Garment, body, size: str | None = None, fabric=None,
                  h: float = 0.015, distance: float | None = None) -> GarmentCloth:
    """Cut ``garment`` in ``size``, place it round ``body`` and build its cloth at spacing h."""
    size = garment.size(size)
    if not body.landmarks:
        raise InputError("the body has no landmarks (make it with `catwalk body make` or "
                         "measure a scan with `catwalk body measure`)")
    fab = resolve_fabric(fabric if fabric is not None else garment.fabric,
                         "fabric" if fabric is not None else "garment fabric")
    pieces, seams = cut_pieces(garment, size)
    if distance is not None:
        garment = replace(garment, panels=[
            replace(p, placement=replace(p.placement, distance=distance))
            if p.placement is not None else p for p in garment.panels])
    placements = place_panels(garment, placement_landmarks(body), size, body_girths(body))
    panels = [Panel(pc.flat.points, name=pc.name, placement=pl.to_world)
              for pc, pl in zip(pieces, placements, strict=True)]
    model = build_cloth(panels, [Seam(*s) for s in seams], fabric=fab, h=h)
    lift = _lift_over_feet(model, body)
    if lift > 0:
        model.rest_positions[:, 1] += lift
    base = garment.path.parent if garment.path else Path(".")
    textures, colors = [], []
    for pc in pieces:
        tex = pc.panel.texture
        if tex and tex.get("image"):
            img = Path(tex["image"])
            img = img if img.is_absolute() else base / img
            textures.append((str(img), tuple(float(s) for s in tex.get("size", (0.1, 0.1)))))
        else:
            textures.append(None)
        colors.append(_TYPE_COLOURS.get(pc.panel.type, _DEFAULT_COLOUR))
    return GarmentCloth(garment, size, model, fab, textures, colors)


def seam_gaps(model: ClothModel, x: np.ndarray) -> np.ndarray:
    """Distance between the partners of every seam pair (m)."""
    d = x[model.seam_b] - x[model.seam_a]
    return np.sqrt(np.sum(d * d, axis=1))


def weld(model: ClothModel, pairs: np.ndarray | None = None) -> tuple[ClothModel, np.ndarray]:
    """Merge seam partners into single particles.

    ``pairs``: bool mask over the model's seam pairs to weld (default all). Returns the welded
    model (its ``uv`` and ``panel`` are those of each particle's first point; ``seam_*`` keep the
    unwelded pairs, re-indexed) and ``rep`` (n_original,) → particle index."""
    n = model.n_points
    sel = np.ones(len(model.seam_a), bool) if pairs is None else np.asarray(pairs, bool)
    # particles = connected components of the graph whose edges are the welded pairs
    graph = coo_matrix((np.ones(int(sel.sum())), (model.seam_a[sel], model.seam_b[sel])),
                       shape=(n, n))
    m, label = connected_components(graph, directed=False)
    # number the particles by their first point, so unwelded points keep their order
    first_of = np.full(m, n)
    np.minimum.at(first_of, label, np.arange(n))
    rank = np.empty(m, dtype=np.int64)
    rank[np.argsort(first_of, kind="stable")] = np.arange(m)
    rep = rank[label]
    mass = np.bincount(rep, weights=model.mass, minlength=m)
    # a particle sits at the mean of its points (weighted by mass)
    pos = np.zeros((m, 3))
    np.add.at(pos, rep, model.rest_positions * model.mass[:, None])
    pos /= mass[:, None]
    sa, sb = rep[model.spring_a], rep[model.spring_b]
    keep = sa != sb
    # springs of the two sides along a seam may now join the same particles: keep one each
    key = np.minimum(sa, sb).astype(np.int64) * m + np.maximum(sa, sb)
    order = np.lexsort((np.arange(len(sa)), key))
    first = np.ones(len(sa), bool)
    first[order[1:]] = key[order[1:]] != key[order[:-1]]
    keep &= first
    lim = np.zeros(len(sa), bool)
    lim[:model.n_limited] = True
    idx = np.concatenate([np.nonzero(keep & lim)[0], np.nonzero(keep & ~lim)[0]])
    n_lim = int(np.count_nonzero(keep & lim))
    sa, sb = sa[idx].astype(np.int32), sb[idx].astype(np.int32)
    adj_ptr, adj_spring, adj_other = adjacency(m, sa[:n_lim], sb[:n_lim])
    tris = rep[model.triangles].astype(np.int32)
    good = (tris[:, 0] != tris[:, 1]) & (tris[:, 1] != tris[:, 2]) & (tris[:, 0] != tris[:, 2])
    first_pt = np.sort(first_of)   # each particle's first point, in particle order
    rest_sel = ~sel
    welded = replace(
        model, uv=model.uv[first_pt], rest_positions=pos, mass=mass,
        panel=model.panel[first_pt], boundary=model.boundary[first_pt],
        spring_a=sa, spring_b=sb, spring_rest=model.spring_rest[idx],
        spring_k=model.spring_k[idx], spring_c=model.spring_c[idx],
        spring_kind=model.spring_kind[idx], n_limited=n_lim, adj_ptr=adj_ptr,
        adj_spring=adj_spring, adj_other=adj_other, triangles=tris[good],
        seam_a=rep[model.seam_a[rest_sel]].astype(np.int32),
        seam_b=rep[model.seam_b[rest_sel]].astype(np.int32),
        seam_id=model.seam_id[rest_sel])
    return welded, rep.astype(np.int64)
