"""``catwalk garment check``: everything that makes a garment unusable, named by panel and edge.

:func:`check_garment` returns a :class:`Report` (errors, warnings, per-panel numbers);
:func:`require_valid` raises :class:`catwalk.errors.InputError` listing every error.

Checked: the garment's type, sizes and panels (a garment built in code skips the reader;
a panel may be cut in some sizes only, each size has at least one); for every size, over the
panels it has: garment-sized (no panel more than :data:`MAX_PANEL_EXTENT` across, the
largest at least :data:`MIN_GARMENT_EXTENT`, at most :data:`MAX_GARMENT_AREA` of fabric),
outlines no more detailed than :data:`MAX_OUTLINE_POINTS` points, closed (a stated segment
``end`` meets the next segment's start), no zero-length edges, not self-intersecting
(flattened within 0.1 mm), positive area;
fold edges straight; seam sides inside the outline, runs of one cut piece not overlapping, seam
partners within 2 % of each other's length (or within the seam's declared ``ease``, for
gathers and eased seams; a seam on a panel a size lacks is not sewn in that size); every panel
of a size reachable from every other through seams; fabric presets known (or custom fabrics
complete); texture images present, readable and at most :data:`MAX_TEXTURE_PIXELS`.
"""

from __future__ import annotations

import ast
import contextlib
import math
import re
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from catwalk.cloth.fabrics import resolve_fabric
from catwalk.errors import InputError
from catwalk.garment.geometry import (
    crossing_work,
    flatten,
    polygon_area,
    polyline_length,
    run_length,
    segment_lengths,
    self_crossings,
)
from catwalk.garment.model import GARMENT_TYPES, Garment, Shape, side_vertices, unfold

SEAM_LENGTH_TOLERANCE = 0.02      # relative
CLOSE_TOLERANCE = 1e-4            # metres: a stated end must meet the next start
MIN_EDGE = 1e-5                   # metres
CROSSING_TOLERANCE = 1e-4         # metres: flattening tolerance for the crossing test
MIN_AREA = 1e-4                   # m² (1 cm²)
# garment-sized: no panel wider or longer than this (a floor-length gown's panel is ≈ 1.7 m,
# a full circle skirt ≈ 2.2 m across), the largest panel at least this, and no more fabric
# than this in one size (the catalogue: 0.5–1.4 m²; a full-length circle skirt ≈ 4 m²)
MAX_PANEL_EXTENT = 3.0            # metres
MIN_GARMENT_EXTENT = 0.1          # metres
MAX_GARMENT_AREA = 8.0            # m², every cut piece of one size (folds opened, copies)
# detail: flattened points of one outline, and the crossing test's work (edge pairs tested,
# geometry.crossing_work) for one outline and for the whole garment (the catalogue: ≤ 200
# points and ≤ 800 pairs an outline; a 20,000-point circle is 80,000 pairs)
MAX_OUTLINE_POINTS = 20_000
MAX_OUTLINE_WORK = 2_000_000
MAX_CROSSING_WORK = 10_000_000
# a texture image (the catalogue's: 128 × 128); a larger one costs the worker and the browser
# memory for detail a garment's weave does not show
MAX_TEXTURE_PIXELS = 4096 * 4096
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

    def problems(self) -> list[dict]:
        """The errors as ``{"panel"?, "edge"?, "seam"?, "size"?, "message"}``."""
        return [problem(m) for m in self.errors]

    def as_dict(self) -> dict:
        return {"garment": self.garment, "ok": self.ok, "errors": self.errors,
                "problems": self.problems(), "warnings": self.warnings,
                "panels": self.panels, "seams": self.seams}


_PANEL = re.compile(r"""panel(?:\(s\))?(?: named)? ('(?:[^'\\]|\\.)*'|"(?:[^"\\]|\\.)*")""")
_EDGE = re.compile(r"\b(?:fold )?edges? (\d+)")
_SEAM = re.compile(r"\bseam (\d+)")
_SIZE = re.compile(r"\(size ([^)]+)\)|\bsize (\S+?):")


def problem(message: str) -> dict:
    """A message of the checker (or the garment reader) with what it names picked out: the
    first panel (``panel 'front'``), the first edge, the seam's number and the size. Every
    message names its panel and edge in these words (the checker's own formats)."""
    out: dict = {}
    if m := _PANEL.search(message):
        with contextlib.suppress(ValueError, SyntaxError):
            out["panel"] = ast.literal_eval(m.group(1))
    if m := _EDGE.search(message):
        out["edge"] = int(m.group(1))
    if m := _SEAM.search(message):
        out["seam"] = int(m.group(1))
    if m := _SIZE.search(message):
        out["size"] = m.group(1) or m.group(2)
    out["message"] = message
    return out


