"""Content keys: the same inputs give the same key, so a result is simulated once.

A try-on's key hashes the body's content key (the scan's bytes, or its measurements), the
garment's id and version (the hash of its file and textures), the size, fabric, seconds and
preset, and the engine version: the hash of the simulation's own source code, so a change to
the solver never serves a result the new code would not make.
"""

from __future__ import annotations

import functools
import hashlib
import json
from pathlib import Path

import catwalk
from catwalk.garment.model import Garment

# the packages whose code decides what a try-on's result is
_ENGINE_PACKAGES = ("geometry", "body", "motion", "cloth", "collide", "garment", "exchange",
                    "render", "simulate")


def sha256(data: bytes) -> str:
    return hashlib.sha256(data).hexdigest()


def canonical(obj) -> bytes:
    """``obj`` as canonical JSON bytes (sorted keys, no spaces)."""
    return json.dumps(obj, sort_keys=True, separators=(",", ":")).encode()


@functools.lru_cache(maxsize=1)
def engine_version() -> str:
    """catwalk's version and a hash of the simulation's source files."""
    root = Path(catwalk.__file__).resolve().parent
    h = hashlib.sha256(catwalk.__version__.encode())
    for pkg in _ENGINE_PACKAGES:
        for f in sorted((root / pkg).rglob("*.py")):
            h.update(f.relative_to(root).as_posix().encode())
            h.update(f.read_bytes())
    return f"{catwalk.__version__}+{h.hexdigest()[:16]}"


def measurements_key(sex: str, values: dict[str, float]) -> str:
    return sha256(canonical({"sex": sex, "measurements": values}))


def scan_key(data: bytes, sex: str | None) -> str:
    return sha256(canonical({"sex": sex, "scan": sha256(data)}))


def tryon_key(body_key: str, garment_id: str, garment_version: str, size: str,
              fabric: str | None, seconds: float, preset: str) -> str:
    return sha256(canonical({
        "body": body_key, "garment": garment_id, "version": garment_version, "size": size,
        "fabric": fabric, "seconds": round(float(seconds), 6), "preset": preset,
        "engine": engine_version()}))


def garment_version(path: Path, garment: Garment) -> str:
    """The hash of the garment file and the texture images it names."""
    parts = [sha256(path.read_bytes())]
    for p in garment.panels:
        if p.texture is not None:
            img = path.parent / str(p.texture["image"])
            parts.append(sha256(img.read_bytes()) if img.is_file() else "missing")
    return sha256("\n".join(parts).encode())[:32]
