"""Smaller try-on files for the browser: gltfpack (meshoptimizer), installed in tools/node.

``compress_glb(src, dst)`` quantises (KHR_mesh_quantization: 14-bit positions, 16-bit morph
displacements, 12-bit rotations) and compresses (EXT_meshopt_compression) a catwalk .glb,
keeping the morph targets, the STEP weights channel and the clip's keyframe times as written
(``-af 0``: no resampling, which would move the garment frame switches by up to one frame)
and the named nodes (``-kn``) and materials (``-km``). Typical ratio on a walking try-on:
about 7×. A compressed file is for players (three.js: ``GLTFLoader.setMeshoptDecoder``); catwalk's
own readers (``read_body``, ``read_garments``, ``catwalk render``) need the uncompressed file.
"""

from __future__ import annotations

import subprocess
from pathlib import Path

from catwalk.errors import InputError, SetupError
from catwalk.fileio import atomic_path

GLTFPACK_ARGS = ("-cc", "-af", "0", "-kn", "-km")


def gltfpack_script() -> Path:
    from catwalk.config import get_config

    tools = get_config().node_tools_dir
    script = tools / "node_modules" / "gltfpack" / "cli.js"
    if not script.is_file():
        raise SetupError(f"gltfpack is not installed in {tools}: run `make install`")
    return script


def compress_glb(src: str | Path, dst: str | Path) -> dict:
    """Write ``dst``, a meshopt-compressed copy of ``src`` (atomically). Returns
    ``{"input_bytes", "output_bytes", "ratio"}``."""
    src, dst = Path(src), Path(dst)
    if not src.is_file():
        raise InputError(f"{src}: no such file")
    if src.resolve() == dst.resolve():
        raise InputError(f"{dst}: compress into another file, not the input")
    if dst.suffix.lower() != ".glb":
        raise InputError(f"{dst}: the compressed file must be a .glb")
    script = gltfpack_script()
    with atomic_path(dst) as tmp:
        res = subprocess.run(["node", str(script), "-i", str(src.resolve()), "-o", str(tmp),
                              *GLTFPACK_ARGS], capture_output=True, text=True, timeout=600)
        if res.returncode != 0 or not tmp.is_file() or tmp.stat().st_size == 0:
            msg = (res.stderr or res.stdout).strip()[-2000:]
            raise InputError(f"{src}: gltfpack failed ({res.returncode}): {msg}")
    a, b = src.stat().st_size, dst.stat().st_size
    return {"input_bytes": a, "output_bytes": b, "ratio": a / b}


def compress_bytes(data: bytes) -> tuple[bytes, dict]:
    """A meshopt-compressed copy of the .glb ``data`` and ``{"input_bytes", "output_bytes",
    "ratio"}``."""
    import tempfile

    with tempfile.TemporaryDirectory(prefix="catwalk-pack-") as tmp:
        src, dst = Path(tmp) / "in.glb", Path(tmp) / "out.glb"
        src.write_bytes(data)
        stats = compress_glb(src, dst)
        return dst.read_bytes(), stats
