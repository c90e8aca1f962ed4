"""``catwalk body make`` and ``catwalk bodies build``."""

from __future__ import annotations

import json
import sys
import time
from pathlib import Path

from catwalk.body.make import BodyRequest, make_body
from catwalk.catalogue.bodies import load_recipes, recipes_path
from catwalk.errors import InputError
from catwalk.exchange.gltf import glb_bytes, write_glb
from catwalk.fileio import atomic_path, check_writable


def _make(args) -> int:
    if not str(args.output).lower().endswith(".glb"):
        raise InputError(f"-o {args.output}: the body is written as a .glb file")
    req = BodyRequest(sex=args.sex, height=args.height, bust=args.bust, waist=args.waist,
                      hips=args.hips, underbust=args.underbust)
    req.check()   # the measurements first, then the output, then seconds of fitting
    check_writable(args.output, "-o")
    t0 = time.perf_counter()
    body = make_body(sex=args.sex, height=args.height, bust=args.bust, waist=args.waist,
                     hips=args.hips, underbust=args.underbust)
    data = glb_bytes(body)
    with atomic_path(args.output, "-o") as tmp:
        tmp.write_bytes(data)
    measured = body.meta["measured"]
    summary = {"file": str(args.output), "seconds": round(time.perf_counter() - t0, 2),
               "requested": body.meta["requested"],
               "measured": {k: round(measured[k], 4) for k in body.meta["requested"]}}
    print(json.dumps(summary, indent=2))
    return 0


def _build(args) -> int:
    recipes_file = Path(args.recipes) if args.recipes else recipes_path()
    out = Path(args.out_dir) if args.out_dir else recipes_file.parent / "generated"
    recipes = load_recipes(recipes_file)
    if args.only:
        recipes = [r for r in recipes if r["name"] in args.only]
        if not recipes:
            raise InputError(f"no recipe named {', '.join(args.only)}")
    for i, r in enumerate(recipes, 1):
        t0 = time.perf_counter()
        body = make_body(sex=r["sex"], height=r["height"], bust=r.get("bust"),
                         waist=r.get("waist"), hips=r.get("hips"), underbust=r.get("underbust"))
        write_glb(out / f"{r['name']}.glb", body)
        err = {k: round(body.meta["measured"][k] - v, 4) for k, v in body.meta["requested"].items()}
        print(f"[{i}/{len(recipes)}] {r['name']}: {time.perf_counter() - t0:.1f} s, "
              f"error (m) {err}", file=sys.stderr)
    return 0


def _add_measurements(p) -> None:
    p.add_argument("--sex", required=True, choices=["female", "male"])
    p.add_argument("--height", type=float, required=True, help="stature, metres")
    p.add_argument("--bust", type=float, help="bust (women) or chest (men) girth, metres")
    p.add_argument("--waist", type=float, help="waist girth, metres")
    p.add_argument("--hips", type=float, help="hip girth, metres")
    p.add_argument("--underbust", type=float, help="underbust girth (women), metres")


def register(top, groups) -> None:
    p = groups["body"].add_parser("make", help="a rigged body from measurements → .glb")
    _add_measurements(p)
    p.add_argument("-o", "--output", required=True, help="the .glb to write")
    p.set_defaults(func=_make)

    b = top.add_parser("bodies", help="sample bodies from bodies/recipes.json")
    bs = b.add_subparsers(dest="bodies_command", metavar="COMMAND")
    bs.required = True
    pb = bs.add_parser("build", help="regenerate the sample bodies from their recipes")
    pb.add_argument("--recipes", default=None, help="default: $CATWALK_BODIES_DIR/recipes.json")
    pb.add_argument("--out-dir", default=None, help="default: generated/ beside the recipes")
    pb.add_argument("--only", nargs="*", help="recipe names to build (default: all)")
    pb.set_defaults(func=_build)
