"""The collider's interface and what every mode shares; see :mod:`catwalk.collide` for the
interface and the method.

:class:`Collider` checks the input, keeps the body's two frames (vertices, velocities,
normals), counts the substeps, splits a pass over threads, pushes cloth off the body's sharp
vertices and reports. What a substep does with the cloth points is the mode's
(:meth:`Collider._resolve`): :class:`~catwalk.collide.image.ImageCollider`,
:class:`~catwalk.collide.object.ObjectCollider` and
:class:`~catwalk.collide.hybrid.HybridCollider`, each with the passes it holds — the depth
maps' (:class:`~catwalk.collide.image_pass.ImagePass`) and the hierarchies'
(:class:`~catwalk.collide.object_pass.ObjectPass`). Make one with
:func:`~catwalk.collide.modes.make_collider`.
"""

from __future__ import annotations

import hashlib
import queue
import time
import weakref
from concurrent.futures import ThreadPoolExecutor, wait
from dataclasses import dataclass, field, fields
from typing import NamedTuple

import numpy as np

from catwalk.body.types import PART_NAMES, PART_TORSO
from catwalk.cloth.state import PLANE_COLUMNS, PLANE_NORMAL
from catwalk.collide import bvh as B
from catwalk.collide.kernels.boxes import bounds
from catwalk.collide.kernels.object_inputs import Workspace
from catwalk.collide.kernels.record import REC_COLUMNS
from catwalk.collide.kernels.stats import N_STATS
from catwalk.collide.sharp import SHARP_DEPTH, push_off_sharp, sharp_vertices
from catwalk.errors import InputError
from catwalk.geometry.raster import incident_faces, vertex_normals, vertex_normals_kernel

# CPU time of this thread: on a shared machine, wall time also counts other processes' turns
cpu_time = time.thread_time

N_PARTS = len(PART_NAMES)
#: an empty mask of points: a pass's ``only`` when it looks at every point, the image pass's
#: ``edge`` when it leaves none to object space
NO_MASK = np.zeros(0, bool)
#: m: the widest band round the body in which points not held get contact planes
MAX_PLANE_BAND = 0.05


@dataclass
class Skips:
    """The work-saving shortcuts, each switchable (the benchmark measures what each saves)."""

    unreached_parts: bool = True   # parts whose swept box cannot reach the cloth get no work
    still_torso: bool = True       # depth maps not re-rendered when the mapped parts did not move
    far_points: bool = True        # points far from every part skip the narrow phase
    reuse_closest: bool = True     # closest triangle reused while a point barely moved
    clearance: bool = True         # a point known to be far skips work until it could touch

    @classmethod
    def names(cls) -> tuple[str, ...]:
        """The skips' names (each switchable alone: ``Settings.skips_off``)."""
        return tuple(f.name for f in fields(cls))

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


#: m. At the frame kept (``Substep.final``), a point the object passes pushed farther than this
#: is looked at again: a push of d leaves a point that was outside every surface at most d
#: inside any of them
RECHECK_MOVE = 0.0005


def to_look_again(held: np.ndarray, pos: np.ndarray, start: np.ndarray,
                  on_limb: np.ndarray) -> np.ndarray:
    """(P,) bool: the points the frame kept looks at again — held ones that the object
    passes pushed farther than :data:`RECHECK_MOVE` from ``start`` (one pushed out along a
    triangle may have gone behind another of the same part where the skinned mesh folds),
    or that a limb holds (``on_limb``: a kept triangle is not checked against its own
    part's others)."""
    d = pos - start
    return held & ((np.einsum("ij,ij->i", d, d) > RECHECK_MOVE * RECHECK_MOVE) | on_limb)


class Substep(NamedTuple):
    """One :meth:`Collider.resolve` call as the passes take it: the cloth's positions,
    velocities (fixed in place) and previous positions, the substep's time and the previous
    call's in the frame, and the box of both sets of positions. ``final``: the answer is the
    frame the caller keeps (a walk's recorded frame): the object passes look once more at the
    points they pushed, each searched afresh (the modes' ``_resolve``)."""

    pos: np.ndarray
    vel: np.ndarray
    prev: np.ndarray
    alpha: float
    alpha_prev: float
    lo: np.ndarray
    hi: np.ndarray
    final: bool = False


