"""The fast kernels against plain references: the run-based force loop must give the plain loop
over springs to the last bit, and the ordered pass that visits only the points near over-long
springs must give what visiting every point gives."""

import numpy as np
import pytest

from catwalk.cloth import contact_planes, springs, strain_limit
from catwalk.cloth.builder import Panel, build_cloth, circle, rectangle, vertical
from catwalk.cloth.scenes import hanging_cloth
from catwalk.cloth.solvers.explicit import kernels as K
from catwalk.cloth.solvers.explicit.solver import Solver
from catwalk.cloth.springs import SOFT_BAND
from catwalk.cloth.state import State


def _irregular_model():
    """A rectangle and a disc (off-grid outline points: many runs of length 1)."""
    return build_cloth([Panel(rectangle(0.3, 0.2), placement=vertical((0, 1, 0))),
                        Panel(circle(0.1, 37, (0.1, 0.1)), placement=vertical((0.4, 1, 0)))],
                       fabric="cotton-jersey", h=0.02)


def _reference_forces(m, x, v, gravity, air):
    """The plain loop over springs in storage order, in numpy (no fused multiply-add)."""
    sa, sb = m.spring_a, m.spring_b
    f = m.mass[:, None] * (gravity[None, :] - air * v)
    d = x[sb] - x[sa]
    ll = np.sqrt(d[:, 0] * d[:, 0] + d[:, 1] * d[:, 1] + d[:, 2] * d[:, 2])
    with np.errstate(divide="ignore", invalid="ignore"):
        nrm = d * (1.0 / ll)[:, None]
    dv = v[sb] - v[sa]
    rv = dv[:, 0] * nrm[:, 0] + dv[:, 1] * nrm[:, 1] + dv[:, 2] * nrm[:, 2]
    rest = m.spring_rest
    e = ll - rest
    cp = m.fabric.compression
    band = SOFT_BAND * rest
    soft = np.where(e > -band, e + (1.0 - cp) * e * e / (2.0 * band),
                    cp * e - (1.0 - cp) * 0.5 * band)
    comp = (e < 0.0) & (np.arange(len(sa)) < m.n_limited)
    fs = m.spring_k * np.where(comp, soft, e) + m.spring_c * rv
    fs = np.where(ll < 1e-12, 0.0, fs)
    fv = fs[:, None] * nrm
    # each point receives its springs' forces in storage order (np.add.at is sequential)
    idx = np.column_stack([sa, sb]).ravel()
    val = np.stack([fv, -fv], axis=1).reshape(-1, 3)
    np.add.at(f, idx, val)
    return f


def test_spring_runs_cover_every_spring_once_in_storage_order():
    m = _irregular_model()
    runs, n_runs_lim = springs.model_runs(m.spring_a, m.spring_b, m.n_limited)
    s = np.concatenate([r[0] + np.arange(r[3]) for r in runs])
    assert np.array_equal(s, np.arange(m.n_springs))  # each once, in storage order
    a = np.concatenate([r[1] + np.arange(r[3]) for r in runs])
    b = np.concatenate([r[2] + np.arange(r[3]) for r in runs])
    assert np.array_equal(a, m.spring_a) and np.array_equal(b, m.spring_b)
    assert runs[n_runs_lim - 1, 0] + runs[n_runs_lim - 1, 3] == m.n_limited
    assert runs[:, 3].max() <= springs.RUN_CHUNK
    # Provot's grid is mostly long runs
    grid, _ = hanging_cloth(0.6, 0.6, h=0.02)
    gr, _ = springs.model_runs(grid.spring_a, grid.spring_b, grid.n_limited)
    assert gr[gr[:, 3] >= 8, 3].sum() > 0.9 * grid.n_springs


@pytest.mark.parametrize("scale", [0.97, 1.0, 1.08])
def test_run_forces_equal_the_plain_spring_loop_bit_for_bit(scale):
    m = _irregular_model()
    rng = np.random.default_rng(3)
    c = m.rest_positions.mean(axis=0)
    # stretched, compressed (in and beyond the soft band) and sheared springs, moving points
    x = c + scale * (m.rest_positions - c) + rng.normal(0, 0.002, (m.n_points, 3))
    v = rng.normal(0, 0.3, (m.n_points, 3))
    gravity = np.array([0.0, -9.81, 0.0])
    runs, n_runs_lim = springs.model_runs(m.spring_a, m.spring_b, m.n_limited)
    F = np.zeros((3, m.n_points))
    none = np.zeros(0, dtype=np.int32)
    K.accumulate_forces(np.ascontiguousarray(x.T), np.ascontiguousarray(v.T), m.mass, runs,
                        n_runs_lim, m.spring_rest, m.spring_k, m.spring_c, m.fabric.compression,
                        gravity, m.fabric.air, none, none, 0.0, F)
    ref = _reference_forces(m, x, v, gravity, m.fabric.air)
    assert np.array_equal(F.T, ref)


