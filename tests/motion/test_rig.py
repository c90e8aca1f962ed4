import numpy as np
import pytest

from catwalk.body.rig import (
    BLENDER_TO_GLTF,
    build_rig,
    default_positions_gltf,
    load_rig,
    part_of_bone,
    vec_roll_to_mat3,
)
from catwalk.body.types import PART_LEFT_ARM, PART_LEFT_LEG, PART_RIGHT_ARM, PART_RIGHT_LEG
from catwalk.errors import CatwalkError


def test_joints_match_default_position(neutral_body):
    sk = neutral_body.skeleton
    names, heads, tails = default_positions_gltf()
    assert names == sk.names
    shift = neutral_body.meta["vertical_shift"]
    heads[:, 1] += shift
    got = sk.rest_world[:, :3, 3]
    err = np.linalg.norm(got - heads, axis=1)
    assert err.max() < 0.003, (sk.names[int(err.argmax())], err.max())


def test_game_engine_rig_has_the_bones_walking_needs(neutral_body):
    names = set(neutral_body.skeleton.names)
    for b in ("pelvis", "spine_01", "spine_02", "spine_03", "neck_01", "head", "clavicle_l",
              "clavicle_r", "upperarm_l", "lowerarm_r", "hand_l", "thigh_r", "calf_l", "foot_r",
              "ball_l"):
        assert b in names
    assert len(names) == 53
    sk = neutral_body.skeleton
    assert all(sk.parents[j] < j for j in range(len(names)))


def test_rest_frames_follow_blender_rules(neutral_body):
    sk = neutral_body.skeleton
    rw = sk.rest_world
    # local Y along head → tail, proper orthonormal frames
    d = sk.tails - rw[:, :3, 3]
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    assert np.allclose(np.sum(rw[:, :3, 1] * d, axis=1), 1.0, atol=1e-9)
    r = rw[:, :3, :3]
    assert np.allclose(r @ np.swapaxes(r, 1, 2), np.eye(3), atol=1e-9)
    assert np.allclose(np.linalg.det(r), 1.0)
    # the roll: the frame's X axis equals Blender's, recomputed in Blender space
    data = load_rig()
    j = sk.index("upperarm_l")
    head_b = BLENDER_TO_GLTF.T @ rw[j, :3, 3]
    tail_b = BLENDER_TO_GLTF.T @ sk.tails[j]
    mb = vec_roll_to_mat3(tail_b - head_b, data["upperarm_l"]["roll"])
    assert np.allclose(BLENDER_TO_GLTF @ mb, r[j], atol=1e-9)
    # mirrored bones: left/right frames mirror (x → −x) with the X axis flipped
    jl, jr = sk.index("thigh_l"), sk.index("thigh_r")
    m = np.diag([-1.0, 1.0, 1.0])
    assert np.allclose(m @ r[jl] @ np.diag([-1.0, 1.0, 1.0]), r[jr], atol=1e-6)


def test_vec_roll_to_mat3_cases():
    # general case: column 1 is the direction, no roll → minimal rotation from +Y
    v = np.array([0.3, 0.5, -0.2])
    m = vec_roll_to_mat3(v, 0.0)
    assert np.allclose(m[:, 1], v / np.linalg.norm(v))
    assert np.allclose(m @ m.T, np.eye(3))
    axis = np.cross([0, 1, 0], v)
    assert np.allclose(m @ axis, axis)   # rotation about the axis ⟂ to +Y and v
    # the special case: pointing straight down −Y mirrors X and Y (Blender's convention)
    m = vec_roll_to_mat3(np.array([0.0, -1.0, 0.0]), 0.0)
    assert np.allclose(m, np.diag([-1.0, -1.0, 1.0]))
    # near −Y with a small x/z part: still a proper rotation
    m = vec_roll_to_mat3(np.array([1e-4, -1.0, 0.0]), 0.7)
    assert np.allclose(m @ m.T, np.eye(3), atol=1e-6) and np.isclose(np.linalg.det(m), 1.0)
    # roll turns the frame about its Y axis
    a = vec_roll_to_mat3(v, 0.0)
    b = vec_roll_to_mat3(v, 0.5)
    assert np.isclose(np.dot(a[:, 0], b[:, 0]), np.cos(0.5))


