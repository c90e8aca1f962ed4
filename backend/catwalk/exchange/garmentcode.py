"""GarmentCode pattern specifications → our garment format.

GarmentCode (Korosteleva & Sorkine-Hornung 2023, MIT) writes a ``*_specification.json``:
``pattern.panels`` maps a panel name to ``vertices`` (2D, in ``properties.units_in_meter``:
100 = centimetres), ``edges`` (a loop; ``endpoints`` [i, j] and an optional ``curvature``),
``translation`` and ``rotation`` (Euler XYZ in degrees, R = Rz·Ry·Rx) placing the panel in 3D
(world: +Y up, the body faces +Z, +X the body's left — the same axes as ours); and
``pattern.stitches``: pairs of ``{"panel", "edge"}`` sewn together.

With ``curvature_coords: relative`` a curve's control point [t, k] is
``start + t·(end − start) + k·perp(end − start)`` with ``perp(x, y) = (−y, x)``. Curvature
types: ``quadratic`` (one control point), ``cubic`` (two), ``circle`` (``[radius, large_arc,
right]``: an arc that bulges to the right of the edge's direction when ``right``).

Conversion: vertex ``i`` of our outline is the start of GarmentCode edge ``i``, so a stitch on
edge ``k`` is the run from vertex ``k`` to vertex ``k + 1``; the stitch direction (which ends
meet) is taken from the 3D placement: the pairing whose endpoints lie closer together in 3D.
A stitch whose sides differ in length by more than 2 % (GarmentCode gathers the longer side)
gets ``ease`` = the difference rounded up plus 1 % and kind ``gather`` (> 10 %) or ``eased``.
The 3D placement is kept in each panel's ``placement.transform`` and turned into hints (body
part, front/back; a cuff is on the limb of the panel it is sewn to, a waistband on the legs).
That placement was made for GarmentCode's body: :func:`catwalk.garment.place.place_panels` keeps
of it only where a torso or skirt panel sits across the body, and, for a sleeve's or trouser
leg's halves (and their cuffs), which pattern direction runs along the limb and which edge is
the outer seam; the panels are then hung from our body's landmarks and wrapped round its limbs.
Without a type given, a garment with trouser legs and a bodice is a ``jumpsuit``.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from catwalk.errors import InputError
from catwalk.exchange.source import read_json
from catwalk.garment.geometry import Segment, run_length, segment_lengths
from catwalk.garment.model import GARMENT_TYPES, Garment, Panel, Placement, Seam, SeamSide, Shape


def euler_xyz(deg) -> np.ndarray:
    """GarmentCode's rotation: R = Rz(γ)·Ry(β)·Rx(α), angles in degrees."""
    a, b, c = (math.radians(float(x)) for x in deg)
    rx = np.array([[1, 0, 0], [0, math.cos(a), -math.sin(a)], [0, math.sin(a), math.cos(a)]])
    ry = np.array([[math.cos(b), 0, math.sin(b)], [0, 1, 0], [-math.sin(b), 0, math.cos(b)]])
    rz = np.array([[math.cos(c), -math.sin(c), 0], [math.sin(c), math.cos(c), 0], [0, 0, 1]])
    return rz @ ry @ rx


MAX_PANELS = 200
MAX_EDGES = 1000       # per panel
MAX_STITCHES = 5000
MAX_METRES = 100.0     # no coordinate of a garment (or its placement) is farther than this


def _number(v, where: str) -> float:
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
        raise InputError(f"{where}: expected a finite number, got {v!r:.60}")
    return float(v)


def _numbers(v, n: int, where: str) -> list[float]:
    if not isinstance(v, list) or len(v) != n:
        raise InputError(f"{where}: expected {n} numbers, got {v!r:.60}")
    return [_number(x, where) for x in v]


def _near(p: np.ndarray, where: str) -> np.ndarray:
    """A point (or points) in metres, checked to lie within :data:`MAX_METRES`."""
    if not np.all(np.isfinite(p)) or np.abs(p).max(initial=0.0) > MAX_METRES:
        raise InputError(f"{where}: lies more than {MAX_METRES:g} m away: not a garment "
                         "(are properties.units_in_meter right?)")
    return p


def _rel_to_abs(p0: np.ndarray, p1: np.ndarray, rel, where: str) -> np.ndarray:
    t, k = _numbers(rel, 2, f"{where}: control point [t, k]")
    e = p1 - p0
    return _near(p0 + t * e + k * np.array([-e[1], e[0]]), f"{where}: control point")


