"""A shopper's bodies as the service keeps them: the row made for a body once its file is
written (from measurements, or from a scan with what the scan told), read, shown and deleted
with everything made from it. Made in the API's pool: :mod:`catwalk.service.body_maker`.

A scan and its measurements are personal data: never logged (the log carries the body's id
and the outcome only), never listed.

A body made on a merchant's shop (a request with its publishable key) is that shopper's on that
shop: it is reached only with the same shop's key and the same shopper's id (a :class:`Scope`),
never through catwalk's own pages nor another shop's; a body made on catwalk's pages only
without a shop's key. Each of these reads answers an unknown body and another's alike."""

from __future__ import annotations

import json
import logging
from typing import NamedTuple

from catwalk.config import Config
from catwalk.service import keys
from catwalk.service.jobs import lifecycle
from catwalk.service.store import db
from catwalk.service.store.files import Storage
from catwalk.service.store.models import BodyRow

log = logging.getLogger("catwalk.api")


class Scope(NamedTuple):
    """Who asks, on a shop: the merchant whose publishable key came, and the shopper (the
    SHA-256 of the shopper's own id with the merchant's: :func:`shopper_hash`), None when the
    request named no shopper."""
    merchant_id: str
    shopper: str | None


def shopper_hash(merchant_id: str, shopper_id: str) -> str:
    """The shopper as the database keeps it: one shopper's id gives another hash on each shop,
    and the id itself is never stored."""
    return keys.sha256(f"catwalk shopper\0{merchant_id}\0{shopper_id}".encode())


def visible(row: BodyRow | None, scope: Scope | None) -> bool:
    """Whether the body can be reached by who asks: a shop's body by its own shopper on that
    shop only, a body made on catwalk's pages only without a shop."""
    if row is None:
        return False
    if scope is None:
        return row.merchant_id is None
    return (row.merchant_id == scope.merchant_id and scope.shopper is not None
            and row.shopper == scope.shopper)


def view(row: BodyRow) -> dict:
    """A body as the API shows it; what a scan told (units, axes, size) for a scan's."""
    m = row.measurements or {}
    out = {"id": row.id, "source": row.source, "fit": row.fit, "sex": row.sex,
           "sex_inferred": bool(m.get("_sex_inferred", False)),
           "measurements": {k: v for k, v in m.items() if not k.startswith("_")},
           "model_measurements": row.model_measurements or {},
           "body_url": f"/api/bodies/{row.id}/body.glb"}
    if row.source == "scan":
        out["scan"] = m.get("_scan")
    return out


def get(config: Config, body_id: str, scope: Scope | None = None) -> BodyRow | None:
    """The body, if who asks (``scope``) can reach it (:func:`visible`)."""
    with db.session(config) as s:
        row = s.get(BodyRow, body_id)
        return row if visible(row, scope) else None


def from_measurements(body_id: str, sex: str, values: dict, made: dict) -> BodyRow:
    """The row of a body made from measurements (``made``: what the maker answered)."""
    return BodyRow(id=body_id, source="measurements", fit="measurements", sex=sex,
                   content_key=keys.measurements_key(sex, values), measurements=values,
                   model_measurements=made["model_measurements"])


def from_scan(body_id: str, scan: bytes, fmt: str, made: dict) -> BodyRow:
    """The row of a body registered to a scan: keyed by the scan's bytes and the sex the body
    was made with, told or inferred alike."""
    return BodyRow(id=body_id, source="scan", fit="surface", sex=made["sex"],
                   content_key=keys.scan_key(scan, made["sex"]), scan_format=fmt,
                   measurements={**made["measurements"], "_sex_inferred": made["sex_inferred"],
                                 "_scan": made["scan"]},
                   model_measurements=made["model_measurements"])


def add(config: Config, row: BodyRow, scope: Scope | None = None) -> None:
    """Store the body's row; made on a shop (``scope``), it is that shopper's there."""
    if scope is not None:
        row.merchant_id, row.shopper = scope.merchant_id, scope.shopper
    with db.session(config) as s:
        s.add(row)


def delete(config: Config, storage: Storage, body_id: str) -> int:
    """Delete the body, its scan, every try-on made from it and their results (those no other
    body shares); a running try-on of it stops. The files first: a crash half-way leaves a row
    to delete again, not a scan without a row; then the database's log emptied
(:func:`~catwalk.service.store.db.forget`). Returns the results removed."""
    storage.remove_body(body_id)
    orphaned = lifecycle.delete_for_body(config, body_id)
    for key in orphaned:
        storage.remove_result(key)
    with db.session(config) as s:
        row = s.get(BodyRow, body_id)
        if row is not None:
            s.delete(row)
    db.forget(config)   # nothing of the row left in SQLite's log either
    log.info(json.dumps({"event": "body_deleted", "body": body_id, "results": len(orphaned)}))
    return len(orphaned)