def _workspace(stats: np.ndarray | None = None) -> Workspace:
    """A thread's scratch for the object passes (the kernels never allocate): the
    hierarchy walk's stack, the part reach, two scratch arrays, and its counters (``stats``,
    or new ones)."""
    return Workspace(np.empty(B.STACK_SIZE, np.int64), np.zeros(N_PARTS, bool), np.zeros(2),
                       np.zeros((1, REC_COLUMNS), np.float32),
                       np.zeros(N_STATS, np.int64) if stats is None else stats)


def face_parts(faces, parts) -> np.ndarray:
    """Each face's part: the label most of its vertices carry (its first vertex's on a tie)."""
    p = np.asarray(parts, dtype=np.int64)[np.asarray(faces, dtype=np.int64)]
    a, b, c = p[:, 0], p[:, 1], p[:, 2]
    return np.where((b == c) & (a != b), b, a).astype(np.int8)


def _checked_body(body_faces, parts) -> tuple[np.ndarray, np.ndarray]:
    faces = np.asarray(body_faces)
    if faces.ndim != 2 or faces.shape[1] != 3 or len(faces) == 0:
        raise InputError(f"body faces must be a non-empty (M, 3) array, got {faces.shape}")
    parts = np.asarray(parts)
    if parts.ndim != 1 or (faces.max() >= len(parts)) or faces.min() < 0:
        raise InputError("parts must give one label per body vertex, covering the faces")
    if parts.min() < 0 or parts.max() >= N_PARTS:
        raise InputError("part labels must be 0 (torso+head) … 4 (right leg)")
    return faces, parts


@dataclass(frozen=True)
class ColliderOptions:
    """The options every mode takes (:func:`~catwalk.collide.make_collider`'s keywords, as
    given; :meth:`checked` raises on a bad one). Lengths in metres."""

    map_size: int | tuple[int, int] = (256, 256)   # depth-map pixels (width, height), or one
    thickness: float = 0.004        # the cloth's: points are kept this far off the surface
    friction: float = 0.3           # Coulomb's μ of the response
    contact_slack: float = 0.0005   # a point within thickness + this is held
    search_radius: float = 0.02     # how far the object passes look beyond a point's motion
    max_depth: float = 0.02         # deeper, a point collides only if it crossed the surface
    reuse_tol: float = 0.002        # a point's closest triangle is kept while it moves less
    leaf_size: int = 8              # triangles in a hierarchy's leaf
    map_margin: float = 0.03        # round the mapped parts' box, of the maps' grid
    still_tol: float = 1e-6         # the mapped parts moved less: the maps are not redrawn
    min_normal_z: float = 0.2       # a map's normal leans to at least this slope to its camera
    edge_normal_z: float = 0.5      # hybrid: a slope below this is left to object space
    map_region_pad: float = 0.05    # round the region the cloth can reach, of the maps drawn
    # a point near its closest part may be inside another one (cloth pinched between a hand
    # and the thigh, an arm and the torso): look for it (kernels.second_surface)
    second_surface: bool = True
    skips: Skips | None = None      # the shortcuts (None: all on)
    threads: int = 1                # the object passes over slices of the points at once
    plane_band: float = 0.0         # points not held but this near get a contact plane too

    def checked(self) -> tuple[int, int]:
        """Raise on a bad option; returns the map size (width, height)."""
        if not (np.isfinite(self.plane_band) and 0.0 <= self.plane_band <= MAX_PLANE_BAND):
            raise InputError(f"plane_band must be within 0–{MAX_PLANE_BAND} m, "
                             f"got {self.plane_band!r}")
        for name in ("thickness", "search_radius", "max_depth"):
            val = getattr(self, name)
            if not (np.isfinite(val) and val > 0):
                raise InputError(f"{name} must be a positive length in metres, got {val!r}")
        if not (np.isfinite(self.edge_normal_z) and 0.0 <= self.edge_normal_z <= 1.0):
            raise InputError(f"edge_normal_z must be within 0..1, got {self.edge_normal_z!r}")
        if not (np.isfinite(self.friction) and self.friction >= 0):
            raise InputError(f"friction must be >= 0, got {self.friction!r}")
        threads = self.threads
        if isinstance(threads, bool) or not isinstance(threads, (int, np.integer)) or \
                not 1 <= threads <= 64:
            raise InputError(f"threads must be a whole number within 1–64, got {threads!r}")
        map_size = self.map_size
        ms = (map_size, map_size) if np.isscalar(map_size) else tuple(map_size)
        if len(ms) != 2 or min(ms) < 8 or max(ms) > 8192:
            raise InputError(f"map size must be 8..8192 pixels, got {map_size!r}")
        return ms


