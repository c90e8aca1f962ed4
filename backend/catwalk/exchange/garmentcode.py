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
part, front/back).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from catwalk.errors import InputError
from catwalk.exchange.source import read_json
from catwalk.garment.geometry import Segment, run_length, segment_lengths
from catwalk.garment.model import Garment, Panel, Placement, Seam, SeamSide, Shape


def euler_xyz(deg) -> np.ndarray:
    """GarmentCode's rotation: R = Rz(γ)·Ry(β)·Rx(α), angles in degrees."""
    a, b, c = (math.radians(float(x)) for x in deg)
    rx = np.array([[1, 0, 0], [0, math.cos(a), -math.sin(a)], [0, math.sin(a), math.cos(a)]])
    ry = np.array([[math.cos(b), 0, math.sin(b)], [0, 1, 0], [-math.sin(b), 0, math.cos(b)]])
    rz = np.array([[math.cos(c), -math.sin(c), 0], [math.sin(c), math.cos(c), 0], [0, 0, 1]])
    return rz @ ry @ rx


def _rel_to_abs(p0: np.ndarray, p1: np.ndarray, rel) -> np.ndarray:
    e = p1 - p0
    return p0 + float(rel[0]) * e + float(rel[1]) * np.array([-e[1], e[0]])


def _segment(p0, p1, curv, where: str) -> Segment:
    if not curv:
        return Segment("line", p0)
    kind = curv.get("type")
    params = curv.get("params", [])
    try:
        if kind == "quadratic":
            return Segment("quadratic", p0, [_rel_to_abs(p0, p1, params[0])])
        if kind == "cubic":
            return Segment("cubic", p0, [_rel_to_abs(p0, p1, params[0]),
                                          _rel_to_abs(p0, p1, params[1])])
        if kind == "circle":
            radius, large, right = float(params[0]), bool(params[1]), bool(params[2])
            chord = float(np.linalg.norm(p1 - p0))
            half = math.asin(min(1.0, chord / (2.0 * radius)))
            theta = 2.0 * half if not large else 2.0 * math.pi - 2.0 * half
            bulge = math.tan(theta / 4.0) * (1.0 if right else -1.0)
            return Segment("arc", p0, bulge=bulge)
    except (IndexError, TypeError, ValueError, ZeroDivisionError):
        raise InputError(f"{where}: curvature {curv!r} cannot be read") from None
    raise InputError(f"{where}: unknown curvature type {kind!r}")


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
    elif ptype == "skirt":
        part = "legs"
    else:
        part = "torso"
    side = "front" if z >= 0 else "back"
    return Placement(part=part, side=side, wrap=part != "torso" or True)


