"""The try-on service: the HTTP API (``api/``), the job queue and its workers (``queue.py``,
``worker.py``), the database (``db.py``, ``models.py``, ``migrations/``, ``jobs.py``), blob
storage (``storage.py``), the catalogue (``catalogue.py``), content keys (``keys.py``),
bodies (``bodies.py``) and thumbnails (``thumbnails.py``); ``serve.py`` runs it all on one
machine. docs/service.md says how it fits together, docs/api.md what it answers."""
