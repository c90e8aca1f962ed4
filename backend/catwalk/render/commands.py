"""``catwalk render FILE.glb --time T -o frame.png``: a frame of a catwalk .glb, on the CPU."""

from __future__ import annotations

from catwalk.errors import InputError


def _size(text: str) -> tuple[int, int]:
    try:
        w, h = (int(x) for x in text.lower().split("x"))
    except ValueError:
        raise InputError(f"--size must be WIDTHxHEIGHT, e.g. 512x768, not {text!r}") from None
    if not (16 <= w <= 8192 and 16 <= h <= 8192):
        raise InputError(f"--size {text} out of range 16..8192")
    return w, h


def _render(args) -> int:
    from catwalk.export.scene import load_scene
    from catwalk.render.preview import render_meshes, save_png

    if args.time < 0:
        raise InputError(f"--time must be ≥ 0, not {args.time}")
    scene = load_scene(args.file)
    if scene.motion is not None and args.time > scene.duration + 1e-9:
        raise InputError(f"--time {args.time} is past the end of the animation "
                         f"({scene.duration:.3f} s)")
    meshes = [(v, f, rgb) for _, v, f, rgb in scene.meshes_at(args.time)]
    image = render_meshes(meshes, view=args.view, size=_size(args.size))
    save_png(image, args.output)
    print(args.output)
    return 0


def register(top, groups) -> None:
    p = top.add_parser("render", help="render a frame of a .glb to PNG (CPU)")
    p.add_argument("file", help="a .glb written by catwalk")
    p.add_argument("--time", type=float, default=0.0, help="seconds into the animation")
    p.add_argument("--view", default="front", help="front, side, back, right or a yaw in degrees")
    p.add_argument("--size", default="512x768", help="WIDTHxHEIGHT in pixels")
    p.add_argument("-o", "--output", required=True, help="PNG to write")
    p.set_defaults(func=_render)
