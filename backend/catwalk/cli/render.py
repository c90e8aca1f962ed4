"""``catwalk render FILE.glb --time T -o frame.png``: frames of a catwalk .glb, on the CPU.

Several ``--time`` values and/or ``--view`` values make one contact sheet: one row per view,
one column per time, the camera fixed over the whole walk so the motion reads across a row.
The image is PNG or JPEG by the output's extension. Limits (a frame is rendered 2×
supersampled, ~400 bytes of memory per pixel): a frame at most :data:`MAX_FRAME_PIXELS`, a
sheet at most :data:`MAX_SHEET_PIXELS` and :data:`MAX_CELLS` frames.
"""

from __future__ import annotations

import json
import math
import time

import numpy as np

from catwalk.bench import cpu_model
from catwalk.body.rig import rigged_base_body
from catwalk.errors import InputError
from catwalk.exchange.scene import load_scene
from catwalk.fileio import check_writable
from catwalk.geometry.raster import view_yaw
from catwalk.render.preview import image_format, render_meshes, save_image
from catwalk.render.sheet import render_sheet

MAX_SIDE = 8192
MAX_FRAME_PIXELS = 4096 * 4096     # ~6.5 GB while rendering it
MAX_SHEET_PIXELS = 8192 * 4096     # the whole contact sheet
MAX_CELLS = 64                     # frames in one contact sheet


def _size(text: str) -> tuple[int, int]:
    try:
        w, h = (int(x) for x in text.lower().split("x"))
    except ValueError:
        raise InputError(f"--size must be WIDTHxHEIGHT, e.g. 512x768, not {text!r}") from None
    if not (16 <= w <= MAX_SIDE and 16 <= h <= MAX_SIDE):
        raise InputError(f"--size {text} out of range 16..{MAX_SIDE}")
    if w * h > MAX_FRAME_PIXELS:
        raise InputError(f"--size {text}: {w * h:,} pixels; a frame has at most "
                         f"{MAX_FRAME_PIXELS:,} (e.g. 4096x4096)")
    return w, h


def _sheet(times, views, size) -> None:
    """Refuse a contact sheet too large to make."""
    cells = len(times) * len(views)
    pixels = cells * size[0] * size[1]
    if cells > MAX_CELLS:
        raise InputError(f"--time × --view: {len(times)} × {len(views)} = {cells} frames; a "
                         f"contact sheet has at most {MAX_CELLS}")
    if pixels > MAX_SHEET_PIXELS:
        raise InputError(f"--time × --view × --size: a {len(times) * size[0]}×"
                         f"{len(views) * size[1]} contact sheet, {pixels:,} pixels; at most "
                         f"{MAX_SHEET_PIXELS:,} (fewer frames or a smaller --size)")


def _render(args) -> int:
    for t in args.time:
        if not math.isfinite(t) or t < 0:
            raise InputError(f"--time must be a number of seconds ≥ 0, not {t}")
    for v in args.view:
        try:
            view_yaw(v)
        except InputError as exc:
            raise InputError(f"--view: {exc}") from None
    size = _size(args.size)
    _sheet(args.time, args.view, size)
    image_format(args.output)
    check_writable(args.output, "-o")
    scene = load_scene(args.file)
    for t in args.time:
        if scene.animated and t > scene.duration + 1e-9:
            raise InputError(f"--time {t} is past the end of the animation "
                             f"({scene.duration:.3f} s)")
    image = render_sheet(scene, args.time, args.view, size)
    save_image(image, args.output, "-o")
    print(args.output)
    return 0


def _bench(args) -> int:
    """Preview render cost on the MakeHuman body (26,756 triangles), best of ``--repeats``."""
    if args.repeats < 1:
        raise InputError("--repeats must be at least 1")
    size = _size(args.size)
    body = rigged_base_body(0.0)
    mesh = [(body.vertices, body.faces, (0.8, 0.66, 0.58))]
    render_meshes(mesh, view="front", size=(64, 96))  # compile / load the kernels
    times = []
    for _ in range(args.repeats):
        t = time.perf_counter()
        render_meshes(mesh, view="front", size=size)
        times.append(time.perf_counter() - t)
    out = {"triangles": int(len(body.faces)), "size": list(size), "supersample": 2,
           "ms_per_frame": 1000 * min(times), "ms_median": 1000 * float(np.median(times)),
           "machine": cpu_model()}
    if args.json:
        print(json.dumps(out))
    else:
        print(f"render: {out['triangles']} triangles at {size[0]}x{size[1]} (2x supersampled): "
              f"best {out['ms_per_frame']:.1f} ms, median {out['ms_median']:.1f} ms "
              f"over {args.repeats} frames ({out['machine']})")
    return 0


def register(top, groups) -> None:
    b = groups["bench"].add_parser("render", help="CPU preview render cost on a MakeHuman body")
    b.add_argument("--size", default="512x768", help="WIDTHxHEIGHT in pixels")
    b.add_argument("--repeats", type=int, default=10)
    b.add_argument("--json", action="store_true", help="print JSON")
    b.set_defaults(func=_bench)

    p = top.add_parser("render", help="render frames of a .glb to PNG or JPEG (CPU)")
    p.add_argument("file", help="a .glb written by catwalk")
    p.add_argument("--time", type=float, nargs="+", default=[0.0],
                   help="seconds into the animation (several: a contact sheet)")
    p.add_argument("--view", nargs="+", default=["front"],
                   help="front, side, back, right or a yaw in degrees (several: one row each)")
    p.add_argument("--size", default="512x768",
                   help=f"WIDTHxHEIGHT of one frame, pixels (at most {MAX_FRAME_PIXELS:,}; a "
                        f"contact sheet at most {MAX_SHEET_PIXELS:,} and {MAX_CELLS} frames)")
    p.add_argument("-o", "--output", required=True,
                   help="the image to write: .png, or .jpg / .jpeg for JPEG")
    p.set_defaults(func=_render)
