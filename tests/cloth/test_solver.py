import numpy as np
import pytest

from catwalk.cloth.analytic import PlaneCollider
from catwalk.cloth.builder import Panel, Seam, build_cloth, rectangle, vertical
from catwalk.cloth.fabrics import PRESETS
from catwalk.cloth.scenes import hanging_cloth
from catwalk.cloth.solvers import ClothExplosionError
from catwalk.cloth.solvers.explicit.solver import Solver, energy, max_strain
from catwalk.cloth.state import State
from catwalk.errors import CatwalkError

G = -9.81


def test_free_fall_is_the_closed_form_semi_implicit_euler_sequence():
    fab = PRESETS["wool-suiting"].with_(air=0.0)
    m = build_cloth([Panel(rectangle(0.1, 0.1), placement=vertical((0, 2, 0)))], fabric=fab,
                    h=0.05)
    st = State.from_model(m)
    y0 = st.positions[:, 1].copy()
    sol = Solver(m, "ordered")
    dt = 0.5 * sol.dt_max
    for n in range(1, 201):
        sol.step(m, st, None, dt)
        if n in (1, 2, 10, 200):
            # v_n = n·g·dt, y_n = y_0 + g·dt²·n(n+1)/2
            assert np.allclose(st.velocities[:, 1], n * G * dt, rtol=0, atol=1e-9)
            assert np.allclose(st.positions[:, 1], y0 + G * dt * dt * n * (n + 1) / 2,
                               rtol=0, atol=1e-9)
            assert np.allclose(st.velocities[:, [0, 2]], 0, atol=1e-9)


def _two_corner(method, E=50.0, seconds=3.0):
    fab = PRESETS["cotton-jersey"].with_(stretch_warp=E, stretch_weft=E, shear=E / 8, tau=0.05,
                                         air=2.0)
    m, st = hanging_cloth(0.4, 0.4, h=0.02, fabric=fab, pins="corners")
    sol = Solver(m, method, extra_air=3.0)
    sol.run(m, st, seconds)
    worst = 0.0
    for _ in range(50):
        sol.step(m, st)
        worst = max(worst, max_strain(m, st.positions))
    return m, st, sol, worst


def test_ordered_pass_keeps_the_strain_limit_where_one_unordered_pass_does_not():
    tau = 0.05
    m, st, sol, ordered = _two_corner("ordered")
    assert ordered <= tau + 0.005
    assert sol.last_speed(st) < 0.05  # settled, not jittering
    assert sol.order_rebuilds == 1  # the centres (two pins) never changed
    _, _, _, unordered = _two_corner("vassilev")
    _, _, _, free = _two_corner("none")
    assert unordered > tau + 0.01  # measurably beyond the limit
    assert unordered - ordered > 0.01
    assert free > unordered  # and the springs alone stretch far more


def test_processing_order_goes_outward_from_the_centres():
    m, st = hanging_cloth(0.2, 0.2, h=0.02, pins="corners")
    sol = Solver(m, "ordered")
    pts, ptr, spr, oth, level, cross = sol.processing_order(st)
    pinned = np.where(st.pinned)[0]
    assert set(pts[:2]) == set(pinned)
    assert sorted(pts) == list(range(m.n_points))
    rank = np.empty(m.n_points, int)
    rank[pts] = np.arange(m.n_points)
    assert np.all(np.diff(level[pts]) >= 0)  # breadth-first
    for k in range(2, m.n_points):
        earlier = oth[ptr[k]:ptr[k + 1]]
        assert len(earlier) > 0 and np.all(rank[earlier] < k)
        for s, q in zip(spr[ptr[k]:ptr[k + 1]], earlier, strict=True):
            assert {m.spring_a[s], m.spring_b[s]} == {pts[k], q}
    # the two fronts meet half-way: springs across are marked
    assert cross.sum() > 0
    # unchanged centres: no recomputation; a new held point: recomputed
    n0 = sol.order_rebuilds
    sol.step(m, st)
    sol.step(m, st)
    assert sol.order_rebuilds == n0
    st.held[5] = True
    sol.step(m, st)
    assert sol.order_rebuilds == n0 + 1


