"""One measurement in progress (:class:`Measurement`): the body, its slicer along the height and
the coarse horizontal sections every stage starts from, and what each stage finds — the
stages, in the order :func:`catwalk.body.measure.measure_body` runs them: :mod:`.torso`
(structure, crotch, armpits), :mod:`.girths` (girths, neck), :mod:`.shoulders`,
:mod:`.limbs` (arms, legs)."""

from __future__ import annotations

import numpy as np

from catwalk.body.measure.slicing import Slicer
from catwalk.body.measure.topology import Topology
from catwalk.errors import InputError


class Measurement:
    """The body ``V`` (its hole fans' centres included) over ``topo``: its height (``ymin``,
    ``ymax``, ``H``), the slicer along the height ``hs`` and the :attr:`K` coarse horizontal
    sections ``sec`` at ``levels`` (``dy`` apart).

    The stages add, in order: ``torso`` (the torso's loop per coarse level), ``top_k``,
    ``crotch_k``, ``armpit_k`` (:func:`~.torso.structure`); ``crotch_y``, ``crotch_pt``
    (:func:`~.torso.crotch`); ``armpit_pt``, ``armpit_y`` (:func:`~.torso.armpits`);
    ``bust_y`` (:func:`~.girths.girths`); ``neck_y``, ``neck_row`` (:func:`~.girths.neck`);
    ``acromion``, ``side_neck`` (:func:`~.shoulders.shoulders`); ``wrist``, ``elbow``,
    ``arm_length``, ``upper_arm`` (:func:`~.limbs.arms`); ``knee``, ``ankle``
    (:func:`~.limbs.legs`). Per side: {1: the body's left (+x), −1: its right}."""

    K = 160  # coarse horizontal levels over the height

    def __init__(self, V: np.ndarray, topo: Topology):
        self.V = V
        self.topo = topo
        y = V[topo.used, 1]
        self.ymin = float(y.min())
        self.ymax = float(y.max())
        self.H = self.ymax - self.ymin
        self.hs = Slicer(topo, V[:, 1], V[:, 0], V[:, 2]).with_bands()
        K = self.K
        self.levels = self.ymin + self.H * (np.arange(K) + 0.5) / K
        self.sec = self.hs.slice(self.levels)
        self.dy = self.H / K


def fail(what: str) -> InputError:
    """The error for a body that cannot be measured (``what`` was not found)."""
    return InputError(
        f"measure: {what}; the body must stand upright in glTF axes (+Y up, facing +Z), "
        "legs apart and arms hanging clear of the torso (A-pose)")
