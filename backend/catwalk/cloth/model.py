"""Model (static arrays) and State (positions, velocities) of a cloth.

The Model is built once by :func:`catwalk.cloth.builder.build_cloth` and never changes during a
simulation; the State is what a step advances. All arrays are flat numpy arrays (structure of
arrays) so that the numba kernels in :mod:`catwalk.cloth.solvers.explicit.kernels` can use them
directly.
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


