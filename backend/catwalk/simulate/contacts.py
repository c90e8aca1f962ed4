"""Contacts: what a detection returns — the cloth points held at this response and the contact
planes of those points and of the points near the body (within the collider's ``plane_band``)
— from each contact source (the body's collider, the catwalk's floor), merged, and kept in the
cloth :class:`~catwalk.cloth.state.State` until the next response (the solver keeps every
point with a plane on its side in between: docs/cloth.md)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from catwalk.cloth.state import PLANE_COLUMNS, State


class Contacts(NamedTuple):
    """``held`` (P,) bool: the points in contact. ``planes``: the contact planes — (P,
    ``PLANE_COLUMNS``) rows (unit normal, offset c: outside while n·x ≥ c, the surface's
    velocity, the friction coefficient) for the held points and those near the body, a zero
    normal for the others; or one row shared by every held point; or None when the source
    gives none."""

    held: np.ndarray
    planes: np.ndarray | None


def body_contacts(collider, state: State, x0: np.ndarray, alpha: float | None,
                  final: bool = False) -> Contacts:
    """The body's collider at ``alpha`` of its frame: it moves the points out of the body and
    fixes their velocities in place (``x0``: where they were at the last response);
    ``final``: the answer is the frame kept (the collider's ``resolve``)."""
    held = np.asarray(collider.resolve(state.positions, state.velocities, x0, alpha=alpha,
                                       final=final), dtype=bool)
    planes = getattr(collider, "planes", None)
    if planes is None or planes.shape != (len(held), PLANE_COLUMNS):
        planes = None
    return Contacts(held, planes)


@dataclass(frozen=True)
class Floor:
    """The catwalk's floor, y = ``y0`` (the body's soles), as a contact source: points below
    ``y0 + thickness`` go up to it, lose their downward velocity and, by Coulomb friction,
    ``friction``·|Δv_y| of their sliding speed."""

    thickness: float
    friction: float
    y0: float = 0.0

    def resolve(self, state: State) -> Contacts:
        x, v = state.positions, state.velocities
        low = x[:, 1] < self.y0 + self.thickness
        plane = np.array([0.0, 1.0, 0.0, self.y0 + self.thickness, 0.0, 0.0, 0.0,
                          self.friction])
        if not low.any():
            return Contacts(low, plane)
        idx = np.nonzero(low)[0]
        x[idx, 1] = self.y0 + self.thickness
        dv = np.maximum(-v[idx, 1], 0.0)
        v[idx, 1] = np.maximum(v[idx, 1], 0.0)
        slide = np.sqrt(v[idx, 0] ** 2 + v[idx, 2] ** 2)
        keep = np.where(slide > 0,
                        np.maximum(slide - self.friction * dv, 0.0) / np.maximum(slide, 1e-12),
                        0.0)
        v[idx, 0] *= keep
        v[idx, 2] *= keep
        return Contacts(low, plane)


def keep(state: State, *sources: Contacts) -> None:
    """The state takes the contacts of ``sources``, in priority order (the body, then the
    floor): held by any; a point several hold keeps the first one's plane (a point the first
    gives a plane without holding it takes a later source's that holds it); no planes when
    the first source gives none."""
    first = sources[0]
    held = first.held.copy()
    for c in sources[1:]:
        held |= c.held
    state.held = held
    if first.planes is None:
        state.planes = None
        return
    if state.planes is None or state.planes.shape != first.planes.shape:
        state.planes = np.empty_like(first.planes)
    state.planes[:] = first.planes
    taken = first.held.copy()
    for c in sources[1:]:
        if c.planes is not None:
            new = c.held & ~taken
            state.planes[new] = c.planes if c.planes.ndim == 1 else c.planes[new]
        taken |= c.held
    state.plane_time = state.time
