"""Benchmarks (``catwalk bench …``) and what they share: the machine they ran on, the
output flags."""

from __future__ import annotations

import platform

from catwalk.errors import InputError
from catwalk.simulate import preset


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


def log_lines(args):
    """A ``log(what)`` printing a line per step of a benchmark, or None when quiet or printing
    JSON (a log of steps, not a progress callback: :mod:`catwalk.progress`)."""
    if args.json or args.quiet:
        return None
    return lambda what: print(what, flush=True)


def add_walk_seconds(parser, default: float = 2.0) -> None:
    """``--seconds``: how long the benchmark's scene walks (checked by
    :func:`check_walk_seconds`)."""
    parser.add_argument("--seconds", type=float, default=default,
                        help=f"walk length (default {default:g}; 0.5–10)")


def add_walk_settings(parser) -> None:
    """``--plane-band``, ``--min-collisions``, ``--max-move``: the walks' collision responses a
    frame and plane band (docs/tryon.md, "How many responses a frame"); ``--integrator``,
    ``--xpbd-dt``, ``--xpbd-iterations``: the walks' cloth integrator (docs/cloth.md);
    ``--skips-off``: collider skips switched off (``Settings.skips_off``); read by
    :func:`walk_settings`."""
    parser.add_argument("--plane-band", type=float, default=None, metavar="M",
                        help="the walks' plane band in metres (default: balanced's, 0)")
    parser.add_argument("--min-collisions", type=int, default=None, metavar="N",
                        help="the walks' least collision responses a frame (default: "
                        "balanced's)")
    parser.add_argument("--max-move", type=float, default=None, metavar="M",
                        help="the walks' body motion between two responses, m (default: "
                        "balanced's)")
    parser.add_argument("--integrator", choices=["explicit", "xpbd", "implicit"], default=None,
                        help="the walks' cloth integrator (default: balanced's, explicit)")
    parser.add_argument("--xpbd-dt", type=float, default=None, metavar="S",
                        help="with --integrator xpbd: its step in seconds (default 1/300)")
    parser.add_argument("--xpbd-iterations", type=int, default=None, metavar="N",
                        help="with --integrator xpbd: its sweeps a step (default 1)")
    parser.add_argument("--implicit-dt", type=float, default=None, metavar="S",
                        help="with --integrator implicit: its step in seconds (default 1/90)")
    parser.add_argument("--implicit-iterations", type=int, default=None, metavar="N",
                        help="with --integrator implicit: its iterations a step (default 10)")
    parser.add_argument("--skips-off", nargs="+", default=None, metavar="SKIP",
                        help="the walks' collider skips switched off, by name (the "
                        "collider's Skips: a wrong name is refused with the list; default: "
                        "none)")


def walk_settings(args) -> dict:
    """The :func:`add_walk_settings` flags given, as :class:`~catwalk.simulate.Settings`
    fields, checked against the ``balanced`` preset (:class:`~catwalk.errors.InputError`)."""
    out = {k: v for k, v in (("plane_band", args.plane_band),
                             ("min_collisions", args.min_collisions),
                             ("max_move", args.max_move),
                             ("integrator", args.integrator), ("xpbd_dt", args.xpbd_dt),
                             ("xpbd_iterations", args.xpbd_iterations),
                             ("implicit_dt", args.implicit_dt),
                             ("implicit_iterations", args.implicit_iterations),
                             ("skips_off", args.skips_off and tuple(args.skips_off)))
           if v is not None}
    preset("balanced").with_(**out)
    return out


def check_walk_seconds(seconds: float) -> None:
    """Refuse a walk length outside 0.5–10 s (:class:`~catwalk.errors.InputError`)."""
    if not 0.5 <= seconds <= 10:
        raise InputError(f"--seconds must be within 0.5–10, got {seconds}")


def walk_errors(s: dict) -> dict:
    """A measured walk's errors as the benchmarks report them, from its statistics
    (``Walked.stats``): max / p99 penetration (mm, of the shown frames), max / p99 strain, and
    the spring-frames over τ + 2 % with those of them across the body."""
    return {"max_penetration_mm": round(s["max_penetration_mm"], 2),
            "p99_penetration_mm": round(s["p99_penetration_mm"], 2),
            "max_strain": round(s["max_strain"], 4), "p99_strain": round(s["p99_strain"], 4),
            "springs_over_limit": s.get("springs_over_limit"),
            "over_limit_crossing_body": s.get("over_limit_crossing_body")}
