"""Blobs on disk, in the storage folder every API and worker process shares.

Layout under ``CATWALK_STORAGE_DIR``::

    bodies/<body id>/scan.<ext>        the shopper's scan as uploaded (personal data)
    bodies/<body id>/body.glb          the rigged body made from it
    results/<key>/tryon.glb            a finished try-on, plain
    results/<key>/tryon.web.glb        the same, meshopt-compressed for the browser
    results/<key>/preview.png          frames of it, rendered on the CPU
    results/<key>/metrics.json
    thumbnails/<garment id>/<version>.png
    garments/<id>/<n>/garment.json     a merchant's garment, version n (and its textures)
    garments/<id>/<n>/dressed/<size>.glb   its dressing check on the size's sample body
    samples/<name>.glb                 sample bodies (thumbnails are dressed on them)

The folder is the service's user's alone (0700, :meth:`Storage.ensure`), its files 0600.
Nothing half-written is ever visible: a file is written to a temporary name beside it and
renamed; a result folder is filled under a temporary name and renamed into place whole (the
first one to arrive stays: a result is stored exactly once).
"""

from __future__ import annotations

import contextlib
import os
import shutil
import tempfile
import time
from pathlib import Path

from catwalk.fileio import atomic_path

RESULT_FILES = ("tryon.glb", "tryon.web.glb", "preview.png", "metrics.json")


class Storage:
    def __init__(self, root: str | Path):
        self.root = Path(root)

    # -- places
    def body_dir(self, body_id: str) -> Path:
        return self.root / "bodies" / body_id

    def body_glb(self, body_id: str) -> Path:
        return self.body_dir(body_id) / "body.glb"

    def scan_path(self, body_id: str, fmt: str) -> Path:
        return self.body_dir(body_id) / f"scan.{fmt}"

    def result_dir(self, key: str) -> Path:
        return self.root / "results" / key

    def result_file(self, key: str, name: str) -> Path:
        return self.result_dir(key) / name

    def thumbnail(self, garment_id: str, version: str) -> Path:
        return self.root / "thumbnails" / garment_id / f"{version}.png"

    def merchant_garment_dir(self, garment_id: str, version: int) -> Path:
        return self.root / "garments" / garment_id / str(int(version))

    def samples_dir(self) -> Path:
        return self.root / "samples"

    # -- writing
    def write(self, path: Path, data: bytes) -> Path:
        """Write ``data`` to ``path`` atomically (folders made as needed), readable by the
        service's user only."""
        with atomic_path(path) as tmp:
            tmp.write_bytes(data)
            os.chmod(tmp, 0o600)
        return path

    def sweep(self, older_than_s: float = 3600.0) -> int:
        """Remove what a process killed mid-write left: ``.name.*`` temporaries under
        ``bodies/`` and ``results/`` older than ``older_than_s``. Returns how many."""
        now, gone = time.time(), 0
        for top in ("bodies", "results", "thumbnails", "garments"):
            root = self.root / top
            if not root.is_dir():
                continue
            for p in root.rglob(".*"):
                try:
                    if now - p.lstat().st_mtime < older_than_s:
                        continue
                    if p.is_dir():
                        shutil.rmtree(p, ignore_errors=True)
                    else:
                        p.unlink(missing_ok=True)
                    gone += 1
                except OSError:
                    continue
        return gone

    def store_result(self, key: str, files: dict[str, bytes]) -> bool:
        """Put the result ``files`` in ``results/<key>/`` whole. Returns False (and stores
        nothing) when the key already has a stored result."""
        final = self.result_dir(key)
        if (final / RESULT_FILES[0]).is_file():
            return False
        final.parent.mkdir(parents=True, exist_ok=True)
        tmp = Path(tempfile.mkdtemp(prefix=f".{key}.", dir=final.parent))
        try:
            for name, data in files.items():   # readable by the service's user only
                (tmp / name).write_bytes(data)
                os.chmod(tmp / name, 0o600)
            os.chmod(tmp, 0o700)
            try:
                os.rename(tmp, final)        # fails if another copy got there first
            except OSError:
                if (final / RESULT_FILES[0]).is_file():
                    return False
                shutil.rmtree(final, ignore_errors=True)   # an empty or broken leftover
                os.rename(tmp, final)
            return True
        finally:
            if tmp.exists():
                shutil.rmtree(tmp, ignore_errors=True)

    # -- removing
    def remove_result(self, key: str) -> None:
        shutil.rmtree(self.result_dir(key), ignore_errors=True)

    def remove_body(self, body_id: str) -> None:
        shutil.rmtree(self.body_dir(body_id), ignore_errors=True)

    def ensure(self) -> None:
        """The storage folder made, and private: 0700, so that nothing under it — scans,
        bodies, results, the embedded database — can be read by another user of the machine,
        whatever a file's own mode."""
        self.root.mkdir(parents=True, exist_ok=True)
        os.chmod(self.root, 0o700)

    def check(self) -> None:
        """The storage folder made private (:meth:`ensure`); raise OSError if it cannot be
        written."""
        self.ensure()
        fd, name = tempfile.mkstemp(prefix=".ready-", dir=self.root)
        os.close(fd)
        with contextlib.suppress(FileNotFoundError):
            os.unlink(name)
