"""DXF import: AAMA / ASTM D6673 pattern exports (Gerber AccuMark, Lectra, CLO) and plain DXF.

AAMA / ASTM style (DXF R12, ``docs/garment-format.md`` has the details):

- one BLOCK per piece per size, placed in model space by an INSERT;
- layer ``1``: the boundary — Gerber writes several open POLYLINEs that are chained end to end,
  CLO one closed POLYLINE (flag 70 = 1); also TEXT ``Piece Name:``, ``Size:``, ``Quantity:``
  (keys in any case);
- layer ``7`` grain line, layer ``4`` notches (POINTs, or short LINEs whose end nearest the
  boundary is the notch), layer ``6`` mirror line (the piece is half, cut on that fold);
- file-level TEXT ``Units: ENGLISH`` (inches) or ``Units: METRIC`` (millimetres); the header's
  ``$INSUNITS`` is used when there is no such text, and ``units=`` overrides both.

Plain DXF: without such pieces, every closed POLYLINE / LWPOLYLINE in model space on any layer
is a piece (named after its layer and number).

Damaged files are read with ezdxf's recover mode. Every problem raises
:class:`catwalk.errors.InputError` naming the file, the piece and the size.
"""

from __future__ import annotations

import io
import math
import re
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from catwalk.errors import InputError
from catwalk.exchange.source import read_source
from catwalk.fileio import atomic_path
from catwalk.garment.check import MAX_PANEL_EXTENT
from catwalk.garment.geometry import (
    Segment,
    flatten,
    polygon_area,
    polyline_length,
    reverse_segments,
)
from catwalk.garment.model import Garment, Panel, Shape

UNIT_SCALE = {"in": 0.0254, "mm": 0.001, "cm": 0.01, "m": 1.0, "ft": 0.3048}
MAX_COORDINATE = 1000.0    # metres from the origin: pieces are laid out side by side
MAX_QUANTITY = 20          # copies of one piece
MAX_PIECES = 2000          # pieces (all sizes) in one file
MAX_BYTES = 256 << 20      # a DXF file
MAX_RUNS = 1000            # boundary polylines of one piece (chained end to end)
MAX_POINTS = 20_000        # boundary points of one piece
AAMA_UNITS = {"ENGLISH": "in", "METRIC": "mm"}
INSUNITS = {1: "in", 2: "ft", 4: "mm", 5: "cm", 6: "m"}
BOUNDARY, NOTCH, MIRROR, GRAIN = "1", "4", "6", "7"
_TEXT_KEY = re.compile(r"^\s*([A-Za-z][A-Za-z ]*?)\s*:\s*(.*?)\s*$")


@dataclass
class Piece:
    """One imported piece in one size (coordinates in metres, lower-left at the origin)."""
    name: str
    size: str
    quantity: int
    segments: list[Segment]
    grain: np.ndarray | None = None
    notches: np.ndarray = field(default_factory=lambda: np.zeros((0, 2)))
    mirror_line: np.ndarray | None = None
    fold: int | None = None
    block: str = ""
    texts: dict = field(default_factory=dict)
    flipped: int | None = None   # ASTM "Quantity: N,M": M of the copies cut mirrored

    @property
    def area_m2(self) -> float:
        return abs(polygon_area(flatten(self.segments, 1e-4).points))

    @property
    def perimeter_m(self) -> float:
        return polyline_length(flatten(self.segments, 1e-4).points)

    def summary(self) -> dict:
        return {"name": self.name, "size": self.size, "quantity": self.quantity,
                "flipped": self.flipped,
                "area_m2": round(self.area_m2, 6), "perimeter_m": round(self.perimeter_m, 5),
                "notches": int(len(self.notches)), "mirrored": self.mirror_line is not None}


# --- reading the file ----------------------------------------------------------------------

