"""Simulation settings and their presets (``fast``, ``balanced``, ``accurate``)."""

from __future__ import annotations

from dataclasses import asdict, dataclass, replace

from catwalk.cloth.solvers.explicit.solver import INTEGRATORS as _SOLVER_INTEGRATORS
from catwalk.collide import MODES, Skips
from catwalk.collide.collider import MAX_PLANE_BAND
from catwalk.errors import InputError

#: the cloth integrators a walk can take: the explicit solver's, and the implicit solver on a
#: prefactored matrix (:mod:`catwalk.cloth.solvers.implicit`)
INTEGRATORS = (*_SOLVER_INTEGRATORS, "implicit")


def _in_range(name: str, value, lo, hi, span: str | None = None, *, whole: bool = False):
    """Refuse a setting that is not a number (``whole``: a whole number) within lo–hi
    (:class:`~catwalk.errors.InputError` naming it; ``span``: how the range reads)."""
    kinds = int if whole else (int, float)
    if isinstance(value, bool) or not isinstance(value, kinds) or not lo <= value <= hi:
        what = "a whole number within" if whole else "within"
        raise InputError(f"setting {name} must be {what} {span or f'{lo}–{hi}'}, got {value!r}")


def _check_skips_off(names) -> None:
    """Refuse ``skips_off`` unless it is a list of the collider's skips' names."""
    known = Skips.names()
    if isinstance(names, str) or not isinstance(names, (tuple, list)) or \
            any(n not in known for n in names):
        raise InputError(f"setting skips_off must be a list of the collider's skips "
                         f"({', '.join(known)}), got {names!r}")


