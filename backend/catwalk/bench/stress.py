"""``catwalk bench stress``: the try-on's numerical stability across its range.

One scene (a catalogue garment in size M on the sample body its size was made for, the
``balanced`` preset, a 1 s catwalk walk) is varied along one axis at a time:

* ``step``: the cloth's time step as a share of its stable step (eq. 4's bound), 0.5–4× the
  default (``Settings.step_safety`` 0.9). Beyond the stable step itself (a share above 1,
  here the factors 2 and 4) the product refuses the settings with a
  message; the evidence that the refusal is needed is measured beside it: the dressed garment
  stepped on the still body at that step with the guard off (``Solver(allow_unstable=True)``),
  and the time at which it blew up;
* ``stiffness``: the fabric's tensile, shear and bending stiffness × 0.1–10 (its stable step
  follows: √10 ≈ 3.2× more steps at 10×);
* ``speed``: the walk at 0.5–2.5× its 1.2 m/s (4×, 4.8 m/s, a run, is beyond the gait's 3 m/s:
  refused with the gait's message);
* ``garment``: every catalogue garment;
* ``long``: the default scene walked for ``--long-seconds``.

Each cell reports: ``status`` (``ok``, ``exploded`` with the solver's message — a blow-up is
always an error naming the step and the point, never NaN in a result — or ``refused`` with the
message a user gets), the max and 99th-percentile penetration (independent check), max and
p99 strain against τ, the cloth's kinetic energy relative to its centre of mass (its own
motion, the walk's forward motion taken out) over the walk (``energy_ratio``: the mean of
the last quarter of the frames over the mean of the first quarter; bounded when ≤ 10) and the
milliseconds per frame.
"""

from __future__ import annotations

import json
import time

STEP_FACTORS = (0.5, 1.0, 1.1, 2.0, 4.0)
STIFFNESS_FACTORS = (0.1, 1.0, 10.0)
SPEED_FACTORS = (0.5, 1.0, 2.0, 2.5, 4.0)
BASE_SPEED = 1.2
BASE_SAFETY = 0.9
ENERGY_BOUND = 10.0
STIFF_FIELDS = ("stretch_warp", "stretch_weft", "shear", "bend_warp", "bend_weft")


def energy_ratio(kinetic: list[float]) -> float | None:
    """Mean kinetic energy of the last quarter of the frames over that of the first."""
    n = len(kinetic) // 4
    if n < 1:
        return None
    first = sum(kinetic[:n]) / n
    last = sum(kinetic[-n:]) / n
    return last / first if first > 0 else None


def blow_up_time(body, dressed, safety: float, seconds: float = 0.5) -> dict:
    """The dressed garment stepped on the still body at ``safety`` × its stable step with
    the guard off: when (simulated seconds) it blew up, or that it did not within
    ``seconds``."""
    from catwalk.cloth.solver import ClothExplosionError, Solver
    from catwalk.collide import make_collider
    from catwalk.simulate.stepping import collide_and_floor

    model, state = dressed.model, dressed.state.copy()
    solver = Solver(model, "ordered", held_fixed=False, allow_unstable=True)
    dt = safety * solver.dt_stable
    collider = make_collider("object", body.faces, body.parts)
    v = body.vertices.astype(float)
    collider.update(v, None)
    x0 = state.positions.copy()
    t_start = state.time
    steps = int(seconds / dt)
    try:
        for i in range(steps):
            x0[:] = state.positions
            solver.step(model, state, None, dt)
            if i % 10 == 9:
                collide_and_floor(state, collider, x0, 1.0)
    except ClothExplosionError as exc:
        return {"blew_up_after_s": round(state.time - t_start, 4), "message": str(exc)}
    return {"blew_up_after_s": None, "stable_for_s": round(steps * dt, 3)}


