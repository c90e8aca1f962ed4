"""What the API takes and gives (Pydantic): the OpenAPI document at ``/openapi.json`` is made
from these."""

from __future__ import annotations

from typing import Literal

from pydantic import BaseModel, ConfigDict, Field

from catwalk.body.make import RANGES


def _range(key: str, what: str):
    lo, hi = RANGES[key]
    return Field(ge=lo, le=hi, description=f"{what}, metres ({lo}–{hi})")


class Measurements(BaseModel):
    """A body from measurements (metres)."""
    model_config = ConfigDict(extra="forbid")
    sex: Literal["female", "male"]
    height: float = _range("height", "stature")
    bust: float = _range("bust", "bust (women) or chest (men) girth")
    waist: float = _range("waist", "waist girth")
    hips: float = _range("hips", "hip girth")


class Body(BaseModel):
    id: str = Field(description="unguessable; the only way to reach the body")
    source: Literal["scan", "measurements"]
    fit: Literal["measurements"] = Field(
        description="how the walking body was made: a MakeHuman body fitted to the "
                    "measurements (of the scan, for a scan)")
    sex: Literal["female", "male"]
    sex_inferred: bool = False
    measurements: dict[str, float] = Field(description="the person's, metres")
    model_measurements: dict[str, float] = Field(description="the walking body's, metres")
    body_url: str
    scan: dict | None = None


class TryOnRequest(BaseModel):
    model_config = ConfigDict(extra="forbid")
    body_id: str
    garment_id: str
    size: str | None = Field(None, description="one of the garment's sizes (default: its "
                                               "default size)")
    fabric: str | None = Field(None, description="a fabric id from the garment's `fabrics` "
                                                 "(default: its own)")
    seconds: float = Field(4.0, ge=0.5, le=10.0, description="length of the walk")
    preset: Literal["fast", "balanced", "accurate"] = "balanced"


class TryOn(BaseModel):
    id: str
    status: Literal["queued", "running", "done", "failed", "cancelled"]
    progress: float = Field(ge=0.0, le=1.0)
    stage: str
    status_url: str
    cached: bool = False
    error: str | None = None
    metrics: dict | None = None
    result_url: str | None = None
    preview_url: str | None = None
    garment_id: str | None = None
    garment_version: str | None = None
    size: str | None = None
    fabric: str | None = None
    seconds: float | None = None
    preset: str | None = None
    attempts: int | None = None
    created_at: str | None = None
    finished_at: str | None = None


class Garment(BaseModel):
    id: str
    name: str
    type: str
    sizes: list[str]
    default_size: str
    fabric: str
    fabrics: list[str]
    version: str
    thumbnail_url: str


class GarmentDetail(Garment):
    description: str = ""
    panels: list[dict] = []
    seams: int = 0
    fit: dict[str, str] = {}
    source: dict = {}


class Garments(BaseModel):
    garments: list[Garment]


class ErrorBody(BaseModel):
    code: str
    message: str
    field: str | None = None


class Error(BaseModel):
    error: ErrorBody


ERRORS = {code: {"model": Error} for code in (400, 404, 409, 413, 415, 422)}
