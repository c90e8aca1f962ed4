"""``catwalk bench collide`` (see :mod:`catwalk.bench.collide`)."""

from __future__ import annotations

from catwalk.bench.collide import main


def _bench(args) -> int:
    return main(args)


def register(top, groups) -> None:
    p = groups["bench"].add_parser(
        "collide", help="collider costs per frame and substep for each mode, and what each "
        "skip saves, on a walking body against ~3,400 cloth points",
        description="Collider costs (image, object, hybrid) on a walking body against a "
        "synthetic dress: per frame (depth maps, hierarchy refit) and per substep (queries), "
        "and each skip's saving. CPU time of the calling thread.")
    p.add_argument("--body", choices=("makehuman", "mannequin"), default="makehuman",
                   help="MakeHuman body walking (default) or the capsule mannequin")
    p.add_argument("--mode", choices=("all", "hybrid", "image", "object"), default="all")
    p.add_argument("--frames", type=int, default=10, help="frames measured (after 2 warm-up)")
    p.add_argument("--substeps", type=int, default=10,
                   help="collision substeps per 30-fps frame (default 10)")
    p.add_argument("--points", type=int, default=3400, help="cloth points (default 3400)")
    p.add_argument("--map-size", type=int, default=256, help="depth map size (default 256)")
    p.add_argument("--drift", type=float, default=0.05,
                   help="cloth speed relative to the body, m/s (default 0.05)")
    p.add_argument("--repeat", type=int, default=3,
                   help="runs per measurement; the least disturbed is kept (default 3)")
    p.add_argument("--no-skips", action="store_true", help="do not measure the skips")
    p.add_argument("--maps-png", metavar="PATH",
                   help="also write the front/back depth maps (the paper's figure 4) as PNG")
    p.add_argument("--figure10-png", metavar="PATH",
                   help="also write the paper's figure-10 case (image vs hybrid) as PNG")
    p.add_argument("--json", action="store_true", help="print JSON")
    p.set_defaults(func=_bench)
