"""Garment thumbnails: the garment dressed on the sample body of its default size, rendered
from the front (``thumbnails/<id>/<version>.png`` in the storage), and that dressed body as a
.glb for the garment page's 3D view (``<version>.glb``, meshopt-compressed).

Made once per garment version in the API's body pool (a dressing and a render: 1–3 s), at the
API's start for the whole catalogue and on first request for a new version; until one is
made the request gets the flat cutting pattern instead (not cached by the browser).
"""

from __future__ import annotations

import asyncio
import io
import json
import logging
from pathlib import Path

import numpy as np
from PIL import Image

from catwalk.catalogue.bodies import sample_body
from catwalk.exchange.compress import compress_bytes
from catwalk.exchange.scene import scene_of
from catwalk.fileio import atomic_path
from catwalk.render.preview import render_meshes
from catwalk.service.keys import engine_version
from catwalk.simulate.fitcheck import sample_for
from catwalk.simulate.tryon import tryon

log = logging.getLogger("catwalk.api")

SIZE = (240, 360)


def dressed_files(res, workdir: Path) -> tuple[bytes, bytes]:
    """A dressed, standing try-on as the catalogue shows it: the meshopt .glb and the front
    view PNG."""
    web, _ = compress_bytes(res.glb(normals=False), workdir=workdir)
    scene = scene_of(res.body, None, [res.frames()])
    meshes = [(v, f, rgb) for _, v, f, rgb in scene.meshes_at(0.0)]
    img = render_meshes(meshes, view="front", size=SIZE)
    buf = io.BytesIO()
    Image.fromarray(np.asarray(img)).save(buf, format="PNG")
    return web, buf.getvalue()


def render_thumbnail(garment_path: str, size: str, sample: str, samples_dir: str,
                     out: str) -> str:
    """(In a pool process.) Dress the garment on the sample body, render it, write ``out``."""
    body = sample_body(sample, Path(samples_dir))
    res = tryon(body, garment_path, size=size, seconds=0, preset="fast",
                measure=False, garment_id=Path(garment_path).stem)
    web, png = dressed_files(res, Path(out).parent)
    with atomic_path(Path(out).with_suffix(".glb")) as tmp:
        tmp.write_bytes(web)
    with atomic_path(out) as tmp:
        tmp.write_bytes(png)
    return out


def thumbnail_path(storage, garment_id: str, version: str) -> Path:
    """Where a garment version's thumbnail is (its dressed .glb beside it): keyed by the
    garment's version and the engine's, so new code draws them anew."""
    return storage.thumbnail(garment_id, f"{version}-{engine_version()[-16:]}")


class Thumbnails:
    """Makes each missing thumbnail once (one at a time per garment version)."""

    def __init__(self, storage, maker, timeout_s: float = 120.0):
        self.storage, self.maker, self.timeout_s = storage, maker, timeout_s
        self._tasks: dict[tuple[str, str], asyncio.Task] = {}
        self._failed: set[tuple[str, str]] = set()

    def path(self, entry) -> Path:
        return thumbnail_path(self.storage, entry.id, entry.version)

    def ensure(self, entry) -> asyncio.Task | None:
        """Start making the thumbnail if it is missing; the task (None when it exists or
        could not be made)."""
        key = (entry.id, entry.version)
        if self.path(entry).is_file() or key in self._failed:
            return None
        task = self._tasks.get(key)
        if task is None:
            task = asyncio.get_running_loop().create_task(self._make(entry))
            self._tasks[key] = task
        return task

    async def _make(self, entry) -> None:
        key = (entry.id, entry.version)
        g = entry.garment
        size = g.size(None)
        sample = sample_for(g, size)
        try:
            await self.maker.run(render_thumbnail, str(entry.path), size, sample,
                                 str(self.storage.samples_dir()), str(self.path(entry)),
                                 timeout=self.timeout_s)
            log.info(json.dumps({"event": "thumbnail", "garment": entry.id}))
        except Exception as exc:   # the pattern drawing stands in
            self._failed.add(key)
            log.warning(json.dumps({"event": "thumbnail_failed", "garment": entry.id,
                                    "error": f"{type(exc).__name__}: {exc}"[:300]}))
        finally:
            self._tasks.pop(key, None)
