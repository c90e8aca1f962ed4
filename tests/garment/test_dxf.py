import copy
import json

import pytest

from catwalk.errors import InputError
from catwalk.exchange.dxf import pieces_to_garment, read_dxf
from catwalk.exchange.garment_json import load_garment
from catwalk.garment.check import check_garment
from catwalk.garment.model import cut_pieces

from .dxf_fixtures import SKIRT_MARKUP, write_pattern, write_plain
from .helpers import cli

IN2 = 0.0254 ** 2


@pytest.mark.parametrize("style,units", [("gerber", "ENGLISH"), ("clo", "METRIC")])
def test_aama_pieces_sizes_areas(tmp_path, style, units):
    path = write_pattern(tmp_path / f"{style}.dxf", style=style, units=units)
    pieces, warnings = read_dxf(path)
    assert not warnings
    got = {(p.name, p.size): p.summary() for p in pieces}
    assert sorted(got) == sorted((n, s) for n in ("FRONT", "BACK") for s in ("S", "M", "L"))
    front_s, back_m = got[("FRONT", "S")], got[("BACK", "M")]
    assert front_s["area_m2"] == pytest.approx(10 * 24 * IN2, rel=1e-5)      # as cut, half
    assert front_s["perimeter_m"] == pytest.approx(2 * (10 + 24) * 0.0254, rel=1e-5)
    assert front_s["mirrored"] is True and front_s["notches"] == 1
    assert back_m["area_m2"] == pytest.approx((21 * 24 + 0.5 * 21 / 2) * IN2, rel=1e-5)
    assert back_m["quantity"] == 2 and back_m["notches"] == 2 and not back_m["mirrored"]
    front = next(p for p in pieces if p.name == "FRONT" and p.size == "M")
    assert front.fold is not None    # the mirror line lies along the boundary
    assert front.grain[1][1] - front.grain[0][1] == pytest.approx(18 * 0.0254)


def test_import_cli_json_and_markup(tmp_path, capsys):
    dxf = write_pattern(tmp_path / "skirt.dxf")
    markup = copy.deepcopy(SKIRT_MARKUP)
    (tmp_path / "markup.json").write_text(json.dumps(markup))
    out = tmp_path / "skirt.json"
    code, stdout, err = cli(["garment", "import", str(dxf), "--markup",
                             str(tmp_path / "markup.json"), "--json", "-o", str(out)], capsys)
    assert code == 0, err
    printed = json.loads(stdout)
    assert printed["warnings"] == []
    rows = printed["pieces"]
    assert {r["name"] for r in rows} == {"FRONT", "BACK"} and len(rows) == 6
    assert set(rows[0]) == {"name", "size", "quantity", "flipped", "area_m2", "perimeter_m",
                            "notches", "mirrored"}
    g = load_garment(out)
    assert [p.name for p in g.panels] == ["front", "back_left", "back_right"]
    assert g.sizes == ["S", "M", "L"] and g.default_size == "M" and g.fabric == "denim"
    rep = check_garment(g)
    assert rep.ok, rep.errors
    pieces, seams = cut_pieces(g, "L")
    assert len(seams) == 3
    # --size picks one size
    code, stdout, _ = cli(["garment", "import", str(dxf), "--size", "S", "--json",
                           "-o", str(tmp_path / "s.json")], capsys)
    assert code == 0 and {r["size"] for r in json.loads(stdout)["pieces"]} == {"S"}


def test_plain_dxf_with_arc(tmp_path, capsys):
    path = write_plain(tmp_path / "plain.dxf")
    code, stdout, err = cli(["garment", "import", str(path), "--json",
                             "-o", str(tmp_path / "p.json")], capsys)
    assert code == 0, err
    rows = json.loads(stdout)["pieces"]
    assert [r["name"] for r in rows] == ["CUT-1", "CUT-2"]
    assert rows[0]["area_m2"] == pytest.approx(0.35)
    assert rows[1]["area_m2"] == pytest.approx(0.12 + 0.013533, rel=1e-3)  # rectangle + arc cap
    assert "no seams yet" in err


