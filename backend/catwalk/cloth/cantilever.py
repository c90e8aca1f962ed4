"""The cantilever bending test (ASTM D1388, option A; Peirce 1930), simulated: a strip 2.5 cm
wide, held flat on a horizontal platform, is pushed out over the platform's edge until its tip
reaches the line through the edge inclined 41.5° below the horizontal; the bending length is
half the overhang then. For a heavy elastic strip clamped at the edge this is the fabric's own
bending length c = (B / w)^(1/3), B its bending rigidity (N·m) along the strip and w = ρ·g its
weight per area (Peirce: l³·cos(θ/2) / (8·tan θ) = c³, which at θ = 41.5° gives l = 2c within
2 %; :func:`peirce_length`).

The strip's grain runs along it: ``direction="warp"`` bends the warp yarns (B = ``bend_warp``),
``"weft"`` the weft yarns. Its points on the platform are held (a clamp at the edge, as the
theory has it: the real test's weight plate). Each overhang is settled from flat with the
explicit solver and extra air drag; the overhang at 41.5° is found by Peirce's estimate from
the tip angle reached, then the secant method on the angle (three to six settles).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from catwalk.cloth.builder import Panel, build_cloth
from catwalk.cloth.fabrics import get_fabric
from catwalk.cloth.solvers.explicit.solver import GRAVITY, Solver
from catwalk.cloth.state import State
from catwalk.errors import InputError

STRIP_WIDTH = 0.025
#: the chord from the platform's edge to the tip at the reading (degrees below horizontal)
ANGLE_DEG = 41.5
PLATFORM_HEIGHT = 0.5
DIRECTIONS = ("warp", "weft")


@dataclass
class CantileverResult:
    fabric: str
    direction: str
    h: float
    bending_length: float      # m: half the overhang at 41.5°
    expected: float            # m: (B / ρg)^(1/3)
    overhang: float            # m
    angle_deg: float           # the tip's angle at that overhang, as simulated
    settles: int
    seconds: float             # simulated, all settles together


def expected_length(fabric, direction: str = "warp") -> float:
    """The fabric's own bending length (B / ρg)^(1/3) (m) along ``direction``."""
    f = get_fabric(fabric)
    b = f.bend_warp if direction == "warp" else f.bend_weft
    return (b / (f.density * abs(GRAVITY[1]))) ** (1.0 / 3.0)


def peirce_length(overhang: float, angle_deg: float) -> float:
    """Peirce's bending length from an overhang and the tip's chord angle:
    c = l·(cos(θ/2) / (8·tan θ))^(1/3)."""
    t = math.radians(angle_deg)
    return overhang * (math.cos(0.5 * t) / (8.0 * math.tan(t))) ** (1.0 / 3.0)


def strip(fabric, overhang: float, h: float, direction: str = "warp", behind: int = 2):
    """The strip's model and state: ``behind`` grid rows on the platform (held) behind the
    edge, ``overhang`` metres beyond it, the pattern's warp (+y) or weft (+x) along world +x,
    flat at the platform's height."""
    back = behind * h
    length = back + overhang
    # (a vertex on each long side at the edge: the outline's points there lie on the edge)
    w = STRIP_WIDTH
    outline = np.array([[0.0, 0.0], [w, 0.0], [w, back], [w, length], [0.0, length],
                        [0.0, back]])
    along, across = 1, 0
    if direction == "weft":
        outline = outline[::-1, ::-1].copy()   # the same strip along the pattern's x
        along, across = 0, 1

    def place(uv):
        return np.column_stack([uv[:, along] - back, np.full(len(uv), PLATFORM_HEIGHT),
                                uv[:, across] - 0.5 * STRIP_WIDTH])

    model = build_cloth([Panel(outline, name="strip", placement=place)], fabric=fabric, h=h)
    state = State.from_model(model)
    x = model.rest_positions[:, 0]
    state.pinned[x <= 1e-9 * h] = True
    return model, state


