"""Small standard scenes: a cloth hanging from pins, the paper-size cloth for the benchmark."""

from __future__ import annotations

import math

import numpy as np

from catwalk.cloth import springs
from catwalk.cloth.builder import Panel, build_cloth, rectangle, vertical
from catwalk.cloth.fabrics import get_fabric
from catwalk.cloth.model import ClothModel
from catwalk.cloth.state import State

#: the paper's dress (§6): 3,372 mass points, 18,623 springs
PAPER_POINTS = 3372
PAPER_SPRINGS = 18623


def hanging_cloth(width: float = 0.5, height: float = 0.5, h: float = 0.02, fabric="cotton-jersey",
                  pins: str = "corners", top: float = 1.5) -> tuple[ClothModel, State]:
    """A ``width`` × ``height`` cloth in the XY plane with its top edge at y = ``top``, pinned
    at its two top corners (``pins="corners"``), one top corner (``"corner"``) or along its
    whole top edge (``"edge"``)."""
    model = build_cloth([Panel(rectangle(width, height), name="cloth",
                               placement=vertical((-0.5 * width, top - height, 0.0)))],
                        fabric=fabric, h=h)
    state = State.from_model(model)
    top_pts = np.where(np.abs(model.uv[:, 1] - height) < 1e-9)[0]
    left = top_pts[np.argmin(model.uv[top_pts, 0])]
    right = top_pts[np.argmax(model.uv[top_pts, 0])]
    if pins == "corners":
        state.pinned[[left, right]] = True
    elif pins == "corner":
        state.pinned[left] = True
    elif pins == "edge":
        state.pinned[top_pts] = True
    else:
        raise ValueError(f"pins must be corners, corner or edge, not {pins!r}")
    return model, state


def paper_size_cloth(fabric="cotton-jersey", h: float = 0.015) -> tuple[ClothModel, State]:
    """A cloth pinned at two corners with about the paper's 3,372 points (58 × 58 grid)."""
    side = round(math.sqrt(PAPER_POINTS)) - 1  # intervals per side
    return hanging_cloth(side * h, side * h, h=h, fabric=fabric, pins="corners")


#: the shear angles (degrees) :func:`shear_energy_ratio` is reported at by ``bench cloth``:
#: KES measures G as the slope between 0.5° and 5°
SHEAR_DEGREES = (0.5, 1.0, 2.0, 5.0, 10.0)


#: the grid :func:`grid_energy` deforms (m): 0.3 × 0.2
GRID_SIZE = (0.3, 0.2)


def grid_energy(fabric, deform, h: float = 0.02):
    """(the springs' elastic energy, the fabric) of a :data:`GRID_SIZE` grid of ``fabric`` at
    spacing ``h`` whose rest positions (in the XY plane) ``deform(x0)`` moves (a new array)."""
    fab = get_fabric(fabric)
    m = build_cloth([Panel(rectangle(*GRID_SIZE))], fabric=fab, h=h)
    x = deform(m.rest_positions)
    e = springs.spring_energy(x, m.spring_a, m.spring_b, m.spring_rest, m.spring_k, m.n_limited,
                              fab.compression)
    return float(e), fab


def sheared_grid_energy(fabric, degrees: float, h: float = 0.02) -> tuple[float, float]:
    """(the springs' elastic energy, the continuum's ½·G·γ²·area) of the grid
    (:func:`grid_energy`) in pure shear by ``degrees`` (in its plane): how much of the
    fabric's shear stiffness the grid carries at that angle (docs/cloth.md, "Fabric → spring
    constants")."""
    g = math.radians(degrees)

    def shear(x0):
        x = x0.copy()
        x[:, 0] += 0.5 * g * x0[:, 1]
        x[:, 1] += 0.5 * g * x0[:, 0]
        return x

    e, fab = grid_energy(fabric, shear, h)
    return e, 0.5 * fab.shear * g * g * GRID_SIZE[0] * GRID_SIZE[1]


def shear_energy_ratio(fabric, degrees=SHEAR_DEGREES, h: float = 0.02) -> dict:
    """{degrees: the grid's shear energy / the continuum's} (:func:`sheared_grid_energy`)."""
    return {float(d): round(e / c, 4) for d in degrees
            for e, c in [sheared_grid_energy(fabric, d, h)]}
