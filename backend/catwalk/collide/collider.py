"""The collider object: see :mod:`catwalk.collide` for the interface and the method."""

from __future__ import annotations

import hashlib
import queue
import time
import weakref
from concurrent.futures import ThreadPoolExecutor, wait
from dataclasses import dataclass, field

import numpy as np

from catwalk.cloth.model import PLANE_COLUMNS
from catwalk.collide import bvh as B
from catwalk.collide import kernels as K
from catwalk.collide.sharp import SHARP_DEPTH, push_off_sharp, sharp_vertices
from catwalk.errors import InputError
from catwalk.render.raster import (
    incident_faces,
    ortho_view,
    vertex_normals,
    vertex_normals_kernel,
)

# CPU time of this thread: on a shared machine, wall time also counts other processes' turns
_clock = time.thread_time

MODES = ("hybrid", "image", "object")
N_PARTS = 5
PART_NAMES = ("torso", "left_arm", "right_arm", "left_leg", "right_leg")


@dataclass
class Skips:
    """The work-saving shortcuts, each switchable (the benchmark measures what each saves)."""

    unreached_parts: bool = True   # parts whose swept box cannot reach the cloth get no work
    still_torso: bool = True       # depth maps not re-rendered when the mapped parts did not move
    far_points: bool = True        # points far from every part skip the narrow phase
    reuse_closest: bool = True     # closest triangle reused while a point barely moved
    clearance: bool = True         # a point known to be far skips work until it could touch

    @classmethod
    def off(cls) -> Skips:
        """Every shortcut off (the exhaustive reference)."""
        return cls(unreached_parts=False, still_torso=False, far_points=False,
                   reuse_closest=False, clearance=False)


@dataclass
class Timings:
    """Seconds spent, accumulated (reset with :meth:`Collider.reset_stats`)."""

    maps: float = 0.0
    normals: float = 0.0
    refit: float = 0.0
    image_queries: float = 0.0
    object_queries: float = 0.0
    sharp: float = 0.0
    sharp_pushes: int = 0
    frames: int = 0
    substeps: int = 0
    maps_rendered: int = 0
    maps_skipped: int = 0
    parts_refit: int = 0
    parts_skipped: int = 0
    counters: dict = field(default_factory=dict)


class _Points:
    """What the object pass keeps per cloth point between calls (see
    :func:`catwalk.collide.kernels.object_pass`), for one set of parts."""

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
        self.rec = np.zeros((n, 54), np.float32)
        self.last = np.zeros((n, 3))
        self.left = np.zeros((n, 3))
        self.pclk = np.full((n, 5), -1.0)   # time < 0: never seen
        self.csw = np.zeros((n, N_PARTS))
        self.crel = np.zeros(n)
        self.cstamp = np.full(n, -1, np.int64)
        self.ct2 = np.full(n, -1, np.int64)
        self.cp2 = np.zeros((n, 3))
        self.cc2 = np.zeros((n, 3))
        self.active_last = np.zeros(N_PARTS, bool)
        self.clear_frame = -1

    def arrays(self):
        """The per-point arrays as the object pass takes them."""
        return K.ObjectPoints(self.cache_tri, self.cache_p, self.cache_c, self.clear,
                              self.clear_rel, self.rkey, self.rec, self.pspeed, self.pstamp,
                              self.last, self.pclk, self.csw, self.crel, self.cstamp, self.ct2,
                              self.cp2, self.cc2, self.left)


def _workspace(stats: np.ndarray | None = None) -> K.Workspace:
    """A thread's scratch for the object and image passes (the kernels never allocate): the
    hierarchy walk's stack, the part reach, two scratch arrays, and its counters (``stats``,
    or new ones)."""
    return K.Workspace(np.empty(B.STACK_SIZE, np.int64), np.zeros(N_PARTS, bool), np.zeros(2),
                       np.zeros((1, 54), np.float32),
                       np.zeros(K.N_STATS, np.int64) if stats is None else stats)


def face_parts(faces, parts) -> np.ndarray:
    """Each face's part: the label most of its vertices carry (its first vertex's on a tie)."""
    p = np.asarray(parts, dtype=np.int64)[np.asarray(faces, dtype=np.int64)]
    a, b, c = p[:, 0], p[:, 1], p[:, 2]
    return np.where((b == c) & (a != b), b, a).astype(np.int8)


