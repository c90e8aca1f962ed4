"""Contacts: what a detection returns — the cloth points held at this response and the contact
planes of those points and of the points near the body (within the collider's ``plane_band``)
— from each contact source (the body's collider, the catwalk's floor), merged, and kept in the
cloth :class:`~catwalk.cloth.state.State` until the next response (the solver keeps every
point with a plane on its side in between: docs/cloth.md)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from catwalk.cloth.solvers import Collider
from catwalk.cloth.state import PLANE_COLUMNS, State


class Contacts(NamedTuple):
    """``held`` (P,) bool: the points in contact. ``planes``: the contact planes — (P,
    ``PLANE_COLUMNS``) rows (unit normal, offset c: outside while n·x ≥ c, the surface's
    velocity, the friction coefficient) for the held points and those near the body, a zero
    normal for the others; or one row shared by every held point; or None when the source
    gives none."""

    held: np.ndarray
    planes: np.ndarray | None


def contacts_of(source: Collider, state: State, x0: np.ndarray | None = None,
                **options) -> Contacts:
    """One detection by ``source`` (a :class:`~catwalk.cloth.solvers.Collider`): it moves the
    state's points out and fixes their velocities in place (``x0``: where they were at the
    last response; ``options``: the source's own, e.g. the body collider's ``alpha`` and
    ``final``); the points it holds and its contact planes."""
    held = np.asarray(source.resolve(state.positions, state.velocities, x0, **options),
                      dtype=bool)
    planes = getattr(source, "planes", None)
    if planes is not None and planes.shape not in ((len(held), PLANE_COLUMNS),
                                                   (PLANE_COLUMNS,)):
        planes = None
    return Contacts(held, planes)


def body_contacts(collider: Collider, state: State, x0: np.ndarray, alpha: float | None,
                  final: bool = False) -> Contacts:
    """The body's collider at ``alpha`` of its frame (``final``: the answer is the frame
    kept)."""
    return contacts_of(collider, state, x0, alpha=alpha, final=final)


@dataclass(frozen=True)
class Floor:
    """The catwalk's floor, y = ``y0`` (the body's soles), as a collider
    (:class:`~catwalk.cloth.solvers.Collider`): points below ``y0 + thickness`` go up to it,
    lose their downward velocity and, by Coulomb friction, ``friction``·|Δv_y| of their
    sliding speed; its contact plane is one row every point it holds shares."""

    thickness: float
    friction: float
    y0: float = 0.0

    @property
    def planes(self) -> np.ndarray:
        return np.array([0.0, 1.0, 0.0, self.y0 + self.thickness, 0.0, 0.0, 0.0,
                         self.friction])

    def resolve(self, positions: np.ndarray, velocities: np.ndarray,
                previous_positions: np.ndarray | None = None) -> np.ndarray:
        x, v = positions, velocities
        low = x[:, 1] < self.y0 + self.thickness
        if not low.any():
            return low
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
        return low


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