def _extent(shape: Shape) -> float:
    """Width or height (the larger) of everything that shapes the outline: its vertices and
    control points (inf when any is not finite)."""
    pts = np.array([p for s in shape.outline for p in (s.start, *s.controls)], dtype=float)
    if not np.all(np.isfinite(pts)):
        return math.inf
    return float(np.ptp(pts, axis=0).max())


def _points(shape: Shape) -> int:
    """How many points flattening the outline for the crossing test makes."""
    segs = shape.outline
    return sum(s.pieces(segs[(i + 1) % len(segs)].start, CROSSING_TOLERANCE)
               for i, s in enumerate(segs))


def _check_size(shape: Shape, where: str, errors: list[str]) -> bool:
    """Garment-sized and not too detailed to check: False (and an error) if not."""
    ext = _extent(shape)
    if not ext <= MAX_PANEL_EXTENT:
        size = "has coordinates that are not finite" if not math.isfinite(ext) else \
            f"is {ext:.4g} m across (at most {MAX_PANEL_EXTENT:g} m)"
        errors.append(f"{where}: the panel {size}: not garment-sized (a pattern is in metres)")
        return False
    n = _points(shape)
    if n > MAX_OUTLINE_POINTS:
        errors.append(f"{where}: the outline flattens to {n:,} points (at most "
                      f"{MAX_OUTLINE_POINTS:,}): too detailed")
        return False
    return True


def _work(shape: Shape) -> int:
    return crossing_work(flatten(shape.outline, CROSSING_TOLERANCE).points)


def _check_shape(shape: Shape, where: str, errors: list[str]) -> dict:
    """The outline closed, edges of length, no self-crossing, an area. Its size was checked
    before (:func:`_check_sizes`): an opened fold may be twice as wide as a stored panel."""
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
    if not _check_garment_fields(g, err):
        return rep
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
            try:
                found = img.is_file()
            except OSError as exc:   # a name too long for the file system, …
                err.append(f"panel {p.name!r}: texture image {str(p.texture['image'])[:80]!r} "
                           f"cannot be looked for ({exc.strerror or exc})")
                found = None
            if found is False:
                err.append(f"panel {p.name!r}: texture image {p.texture['image']!r} not found "
                           f"(looked for {img})")
            elif found:
                try:
                    from PIL import Image
                    with Image.open(img) as im:
                        w, h = im.size
                        im.verify()
                    if w * h > MAX_TEXTURE_PIXELS:
                        err.append(f"panel {p.name!r}: texture image {p.texture['image']!r} is "
                                   f"{w} × {h} pixels; at most {MAX_TEXTURE_PIXELS:,} (4096 × "
                                   "4096)")
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
    if not _check_sizes(g, err):
        return rep
    stats: dict[tuple[str, str], dict] = {}
    unsound: set[str] = set()   # panels with an outline error: their seams are not checked
    for size in g.sizes:
        for p in g.panels:
            if p.copy_of is not None or size not in p.shapes:
                continue
            before = len(err)
            where = f"panel {p.name!r} (size {size})"
            shape = p.shapes[size]
            stats[(size, p.name)] = _check_shape(shape, where, err)
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
            if p.name in sewn and any(len(sh.outline) != n for sh in p.shapes.values()):
                counts = ", ".join(f"{s}: {len(p.shapes[s].outline)}" for s in g.sizes
                                   if s in p.shapes)
                err.append(f"panel {p.name!r}: sizes have different numbers of edges "
                           f"({counts}); seams need the same vertices in every size")
            if len(err) > before:
                unsound.add(p.name)
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
    for size in g.sizes:
        fabric = sum(r["area_m2"] * (2 if r["fold"] else 1) for r in rep.panels
                     if r["size"] == size)
        if fabric > MAX_GARMENT_AREA:
            err.append(f"size {size}: the panels add up to {fabric:.3g} m² of fabric (at most "
                       f"{MAX_GARMENT_AREA:g} m²): not garment-sized")
    if len(err) > n_before and not unsound:
        return rep
    # seams need sound outlines: those touching a panel with an outline error are left out
    _check_seams(g, rep, unsound)
    _check_reachable(g, rep)
    return rep


