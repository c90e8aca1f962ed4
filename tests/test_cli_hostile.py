"""The command line as a hostile user tries it: every case exits 2 with a clear message naming
what is wrong, prints no traceback and no numpy warning, and leaves nothing behind (no output,
no temporary file, no folder it made)."""

from __future__ import annotations

import importlib.util
import json
import math
import os
import struct
import warnings
from pathlib import Path

import pytest

from catwalk.cli.main import main

REPO = Path(__file__).resolve().parents[1]
GARMENTS = REPO / "garments"
SPEC = GARMENTS / "garmentcode" / "dress_pencil_specification.json"
DEEP = "[" * 10_000 + "]" * 10_000


def _listing(folder: Path) -> set[str]:
    return {str(p.relative_to(folder)) for p in folder.rglob("*")}


def refused(argv, capsys, folder: Path, *expect: str) -> str:
    """Run ``catwalk argv``: exit 2, each of ``expect`` in the message, no warning, nothing
    new in ``folder``. Returns the message."""
    before = _listing(folder)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        code = main([str(a) for a in argv])
    err = capsys.readouterr().err
    assert code == 2, err
    assert err.startswith("catwalk: error: "), err
    assert "Traceback" not in err
    for text in expect:
        assert text in err, err
    noisy = [w for w in caught if issubclass(w.category, (RuntimeWarning, UserWarning))]
    assert not noisy, [str(w.message) for w in noisy]
    assert _listing(folder) == before, "left behind: " + ", ".join(_listing(folder) - before)
    return err


@pytest.fixture
def work(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "textures").symlink_to(GARMENTS / "textures")
    (tmp_path / "a-file").write_text("not a folder")
    return tmp_path


@pytest.fixture(scope="module")
def body_glb(tmp_path_factory, mpfb2):
    """A body that dresses (the female base body, measured), as catwalk writes it."""
    from catwalk.body.rig import measured_base_body
    from catwalk.exchange.gltf import write_glb

    path = tmp_path_factory.mktemp("body") / "body.glb"
    write_glb(path, measured_base_body(0.0))
    return path


def _spec(change) -> str:
    spec = json.loads(SPEC.read_text())
    change(spec)
    return json.dumps(spec, allow_nan=True)


def _scaled_garment(k: float) -> dict:
    """The catalogue dress with every outline coordinate multiplied by ``k``."""
    g = json.loads((GARMENTS / "dress.json").read_text())

    def scale(node):
        if isinstance(node, list):
            return [scale(x) for x in node]
        if isinstance(node, dict):
            return {key: scale(v) for key, v in node.items()}
        return node * k if isinstance(node, float) or type(node) is int else node

    for p in g["panels"]:
        for size, shape in (p.get("shapes") or {}).items():
            p["shapes"][size] = {key: scale(v) if key in ("outline", "grain", "notches") else v
                                 for key, v in shape.items()}
    return g


