"""Where a cloth step of `catwalk bench paper`'s hybrid walk goes, phase by phase, and how
much of the walk runs outside the numba kernels:

    .venv/bin/python tools/profile/step_phases.py [--seconds 2] [--repeat 300]

Walks the paper's scene (the dress dressed as `bench paper` dresses it, the hybrid collider)
once to compile, then again with every catwalk numba kernel wrapped in a wall-clock timer
(the walk's wall time less the kernels' is the Python and numpy between them; the recorded
frames' error measures are left out, as the walk's own ``ms_per_frame`` leaves them) and
with the cloth's state copied at three of the solver's calls (early, middle, late); the
kernels are put back after that walk. On each copy it times each phase of an explicit step
(best of five rounds of ``--repeat`` calls, less the copies some of them need): the forces
(split into the runs of two or more springs and the single springs across seams and
outlines), the velocity update, the predicted positions, the marking of over-long springs,
the ordered pass, the position update, the contact planes, and the whole step as
`run_steps` takes it (ten steps a call); and what sets the stable step (the stretch and shear
springs' share of each point's summed stiffness). docs/cloth.md "In a walk frame" and
docs/benchmarks.md quote it. A development tool: the product does not import it."""

import argparse
import collections
import sys
import time

import numba
import numpy as np
from timing import best_us  # tools/profile/timing.py (the tools run as scripts)

from catwalk.bench.paper import paper_dressed
from catwalk.cloth import bending, contact_planes, springs, strain_limit
from catwalk.cloth.solvers.explicit import kernels as K
from catwalk.cloth.solvers.explicit import solver as S
from catwalk.simulate import walking as W


