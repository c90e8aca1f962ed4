"""The catalogue the service shows: the garments in ``CATWALK_CATALOGUE_DIR``, then the
merchants' published garments (``service/merchant_garments.py``).

A file's garment's id is its file's stem; a merchant's garment's id is made at its upload.
A garment's version is the hash of its file and of the texture images it names, so an edited
garment gets a new version (and new cached results). The list is read once and read again
when a file in the folder changes or a merchant publishes or deletes a garment.
"""

from __future__ import annotations

import json
import logging
import threading
import time
from dataclasses import dataclass, field
from pathlib import Path

from catwalk.catalogue.garments import catalogue_files
from catwalk.cloth.fabrics import fabric_choices
from catwalk.config import Config
from catwalk.errors import CatwalkError, InputError
from catwalk.exchange.garment_json import load_garment
from catwalk.garment.model import Garment
from catwalk.service.keys import garment_version
from catwalk.service.merchant_garments import published
from catwalk.service.store.files import Storage

log = logging.getLogger("catwalk.catalogue")


@dataclass
class Entry:
    id: str
    version: str
    path: Path
    garment: Garment
    fabric: str
    fabrics: list[str] = field(default_factory=list)
    merchant_id: str | None = None   # a merchant's published garment: whose

    def summary(self) -> dict:
        g = self.garment
        return {"id": self.id, "name": g.name, "type": g.type, "sizes": list(g.sizes),
                "default_size": g.size(None), "fabric": self.fabric,
                "fabrics": self.fabrics, "version": self.version,
                "thumbnail_url": f"/api/garments/{self.id}/thumbnail.png"}

    def detail(self) -> dict:
        g = self.garment
        return {**self.summary(), "description": g.description,
                "panels": [{"name": p.name, "type": p.type} for p in g.panels],
                "seams": len(g.seams), "fit": dict(g.fit), "source": dict(g.source)}


CHECK_EVERY_S = 1.0


class Catalogue:
    def __init__(self, config: Config, *, merchants: bool = True):
        """``merchants``: with the merchants' published garments (from the database)."""
        self.root = config.catalogue_dir
        self.config = config if merchants else None
        self._merchant: tuple = ()
        self._lock = threading.Lock()
        self._stamp: tuple | None = None
        self._entries: dict[str, Entry] = {}
        self._listing: list[dict] | None = None
        self._checked = -1e9   # when the files were last looked at (time.monotonic)

    def _current_stamp(self) -> tuple:
        files = sorted(self.root.glob("*.json")) + sorted((self.root / "textures").glob("*"))
        return (tuple((f.name, f.stat().st_mtime_ns, f.stat().st_size) for f in files),
                self._published())

    def _published(self) -> tuple:
        """The merchants' published garments (id, version, content); the last known when the
        database cannot be asked."""
        if self.config is None:
            return ()

        try:
            self._merchant = tuple(published(self.config))
        except Exception as exc:  # noqa: BLE001 - the database away: the files still serve
            log.warning(json.dumps({"event": "catalogue_db_unreachable",
                                    "error": type(exc).__name__}))
        return self._merchant

    def _entry(self, gid: str, path: Path, g: Garment, fabrics: list[str],
               version: str | None = None, merchant_id: str | None = None) -> Entry:
        own = g.fabric if isinstance(g.fabric, str) else "custom"
        return Entry(gid, version or garment_version(path, g), path, g, own,
                     [own] + [f for f in fabrics if f != own], merchant_id)

    def _load(self, published: tuple) -> dict[str, Entry]:
        fabrics = fabric_choices()
        out = {}
        for path in catalogue_files(self.root):
            try:
                g = load_garment(path)
            except CatwalkError as exc:   # one broken file does not take the others down
                log.warning(json.dumps({"event": "garment_skipped", "file": path.name,
                                        "error": str(exc)[:300]}))
                continue
            out[path.stem] = self._entry(path.stem, path, g, fabrics)
        storage = Storage(self.config.storage_dir) if self.config is not None else None
        for gid, n, content, merchant_id in published:
            if gid in out:
                continue   # a file's garment keeps its id
            old = self._entries.get(gid)
            if old is not None and old.version == content:
                out[gid] = old   # versions never change: not read again
                continue
            path = storage.merchant_garment_dir(gid, n) / "garment.json"
            try:
                out[gid] = self._entry(gid, path, load_garment(path), fabrics, content,
                                       merchant_id)
            except CatwalkError as exc:
                log.warning(json.dumps({"event": "garment_skipped", "garment": gid,
                                        "error": str(exc)[:300]}))
        return out

    def fresh(self) -> dict[str, Entry] | None:
        """The garments if the folder was looked at less than a second ago, else None (then
        :meth:`entries`, in a thread: it may read files). For ``async`` routes."""
        return self._entries if time.monotonic() - self._checked < CHECK_EVERY_S else None

    def entries(self, *, recheck: bool = False) -> dict[str, Entry]:
        """The garments, read again when a file or a published garment changed: the folder
        and the database are looked at once a second at most (a glob, two stats a file and a
        query cost more than the rest of a catalogue route); ``recheck``: now. The look is
        claimed before it is taken, so requests meanwhile keep the entries they have."""
        now = time.monotonic()
        if not recheck and now - self._checked < CHECK_EVERY_S:
            return self._entries
        self._checked = now
        stamp = self._current_stamp()
        with self._lock:
            if stamp != self._stamp:
                self._entries, self._stamp = self._load(stamp[1]), stamp
                self._listing = None
            return self._entries

    def listing(self) -> list[dict]:
        """Every garment's summary (``GET /api/garments``), made again only when a file
        changed."""
        self.entries()
        with self._lock:   # from the entries the listing belongs to (a reload may have come)
            if self._listing is None:
                self._listing = [e.summary() for e in self._entries.values()]
            return self._listing

    def get(self, garment_id: str, *, recheck: bool = False,
            merchant_id: str | None = None) -> Entry:
        """The garment; with ``merchant_id`` (a shop's page asks) only that merchant's
        published garments: any other is answered as unknown."""
        entry = self.entries(recheck=recheck).get(garment_id)
        if entry is not None and merchant_id is not None and entry.merchant_id != merchant_id:
            entry = None
        if entry is None:
            raise InputError(f"no garment {garment_id!r} in the catalogue", "garment_id")
        return entry
