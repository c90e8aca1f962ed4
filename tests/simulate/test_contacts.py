"""Contacts from their sources: the floor lifts and slows what sinks into it; the state keeps
the sources' held points and planes in priority order (the body's plane before the floor's)."""

import numpy as np

from catwalk.cloth.model import PLANE_COLUMNS, State
from catwalk.simulate.contacts import Contacts, Floor, keep


def _state(x, v):
    n = len(x)
    return State(positions=np.array(x, float), velocities=np.array(v, float),
                 pinned=np.zeros(n, bool), held=np.zeros(n, bool), time=0.25)


def test_the_floor_lifts_stops_and_slows_what_sinks_into_it():
    st = _state([[0, 0.001, 0], [0, 0.5, 0], [0, -0.01, 0]],
                [[1.0, -2.0, 0], [1.0, -2.0, 0], [0.1, -1.0, 0]])
    c = Floor(thickness=0.004, friction=0.3).resolve(st)
    assert c.held.tolist() == [True, False, True]
    assert np.allclose(st.positions[[0, 2], 1], 0.004) and st.positions[1, 1] == 0.5
    assert np.all(st.velocities[[0, 2], 1] == 0.0) and st.velocities[1, 1] == -2.0
    # Coulomb: the sliding speed loses μ·|Δv_y| (1 → 0.4), and stops at zero (0.1 → 0)
    assert np.isclose(st.velocities[0, 0], 0.4) and st.velocities[2, 0] == 0.0
    assert st.velocities[1, 0] == 1.0
    assert c.planes.tolist() == [0.0, 1.0, 0.0, 0.004, 0.0, 0.0, 0.0, 0.3]


def test_the_state_keeps_the_sources_in_priority_order():
    st = _state(np.zeros((3, 3)), np.zeros((3, 3)))
    body_planes = np.zeros((3, PLANE_COLUMNS))
    body_planes[0] = (1, 0, 0, 0.2, 0.5, 0, 0, 0.4)
    body = Contacts(np.array([True, False, False]), body_planes)
    floor = Contacts(np.array([True, True, False]), np.array([0, 1, 0, 0.004, 0, 0, 0, 0.3]))
    keep(st, body, floor)
    assert st.held.tolist() == [True, True, False]
    assert st.planes[0].tolist() == body_planes[0].tolist()     # the body's, not the floor's
    assert st.planes[1].tolist() == [0, 1, 0, 0.004, 0, 0, 0, 0.3]
    assert not st.planes[2, :3].any() and st.plane_time == 0.25
    assert not body.held[1]                                     # the sources are not changed
    keep(st, Contacts(body.held, None), floor)                  # a source without planes
    assert st.planes is None and st.held.tolist() == [True, True, False]
