"""The registration's parts on small scenes: the similarity finds a known scale, turn and move;
arms posed and posed back return to rest; the non-rigid ICP reaches a smoothly bent copy of the
template and leaves a hole to the template."""

import numpy as np
import pytest

from catwalk.body import register as reg
from catwalk.body.limbs import pose_arms
from catwalk.body.rig import rigged_base_body
from catwalk.geometry.quat import rot_y


@pytest.fixture(scope="module")
def base():
    return rigged_base_body(0.0)


def test_similarity_recovers_a_known_transform(base):
    v = base.vertices
    target = reg.Target.of(v, base.faces)
    # as a fit starts: feet on the floor, 2 % too tall, turned 3°, off centre
    moved = 1.02 * v @ rot_y(np.radians(3.0)).T + [0.01, 0.0, -0.015]
    trunk = np.flatnonzero((base.parts != 1) & (base.parts != 2))
    back, s, rot, t = reg.similarity(moved, trunk, target)
    assert abs(s * 1.02 - 1.0) < 2e-3
    assert np.abs(back - v).max() < 0.004
    assert np.allclose(s * moved @ rot.T + t, back)


def test_arms_posed_and_posed_back_are_at_rest(base):
    angles = {"l": np.radians([12.0, 6.0, 20.0, -5.0, 4.0]),
              "r": np.radians([-8.0, 3.0, 10.0, 5.0, -4.0])}
    posed = pose_arms(base.vertices, base.skeleton, base.skin_joints, base.skin_weights, angles)
    arm = (base.parts == 1) | (base.parts == 2)
    assert np.linalg.norm(posed - base.vertices, axis=1)[arm].max() > 0.05   # it moved
    assert np.abs(posed[base.parts == 3] - base.vertices[base.parts == 3]).max() < 1e-5
    back = pose_arms(posed, base.skeleton, base.skin_joints, base.skin_weights, angles,
                     undo=True)
    err = np.linalg.norm(back - base.vertices, axis=1)
    # blended vertices (the shoulders) are not undone exactly by blended inverses: near enough
    assert np.percentile(err, 99) < 1e-3 and err.max() < 0.01


def test_fit_arms_finds_the_scans_arm_pose(base):
    want = {"l": np.radians([9.0, 5.0, 0.0, 0.0, 0.0]), "r": np.radians([-6.0, 2.0, 0, 0, 0])}
    posed = pose_arms(base.vertices, base.skeleton, base.skin_joints, base.skin_weights, want)
    target = reg.Target.of(posed, base.faces)
    got_v, got = reg.fit_arms(base.vertices, base.skeleton, base.skin_joints, base.skin_weights,
                              base.parts, target)
    for side in ("l", "r"):
        assert np.degrees(np.abs(np.asarray(got[side][:2]) - want[side][:2])).max() < 1.0
    assert np.linalg.norm(got_v - posed, axis=1).max() < 0.01


def test_nonrigid_reaches_a_bent_copy_and_fills_a_hole(base):
    v, f = base.vertices, base.faces
    # the truth: a smooth belly 2 cm deep, and a hole in the back the template must fill
    bump = 0.02 * np.exp(-(((v[:, 1] - 1.0) / 0.12) ** 2 + (v[:, 0] / 0.12) ** 2))
    truth = v + bump[:, None] * np.array([0.0, 0.0, 1.0]) * (v[:, 2] > 0)[:, None]
    centre = truth[f].mean(axis=1)
    back = v[np.argmin(np.linalg.norm(v - [0.0, 1.2, -0.3], axis=1))]   # mid-back
    hole = np.linalg.norm(centre - back, axis=1) < 0.04
    target = reg.Target.of(truth, f[~hole])
    out = reg.nonrigid(v, f, target)
    err = np.linalg.norm(out - truth, axis=1)
    assert np.percentile(err, 99) < 0.002, np.percentile(err, 99)
    in_hole = np.unique(f[hole])
    assert err[in_hole].max() < 0.005        # the template filled it where it was
    assert np.linalg.norm(v - truth, axis=1).max() > 0.015   # there was something to reach
