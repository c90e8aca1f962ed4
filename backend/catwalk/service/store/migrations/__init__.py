"""Alembic migrations of the service's database (``catwalk.service.store.db.migrate``)."""
