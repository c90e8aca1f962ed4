"""The implicit solver on a prefactored matrix (catwalk.cloth.solvers.implicit) against the
explicit reference: the static sag, energy at its largest step, the factor made once and
reused, the quadratic bending's energy, contacts with a fast capsule."""

import numpy as np
import pytest

from catwalk.bench.stress import cell
from catwalk.catalogue.bodies import sample_body
from catwalk.catalogue.garments import catalogue_files
from catwalk.cloth import bending as B
from catwalk.cloth import springs
from catwalk.cloth.builder import Panel, build_cloth, horizontal, rectangle
from catwalk.cloth.scenes import hanging_cloth
from catwalk.cloth.solvers.explicit.solver import Solver, max_strain
from catwalk.cloth.solvers.implicit import ImplicitSolver
from catwalk.cloth.solvers.implicit import system as S
from catwalk.cloth.solvers.implicit.factor import Factor
from catwalk.collide import make_collider
from catwalk.collide.shapes import capsule
from catwalk.errors import CatwalkError
from catwalk.exchange.garment_json import load_garment
from catwalk.simulate import preset
from catwalk.simulate.stepping import advance


def _sag(solver_of, seconds=1.5):
    m, st = hanging_cloth(0.4, 0.4, h=0.02, fabric="cotton-jersey", pins="corners")
    sol = solver_of(m)
    sol.run(m, st, seconds)
    return m, st, sol, 1.5 - float(st.positions[:, 1].min())


def test_a_pinned_square_sags_as_the_explicit_solver_s_at_rest():
    m, st_e, sol_e, sag_e = _sag(lambda m: Solver(m, "ordered", extra_air=3.0))
    assert sol_e.last_speed(st_e) < 0.05 and sag_e > 0.39
    for bending, in_matrix in (("quadratic", True), ("quadratic", False), ("springs", True)):
        m, st, sol, sag = _sag(lambda m, b=bending, i=in_matrix: ImplicitSolver(
            m, "ordered", extra_air=3.0, dt=1 / 90, bending=b, bend_in_matrix=i))
        assert sol.last_speed(st) < 0.05
        assert abs(sag - sag_e) / sag_e < 0.01, (bending, in_matrix, sag, sag_e)
        assert max_strain(m, st.positions) <= m.tau + 0.005
        # the same at rest without the ordered clamp: the implicit step alone hangs there
        m, st, sol, sag_free = _sag(lambda m: ImplicitSolver(m, "none", extra_air=3.0))
        assert abs(sag_free - sag_e) / sag_e < 0.01


def _energy(model, state, sol) -> float:
    """The energy of what the implicit solver simulates (J): kinetic, gravity, the stretch
    and shear springs (softer in compression), the quadratic bending."""
    x, v = state.positions, state.velocities
    ke = 0.5 * float(np.sum(model.mass * np.sum(v * v, axis=1)))
    ge = 9.81 * float(np.sum(model.mass * x[:, 1]))
    n = model.n_limited
    se = float(springs.spring_energy(x, model.spring_a[:n], model.spring_b[:n],
                                model.spring_rest[:n], model.spring_k[:n], n,
                                model.fabric.compression))
    lap, coef, _ = B.bending(model, B.bending_rigidity(model))
    be = 0.5 * float(np.sum(coef[:, None] * (lap @ x) ** 2))
    return ke + ge + se + be


def test_a_hanging_cloth_loses_energy_without_blowing_up_at_the_largest_step():
    m, st = hanging_cloth(0.4, 0.4, h=0.02, fabric="cotton-jersey", pins="corner")
    sol = ImplicitSolver(m, "none", dt=1 / 30)      # the largest step the settings allow
    e = [_energy(m, st, sol)]
    for _ in range(90):                             # 3 s: it swings about its one corner
        sol.step(m, st)
        e.append(_energy(m, st, sol))
        assert np.all(np.isfinite(st.positions))
    e = np.array(e)
    # implicit Euler takes energy away (the iterations not converged: up to 1 mJ back)
    assert np.all(np.diff(e) <= 1e-3), np.diff(e).max()
    assert e[-1] < e[0] - 0.01
    # with the ordered clamp too, at the same step
    m, st = hanging_cloth(0.4, 0.4, h=0.02, fabric="cotton-jersey", pins="corner")
    sol = ImplicitSolver(m, "ordered", dt=1 / 30)
    e0 = _energy(m, st, sol)
    sol.run(m, st, 3.0)
    assert np.all(np.isfinite(st.positions)) and _energy(m, st, sol) < e0 - 0.01
    assert max_strain(m, st.positions) <= m.tau + 0.005


