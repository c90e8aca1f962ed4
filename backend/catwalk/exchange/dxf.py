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

What real exports carry (``docs/garment-format.md``, "What real exports carry") is read, not
refused: the sample size's ``Quantity: 0`` where the other sizes state none, pieces of some
sizes only, repeated boundary points and small self-crossing loops
(:mod:`catwalk.exchange.dxf_repair`), pieces too small in the file's units (read in the unit
that makes them garment-sized). Each repair and assumption is a warning
(:class:`~catwalk.exchange.dxf_repair.Note`): returned by :func:`read_dxf` and kept on the
piece's panel.
"""

from __future__ import annotations

import io
import math
import re
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from catwalk.errors import InputError
from catwalk.exchange.dxf_repair import (
    DUPLICATE,
    Note,
    drop_repeats,
    remove_small_loops,
    segments_of,
)
from catwalk.exchange.source import read_source
from catwalk.fileio import atomic_path
from catwalk.garment.check import MAX_PANEL_EXTENT, MIN_GARMENT_EXTENT
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
GUESSES = ("cm", "in", "m")   # what a file too small in its stated units may be drawn in
UNIT_NAMES = {"in": "inches", "mm": "millimetres", "cm": "centimetres", "m": "metres",
              "ft": "feet"}
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
    notes: list[Note] = field(default_factory=list)   # what reading it repaired or assumed

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
    """The DXF document in ``data`` and notes: read strictly (text in the encoding its header
    names, or binary DXF), else in ezdxf's recover mode, else refused with the reason."""
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
    return doc, [Note("recovered", f"damaged DXF read in recover mode ({len(auditor.fixes)} "
                                   "fix(es))", data={"fixes": len(auditor.fixes)})]


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


def _chain(runs: list[list], tol: float, where: str) -> tuple[list, float]:
    """Chain open runs end to end into one closed loop of (x, y, bulge); also the widest gap
    (metres) closed between runs, or between the loop's ends."""
    runs = [r for r in runs if len(r) >= 2]
    if not runs:
        raise InputError(f"{where}: no boundary on layer 1")
    loop = list(runs.pop(0))
    widest = 0.0
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
        widest = max(widest, best_d)
        r = runs.pop(best)
        if flip:
            r = _reverse_run(r)
        loop.extend(r[1:])
    gap = float(np.hypot(loop[-1][0] - loop[0][0], loop[-1][1] - loop[0][1]))
    if gap > tol:
        raise InputError(f"{where}: boundary cannot be closed: its ends are "
                         f"{gap * 1000:.1f} mm apart, at ({loop[0][0]:.4f}, {loop[0][1]:.4f}) "
                         f"and ({loop[-1][0]:.4f}, {loop[-1][1]:.4f}) m")
    loop[-1] = (loop[0][0], loop[0][1], loop[-1][2])
    return (loop[:-1] if len(loop) > 1 else loop), max(widest, gap)


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


def _boundary_polylines(entities, where: str):
    """(vertices, closed) of every boundary polyline, within the caps (counted before any
    conversion)."""
    out, points = [], 0
    for e in entities:
        got = _polyline_vertices(e)
        if got is None:
            continue
        points += len(got[0])
        if len(out) >= MAX_RUNS:
            raise InputError(f"{where}: more than {MAX_RUNS:,} boundary polylines: at most "
                             f"{MAX_RUNS:,} are chained")
        if points > MAX_POINTS:
            raise InputError(f"{where}: more than {MAX_POINTS:,} boundary points: too detailed")
        out.append(got)
    return out


