"""DXF pattern files written with ezdxf the way Gerber AccuMark and CLO export them."""

from __future__ import annotations

import ezdxf


def _rect(w, h):
    return [(0.0, 0.0), (w, 0.0), (w, h), (0.0, h)]


def _block(doc, name, piece, size, qty, outline, *, style, grain=None, notches=(),
           mirror=None, texts_upper=False):
    blk = doc.blocks.new(name=name)
    if style == "gerber":   # several open polylines on layer 1, chained end to end
        pts = list(outline) + [outline[0]]
        cut = max(2, len(pts) // 2)
        blk.add_polyline2d(pts[:cut], dxfattribs={"layer": "1"})
        # the second run drawn backwards, as exporters sometimes do
        blk.add_polyline2d(list(reversed(pts[cut - 1:])), dxfattribs={"layer": "1"})
    else:                   # CLO: one closed polyline (flag 70 = 1)
        blk.add_polyline2d(outline, close=True, dxfattribs={"layer": "1"})
    if grain is not None:
        blk.add_line(grain[0], grain[1], dxfattribs={"layer": "7"})
    for pt in notches:
        if style == "gerber":
            blk.add_line(pt, (pt[0] + 0.1, pt[1] + 0.1), dxfattribs={"layer": "4"})
        else:
            blk.add_point(pt, dxfattribs={"layer": "4", "angle": 90.0})
    if mirror is not None:
        blk.add_line(mirror[0], mirror[1], dxfattribs={"layer": "6"})
    keys = ("PIECE NAME", "SIZE", "QUANTITY") if texts_upper else ("Piece Name", "Size",
                                                                   "Quantity")
    for k, v, y in zip(keys, (piece, size, qty), (1, 2, 3), strict=True):
        if v is not None:   # a quantity of None: no 'Quantity:' text
            blk.add_text(f"{k}: {v}", dxfattribs={"layer": "1", "height": 0.2,
                                                   "insert": (1, y)})
    return blk


def write_pattern(path, *, style="gerber", units="ENGLISH", sizes=("S", "M", "L"),
                  extra_pieces=(), drop_units=False, back_qty=2, width=10.0, taper=0.0,
                  quantities=None, drawn_in=None, outline=None):
    """A two-piece skirt (front cut on fold, back with quantity ``back_qty``: 2, or ASTM's
    "1,1") in ``sizes``; ``extra_pieces``: (block, piece, size, outline[, quantity]).

    Units ENGLISH: inches; METRIC: millimetres. Front: a half panel ``width`` × 24 in (+ 0.5
    per size step) with a mirror line along its left edge; back: twice as wide, 2 notches. Each
    side comes in by ``taper`` inches at the top (the waist): 0, rectangles (a 152 cm waist:
    too wide to stay up on a body); ``width=7.87, taper=2.63``: an A-line skirt of 120 cm hem
    and 80 cm waist in size M.

    As real exports have them: ``quantities`` {size: text} sets both pieces' 'Quantity:' text
    per size (None: no text; sizes not named keep theirs); ``drawn_in="cm"`` writes the
    coordinates in centimetres whatever ``units`` says; ``outline(piece, size, points)`` may
    change a piece's boundary points (in the file's units) before they are written."""
    doc = ezdxf.new("R12")
    k = {None: 1.0 if units == "ENGLISH" else 25.4, "cm": 2.54}[drawn_in]
    d = taper * k
    x = 0.0
    quantities = quantities or {}
    shape = outline or (lambda piece, size, pts: pts)
    for i, size in enumerate(sizes):
        w = (width + 0.5 * i) * k
        h = 24.0 * k
        front = [(0.0, 0.0), (w, 0.0), (w - d, h), (0.0, h)]
        notch = 10 * d / 24   # the side's inset 10 in up
        _block(doc, f"FRONT_{size}", "FRONT", size, quantities.get(size, 1),
               shape("FRONT", size, front), style=style,
               grain=((w / 2, 2 * k), (w / 2, 20 * k)), notches=[(w - notch, 10 * k)],
               mirror=((0.0, 0.0), (0.0, h)))
        back = [(0.0, 0.0), (2 * w, 0.0), (2 * w - d, h), (w, h + 0.5 * k), (d, h)]
        _block(doc, f"BACK_{size}", "BACK", size, quantities.get(size, back_qty),
               shape("BACK", size, back), style=style,
               grain=((w, 2 * k), (w, 20 * k)),
               notches=[(notch, 10 * k), (2 * w - notch, 10 * k)],
               texts_upper=(style == "clo"))
        for name in (f"FRONT_{size}", f"BACK_{size}"):
            doc.modelspace().add_blockref(name, (x, 0.0))
            x += 30.0 * k
    for blkname, piece, size, outline, *qty in extra_pieces:
        _block(doc, blkname, piece, size, qty[0] if qty else 1, outline, style=style)
        doc.modelspace().add_blockref(blkname, (x, 0.0))
        x += 30.0 * k
    msp = doc.modelspace()
    msp.add_text("Style Name: SKIRT01", dxfattribs={"layer": "1", "insert": (0, -5)})
    if not drop_units:
        msp.add_text(f"Units: {units}", dxfattribs={"layer": "1", "insert": (0, -6)})
    doc.saveas(path)
    return path


def write_plain(path, insunits=6):
    """Plain DXF: two closed LWPOLYLINEs in model space, metres ($INSUNITS = 6)."""
    doc = ezdxf.new("R2010")
    doc.header["$INSUNITS"] = insunits
    msp = doc.modelspace()
    msp.add_lwpolyline(_rect(0.5, 0.7), close=True, dxfattribs={"layer": "CUT"})
    # a panel with an arc (bulge) edge: a 0.4 × 0.3 rectangle whose top bulges outwards
    msp.add_lwpolyline([(1, 0, 0), (1.4, 0, 0), (1.4, 0.3, 0.25), (1, 0.3, 0)], format="xyb",
                       close=True, dxfattribs={"layer": "CUT"})
    doc.saveas(path)
    return path


# the markup of write_pattern's skirt: types, placement, a mirrored back copy, three seams
SKIRT_MARKUP = {
    "name": "Test skirt", "type": "skirt", "fabric": "denim", "default_size": "M",
    "panels": {
        "FRONT": {"name": "front", "type": "skirt",
                  "placement": {"part": "legs", "side": "front", "anchor": "waist",
                                "anchor_vertex": 3}},
        "BACK": {"name": "back_left", "type": "skirt",
                 "placement": {"part": "legs", "side": "back", "anchor": "waist",
                               "anchor_vertex": 3},
                 "copies": [{"name": "back_right", "mirror": True,
                             "placement": {"part": "legs", "side": "back", "anchor": "waist",
                                           "anchor_vertex": 3}}]},
    },
    "seams": [
        {"name": "side left", "a": {"panel": "front", "start": 1, "end": 2},
         "b": {"panel": "BACK", "start": {"point": [0.0, 0.6096]}, "end": 0},
         "reverse": True},
        {"name": "side right", "a": {"panel": "front", "start": 1, "end": 2, "half": "mirror"},
         "b": {"panel": "back_right", "start": 4, "end": 0}, "reverse": True},
        {"name": "centre back", "a": {"panel": "back_left", "start": 1, "end": 2},
         "b": {"panel": "back_right", "start": 1, "end": 2}, "reverse": False},
    ],
}


# --- what real exports carry (issue 46): boundary changes for write_pattern(outline=…) ------
# Points are in the file's units (inches for ENGLISH, or as drawn); the skirt's front is
# [(0, 0), (w, 0), (w - d, h), (0, h)], its back [(0, 0), (2w, 0), (2w - d, h), (w, h + ½), (d, h)].

def repeated_points(k=1.0, sizes=("M",)):
    """The back's second corner written twice in a row (1e-4 in apart: the same point) and its
    first point again at the end, in ``sizes``: zero-length edges. ``k``: file units per inch."""
    def change(piece, size, pts):
        if piece != "BACK" or size not in sizes:
            return pts
        pts = list(pts)
        pts.insert(2, (pts[1][0] + 1e-4 * k, pts[1][1]))
        return pts + [(pts[0][0], pts[0][1] + 1e-4 * k)]
    return change


def corner_twice(k=1.0, sizes=("S", "M", "L"), e=0.12):
    """The back's hem-side corner drawn twice: the hem runs ``e`` inches past it and the side
    starts ``e`` below it, so the outline crosses itself in a small loop (0.12 in: 3 mm)."""
    def change(piece, size, pts):
        if piece != "BACK" or size not in sizes:
            return pts
        x1 = pts[1][0]
        return [pts[0], (x1 + e * k, 0.0), (x1, -e * k)] + list(pts[2:])
    return change


def notch_twice(k=1.0, sizes=("S", "M", "L"), at=5.0):
    """A V notch on the front's hem ``at`` inches from the fold, its two strokes drawn crossed:
    a 2 mm bow tie below the hem."""
    def change(piece, size, pts):
        if piece != "FRONT" or size not in sizes:
            return pts
        a = at * k
        return [pts[0], (a - 0.12 * k, 0.0), (a + 0.04 * k, -0.2 * k), (a - 0.04 * k, -0.2 * k),
                (a + 0.12 * k, 0.0)] + list(pts[1:])
    return change


def figure_eight(sizes=("L",)):
    """The back's waist drawn to the wrong ends: the outline crosses itself in two big lobes."""
    def change(piece, size, pts):
        if piece != "BACK" or size not in sizes:
            return pts
        return [pts[0], pts[1], pts[4], pts[3], pts[2]]
    return change


def both(*changes):
    def change(piece, size, pts):
        for c in changes:
            pts = c(piece, size, pts)
        return pts
    return change


def write_real_export(path, *, style="clo"):
    """Every class of issue 46 in one file, as a CLO-style export under 'Units: METRIC' whose
    coordinates are centimetres: the sample size M's blocks alone say 'Quantity: 0', a pocket
    in sizes M and L only, the back's corner written twice in size M (repeated points), the
    back's hem corner and a front notch drawn twice in every size (small loops)."""
    k = 2.54   # centimetres per inch
    pocket = [(0.0, 0.0), (6 * k, 0.0), (6 * k, 7 * k), (0.0, 7 * k)]
    extra = [(f"POCKET_{s}", "POCKET", s, [(x + 0.25 * k * i, y) for x, y in pocket], q)
             for i, (s, q) in enumerate((("M", 0), ("L", None)))]
    return write_pattern(path, style=style, units="METRIC", drawn_in="cm",
                         quantities={"S": None, "M": 0, "L": None}, extra_pieces=extra,
                         outline=both(corner_twice(k), notch_twice(k), repeated_points(k)))


def real_export_markup() -> dict:
    """write_real_export's markup: the skirt's, numbered as the repaired front is (its notch
    adds three vertices before the side seam), and the pocket sewn onto the front's hem
    (eased: it is narrower) in the sizes that have it."""
    import copy

    m = copy.deepcopy(SKIRT_MARKUP)
    m["name"] = "Real export skirt"
    m["panels"]["FRONT"]["placement"]["anchor_vertex"] = 6
    m["panels"]["POCKET"] = {"name": "pocket", "type": "pocket",
                             "placement": {"part": "legs", "side": "front", "anchor": "hips"}}
    for s in m["seams"][:2]:
        s["a"].update(start=4, end=5)
    m["seams"].append({"name": "pocket", "a": {"panel": "pocket", "start": 0, "end": 1},
                       "b": {"panel": "front", "start": 3, "end": 4}, "ease": 0.5})
    return m
