"""The service's tables (SQLAlchemy ORM). The database is the source of truth for every job.

- ``bodies``: a shopper's body: where it came from (a scan or measurements), its measurements
  (personal data: never logged, never listed, deleted with the body) and the content key that
  makes two identical uploads share cached results; one made on a merchant's shop (with its
  publishable key) names the merchant and the SHA-256 of the shopper's own id, and is reached
  only through that shop, by that shopper.
- ``tryons``: one try-on asked for by a shopper: what (body, garment and version, size,
  fabric, seconds, preset), its state (``queued`` → ``running`` → ``done`` | ``failed`` |
  ``cancelled``), progress, and the worker's heartbeat; ``key`` is the content key of the
  result it makes.
- ``workers``: the worker processes as last seen (for the metrics).
- ``merchants``: a merchant (made by an operator, ``catwalk merchant create``): its name and
  the SHA-256 of its API key (the key itself is shown once and never stored), revoked or not;
  its publishable key (``pk_…``: public, for its shop's pages, kept as it is) and the origins
  those pages may use it from.
- ``merchant_garments``: a merchant's garment: its catalogue id, its latest version and the
  version published in the catalogue (none: a draft), deleted or not.
- ``garment_versions``: each upload or change of a garment, immutable: its files under
  ``garments/<id>/<n>/`` in the storage, the content hash a try-on's key names, the check's
  warnings, and the dressing check per size (the worker's report).
- ``results``: a finished result, stored exactly once per content key (the files under
  ``results/<key>/`` in the storage are written first, then this row).

Schema changes go through Alembic (``service/migrations``), from the first table on.
"""

from __future__ import annotations

from datetime import UTC, datetime

from sqlalchemy import (
    JSON,
    Boolean,
    DateTime,
    Float,
    ForeignKey,
    Index,
    Integer,
    String,
    Text,
    text,
)
from sqlalchemy.orm import DeclarativeBase, Mapped, mapped_column

STATES = ("queued", "running", "done", "failed", "cancelled")
ACTIVE = ("queued", "running")
FINISHED = ("done", "failed", "cancelled")


def utcnow() -> datetime:
    return datetime.now(UTC).replace(tzinfo=None)


class Base(DeclarativeBase):
    pass


class BodyRow(Base):
    __tablename__ = "bodies"
    __table_args__ = (Index("ix_bodies_shop", "merchant_id", "shopper"),)

    id: Mapped[str] = mapped_column(String(43), primary_key=True)
    created_at: Mapped[datetime] = mapped_column(DateTime, default=utcnow)
    source: Mapped[str] = mapped_column(String(16))           # scan | measurements
    fit: Mapped[str] = mapped_column(String(16))              # how the body was made
    content_key: Mapped[str] = mapped_column(String(64))      # sha256 of what it came from
    sex: Mapped[str] = mapped_column(String(8))
    measurements: Mapped[dict] = mapped_column(JSON)          # the person's
    model_measurements: Mapped[dict] = mapped_column(JSON)    # the made body's
    scan_format: Mapped[str | None] = mapped_column(String(8), nullable=True)
    # made on a shop: the merchant and the SHA-256 of the shopper's id (else both None)
    merchant_id: Mapped[str | None] = mapped_column(String(43), nullable=True)
    shopper: Mapped[str | None] = mapped_column(String(64), nullable=True)


class TryOnRow(Base):
    __tablename__ = "tryons"
    __table_args__ = (Index("ix_tryons_status", "status"), Index("ix_tryons_key", "key"),
                      Index("ix_tryons_body", "body_id"),
                      Index("ix_tryons_finished", "finished_at"),
                      # one queued or running try-on per body and content key
                      Index("ux_tryons_active", "body_id", "key", unique=True,
                            postgresql_where=text("status IN ('queued', 'running')"),
                            sqlite_where=text("status IN ('queued', 'running')")))

    id: Mapped[str] = mapped_column(String(43), primary_key=True)
    key: Mapped[str] = mapped_column(String(64))
    body_id: Mapped[str] = mapped_column(ForeignKey("bodies.id", ondelete="CASCADE"))
    garment_id: Mapped[str] = mapped_column(String(128))
    garment_version: Mapped[str] = mapped_column(String(64))
    size: Mapped[str] = mapped_column(String(32))
    fabric: Mapped[str | None] = mapped_column(String(64), nullable=True)
    seconds: Mapped[float] = mapped_column(Float)
    preset: Mapped[str] = mapped_column(String(16))
    status: Mapped[str] = mapped_column(String(16), default="queued")
    progress: Mapped[float] = mapped_column(Float, default=0.0)
    stage: Mapped[str] = mapped_column(String(32), default="queued")
    error: Mapped[str | None] = mapped_column(Text, nullable=True)
    cached: Mapped[bool] = mapped_column(Boolean, default=False)
    cancel_requested: Mapped[bool] = mapped_column(Boolean, default=False)
    attempts: Mapped[int] = mapped_column(Integer, default=0)
    worker: Mapped[str | None] = mapped_column(String(255), nullable=True)
    created_at: Mapped[datetime] = mapped_column(DateTime, default=utcnow)
    enqueued_at: Mapped[datetime] = mapped_column(DateTime, default=utcnow)
    started_at: Mapped[datetime | None] = mapped_column(DateTime, nullable=True)
    heartbeat_at: Mapped[datetime | None] = mapped_column(DateTime, nullable=True)
    finished_at: Mapped[datetime | None] = mapped_column(DateTime, nullable=True)
    timings: Mapped[dict | None] = mapped_column(JSON, nullable=True)   # stage → seconds


