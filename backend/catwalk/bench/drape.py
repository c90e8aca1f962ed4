"""``catwalk bench drape``: the Cusick drape test (30 cm specimen on an 18 cm support disc) for
every fabric preset and the six measured fabrics of Petrak et al. 2025; prints each drape
coefficient DC = (shadow − disc) / (specimen − disc), its number of nodes (folds hanging
outward: :func:`catwalk.cloth.drape.drape_nodes`) and the grid spacing h used; for m1–m6 also
the measured DC and CLO3D's, our error and the mean absolute errors (``--plot FILE``: the
same as a PNG, simulated against measured).

``--bend-scale``, ``--shear-scale``, ``--compression``: the same fabrics with their bending
rigidity or shear stiffness scaled, or another compression share — what each property moves
the drape by (docs/cloth.md, "What each property moves")."""

from __future__ import annotations

import dataclasses
import json
import math
import time
from pathlib import Path

from catwalk.bench.chart import Chart
from catwalk.bench.cloth import machine
from catwalk.cloth.drape import cusick_drape
from catwalk.cloth.fabrics import PRESETS, get_fabric, load_petrak
from catwalk.errors import InputError

#: Cusick DC of m1–m6 measured and simulated by CLO3D from the same KES-derived inputs (Petrak
#: et al., Sustainability 2025, 17, 1388, tables 4–5, as transcribed with the fabrics'
#: properties: shared/data/fabrics/petrak2025-woven.json; check against the paper)
MEASURED_DC = {"m1": (0.223, 0.349), "m2": (0.228, 0.313), "m3": (0.349, 0.404),
               "m4": (0.286, 0.323), "m5": (0.443, 0.438), "m6": (0.549, 0.613)}


def probed(fabric_id: str, bend_scale: float = 1.0, shear_scale: float = 1.0,
           compression: float | None = None):
    """The fabric with its bending rigidity and shear stiffness scaled and its compression
    share replaced (None: its own)."""
    f = get_fabric(fabric_id)
    if bend_scale == 1.0 and shear_scale == 1.0 and compression is None:
        return f
    return dataclasses.replace(
        f, bend_warp=f.bend_warp * bend_scale, bend_weft=f.bend_weft * bend_scale,
        shear=f.shear * shear_scale,
        compression=f.compression if compression is None else compression).validate()


def against_measured(dcs: dict) -> dict:
    """For the fabrics of ``dcs`` whose DC was measured: measured, CLO3D's, our error; and the
    mean absolute errors, ours and CLO3D's, over them."""
    rows = {k: {"measured": m, "clo3d": c, "error": round(dcs[k] - m, 4)}
            for k, (m, c) in MEASURED_DC.items() if k in dcs}
    if not rows:
        return {}
    n = len(rows)
    return {"fabrics": rows,
            "mean_abs_error": round(sum(abs(r["error"]) for r in rows.values()) / n, 4),
            "clo3d_mean_abs_error": round(sum(abs(r["clo3d"] - r["measured"])
                                              for r in rows.values()) / n, 4)}


def plot(dcs: dict, h: float, path) -> None:
    """Simulated DC (y) against measured DC (x) for the measured fabrics among ``dcs``: ours
    (blue dots, named) and CLO3D's from the same inputs (grey squares), with y = x and the
    target band ± 0.03."""
    rows = against_measured(dcs)["fabrics"]
    hi = max([0.7] + [max(dcs[k], r["measured"], r["clo3d"]) + 0.05 for k, r in rows.items()])
    hi = min(math.ceil(hi * 10) / 10, 1.0)
    n = int(round(hi * 10))
    c = Chart((0.0, hi), (0.0, hi), "measured drape coefficient (Cusick)",
              f"simulated drape coefficient (ours at h = {h * 100:g} cm: blue; CLO3D: grey)",
              x_ticks=n, y_ticks=n)
    c.line([(0.0, 0.0), (hi, hi)], (120, 120, 120))
    for off in (-0.03, 0.03):
        c.line([(max(0.0, -off), max(0.0, off)), (min(hi, hi - off), min(hi, hi + off))],
               (200, 200, 200))
    c.text(hi - 0.12, hi - 0.12 - 0.03, "± 0.03", (120, 120, 120), dx=10, dy=4)
    for k, r in rows.items():
        c.dot(r["measured"], r["clo3d"], (150, 150, 150), square=True)
        c.line([(r["measured"], r["measured"]), (r["measured"], dcs[k])], (150, 170, 230))
        c.dot(r["measured"], dcs[k], (60, 90, 200))
        c.text(r["measured"], dcs[k], k)
    c.save(path)


