"""The HTTP API (FastAPI): routes under ``routes/``, request and response models in
``schemas.py``, the JSON errors in ``errors.py``, the app and its lifespan in ``app.py``."""
