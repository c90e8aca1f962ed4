"""Every setting catwalk reads from its environment, in one place.

One :class:`Config` object, read from ``CATWALK_*`` environment variables (pydantic-settings);
:func:`get_config` gives the process's copy. Nothing else in the package reads the environment or
computes a path from ``__file__``: the repository's own folders (the catalogue, the sample-body
recipes, the Node tools) are defaults here, found once from where the package lies.

With nothing set, everything runs on one machine with nothing but Python: SQLite and a broker
on the filesystem, both inside the storage folder (the embedded default of ``catwalk serve``).
Set ``CATWALK_DATABASE_URL`` (PostgreSQL) and ``CATWALK_BROKER_URL`` (Redis) to run any number of
API and worker processes on any number of machines that share them and the storage folder.
"""

from __future__ import annotations

import functools
import os
import sys
from pathlib import Path

import platformdirs
from pydantic import AliasChoices, Field, field_validator
from pydantic_settings import BaseSettings, SettingsConfigDict

# backend/catwalk/config.py → the repository (or the folder an installed package lies in)
REPO_DIR = Path(__file__).resolve().parents[2]


def _cores() -> int:
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:   # not Linux
        return max(1, os.cpu_count() or 1)


class Config(BaseSettings):
    """catwalk's settings (each field is the environment variable ``CATWALK_<NAME>``)."""

    model_config = SettingsConfigDict(env_prefix="CATWALK_", extra="ignore", frozen=True)

    # --- data and storage
    data_dir: Path = Field(
        default_factory=lambda: Path(platformdirs.user_cache_dir("catwalk")),
        validation_alias=AliasChoices("CATWALK_DATA_DIR", "CATWALK_DATA"),
        description="the MakeHuman assets (fetched on first use)")
    storage_dir: Path = Field(
        default_factory=lambda: Path(platformdirs.user_data_dir("catwalk")) / "storage",
        description="scans, bodies, results, thumbnails; shared by every API and worker")
    catalogue_dir: Path = Field(default=REPO_DIR / "garments",
                                description="the catalogue's garments (*.json)")
    bodies_dir: Path = Field(default=REPO_DIR / "bodies",
                             description="sample-body recipes (recipes.json); sample bodies "
                                         "are made into generated/ below it")
    node_tools_dir: Path = Field(default=REPO_DIR / "tools" / "node",
                                 description="gltfpack and the glTF validator (npm)")
    frontend_dir: Path = Field(default=REPO_DIR / "frontend" / "dist",
                               description="the built pages `catwalk serve` serves at /")

    # --- the service
    database_url: str | None = Field(
        default=None, description="SQLAlchemy URL; default: SQLite in the storage folder")
    broker_url: str | None = Field(
        default=None, description="Celery broker URL; default: a folder in the storage folder")
    queue: str = Field(default="catwalk", description="the Celery queue of the jobs")
    workers: int = Field(default_factory=_cores, ge=0,
                         description="worker processes `catwalk serve` starts (0: none)")
    upload_max_bytes: int = Field(default=100 * 1024 * 1024, gt=0,
                                  description="the largest upload accepted (413 above)")
    job_time_limit_s: float = Field(default=1800.0, ge=10,
                                    description="a job is killed after this long")
    job_stale_s: float = Field(default=30.0, gt=0,
                               description="a running job without a heartbeat for this long "
                                           "is run again (its worker died)")
    requeue_after_s: float = Field(default=20.0, gt=0,
                                   description="a queued job that the broker no longer holds "
                                               "after this long is sent again")
    body_timeout_s: float = Field(default=300.0, gt=0,
                                  description="how long POST /api/bodies waits for a body")
    rate_key_per_minute: int = Field(
        default=1200, gt=0,
        description="requests a shop's publishable key may make a minute (429 beyond)")
    rate_shopper_per_minute: int = Field(
        default=120, gt=0,
        description="requests one shopper on a shop may make a minute (429 beyond)")
    rate_shopper_jobs_per_hour: int = Field(
        default=30, gt=0,
        description="bodies and try-ons one shopper on a shop may ask for an hour (429 beyond)")
    log_level: str = Field(default="INFO")

    @field_validator("data_dir", "storage_dir", "catalogue_dir", "bodies_dir", "node_tools_dir",
                     "frontend_dir")
    @classmethod
    def _expand(cls, v: Path) -> Path:
        return Path(v).expanduser()

    @property
    def db_url(self) -> str:
        """The database URL in use (SQLite in the storage folder unless one is set)."""
        return self.database_url or f"sqlite:///{self.storage_dir / 'catwalk.sqlite3'}"

    @property
    def broker(self) -> str:
        """The broker URL in use (kombu's filesystem transport unless one is set)."""
        return self.broker_url or "filesystem://localhost/"

    @property
    def broker_folder(self) -> Path:
        """The filesystem broker's message folder (used when no broker URL is set)."""
        return self.storage_dir / "broker"

    @property
    def embedded(self) -> bool:
        """True when neither a database nor a broker server is configured."""
        return self.database_url is None and self.broker_url is None


def unknown_variables() -> list[str]:
    """``CATWALK_*`` variables in the environment that no setting reads (a misspelt
    ``CATWALK_DATABSE_URL`` would otherwise quietly give SQLite)."""
    known = {f"CATWALK_{name.upper()}" for name in Config.model_fields} | {"CATWALK_DATA"}
    ours = {k for k in os.environ if k.startswith("CATWALK_")}
    test_only = {k for k in ours if k.startswith(("CATWALK_TEST_", "CATWALK_FUZZ_"))}
    return sorted(ours - known - test_only)


@functools.lru_cache(maxsize=1)
def get_config() -> Config:
    """This process's settings, read from the environment once (``get_config.cache_clear()``
    reads them again). Unknown ``CATWALK_*`` variables are reported on stderr."""
    for name in unknown_variables():
        print(f"catwalk: warning: {name} is not a catwalk setting (see README, "
              "Configuration); ignored", file=sys.stderr)
    return Config()
