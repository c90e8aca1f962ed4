"""``catwalk bench stress``: the try-on's numerical stability across its range.

One scene (a catalogue garment in size M on the sample body its size was made for, the
``balanced`` preset, a 1 s catwalk walk) is varied along one axis at a time (``--axes``), and
over every pair of values of two axes (``--grid A B``):

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
* ``arms``: the arms' swing amplitude about the shoulder, the catwalk's 11° up to 90° (arms
  raised to the horizontal at the front of the swing, and beyond the shoulder's range at its
  back: a stress case, not a pose);
* ``garment``: every catalogue garment;
* ``long``: the default scene walked for ``--long-seconds``.

``--collider`` changes every cell's collider; ``--plane-band``, ``--min-collisions``,
``--max-move``, ``--skips-off`` every cell's walk (not its dressing), as in ``catwalk bench
paper``.

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
from dataclasses import replace

import numpy as np

from catwalk.bench import (
    add_output_flags,
    add_walk_settings,
    cpu_model,
    log_lines,
    walk_errors,
    walk_settings,
)
from catwalk.catalogue.bodies import sample_body
from catwalk.catalogue.garments import catalogue_files
from catwalk.cloth.fabrics import resolve_fabric
from catwalk.cloth.solvers import ClothExplosionError
from catwalk.cloth.solvers.explicit.solver import Solver
from catwalk.collide import MODES, make_collider
from catwalk.errors import CatwalkError, InputError
from catwalk.exchange.garment_json import load_garment
from catwalk.motion.gait import walk_motion
from catwalk.simulate import dress, preset
from catwalk.simulate.settings import PRESETS
from catwalk.simulate.stepping import collide_and_floor
from catwalk.simulate.walking import walk

STEP_FACTORS = (0.5, 1.0, 1.1, 2.0, 4.0)
STIFFNESS_FACTORS = (0.1, 1.0, 10.0)
SPEED_FACTORS = (0.5, 1.0, 2.0, 2.5, 4.0)
#: the arms' swing amplitude (degrees about the shoulder, forward and back): the catwalk
#: style's own first (gait.STYLES["catwalk"].arm_swing_deg, a test keeps them equal; not
#: imported here: the gait loads scipy, ≈ 1 s on every command's start), up to arms raised
ARM_SWING_DEG = (11.0, 30.0, 60.0, 90.0)
BASE_SPEED = 1.2
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
         seconds: float = 1.0, arm_swing_deg: float | None = None,
         walk_settings: dict | None = None) -> dict:
    """Dress and walk one variant; its errors (module docstring). ``walk_settings``: fields
    of ``settings`` changed for the walk alone (not the dressing)."""
    try:
        settings = settings.check()
        walking = settings.with_(**(walk_settings or {}))
        motion = walk_motion(body, seconds, speed=speed, style="catwalk",
                             arm_swing_deg=arm_swing_deg)
    except InputError as exc:
        return {"status": "refused", "message": str(exc)}
    t0 = time.perf_counter()
    try:
        dressed = dress(body, garment, size, fabric=fabric, settings=settings)
        w = walk(body, motion, dressed, walking)
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
        **walk_errors(s),
        "tau": dressed.model.tau,
        "max_internal_kinetic_j": round(max(kinetic), 6),
        "energy_ratio": None if ratio is None else round(ratio, 3),
        "energy_bounded": ratio is not None and ratio <= ENERGY_BOUND,
        "ms_per_frame": round(s["ms_per_frame"]["total"], 1),
        "frames": s["frames"], "seconds": round(time.perf_counter() - t0, 1),
    }


#: the axes a cell can vary, and the value of each at the default scene
AXES = {"step": STEP_FACTORS, "stiffness": STIFFNESS_FACTORS, "speed": SPEED_FACTORS,
        "arms": ARM_SWING_DEG}
#: the single-axis runs, in order
ALL_AXES = ("step", "stiffness", "speed", "arms", "garment", "long")


def run(garment_name: str = "dress", axes=ALL_AXES, long_seconds: float = 20.0,
        log=None, collider: str | None = None, sizes=("M",),
        grid: tuple[str, str] | None = None, walk: dict | None = None,
        preset_name: str = "balanced") -> dict:
    """The runs of the module docstring on a preset (``balanced`` unless ``preset_name``; its
    ``collider`` changed if given; ``walk``: fields changed for the walks alone, as ``bench
    paper``'s): each of ``axes`` varied alone, then, if ``grid`` names two of :data:`AXES`,
    every pair of their values. The garment axis walks each catalogue garment in each of
    ``sizes`` it has (the default scene's garment in M, or its middle size). A cell asked twice
    (the default scene is each axis's 1× cell) is simulated once."""
    log = log or (lambda what: None)
    files = {p.stem: p for p in catalogue_files()}
    if garment_name not in files:
        raise InputError(f"no catalogue garment {garment_name!r} (choose from "
                         f"{', '.join(files)})", "garment")
    if grid is not None and (len(grid) != 2 or grid[0] == grid[1] or
                             any(a not in AXES for a in grid)):
        raise InputError(f"--grid takes two different axes of {', '.join(AXES)}, got "
                         f"{' '.join(grid)}", "grid")
    base = preset(preset_name).with_(collider=collider)
    scene = _Scene(base, files, walk or {})
    g = scene.garment(garment_name)
    size = "M" if "M" in g.sizes else g.sizes[len(g.sizes) // 2]
    out = {"machine": {"cpu": cpu_model(), "threads": 1}, "garment": garment_name,
           "size": size, "preset": base.name, "collider": base.collider,
           "walk_settings": walk or {}, "cells": []}

    def add(axis, value, result):
        log(f"{axis} {value}: {result['status']}")
        out["cells"].append({"axis": axis, "value": value, **result})

    for axis in (a for a in ALL_AXES if a in axes):
        if axis in AXES:
            dressed = None
            for value in AXES[axis]:
                r = scene.cell(garment_name, size, **{axis: value})
                if axis == "step" and r["status"] == "refused":
                    # the refusal is needed: the default dressing stepped with the guard off
                    body = scene.body(g, size)
                    dressed = dressed or dress(body, g, size, settings=base)
                    r["guard_off"] = blow_up_time(body, dressed, base.step_safety * value)
                add(axis, value, r)
        elif axis == "garment":
            for name in files:
                gg = scene.garment(name)
                chosen = [x for x in gg.sizes if x in sizes]
                if not chosen and tuple(sizes) == ("M",):   # no M: its middle size
                    chosen = [gg.sizes[len(gg.sizes) // 2]]
                for ss in chosen:
                    add("garment", f"{name} {ss}", scene.cell(name, ss))
        elif axis == "long":
            add("long", long_seconds, scene.cell(garment_name, size, seconds=long_seconds))
    if grid is not None:
        a, b = grid
        out["grid"] = {"axes": [a, b], "values": [list(AXES[a]), list(AXES[b])]}
        for va in AXES[a]:
            for vb in AXES[b]:
                add(f"{a}×{b}", [va, vb], scene.cell(garment_name, size, **{a: va, b: vb}))
    ok = [c for c in out["cells"] if c["status"] == "ok"]
    out["summary"] = {
        "cells": len(out["cells"]), "ok": len(ok),
        "exploded": sum(c["status"] == "exploded" for c in out["cells"]),
        "refused": sum(c["status"] == "refused" for c in out["cells"]),
        "nan": sum(c["status"] == "nan" for c in out["cells"]),
        "energy_unbounded": sum(not c["energy_bounded"] for c in ok),
    }
    return out


class _Scene:
    """The catalogue's garments and sample bodies, loaded once, and the cells already run."""

    def __init__(self, base, files, walk=None):
        self.base, self.files, self.walk = base, files, walk or {}
        self.garments, self.bodies, self.memo = {}, {}, {}

    def garment(self, name):
        if name not in self.garments:
            self.garments[name] = load_garment(self.files[name])
        return self.garments[name]

    def body(self, g, size):
        name = g.fit.get(size)
        if name not in self.bodies:
            self.bodies[name] = sample_body(name)
        return self.bodies[name]

    def cell(self, name, size, *, step=1.0, stiffness=1.0, speed=1.0, arms=ARM_SWING_DEG[0],
             seconds=1.0) -> dict:
        """:func:`cell` for the garment ``name`` in ``size`` with each axis at its factor
        (``arms``: the swing amplitude in degrees)."""
        key = (name, size, step, stiffness, speed, arms, seconds)
        if key not in self.memo:
            g = self.garment(name)
            fab = None
            if stiffness != 1.0:
                fab = resolve_fabric(g.fabric, "garment fabric")
                fab = replace(fab, **{k: getattr(fab, k) * stiffness for k in STIFF_FIELDS})
            settings = self.base if step == 1.0 else \
                replace(self.base, step_safety=self.base.step_safety * step)
            self.memo[key] = cell(self.body(g, size), g, size, settings, fabric=fab,
                                  speed=BASE_SPEED * speed, seconds=seconds, arm_swing_deg=arms,
                                  walk_settings=self.walk)
        return dict(self.memo[key])


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
    if "grid" in r:
        lines += ["", *grid_table(r)]
    s = r["summary"]
    lines += ["", f"{s['cells']} cells: {s['ok']} ok, {s['exploded']} exploded, {s['refused']} "
              f"refused, {s['nan']} with NaN, {s['energy_unbounded']} with growing energy"]
    return "\n".join(lines)


def _brief(c: dict) -> str:
    if c["status"] != "ok":
        return f"**{c['status']}**"
    return (f"{c['max_penetration_mm']:.2f} mm, {c['max_strain']:.3f} / "
            f"{c['p99_strain']:.4f}")


def grid_table(r: dict) -> list[str]:
    """The ``--grid`` cells as a table: the first axis down, the second across; each entry
    the max penetration and the max / p99 strain (or the status when not ok)."""
    a, b = r["grid"]["axes"]
    va, vb = r["grid"]["values"]
    cells = {tuple(c["value"]): c for c in r["cells"] if c["axis"] == f"{a}×{b}"}
    lines = [f"grid: {a} (down) × {b} (across); each: max penetration, max / p99 strain",
             "", f"| {a} \\ {b} | " + " | ".join(str(x) for x in vb) + " |",
             "|---" * (len(vb) + 1) + "|"]
    for x in va:
        lines.append(f"| {x} | " + " | ".join(_brief(cells[(x, y)]) for y in vb) + " |")
    return lines


def register(bench) -> None:
    p = bench.add_parser(
        "stress", help="stability across the range: time step, stiffness, walking speed, "
        "arm swing, every garment, a long walk (explosions, NaN, energy, penetration, strain)",
        description="One scene varied along one axis at a time, and over a grid of two axes "
        "(the module docstring of catwalk.bench.stress); each cell: ok / exploded / refused "
        "with its message, penetration, strain, kinetic energy over the walk, ms per frame.")
    p.add_argument("--garment", default="dress", help="catalogue garment (default dress)")
    p.add_argument("--axes", nargs="+", choices=list(ALL_AXES),
                   help="the axes varied one at a time (default: all of them, or none with "
                   "--grid)")
    p.add_argument("--grid", nargs=2, metavar=("AXIS", "AXIS"), choices=list(AXES),
                   help="also every pair of values of these two axes")
    p.add_argument("--long-seconds", type=float, default=20.0,
                   help="length of the long walk (default 20 s = 600 frames)")
    p.add_argument("--preset", default="balanced", choices=list(PRESETS),
                   help="the preset every cell starts from (default balanced)")
    p.add_argument("--collider", choices=list(MODES),
                   help="the collider of every cell (default: the preset's, hybrid)")
    p.add_argument("--sizes", nargs="+", default=["M"],
                   help="the sizes the garment axis walks (default M)")
    add_walk_settings(p)
    add_output_flags(p)
    p.set_defaults(func=main)


def main(args) -> int:
    if not 1.0 <= args.long_seconds <= 400.0:
        raise InputError(f"--long-seconds must be within 1–400, got {args.long_seconds}")
    axes = args.axes if args.axes is not None else (() if args.grid else ALL_AXES)
    r = run(args.garment, tuple(axes), args.long_seconds, log=log_lines(args),
            collider=args.collider, sizes=tuple(args.sizes),
            grid=tuple(args.grid) if args.grid else None, walk=walk_settings(args),
            preset_name=args.preset)
    print(json.dumps(r, indent=2) if args.json else format_table(r))
    return 0
