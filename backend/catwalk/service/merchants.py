"""Merchants, their API keys, their publishable keys and the origins of their shops.

An operator makes a merchant (``catwalk merchant create NAME``); its API key is shown once and
only its SHA-256 is stored (a key is 256 random bits: a plain hash is as strong as a slow one
here, and costs microseconds per request). A request names its merchant with
``Authorization: Bearer KEY``; a revoked merchant's key is refused like an unknown one.

Each merchant also has a **publishable key** (``pk_…``, 192 random bits, kept as it is: it is
public, in the shop's pages) which opens only the shoppers' routes, and only from the origins
the merchant allows (``catwalk merchant origins``, ``PUT /api/merchant/origins``): a
:class:`Shop`. Origins are kept as browsers send them (``scheme://host[:port]``, lower case,
no default port), so a request's ``Origin`` is compared as a string.
"""

from __future__ import annotations

import re
import secrets
from dataclasses import dataclass
from urllib.parse import urlsplit

from sqlalchemy import select

from catwalk.config import Config
from catwalk.errors import InputError
from catwalk.service.keys import sha256
from catwalk.service.store import db
from catwalk.service.store.models import MerchantRow, utcnow

KEY_PREFIX = "cwk_"
PUBLISHABLE_PREFIX = "pk_"
MAX_ORIGINS = 32
_NAME = re.compile(r"[a-z0-9][a-z0-9_-]{0,63}")
_HOST = re.compile(r"[a-z0-9]([a-z0-9-]*[a-z0-9])?(\.[a-z0-9]([a-z0-9-]*[a-z0-9])?)*")
_DEFAULT_PORTS = {"http": 80, "https": 443}


@dataclass(frozen=True)
class Shop:
    """What a publishable key opens: its merchant, and the origins its pages are on."""
    merchant_id: str
    name: str
    origins: tuple[str, ...]


def new_publishable_key() -> str:
    return PUBLISHABLE_PREFIX + secrets.token_urlsafe(24)


def check_origin(text) -> str:
    """``text`` as the origin a browser sends (``https://shop.example``, ``http://127.0.0.1:
    8080``): http or https, a host, a port if not the default; no path, query or user.
    :class:`InputError` (``field: origins``) naming what is wrong."""
    shown = str(text)[:120]
    if not isinstance(text, str) or not text.strip() or len(text) > 200:
        raise InputError(f"origin {shown!r}: give it as https://shop.example", "origins")
    if text.strip() == "*":
        raise InputError("origin '*': name each origin the shop's pages are on "
                         "(https://shop.example); any origin is never allowed", "origins")
    try:
        parts = urlsplit(text.strip())
        port = parts.port
    except ValueError as exc:
        raise InputError(f"origin {shown!r}: {exc}", "origins") from None
    scheme, host = parts.scheme.lower(), (parts.hostname or "")
    if scheme not in _DEFAULT_PORTS:
        raise InputError(f"origin {shown!r}: it starts with https:// (or http://)", "origins")
    if parts.username is not None or parts.password is not None:
        raise InputError(f"origin {shown!r}: an origin has no user name or password",
                         "origins")
    if parts.path not in ("", "/") or parts.query or parts.fragment:
        raise InputError(f"origin {shown!r}: an origin is the scheme, host and port only (no "
                         "path, query or '#')", "origins")
    if ":" in host:   # an IPv6 address
        host = f"[{host}]"
    elif not _HOST.fullmatch(host):
        raise InputError(f"origin {shown!r}: {host or 'no'} host name", "origins")
    keep_port = port is not None and port != _DEFAULT_PORTS[scheme]
    return f"{scheme}://{host}" + (f":{port}" if keep_port else "")


def check_origins(items) -> list[str]:
    """Each origin checked (:func:`check_origin`), repeats dropped, order kept; at most
    :data:`MAX_ORIGINS`."""
    if not isinstance(items, list | tuple):
        raise InputError("origins is a list of origins (https://shop.example)", "origins")
    out: list[str] = []
    for item in items:
        origin = check_origin(item)
        if origin not in out:
            out.append(origin)
    if len(out) > MAX_ORIGINS:
        raise InputError(f"at most {MAX_ORIGINS} origins, not {len(out)}", "origins")
    return out


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
                          created_at=utcnow(), publishable_key=new_publishable_key(),
                          origins=[]))
    return key


def _named(s, name: str) -> MerchantRow:
    check_name(name)
    row = s.scalars(select(MerchantRow).where(MerchantRow.name == name)).first()
    if row is None:
        raise InputError(f"no merchant named {name!r}", "name")
    return row


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
    with db.session(config) as s:
        row = _named(s, name)
        if row.revoked_at is not None:
            return False
        row.revoked_at = utcnow()
        return True


def publishable_key(config: Config, name: str, *, new: bool = False) -> str:
    """The merchant's publishable key; ``new``: a new one in its place (the old one stops
    working at once: every page must be given the new one)."""
    with db.session(config) as s:
        row = _named(s, name)
        if new or row.publishable_key is None:
            row.publishable_key = new_publishable_key()
        return row.publishable_key


def origins(config: Config, name: str, *, replace: list[str] | None = None,
            add: list[str] = (), remove: list[str] = ()) -> list[str]:
    """The origins the merchant's publishable key may be used from: ``replace`` them with a
    list, ``add`` some, ``remove`` some (each checked; :class:`InputError` for a bad one or
    one to remove that is not there); the list as it is then."""
    with db.session(config) as s:
        row = _named(s, name)
        current = list(replace) if replace is not None else list(row.origins or [])
        current = check_origins(current + list(add))
        for item in remove:
            origin = check_origin(item)
            if origin not in current:
                raise InputError(f"origin {origin!r} is not one of merchant {name!r}'s",
                                 "origins")
            current.remove(origin)
        row.origins = current
        return current


def set_origins(config: Config, merchant_id: str, items) -> list[str]:
    """Replace the merchant's origins (checked: :func:`check_origins`)."""
    checked = check_origins(items)
    with db.session(config) as s:
        row = s.get(MerchantRow, merchant_id)
        if row is None:
            raise InputError("no such merchant", "origins")
        row.origins = checked
    return checked


def shop(config: Config, key: str) -> Shop | None:
    """The shop a publishable key opens, if its merchant is not revoked."""
    if not key.startswith(PUBLISHABLE_PREFIX) or len(key) > 64:
        return None
    with db.session(config) as s:
        row = s.scalars(select(MerchantRow).where(MerchantRow.publishable_key == key)).first()
        if row is None or row.revoked_at is not None:
            return None
        return Shop(row.id, row.name, tuple(row.origins or ()))


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
