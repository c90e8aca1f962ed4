"""Cloth commands: ``catwalk bench cloth``, ``catwalk bench drape``."""

from __future__ import annotations


def register(top, groups) -> None:
    from catwalk.bench import cloth as bench_cloth
    from catwalk.bench import drape as bench_drape

    bench_cloth.register(groups["bench"])
    bench_drape.register(groups["bench"])