def test_sag_is_resolution_independent():
    sags = []
    for h in (0.02, 0.01):
        m, st = hanging_cloth(0.4, 0.4, h=h, fabric="cotton-jersey", pins="corners")
        sol = Solver(m, "ordered", extra_air=3.0)
        sol.run(m, st, 1.5)
        assert sol.last_speed(st) < 0.05
        sags.append(1.5 - st.positions[:, 1].min())
    assert sags[0] > 0.39  # it hangs
    assert abs(sags[0] - sags[1]) / sags[1] < 0.05


def test_undamped_cloth_below_the_bound_gains_no_energy():
    fab = PRESETS["cotton-jersey"].with_(damping=0.0, air=0.0)
    m, st = hanging_cloth(0.2, 0.2, h=0.04, fabric=fab, pins="corners")
    sol = Solver(m, "none")
    e0 = energy(m, st)["total"]
    totals, kinetic = [], []
    for _ in range(100):  # 100 × 100 = 10,000 steps at dt_max
        sol.step(m, st, None, 100 * sol.dt_max)
        e = energy(m, st)
        totals.append(e["total"])
        kinetic.append(e["kinetic"])
    assert st.steps == 10_000
    assert max(kinetic) > 1e-5  # it swings
    assert max(totals) - e0 < 0.05 * max(kinetic)
    assert abs(np.mean(totals[-10:]) - e0) < 0.01 * max(kinetic)


def test_too_large_a_step_is_subdivided_not_run():
    m, st = hanging_cloth(0.2, 0.2, h=0.04, pins="corners")
    sol = Solver(m, "ordered")
    info = sol.step(m, st, None, 10.5 * sol.dt_max)
    assert info.substeps == 11 and info.dt <= sol.dt_max
    assert sol.dt_max < sol.dt_stable < sol.t0_eq4  # safety factor, Gershgorin ≤ eq. 4


def test_explosion_is_detected_and_reported():
    m, st = hanging_cloth(0.2, 0.2, h=0.04, pins="corners")
    sol = Solver(m, "none", allow_unstable=True)
    with pytest.raises(ClothExplosionError, match="exploded"):
        for _ in range(2000):
            sol.step(m, st, None, 3.0 * sol.dt_stable)
    assert st.failed
    assert np.all(np.isfinite(st.positions))  # stopped before positions went bad
    with pytest.raises(CatwalkError, match="failed earlier"):
        sol.step(m, st)


def test_nan_input_is_detected_not_propagated():
    m, st = hanging_cloth(0.2, 0.2, h=0.04, pins="corners")
    st.positions[7, 1] = np.nan
    with pytest.raises(ClothExplosionError, match="non-finite"):
        Solver(m, "ordered").step(m, st)
    assert issubclass(ClothExplosionError, CatwalkError)


def test_bad_solver_arguments_are_user_errors():
    m, st = hanging_cloth(0.2, 0.2, h=0.04)
    with pytest.raises(CatwalkError, match="method"):
        Solver(m, "magic")
    with pytest.raises(CatwalkError, match="time step"):
        Solver(m).step(m, st, None, -1.0)


def test_cloth_falls_onto_a_plane_and_rests_on_it():
    m = build_cloth([Panel(rectangle(0.2, 0.2), placement=vertical((0, 0.3, 0)))], h=0.04)
    st = State.from_model(m)
    st.positions[:] = st.positions[:, [0, 2, 1]] + [0, 0.05, 0]  # flat, 5 cm above the floor
    floor = PlaneCollider(thickness=0.002)
    sol = Solver(m, "ordered", extra_air=2.0)
    sol.run(m, st, 0.6, collider=floor, dt=0.01)
    assert st.positions[:, 1].min() > 0.0
    assert np.all(np.abs(st.positions[:, 1] - 0.002) < 0.003)
    assert st.held.all()


def test_seam_forces_pull_matched_points_together():
    a = rectangle(0.2, 0.2)
    b = rectangle(0.2, 0.2)
    m = build_cloth([Panel(a, placement=vertical((0, 1, 0))),
                     Panel(b, placement=vertical((0.3, 1, 0)))],
                    [Seam(0, 1, 2, 1, 3, 0, reverse=True)], h=0.04)
    st = State.from_model(m)
    gap0 = np.linalg.norm(st.positions[m.seam_a] - st.positions[m.seam_b], axis=1).mean()
    assert gap0 == pytest.approx(0.1)
    sol = Solver(m, "ordered", gravity=(0, 0, 0), sewing=True, seam_stiffness=20.0,
                 extra_air=5.0)
    assert sol._seam_pts[m.seam_a].all()
    sol.run(m, st, 1.5)
    gap = np.linalg.norm(st.positions[m.seam_a] - st.positions[m.seam_b], axis=1).mean()
    assert gap < 0.2 * gap0


