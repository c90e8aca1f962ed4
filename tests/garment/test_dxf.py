import copy
import json

import pytest

from catwalk.errors import InputError
from catwalk.exchange.dxf import read_dxf
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
    rows = json.loads(stdout)
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
    assert code == 0 and {r["size"] for r in json.loads(stdout)} == {"S"}


def test_plain_dxf_with_arc(tmp_path, capsys):
    path = write_plain(tmp_path / "plain.dxf")
    code, stdout, err = cli(["garment", "import", str(path), "--json",
                             "-o", str(tmp_path / "p.json")], capsys)
    assert code == 0, err
    rows = json.loads(stdout)
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
    rows = {(r["name"], r["size"]): r for r in json.loads(out)}
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
    assert sum("quantity 0 (not cut): skipped" in w and "SPARE" in w for w in warnings) == 3


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
