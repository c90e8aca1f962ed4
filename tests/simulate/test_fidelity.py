"""A walk against its reference (catwalk.simulate.fidelity): per-vertex RMS distance and the
hem's swing, on made-up recordings whose answers are known."""

import numpy as np
import pytest

from catwalk.bench.paper import reference_walk_settings
from catwalk.errors import InputError
from catwalk.simulate import preset
from catwalk.simulate.fidelity import hem_points, hem_swing, vertex_rms


def _skirt(frames=60, amplitude=0.05, travel=0.0):
    """A ring of 24 hem points at y = 0.6 swinging ±amplitude along x (a sine over the
    frames) under a waist ring at y = 1.0 that does not swing, both carried ``travel`` m
    along z a frame."""
    t = np.arange(frames)
    ang = np.linspace(0, 2 * np.pi, 24, endpoint=False)
    ring = np.stack([0.2 * np.cos(ang), np.zeros(24), 0.2 * np.sin(ang)], axis=1)
    p = np.zeros((frames, 48, 3))
    p[:, :24] = ring + [0.0, 1.0, 0.0]
    p[:, 24:] = ring + [0.0, 0.6, 0.0]
    p[:, 24:, 0] += amplitude * np.sin(2 * np.pi * t / 20)[:, None]
    p[:, :, 2] += travel * t[:, None]
    return p


def test_the_distance_is_zero_to_itself_and_the_offset_when_moved():
    a = _skirt()
    assert vertex_rms(a, a) == 0.0
    b = a + [0.003, 0.004, 0.0]
    assert vertex_rms(a, b) == pytest.approx(0.005)
    with pytest.raises(InputError, match="different points"):
        vertex_rms(a, a[:, :10])
    with pytest.raises(InputError, match="frames, points, 3"):
        vertex_rms(a[0], a[0])


def test_the_hem_is_the_lowest_band_and_its_swing_the_sine_s_spread():
    a = _skirt(amplitude=0.05)
    hem = hem_points(a)
    assert sorted(hem) == list(range(24, 48))
    # the hem moves ±5 cm, the centroid half as much: ±2.5 cm relative, RMS 2.5/√2 cm
    assert hem_swing(a, hem) == pytest.approx(0.025 / np.sqrt(2), rel=1e-3)
    # walking along the catwalk does not swing it
    assert hem_swing(_skirt(amplitude=0.05, travel=0.02), hem) == pytest.approx(
        hem_swing(a, hem), rel=1e-9)
    assert hem_swing(_skirt(amplitude=0.0), hem) == pytest.approx(0.0, abs=1e-12)
    assert hem_swing(_skirt(amplitude=0.04), hem) / hem_swing(a, hem) == pytest.approx(0.8)


def test_the_reference_walk_responds_after_every_cloth_step():
    s = reference_walk_settings(preset("balanced"), 95)
    assert s.min_collisions == s.max_collisions == 95
    assert (s.collider, s.h, s.method) == ("hybrid", preset("balanced").h, "ordered")


def test_the_reference_walk_is_explicit_whatever_the_default_integrator():
    s = reference_walk_settings(preset("balanced").with_(integrator="xpbd"), 95)
    assert s.integrator == "paper"     # the explicit integrator with the paper's bend springs
    assert s.min_collisions == s.max_collisions == 95
