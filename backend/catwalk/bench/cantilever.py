"""``catwalk bench cantilever``: the ASTM D1388 cantilever test simulated for every fabric
(:func:`catwalk.cloth.cantilever.cantilever`: a 2.5 cm strip pushed over the platform's edge
until its tip reaches the 41.5° line; the bending length is half the overhang), warp and weft,
at each grid spacing of ``--h`` (default 0.5, 1 and 1.5 cm), against the fabric's own bending
length (B / ρg)^(1/3).

JSON: ``{"h": [...], "fabrics": {id: {"bending_length_m": {dir: {h: m}}, "expected_m": {dir:
m}, "error": {dir: {h: relative}}, "worst_error": relative}}, "worst_error": relative}``."""

from __future__ import annotations

import json
import math
import time

from catwalk.bench.cloth import machine
from catwalk.bench.drape import fabric_ids
from catwalk.cloth.cantilever import DIRECTIONS, cantilever, expected_length
from catwalk.cloth.fabrics import get_fabric
from catwalk.errors import InputError

DEFAULT_H = (0.005, 0.01, 0.015)


def run(ids, hs, directions=DIRECTIONS) -> dict:
    """Every fabric of ``ids`` at every h of ``hs`` along each direction: the JSON above
    (``settles`` and ``wall_s`` beside each bending length)."""
    out = {}
    for fid in ids:
        row = {"bending_length_m": {}, "expected_m": {}, "error": {}, "settles": {}}
        for d in directions:
            c0 = expected_length(fid, d)
            row["expected_m"][d] = round(c0, 6)
            row["bending_length_m"][d] = {}
            row["error"][d] = {}
            row["settles"][d] = {}
            for h in hs:
                r = cantilever(fid, h, d)
                key = f"{h:g}"
                row["bending_length_m"][d][key] = round(r.bending_length, 6)
                row["error"][d][key] = round(r.bending_length / c0 - 1.0, 4)
                row["settles"][d][key] = r.settles
        row["worst_error"] = max((abs(e) for d in row["error"].values() for e in d.values()),
                                 default=0.0)
        out[fid] = row
    worst = max((r["worst_error"] for r in out.values()), default=0.0)
    return {"h": [float(h) for h in hs], "fabrics": out, "worst_error": worst}


def main(args) -> int:
    hs = tuple(args.h) if args.h else DEFAULT_H
    for h in hs:
        if not (math.isfinite(h) and 0 < h <= 0.05):
            raise InputError(f"--h must be grid spacings in (0, 0.05] m, got {h}")
    ids = fabric_ids(args.fabrics)
    t0 = time.perf_counter()
    res = run(ids, hs)
    if args.json:
        print(json.dumps(res))
        return 0
    print(f"cantilever (ASTM D1388): 2.5 cm strip, tip at 41.5°, bending length = overhang / 2 "
          f"against (B/ρg)^(1/3); machine: {machine()}")
    cols = "  ".join(f"{'h=' + format(h * 100, 'g') + ' cm':>13}" for h in hs)
    print(f"{'fabric':<15} {'dir':<5} {'expected':>9}  {cols}")
    for fid, r in res["fabrics"].items():
        for d in DIRECTIONS:
            cells = "  ".join(f"{1e3 * r['bending_length_m'][d][f'{h:g}']:6.2f} "
                              f"({100 * r['error'][d][f'{h:g}']:+4.0f}%)" for h in hs)
            print(f"{fid:<15} {d:<5} {1e3 * r['expected_m'][d]:6.2f} mm  {cells}  "
                  f"{get_fabric(fid).name if d == 'warp' else ''}")
    print(f"worst |error| {100 * res['worst_error']:.1f} % "
          f"({time.perf_counter() - t0:.0f} s)")
    return 0


def register(bench) -> None:
    p = bench.add_parser("cantilever", help="simulated cantilever bending length of every "
                         "fabric (ASTM D1388) against its own")
    p.add_argument("--h", type=float, nargs="+", default=None, metavar="H",
                   help="grid spacings in metres (default 0.005 0.01 0.015)")
    p.add_argument("--fabrics", default="", help="comma-separated fabric ids (default: all)")
    p.add_argument("--json", action="store_true")
    p.set_defaults(func=main)
