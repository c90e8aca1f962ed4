"""``catwalk body info FILE``, ``catwalk body measure FILE`` and ``catwalk body from-scan SCAN``:
scans, their measurements, and the shopper's own body registered to a scan."""

from __future__ import annotations

import json
import sys
import time

import numpy as np

from catwalk.bench import scan as bench_scan
from catwalk.body.from_scan import body_from_scan
from catwalk.body.measure import measure_body
from catwalk.errors import InputError
from catwalk.exchange.gltf import glb_bytes
from catwalk.exchange.scan import load_scan
from catwalk.fileio import atomic_path, check_writable


def _round(obj, nd=4):
    if isinstance(obj, float):
        return round(obj, nd)
    if isinstance(obj, dict):
        return {k: _round(v, nd) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_round(v, nd) for v in obj]
    return obj


def dumps(obj, indent: int = 0) -> str:
    """Indented JSON with short lists (coordinates, matrix rows) kept on one line."""
    pad = "  " * indent
    if isinstance(obj, dict):
        if not obj:
            return "{}"
        items = [f'{pad}  {json.dumps(str(k))}: {dumps(v, indent + 1)}' for k, v in obj.items()]
        return "{\n" + ",\n".join(items) + "\n" + pad + "}"
    if isinstance(obj, (list, tuple)):
        if all(not isinstance(v, (dict, list, tuple)) for v in obj):
            return json.dumps(list(obj))
        items = [f"{pad}  {dumps(v, indent + 1)}" for v in obj]
        return "[\n" + ",\n".join(items) + "\n" + pad + "]"
    return json.dumps(obj)


def _info(args) -> int:
    scan = load_scan(args.file)
    print(dumps(scan.info()))
    return 0


def _measure(args) -> int:
    scan = load_scan(args.file)
    try:
        m = measure_body(scan.vertices, scan.faces, sex=args.sex)
    except InputError as exc:  # name the file: "FILE: measure: no crotch found; …"
        raise InputError(f"{scan.path}: {exc}") from None
    inv = np.linalg.inv(scan.transform)
    lm = m.pop("landmarks")
    pts = np.array(list(lm.values()), dtype=np.float64)
    file_pts = pts @ inv[:3, :3].T + inv[:3, 3]
    out = {
        "file": scan.path,
        "sex": args.sex,
        "units": "m",
        **m,
        "landmarks": lm,
        "frame": "landmarks: metres, +Y up, facing +Z, feet on y = 0, centred on x = z = 0 "
                 "(landmarks_file: the same points in the file's own coordinates)",
        "landmarks_file": dict(zip(lm.keys(), file_pts.tolist(), strict=True)),
        "scan": {"units": scan.units, "up_axis": scan.up, "forward_axis": scan.forward,
                 "vertices": int(len(scan.vertices)), "faces": int(len(scan.faces))},
    }
    print(dumps(_round(out)))
    return 0


def _from_scan(args) -> int:
    if not str(args.output).lower().endswith(".glb"):
        raise InputError(f"-o {args.output}: the body is written as a .glb file")
    check_writable(args.output, "-o")
    if args.report:
        check_writable(args.report, "--report")
    t0 = time.perf_counter()
    scan = load_scan(args.scan)

    def progress(stage, done, total):
        print(f"{stage}: done at {time.perf_counter() - t0:.1f} s", file=sys.stderr)

    load_s = time.perf_counter() - t0
    progress("load", 0, 1)
    try:
        body, report = body_from_scan(scan, sex=args.sex, progress=progress, t0=t0)
    except InputError as exc:   # name the file: "SCAN: scan: covers 40 % of a body; …"
        raise InputError(f"{scan.path}: {exc}") from None
    data = glb_bytes(body)
    info = {k: v for k, v in scan.info().items() if k not in ("file", "transform")}
    report = {"file": str(args.output), "scan": info, **report}
    report["seconds"] = {"load": round(load_s, 3), **report["seconds"]}
    with atomic_path(args.output, "-o") as tmp:
        tmp.write_bytes(data)
    text = dumps(report)
    if args.report:
        with atomic_path(args.report, "--report") as tmp:
            tmp.write_text(text + "\n")
    print(text)
    return 0


def register(top, groups) -> None:
    bench_scan.register(groups["bench"])
    body = groups["body"]
    p = body.add_parser(
        "info", help="load a body scan (OBJ, PLY, STL, GLB) and report units, axes, holes",
        description="Load a body scan (OBJ, PLY, STL, GLB): detect its units (m/dm/cm/mm) and "
                    "up/facing axes, and report vertices, faces, watertightness, holes and "
                    "components as JSON.")
    p.add_argument("file", help="scan file (.obj, .ply, .stl, .glb)")
    p.set_defaults(func=_info)

    p = body.add_parser(
        "measure", help="measurements and landmarks of a body or scan, as JSON",
        description="Measure a standing body or scan from its surface (ISO 8559-1 style girths "
                    "as convex-hull lengths of horizontal sections): height, bust/chest, "
                    "underbust, bust span, waist, hips, inseam, shoulder width, arm length, "
                    "upper-arm girth, neck girth (metres) and landmark positions. See "
                    "docs/bodies-measure.md.")
    p.add_argument("file", help="body or scan file (.obj, .ply, .stl, .glb)")
    p.add_argument("--sex", choices=("female", "male"), default=None,
                   help="female: bust, underbust and bust span; male: chest, no underbust or "
                        "bust span")
    p.set_defaults(func=_measure)

    p = body.add_parser(
        "from-scan", help="a rigged body registered to a scan's surface → .glb",
        description="Register the MakeHuman template to a body scan (OBJ, PLY, STL, GLB; any "
                    "units and up axis; holes allowed; standing in an A-pose or near it): "
                    "aligned, fitted to the scan's measurements, its arms posed to the scan's, "
                    "then non-rigidly registered to the surface and rigged again. Writes a "
                    "body like `catwalk body make`'s and prints a report (surface distances "
                    "both ways in mm, measurements of both, seconds). See docs/bodies.md.")
    p.add_argument("scan", help="scan file (.obj, .ply, .stl, .glb)")
    p.add_argument("-o", "--output", required=True, help="the body .glb to write")
    p.add_argument("--report", default=None, help="also write the report (JSON) here")
    p.add_argument("--sex", choices=("female", "male"), default=None,
                   help="the body model's sex (default: inferred from the scan's shape)")
    p.set_defaults(func=_from_scan)
