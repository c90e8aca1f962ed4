"""FreeSewing drafts → our garment format.

``garments/freesewing/draft.mjs`` (Node, npm ``@freesewing/*@4.10.2``, MIT) drafts a design for
each size and writes ``drafts/<id>.json``: per size the measurements used and each visible
part's seam line (FreeSewing's ``seam`` path, without seam allowance: millimetres, +x right,
+y down) as ops ``["M", x, y]``, ``["L", x, y]``, ``["C", c1x, c1y, c2x, c2y, x, y]``,
``["Z"]``, with the part's cut count and ``onFold``.

Conversion: millimetres → metres with y flipped (+y up), loops made counter-clockwise, zero
-length edges dropped; vertex ``i`` is the start of edge ``i``, counted from the path's first
point in the counter-clockwise order. A part cut on fold is folded along its straight edge on
x = 0 (FreeSewing drafts fold parts with the fold on the y axis); a part cut twice gets a mirrored
copy ``NAME (2)``. FreeSewing does not say which edges sew together: the markup
(``garments/freesewing/markup/<id>.json``, the same format as DXF markup, keyed by part name)
adds panel names, types, placement and the seams.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from catwalk.errors import InputError
from catwalk.exchange.source import read_json
from catwalk.garment.geometry import (
    Segment,
    flatten,
    polygon_area,
    reverse_segments,
    segment_lengths,
)
from catwalk.garment.model import Garment, Panel, Shape

MIN_EDGE = 1e-4  # metres: shorter FreeSewing edges (zero-length curves) are dropped


def ops_to_segments(ops: list, where: str) -> list[Segment]:
    segs: list[Segment] = []
    first = cur = None
    for k, op in enumerate(ops):
        try:
            kind = op[0]
            if kind == "M":
                if first is not None:
                    raise InputError(f"{where}: op {k}: a second move (the seam line must be one "
                                     f"loop)")
                first = cur = np.array([op[1], -op[2]], dtype=float) / 1000.0
            elif kind == "L":
                to = np.array([op[1], -op[2]], dtype=float) / 1000.0
                segs.append(Segment("line", cur))
                cur = to
            elif kind == "C":
                c1 = np.array([op[1], -op[2]], dtype=float) / 1000.0
                c2 = np.array([op[3], -op[4]], dtype=float) / 1000.0
                to = np.array([op[5], -op[6]], dtype=float) / 1000.0
                segs.append(Segment("cubic", cur, [c1, c2]))
                cur = to
            elif kind == "Z":
                if first is not None and np.linalg.norm(cur - first) > MIN_EDGE:
                    segs.append(Segment("line", cur))
                    cur = first
            else:
                raise InputError(f"{where}: op {k}: unknown op {kind!r}")
        except (IndexError, TypeError, ValueError):
            raise InputError(f"{where}: op {k} is malformed: {op!r}") from None
    if first is None or not segs:
        raise InputError(f"{where}: empty seam path")
    if np.linalg.norm(cur - first) > 1e-3:
        raise InputError(f"{where}: the seam path does not close (its ends are "
                         f"{np.linalg.norm(cur - first) * 1000:.1f} mm apart)")
    # drop zero-length edges: an edge whose start equals the next edge's start
    n = len(segs)
    ends = [segs[(i + 1) % n].start if i + 1 < n else first for i in range(n)]
    keep = [s for s, e in zip(segs, ends, strict=True)
            if np.linalg.norm(e - s.start) > MIN_EDGE
            or (s.kind == "cubic" and max(np.linalg.norm(c - s.start) for c in s.controls)
                > MIN_EDGE)]
    if polygon_area(flatten(keep, 1e-4).points) < 0:
        keep = reverse_segments(keep)
    return keep


def _fold_edge(segs: list[Segment]) -> int | None:
    n = len(segs)
    best, best_len = None, 0.0
    for i, s in enumerate(segs):
        a, b = s.start, segs[(i + 1) % n].start
        if s.kind == "line" and abs(a[0]) < 1e-6 and abs(b[0]) < 1e-6:
            ln = abs(a[1] - b[1])
            if ln > best_len:
                best, best_len = i, ln
    return best


def freesewing_to_garment(draft: dict, where: str = "draft") -> Garment:
    try:
        sizes = list(draft["sizes"])
        design = draft["design"]
    except (KeyError, TypeError):
        raise InputError(f"{where}: not a FreeSewing draft from draft.mjs") from None
    if not sizes:
        raise InputError(f"{where}: no sizes")
    part_names = list(draft["sizes"][sizes[0]]["parts"])
    panels = []
    for pname in part_names:
        shapes = {}
        info = None
        for size in sizes:
            parts = draft["sizes"][size]["parts"]
            if pname not in parts:
                raise InputError(f"{where}: part {pname!r} missing in size {size}")
            info = parts[pname]
            segs = ops_to_segments(info["seam"], f"{where}: part {pname!r} (size {size})")
            shapes[size] = Shape(segs, np.array([[0.0, 0.0], [0.0, 1.0]]))
        counts = {len(s.outline) for s in shapes.values()}
        if len(counts) > 1:
            raise InputError(f"{where}: part {pname!r} has different numbers of edges in "
                             f"different sizes ({sorted(counts)})")
        fold = None
        meta = {"freesewing_part": pname, "cut": int(info.get("cut", 1))}
        cut = int(info.get("cut", 1))
        if info.get("onFold"):
            folds = {_fold_edge(s.outline) for s in shapes.values()}
            if None in folds:
                # FreeSewing quirk: bella.back says "cut 2 on fold" but its centre back is
                # shaped; it is two mirrored pieces with a centre-back seam
                meta["note"] = ("cut list says on fold, but no straight edge lies on x = 0: "
                                "cut as separate pieces")
            elif len(folds) > 1:
                raise InputError(f"{where}: part {pname!r}: the fold edge moves between sizes")
            else:
                fold = folds.pop()
                cut = 1   # a part cut on fold is one piece however FreeSewing counts it
        panels.append(Panel(pname, "other", shapes, fold=fold, meta=meta))
        for k in range(2, cut + 1):
            panels.append(Panel(f"{pname} ({k})", "other", copy_of=pname, mirror=(k % 2 == 0)))
    measurements = {s: {"model": draft["sizes"][s].get("model"),
                        "recipe": draft["sizes"][s].get("recipe")} for s in sizes}
    fit = {s: str(v["recipe"]) for s, v in measurements.items() if v.get("recipe")}
    return Garment(draft.get("id", design), "other", sizes, panels, [], "cotton-jersey",
                   sizes[len(sizes) // 2], fit=fit,
                   source={"freesewing": f"@freesewing/{design}@{draft.get('version')}",
                           "licence": "FreeSewing designs: MIT", "options": draft.get("options"),
                           "measurements": measurements,
                           "converter": "catwalk garment from-freesewing"})


def load_freesewing(source) -> Garment:
    """A FreeSewing draft from draft.mjs (a path, bytes or a binary file object)."""
    if isinstance(source, (str, Path)) and not Path(source).is_file():
        raise InputError(f"{source}: no such draft (run node garments/freesewing/draft.mjs)")
    data, where = read_json(source, "draft")
    return freesewing_to_garment(data, Path(where).name)


def describe(g: Garment, size: str | None = None) -> str:
    """Vertices of every panel (for writing seam markup by hand)."""
    size = g.size(size)
    lines = []
    for p in g.panels:
        if p.copy_of:
            continue
        segs = p.shapes[size].outline
        lens = segment_lengths(segs)
        lines.append(f"{p.name}" + (f" (fold edge {p.fold})" if p.fold is not None else ""))
        for i, s in enumerate(segs):
            lines.append(f"  v{i:<3} ({s.start[0]:+.4f}, {s.start[1]:+.4f})  edge {i}: {s.kind:<9} "
                         f"{lens[i]:.4f} m")
    return "\n".join(lines)