def _segment(p0, p1, curv, where: str) -> Segment:
    if not curv:
        return Segment("line", p0)
    if not isinstance(curv, dict):
        raise InputError(f"{where}: curvature must be an object with type and params, got "
                         f"{curv!r:.60}")
    kind = curv.get("type")
    params = curv.get("params", [])
    if not isinstance(params, list):
        raise InputError(f"{where}: curvature params must be a list, got {params!r:.60}")
    need = {"quadratic": 1, "cubic": 2, "circle": 3}.get(kind) if isinstance(kind, str) else None
    if need is None:
        raise InputError(f"{where}: unknown curvature type {kind!r:.60} (quadratic, cubic, "
                         "circle)")
    if len(params) < need:
        raise InputError(f"{where}: a {kind} curvature needs {need} params, got {len(params)}")
    if kind == "quadratic":
        return Segment("quadratic", p0, [_rel_to_abs(p0, p1, params[0], where)])
    if kind == "cubic":
        return Segment("cubic", p0, [_rel_to_abs(p0, p1, params[0], where),
                                      _rel_to_abs(p0, p1, params[1], where)])
    radius = _number(params[0], f"{where}: circle radius")
    if radius <= 0:
        raise InputError(f"{where}: circle radius must be positive, got {radius:g}")
    large, right = bool(params[1]), bool(params[2])
    chord = float(np.linalg.norm(p1 - p0))
    half = math.asin(min(1.0, chord / (2.0 * radius)))
    theta = 2.0 * half if not large else 2.0 * math.pi - 2.0 * half
    bulge = math.tan(theta / 4.0) * (1.0 if right else -1.0)
    return Segment("arc", p0, bulge=bulge)


def _panel_type(name: str, label) -> str:
    n = name.lower()
    if "sleeve" in n:
        return "sleeve"
    if "collar" in n:
        return "collar"
    if "cuff" in n:
        return "cuff"
    if "wb" in n or "waistband" in n:
        return "waistband"
    if "skirt" in n:
        return "skirt"
    if "pant" in n or "leg" in n:
        return "leg"
    if "ftorso" in n or "front" in n:
        return "front"
    if "btorso" in n or "back" in n:
        return "back"
    return "other"


def _hints(name: str, ptype: str, centre3d: np.ndarray) -> Placement:
    x, _, z = centre3d
    if ptype == "sleeve" or abs(x) > 0.3:
        part = "left_arm" if x > 0 else "right_arm"
    elif ptype == "leg":
        part = "left_leg" if x > 0 else "right_leg"
    elif ptype in ("skirt", "waistband"):   # (a waistband hangs at the waist, not the neck)
        part = "legs"
    else:
        part = "torso"
    side = "front" if z >= 0 else "back"
    return Placement(part=part, side=side, wrap=True)


def _limb_parts_of_cuffs(panels: list[Panel], seams: list[Seam]) -> None:
    """A cuff is on the limb of the sleeve or trouser leg it is sewn to (a trouser cuff lies
    within the torso's width, where :func:`_hints` alone would put it on the torso)."""
    part = {p.name: p.placement.part for p in panels}
    for p in panels:
        if p.type != "cuff":
            continue
        for s in seams:
            other = s.b.panel if s.a.panel == p.name else s.a.panel if s.b.panel == p.name \
                else None
            if other is not None and part[other] in ("left_arm", "right_arm", "left_leg",
                                                      "right_leg"):
                p.placement.part = part[other]
                break


def _check_names(name: str, garment_type: str | None, size: str) -> None:
    if garment_type is not None and (not isinstance(garment_type, str)
                                     or garment_type not in GARMENT_TYPES):
        raise InputError(f"garment type {garment_type!r} is not one of "
                         f"{', '.join(GARMENT_TYPES)}", "type")
    if not isinstance(size, str) or not size.strip() or size != size.strip():
        raise InputError(f"size {size!r}: a size is a non-empty name without surrounding "
                         "spaces (e.g. M)", "size")
    if not isinstance(name, str) or not name.strip():
        raise InputError(f"name {name!r}: a garment needs a name", "name")