def fabric_ids(only: str = "") -> list[str]:
    if only:
        ids = [s.strip() for s in only.split(",") if s.strip()]
        for i in ids:
            get_fabric(i)
        return ids
    return list(PRESETS) + list(load_petrak())


def main(args) -> int:
    if not (math.isfinite(args.h) and args.h > 0):
        raise InputError("--h must be a positive number of metres")
    for flag, v in (("--bend-scale", args.bend_scale), ("--shear-scale", args.shear_scale)):
        if not (math.isfinite(v) and v > 0):
            raise InputError(f"{flag} must be a positive factor, got {v}")
    if args.compression is not None and not 0.0 <= args.compression <= 1.0:
        raise InputError(f"--compression must be within 0–1, got {args.compression}")
    ids = fabric_ids(args.fabrics)
    if args.plot and not any(i in MEASURED_DC for i in ids):
        raise InputError(f"--plot draws the fabrics with a measured drape coefficient "
                         f"({', '.join(MEASURED_DC)}); none is among {', '.join(ids)}")
    out = {}
    rows = []
    for fid in ids:
        fabric = probed(fid, args.bend_scale, args.shear_scale, args.compression)
        t0 = time.perf_counter()
        r = cusick_drape(fabric, h=args.h, method=args.method, max_seconds=args.max_seconds)
        wall = time.perf_counter() - t0
        out[fid] = {"dc": r.dc, "h": r.h, "nodes": r.nodes}
        rows.append((fid, get_fabric(fid).name, r, wall))
        if args.png:
            from catwalk.render.cloth import render_cloth

            render_cloth(r.model, r.state.positions, Path(args.png) / f"drape-{fid}.png",
                         view=30, size=(480, 320), floor=False)
    measured = against_measured({k: v["dc"] for k, v in out.items()})
    if args.plot:
        plot({k: v["dc"] for k, v in out.items()}, args.h, args.plot)
    probes = {"bend_scale": args.bend_scale, "shear_scale": args.shear_scale,
              "compression": args.compression}
    if args.json:
        print(json.dumps({"fabrics": out, "against_measured": measured, "probes": probes}))
        return 0
    print(f"Cusick drape: 30 cm specimen on an 18 cm disc, method {args.method}; "
          f"machine: {machine()}")
    if probes != {"bend_scale": 1.0, "shear_scale": 1.0, "compression": None}:
        print(f"fabrics probed: B × {args.bend_scale:g}, G × {args.shear_scale:g}, compression "
              f"{'as given' if args.compression is None else f'{args.compression:g}'}")
    print(f"{'fabric':<15} {'DC':>6} {'measured':>8} {'CLO3D':>6} {'nodes':>5} {'h (m)':>7} "
          f"{'sim s':>6} {'settled':>8} {'wall s':>7}  name")
    for fid, name, r, wall in rows:
        m = measured.get("fabrics", {}).get(fid)
        ms, cs = (f"{m['measured']:.3f}", f"{m['clo3d']:.3f}") if m else ("—", "—")
        print(f"{fid:<15} {r.dc:>6.3f} {ms:>8} {cs:>6} {r.nodes:>5} {r.h:>7.3f} "
              f"{r.seconds:>6.2f} {str(r.settled):>8} {wall:>7.1f}  {name}")
    if measured:
        print(f"mean |DC − measured| over {len(measured['fabrics'])} measured fabrics: ours "
              f"{measured['mean_abs_error']:.3f}, CLO3D {measured['clo3d_mean_abs_error']:.3f}")
    return 0


def register(bench) -> None:
    p = bench.add_parser("drape", help="Cusick drape coefficient of every fabric")
    p.add_argument("--h", type=float, default=0.015, help="grid spacing in metres")
    p.add_argument("--fabrics", default="", help="comma-separated fabric ids (default: all)")
    p.add_argument("--method", default="ordered", help="strain-limit method")
    p.add_argument("--max-seconds", type=float, default=6.0,
                   help="simulated seconds at most, if it has not settled before")
    p.add_argument("--bend-scale", type=float, default=1.0, metavar="X",
                   help="scale every fabric's bending rigidity by X (what it moves the DC by)")
    p.add_argument("--shear-scale", type=float, default=1.0, metavar="X",
                   help="scale every fabric's shear stiffness by X")
    p.add_argument("--compression", type=float, default=None, metavar="C",
                   help="every fabric's compression share (0–1; default: its own)")
    p.add_argument("--png", default="", help="folder to write a rendered PNG per fabric")
    p.add_argument("--plot", default="", metavar="FILE",
                   help="plot simulated against measured DC of the measured fabrics (m1–m6) "
                   "into this PNG")
    p.add_argument("--json", action="store_true")
    p.set_defaults(func=main)
