"""Object mode: every part in its own hierarchy."""

from __future__ import annotations

from catwalk.collide.collider import N_PARTS, NO_MASK, Collider, Substep, to_look_again
from catwalk.collide.object_pass import ObjectPass


class ObjectCollider(Collider):
    """Every part with faces in its own hierarchy
    (:class:`~catwalk.collide.object_pass.ObjectPass`); no depth maps."""

    mode = "object"

    def __init__(self, body_faces, parts, **options):
        super().__init__(body_faces, parts, **options)
        self._use_parts(in_maps=(), in_tree=range(N_PARTS))
        self._object_pass = ObjectPass(self.faces, self.face_part, self.hier_parts,
                                       self.n_vertices, self.leaf_size)
        self._pts = None   # the object pass's per-point state (object_pass.PointState)

    def _resolve(self, s: Substep, held) -> None:
        reach = self._object_pass.reach(self, s.lo, s.hi)
        start = s.pos.copy() if s.final else None   # the frame kept: what the pass moved
        self._pts = self._object_pass.run(self, s, held, reach & self.tree_parts, self._pts,
                                          NO_MASK)
        if s.final and held.any():
            # the frame kept: the points pushed farther than RECHECK_MOVE, and those a limb
            # holds, once more, each searched afresh (as hybrid's HybridCollider._look_again)
            again = to_look_again(held, s.pos, start, self._on_limb(self._pts.cache_tri))
            if again.any():
                self._pts = self._object_pass.run(self, s, held, reach & self.tree_parts,
                                                  self._pts, again, recheck=True)
