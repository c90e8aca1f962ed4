"""Model (static arrays) and State (positions, velocities) of a cloth.

The Model is built once by :func:`catwalk.cloth.builder.build_cloth` and never changes during a
simulation; the State is what a step advances. All arrays are flat numpy arrays (structure of
arrays) so that the numba kernels in :mod:`catwalk.cloth.kernels` can use them directly.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from catwalk.cloth.fabrics import Fabric

STRETCH, SHEAR, BEND, SEAM = 0, 1, 2, 3
KIND_NAMES = {STRETCH: "stretch", SHEAR: "shear", BEND: "bend"}


@dataclass
class ClothModel:
    """Static description of a cloth (SI units, glTF axes).

    Points: ``uv`` (n, 2) pattern coordinates in metres (also the texture coordinates),
    ``rest_positions`` (n, 3) the panels placed in 3D, ``mass`` (n,) kg, ``panel`` (n,) the panel
    index of each point, ``boundary`` (n,) True for points on a panel outline.

    Springs, sorted so that the strain-limited ones (stretch, shear) come first — indices
    ``[0, n_limited)``: ``spring_a``/``spring_b`` (int32 end points), ``spring_rest`` (m, rest
    length from the 2D pattern), ``spring_k`` (N/m), ``spring_c`` (N·s/m, damping along the
    spring), ``spring_kind`` (0 stretch, 1 shear, 2 bend).

    ``adj_ptr``/``adj_spring``/``adj_other``: for each point, the strain-limited springs at it
    (CSR), used to compute the processing order of the ordered pass.

    ``triangles`` (t, 3) int32 over the same points, for rendering and collision.

    ``seam_a``/``seam_b``: matched point pairs of the seams (one row per pair of points that the
    garment will sew together); ``seam_id`` the seam each pair belongs to.
    """

    h: float
    fabric: Fabric
    uv: np.ndarray
    rest_positions: np.ndarray
    mass: np.ndarray
    panel: np.ndarray
    boundary: np.ndarray
    spring_a: np.ndarray
    spring_b: np.ndarray
    spring_rest: np.ndarray
    spring_k: np.ndarray
    spring_c: np.ndarray
    spring_kind: np.ndarray
    n_limited: int
    adj_ptr: np.ndarray
    adj_spring: np.ndarray
    adj_other: np.ndarray
    triangles: np.ndarray
    seam_a: np.ndarray = field(default_factory=lambda: np.zeros(0, np.int32))
    seam_b: np.ndarray = field(default_factory=lambda: np.zeros(0, np.int32))
    seam_id: np.ndarray = field(default_factory=lambda: np.zeros(0, np.int32))
    panel_names: list = field(default_factory=list)

    @property
    def n_points(self) -> int:
        return len(self.mass)

    @property
    def n_springs(self) -> int:
        return len(self.spring_a)

    @property
    def tau(self) -> float:
        return self.fabric.tau

    def counts(self) -> dict:
        kinds = np.bincount(self.spring_kind, minlength=3)
        return {"points": self.n_points, "springs": self.n_springs,
                "stretch": int(kinds[0]), "shear": int(kinds[1]), "bend": int(kinds[2]),
                "triangles": len(self.triangles), "seam_pairs": len(self.seam_a)}


#: numbers per contact plane in :attr:`State.planes` (normal 3, offset, body velocity 3, μ)
PLANE_COLUMNS = 8


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