def _read_doc(data: bytes, path: str):
    """The DXF document in ``data`` and warnings: read strictly (text in the encoding its
    header names, or binary DXF), else in ezdxf's recover mode, else refused with the reason."""
    import ezdxf  # deferred: ezdxf loads in ≈ 0.2 s; only DXF files need it
    from ezdxf import recover  # deferred: ezdxf loads in ≈ 0.2 s; only DXF files need it
    from ezdxf.document import Drawing  # deferred: ezdxf loads in ≈ 0.2 s; only DXF files need it
    from ezdxf.filemanagement import (
        dxf_stream_info,  # deferred: ezdxf loads in ≈ 0.2 s; only DXF files need it
    )  # deferred: ezdxf loads in ≈ 0.2 s; only DXF files need it
    from ezdxf.lldxf.tagger import (
        binary_tags_loader,  # deferred: ezdxf loads in ≈ 0.2 s; only DXF files need it
    )  # deferred: ezdxf loads in ≈ 0.2 s; only DXF files need it
    from ezdxf.lldxf.validator import (
        is_dxf_stream,  # deferred: ezdxf loads in ≈ 0.2 s; only DXF files need it
    )  # deferred: ezdxf loads in ≈ 0.2 s; only DXF files need it

    if not data.strip():
        raise InputError(f"{path}: the file is empty")
    try:
        if data.startswith(b"AutoCAD Binary DXF"):
            return Drawing.load(binary_tags_loader(data, errors="surrogateescape")), []
        head = data[:65536].decode("cp1252", errors="surrogateescape")
        if not is_dxf_stream(io.StringIO(head)):
            raise InputError(f"{path}: not readable as DXF (no DXF section structure at the "
                             "start)")
        encoding = dxf_stream_info(io.StringIO(head)).encoding
        return ezdxf.read(io.StringIO(data.decode(encoding, errors="surrogateescape"))), []
    except InputError:
        raise
    except RecursionError:
        raise InputError(f"{path}: not readable as DXF (nested too deeply)") from None
    except Exception:  # noqa: BLE001 - ezdxf raises many kinds on damaged files: recover
        pass
    try:
        doc, auditor = recover.read(io.BytesIO(data))
    except ezdxf.DXFStructureError as exc:
        raise InputError(f"{path}: not a DXF file, or damaged beyond repair ({exc})") from None
    except Exception as exc:  # noqa: BLE001 - ezdxf raises many kinds on damaged files
        raise InputError(f"{path}: not readable as DXF ({type(exc).__name__}: "
                         f"{str(exc)[:200]})") from None
    if auditor.has_errors:
        msgs = "; ".join(str(e.message) for e in auditor.errors[:3])
        raise InputError(f"{path}: DXF damaged beyond repair ({msgs})")
    return doc, [f"{path}: damaged DXF read in recover mode ({len(auditor.fixes)} fix(es))"]


def _texts(entities) -> dict[str, str]:
    out = {}
    for e in entities:
        if e.dxftype() not in ("TEXT", "MTEXT"):
            continue
        raw = e.dxf.text if e.dxftype() == "TEXT" else e.plain_text()
        m = _TEXT_KEY.match(raw or "")
        if m:
            out.setdefault(m.group(1).strip().lower(), m.group(2).strip())
    return out


def _polyline_vertices(e) -> tuple[list[tuple[float, float, float]], bool] | None:
    """(x, y, bulge) vertices and closed flag of a 2D polyline-like entity."""
    t = e.dxftype()
    if t == "LWPOLYLINE":
        return [(float(x), float(y), float(b)) for x, y, b in e.get_points("xyb")], e.closed
    if t == "POLYLINE":
        if e.get_mode() not in ("AcDb2dPolyline", "AcDb3dPolyline"):
            return None
        verts = [(float(v.dxf.location.x), float(v.dxf.location.y),
                  float(v.dxf.get("bulge", 0.0))) for v in e.vertices]
        return verts, e.is_closed
    if t == "LINE":
        s, d = e.dxf.start, e.dxf.end
        return [(s.x, s.y, 0.0), (d.x, d.y, 0.0)], False
    if t == "ARC":
        c, r = e.dxf.center, e.dxf.radius
        a0, a1 = math.radians(e.dxf.start_angle), math.radians(e.dxf.end_angle)
        sweep = (a1 - a0) % (2 * math.pi) or 2 * math.pi
        return [(c.x + r * math.cos(a0), c.y + r * math.sin(a0), math.tan(sweep / 4)),
                (c.x + r * math.cos(a1), c.y + r * math.sin(a1), 0.0)], False
    return None


