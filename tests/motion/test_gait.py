import numpy as np
import pytest

from catwalk.body.skinning import body_frames, joint_world_matrices
from catwalk.body.types import Body
from catwalk.errors import CatwalkError
from catwalk.geometry.quat import quat_to_mat
from catwalk.motion.checks import foot_sliding, foot_vertices
from catwalk.motion.gait import stride_length, walk_motion


@pytest.fixture(scope="module", params=["catwalk", "normal"])
def walk(request, neutral_body):
    m = walk_motion(neutral_body, 4.0, speed=1.2, style=request.param, fps=30)
    verts, vel = body_frames(neutral_body, m)
    return neutral_body, m, verts, vel


def test_stance_foot_does_not_slide(walk):
    body, m, verts, _ = walk
    slide = foot_sliding(body, m, verts)
    assert len(slide) >= 8
    assert slide.max() < 0.01, slide


def test_feet_on_the_floor(walk):
    body, m, verts, _ = walk
    feet = np.concatenate([foot_vertices(body, "l"), foot_vertices(body, "r")])
    low = verts[:, feet, 1].min(axis=1)
    assert low.min() > -0.006            # never more than a few mm into the floor
    assert low.max() < 0.006             # some foot always touches it
    assert verts[:, :, 1].min() > -0.006


def test_no_joint_flips(walk):
    _, m, _, _ = walk
    q = m.rotations
    assert np.allclose(np.linalg.norm(q, axis=-1), 1.0, atol=1e-9)
    dots = np.sum(q[1:] * q[:-1], axis=-1)
    assert dots.min() > 0.9                # same hemisphere, and no jumps either
    wrap = np.sum(q[0] * q[-1], axis=-1)
    assert wrap.min() > 0.9


def test_loop_closes(walk):
    body, m, verts, vel = walk
    sk = body.skeleton
    offset = np.asarray(m.meta["loop_offset"])
    assert np.isclose(offset[2], m.meta["stride_m"] * m.meta["cycles"])
    assert np.isclose(m.seconds, m.meta["cycle_s"] * m.meta["cycles"])
    # the frame after the last one is the first one, one loop further on
    mc = walk_motion(body, 4.0, speed=1.2, style=m.meta["style"], fps=30, closing_frame=True)
    assert mc.frames == m.frames + 1
    assert np.allclose(mc.rotations[:-1], m.rotations)
    rot = quat_to_mat(mc.rotations)
    assert np.abs(rot[-1] - rot[0]).max() < 1e-6              # joint angles close
    world = joint_world_matrices(sk, mc.rotations, mc.translations)[..., :3, 3]
    assert np.abs(world[-1] - world[0] - offset).max() < 1e-6  # feet too, modulo the strides
    # the wrap (last frame → first frame + offset) is an ordinary step
    wrap = np.linalg.norm(verts[0] + offset - verts[-1], axis=1).max()
    steps = np.linalg.norm(np.diff(verts, axis=0), axis=2).max()
    assert wrap <= 1.05 * steps
    # velocities: central differences, the walking speed on average
    assert abs(float(vel[..., 2].mean()) - 1.2) < 0.02


def test_gait_numbers(walk, neutral_body):
    _, m, _, _ = walk
    meta = m.meta
    assert 100 <= meta["cadence_steps_per_min"] <= 135
    assert np.isclose(meta["stride_m"], 1.2 * meta["cycle_s"])
    expected = stride_length(meta["hip_height_m"], 1.2)
    assert abs(meta["stride_m"] - expected * (0.95 if meta["style"] == "catwalk" else 1)) < 0.15
    if meta["style"] == "catwalk":
        assert meta["step_width_m"] < 0.05
    else:
        assert 0.12 < meta["step_width_m"] < 0.3


def test_arms_come_down_and_swing(walk):
    body, m, _, _ = walk
    sk = body.skeleton
    world = joint_world_matrices(sk, m.rotations, m.translations)[..., :3, 3]
    for side, sgn in (("l", 1), ("r", -1)):
        u = world[:, sk.index(f"lowerarm_{side}")] - world[:, sk.index(f"upperarm_{side}")]
        abduction = np.degrees(np.arctan2(sgn * u[:, 0], -u[:, 1]))
        assert abduction.max() < 25 and abduction.min() > 0       # A-pose was ~42°
        swing = np.degrees(np.arctan2(u[:, 2], -u[:, 1]))
        assert np.ptp(swing) > 12                                    # the arm swings
    # antiphase with the same-side leg: left arm forward while the left thigh is back
    lk = world[:, sk.index("calf_l"), 2] - world[:, sk.index("thigh_l"), 2]
    la = world[:, sk.index("lowerarm_l"), 2] - world[:, sk.index("upperarm_l"), 2]
    assert np.corrcoef(lk, la)[0, 1] < -0.5


def test_the_armpits_do_not_fold(walk):
    """With the arms lowered from the A-pose, no triangle round the armpits is turned inside
    out by the skinning; with MakeHuman's weights as they are, some are (the check can fail)."""
    from dataclasses import replace

    from catwalk.body.rig import skin_weights
    from catwalk.motion.checks import armpit_faces, inverted_triangles

    body, m, verts, _ = walk
    pits = body.faces[armpit_faces(body)]
    assert len(pits) > 500
    assert inverted_triangles(body, m, verts, pits).max() == 0
    joints, weights, parts = skin_weights(body.skeleton.names, armpit_smoothing=0)
    raw = replace(body, skin_joints=joints, skin_weights=weights, parts=parts)
    raw_verts, _ = body_frames(raw, m)
    assert inverted_triangles(raw, m, raw_verts, pits).max() >= 5


def test_speeds_and_bodies(female_body, male_body):
    for body in (female_body, male_body):
        for speed in (0.6, 1.6):
            m = walk_motion(body, 2.0, speed=speed, style="catwalk", fps=30)
            verts, _ = body_frames(body, m)
            assert np.isfinite(verts).all()
            assert foot_sliding(body, m, verts).max() < 0.01
            assert np.sum(m.rotations[1:] * m.rotations[:-1], axis=-1).min() > 0


def test_bad_arguments(neutral_body):
    with pytest.raises(CatwalkError):
        walk_motion(neutral_body, 0.0)
    with pytest.raises(CatwalkError):
        walk_motion(neutral_body, 2.0, speed=3.5)
    with pytest.raises(CatwalkError):
        walk_motion(neutral_body, 2.0, speed=0.1)
    with pytest.raises(CatwalkError):
        walk_motion(neutral_body, 2.0, style="moonwalk")
    with pytest.raises(CatwalkError):
        walk_motion(Body(vertices=neutral_body.vertices, faces=neutral_body.faces), 2.0)
