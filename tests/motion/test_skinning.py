import numpy as np

from catwalk.body.skinning import (
    body_frames,
    joint_world_matrices,
    skin,
    skinning_matrices,
)
from catwalk.body.types import Motion
from catwalk.geometry.quat import axis_angle, make_continuous, mat_to_quat, quat_to_mat


def reference_skin(rest, joints, weights, mats):
    """Plain numpy linear blend skinning: Σ_k w_k · M_{j_k} · [v, 1]."""
    vh = np.concatenate([rest, np.ones((len(rest), 1))], axis=1)
    out = np.zeros((len(rest), 3))
    for k in range(joints.shape[1]):
        m = mats[joints[:, k].astype(np.int64)]                  # (N, 4, 4)
        out += weights[:, k, None] * np.einsum("nij,nj->ni", m, vh)[:, :3]
    return out


def random_rigid(rng, n):
    q = rng.normal(size=(n, 4))
    m = np.zeros((n, 4, 4))
    m[:, :3, :3] = quat_to_mat(q)
    m[:, :3, 3] = rng.normal(scale=0.5, size=(n, 3))
    m[:, 3, 3] = 1
    return m


def test_kernel_matches_reference():
    rng = np.random.default_rng(1)
    n, j = 5000, 53
    rest = rng.normal(size=(n, 3))
    joints = rng.integers(0, j, size=(n, 4)).astype(np.uint16)
    w = rng.random((n, 4))
    w[:, 3] = 0.0                       # an unused slot, as in sparse rows
    w /= w.sum(axis=1, keepdims=True)
    mats = random_rigid(rng, j)
    got = skin(rest, joints, w.astype(np.float32), mats)
    ref = reference_skin(rest, joints, w, mats)
    assert got.dtype == np.float32
    assert np.abs(got - ref).max() < 1e-4
    # batched frames
    mats_f = np.stack([mats, random_rigid(rng, j)])
    got_f = skin(rest, joints, w.astype(np.float32), mats_f)
    assert got_f.shape == (2, n, 3)
    assert np.abs(got_f[1] - reference_skin(rest, joints, w, mats_f[1])).max() < 1e-4


def test_body_rest_pose_is_identity(neutral_body):
    b = neutral_body
    sk = b.skeleton
    q = mat_to_quat(sk.rest_local[:, :3, :3])
    world = joint_world_matrices(sk, q, sk.rest_local[:, :3, 3])
    assert np.allclose(world, sk.rest_world, atol=1e-9)
    v = skin(b.vertices, b.skin_joints, b.skin_weights, skinning_matrices(sk, world))
    assert np.abs(v - b.vertices).max() < 1e-5
    ref = reference_skin(b.vertices, b.skin_joints, b.skin_weights.astype(np.float64),
                         skinning_matrices(sk, world))
    assert np.abs(v - ref).max() < 1e-5


def test_body_frames_velocity_of_a_translation(neutral_body):
    b = neutral_body
    sk = b.skeleton
    f, fps, speed = 10, 20.0, 1.5
    q = np.repeat(mat_to_quat(sk.rest_local[:, :3, :3])[None], f, axis=0)
    t = np.repeat(sk.rest_local[None, :, :3, 3], f, axis=0).copy()
    root = int(np.flatnonzero(sk.parents < 0)[0])
    t[:, root, 2] += speed * np.arange(f) / fps
    m = Motion(fps=fps, rotations=q, translations=t, loop=True,
               meta={"loop_offset": [0.0, 0.0, speed * f / fps]})
    verts, vel = body_frames(b, m)
    assert verts.shape == (f, 13380, 3) and vel.shape == verts.shape
    assert verts.dtype == np.float32 and vel.dtype == np.float32
    assert np.allclose(vel[..., 2], speed, atol=1e-3)
    assert np.allclose(vel[..., :2], 0.0, atol=1e-3)


def test_quaternion_helpers():
    rng = np.random.default_rng(2)
    axes = rng.normal(size=(100, 3))
    axes /= np.linalg.norm(axes, axis=1, keepdims=True)
    ang = rng.uniform(-3.1, 3.1, 100)
    m = axis_angle(axes, ang)
    q = mat_to_quat(m)
    assert np.allclose(quat_to_mat(q), m, atol=1e-9)
    track = np.stack([q, -q, q])           # sign flips along time
    c = make_continuous(track)
    assert np.all(np.sum(c[1:] * c[:-1], axis=-1) > 0)


def test_skinner_reuses_its_buffer(neutral_body):
    from catwalk.body.skinning import Skinner

    b = neutral_body
    sk = b.skeleton
    sk_mats = skinning_matrices(sk, sk.rest_world)
    s = Skinner(b.vertices, b.skin_joints, b.skin_weights, len(sk.names))
    out = np.zeros((len(b.vertices), 3), np.float32)
    res = s(sk_mats, out=out)
    assert res is out
    assert np.abs(out - b.vertices).max() < 1e-5


def test_rigid_deviation_is_zero_for_single_bone_skin_and_grows_at_a_bent_joint(neutral_body,
                                                                                 bent_elbow):
    from catwalk.body.skinning import motion_matrices, rigid_deviation

    b = neutral_body
    # walking forward: every bone alike
    m = bent_elbow(b, degrees=0.0, forward=0.05)
    assert rigid_deviation(b, motion_matrices(b, m), body_frames(b, m)[0]).max() < 1e-5
    # the left elbow bent 60° by the last frame: skin blended across it strays from either
    # bone, skin on one bone alone does not
    m = bent_elbow(b, forward=0.05)
    dev = rigid_deviation(b, motion_matrices(b, m), body_frames(b, m)[0])
    one_bone = b.skin_weights.max(axis=1) > 0.999
    assert dev[one_bone].max() < 1e-4
    assert dev[~one_bone].max() > 0.005