def _reverse_run(verts):
    """An open (x, y, bulge) run walked backwards."""
    out = []
    for i in range(len(verts) - 1, -1, -1):
        bulge = -verts[i - 1][2] if i > 0 else 0.0
        out.append((verts[i][0], verts[i][1], bulge))
    return out


def _chain(runs: list[list], tol: float, where: str):
    """Chain open runs end to end into one closed loop of (x, y, bulge)."""
    runs = [r for r in runs if len(r) >= 2]
    if not runs:
        raise InputError(f"{where}: no boundary on layer 1")
    loop = list(runs.pop(0))
    while runs:
        end = np.array(loop[-1][:2])
        best, best_d, flip = None, None, False
        for k, r in enumerate(runs):
            for f, pt in ((False, r[0]), (True, r[-1])):
                d = float(np.hypot(pt[0] - end[0], pt[1] - end[1]))
                if best_d is None or d < best_d:
                    best, best_d, flip = k, d, f
        if best_d > tol:
            raise InputError(f"{where}: boundary cannot be closed: a gap of "
                             f"{best_d * 1000:.1f} mm after ({end[0]:.4f}, {end[1]:.4f}) m")
        r = runs.pop(best)
        if flip:
            r = _reverse_run(r)
        loop[-1] = (loop[-1][0], loop[-1][1], loop[-1][2])
        loop.extend(r[1:])
    gap = float(np.hypot(loop[-1][0] - loop[0][0], loop[-1][1] - loop[0][1]))
    if gap > tol:
        raise InputError(f"{where}: boundary cannot be closed: its ends are "
                         f"{gap * 1000:.1f} mm apart, at ({loop[0][0]:.4f}, {loop[0][1]:.4f}) "
                         f"and ({loop[-1][0]:.4f}, {loop[-1][1]:.4f}) m")
    loop[-1] = (loop[0][0], loop[0][1], loop[-1][2])
    return loop[:-1] if len(loop) > 1 else loop


def _to_segments(loop, where: str) -> list[Segment]:
    pts = []
    for x, y, b in loop:   # drop repeated points (keep the bulge of the last copy)
        if pts and abs(pts[-1][0] - x) < 1e-9 and abs(pts[-1][1] - y) < 1e-9:
            pts[-1] = (x, y, b)
            continue
        pts.append((x, y, b))
    if len(pts) > 1 and abs(pts[-1][0] - pts[0][0]) < 1e-9 and abs(pts[-1][1] - pts[0][1]) < 1e-9:
        pts.pop()
    if len(pts) < 3 and not any(abs(p[2]) > 0 for p in pts):
        raise InputError(f"{where}: boundary has fewer than 3 distinct points")
    segs = [Segment("arc" if abs(b) > 1e-12 else "line", np.array([x, y]), bulge=b)
            for x, y, b in pts]
    if polygon_area(flatten(segs, 1e-4).points) < 0:
        segs = reverse_segments(segs)
    return segs


def _checked(verts, scale: float, where: str, what: str = "a boundary point"
             ) -> list[tuple[float, float, float]]:
    """(x, y, bulge) in metres, every number finite and every point within MAX_COORDINATE."""
    try:
        a = np.asarray(verts, dtype=float).reshape(-1, 3)
    except (TypeError, ValueError):
        raise InputError(f"{where}: {what} is not a number") from None
    with np.errstate(all="ignore"):   # an overflow is reported as not finite, just below
        a[:, :2] *= scale
    if not np.isfinite(a).all():
        raise InputError(f"{where}: {what} (or its bulge) is not a finite number")
    far = float(np.abs(a[:, :2]).max()) if len(a) else 0.0
    if far > MAX_COORDINATE:
        raise InputError(f"{where}: {what} lies {far:.3g} m from the origin: not a pattern "
                         "(are the units right?)")
    return [tuple(p) for p in a.tolist()]


