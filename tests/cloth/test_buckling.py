"""Compression that buckles: a strip whose ends are pushed together shortens, folding out of
its plane, and pushes back no harder than its compressive law (``cloth/springs.py``: the
stretch and shear springs at ``fabric.compression`` of their tensile stiffness beyond a 1 %
band) gives for the strip compressed flat — at 10 % a tenth of what the same stretch pulls."""

import numpy as np
import pytest

from catwalk.cloth import bending as B
from catwalk.cloth import springs
from catwalk.cloth.builder import Panel, build_cloth, rectangle
from catwalk.cloth.solvers.explicit import kernels as K
from catwalk.cloth.solvers.explicit.solver import Solver
from catwalk.cloth.state import State

LENGTH, WIDTH, PUSH = 0.2, 0.025, 0.02


def _push_back(model, x, ends, q) -> float:
    """The force (N) along +x with which the cloth at rest at ``x`` pushes the ``ends``."""
    X = np.ascontiguousarray(x.T)
    F = np.zeros_like(X)
    runs, n_lim = springs.model_runs(model.spring_a[:model.n_limited],
                                     model.spring_b[:model.n_limited], model.n_limited)
    none = np.zeros(0, np.int32)
    K.accumulate_forces(X, np.zeros_like(X), model.mass, runs, n_lim, model.spring_rest,
                        model.spring_k, model.spring_c, model.fabric.compression,
                        np.zeros(3), 0.0, none, none, 0.0, F)
    _, _, k, bruns = B.bending_pairs(q)
    B.add_bending_forces(X, np.zeros_like(X), bruns, k, np.zeros_like(k), F)
    return float(F[0, ends].sum())


@pytest.mark.parametrize("fabric", ["m1", "denim"])
def test_a_strip_pushed_together_buckles_and_pushes_back_no_more_than_its_law(fabric):
    m = build_cloth([Panel(rectangle(LENGTH, WIDTH))], fabric=fabric, h=0.01)
    st = State.from_model(m)
    x0 = m.rest_positions[:, 0]
    left, right = x0 <= 0.01 + 1e-9, x0 >= LENGTH - 0.01 - 1e-9
    st.pinned[left | right] = True
    st.positions[:, 2] += np.random.default_rng(0).uniform(-1e-4, 1e-4, m.n_points)
    solver = Solver(m, "ordered", gravity=(0.0, 0.0, 0.0), extra_air=10.0)
    for i in range(40):                                      # the push, 0.4 s
        st.positions[right, 0] = m.rest_positions[right, 0] - PUSH * (i + 1) / 40
        solver.step(m, st, None, 0.01)
    solver.run(m, st, 1.0)                                   # held there
    q = B.bending_matrix(m, still=st.pinned)
    ends = np.flatnonzero(right)
    buckled = _push_back(m, st.positions, ends, q)
    flat = m.rest_positions.copy()
    flat[:, 0] *= (LENGTH - PUSH) / LENGTH                   # the same shortening, in its plane
    law = _push_back(m, flat, ends, q)
    assert np.abs(st.positions[:, 2]).max() > 0.01           # it folded out of its plane
    assert 0.0 <= buckled <= law, (buckled, law)
    # the law itself: at 10 % a tenth of the tension (5 % of k beyond the 1 % band)
    tension = flat.copy()
    tension[:, 0] = m.rest_positions[:, 0] * (LENGTH + PUSH) / LENGTH
    assert law < -0.11 * _push_back(m, tension, ends, q)
