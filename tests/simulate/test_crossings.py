"""The independent check of springs across the body (`simulate.metrics.segments_crossing`),
and the walk's `springs_over_limit` / `over_limit_crossing_body` that rest on it."""

from types import SimpleNamespace

import numpy as np

import catwalk.simulate.walking as walking
from catwalk.collide.shapes import capsule, sphere
from catwalk.geometry.surface import BodySurface, segments_crossing


def _tally(x, frames=1, tau=0.1, vx=None, body_v=(0.0, 0.0, 0.0)):
    """A walk's tally over ``frames`` frames of springs of rest 0.3 m joining points 0–1, 2–3,
    … of ``x`` (velocities ``vx``, default at rest) beside a sphere of radius 0.1 m at (0, 1,
    0) moving at ``body_v``."""
    v, f = sphere((0.0, 1.0, 0.0), 0.1, 48, 24)
    n = len(x) // 2
    model = SimpleNamespace(n_limited=n, spring_a=np.arange(0, 2 * n, 2),
                            spring_b=np.arange(1, 2 * n, 2), spring_rest=np.full(n, 0.3),
                            mass=np.ones(len(x)), seam_a=np.zeros(0, int))
    state = SimpleNamespace(positions=x, velocities=np.zeros_like(x) if vx is None else vx)
    tally = walking._Tally(BodySurface(f, len(v)), tau=tau)
    for _ in range(frames):
        tally.frame(model, state, x, v, np.tile(body_v, (len(v), 1)), 0)
    return model, tally


def _tallied(x, frames=1, tau=0.1):
    _, tally = _tally(x, frames, tau)
    return tally.over, tally.over_crossing


def test_points_carried_by_the_body_rest_those_sliding_over_it_do_not():
    # four points 5 mm off a sphere walking at 1.2 m/s: two carried along (one within 1 cm/s
    # of it), two sliding 5 cm/s over it or standing still while it walks
    x = np.array([[0.105, 1.0, 0.0], [-0.105, 1.0, 0.0], [0.0, 1.105, 0.0], [0.0, 0.895, 0.0]])
    vx = np.array([[1.2, 0.0, 0.0], [1.2, 0.005, 0.0], [1.2, 0.0, 0.05], [0.0, 0.0, 0.0]])
    model, tally = _tally(x, frames=2, vx=vx, body_v=(1.2, 0.0, 0.0))
    assert tally.stats(model, 2, 0.0)["resting_share"] == 0.5


def test_a_segment_through_a_sphere_meets_it_one_beside_it_does_not():
    v, f = sphere((0.0, 1.0, 0.0), 0.1, 48, 24)
    a = np.array([[-0.2, 1.0, 0.0], [-0.2, 1.2, 0.0], [0.0, 1.0, 0.0], [-0.2, 1.0, 0.0]])
    b = np.array([[0.2, 1.0, 0.0], [0.2, 1.2, 0.0], [0.0, 1.0, 0.3], [-0.15, 1.0, 0.0]])
    # through; above it; from the centre out; ending short of it
    assert segments_crossing(v, f, a, b).tolist() == [True, False, True, False]


def test_a_spring_across_a_flat_hand_is_found():
    # a hand 1.2 cm thick; a 2.4 cm spring with a point 4 mm off each face crosses it, one
    # with both points on the palm's side does not
    v, f = capsule([0.0, 0.6, 0.0], [0.0, 0.8, 0.0], 0.04, n_around=48, n_cap=8, n_body=12,
                   squash=0.15, squash_dir=[1.0, 0.0, 0.0])
    a = np.array([[0.010, 0.7, 0.0], [0.010, 0.7, 0.0]])
    b = np.array([[-0.010, 0.7, 0.005], [0.012, 0.7, 0.018]])
    assert segments_crossing(v, f, a, b).tolist() == [True, False]
    assert segments_crossing(v, f, a[:0], b[:0]).shape == (0,)


def test_the_walk_counts_the_springs_over_the_limit_and_those_across_the_body():
    # across the sphere at 0.4 m, beside it at 0.4 m (both over τ + 2 %), beside it at 0.31 m
    x = np.array([[-0.2, 1.0, 0.001], [0.2, 1.0, 0.001], [-0.2, 1.2, 0.0], [0.2, 1.2, 0.0],
                  [-0.155, 1.3, 0.0], [0.155, 1.3, 0.0]])
    assert _tallied(x, frames=2) == (4, 2)


def test_only_the_longest_springs_over_the_limit_are_tested(monkeypatch):
    # both over the limit; the one beside the sphere is the longer and the only one tested
    x = np.array([[-0.2, 1.0, 0.001], [0.2, 1.0, 0.001], [-0.25, 1.2, 0.0], [0.25, 1.2, 0.0]])
    monkeypatch.setattr(walking, "MAX_CROSSING_TESTS", 1)
    assert _tallied(x) == (2, 0)
