"""The cloth's stable step from the spectrum of its stiffness instead of the per-point
(Gershgorin) bounds the solver takes, and what the longer step does to the walk:

    .venv/bin/python tools/profile/spectral_step.py [--over-walk] [--walk N] [--stress]
                                                    [--passes 2]

Prints, for the paper's dressed dress, λmax of M⁻¹K and of M⁻¹C (the springs' k·n̂n̂ᵀ and
c·n̂n̂ᵀ blocks assembled at the dressed positions; scipy's ``eigsh``) beside the bounds the
solver uses (``Solver._stability``: 2Σk/m and 2Σc/m per point), and the stable step and
steps a frame from each. ``--over-walk``: λmax(M⁻¹K) at every fourth recorded frame of the
paper's hybrid walk. ``--walk N``: the paper's hybrid walk (`catwalk bench paper --modes
hybrid --threads 1 --no-reference`'s) N times each way, alternating: the walk's solver as
it is, then given the spectral step (``--passes``: the ordered pass that many times a step
with it). ``--stress``: the catalogue's one-second walks (`catwalk bench stress --axes garment
--sizes S M L`'s) each way, cell by cell. docs/cloth.md "Measured and not kept" quotes it. A
development tool: the product does not import it."""

import argparse
import json
import math

import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import eigsh

from catwalk.bench.paper import paper_dressed
from catwalk.simulate import walking as W

FRAME = 1.0 / 30.0


def assembled(model, x: np.ndarray, coef: np.ndarray) -> sp.csr_matrix:
    """Σ over springs of coef·n̂n̂ᵀ at the positions ``x`` (3P × 3P): the springs' stiffness
    (coef = k) or damping (coef = c) along their directions."""
    a, b = model.spring_a, model.spring_b
    d = x[b] - x[a]
    n = d / np.maximum(np.linalg.norm(d, axis=1), 1e-12)[:, None]
    blocks = coef[:, None, None] * n[:, :, None] * n[:, None, :]
    rows, cols, vals = [], [], []
    for i, j, sign in ((a, a, 1.0), (b, b, 1.0), (a, b, -1.0), (b, a, -1.0)):
        for p in range(3):
            for q in range(3):
                rows.append(3 * i + p)
                cols.append(3 * j + q)
                vals.append(sign * blocks[:, p, q])
    size = 3 * model.n_points
    return sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                         shape=(size, size))


def lambda_max(model, x: np.ndarray, coef: np.ndarray) -> float:
    """λmax of M⁻¹A for A = :func:`assembled` (as the symmetric M^-½ A M^-½)."""
    m = sp.diags(np.repeat(1.0 / np.sqrt(model.mass), 3))
    return float(eigsh(m @ assembled(model, x, coef) @ m, k=1, which="LA",
                       return_eigenvectors=False)[0])


def stable_step(w2: float, gamma: float) -> float:
    """The largest dt with dt²·w2 + 2·dt·gamma < 4 (semi-implicit Euler, docs/cloth.md)."""
    return (-2.0 * gamma + math.sqrt(4.0 * gamma * gamma + 16.0 * w2)) / (2.0 * w2)


def spectral_dt(model, x: np.ndarray, air: float) -> tuple[float, float, float]:
    lk = lambda_max(model, x, model.spring_k)
    lc = lambda_max(model, x, model.spring_c)
    return stable_step(lk, lc + air), lk, lc


def with_spectral_step(passes: int):
    """The walk's solver given the spectral step (at the dressed positions) and ``passes``
    ordered passes a step; returns what to call to put the solver as it is back."""
    as_it_is = W.cloth_solver

    def cloth_solver(dressed, settings):
        s = as_it_is(dressed, settings)
        if s.integrator == "explicit" and len(s._seam_a) == 0:
            dt, _, _ = spectral_dt(dressed.model, dressed.state.positions,
                                   dressed.model.fabric.air + s.extra_air)
            s.dt_stable = dt
            s.dt_max = s.safety * dt
            s.passes = passes
        return s

    W.cloth_solver = cloth_solver
    return lambda: setattr(W, "cloth_solver", as_it_is)


def bounds(body, motion, settings, dressed, over_walk: bool) -> None:
    m = dressed.model
    ksum = np.zeros(m.n_points)
    csum = np.zeros(m.n_points)
    for ends in (m.spring_a, m.spring_b):
        np.add.at(ksum, ends, m.spring_k)
        np.add.at(csum, ends, m.spring_c)
    gk, gc = float((2 * ksum / m.mass).max()), float((2 * csum / m.mass).max())
    dt, lk, lc = spectral_dt(m, dressed.state.positions, m.fabric.air)
    dt_g = stable_step(gk, gc + m.fabric.air)
    print(f"λmax(M⁻¹K) {lk:.4g} s⁻² against the per-point bound {gk:.4g} ({gk / lk:.2f}×); "
          f"λmax(M⁻¹C) {lc:.4g} s⁻¹ against {gc:.4g} ({gc / lc:.2f}×)")
    print(f"stable step {dt * 1e6:.0f} µs against {dt_g * 1e6:.0f}: at 0.9 of it "
          f"{math.ceil(FRAME / (0.9 * dt))} steps a frame against "
          f"{math.ceil(FRAME / (0.9 * dt_g))}")
    if not over_walk:
        return
    seen = []
    frame = W._Tally.frame
    W._Tally.frame = lambda self, model, state, *a, **kw: seen.append(state.positions.copy())
    try:
        W.walk(body, motion, dressed, settings.with_(collider="hybrid"), measure=False)
    finally:
        W._Tally.frame = frame
    lams = [lambda_max(m, x, m.spring_k) for x in seen[3::4]]
    print(f"λmax(M⁻¹K) at every fourth recorded frame of the walk: {min(lams):.4g}–"
          f"{max(lams):.4g} s⁻²")


def walks(n: int, passes: int) -> None:
    from catwalk.bench import paper

    keys = ("ms_per_frame", "max_penetration_mm", "max_strain", "p99_strain",
            "springs_over_limit", "cloth_steps_per_frame")
    for _ in range(n):
        for spectral in (False, True):
            undo = with_spectral_step(passes) if spectral else (lambda: None)
            try:
                h = paper.run(modes=("hybrid",), threads=1, reference=False)["hybrid"]
            finally:
                undo()
            print("spectral" if spectral else "as it is", {k: h[k] for k in keys},
                  "cloth steps", h["frame_ms"]["cloth_steps"], "ms a frame")


def stress(passes: int) -> None:
    from catwalk.bench import stress as B

    cells = []
    for spectral in (False, True):
        undo = with_spectral_step(passes) if spectral else (lambda: None)
        try:
            cells.append(B.run(axes=("garment",), sizes=("S", "M", "L"))["cells"])
        finally:
            undo()
    keys = ("max_penetration_mm", "p99_strain", "springs_over_limit", "ms_per_frame")
    for a, b in zip(*cells, strict=True):
        print(a["value"], json.dumps({k: [a.get(k), b.get(k)] for k in keys}))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--over-walk", action="store_true")
    ap.add_argument("--walk", type=int, default=0, metavar="N")
    ap.add_argument("--stress", action="store_true")
    ap.add_argument("--passes", type=int, default=1)
    args = ap.parse_args()
    bounds(*paper_dressed(2.0), args.over_walk)
    if args.walk:
        walks(args.walk, args.passes)
    if args.stress:
        stress(args.passes)


if __name__ == "__main__":
    main()