def _overstretched_run(method, steps=400):
    m, st = hanging_cloth(0.3, 0.3, h=0.03, fabric="cotton-jersey", pins="corner")
    centre = st.positions.mean(axis=0)
    st.positions[:] = centre + 1.5 * (st.positions - centre)   # every spring 50 % too long
    sol = Solver(m, method, gravity=(0.0, 0.0, 0.0))
    start = max_strain(m, st.positions)
    fastest = 0.0
    for _ in range(steps):
        before = st.positions.copy()
        sol.step(m, st, None, sol.dt_max)
        fastest = max(fastest, np.linalg.norm(st.positions - before, axis=1).max() / sol.dt_max)
    return start, max_strain(m, st.positions), fastest


@pytest.mark.parametrize("method", ["ordered", "vassilev"])
def test_a_badly_overstretched_start_is_pulled_back_without_exploding(method):
    """Panels placed on a body, or points pushed out by the collider, can start far beyond the
    strain limit; the velocity passes must bring them back over a few steps (each spring's
    correction capped at MAX_CORRECTION_SPEED), not throw the points at excess / dt."""
    from catwalk.cloth.strain_limit import MAX_CORRECTION_SPEED

    start, end, fastest = _overstretched_run(method)
    _, _, fastest_free = _overstretched_run("none")   # the springs alone, no strain limit
    assert start > 0.45
    assert end < start - 0.3
    # the limit adds at most a few capped corrections per point to what the springs do
    assert fastest < fastest_free + 12 * MAX_CORRECTION_SPEED   # ≤ 8 limited springs a point


def _flat_sheet():
    m = build_cloth([Panel(rectangle(0.2, 0.2), placement=vertical((0, 0.3, 0)))], h=0.04)
    st = State.from_model(m)
    st.positions[:] = st.positions[:, [0, 2, 1]] + [0, 0.05, 0]  # flat, 5 cm up
    return m, st


def test_contact_planes_hold_points_between_collision_responses():
    m, st = _flat_sheet()
    n = m.n_points
    planes = np.zeros((n, 8))
    held = np.arange(n) % 2 == 0          # half the points rest on the plane y = 0.05
    planes[held] = (0.0, 1.0, 0.0, 0.05, 0.0, 0.0, 0.0, 0.0)
    st.planes, st.plane_time = planes, st.time
    sol = Solver(m, "ordered")
    sol.run(m, st, 0.3)
    y = st.positions[:, 1]
    assert y[held].min() >= 0.05 - 1e-12          # never behind their plane
    on = held & (y < 0.05 + 1e-12)
    assert on.sum() > 5 and st.velocities[on, 1].min() >= -1e-9   # those on it: not into it
    assert y[~held].min() < 0.05 - 1e-3            # the others hang between them under gravity
    # a plane moving with the body (0.2 m/s along its normal) carries its point along
    m, st = _flat_sheet()
    planes = np.zeros((n, 8))
    planes[:] = (0.0, 1.0, 0.0, 0.05, 0.0, 0.2, 0.0, 0.0)
    st.planes, st.plane_time = planes, st.time
    sol = Solver(m, "ordered")
    sol.run(m, st, 0.25)
    assert st.positions[:, 1] == pytest.approx(0.05 + 0.2 * st.time, abs=1e-9)
    # no planes (None) or planes of another size: the solver ignores them
    m, st = _flat_sheet()
    st.planes = np.zeros((3, 8))
    Solver(m, "ordered").run(m, st, 0.1)
    assert st.positions[:, 1].max() < 0.05


def test_contact_planes_apply_coulomb_friction_relative_to_the_body():
    def slide(mu, body_vx=0.0):
        m, st = _flat_sheet()
        st.positions[:, 1] = 0.05
        st.velocities[:, 0] = 1.0
        st.planes = np.tile([0.0, 1.0, 0.0, 0.05, body_vx, 0.0, 0.0, mu], (m.n_points, 1))
        st.plane_time = st.time
        Solver(m, "ordered").run(m, st, 0.1)
        return float(st.velocities[:, 0].mean())

    # gravity presses the sheet on the plane: friction takes μ·g·t of the sliding speed
    assert slide(0.0) - slide(0.5) == pytest.approx(0.5 * 9.81 * 0.1, rel=0.05)
    # a body moving with the cloth carries it along (against the air drag that slows it
    # on a frictionless plane)
    carried = slide(0.5, body_vx=1.0)
    assert carried == pytest.approx(1.0, abs=1e-6) and carried > slide(0.0) + 0.02