@pytest.mark.parametrize("share", [False, True])
def test_ordered_pass_on_marked_points_equals_the_pass_over_every_point(share):
    m, st = hanging_cloth(0.4, 0.4, h=0.02, pins="corners")  # two clusters: fronts meet
    sol = Solver(m, "ordered", share=share)
    sol.run(m, st, 0.2)
    rng = np.random.default_rng(5)
    n = m.n_points
    X = np.ascontiguousarray(st.positions.T)
    V = np.ascontiguousarray(st.velocities.T)
    kicked = rng.random(n) < 0.08
    V[:, kicked] += rng.normal(0, 8.0, (3, kicked.sum()))  # a few points ±2 mm a step
    dt = sol.dt_max
    order = sol.processing_order(st)
    pts, ptr, _, oth, _, cross = order
    assert cross.sum() > 0
    results = []
    for everything in (False, True):
        Vw = V.copy()
        XP = np.zeros((3, n))
        R = np.zeros((3, n))
        dirty = np.zeros(n, dtype=np.uint8)
        K.predict(X, Vw, dt, XP)
        strain_limit.mark_overstretched(XP, sol._runs, sol._n_runs_lim, m.spring_rest, sol.tau,
                                        dirty)
        if everything:
            assert 0.05 * n < dirty.sum() < 0.8 * n
            dirty[:] = 1
        strain_limit.limit_ordered_velocity(XP, Vw, sol._w_lim, dt, pts, ptr, oth, cross,
                                            sol._order_lim, sol._order_lim2,
                                            sol._order_pt_cross, 2, 1.0, R, share, dirty,
                                            m.adj_ptr, m.adj_other,
                                            np.empty(16, dtype=np.int64), np.empty((16, 3)))
        results.append((Vw, XP, R))
    for a, b in zip(*results, strict=True):
        assert np.array_equal(a, b)
    assert not np.array_equal(results[0][0], V)  # the pass did correct something


def test_solver_results_do_not_depend_on_how_steps_are_grouped():
    """One kernel call of 50 steps = 50 calls of one step (the (3, n) copies in and out)."""
    m, st = hanging_cloth(0.3, 0.3, h=0.03, pins="corners")
    a, b = st.copy(), st.copy()
    sa, sb = Solver(m, "ordered"), Solver(m, "ordered")
    sa.step(m, a, None, 50 * sa.dt_max)
    for _ in range(50):
        sb.step(m, b, None, sb.dt_max)
    assert np.array_equal(a.positions, b.positions)
    assert np.array_equal(a.velocities, b.velocities)
    assert sa.last_speed(a) == sb.last_speed(b)


def test_a_cloth_with_irregular_outlines_runs():
    m = _irregular_model()
    st = State.from_model(m)
    st.pinned[0] = True
    sol = Solver(m, "ordered")
    sol.run(m, st, 0.05)
    assert np.all(np.isfinite(st.positions))


def test_seam_damping_is_implicit_pair_by_pair_and_keeps_momentum():
    rng = np.random.default_rng(3)
    n = 6
    V = rng.normal(0, 1.0, (3, n))
    w = np.array([1.0 / 2e-5, 1.0 / 3e-5, 1.0 / 5e-5, 0.0, 1.0 / 4e-5, 1.0 / 1e-5])
    sa = np.array([0, 2, 4], dtype=np.int32)
    sb = np.array([1, 3, 5], dtype=np.int32)
    c, dt = 0.05, 1e-3          # dt·c·w ≫ 1: explicit damping would overshoot and flip
    V0 = V.copy()
    K.damp_seams(V, sa, sb, w, c, dt)
    for a, b in zip(sa, sb, strict=True):
        rel0 = V0[:, b] - V0[:, a]
        rel = V[:, b] - V[:, a]
        assert np.allclose(rel, rel0 / (1.0 + dt * c * (w[a] + w[b])))
        m = np.where(w[[a, b]] > 0, 1.0 / np.maximum(w[[a, b]], 1e-300), 0.0)
        if w[a] > 0 and w[b] > 0:   # momentum of the pair kept
            assert np.allclose(m[0] * V[:, a] + m[1] * V[:, b],
                               m[0] * V0[:, a] + m[1] * V0[:, b])
    assert np.array_equal(V[:, 3], V0[:, 3])   # a pinned point (w = 0) is not moved
    # the same as the explicit damping force for small dt·c·w
    V = V0.copy()
    K.damp_seams(V, sa, sb, w, 1e-9, 1e-6)
    a, b = 0, 1
    f = 1e-9 * (V0[:, b] - V0[:, a])
    assert np.allclose(V[:, a] - V0[:, a], 1e-6 * w[a] * f, rtol=1e-6)


