"""Object space: the parts' hierarchies over a body frame (built from the first pose, refitted
per frame, :mod:`catwalk.collide.bvh`) and the pass that finds each cloth point's closest
triangle in them (:class:`ObjectPass`, over
:func:`catwalk.collide.kernels.object_space.object_pass`), with what it keeps per point between
calls (:class:`PointState`); the method is in :mod:`catwalk.collide`."""

from __future__ import annotations

import numpy as np

from catwalk.collide import bvh as B
from catwalk.collide.bvh import NB_COLUMNS, NB_FRAME, NB_LO0, NB_LO1, VP_COLUMNS
from catwalk.collide.collider import N_PARTS, Substep, cpu_time
from catwalk.collide.kernels.boxes import body_motion, bounds_of
from catwalk.collide.kernels.object_inputs import (
    CLK_BODY,
    CLK_TIME,
    CLK_TRAVEL,
    N_CLOCKS,
    ObjectBody,
    ObjectCloth,
    ObjectConfig,
    ObjectPoints,
    ObjectTime,
)
from catwalk.collide.kernels.object_space import object_pass
from catwalk.collide.kernels.record import REC_COLUMNS, VB_COLUMNS, pack_body
from catwalk.collide.kernels.stats import ST_SKIPPED


class PointState:
    """What the object pass keeps per cloth point between calls (see
    :func:`catwalk.collide.kernels.object_space.object_pass`), for one set of parts."""

    def __init__(self, n: int):
        self.n = n
        self.cache_tri = np.full(n, -1, np.int64)
        self.cache_p = np.zeros((n, 3))
        self.cache_c = np.zeros((n, 3))
        self.clear = np.zeros(n)
        self.clear_rel = np.zeros(n)
        self.rkey = np.full(n, -1, np.int64)
        self.pspeed = np.zeros(n)
        self.pstamp = np.full(n, -1, np.int64)
        self.rec = np.zeros((n, REC_COLUMNS), np.float32)
        self.last = np.zeros((n, 3))
        self.left = np.zeros((n, 3))
        self.pclk = np.full((n, N_CLOCKS), -1.0)   # time < 0: never seen
        self.csw = np.zeros((n, N_PARTS))
        self.crel = np.zeros(n)
        self.cstamp = np.full(n, -1, np.int64)
        self.ct2 = np.full(n, -1, np.int64)
        self.cp2 = np.zeros((n, 3))
        self.cc2 = np.zeros((n, 3))
        self.active_last = np.zeros(N_PARTS, bool)
        self.clear_frame = -1
        # the per-point arrays as the object pass takes them (a plain tuple, as its other
        # groups: see ObjectPass.run)
        self.arrays = tuple(ObjectPoints(
            self.cache_tri, self.cache_p, self.cache_c, self.clear, self.clear_rel, self.rkey,
            self.rec, self.pspeed, self.pstamp, self.last, self.pclk, self.csw, self.crel,
            self.cstamp, self.ct2, self.cp2, self.cc2, self.left))

    def start(self, active, frame: int) -> None:
        """Before a pass over the ``active`` parts in ``frame``: the clearances that no longer
        hold dropped."""
        came = bool((active & ~self.active_last).any())
        if came:
            # a part came into play: no clearance bounds it
            self.clear_rel[:] = 0.0
            self.cstamp[:] = -1
            self.ct2[:] = -1
        if self.clear_frame != frame or came:
            # clearances hold against this frame's swept boxes of the parts then in play
            self.clear[:] = 0.0
            self.clear_frame = frame
        self.active_last = active.copy()


