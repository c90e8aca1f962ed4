"""The independent check of springs across the body (`simulate.metrics.segments_crossing`),
which the walk's `springs_over_limit` / `over_limit_crossing_body` rest on."""

import numpy as np

from catwalk.collide.shapes import capsule, sphere
from catwalk.simulate.metrics import segments_crossing


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