def test_the_factor_is_made_once_for_a_garment_and_reused():
    m, st = hanging_cloth(0.3, 0.3, h=0.03, pins="corners")
    sol = ImplicitSolver(m, "ordered", dt=1 / 90)
    assert sol.factorizations == 0
    for _ in range(30):
        sol.step(m, st, None, 1 / 30)               # three steps each
    assert sol.factorizations == 1 and st.steps == 90
    st.pinned[:] = False                            # the prescribed points changed: again
    sol.step(m, st)
    assert sol.factorizations == 2
    for _ in range(10):
        sol.step(m, st)
    assert sol.factorizations == 2


def test_the_factor_solves_the_system():
    m, _ = hanging_cloth(0.3, 0.3, h=0.03)
    a = S.system_matrix(m, 1 / 90, np.arange(m.n_limited), None, 0.3)
    rng = np.random.default_rng(1)
    b = rng.standard_normal((m.n_points, 3))
    lengths = set()
    for order in ("metis", "mmd", "rcm", "natural"):
        f = Factor(a, order)
        assert np.abs(a @ f.solve(b) - b).max() < 1e-9 * np.abs(b).max()
        assert f.chains[:, 1].sum() == m.n_points
        lengths |= set(f.chains[:, 1].tolist())
    assert lengths == {1, 2, 3}                     # every kind of run of columns solved
    with pytest.raises(CatwalkError):
        Factor(-a)


@pytest.mark.parametrize("h", [0.01, 0.02])
def test_the_quadratic_bending_stores_half_b_kappa_squared_in_every_direction(h):
    m = build_cloth([Panel(rectangle(0.6, 0.6), placement=horizontal(1.0))],
                    fabric="cotton-jersey", h=h)
    lap, coef, q = B.bending(m, 1.0)
    uv = m.uv - m.uv.mean(axis=0)
    inner = np.all(np.abs(uv) < 0.2, axis=1)
    _, area = B.cotan_laplacian(m)
    R = 0.1
    for deg in (0, 30, 45, 90):
        a = np.radians(deg)
        u = uv[:, 0] * np.cos(a) + uv[:, 1] * np.sin(a)
        v = -uv[:, 0] * np.sin(a) + uv[:, 1] * np.cos(a)
        x = np.stack([R * np.sin(u / R), v, R * (1 - np.cos(u / R))], axis=1)
        lx = lap @ x
        e = 0.5 * np.sum((coef[:, None] * lx * lx)[inner])
        # (anisotropic: B(θ) over the mean rigidity, issue 44's law)
        want = B.fold_rigidity(m.fabric, a) / B.bending_rigidity(m)
        assert e / (0.5 * area[inner].sum() / R ** 2) == pytest.approx(want, abs=0.06)
    # the Hessian is what the energy says: ½·xᵀQx summed over the coordinates
    x = np.random.default_rng(0).standard_normal((m.n_points, 3))
    assert 0.5 * np.sum(x * (q @ x)) == pytest.approx(0.5 * np.sum(coef[:, None] *
                                                                     (lap @ x) ** 2))


def test_bad_arguments_are_user_errors():
    m, _ = hanging_cloth(0.2, 0.2, h=0.05)
    for kw in ({"dt": 0.0}, {"dt": 1.0}, {"iterations": 0}, {"rho": 1.0}, {"bending": "x"},
               {"bend_rigidity": -1.0}, {"order": "x"}, {"contacts": "x"}):
        with pytest.raises(CatwalkError):
            ImplicitSolver(m, **kw)


