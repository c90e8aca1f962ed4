"""The ``catwalk`` command.

Each area of the product registers its own sub-commands from its ``commands`` module (so the
areas stay apart): ``register(top, groups)`` where ``top`` is the top-level sub-parser set and
``groups`` maps a group name (``body``, ``bench``) to that group's sub-parser set. A command's
handler is ``args.func(args) -> int``. catwalk's errors print ``catwalk: error: …`` without a
traceback and exit by whose they are (:mod:`catwalk.errors`): 2 for the user's input
(:class:`InputError`), 3 for a simulation that failed (:class:`SimulationError`), 130 when
cancelled or interrupted, 1 for an incomplete installation (:class:`SetupError`).
"""

from __future__ import annotations

import argparse
import importlib
import sys

from catwalk.errors import Cancelled, CatwalkError, InputError, SimulationError

# Modules that add commands; each has register(top, groups).
COMMAND_MODULES = [
    "catwalk.cli.assets",
    "catwalk.cli.body",
    "catwalk.cli.scan",
    "catwalk.cli.walk",
    "catwalk.cli.render",
    "catwalk.cli.cloth",
    "catwalk.cli.collide",
    "catwalk.cli.garment",
    "catwalk.cli.tryon",
    "catwalk.cli.service",
    "catwalk.cli.loadtest",
]

GROUPS = {
    "body": "bodies: make from measurements, measure, inspect scans",
    "bench": "benchmarks (each with --json)",
    "merchant": "merchants' accounts, API keys, publishable keys and origins (operators)",
}


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="catwalk", description="catwalk: virtual try-on on a walking body")
    top = parser.add_subparsers(dest="command", metavar="COMMAND")
    top.required = True
    groups = {}
    for name, help_text in GROUPS.items():
        gp = top.add_parser(name, help=help_text, description=help_text)
        sub = gp.add_subparsers(dest=f"{name}_command", metavar="COMMAND")
        sub.required = True
        groups[name] = sub
    for modname in COMMAND_MODULES:
        try:
            mod = importlib.import_module(modname)
        except ModuleNotFoundError as exc:
            if exc.name == modname:
                continue  # that area has no commands yet
            raise
        mod.register(top, groups)
    return parser


def exit_code(exc: CatwalkError) -> int:
    """The exit status for one of catwalk's errors (module docstring)."""
    if isinstance(exc, InputError):
        return 2
    if isinstance(exc, SimulationError):
        return 3
    if isinstance(exc, Cancelled):
        return 130
    return 1


def main(argv: list[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        rc = args.func(args)
    except CatwalkError as exc:
        print(f"catwalk: error: {exc}", file=sys.stderr)
        return exit_code(exc)
    except KeyboardInterrupt:
        print("catwalk: interrupted", file=sys.stderr)
        return 130
    return int(rc or 0)


if __name__ == "__main__":
    sys.exit(main())
