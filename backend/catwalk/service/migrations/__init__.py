"""Alembic migrations of the service's database (``catwalk.service.db.migrate``)."""
