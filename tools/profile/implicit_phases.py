"""What one step of the implicit solver costs on the paper's dress, phase by phase:

    .venv/bin/python tools/profile/implicit_phases.py [--repeat 200]

Dresses the paper's scene (`bench.paper.paper_dressed`), builds the walk's implicit solver
(`walking.cloth_solver` with ``integrator="implicit"``: its step 1/90 s) and times, on the
settled drape with its contact planes (best of five rounds of ``--repeat`` calls): the
factorisation (ordering, analysis, numeric; once per garment), the factor's size for each
order and with the bending in the matrix or on its diagonal, one solve (the three
coordinates), one residual (the force loop over the stretch and shear springs, the bending,
the inertia), one iteration and one whole step (its ten iterations, the friction, the
ordered clamp). A development tool: the product does not import it."""

import argparse
import json
import time

import numpy as np
from timing import best_us  # tools/profile/timing.py (the tools run as scripts)

from catwalk.bench.paper import paper_dressed
from catwalk.cloth import bending as bend_law
from catwalk.cloth.solvers.implicit import kernels as K
from catwalk.cloth.solvers.implicit import system as S
from catwalk.cloth.solvers.implicit.factor import Factor
from catwalk.simulate.walking import cloth_solver


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeat", type=int, default=200)
    args = ap.parse_args()
    _, _, settings, dressed = paper_dressed(2.0)
    model = dressed.model
    settings = settings.with_(integrator="implicit")
    sol = cloth_solver(dressed, settings)
    h = sol.dt_max
    out = {"points": model.n_points, "springs": model.n_springs, "h_s": h}
    st = dressed.state.copy()
    t = time.perf_counter()
    sol.step(model, st, None, h)                  # the factor, the kernels loaded
    out["first_step_ms"] = round(1e3 * (time.perf_counter() - t), 1)
    f = sol._factor
    factors = {}
    for order in ("metis", "mmd"):
        in_matrix = bend_law.bending(model, bend_law.bending_rigidity(model))[2]
        for name, q in (("bend_on_diagonal", sol._bend_q), ("bend_in_matrix", in_matrix)):
            aa = S.system_matrix(model, h, sol._springs, q, model.fabric.air, None)
            t = time.perf_counter()
            ff = Factor(aa, order)
            factors[f"{order}/{name}"] = {"nnz": ff.nnz,
                                          "factor_ms": round(1e3 * (time.perf_counter() - t), 1)}
    out["factors"] = factors
    n = model.n_points
    rng = np.random.default_rng(0)
    B = np.ascontiguousarray(rng.standard_normal((3, n)))
    D = np.empty_like(B)
    W = np.empty(3 * n)
    out["solve_us"] = round(best_us(lambda: K.solve_soa(f.lp, f.li, f.lx, f.perm, f.chains, B,
                                                        D, W),
                                    args.repeat), 1)
    fixed = (sol._w_int == 0.0)
    mdl = tuple(K.ImplicitModel(model.mass, fixed.astype(np.uint8), sol._runs_used,
                                sol._n_runs_lim, model.spring_rest, model.spring_k,
                                model.spring_c, model.fabric.compression, sol.gravity,
                                model.fabric.air, sol._seam_a, sol._seam_b, sol.seam_stiffness))
    work = tuple(sol._iwork)
    X = work[0].copy()
    out["residual_us"] = round(best_us(lambda: K.residual(X, h, mdl, tuple(sol._bend), work),
                                       args.repeat), 1)
    st1 = dressed.state.copy()
    sol.iterations = 1
    sol.last_residuals = np.zeros(2)
    one = best_us(lambda: sol.step(model, st1.copy(), None, h), max(1, args.repeat // 4))
    sol.iterations = 10
    sol.last_residuals = np.zeros(11)
    ten = best_us(lambda: sol.step(model, st1.copy(), None, h), max(1, args.repeat // 4))
    out["step_1_iteration_us"] = round(one, 1)
    out["step_10_iterations_us"] = round(ten, 1)
    out["iteration_us"] = round((ten - one) / 9, 1)
    out["step_outside_iterations_us"] = round(one - (ten - one) / 9, 1)
    out["factorizations"] = sol.factorizations
    print(json.dumps(out, indent=1))


if __name__ == "__main__":
    main()
