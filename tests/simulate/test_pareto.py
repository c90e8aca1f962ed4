"""``catwalk bench pareto``'s comparison with the reference run: zero for identical settings,
growing with the time step; the Pareto front."""

import numpy as np

from catwalk.bench.pareto import pareto_front, reference_settings, surface_rms
from catwalk.cloth.scenes import hanging_cloth
from catwalk.cloth.solver import Solver
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


def test_the_front():
    pts = [(1.0, 5.0), (2.0, 3.0), (3.0, 4.0), (4.0, 1.0), (2.0, 3.0)]
    assert pareto_front(pts) == [True, True, False, True, True]


def test_the_reference_is_finer_in_every_setting():
    base = preset("balanced")
    ref = reference_settings(base)
    assert ref.collider == "object" and not ref.skips
    assert ref.step_safety == base.step_safety / 4 and ref.max_move == base.max_move / 4
    assert ref.min_collisions == 4 * base.min_collisions and ref.h <= base.h
