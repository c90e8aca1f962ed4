"""``catwalk bench pareto``: what each setting buys — run time against error.

One scene, the paper's inputs (:func:`catwalk.bench.paper.paper_inputs`: the catalogue dress,
size M, on the female base body, a 2 s catwalk walk; each run at its own settings' h, not at
``bench paper``'s 3,378-point one), is simulated with each setting of a list, and every run is
compared with a **reference run** of the same scene: the cloth's time step 4× finer
(``step_safety`` ÷ 4), 4× the collision resolves a frame (``max_move`` ÷ 4,
``min_collisions`` × 4), the object-space collider, every collider skip off, at the finest
grid of the runs (h = 1 cm).

Error of a run against the reference, over the walk's recorded frames: ``rms_mm``, the RMS
distance between the two cloths' surfaces (both directions: each cloth's vertices to the other
cloth's surface, so runs at another grid spacing compare too); beside it the run's own max and
p99 penetration (independent check), max and p99 strain, and widest open seam. Each run's
cost is its milliseconds per 30-fps frame (collider + cloth, one core). A run is on the
**Pareto front** when no other run is both faster and nearer the reference.

The settings run by default: the three presets, and ``balanced`` with one thing changed at a
time (collider mode, resolves a frame, grid spacing, depth-map size, the skips all off and
each skip off alone) — each change's saving and its error cost side by side. ``--grid`` runs
every combination of collider × resolves × h × skips instead.

The cloth is chaotic: two walks a few micrometres apart at the start part by centimetres
within a second where folds form. ``noise_mm`` measures that floor — the reference against
itself with the dressing's result moved 0.1 mm — and errors within it are not differences.
"""

from __future__ import annotations

import itertools
import json
import time

import numpy as np

from catwalk.bench import (
    add_output_flags,
    add_walk_seconds,
    check_walk_seconds,
    cpu_model,
    log_lines,
    walk_errors,
)
from catwalk.bench.chart import Chart
from catwalk.bench.paper import paper_inputs
from catwalk.collide import Skips
from catwalk.errors import CatwalkError
from catwalk.geometry.surface import BodySurface
from catwalk.simulate import dress, preset
from catwalk.simulate.fidelity import NUDGE, nudged
from catwalk.simulate.walking import walk

REFERENCE_H = 0.01
#: the collider's skips (:class:`~catwalk.collide.collider.Skips`), each switched off alone in
#: a run of the default list
SKIP_NAMES = Skips.names()
RESOLVES = {"5": {"min_collisions": 5, "max_move": 0.02},
            "10": {"min_collisions": 10, "max_move": 0.01},
            "20": {"min_collisions": 20, "max_move": 0.005, "max_collisions": 80}}


def default_runs(presets) -> list[tuple[str, dict]]:
    """(label, Settings changes on top of a preset) of the default list."""
    runs = [(f"preset {name}", {"preset": name}) for name in presets]
    variants = [
        ("collider object", {"collider": "object"}),
        ("collider image", {"collider": "image"}),
        ("resolves 5/frame", RESOLVES["5"]),
        ("resolves 20/frame", RESOLVES["20"]),
        ("h 2.5 cm", {"h": 0.025}),
        ("h 1 cm", {"h": 0.01}),
        ("skips off", {"skips": False}),
        *((f"skip {name} off", {"skips_off": (name,)}) for name in SKIP_NAMES),
        ("maps 128", {"map_size": 128}),
        ("maps 384", {"map_size": 384}),
    ]
    return runs + [(f"balanced, {label}", {"preset": "balanced", **ch})
                   for label, ch in variants]


def grid_runs() -> list[tuple[str, dict]]:
    out = []
    for col, res, h, skips in itertools.product(("object", "hybrid", "image"), RESOLVES,
                                                (0.01, 0.015, 0.025), (True, False)):
        out.append((f"{col}, {res}/frame, h {h * 100:g} cm, skips {'on' if skips else 'off'}",
                    {"preset": "balanced", "collider": col, "h": h, "skips": skips,
                     **RESOLVES[res]}))
    return out


def reference_settings(base):
    return base.with_(h=REFERENCE_H, collider="object", skips=False,
                      step_safety=base.step_safety / 4, max_move=base.max_move / 4,
                      min_collisions=base.min_collisions * 4,
                      max_collisions=base.max_collisions * 4)