class ResultRow(Base):
    __tablename__ = "results"

    key: Mapped[str] = mapped_column(String(64), primary_key=True)
    created_at: Mapped[datetime] = mapped_column(DateTime, default=utcnow)
    metrics: Mapped[dict] = mapped_column(JSON)
    glb_bytes: Mapped[int] = mapped_column(Integer)
    web_bytes: Mapped[int] = mapped_column(Integer)
    glb_sha256: Mapped[str] = mapped_column(String(64))
    web_sha256: Mapped[str] = mapped_column(String(64))


class WorkerRow(Base):
    """A worker process (``catwalk worker``'s main process) as last seen: its recovery loop
    touches ``seen_at`` every few seconds; the metrics count those seen lately."""
    __tablename__ = "workers"

    id: Mapped[str] = mapped_column(String(255), primary_key=True)   # host:pid
    host: Mapped[str] = mapped_column(String(255))
    pid: Mapped[int] = mapped_column(Integer)
    concurrency: Mapped[int] = mapped_column(Integer)
    started_at: Mapped[datetime] = mapped_column(DateTime, default=utcnow)
    seen_at: Mapped[datetime] = mapped_column(DateTime, default=utcnow)


class MerchantRow(Base):
    __tablename__ = "merchants"
    __table_args__ = (Index("ux_merchants_publishable_key", "publishable_key", unique=True),)

    id: Mapped[str] = mapped_column(String(43), primary_key=True)
    name: Mapped[str] = mapped_column(String(64), unique=True)
    key_sha256: Mapped[str] = mapped_column(String(64), unique=True)
    created_at: Mapped[datetime] = mapped_column(DateTime, default=utcnow)
    revoked_at: Mapped[datetime | None] = mapped_column(DateTime, nullable=True)
    publishable_key: Mapped[str | None] = mapped_column(String(64), nullable=True)
    origins: Mapped[list | None] = mapped_column(JSON, nullable=True)   # normalised, in order


class MerchantGarmentRow(Base):
    __tablename__ = "merchant_garments"
    __table_args__ = (Index("ix_merchant_garments_merchant", "merchant_id"),)

    id: Mapped[str] = mapped_column(String(64), primary_key=True)   # the catalogue id
    merchant_id: Mapped[str] = mapped_column(ForeignKey("merchants.id", ondelete="CASCADE"))
    name: Mapped[str] = mapped_column(String(200))
    type: Mapped[str] = mapped_column(String(32))
    version: Mapped[int] = mapped_column(Integer)                    # the latest
    published_version: Mapped[int | None] = mapped_column(Integer, nullable=True)
    created_at: Mapped[datetime] = mapped_column(DateTime, default=utcnow)
    updated_at: Mapped[datetime] = mapped_column(DateTime, default=utcnow)
    deleted_at: Mapped[datetime | None] = mapped_column(DateTime, nullable=True)


class GarmentVersionRow(Base):
    __tablename__ = "garment_versions"

    garment_id: Mapped[str] = mapped_column(
        ForeignKey("merchant_garments.id", ondelete="CASCADE"), primary_key=True)
    version: Mapped[int] = mapped_column(Integer, primary_key=True)
    content: Mapped[str] = mapped_column(String(64))   # catalogue.garment_version of its files
    created_at: Mapped[datetime] = mapped_column(DateTime, default=utcnow)
    sizes: Mapped[list] = mapped_column(JSON)
    warnings: Mapped[list] = mapped_column(JSON)
    dressing: Mapped[dict] = mapped_column(JSON)       # size → the dressing check's report
    # the dressing check as a job (claimed, beating and run again like a try-on)
    check_status: Mapped[str] = mapped_column(String(16), default="queued")
    check_attempts: Mapped[int] = mapped_column(Integer, default=0)
    check_beat_at: Mapped[datetime | None] = mapped_column(DateTime, nullable=True)
