"""What the API takes and gives (Pydantic): the OpenAPI document at ``/openapi.json`` is made
from these."""

from __future__ import annotations

from typing import Annotated, Literal

from fastapi import Path, Query
from pydantic import BaseModel, ConfigDict, Field, model_serializer

from catwalk.body.make import RANGES

# a body's or try-on's id as the service makes them (``jobs.new_id``: 32 URL-safe characters);
# any other string is answered 404 before a query (``errors.check_id``), so the pattern is
# documented here but not enforced as a 422
ID_PATTERN = r"^[A-Za-z0-9_-]{8,64}$"
_ID_DOC = "; unguessable (32 URL-safe characters). Unknown or malformed: 404"
BodyId = Annotated[str, Path(description="the body's id" + _ID_DOC,
                             json_schema_extra={"pattern": ID_PATTERN})]
JobId = Annotated[str, Path(description="the try-on's id" + _ID_DOC,
                            json_schema_extra={"pattern": ID_PATTERN})]
BodyIdQuery = Annotated[str, Query(description="the shopper's body" + _ID_DOC,
                                   json_schema_extra={"pattern": ID_PATTERN})]
GarmentId = Annotated[str, Path(description="a catalogue garment's id (its file's stem)")]


def _range(key: str, what: str):
    lo, hi = RANGES[key]
    return Field(ge=lo, le=hi, description=f"{what}, metres ({lo}–{hi})")


#: what a request's JSON is held to: no unknown keys, and a number is a number (not "1.68",
#: not true)
STRICT = ConfigDict(extra="forbid", strict=True)
#: the largest version number a route takes (a 32-bit integer, the database's)
MAX_VERSION = 2 ** 31 - 1
Version = Annotated[int, Path(ge=1, le=MAX_VERSION, description="a version number")]


class Measurements(BaseModel):
    """A body from measurements (metres)."""
    model_config = STRICT
    sex: Literal["female", "male"]
    height: float = _range("height", "stature")
    bust: float = _range("bust", "bust (women) or chest (men) girth")
    waist: float = _range("waist", "waist girth")
    hips: float = _range("hips", "hip girth")


class Body(BaseModel):
    id: str = Field(description="unguessable; the only way to reach the body")
    source: Literal["scan", "measurements"]
    fit: Literal["measurements", "surface"] = Field(
        description="how the walking body was made: 'measurements', a MakeHuman body fitted "
                    "to the measurements sent; 'surface', the MakeHuman template registered to "
                    "the scan's own surface (the shopper's shape walks)")
    sex: Literal["female", "male"]
    sex_inferred: bool = False
    measurements: dict[str, float] = Field(description="the person's, metres")
    model_measurements: dict[str, float] = Field(description="the walking body's, metres")
    body_url: str
    scan: dict | None = None


class TryOnRequest(BaseModel):
    model_config = STRICT
    body_id: str = Field(description="the body's id (unknown or malformed: 404)",
                         json_schema_extra={"pattern": ID_PATTERN})
    garment_id: str = Field(description="a catalogue garment's id")
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


# one server-sent event of GET /api/tryons/{job_id}/events (the schema is each event's)
TRYON_EVENT = {
    "type": "object", "required": ["event", "data"],
    "properties": {
        "event": {"enum": ["progress", "done", "failed", "cancelled"]},
        "data": {"type": "string", "contentMediaType": "application/json",
                 "contentSchema": {"$ref": "#/components/schemas/TryOn"},
                 "description": "the try-on as `GET /api/tryons/{job_id}` answers it"},
    },
}


class SizeFit(BaseModel):
    size: str
    chart: dict[str, float] | None = Field(description="the girths of the sample body the "
                                                        "size was made for, metres")
    ease: dict[str, float] | None = Field(description="chart − body per girth, metres")
    fits: bool | None


