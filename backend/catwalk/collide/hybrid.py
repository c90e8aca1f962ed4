"""Hybrid mode (the paper's collider, §4): torso+head in depth maps, each limb in its own
hierarchy; the points the maps cannot answer, and those a limb held, go to object space."""

from __future__ import annotations

import numpy as np

from catwalk.body.types import (
    PART_LEFT_ARM,
    PART_LEFT_LEG,
    PART_RIGHT_ARM,
    PART_RIGHT_LEG,
    PART_TORSO,
)
from catwalk.collide.collider import NO_MASK, Collider, Substep, to_look_again
from catwalk.collide.image_pass import ImagePass
from catwalk.collide.object_pass import ObjectPass

LIMBS = (PART_LEFT_ARM, PART_RIGHT_ARM, PART_LEFT_LEG, PART_RIGHT_LEG)


class HybridCollider(Collider):
    """Torso+head in the depth maps (:class:`~catwalk.collide.image_pass.ImagePass`), the
    limbs in hierarchies (:class:`~catwalk.collide.object_pass.ObjectPass`).

    ``edge_fallback``: the points the torso's maps cannot answer (at their silhouette, where
    the surface turns away from both cameras) go to object space against every part, the
    torso's own hierarchy included (built for them alone); False: the paper's hybrid.
    ``limb_fallback`` (with the edge fallback): so do the points a limb held at the last
    resolve (a point pinched between an arm and the torso, answered by the maps and by the
    arm's hierarchy in turn, is pushed back and forth)."""

    mode = "hybrid"
    MODE_OPTIONS = ("edge_fallback", "limb_fallback")

    def __init__(self, body_faces, parts, *, edge_fallback=True, limb_fallback=True,
                 **options):
        super().__init__(body_faces, parts, **options)
        self.edge_fallback = bool(edge_fallback and self._present[PART_TORSO])
        self.limb_fallback = bool(self.edge_fallback and limb_fallback)
        self._use_parts(in_maps=(PART_TORSO,), in_tree=LIMBS, mapped_in_tree=self.edge_fallback)
        map_faces = self._mapped_faces()
        if len(map_faces):
            self._image_pass = ImagePass(self.faces, map_faces, self._map_size,
                                         self._map_margin)
        if self.hier_parts.any():
            self._object_pass = ObjectPass(self.faces, self.face_part, self.hier_parts,
                                           self.n_vertices, self.leaf_size)
        self._pts = self._edge_pts = None  # the object pass's PointState: limbs, edge fallback
        self._edge = np.zeros(0, bool)   # the points the image pass leaves to object space
        self._rest = np.zeros(0, bool)   # and the others
        self._near_limb = np.zeros(0, bool)  # the points a limb held at the last resolve
        self._held_edge = self._held_limbs = np.zeros(0, bool)   # each object pass's held

    def _resolve(self, s: Substep, held) -> None:
        reach = None if self._object_pass is None else self._object_pass.reach(self, s.lo, s.hi)
        use_edge = self.edge_fallback and reach is not None and bool(reach[PART_TORSO])
        flagged = False
        start = s.pos.copy() if s.final else None   # the frame kept: what the pushes moved
        if self._image_pass is not None:
            edge = self._edge_marks(len(s.pos)) if use_edge else NO_MASK
            self._image_pass.run(self, s, held, edge)
            flagged = use_edge and bool(self._edge.any())
        if self._object_pass is not None:
            self._object_space(s, held, reach, flagged, track=use_edge and self.limb_fallback)
            if s.final:
                self._look_again(s, held, reach, flagged, use_edge and self.limb_fallback,
                                 start)

    def _edge_marks(self, n: int) -> np.ndarray:
        """The edge marks before the image pass: none, or (limb fallback) the points a limb
        held at the last resolve."""
        if len(self._edge) != n:
            self._edge = np.zeros(n, bool)
            self._rest = np.ones(n, bool)
        elif self.limb_fallback and len(self._near_limb) == n:
            # points a limb held at the last resolve: object space against every part (a
            # point pinched between an arm and the torso answered by the maps and by the
            # arm's hierarchy in turn is pushed back and forth)
            self._edge[:] = self._near_limb
        else:
            self._edge[:] = False
        return self._edge

    def _object_space(self, s: Substep, held, reach, flagged: bool, track: bool) -> None:
        """The object passes: the points the maps left (``flagged``) against every part in
        ``reach``, the others against the limbs; ``track``: note the points a limb held."""
        n = len(s.pos)
        if track:
            if len(self._held_edge) != n:
                self._held_edge, self._held_limbs = np.zeros((2, n), bool)
            he, hl = self._held_edge, self._held_limbs
            he[:] = False
            hl[:] = False
        else:
            he = hl = held
        op = self._object_pass
        if flagged:
            # the points the maps left alone: object space, every part in reach (the
            # nearest surface of all, as in object mode); the others: the limbs
            np.logical_not(self._edge, out=self._rest)
            self._edge_pts = op.run(self, s, he, reach, self._edge_pts, self._edge)
        if self.tree_parts.any():
            # (without the torso, the pass answers only points near the limbs: ObjectPass.run)
            self._pts = op.run(self, s, hl, reach & self.tree_parts, self._pts,
                               self._rest if flagged else NO_MASK)
        if track and hl.any():
            # a point a limb just pushed may now be inside the torso, which that pass does not
            # see (the maps looked before it): such points again in object space against every
            # part, where the torso facing the limb is seen — the pinch (kernels.
            # second_surface.second_surface) puts the point between the two
            again = hl & ~self._edge if flagged else hl.copy()
            if again.any():
                self._edge_pts = op.run(self, s, he, reach, self._edge_pts, again)
        if track:
            held |= he
            held |= hl
            self._near_limb = self._held_by_limb(he, hl, flagged)

    def _held_by_limb(self, he, hl, flagged: bool) -> np.ndarray:
        """The points a limb held: by the limbs' pass (``hl``), or by a limb's triangle in
        the all-parts pass (``he``)."""
        near = hl.copy()
        if flagged and self._edge_pts is not None:
            near |= he & self._on_limb(self._edge_pts.cache_tri)
        return near

    def _look_again(self, s: Substep, held, reach, flagged: bool, track: bool, start) -> None:
        """The frame kept (``s.final``): the points the object passes pushed farther than
        ``RECHECK_MOVE`` (:mod:`~catwalk.collide.collider`) since ``start`` (one pushed out
        along a triangle may have gone behind another of the same part where the skinned
        mesh folds, under the arm), and those a limb holds (a kept triangle is not checked
        against its own part's others: a hand turning over a point held against a finger),
        once more against every part in ``reach``, each searched afresh
        (``ObjectPass.run(recheck=True)``)."""
        op = self._object_pass
        if track:
            he, hl = self._held_edge, self._held_limbs
            again = to_look_again(he | hl, s.pos, start, self._near_limb)
            if again.any():
                self._edge_pts = op.run(self, s, he, reach, self._edge_pts, again,
                                        recheck=True)
                held |= he
        elif self.tree_parts.any():
            # the limbs' pass alone saw the points: every point it holds is a limb's
            again = held & self._rest if flagged else held.copy()
            if again.any():
                self._pts = op.run(self, s, held, reach & self.tree_parts, self._pts, again,
                                   recheck=True)
