"""``catwalk dress`` (a static dressed body) and ``catwalk tryon`` (the dressed body walking),
the product's main job; ``catwalk bench paper`` (the seed's table side by side)."""

from __future__ import annotations

import json
import math
import shutil
import sys
import tempfile
import time
from pathlib import Path

from catwalk.errors import CatwalkError, InputError


class ProgressBar:
    """One line on stderr per stage, redrawn in place on a terminal (a line every 10 % when
    stderr is not a terminal, e.g. in CI logs)."""

    def __init__(self, stream=None, quiet: bool = False):
        self.stream = stream or sys.stderr
        self.quiet = quiet
        self.tty = hasattr(self.stream, "isatty") and self.stream.isatty()
        self.stage = None
        self.t0 = time.perf_counter()
        self.last_pct = -1

    def __call__(self, stage: str, i: int, total: int) -> None:
        if self.quiet:
            return
        if stage != self.stage:
            if self.stage is not None and self.tty:
                self.stream.write("\n")
            self.stage, self.t0, self.last_pct = stage, time.perf_counter(), -1
        pct = int(100 * i / max(total, 1))
        el = time.perf_counter() - self.t0
        eta = el / i * (total - i) if i else 0.0
        if self.tty:
            bar = "#" * (pct // 4) + "-" * (25 - pct // 4)
            self.stream.write(f"\r{stage:9s} [{bar}] {i}/{total} {el:5.1f} s, "
                              f"~{eta:4.0f} s left ")
        elif pct // 10 != self.last_pct // 10 or i == total:
            self.stream.write(f"{stage}: {i}/{total} ({pct} %), {el:.1f} s\n")
        self.last_pct = pct
        self.stream.flush()

    def done(self) -> None:
        if self.tty and self.stage is not None and not self.quiet:
            self.stream.write("\n")
            self.stream.flush()


def _load_inputs(args):
    from catwalk.export.gltf import read_body
    from catwalk.garment.check import require_valid
    from catwalk.garment.model import load_garment
    from catwalk.simulate.settings import preset

    body_path = Path(args.body)
    if not body_path.is_file():
        raise InputError(f"--body {body_path}: no such file")
    if not str(args.output).lower().endswith(".glb"):
        raise InputError(f"-o {args.output}: the result is written as a .glb file")
    from catwalk.fileio import check_writable

    # before minutes of simulation: every output can be written
    obj_dir = getattr(args, "obj_dir", None)
    for flag, path in (("-o", args.output), ("--metrics", args.metrics), ("--iv", args.iv),
                       ("--obj-dir", obj_dir and Path(obj_dir) / "frame.obj")):
        if path:
            check_writable(path, flag)
    garment = load_garment(args.garment)
    require_valid(garment, Path(args.garment).parent)
    garment.size(args.size)   # a clear error for an unknown size before any work
    settings = preset(args.preset).with_(collider=args.collider, h=args.h)
    if args.fabric is not None:
        from catwalk.garment.check import resolve_fabric
        resolve_fabric(args.fabric, "--fabric")
    body = read_body(body_path)
    if body.parts is None or not body.landmarks:
        raise CatwalkError(f"--body {body_path}: the body has no parts or landmarks; make it "
                           "with `catwalk body make`")
    return body, garment, settings


def _write_metrics(path, metrics: dict) -> None:
    from catwalk.fileio import atomic_path

    with atomic_path(path) as tmp:
        Path(tmp).write_text(json.dumps(metrics, indent=2) + "\n")


def _summary(metrics: dict, keys) -> dict:
    return {k: metrics[k] for k in keys if k in metrics}


def _simulate(args, body, garment, settings, motion):
    from catwalk.simulate.pipeline import run_tryon

    bar = ProgressBar(quiet=args.quiet)
    try:
        return run_tryon(body, garment, motion, size=args.size, fabric=args.fabric,
                         settings=settings, progress=bar)
    finally:
        bar.done()


def _dress_cmd(args) -> int:
    from catwalk.export.garment import write_tryon
    from catwalk.simulate.pipeline import static_frames

    body, garment, settings = _load_inputs(args)
    res = _simulate(args, body, garment, settings, None)
    frames = static_frames(res.dressed)
    write_tryon(args.output, body, None, [frames], extras={"metrics": res.metrics})
    if args.iv:
        from catwalk.export.inventor import write_inventor
        write_inventor(args.iv, body.vertices, body.faces, [frames.mesh_at_frame(0)])
    if args.metrics:
        _write_metrics(args.metrics, res.metrics)
    out = _summary(res.metrics, ("garment", "size", "fabric", "points", "springs",
                                 "dressing_seconds", "max_seam_gap_mm", "max_strain"))
    out["settled"] = res.metrics["dressing"]["settled"]
    out["file"] = str(args.output)
    print(json.dumps(out, indent=2))
    return 0


def _tryon_cmd(args) -> int:
    if not math.isfinite(args.seconds) or not 0 < args.seconds <= 60:
        raise InputError(f"--seconds must be within (0, 60], got {args.seconds}")
    if not math.isfinite(args.fps) or not 10 <= args.fps <= 60:
        raise InputError(f"--fps must be within 10–60, got {args.fps}")
    body, garment, settings = _load_inputs(args)
    from catwalk.export.garment import write_tryon
    from catwalk.motion.gait import walk_motion
    from catwalk.simulate.pipeline import garment_frames

    if body.skeleton is None or body.skin_joints is None:
        raise CatwalkError(f"--body {args.body}: the body has no rig; make it with "
                           "`catwalk body make`")
    motion = walk_motion(body, args.seconds, speed=args.speed, style=args.style, fps=args.fps)
    res = _simulate(args, body, garment, settings, motion)
    w = res.walked
    frames = garment_frames(res.dressed, w.times, w.positions)
    extras = {"metrics": {k: v for k, v in res.metrics.items()
                          if k != "penetration_mm_per_frame"}}
    out = Path(args.output)
    if args.compress:
        from catwalk.export.compress import compress_glb
        with tempfile.TemporaryDirectory() as tmp:
            raw = Path(tmp) / "raw.glb"
            write_tryon(raw, body, motion, [frames], extras=extras)
            res.metrics["compression"] = compress_glb(raw, out)
    else:
        write_tryon(out, body, motion, [frames], extras=extras)
    if args.obj_dir:
        from catwalk.export.obj import write_obj_frames
        from catwalk.motion.skinning import body_frames
        verts, _ = body_frames(body, motion)
        final = Path(args.obj_dir)
        if final.exists() and any(final.iterdir()):
            raise InputError(f"--obj-dir {final}: exists and is not empty")
        tmpdir = Path(tempfile.mkdtemp(prefix=".obj-", dir=final.parent if
                                       final.parent.exists() else None))
        try:
            write_obj_frames(tmpdir, body.faces, verts, [frames])
            if final.exists():
                final.rmdir()
            shutil.move(str(tmpdir), str(final))
        except BaseException:
            shutil.rmtree(tmpdir, ignore_errors=True)
            raise
    if args.iv:
        from catwalk.export.inventor import write_inventor
        from catwalk.simulate.pipeline import static_frames
        write_inventor(args.iv, body.vertices, body.faces,
                       [static_frames(res.dressed).mesh_at_frame(0)])
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
    from catwalk.simulate.settings import PRESETS

    p.add_argument("--body", required=True, help="a body .glb (`catwalk body make`)")
    p.add_argument("--garment", required=True, help="a garment .json (garments/*.json)")
    p.add_argument("--size", help="garment size (default: the garment's default size)")
    p.add_argument("--fabric", help="fabric preset instead of the garment's (e.g. denim)")
    p.add_argument("--preset", default="balanced", choices=list(PRESETS),
                   help="speed/accuracy preset (default balanced)")
    p.add_argument("--collider", choices=["hybrid", "image", "object"],
                   help="collider mode (default: the preset's, object)")
    p.add_argument("--h", type=float, help="cloth grid spacing in metres (default: preset's)")
    p.add_argument("-o", "--output", required=True, help=output_help)
    p.add_argument("--metrics", help="also write the metrics as JSON to this file")
    p.add_argument("--iv", help="also write the dressed body as Open Inventor ASCII (.iv)")
    p.add_argument("--quiet", action="store_true", help="no progress bar")


def _bench_paper(args) -> int:
    from catwalk.bench.paper import main

    return main(args)


def _bench_dress(args) -> int:
    from catwalk.bench.dress import main

    return main(args)


def register(top, groups) -> None:
    from catwalk.simulate.settings import PRESETS

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

    p = groups["bench"].add_parser(
        "paper", help="the seed's table side by side: sewing the dress, walking it with the "
        "image-space and hybrid colliders (with penetration and strain)",
        description="The paper's scene (the dress at ≈3,372 points on a walking body): sewing "
        "time and ms per 30-fps frame per collider mode, each with max/p99 penetration and "
        "max strain; and the figure-10 failure of image space.")
    p.add_argument("--seconds", type=float, default=2.0, help="walk length (default 2)")
    p.add_argument("--modes", nargs="+", default=["image", "hybrid", "object"],
                   choices=["image", "hybrid", "object"], help="collider modes to walk")
    p.add_argument("--quiet", action="store_true", help="no progress")
    p.add_argument("--json", action="store_true", help="print JSON")
    p.set_defaults(func=_bench_paper)

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
