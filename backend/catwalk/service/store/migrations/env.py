"""Alembic's environment: migrations run on the connection ``catwalk.service.store.db.migrate``
hands over (online only; the URL comes from catwalk's settings, not from an ini file)."""

from alembic import context

from catwalk.service.store.models import Base

connection = context.config.attributes.get("connection")
if connection is None:
    raise RuntimeError("run migrations with catwalk.service.store.db.migrate(config)")
context.configure(connection=connection, target_metadata=Base.metadata,
                  render_as_batch=connection.dialect.name == "sqlite")
with context.begin_transaction():
    context.run_migrations()
