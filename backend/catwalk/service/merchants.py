"""Merchants and their API keys.

An operator makes a merchant (``catwalk merchant create NAME``); its API key is shown once and
only its SHA-256 is stored (a key is 256 random bits: a plain hash is as strong as a slow one
here, and costs microseconds per request). A request names its merchant with
``Authorization: Bearer KEY``; a revoked merchant's key is refused like an unknown one.
"""

from __future__ import annotations

import re
import secrets

from sqlalchemy import select

from catwalk.config import Config
from catwalk.errors import InputError
from catwalk.service.keys import sha256
from catwalk.service.store import db
from catwalk.service.store.models import MerchantRow, utcnow

KEY_PREFIX = "cwk_"
_NAME = re.compile(r"[a-z0-9][a-z0-9_-]{0,63}")


def check_name(name: str) -> str:
    if not isinstance(name, str) or not _NAME.fullmatch(name):
        raise InputError(f"merchant name {str(name)[:80]!r}: use 1–64 lower-case letters, "
                         "digits, '-' or '_', starting with a letter or digit", "name")
    return name


def create(config: Config, name: str) -> str:
    """A new merchant named ``name``; returns its API key (shown once: only its hash is
    kept)."""
    check_name(name)
    key = KEY_PREFIX + secrets.token_urlsafe(32)
    with db.session(config) as s:
        if s.scalars(select(MerchantRow).where(MerchantRow.name == name)).first() is not None:
            raise InputError(f"a merchant named {name!r} exists already", "name")
        s.add(MerchantRow(id=secrets.token_urlsafe(16), name=name, key_sha256=sha256(key.encode()),
                          created_at=utcnow()))
    return key


def listing(config: Config) -> list[dict]:
    """Every merchant: name, created, revoked (never a key)."""
    with db.session(config) as s:
        rows = s.scalars(select(MerchantRow).order_by(MerchantRow.created_at)).all()
        return [{"name": r.name, "created_at": r.created_at.isoformat() + "Z",
                 "revoked_at": r.revoked_at.isoformat() + "Z" if r.revoked_at else None}
                for r in rows]


def revoke(config: Config, name: str) -> bool:
    """Revoke the merchant's key (its garments stay in the catalogue). False if it was
    revoked already."""
    check_name(name)
    with db.session(config) as s:
        row = s.scalars(select(MerchantRow).where(MerchantRow.name == name)).first()
        if row is None:
            raise InputError(f"no merchant named {name!r}", "name")
        if row.revoked_at is not None:
            return False
        row.revoked_at = utcnow()
        return True


def authenticate(config: Config, key: str) -> MerchantRow | None:
    """The merchant whose key this is, if it is not revoked."""
    if not key.startswith(KEY_PREFIX) or len(key) > 128:
        return None
    with db.session(config) as s:
        row = s.scalars(select(MerchantRow).where(
            MerchantRow.key_sha256 == sha256(key.encode()))).first()
        if row is None or row.revoked_at is not None:
            return None
        s.expunge(row)
        return row
