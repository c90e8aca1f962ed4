"""``catwalk serve``, ``catwalk worker``, ``catwalk demo`` and ``catwalk bench service``."""

from __future__ import annotations

import json

from sqlalchemy.exc import DBAPIError

from catwalk.bench import add_walk_seconds
from catwalk.bench import player as bench_player
from catwalk.bench import service as bench_service
from catwalk.cli import demo
from catwalk.config import get_config
from catwalk.errors import InputError, SetupError
from catwalk.service import merchants
from catwalk.service.jobs import worker
from catwalk.service.serve import main
from catwalk.service.store import db


def _serve(args) -> int:
    if not 0 < args.port < 65536:
        raise InputError(f"--port must be 1–65535, got {args.port}")
    if args.workers is not None and args.workers < 0:
        raise InputError(f"--workers must be ≥ 0, got {args.workers}")
    return main(args.host, args.port, args.workers)


def _worker(args) -> int:
    if args.concurrency is not None and args.concurrency < 1:
        raise InputError(f"--concurrency must be ≥ 1, got {args.concurrency}")
    return worker.main(args.concurrency, args.loglevel)


def _demo(args) -> int:
    return demo.main(args)


def _shop_keys(config, args) -> None:
    """``catwalk merchant publishable-key|origins``."""
    if args.merchant_command == "publishable-key":
        key = merchants.publishable_key(config, args.name, new=args.new)
        print(f"merchant {args.name!r}: {'a new' if args.new else 'its'} publishable key, "
              "for its shop's pages (<catwalk-tryon key=…>), usable from the origins "
              f"allowed (`catwalk merchant origins {args.name} https://shop.example`):")
        print(key)
        return
    changing = args.origins or args.add or args.remove or args.clear
    if args.clear and args.origins:
        raise InputError("give origins to allow, or --clear, not both", "origins")
    now = merchants.origins(config, args.name,
                            replace=[] if args.clear else (args.origins or None),
                            add=args.add or [], remove=args.remove or [])
    if args.json:
        print(json.dumps(now))
        return
    told = "now allowed" if changing else "allowed"
    print(f"merchant {args.name!r}: origins {told} for its publishable key: "
          f"{len(now)}" + ("" if now else " (its shop's pages cannot use it yet)"))
    for origin in now:
        print(origin)


def _merchant(args) -> int:
    """``catwalk merchant create|list|revoke|publishable-key|origins``: against the
    service's database (migrated first), which must be reachable."""
    config = get_config()
    try:
        db.migrate(config)
        if args.merchant_command in ("publishable-key", "origins"):
            _shop_keys(config, args)
        elif args.merchant_command == "create":
            key = merchants.create(config, args.name)
            print(f"merchant {args.name!r} created; its API key (shown once, not stored; send "
                  "it as 'Authorization: Bearer KEY'):")
            print(key)
        elif args.merchant_command == "list":
            rows = merchants.listing(config)
            if args.json:
                print(json.dumps(rows, indent=1))
            for r in [] if args.json else rows:
                state = f"revoked {r['revoked_at']}" if r["revoked_at"] else "active"
                print(f"{r['name']:<32} created {r['created_at']}  {state}")
        else:
            done = merchants.revoke(config, args.name)
            print(f"merchant {args.name!r}: key revoked" if done else
                  f"merchant {args.name!r}: its key was revoked already")
    except DBAPIError as exc:
        raise SetupError(f"the database cannot be reached ({type(exc.orig).__name__}); check "
                         "CATWALK_DATABASE_URL") from None
    return 0


def _bench_player(args) -> int:
    return bench_player.main(args)


def _bench_service(args) -> int:
    return bench_service.main(args)