def surface_rms(a_pos, a_tri, b_pos, b_tri) -> float:
    """RMS over frames and vertices of the distance from each cloth's vertices to the other
    cloth's surface (m), both directions pooled."""
    sa = BodySurface(a_tri, a_pos.shape[1])
    sb = BodySurface(b_tri, b_pos.shape[1])
    total, count = 0.0, 0
    for f in range(min(len(a_pos), len(b_pos))):
        _, d1, _, _ = sb.closest(b_pos[f], a_pos[f])
        _, d2, _, _ = sa.closest(a_pos[f], b_pos[f])
        total += float(np.sum(d1 * d1) + np.sum(d2 * d2))
        count += len(d1) + len(d2)
    return float(np.sqrt(total / max(count, 1)))


def pareto_front(points: list[tuple[float, float]]) -> list[bool]:
    """For (time, error) pairs: True where no other pair is at least as good in both and
    better in one."""
    out = []
    for i, (t, e) in enumerate(points):
        dominated = any((t2 <= t and e2 <= e) and (t2 < t or e2 < e)
                        for j, (t2, e2) in enumerate(points) if j != i)
        out.append(not dominated)
    return out


class _Scene:
    """The paper's scene: each run dresses the garment with its settings and walks it."""

    def __init__(self, seconds: float):
        self.garment, self.body, self.motion = paper_inputs(seconds)

    def dress(self, settings):
        return dress(self.body, self.garment, "M", settings=settings)

    def walk(self, dressed, settings, nudge: float = 0.0) -> dict:
        """The walk from ``dressed`` (moved ``nudge`` metres along x first, on a copy:
        :func:`catwalk.simulate.fidelity.nudged`)."""
        if nudge:
            dressed = nudged(dressed, nudge)
        w = walk(self.body, self.motion, dressed, settings)
        return {"positions": w.positions, "triangles": dressed.cloth.model.triangles,
                "stats": w.stats, "points": w.stats["points"]}

    def run(self, settings) -> dict:
        return self.walk(self.dress(settings), settings)


def run(seconds: float = 2.0, grid: bool = False, presets=("fast", "balanced", "accurate"),
        log=None) -> dict:
    log = log or (lambda what: None)
    scene = _Scene(seconds)
    ref_settings = reference_settings(preset("balanced"))
    t0 = time.perf_counter()
    log("reference")
    ref_dressed = scene.dress(ref_settings)
    ref = scene.walk(ref_dressed, ref_settings)
    ref_s = time.perf_counter() - t0
    log("noise floor")
    again = scene.walk(ref_dressed, ref_settings, nudge=NUDGE)
    noise = surface_rms(ref["positions"], ref["triangles"], again["positions"],
                        again["triangles"])
    out = {"machine": {"cpu": cpu_model(), "threads": 1}, "seconds": seconds,
           "frames": scene.motion.frames,
           "reference": {"settings": _settings_dict(ref_settings), "points": ref["points"],
                         **_errors(ref["stats"]), "wall_s": round(ref_s, 1)},
           "noise_mm": round(1e3 * noise, 2), "runs": []}
    for label, changes in (grid_runs() if grid else default_runs(presets)):
        ch = dict(changes)
        base = preset(ch.pop("preset"))
        settings = base.with_(**ch)
        log(label)
        try:
            r = scene.run(settings)
        except CatwalkError as exc:   # a failed run is a row of the table
            out["runs"].append({"label": label, "settings": _settings_dict(settings),
                                "failed": str(exc)})
            continue
        rms = surface_rms(r["positions"], r["triangles"], ref["positions"], ref["triangles"])
        out["runs"].append({"label": label, "settings": _settings_dict(settings),
                            "points": r["points"], "rms_mm": round(1e3 * rms, 2),
                            **_errors(r["stats"])})
    ok = [r for r in out["runs"] if "failed" not in r]
    front = pareto_front([(r["ms_per_frame"], r["rms_mm"]) for r in ok])
    for r, on in zip(ok, front, strict=True):
        r["pareto"] = on
    return out


