"""``catwalk bench pareto``'s comparison with the reference run: zero for identical settings,
growing with the time step; the Pareto front."""

import numpy as np

from catwalk.bench.pareto import format_table, pareto_front, reference_settings, surface_rms
from catwalk.cloth.scenes import hanging_cloth
from catwalk.cloth.solvers.explicit.solver import Solver
from catwalk.collide import Skips
from catwalk.simulate import preset


def _swing(safety: float, frames: int = 12) -> tuple[np.ndarray, np.ndarray]:
    """A cloth pinned at two corners swinging down from horizontal-ish: positions per 1/30 s
    with steps of ``safety`` × the stable step."""
    model, state = hanging_cloth(0.3, 0.3, h=0.03, pins="corners")
    state.positions[:, 2] = (state.positions[:, 1] - 1.5) * 0.9   # tilted towards the viewer
    solver = Solver(model, "ordered", safety=safety)
    out = []
    for _ in range(frames):
        solver.step(model, state, None, 1.0 / 30.0)
        out.append(state.positions.copy())
    return np.array(out), model.triangles


def test_identical_runs_compare_to_zero_and_the_error_grows_with_the_step():
    ref, tri = _swing(0.05)
    again, _ = _swing(0.05)
    assert surface_rms(ref, tri, again, tri) == 0.0
    errs = [surface_rms(_swing(s)[0], tri, ref, tri) for s in (0.1, 0.3, 0.9)]
    assert 0.0 < errs[0] < errs[1] < errs[2], errs


def test_each_skip_is_a_run_of_its_own():
    from catwalk.bench.pareto import default_runs

    runs = dict(default_runs(["balanced"]))
    for name in Skips.names():
        ch = runs[f"balanced, skip {name} off"]
        skips = preset("balanced").with_(skips_off=ch["skips_off"]).collider_options()["skips"]
        assert [k for k, on in vars(skips).items() if not on] == [name]
    assert runs["balanced, skips off"] == {"preset": "balanced", "skips": False}


def test_the_front():
    pts = [(1.0, 5.0), (2.0, 3.0), (3.0, 4.0), (4.0, 1.0), (2.0, 3.0)]
    assert pareto_front(pts) == [True, True, False, True, True]


def test_the_reference_is_finer_in_every_setting():
    base = preset("balanced")
    ref = reference_settings(base)
    assert ref.collider == "object" and not ref.skips
    assert ref.step_safety == base.step_safety / 4 and ref.max_move == base.max_move / 4
    assert ref.min_collisions == 4 * base.min_collisions and ref.h <= base.h


def test_the_table_marks_the_front_and_failed_runs():
    ref = {"settings": {"h": 0.01}, "points": 100, "ms_per_frame": 900.0}
    run = {"label": "preset fast", "points": 50, "ms_per_frame": 20.0, "rms_mm": 12.5,
           "max_penetration_mm": 0.0, "p99_penetration_mm": 0.0, "max_strain": 0.2,
           "p99_strain": 0.1, "max_seam_gap_mm": 0.0, "pareto": True}
    r = {"seconds": 2.0, "frames": 53, "machine": {"cpu": "test"}, "reference": ref,
         "noise_mm": 9.0, "runs": [run, {"label": "image", "failed": "exploded"}]}
    t = format_table(r)
    assert "| preset fast | 50 | 20.0 | 12.5 |" in t and "**yes**" in t
    assert "| image | | failed: exploded |" in t
    assert "noise floor (reference vs itself moved 0.1 mm): 9.0 mm RMS" in t