def _loop_from(entities, scale: float, where: str, tol: float):
    closed, runs, points = [], [], 0
    for e in entities:
        got = _polyline_vertices(e)
        if got is None:
            continue
        verts, is_closed = got
        points += len(verts)   # the caps before any conversion
        if len(closed) + len(runs) >= MAX_RUNS:
            raise InputError(f"{where}: more than {MAX_RUNS:,} boundary polylines: at most "
                             f"{MAX_RUNS:,} are chained")
        if points > MAX_POINTS:
            raise InputError(f"{where}: more than {MAX_POINTS:,} boundary points: too detailed")
        (closed if is_closed else runs).append(_checked(verts, scale, where))
    if closed and not runs:
        if len(closed) > 1:  # keep the largest; inner loops are cut-outs we do not model
            closed.sort(key=lambda v: -abs(polygon_area(np.array([p[:2] for p in v]))))
        return closed[0]
    if closed and runs:
        runs = runs + [closed[0] + [closed[0][0]]]
    return _chain(runs, tol, where)


def _units(doc, units: str | None, path: Path) -> float:
    if units is not None:
        if units not in UNIT_SCALE:
            raise InputError(f"units {units!r}: use one of {', '.join(UNIT_SCALE)}")
        return UNIT_SCALE[units]
    found = set()
    for layout in [doc.modelspace(), *doc.blocks]:
        t = _texts(layout)
        if "units" in t:
            found.add(t["units"].strip().upper())
    if len(found) > 1:
        raise InputError(f"{path}: conflicting 'Units:' texts ({', '.join(sorted(found))})")
    if found:
        u = found.pop()
        if u not in AAMA_UNITS:
            raise InputError(f"{path}: 'Units: {u}' is neither ENGLISH nor METRIC")
        return UNIT_SCALE[AAMA_UNITS[u]]
    ins = doc.header.get("$INSUNITS", 0)
    if ins in INSUNITS:
        return UNIT_SCALE[INSUNITS[ins]]
    raise InputError(f"{path}: missing units: no 'Units: ENGLISH|METRIC' text and no $INSUNITS "
                     f"in the header; give --units (in, mm, cm, m)")


def _notch_points(entities, scale: float, boundary: np.ndarray, where: str) -> np.ndarray:
    pts = []
    for e in entities:
        t = e.dxftype()
        if t == "POINT":
            loc = e.dxf.location
            pts.append(_checked([(loc.x, loc.y, 0.0)], scale, where, "a notch")[0][:2])
        elif t in ("LINE", "POLYLINE", "LWPOLYLINE"):
            got = _polyline_vertices(e)
            if not got or not got[0]:
                continue
            ends = np.array([p[:2] for p in _checked([got[0][0], got[0][-1]], scale, where,
                                                     "a notch")])
            d = [np.min(np.linalg.norm(boundary - p, axis=1)) for p in ends]
            pts.append(tuple(ends[int(np.argmin(d))]))
        if len(pts) > 1000:
            raise InputError(f"{where}: more than 1,000 notches")
    return np.array(pts, dtype=float).reshape(-1, 2)


def _line_points(entities, scale: float, where: str, what: str) -> np.ndarray | None:
    for e in entities:
        got = _polyline_vertices(e)
        if got and len(got[0]) >= 2:
            v = _checked([got[0][0], got[0][-1]], scale, where, what)
            return np.array([p[:2] for p in v], dtype=float)
    return None


def _find_fold(segs: list[Segment], line: np.ndarray, tol: float) -> int | None:
    d = line[1] - line[0]
    ln = float(np.linalg.norm(d))
    if ln == 0:
        return None
    nrm = np.array([-d[1], d[0]]) / ln
    n = len(segs)
    for i, s in enumerate(segs):
        if s.kind != "line":
            continue
        a, b = s.start, segs[(i + 1) % n].start
        if abs(np.dot(a - line[0], nrm)) < tol and abs(np.dot(b - line[0], nrm)) < tol \
                and np.linalg.norm(b - a) > 0.5 * ln:
            return i
    return None


def _on_layer(entities, layer: str):
    return [e for e in entities if str(e.dxf.get("layer", "0")).strip().upper() == layer]


