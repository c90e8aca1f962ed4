"""Smaller try-on files for the browser: gltfpack (meshoptimizer), installed in tools/node.

``compress_glb(src, dst)`` quantises (KHR_mesh_quantization: 14-bit positions, 16-bit morph
displacements, 8-bit normals, 12-bit rotations; texture coordinates stay float, ``-vtf``, so
``TEXCOORD_1`` keeps the pattern's metres) and compresses (EXT_meshopt_compression) a catwalk
.glb, keeping the morph targets, the weights and scale channels and the clip's keyframe times
as written (``-af 0``: no resampling), the named nodes (``-kn``: the garments' chunk nodes),
the materials (``-km``) and the texture coordinates no material uses (``-kv``). gltfpack drops
application attributes (``_PART``) and extras: a player gets the frame times from the weights
channels and the chunks from the node names. A compressed file is for players (three.js:
``GLTFLoader.setMeshoptDecoder``); catwalk's own readers (``read_body``, ``read_garments``,
``catwalk render``) need the uncompressed file.
"""

from __future__ import annotations

import subprocess
import tempfile
import time
from pathlib import Path

from catwalk.config import get_config
from catwalk.errors import Cancelled, InputError, SetupError
from catwalk.fileio import atomic_path

GLTFPACK_ARGS = ("-cc", "-af", "0", "-kn", "-km", "-kv", "-vtf")


def gltfpack_script() -> Path:
    tools = get_config().node_tools_dir
    script = tools / "node_modules" / "gltfpack" / "cli.js"
    if not script.is_file():
        raise SetupError(f"gltfpack is not installed in {tools}: run `make install`")
    return script


def compress_glb(src: str | Path, dst: str | Path, cancel=None) -> dict:
    """Write ``dst``, a meshopt-compressed copy of ``src`` (atomically). Returns
    ``{"input_bytes", "output_bytes", "ratio"}``. ``cancel()`` is asked every 50 ms while
    gltfpack runs (it is stopped and :class:`~catwalk.errors.Cancelled` raised)."""
    src, dst = Path(src), Path(dst)
    if not src.is_file():
        raise InputError(f"{src}: no such file")
    if src.resolve() == dst.resolve():
        raise InputError(f"{dst}: compress into another file, not the input")
    if dst.suffix.lower() != ".glb":
        raise InputError(f"{dst}: the compressed file must be a .glb")
    script = gltfpack_script()
    with atomic_path(dst) as tmp:
        code, out = _run(["node", str(script), "-i", str(src.resolve()), "-o", str(tmp),
                          *GLTFPACK_ARGS], cancel)
        if code != 0 or not tmp.is_file() or tmp.stat().st_size == 0:
            raise InputError(f"{src}: gltfpack failed ({code}): {out.strip()[-2000:]}")
    a, b = src.stat().st_size, dst.stat().st_size
    return {"input_bytes": a, "output_bytes": b, "ratio": a / b}


def _run(cmd: list[str], cancel, timeout: float = 600.0) -> tuple[int, str]:
    """Run ``cmd``; (exit code, its output). Stopped when ``cancel()`` or after ``timeout``."""
    with subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                          text=True) as proc:
        t0 = time.monotonic()
        while True:
            try:
                out, _ = proc.communicate(timeout=0.05)
                return proc.returncode, out or ""
            except subprocess.TimeoutExpired:
                if (cancel is not None and cancel()) or time.monotonic() - t0 > timeout:
                    proc.kill()
                    proc.communicate()
                    if cancel is not None and cancel():
                        raise Cancelled("try-on cancelled") from None
                    return -9, f"gltfpack took more than {timeout:g} s"


def compress_bytes(data: bytes, cancel=None, workdir: str | Path | None = None
                   ) -> tuple[bytes, dict]:
    """A meshopt-compressed copy of the .glb ``data`` and ``{"input_bytes", "output_bytes",
    "ratio"}``; gltfpack's files go to a temporary folder in ``workdir`` (default: the
    system's)."""
    if workdir is not None:
        Path(workdir).mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory(prefix=".catwalk-pack-", dir=workdir) as tmp:
        src, dst = Path(tmp) / "in.glb", Path(tmp) / "out.glb"
        src.write_bytes(data)
        stats = compress_glb(src, dst, cancel)
        return dst.read_bytes(), stats
