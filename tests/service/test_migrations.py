"""The schema's migrations on data an older version left: 0001 → head on SQLite and PostgreSQL
with two active try-ons of one body and key (possible before 0002's unique index): the upgrade
keeps the first, cancels the others and succeeds."""

from __future__ import annotations

import datetime
import uuid

import pytest
import sqlalchemy as sa

from .helpers import DB_URL


def _upgrade(engine, revision: str) -> None:
    from alembic import command
    from alembic.config import Config as AlembicConfig

    from catwalk.service.store.db import MIGRATIONS

    with engine.begin() as conn:
        cfg = AlembicConfig()
        cfg.set_main_option("script_location", str(MIGRATIONS))
        cfg.set_main_option("path_separator", "os")
        cfg.attributes["connection"] = conn
        command.upgrade(cfg, revision)


def _filled(table, **given) -> dict:
    """``given``, and a plain value for every other column that needs one."""
    plain = {str: "x", int: 0, float: 0.0, bool: False, dict: {},
             datetime.datetime: datetime.datetime(2026, 1, 1)}
    return {c.name: given.get(c.name, plain.get(c.type.python_type)) for c in table.columns
            if c.name in given or not c.nullable}


@pytest.fixture(params=["sqlite", "postgresql"])
def engine(request, tmp_path):
    if request.param == "sqlite":
        yield sa.create_engine(f"sqlite:///{tmp_path / 'old.sqlite3'}")
        return
    import psycopg

    name = f"catwalk_migrate_{uuid.uuid4().hex[:10]}"
    plain = DB_URL.replace("+psycopg", "")
    with psycopg.connect(plain, autocommit=True, connect_timeout=5) as c:
        c.execute(f'CREATE DATABASE "{name}"')
    eng = sa.create_engine(f"{DB_URL.rpartition('/')[0]}/{name}")
    yield eng
    eng.dispose()
    with psycopg.connect(plain, autocommit=True) as c:
        c.execute(f'DROP DATABASE IF EXISTS "{name}"')


def test_duplicate_active_tryons_are_cancelled_before_the_unique_index(engine):
    _upgrade(engine, "0001")
    meta = sa.MetaData()
    tryons = sa.Table("tryons", meta, autoload_with=engine)
    bodies = sa.Table("bodies", meta, autoload_with=engine)
    with engine.begin() as c:
        c.execute(bodies.insert().values(**_filled(bodies, id="B1")))
        for i, status in enumerate(["queued", "running", "queued", "done"]):
            c.execute(tryons.insert().values(**_filled(tryons, id=f"J{i}", body_id="B1",
                                                       key="K", status=status)))
    _upgrade(engine, "head")
    with engine.connect() as c:
        got = dict(c.execute(sa.select(tryons.c.id, tryons.c.status)).all())
    assert got == {"J0": "queued", "J1": "cancelled", "J2": "cancelled", "J3": "done"}
    with pytest.raises(sa.exc.IntegrityError), engine.begin() as c:   # the index holds now
        c.execute(tryons.insert().values(**_filled(tryons, id="J9", body_id="B1", key="K",
                                                   status="queued")))


def test_merchants_made_before_shops_get_a_publishable_key(engine):
    """0003 → head: each merchant gets its own publishable key, no origin allowed; bodies
    made before belong to no shop."""
    _upgrade(engine, "0003")
    meta = sa.MetaData()
    merchants = sa.Table("merchants", meta, autoload_with=engine)
    bodies = sa.Table("bodies", meta, autoload_with=engine)
    with engine.begin() as c:
        for i in range(2):
            c.execute(merchants.insert().values(**_filled(merchants, id=f"M{i}",
                                                          name=f"shop-{i}",
                                                          key_sha256=f"{i:064d}")))
        c.execute(bodies.insert().values(**_filled(bodies, id="B1")))
    _upgrade(engine, "head")
    meta = sa.MetaData()
    merchants = sa.Table("merchants", meta, autoload_with=engine)
    bodies = sa.Table("bodies", meta, autoload_with=engine)
    with engine.connect() as c:
        rows = c.execute(sa.select(merchants.c.publishable_key, merchants.c.origins)).all()
        shop = c.execute(sa.select(bodies.c.merchant_id, bodies.c.shopper)).one()
    keys = [k for k, _ in rows]
    assert len(set(keys)) == 2 and all(k.startswith("pk_") and len(k) == 35 for k in keys)
    assert [o for _, o in rows] == [None, None]
    assert tuple(shop) == (None, None)