def phases(snap, repeat: int) -> dict:
    """µs a call of each phase of one explicit step on the copied state ``snap``."""
    x, v, xprev, h, groups = snap
    model, seams, limit, order, contact, work, bend = groups
    (mass, w_int, w_lim, sa, sb, rest, k, c, n_lim, runs, n_runs_lim, compress, gravity,
     air) = model
    X, V, XP, XPREV, F, R, dirty = work
    springs.to_soa(x, X)
    springs.to_soa(v, V)
    X0, V0 = X.copy(), V.copy()
    qbuf, dbuf = strain_limit._order_buffers(order[0], order[1])
    single = runs[:, 3] == 1
    parts = {"forces (runs)": (np.ascontiguousarray(runs[~single]),
                               int(np.count_nonzero(~single[:n_runs_lim]))),
             "forces (single springs)": (np.ascontiguousarray(runs[single]),
                                         int(np.count_nonzero(single[:n_runs_lim])))}

    def forces(rr=runs, nl=n_runs_lim):
        K.accumulate_forces(X, V, mass, rr, nl, rest, k, c, compress, gravity, air, seams[0],
                            seams[1], seams[2], F)

    out = {"forces": best_us(forces, repeat)}
    if bend[0].shape[0]:
        out["bending (−Q·x − C·v)"] = best_us(
            lambda: bending.add_bending_forces(X, V, bend[0], bend[1], bend[2], F), repeat)
    for name, (rr, nl) in parts.items():
        out[name] = best_us(lambda rr=rr, nl=nl: forces(rr, nl), repeat)
    forces()
    # the phases that change their input run on a fresh copy each call: its cost is taken off
    copy = best_us(lambda: V0.copy(), repeat)
    out["velocity update"] = best_us(
        lambda: K.integrate_velocities(V0.copy(), F, w_int, h, limit[7]), repeat) - copy
    K.integrate_velocities(V, F, w_int, h, limit[7])
    V1 = V.copy()
    out["predicted positions"] = best_us(lambda: K.predict(X, V, h, XP), repeat)
    out["marking"] = best_us(
        lambda: strain_limit.mark_overstretched(XP, runs, n_runs_lim, rest, limit[1], dirty),
        repeat)
    out["marked points"] = int(dirty.sum())

    def before():
        V[:] = V1
        K.predict(X, V, h, XP)
        strain_limit.mark_overstretched(XP, runs, n_runs_lim, rest, limit[1], dirty)

    def ordered():
        before()
        strain_limit.limit_ordered_velocity(XP, V, w_lim, h, order[0], order[1], order[2],
                                            order[3], order[4], order[5], order[6], limit[2],
                                            limit[3], R, limit[4], dirty, order[7], order[8],
                                            qbuf, dbuf)

    out["ordered pass"] = best_us(ordered, repeat) - best_us(before, repeat)
    out["position update"] = best_us(
        lambda: K.advance_positions(X0.copy(), V1, R, h, True, XPREV), repeat) - copy
    out["contact planes"] = best_us(
        lambda: contact_planes.apply_planes(X0.copy(), V1.copy(), contact[0], contact[1],
                                            contact[2]), repeat) - 2 * copy
    out["points with a plane"] = len(contact[0])
    bad = np.zeros(2, np.int64)

    def ten_steps():
        K.run_steps(x.copy(), v.copy(), xprev.copy(), h, 10, model, seams, limit, order,
                    contact, work, bend, bad)

    def copies():
        x.copy(), v.copy(), xprev.copy()

    out["step (run_steps, 10 a call)"] = (best_us(ten_steps, max(1, repeat // 10))
                                          - best_us(copies, repeat)) / 10
    return out


def stiffness_shares(model) -> str:
    """What sets the explicit step: the share of each point's Σk (the bound's ω² = 2Σk/m)
    that its stretch and shear springs give, at the stiffest point for its mass and the
    median point."""
    n = model.n_limited
    total = np.zeros(model.n_points)
    limited = np.zeros(model.n_points)
    for acc, sel in ((total, slice(None)), (limited, slice(0, n))):
        np.add.at(acc, model.spring_a[sel], model.spring_k[sel])
        np.add.at(acc, model.spring_b[sel], model.spring_k[sel])
    share = limited / total
    w2 = 2.0 * total / model.mass
    return (f"stretch and shear springs give {100 * share[np.argmax(w2)]:.1f} % of the "
            f"stiffest point's Σk ({100 * np.median(share):.1f} % at the median point); "
            f"median k: stretch/shear {np.median(model.spring_k[:n]):.1f} N/m, bend "
            f"{np.median(model.spring_k[n:]):.3f} N/m")


def time_kernels(acc: dict) -> list:
    """Wrap every catwalk numba kernel that modules reach by name in a wall-clock timer;
    returns (module, name, kernel) for each, to put back."""
    replaced = []
    for name, mod in list(sys.modules.items()):
        if not name.startswith("catwalk") or mod is None:
            continue
        for attr, val in list(vars(mod).items()):
            if isinstance(val, numba.core.registry.CPUDispatcher):
                def timed(*a, f=val, key=f"{val.py_func.__module__}.{val.__name__}", **kw):
                    t = time.perf_counter()
                    r = f(*a, **kw)
                    acc[key][0] += 1
                    acc[key][1] += time.perf_counter() - t
                    return r
                setattr(mod, attr, timed)
                replaced.append((mod, attr, val))
    return replaced


def wrapper_us() -> float:
    """What the timer adds to a call, µs: a trivial kernel called with and without it."""
    @numba.njit
    def nothing(a):
        return a

    acc = collections.defaultdict(lambda: [0, 0.0])

    def timed(a):
        t = time.perf_counter()
        r = nothing(a)
        acc["x"][0] += 1
        acc["x"][1] += time.perf_counter() - t
        return r

    return best_us(lambda: timed(1.0), 20000) - best_us(lambda: nothing(1.0), 20000)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--seconds", type=float, default=2.0)
    ap.add_argument("--repeat", type=int, default=300)
    args = ap.parse_args()
    body, motion, settings, dressed = paper_dressed(args.seconds)
    walking = settings.with_(collider="hybrid")
    W.walk(body, motion, dressed, walking)   # compiled, warm

    snaps, calls = [], [0, 0]
    run_explicit = S.Solver._run_explicit

    def keep_some(self, model, state, w_int, w_lim, h, nsteps):
        calls[0] += 1
        calls[1] += nsteps
        if calls[0] in (200, 400, 600):
            g = self._step_groups(model, state, w_int, w_lim, self.react)
            snaps.append((state.positions.copy(), state.velocities.copy(),
                          self._xprev.copy(), h, tuple(tuple(np.copy(a) if isinstance(
                              a, np.ndarray) else a for a in grp) for grp in g)))
        return run_explicit(self, model, state, w_int, w_lim, h, nsteps)

    # the recorded frames' error measures (independent of the simulation) are left out
    tally_frame = W._Tally.frame
    acc = collections.defaultdict(lambda: [0, 0.0])
    S.Solver._run_explicit = keep_some
    W._Tally.frame = lambda *a, **kw: None
    replaced = time_kernels(acc)
    try:
        t = time.perf_counter()
        w = W.walk(body, motion, dressed, walking)
        wall = time.perf_counter() - t
    finally:
        S.Solver._run_explicit = run_explicit
        W._Tally.frame = tally_frame
        for mod, attr, val in replaced:
            setattr(mod, attr, val)
    in_kernels = sum(a[1] for a in acc.values())
    calls_timed = sum(a[0] for a in acc.values())
    frames = motion.frames + W.blend_frame_count(walking, motion.fps)
    print(f"walk of {frames} frames, the blend into it and the set-up (the motion skinned, "
          f"the hierarchies built) included: {calls[1] / frames:.1f} cloth steps a frame; "
          f"wall {wall * 1e3 / frames:.1f} ms a frame, in the kernels "
          f"{in_kernels * 1e3 / frames:.1f}, Python and numpy between them "
          f"{(wall - in_kernels) * 1e3 / frames:.1f} ({100 * (1 - in_kernels / wall):.0f} %; "
          f"the timer's own {calls_timed / frames:.0f} calls a frame × "
          f"{wrapper_us():.2f} µs counted there); the walk's own figures, per recorded frame: "
          f"{w.stats['collisions_per_frame']['mean']:.1f} responses, ms_per_frame "
          f"{ {k: round(v, 2) for k, v in w.stats['ms_per_frame'].items()} }")
    print(stiffness_shares(dressed.model))
    for key, (n, s) in sorted(acc.items(), key=lambda kv: -kv[1][1])[:8]:
        print(f"  {key}: {s * 1e3 / frames:.2f} ms a frame (of the {frames}), "
              f"{n / frames:.1f} calls")
    for i, snap in enumerate(snaps):
        ph = phases(snap, args.repeat)
        print(f"step at solver call {200 * (i + 1)}: " + "; ".join(
            f"{k} {v:.1f} µs" if isinstance(v, float) else f"{k} {v}" for k, v in ph.items()))


if __name__ == "__main__":
    main()
