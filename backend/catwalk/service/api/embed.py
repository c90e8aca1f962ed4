"""Shops' pages calling the API: publishable keys, allowed origins, CORS, rate limits
(docs/embed.md).

A request with ``?key=pk_…`` comes from a merchant's shop page (the ``<catwalk-tryon>``
component). :class:`Shops` (ASGI middleware) lets it through only when

- the key is a merchant's publishable key, the merchant not revoked (else 401),
- its ``Origin`` is one the merchant allows (else 403 ``origin_not_allowed``),
- its route is a shopper's (:data:`SHOPPER_ROUTES`: bodies, try-ons and their results, the
  merchant's published garments; else 403 ``key_not_allowed``),
- the shopper's own id comes (``X-Catwalk-Shopper``) where a body is reached (else 422),
- it is within the rate limits per key and per shopper (else 429 with ``Retry-After``),

and hands the routes a :class:`~catwalk.service.bodies.Scope` (``scope["catwalk.shop"]``).
Preflights are answered for those origins only (a refused one names no origin); every answer
to an allowed origin names it in ``Access-Control-Allow-Origin`` (never ``*``, never
credentials), with ``Vary: Origin``. A refusal of the key or its origin also names the
request's origin, so the page can read why (it carries nothing else). A secret key
(``cwk_…``) is refused in a URL always, and in an ``Authorization`` header sent from a page of
another origin than the service's own (403 ``secret_key_exposed``): the merchant's editor, on
the service's origin, still uses it.
"""

from __future__ import annotations

import asyncio
import json
import logging
import re
import time
from urllib.parse import parse_qs

from catwalk.config import Config
from catwalk.service import merchants
from catwalk.service.api import errors
from catwalk.service.bodies import Scope, shopper_hash
from catwalk.service.ratelimit import RateLimits

log = logging.getLogger("catwalk.api")

SHOPPER_HEADER = "X-Catwalk-Shopper"
_SHOPPER_ID = re.compile(r"[A-Za-z0-9_-]{16,64}")
_SEG = r"[^/]+"
#: (methods, path, whether the shopper's id is needed): what a publishable key opens
SHOPPER_ROUTES = [
    ({"POST"}, re.compile(r"/api/bodies"), True),
    ({"GET", "HEAD", "DELETE"}, re.compile(rf"/api/bodies/{_SEG}"), True),
    ({"GET", "HEAD"}, re.compile(rf"/api/bodies/{_SEG}/body\.glb"), True),
    ({"GET", "HEAD"},
     re.compile(rf"/api/garments/{_SEG}(/thumbnail\.png|/dressed\.glb|/pattern\.png)?"), False),
    ({"GET"}, re.compile(rf"/api/garments/{_SEG}/sizes"), True),
    ({"POST"}, re.compile(r"/api/tryons"), True),
    ({"GET", "DELETE"}, re.compile(rf"/api/tryons/{_SEG}"), False),
    ({"GET"}, re.compile(rf"/api/tryons/{_SEG}/events"), False),
    ({"GET", "HEAD"}, re.compile(rf"/api/tryons/{_SEG}/(result\.glb|preview\.png)"), False),
]
_MAKES = {("POST", "/api/bodies"), ("POST", "/api/tryons")}   # counted per hour too
ALLOW_HEADERS = f"Content-Type, {SHOPPER_HEADER}, Range, If-None-Match, If-Range"
EXPOSE_HEADERS = "Retry-After, ETag, Content-Range, Content-Disposition"
KEY_CACHE_S = 5.0   # a key's origins and revocation reach every API process within this
_KEY_CACHE_MAX = 4096


def shopper_route(method: str, path: str) -> tuple[set[str], bool] | None:
    """(the route's methods, whether it needs the shopper's id) for a shopper's route that
    answers ``method`` (for a preflight: the method asked for) on ``path``; else None."""
    for methods, pattern, shopper in SHOPPER_ROUTES:
        if pattern.fullmatch(path) and method in methods:
            return methods, shopper
    return None


def _service_origin(headers: dict[bytes, bytes], scheme: str) -> set[str]:
    """The host[:port] the service is reached at (Host, and a proxy's X-Forwarded-Host)."""
    hosts = {headers.get(b"host", b"").decode("latin-1").lower()}
    forwarded = headers.get(b"x-forwarded-host", b"").decode("latin-1").lower()
    hosts |= {h.strip() for h in forwarded.split(",") if h.strip()}
    # a default port is left out of an Origin; a Host may carry it
    return {h.removesuffix(":443" if scheme == "https" else ":80") for h in hosts if h}


