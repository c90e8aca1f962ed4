"""Cloth commands: ``catwalk bench cloth``, ``catwalk bench drape``."""

from __future__ import annotations

from catwalk.bench import cloth as bench_cloth
from catwalk.bench import drape as bench_drape


def register(top, groups) -> None:
    bench_cloth.register(groups["bench"])
    bench_drape.register(groups["bench"])