class SizeAdvice(BaseModel):
    garment_id: str
    body_id: str
    recommended: str
    sizes: list[SizeFit]
    basis: str


class Health(BaseModel):
    status: Literal["ok"]


class Check(BaseModel):
    ok: bool
    ms: float | None = None
    error: str | None = Field(None, description="`<Type>: <message>` of a failed check")


class Readiness(BaseModel):
    status: Literal["ready", "not ready"]
    checks: dict[str, Check]


class ErrorDetail(BaseModel):
    field: str | None
    message: str


class Problem(BaseModel):
    panel: str | None = Field(None, description="the panel named by the problem")
    edge: int | None = Field(None, description="the outline edge (its number) named")
    seam: int | None = Field(None, description="the seam (its number) named")
    size: str | None = Field(None, description="the size the problem is in")
    message: str


class GarmentWarning(BaseModel):
    """A repair or assumption of the import, or a warning of the check: a garment was made,
    but not exactly as sent."""
    model_config = ConfigDict(extra="allow")
    code: str | None = Field(None, description="what kind: `duplicate-points`, "
                             "`loop-removed`, `units`, `sample-quantity`, `sizes`, "
                             "`not-cut`, … (docs/garment-format.md, \"DXF import\"); `check` "
                             "for the checker's")
    message: str
    panel: str | None = Field(None, description="the panel it concerns (as named now)")
    piece: str | None = Field(None, description="the DXF piece it concerns (as the file "
                                                "names it)")
    size: str | None = Field(None, description="the size it concerns (none: every size)")

    @model_serializer(mode="wrap")
    def _given(self, handler):
        """Only what the warning says (no nulls for what it does not)."""
        return {k: v for k, v in handler(self).items() if v is not None}


class ErrorBody(BaseModel):
    code: str
    message: str
    field: str | None = Field(None, description="the parameter at fault, when one is")
    details: list[ErrorDetail] | None = Field(
        None, description="a request FastAPI refused: one entry per problem")
    problems: list[Problem] | None = Field(
        None, description="an uploaded garment's problems (`invalid_garment`): every one, "
                          "as `catwalk garment check` lists them")


class Error(BaseModel):
    error: ErrorBody


_WHY = {
    401: "no merchant API key, or one unknown or revoked (`Authorization: Bearer KEY`)",
    400: "unreadable: JSON that does not parse, a multipart body that cannot be read, a "
         "`Range` that is not `bytes=start-end` (code `bad_range`)",
    404: "unknown id (or the file it names missing)",
    409: "not possible in the try-on's state (`finished`, `not_done`); a garment changed by "
         "another request at the same time (`conflict`)",
    413: "the request body is over `CATWALK_UPLOAD_MAX_BYTES` (`too_large`)",
    415: "a `Content-Type` (or a scan type) this route does not take",
    416: "a `Range` no byte of the file satisfies (`bad_range`, `Content-Range: bytes */size`)",
    422: "a value missing, out of range, unknown or extra (`invalid`); an uploaded garment "
         "with problems (`invalid_garment`, each in `problems`)",
    503: "not now: the database cannot be reached (`unavailable`, `Retry-After`), a body not "
         "made in time (`busy`), a file still being made (`not_ready`)",
}


def errors(*codes: int) -> dict:
    """``responses=`` entries for these error statuses, each the API's JSON error."""
    return {code: {"model": Error, "description": _WHY[code]} for code in codes}


_BINARY = {"schema": {"type": "string", "format": "binary"}}
_STR = {"schema": {"type": "string"}}


