"""Data shared by bodies, motion, colliders and export.

Everything is SI and in glTF axes: metres, +Y up, the body faces +Z, feet on y = 0.

Body parts (per vertex, used by the hybrid collider): 0 torso + head, 1 left arm, 2 right arm,
3 left leg, 4 right leg. "Left" is the body's own left, which is +X in glTF axes (the body
faces +Z).

Quaternions are (x, y, z, w), as glTF stores them.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

PART_TORSO = 0
PART_LEFT_ARM = 1
PART_RIGHT_ARM = 2
PART_LEFT_LEG = 3
PART_RIGHT_LEG = 4
PART_NAMES = ("torso", "left_arm", "right_arm", "left_leg", "right_leg")

#: what :func:`catwalk.body.measure.measure_body` measures that is shown for a body (metres),
#: in this order; ``GIRTHS``: those round the body
MEASUREMENTS = ("height", "bust", "underbust", "waist", "hips", "inseam", "shoulder_width",
                "arm_length", "upper_arm_girth", "neck_girth")
GIRTHS = ("bust", "underbust", "waist", "hips", "neck_girth", "upper_arm_girth")


@dataclass
class Skeleton:
    """A joint hierarchy in its rest pose (parents come before children)."""
    names: list[str]
    parents: np.ndarray          # (J,) int32, -1 for a root
    rest_local: np.ndarray       # (J, 4, 4) float64: joint frame relative to its parent
    tails: np.ndarray | None = None  # (J, 3) bone tail positions in world space (rest), optional

    @property
    def rest_world(self) -> np.ndarray:
        """(J, 4, 4) world matrices of the joints at rest."""
        out = np.empty_like(self.rest_local)
        for j, p in enumerate(self.parents):
            out[j] = self.rest_local[j] if p < 0 else out[p] @ self.rest_local[j]
        return out

    @property
    def inverse_bind(self) -> np.ndarray:
        return np.linalg.inv(self.rest_world)

    def index(self, name: str) -> int:
        return self.names.index(name)


@dataclass
class Body:
    """A body surface, optionally rigged."""
    vertices: np.ndarray                 # (N, 3) float64 rest positions
    faces: np.ndarray                    # (M, 3) int32
    parts: np.ndarray | None = None      # (N,) int8 body part per vertex
    skeleton: Skeleton | None = None
    skin_joints: np.ndarray | None = None   # (N, 4) uint16 joint indices
    skin_weights: np.ndarray | None = None  # (N, 4) float32, rows sum to 1
    landmarks: dict[str, list[float]] = field(default_factory=dict)
    meta: dict = field(default_factory=dict)  # e.g. sex, requested measurements, sliders


@dataclass
class Motion:
    """Joint animation sampled at a fixed rate: full local node transforms per frame."""
    fps: float
    rotations: np.ndarray      # (F, J, 4) float64 local rotation quaternions (x, y, z, w)
    translations: np.ndarray   # (F, J, 3) float64 local translations
    loop: bool = True
    meta: dict = field(default_factory=dict)

    @property
    def frames(self) -> int:
        return int(self.rotations.shape[0])

    @property
    def seconds(self) -> float:
        return self.frames / self.fps
