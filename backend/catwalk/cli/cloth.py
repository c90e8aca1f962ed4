"""Cloth commands: ``catwalk bench cloth``, ``bench drape``, ``bench cantilever``."""

from __future__ import annotations

from catwalk.bench import cantilever as bench_cantilever
from catwalk.bench import cloth as bench_cloth
from catwalk.bench import drape as bench_drape


def register(top, groups) -> None:
    bench_cloth.register(groups["bench"])
    bench_drape.register(groups["bench"])
    bench_cantilever.register(groups["bench"])