def _loop_from(src: _Source, scale: float, tol: float):
    """The boundary's closed loop of (x, y, bulge) in metres: one closed polyline, or open
    runs chained end to end (within ``tol``)."""
    closed, runs = [], []
    for verts, is_closed in _boundary_polylines(src.boundary, src.where):
        verts = _checked(verts, scale, src.where)
        if is_closed and len(verts) > 1 and verts[-1][:2] == verts[0][:2]:
            verts = verts[:-1]   # closed, and its first point written again at the end
        (closed if is_closed else runs).append(verts)
    if len(closed) > 1:  # keep the largest; inner loops are cut-outs we do not model
        closed.sort(key=lambda v: -abs(polygon_area(np.array([p[:2] for p in v]))))
        src.note("inner-loops", f"{len(closed) - 1} more closed outline(s) in the piece "
                                "ignored: the largest is its boundary (cut-outs inside a piece "
                                "are not modelled)", count=len(closed) - 1)
    if closed and runs:
        runs = runs + [closed[0] + [closed[0][0]]]
    if closed and not runs:
        return closed[0]
    loop, gap = _chain(runs, tol, src.where)
    if gap > DUPLICATE:
        src.note("gap-closed", f"the boundary's lines were joined across gaps of up to "
                               f"{gap * 1000:.2f} mm", gap_mm=round(gap * 1000, 3))
    return loop


def _units(doc, units: str | None, path: str) -> tuple[str, str]:
    """The units (a key of UNIT_SCALE) and where they come from: ``given``, or the file's
    text or header as words."""
    if units is not None:
        if units not in UNIT_SCALE:
            raise InputError(f"units {units!r}: use one of {', '.join(UNIT_SCALE)}")
        return units, "given"
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
        return AAMA_UNITS[u], f"the file's 'Units: {u}'"
    ins = doc.header.get("$INSUNITS", 0)
    if ins in INSUNITS:
        return INSUNITS[ins], f"the header's $INSUNITS = {ins}"
    raise InputError(f"{path}: missing units: no 'Units: ENGLISH|METRIC' text and no $INSUNITS "
                     f"in the header; give --units (in, mm, cm, m)")


def _raw_extent(src: _Source) -> float | None:
    """How wide or tall the piece's boundary points are, in the file's units (None when they
    cannot tell: not finite, or too many to look at; the piece's reading says why)."""
    pts, count = [], 0
    for e in src.boundary:
        got = _polyline_vertices(e)
        if got is None:
            continue
        count += len(got[0])
        if count > MAX_POINTS:
            return None
        pts.extend(v[:2] for v in got[0])
    a = np.asarray(pts, dtype=float).reshape(-1, 2)
    a = a[np.isfinite(a).all(axis=1)]
    if len(a) < 2:
        return None
    with np.errstate(all="ignore"):
        ext = float(np.ptp(a, axis=0).max())
    return ext if math.isfinite(ext) else None


def _fit_units(sources: list[_Source], unit: str, how: str, path: str
               ) -> tuple[str, list[Note]]:
    """The units to read the pieces in. Pieces too small for a garment in the file's units (a
    size's largest under MIN_GARMENT_EXTENT) are read in the smallest larger unit of GUESSES
    that makes every size garment-sized (its largest piece MIN_GARMENT_EXTENT –
    MAX_PANEL_EXTENT), with a note; units given are not second-guessed, and pieces too large
    are refused as they are read (a 6 m² box is not a garment in any unit)."""
    largest: dict[str, float] = {}
    for s in sources:
        ext = _raw_extent(s)
        if ext is not None:
            largest[s.size] = max(largest.get(s.size, 0.0), ext)
    if not largest:
        return unit, []

    def span(u: str) -> tuple[float, float]:   # the smallest size's largest piece, the largest
        k = UNIT_SCALE[u]
        return min(largest.values()) * k, max(largest.values()) * k

    lo, hi = span(unit)
    if lo >= MIN_GARMENT_EXTENT or hi > MAX_PANEL_EXTENT:
        return unit, []
    fits = [u for u in GUESSES if UNIT_SCALE[u] > UNIT_SCALE[unit]
            and span(u)[0] >= MIN_GARMENT_EXTENT and span(u)[1] <= MAX_PANEL_EXTENT]
    small = min(largest, key=largest.get)
    which = f" (size {small})" if len(largest) > 1 else ""
    said = f"in {UNIT_NAMES[unit]}, as " + ("given" if how == "given" else f"{how} says")
    if how == "given" or not fits:
        raise InputError(
            f"{path}: the pieces are too small for a garment: the largest{which} is "
            f"{lo * 100:.3g} cm across {said} (a garment's largest piece is "
            f"{MIN_GARMENT_EXTENT * 100:g} cm – {MAX_PANEL_EXTENT:g} m)"
            + (" — are the units given right?" if how == "given" else
               "; no other unit makes every size garment-sized — are the units right? Give "
               "them (--units, or the upload's units)"))
    u = fits[0]
    lo2, hi2 = span(u)
    now = f"{lo2 * 100:.3g} cm" if hi2 - lo2 < 5e-4 else \
        f"{lo2 * 100:.3g}–{hi2 * 100:.3g} cm (by size)"
    return u, [Note("units", f"{how} means {UNIT_NAMES[unit]}, which makes the largest "
                             f"piece{which} {lo * 100:.3g} cm across: too small for a garment; "
                             f"read in {UNIT_NAMES[u]} instead, which makes the largest piece "
                             f"{now} across (give the units if that is wrong)",
                    data={"units": u, "stated": unit})]


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


