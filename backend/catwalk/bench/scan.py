"""``catwalk bench scan``: a scan of a body the template was never fitted to (see
:mod:`catwalk.body.synthetic`), at several face counts, registered as ``catwalk body
from-scan`` does (loading the file included), on one core by default; the time and the
distance of the registered body's surface to the true surface (both directions together)."""

from __future__ import annotations

import json
import os
import tempfile
import time
from functools import lru_cache
from pathlib import Path

import numpy as np

from catwalk.bench.cloth import machine
from catwalk.body import synthetic as sy
from catwalk.body.from_scan import body_from_scan
from catwalk.body.measure import measure_body
from catwalk.body.rig import measured_base_body
from catwalk.body.skinning import body_frames
from catwalk.body.types import GIRTHS
from catwalk.errors import InputError
from catwalk.exchange.scan import MAX_FACES, load_scan
from catwalk.geometry.surface import BodySurface
from catwalk.motion.checks import walk_folds
from catwalk.motion.gait import walk_motion
from catwalk.render.preview import render_meshes, save_png

FACES = (50_000, 300_000, 2_000_000)


def run_one(case_name: str, faces: int, folder: Path, seed: int = 0, png: str | None = None
            ) -> dict:
    truth = sy.true_body(sy.case(case_name))
    v, f = sy.scan_of(truth, faces=faces, seed=seed)
    if len(f) > MAX_FACES:   # subdivision overshoots a little: keep within what a scan may be
        f = f[:MAX_FACES]
    path = folder / f"{case_name}-{faces}.ply"
    sy.write_scan(path, v, f)
    t0 = time.perf_counter()
    scan = load_scan(path)
    body, report = body_from_scan(scan)
    seconds = time.perf_counter() - t0
    truth_v = sy.truth_in_scan_frame(truth, scan, report)
    dist = sy.distance_to_truth(truth_v, truth.faces, body.vertices, body.faces)
    if png:
        figure(scan, body, truth_v, truth.faces, png)
    girth_cm = {k: round(100 * (m["body"] - m["scan"]), 2)
                for k, m in report["measurements"].items() if k in GIRTHS}
    true_m = measure_body(truth_v, truth.faces, sex=report["sex"])
    truth_cm = {k: round(100 * (m["body"] - true_m[k]), 2)
                for k, m in report["measurements"].items() if k in GIRTHS and k in true_m}
    return {"case": case_name, "faces": int(len(scan.faces)), "seconds": round(seconds, 2),
            **dist, "scan_to_body_mm": report["scan_to_body_mm"],
            "body_to_scan_mm": report["body_to_scan_mm"], "girth_error_cm": girth_cm,
            "girth_error_vs_truth_cm": truth_cm,
            "rest_folds": report["registration"]["folded_triangle_pairs"],
            "walk_folds": walk_folds_of(body),
            "template_walk_folds": template_walk_folds(report["sex"]),
            "stages_s": report["seconds"]}


def walk_folds_of(body) -> int:
    """Triangle pairs the body's 2 s walk folds over at worst (:func:`walk_folds`)."""
    motion = walk_motion(body, 2.0, speed=1.2, fps=30)
    return walk_folds(body, body_frames(body, motion)[0])


@lru_cache(maxsize=2)
def template_walk_folds(sex: str) -> int:
    """The same for the MakeHuman template of that sex (its skinning's own creases)."""
    return walk_folds_of(measured_base_body(0.0 if sex == "female" else 1.0))


def distance_colours(mm: np.ndarray, top: float = 4.0) -> np.ndarray:
    """Blue (0 mm) through green and yellow to red (``top`` mm and more), per value."""
    t = np.clip(np.asarray(mm) / top, 0.0, 1.0)[:, None]
    stops = np.array([[0.20, 0.35, 0.85], [0.20, 0.75, 0.35], [0.95, 0.85, 0.20],
                      [0.85, 0.15, 0.15]])
    pos = t * (len(stops) - 1)
    i = np.minimum(pos.astype(int), len(stops) - 2)
    f = pos - i
    return stops[i[:, 0]] * (1 - f) + stops[i[:, 0] + 1] * f


