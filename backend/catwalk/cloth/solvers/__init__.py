"""The cloth solvers, one folder each in the shape of NVIDIA Newton's ``solvers/<name>/``
(``solver.py``: the class, ``kernels.py``: its numba kernels), behind one interface,
:class:`ClothSolver`, which the dressing and the walk (:mod:`catwalk.simulate.stepping`) call:

- :mod:`~catwalk.cloth.solvers.explicit`: the paper's explicit mass–spring scheme (eq. 2–4)
  with its strain limits; its ``integrator="xpbd"`` runs
  :mod:`~catwalk.cloth.solvers.xpbd`'s sweeps instead of the explicit step;
- :mod:`~catwalk.cloth.solvers.implicit`: implicit Euler on a matrix factored once per garment
  (issue 43; docs/cloth.md).

What every solver shares lives one floor up in :mod:`catwalk.cloth`: the spring law
(:mod:`~catwalk.cloth.springs`), the strain limits (:mod:`~catwalk.cloth.strain_limit`) and
the contact planes (:mod:`~catwalk.cloth.contact_planes`).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Protocol

import numpy as np

from catwalk.cloth.model import ClothModel
from catwalk.cloth.state import State
from catwalk.errors import SimulationError

#: what a step's kernel returns: all well, a non-finite value, a speed over the solver's bound
STATUS_OK, STATUS_NONFINITE, STATUS_EXPLODED = 0, 1, 2


class ClothExplosionError(SimulationError):
    """The simulation produced non-finite values or an absurd speed."""


@dataclass
class StepInfo:
    """What one :meth:`ClothSolver.step` did: its substeps of ``dt`` seconds, the points held
    by the body at its end, and whether the strain limit's processing order was rebuilt."""
    substeps: int
    dt: float
    held: int
    order_rebuilt: bool


class Collider(Protocol):
    """Something that resolves collisions with the cloth: the body's colliders
    (:mod:`catwalk.collide`), the catwalk's floor (:class:`catwalk.simulate.contacts.Floor`),
    the analytic shapes of the tests and the drape (:mod:`catwalk.cloth.analytic`).

    :meth:`resolve` moves the points that crossed into it back out (``previous_positions``:
    where they were at the last response) and fixes their velocities, in place, and returns
    the points it holds (a bool mask, an index array or None). ``planes``: the contact planes of
    its last answer — (P, ``PLANE_COLUMNS``) rows, one row shared by every held point, or None —
    which the state keeps and the solver holds the points behind until the next response."""

    planes: np.ndarray | None

    def resolve(self, positions: np.ndarray, velocities: np.ndarray,
                previous_positions: np.ndarray):
        """Push the points out; the points held."""


class ClothSolver(Protocol):
    """What the dressing and the walk need of a cloth solver."""

    #: the longest step (s) it takes; a longer ``dt`` is split into substeps
    dt_max: float
    #: the strain limit τ its clamp holds
    tau: float

    def step(self, model: ClothModel, state: State, collider: Collider | None = None,
             dt: float | None = None) -> StepInfo:
        """Advance ``state`` by ``dt`` seconds (``collider``: resolved after every substep)."""

    def after_collision(self, model: ClothModel, state: State, dt: float,
                        iterations: int = 4, move_held: bool = False) -> None:
        """Let the cloth round the points a collision response moved follow them."""

    def last_speed(self, state: State) -> float:
        """The largest speed over the last substep, |x − x_prev| / dt."""