def _fails(tmp_path, capsys, argv, needle):
    out = tmp_path / "out.json"
    code, _, err = cli(argv + ["-o", str(out)], capsys)
    assert code == 2
    assert needle in err, err
    assert "Traceback" not in err
    assert not out.exists()


def test_broken_files_exit_2_nothing_written(tmp_path, capsys):
    good = write_pattern(tmp_path / "good.dxf")
    text = good.read_text()
    # damaged: recover mode reads a file without its EOF
    (tmp_path / "noeof.dxf").write_text(text[:text.rindex("EOF")])
    code, _, err = cli(["garment", "import", str(tmp_path / "noeof.dxf"), "--json",
                        "-o", str(tmp_path / "r.json")], capsys)
    assert code == 0 and "recover mode" in err
    (tmp_path / "garbage.dxf").write_text("hello\nthis is not a dxf\n")
    _fails(tmp_path, capsys, ["garment", "import", str(tmp_path / "garbage.dxf")],
           "not readable as DXF")
    (tmp_path / "empty.dxf").write_text("")
    _fails(tmp_path, capsys, ["garment", "import", str(tmp_path / "empty.dxf")], "empty.dxf")
    (tmp_path / "trunc.dxf").write_text(text[: len(text) // 3])
    _fails(tmp_path, capsys, ["garment", "import", str(tmp_path / "trunc.dxf")],
           "no pattern pieces found")
    nounits = write_pattern(tmp_path / "nounits.dxf", drop_units=True)
    _fails(tmp_path, capsys, ["garment", "import", str(nounits)], "missing units")
    dup = write_pattern(tmp_path / "dup.dxf", sizes=("M",),
                        extra_pieces=[("OTHER", "FRONT", "M", [(0, 0), (5, 0), (5, 5)])])
    _fails(tmp_path, capsys, ["garment", "import", str(dup)],
           "duplicate piece name 'FRONT' in size M")
    gap = write_pattern(tmp_path / "gap.dxf", sizes=("M",))
    t = gap.read_text()
    # move one vertex of the first boundary run far away: the runs no longer meet
    import ezdxf
    doc = ezdxf.readfile(gap)
    poly = next(e for e in doc.blocks["FRONT_M"] if e.dxftype() == "POLYLINE")
    v = poly.vertices[-1]
    v.dxf.location = (v.dxf.location.x + 3.0, v.dxf.location.y)
    doc.saveas(gap)
    assert gap.read_text() != t
    _fails(tmp_path, capsys, ["garment", "import", str(gap)], "boundary cannot be closed")
    _fails(tmp_path, capsys, ["garment", "import", str(good), "--size", "XXL"],
           "no piece in size 'XXL'")
    nopieces = tmp_path / "nopieces.dxf"
    doc = ezdxf.new("R12")
    doc.modelspace().add_line((0, 0), (1, 1))
    doc.modelspace().add_text("Units: METRIC")
    doc.saveas(nopieces)
    _fails(tmp_path, capsys, ["garment", "import", str(nopieces)], "no pattern pieces found")


def test_markup_errors(tmp_path, capsys):
    dxf = write_pattern(tmp_path / "skirt.dxf", sizes=("M",))
    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps({"panels": {"SLEEVE": {"type": "sleeve"}}}))
    _fails(tmp_path, capsys, ["garment", "import", str(dxf), "--markup", str(bad)],
           "panel 'SLEEVE': unknown panel")
    bad.write_text(json.dumps({"seams": [{"a": {"panel": "FRONT", "start": 1, "end": 2},
                                          "b": {"panel": "BACK", "start": 0, "end": 1}}]}))
    _fails(tmp_path, capsys, ["garment", "import", str(dxf), "--markup", str(bad)],
           "lengths differ by")
    bad.write_text(json.dumps({"seams": [{"a": {"panel": "FRONT", "start": 1, "end": 2},
                                          "b": {"panel": "CUFF", "start": 0, "end": 1}}]}))
    _fails(tmp_path, capsys, ["garment", "import", str(dxf), "--markup", str(bad)],
           "unknown panel 'CUFF'")


@pytest.mark.parametrize("style,units", [("gerber", "ENGLISH"), ("clo", "METRIC")])
def test_catalogue_garment_round_trips_through_dxf(tmp_path, capsys, style, units):
    """A graded FreeSewing garment exported as AAMA DXF (curves flattened to 0.5 mm, as CAD
    exports them) imports back with the same pieces, sizes, quantities and areas."""
    from pathlib import Path

    from catwalk.garment.check import check_garment

    src = Path(__file__).resolve().parents[2] / "garments" / "pencil-skirt.json"
    dxf = tmp_path / "skirt.dxf"
    code, _, err = cli(["garment", "export-dxf", str(src), "--style", style, "--units", units,
                        "-o", str(dxf)], capsys)
    assert code == 0, err
    code, out, err = cli(["garment", "import", str(dxf), "--json", "-o",
                          str(tmp_path / "back.json")], capsys)
    assert code == 0, err
    rows = {(r["name"], r["size"]): r for r in json.loads(out)["pieces"]}
    assert set(rows) == {(n, s) for n in ("front", "back_right") for s in ("S", "M", "L")}
    want = {(r["panel"], r["size"]): r for r in check_garment(load_garment(src)).panels}
    for key, r in rows.items():
        assert r["area_m2"] == pytest.approx(want[key]["area_m2"], rel=2e-3)
        assert r["perimeter_m"] == pytest.approx(want[key]["perimeter_m"], rel=2e-3)
    assert rows[("front", "M")]["mirrored"] and rows[("back_right", "M")]["quantity"] == 2
    g = load_garment(tmp_path / "back.json")
    assert g.panel("front").fold is not None and g.panel("back_right (2)").mirror
    # graded as CAD grades: the same points in every size, so one markup serves all sizes
    for name in ("front", "back_right"):
        assert len({len(sh.outline) for sh in g.panel(name).shapes.values()}) == 1


def test_malformed_markup_raises_input_errors_only(tmp_path):
    import copy

    from catwalk.exchange.dxf import pieces_to_garment
    from catwalk.exchange.markup import apply_markup
    from catwalk.garment.check import check_garment

    from .helpers import BAD_VALUES, assert_only_input_errors

    pieces, _ = read_dxf(write_pattern(tmp_path / "p.dxf", sizes=("M",)))
    base = {
        "name": "x", "type": "skirt", "fabric": "denim", "default_size": "M",
        "panels": {"FRONT": {"name": "front", "type": "skirt", "fold": 3,
                             "texture": {"image": "t.png", "size": [0.1, 0.1]},
                             "placement": {"part": "legs", "side": "front", "offset": [0, 0, 0]}},
                   "BACK": {"split": [{"from": 1, "length": 0.05}],
                            "copies": [{"name": "back2", "mirror": True, "type": "skirt"}]}},
        "seams": [{"name": "s", "a": {"panel": "front", "start": 1, "end": 2},
                   "b": {"panel": "BACK", "start": {"point": [0.0, 0.61]}, "end": 0},
                   "reverse": True, "ease": 0.0, "kind": "seam"}],
    }

    def use(doc):
        g = apply_markup(pieces_to_garment(copy.deepcopy(pieces), "x"), doc)
        check_garment(g, tmp_path)

    tried = assert_only_input_errors(base, use, BAD_VALUES[:4])
    assert tried > 100


def test_a_panel_renamed_to_nothing_is_refused_by_name(tmp_path):
    """Found by `make fuzz`: a piece with copies renamed to "" left its copies pointing at a
    falsy name, and a seam on a copy raised KeyError; names follow the garment format's rule."""
    from catwalk.exchange.markup import apply_markup

    pieces, _ = read_dxf(write_pattern(tmp_path / "p.dxf", sizes=("M",)))
    for bad, where in (("", "panel 'BACK': name"), (" back", "panel 'BACK': name"),
                       (7, "panel 'BACK': name")):
        markup = copy.deepcopy(SKIRT_MARKUP)
        markup["panels"]["BACK"]["name"] = bad
        with pytest.raises(InputError, match=where):
            apply_markup(pieces_to_garment(copy.deepcopy(pieces), "x"), markup)
    markup = copy.deepcopy(SKIRT_MARKUP)
    markup["panels"]["BACK"]["copies"][0]["name"] = ""
    with pytest.raises(InputError, match="copy 0: name '' is not a name"):
        apply_markup(pieces_to_garment(copy.deepcopy(pieces), "x"), markup)

def test_a_piece_split_thousands_of_times_is_refused_at_once(tmp_path):
    """Found by `make fuzz`: 5,000 splits of one sleeve took minutes; a piece is split at most
    MAX_SPLITS times (a markup splits where a dart or a notch ends a seam)."""
    from catwalk.exchange.markup import MAX_SPLITS, apply_markup

    pieces, _ = read_dxf(write_pattern(tmp_path / "p.dxf", sizes=("M",)))
    markup = copy.deepcopy(SKIRT_MARKUP)
    markup["panels"]["BACK"]["split"] = [{"from": 1, "length": 0.05}] * (MAX_SPLITS + 1)
    with pytest.raises(InputError, match=f"panel 'BACK': {MAX_SPLITS + 1} splits"):
        apply_markup(pieces_to_garment(copy.deepcopy(pieces), "x"), markup)


@pytest.mark.parametrize("qty,copies", [("1,1", [False, True]), ("2,0", [False, False]),
                                        ("2,1", [False, False, True]),
                                        ("2", [False, True])])
def test_astm_quantity_as_drawn_and_mirrored(tmp_path, qty, copies):
    """ASTM D6673's 'Quantity: N,M' (N as drawn, M mirrored) beside AAMA's 'Quantity: N' (a
    pair alternates plain and mirrored)."""
    from catwalk.exchange.dxf import pieces_to_garment, read_dxf

    path = write_pattern(tmp_path / "astm.dxf", style="clo", units="METRIC", back_qty=qty)
    pieces, _ = read_dxf(path)
    back = next(p for p in pieces if p.name == "BACK")
    assert back.quantity == len(copies)
    assert back.flipped == (None if "," not in qty else int(qty.split(",")[1]))
    g = pieces_to_garment(pieces, "skirt")
    panels = [p for p in g.panels if p.name == "BACK" or p.copy_of == "BACK"]
    assert [bool(p.mirror) for p in panels] == copies


def test_a_piece_of_quantity_zero_is_skipped_with_a_warning(tmp_path):
    from catwalk.exchange.dxf import read_dxf

    extra = [(f"SPARE_{s}", "SPARE", s, [(0, 0), (100, 0), (100, 100), (0, 100)], 0)
             for s in ("S", "M", "L")]
    pieces, warnings = read_dxf(write_pattern(tmp_path / "z.dxf", style="clo", units="METRIC",
                                              extra_pieces=extra))
    assert {p.name for p in pieces} == {"FRONT", "BACK"}
    skipped = [w for w in warnings if w["code"] == "not-cut"]
    assert [(w["piece"], w["size"]) for w in skipped] == [("SPARE", s) for s in ("S", "M", "L")]
    assert all("'Quantity: 0': not cut, skipped" in w["message"] for w in skipped)


@pytest.mark.parametrize("qty,message", [("1,x", "is not a number"),
                                         ("1,1,1", "neither N nor N,M"),
                                         ("0,2", "cut only mirrored"),
                                         ("15,15", "30 copies; at most")])
def test_bad_astm_quantities_are_refused(tmp_path, qty, message):
    from catwalk.errors import InputError
    from catwalk.exchange.dxf import read_dxf

    path = write_pattern(tmp_path / "bad.dxf", style="clo", units="METRIC", back_qty=qty)
    with pytest.raises(InputError, match=message) as caught:
        read_dxf(path)
    assert "piece 'BACK'" in str(caught.value) and f"Quantity: {qty}" in str(caught.value)


def test_a_metric_file_labelled_english_is_refused_as_not_garment_sized(tmp_path):
    """Millimetres read as inches make 15 m pieces: refused, the units named as the cause."""
    path = write_pattern(tmp_path / "metric.dxf", style="clo", units="METRIC")
    path.write_bytes(path.read_bytes().replace(b"Units: METRIC", b"Units: ENGLISH"))
    with pytest.raises(InputError, match=r"not garment-sized .* units right"):
        read_dxf(path)
    assert len(read_dxf(path, units="mm")[0]) == 6   # the right units given: read


@pytest.mark.parametrize("bad", ["nan", "inf", "-inf", "1e400"])
def test_a_coordinate_that_is_not_finite_is_refused(tmp_path, bad):
    import ezdxf

    doc = ezdxf.new("R2010")
    doc.header["$INSUNITS"] = 6
    doc.modelspace().add_lwpolyline([(0, 0), (0.5, 0), (0.5, 0.7), (0, 0.7)], close=True)
    doc.saveas(tmp_path / "p.dxf")
    text = (tmp_path / "p.dxf").read_text()
    at = text.index("LWPOLYLINE")   # the second vertex's x (0.5) written as the bad number
    text = text[:at] + text[at:].replace("\n 10\n0.5\n", f"\n 10\n{bad}\n", 1)
    (tmp_path / "p.dxf").write_text(text)
    with pytest.raises(InputError, match="finite|not a number|not readable|damaged"):
        read_dxf(tmp_path / "p.dxf")


# --- real exports (issue 46): each class imports with every size and piece, or is refused ----

def _areas(pieces) -> dict:
    return {(p.name, p.size): p.area_m2 for p in pieces}


def _codes(warnings) -> list[tuple]:
    return [(w["code"], w.get("piece"), w.get("size")) for w in warnings]


def _sound(pieces) -> None:
    """The pieces make a garment whose outlines the checker finds sound (seams aside)."""
    rep = check_garment(pieces_to_garment(pieces, "x"))
    assert [e for e in rep.errors if "reachable" not in e] == []


@pytest.mark.parametrize("style,units", [("gerber", "ENGLISH"), ("clo", "METRIC")])
def test_the_sample_sizes_quantity_0_is_read_as_cut(tmp_path, style, units):
    """Only the sample size's blocks say 'Quantity: 0' (the other sizes say nothing): every
    size is read, the sample size cut once like the others, each assumption told."""
    clean, _ = read_dxf(write_pattern(tmp_path / "clean.dxf", style=style, units=units))
    path = write_pattern(tmp_path / "q.dxf", style=style, units=units,
                         quantities={"S": None, "M": "0", "L": None})
    pieces, warnings = read_dxf(path)
    assert sorted(_areas(pieces)) == sorted(_areas(clean))
    assert all(p.quantity == 1 for p in pieces)
    assert _codes(warnings) == [("sample-quantity", "FRONT", "M"), ("sample-quantity", "BACK", "M")]
    assert "'Quantity: 0' read as 1, as in sizes S, L (no 'Quantity:' text there)" \
        in warnings[0]["message"]
    assert _areas(pieces) == pytest.approx(_areas(clean), rel=1e-9)
    # read alone, the sample size is there too
    assert {p.name for p in read_dxf(path, size="M")[0]} == {"FRONT", "BACK"}


def test_a_quantity_0_where_the_other_sizes_state_theirs_is_not_cut(tmp_path):
    """'Quantity: 0' in M while S and L say 2: not cut in M (the back is then a piece of sizes
    S and L only); 0 in every size: not cut at all."""
    path = write_pattern(tmp_path / "q.dxf", quantities={"M": "0"})
    pieces, warnings = read_dxf(path)
    assert sorted((p.name, p.size) for p in pieces) == sorted(
        [("FRONT", "S"), ("FRONT", "L"), ("BACK", "S"), ("BACK", "L")])
    assert _codes(warnings) == [("not-cut", "FRONT", "M"), ("not-cut", "BACK", "M"),
                                ("size-not-cut", None, "M")]
    assert warnings[-1]["message"].endswith(
        "size M: every piece has quantity 0 (not cut): the size is not imported")
    assert pieces_to_garment(pieces, "x").sizes == ["S", "L"]
    # no text in M: cut once there, twice in S and L: the garment cuts 2 in every size, told
    pieces, warnings = read_dxf(write_pattern(tmp_path / "q.dxf", quantities={"M": None}))
    assert [p.quantity for p in pieces if p.name == "BACK"] == [2, 1, 2]
    assert _codes(warnings) == [("quantity-differs", "BACK", None)]
    assert "the quantity differs between sizes (S: 2, M: 1, L: 2): every size is cut 2, as " \
           "size S says" in warnings[0]["message"]
    assert [p.name for p in pieces_to_garment(pieces, "x").panels] == ["FRONT", "BACK",
                                                                      "BACK (2)"]


def test_pieces_in_some_sizes_only_are_imported_in_those(tmp_path, capsys):
    """A pocket in M and L, a label in S: every size with the pieces it has, told per piece;
    the garment cuts each size's own pieces, and a seam on the pocket is sewn where it is."""
    from .dxf_fixtures import _rect

    extra = [("POCKET_M", "POCKET", "M", _rect(6, 7)), ("POCKET_L", "POCKET", "L", _rect(6.5, 7)),
             ("LABEL_S", "LABEL", "S", _rect(2, 3))]
    path = write_pattern(tmp_path / "sizes.dxf", extra_pieces=extra)
    pieces, warnings = read_dxf(path)
    assert len(pieces) == 9
    assert [(w["code"], w["piece"], w["sizes"], w["missing"]) for w in warnings] == [
        ("sizes", "POCKET", ["M", "L"], ["S"]), ("sizes", "LABEL", ["S"], ["M", "L"])]
    assert warnings[0]["message"].endswith(
        "piece 'POCKET': in sizes M, L only (not in size S): imported in those sizes")
    g = pieces_to_garment(pieces, "x")
    assert g.sizes == ["S", "M", "L"]
    assert sorted(g.panel("POCKET").shapes) == ["L", "M"] and g.panel_sizes("LABEL") == ["S"]
    assert g.panel("POCKET").meta["import_warnings"] == [
        {"code": "sizes", "message": "in sizes M, L only (not in size S): imported in those "
                                     "sizes"}]
    for size, want in (("S", {"FRONT", "BACK", "BACK (2)", "LABEL"}),
                       ("M", {"FRONT", "BACK", "BACK (2)", "POCKET"})):
        assert {pc.name for pc in cut_pieces(g, size)[0]} == want
    _sound(pieces)
    # with the skirt's markup, the pocket and the label sewn to the front (eased: they are
    # narrower): the garment is sound, each seam sewn in the sizes that have its pieces
    markup = copy.deepcopy(SKIRT_MARKUP)
    markup["panels"]["POCKET"] = {"name": "pocket", "type": "pocket"}
    markup["panels"]["LABEL"] = {"name": "label", "type": "other"}
    markup["seams"] += [
        {"name": "pocket", "a": {"panel": "pocket", "start": 0, "end": 1},
         "b": {"panel": "front", "start": 0, "end": 1}, "ease": 0.5},
        {"name": "label", "a": {"panel": "label", "start": 0, "end": 1},
         "b": {"panel": "front", "start": 0, "end": 1}, "ease": 0.85}]
    (tmp_path / "m.json").write_text(json.dumps(markup))
    code, _, err = cli(["garment", "import", str(path), "--markup", str(tmp_path / "m.json"),
                        "-o", str(tmp_path / "g.json")], capsys)
    assert code == 0, err
    assert "warning: " in err and "piece 'POCKET': in sizes M, L only" in err
    rep = check_garment(load_garment(tmp_path / "g.json"))
    assert rep.ok, rep.errors
    assert [(r["name"], r["size"]) for r in rep.seams if r["name"] in ("pocket", "label")] == [
        ("label", "S"), ("pocket", "M"), ("pocket", "L")]


def test_repeated_points_are_dropped_and_counted(tmp_path):
    """The back's corner twice in a row in size M, and its first point again at the end (a
    few microns off): dropped and counted; the outline as in the other sizes."""
    from .dxf_fixtures import repeated_points

    clean, _ = read_dxf(write_pattern(tmp_path / "clean.dxf", style="clo", units="METRIC"))
    pieces, warnings = read_dxf(write_pattern(tmp_path / "d.dxf", style="clo", units="METRIC",
                                              outline=repeated_points(25.4)))
    assert [(w["code"], w["piece"], w["size"], w["count"]) for w in warnings] == [
        ("duplicate-points", "BACK", "M", 2)]
    assert "2 repeated boundary point(s) dropped" in warnings[0]["message"]
    assert _areas(pieces) == pytest.approx(_areas(clean), rel=1e-6)
    assert {len(p.segments) for p in pieces if p.name == "BACK"} == {5}
    _sound(pieces)


@pytest.mark.parametrize("style,units,k", [("gerber", "ENGLISH", 1.0), ("clo", "METRIC", 25.4)])
def test_small_self_crossing_loops_are_removed_and_told(tmp_path, style, units, k):
    """A corner and a notch drawn twice in every size: each small loop cut off at the crossing,
    told with where it was; areas within 1 %, the outlines sound, the sizes still graded."""
    from .dxf_fixtures import both, corner_twice, notch_twice

    clean, _ = read_dxf(write_pattern(tmp_path / "clean.dxf", style=style, units=units))
    pieces, warnings = read_dxf(write_pattern(tmp_path / "l.dxf", style=style, units=units,
                                              outline=both(corner_twice(k), notch_twice(k))))
    assert _codes(warnings) == [("loop-removed", n, s) for s in ("S", "M", "L")
                                for n in ("FRONT", "BACK")]
    back_m = next(w for w in warnings if w["piece"] == "BACK" and w["size"] == "M")
    assert back_m["at"] == pytest.approx([0.5334, 0.003], abs=2e-3) and back_m["loop_mm"] < 4
    assert "crossed itself in a small loop near (53.3, 0.3) cm from the piece's lower-left " \
           "corner: the loop (3.0 mm across" in back_m["message"]
    assert _areas(pieces) == pytest.approx(_areas(clean), rel=1e-2)
    for name in ("FRONT", "BACK"):
        assert len({len(p.segments) for p in pieces if p.name == name}) == 1
    _sound(pieces)


def test_a_large_self_crossing_is_refused_naming_piece_size_and_place(tmp_path, capsys):
    from .dxf_fixtures import figure_eight

    path = write_pattern(tmp_path / "x.dxf", outline=figure_eight())
    with pytest.raises(InputError) as caught:
        read_dxf(path)
    msg = str(caught.value)
    assert "piece 'BACK' (size L): the outline crosses itself near (27.9, 30.5) cm from the " \
           "piece's lower-left corner" in msg
    assert "more than a drawing slip" in msg and "correct the outline in the pattern CAD" in msg
    _fails(tmp_path, capsys, ["garment", "import", str(path)], "crosses itself near")


def test_a_cm_file_labelled_metric_is_read_in_centimetres(tmp_path):
    """Centimetres under 'Units: METRIC' make 6 cm pieces: read in centimetres, told; the
    units given are taken as given (then refused as too small, with the reason)."""
    clean, _ = read_dxf(write_pattern(tmp_path / "clean.dxf", style="clo", units="METRIC"))
    path = write_pattern(tmp_path / "cm.dxf", style="clo", units="METRIC", drawn_in="cm")
    pieces, warnings = read_dxf(path)
    assert [(w["code"], w["units"], w["stated"]) for w in warnings] == [("units", "cm", "mm")]
    assert "the file's 'Units: METRIC' means millimetres, which makes the largest piece (size " \
           "S) 6.22 cm across: too small for a garment; read in centimetres instead" \
        in warnings[0]["message"]
    assert _areas(pieces) == pytest.approx(_areas(clean), rel=1e-9)
    with pytest.raises(InputError, match=r"too small for a garment: the largest \(size S\) is "
                                         r"6\.22 cm across in millimetres, as given \(a "):
        read_dxf(path, units="mm")
    assert _areas(read_dxf(path, units="cm")[0]) == pytest.approx(_areas(clean), rel=1e-9)


def test_pieces_too_small_in_every_unit_are_refused(tmp_path):
    """A 5 × 3 mm box under $INSUNITS = mm: in cm, inches or metres still not a garment."""
    import ezdxf

    doc = ezdxf.new("R2010")
    doc.header["$INSUNITS"] = 4
    doc.modelspace().add_lwpolyline([(0, 0), (0.05, 0), (0.05, 0.03), (0, 0.03)], close=True)
    doc.saveas(tmp_path / "tiny.dxf")
    with pytest.raises(InputError, match=r"the pieces are too small for a garment: the largest "
                                         r"is 0\.005 cm across in millimetres, as the header's "
                                         r"\$INSUNITS = 4 says .*; no other unit makes every "
                                         r"size garment-sized"):
        read_dxf(tmp_path / "tiny.dxf")


@pytest.mark.parametrize("insunits,unit", [(4, "mm"), (5, "cm")])
def test_a_6_m2_box_is_not_a_garment_in_any_unit(tmp_path, insunits, unit):
    """3.5 × 1.7 m is refused as it is read (pieces too large are never read in a smaller
    unit: a garment is not guessed out of a box)."""
    import ezdxf

    k = {"mm": 1000.0, "cm": 100.0}[unit]
    doc = ezdxf.new("R2010")
    doc.header["$INSUNITS"] = insunits
    doc.modelspace().add_lwpolyline([(0, 0), (3.5 * k, 0), (3.5 * k, 1.715 * k),
                                     (0, 1.715 * k)], close=True)
    doc.saveas(tmp_path / "box.dxf")
    with pytest.raises(InputError, match=r"piece '0-1': the piece is 3\.5 m across \(at most "
                                         r"3 m\): not garment-sized — are the units right"):
        read_dxf(tmp_path / "box.dxf")


def test_a_size_whose_loop_starts_elsewhere_keeps_the_fold(tmp_path):
    """Size L's front drawn from another corner: its fold is another edge number there; the
    panel's one fold edge is made to fit every size (its vertices renumbered)."""
    def rotate(piece, size, pts):
        return list(pts[2:]) + list(pts[:2]) if piece == "FRONT" and size == "L" else pts

    pieces, warnings = read_dxf(write_pattern(tmp_path / "r.dxf", outline=rotate))
    assert warnings == []
    assert [p.fold for p in pieces if p.name == "FRONT"] == [3, 3, 1]
    g = pieces_to_garment(pieces, "x")
    front = g.panel("FRONT")
    for size in g.sizes:
        a, b = (front.shapes[size].outline[k].start for k in (front.fold, (front.fold + 1) % 4))
        assert a[0] == pytest.approx(0) and b[0] == pytest.approx(0)   # the fold: x = 0
    _sound(pieces)


def test_every_warning_reaches_the_cli_and_the_panels(tmp_path, capsys):
    """All the classes in one export: the CLI prints each repair and assumption (stderr, and
    in --json), the garment keeps each piece's on its panel."""
    from .dxf_fixtures import write_real_export

    path = write_real_export(tmp_path / "real.dxf")
    out = tmp_path / "real.json"
    code, stdout, err = cli(["garment", "import", str(path), "--json", "-o", str(out)], capsys)
    assert code == 0, err
    printed = json.loads(stdout)
    codes = [w["code"] for w in printed["warnings"]]
    assert codes.count("units") == 1 and codes.count("sample-quantity") == 3
    assert codes.count("loop-removed") == 6 and codes.count("duplicate-points") == 1
    assert codes.count("sizes") == 1 and len(codes) == 12
    for w in printed["warnings"]:
        assert f"warning: {w['message']}" in err
    assert len(printed["pieces"]) == 8
    g = load_garment(out)
    told = {p.name: [w["code"] for w in p.meta.get("import_warnings", [])] for p in g.panels}
    assert told == {"FRONT": ["loop-removed", "sample-quantity", "loop-removed", "loop-removed"],
                    "BACK": ["loop-removed", "sample-quantity", "duplicate-points",
                             "loop-removed", "loop-removed"],
                    "POCKET": ["sample-quantity", "sizes"]}
    back = g.panel("BACK").meta["import_warnings"]
    assert back[2] == {"code": "duplicate-points", "size": "M",
                       "message": "size M: 2 repeated boundary point(s) dropped (the same "
                                  "point twice in a row, within 0.05 mm: an edge of no length)"}
