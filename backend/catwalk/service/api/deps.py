"""What routes get from the app: its settings, storage, catalogue, pools.

Each is ``async``: FastAPI runs a plain ``def`` dependency in its thread pool, a hop per
dependency per request; these only read the app's state."""

from __future__ import annotations

import asyncio

from fastapi import Request

from catwalk.config import Config
from catwalk.service.api.errors import ApiError
from catwalk.service.bodies import Scope
from catwalk.service.catalogue import Catalogue
from catwalk.service.store.files import Storage


async def config(request: Request) -> Config:
    return request.app.state.config


async def storage(request: Request) -> Storage:
    return request.app.state.storage


async def catalogue(request: Request) -> Catalogue:
    """The catalogue, its folder looked at within the last second: when a look is due it is
    taken in a thread (a glob, stats, and reading a changed garment stay off the event loop),
    so the route's own reads are answered from memory."""
    cat = request.app.state.catalogue
    if cat.fresh() is None:
        await asyncio.to_thread(cat.entries)
    return cat


async def json_body(request: Request) -> None:
    """Refuse (415) a request body that is not declared as JSON."""
    ctype = request.headers.get("content-type", "").split(";")[0].strip().lower()
    if ctype != "application/json":
        raise ApiError(415, f"send the request as application/json, not {ctype or 'nothing'}")


async def shop(request: Request) -> Scope | None:
    """Who asks, on a merchant's shop (its publishable key, checked by
    :class:`~catwalk.service.api.embed.Shops`); None for catwalk's own pages."""
    return request.scope.get("catwalk.shop")