# --- the pieces a file holds ---------------------------------------------------------------

@dataclass
class _Source:
    """A piece in one size as the file holds it, before its geometry is read; ``notes``: what
    reading it assumed or repaired."""
    name: str
    size: str
    block: str
    ents: list
    boundary: list
    texts: dict
    quantity: int
    flipped: int | None
    where: str
    sized: bool = True    # an AAMA piece (it names its size); False: a plain DXF's polyline
    notes: list[Note] = field(default_factory=list)

    def note(self, code: str, text: str, **data) -> None:
        self.notes.append(Note(code, text, self.name, self.size if self.sized else None, data))


def _aama_sources(msp, path: str, notes: list[Note]) -> list[_Source]:
    """A source per inserted block with a boundary (blocks without geometry or a piece name,
    such as a style's texts, are not pieces)."""
    out: list[_Source] = []
    seen: set[str] = set()
    for ins in msp.query("INSERT"):
        bname = ins.dxf.name
        if bname in seen:
            notes.append(Note("block-reused", f"block {bname!r} is inserted more than once; "
                                              "used once", data={"block": str(bname)}))
            continue
        seen.add(bname)
        try:
            ents = list(ins.virtual_entities())
        except Exception as exc:  # noqa: BLE001 - ezdxf raises many kinds on broken blocks
            raise InputError(f"{path}: block {bname!r} cannot be read ({exc})") from None
        texts = _texts(ents)
        # names as the garment format takes them: non-empty, no surrounding spaces, ≤ 200
        name = (texts.get("piece name") or "")[:200].strip() or str(bname)[:200].strip() \
            or f"piece-{len(out) + 1}"
        psize = (texts.get("size") or "")[:200].strip() or "one-size"
        where = f"{path}: piece {name!r} (size {psize})"
        boundary = _on_layer(ents, BOUNDARY)
        if not any(_polyline_vertices(e) for e in boundary):
            boundary = [e for e in ents if (g := _polyline_vertices(e)) and g[1]]
            if not boundary:
                if "piece name" not in texts:
                    continue   # a style-text block, or one without geometry
                raise InputError(f"{where}: no boundary (layer 1) and no closed polyline")
        qty, flipped = _quantity(texts.get("quantity"), where)
        out.append(_Source(name, psize, str(bname), ents, boundary, texts, qty, flipped, where))
    return out


