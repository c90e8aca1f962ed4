"""Top-level commands that belong to no area: ``catwalk assets``."""

from __future__ import annotations

from catwalk.assets import ensure_assets


def _assets(args) -> int:
    path = ensure_assets(verbose=not args.quiet)
    print(path)
    return 0


def register(top, groups) -> None:
    p = top.add_parser("assets", help="download and unpack the MakeHuman CC0 assets (once)")
    p.add_argument("--quiet", action="store_true")
    p.set_defaults(func=_assets)
