"""``catwalk loadtest``."""

from __future__ import annotations

from catwalk.loadtest.run import main


def _loadtest(args) -> int:
    return main(args)


def register(top, groups) -> None:
    p = top.add_parser("loadtest", help="a mix of shoppers against a running service (Locust)",
                       description="Browse the catalogue, fetch thumbnails, follow try-ons, ask "
                       "for cached and new fast try-ons, make bodies — as N shoppers at once "
                       "for S seconds; then throughput, latency per route and errors.")
    p.add_argument("--url", required=True, help="the service, e.g. http://127.0.0.1:8000")
    p.add_argument("--users", type=int, default=50, help="shoppers at once (50)")
    p.add_argument("--seconds", type=float, default=60.0, help="how long (60)")
    p.add_argument("--garment", default="pencil-skirt",
                   help="the catalogue garment the try-ons use (pencil-skirt)")
    p.add_argument("--mix", choices=["shoppers", "api"], default="shoppers",
                   help="shoppers: everything (default); api: no bodies made — the API's own "
                        "routes, with new try-ons so that the workers simulate")
    p.add_argument("--json", action="store_true", help="print JSON")
    p.set_defaults(func=_loadtest)
