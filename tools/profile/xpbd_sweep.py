"""What one XPBD sweep over the paper dress's springs costs, against the explicit step's force
loop over the same springs:

    .venv/bin/python tools/profile/xpbd_sweep.py

The sweep in storage order (as `kernels.run_steps_xpbd` runs it: each projection sees the
ones before it) and in colour groups (a greedy edge colouring in storage order: no two
springs of a group share a point, so a group's projections are independent — what a
vectorised sweep would need), the same projection (`kernels._xpbd_distance`) either way.
Best of five rounds of 200 calls, µs a call. docs/cloth.md "An alternative integrator: XPBD"
quotes it. A development tool: the product does not import it."""


import numba
import numpy as np
from timing import best_us  # tools/profile/timing.py (the tools run as scripts)

from catwalk.bench.paper import paper_dressed
from catwalk.cloth import springs
from catwalk.cloth.solvers.explicit import kernels as K
from catwalk.cloth.solvers.xpbd import kernels as xpbd_kernels

DT = 1.0 / 300.0   # the walk's XPBD step (ten a 30-fps frame)
REPEAT = 200       # calls a round


def colour_groups(sa: np.ndarray, sb: np.ndarray, n_points: int):
    """A greedy edge colouring in storage order: the springs' order by colour and each
    colour's range in it."""
    used = [set() for _ in range(n_points)]
    colour = np.empty(len(sa), np.int64)
    for s, (a, b) in enumerate(zip(sa.tolist(), sb.tolist(), strict=True)):
        c = 0
        while c in used[a] or c in used[b]:
            c += 1
        colour[s] = c
        used[a].add(c)
        used[b].add(c)
    order = np.argsort(colour, kind="stable")
    ptr = np.searchsorted(colour[order], np.arange(colour.max() + 2))
    return order, ptr


@numba.njit(error_model="numpy")
def sweep_in_storage_order(p, x, w, sa, sb, rest, k, c, lam, dt):
    inv_dt = 1.0 / dt
    for s in range(sa.shape[0]):
        a = sa[s]
        b = sb[s]
        ikd = 1.0 / (k[s] * dt)
        lam[s] += xpbd_kernels._xpbd_distance(p, x, a, b, w[a], w[b], rest[s], ikd * inv_dt,
                                              c[s] * ikd, lam[s])


def main() -> None:
    m = paper_dressed(2.0)[3].model
    sa = m.spring_a.astype(np.int64)
    sb = m.spring_b.astype(np.int64)
    order, ptr = colour_groups(sa, sb, m.n_points)
    sizes = np.diff(ptr)
    print(f"{len(sa)} springs in {len(sizes)} colour groups of {sizes.min()}–{sizes.max()}")
    w = 1.0 / m.mass
    rng = np.random.default_rng(0)
    x = m.rest_positions.copy()
    p = x + rng.normal(0.0, 0.001, x.shape)
    lam = np.zeros(len(sa))
    copy = best_us(lambda: p.copy(), REPEAT)
    storage = best_us(lambda: sweep_in_storage_order(
        p.copy(), x, w, sa, sb, m.spring_rest, m.spring_k, m.spring_c, lam, DT), REPEAT) - copy
    # within a group no two springs share a point: projecting them one after the other is
    # the same as finding all of a group's corrections first and applying them after
    ca, cb = sa[order], sb[order]
    rest, k, c = m.spring_rest[order], m.spring_k[order], m.spring_c[order]
    groups = best_us(lambda: sweep_in_storage_order(
        p.copy(), x, w, ca, cb, rest, k, c, lam, DT), REPEAT) - copy
    X = np.ascontiguousarray(x.T)
    runs, n_runs_lim = springs.model_runs(m.spring_a, m.spring_b, m.n_limited)
    F = np.zeros((3, m.n_points))
    none = np.zeros(0, np.int32)
    V = np.zeros_like(X)
    gravity = np.array([0.0, -9.81, 0.0])
    forces = best_us(lambda: K.accumulate_forces(
        X, V, m.mass, runs, n_runs_lim, m.spring_rest, m.spring_k, m.spring_c,
        m.fabric.compression, gravity, m.fabric.air, none, none, 0.0, F), REPEAT)
    print(f"one XPBD sweep: {storage:.1f} µs in storage order, {groups:.1f} µs in colour "
          f"groups; the explicit step's force loop: {forces:.1f} µs")


if __name__ == "__main__":
    main()
