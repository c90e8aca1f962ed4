"""The State of a cloth: what a step advances (positions, velocities), the scene's kinematic
facts (pinned and held points) and the contact planes the last collision response left."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from catwalk.cloth.model import ClothModel

#: numbers per contact plane in :attr:`State.planes` (normal 3, offset, body velocity 3, μ)
PLANE_COLUMNS = 8
#: a contact plane's columns: the unit normal (3), the offset, the body's velocity there (3),
#: the friction coefficient
PLANE_NORMAL, PLANE_OFFSET, PLANE_VELOCITY, PLANE_FRICTION = 0, 3, 4, 7


@dataclass
class State:
    """Positions and velocities at one time, plus the scene's kinematic facts.

    ``pinned`` (n,) bool: points that the solver never moves by forces (their velocity is kept,
    so a script may move them); they are high-tension centres of the ordered pass.
    ``held`` (n,) bool: points the collider reported as held by the body on the last step.
    ``failed`` is set when the solver detected NaN/explosion; a failed state is refused.
    ``planes`` (n, 8) or None: the contact planes a collision response left (unit normal n,
    offset c, the body's velocity w there, friction μ; zero normal: none), set at time
    ``plane_time``; until the next response the solver keeps each such point on its side,
    n·x ≥ c + (n·w)·(t − ``plane_time``) (the body's surface seen from the point, offset by
    the cloth's thickness), with Coulomb friction, so it does not sink between two responses.
    """

    positions: np.ndarray
    velocities: np.ndarray
    pinned: np.ndarray
    held: np.ndarray
    time: float = 0.0
    steps: int = 0
    failed: str | None = None
    planes: np.ndarray | None = None
    plane_time: float = 0.0

    @classmethod
    def from_model(cls, model: ClothModel, positions=None) -> State:
        x = np.array(model.rest_positions if positions is None else positions, dtype=np.float64)
        n = model.n_points
        if x.shape != (n, 3):
            raise ValueError(f"positions must be ({n}, 3), got {x.shape}")
        return cls(positions=np.ascontiguousarray(x), velocities=np.zeros((n, 3)),
                   pinned=np.zeros(n, dtype=bool), held=np.zeros(n, dtype=bool))

    def copy(self) -> State:
        return State(self.positions.copy(), self.velocities.copy(), self.pinned.copy(),
                     self.held.copy(), self.time, self.steps, self.failed,
                     None if self.planes is None else self.planes.copy(), self.plane_time)
