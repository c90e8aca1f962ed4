"""``catwalk bench peers``: the scene a peer reads, the measures every run is judged by (the
same as the walk's own), and the harness that runs a peer process and reads its result.

The peers themselves (Blender, Newton) are not installed by ``make test``; here a stand-in
peer (a Python script following the same contract: read the scene, write the garment per frame
and the seconds per frame) runs through the same harness."""

import json
import sys
import textwrap

import numpy as np
import pytest

from catwalk.bench import peers
from catwalk.bench.peers.scene import PeerScene, measure, rms_mm, welded


@pytest.fixture(scope="module")
def scene(dressable_body):
    from catwalk.catalogue.garments import catalogue_files
    from catwalk.exchange.garment_json import load_garment
    from catwalk.motion.gait import walk_motion
    from catwalk.simulate import dress, preset
    from catwalk.simulate.walking import walk_body_frames

    skirt = load_garment(next(p for p in catalogue_files() if p.stem == "pencil-skirt"))
    settings = preset("fast").with_(settle_seconds=0.5)
    dressed = dress(dressable_body, skirt, "M", settings=settings)
    motion = walk_motion(dressable_body, 0.5, style="catwalk")
    frames, _, n_pre = walk_body_frames(dressable_body, motion, settings)
    return PeerScene(dressable_body, dressed, motion, settings, frames, n_pre, settings.h)


def test_the_scene_file_holds_what_a_peer_reads(scene, tmp_path):
    s = np.load(scene.save(tmp_path / "scene.npz"))
    n = scene.dressed.model.n_points
    assert s["cloth_positions"].shape == (n, 3) and s["cloth_mass"].shape == (n,)
    assert s["cloth_triangles"].max() < n
    assert s["body_frames"].shape == (len(scene.frames), len(scene.body.vertices), 3)
    assert int(s["record_from"]) == scene.n_pre and len(scene.recorded) == scene.motion.frames
    # frame 0 is the pose the garment was dressed on
    np.testing.assert_allclose(s["body_frames"][0], scene.body.vertices, atol=1e-6)
    assert float(s["stretch"]) > 0 and float(s["bend"]) > 0 and float(s["thickness"]) > 0


def test_the_measures_are_the_walks_own(scene):
    from catwalk.simulate.walking import walk

    # object space (the bench's second catwalk row): its counters have the invariant below
    w = walk(scene.body, scene.motion, scene.dressed, scene.settings.with_(collider="object"))
    pos = welded(scene.dressed, w.positions)
    m = measure(scene, pos)
    assert m["finite"]
    assert m["max_penetration_mm"] == pytest.approx(w.stats["max_penetration_mm"], abs=0.01)
    assert m["p99_penetration_mm"] == pytest.approx(w.stats["p99_penetration_mm"], abs=0.01)
    # strain of the positions shown (off the body's sharp vertices); the walk's own figure is
    # of its simulated state: the same but where a sharp vertex pushed a triangle off
    assert m["p99_strain"] == pytest.approx(w.stats["p99_strain"], abs=0.01)
    assert rms_mm(pos, pos) == 0.0
    # the collider's counters over the recorded frames (object space): at every call each
    # point is counted once — far enough not to look, its kept triangle, a search, or out
    # of every part's reach — so the calls are the recorded frames' and no others, plus the
    # points the frame kept looks at again
    c, calls = w.stats["collider_counts"], w.stats["collider_calls"]
    seen = c["clearance_skips"] + c["reused"] + c["boxed"] + c["skipped"]
    assert w.stats["collider"] == "object" and c["boxed"] > 0 and c["contacts"] > 0
    assert 0 < c["rechecked"] < calls * w.stats["points"]
    assert seen == calls * w.stats["points"] + c["rechecked"]
    # a frame's time by stage, in the order a frame runs them: object space draws no maps;
    # the measured stages take most of the frame and no more than all of it ("other", the
    # remainder, is neither negative — a stage counted twice — nor most of the frame — a
    # stage not counted)
    fm, ms = w.stats["frame_ms"], w.stats["ms_per_frame"]
    assert list(fm) == ["normals", "refits", "maps", "image_look_ups", "object_passes",
                        "sharp_push", "position_correction", "cloth_steps", "other"]
    assert fm["maps"] == fm["image_look_ups"] == 0.0
    assert fm["object_passes"] > 0 and fm["position_correction"] > 0 and fm["refits"] > 0
    frame = ms["collider"] + ms["cloth"]
    assert -0.05 <= fm["other"] <= 0.3 * frame, fm
    # cloth pulled 3 cm towards the body's axis is inside it, and the measure says so
    x = pos.copy()
    c = x.mean(axis=1, keepdims=True)
    d = x - c
    d[..., 1] = 0.0
    x -= 0.03 * d / np.maximum(np.linalg.norm(d, axis=-1, keepdims=True), 1e-9)
    inside = measure(scene, x)
    assert inside["max_penetration_mm"] > 10.0 > m["max_penetration_mm"]
    assert rms_mm(x, pos) == pytest.approx(30.0, abs=0.5)
    x[0, 0] = np.nan
    assert measure(scene, x) == {"finite": False}