def garmentcode_to_garment(spec: dict, name: str = "garmentcode", garment_type: str | None = None,
                           size: str = "M", where: str = "spec") -> Garment:
    try:
        pattern = spec["pattern"]
        raw_panels = pattern["panels"]
        stitches = pattern.get("stitches", [])
    except (KeyError, TypeError):
        raise InputError(f"{where}: not a GarmentCode specification (no pattern.panels)") from None
    props = spec.get("properties", {})
    if props.get("curvature_coords", "relative") != "relative":
        raise InputError(f"{where}: only curvature_coords \"relative\" is supported")
    units = float(props.get("units_in_meter", 100))
    scale = 1.0 / units
    order = pattern.get("panel_order") or list(raw_panels)
    panels: list[Panel] = []
    world: dict[str, tuple[np.ndarray, np.ndarray]] = {}
    edge_vertex: dict[str, list[int]] = {}
    for pname in order:
        rp = raw_panels[pname]
        w = f"{where}: panel {pname!r}"
        try:
            verts = np.asarray(rp["vertices"], dtype=float) * scale
            edges = rp["edges"]
        except (KeyError, TypeError, ValueError):
            raise InputError(f"{w}: needs vertices and edges") from None
        segs = []
        starts = []
        for k, e in enumerate(edges):
            i, j = e["endpoints"]
            nxt = edges[(k + 1) % len(edges)]["endpoints"][0]
            if j != nxt:
                raise InputError(f"{w}, edge {k}: ends at vertex {j} but edge "
                                 f"{(k + 1) % len(edges)} starts at vertex {nxt} (the edges do "
                                 f"not form a loop)")
            segs.append(_segment(verts[i], verts[j], e.get("curvature"), f"{w}, edge {k}"))
            starts.append(i)
        edge_vertex[pname] = starts
        rot = euler_xyz(rp.get("rotation", [0, 0, 0]))
        trans = np.asarray(rp.get("translation", [0, 0, 0]), dtype=float) * scale
        world[pname] = (rot, trans)
        centre = rot @ np.append(verts.mean(axis=0), 0.0) + trans
        ptype = _panel_type(pname, rp.get("label"))
        pl = _hints(pname, ptype, centre)
        pl.transform = {"rotation": [[round(float(v), 9) for v in row] for row in rot],
                        "translation": [round(float(v), 6) for v in trans],
                        "reference": "GarmentCode average body (SMPL, metres)"}
        labels = {k: str(e["label"]) for k, e in enumerate(edges) if e.get("label")}
        panels.append(Panel(pname, ptype, {size: Shape(segs, np.array([[0.0, 0.0], [0.0, 1.0]]),
                                                       labels=labels)},
                            placement=pl, meta={"garmentcode_label": rp.get("label")}))
    seams = []
    for i, st in enumerate(stitches):
        try:
            (a, b) = st[:2]
            pa, ea, pb, eb = a["panel"], int(a["edge"]), b["panel"], int(b["edge"])
        except (KeyError, TypeError, ValueError):
            raise InputError(f"{where}: stitch {i} is not a pair of {{panel, edge}}") from None
        sides = []
        ends3d = []
        for p, e in ((pa, ea), (pb, eb)):
            if p not in raw_panels:
                raise InputError(f"{where}: stitch {i} names no panel {p!r}")
            n = len(edge_vertex[p])
            if not 0 <= e < n:
                raise InputError(f"{where}: stitch {i}: panel {p!r} has no edge {e}")
            sides.append(SeamSide(p, e, (e + 1) % n))
            rot, trans = world[p]
            shape = next(q for q in panels if q.name == p).shapes[size]
            v0, v1 = shape.outline[e].start, shape.outline[(e + 1) % n].start
            ends3d.append([rot @ np.append(v, 0.0) + trans for v in (v0, v1)])
        (a0, a1), (b0, b1) = ends3d
        same = np.linalg.norm(a0 - b0) + np.linalg.norm(a1 - b1)
        cross = np.linalg.norm(a0 - b1) + np.linalg.norm(a1 - b0)
        kind = "dart" if pa == pb else "seam"
        seam = Seam(sides[0], sides[1], bool(cross < same), f"{pa}:{ea}-{pb}:{eb}", kind)
        # GarmentCode gathers (or eases) the longer side of a mismatched stitch: declare it
        la, lb = (run_length(segment_lengths(next(q for q in panels if q.name == sd.panel)
                                             .shapes[size].outline), sd.start, sd.end)
                  for sd in sides)
        diff = abs(la - lb) / max(la, lb)
        if diff > 0.02:
            seam.ease = math.ceil(diff * 100.0 + 1.0) / 100.0
            seam.kind = "gather" if diff > 0.1 else "eased"
        seams.append(seam)
    if garment_type is None:
        types = {p.type for p in panels}
        if "skirt" in types and types & {"front", "back"}:
            garment_type = "dress"
        elif "skirt" in types:
            garment_type = "skirt"
        elif "sleeve" in types:
            garment_type = "shirt"
        elif "leg" in types:
            garment_type = "trousers"
        else:
            garment_type = "top"
    return Garment(name, garment_type, [size], panels, seams, "cotton-jersey", size,
                   source={"garmentcode": where, "licence": "MIT (c) 2024 Maria Korosteleva",
                           "converter": "catwalk garment from-garmentcode"})


def load_garmentcode(source, name: str | None = None, garment_type: str | None = None,
                     size: str = "M") -> Garment:
    """A GarmentCode specification (a path, bytes or a binary file object) as a garment."""
    spec, where = read_json(source, "garmentcode")
    where = Path(where).name
    stem = Path(where).stem.replace("_specification", "")
    return garmentcode_to_garment(spec, name or stem, garment_type, size, where=where)