def test_after_collision_moves_held_points_only_when_asked():
    """Provot's correction after a collision keeps points the body holds where they are; with
    ``move_held`` (dressing's final strain relief) it shortens a spring held at both ends too."""
    model, state = hanging_cloth(0.1, 0.1, 0.02, pins="corners")
    state.pinned[:] = False
    solver = Solver(model, "ordered", tau=0.1)
    x = state.positions
    x[:, 0] *= 1.3           # stretched 30 % across: every horizontal spring over the limit
    n = model.n_limited
    e0 = np.linalg.norm(x[model.spring_b[:n]] - x[model.spring_a[:n]], axis=1) \
        / model.spring_rest[:n] - 1.0
    assert e0.max() > 0.25
    state.held[:] = True      # the body holds every point
    before = x.copy()
    solver.after_collision(model, state, 1e-3)
    np.testing.assert_array_equal(x, before)            # held: nothing moves
    solver.after_collision(model, state, 1e-3, iterations=40, move_held=True)
    assert max_strain(model, x) < 0.12                  # near the limit τ = 0.1
    assert np.abs(x - before).max() > 0.005
    state.pinned[0] = True    # pinned points stay put even then
    x[:, 0] *= 1.2
    p0 = x[0].copy()
    solver.after_collision(model, state, 1e-3, move_held=True)
    np.testing.assert_array_equal(x[0], p0)


def test_the_explicit_solver_bends_by_the_quadratic_law_or_the_paper_s_springs():
    """The default: the law of cloth/bending.py, −Q·x a step, its bound in the stable step;
    ``integrator="paper"``: the paper's bend springs (the seed's reference scheme)."""
    m, st = hanging_cloth(0.3, 0.3, h=0.02, fabric="m3", pins="edge")
    assert Solver(m).bend_law == "quadratic"
    paper = Solver(m, integrator="paper")
    assert (paper.bend_law, paper.integrator) == ("springs", "explicit")
    assert Solver(m, bending="springs").dt_stable == paper.dt_stable
    with pytest.raises(CatwalkError):
        Solver(m, bending="hinges")
    # ten thousand times the bending: a shorter stable step, and stable at it
    stiff = m.fabric.with_(bend_warp=m.fabric.bend_warp * 1e4, bend_weft=m.fabric.bend_weft * 1e4)
    ms, ss = hanging_cloth(0.3, 0.3, h=0.02, fabric=stiff, pins="edge")
    sol = Solver(ms, extra_air=1.0)
    assert sol.dt_stable < 0.9 * Solver(m).dt_stable
    sol.run(ms, ss, 0.5)
    assert np.all(np.isfinite(ss.positions)) and sol.last_speed(ss) < 1.0


def test_the_bending_held_over_a_few_steps_is_opt_in_and_hangs_like_every_step():
    """``bend_every=1`` by default; ``"auto"`` evaluates −Q·x − C·v every few steps (as many as
    the bending's own stable step allows, ≤ MAX_BEND_EVERY) and holds it between: a sheet
    hung by an edge comes to the same rest within a millimetre."""
    from catwalk.cloth.solvers.explicit.solver import MAX_BEND_EVERY

    rest = {}
    for every in (1, "auto", 3):
        m, st = hanging_cloth(0.3, 0.3, h=0.02, fabric="m3", pins="edge")
        sol = Solver(m, bend_every=every, extra_air=1.0)
        sol.run(m, st, 0.6)
        rest[every] = st.positions.copy()
        interval = sol._bend_interval(m)
        assert interval == every if every != "auto" else 1 < interval <= MAX_BEND_EVERY
    assert Solver(m)._bend_interval(m) == 1
    for every in ("auto", 3):
        assert np.abs(rest[every] - rest[1]).max() < 1e-3
    for bad in (0, 2.5, True, "sometimes"):
        with pytest.raises(CatwalkError, match="bend_every"):
            Solver(m, bend_every=bad)