STILL_PEER = textwrap.dedent("""
    import json, sys, time
    import numpy as np
    s = np.load(sys.argv[1])
    f = s["body_frames"].shape[0]
    pos = np.repeat(s["cloth_positions"][None].astype(np.float32), f, axis=0)
    np.savez(sys.argv[2], positions=pos, frame_seconds=np.full(f - 1, 0.002),
             info=json.dumps({"peer": "still", "error": None}))
""")


def test_a_peer_process_is_run_timed_and_read(scene, tmp_path, monkeypatch):
    runner = tmp_path / "still.py"
    runner.write_text(STILL_PEER)
    monkeypatch.setattr(peers, "_setup", lambda peer: [sys.executable, str(runner)])
    path = scene.save(tmp_path / "scene.npz")
    r = peers.run_peer("still", path, tmp_path / "out.npz", [])
    assert r["error"] is None and r["info"]["peer"] == "still"
    assert r["positions"].shape == (len(scene.frames), scene.dressed.model.n_points, 3)
    assert np.all(r["frame_seconds"] == 0.002) and r["wall_s"] > 0

    row = peers._peer_row(scene, r)
    assert row["ms_per_frame"] == 2.0 and row["finite"] and row["max_penetration_mm"] >= 0

    # a peer that fails says so, with the tail of what it printed, and an earlier run's
    # result in the same place is not taken for this one's
    runner.write_text("import sys\nprint('no licence for the solver', file=sys.stderr)\n"
                      "sys.exit(3)\n")
    bad = peers.run_peer("still", path, tmp_path / "out.npz", [])
    assert "exit 3" in bad["error"] and "no licence" in bad["error"]
    assert "positions" not in bad and not (tmp_path / "out.npz").exists()


def test_a_peer_that_stops_early_is_reported_so(scene):
    f = len(scene.frames)
    pos = np.repeat(scene.dressed.state.positions[None], f, axis=0)
    partial = {"positions": pos[: scene.n_pre + 2], "frame_seconds": np.full(scene.n_pre + 1, 0.5),
               "info": {}, "wall_s": 1.0, "error": "non-finite positions at frame 18"}
    row = peers._peer_row(scene, partial)
    assert row["incomplete"] == 2 and row["ms_per_frame"] == 500.0
    assert row["error"].startswith("non-finite") and "max_penetration_mm" not in row
    early = peers._peer_row(scene, {**partial, "positions": pos[:3],
                                    "frame_seconds": np.full(2, 0.5)})
    assert "ms_per_frame" not in early and early["error"]


def test_blender_runs_once_per_quality():
    runs = peers._peer_runs(["blender", "newton"], {"blender_quality": [10, 20]})
    assert [(name, peer) for name, peer, _ in runs] == [
        ("blender-q10", "blender"), ("blender-q20", "blender"), ("newton", "newton")]
    assert runs[1][2][:2] == ["--quality", "20"]


def test_the_table_names_failed_runs():
    r = {"machine": {"cpu": "cpu"},
         "scene": {"garment": "dress", "size": "M", "points": 10, "triangles": 12,
                   "body_triangles": 100, "frames": 5, "fps": 30.0, "tau": 0.1},
         "runs": {"catwalk-object": {"ms_per_frame": 50.0, "ratio_to_catwalk": 1.0,
                                     "finite": True, "max_penetration_mm": 0.0,
                                     "p99_penetration_mm": 0.0, "max_strain": 0.1,
                                     "p99_strain": 0.09, "rms_to_catwalk_mm": 0.0},
                  "blender-q10": {"ms_per_frame": 400.0, "ratio_to_catwalk": 8.0, "finite": False},
                  "newton": {"error": "could not install newton: no network"}}}
    r["runs"]["blender-q20"] = {"ms_per_frame": 900.0, "incomplete": 3}
    table = peers.format_table(r)
    assert "| blender-q20 | 900.0 |  | stopped after 3 of 5 frames" in table
    assert "| blender-q10 | 400.0 | 8.0 | non-finite" in table
    assert "| newton | failed: could not install newton: no network" in table
    assert json.dumps(r)