def from_another_origin(headers: dict[bytes, bytes], scheme: str) -> bool:
    """Whether the request was sent by a page of another origin than the service's: the
    browser's ``Sec-Fetch-Site`` where it sends one (a page cannot forge it), else its
    ``Origin`` against the service's host."""
    site = headers.get(b"sec-fetch-site", b"").decode("latin-1").lower()
    if site:
        return site not in ("same-origin", "none")
    origin = headers.get(b"origin", b"").decode("latin-1").lower()
    if not origin or origin == "null":
        return bool(origin)
    host = origin.split("://", 1)[-1]
    return host.removesuffix(":443").removesuffix(":80") not in \
        _service_origin(headers, scheme)


class _KeyCache:
    """Publishable key → :class:`~catwalk.service.merchants.Shop` (None: unknown or revoked),
    kept :data:`KEY_CACHE_S` seconds."""

    def __init__(self, config: Config):
        self.config = config
        self.items: dict[str, tuple[float, merchants.Shop | None]] = {}

    async def get(self, key: str) -> merchants.Shop | None:
        now = time.monotonic()
        hit = self.items.get(key)
        if hit is not None and hit[0] > now:
            return hit[1]
        shop = await asyncio.to_thread(merchants.shop, self.config, key)
        if len(self.items) >= _KEY_CACHE_MAX:
            self.items.clear()
        self.items[key] = (now + KEY_CACHE_S, shop)
        return shop


class Refused(Exception):
    """A request refused before any route. ``readable``: the answer names the request's origin
    (the page can read why; it carries nothing else)."""

    def __init__(self, status: int, code: str, message: str, reason: str,
                 field: str | None = None, readable: bool = True,
                 headers: dict | None = None):
        super().__init__(message)
        self.status, self.code, self.message, self.field = status, code, message, field
        self.reason, self.readable, self.headers = reason, readable, headers or {}


def _cors(origin: str) -> list[tuple[bytes, bytes]]:
    return [(b"access-control-allow-origin", origin.encode("latin-1")),
            (b"vary", b"Origin"),
            (b"access-control-expose-headers", EXPOSE_HEADERS.encode())]


