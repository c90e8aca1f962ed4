"""``catwalk bench drape``: the Cusick drape test (30 cm specimen on an 18 cm support disc) for
every fabric preset and the six measured fabrics of Petrak et al. 2025; prints each drape
coefficient DC = (shadow − disc) / (specimen − disc), its number of nodes (folds hanging
outward: :func:`catwalk.cloth.drape.drape_nodes`) and the grid spacing h used."""

from __future__ import annotations

import json
import time
from pathlib import Path

from catwalk.bench.cloth import machine
from catwalk.cloth.drape import cusick_drape
from catwalk.cloth.fabrics import PRESETS, get_fabric, load_petrak
from catwalk.errors import InputError


def fabric_ids(only: str = "") -> list[str]:
    if only:
        ids = [s.strip() for s in only.split(",") if s.strip()]
        for i in ids:
            get_fabric(i)
        return ids
    return list(PRESETS) + list(load_petrak())


def main(args) -> int:
    if args.h <= 0:
        raise InputError("--h must be a positive number of metres")
    out = {}
    rows = []
    for fid in fabric_ids(args.fabrics):
        t0 = time.perf_counter()
        r = cusick_drape(fid, h=args.h, method=args.method, max_seconds=args.max_seconds)
        wall = time.perf_counter() - t0
        out[fid] = {"dc": r.dc, "h": r.h, "nodes": r.nodes}
        rows.append((fid, get_fabric(fid).name, r, wall))
        if args.png:
            from catwalk.cloth.preview import render_cloth

            render_cloth(r.model, r.state.positions, Path(args.png) / f"drape-{fid}.png",
                         view=30, size=(480, 320), floor=False)
    if args.json:
        print(json.dumps({"fabrics": out}))
        return 0
    print(f"Cusick drape: 30 cm specimen on an 18 cm disc, method {args.method}; "
          f"machine: {machine()}")
    print(f"{'fabric':<15} {'DC':>6} {'nodes':>5} {'h (m)':>7} {'sim s':>6} {'settled':>8} "
          f"{'wall s':>7}  name")
    for fid, name, r, wall in rows:
        print(f"{fid:<15} {r.dc:>6.3f} {r.nodes:>5} {r.h:>7.3f} {r.seconds:>6.2f} "
              f"{str(r.settled):>8} {wall:>7.1f}  {name}")
    return 0


def register(bench) -> None:
    p = bench.add_parser("drape", help="Cusick drape coefficient of every fabric")
    p.add_argument("--h", type=float, default=0.015, help="grid spacing in metres")
    p.add_argument("--fabrics", default="", help="comma-separated fabric ids (default: all)")
    p.add_argument("--method", default="ordered", help="strain-limit method")
    p.add_argument("--max-seconds", type=float, default=6.0,
                   help="simulated seconds at most, if it has not settled before")
    p.add_argument("--png", default="", help="folder to write a rendered PNG per fabric")
    p.add_argument("--json", action="store_true")
    p.set_defaults(func=main)
