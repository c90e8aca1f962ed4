"""Two answers the nearest triangle alone gets wrong.

1. Parts overlap (a skinned hand resting on a thigh): a point inside the hand can be nearer to
   the thigh's surface, outside it; the closest triangle of all says "outside". A KNOWN
   LIMIT (docs/collide.md): asking each part on its own fixed this case but cost 30–75 % of
   the object pass and moved pinched points elsewhere; the test stays, expected to fail, as
   the specification of the fix.
2. Hybrid: where the torso's surface turns away from both cameras (the crotch's underside is
   drawn in no pixel of the front map), depth differences do not measure the distance; those
   points go to object space against the torso's own hierarchy."""

import numpy as np
import pytest

from catwalk.collide import make_collider
from catwalk.collide.kernels.stats import ST_PINCH
from catwalk.collide.shapes import merge, sphere

T = 0.004


def _knee_and_hand():
    knee_c = np.array([0.0, 1.0, 0.0])
    hand_c = np.array([0.0, 1.0, 0.083])
    vk, fk = sphere(knee_c, 0.06, 96, 48)
    vh, fh = sphere(hand_c, 0.025, 64, 32)
    v, f = merge([(vk, fk), (vh, fh)])
    parts = np.r_[np.full(len(vk), 4, np.int8), np.full(len(vh), 2, np.int8)]
    return v, f, parts, knee_c, hand_c


@pytest.mark.xfail(strict=True, reason="known limit: the closest triangle of all answers "
                   "(docs/collide.md, 'Overlapping parts')")
@pytest.mark.parametrize("mode", ["object", "hybrid"])
def test_a_point_inside_the_hand_but_nearer_the_thigh_leaves_the_hand(mode):
    v, f, parts, knee_c, hand_c = _knee_and_hand()
    c = make_collider(mode, f, parts)
    c.update(v)
    # 6 mm outside the knee (beyond the thickness: the knee does not hold it) and 8 mm inside
    # the hand (whose surface, 8 mm away, is farther than the knee's)
    rng = np.random.default_rng(3)
    d = np.c_[rng.uniform(-0.05, 0.05, (50, 2)), np.ones(50)]
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    pts = knee_c + 0.066 * d
    depth_hand = 0.025 - np.linalg.norm(pts - hand_c, axis=1)
    assert (depth_hand > 0.0062).all()
    assert (np.linalg.norm(pts - knee_c, axis=1) - 0.06 > T + 0.001).all()
    p = pts.copy()
    held = c.resolve(p, np.zeros_like(p), pts.copy())
    assert held.all()
    out_of_hand = np.linalg.norm(p - hand_c, axis=1) - 0.025
    # out of the (tessellated) hand, by about the thickness
    assert out_of_hand.min() > -0.0005, f"{-out_of_hand.min() * 1e3:.2f} mm inside the hand"
    assert np.median(out_of_hand) == pytest.approx(T, abs=0.001)


def _torso_ball():
    centre = np.array([0.0, 1.2, 0.0])
    v, f = sphere(centre, 0.15, 96, 48)
    return v, f, np.zeros(len(v), np.int8), centre


def _near_the_underside(centre, n=300, seed=4):
    """Points 1-3 mm inside the ball where its surface faces down and away from both
    cameras (the normal within 30° of −y: n·z < 0.5)."""
    rng = np.random.default_rng(seed)
    th = np.radians(rng.uniform(0.0, 28.0, n))
    ph = rng.uniform(0.0, 2 * np.pi, n)
    d = np.c_[np.sin(th) * np.cos(ph), -np.cos(th), np.sin(th) * np.sin(ph)]
    return centre + d * (0.15 - rng.uniform(0.001, 0.003, n))[:, None], d


