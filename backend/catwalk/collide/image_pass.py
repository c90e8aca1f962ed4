"""Image space: the mapped parts' front and back depth maps (:class:`DepthMaps`) and the pass
that looks cloth points up in them (:class:`ImagePass`, over
:func:`catwalk.collide.kernels.image_space.image_pass`); the method is in
:mod:`catwalk.collide`."""

from __future__ import annotations

import numpy as np

from catwalk.collide.collider import Substep, cpu_time
from catwalk.collide.kernels.boxes import bounds_of, max_displacement
from catwalk.collide.kernels.depth_maps import (
    N_ATTRS,
    SIDE_BACK,
    SIDE_FRONT,
    map_region,
    render_maps,
)
from catwalk.collide.kernels.image_space import (
    PATT_COLUMNS,
    PDEP_COLUMNS,
    PKEY_COLUMNS,
    ImageConfig,
    ImageMaps,
    ImagePoints,
    image_pass,
)
from catwalk.collide.kernels.stats import ST_SKIPPED
from catwalk.geometry.raster import ortho_view


class DepthMaps:
    """Front and back depth maps (two slots: the previous and the current frame) of a set of
    faces, packed for look-ups (see :func:`catwalk.collide.kernels.image_space.image_pass`)."""

    def __init__(self, faces, face_ids, size, margin, k=N_ATTRS):
        f = np.asarray(faces, dtype=np.int64)[face_ids]
        self.vidx, inv = np.unique(f, return_inverse=True)
        self.faces = inv.reshape(-1, 3).astype(np.int64)
        self.size = (int(size[0]), int(size[1]))
        self.margin = float(margin)
        w, h = self.size
        # the layout: kernels.depth_maps
        self.D = np.full((h, w, 2, 2), -np.inf, np.float32)   # [row, col, slot, side]
        self.D[:, :, :, SIDE_BACK] = np.inf
        self.A = np.zeros((h, w, 2, 2, k), np.float32)       # [row, col, side, slot, attr]
        self.tri = np.full((2, 2, h, w), -1, np.int32)        # [slot, side, row, col]
        self.cur = 0
        self.prev = 0
        self.keys = [-2, -2]  # the frame drawn in each slot
        self.version = 0  # counts the (prev, cur) contents the look-ups saw
        self.full = (0, h - 1, 0, w - 1)
        self.region = [None, None]  # the rows and columns drawn in each slot
        self._need = np.array([0, h - 1, 0, w - 1], np.int64)
        self.matrix = None
        self.pixel = (0.0, 0.0)
        self.grid_lo = None
        self.grid_hi = None
        self.sv = np.empty((len(self.vidx), 3))
        self.attrs = np.empty((len(self.vidx), k))

    def fit(self, v_a, v_b) -> bool:
        """Fit the pixel grid (x, y) to the mapped vertices of both frames, with a margin;
        keep the old grid while they stay inside it. Returns True when the grid changed."""
        lo = np.full(3, np.inf)
        hi = np.full(3, -np.inf)
        bounds_of(v_a, self.vidx, lo, hi)
        bounds_of(v_b, self.vidx, lo, hi)
        if self.grid_lo is not None and np.all(lo[:2] >= self.grid_lo[:2]) and \
                np.all(hi[:2] <= self.grid_hi[:2]):
            return False
        lo[:2] -= self.margin
        hi[:2] += self.margin
        self.grid_lo, self.grid_hi = lo, hi
        cam = ortho_view(lo, hi, "front", self.size, square_pixels=False)
        m = cam.matrix.copy()
        m[2, 3] = 0.0  # depth = world z (towards the front camera)
        self.matrix = m
        self.pixel = cam.pixel
        return True

    def render(self, slot, v, n, w, region=None):
        """Draw a slot over ``region`` (r0, r1, c0, c1) of the pixel grid (default: all)."""
        r0, r1, c0, c1 = region or self.full
        render_maps(self.matrix, (v, n, w), self.vidx, self.faces, (self.sv, self.attrs),
                    (self.D, self.A, self.tri), slot, (r0, r1, c0, c1))
        self.region[slot] = (r0, r1, c0, c1)

    def need(self, lo, hi, pad):
        """The rows and columns whose pixels the look-ups of points in the box [lo, hi]
        (world, grown by ``pad``) can read (2×2 blocks), clipped to the grid."""
        map_region(self.matrix, lo, hi, pad, self.size[0], self.size[1], self._need)
        return tuple(int(x) for x in self._need)

    def covers(self, slot, need) -> bool:
        g = self.region[slot]
        return g is not None and g[0] <= need[0] and g[1] >= need[1] and g[2] <= need[2] \
            and g[3] >= need[3]

    def front_back(self, slot):
        """(front depth, back depth, covered) of a slot, float64 copies; covered: both sides
        drawn (what the look-ups answer from)."""
        return (self.D[:, :, slot, SIDE_FRONT].astype(np.float64),
                self.D[:, :, slot, SIDE_BACK].astype(np.float64),
                (self.tri[slot, SIDE_FRONT] >= 0) & (self.tri[slot, SIDE_BACK] >= 0))