def _plain_sources(msp, path: str) -> list[_Source]:
    """Plain DXF: a source per closed polyline in model space, on any layer."""
    out, counts = [], {}
    for e in msp:
        got = _polyline_vertices(e)
        if not got or not got[1]:
            continue
        layer = str(e.dxf.get("layer", "0"))
        counts[layer] = counts.get(layer, 0) + 1
        name = f"{layer}-{counts[layer]}"
        out.append(_Source(name, "one-size", "", [e], [e], {}, 1, None,
                           f"{path}: piece {name!r}", sized=False))
    return out


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
    cut (but see :func:`_sample_quantities`)."""
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


def _by_name(items) -> dict[str, list]:
    out: dict[str, list] = {}
    for it in items:
        out.setdefault(it.name, []).append(it)
    return out


def _sample_quantities(sources: list[_Source], notes: list[Note]) -> list[_Source]:
    """The sources to read. A piece whose every ``Quantity:`` text says 0 while another of its
    sizes has none (so cuts it once) is cut in those sizes too: several exports write
    'Quantity: 0' on the sample size's blocks only; it is read as 1, with a note. Other
    quantity-0 pieces are not cut: skipped, with a note."""
    out = []
    for name, group in _by_name(sources).items():
        stated = [s for s in group if "quantity" in s.texts]
        unstated = [s for s in group if "quantity" not in s.texts]
        mark = bool(unstated) and all(s.quantity == 0 for s in stated)
        for s in group:
            if s.quantity > 0:
                out.append(s)
            elif mark:
                s.quantity, s.flipped = 1, None
                s.note("sample-quantity",
                       f"'Quantity: {s.texts['quantity']}' read as 1, as in "
                       f"{_sizes_text([u.size for u in unstated])} (no 'Quantity:' text "
                       "there): an export's mark on its sample size, not 'do not cut'")
                out.append(s)
            else:
                notes.append(Note("not-cut", f"'Quantity: {s.texts.get('quantity')}': not cut, "
                                             "skipped", name, s.size if s.sized else None))
    order = {id(s): k for k, s in enumerate(sources)}
    return sorted(out, key=lambda s: order[id(s)])


def _size_notes(pieces: list[Piece], notes: list[Note]) -> None:
    """Notes on pieces in some sizes only (each size gets the pieces it has), and on pieces
    whose quantity differs between sizes (the garment cuts the first size's in all)."""
    sizes = list(dict.fromkeys(p.size for p in pieces))
    for name, group in _by_name(pieces).items():
        have = [p.size for p in group]
        missing = [s for s in sizes if s not in have]
        if missing:
            notes.append(Note("sizes", f"in {_sizes_text(have)} only (not in "
                                       f"{_sizes_text(missing)}): imported in those sizes",
                              name, data={"sizes": have, "missing": missing}))
        points = [len(p.segments) for p in group]
        if len(set(points)) > 1:
            said = ", ".join(f"{p.size}: {len(p.segments)}" for p in group)
            notes.append(Note("points-differ",
                              f"its outline has a different number of points in different "
                              f"sizes ({said}): a seam given by vertex numbers (the markup's, "
                              "the editor's) cannot be sewn in every size", name,
                              data={"points": dict(zip(have, points, strict=True))}))
        counts = [(p.quantity, p.flipped) for p in group]
        if len(set(counts)) > 1:
            said = ", ".join(f"{p.size}: {_qty_text(p.quantity, p.flipped)}" for p in group)
            notes.append(Note("quantity-differs",
                              f"the quantity differs between sizes ({said}): every size is "
                              f"cut {_qty_text(*counts[0])}, as size {group[0].size} says",
                              name, data={"quantity": counts[0][0]}))


def _sizes_text(sizes: list[str]) -> str:
    """'size M', 'sizes S, M, L', or for many '15 sizes (34, 36, … 62)'."""
    if len(sizes) == 1:
        return f"size {sizes[0]}"
    if len(sizes) > 6:
        return f"{len(sizes)} sizes ({sizes[0]}, {sizes[1]}, … {sizes[-1]})"
    return f"sizes {', '.join(sizes)}"


def _qty_text(quantity: int, flipped: int | None) -> str:
    return str(quantity) if flipped is None else f"{quantity - flipped},{flipped}"


def read_dxf(source, size: str | None = None, units: str | None = None
             ) -> tuple[list[Piece], list[dict]]:
    """Pieces of a pattern DXF (a path, bytes or a binary file object; all sizes, or only
    ``size``) and warnings: every repair and assumption made, as objects (``{"code",
    "message", "piece"?, "size"?, …}``, :class:`catwalk.exchange.dxf_repair.Note`); each
    piece's own are also on it (``Piece.notes``)."""
    data, path = read_source(source, "dxf", max_bytes=MAX_BYTES)
    doc, notes = _read_doc(data, path)
    msp = doc.modelspace()
    if len(msp) == 0:
        raise InputError(f"{path}: no pattern pieces found (model space is empty: an empty or "
                         f"truncated file)")
    unit, how = _units(doc, units, path)
    sources = _aama_sources(msp, path, notes) or _plain_sources(msp, path)
    unit, said = _fit_units(sources, unit, how, path)
    notes.extend(said)
    every = list(dict.fromkeys(s.size for s in sources if s.sized))
    sources = _sample_quantities(sources, notes)
    for gone in [s for s in every if s not in {src.size for src in sources}]:
        notes.append(Note("size-not-cut", f"size {gone}: every piece has quantity 0 (not "
                                          "cut): the size is not imported", size=gone))
    if len(sources) > MAX_PIECES:
        raise InputError(f"{path}: {len(sources):,} pieces; at most {MAX_PIECES:,} are read")
    if not sources:
        raise InputError(f"{path}: no pattern pieces found (no blocks with a layer-1 boundary and "
                         f"no closed polylines)" + (" to cut: every piece has quantity 0"
                                                     if any(n.code == "not-cut" for n in notes)
                                                     else ""))
    pieces = [_piece(s, UNIT_SCALE[unit]) for s in sources]
    seen: dict[tuple[str, str], str] = {}
    for p in pieces:
        key = (p.name, p.size)
        if key in seen:
            raise InputError(f"{path}: duplicate piece name {p.name!r} in size {p.size} "
                             f"(blocks {seen[key]!r} and {p.block!r})")
        seen[key] = p.block
    if size is not None:
        sizes = list(dict.fromkeys(p.size for p in pieces))
        pieces = [p for p in pieces if p.size == size]
        if not pieces:
            raise InputError(f"{path}: no piece in size {size!r} (sizes: {', '.join(sizes)})")
    notes.extend(n for s in sources for n in s.notes if s.size == size or size is None)
    _size_notes(pieces, notes)
    built = {name: {p.size for p in group} for name, group in _by_name(pieces).items()}
    for p in pieces:   # its own notes, those on every size, and those on sizes not read
        p.notes = [n for n in notes if n.piece == p.name
                   and (n.size is None or n.size == p.size or n.size not in built[p.name])]
    return pieces, [n.as_warning(path) for n in notes]


def _piece(src: _Source, scale: float) -> Piece:
    # chaining tolerance: 0.5 mm
    segs, origin = _outline(_loop_from(src, scale, tol=5e-4), src)
    ents, where = src.ents, src.where
    grain = _line_points(_on_layer(ents, GRAIN), scale, where, "the grain line")
    if grain is not None:
        grain = grain - origin
    bpts = flatten(segs, 1e-4).points
    notches = _notch_points(_on_layer(ents, NOTCH), scale, bpts + origin, where) - origin \
        if _on_layer(ents, NOTCH) else np.zeros((0, 2))
    mline = _line_points(_on_layer(ents, MIRROR), scale, where, "the mirror line")
    fold = None
    if mline is not None:
        mline = mline - origin
        fold = _find_fold(segs, mline, tol=5e-4)
    return Piece(src.name, src.size, src.quantity, segs, grain, notches.reshape(-1, 2), mline,
                 fold, src.block, src.texts, src.flipped)


def _outline(loop: list[tuple], src: _Source) -> tuple[list[Segment], np.ndarray]:
    """The boundary as counter-clockwise segments with its lower-left corner at the origin,
    and where that corner was: repeated points dropped, small self-crossing loops removed
    (each told in a note), a piece not garment-sized or without area refused."""
    where = src.where
    loop, repeats = drop_repeats(loop)
    if repeats:
        src.note("duplicate-points", f"{repeats} repeated boundary point(s) dropped (the same "
                                     f"point twice in a row, within {DUPLICATE * 1000:g} mm: "
                                     "an edge of no length)", count=repeats)
    if len(loop) < 3 and not any(abs(p[2]) > 0 for p in loop):
        raise InputError(f"{where}: boundary has fewer than 3 distinct points")
    pts = flatten(segments_of(loop), 1e-4).points
    ext = float(np.ptp(pts, axis=0).max())
    if ext > MAX_PANEL_EXTENT:
        raise InputError(f"{where}: the piece is {ext:.4g} m across (at most "
                         f"{MAX_PANEL_EXTENT:g} m): not garment-sized — are the units right "
                         "(the file's 'Units:' text or $INSUNITS, or give the units)?")
    if abs(polygon_area(pts)) < 1e-6:
        raise InputError(f"{where}: the boundary encloses no area")
    origin = pts.min(axis=0)
    loop = [(x - origin[0], y - origin[1], b) for x, y, b in loop]
    loop = remove_small_loops(loop, where, src.note)
    if len(loop) < 3 and not any(abs(p[2]) > 0 for p in loop):
        raise InputError(f"{where}: boundary has fewer than 3 distinct points")
    segs = segments_of(loop)
    pts = flatten(segs, 1e-4).points
    if polygon_area(pts) < 0:
        segs = reverse_segments(segs)
    shift = pts.min(axis=0)   # a loop removed at the corner moves it
    if np.any(shift != 0.0):
        for s in segs:
            s.start = s.start - shift
    return segs, origin + shift


# --- to a garment ---------------------------------------------------------------------------

def pieces_to_garment(pieces: list[Piece], name: str, source: dict | None = None) -> Garment:
    """A garment with one panel per piece name (the sizes it is in as shapes: a piece of some
    sizes only is a panel of those); quantity 2 adds a mirrored copy ``NAME (2)``, higher
    quantities alternate plain and mirrored copies (ASTM's ``N,M``: the copies after the first
    N are the mirrored ones). What reading a piece repaired or assumed (its notes) is kept on
    its panel, ``meta.import_warnings``."""
    sizes = []
    for p in pieces:
        if p.size not in sizes:
            sizes.append(p.size)
    by_name: dict[str, list[Piece]] = {}
    for p in pieces:
        by_name.setdefault(p.name, []).append(p)
    panels = []
    for pname, group in by_name.items():
        first = group[0]
        shapes = {p.size: Shape(_fold_at(p, first.fold), p.grain, p.notches) for p in group}
        meta = {"dxf_block": first.block, "quantity": first.quantity}
        if first.flipped is not None:
            meta["flipped"] = first.flipped
        if first.mirror_line is not None and first.fold is None:
            meta["mirror_line"] = [[round(float(x), 6) for x in pt] for pt in first.mirror_line]
        told = [n.on_panel() for p in group for n in p.notes]
        if told:
            meta["import_warnings"] = [w for k, w in enumerate(told) if w not in told[:k]]
        panels.append(Panel(pname, "other", shapes, fold=first.fold, meta=meta))
        plain = first.quantity - (first.flipped or 0)
        for k in range(2, first.quantity + 1):
            # AAMA: alternate (a pair is a left and a right); ASTM N,M: N as drawn, M mirrored
            mirror = k % 2 == 0 if first.flipped is None else k > plain
            panels.append(Panel(f"{pname} ({k})", "other", copy_of=pname, mirror=mirror))
    return Garment(name, "other", sizes, panels, [], "cotton-jersey", source=source or {})


def _fold_at(p: Piece, fold: int | None) -> list[Segment]:
    """The piece's outline (a copy), its vertices renumbered to start elsewhere when that puts
    its fold on edge ``fold``: a panel has one fold edge for all its sizes, and a size whose
    loop starts at another corner has it elsewhere."""
    segs = [s.copy() for s in p.segments]
    if fold is None or p.fold is None or p.fold == fold or fold >= len(segs):
        return segs
    r = (p.fold - fold) % len(segs)
    return segs[r:] + segs[:r]


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
        if p.copy_of is None and len({len(sh.outline) for sh in p.shapes.values()}) == 1:
            per = [[seg.pieces(sh.outline[(i + 1) % len(sh.outline)].start, tolerance)
                    for i, seg in enumerate(sh.outline)] for sh in p.shapes.values()]
            chords[p.name] = np.max(np.array(per), axis=0)
    x = 0.0
    blocks = 0
    for size in g.sizes:
        for p in g.panels:
            if p.copy_of is not None or size not in p.shapes:
                continue   # a copy adds to its source's quantity; a panel of other sizes
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