def test_hybrid_answers_where_the_maps_see_the_torso_edge_on_in_object_space():
    v, f, parts, centre = _torso_ball()
    pts, d = _near_the_underside(centre)
    moved = {}
    for mode, fallback in (("hybrid", True), ("hybrid", False), ("object", False)):
        c = make_collider(mode, f, parts, edge_fallback=fallback)
        c.update(v)
        p = pts.copy()
        held = c.resolve(p, np.zeros_like(p), pts.copy())
        assert held.all()
        moved[(mode, fallback)] = p - pts
        if mode == "hybrid":
            assert (c.stats[8] > 0) == fallback  # the points sent to object space
    # with the fallback, the push is object space's: radial, to the surface + thickness
    h = moved[("hybrid", True)]
    assert np.abs(h - moved[("object", False)]).max() < 1e-4
    radial = np.einsum("ij,ij->i", h, d)
    assert (np.linalg.norm(h - radial[:, None] * d, axis=1) < 0.0005).all()
    # ... and ends at the surface plus the thickness (within the tessellation); the maps
    # alone misjudge the distance there (measured: up to 2.7 mm too far out, 1.9 mm sideways)
    gap = {k: np.linalg.norm(pts + m - centre, axis=1) - 0.15 for k, m in moved.items()}
    assert np.abs(gap[("hybrid", True)] - T).max() < 3e-4
    assert np.abs(gap[("hybrid", False)] - T).max() > 1e-3


def test_hybrid_points_a_limb_held_go_to_object_space_at_the_next_resolve():
    """Hybrid: a point an arm held at the last resolve is answered at the next one by the
    object pass against every part (the nearest surface of all, as in object mode), not by the
    torso's maps and then the arm's hierarchy in turn, which push a point pinched between an
    arm and the torso back and forth (a bodice's front armpit blew up in a walk that way)."""
    torso_c = np.array([0.0, 1.2, 0.0])
    arm_c = np.array([0.06, 1.2, 0.185])      # an arm before the chest, sunk 0.5 mm into it
    vt, ft = sphere(torso_c, 0.15, 96, 48)
    va, fa = sphere(arm_c, 0.045, 64, 32)
    v, f = merge([(vt, ft), (va, fa)])
    parts = np.r_[np.zeros(len(vt), np.int8), np.ones(len(va), np.int8)]
    rng = np.random.default_rng(1)
    d = rng.normal(size=(200, 3))
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    pts = arm_c + 0.043 * d                     # 2 mm inside the arm …
    r = np.linalg.norm(pts - torso_c, axis=1)
    pts = pts[(r > 0.151) & (r < 0.17) & (pts[:, 2] > 0.0)]   # … in the crease, before it
    assert len(pts) > 20
    got = {}
    for mode, fallback in (("object", True), ("hybrid", True), ("hybrid", False)):
        c = make_collider(mode, f, parts, limb_fallback=fallback)
        c.update(v)
        p = pts.copy()
        c.resolve(p, np.zeros_like(p), pts.copy(), alpha=1.0)   # the arm holds them
        near = c._near_limb.copy() if mode == "hybrid" else None
        p = pts.copy()
        c.resolve(p, np.zeros_like(p), pts.copy(), alpha=1.0)   # the same input again
        got[mode, fallback] = p, near
    near = got["hybrid", True][1]
    assert near.sum() > 0.9 * len(pts)
    np.testing.assert_allclose(got["hybrid", True][0][near], got["object", True][0][near],
                               atol=1e-9)
    # without it the maps answer first and the arm after: up to 7.8 mm elsewhere
    assert np.abs(got["hybrid", False][0][near] - got["object", True][0][near]).max() > 0.003


def _knee_and_hand_overlapping(overlap):
    """The hand's sphere sunk ``overlap`` metres into the knee's along +z (negative: a gap)."""
    knee_c = np.array([0.0, 1.0, 0.0])
    hand_c = knee_c + np.array([0.0, 0.0, 0.06 + 0.025 - overlap])
    vk, fk = sphere(knee_c, 0.06, 96, 48)
    vh, fh = sphere(hand_c, 0.025, 64, 32)
    v, f = merge([(vk, fk), (vh, fh)])
    parts = np.r_[np.full(len(vk), 4, np.int8), np.full(len(vh), 2, np.int8)]
    return v, f, parts, knee_c, hand_c


def _near_axis(centre, radius, n=40, seed=5):
    rng = np.random.default_rng(seed)
    d = np.c_[rng.uniform(-0.03, 0.03, (n, 2)), np.ones(n)]
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    return centre + radius * d