class ObjectPass:
    """The object pass of a collider (``col`` in the methods: the body's frames, the options,
    the counters) over the parts ``parts`` (N_PARTS,) bool: their hierarchies (:attr:`tree`,
    built at the first frame), the body's vertices packed for the kernels and the nodes'
    boxes at both frames (once a frame, for the parts a pass reaches), and the clocks by
    which a point's motion since the pass last saw it is measured."""

    def __init__(self, faces, face_part, parts, n_vertices: int, leaf_size: int):
        self.parts = parts
        self.leaf_size = leaf_size
        self._part_faces = {p: np.nonzero(face_part == p)[0] for p in np.nonzero(parts)[0]}
        self._part_vidx = {p: np.unique(faces[f]) for p, f in self._part_faces.items()}
        self._tree_vidx = np.unique(faces[np.nonzero(parts[face_part])[0]])
        # workspaces for the kernels (they run without numba's runtime, so never allocate)
        self._vb = np.zeros((n_vertices, VB_COLUMNS), np.float32)
        self._vp = np.zeros((n_vertices, VP_COLUMNS), np.float32)
        self._ref = np.zeros(3)      # the body's mean displacement over the frame
        self._body_speed = 0.0       # the farthest a tree vertex moves relative to it
        # clocks at the start of this frame: the moving frame's travel (3), the body's travel
        # relative to it (an upper bound: the sum of the frames' body speeds); with the time
        # (frame + alpha) the object pass measures each point's motion since it last saw it
        # (the clocks' columns: kernels.object_inputs.CLK_TRAVEL …; the time, CLK_TIME, last)
        self._clock0 = np.zeros(CLK_TIME)   # the clocks before the time
        self._clock = np.zeros(N_CLOCKS)
        self._packed_frame = -1
        self._nb = None              # node boxes at the previous and the current frame
        self._box_frame = np.full(N_PARTS, -2)  # the frame whose boxes are nb's current ones
        # the nodes' table the searches read (bvh.NODE_COLUMNS: the swept boxes once a frame,
        # bvh.swept_boxes; the boxes at one time of the frame, bvh.blend_at), the vertices at
        # that time, and the (frame, alpha) each part's are for
        self._nbl = None
        self._vpl = np.zeros((n_vertices, 3))
        self._blend_frame = np.full(N_PARTS, -2)
        self._blend_alpha = np.full(N_PARTS, np.nan)
        self._refit_done = np.zeros(N_PARTS, bool)
        self._reach_key = self._reach_box = self._reach = None
        self.tree = None  # built from the first frame's pose
        self._body = None  # the kernel's body group (its arrays change in place)

    def new_frame(self, col, first: bool) -> None:
        """The body's frame changed (``col._frame`` the new one)."""
        if not first:
            # the previous frame is over (whatever alpha its last resolve had)
            self._clock0[CLK_TRAVEL:CLK_TRAVEL + 3] += self._ref
            self._clock0[CLK_BODY] += self._body_speed
        self._refit_done[:] = False
        if first:
            v = col.v1
            self.tree = B.build(v, col.faces, self._part_faces, self.leaf_size)
            self._lv_start, self._lv = B.leaf_vertices(self.tree, col.faces)
            self._lf = np.ascontiguousarray(col.faces[self.tree.tris], dtype=np.int32)
            self._nb = np.zeros((self.tree.n_nodes, NB_COLUMNS), np.float32)
            self._nbl = np.zeros((self.tree.n_nodes, B.NODE_COLUMNS))
            h = self.tree
            self._body = tuple(ObjectBody(self._vb, self._vp, col.faces, col.face_part,
                                            self._nb, h.links, h.tris, h.root, self._lf,
                                            self._nbl, self._vpl))
        # the frame's motion, for the clocks (packing, later, finds the same values)
        self._body_speed = body_motion(col.v0, col.v1, self._tree_vidx, self._ref)

    def reach(self, col, lo, hi):
        """The parts whose swept box (dilated) reaches the cloth's box [lo, hi] (all of them
        with the ``unreached_parts`` skip off); worked out once a frame for the box grown by
        5 cm, again only when the cloth leaves that."""
        if not col.skips.unreached_parts:
            return self.parts
        if self._reach_key != col._frame or self._reach_box is None or \
                np.any(lo < self._reach_box[0]) or np.any(hi > self._reach_box[1]):
            m = 0.05
            blo, bhi = lo - m, hi + m
            act = self._active(col, blo, bhi)
            self._reach_key = col._frame
            self._reach_box = (blo, bhi)
            self._reach = act
            n_off = int((col.tree_parts & ~act).sum())
            col.timings.parts_skipped += n_off
        return self._reach

    def _active(self, col, lo, hi):
        """Parts in hierarchies whose swept box (dilated) reaches the box [lo, hi]."""
        active = self.parts.copy()
        pad = col.search_radius + col.thickness
        for p in np.nonzero(active)[0]:
            vi = self._part_vidx[p]
            # a cheap bound without refitting: the part's vertices at both frames
            plo = np.full(3, np.inf)
            phi = np.full(3, -np.inf)
            bounds_of(col.v0, vi, plo, phi)
            bounds_of(col.v1, vi, plo, phi)
            plo -= pad
            phi += pad
            if np.any(plo > hi) or np.any(phi < lo):
                active[p] = False
        return active

    def _pack(self, col):
        """The parts' vertices of both frames, packed for the object pass (once a frame)."""
        if self._packed_frame == col._frame:
            return
        col._ensure_normals()
        t = cpu_time()
        self._body_speed = pack_body(col.v0, col.v1, col.n0, col.n1, col.w0, col.w1,
                                       self._tree_vidx, self._vb, self._vp, self._ref)
        self._packed_frame = col._frame
        col.timings.normals += cpu_time() - t

    def _refit(self, col, active):
        """The ``active`` parts' node boxes at both frames (once a frame each)."""
        need = active & ~self._refit_done
        if not need.any():
            return
        self._pack(col)
        t = cpu_time()
        h = self.tree
        nb = self._nb
        for p in np.nonzero(need)[0]:
            a, e = h.root[p], h.end[p]
            if self._box_frame[p] == col._frame - 1:
                # the previous frame's boxes: already known
                nb[a:e, NB_LO0:NB_LO0 + NB_FRAME] = nb[a:e, NB_LO1:NB_LO1 + NB_FRAME]
            else:
                B.refit_frame(self._vp, 0, self._lv_start, self._lv, h.links, nb, a, e)
            B.refit_frame(self._vp, 1, self._lv_start, self._lv, h.links, nb, a, e)
            B.node_speeds(self._vp, self._ref, self._lv_start, self._lv, h.links, nb, a, e)
            B.swept_boxes(nb, self._ref, a, e, self._nbl)
            self._box_frame[p] = col._frame
            self._refit_done[p] = True
            col.timings.parts_refit += 1
        col.timings.refit += cpu_time() - t

    def _blend(self, col, active, alpha: float) -> None:
        """The ``active`` parts' pose at ``alpha`` (node boxes and vertices, bvh.blend_at),
        once for all the searches at that time of the frame."""
        for p in np.nonzero(active)[0]:
            if self._blend_frame[p] == col._frame and self._blend_alpha[p] == alpha:
                continue
            B.blend_at(self._vp, self._nb, self.tree.root[p], self.tree.end[p],
                       self._part_vidx[p], alpha, self._nbl, self._vpl)
            self._blend_frame[p] = col._frame
            self._blend_alpha[p] = alpha

    def run(self, col, s: Substep, held, active, pts: PointState | None, only,
            recheck: bool = False):
        """The pass over the ``active`` parts with the per-point state ``pts`` (made when
        missing or of another size; returned); ``only``: the points to see (empty: all).
        Fixes the points in contact, marks them in ``held``, sets their planes.

        A pass that does not see every part the body has (hybrid's limbs' pass, without the
        torso) answers only points within the search radius (plus their motion) whether or
        not the ``far_points`` skip is on: a triangle of its parts farther away says nothing
        of the point's side — beyond a limb's open rim its tangent plane puts torso points
        "inside".

        ``recheck``: the points seen were pushed earlier in this response (the frame kept
        looks at them again, :class:`~catwalk.collide.collider.Substep` ``final``): each is
        searched afresh (no kept triangle reused); one found outside is left as it is, one
        behind a surface facing the one it was pushed off goes between the two
        (:func:`catwalk.collide.kernels.second_surface.fold`)."""
        n = len(s.pos)
        if not active.any():
            if len(only) == 0:
                col.stats[ST_SKIPPED] += n
            return pts
        self._refit(col, active)
        if pts is None or pts.n != n:
            pts = PointState(n)
        pts.start(active, col._frame)
        self._pack(col)
        t = cpu_time()
        self._blend(col, active, s.alpha)
        col.timings.object_queries += cpu_time() - t
        ck = self._clock
        ck[CLK_TRAVEL:CLK_TRAVEL + 3] = self._clock0[CLK_TRAVEL:CLK_TRAVEL + 3] + \
            s.alpha * self._ref
        ck[CLK_BODY] = self._clock0[CLK_BODY] + s.alpha * self._body_speed
        ck[CLK_TIME] = col._frame + s.alpha
        t = cpu_time()

        # the groups go to the kernel as plain tuples (it names them again inside: numba
        # types a named tuple ≈ 6 µs slower a call, and a walk frame makes 30–240 calls); the
        # body's and the points' are made once (their arrays change in place)
        cloth = tuple(ObjectCloth(s.pos, s.vel, s.prev, held, col.planes))
        now = tuple(ObjectTime(s.alpha, s.alpha_prev, col._frame, self._ref, ck,
                               self._body_speed))
        body = self._body
        cfg = tuple(ObjectConfig(col.thickness, col.friction, col.contact_slack,
                                 col.search_radius, col.max_depth,
                                 col.skips.far_points or bool((col._present & ~active).any()),
                                 col.skips.reuse_closest and not recheck, col.reuse_tol,
                                 col.skips.clearance, col.second_surface, col.plane_band,
                                 recheck))
        arrays = pts.arrays

        def points(start, stop, stack, reach, spd, rec2, stats):
            object_pass(cloth, only, active, s.lo, s.hi, now, body, cfg, arrays,
                        (stack, reach, spd, rec2, stats), start, stop)

        col._split(points, n, only)
        col.timings.object_queries += cpu_time() - t
        return pts
