"""The bending law (:mod:`catwalk.cloth.bending`): what a fold stores in every direction and at
every grid spacing, nothing for a flat cloth however it is moved or stretched, the force loop's
pairs against Q, and the cantilever's bending length at two spacings."""

import numpy as np
import pytest

from catwalk.cloth import bending as B
from catwalk.cloth.builder import Panel, build_cloth, circle, horizontal, rectangle
from catwalk.cloth.cantilever import cantilever
from catwalk.cloth.fabrics import get_fabric


def _fold(uv, degrees, radius):
    """A cylindrical fold of ``radius`` whose curvature runs at ``degrees`` to the weft."""
    a = np.radians(degrees)
    u = uv[:, 0] * np.cos(a) + uv[:, 1] * np.sin(a)
    v = -uv[:, 0] * np.sin(a) + uv[:, 1] * np.cos(a)
    return np.stack([radius * np.sin(u / radius), v, radius * (1 - np.cos(u / radius))], axis=1)


@pytest.mark.parametrize("h", [0.01, 0.02])
def test_a_fold_stores_half_b_theta_kappa_squared_in_every_direction_at_every_spacing(h):
    """Inside a grid (the edges' share left out), against ½·B(θ)·κ² with Huber's B(θ), for an
    anisotropic fabric (m1: warp 3.2 × the weft)."""
    f = get_fabric("m1")
    m = build_cloth([Panel(rectangle(0.4, 0.4), placement=horizontal(1.0))], fabric=f, h=h)
    r, flux, area, _ = B._operator(m, f)
    uv = m.uv - m.uv.mean(axis=0)
    inner = np.all(np.abs(uv) < 0.12, axis=1)
    for deg in (0, 30, 45, 60, 90):
        x = _fold(uv, deg, 0.1)
        rx = (r + flux) @ x
        e = 0.5 * np.sum((rx * rx).sum(axis=1)[inner] / area[inner])
        want = 0.5 * B.fold_rigidity(f, np.radians(deg)) / 0.1 ** 2 * area[inner].sum()
        assert e / want == pytest.approx(1.0, abs=0.01), deg
    assert B.fold_rigidity(f, 0.0) == pytest.approx(f.bend_weft)
    assert B.fold_rigidity(f, np.pi / 2) == pytest.approx(f.bend_warp)
    assert B.fold_rigidity(f, np.pi / 4) == pytest.approx(
        ((np.sqrt(f.bend_warp) + np.sqrt(f.bend_weft)) / 2) ** 2)


def test_a_flat_cloth_stores_nothing_however_it_is_moved_or_stretched():
    m = build_cloth([Panel(circle(0.15, 94), placement=horizontal(0.5))], fabric="m6", h=0.01)
    q = B.bending_matrix(m)
    uv = m.uv
    rot = np.array([[0.36, 0.48, -0.8], [-0.8, 0.6, 0.0], [0.48, 0.64, 0.6]])
    for x in (m.rest_positions, m.rest_positions @ rot.T + [1.0, 2.0, 3.0],
              np.column_stack([1.1 * uv[:, 0] + 0.2 * uv[:, 1], 0.9 * uv[:, 1], 0 * uv[:, 0]])):
        assert np.abs(q @ x).max() < 1e-12
    assert abs(q - q.T).max() < 1e-12 * abs(q).max()


def test_the_force_loop_s_pairs_are_minus_q_x():
    m = build_cloth([Panel(circle(0.1, 40), placement=horizontal(0.5))], fabric="m1", h=0.015)
    q = B.bending_matrix(m)
    a, b, k, runs = B.bending_pairs(q)
    rng = np.random.default_rng(0)
    x, v = rng.standard_normal((m.n_points, 3)), rng.standard_normal((m.n_points, 3))
    F = np.zeros((3, m.n_points))
    c = B.pair_damping(a, b, k, m.mass, 0.05)
    B.add_bending_forces(np.ascontiguousarray(x.T), np.zeros((3, m.n_points)), runs, k, c, F)
    assert np.abs(F.T + q @ x).max() < 1e-12 * np.abs(q @ x).max()
    # the damping: along each pair, c ≥ 0, so it only takes energy out (vᵀ·f ≤ 0)
    F[:] = 0.0
    B.add_bending_forces(np.zeros((3, m.n_points)), np.ascontiguousarray(v.T), runs, k, c, F)
    assert np.all(c >= 0) and np.sum(F.T * v) < 0
    assert B.bending_energy(q, x) == pytest.approx(0.5 * np.sum(x * (q @ x)))