class _Maps:
    """Front and back depth maps (two slots: the previous and the current frame) of a set of
    faces, packed for look-ups (see :func:`catwalk.collide.kernels.image_pass`)."""

    def __init__(self, faces, face_ids, size, margin, k=6):
        f = np.asarray(faces, dtype=np.int64)[face_ids]
        self.vidx, inv = np.unique(f, return_inverse=True)
        self.faces = inv.reshape(-1, 3).astype(np.int64)
        self.size = (int(size[0]), int(size[1]))
        self.margin = float(margin)
        w, h = self.size
        self.D = np.full((h, w, 2, 2), -np.inf, np.float32)   # [row, col, slot, side]
        self.D[:, :, :, 1] = np.inf
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
        K.bounds_of(v_a, self.vidx, lo, hi)
        K.bounds_of(v_b, self.vidx, lo, hi)
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
        K.render_maps(self.matrix, v, n, w, self.vidx, self.faces, self.sv, self.attrs, slot,
                      self.D, self.A, self.tri, r0, r1, c0, c1)
        self.region[slot] = (r0, r1, c0, c1)

    def need(self, lo, hi, pad):
        """The rows and columns whose pixels the look-ups of points in the box [lo, hi]
        (world, grown by ``pad``) can read (2×2 blocks), clipped to the grid."""
        K.map_region(self.matrix, lo, hi, pad, self.size[0], self.size[1], self._need)
        return tuple(int(x) for x in self._need)

    def covers(self, slot, need) -> bool:
        g = self.region[slot]
        return g is not None and g[0] <= need[0] and g[1] >= need[1] and g[2] <= need[2] \
            and g[3] >= need[3]

    def front_back(self, slot):
        """(front depth, back depth, covered) of a slot, float64 copies."""
        return (self.D[:, :, slot, 0].astype(np.float64), self.D[:, :, slot, 1].astype(np.float64),
                self.tri[slot, 0] >= 0)


#: the torso's sharp vertices per first pose (a digest of its torso vertices): a worker
#: dresses many garments on one body, and finding them costs ≈ 40 ms
_SHARP_CACHE: dict = {}