def _pattern(spec: dict, where: str) -> tuple[dict, list, float, list[str]]:
    """The specification's panels, stitches, scale to metres and panel order, checked."""
    pattern = spec.get("pattern") if isinstance(spec, dict) else None
    if not isinstance(pattern, dict) or "panels" not in pattern:
        raise InputError(f"{where}: not a GarmentCode specification (no pattern.panels)")
    raw_panels = pattern["panels"]
    if not isinstance(raw_panels, dict):
        raise InputError(f"{where}: pattern.panels must be an object mapping panel names to "
                         f"panels, got {type(raw_panels).__name__}")
    if not raw_panels:
        raise InputError(f"{where}: pattern.panels is empty: a garment needs panels")
    if len(raw_panels) > MAX_PANELS:
        raise InputError(f"{where}: {len(raw_panels):,} panels; at most {MAX_PANELS} are read")
    stitches = pattern.get("stitches", [])
    if not isinstance(stitches, list):
        raise InputError(f"{where}: pattern.stitches must be a list of stitches")
    if len(stitches) > MAX_STITCHES:
        raise InputError(f"{where}: {len(stitches):,} stitches; at most {MAX_STITCHES} are read")
    props = spec.get("properties", {})
    if not isinstance(props, dict):
        raise InputError(f"{where}: properties must be an object")
    if props.get("curvature_coords", "relative") != "relative":
        raise InputError(f"{where}: only curvature_coords \"relative\" is supported")
    units = props.get("units_in_meter", 100)
    if isinstance(units, bool) or not isinstance(units, (int, float)) \
            or not math.isfinite(units) or units <= 0:
        raise InputError(f"{where}: properties.units_in_meter must be a positive number (100: "
                         f"the pattern is in centimetres), got {units!r}")
    order = pattern.get("panel_order") or list(raw_panels)
    if not isinstance(order, list) or not all(isinstance(p, str) and p in raw_panels
                                              for p in order) or len(set(order)) != len(order):
        raise InputError(f"{where}: pattern.panel_order must list the panels' names, each once")
    order += [p for p in raw_panels if p not in order]
    return raw_panels, stitches, 1.0 / units, order


def _edge_ends(edges: list, n_verts: int, w: str) -> list:
    """Each edge's two vertex numbers, checked to form one loop."""
    if len(edges) < 3:
        raise InputError(f"{w}: needs at least 3 edges, has {len(edges)}")
    if len(edges) > MAX_EDGES:
        raise InputError(f"{w}: {len(edges):,} edges; at most {MAX_EDGES} are read")
    ends = []
    for k, e in enumerate(edges):
        ep = e.get("endpoints") if isinstance(e, dict) else None
        if not isinstance(ep, list) or len(ep) != 2 or not all(
                isinstance(x, int) and not isinstance(x, bool) and 0 <= x < n_verts
                for x in ep):
            raise InputError(f"{w}, edge {k}: endpoints must be two vertex numbers "
                             f"0…{n_verts - 1}, got {ep!r:.60}")
        ends.append(ep)
    for k in range(len(edges)):
        j, nxt = ends[k][1], ends[(k + 1) % len(edges)][0]
        if j != nxt:
            raise InputError(f"{w}, edge {k}: ends at vertex {j} but edge "
                             f"{(k + 1) % len(edges)} starts at vertex {nxt} (the edges do "
                             f"not form a loop)")
    return ends


def _panel(pname: str, rp, scale: float, size: str, where: str):
    """A panel of the specification: (the :class:`Panel`, its placement (rotation,
    translation) in the specification's world)."""
    w = f"{where}: panel {pname!r}"
    if not isinstance(rp, dict) or not isinstance(rp.get("vertices"), list) \
            or not isinstance(rp.get("edges"), list):
        raise InputError(f"{w}: needs vertices and edges")
    verts = _near(np.array([_numbers(v, 2, f"{w}, vertex {k}")
                            for k, v in enumerate(rp["vertices"])],
                           dtype=float).reshape(-1, 2) * scale, f"{w}: a vertex")
    edges = rp["edges"]
    ends = _edge_ends(edges, len(verts), w)
    segs = [_segment(verts[i], verts[j], e.get("curvature"), f"{w}, edge {k}")
            for k, (e, (i, j)) in enumerate(zip(edges, ends, strict=True))]
    rot = euler_xyz(_numbers(rp.get("rotation", [0, 0, 0]), 3, f"{w}: rotation"))
    trans = _near(np.asarray(_numbers(rp.get("translation", [0, 0, 0]), 3,
                                      f"{w}: translation")) * scale, f"{w}: translation")
    centre = rot @ np.append(verts.mean(axis=0), 0.0) + trans
    ptype = _panel_type(pname, rp.get("label"))
    pl = _hints(pname, ptype, centre)
    pl.transform = {"rotation": [[round(float(v), 9) for v in row] for row in rot],
                    "translation": [round(float(v), 6) for v in trans],
                    "reference": "GarmentCode average body (SMPL, metres)"}
    labels = {k: str(e["label"])[:200] for k, e in enumerate(edges) if e.get("label")}
    label = rp.get("label")
    panel = Panel(pname, ptype, {size: Shape(segs, np.array([[0.0, 0.0], [0.0, 1.0]]),
                                             labels=labels)},
                  placement=pl, meta={"garmentcode_label": label if isinstance(
                      label, (str, int, float, type(None))) else str(label)[:200]})
    return panel, (rot, trans)


