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


def render_sheet(scene, times, views, size) -> np.ndarray:
    """Images of ``scene`` at ``times`` (columns) from ``views`` (rows), one fixed camera box
    per view covering every frame drawn."""
    from catwalk.render.preview import render_meshes

    frames = {t: [(v, f, rgb) for _, v, f, rgb in scene.meshes_at(t)] for t in times}
    allv = np.concatenate([m[0] for ms in frames.values() for m in ms])
    lo, hi = allv.min(axis=0), allv.max(axis=0)
    lo[1] = min(lo[1], 0.0)
    rows = []
    for view in views:
        cells = []
        for t in times:
            bbox = None if len(times) == 1 else (lo, hi)
            cells.append(render_meshes(frames[t], view=view, size=size, bbox=bbox))
        rows.append(np.concatenate(cells, axis=1))
    return np.concatenate(rows, axis=0)


def _render(args) -> int:
    from catwalk.export.scene import load_scene
    from catwalk.render.preview import save_png

    for t in args.time:
        if t < 0:
            raise InputError(f"--time must be ≥ 0, not {t}")
    scene = load_scene(args.file)
    for t in args.time:
        if scene.motion is not None and t > scene.duration + 1e-9:
            raise InputError(f"--time {t} is past the end of the animation "
                             f"({scene.duration:.3f} s)")
    image = render_sheet(scene, args.time, args.view, _size(args.size))
    save_png(image, args.output)
    print(args.output)
    return 0


def register(top, groups) -> None:
    p = top.add_parser("render", help="render frames of a .glb to PNG (CPU)")
    p.add_argument("file", help="a .glb written by catwalk")
    p.add_argument("--time", type=float, nargs="+", default=[0.0],
                   help="seconds into the animation (several: a contact sheet)")
    p.add_argument("--view", nargs="+", default=["front"],
                   help="front, side, back, right or a yaw in degrees (several: one row each)")
    p.add_argument("--size", default="512x768", help="WIDTHxHEIGHT of one frame, pixels")
    p.add_argument("-o", "--output", required=True, help="PNG to write")
    p.set_defaults(func=_render)