def test_weights_and_parts(neutral_body):
    b = neutral_body
    assert b.skin_joints.shape == (13380, 4) and b.skin_joints.dtype == np.uint16
    assert b.skin_weights.dtype == np.float32
    assert np.allclose(b.skin_weights.sum(axis=1), 1.0, atol=1e-5)
    assert b.parts.shape == (13380,) and b.parts.dtype == np.int8
    counts = np.bincount(b.parts, minlength=5)
    assert counts[PART_LEFT_ARM] == counts[PART_RIGHT_ARM]
    assert abs(int(counts[PART_LEFT_LEG]) - int(counts[PART_RIGHT_LEG])) <= 5
    v = b.vertices
    # left = +X: hands far out on +X are left arm; feet are legs
    assert np.all(b.parts[v[:, 0] > 0.4] == PART_LEFT_ARM)
    assert np.all(b.parts[v[:, 0] < -0.4] == PART_RIGHT_ARM)
    low = v[:, 1] < 0.3
    assert np.all(b.parts[low & (v[:, 0] > 0)] == PART_LEFT_LEG)
    assert np.all(b.parts[low & (v[:, 0] < 0)] == PART_RIGHT_LEG)
    assert np.all(b.parts[v[:, 1] > 1.45] == 0)


def test_armpit_weights_are_diffused(neutral_body):
    from catwalk.body.makehuman import body_triangles
    from catwalk.body.rig import armpit_seam, skin_weights
    from catwalk.geometry.mesh import vertex_adjacency

    b = neutral_body
    names = b.skeleton.names

    def dense(joints, weights):
        d = np.zeros((len(joints), len(names)))
        for k in range(4):
            np.add.at(d, (np.arange(len(joints)), joints[:, k].astype(int)), weights[:, k])
        return d

    raw_joints, raw_weights, raw_parts = skin_weights(names, armpit_smoothing=0)
    raw = dense(raw_joints, raw_weights)
    smooth = dense(b.skin_joints, b.skin_weights)
    moved = np.abs(raw - smooth).max(axis=1) > 1e-6
    tri = body_triangles()
    seam = armpit_seam(tri, raw_parts)
    adj = vertex_adjacency(tri, len(raw))
    near = seam.copy()
    for _ in range(4):
        near |= (adj @ near.astype(float)) > 0
    # only round the armpits (and the shoulders' tops, the same seam), and there: 630 of the
    # 13,380 vertices (docs/motion.md)
    assert near.sum() == 630
    assert moved.any() and not moved[~near].any()
    assert np.allclose(smooth.sum(axis=1), 1.0, atol=1e-5)
    # the upper arm's weight changes by less from one vertex to the next across the seam
    ua = names.index("upperarm_l")
    e = np.argwhere(adj.multiply(near[:, None] & near[None, :]))
    jump_raw = np.abs(raw[e[:, 0], ua] - raw[e[:, 1], ua]).max()
    jump = np.abs(smooth[e[:, 0], ua] - smooth[e[:, 1], ua]).max()
    assert jump < 0.6 * jump_raw, (jump, jump_raw)


def test_part_of_bone():
    assert part_of_bone("upperarm_l") == PART_LEFT_ARM
    assert part_of_bone("middle_03_r") == PART_RIGHT_ARM
    assert part_of_bone("clavicle_l") == 0
    assert part_of_bone("ball_r") == PART_RIGHT_LEG
    assert part_of_bone("spine_02") == 0


def test_joints_follow_the_shape(neutral_body, male_body):
    # a taller body gets a higher pelvis; the rig reads the shaped mesh
    hn = neutral_body.skeleton.rest_world[neutral_body.skeleton.index("head"), 1, 3]
    hm = male_body.skeleton.rest_world[male_body.skeleton.index("head"), 1, 3]
    assert hm > hn + 0.02


def test_bad_input():
    with pytest.raises(CatwalkError):
        build_rig(np.zeros((100, 3)))
    with pytest.raises(CatwalkError):
        load_rig("nonexistent")
