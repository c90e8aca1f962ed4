"""The try-on end to end on a small scene: the pencil skirt at h = 3 cm, the fast preset,
on the female base body, walking one gait cycle."""

import json

import numpy as np
import pytest

from catwalk.cli.main import main
from catwalk.exchange.garment_json import load_garment
from catwalk.geometry.surface import BodySurface, penetration
from catwalk.simulate import Cancelled, dress, preset

SKIRT = "garments/pencil-skirt.json"
FAST = ["--preset", "fast", "--h", "0.03", "--quiet"]


@pytest.fixture(scope="module")
def skirt(repo_root):
    return load_garment(repo_root / SKIRT)


@pytest.fixture(scope="module")
def dressed(dressable_body, skirt):
    return dress(dressable_body, skirt, "M", settings=preset("fast").with_(h=0.03))


def test_dress_closes_every_seam_and_stays_outside(dressable_body, dressed):
    st = dressed.stats
    assert st["open_seam_pairs"] == 0
    assert st["seam_gap_start_m"] > 0.05          # the pieces started well apart
    assert dressed.model.n_points < dressed.cloth.model.n_points   # seams are now shared
    pts = dressed.pattern_positions()
    # partners of every seam are one particle now
    m = dressed.cloth.model
    assert np.allclose(pts[m.seam_a], pts[m.seam_b])
    pen = penetration(BodySurface(dressable_body.faces, len(dressable_body.vertices)),
                      dressable_body.vertices, pts)
    assert pen.max() < 0.002
    # the skirt hangs from the hips: its top above the crotch, its hem below it
    crotch = dressable_body.landmarks["crotch"][1]
    assert pts[:, 1].max() > crotch + 0.1 and pts[:, 1].min() < crotch - 0.15


def test_dress_cancel(dressable_body, skirt):
    calls = []

    def cancel():
        calls.append(1)
        return len(calls) > 3

    with pytest.raises(Cancelled):
        dress(dressable_body, skirt, "M", settings=preset("fast").with_(h=0.03), cancel=cancel)
    assert len(calls) == 4


def test_tryon_cli_end_to_end(body_glb, tmp_path, repo_root, capsys):
    from catwalk.body.skinning import body_frames
    from catwalk.exchange.gltf import read_body, read_motion, validate
    from catwalk.exchange.tryon_glb import read_garments

    out = tmp_path / "tryon.glb"
    metrics = tmp_path / "metrics.json"
    rc = main(["tryon", "--body", str(body_glb), "--garment", str(repo_root / SKIRT),
               "--seconds", "1", *FAST, "-o", str(out), "--metrics", str(metrics),
               "--iv", str(tmp_path / "dressed.iv")])
    assert rc == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary["file"] == str(out)
    report = validate([out])[0]
    assert report["numErrors"] == 0, report["messages"][:5]
    m = json.loads(metrics.read_text())
    for key in ("points", "springs", "body_triangles", "substeps_per_frame",
                "dressing_seconds", "ms_per_frame", "max_penetration_mm",
                "p99_penetration_mm", "max_strain", "max_seam_gap_mm", "nan", "exploded"):
        assert key in m, key
    assert set(m["ms_per_frame"]) >= {"body", "collider", "cloth"}
    # the springs over τ + 2 % (spring-frames), and of those the ones across the body
    assert 0 <= m["over_limit_crossing_body"] <= m["springs_over_limit"]
    assert not m["nan"] and not m["exploded"]
    # independent check: skin the body from the file, read the garment frames back
    body = read_body(out)
    motion = read_motion(out)
    (garment,) = read_garments(out)
    assert garment.frames == motion.frames == m["frames"]
    verts, _ = body_frames(body, motion)
    surface = BodySurface(body.faces, len(body.vertices))
    worst = max(float(penetration(surface, verts[f], garment.positions[f]).max())
                for f in range(garment.frames))
    assert worst <= 0.002
    # the garment moved with the body: the hip point travelled as far as the walk did
    walked = float(verts[-1][:, 2].mean() - verts[0][:, 2].mean())
    moved = float(garment.positions[-1][:, 2].mean() - garment.positions[0][:, 2].mean())
    assert walked > 0.5 and abs(moved - walked) < 0.1
    assert (tmp_path / "dressed.iv").read_text().startswith("#Inventor V2.1 ascii")