def _dxf(folder: Path) -> Path:
    spec = importlib.util.spec_from_file_location(
        "_hostile_dxf_fixtures", REPO / "tests" / "garment" / "dxf_fixtures.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod.write_pattern(folder / "skirt.dxf", sizes=("M",))


UNWRITABLE = ["/sys/catwalk-hostile/out", "a-file/out"]   # + the suffix each command wants


# --- tracebacks today --------------------------------------------------------------------

def test_body_make_without_girths(work, capsys, mpfb2):
    refused(["body", "make", "--sex", "female", "--height", "1.68", "-o", "x.glb"], capsys,
            work, "bust, waist and hips are missing")


@pytest.mark.parametrize("how", ["check", "from-garmentcode", "markup"])
def test_json_nested_10000_deep(work, capsys, how):
    (work / "deep.json").write_text(DEEP)
    if how == "check":
        argv = ["garment", "check", "deep.json"]
    elif how == "from-garmentcode":
        argv = ["garment", "from-garmentcode", "deep.json", "-o", "g.json"]
    else:
        _dxf(work)
        argv = ["garment", "import", "skirt.dxf", "--markup", "deep.json", "-o", "g.json"]
    refused(argv, capsys, work, "deep.json", "nested too deeply")


@pytest.mark.parametrize("change, expect", [
    (lambda s: s["pattern"]["panels"]["skirt_back"]["vertices"][1].__setitem__(0, math.nan),
     "panel 'skirt_back', vertex 1: expected a finite number, got nan"),
    (lambda s: s["properties"].__setitem__("units_in_meter", 0), "units_in_meter"),
    (lambda s: s["properties"].__setitem__("units_in_meter", -100), "units_in_meter"),
    (lambda s: s["pattern"].__setitem__("panels", list(s["pattern"]["panels"].values())),
     "pattern.panels must be an object"),
    (lambda s: s["pattern"].update(panels={}, stitches=[], panel_order=[]),
     "pattern.panels is empty"),
])
def test_garmentcode_spec_refused(work, capsys, change, expect):
    (work / "spec.json").write_text(_spec(change))
    refused(["garment", "from-garmentcode", "spec.json", "-o", "g.json"], capsys, work, expect)


@pytest.mark.parametrize("option, expect", [
    (["--type", "spaceship"], "garment type 'spaceship' is not one of"),
    (["--size", ""], "size ''"),
    (["--size", " M"], "size ' M'"),
])
def test_garmentcode_options_refused(work, capsys, option, expect):
    refused(["garment", "from-garmentcode", SPEC, *option, "-o", "g.json"], capsys, work,
            expect)


def test_render_truncated_glb(work, capsys, body_glb):
    data = body_glb.read_bytes()
    (work / "cut.glb").write_bytes(data[: len(data) // 2])
    refused(["render", "cut.glb", "-o", "r.png"], capsys, work, "cut.glb: truncated GLB")
    # cut inside the binary chunk, the lengths in the header made to agree: no traceback
    (jlen,) = struct.unpack("<I", data[12:16])
    keep = 20 + jlen + 8 + 4096
    cut = bytearray(data[:keep])
    cut[8:12] = struct.pack("<I", keep)
    cut[20 + jlen:24 + jlen] = struct.pack("<I", 4096)
    (work / "cut.glb").write_bytes(bytes(cut))
    refused(["render", "cut.glb", "-o", "r.png"], capsys, work, "cut.glb: ",
            "binary chunk has 4,096")


@pytest.mark.parametrize("time", ["nan", "inf", "-1"])
def test_render_time_not_a_time(work, capsys, body_glb, time):
    refused(["render", body_glb, "--time", time, "-o", "r.png"], capsys, work, "--time")


def test_render_view_not_a_view(work, capsys, body_glb):
    refused(["render", body_glb, "--view", "nan", "-o", "r.png"], capsys, work, "--view")


@pytest.mark.parametrize("where", UNWRITABLE)
def test_unwritable_output_body_make(work, capsys, mpfb2, where):
    refused(["body", "make", "--sex", "female", "--height", "1.68", "--bust", "0.9", "--waist",
             "0.72", "--hips", "0.98", "-o", f"{where}.glb"], capsys, work, f"-o {where}.glb")


@pytest.mark.parametrize("where", UNWRITABLE)
def test_unwritable_output_garment_import(work, capsys, where):
    _dxf(work)
    refused(["garment", "import", "skirt.dxf", "-o", f"{where}.json"], capsys, work,
            f"-o {where}.json")


@pytest.mark.parametrize("where", UNWRITABLE)
def test_unwritable_output_from_garmentcode(work, capsys, where):
    refused(["garment", "from-garmentcode", SPEC, "-o", f"{where}.json"], capsys, work,
            f"-o {where}.json")


@pytest.mark.parametrize("where", UNWRITABLE)
def test_unwritable_output_dress(work, capsys, body_glb, where):
    refused(["dress", "--body", body_glb, "--garment", GARMENTS / "dress.json", "--quiet",
             "-o", f"{where}.glb"], capsys, work, f"-o {where}.glb")


@pytest.mark.parametrize("where", UNWRITABLE)
def test_unwritable_output_render(work, capsys, body_glb, where):
    refused(["render", body_glb, "-o", f"{where}.png"], capsys, work, f"-o {where}.png")


@pytest.mark.parametrize("where", UNWRITABLE)
def test_tryon_with_unwritable_metrics_leaves_no_glb(work, capsys, body_glb, where):
    refused(["tryon", "--body", body_glb, "--garment", GARMENTS / "dress.json", "--seconds",
             "0.5", "--quiet", "--metrics", f"{where}.json", "-o", "t.glb"], capsys, work,
            f"--metrics {where}.json")
    assert not (work / "t.glb").exists()


def test_output_folders_made_for_a_failed_write_are_removed(work):
    from catwalk.errors import InputError
    from catwalk.fileio import atomic_path

    with pytest.raises(RuntimeError), atomic_path(work / "new" / "deeper" / "x.json") as tmp:
        tmp.write_text("half")
        raise RuntimeError("the writer failed")
    assert not (work / "new").exists()
    with pytest.raises(InputError, match="a-file"), atomic_path(work / "a-file" / "x.json"):
        pass


# --- wrong successes -----------------------------------------------------------------------

def _scaled_body_glb(folder: Path, height: float) -> Path:
    """The base body scaled to ``height`` (file units: glTF's metres, or what a scanner wrote)."""
    from catwalk.body.rig import measured_base_body
    from catwalk.exchange.gltf import write_glb

    body = measured_base_body(0.0)
    body.vertices = body.vertices * (height / 1.59)
    path = folder / f"h{height:g}.glb"
    write_glb(path, body)
    return path


@pytest.fixture(scope="module")
def giant_glb(tmp_path_factory, mpfb2):
    """The base body scaled to 150 m: in centimetres it would be 1.5 m, but glTF is metres."""
    return _scaled_body_glb(tmp_path_factory.mktemp("giant"), 150.0)


@pytest.mark.parametrize("command", ["info", "measure"])
def test_glb_scan_is_metres_and_must_be_human_sized(work, capsys, giant_glb, command):
    refused(["body", command, giant_glb], capsys, work, "not a human size", "metres")


def test_dress_refuses_a_body_that_is_not_human_sized(work, capsys, giant_glb):
    refused(["dress", "--body", giant_glb, "--garment", GARMENTS / "dress.json", "--quiet",
             "-o", "d.glb"], capsys, work, "h150.glb: the body is 150 m tall")


@pytest.mark.parametrize("k", [10.0, 1e6, 0.01])
def test_garment_must_be_garment_sized(work, capsys, k):
    (work / "g.json").write_text(json.dumps(_scaled_garment(k)))
    refused(["garment", "check", "g.json"], capsys, work, "not garment-sized")


def test_dress_refuses_a_garment_ten_times_too_big_at_once(work, capsys, body_glb):
    import time

    (work / "g.json").write_text(json.dumps(_scaled_garment(10.0)))
    t0 = time.perf_counter()
    refused(["dress", "--body", body_glb, "--garment", "g.json", "--quiet", "-o", "d.glb"],
            capsys, work, "8.861 m across", "not garment-sized")
    assert time.perf_counter() - t0 < 10


# --- unclear -------------------------------------------------------------------------------

def test_fabric_density_heavy(work, capsys):
    g = json.loads((GARMENTS / "dress.json").read_text())
    g["fabric"] = {"base": "cotton-jersey", "density": "heavy"}
    (work / "g.json").write_text(json.dumps(g))
    err = refused(["garment", "check", "g.json"], capsys, work,
                  "density must be a number, got 'heavy'")
    assert "ufunc" not in err


def test_huge_coordinate_prints_no_numpy_warning(work, capsys):
    g = json.loads((GARMENTS / "dress.json").read_text())
    shape = next(iter(g["panels"][0]["shapes"].values()))
    shape["outline"][0]["start"][0] = 1e308
    (work / "g.json").write_text(json.dumps(g))
    err = refused(["garment", "check", "g.json"], capsys, work, "[1e+308, ",
                  "more than 1000 m from the origin", "not garment-sized")
    assert "Warning" not in err


def test_render_writes_jpeg_for_jpg_and_refuses_other_suffixes(work, capsys, body_glb):
    assert main(["render", str(body_glb), "--size", "64x96", "-o", "r.jpg"]) == 0
    assert (work / "r.jpg").read_bytes()[:3] == b"\xff\xd8\xff"
    assert main(["render", str(body_glb), "--size", "64x96", "-o", "r.png"]) == 0
    assert (work / "r.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    capsys.readouterr()
    refused(["render", body_glb, "-o", "r.gif"], capsys, work, "-o r.gif", ".png, .jpg")


@pytest.mark.parametrize("argv, expect", [
    (["--size", "8192x8192"], "a frame has at most"),
    (["--time", "0", "0", "0", "0", "--view", "front", "side", "back", "right", "--size",
      "4096x4096"], "contact sheet"),
    (["--time", *["0"] * 13, "--view", "front", "side", "back", "right", "10", "--size",
      "16x16"], "at most 64"),
])
def test_contact_sheet_is_capped(work, capsys, body_glb, argv, expect):
    refused(["render", body_glb, *argv, "-o", "r.png"], capsys, work, expect)


def test_garmentcode_written_garments_pass_the_check(work, capsys):
    """What from-garmentcode writes, check accepts (the real spec, converted)."""
    assert main(["garment", "from-garmentcode", str(SPEC), "-o", "g.json"]) == 0
    assert main(["garment", "check", "g.json"]) == 0
    capsys.readouterr()


def test_no_stray_files_from_a_probe(work, capsys):
    """Checking that an output can be written leaves no probe file behind."""
    from catwalk.fileio import check_writable

    before = set(os.listdir(work))
    check_writable(work / "out.json", "-o")
    assert set(os.listdir(work)) == before


@pytest.mark.parametrize("args,message", [
    (["--plane-band", "0.2"], "plane_band must be within 0–0.05 m, got 0.2"),
    (["--min-collisions", "0"], "need 1 <= min_collisions <= max_collisions"),
    (["--max-move", "-0.01"], "setting max_move must be a positive number"),
    (["--integrator", "xpbd", "--xpbd-dt", "0.1"], "setting xpbd_dt must be within"),
    (["--integrator", "xpbd", "--xpbd-iterations", "0"],
     "setting xpbd_iterations must be a whole number within 1–100, got 0"),
    (["--skips-off", "sleep"], "skips_off must be a list of the collider's skips "
     "(unreached_parts, still_torso, far_points, reuse_closest, clearance), got ('sleep',)"),
    (["--seconds", "20"], "--seconds must be within 0.5–10")])
def test_bench_paper_refuses_bad_walk_settings_before_any_work(work, capsys, args, message):
    refused(["bench", "paper", "--json", *args], capsys, work, message)


@pytest.mark.parametrize("args,message", [
    (["--plane-band", "0.2"], "plane_band must be within 0–0.05 m, got 0.2"),
    (["--min-collisions", "0"], "need 1 <= min_collisions <= max_collisions")])
def test_bench_stress_refuses_bad_walk_settings_before_any_work(work, capsys, args, message):
    refused(["bench", "stress", "--axes", "garment", "--json", *args], capsys, work, message)