def tip_angle(model, positions: np.ndarray) -> float:
    """The chord's angle (degrees below horizontal) from the platform's edge to the tip (the
    mean of the strip's far end's points)."""
    x0 = model.rest_positions[:, 0]
    tip = positions[x0 >= x0.max() - 1e-9]
    p = tip.mean(axis=0)
    return math.degrees(math.atan2(PLATFORM_HEIGHT - p[1], max(p[0], 1e-12)))


def settle(fabric, overhang: float, h: float, direction: str, extra_air: float = 30.0,
           max_seconds: float = 4.0, tolerance_deg: float = 0.01) -> tuple[float, float]:
    """The tip angle (degrees) of the strip settled at ``overhang``, and the seconds it took
    (until the angle changes by less than ``tolerance_deg`` over 0.1 s)."""
    model, state = strip(fabric, overhang, h, direction)
    solver = Solver(model, "ordered", extra_air=extra_air)
    chunk = 0.1
    last = tip_angle(model, state.positions)
    while state.time < max_seconds - 1e-9:
        solver.step(model, state, None, chunk)
        a = tip_angle(model, state.positions)
        if state.time > 0.3 and abs(a - last) < tolerance_deg:
            return a, state.time
        last = a
    return last, state.time


def cantilever(fabric, h: float = 0.01, direction: str = "warp", tolerance_deg: float = 0.05,
               max_settles: int = 8) -> CantileverResult:
    """The simulated bending length of ``fabric`` along ``direction`` at grid spacing ``h``
    (module docstring)."""
    if direction not in DIRECTIONS:
        raise InputError(f"direction must be one of {', '.join(DIRECTIONS)}, got {direction!r}")
    if not (isinstance(h, (int, float)) and math.isfinite(h) and 0 < h <= 0.05):
        raise InputError(f"h must be a grid spacing in (0, 0.05] m, got {h!r}")
    f = get_fabric(fabric)
    c0 = expected_length(f, direction)
    tried: list[tuple[float, float]] = []
    seconds = 0.0
    overhang = 2.0 * c0
    for _ in range(max_settles):
        angle, s = settle(f, overhang, h, direction)
        seconds += s
        tried.append((overhang, angle))
        if abs(angle - ANGLE_DEG) < tolerance_deg:
            break
        overhang = _next_overhang(tried)
    best = min(tried, key=lambda t: abs(t[1] - ANGLE_DEG))
    length = 0.5 * _at_angle(tried, best)
    return CantileverResult(f.id, direction, h, length, c0, best[0], best[1], len(tried),
                            seconds)


def _next_overhang(tried: list[tuple[float, float]]) -> float:
    """Peirce's estimate from the last settle, then the secant through the two closest."""
    if len(tried) == 1:
        l, a = tried[0]
        return 2.0 * peirce_length(l, max(min(a, 80.0), 1.0))
    (l1, a1), (l2, a2) = sorted(tried, key=lambda t: abs(t[1] - ANGLE_DEG))[:2]
    if a1 == a2:
        return 0.5 * (l1 + l2) * (1.05 if a1 < ANGLE_DEG else 0.95)
    l_new = l1 + (ANGLE_DEG - a1) * (l2 - l1) / (a2 - a1)
    return float(np.clip(l_new, 0.5 * min(l1, l2), 2.0 * max(l1, l2)))


def _at_angle(tried: list[tuple[float, float]], best: tuple[float, float]) -> float:
    """The overhang at 41.5°: the best settle's, moved along the secant of the two closest
    settles when they bracket the angle."""
    if len(tried) < 2:
        return best[0]
    (l1, a1), (l2, a2) = sorted(tried, key=lambda t: abs(t[1] - ANGLE_DEG))[:2]
    if (a1 - ANGLE_DEG) * (a2 - ANGLE_DEG) <= 0 and a1 != a2:
        return l1 + (ANGLE_DEG - a1) * (l2 - l1) / (a2 - a1)
    return best[0]
