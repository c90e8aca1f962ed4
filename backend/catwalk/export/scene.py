"""A .glb written by catwalk, evaluated at any time: the skinned body (and, later, garments).

``load_scene(path).meshes_at(t)`` gives ``[(name, vertices, faces, rgb)]`` in world space —
the body skinned from the joint animation stored in the file itself (quaternions interpolated
between the stored frames), so what is checked or rendered is what a viewer plays.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np

from catwalk.body.types import Body, Motion
from catwalk.export.gltf import read_body, read_motion

SKIN_RGB = (0.80, 0.66, 0.58)


def sample_motion(motion: Motion, t: float) -> tuple[np.ndarray, np.ndarray]:
    """(rotations (J,4), translations (J,3)) at time ``t`` (clamped to the clip), normalised
    lerp between the stored frames."""
    n = motion.frames
    f = min(max(t * motion.fps, 0.0), n - 1.0)
    k = int(np.floor(f))
    k1 = min(k + 1, n - 1)
    a = f - k
    q0, q1 = motion.rotations[k], motion.rotations[k1]
    sign = np.where(np.sum(q0 * q1, axis=1, keepdims=True) < 0, -1.0, 1.0)
    q = (1 - a) * q0 + a * sign * q1
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    tr = (1 - a) * motion.translations[k] + a * motion.translations[k1]
    return q, tr


@dataclass
class Scene:
    body: Body
    motion: Motion | None

    @cached_property
    def _inverse_bind(self) -> np.ndarray:
        return self.body.skeleton.inverse_bind   # rest pose: computed once, not per frame

    @property
    def duration(self) -> float:
        return 0.0 if self.motion is None else (self.motion.frames - 1) / self.motion.fps

    def body_vertices_at(self, t: float) -> np.ndarray:
        if self.motion is None or self.body.skeleton is None:
            return self.body.vertices
        from catwalk.motion.skinning import joint_world_matrices, skin

        rot, tr = sample_motion(self.motion, t)
        world = joint_world_matrices(self.body.skeleton, rot, tr)
        mats = world @ self._inverse_bind
        return skin(self.body.vertices, self.body.skin_joints, self.body.skin_weights, mats)

    def meshes_at(self, t: float) -> list[tuple[str, np.ndarray, np.ndarray, tuple]]:
        return [("body", self.body_vertices_at(t), self.body.faces, SKIN_RGB)]


def load_scene(path) -> Scene:
    return Scene(body=read_body(path), motion=read_motion(path))