#: the torso's sharp vertices per first pose (a digest of its torso vertices): a worker
#: dresses many garments on one body, and finding them costs ≈ 40 ms
_SHARP_CACHE: dict = {}


class Collider:
    """Cloth–body collider: the interface every mode implements (:mod:`catwalk.collide`).
    Make one with :func:`~catwalk.collide.make_collider`; a mode's class sets which parts go
    in the depth maps and which in hierarchies (:meth:`_use_parts`), makes the passes it
    needs and answers a substep's points in :meth:`_resolve`."""

    mode: str = ""
    #: options only this mode takes (make_collider drops another mode's)
    MODE_OPTIONS: tuple[str, ...] = ()
    edge_fallback = False   # hybrid's fallbacks (hybrid.py); off in the other modes
    limb_fallback = False

    def __init__(self, body_faces, parts, **options):
        """``options``: :class:`ColliderOptions`' fields by name."""
        o = ColliderOptions(**options)
        faces, parts = _checked_body(body_faces, parts)
        self._map_size = o.checked()
        self.faces = np.ascontiguousarray(faces, dtype=np.int64)
        self.parts = parts.astype(np.int8)
        self.n_vertices = len(parts)
        self.face_part = face_parts(self.faces, self.parts)
        self._present = np.bincount(self.face_part, minlength=N_PARTS) > 0   # parts with faces
        self._take_options(o)
        # the parts in the depth maps, in hierarchies, with a hierarchy: the mode's (_use_parts)
        self.map_parts, self.tree_parts, self.hier_parts = np.zeros((3, N_PARTS), bool)
        self._image_pass = None    # image_pass.ImagePass: the depth maps, for the mapped parts
        self._object_pass = None   # object_pass.ObjectPass: the hierarchies, for hier_parts
        self._init_frames()
        # with threads > 1 the object passes run over slices of the points at once, each
        # thread with its own workspaces (kernels.object_space.object_pass; the image pass
        # stays on the calling thread)
        self._pool = None
        self._thread_ws = [_workspace() for _ in range(self.threads - 1)]
        self.stats = np.zeros(N_STATS, np.int64)
        self._ws = _workspace(self.stats)   # the calling thread's
        # (P, 8) after each resolve: the contact planes of the held points and of those within
        # plane_band of the surface (normal, offset, the body's velocity, friction; normal 0
        # for the others), see kernels.response.record_plane
        self.planes = np.zeros((0, PLANE_COLUMNS))
        self.timings = Timings()
        self._first_v = None          # the first pose given to update()
        self._sharp = None            # the body's sharp vertices (collide/sharp.py)
        self._sharp_csr = None
        self._sharp_csr_key = None
        self._sharp_src = self._sharp_tris = None   # the triangles last given, as given/int64
        self._sharp_n = -1

    def _take_options(self, o: ColliderOptions) -> None:
        """The options as the collider's attributes (numbers as float, int or bool; the
        callers may change ``friction`` between walks)."""
        self._map_margin = float(o.map_margin)
        self.thickness = float(o.thickness)
        self.friction = float(o.friction)
        self.contact_slack = float(o.contact_slack)
        self.plane_band = float(o.plane_band)
        self.search_radius = float(o.search_radius)
        self.max_depth = float(o.max_depth)
        self.reuse_tol = float(o.reuse_tol)
        self.still_tol = float(o.still_tol)
        self.min_normal_z = float(o.min_normal_z)
        self.edge_normal_z = float(o.edge_normal_z)
        self.map_region_pad = float(o.map_region_pad)
        self.leaf_size = int(o.leaf_size)
        self.second_surface = bool(o.second_surface)
        self.skips = o.skips or Skips()
        self.threads = int(o.threads)

    def _init_frames(self):
        """No body frame yet: :meth:`update` gives them."""
        self._normals_ready = False
        self.v0 = self.v1 = self.w0 = self.w1 = self.n0 = self.n1 = None
        self._frame = -1
        self._alpha_last = 0.0
        self._calls = 0
        self._calls_last_frame = 0
        self._substeps = None

    def _use_parts(self, in_maps, in_tree, mapped_in_tree: bool = False) -> None:
        """The parts ``in_maps`` go in the depth maps (:attr:`map_parts`), those of ``in_tree``
        with faces in hierarchies (:attr:`tree_parts`); ``mapped_in_tree``: the mapped parts
        with faces get a hierarchy too (:attr:`hier_parts`: every part with one)."""
        self.map_parts = np.zeros(N_PARTS, bool)
        self.map_parts[list(in_maps)] = True
        self.tree_parts = np.zeros(N_PARTS, bool)
        self.tree_parts[list(in_tree)] = True
        self.tree_parts &= self._present
        self.hier_parts = self.tree_parts | (self.map_parts & self._present & mapped_in_tree)

    def _on_limb(self, tri: np.ndarray) -> np.ndarray:
        """(P,) bool: the points whose kept triangle ``tri`` (an object pass's ``cache_tri``,
        −1: none) is a limb's."""
        return (tri >= 0) & (self.face_part[np.maximum(tri, 0)] != PART_TORSO)

    def _mapped_faces(self) -> np.ndarray:
        """The faces of the parts in the depth maps (:attr:`map_parts`)."""
        return np.nonzero(self.map_parts[self.face_part])[0]

    @property
    def maps(self):
        """The depth maps (:class:`~catwalk.collide.image_pass.DepthMaps`), or None when this
        collider maps no part."""
        return None if self._image_pass is None else self._image_pass.maps

    @property
    def tree(self):
        """The parts' hierarchies (:func:`catwalk.collide.bvh.build`, from the first frame's
        pose), or None before the first frame or when no part has one."""
        return None if self._object_pass is None else self._object_pass.tree

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
        self._next_frame(v, w, first)
        self._frame += 1
        self._calls_last_frame = self._calls if not first else 0
        self._calls = 0
        self._substeps = int(substeps) if substeps is not None else (
            self._calls_last_frame or None)
        self._alpha_last = 0.0
        self._normals_ready = False
        self.timings.frames += 1
        for p in (self._object_pass, self._image_pass):
            if p is not None:
                p.new_frame(self, first)

    def _next_frame(self, v, w, first: bool) -> None:
        """The current frame becomes the previous one; ``v``, ``w`` the current."""
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

    def _ensure_normals(self):
        """The body's vertex normals at both frames (:attr:`n0`, :attr:`n1`)."""
        if self._normals_ready:
            return
        t = cpu_time()
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
        self.timings.normals += cpu_time() - t

    # ------------------------------------------------------------------ per substep
    def resolve(self, positions, velocities, previous_positions, alpha: float | None = None,
                final: bool = False):
        """Collide cloth points with the body at this substep; fixes ``positions`` and
        ``velocities`` (float64 (P,3), C-contiguous) in place and returns the held mask (P,)
        bool. ``alpha``: the substep's time in [0, 1] between the previous and the current
        body frame (default: from the substep count, see :meth:`update`). ``final``: this
        answer is the frame the caller keeps (a walk's recorded frame): the points pushed are
        looked at once more, each searched afresh — one pushed off a triangle may have gone
        behind another where the body folds onto itself, or have been held against a kept
        triangle while another of the same part came over it. Afterwards
        :attr:`planes` holds the contact plane of each held point and of each point within
        ``plane_band`` of the surface (zero normal for the others)."""
        if self.v1 is None:
            raise InputError("collider.update(body) must be called before resolve()")
        pos, vel = positions, velocities
        for name, a in (("positions", pos), ("velocities", vel)):
            if not (isinstance(a, np.ndarray) and a.dtype == np.float64 and a.ndim == 2 and
                    a.shape[1] == 3 and a.flags.c_contiguous and a.flags.writeable):
                raise InputError(f"{name} must be a writable C-contiguous float64 (P, 3) array")
        if vel.shape != pos.shape:
            raise InputError("positions and velocities differ in shape")
        prev = np.ascontiguousarray(previous_positions, dtype=np.float64)
        if prev.shape != pos.shape:
            raise InputError("previous positions differ in shape from positions")
        alpha, alpha_prev = self._substep_time(alpha)
        n = len(pos)
        held = np.zeros(n, dtype=bool)
        if self.planes.shape[0] != n:
            self.planes = np.zeros((n, PLANE_COLUMNS))
        else:
            self.planes[:, PLANE_NORMAL:PLANE_NORMAL + 3] = 0.0
        if n == 0:
            return held
        lo = np.full(3, np.inf)
        hi = np.full(3, -np.inf)
        bounds(pos, lo, hi)
        bounds(prev, lo, hi)
        self._resolve(Substep(pos, vel, prev, alpha, alpha_prev, lo, hi, bool(final)), held)
        return held

    def _substep_time(self, alpha: float | None) -> tuple[float, float]:
        """This call's time in the frame (given, or counted) and the previous call's."""
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
        return alpha, alpha_prev

    def _resolve(self, s: Substep, held: np.ndarray) -> None:
        """The mode's answer to a substep's (non-empty) points: fix ``s.pos`` and ``s.vel``,
        set ``held`` and :attr:`planes` for the points in contact."""
        raise NotImplementedError

    def _split(self, points, n, only=NO_MASK):
        """``points(start, stop, stack, reach, spd, rec2, stats)`` over all ``n`` points (of
        which those marked in ``only`` are looked at, all when it is empty): at once on one
        thread (also when those are too few to share), or over slices on ``threads`` threads —
        4 slices a thread, taken as threads come free (the cost per point varies along the
        garment), the calling thread one of them with the collider's own workspaces, each
        other with its own (its counters added to :attr:`stats` after)."""
        own = self._ws
        if self.threads == 1 or (
                int(np.count_nonzero(only)) if len(only) else n) < 64 * self.threads:
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

    # ------------------------------------------------------------------ per frame, after
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
            self._sharp_triangles(triangles, len(x))
        tris = self._sharp_tris
        if moved is None:
            moved = np.zeros(0, bool)
        elif not (isinstance(moved, np.ndarray) and moved.dtype == bool
                  and moved.shape == (len(x),)):
            raise InputError("moved must be a (P,) bool array")
        self._ensure_normals()
        if self._sharp is None:
            self._sharp = self._sharp_vertices()
        t = cpu_time()
        n = push_off_sharp(x, tris, *self._sharp_csr, self._sharp, self.v1, self.n1,
                           self.thickness, SHARP_DEPTH, 0.02, moved)
        self.timings.sharp += cpu_time() - t
        self.timings.sharp_pushes += int(n)
        return int(n)

    def _sharp_triangles(self, triangles, n_points: int) -> None:
        """Take new cloth triangles: a walk passes the same triangles every frame, converted,
        checked and their incidence built once per array (held here, so its identity is not
        reused; a model's triangles are never changed in place)."""
        tris = np.ascontiguousarray(triangles, dtype=np.int64)
        if tris.ndim != 2 or tris.shape[1] != 3 or tris.min() < 0 or tris.max() >= n_points:
            raise InputError("cloth triangles must be (T, 3) indices of the positions")
        key = (hashlib.blake2b(tris.tobytes(), digest_size=16).digest(), n_points)
        if self._sharp_csr_key != key:
            self._sharp_csr = incident_faces(tris, n_points)
            self._sharp_csr_key = key
        self._sharp_src, self._sharp_n, self._sharp_tris = triangles, n_points, tris

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
        self._image_pass.ensure(self)
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
