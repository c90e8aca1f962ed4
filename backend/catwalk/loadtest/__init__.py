"""``catwalk loadtest``: a realistic mix of shoppers against a running service (Locust)."""