def figure(scan, body, truth_v, truth_f, path, size=(300, 600)) -> None:
    """The scan, the registered body, and the body coloured by its distance to the true
    surface (blue 0 → red ≥ 4 mm), front and side, side by side."""
    mm = np.abs(BodySurface(truth_f, len(truth_v)).signed_distance(truth_v, body.vertices))
    meshes = [(scan.vertices, scan.faces, (0.75, 0.78, 0.70)),
              (body.vertices, body.faces, (0.80, 0.66, 0.56)),
              (body.vertices, body.faces, distance_colours(mm * 1000.0))]
    lo = np.minimum(scan.vertices.min(axis=0), body.vertices.min(axis=0))
    hi = np.maximum(scan.vertices.max(axis=0), body.vertices.max(axis=0))
    rows = [np.concatenate([render_meshes([m], view=view, size=size, bbox=(lo, hi))
                            for m in meshes], axis=1) for view in ("front", "right")]
    save_png(np.concatenate(rows, axis=0), path)


def main(args) -> int:
    try:
        faces = [int(x) for x in args.faces.split(",") if x.strip()]
    except ValueError:
        raise InputError(f"--faces: comma-separated face counts, got {args.faces!r}") from None
    if not faces or any(not 1_000 <= n <= 2_000_000 for n in faces):
        raise InputError("--faces: each count within 1,000–2,000,000")
    if args.png:
        from catwalk.fileio import check_writable
        from catwalk.render.preview import image_format

        image_format(args.png, "--png")
        check_writable(args.png, "--png")
    if args.cores < 1 or args.cores > (os.cpu_count() or 1):
        raise InputError(f"--cores: 1–{os.cpu_count()}")
    if hasattr(os, "sched_setaffinity"):
        os.sched_setaffinity(0, set(sorted(os.sched_getaffinity(0))[: args.cores]))
    rows = []
    with tempfile.TemporaryDirectory(prefix="catwalk-bench-scan-") as tmp:
        run_one(args.case, 20_000, Path(tmp))        # warm-up: imports, numba caches
        for i, n in enumerate(faces):
            rows.append(run_one(args.case, n, Path(tmp), png=args.png if i == 0 else None))
    if args.json:
        print(json.dumps({"scans": rows}))
        return 0
    print(f"Scan registration, case {args.case!r} ({args.cores} core(s)); machine: {machine()}")
    print(f"{'faces':>9} {'seconds':>8} {'mean mm':>8} {'p99 mm':>7} {'max mm':>7} "
          f"{'folds':>11}  girths (cm): body − scan | body − truth")
    for r in rows:
        folds = f"{r['walk_folds']}/{r['template_walk_folds']}"
        print(f"{r['faces']:>9,} {r['seconds']:>8.2f} {r['mean_mm']:>8.2f} {r['p99_mm']:>7.2f} "
              f"{r['max_mm']:>7.2f} {folds:>11}  {r['girth_error_cm']} | "
              f"{r['girth_error_vs_truth_cm']}")
    print("folds: triangle pairs folded over at worst in a 2 s walk, the scan's body / the "
          "template's")
    return 0


def register(bench) -> None:
    p = bench.add_parser("scan", help="scan → registered body: time and distance to the truth")
    p.add_argument("--faces", default=",".join(str(n) for n in FACES),
                   help="comma-separated face counts of the scans (default: %(default)s)")
    p.add_argument("--case", default="belly", choices=("belly", "shoulders", "hip"),
                   help="the true body (catwalk.body.synthetic.CASES)")
    p.add_argument("--cores", type=int, default=1, help="CPU cores to run on (default 1)")
    p.add_argument("--png", default=None, help="also draw the first scan, its registered body "
                                               "and their distance as colour to this PNG")
    p.add_argument("--json", action="store_true", help="JSON: {\"scans\": [...]}")
    p.set_defaults(func=main)