def read_dxf(source, size: str | None = None, units: str | None = None
             ) -> tuple[list[Piece], list[str]]:
    """Pieces of a pattern DXF (a path, bytes or a binary file object; all sizes, or only
    ``size``) and warnings."""
    data, path = read_source(source, "dxf", max_bytes=MAX_BYTES)
    doc, warnings = _read_doc(data, path)
    msp = doc.modelspace()
    if len(msp) == 0:
        raise InputError(f"{path}: no pattern pieces found (model space is empty: an empty or "
                         f"truncated file)")
    scale = _units(doc, units, path)
    pieces: list[Piece] = []
    seen_blocks: set[str] = set()
    for ins in msp.query("INSERT"):
        bname = ins.dxf.name
        if bname in seen_blocks:
            warnings.append(f"{path}: block {bname!r} is inserted more than once; used once")
            continue
        seen_blocks.add(bname)
        try:
            ents = list(ins.virtual_entities())
        except Exception as exc:  # noqa: BLE001 - ezdxf raises many kinds on broken blocks
            raise InputError(f"{path}: block {bname!r} cannot be read ({exc})") from None
        texts = _texts(ents)
        # names as the garment format takes them: non-empty, no surrounding spaces, ≤ 200
        name = (texts.get("piece name") or "")[:200].strip() or str(bname)[:200].strip() \
            or f"piece-{len(pieces) + 1}"
        psize = (texts.get("size") or "")[:200].strip() or "one-size"
        where = f"{path}: piece {name!r} (size {psize})"
        boundary_ents = _on_layer(ents, BOUNDARY)
        if not any(_polyline_vertices(e) for e in boundary_ents):
            boundary_ents = [e for e in ents if (g := _polyline_vertices(e)) and g[1]]
            if not boundary_ents:
                if "piece name" not in texts:
                    continue   # a style-text block, or one without geometry
                raise InputError(f"{where}: no boundary (layer 1) and no closed polyline")
        qty, flipped = _quantity(texts.get("quantity"), where)
        if qty == 0:
            warnings.append(f"{where}: quantity 0 (not cut): skipped")
            continue
        pieces.append(_piece(ents, boundary_ents, texts, name, psize, bname, scale, where,
                             qty, flipped))
    if not pieces:  # plain DXF: closed polylines in model space on any layer
        counts: dict[str, int] = {}
        for e in msp:
            got = _polyline_vertices(e)
            if not got or not got[1]:
                continue
            layer = str(e.dxf.get("layer", "0"))
            counts[layer] = counts.get(layer, 0) + 1
            name = f"{layer}-{counts[layer]}"
            where = f"{path}: piece {name!r}"
            pieces.append(_piece([e], [e], {}, name, "one-size", "", scale, where, 1, None))
    if len(pieces) > MAX_PIECES:
        raise InputError(f"{path}: {len(pieces):,} pieces; at most {MAX_PIECES:,} are read")
    if not pieces:
        raise InputError(f"{path}: no pattern pieces found (no blocks with a layer-1 boundary and "
                         f"no closed polylines)")
    seen: dict[tuple[str, str], str] = {}
    for p in pieces:
        key = (p.name, p.size)
        if key in seen:
            raise InputError(f"{path}: duplicate piece name {p.name!r} in size {p.size} "
                             f"(blocks {seen[key]!r} and {p.block!r})")
        seen[key] = p.block
    if size is not None:
        sizes = sorted({p.size for p in pieces})
        pieces = [p for p in pieces if p.size == size]
        if not pieces:
            raise InputError(f"{path}: no piece in size {size!r} (sizes: {', '.join(sizes)})")
    return pieces, warnings


def _count(text: str, raw: str, where: str) -> int:
    try:
        n = float(text)
    except ValueError:
        raise InputError(f"{where}: 'Quantity: {raw}' is not a number") from None
    if not (math.isfinite(n) and n == int(n) and 0 <= n <= MAX_QUANTITY):
        raise InputError(f"{where}: 'Quantity: {raw}' is not a whole number of copies "
                         f"0–{MAX_QUANTITY}")
    return int(n)


