"""`catwalk bench paper`'s table: the worker's dressing time leads and is judged against the
target, the fresh process's is named as such; the walk rows say what blew up."""

from catwalk.bench.paper import PAPER, TARGET, format_table


def _result(warm, fresh):
    walk = {"ms_per_frame": 44.0, "max_penetration_mm": 0.3, "p99_penetration_mm": 0.0,
            "max_strain": 0.5, "p99_strain": 0.1}
    return {"garment": "dress", "size": "M", "h_m": 0.0177, "points": 3378, "springs": 19683,
            "frames": 53, "machine": {"cpu": "test", "threads": 1},
            "sewing_s": fresh, "sewing_warm_s": warm,
            "sewing": {"sewing_s": 0.2, "settling_s": 0.3, "seam_gap_m": 0.0},
            "image": {"exploded": "walk frame 35: a point over 100 m/s"},
            "hybrid": walk, "object": walk, "figure10": {}, "paper": PAPER, "target": TARGET,
            "tryon_4s_warm": {"seconds": 7.9, "walk_seconds": 4.0, "dress_s": 0.6,
                              "walk_s": 7.1, "export_s": 0.2, "glb_mb": 3.1, "points": 4701,
                              "collider": "object", "frames": 120}}


def test_the_worker_time_leads_and_is_judged_against_the_target():
    t = format_table(_result(0.43, 0.52))
    row = next(line for line in t.splitlines() if line.startswith("| sewing the dress"))
    assert row.index("0.43 s in a worker") < row.index("0.52 s")
    assert "fresh process" in row
    assert "sewing ≤ 0.5 s (worker: met)" in t
    assert "sewing ≤ 0.5 s (worker: missed)" in format_table(_result(0.61, 0.7))
    assert "exploded: walk frame 35" in t
    assert "44.0 ms/frame (max penetration 0.30 mm" in t
    assert "7.90 s (dress 0.60 + walk 7.10 + .glb 0.20); target ≤ 2.0 s: missed" in t


def test_the_reference_line_says_the_ratio_and_the_fidelity_or_that_it_was_not_run():
    r = _result(0.43, 0.52)
    assert "explicit reference (a response after every cloth step): not run" in format_table(r)
    r["default"] = {"rms_to_reference_mm": 12.34, "noise_mm": 9.87, "hem_swing_mm": 20.0,
                    "hem_swing_ratio": 0.952}
    r["reference"] = {"collisions_per_frame": {"mean": 95.0}, "ms_per_frame": 210.0,
                      "ratio_to_default": 4.77, "max_penetration_mm": 0.0, "max_strain": 0.3,
                      "hem_swing_mm": 21.0}
    line = next(x for x in format_table(r).splitlines() if x.startswith("explicit reference"))
    assert "95 a frame): 210.0 ms/frame, 4.77× the default's" in line
    assert "per-vertex RMS 12.3 mm (noise floor 9.9 mm)" in line
    assert "hem swing 20.0 against 21.0 mm (ratio 0.952)" in line
    r["reference"] = {"exploded": "walk frame 3: a point over 100 m/s"}
    assert "exploded: walk frame 3" in format_table(r)
