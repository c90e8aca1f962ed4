"""``catwalk dress`` (a static dressed body) and ``catwalk tryon`` (the dressed body walking),
the product's main job; ``catwalk bench paper`` (the seed's table side by side)."""

from __future__ import annotations

import json
import math
import shutil
import tempfile
from pathlib import Path

from catwalk.bench import paper as bench_paper
from catwalk.bench import pareto as bench_pareto
from catwalk.bench import peers as bench_peers
from catwalk.bench import stress as bench_stress
from catwalk.bench.dress import main
from catwalk.body.skinning import body_frames
from catwalk.console import ProgressBar
from catwalk.errors import InputError
from catwalk.exchange.compress import compress_bytes
from catwalk.exchange.inventor import write_inventor
from catwalk.exchange.obj import write_obj_frames
from catwalk.fileio import atomic_path, check_writable
from catwalk.simulate.settings import PRESETS
from catwalk.simulate.tryon import static_frames, tryon


def _check_outputs(args) -> None:
    """Before minutes of simulation: every output can be written."""
    if not str(args.output).lower().endswith(".glb"):
        raise InputError(f"-o {args.output}: the result is written as a .glb file")
    obj_dir = getattr(args, "obj_dir", None)
    for flag, path in (("-o", args.output), ("--metrics", args.metrics), ("--iv", args.iv),
                       ("--obj-dir", obj_dir and Path(obj_dir) / "frame.obj")):
        if path:
            check_writable(path, flag)


def _write_metrics(path, metrics: dict) -> None:
    with atomic_path(path) as tmp:
        Path(tmp).write_text(json.dumps(metrics, indent=2) + "\n")


def _summary(metrics: dict, keys) -> dict:
    return {k: metrics[k] for k in keys if k in metrics}


def _run(args, seconds: float):
    """The try-on through the public entry point, with a progress bar on stderr."""
    bar = ProgressBar(quiet=args.quiet)
    try:
        return tryon(args.body, args.garment, size=args.size, fabric=args.fabric,
                     seconds=seconds, fps=getattr(args, "fps", 30.0),
                     speed=getattr(args, "speed", 1.2), style=getattr(args, "style", "catwalk"),
                     preset=args.preset, collider=args.collider, h=args.h, progress=bar)
    finally:
        bar.done()


def _write_iv(path, res) -> None:
    write_inventor(path, res.body.vertices, res.body.faces,
                   [static_frames(res.dressed).mesh_at_frame(0)])


def _dress_cmd(args) -> int:
    _check_outputs(args)
    res = _run(args, 0.0)
    res.write(args.output)
    if args.iv:
        _write_iv(args.iv, res)
    if args.metrics:
        _write_metrics(args.metrics, res.metrics)
    out = _summary(res.metrics, ("garment", "size", "fabric", "points", "springs",
                                 "dressing_seconds", "max_seam_gap_mm", "max_strain"))
    out["settled"] = res.metrics["dressing"]["settled"]
    out["file"] = str(args.output)
    print(json.dumps(out, indent=2))
    return 0


def _write_obj_dir(obj_dir, res) -> None:
    verts, _ = body_frames(res.body, res.motion)
    final = Path(obj_dir)
    if final.exists() and any(final.iterdir()):
        raise InputError(f"--obj-dir {final}: exists and is not empty")
    tmpdir = Path(tempfile.mkdtemp(prefix=".obj-", dir=final.parent if
                                   final.parent.exists() else None))
    try:
        write_obj_frames(tmpdir, res.body.faces, verts, [res.frames()])
        if final.exists():
            final.rmdir()
        shutil.move(str(tmpdir), str(final))
    except BaseException:
        shutil.rmtree(tmpdir, ignore_errors=True)
        raise