def _quantity(raw: str | None, where: str) -> tuple[int, int | None]:
    """The copies a piece is cut in and how many of them mirrored: AAMA's ``Quantity: N``
    (N, None: copies alternate plain and mirrored, a left and right pair) or ASTM D6673's
    ``Quantity: N,M`` (N + M, M: N cut as drawn, M mirrored). 0 copies: the piece is not
    cut."""
    raw = (raw or "1").strip() or "1"
    parts = [p.strip() for p in raw.split(",")]
    if len(parts) > 2:
        raise InputError(f"{where}: 'Quantity: {raw}' is neither N nor N,M (as drawn, "
                         "mirrored)")
    counts = [_count(p, raw, where) for p in parts]
    if len(counts) == 1:
        return counts[0], None
    plain, flipped = counts
    if plain + flipped > MAX_QUANTITY:
        raise InputError(f"{where}: 'Quantity: {raw}': {plain + flipped} copies; at most "
                         f"{MAX_QUANTITY}")
    if plain == 0 and flipped > 0:
        raise InputError(f"{where}: 'Quantity: {raw}': a piece cut only mirrored is not read; "
                         f"mirror it in the file and give 'Quantity: {flipped},0'")
    return plain + flipped, flipped


def _piece(ents, boundary_ents, texts, name, psize, bname, scale, where, qty: int,
           flipped: int | None) -> Piece:
    # chaining tolerance: 0.5 mm
    loop = _loop_from(boundary_ents, scale, where, tol=5e-4)
    segs = _to_segments(loop, where)
    pts = flatten(segs, 1e-4).points
    ext = float(np.ptp(pts, axis=0).max())
    if ext > MAX_PANEL_EXTENT:
        raise InputError(f"{where}: the piece is {ext:.4g} m across (at most "
                         f"{MAX_PANEL_EXTENT:g} m): not garment-sized — are the units right "
                         "(the file's 'Units:' text or $INSUNITS, or give the units)?")
    if abs(polygon_area(pts)) < 1e-6:
        raise InputError(f"{where}: the boundary encloses no area")
    origin = pts.min(axis=0)
    for s in segs:
        s.start = s.start - origin
    bpts = pts - origin
    grain = _line_points(_on_layer(ents, GRAIN), scale, where, "the grain line")
    if grain is not None:
        grain = grain - origin
    notches = _notch_points(_on_layer(ents, NOTCH), scale, bpts + origin, where) - origin \
        if _on_layer(ents, NOTCH) else np.zeros((0, 2))
    mline = _line_points(_on_layer(ents, MIRROR), scale, where, "the mirror line")
    fold = None
    if mline is not None:
        mline = mline - origin
        fold = _find_fold(segs, mline, tol=5e-4)
    return Piece(name, psize, qty, segs, grain, notches.reshape(-1, 2), mline, fold, bname,
                 texts, flipped)


# --- to a garment ---------------------------------------------------------------------------

def pieces_to_garment(pieces: list[Piece], name: str, source: dict | None = None) -> Garment:
    """A garment with one panel per piece name (its sizes as shapes); quantity 2 adds a
    mirrored copy ``NAME (2)``, higher quantities alternate plain and mirrored copies (ASTM's
    ``N,M``: the copies after the first N are the mirrored ones)."""
    sizes = []
    for p in pieces:
        if p.size not in sizes:
            sizes.append(p.size)
    by_name: dict[str, list[Piece]] = {}
    for p in pieces:
        by_name.setdefault(p.name, []).append(p)
    panels = []
    for pname, group in by_name.items():
        have = {p.size for p in group}
        missing = [s for s in sizes if s not in have]
        if missing:
            raise InputError(f"piece {pname!r}: missing in size(s) {', '.join(missing)}")
        shapes = {p.size: Shape([s.copy() for s in p.segments], p.grain, p.notches)
                  for p in group}
        first = group[0]
        meta = {"dxf_block": first.block, "quantity": first.quantity}
        if first.flipped is not None:
            meta["flipped"] = first.flipped
        if first.mirror_line is not None and first.fold is None:
            meta["mirror_line"] = [[round(float(x), 6) for x in pt] for pt in first.mirror_line]
        panels.append(Panel(pname, "other", shapes, fold=first.fold, meta=meta))
        plain = first.quantity - (first.flipped or 0)
        for k in range(2, first.quantity + 1):
            # AAMA: alternate (a pair is a left and a right); ASTM N,M: N as drawn, M mirrored
            mirror = k % 2 == 0 if first.flipped is None else k > plain
            panels.append(Panel(f"{pname} ({k})", "other", copy_of=pname, mirror=mirror))
    return Garment(name, "other", sizes, panels, [], "cotton-jersey", source=source or {})