def register(top, groups) -> None:
    p = top.add_parser("serve", help="the service: the API and local workers on this machine",
                       description="Run the HTTP API (and, unless --workers 0, a worker "
                       "process). With no CATWALK_DATABASE_URL / CATWALK_BROKER_URL set: "
                       "SQLite and a filesystem broker in CATWALK_STORAGE_DIR.")
    p.add_argument("--host", default="127.0.0.1", help="address to listen on (127.0.0.1)")
    p.add_argument("--port", type=int, default=8000, help="port (8000)")
    p.add_argument("--workers", type=int, default=None,
                   help="try-ons run at once by the local worker (default: CATWALK_WORKERS, "
                        "the number of cores; 0: no local worker)")
    p.set_defaults(func=_serve)

    p = top.add_parser("worker", help="run try-on jobs from the queue",
                       description="Consume try-on jobs from the broker (CATWALK_BROKER_URL) "
                       "and store results in CATWALK_STORAGE_DIR; any number of these may run "
                       "on any number of machines.")
    p.add_argument("--concurrency", type=int, default=None,
                   help="jobs at once (processes; default CATWALK_WORKERS, the cores)")
    p.add_argument("--loglevel", default=None, help="DEBUG, INFO (default), WARNING")
    p.set_defaults(func=_worker)

    p = top.add_parser("demo", help="start the service and run the sample try-on through its "
                                    "API (what `make demo` does)")
    p.add_argument("--url", default=None,
                   help="use a service already running there instead of starting one")
    p.add_argument("--port", type=int, default=8000)
    p.add_argument("--out-dir", default="demo", help="where tryon.glb, tryon.png and "
                                                     "metrics.json go (demo/)")
    p.add_argument("--garment", default="dress", help="catalogue garment id (dress)")
    p.add_argument("--size", default="M")
    p.add_argument("--seconds", type=float, default=4.0)
    p.add_argument("--preset", default="balanced", choices=["fast", "balanced", "accurate"])
    p.add_argument("--exit", action="store_true",
                   help="stop once the try-on is written (also DEMO_EXIT=1)")
    p.set_defaults(func=_demo)

    merchant = groups["merchant"]
    p = merchant.add_parser("create", help="a new merchant; prints its API key once, alone on "
                                           "the last line")
    p.add_argument("name", help="1–64 lower-case letters, digits, '-' or '_'")
    p.set_defaults(func=_merchant)
    p = merchant.add_parser("list", help="every merchant (never a key)")
    p.add_argument("--json", action="store_true", help="print JSON")
    p.set_defaults(func=_merchant)
    p = merchant.add_parser("revoke", help="revoke a merchant's key (its garments stay)")
    p.add_argument("name")
    p.set_defaults(func=_merchant)
    p = merchant.add_parser("publishable-key",
                            help="the merchant's publishable key (pk_…) for its shop's pages, "
                                 "alone on the last line")
    p.add_argument("name")
    p.add_argument("--new", action="store_true",
                   help="a new key in its place (the old one stops working at once)")
    p.set_defaults(func=_merchant)
    p = merchant.add_parser("origins",
                            help="the origins the shop's pages may use the publishable key "
                                 "from: list them, or set them (replacing), --add, --remove, "
                                 "--clear")
    p.add_argument("name")
    p.add_argument("origins", nargs="*", metavar="ORIGIN",
                   help="https://shop.example …: these exactly, replacing those allowed")
    p.add_argument("--add", action="append", metavar="ORIGIN", help="allow one more")
    p.add_argument("--remove", action="append", metavar="ORIGIN", help="allow it no more")
    p.add_argument("--clear", action="store_true", help="allow none")
    p.add_argument("--json", action="store_true", help="print the list as JSON")
    p.set_defaults(func=_merchant)

    p = groups["bench"].add_parser(
        "service", help="try-ons through the HTTP API: per minute, latency, overhead against "
                        "the library, a cached answer's latency")
    p.add_argument("--tryons", type=int, default=4, help="concurrent fast try-ons (4)")
    p.add_argument("--workers", type=int, default=None,
                   help="try-ons the service under test runs at once (default 1)")
    add_walk_seconds(p)
    p.add_argument("--json", action="store_true", help="print JSON")
    p.set_defaults(func=_bench_service)

    p = groups["bench"].add_parser(
        "player", help="the try-on page in chromium: first frame, download size, work per "
                       "frame against the try-on's length; the shops' component: its size and "
                       "its first frame on a shop's page")
    p.add_argument("--seconds", type=float, nargs="+", default=[2.0, 10.0],
                   help="walk lengths to compare (2 10)")
    p.add_argument("--frames", type=int, default=240, help="frames of playback measured")
    p.add_argument("--no-embed", action="store_true",
                   help="leave out the shops' component (docs/embed.md)")
    p.add_argument("--json", action="store_true", help="print JSON")
    p.set_defaults(func=_bench_player)