def _capsule_through_cloth(speed=3.0, fps=30.0, steps=3, band=0.0, frames=8):
    """A forearm-sized capsule (radius 4 cm) crossing a hanging cloth at ``speed`` m/s
    (its axis along x, moving along +z), the walk's implicit scheme: ``steps`` implicit steps
    a frame, a collision response after each (the planes they leave — the held points' and
    those within ``band`` — projected inside every iteration). Returns the deepest any cloth
    point is inside the capsule after a response, and after a step before it (m)."""
    model, st = hanging_cloth(0.4, 0.4, h=0.02, pins="edge", top=1.4)
    sol = ImplicitSolver(model, "ordered", dt=1.0 / (fps * steps), held_fixed=False)
    sol.run(model, st, 0.5)                         # hangs still
    R = 0.04
    a0, b0 = np.array([-0.12, 1.2, -R - 0.006]), np.array([0.12, 1.2, -R - 0.006])
    v, f = capsule(a0, b0, R)
    col = make_collider("object", f, np.ones(len(v), np.int8), plane_band=band)
    vel = np.tile([0.0, 0.0, speed], (len(v), 1))
    col.update(v, vel)
    x0 = st.positions.copy()
    worst = {"response": 0.0, "step": 0.0}

    def depth(x, t):
        """How far each point is inside the capsule at time ``t`` (s) of its motion."""
        a = a0 + [0.0, 0.0, speed * t]
        d = b0 - a0
        s = np.clip((x - a) @ d / (d @ d), 0.0, 1.0)
        return R - np.linalg.norm(x - (a + s[:, None] * d), axis=1)

    step = sol.step

    def watched(model, state, collider=None, dt=None):
        step(model, state, collider, dt)
        worst["step"] = max(worst["step"], float(depth(state.positions, state.time - t0).max()))

    sol.step = watched
    t0 = st.time
    for k in range(1, frames + 1):
        col.update(v + [0.0, 0.0, speed * k / fps], vel, substeps=steps)
        advance(sol, model, st, col, 1.0 / fps, steps, x0)
        worst["response"] = max(worst["response"], float(depth(st.positions, k / fps).max()))
        assert np.isfinite(st.positions).all()
    assert sol.factorizations == 1
    return worst


def test_contacts_keep_the_cloth_outside_a_capsule_crossing_it_at_3_m_s():
    """After every response no point is inside the capsule. Between two (a step: the capsule
    moves 33 mm) the cloth it reaches that had no plane goes in (27 mm measured at three steps
    a frame, 11–15 mm at six): the response pushes it out, as the explicit walk's do."""
    worst = _capsule_through_cloth()
    assert worst["response"] < 0.0005
    assert worst["step"] < 0.035


#: the catalogue cells whose implicit walk leaves points more than 2 mm inside today
#: (docs/cloth.md, "On the catalogue": the bodice M/L 4.7 / 10.5 mm, the GarmentCode shirt
#: M/L 49.7 / 16.7 mm, the trousers 23.8–50.4 mm — torn where the arms or legs pinch)
# (which cells tear moves with any change to the dressing they start from and with the CPU
# numba compiles for: on an AMD EPYC with AVX-512 at the welded seams' one-split bending the
# bodice M, the GarmentCode pencil dress M and shirt M walk within 2 mm (0.0 / 0.0 / 1.2 mm,
# max strain 0.27 / 3.5 / 5.0: the last two torn but outside), the trousers M 51 mm inside;
# elsewhere they were inside. Sizes S and L: `catwalk bench stress --integrator implicit
# --axes garment --sizes S M L`.)
_IMPLICIT_INSIDE = {("bodice", "M"), ("gc-dress-pencil", "M"), ("gc-shirt", "M"),
                    ("trousers", "M")}


@pytest.mark.slow
@pytest.mark.parametrize("size", ["M"])
@pytest.mark.parametrize("name", ["bodice", "dress", "gc-dress-pencil", "gc-shirt",
                                  "pencil-skirt", "trousers", "tshirt"])
def test_every_catalogue_garment_walks_with_the_implicit_solver_outside_the_body(
        request, name, size):
    """Dressed on its sample body and walked 1 s with ``integrator="implicit"``: no blow-up
    and no point more than 2 mm inside the body by the independent check
    (:mod:`catwalk.geometry.surface`, every recorded frame)."""
    if (name, size) in _IMPLICIT_INSIDE:
        request.applymarker(pytest.mark.xfail(reason="torn where the body pinches: "
                                              "docs/cloth.md", strict=False))
    g = load_garment(next(p for p in catalogue_files() if p.stem == name))
    r = cell(sample_body(g.fit[size]), g, size, preset("balanced").with_(integrator="implicit"))
    assert r["status"] == "ok", r
    assert r["max_penetration_mm"] <= 2.0, r