@pytest.mark.parametrize("mode", ["object", "hybrid"])
def test_cloth_in_a_gap_narrower_than_twice_the_thickness_keeps_half_of_it_from_each(mode):
    v, f, parts, knee_c, hand_c = _knee_and_hand_overlapping(-0.005)  # a 5 mm gap
    pts = _near_axis(knee_c, 0.059)  # 1 mm inside the knee: pushed out to 4 mm from it
    gaps = {}
    for second in (False, True):
        c = make_collider(mode, f, parts, second_surface=second)
        c.update(v)
        p = pts.copy()
        vel = np.tile([0.0, 0.0, -0.5], (len(p), 1))  # moving into the knee
        held = c.resolve(p, vel, pts.copy())
        assert held.all()
        out_knee = np.linalg.norm(p - knee_c, axis=1) - 0.06
        out_hand = np.linalg.norm(p - hand_c, axis=1) - 0.025
        gaps[second] = np.minimum(out_knee, out_hand).min()
        if second:
            assert c.stats[ST_PINCH] == len(pts)  # every one pinched
            # in the middle of the gap: 2.5 mm from each (tessellation: ±0.5 mm)
            assert np.abs(out_knee - out_hand).max() < 0.001
            # its contact plane runs through it, across the gap (normal ≈ the knee–hand
            # axis), not the knee's plane 4 mm out, which would push it back against the hand
            n = c.planes[:, :3]
            np.testing.assert_allclose(np.einsum("ij,ij->i", n, p), c.planes[:, 3], atol=1e-9)
            assert (n[:, 2] > 0.95).all()
            # they were moving into the knee: that motion is gone (the surfaces are still)
            assert (vel[:, 2] >= -1e-12).all()
    assert gaps[False] < 0.0015, "the scene must show the failure it is for (1 mm from the hand)"
    assert gaps[True] > 0.002


def test_overlapping_parts_are_left_to_the_nearest_surface():
    # the hand sunk 4 mm into the knee (a body touching itself, an arm sunk into the torso):
    # no position is outside both; the nearest surface answers alone (measured: putting such
    # points in the middle of the overlap made the armpit walks worse, docs/collide.md)
    v, f, parts, knee_c, hand_c = _knee_and_hand_overlapping(0.004)
    pts = _near_axis(knee_c, 0.059)
    out = []
    for second in (False, True):
        c = make_collider("object", f, parts, second_surface=second)
        c.update(v)
        p = pts.copy()
        c.resolve(p, np.zeros_like(p), pts.copy())
        assert c.stats[ST_PINCH] == 0
        out.append(p)
    np.testing.assert_array_equal(out[0], out[1])


def test_hybrid_a_point_a_limb_pushes_against_the_torso_is_put_between_them():
    """Hybrid: the torso's maps look before the limbs' hierarchies, so a point an arm pushes
    out against the torso (the cloth in an armpit 3 mm wide) was left inside the torso — the
    limbs' pass does not see it (a shirt's armpit in the catalogue walk: 2.4 mm inside). The
    points a limb held are looked at again against every part, where the pinch between the
    two is seen: they end in the gap, as in object space."""
    torso_c = np.array([0.0, 1.2, 0.0])
    arm_c = torso_c + [0.0, 0.0, 0.15 + 0.045 + 0.003]   # a 3 mm gap along +z
    vt, ft = sphere(torso_c, 0.15, 96, 48)
    va, fa = sphere(arm_c, 0.045, 64, 32)
    v, f = merge([(vt, ft), (va, fa)])
    parts = np.r_[np.zeros(len(vt), np.int8), np.ones(len(va), np.int8)]
    rng = np.random.default_rng(6)
    d = np.c_[rng.uniform(-0.03, 0.03, (40, 2)), -np.ones(40)]
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    pts = arm_c + 0.044 * d   # 1 mm inside the arm, on its side facing the torso
    out = {}
    for mode in ("object", "hybrid"):
        c = make_collider(mode, f, parts)
        c.update(v)
        p = pts.copy()
        held = c.resolve(p, np.zeros_like(p), pts.copy(), alpha=1.0)
        assert held.all()
        out[mode] = (np.linalg.norm(p - torso_c, axis=1) - 0.15,
                     np.linalg.norm(p - arm_c, axis=1) - 0.045)
    for mode, (o_torso, o_arm) in out.items():
        # in the gap, about half of it from each (the tessellation: ±0.5 mm)
        assert o_torso.min() > 0.0008 and o_arm.min() > 0.0008, mode