def _settings_dict(s) -> dict:
    keys = ("name", "collider", "h", "map_size", "skips", "skips_off", "min_collisions",
            "max_collisions", "max_move", "step_safety", "thickness")
    d = s.as_dict()
    return {k: d[k] for k in keys}


def _errors(s: dict) -> dict:
    ms = s["ms_per_frame"]
    return {"ms_per_frame": round(ms["collider"] + ms["cloth"], 2), **walk_errors(s),
            "max_seam_gap_mm": round(s["max_seam_gap_mm"], 2),
            "resting_share": s.get("resting_share")}


def format_table(r: dict) -> str:
    ref = r["reference"]
    lines = [f"scene: the paper's dress on the walking female base body, {r['seconds']} s "
             f"({r['frames']} frames); machine: {r['machine']['cpu']}, one thread",
             f"reference: h {ref['settings']['h'] * 100:g} cm, {ref['points']} points, "
             f"object collider, skips off, step and resolves 4× finer: "
             f"{ref['ms_per_frame']} ms/frame; noise floor (reference vs itself moved 0.1 mm): "
             f"{r['noise_mm']} mm RMS", "",
             "| run | points | ms/frame | RMS to reference mm | max / p99 penetration mm | "
             "max / p99 strain | seam gap mm | front |", "|---|---|---|---|---|---|---|---|"]
    for x in r["runs"]:
        if "failed" in x:
            lines.append(f"| {x['label']} | | failed: {x['failed']} | | | | | |")
            continue
        lines.append(f"| {x['label']} | {x['points']} | {x['ms_per_frame']} | {x['rms_mm']} | "
                     f"{x['max_penetration_mm']} / {x['p99_penetration_mm']} | "
                     f"{x['max_strain']} / {x['p99_strain']} | {x['max_seam_gap_mm']} | "
                     f"{'**yes**' if x.get('pareto') else ''} |")
    return "\n".join(lines)


def plot(r: dict, path) -> None:
    """Time (x, log) against RMS error (y): every run a dot, the front joined, the presets
    named."""
    runs = [x for x in r["runs"] if "failed" not in x]
    ts = [x["ms_per_frame"] for x in runs]
    es = [x["rms_mm"] for x in runs] + [r["noise_mm"]]
    c = Chart((min(ts) / 10 ** 0.05, max(ts) * 10 ** 0.05), (0.0, max(es) * 1.1 or 1.0),
              "ms per frame (log scale)", "RMS distance to the reference (mm)", log_x=True)
    c.line([(c.x_at_left(), r["noise_mm"]), (max(ts) * 10 ** 0.05, r["noise_mm"])],
           (170, 170, 170))
    c.text(max(ts) * 10 ** 0.05, r["noise_mm"], "noise floor", (120, 120, 120), dx=-150)
    front = sorted((x["ms_per_frame"], x["rms_mm"]) for x in runs if x.get("pareto"))
    if len(front) > 1:
        c.line(front, (200, 60, 60), width=2)
    for x in runs:
        preset_run = x["label"].startswith("preset ")
        col = (200, 60, 60) if x.get("pareto") else (60, 90, 200)
        c.dot(x["ms_per_frame"], x["rms_mm"], col, 6 if preset_run else 4,
              filled=not preset_run)
        if preset_run:
            c.text(x["ms_per_frame"], x["rms_mm"], x["label"].split()[1])
    c.save(path)


def register(bench) -> None:
    p = bench.add_parser(
        "pareto", help="run time against error: each setting of the paper's scene against a "
        "4×-finer object-space reference, with the Pareto front",
        description="The paper's scene simulated with each preset and with balanced changed "
        "one setting at a time (or every combination, --grid); each run's ms per frame "
        "against its RMS distance to a reference run, penetration, strain and seam gap.")
    add_walk_seconds(p)
    p.add_argument("--grid", action="store_true",
                   help="every combination of collider × resolves × h × skips")
    p.add_argument("--png", help="also plot time against error into this PNG")
    add_output_flags(p)
    p.set_defaults(func=main)


def main(args) -> int:
    check_walk_seconds(args.seconds)
    r = run(args.seconds, args.grid,
            log=log_lines(args))
    if args.png:
        plot(r, args.png)
    print(json.dumps(r, indent=2) if args.json else format_table(r))
    return 0