@dataclass(frozen=True)
class Settings:
    """Everything that trades speed for accuracy in a try-on.

    Cloth: ``h`` grid spacing (m), ``method`` strain limit (the paper's ``ordered``),
    ``step_safety`` the share of the cloth's stable time step (eq. 4's bound,
    :class:`~catwalk.cloth.solvers.explicit.solver.Solver`) its steps take — above 1 the explicit
    integration blows up, so it is refused (``catwalk bench stress`` shows the evidence).
    ``integrator``: ``explicit`` (the paper's, the default) or ``xpbd`` (XPBD steps of
    ``xpbd_dt`` seconds with ``xpbd_iterations`` sweeps each, the ordered pass as their final
    clamp: :class:`~catwalk.cloth.solvers.explicit.solver.Solver`; the walk only — dressing stays
    explicit) or ``implicit`` (implicit Euler steps of ``implicit_dt`` seconds,
    ``implicit_iterations`` iterations each, on a matrix factored once per garment:
    :class:`~catwalk.cloth.solvers.implicit.ImplicitSolver`; the walk only; a collision
    response after each step but a frame's last, which the frame's closing response follows;
    the walk's plane band at least ``implicit_plane_band``).
    Collider: ``collider`` mode, ``map_size`` depth-map pixels per side, ``thickness`` (m) the
    cloth keeps from the body, ``friction`` (None: the fabric's), ``max_move`` (m): the body
    moves at most this far between two collision substeps of the walk (sets their number from
    the body's fastest vertex), ``min_collisions``/``max_collisions`` per 30-fps frame,
    ``plane_band`` (m): in the walk, points not held but within this of the body's surface
    get a contact plane at each resolve too, which the solver keeps them behind until the
    next (0, the default: planes for the held points only; docs/tryon.md "How many responses
    a frame" has what 1 cm buys and why it is off),
    ``skips`` the collider's work-saving skips (:class:`~catwalk.collide.collider.Skips`) all
    on, or all off (the reference of ``catwalk bench pareto``); with them on, ``skips_off``
    names those switched off one by one (``Skips``' fields: what each saves and costs is a
    row of ``catwalk bench pareto``), ``threads`` the threads the
    collider's object passes split the cloth's points over (one try-on on a machine
    of its own: its cores; a worker among as many as the cores: 1).
    Dressing: ``sew_collisions`` / ``settle_collisions`` collider resolves per 1/30 s while
    sewing / settling (the body stands still: between two, contact planes hold the points it
    holds; settling cloth moves at cm/s, sewing cloth at up to m/s). Seams pull with angular
    frequency ``sew_omega`` (rad/s, spring k = ω²·m) for at
    most ``sew_seconds`` of simulated time or until every gap is under ``weld_gap`` or the gaps
    stopped shrinking for ``sew_stall_seconds`` (0: never give up early); pairs within
    ``weld_reach`` are then welded, the others keep pulling while gravity settles the garment
    and are welded as they close to ``weld_gap``; a seam still open by more than
    ``max_open_gap`` at the end fails the dressing. Gravity settles the
    garment for at most ``settle_seconds`` until the points' RMS speed is under
    ``settle_speed`` (m/s). ``blend_seconds``: the body's move from its rest pose into the
    walk's first pose before recording starts.
    """

    name: str = "balanced"
    h: float = 0.015
    method: str = "ordered"
    step_safety: float = 0.9
    integrator: str = "explicit"
    xpbd_dt: float = 1.0 / 300.0
    xpbd_iterations: int = 1
    implicit_dt: float = 1.0 / 90.0
    implicit_iterations: int = 10
    implicit_plane_band: float = 0.01
    collider: str = "hybrid"
    map_size: int = 256
    skips: bool = True
    skips_off: tuple[str, ...] = ()
    threads: int = 1
    thickness: float = 0.004
    friction: float | None = None
    max_move: float = 0.01
    min_collisions: int = 10
    plane_band: float = 0.0
    max_collisions: int = 60
    sew_collisions: int = 10
    settle_collisions: int = 5
    sew_omega: float = 500.0
    sew_seconds: float = 2.0
    sew_stall_seconds: float = 0.3
    sew_free_seconds: float = 0.0
    weld_gap: float = 0.002
    weld_reach: float = 0.01
    max_open_gap: float = 0.03
    settle_seconds: float = 2.0
    settle_speed: float = 0.02
    blend_seconds: float = 0.5

    def check(self) -> Settings:
        if self.collider not in MODES:
            raise InputError(f"collider must be one of {', '.join(MODES)}, got {self.collider!r}")
        if self.integrator not in INTEGRATORS:
            raise InputError(f"setting integrator must be one of {', '.join(INTEGRATORS)}, got "
                             f"{self.integrator!r}")
        _in_range("xpbd_iterations", self.xpbd_iterations, 1, 100, whole=True)
        _in_range("implicit_iterations", self.implicit_iterations, 1, 100, whole=True)
        _in_range("implicit_dt", self.implicit_dt, 1e-4, 1.0 / 30.0, "1e-04–0.0333 s")
        _in_range("xpbd_dt", self.xpbd_dt, 1e-5, 1.0 / 30.0, "1e-05–0.0333 s (at least one step "
                  "a 30-fps frame)")
        for key in ("h", "thickness", "max_move", "sew_omega", "sew_seconds", "weld_gap",
                    "weld_reach",
                    "max_open_gap", "settle_speed"):
            v = getattr(self, key)
            if not (isinstance(v, (int, float)) and v > 0):
                raise InputError(f"setting {key} must be a positive number, got {v!r}")
        if not isinstance(self.skips, bool):
            raise InputError(f"setting skips must be true or false, got {self.skips!r}")
        _check_skips_off(self.skips_off)
        object.__setattr__(self, "skips_off", tuple(self.skips_off))   # (a JSON list given)
        _in_range("step_safety", self.step_safety, 0.05, 1.0, "0.05–1 (the share of the cloth's "
                  "stable time step its steps take; beyond 1 the explicit integration is "
                  "unstable and blows up)")
        _in_range("threads", self.threads, 1, 64, whole=True)
        if not (0.004 <= self.h <= 0.1):
            raise InputError(f"grid spacing h must be within 0.004–0.1 m, got {self.h}")
        if self.min_collisions < 1 or self.max_collisions < self.min_collisions:
            raise InputError("need 1 <= min_collisions <= max_collisions")
        if self.sew_collisions < 1 or self.settle_collisions < 1:
            raise InputError("sew_collisions and settle_collisions must be >= 1")
        _in_range("plane_band", self.plane_band, 0.0, MAX_PLANE_BAND, f"0–{MAX_PLANE_BAND} m")
        _in_range("implicit_plane_band", self.implicit_plane_band, 0.0, MAX_PLANE_BAND,
                  f"0–{MAX_PLANE_BAND} m")
        if self.settle_seconds < 0 or self.blend_seconds < 0:
            raise InputError("settle_seconds and blend_seconds must be >= 0")
        return self

    def collider_options(self, walking: bool = False) -> dict:
        """The keyword arguments of :func:`~catwalk.collide.make_collider` these settings
        fix (friction is the caller's: the fabric's, or none while sewing); ``walking``: the
        walk's collider (with ``plane_band``)."""
        return {"map_size": (self.map_size, self.map_size), "thickness": self.thickness,
                "skips": Skips(**dict.fromkeys(self.skips_off, False)) if self.skips
                else Skips.off(), "threads": self.threads,
                "plane_band": self.walk_plane_band() if walking else 0.0}

    def walk_plane_band(self) -> float:
        """The walk's plane band: ``plane_band``, at least ``implicit_plane_band`` with the
        implicit integrator (its three responses a frame need it: docs/cloth.md)."""
        if self.integrator == "implicit":
            return max(self.plane_band, self.implicit_plane_band)
        return self.plane_band

    def with_(self, **changes) -> Settings:
        """A copy with some settings changed (None values are ignored)."""
        return replace(self, **{k: v for k, v in changes.items() if v is not None}).check()

    def as_dict(self) -> dict:
        return asdict(self)


PRESETS: dict[str, Settings] = {
    "fast": Settings(name="fast", h=0.025, map_size=128, max_move=0.015, min_collisions=6,
                     sew_collisions=10,
                     sew_seconds=1.5, settle_seconds=1.5, blend_seconds=0.4),
    "balanced": Settings(),
    # the walk as balanced's at a finer grid: 4× the resolves and a 3 mm thickness cost 36 %
    # more a frame and bought nothing measurable (catwalk bench pareto, docs/accuracy.md)
    "accurate": Settings(name="accurate", h=0.01, map_size=384,
                         sew_collisions=40, settle_collisions=20,
                         sew_seconds=3.0, settle_seconds=3.0, settle_speed=0.015),
}


def preset(name: str) -> Settings:
    if name not in PRESETS:
        raise InputError(f"unknown preset {name!r} (choose from {', '.join(PRESETS)})")
    return PRESETS[name]