def test_tryon_interrupt_leaves_no_file(body_glb, tmp_path, repo_root, monkeypatch):
    import catwalk.cli.tryon as cmds

    class Stop(cmds.ProgressBar):
        def __call__(self, stage, done, total=1.0):
            if stage == "walking":
                raise KeyboardInterrupt

    monkeypatch.setattr(cmds, "ProgressBar", Stop)
    out = tmp_path / "tryon.glb"
    rc = main(["tryon", "--body", str(body_glb), "--garment", str(repo_root / SKIRT),
               "--seconds", "1", *FAST, "-o", str(out)])
    assert rc == 130
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("args, message", [
    (["--body", "nope.glb"], "no such file"),
    (["--size", "XXXL"], "no size"),
    (["--seconds", "0"], "--seconds"),
    (["--fabric", "cardboard"], "unknown fabric"),
    (["-o", "out.obj"], ".glb"),
])
def test_tryon_bad_arguments_exit_2(body_glb, tmp_path, repo_root, capsys, args, message):
    base = {"--body": str(body_glb), "--garment": str(repo_root / SKIRT),
            "-o": str(tmp_path / "t.glb")}
    argv = ["tryon"]
    for i in range(0, len(args), 2):
        base[args[i]] = args[i + 1]
    for k, v in base.items():
        argv += [k, v]
    rc = main(argv + FAST)
    assert rc == 2
    assert message in capsys.readouterr().err
    assert not (tmp_path / "t.glb").exists()


@pytest.mark.parametrize("flag", ["-o", "--metrics", "--iv", "--obj-dir"])
def test_tryon_refuses_an_unwritable_output_before_simulating(body_glb, tmp_path, repo_root,
                                                              capsys, monkeypatch, flag):
    import catwalk.simulate.tryon as entry

    def never(*a, **k):
        raise AssertionError("simulated before checking the outputs")

    monkeypatch.setattr(entry, "tryon", never)
    blocker = tmp_path / "a-file"
    blocker.write_text("not a folder")
    out = {"-o": str(tmp_path / "t.glb")}
    out[flag] = str(blocker / ("t.glb" if flag == "-o" else "x"))
    argv = ["tryon", "--body", str(body_glb), "--garment", str(repo_root / SKIRT), *FAST]
    for k, v in out.items():
        argv += [k, v]
    assert main(argv) == 2
    assert "not a writable folder" in capsys.readouterr().err
    assert sorted(tmp_path.iterdir()) == [blocker] and blocker.read_text() == "not a folder"


def test_dress_cli_writes_a_valid_static_glb(body_glb, tmp_path, repo_root, capsys):
    from catwalk.exchange.gltf import validate
    from catwalk.exchange.tryon_glb import read_garments

    out = tmp_path / "dressed.glb"
    rc = main(["dress", "--body", str(body_glb), "--garment", str(repo_root / SKIRT),
               "--size", "S", *FAST, "-o", str(out), "--iv", str(tmp_path / "d.iv"),
               "--metrics", str(tmp_path / "m.json")])
    assert rc == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary["max_seam_gap_mm"] == 0.0 and summary["file"] == str(out)
    assert validate([out])[0]["numErrors"] == 0
    (garment,) = read_garments(out)
    assert garment.frames == 1 and len(garment.panel_names) >= 3
    assert json.loads((tmp_path / "m.json").read_text())["points"] > 100
    assert (tmp_path / "d.iv").stat().st_size > 1000
    # a garment that is not there: exit 2, nothing written
    rc = main(["dress", "--body", str(body_glb), "--garment", str(tmp_path / "nope.json"),
               *FAST, "-o", str(tmp_path / "x.glb")])
    assert rc == 2 and not (tmp_path / "x.glb").exists()


def test_a_simulation_that_fails_exits_3_and_writes_nothing(body_glb, tmp_path, repo_root,
                                                            capsys, monkeypatch):
    """The simulation's failure (here: a dressing that does not close its seams) is not the
    user's input: exit 3, its reason printed, no file."""
    import catwalk.simulate.tryon as entry
    from catwalk.simulate.dressing import DressingError

    def fails(*a, **k):
        raise DressingError("garment 'x' size M: these seams are still open: 'side' by 4.0 cm")

    monkeypatch.setattr(entry, "dress", fails)
    out = tmp_path / "t.glb"
    rc = main(["tryon", "--body", str(body_glb), "--garment", str(repo_root / SKIRT),
               *FAST, "-o", str(out)])
    assert rc == 3
    err = capsys.readouterr().err
    assert "still open" in err and "Traceback" not in err
    assert not out.exists()


def test_a_settling_that_blows_up_is_run_again_with_twice_the_resolves(dressable_body, skirt,
                                                                        monkeypatch):
    import catwalk.simulate.dressing as dressing
    from catwalk.cloth.solvers import ClothExplosionError

    settings = preset("fast").with_(h=0.03)
    real, calls = dressing.advance, []

    def advance(solver, model, state, collider, duration, collisions, *args, **kw):
        # the first settling interval blows up (a fault injected where the bodice S tore on
        # one machine); everything else runs as it does
        calls.append(collisions)
        if collisions == settings.settle_collisions and calls.count(collisions) == 1:
            raise ClothExplosionError("injected")
        return real(solver, model, state, collider, duration, collisions, *args, **kw)

    monkeypatch.setattr(dressing, "advance", advance)
    d = dress(dressable_body, skirt, "M", settings=settings)
    assert d.stats["settle_retries"] == 1
    assert d.stats["settle_collisions"] == 2 * settings.settle_collisions
    assert d.stats["open_seam_pairs"] == 0