# --- export ---------------------------------------------------------------------------------

def write_dxf(g: Garment, path: str | Path, style: str = "clo", units: str = "METRIC",
              tolerance: float = 5e-4) -> int:
    """Write ``g`` as an AAMA-style DXF R12 (one block per panel per size; curves flattened
    within ``tolerance`` m, as pattern CAD exports them). ``style`` ``"gerber"`` splits each
    boundary into open polylines, ``"clo"`` writes one closed polyline. Panels cut on fold are
    written as their stored half with a mirror line (layer 6); a mirrored copy adds to its
    source's quantity. Returns the number of blocks."""
    import ezdxf  # deferred: ezdxf loads in ≈ 0.2 s; only DXF files need it


    if units not in AAMA_UNITS:
        raise InputError(f"units must be ENGLISH or METRIC, not {units!r}")
    k = 1.0 / UNIT_SCALE[AAMA_UNITS[units]]
    doc = ezdxf.new("R12")
    msp = doc.modelspace()
    qty = {p.name: 1 for p in g.panels}
    for p in g.panels:
        if p.copy_of is not None:
            src = g.source_vertex_map(p)[0]
            qty[src] += 1
    # graded sizes get the same points (as CAD grading keeps them): per edge, the most chords
    # any size needs
    chords = {}
    for p in g.panels:
        if p.copy_of is None and len({len(p.shapes[s].outline) for s in g.sizes}) == 1:
            per = [[seg.pieces(p.shapes[s].outline[(i + 1) % len(p.shapes[s].outline)].start,
                               tolerance) for i, seg in enumerate(p.shapes[s].outline)]
                   for s in g.sizes]
            chords[p.name] = np.max(np.array(per), axis=0)
    x = 0.0
    blocks = 0
    for size in g.sizes:
        for p in g.panels:
            if p.copy_of is not None:
                continue
            shape = p.shapes[size]
            pts = flatten(shape.outline, tolerance, chords.get(p.name)).points * k
            name = f"{p.name}_{size}".replace(" ", "_")
            blk = doc.blocks.new(name=name)
            loop = [tuple(v) for v in pts]
            if style == "gerber":
                ring = loop + [loop[0]]
                cuts = [0, len(ring) // 3, 2 * len(ring) // 3, len(ring) - 1]
                for a, b in zip(cuts[:-1], cuts[1:], strict=True):
                    blk.add_polyline2d(ring[a:b + 1], dxfattribs={"layer": "1"})
            else:
                blk.add_polyline2d(loop, close=True, dxfattribs={"layer": "1"})
            if shape.grain is not None:
                gr = shape.grain * k
                blk.add_line(tuple(gr[0]), tuple(gr[1]), dxfattribs={"layer": "7"})
            for n in shape.notches * k:
                blk.add_point(tuple(n), dxfattribs={"layer": "4"})
            if p.fold is not None:
                segs = shape.outline
                a, b = segs[p.fold].start * k, segs[(p.fold + 1) % len(segs)].start * k
                blk.add_line(tuple(a), tuple(b), dxfattribs={"layer": "6"})
            lo = pts.min(axis=0)
            for j, text in enumerate((f"Piece Name: {p.name}", f"Size: {size}",
                                      f"Quantity: {qty[p.name]}")):
                blk.add_text(text, dxfattribs={"layer": "1", "height": 0.01 * k,
                                               "insert": (lo[0], lo[1] - (j + 1) * 0.02 * k)})
            msp.add_blockref(name, (x - lo[0], 0.0))
            x += float(np.ptp(pts[:, 0])) + 0.05 * k
            blocks += 1
    msp.add_text(f"Style Name: {g.name}", dxfattribs={"layer": "1", "insert": (0, -0.2 * k)})
    msp.add_text(f"Units: {units}", dxfattribs={"layer": "1", "insert": (0, -0.25 * k)})
    with atomic_path(path) as tmp:
        doc.saveas(tmp)
    return blocks