def _tryon_cmd(args) -> int:
    if not math.isfinite(args.seconds) or not 0 < args.seconds <= 60:
        raise InputError(f"--seconds must be within (0, 60], got {args.seconds}")
    _check_outputs(args)
    res = _run(args, args.seconds)
    out = Path(args.output)
    if args.compress:
        data, res.metrics["compression"] = compress_bytes(res.glb(normals=False))
        with atomic_path(out) as tmp:
            tmp.write_bytes(data)
    else:
        res.write(out)
    if args.obj_dir:
        _write_obj_dir(args.obj_dir, res)
    if args.iv:
        _write_iv(args.iv, res)
    if args.metrics:
        _write_metrics(args.metrics, res.metrics)
    s = _summary(res.metrics, ("garment", "size", "fabric", "collider", "points", "springs",
                               "frames", "dressing_seconds", "ms_per_frame",
                               "max_penetration_mm", "p99_penetration_mm", "max_strain",
                               "p99_strain", "max_seam_gap_mm"))
    s["file"] = str(out)
    print(json.dumps(s, indent=2))
    return 0


def _common(p, output_help: str) -> None:
    p.add_argument("--body", required=True,
                   help="a body .glb (`catwalk body make`, `catwalk body from-scan`) or a "
                        "scan (OBJ, PLY, STL, or a GLB with no skin), registered first")
    p.add_argument("--garment", required=True, help="a garment .json (garments/*.json)")
    p.add_argument("--size", help="garment size (default: the garment's default size)")
    p.add_argument("--fabric", help="fabric preset instead of the garment's (e.g. denim)")
    p.add_argument("--preset", default="balanced", choices=list(PRESETS),
                   help="speed/accuracy preset (default balanced)")
    p.add_argument("--collider", choices=["hybrid", "image", "object"],
                   help="collider mode (default: the preset's, hybrid)")
    p.add_argument("--h", type=float, help="cloth grid spacing in metres (default: preset's)")
    p.add_argument("-o", "--output", required=True, help=output_help)
    p.add_argument("--metrics", help="also write the metrics as JSON to this file")
    p.add_argument("--iv", help="also write the dressed body as Open Inventor ASCII (.iv)")
    p.add_argument("--quiet", action="store_true", help="no progress bar")


def _bench_dress(args) -> int:
    return main(args)


def register(top, groups) -> None:
    p = groups["bench"].add_parser(
        "dress", help="every catalogue garment in every size dressed on its sample body: "
        "seconds, converged, seam gap, penetration, strain",
        description="Dress each catalogue garment, in each size, on the sample body that size "
        "was made for (made once into bodies/generated/), and report time and errors.")
    p.add_argument("--garments", nargs="+", help="only these catalogue garments (file stems)")
    p.add_argument("--sizes", nargs="+", help="only these sizes")
    p.add_argument("--preset", default="balanced", choices=list(PRESETS))
    p.add_argument("--h", type=float, help="grid spacing (m) instead of the preset's")
    p.add_argument("--png-dir", help="also render each dressed garment (front, side, back) "
                   "into DIR/<garment>-<size>.png")
    p.add_argument("--json", action="store_true", help="print JSON")
    p.set_defaults(func=_bench_dress)


    bench_paper.register(groups["bench"])


    bench_pareto.register(groups["bench"])


    bench_peers.register(groups["bench"])


    bench_stress.register(groups["bench"])

    p = top.add_parser("dress", help="sew a garment onto a body and settle it (static .glb)",
                       description="Place the garment's panels round the body, sew, weld and "
                                   "settle them; write the dressed body as a .glb.")
    _common(p, "the dressed body (.glb)")
    p.set_defaults(func=_dress_cmd)

    p = top.add_parser("tryon", help="the dressed body walking: an animated .glb",
                       description="Dress the body, then walk it with the garment simulated; "
                                   "write one .glb (skinned body + morph-target garment).")
    _common(p, "the try-on (.glb)")
    p.add_argument("--seconds", type=float, default=4.0, help="length of the walk (default 4)")
    p.add_argument("--fps", type=float, default=30.0, help="frames per second (default 30)")
    p.add_argument("--speed", type=float, default=1.2, help="walking speed m/s (default 1.2)")
    p.add_argument("--style", default="catwalk", choices=["catwalk", "normal"],
                   help="walk style (default catwalk)")
    p.add_argument("--obj-dir", help="also write one OBJ per frame into this directory")
    p.add_argument("--compress", action="store_true",
                   help="meshopt-compress the .glb for the web (gltfpack)")
    p.set_defaults(func=_tryon_cmd)
