"""``catwalk garment check``: everything that makes a garment unusable, named by panel and edge.

:func:`check_garment` returns a :class:`Report` (errors, warnings, per-panel numbers);
:func:`require_valid` raises :class:`catwalk.errors.InputError` listing every error.

Checked, for every size: outlines closed (a stated segment ``end`` meets the next segment's
start), no zero-length edges, not self-intersecting (flattened within 0.1 mm), positive area;
fold edges straight; seam sides inside the outline, runs of one cut piece not overlapping, seam
partners within 2 % of each other's length (or within the seam's declared ``ease``, for
gathers and eased seams); every panel reachable from every other through
seams; fabric presets known (or custom fabrics complete); texture images present.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from catwalk.errors import InputError
from catwalk.garment.geometry import (
    flatten,
    polygon_area,
    polyline_length,
    run_length,
    segment_lengths,
    self_crossings,
)
from catwalk.garment.model import Garment, Shape, side_vertices, unfold

SEAM_LENGTH_TOLERANCE = 0.02      # relative
CLOSE_TOLERANCE = 1e-4            # metres: a stated end must meet the next start
MIN_EDGE = 1e-5                   # metres
CROSSING_TOLERANCE = 1e-4         # metres: flattening tolerance for the crossing test
MIN_AREA = 1e-4                   # m² (1 cm²)
# the landmarks catwalk.body.measure finds (bust, underbust, waist, hips: centres of the torso
# sections at those heights), and the aliases catwalk.garment.place accepts
KNOWN_LANDMARKS = (
    "neck_base", "neck", "neck_side_left", "neck_side_right", "shoulder_left", "shoulder_right",
    "armpit_left", "armpit_right", "bust", "underbust", "waist", "hips", "crotch", "elbow_left",
    "elbow_right", "wrist_left", "wrist_right", "knee_left", "knee_right", "ankle_left",
    "ankle_right", "top_of_head", "neck_front", "neck_back", "chest",
)


@dataclass
class Report:
    garment: str
    errors: list[str] = field(default_factory=list)
    warnings: list[str] = field(default_factory=list)
    panels: list[dict] = field(default_factory=list)   # per size and panel: area, perimeter
    seams: list[dict] = field(default_factory=list)    # per size and seam: lengths

    @property
    def ok(self) -> bool:
        return not self.errors

    def as_dict(self) -> dict:
        return {"garment": self.garment, "ok": self.ok, "errors": self.errors,
                "warnings": self.warnings, "panels": self.panels, "seams": self.seams}


def resolve_fabric(spec, where: str = "fabric"):
    """A :class:`catwalk.cloth.fabrics.Fabric` from a preset name or a custom fabric object
    (``{"base": "denim", "density": 0.3}`` overrides a preset; otherwise every field of
    ``Fabric`` is given)."""
    from catwalk.cloth.fabrics import Fabric, get_fabric
    from catwalk.errors import CatwalkError

    try:
        if isinstance(spec, str):
            return get_fabric(spec)
        if isinstance(spec, dict):
            spec = dict(spec)
            if "base" in spec:
                base = get_fabric(str(spec.pop("base")))
                return base.with_(**spec)
            return Fabric(**spec).validate()
    except TypeError as exc:
        raise InputError(f"{where}: not a usable custom fabric ({exc})") from None
    except CatwalkError as exc:
        raise InputError(f"{where}: {exc}") from None
    raise InputError(f"{where}: a fabric is a preset name or an object, got {spec!r}")


def _check_shape(shape: Shape, where: str, errors: list[str]) -> dict | None:
    segs = shape.outline
    n = len(segs)
    for i, s in enumerate(segs):
        nxt = segs[(i + 1) % n].start
        if s.declared_end is not None and np.linalg.norm(s.declared_end - nxt) > CLOSE_TOLERANCE:
            errors.append(f"{where}: outline not closed: edge {i} ends at "
                          f"({s.declared_end[0]:.4f}, {s.declared_end[1]:.4f}) but edge "
                          f"{(i + 1) % n} starts at ({nxt[0]:.4f}, {nxt[1]:.4f})")
    lengths = segment_lengths(segs)
    for i in np.nonzero(lengths < MIN_EDGE)[0]:
        errors.append(f"{where}: edge {i} has zero length (vertex {i} and vertex "
                      f"{(i + 1) % n} coincide)")
    flat = flatten(segs, CROSSING_TOLERANCE)
    pts = flat.points
    keep = np.linalg.norm(np.roll(pts, -1, axis=0) - pts, axis=1) > 1e-9
    pts_k, seg_k = pts[keep], flat.edge_segment[keep]
    for i, j, at in self_crossings(pts_k, eps=1e-9, limit=3):
        ei, ej = int(seg_k[i]), int(seg_k[j])
        what = f"edges {ei} and {ej} cross" if ei != ej else f"edge {ei} crosses itself"
        errors.append(f"{where}: outline intersects itself: {what} near "
                      f"({at[0]:.4f}, {at[1]:.4f})")
    area = abs(polygon_area(pts))
    if area < MIN_AREA:
        errors.append(f"{where}: outline encloses no area ({area * 1e4:.2f} cm²)")
    if shape.grain is not None and np.linalg.norm(shape.grain[1] - shape.grain[0]) < 1e-6:
        errors.append(f"{where}: grain line has zero length")
    return {"area_m2": area, "perimeter_m": polyline_length(pts), "edges": n,
            "lengths": lengths}


def check_garment(g: Garment, base_dir: str | Path | None = None) -> Report:
    rep = Report(g.name)
    err, warn = rep.errors, rep.warnings
    base = Path(base_dir) if base_dir else (g.path.parent if g.path else Path("."))
    # fabric and textures
    try:
        resolve_fabric(g.fabric, "garment fabric")
    except InputError as exc:
        err.append(str(exc))
    for p in g.panels:
        if p.fabric is not None:
            try:
                resolve_fabric(p.fabric, f"panel {p.name!r}: fabric")
            except InputError as exc:
                err.append(str(exc))
        if p.texture is not None:
            img = base / str(p.texture["image"])
            if not img.is_file():
                err.append(f"panel {p.name!r}: texture image {p.texture['image']!r} not found "
                           f"(looked for {img})")
            else:
                try:
                    from PIL import Image
                    with Image.open(img) as im:
                        im.verify()
                except Exception as exc:  # noqa: BLE001 - any decoder failure is the user's file
                    err.append(f"panel {p.name!r}: texture image {p.texture['image']!r} is not "
                               f"a readable image ({exc})")
        if p.placement is not None and p.placement.anchor is not None \
                and p.placement.anchor not in KNOWN_LANDMARKS:
            warn.append(f"panel {p.name!r}: placement anchor {p.placement.anchor!r} is not a "
                        f"landmark catwalk knows ({', '.join(KNOWN_LANDMARKS)})")
        if p.placement is None:
            warn.append(f"panel {p.name!r}: no placement hint (it will be placed in front of "
                        f"the torso)")
    # geometry per size
    n_before = len(err)
    stats: dict[tuple[str, str], dict] = {}
    for size in g.sizes:
        for p in g.panels:
            if p.copy_of is not None:
                continue
            where = f"panel {p.name!r} (size {size})"
            shape = p.shapes[size]
            st = _check_shape(shape, where, err)
            stats[(size, p.name)] = st
            n = len(shape.outline)
            if p.fold is not None:
                if not 0 <= p.fold < n:
                    err.append(f"{where}: fold edge {p.fold} does not exist (edges 0…{n - 1})")
                elif shape.outline[p.fold].kind != "line" and not (
                        shape.outline[p.fold].kind == "arc" and shape.outline[p.fold].bulge == 0):
                    err.append(f"{where}: fold edge {p.fold} is a "
                               f"{shape.outline[p.fold].kind}, not a straight line")
                elif not any(e.startswith(where) for e in err):
                    full, _ = unfold(shape, p.fold)   # the opened piece must not cross itself
                    errs: list[str] = []
                    _check_shape(full, f"{where} opened on its fold", errs)
                    err.extend(e for e in errs if "intersects" in e)
            sewn = {g.source_vertex_map(g.panel(sd.panel))[0]
                    for sm in g.seams for sd in (sm.a, sm.b)}
            if p.name in sewn and any(len(p.shapes[s].outline) != n for s in g.sizes):
                err.append(f"panel {p.name!r}: sizes have different numbers of edges "
                           f"({', '.join(f'{s}: {len(p.shapes[s].outline)}' for s in g.sizes)})"
                           f"; seams need the same vertices in every size")
        for p in g.panels:
            base_name, _ = g.source_vertex_map(p)
            st = stats.get((size, base_name))
            if st is None:
                continue
            # the panel as stored: half of it when cut on fold
            rep.panels.append({"size": size, "panel": p.name,
                               "area_m2": round(st["area_m2"], 6),
                               "perimeter_m": round(st["perimeter_m"], 5), "edges": st["edges"],
                               "fold": p.fold is not None, "copy_of": p.copy_of})
    if len(err) > n_before:
        return rep   # seams need sound outlines
    _check_seams(g, rep)
    _check_reachable(g, rep)
    return rep


def _check_seams(g: Garment, rep: Report) -> None:
    err = rep.errors
    for size in g.sizes:
        used: dict[str, list[tuple[int, int, int, str]]] = {}
        for i, s in enumerate(g.seams):
            lab = s.label(i)
            lens = []
            bad = False
            for side, sname in ((s.a, "a"), (s.b, "b")):
                p = g.panel(side.panel)
                # seam vertices of a copy are numbered as in its source panel
                shape = g.panel(g.source_vertex_map(p)[0]).shapes[size]
                n = len(shape.outline)
                where = f"{lab}, side {sname} (panel {side.panel!r}, size {size})"
                if not (0 <= side.start < n and 0 <= side.end < n):
                    err.append(f"{where}: vertices {side.start}→{side.end} are outside the "
                               f"outline (vertices 0…{n - 1})")
                    bad = True
                    continue
                if side.start == side.end:
                    err.append(f"{where}: start and end are the same vertex {side.start}")
                    bad = True
                    continue
                if side.half == "mirror" and p.fold is None:
                    err.append(f"{where}: half \"mirror\" but the panel is not cut on fold")
                    bad = True
                    continue
                if p.fold is not None:
                    k = p.fold
                    covered = {(side.start + t) % n for t in range((side.end - side.start) % n)}
                    if k in covered:
                        err.append(f"{where}: the run {side.start}→{side.end} includes the "
                                   f"fold edge {k}")
                        bad = True
                        continue
                lengths = segment_lengths(shape.outline)
                lens.append(run_length(lengths, side.start, side.end))
                a, b, _ = side_vertices(g, p, side, size)
                n_cut = 2 * n - 2 if p.fold is not None else n
                used.setdefault(p.name, []).append((a, b, n_cut, lab))
            if bad or len(lens) != 2:
                continue
            la, lb = lens
            rel = abs(la - lb) / max(la, lb)
            rep.seams.append({"size": size, "seam": i, "name": s.name, "length_a_m": round(la, 5),
                              "length_b_m": round(lb, 5), "difference": round(rel, 4)})
            limit = max(SEAM_LENGTH_TOLERANCE, s.ease)
            if rel > limit:
                err.append(f"{lab} (size {size}): lengths differ by {rel * 100:.1f} % (limit "
                           f"{limit * 100:.0f} %): panel {s.a.panel!r} edges "
                           f"{s.a.start}→{s.a.end} is {la:.4f} m, panel {s.b.panel!r} edges "
                           f"{s.b.start}→{s.b.end} is {lb:.4f} m")
        for pname, runs in used.items():
            owner: dict[int, str] = {}
            for a, b, n, lab in runs:
                for t in range((b - a) % n):
                    e = (a + t) % n
                    if e in owner and owner[e] != lab:
                        err.append(f"panel {pname!r} (size {size}): {owner[e]} and {lab} both "
                                   f"use edge {e} of the cut outline")
                        break
                    owner[e] = lab


def _check_reachable(g: Garment, rep: Report) -> None:
    names = [p.name for p in g.panels]
    if len(names) < 2:
        return
    adj = {n: set() for n in names}
    for s in g.seams:
        adj[s.a.panel].add(s.b.panel)
        adj[s.b.panel].add(s.a.panel)
    seen, todo = {names[0]}, [names[0]]
    while todo:
        for m in adj[todo.pop()]:
            if m not in seen:
                seen.add(m)
                todo.append(m)
    lost = [n for n in names if n not in seen]
    if lost:
        rep.errors.append(f"panel(s) {', '.join(repr(n) for n in lost)} not reachable from "
                          f"panel {names[0]!r} through seams (every panel must be sewn to the "
                          f"rest)")


def require_valid(g: Garment, base_dir: str | Path | None = None) -> Report:
    rep = check_garment(g, base_dir)
    if rep.errors:
        where = f"{g.path}: " if g.path else ""
        raise InputError(where + f"garment {g.name!r} has {len(rep.errors)} problem(s):\n  "
                         + "\n  ".join(rep.errors))
    return rep
