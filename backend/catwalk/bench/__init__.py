"""Benchmarks (``catwalk bench …``) and what they share: the machine they ran on, the
output flags."""

from __future__ import annotations

import platform


def cpu_model() -> str:
    """The CPU's model name from /proc/cpuinfo (or what platform knows)."""
    try:
        with open("/proc/cpuinfo") as fh:
            for line in fh:
                if line.startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown cpu"


def add_output_flags(parser) -> None:
    """``--quiet`` (no progress lines) and ``--json`` (print JSON instead of the table)."""
    parser.add_argument("--quiet", action="store_true", help="no progress lines")
    parser.add_argument("--json", action="store_true", help="print JSON")


def progress_lines(args):
    """A ``progress(what)`` printing a line per step, or None when quiet or printing JSON."""
    if args.json or args.quiet:
        return None
    return lambda what: print(what, flush=True)


def add_walk_seconds(parser, default: float = 2.0) -> None:
    """``--seconds``: how long the benchmark's scene walks (checked by
    :func:`check_walk_seconds`)."""
    parser.add_argument("--seconds", type=float, default=default,
                        help=f"walk length (default {default:g}; 0.5–10)")


def check_walk_seconds(seconds: float) -> None:
    """Refuse a walk length outside 0.5–10 s (:class:`~catwalk.errors.InputError`)."""
    from catwalk.errors import InputError

    if not 0.5 <= seconds <= 10:
        raise InputError(f"--seconds must be within 0.5–10, got {seconds}")