def _check_garment_fields(g: Garment, err: list[str]) -> bool:
    """What the garment format's reader checks, for garments built in code: the type, sizes,
    panels and their shapes. False (with errors) if the garment cannot be checked further."""
    n = len(err)
    if g.type not in GARMENT_TYPES:
        err.append(f"garment type {g.type!r} is not one of {', '.join(GARMENT_TYPES)}")
    if not g.sizes or not all(isinstance(s, str) and s.strip() for s in g.sizes) \
            or len(set(g.sizes)) != len(g.sizes):
        err.append(f"sizes {g.sizes!r}: a garment needs distinct, non-empty size names")
    if not g.panels:
        err.append("the garment has no panels")
    names = [p.name for p in g.panels]
    if not all(isinstance(x, str) and x.strip() for x in names) or len(set(names)) != len(names):
        err.append(f"panel names {names!r}: each panel needs its own non-empty name")
    for p in g.panels:
        if p.copy_of is None:
            if not any(s in p.shapes for s in g.sizes):
                err.append(f"panel {p.name!r}: no outline in any size (sizes: "
                           f"{', '.join(map(str, g.sizes))})")
        elif p.copy_of not in names:
            err.append(f"panel {p.name!r}: copy_of names no panel ({p.copy_of!r})")
    if len(err) == n:
        for s in g.sizes:
            if not any(p.copy_of is None and s in p.shapes for p in g.panels):
                err.append(f"size {s}: no panel has an outline in this size")
    for i, s in enumerate(g.seams):
        for side in (s.a, s.b):
            if side.panel not in names:
                err.append(f"{s.label(i)}: no panel named {side.panel!r}")
    return len(err) == n


def _check_sizes(g: Garment, err: list[str]) -> bool:
    """Every outline garment-sized and not too detailed, and the whole garment checkable in
    reasonable time; the largest panel of each size at least MIN_GARMENT_EXTENT across."""
    n = len(err)
    work = 0
    for size in g.sizes:
        largest = 0.0
        for p in g.panels:
            if p.copy_of is not None or size not in p.shapes:
                continue
            shape = p.shapes[size]
            where = f"panel {p.name!r} (size {size})"
            if _check_size(shape, where, err):
                largest = max(largest, _extent(shape))
                w = _work(shape)
                if w > MAX_OUTLINE_WORK:
                    err.append(f"{where}: the outline is too convoluted to check ({w:,} edge "
                               f"pairs to test; at most {MAX_OUTLINE_WORK:,})")
                work += w
        if len(err) == n and largest < MIN_GARMENT_EXTENT:
            err.append(f"size {size}: the largest panel is {largest * 100:.3g} cm across (at "
                       f"least {MIN_GARMENT_EXTENT * 100:g} cm): not garment-sized (a pattern "
                       "is in metres)")
    if len(err) == n and work > MAX_CROSSING_WORK:
        err.append(f"the outlines are too detailed to check ({work:,} edge pairs to test; at "
                   f"most {MAX_CROSSING_WORK:,})")
    return len(err) == n


def _check_seams(g: Garment, rep: Report, unsound: set[str] = frozenset()) -> None:
    err = rep.errors
    for size in g.sizes:
        used: dict[str, list[tuple[int, int, int, str]]] = {}
        for i, s in enumerate(g.seams):
            if {g.source_vertex_map(g.panel(sd.panel))[0] for sd in (s.a, s.b)} & unsound:
                continue
            if not (g.cut_in(s.a.panel, size) and g.cut_in(s.b.panel, size)):
                continue   # a seam on a panel of other sizes only: not sewn in this one
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
    """Every panel of each size sewn to the rest of that size (sizes with the same panels are
    told once; a garment whose panels are in every size names no size)."""
    groups: dict[tuple[str, ...], list[str]] = {}
    for size in g.sizes:
        names = tuple(p.name for p in g.panels if g.cut_in(p, size))
        groups.setdefault(names, []).append(size)
    for names, sizes in groups.items():
        lost = _unreachable(g, names)
        if lost:
            which = "" if len(groups) == 1 else \
                f" (size{'s' if len(sizes) > 1 else ''} {', '.join(sizes)})"
            rep.errors.append(f"panel(s) {', '.join(repr(n) for n in lost)} not reachable from "
                              f"panel {names[0]!r} through seams{which} (every panel must be "
                              "sewn to the rest)")


def _unreachable(g: Garment, names: tuple[str, ...]) -> list[str]:
    """The panels of ``names`` no seam path joins to the first."""
    if len(names) < 2:
        return []
    adj: dict[str, set[str]] = {n: set() for n in names}
    for s in g.seams:
        if s.a.panel in adj and s.b.panel in adj:
            adj[s.a.panel].add(s.b.panel)
            adj[s.b.panel].add(s.a.panel)
    seen, todo = {names[0]}, [names[0]]
    while todo:
        for m in adj[todo.pop()]:
            if m not in seen:
                seen.add(m)
                todo.append(m)
    return [n for n in names if n not in seen]


def require_valid(g: Garment, base_dir: str | Path | None = None) -> Report:
    rep = check_garment(g, base_dir)
    if rep.errors:
        where = f"{g.path}: " if g.path else ""
        raise InputError(where + f"garment {g.name!r} has {len(rep.errors)} problem(s):\n  "
                         + "\n  ".join(rep.errors))
    return rep