class Collider:
    """Cloth–body collider (image, object or hybrid); make one with :func:`make_collider`."""

    def __init__(self, mode, body_faces, parts, *, map_size=(256, 256), thickness=0.004,
                 friction=0.3, contact_slack=0.0005, search_radius=0.02, max_depth=0.02,
                 reuse_tol=0.002,
                 leaf_size=8, map_margin=0.03, still_tol=1e-6, min_normal_z=0.2, edge_normal_z=0.5,
                 map_region_pad=0.05, edge_fallback=True, limb_fallback=True,
                 second_surface=True, skips: Skips | None = None, threads: int = 1):
        if mode not in MODES:
            raise InputError(f"collider mode must be one of {', '.join(MODES)}, not {mode!r}")
        faces = np.asarray(body_faces)
        if faces.ndim != 2 or faces.shape[1] != 3 or len(faces) == 0:
            raise InputError(f"body faces must be a non-empty (M, 3) array, got {faces.shape}")
        parts = np.asarray(parts)
        if parts.ndim != 1 or (faces.max() >= len(parts)) or faces.min() < 0:
            raise InputError("parts must give one label per body vertex, covering the faces")
        if parts.min() < 0 or parts.max() >= N_PARTS:
            raise InputError("part labels must be 0 (torso+head) … 4 (right leg)")
        for name, val in (("thickness", thickness), ("search_radius", search_radius),
                          ("max_depth", max_depth)):
            if not (np.isfinite(val) and val > 0):
                raise InputError(f"{name} must be a positive length in metres, got {val!r}")
        if not (np.isfinite(edge_normal_z) and 0.0 <= edge_normal_z <= 1.0):
            raise InputError(f"edge_normal_z must be within 0..1, got {edge_normal_z!r}")
        if not (np.isfinite(friction) and friction >= 0):
            raise InputError(f"friction must be >= 0, got {friction!r}")
        if isinstance(threads, bool) or not isinstance(threads, (int, np.integer)) or \
                not 1 <= threads <= 64:
            raise InputError(f"threads must be a whole number within 1–64, got {threads!r}")
        ms = (map_size, map_size) if np.isscalar(map_size) else tuple(map_size)
        if len(ms) != 2 or min(ms) < 8 or max(ms) > 8192:
            raise InputError(f"map size must be 8..8192 pixels, got {map_size!r}")
        self.mode = mode
        self.faces = np.ascontiguousarray(faces, dtype=np.int64)
        self._faces32 = self.faces.astype(np.int32)
        self.parts = parts.astype(np.int8)
        self.n_vertices = len(parts)
        self.face_part = face_parts(self.faces, self.parts)
        self.thickness = float(thickness)
        self.friction = float(friction)
        self.contact_slack = float(contact_slack)
        self.search_radius = float(search_radius)
        self.max_depth = float(max_depth)
        self.reuse_tol = float(reuse_tol)
        self.still_tol = float(still_tol)
        self.min_normal_z = float(min_normal_z)
        self.edge_normal_z = float(edge_normal_z)
        self.map_region_pad = float(map_region_pad)
        self.leaf_size = int(leaf_size)
        # a point near its closest part may be inside another one (cloth pinched between a
        # hand and the thigh, an arm and the torso): look for it (kernels._second_surface)
        self.second_surface = bool(second_surface)
        self.skips = skips or Skips()
        in_maps = {"image": range(5), "hybrid": [0], "object": []}[mode]
        in_tree = {"image": [], "hybrid": [1, 2, 3, 4], "object": range(5)}[mode]
        self.map_parts = np.zeros(N_PARTS, bool)
        self.map_parts[list(in_maps)] = True
        present = np.bincount(self.face_part, minlength=N_PARTS) > 0
        self.tree_parts = np.zeros(N_PARTS, bool)
        self.tree_parts[list(in_tree)] = True
        self.tree_parts &= present
        # hybrid: the points the torso's maps cannot answer (at their silhouette, where the
        # surface turns away from both cameras) go to object space against every part, the
        # torso's own hierarchy included (built for them alone)
        self.edge_fallback = bool(mode == "hybrid" and edge_fallback and present[0])
        self.limb_fallback = bool(self.edge_fallback and limb_fallback)
        self.hier_parts = self.tree_parts | (self.map_parts & present & self.edge_fallback)
        in_tree = list(np.nonzero(self.hier_parts)[0])
        map_faces = np.nonzero(self.map_parts[self.face_part])[0]
        self.maps = _Maps(self.faces, map_faces, ms, map_margin) if len(map_faces) else None
        self.map_vidx = self.maps.vidx if self.maps else np.zeros(0, np.int64)
        self._part_faces = {p: np.nonzero(self.face_part == p)[0] for p in in_tree}
        self._part_vidx = {p: np.unique(self.faces[f]) for p, f in self._part_faces.items()}
        self._tree_vidx = np.unique(self.faces[np.nonzero(self.hier_parts[self.face_part])[0]])
        # workspaces for the kernels (they run without numba's runtime, so never allocate)
        self._vb = np.zeros((self.n_vertices, 18), np.float32)
        self._vp = np.zeros((self.n_vertices, 6), np.float32)
        self._ref = np.zeros(3)      # the body's mean displacement over the frame
        self._body_speed = 0.0       # the farthest a tree vertex moves relative to it
        # clocks at the start of this frame: the moving frame's travel (3), the body's travel
        # relative to it (an upper bound: the sum of the frames' body speeds); with the time
        # (frame + alpha) the object pass measures each point's motion since it last saw it
        self._clock0 = np.zeros(4)
        self._clock = np.zeros(5)
        self._packed_frame = -1
        self._nb = None              # node boxes at the previous and the current frame
        self._box_frame = np.full(N_PARTS, -2)  # the frame whose boxes are in nb[:, 6:12]
        self._img_n = -1
        # with threads > 1 the object and image passes run over slices of the points at
        # once, each thread with its own workspaces (kernels.object_pass, image_pass)
        self.threads = int(threads)
        self._pool = None
        self._thread_ws = [_workspace() for _ in range(self.threads - 1)]
        self.tree = None  # built from the first frame's pose
        self._refit_done = np.zeros(N_PARTS, bool)
        self._maps_ready = False
        self._maps_still = False
        self._normals_ready = False
        self.v0 = self.v1 = self.w0 = self.w1 = self.n0 = self.n1 = None
        self._frame = -1
        self._alpha_last = 0.0
        self._calls = 0
        self._calls_last_frame = 0
        self._substeps = None
        self._pts = self._edge_pts = None  # _Points of the object pass and of the edge fallback
        self._edge = np.zeros(0, bool)   # the points the image pass leaves to object space
        self._near_limb = np.zeros(0, bool)  # hybrid: the points a limb held at the last resolve
        self._rest = np.zeros(0, bool)   # and the others
        self.stats = np.zeros(K.N_STATS, np.int64)
        self._ws = _workspace(self.stats)   # the calling thread's
        # (P, 8) after each resolve: the held points' contact planes (normal, offset, the
        # body's velocity, friction; normal 0 for points not held), see kernels.record_plane
        self.planes = np.zeros((0, PLANE_COLUMNS))
        self.timings = Timings()
        self._torso_lo = np.zeros(3)
        self._torso_hi = np.zeros(3)
        self._first_v = None          # the first pose given to update()
        self._sharp = None            # the body's sharp vertices (collide/sharp.py)
        self._sharp_csr = None
        self._sharp_csr_key = None
        self._sharp_src = self._sharp_tris = None   # the triangles last given, as given/int64
        self._sharp_n = -1

    # ------------------------------------------------------------------ per frame
    def update(self, body_vertices, body_velocities=None, substeps: int | None = None) -> None:
        """Give the body's next frame: world vertices (N,3) and velocities (N,3) (m/s; zero if
        None). During the following ``resolve`` calls the body moves linearly from the previous
        frame to this one; ``substeps``: how many resolve calls this frame will have (default:
        as many as the previous frame had; 1 on the first frame)."""
        v = np.asarray(body_vertices, dtype=np.float64)
        if v.shape != (self.n_vertices, 3):
            raise InputError(f"body vertices must be ({self.n_vertices}, 3), got {v.shape}")
        if not np.all(np.isfinite(v)):
            raise InputError("body vertices contain non-finite values")
        if body_velocities is None:
            w = np.zeros_like(v)
        else:
            w = np.asarray(body_velocities, dtype=np.float64)
            if w.shape != v.shape or not np.all(np.isfinite(w)):
                raise InputError(f"body velocities must be finite ({self.n_vertices}, 3)")
        if substeps is not None and int(substeps) < 1:
            raise InputError(f"substeps must be >= 1, got {substeps}")
        first = self.v1 is None
        if first:
            self._first_v = v.copy()   # the pose the sharp vertices are found in
            self.v0 = v.copy()
            self.v1 = v.copy()
            self.w0 = w.copy()
            self.w1 = w.copy()
            self.n0 = np.empty_like(v)
            self.n1 = np.empty_like(v)
            self._n_valid = [False, False]
        else:
            self.v0, self.v1 = self.v1, self.v0
            self.w0, self.w1 = self.w1, self.w0
            self.n0, self.n1 = self.n1, self.n0
            self._n_valid = [self._n_valid[1], False]
            self.v1[:] = v
            self.w1[:] = w
        if not first and self.tree is not None:
            # the previous frame is over (whatever alpha its last resolve had)
            self._clock0[:3] += self._ref
            self._clock0[3] += self._body_speed
        self._frame += 1
        self._calls_last_frame = self._calls if not first else 0
        self._calls = 0
        self._substeps = int(substeps) if substeps is not None else (
            self._calls_last_frame or None)
        self._alpha_last = 0.0
        self._refit_done[:] = False
        self._normals_ready = False
        self._maps_ready = False
        self.timings.frames += 1
        if first and self.hier_parts.any():
            self.tree = B.build(v, self.faces, self._part_faces, self.leaf_size)
            self._lv_start, self._lv = B.leaf_vertices(self.tree, self.faces)
            self._lf = np.ascontiguousarray(self.faces[self.tree.tris], dtype=np.int32)
            self._nb = np.zeros((self.tree.n_nodes, 16), np.float32)
        if self.tree is not None:
            # the frame's motion, for the clocks (packing, later, finds the same values)
            self._body_speed = K.body_motion(self.v0, self.v1, self._tree_vidx, self._ref)
        if self.maps is not None:
            self._torso_lo[:] = np.inf
            self._torso_hi[:] = -np.inf
            K.bounds_of(self.v0, self.map_vidx, self._torso_lo, self._torso_hi)
            K.bounds_of(self.v1, self.map_vidx, self._torso_lo, self._torso_hi)
            pad = self.thickness + self.search_radius
            self._torso_lo -= pad
            self._torso_hi += pad
            moved = K.max_displacement(self.v0, self.v1, self.map_vidx)
            wmoved = K.max_displacement(self.w0, self.w1, self.map_vidx)
            self._maps_still = (not first) and self.skips.still_torso and \
                moved <= self.still_tol and wmoved <= self.still_tol

    def _ensure_normals(self):
        if self._normals_ready:
            return
        t = _clock()
        if not self._n_valid[1]:
            vertex_normals_kernel(self.v1, self.faces, self.n1)
            self._n_valid[1] = True
        if not self._n_valid[0]:
            if self._frame == 0:
                self.n0[:] = self.n1
            else:
                vertex_normals_kernel(self.v0, self.faces, self.n0)
            self._n_valid[0] = True
        self._normals_ready = True
        self.timings.normals += _clock() - t

    def _ensure_maps(self, lo=None, hi=None):
        """The maps of the previous and the current frame, drawn over the region the cloth
        (box [lo, hi], grown by ``map_region_pad``) can reach; everywhere without a box."""
        if self._maps_ready:
            if lo is None:
                need = self.maps.full
            else:
                need = self.maps.need(lo, hi, 0.0)
            mp = self.maps
            if mp.covers(mp.prev, need) and mp.covers(mp.cur, need):
                return
            # the cloth left the region drawn this frame: draw both slots again
            self._maps_ready = False
        self._ensure_normals()
        t = _clock()
        mp = self.maps
        f = self._frame
        if mp.fit(self.v0, self.v1):
            mp.keys = [-2, -2]  # a new grid: nothing drawn on it yet
        # what the look-ups need now; what is drawn: that, grown by map_region_pad, so that
        # the region usually holds for the frame after too (when it becomes the previous)
        need = mp.full if lo is None else mp.need(lo, hi, 0.0)
        draw = mp.full if lo is None else mp.need(lo, hi, self.map_region_pad)
        if f == 0:
            if not (mp.keys[0] == 0 and mp.covers(0, need)):
                mp.render(0, self.v1, self.n1, self.w1, draw)
                self.timings.maps_rendered += 1
            mp.keys = [0, -2]
            mp.prev = mp.cur = 0
        else:
            sp = mp.keys.index(f - 1) if (f - 1) in mp.keys else None
            if sp is None and f in mp.keys and self._maps_still:
                sp = mp.keys.index(f)  # drawn already this frame (a still body)
            if self._maps_still and sp is not None:
                if not mp.covers(sp, need):
                    mp.render(sp, self.v1, self.n1, self.w1, draw)
                    self.timings.maps_rendered += 1
                else:
                    self.timings.maps_skipped += 1
                mp.prev = mp.cur = sp
                mp.keys[sp] = f  # frame f looks the same as frame f − 1
            else:
                if f in mp.keys:
                    sc = mp.keys.index(f)
                    sp = 1 - sc if mp.keys[1 - sc] == f - 1 else None
                else:
                    sc = None
                if sp is None or not mp.covers(sp, need):
                    sp = 0 if sc is None else 1 - sc
                    mp.render(sp, self.v0, self.n0, self.w0, draw)
                    mp.keys[sp] = f - 1
                    self.timings.maps_rendered += 1
                sc = 1 - sp
                if not (mp.keys[sc] == f and mp.covers(sc, need)):
                    mp.render(sc, self.v1, self.n1, self.w1, draw)
                    mp.keys[sc] = f
                    self.timings.maps_rendered += 1
                mp.prev, mp.cur = sp, sc
        mp.version += 1  # the points' copies of map pixels are stale
        self._maps_ready = True
        self.timings.maps += _clock() - t

    def _pack(self):
        """The limbs' vertices of both frames, packed for the object pass (once a frame)."""
        if self._packed_frame == self._frame:
            return
        self._ensure_normals()
        t = _clock()
        self._body_speed = K.pack_body(self.v0, self.v1, self.n0, self.n1, self.w0, self.w1,
                                       self._tree_vidx, self._vb, self._vp, self._ref)
        self._packed_frame = self._frame
        self.timings.normals += _clock() - t

    def _refit(self, active):
        need = active & ~self._refit_done
        if not need.any():
            return
        self._pack()
        t = _clock()
        h = self.tree
        nb = self._nb
        for p in np.nonzero(need)[0]:
            a, e = h.root[p], h.end[p]
            if self._box_frame[p] == self._frame - 1:
                nb[a:e, 0:6] = nb[a:e, 6:12]  # the previous frame's boxes: already known
            else:
                B.refit_frame(self._vp, 0, self._lv_start, self._lv, h.links, nb, a, e)
            B.refit_frame(self._vp, 1, self._lv_start, self._lv, h.links, nb, a, e)
            B.node_speeds(self._vp, self._ref, self._lv_start, self._lv, h.links, nb, a, e)
            self._box_frame[p] = self._frame
            self._refit_done[p] = True
            self.timings.parts_refit += 1
        self.timings.refit += _clock() - t

    # ------------------------------------------------------------------ per substep
    def resolve(self, positions, velocities, previous_positions, alpha: float | None = None):
        """Collide cloth points with the body at this substep; fixes ``positions`` and
        ``velocities`` (float64 (P,3), C-contiguous) in place and returns the held mask (P,)
        bool. ``alpha``: the substep's time in [0, 1] between the previous and the current
        body frame (default: from the substep count, see :meth:`update`). Afterwards
        :attr:`planes` holds each held point's contact plane (zero normal for the others)."""
        if self.v1 is None:
            raise InputError("collider.update(body) must be called before resolve()")
        pos, vel, prev = positions, velocities, previous_positions
        for name, a in (("positions", pos), ("velocities", vel)):
            if not (isinstance(a, np.ndarray) and a.dtype == np.float64 and a.ndim == 2 and
                    a.shape[1] == 3 and a.flags.c_contiguous and a.flags.writeable):
                raise InputError(f"{name} must be a writable C-contiguous float64 (P, 3) array")
        if vel.shape != pos.shape:
            raise InputError("positions and velocities differ in shape")
        prev = np.ascontiguousarray(prev, dtype=np.float64)
        if prev.shape != pos.shape:
            raise InputError("previous positions differ in shape from positions")
        n = len(pos)
        if alpha is None:
            # only the counted calls count: an explicit alpha (the walk's end-of-frame
            # resolve) does not shift the substeps after it nor the next frame's count
            self._calls += 1
            alpha = 1.0 if not self._substeps else min(self._calls / self._substeps, 1.0)
        alpha = float(alpha)
        if not 0.0 <= alpha <= 1.0:
            raise InputError(f"alpha must be in [0, 1], got {alpha}")
        alpha_prev = min(self._alpha_last, alpha)
        self._alpha_last = alpha
        self.timings.substeps += 1
        held = np.zeros(n, dtype=bool)
        if self.planes.shape[0] != n:
            self.planes = np.zeros((n, PLANE_COLUMNS))
        else:
            self.planes[:, :3] = 0.0
        if n == 0:
            return held
        lo = np.full(3, np.inf)
        hi = np.full(3, -np.inf)
        K.bounds(pos, lo, hi)
        K.bounds(prev, lo, hi)
        reach = None
        if self.tree is not None:
            reach = self._part_reach_cache(lo, hi) if self.skips.unreached_parts else \
                self.hier_parts
        use_edge = self.edge_fallback and reach is not None and bool(reach[0])
        flagged = False
        if self.maps is not None:
            if use_edge:
                if len(self._edge) != n:
                    self._edge = np.zeros(n, bool)
                    self._rest = np.ones(n, bool)
                elif self.limb_fallback and len(self._near_limb) == n:
                    # points a limb held at the last resolve: object space against every
                    # part (a point pinched between an arm and the torso answered by the maps
                    # and by the arm's hierarchy in turn is pushed back and forth)
                    self._edge[:] = self._near_limb
                else:
                    self._edge[:] = False
            self._image(pos, vel, alpha, lo, hi, held, self._edge if use_edge else self._edge[:0])
            flagged = use_edge and bool(self._edge.any())
        if self.tree is not None:
            track = use_edge and self.limb_fallback
            he = np.zeros(n, bool) if track else held
            hl = np.zeros(n, bool) if track else held
            if flagged:
                # the points the maps left alone: object space, every part in reach (the
                # nearest surface of all, as in object mode); the others: the limbs
                np.logical_not(self._edge, out=self._rest)
                self._edge_pts = self._object(pos, vel, prev, alpha, alpha_prev, lo, hi, he,
                                              reach, self._edge_pts, self._edge)
            if self.tree_parts.any():
                self._pts = self._object(pos, vel, prev, alpha, alpha_prev, lo, hi, hl,
                                         reach & self.tree_parts, self._pts,
                                         self._rest if flagged else self._edge[:0])
            if track:
                held |= he
                held |= hl
                # held by a limb: by the limbs' pass, or by a limb's triangle in the
                # all-parts pass
                near = hl
                if flagged and self._edge_pts is not None:
                    t = self._edge_pts.cache_tri
                    near = near | (he & (t >= 0) & (self.face_part[np.maximum(t, 0)] != 0))
                self._near_limb = near
        return held

    def _active_tree_parts(self, lo, hi):
        """Parts in hierarchies whose swept box (dilated) reaches the cloth's box."""
        active = self.hier_parts.copy()
        if not self.skips.unreached_parts:
            return active
        pad = self.search_radius + self.thickness
        for p in np.nonzero(active)[0]:
            vi = self._part_vidx[p]
            # a cheap bound without refitting: the part's vertices at both frames
            plo = np.full(3, np.inf)
            phi = np.full(3, -np.inf)
            K.bounds_of(self.v0, vi, plo, phi)
            K.bounds_of(self.v1, vi, plo, phi)
            plo -= pad
            phi += pad
            if np.any(plo > hi) or np.any(phi < lo):
                active[p] = False
        return active

    def _part_reach_cache(self, lo, hi):
        key = (self._frame,)
        if getattr(self, "_reach_key", None) != key or self._reach_box is None or \
                np.any(lo < self._reach_box[0]) or np.any(hi > self._reach_box[1]):
            # recompute once per frame for a cloth box grown by a margin
            m = 0.05
            blo, bhi = lo - m, hi + m
            act = self._active_tree_parts(blo, bhi)
            self._reach_key = key
            self._reach_box = (blo, bhi)
            self._reach = act
            n_off = int((self.tree_parts & ~act).sum())
            self.timings.parts_skipped += n_off
        return self._reach

    def _object(self, pos, vel, prev, alpha, alpha_prev, lo, hi, held, active, pts, only):
        """The object pass over the ``active`` parts with the per-point state ``pts`` (made
        when missing or of another size; returned); ``only``: the points to see (empty: all)."""
        n = len(pos)
        if not active.any():
            if len(only) == 0:
                self.stats[K.ST_SKIPPED] += n
            return pts
        self._refit(active)
        if pts is None or pts.n != n:
            pts = _Points(n)
        if np.any(active & ~pts.active_last):
            # a part came into play: no clearance bounds it
            pts.clear_rel[:] = 0.0
            pts.cstamp[:] = -1
            pts.ct2[:] = -1
        if pts.clear_frame != self._frame or np.any(active & ~pts.active_last):
            # clearances hold against this frame's swept boxes of the parts then in play
            pts.clear[:] = 0.0
            pts.clear_frame = self._frame
        pts.active_last = active.copy()
        self._pack()
        h = self.tree
        ck = self._clock
        ck[:3] = self._clock0[:3] + alpha * self._ref
        ck[3] = self._clock0[3] + alpha * self._body_speed
        ck[4] = self._frame + alpha
        t = _clock()

        now = K.ObjectTime(alpha, alpha_prev, self._frame, self._ref, ck, self._body_speed)
        body = K.ObjectBody(self._vb, self._vp, self.faces, self.face_part, self._nb, h.links,
                            h.tris, h.root, self._lf)
        cfg = K.ObjectConfig(self.thickness, self.friction, self.contact_slack,
                             self.search_radius, self.max_depth, self.skips.far_points,
                             self.skips.reuse_closest, self.reuse_tol, self.skips.clearance,
                             self.search_radius, self.second_surface)
        arrays = pts.arrays()

        def points(start, stop, stack, reach, spd, rec2, stats):
            K.object_pass(pos, vel, prev, held, self.planes, only, active, lo, hi, now, body,
                          cfg, arrays, K.Workspace(stack, reach, spd, rec2, stats), start, stop)

        self._split(points, n, int(only.sum()) if len(only) else n)
        self.timings.object_queries += _clock() - t
        return pts

    def _split(self, points, n, seen: int | None = None):
        """``points(start, stop, stack, reach, spd, rec2, stats)`` over all ``n`` points (of
        which ``seen`` are looked at, default all): at once on one thread (also when ``seen``
        is too few to share), or over slices on ``threads`` threads — 4 slices a thread, taken
        as threads come free (the cost per point varies along the garment), the calling
        thread one of them with the collider's own workspaces, each other with its own (its
        counters added to :attr:`stats` after)."""
        own = self._ws
        if self.threads == 1 or (n if seen is None else seen) < 64 * self.threads:
            points(0, n, *own)
            return
        if self._pool is None:
            self._pool = ThreadPoolExecutor(self.threads - 1,
                                            thread_name_prefix="catwalk-collide")
            # the idle threads end with the collider
            weakref.finalize(self, self._pool.shutdown, wait=False)
        bounds = np.linspace(0, n, 4 * self.threads + 1).astype(int)
        todo = queue.SimpleQueue()
        for a, b in zip(bounds[:-1], bounds[1:], strict=True):
            todo.put((int(a), int(b)))

        def work(ws):
            while True:
                try:
                    a, b = todo.get_nowait()
                except queue.Empty:
                    return
                points(a, b, *ws)

        futures = [self._pool.submit(work, ws) for ws in self._thread_ws]
        try:
            work(own)
        finally:
            # every helper has stopped before this returns or raises: none writes to the
            # points after it, and their counters are taken even from a failed call
            wait(futures)
            for ws in self._thread_ws:
                self.stats += ws.stats
                ws.stats[:] = 0
        for f in futures:
            f.result()   # a helper's error, raised here

    def _image(self, pos, vel, alpha, lo, hi, held, edge):
        if self.skips.unreached_parts and (np.any(self._torso_lo > hi) or
                                           np.any(self._torso_hi < lo)):
            self.stats[K.ST_SKIPPED] += len(pos)
            return
        self._ensure_maps(lo, hi)
        mp = self.maps
        t = _clock()
        n = len(pos)
        if self._img_n != n:
            self._pkey = np.full((n, 3), -1, np.int64)
            self._pdep = np.zeros((n, 16), np.float32)
            self._patt = np.zeros((n, 12), np.float32)
            self._pwin = np.zeros(n, np.int8)
            self._img_n = n

        def points(start, stop, stack, reach, spd, rec2, stats):
            K.image_pass(pos, vel, alpha, mp.matrix, mp.D, mp.A, mp.prev, mp.cur, mp.version,
                         self._torso_lo, self._torso_hi, self.thickness, self.friction,
                         self.contact_slack, self.min_normal_z, self.skips.far_points, held,
                         stats, self._pkey, self._pdep, self._patt, self.planes, edge,
                         self.edge_normal_z, self._pwin, start, stop)

        self._split(points, n)
        self.timings.image_queries += _clock() - t

    def push_off_sharp(self, positions, triangles, moved=None) -> int:
        """Push cloth triangles off the body's sharp vertices at the current frame (see
        :mod:`catwalk.collide.sharp`): the body's side of the collision, once per frame after
        the last :meth:`resolve`. ``positions`` (P, 3) float64, changed in place;
        ``triangles`` (T, 3) over them; ``moved`` (P,) bool, if given: set True for the points
        moved. Returns the number of pushes."""
        if self.v1 is None:
            raise InputError("collider.update(body) must be called before push_off_sharp()")
        x = positions
        if not (isinstance(x, np.ndarray) and x.dtype == np.float64 and x.ndim == 2 and
                x.shape[1] == 3 and x.flags.c_contiguous and x.flags.writeable):
            raise InputError("positions must be a writable C-contiguous float64 (P, 3) array")
        if len(x) == 0 or len(triangles) == 0:
            return 0
        if triangles is not self._sharp_src or len(x) != self._sharp_n:
            # a walk passes the same triangles every frame: converted, checked and their
            # incidence built once per array (held here, so its identity is not reused; a
            # model's triangles are never changed in place)
            tris = np.ascontiguousarray(triangles, dtype=np.int64)
            if tris.ndim != 2 or tris.shape[1] != 3 or tris.min() < 0 or tris.max() >= len(x):
                raise InputError("cloth triangles must be (T, 3) indices of the positions")
            key = (hashlib.blake2b(tris.tobytes(), digest_size=16).digest(), len(x))
            if self._sharp_csr_key != key:
                self._sharp_csr = incident_faces(tris, len(x))
                self._sharp_csr_key = key
            self._sharp_src, self._sharp_n, self._sharp_tris = triangles, len(x), tris
        tris = self._sharp_tris
        if moved is None:
            moved = np.zeros(0, bool)
        elif not (isinstance(moved, np.ndarray) and moved.dtype == bool
                  and moved.shape == (len(x),)):
            raise InputError("moved must be a (P,) bool array")
        self._ensure_normals()
        if self._sharp is None:
            self._sharp = self._sharp_vertices()
        t = _clock()
        n = push_off_sharp(x, tris, *self._sharp_csr, self._sharp, self.v1, self.n1,
                           self.thickness, SHARP_DEPTH, 0.02, moved)
        self.timings.sharp += _clock() - t
        self.timings.sharp_pushes += int(n)
        return int(n)

    def _sharp_vertices(self) -> np.ndarray:
        """The torso's sharp vertices in the first pose the collider was given (kept per pose
        and parts for the process). Of the torso only: the limbs' (fingers, knuckles, toes) rub
        cloth at every step of a walk and would tent it frame after frame."""
        torso = np.nonzero(self.parts == 0)[0]
        v = self._first_v[torso]
        # (in float32: the walk's poses are skinned in float32, the dressing's rest pose not)
        hsh = hashlib.blake2b(v.astype(np.float32).tobytes(), digest_size=16)
        hsh.update(torso.tobytes())
        key = hsh.digest()
        if key not in _SHARP_CACHE:
            if len(_SHARP_CACHE) >= 8:
                _SHARP_CACHE.pop(next(iter(_SHARP_CACHE)))
            n = vertex_normals(self._first_v, self.faces)[torso]
            _SHARP_CACHE[key] = torso[sharp_vertices(v, n)]
        return _SHARP_CACHE[key]

    # ------------------------------------------------------------------ reports
    def reset_stats(self) -> None:
        self.stats[:] = 0
        self.timings = Timings()

    def depth_maps(self):
        """(front depth (H,W), back depth (H,W), covered (H,W) bool, matrix 3×4) of the current
        frame, or None when this mode has no maps."""
        if self.maps is None or self.v1 is None:
            return None
        self._ensure_maps()
        f, b, cov = self.maps.front_back(self.maps.cur)
        return f, b, cov, self.maps.matrix.copy()

    def describe(self) -> dict:
        d = {"mode": self.mode, "thickness": self.thickness, "friction": self.friction,
             "map_parts": [PART_NAMES[p] for p in np.nonzero(self.map_parts)[0]],
             "tree_parts": [PART_NAMES[p] for p in np.nonzero(self.tree_parts)[0]],
             "edge_fallback": self.edge_fallback, "limb_fallback": self.limb_fallback,
             "second_surface": self.second_surface}
        if self.maps is not None:
            d["map_size"] = list(self.maps.size)
        if self.tree is not None:
            d["hierarchy_nodes"] = int(self.tree.n_nodes)
            d["triangle_duplication"] = round(float(self.tree.dup), 3)
        return d


def make_collider(mode, body_faces, parts, **options) -> Collider:
    """A collider in ``mode`` (``hybrid``: torso+head in depth maps, limbs in hierarchies;
    ``image``: the whole body in depth maps; ``object``: every part in hierarchies) for a body
    with faces (M,3) and per-vertex ``parts`` (N,) (0 torso+head, 1 left arm, 2 right arm,
    3 left leg, 4 right leg). Options: see :class:`Collider` (thickness, friction, map_size,
    search_radius, max_depth, reuse_tol, leaf_size, edge_fallback, limb_fallback,
    second_surface, edge_normal_z, skips=Skips(...))."""
    return Collider(mode, body_faces, parts, **options)