def _seam(i: int, st, panels: dict, world: dict, size: str, where: str) -> Seam:
    """Stitch ``i`` as a seam (a dart within one panel), its direction from where its edges
    lie in the specification's world; the longer side of a mismatched stitch gathered or
    eased, as GarmentCode does."""
    if not isinstance(st, list) or len(st) < 2 or not all(
            isinstance(x, dict) and isinstance(x.get("panel"), str)
            and isinstance(x.get("edge"), int) and not isinstance(x.get("edge"), bool)
            for x in st[:2]):
        raise InputError(f"{where}: stitch {i} is not a pair of {{panel, edge}}")
    (a, b) = st[:2]
    pa, ea, pb, eb = a["panel"], a["edge"], b["panel"], b["edge"]
    sides = []
    ends3d = []
    for p, e in ((pa, ea), (pb, eb)):
        if p not in panels:
            raise InputError(f"{where}: stitch {i} names no panel {p!r}")
        outline = panels[p].shapes[size].outline
        n = len(outline)
        if not 0 <= e < n:
            raise InputError(f"{where}: stitch {i}: panel {p!r} has no edge {e}")
        sides.append(SeamSide(p, e, (e + 1) % n))
        rot, trans = world[p]
        v0, v1 = outline[e].start, outline[(e + 1) % n].start
        ends3d.append([rot @ np.append(v, 0.0) + trans for v in (v0, v1)])
    (a0, a1), (b0, b1) = ends3d
    same = np.linalg.norm(a0 - b0) + np.linalg.norm(a1 - b1)
    cross = np.linalg.norm(a0 - b1) + np.linalg.norm(a1 - b0)
    kind = "dart" if pa == pb else "seam"
    seam = Seam(sides[0], sides[1], bool(cross < same), f"{pa}:{ea}-{pb}:{eb}", kind)
    la, lb = (run_length(segment_lengths(panels[sd.panel].shapes[size].outline), sd.start,
                         sd.end) for sd in sides)
    diff = abs(la - lb) / max(la, lb) if max(la, lb) > 0 else 0.0
    if diff > 0.02:
        seam.ease = min(0.99, math.ceil(diff * 100.0 + 1.0) / 100.0)
        seam.kind = "gather" if diff > 0.1 else "eased"
    return seam


def _garment_type(panels: list[Panel]) -> str:
    """The garment's type from its panels' types."""
    types = {p.type for p in panels}
    if "skirt" in types and types & {"front", "back"}:
        return "dress"
    if "skirt" in types:
        return "skirt"
    if "leg" in types and types & {"front", "back"}:
        return "jumpsuit"
    if "sleeve" in types:
        return "shirt"
    if "leg" in types:
        return "trousers"
    return "top"


def garmentcode_to_garment(spec: dict, name: str = "garmentcode", garment_type: str | None = None,
                           size: str = "M", where: str = "spec") -> Garment:
    _check_names(name, garment_type, size)
    raw_panels, stitches, scale, order = _pattern(spec, where)
    panels: list[Panel] = []
    world: dict[str, tuple[np.ndarray, np.ndarray]] = {}
    for pname in order:
        panel, world[pname] = _panel(pname, raw_panels[pname], scale, size, where)
        panels.append(panel)
    by_name = {p.name: p for p in panels}
    seams = [_seam(i, st, by_name, world, size, where) for i, st in enumerate(stitches)]
    _limb_parts_of_cuffs(panels, seams)
    return Garment(name, garment_type or _garment_type(panels), [size], panels, seams,
                   "cotton-jersey", size,
                   source={"garmentcode": where, "licence": "MIT (c) 2024 Maria Korosteleva",
                           "converter": "catwalk garment from-garmentcode"})


def load_garmentcode(source, name: str | None = None, garment_type: str | None = None,
                     size: str = "M") -> Garment:
    """A GarmentCode specification (a path, bytes or a binary file object) as a garment."""
    spec, where = read_json(source, "garmentcode")
    where = Path(where).name
    stem = Path(where).stem.replace("_specification", "")
    return garmentcode_to_garment(spec, name or stem, garment_type, size, where=where)
