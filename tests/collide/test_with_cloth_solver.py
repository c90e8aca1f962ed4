"""The collider driven by the cloth solver (catwalk.cloth), through its real interface."""

import numpy as np
import pytest

from catwalk.cloth import builder as cloth
from catwalk.cloth.solvers.explicit import solver as solver_mod
from catwalk.cloth.state import State
from catwalk.collide import make_collider
from catwalk.collide.shapes import sphere


@pytest.mark.parametrize("mode", ["hybrid", "object"])
def test_cloth_dropped_on_a_sphere_drapes_over_it(mode):
    centre, R = np.array([0.0, 1.0, 0.0]), 0.12
    v, f = sphere(centre, R, 48, 24)
    part = 0 if mode == "hybrid" else 1  # the torso's maps, or a limb's hierarchy
    col = make_collider(mode, f, np.full(len(v), part, np.int8))
    # a 40 cm square, 2 cm above the top of the sphere
    place = cloth.horizontal(centre[1] + R + 0.02)
    model = cloth.build_cloth([cloth.Panel(cloth.rectangle(0.4, 0.4), placement=place)],
                              fabric="cotton-jersey", h=0.02)
    state = State.from_model(model)
    state.positions[:, 0] -= 0.2
    state.positions[:, 2] += 0.2
    solver = solver_mod.Solver(model)
    col.update(v)
    for _ in range(12):  # 12 frames of 1/30 s
        col.update(v)
        solver.step(model, state, col, 1.0 / 30.0)
    d = np.linalg.norm(state.positions - centre, axis=1)
    assert d.min() > R * 0.98  # nothing went through
    # the middle rests on the sphere; the edges have fallen below its top
    mid = np.argmin(np.linalg.norm(state.positions[:, [0, 2]] - centre[[0, 2]], axis=1))
    assert d[mid] < R + 0.006
    assert state.positions[:, 1].min() < centre[1] + R - 0.03
    assert state.held.sum() > 50
    if mode == "object":
        # (the very top is edge-on to the depth maps' cameras: held there only in hierarchies)
        assert state.held[mid]
