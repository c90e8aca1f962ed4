"""Markup: what a pattern file lacks (panel types, seams, fabric, textures, placement).

A markup file is JSON (``docs/garment-format.md``, "Markup")::

    {
      "name": "Basic dress", "type": "dress", "fabric": "cotton-jersey", "default_size": "M",
      "panels": {
        "FRONT":  {"name": "front", "type": "front", "placement": {"part": "torso",
                   "side": "front", "anchor": "bust"}, "texture": {"image": "front.png"}},
        "SLEEVE": {"name": "sleeve_left", "type": "sleeve",
                   "copies": [{"name": "sleeve_right", "mirror": true}]}
      },
      "seams": [
        {"name": "side left", "a": {"panel": "front", "start": 1, "end": 2},
         "b": {"panel": "back", "start": {"point": [0.0, 0.0]}, "end": {"notch": 3}},
         "reverse": true}
      ]
    }

Keys of ``panels`` are the pattern's piece names; ``name`` renames the panel; ``split`` inserts
vertices where a seam must end but the pattern has none: ``{"from": v, "length": L}`` puts a
vertex at arc length L (metres, or the length of a run ``{"panel", "start", "end"}`` of another
piece in the same size) forward from vertex v — later vertices shift up by one. Seam sides name
panels by their new or their original name; ``start`` / ``end`` are outline vertex numbers, or
``{"point": [x, y]}`` (metres in the imported panel's coordinates: the nearest vertex, within
5 mm) or ``{"notch": k}`` (the vertex nearest the k-th notch). Points and notches are resolved
in the first size the piece is cut in; graded pieces keep their vertex numbers across sizes.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from catwalk.errors import InputError
from catwalk.exchange.garment_json import (
    _bool,
    _int,
    _list,
    _num,
    _obj,
    _placement,
    _pt,
    _str,
    check_name,
    garment_from_dict,
    garment_to_dict,
)
from catwalk.exchange.source import read_json
from catwalk.garment.geometry import run_length, segment_lengths, split_at_length
from catwalk.garment.model import GARMENT_TYPES, PANEL_TYPES, Garment, Panel, Seam, SeamSide

#: splits of one piece: a markup splits a piece where a seam ends off its vertices (a dart, a
#: notch), a few times at most; thousands took minutes
MAX_SPLITS = 50

SNAP = 5e-3   # metres


def load_markup(source) -> dict:
    """A markup document (a path, bytes or a binary file object)."""
    if isinstance(source, (str, Path)) and not Path(source).is_file():
        raise InputError(f"{source}: no such markup file")
    data, path = read_json(source, "markup")
    if not isinstance(data, dict):
        raise InputError(f"{path}: markup must be a JSON object")
    return data


def apply_markup(g: Garment, markup: dict, where: str = "markup") -> Garment:
    """Apply ``markup`` to ``g`` (in place) and return it."""
    _obj(markup, where, "a markup object")
    for key in ("name", "description"):
        if key in markup:
            setattr(g, key, _str(markup[key], f"{where}: {key}"))
    _obj(markup, where, "a markup object")
    if "type" in markup:
        if markup["type"] not in GARMENT_TYPES:
            raise InputError(f"{where}: garment type {markup['type']!r} is not one of "
                             f"{', '.join(GARMENT_TYPES)}")
        g.type = markup["type"]
    if "fabric" in markup:
        if not isinstance(markup["fabric"], (str, dict)):
            raise InputError(f"{where}: fabric is a preset name or a custom fabric object")
        g.fabric = markup["fabric"]
    if "default_size" in markup:
        if markup["default_size"] not in g.sizes:
            raise InputError(f"{where}: default_size {markup['default_size']!r} is not one of "
                             f"the pattern's sizes ({', '.join(g.sizes)})")
        g.default_size = markup["default_size"]
    if "fit" in markup:
        fit = _obj(markup["fit"], f"{where}: fit", "an object mapping sizes to sample bodies")
        for size, sample in fit.items():
            if size not in g.sizes or not isinstance(sample, str):
                raise InputError(f"{where}: fit maps the pattern's sizes ({', '.join(g.sizes)})"
                                 f" to sample-body names (bodies/recipes.json), got {size!r}")
        g.fit = dict(fit)
    pieces = {p.name: p for p in g.panels if p.copy_of is None}
    renames: dict[str, str] = {}
    raw_panels = markup.get("panels", {})
    if not isinstance(raw_panels, dict):
        raise InputError(f"{where}: \"panels\" maps piece names to panel markup")
    for pname, pm in raw_panels.items():
        w = f"{where}: panel {pname!r}"
        if pname not in pieces:
            raise InputError(f"{w}: unknown panel, not a piece of the pattern (pieces: "
                             f"{', '.join(sorted(pieces))})")
        if not isinstance(pm, dict):
            raise InputError(f"{w}: panel markup must be an object")
        p = pieces[pname]
        if "type" in pm:
            if pm["type"] not in PANEL_TYPES:
                raise InputError(f"{w}: panel type {pm['type']!r} is not one of "
                                 f"{', '.join(PANEL_TYPES)}")
            p.type = pm["type"]
        if "fabric" in pm:
            if not isinstance(pm["fabric"], (str, dict)):
                raise InputError(f"{w}: fabric is a preset name or a custom fabric object")
            p.fabric = pm["fabric"]
        if "texture" in pm:
            p.texture = _texture(pm["texture"], w)
        if "placement" in pm:
            p.placement = _placement(pm["placement"], w)
        if "fold" in pm:
            p.fold = None if pm["fold"] is None else _int(pm["fold"], f"{w}: fold")
        if "name" in pm:
            renames[pname] = check_name(pm["name"], w, "name")
        splits = _list(pm.get("split", []), f"{w}: split")
        if len(splits) > MAX_SPLITS:
            raise InputError(f"{w}: {len(splits):,} splits; a piece is split at most "
                             f"{MAX_SPLITS} times")
        for j, sp in enumerate(splits):
            _split(g, p, sp, f"{w}, split {j}")
        if "copies" in pm:
            g.panels = [q for q in g.panels if q.copy_of != pname]
            at = g.panels.index(p) + 1
            for j, c in enumerate(_list(pm["copies"], f"{w}: copies")):
                wc = f"{w}, copy {j}"
                if not isinstance(c, dict) or "name" not in c:
                    raise InputError(f"{wc}: needs a name")
                check_name(c["name"], wc, "name")
                ctype = c.get("type", p.type)
                if ctype not in PANEL_TYPES:
                    raise InputError(f"{wc}: panel type {ctype!r} is not one of "
                                     f"{', '.join(PANEL_TYPES)}")
                fabric = c.get("fabric", p.fabric)
                if fabric is not None and not isinstance(fabric, (str, dict)):
                    raise InputError(f"{wc}: fabric is a preset name or a custom fabric object")
                q = Panel(c["name"], ctype, copy_of=pname,
                          mirror=_bool(c.get("mirror", True), f"{wc}: mirror"),
                          texture=_texture(c["texture"], wc) if "texture" in c else p.texture,
                          fabric=fabric, placement=_placement(c.get("placement"), wc))
                g.panels.insert(at + j, q)
    for old, new in renames.items():
        for q in g.panels:
            if q.name == old:
                q.name = new
            if q.copy_of == old:
                q.copy_of = new
    names = [q.name for q in g.panels]
    dup = {n for n in names if names.count(n) > 1}
    if dup:
        raise InputError(f"{where}: two panels would be named {', '.join(sorted(dup))}")
    g.seams = []
    for i, rs in enumerate(_list(markup.get("seams", []), f"{where}: seams")):
        w = f"{where}: seam {i}" + (f" ({rs.get('name')!r})" if isinstance(rs, dict)
                                    and rs.get("name") else "")
        if not isinstance(rs, dict) or "a" not in rs or "b" not in rs:
            raise InputError(f"{w}: a seam is {{\"a\": side, \"b\": side, \"reverse\": bool}}")
        sides = []
        for lab in ("a", "b"):
            sides.append(_side(g, rs[lab], renames, f"{w}, side {lab}"))
        ease = _num(rs.get("ease", 0.0), f"{w}: ease", 0.0)
        if ease >= 1.0:
            raise InputError(f"{w}: ease is a fraction in [0, 1), got {ease!r}")
        g.seams.append(Seam(sides[0], sides[1], _bool(rs.get("reverse", False), f"{w}: reverse"),
                            _str(rs.get("name", ""), f"{w}: name"),
                            _str(rs.get("kind", "seam"), f"{w}: kind"), ease))
    # the result must be a garment the format accepts (types of everything the markup gave)
    try:
        garment_from_dict(garment_to_dict(g))
    except InputError as exc:
        raise InputError(f"{where}: {exc}") from None
    return g


def _texture(t, where: str) -> dict:
    if not isinstance(t, dict) or not isinstance(t.get("image"), str):
        raise InputError(f"{where}: texture is {{\"image\": path, \"size\": [w, h]}}")
    return t


def _side(g: Garment, raw, renames: dict[str, str], where: str) -> SeamSide:
    if not isinstance(raw, dict) or "panel" not in raw:
        raise InputError(f"{where}: a seam side is {{\"panel\": name, \"start\": …, \"end\": …}}")
    pname = _str(raw["panel"], f"{where}: panel")
    name = renames.get(pname, pname)
    names = [p.name for p in g.panels]
    if name not in names:
        raise InputError(f"{where}: unknown panel {raw['panel']!r} (panels: "
                         f"{', '.join(names)})")
    panel = g.panel(name)
    first = g.panel_sizes(panel)[0]   # the first size the panel is cut in
    shape = g.shape(panel.copy_of or panel.name, first) if panel.copy_of else panel.shapes[first]
    verts = np.array([s.start for s in shape.outline])
    out = []
    for key in ("start", "end"):
        if key not in raw:
            raise InputError(f"{where}: missing {key!r}")
        v = raw[key]
        if isinstance(v, int) and not isinstance(v, bool):
            if not 0 <= v < len(verts):
                raise InputError(f"{where}: {key} vertex {v} does not exist (panel {name!r} has "
                                 f"vertices 0…{len(verts) - 1})")
            out.append(v)
            continue
        if isinstance(v, dict) and "point" in v:
            pt = _pt(v["point"], f"{where}: {key} point")
        elif isinstance(v, dict) and "notch" in v:
            k = v["notch"]
            if not isinstance(k, int) or not 0 <= k < len(shape.notches):
                raise InputError(f"{where}: {key}: panel {name!r} has no notch {k!r} "
                                 f"({len(shape.notches)} notches)")
            pt = shape.notches[k]
        else:
            raise InputError(f"{where}: {key} is a vertex number, {{\"point\": [x, y]}} or "
                             f"{{\"notch\": k}}, got {v!r}")
        d = np.linalg.norm(verts - pt, axis=1)
        j = int(np.argmin(d))
        if d[j] > SNAP:
            raise InputError(f"{where}: {key}: no outline vertex of panel {name!r} within "
                             f"{SNAP * 1000:.0f} mm of ({pt[0]:.4f}, {pt[1]:.4f}) (nearest is "
                             f"vertex {j}, {d[j] * 1000:.1f} mm away)")
        out.append(j)
    half = raw.get("half", "cut")
    if half not in ("cut", "mirror"):
        raise InputError(f"{where}: half must be \"cut\" or \"mirror\", got {half!r}")
    return SeamSide(name, out[0], out[1], half)


def _split(g: Garment, p: Panel, sp, where: str) -> None:
    """Insert a vertex ``length`` along the outline from vertex ``from`` in every size; the
    length is metres or the length of a run ``{"panel", "start", "end"}`` in the same size."""
    if not isinstance(sp, dict) or "from" not in sp or "length" not in sp:
        raise InputError(f"{where}: a split is {{\"from\": vertex, \"length\": metres or run}}")
    new: set[int] = set()
    for size in g.panel_sizes(p):
        shape = p.shapes[size]
        length = sp["length"]
        if isinstance(length, dict):
            try:
                other = g.panel(length["panel"])
                segs = other.shapes[size].outline
                length = run_length(segment_lengths(segs), int(length["start"]),
                                    int(length["end"]))
            except (KeyError, TypeError, ValueError, OverflowError):
                raise InputError(f"{where}: length run {sp['length']!r:.80} cannot be "
                                 "measured") from None
        try:
            shape.outline, v = split_at_length(shape.outline, int(sp["from"]), float(length))
        except (ValueError, TypeError, IndexError, OverflowError) as exc:
            raise InputError(f"{where} (size {size}): {exc}") from None
        new.add(v)
    if len(new) > 1:
        raise InputError(f"{where}: the split falls on different edges in different sizes "
                         f"(new vertex {sorted(new)}); split from a nearer vertex")
    v = new.pop()
    if p.fold is not None and p.fold >= v:
        p.fold += 1