def test_planes_set_takes_the_points_with_a_plane_in_point_order():
    rng = np.random.default_rng(5)
    planes = np.zeros((50, 8))
    have = rng.random(50) < 0.4
    nrm = rng.normal(size=(50, 3))
    planes[have, :3] = nrm[have] / np.linalg.norm(nrm[have], axis=1)[:, None]
    planes[have, 3:] = rng.normal(size=(int(have.sum()), 5))
    idx = np.full(50, -1, dtype=np.int64)
    rows = np.zeros((50, 8))
    m = contact_planes.planes_set(planes, idx, rows)
    assert m == have.sum()
    assert np.array_equal(idx[:m], np.flatnonzero(have))
    assert np.array_equal(rows[:m], planes[have])


def test_cap_speed_slows_only_the_points_above_it_to_it():
    rng = np.random.default_rng(6)
    v = rng.normal(0.0, 8.0, (200, 3))
    before = v.copy()
    speed = np.linalg.norm(before, axis=1)
    fast = speed > 10.0
    assert 0 < fast.sum() < 200
    assert contact_planes.cap_speed(v, 10.0) == fast.sum()
    assert np.array_equal(v[~fast], before[~fast])
    assert np.allclose(np.linalg.norm(v[fast], axis=1), 10.0, rtol=1e-12)
    assert np.allclose(v[fast] / np.linalg.norm(v[fast], axis=1)[:, None],
                       before[fast] / speed[fast, None], rtol=1e-12)


def _provot_every_spring(X, V, w, sa, sb, rest, n_lim, tau, dt, iterations):
    """Provot's correction measuring every spring every round (plain Python)."""
    for _ in range(iterations):
        changed = False
        for s in range(n_lim):
            a, b = sa[s], sb[s]
            wsum = w[a] + w[b]
            if wsum == 0.0:
                continue
            d = [X[q, b] - X[q, a] for q in range(3)]
            ll = np.sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2])
            lim = (1.0 + tau) * rest[s]
            if ll <= lim:
                continue
            changed = True
            g = (ll - lim) / (ll * wsum)
            ga, gb = w[a] * g, w[b] * g
            for q in range(3):
                X[q, a] += ga * d[q]
            for q in range(3):
                X[q, b] -= gb * d[q]
            for q in range(3):
                V[q, a] += ga * d[q] * (1.0 / dt)
            for q in range(3):
                V[q, b] -= gb * d[q] * (1.0 / dt)
        if not changed:
            break


def test_provot_measures_again_only_springs_whose_ends_moved_and_gives_the_full_rounds():
    m = _irregular_model()
    rng = np.random.default_rng(7)
    c = m.rest_positions.mean(axis=0)
    x = c + 1.05 * (m.rest_positions - c) + rng.normal(0, 0.003, (m.n_points, 3))
    v = rng.normal(0, 0.1, (m.n_points, 3))
    w = 1.0 / m.mass
    w[rng.random(m.n_points) < 0.1] = 0.0   # held points
    for iterations in (1, 4, 8):
        X, V = np.ascontiguousarray(x.T), np.ascontiguousarray(v.T)
        Xr, Vr = X.copy(), V.copy()
        strain_limit.limit_provot_positions(X, V, w, m.spring_a, m.spring_b, m.spring_rest,
                                            m.n_limited, 0.05, 1e-3, iterations)
        _provot_every_spring(Xr, Vr, w, m.spring_a, m.spring_b, m.spring_rest, m.n_limited,
                             0.05, 1e-3, iterations)
        assert np.array_equal(X, Xr) and np.array_equal(V, Vr)
        assert not np.array_equal(X, x.T)


def test_provot_stops_at_a_round_that_moves_nothing_as_the_full_rounds_do():
    m = _irregular_model()
    x = m.rest_positions.copy()
    x[m.n_points // 2] += (0.003, 0.0, 0.006)   # one point pulled: its springs too long
    w = 1.0 / m.mass
    X, V = np.ascontiguousarray(x.T), np.zeros((3, m.n_points))
    Xr, Vr = X.copy(), V.copy()
    strain_limit.limit_provot_positions(X, V, w, m.spring_a, m.spring_b, m.spring_rest,
                                        m.n_limited, 0.05, 1e-3, 50)
    _provot_every_spring(Xr, Vr, w, m.spring_a, m.spring_b, m.spring_rest, m.n_limited, 0.05,
                         1e-3, 50)
    assert np.array_equal(X, Xr) and np.array_equal(V, Vr)
    # converged before the 50th round: the last round found every spring within its limit
    d = X[:, m.spring_b[:m.n_limited]] - X[:, m.spring_a[:m.n_limited]]
    assert (np.sqrt((d * d).sum(axis=0)) <= 1.05 * m.spring_rest[:m.n_limited]).all()
    assert not np.array_equal(X, x.T)