def file_responses(media_type: str, *, ranges: bool = True, etag: bool = True) -> dict:
    """``responses=`` for a route answering a file: 200 with it, 304 for a matching
    ``If-None-Match`` and, with ``ranges``, 206 for a ``Range`` (several: multipart/byteranges)
    and its 400/416."""
    headers = {"Cache-Control": {"schema": {"type": "string"}, "required": True}}
    if etag:
        headers["ETag"] = {"schema": {"type": "string"}}
    out = {200: {"description": "the file", "content": {media_type: _BINARY},
                 "headers": headers},
           304: {"description": "`If-None-Match` matched the `ETag`: not modified"}}
    if ranges:
        out[206] = {"description": "the bytes of a `Range` (several ranges: "
                                   "multipart/byteranges)",
                    "content": {media_type: _BINARY, "multipart/byteranges": _BINARY},
                    "headers": {"Content-Range": {"schema": {"type": "string"}}}}
        out.update(errors(400, 416))
    return out


# the request headers a file route reads (documented, so that a client and a fuzzer see them)
FILE_HEADERS = {"parameters": [
    {"name": "Range", "in": "header", "required": False, "schema": {"type": "string"},
     "description": "`bytes=start-end[,start-end…]` → 206; past the end → 416; "
                    "another form → 400"},
    {"name": "If-Range", "in": "header", "required": False, "schema": {"type": "string"},
     "description": "the `ETag`: the `Range` is answered only if it still matches"},
    {"name": "If-None-Match", "in": "header", "required": False, "schema": {"type": "string"},
     "description": "the `ETag` (a list, `W/` or `*`) → 304"},
]}
CONDITIONAL_HEADERS = {"parameters": FILE_HEADERS["parameters"][2:]}


# ------------------------------------------------------------------------------ merchants

class PublishRequest(BaseModel):
    """``POST …/publish``'s body (or none: the latest version)."""
    model_config = STRICT
    version: int | None = Field(None, ge=1, le=MAX_VERSION,
                                description="the version to publish (default: the latest)")


class Merchant(BaseModel):
    name: str
    created_at: str
    publishable_key: str | None = Field(
        None, description="the key for the shop's pages (`pk_…`): it opens only the shoppers' "
                          "routes, from the origins below (docs/embed.md)")
    origins: list[str] = Field(
        default_factory=list, description="the origins the shop's pages may use the "
                                          "publishable key from")


class Origins(BaseModel):
    """``PUT /api/merchant/origins``: the origins the shop's pages are on (replacing those
    allowed before), each as a browser sends it: ``https://shop.example``."""
    model_config = STRICT
    origins: list[str] = Field(..., max_length=64)


class SizeDressing(BaseModel):
    """A size's dressing check on its sample body."""
    model_config = ConfigDict(extra="allow")
    status: Literal["queued", "running", "dressed", "failed"]
    ok: bool | None = None
    sample: str | None = Field(None, description="the sample body (bodies/recipes.json)")
    message: str | None = None
    glb_url: str | None = Field(None, description="the size dressed, as a .glb")


class GarmentVersionCreated(BaseModel):
    id: str = Field(description="the garment's catalogue id")
    version: int
    sizes: list[str]
    warnings: list[GarmentWarning]
    dressing: dict[str, SizeDressing]


class GarmentVersion(BaseModel):
    version: int
    content: str = Field(description="the hash of its files (a try-on's garment_version)")
    created_at: str
    sizes: list[str]
    warnings: list[GarmentWarning]
    check_status: Literal["queued", "running", "done"]
    dressing: dict[str, SizeDressing]


class MerchantGarment(BaseModel):
    id: str
    name: str
    type: str
    version: int = Field(description="the latest version")
    published_version: int | None = Field(description="the version in the catalogue (none: a "
                                                      "draft)")
    sizes: list[str]
    created_at: str
    updated_at: str
    catalogue_url: str | None
    versions: list[GarmentVersion]


class MerchantGarmentDetail(MerchantGarment):
    garment: dict = Field(description="the latest version's garment JSON")


class MerchantGarments(BaseModel):
    garments: list[MerchantGarment]


class DxfImport(BaseModel):
    garment: dict = Field(description="the pieces as a garment JSON without seams")
    pieces: list[dict]
    warnings: list[GarmentWarning]