class Shops:
    """ASGI middleware: the checks above, the CORS headers, the rate limits."""

    def __init__(self, app, config: Config, refused=None):
        self.app, self.config, self.refused = app, config, refused
        self.keys = _KeyCache(config)
        self.limits = RateLimits(config)

    async def __call__(self, scope, receive, send):
        if scope["type"] != "http":
            return await self.app(scope, receive, send)
        headers = dict(scope.get("headers") or [])
        origin = headers.get(b"origin", b"").decode("latin-1")
        preflight = scope["method"] == "OPTIONS" and b"access-control-request-method" in headers
        try:
            key = await self._secret_keys(scope, headers)
            if key is None:
                return await self.app(scope, receive, send)
            shop, route = await self._shop(scope, headers, key, origin, preflight)
            if preflight:
                return await self._preflight(send, origin, route[0])
            scope["catwalk.shop"] = await self._scope(scope, headers, shop, route[1])
        except Refused as exc:
            exc.readable = exc.readable and not preflight   # a refused preflight names no one
            return await self._refuse(send, exc, origin)

        async def with_cors(msg):
            if msg["type"] == "http.response.start":
                msg = {**msg, "headers": [*msg.get("headers", []), *_cors(origin)]}
            await send(msg)

        return await self.app(scope, receive, with_cors)

    async def _secret_keys(self, scope, headers) -> str | None:
        """The ``key`` the query names (None: none); a secret key in the query, or in an
        Authorization header from another origin's page, refused."""
        raw = scope.get("query_string", b"")
        key = None
        if b"key=" in raw:   # most requests name none: no parsing for them
            key = (parse_qs(raw.decode("latin-1")).get("key") or [None])[0]
        auth = headers.get(b"authorization", b"").decode("latin-1")
        secret_in_header = auth.split(" ", 1)[-1].strip().startswith(merchants.KEY_PREFIX)
        if key is not None and key.startswith(merchants.KEY_PREFIX):
            await asyncio.to_thread(self._exposed, key)
            raise Refused(403, "secret_key_exposed", "this is a merchant's secret API key "
                          "(cwk_…): it must never be in a web page or a URL. Use the "
                          "publishable key (pk_…, `catwalk merchant publishable-key NAME`), "
                          "and revoke this one: whoever saw the page has it",
                          "secret_key", "key")
        if secret_in_header and from_another_origin(headers, scope.get("scheme", "http")):
            raise Refused(403, "secret_key_exposed", "a merchant's secret API key (cwk_…) is "
                          "never sent from a web page of another origin: it belongs on the "
                          "merchant's server. A shop's pages use its publishable key (pk_…)",
                          "secret_key", "Authorization", readable=False)
        return key

    def _exposed(self, key: str) -> None:
        who = merchants.authenticate(self.config, key) if len(key) <= 128 else None
        log.warning(json.dumps({"event": "secret_key_exposed",
                                "merchant": who.name if who else None}))

    async def _shop(self, scope, headers, key: str, origin: str, preflight: bool):
        method = scope["method"]
        if preflight:
            method = headers[b"access-control-request-method"].decode("latin-1").upper()
        shop = await self.keys.get(key) if key.startswith(merchants.PUBLISHABLE_PREFIX) \
            else None
        if shop is None:
            raise Refused(401, "unauthorized", "the publishable key is not valid (unknown, "
                          "replaced, or its merchant's keys revoked)", "key", "key")
        if not origin:
            raise Refused(403, "origin_not_allowed", "a publishable key is used from the "
                          "shop's pages: this request names no Origin", "origin")
        if origin not in shop.origins:
            raise Refused(403, "origin_not_allowed", f"the page's origin {origin[:120]} is "
                          f"not one merchant {shop.name!r} allows for this key (allowed: "
                          f"{', '.join(shop.origins) or 'none yet'}); the merchant adds it "
                          "with `catwalk merchant origins` or in its editor", "origin")
        route = shopper_route(method, scope["path"])
        if route is None:
            raise Refused(403, "key_not_allowed", f"a publishable key opens only the "
                          f"shoppers' routes (bodies, try-ons, the shop's garments), not "
                          f"{method} {scope['path'][:200]}", "route", "key")
        return shop, route

    async def _scope(self, scope, headers, shop: merchants.Shop, needs_shopper: bool) -> Scope:
        """The shop's scope for the routes; the rate limits counted."""
        sent = headers.get(SHOPPER_HEADER.lower().encode())
        shopper = sent.decode("latin-1") if sent is not None else None
        if shopper is not None and not _SHOPPER_ID.fullmatch(shopper):
            raise Refused(422, "invalid", f"{SHOPPER_HEADER} is the shopper's own id: 16–64 "
                          "URL-safe characters", "shopper", SHOPPER_HEADER)
        if needs_shopper and shopper is None:
            raise Refused(422, "invalid", f"send the shopper's own id as {SHOPPER_HEADER} (a "
                          "shopper's body is theirs on this shop)", "shopper", SHOPPER_HEADER)
        c = self.config
        checks = [(f"key:{shop.merchant_id}", c.rate_key_per_minute, 60,
                   f"this shop's limit of {c.rate_key_per_minute} requests a minute")]
        hashed = shopper_hash(shop.merchant_id, shopper) if shopper else None
        if hashed:
            checks.append((f"shopper:{hashed}", c.rate_shopper_per_minute, 60,
                           f"a shopper's limit of {c.rate_shopper_per_minute} requests a "
                           "minute"))
            if (scope["method"], scope["path"]) in _MAKES:
                checks.append((f"made:{hashed}", c.rate_shopper_jobs_per_hour, 3600,
                               f"a shopper's limit of {c.rate_shopper_jobs_per_hour} bodies "
                               "and try-ons an hour"))
        for name, limit, seconds, what in checks:
            wait = await self.limits.hit(name, limit, seconds)
            if wait is not None:
                wait_s = int(wait + 0.999)
                raise Refused(429, "rate_limited", f"over {what}; try again in {wait_s} s",
                              "rate", headers={"Retry-After": str(wait_s)})
        return Scope(shop.merchant_id, hashed)

    async def _preflight(self, send, origin: str, methods: set[str]) -> None:
        allowed = ", ".join(sorted(methods | {"OPTIONS"}))
        await send({"type": "http.response.start", "status": 204, "headers": [
            *_cors(origin), (b"access-control-allow-methods", allowed.encode()),
            (b"access-control-allow-headers", ALLOW_HEADERS.encode()),
            (b"access-control-max-age", b"600"), (b"content-length", b"0")]})
        await send({"type": "http.response.body", "body": b""})

    async def _refuse(self, send, exc: Refused, origin: str) -> None:
        if self.refused is not None:
            self.refused.labels(exc.reason).inc()
        body = json.dumps(errors.error_body(exc.status, exc.message, exc.field, exc.code),
                          separators=(",", ":")).encode()
        out = [(b"content-type", b"application/json"),
               (b"content-length", str(len(body)).encode())]
        out += [(k.lower().encode(), v.encode()) for k, v in exc.headers.items()]
        # a refused key or origin is told to any page (it carries nothing but why); the
        # other refusals come after the origin was found allowed
        if origin and exc.readable:
            out += _cors(origin)
        await send({"type": "http.response.start", "status": exc.status, "headers": out})
        await send({"type": "http.response.body", "body": body})
