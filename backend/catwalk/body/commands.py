"""``catwalk body make`` and ``catwalk bodies build``."""

from __future__ import annotations

import json
import sys
import time
from pathlib import Path

from catwalk.errors import InputError


def recipes_path() -> Path:
    from catwalk.config import get_config

    return get_config().bodies_dir / "recipes.json"


def _make(args) -> int:
    from catwalk.body.make import BodyRequest, make_body
    from catwalk.exchange.gltf import glb_bytes
    from catwalk.fileio import atomic_path, check_writable

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


def load_recipes(path: Path | None = None) -> list[dict]:
    path = path or recipes_path()
    try:
        data = json.loads(Path(path).read_text())
        return list(data["bodies"])
    except (OSError, ValueError, KeyError) as exc:
        raise InputError(f"{path}: not a readable recipe file ({exc})") from exc


def sample_body(name: str, out_dir: Path | None = None):
    """The sample body ``name`` (a recipe in bodies/recipes.json, e.g. ``female-M``), made once
    and kept in ``bodies/generated/`` (git-ignored) for the next call; made again where the
    kept one's skin weights were made another way (its meta's ``"skin"``)."""
    from catwalk.body.make import make_body
    from catwalk.body.rig import SKIN_RECIPE
    from catwalk.exchange.gltf import read_body, write_glb

    out = Path(out_dir) if out_dir is not None else recipes_path().parent / "generated"
    path = out / f"{name}.glb"
    if path.is_file():
        kept = read_body(path)
        if kept.meta.get("skin") == SKIN_RECIPE:
            return kept
    recipe = next((r for r in load_recipes() if r["name"] == name), None)
    if recipe is None:
        raise InputError(f"no sample body named {name!r} in {recipes_path()}")
    body = make_body(sex=recipe["sex"], height=recipe["height"], bust=recipe.get("bust"),
                     waist=recipe.get("waist"), hips=recipe.get("hips"),
                     underbust=recipe.get("underbust"))
    write_glb(path, body)
    return read_body(path)


def _build(args) -> int:
    from catwalk.body.make import make_body
    from catwalk.exchange.gltf import write_glb

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