class ImagePass:
    """The image pass of a collider (``col`` in the methods: the body's frames, the options,
    the counters): its :class:`DepthMaps` of the faces ``face_ids``, drawn once a frame over
    the region the cloth can reach; the mapped parts' box over the frame; what each cloth
    point kept of the pixels it read."""

    def __init__(self, faces, face_ids, size, margin):
        self.maps = DepthMaps(faces, face_ids, size, margin)
        # the mapped vertices' box over the frame, grown by thickness + search radius
        self.lo = np.zeros(3)
        self.hi = np.zeros(3)
        self.ready = False   # both slots drawn for this frame
        self.still = False   # the mapped parts did not move since the previous frame
        self._n = -1         # the number of points the per-point copies below are for

    def new_frame(self, col, first: bool) -> None:
        """The body's frame changed: the mapped parts' box and whether they moved."""
        vidx = self.maps.vidx
        self.ready = False
        self.lo[:] = np.inf
        self.hi[:] = -np.inf
        bounds_of(col.v0, vidx, self.lo, self.hi)
        bounds_of(col.v1, vidx, self.lo, self.hi)
        pad = col.thickness + col.search_radius
        self.lo -= pad
        self.hi += pad
        moved = max_displacement(col.v0, col.v1, vidx)
        wmoved = max_displacement(col.w0, col.w1, vidx)
        self.still = (not first) and col.skips.still_torso and \
            moved <= col.still_tol and wmoved <= col.still_tol

    def ensure(self, col, lo=None, hi=None) -> None:
        """The maps of the previous and the current frame, drawn over the region the cloth
        (box [lo, hi], grown by ``map_region_pad``) can reach; everywhere without a box."""
        mp = self.maps
        if self.ready:
            need = mp.full if lo is None else mp.need(lo, hi, 0.0)
            if mp.covers(mp.prev, need) and mp.covers(mp.cur, need):
                return
            # the cloth left the region drawn this frame: draw both slots again
            self.ready = False
        col._ensure_normals()
        t = cpu_time()
        if mp.fit(col.v0, col.v1):
            mp.keys = [-2, -2]  # a new grid: nothing drawn on it yet
        # what the look-ups need now; what is drawn: that, grown by map_region_pad, so that
        # the region usually holds for the frame after too (when it becomes the previous)
        need = mp.full if lo is None else mp.need(lo, hi, 0.0)
        draw = mp.full if lo is None else mp.need(lo, hi, col.map_region_pad)
        if col._frame == 0:
            if not (mp.keys[0] == 0 and mp.covers(0, need)):
                mp.render(0, col.v1, col.n1, col.w1, draw)
                col.timings.maps_rendered += 1
            mp.keys = [0, -2]
            mp.prev = mp.cur = 0
        else:
            self._draw_slots(col, need, draw)
        mp.version += 1  # the points' copies of map pixels are stale
        self.ready = True
        col.timings.maps += cpu_time() - t

    def _draw_slots(self, col, need, draw) -> None:
        """After the first frame: the slots of the previous and the current frame, each kept
        when it already holds that frame over ``need``, drawn over ``draw`` otherwise (a still
        body: one slot for both)."""
        mp = self.maps
        f = col._frame
        sp = mp.keys.index(f - 1) if (f - 1) in mp.keys else None
        if sp is None and f in mp.keys and self.still:
            sp = mp.keys.index(f)  # drawn already this frame (a still body)
        if self.still and sp is not None:
            if not mp.covers(sp, need):
                mp.render(sp, col.v1, col.n1, col.w1, draw)
                col.timings.maps_rendered += 1
            else:
                col.timings.maps_skipped += 1
            mp.prev = mp.cur = sp
            mp.keys[sp] = f  # frame f looks the same as frame f − 1
            return
        if f in mp.keys:
            sc = mp.keys.index(f)
            sp = 1 - sc if mp.keys[1 - sc] == f - 1 else None
        else:
            sc = None
        if sp is None or not mp.covers(sp, need):
            sp = 0 if sc is None else 1 - sc
            mp.render(sp, col.v0, col.n0, col.w0, draw)
            mp.keys[sp] = f - 1
            col.timings.maps_rendered += 1
        sc = 1 - sp
        if not (mp.keys[sc] == f and mp.covers(sc, need)):
            mp.render(sc, col.v1, col.n1, col.w1, draw)
            mp.keys[sc] = f
            col.timings.maps_rendered += 1
        mp.prev, mp.cur = sp, sc

    def run(self, col, s: Substep, held, edge) -> None:
        """Look the substep's points up in the maps: fix the ones inside (or within the
        thickness), mark them in ``held`` and set their planes in ``col.planes``; ``edge``
        (P,) bool, or empty: marks the points the maps leave to object space (hybrid's edge
        fallback; those marked on entry are left alone)."""
        if col.skips.unreached_parts and (np.any(self.lo > s.hi) or np.any(self.hi < s.lo)):
            col.stats[ST_SKIPPED] += len(s.pos)
            return
        self.ensure(col, s.lo, s.hi)
        mp = self.maps
        t = cpu_time()
        n = len(s.pos)
        if self._n != n:
            self._pkey = np.full((n, PKEY_COLUMNS), -1, np.int64)
            self._pdep = np.zeros((n, PDEP_COLUMNS), np.float32)
            self._patt = np.zeros((n, PATT_COLUMNS), np.float32)
            self._pwin = np.zeros(n, np.int8)
            self._n = n
            # (the groups go to the kernel as plain tuples, as the object pass's)
            self._points = tuple(ImagePoints(self._pkey, self._pdep, self._patt, self._pwin))

        # on the calling thread whatever the collider's threads (kernels.image_space.image_pass)
        maps = tuple(ImageMaps(mp.matrix, mp.D, mp.A, mp.prev, mp.cur, mp.version))
        cfg = tuple(ImageConfig(col.thickness, col.friction, col.contact_slack, col.plane_band,
                                col.min_normal_z, col.edge_normal_z, col.skips.far_points))
        image_pass(s.pos, s.vel, held, col.planes, edge, col.stats, s.alpha, self.lo, self.hi,
                   maps, cfg, self._points)
        col.timings.image_queries += cpu_time() - t