def cell(body, garment, size: str, settings, *, fabric=None, speed: float = BASE_SPEED,
         seconds: float = 1.0) -> dict:
    """Dress and walk one variant; its errors (module docstring)."""
    import numpy as np

    from catwalk.cloth.solver import ClothExplosionError
    from catwalk.errors import CatwalkError, InputError
    from catwalk.motion.gait import walk_motion
    from catwalk.simulate import dress
    from catwalk.simulate.walking import walk

    try:
        settings = settings.check()
        motion = walk_motion(body, seconds, speed=speed, style="catwalk")
    except InputError as exc:
        return {"status": "refused", "message": str(exc)}
    t0 = time.perf_counter()
    try:
        dressed = dress(body, garment, size, fabric=fabric, settings=settings)
        w = walk(body, motion, dressed, settings)
    except ClothExplosionError as exc:
        return {"status": "exploded", "message": str(exc),
                "seconds": round(time.perf_counter() - t0, 1)}
    except CatwalkError as exc:
        return {"status": "failed", "message": str(exc)}
    s = w.stats
    kinetic = s["internal_kinetic_j_per_frame"]
    ratio = energy_ratio(kinetic)
    if not np.isfinite(w.positions).all():
        return {"status": "nan", "message": "non-finite cloth positions in the walk's result",
                "seconds": round(time.perf_counter() - t0, 1)}
    return {
        "status": "ok",
        "max_penetration_mm": round(s["max_penetration_mm"], 2),
        "p99_penetration_mm": round(s["p99_penetration_mm"], 2),
        "max_strain": round(s["max_strain"], 4), "p99_strain": round(s["p99_strain"], 4),
        "tau": dressed.model.tau,
        "max_internal_kinetic_j": round(max(kinetic), 6),
        "energy_ratio": None if ratio is None else round(ratio, 3),
        "energy_bounded": ratio is not None and ratio <= ENERGY_BOUND,
        "ms_per_frame": round(s["ms_per_frame"]["total"], 1),
        "frames": s["frames"], "seconds": round(time.perf_counter() - t0, 1),
    }


