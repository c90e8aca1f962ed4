"""``catwalk render FILE.glb --time T -o frame.png``: frames of a catwalk .glb, on the CPU.

Several ``--time`` values and/or ``--view`` values make one contact sheet: one row per view,
one column per time, the camera fixed over the whole walk so the motion reads across a row.
"""

from __future__ import annotations

import numpy as np

from catwalk.errors import InputError


def _size(text: str) -> tuple[int, int]:
    try:
        w, h = (int(x) for x in text.lower().split("x"))
    except ValueError:
        raise InputError(f"--size must be WIDTHxHEIGHT, e.g. 512x768, not {text!r}") from None
    if not (16 <= w <= 8192 and 16 <= h <= 8192):
        raise InputError(f"--size {text} out of range 16..8192")
    return w, h


def render_sheet(scene, times, views, size, cancel=None) -> np.ndarray:
    """Images of ``scene`` at ``times`` (columns) from ``views`` (rows). Every cell has the
    same scale — a box as large as the largest frame's — centred on its own frame, so a body
    walking metres down the catwalk stays the same size and in view. ``cancel()`` is asked
    before each cell (:class:`~catwalk.errors.Cancelled`)."""
    from catwalk.render.preview import render_meshes

    frames = {t: [(v, f, rgb) for _, v, f, rgb in scene.meshes_at(t)] for t in times}
    boxes = {}
    for t, ms in frames.items():
        v = np.concatenate([m[0] for m in ms])
        lo, hi = v.min(axis=0), v.max(axis=0)
        lo[1] = min(lo[1], 0.0)
        boxes[t] = (lo, hi)
    extent = np.max([hi - lo for lo, hi in boxes.values()], axis=0)
    rows = []
    for view in views:
        cells = []
        for t in times:
            lo, hi = boxes[t]
            mid = 0.5 * (lo + hi)
            box = (mid - 0.5 * extent, mid + 0.5 * extent)
            box[0][1], box[1][1] = lo[1], lo[1] + extent[1]
            bbox = None if len(times) == 1 else box
            if cancel is not None and cancel():
                from catwalk.errors import Cancelled

                raise Cancelled("try-on cancelled")
            cells.append(render_meshes(frames[t], view=view, size=size, bbox=bbox))
        rows.append(np.concatenate(cells, axis=1))
    return np.concatenate(rows, axis=0)


def _render(args) -> int:
    from catwalk.exchange.scene import load_scene
    from catwalk.render.preview import save_png

    for t in args.time:
        if t < 0:
            raise InputError(f"--time must be ≥ 0, not {t}")
    scene = load_scene(args.file)
    for t in args.time:
        if scene.animated and t > scene.duration + 1e-9:
            raise InputError(f"--time {t} is past the end of the animation "
                             f"({scene.duration:.3f} s)")
    image = render_sheet(scene, args.time, args.view, _size(args.size))
    save_png(image, args.output)
    print(args.output)
    return 0


def _bench(args) -> int:
    """Preview render cost on the MakeHuman body (26,756 triangles), best of ``--repeats``."""
    import json
    import time

    from catwalk.bench import cpu_model
    from catwalk.body.rig import rigged_base_body
    from catwalk.render.preview import render_meshes

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

    p = top.add_parser("render", help="render frames of a .glb to PNG (CPU)")
    p.add_argument("file", help="a .glb written by catwalk")
    p.add_argument("--time", type=float, nargs="+", default=[0.0],
                   help="seconds into the animation (several: a contact sheet)")
    p.add_argument("--view", nargs="+", default=["front"],
                   help="front, side, back, right or a yaw in degrees (several: one row each)")
    p.add_argument("--size", default="512x768", help="WIDTHxHEIGHT of one frame, pixels")
    p.add_argument("-o", "--output", required=True, help="PNG to write")
    p.set_defaults(func=_render)
