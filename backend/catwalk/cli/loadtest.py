"""``catwalk loadtest``."""

from __future__ import annotations

import json

from catwalk.errors import InputError
from catwalk.loadtest import chaos
from catwalk.loadtest.run import main


def _loadtest(args) -> int:
    if not args.chaos:
        if not args.url:
            raise InputError("--url is needed (or --chaos, which starts a service of its own)")
        return main(args)
    if args.url:
        raise InputError("--chaos starts a service of its own: leave --url out")
    if not 1 <= args.users <= 500:
        raise InputError(f"--users must be within 1–500, got {args.users}")
    r = chaos.run(args.users, args.seconds, args.kill_every, args.garment, args.keep)
    print(json.dumps(r, indent=2) if args.json else chaos.format_report(r))
    return 0 if r["ok"] else 3      # a try-on lost or done twice, or an unexpected 5xx


def register(top, groups) -> None:
    p = top.add_parser("loadtest", help="a mix of shoppers against a running service (Locust)",
                       description="Browse the catalogue, fetch thumbnails, follow try-ons, ask "
                       "for cached and new fast try-ons, make bodies — as N shoppers at once "
                       "for S seconds; then throughput, latency per route and errors.")
    p.add_argument("--url", help="the service, e.g. http://127.0.0.1:8000")
    p.add_argument("--users", type=int, default=50, help="shoppers at once (50)")
    p.add_argument("--seconds", type=float, default=60.0, help="how long (60)")
    p.add_argument("--garment", default="pencil-skirt",
                   help="the catalogue garment the try-ons use (pencil-skirt)")
    p.add_argument("--mix", choices=["shoppers", "api"], default="shoppers",
                   help="shoppers: everything (default); api: no bodies made — the API's own "
                        "routes, with new try-ons so that the workers simulate")
    p.add_argument("--chaos", action="store_true",
                   help="start a service of its own (Redis and PostgreSQL in a temporary "
                        "folder, the API, two workers), run the shoppers against it and kill a "
                        "worker every --kill-every s, restart Redis once and PostgreSQL once; "
                        "then try-ons lost, done twice, unexpected 5xx, req/s and p99 around "
                        "each fault (docs/operations.md)")
    p.add_argument("--kill-every", type=float, default=20.0, metavar="S",
                   help="with --chaos: seconds between two workers killed (20)")
    p.add_argument("--keep", metavar="DIR", help="with --chaos: keep the stack's logs here")
    p.add_argument("--json", action="store_true", help="print JSON")
    p.set_defaults(func=_loadtest)
