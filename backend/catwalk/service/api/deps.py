"""What routes get from the app: its settings, storage, catalogue, pools."""

from __future__ import annotations

from fastapi import Request

from catwalk.config import Config
from catwalk.service.catalogue import Catalogue
from catwalk.service.storage import Storage


def config(request: Request) -> Config:
    return request.app.state.config


def storage(request: Request) -> Storage:
    return request.app.state.storage


def catalogue(request: Request) -> Catalogue:
    return request.app.state.catalogue


def json_body(request: Request) -> None:
    """Refuse (415) a request body that is not declared as JSON."""
    from catwalk.service.api.errors import ApiError

    ctype = request.headers.get("content-type", "").split(";")[0].strip().lower()
    if ctype != "application/json":
        raise ApiError(415, f"send the request as application/json, not {ctype or 'nothing'}")