def test_the_implicit_solver_s_form_is_the_same_law_inside_the_cloth():
    """:func:`bending` (symmetric R, the free edges' points left out) against
    :func:`bending_matrix` on a fold inside the cloth."""
    m = build_cloth([Panel(rectangle(0.3, 0.3), placement=horizontal(1.0))], fabric="m4",
                    h=0.015)
    r, coef, q = B.bending(m, B.bending_rigidity(m))
    assert abs(r - r.T).max() == 0.0 and np.all(coef[m.boundary] == 0.0)
    x = _fold(m.uv - m.uv.mean(axis=0), 30, 0.08)
    inside = 0.5 * np.sum(coef[:, None] * (r @ x) ** 2)
    assert 0.5 * np.sum(x * (q @ x)) == pytest.approx(inside)
    whole = B.bending_energy(B.bending_matrix(m), x)
    assert inside < whole < 1.5 * inside     # the edges' points add their share


@pytest.mark.parametrize("direction", ["warp", "weft"])
def test_the_cantilever_bending_length_does_not_depend_on_h(direction):
    """The ASTM D1388 cantilever of m6 (bending length 1.4 / 1.1 cm) at h = 0.5 and 0.25 cm:
    within 4 % of (B / ρg)^(1/3) and of each other (at 1 and 1.5 cm the overhang is two
    cells or less: docs/cloth.md, "The cantilever")."""
    got = [cantilever("m6", h, direction) for h in (0.005, 0.0025)]
    for r in got:
        assert r.bending_length / r.expected == pytest.approx(1.0, abs=0.04), r
    assert got[0].bending_length == pytest.approx(got[1].bending_length, rel=0.04)


def test_a_welded_seam_s_cells_bend_by_the_law_and_store_nothing_laid_flat():
    """Two panels sewn edge to edge and welded: a triangle by the seam has a corner of the
    other panel (its pattern frame lost, laid out from its rest lengths); its grid cell is
    then taken as one split, not paired across two frames (that gave infinite entries and a
    NaN step on a merchant's two-piece skirt). Laid flat, the welded sheet of a fabric as stiff
    along the warp as the weft stores nothing (the seam's triangles bend isotropically, the
    rest by the fabric's two rigidities: with those unequal a flat sheet's seam feels a small
    in-plane force)."""
    from catwalk.cloth.builder import Seam
    from catwalk.simulate.garment_cloth import weld

    front = rectangle(0.1, 0.1)
    back = front + [0.15, 0.0]
    m = build_cloth([Panel(front, "front"), Panel(back, "back")],
                    [Seam(0, 1, 2, 1, 3, 0, reverse=True)], h=0.02,
                    fabric=get_fabric("m6").with_(bend_weft=get_fabric("m6").bend_warp))
    w, rep = weld(m)
    assert w.n_points < m.n_points
    q = B.bending_matrix(w)
    assert np.isfinite(q.data).all() and abs(q - q.T).max() < 1e-12 * abs(q).max()
    flat = np.zeros((w.n_points, 3))
    np.add.at(flat, rep, np.column_stack([m.uv[:, 0] - 0.05 * (m.panel == 1), m.uv[:, 1],
                                          np.zeros(m.n_points)]))
    flat /= np.bincount(rep, minlength=w.n_points)[:, None]
    assert np.abs(q @ flat).max() < 1e-9 * abs(q).max()