def run(garment_name: str = "dress", axes=("step", "stiffness", "speed", "garment", "long"),
        long_seconds: float = 20.0, progress=None, collider: str | None = None,
        sizes=("M",)) -> dict:
    """The grid (module docstring) on the ``balanced`` preset (its ``collider`` changed if
    given); the garment axis walks each catalogue garment in each of ``sizes`` it has (the
    default scene's garment in M, or its middle size). A cell asked twice (the default scene
    is each axis's 1× cell) is simulated once."""
    from dataclasses import replace

    from catwalk.bench import cpu_model
    from catwalk.body.commands import sample_body
    from catwalk.errors import InputError
    from catwalk.exchange.garment_json import load_garment
    from catwalk.garment.catalogue import catalogue_files
    from catwalk.garment.check import resolve_fabric
    from catwalk.simulate import dress, preset

    progress = progress or (lambda what: None)
    files = {p.stem: p for p in catalogue_files()}
    if garment_name not in files:
        raise InputError(f"no catalogue garment {garment_name!r} (choose from "
                         f"{', '.join(files)})", "garment")
    base = preset("balanced").with_(collider=collider)
    garments, bodies, memo = {}, {}, {}

    def body_for(g, size):
        name = g.fit.get(size)
        if name not in bodies:
            bodies[name] = sample_body(name)
        return bodies[name]

    def measured(name, size, settings=base, stiffness=1.0, speed=BASE_SPEED, seconds=1.0):
        key = (name, size, settings, stiffness, speed, seconds)
        if key not in memo:
            g = garments.setdefault(name, load_garment(files[name]))
            fab = None
            if stiffness != 1.0:
                fab = resolve_fabric(g.fabric, "garment fabric")
                fab = replace(fab, **{k: getattr(fab, k) * stiffness for k in STIFF_FIELDS})
            memo[key] = cell(body_for(g, size), g, size, settings, fabric=fab, speed=speed,
                             seconds=seconds)
        return dict(memo[key])

    g = garments.setdefault(garment_name, load_garment(files[garment_name]))
    size = "M" if "M" in g.sizes else g.sizes[len(g.sizes) // 2]
    body = body_for(g, size)
    out = {"machine": {"cpu": cpu_model(), "threads": 1}, "garment": garment_name,
           "size": size, "preset": base.name, "collider": base.collider, "cells": []}

    def add(axis, value, result):
        progress(f"{axis} {value}: {result['status']}")
        out["cells"].append({"axis": axis, "value": value, **result})

    if "step" in axes:
        dressed = None
        for f in STEP_FACTORS:
            r = measured(garment_name, size, replace(base, step_safety=BASE_SAFETY * f))
            if r["status"] == "refused":
                # the refusal is needed: the default dressing stepped with the guard off
                dressed = dressed or dress(body, g, size, settings=base)
                r["guard_off"] = blow_up_time(body, dressed, BASE_SAFETY * f)
            add("step", f, r)
    if "stiffness" in axes:
        for f in STIFFNESS_FACTORS:
            add("stiffness", f, measured(garment_name, size, stiffness=f))
    if "speed" in axes:
        for f in SPEED_FACTORS:
            add("speed", f, measured(garment_name, size, speed=BASE_SPEED * f))
    if "garment" in axes:
        for name in files:
            gg = garments.setdefault(name, load_garment(files[name]))
            chosen = [x for x in gg.sizes if x in sizes]
            if not chosen and sizes == ("M",):   # a garment without an M: its middle size
                chosen = [gg.sizes[len(gg.sizes) // 2]]
            for ss in chosen:
                add("garment", f"{name} {ss}", measured(name, ss))
    if "long" in axes:
        add("long", long_seconds, measured(garment_name, size, seconds=long_seconds))
    ok = [c for c in out["cells"] if c["status"] == "ok"]
    out["summary"] = {
        "cells": len(out["cells"]), "ok": len(ok),
        "exploded": sum(c["status"] == "exploded" for c in out["cells"]),
        "refused": sum(c["status"] == "refused" for c in out["cells"]),
        "nan": sum(c["status"] == "nan" for c in out["cells"]),
        "energy_unbounded": sum(not c["energy_bounded"] for c in ok),
    }
    return out


def format_table(r: dict) -> str:
    lines = [f"scene: {r['garment']} size {r['size']}, preset {r['preset']} "
             f"({r.get('collider', 'object')} collider), 1 s catwalk walk "
             f"unless the axis says otherwise; machine: {r['machine']['cpu']}, one thread", "",
             "| axis | value | status | max / p99 penetration mm | max / p99 strain (τ) | "
             "energy last/first quarter | ms/frame |", "|---|---|---|---|---|---|---|"]
    for c in r["cells"]:
        if c["status"] == "ok":
            lines.append(
                f"| {c['axis']} | {c['value']} | ok | {c['max_penetration_mm']:.2f} / "
                f"{c['p99_penetration_mm']:.2f} | {c['max_strain']:.3f} / {c['p99_strain']:.4f} "
                f"({c['tau']}) | {c['energy_ratio']} | {c['ms_per_frame']} |")
        else:
            extra = ""
            if "guard_off" in c:
                t = c["guard_off"].get("blew_up_after_s")
                extra = (f"; with the guard off it blew up after {t} s" if t is not None else
                         "; with the guard off it did not blow up within "
                         f"{c['guard_off']['stable_for_s']} s")
            lines.append(f"| {c['axis']} | {c['value']} | {c['status']}: {c['message']}{extra} "
                         "| | | | |")
    s = r["summary"]
    lines += ["", f"{s['cells']} cells: {s['ok']} ok, {s['exploded']} exploded, {s['refused']} "
              f"refused, {s['nan']} with NaN, {s['energy_unbounded']} with growing energy"]
    return "\n".join(lines)


def register(bench) -> None:
    from catwalk.bench import add_output_flags

    p = bench.add_parser(
        "stress", help="stability across the range: time step, stiffness, walking speed, "
        "every garment, a long walk (explosions, NaN, energy, penetration, strain)",
        description="One scene varied along one axis at a time (the module docstring of "
        "catwalk.bench.stress); each cell: ok / exploded / refused with its message, "
        "penetration, strain, kinetic energy over the walk, ms per frame.")
    p.add_argument("--garment", default="dress", help="catalogue garment (default dress)")
    p.add_argument("--axes", nargs="+", default=["step", "stiffness", "speed", "garment",
                                                   "long"],
                   choices=["step", "stiffness", "speed", "garment", "long"])
    p.add_argument("--long-seconds", type=float, default=20.0,
                   help="length of the long walk (default 20 s = 600 frames)")
    p.add_argument("--collider", choices=["object", "hybrid", "image"],
                   help="the collider of every cell (default: the preset's, object)")
    p.add_argument("--sizes", nargs="+", default=["M"],
                   help="the sizes the garment axis walks (default M)")
    add_output_flags(p)
    p.set_defaults(func=main)


def main(args) -> int:
    from catwalk.bench import progress_lines
    from catwalk.errors import InputError

    if not 1.0 <= args.long_seconds <= 400.0:
        raise InputError(f"--long-seconds must be within 1–400, got {args.long_seconds}")
    r = run(args.garment, tuple(args.axes), args.long_seconds,
            progress=progress_lines(args), collider=args.collider, sizes=tuple(args.sizes))
    print(json.dumps(r, indent=2) if args.json else format_table(r))
    return 0
