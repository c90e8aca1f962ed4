"""Posing a rest body's arms: rotations at the shoulder, elbow and wrist (each carried to the
joints below it), blended by the body's skin weights (linear blend skinning).

The registration of a scan poses the MakeHuman template's arms to the scan's before it fits
the surface; the test scans of :mod:`catwalk.body.synthetic` pose their true bodies' arms away
from the template's A-pose. Angles: abduction about the body's forward axis (+Z), positive
lowering the arm towards the side; flexion about +X, positive swinging it forwards.
"""

from __future__ import annotations

import numpy as np

from catwalk.body.skinning import skin
from catwalk.body.types import Skeleton
from catwalk.geometry.quat import rot_x, rot_z

ARM_PARAMETERS = ("abduction", "flexion", "elbow", "wrist_flexion", "wrist_abduction")


def arm_rotations(side: str, a) -> dict:
    """Joint name -> rotation (3×3, world axes at rest) for one arm's parameters ``a`` (radians,
    in :data:`ARM_PARAMETERS` order; missing ones are 0): the upper arm abducted about the
    forward axis and flexed forwards; the forearm flexed forwards at the elbow; the hand bent
    forwards and sideways at the wrist."""
    a = list(a) + [0.0] * (len(ARM_PARAMETERS) - len(a))
    sgn = 1.0 if side == "l" else -1.0
    return {f"upperarm_{side}": rot_x(-a[1]) @ rot_z(-sgn * a[0]),
            f"lowerarm_{side}": rot_x(-a[2]),
            f"hand_{side}": rot_x(-a[3]) @ rot_z(-sgn * a[4])}


def joint_matrices(skeleton: Skeleton, rotations: dict, world: np.ndarray | None = None
                   ) -> np.ndarray:
    """Skinning matrices (J, 4, 4) turning each named joint by its rotation about its own
    head at rest, carried down the hierarchy; joints not named follow their parents.
    ``world``: the skeleton's ``rest_world``, when already computed."""
    world = skeleton.rest_world if world is None else world
    mats = np.empty((len(skeleton.names), 4, 4))
    for j, p in enumerate(skeleton.parents):   # parents come before their children
        local = np.eye(4)
        rot = rotations.get(skeleton.names[j])
        if rot is not None:
            c = world[j, :3, 3]
            local[:3, :3] = rot
            local[:3, 3] = c - rot @ c
        mats[j] = local if p < 0 else mats[p] @ local
    return mats


def pose_arms(vertices: np.ndarray, skeleton: Skeleton, skin_joints: np.ndarray,
              skin_weights: np.ndarray, angles: dict, undo: bool = False,
              world: np.ndarray | None = None) -> np.ndarray:
    """The rest vertices with each arm ``side -> parameters`` (see :func:`arm_rotations`)
    posed, float64; ``undo``: posed vertices back to rest (the inverse matrices, blended);
    ``world``: as for :func:`joint_matrices`."""
    rotations = {}
    for side, a in angles.items():
        rotations.update(arm_rotations(side, a))
    mats = joint_matrices(skeleton, rotations, world)
    if undo:
        mats = np.linalg.inv(mats)
    return skin(np.asarray(vertices, dtype=np.float64), skin_joints, skin_weights,
                mats).astype(np.float64)
