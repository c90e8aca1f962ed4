"""Object space: the paper's per-limb hierarchy (§4 "Object-space details") and its kernels.

Each part's triangles go into a binary hierarchy that halves the node's box with a plane across
its largest dimension (spatial median, no search for the best split: body triangles are small
and evenly spread). A triangle spanning the plane goes into *both* halves; no triangle is split.
The topology is built once from the rest pose; each frame only the bounds are refitted
(:func:`refit_frame`): a node keeps its box at the previous and at the current frame, and the
walk (:func:`closest_triangle_t`) reads their blend at the substep's time, which bounds the body
at every substep in between — blended once a substep for all the walks of that substep, with the
vertices, into one table of the nodes (:func:`blend_at`; the boxes swept over the frame and the
nodes' speeds once a frame, :func:`swept_boxes`).

All parts' hierarchies live in one set of flat arrays (:class:`Hierarchy`); nodes are in
pre-order, so children come after parents and a refit walks a part's node range backwards.
"""

from __future__ import annotations

import math
from collections import namedtuple
from dataclasses import dataclass

import numba
import numpy as np

from catwalk.geometry.triangles import closest_on_triangle

#: the body's vertex positions at both frames (``vp`` (N, VP_COLUMNS) float32, which the
#: hierarchies are refitted from): the previous frame's xyz (VP_X0) and the current one's (VP_X1)
VP_X0, VP_X1 = 0, 3
VP_COLUMNS = 6
#: a box's columns (``Hierarchy.bounds`` rows, the build's): lo xyz, hi xyz
BOX_LO, BOX_HI = 0, 3
#: a node's links (``Hierarchy.links`` rows, int64): its children (−1 in a leaf) and a leaf's
#: slice of ``tris``
LINK_LEFT, LINK_RIGHT, LINK_START, LINK_COUNT = 0, 1, 2, 3
#: the nodes' boxes refitted at both frames (``nb`` (K, NB_COLUMNS) float32, :func:`refit_frame`):
#: lo and hi at the previous frame (NB_LO0, NB_HI0) and at the current one (NB_LO1, NB_HI1: a
#: frame's box starts at NB_FRAME × its index), the node's speed (NB_SPEED,
#: :func:`node_speeds`); 13–15 unused
NB_LO0, NB_HI0, NB_LO1, NB_HI1, NB_SPEED = 0, 3, 6, 9, 12
NB_FRAME = 6
NB_COLUMNS = 16
#: the nodes' table the searches read (``nbl`` (K, NODE_COLUMNS) float64): the box at the
#: search's time (lo NL_LO, hi NL_HI) and its centre (NL_CENTRE), by :func:`blend_at`; the box
#: swept over the frame in the frame moving with the reference displacement (NL_SWEPT_LO,
#: NL_SWEPT_HI) and the node's speed (NL_SPEED), by :func:`swept_boxes`
NL_LO, NL_HI, NL_CENTRE, NL_SWEPT_LO, NL_SWEPT_HI, NL_SPEED = 0, 3, 6, 9, 12, 15
NODE_COLUMNS = 16
#: a search's speed accumulators (``spd`` (2,), :func:`closest_triangle_t`): the max over the
#: nodes pruned of their speed less their distance over the rest of the frame, and the max
#: speed of the leaves visited
SPD_PRUNED, SPD_LEAVES = 0, 1
#: a search's time (:func:`closest_triangle_t`): ``alpha`` of the frame, the frame's reference
#: displacement (``rx``, ``ry``, ``rz``: the swept boxes' moving frame) and 1 / the rest of the
#: frame (``inv_t``)
SearchTime = namedtuple("SearchTime", "alpha rx ry rz inv_t")
#: the hierarchies as the searches read them at one time (:func:`blend_at`): the vertices
#: ``vpl``, each reference's vertices ``lf``, the nodes' table ``nbl``, ``links``, ``tris``
TreeAt = namedtuple("TreeAt", "vpl lf nbl links tris")


@dataclass
class Hierarchy:
    """Flat arrays for several parts' hierarchies.

    ``bounds`` (K,6) node boxes (:data:`BOX_LO`, :data:`BOX_HI`); ``links`` (K,4)
    (:data:`LINK_LEFT`, right, start, count): children (−1 in leaves) and a leaf's slice of
    ``tris`` (global face indices);
    ``root[p]``/``end[p]``: part p's node range [root, end) (root = end when the part has no
    hierarchy); ``dup``: triangle references / triangles (duplication across split planes)."""

    bounds: np.ndarray
    links: np.ndarray
    tris: np.ndarray
    root: np.ndarray
    end: np.ndarray
    dup: float

    @property
    def n_nodes(self) -> int:
        return len(self.links)

    @property
    def left(self) -> np.ndarray:
        return self.links[:, LINK_LEFT]


def build(vertices, faces, part_faces: dict, leaf_size: int = 8, max_depth: int = 30,
          n_parts: int = 5, max_dup: float = 1.25) -> Hierarchy:
    """Build hierarchies for ``part_faces`` {part: face indices} over ``vertices`` (rest).

    A node is halved by a plane across the largest dimension of its box (the box of its
    triangles); a triangle spanning the plane goes to both halves, one merely touching it to
    its side only. A node becomes a leaf at ``leaf_size`` triangles or fewer, at ``max_depth``,
    or when halving it would put more than ``max_dup`` × its triangles into the two halves
    (the box is then about as small as its triangles, and splitting further only copies them):
    then the other two axes are tried, and a big node (> 4 × leaf_size) still splits on the
    axis that copies fewest, if that is below 1.5 ×."""
    v = np.asarray(vertices, dtype=np.float64)
    f = np.asarray(faces, dtype=np.int64)
    tv = v[f]
    tlo = np.ascontiguousarray(tv.min(axis=1))
    thi = np.ascontiguousarray(tv.max(axis=1))
    root = np.zeros(n_parts, np.int64)
    end = np.zeros(n_parts, np.int64)
    bounds_l, links_l, tris_l = [], [], []
    n_nodes = n_refs = n_tris = 0
    for p in range(n_parts):
        ids = np.asarray(part_faces.get(p, []), dtype=np.int64)
        root[p] = n_nodes
        if len(ids) == 0:
            end[p] = n_nodes
            continue
        n_tris += len(ids)
        cap = 8 * len(ids) + 64
        while True:  # capacities are guesses: grow until the build fits
            bounds = np.empty((cap // 2, 6))
            links = np.empty((cap // 2, 4), np.int64)
            tris = np.empty(cap, np.int64)
            scratch = np.empty(4 * cap, np.int64)
            nn, nr = _build_kernel(tlo, thi, ids, leaf_size, max_depth, max_dup, bounds, links,
                                   tris, scratch)
            if nn >= 0:
                break
            cap *= 2
        links = links[:nn].copy()
        inner = links[:, LINK_LEFT] >= 0
        links[inner, LINK_LEFT] += n_nodes
        links[inner, LINK_RIGHT] += n_nodes
        links[~inner, LINK_START] += n_refs
        bounds_l.append(bounds[:nn])
        links_l.append(links)
        tris_l.append(tris[:nr])
        n_nodes += nn
        n_refs += nr
        end[p] = n_nodes
    if not n_nodes:
        return Hierarchy(np.zeros((0, 6)), np.zeros((0, 4), np.int64), np.zeros(0, np.int64),
                         root, end, 1.0)
    return Hierarchy(np.ascontiguousarray(np.vstack(bounds_l)),
                     np.ascontiguousarray(np.vstack(links_l)), np.concatenate(tris_l), root, end,
                     n_refs / max(n_tris, 1))


@numba.njit(cache=True)
def _build_kernel(tlo, thi, ids, leaf_size, max_depth, max_dup, bounds, links, tris, scratch):
    """Depth-first build of one part's hierarchy (see :func:`build`) into preallocated arrays;
    returns (nodes, triangle references), or (−1, −1) when a buffer was too small.

    The triangles' boxes ``tlo``/``thi`` (T,3); ``scratch``: the id lists of the nodes on the
    stack, each node's children's lists going on top of the live ones."""
    n = ids.shape[0]
    # the stack: per entry its ids' slice of scratch, box, depth, and the parent to link
    # (−1: the root, or a left child; else the node whose *right* child it is)
    max_stack = 2 * max_depth + 4
    stack = (np.empty(max_stack, np.int64), np.empty(max_stack, np.int64),
             np.empty((max_stack, 6)), np.empty(max_stack, np.int64),
             np.empty(max_stack, np.int64))
    st_start, st_len, st_box, st_depth, st_parent = stack
    if 4 * n > scratch.shape[0]:
        return -1, -1
    for k in range(n):
        scratch[k] = ids[k]
    st_start[0] = 0
    st_len[0] = n
    _box_of(tlo, thi, scratch, 0, n, st_box, 0)
    st_depth[0] = 0
    st_parent[0] = -1
    sp = 1
    nn = 0
    nr = 0
    blo = np.empty(3)
    bhi = np.empty(3)
    while sp > 0:
        sp -= 1
        s0 = st_start[sp]
        m = st_len[sp]
        depth = st_depth[sp]
        # scratch above this list and the live lists below it on the stack is free again
        top = s0 + m
        if sp > 0:
            top = max(top, st_start[sp - 1] + st_len[sp - 1])
        for q in range(3):
            blo[q] = st_box[sp, BOX_LO + q]
            bhi[q] = st_box[sp, BOX_HI + q]
        if nn >= bounds.shape[0]:
            return -1, -1
        idx = nn
        nn += 1
        if st_parent[sp] >= 0:
            links[st_parent[sp], LINK_RIGHT] = idx
        _box_of(tlo, thi, scratch, s0, m, bounds, idx)
        links[idx, LINK_LEFT] = -1
        links[idx, LINK_RIGHT] = -1
        links[idx, LINK_START] = 0
        links[idx, LINK_COUNT] = 0
        axis = -1
        mid = 0.0
        if m > leaf_size and depth < max_depth:
            axis, mid = _split_plane(tlo, thi, scratch, s0, m, bounds, idx, leaf_size, max_dup)
        if axis < 0:
            if nr + m > tris.shape[0]:
                return -1, -1
            links[idx, LINK_START] = nr
            links[idx, LINK_COUNT] = m
            for k in range(s0, s0 + m):
                tris[nr] = scratch[k]
                nr += 1
            continue
        # children's id lists go on top of scratch: left, then right
        if top + 2 * m > scratch.shape[0] or sp + 2 > max_stack:
            return -1, -1
        ls, rs, top = _partition(tlo, thi, scratch, s0, m, top, axis, mid)
        # push right first (popped after the whole left subtree), then left (next node)
        _push(stack, sp, rs, top - rs, blo, bhi, BOX_LO + axis, mid, depth + 1, idx)
        _push(stack, sp + 1, ls, rs - ls, blo, bhi, BOX_HI + axis, mid, depth + 1, -1)
        sp += 2
        links[idx, LINK_LEFT] = idx + 1
    return nn, nr


@numba.njit(cache=True)
def _box_of(tlo, thi, scratch, s0, m, out, row):
    """``out[row]`` (:data:`BOX_LO`, :data:`BOX_HI`): the box of the triangles
    ``scratch[s0 : s0 + m]``."""
    for q in range(3):
        out[row, BOX_LO + q] = np.inf
        out[row, BOX_HI + q] = -np.inf
    for k in range(s0, s0 + m):
        t = scratch[k]
        for q in range(3):
            out[row, BOX_LO + q] = min(out[row, BOX_LO + q], tlo[t, q])
            out[row, BOX_HI + q] = max(out[row, BOX_HI + q], thi[t, q])


@numba.njit(cache=True)
def _split_plane(tlo, thi, scratch, s0, m, bounds, idx, leaf_size, max_dup):
    """Where node idx (its triangles ``scratch[s0 : s0 + m]``, its box ``bounds[idx]``) is
    halved: its box's largest dimension at its middle; if that copies too many triangles into
    both halves (more than ``max_dup`` × m), the axis that copies fewest (big nodes must
    split). Returns (axis, the plane's coordinate), axis −1 for a leaf."""
    axis = -1
    mid = 0.0
    best_sum = m * 3
    best_axis = 0
    best_mid = 0.0
    first = True
    ax0 = 0
    ax1 = 0
    for rank in range(3):
        # axes by decreasing extent
        a = 0
        ea = -1.0
        for q in range(3):
            e = bounds[idx, BOX_HI + q] - bounds[idx, BOX_LO + q]
            taken = (rank >= 1 and q == ax0) or (rank >= 2 and q == ax1)
            if not taken and e > ea:
                ea = e
                a = q
        if rank == 0:
            ax0 = a
        elif rank == 1:
            ax1 = a
        if not (ea > 0.0):
            continue
        md = 0.5 * (bounds[idx, BOX_LO + a] + bounds[idx, BOX_HI + a])
        nl, nrr = _split_counts(tlo, thi, scratch, s0, m, a, md)
        if nl < m and nrr < m:
            if first and nl + nrr <= max_dup * m:
                axis = a
                mid = md
                break
            if nl + nrr < best_sum:
                best_sum = nl + nrr
                best_axis = a
                best_mid = md
        first = False
    if axis < 0 and best_sum < m * 3:
        if best_sum <= max_dup * m or (m > 4 * leaf_size and best_sum <= 1.5 * m):
            axis = best_axis
            mid = best_mid
    return axis, mid


@numba.njit(cache=True)
def _split_counts(tlo, thi, scratch, s0, m, axis, mid):
    """How many of the triangles ``scratch[s0 : s0 + m]`` go left and right of the plane at
    ``mid`` across ``axis`` (one spanning it goes both ways, one merely touching it to its
    side)."""
    nl = 0
    nr = 0
    for k in range(s0, s0 + m):
        t = scratch[k]
        r = thi[t, axis] > mid
        if r:
            nr += 1
        if tlo[t, axis] < mid or not r:
            nl += 1
    return nl, nr


@numba.njit(cache=True)
def _partition(tlo, thi, scratch, s0, m, top, axis, mid):
    """The children's id lists of the triangles ``scratch[s0 : s0 + m]`` split at ``mid``
    across ``axis``, written from ``top`` on: left, then right. Returns (left's start,
    right's start, the new top)."""
    ls = top
    for k in range(s0, s0 + m):
        t = scratch[k]
        if tlo[t, axis] < mid or not (thi[t, axis] > mid):
            scratch[top] = t
            top += 1
    rs = top
    for k in range(s0, s0 + m):
        t = scratch[k]
        if thi[t, axis] > mid:
            scratch[top] = t
            top += 1
    return ls, rs, top


@numba.njit(cache=True)
def _push(stack, sp, start, length, blo, bhi, cut, mid, depth, parent):
    """Stack entry sp: an id list's slice of scratch, its cell (the box ``blo``/``bhi`` with
    column ``cut`` set to ``mid``), its depth and the node to link it to."""
    st_start, st_len, st_box, st_depth, st_parent = stack
    st_start[sp] = start
    st_len[sp] = length
    for q in range(3):
        st_box[sp, BOX_LO + q] = blo[q]
        st_box[sp, BOX_HI + q] = bhi[q]
    st_box[sp, cut] = mid
    st_depth[sp] = depth
    st_parent[sp] = parent


def leaf_vertices(h: Hierarchy, faces) -> tuple[np.ndarray, np.ndarray]:
    """Each leaf's distinct vertices, for :func:`refit_frame`: (``start`` (K+1,), ``verts``)
    with node n's vertices ``verts[start[n]:start[n + 1]]`` in increasing order (none for
    inner nodes). A leaf of ~15 triangles has ~12 distinct vertices: a third of the reads of a
    walk over its triangles' corners."""
    f = np.ascontiguousarray(faces, dtype=np.int64).reshape(-1, 3)
    return _leaf_vertices_kernel(h.links, h.tris, f)


@numba.njit(cache=True)
def _leaf_vertices_kernel(links, tris, faces):
    k = links.shape[0]
    start = np.zeros(k + 1, np.int64)
    room = 0
    nv = 1
    for nd in range(k):
        if links[nd, LINK_LEFT] < 0:
            room += 3 * links[nd, LINK_COUNT]
    for i in range(faces.shape[0]):
        for q in range(3):
            nv = max(nv, faces[i, q] + 1)
    seen = np.full(nv, -1, np.int64)   # the last leaf a vertex was taken for
    out = np.empty(room, np.int64)
    m = 0
    for nd in range(k):
        start[nd] = m
        if links[nd, LINK_LEFT] >= 0:
            continue
        s = links[nd, LINK_START]
        first = m
        for t in range(links[nd, LINK_COUNT]):
            for q in range(3):
                v = faces[tris[s + t], q]
                if seen[v] == nd:
                    continue
                seen[v] = nd
                # insertion into the leaf's sorted run
                j = m
                while j > first and out[j - 1] > v:
                    out[j] = out[j - 1]
                    j -= 1
                out[j] = v
                m += 1
    start[k] = m
    return start, out[:m].copy()


@numba.njit(cache=True, _nrt=False)
def node_speeds(vp, ref, lv_start, lv, links, nb, first, last):
    """``nb[:, NB_SPEED]``: how far any vertex of the node moves over the frame relative to the
    reference displacement ``ref``, as the norm of the per-axis maxima — a bound on how
    fast the node's (blended) box, and any of its triangles, approaches a point that moves
    with ``ref``."""
    for nd in range(last - 1, first - 1, -1):
        if links[nd, LINK_LEFT] < 0:
            mx = 0.0
            my = 0.0
            mz = 0.0
            for s in range(lv_start[nd], lv_start[nd + 1]):
                v = lv[s]
                mx = max(mx, abs(vp[v, VP_X1] - vp[v, VP_X0] - ref[0]))
                my = max(my, abs(vp[v, VP_X1 + 1] - vp[v, VP_X0 + 1] - ref[1]))
                mz = max(mz, abs(vp[v, VP_X1 + 2] - vp[v, VP_X0 + 2] - ref[2]))
            nb[nd, NB_SPEED] = math.sqrt(mx * mx + my * my + mz * mz) * (1.0 + 1e-6) + 1e-9
        else:
            nb[nd, NB_SPEED] = max(nb[links[nd, LINK_LEFT], NB_SPEED],
                                   nb[links[nd, LINK_RIGHT], NB_SPEED])


@numba.njit(cache=True, _nrt=False)
def refit_frame(vp, col, lv_start, lv, links, nb, first, last):
    """Refit nodes [first, last) (one part) to the body at one frame: node boxes (lo, hi)
    ``nb[:, NB_LO0 + NB_FRAME·col :][:6]`` from the positions
    ``vp[:, VP_X0 + (VP_X1 − VP_X0)·col :][:3]`` (leaves over their distinct vertices ``lv``, see
    :func:`leaf_vertices`; inner nodes the union of their children). The collider keeps a
    node's boxes at the previous (col 0) and the current frame (col 1): the box at any time
    between them is their blend."""
    o = NB_LO0 + NB_FRAME * col
    c3 = VP_X0 + (VP_X1 - VP_X0) * col
    for nd in range(last - 1, first - 1, -1):
        if links[nd, LINK_LEFT] < 0:
            lx = np.inf
            ly = np.inf
            lz = np.inf
            hx = -np.inf
            hy = -np.inf
            hz = -np.inf
            for s in range(lv_start[nd], lv_start[nd + 1]):
                v = lv[s]
                x = vp[v, c3]
                y = vp[v, c3 + 1]
                z = vp[v, c3 + 2]
                lx = min(lx, x)
                hx = max(hx, x)
                ly = min(ly, y)
                hy = max(hy, y)
                lz = min(lz, z)
                hz = max(hz, z)
            h = o + (NB_HI0 - NB_LO0)
            nb[nd, o] = lx
            nb[nd, o + 1] = ly
            nb[nd, o + 2] = lz
            nb[nd, h] = hx
            nb[nd, h + 1] = hy
            nb[nd, h + 2] = hz
        else:
            l = links[nd, LINK_LEFT]
            r = links[nd, LINK_RIGHT]
            h = o + (NB_HI0 - NB_LO0)
            for q in range(3):
                nb[nd, o + q] = min(nb[l, o + q], nb[r, o + q])
                nb[nd, h + q] = max(nb[l, h + q], nb[r, h + q])


@numba.njit(cache=True, _nrt=False)
def swept_boxes(nb, ref, first, last, nbl):
    """Nodes [first, last) (one part) over the frame, once it is refitted: the boxes swept
    over it in the frame moving by ``ref`` (``nbl`` :data:`NL_SWEPT_LO`, :data:`NL_SWEPT_HI`:
    no triangle of the node comes nearer, at any time of the frame, to a point's position in
    that moving frame; :func:`swept_d2`) and the speeds (``nb`` :data:`NB_SPEED` → ``nbl``
    :data:`NL_SPEED`)."""
    for nd in range(first, last):
        for q in range(3):
            nbl[nd, NL_SWEPT_LO + q] = min(nb[nd, NB_LO0 + q], nb[nd, NB_LO1 + q] - ref[q])
            nbl[nd, NL_SWEPT_HI + q] = max(nb[nd, NB_HI0 + q], nb[nd, NB_HI1 + q] - ref[q])
        nbl[nd, NL_SPEED] = nb[nd, NB_SPEED]


@numba.njit(cache=True, _nrt=False, inline="always")
def vp_at(vp, v, k, alpha):
    """Vertex v's position at time ``alpha`` of the frame: k × the previous frame's + alpha ×
    the current one's (k = 1 − alpha)."""
    return (k * vp[v, VP_X0] + alpha * vp[v, VP_X1],
            k * vp[v, VP_X0 + 1] + alpha * vp[v, VP_X1 + 1],
            k * vp[v, VP_X0 + 2] + alpha * vp[v, VP_X1 + 2])


@numba.njit(cache=True, _nrt=False, inline="always")
def box_d2(px, py, pz, nbl, nd):
    """Squared distance from p to node nd's box at the table's time (:func:`blend_at`: the
    blend of its two frames' boxes, which holds every triangle of the node at that time).
    Branch-free (max/min selects): the walks' box tests are otherwise bound by mispredicted
    branches."""
    x = max(max(nbl[nd, NL_LO] - px, px - nbl[nd, NL_HI]), 0.0)
    y = max(max(nbl[nd, NL_LO + 1] - py, py - nbl[nd, NL_HI + 1]), 0.0)
    z = max(max(nbl[nd, NL_LO + 2] - pz, pz - nbl[nd, NL_HI + 2]), 0.0)
    return x * x + y * y + z * z


@numba.njit(cache=True, _nrt=False, inline="always")
def swept_d2(mx, my, mz, nbl, nd):
    """Squared distance from the point (mx, my, mz), given in the frame moving with the
    reference displacement (p − alpha·ref for p at time alpha), to node nd's box swept over
    the frame (:func:`swept_boxes`; branch-free)."""
    x = max(max(nbl[nd, NL_SWEPT_LO] - mx, mx - nbl[nd, NL_SWEPT_HI]), 0.0)
    y = max(max(nbl[nd, NL_SWEPT_LO + 1] - my, my - nbl[nd, NL_SWEPT_HI + 1]), 0.0)
    z = max(max(nbl[nd, NL_SWEPT_LO + 2] - mz, mz - nbl[nd, NL_SWEPT_HI + 2]), 0.0)
    return x * x + y * y + z * z


@numba.njit(cache=True, _nrt=False)
def blend_at(vp, nb, first, last, vidx, alpha, nbl, vpl):
    """One part's pose at time ``alpha`` of the frame, as :func:`closest_triangle_t` reads
    it: its nodes [first, last) in ``nbl`` (:data:`NODE_COLUMNS`) — the box blended between
    the frame's two in ``nb`` (:data:`NL_LO`, :data:`NL_HI`; :func:`box_d2`) and its centre
    (:data:`NL_CENTRE`, by which the walk orders a node's children) — and its vertices ``vidx``
    in ``vpl`` (N,3), blended between the two frames' positions in ``vp`` (:data:`VP_X0`,
    :data:`VP_X1`). Blended once for the many searches at one time (the object pass's at one
    substep) instead of inside every node visit and triangle test."""
    b = 1.0 - alpha
    for nd in range(first, last):
        for q in range(3):
            nbl[nd, NL_LO + q] = b * nb[nd, NB_LO0 + q] + alpha * nb[nd, NB_LO1 + q]
            nbl[nd, NL_HI + q] = b * nb[nd, NB_HI0 + q] + alpha * nb[nd, NB_HI1 + q]
            nbl[nd, NL_CENTRE + q] = 0.5 * (b * (nb[nd, NB_LO0 + q] + nb[nd, NB_HI0 + q])
                                            + alpha * (nb[nd, NB_LO1 + q] + nb[nd, NB_HI1 + q]))
    for k in range(vidx.shape[0]):
        v = vidx[k]
        vpl[v, 0], vpl[v, 1], vpl[v, 2] = vp_at(vp, v, b, alpha)


@numba.njit(cache=True, _nrt=False, inline="always")
def offset_to_triangle(px, py, pz, ax, ay, az, bx, by, bz, cx, cy, cz):
    """q − p, q the point of triangle abc nearest to p."""
    v, w = closest_on_triangle(px, py, pz, ax, ay, az, bx, by, bz, cx, cy, cz)
    return (ax + v * (bx - ax) + w * (cx - ax) - px,
            ay + v * (by - ay) + w * (cy - ay) - py,
            az + v * (bz - az) + w * (cz - az) - pz)


@numba.njit(cache=True, _nrt=False, inline="always")
def _push_children(px, py, pz, nbl, links, nd, stack, sp):
    """Node nd's children onto the stack at ``sp``, the one whose centre is nearer to p on
    top (walked first); returns the new top."""
    l = links[nd, LINK_LEFT]
    r = links[nd, LINK_RIGHT]
    cl = 0.0
    cr = 0.0
    for q in range(3):
        c = px if q == 0 else (py if q == 1 else pz)
        e = nbl[l, NL_CENTRE + q] - c
        cl += e * e
        e = nbl[r, NL_CENTRE + q] - c
        cr += e * e
    if cl < cr:
        stack[sp] = r
        stack[sp + 1] = l
    else:
        stack[sp] = l
        stack[sp + 1] = r
    return sp + 2


@numba.njit(cache=True, _nrt=False, inline="always")
def _leaf_closest(px, py, pz, tree, nd, best_d2, best_t):
    """Leaf nd's triangles nearer to p than √best_d2 (each first by its box, branch-free);
    returns (best_d2, best_t, triangles tested)."""
    vpl = tree.vpl
    lf = tree.lf
    links = tree.links
    tested = 0
    for s in range(links[nd, LINK_START], links[nd, LINK_START] + links[nd, LINK_COUNT]):
        ia = lf[s, 0]
        ib = lf[s, 1]
        ic = lf[s, 2]
        ax = vpl[ia, 0]
        ay = vpl[ia, 1]
        az = vpl[ia, 2]
        bx = vpl[ib, 0]
        by = vpl[ib, 1]
        bz = vpl[ib, 2]
        cx = vpl[ic, 0]
        cy = vpl[ic, 1]
        cz = vpl[ic, 2]
        x = max(max(min(ax, min(bx, cx)) - px, px - max(ax, max(bx, cx))), 0.0)
        y = max(max(min(ay, min(by, cy)) - py, py - max(ay, max(by, cy))), 0.0)
        z = max(max(min(az, min(bz, cz)) - pz, pz - max(az, max(bz, cz))), 0.0)
        d = x * x + y * y + z * z
        if d >= best_d2:
            continue
        tested += 1
        qx, qy, qz = offset_to_triangle(px, py, pz, ax, ay, az, bx, by, bz, cx, cy, cz)
        d = qx * qx + qy * qy + qz * qz
        if d < best_d2:
            best_d2 = d
            best_t = tree.tris[s]
    return best_d2, best_t, tested


@numba.njit(cache=True, _nrt=False)
def closest_triangle_t(px, py, pz, tree, root, at, best_d2, best_t, stack, spd):
    """Closest triangle to p among one part's hierarchy (its ``root``) at the search's time
    (``at``, :data:`SearchTime`), if nearer than √best_d2, with the part's pose at that time
    and its nodes' bounds over the frame (``tree``, :data:`TreeAt`: ``nbl``
    (:data:`NODE_COLUMNS`: the node boxes blended at ``alpha`` — tighter than the box swept
    over the frame: a fast limb is pruned where it is at that time — the centres children are
    ordered by, the boxes swept over the frame and the nodes' speeds; :func:`blend_at`,
    :func:`swept_boxes`), ``vpl`` (N,3) the vertices at ``alpha``, ``lf`` (R,3) int32 the
    vertices of each reference of ``tris`` (a leaf's are read in sequence, not through the
    faces)). Returns (best_d2, best_t, nodes visited, triangles tested, frame_d2): frame_d2 is
    a lower bound of the squared distance, for the whole frame and in the frame moving by the
    reference displacement (rx, ry, rz), from the point to every triangle of the part (over
    the leaves visited and the subtrees pruned).

    ``spd`` (2,) accumulates, for the point's speed bound after the search (see
    :func:`catwalk.collide.kernels.object_space.object_pass`): ``spd[SPD_PRUNED]`` the max over
    pruned nodes of m − d·``inv_t`` (m the node's speed, d its box distance now, inv_t 1 / the
    rest of the frame), ``spd[SPD_LEAVES]`` the max speed of the leaves visited."""
    nbl = tree.nbl
    stack[0] = root
    sp = 1
    visited = 0
    tested = 0
    frame_d2 = np.inf
    # the point in the frame moving with the reference displacement (the swept boxes')
    mx = px - at.alpha * at.rx
    my = py - at.alpha * at.ry
    mz = pz - at.alpha * at.rz
    while sp > 0:
        sp -= 1
        nd = stack[sp]
        visited += 1
        d = box_d2(px, py, pz, nbl, nd)
        if d >= best_d2:
            ds = swept_d2(mx, my, mz, nbl, nd)
            if ds < frame_d2:
                frame_d2 = ds
            sv = nbl[nd, NL_SPEED] - math.sqrt(d) * at.inv_t
            if sv > spd[SPD_PRUNED]:
                spd[SPD_PRUNED] = sv
            continue
        if tree.links[nd, LINK_LEFT] >= 0:
            if sp + 2 > stack.shape[0]:
                frame_d2 = 0.0  # (never: the stack holds 2 × the depth limit)
                continue
            sp = _push_children(px, py, pz, nbl, tree.links, nd, stack, sp)
            continue
        ds = swept_d2(mx, my, mz, nbl, nd)
        if ds < frame_d2:
            frame_d2 = ds
        if nbl[nd, NL_SPEED] > spd[SPD_LEAVES]:
            spd[SPD_LEAVES] = nbl[nd, NL_SPEED]
        best_d2, best_t, nt = _leaf_closest(px, py, pz, tree, nd, best_d2, best_t)
        tested += nt
    return best_d2, best_t, visited, tested, frame_d2


def depth_of(h: Hierarchy, part: int) -> int:
    """The depth of a part's hierarchy (levels), for reports."""
    if h.end[part] <= h.root[part]:
        return 0
    best = 0
    stack = [(int(h.root[part]), 1)]
    while stack:
        nd, d = stack.pop()
        best = max(best, d)
        if h.links[nd, LINK_LEFT] >= 0:
            stack.append((int(h.links[nd, LINK_LEFT]), d + 1))
            stack.append((int(h.links[nd, LINK_RIGHT]), d + 1))
    return best


# a depth-first walk holds at most one sibling per level plus two: 2·max_depth + 2 < 128
STACK_SIZE = 128


@numba.njit(cache=True, _nrt=False)
def swept_lower(mx, my, mz, nbl, links, root, bound2, stack):
    """A lower bound, for the whole frame and in the frame moving by the reference
    displacement (the point (mx, my, mz) given in it, as :func:`swept_d2`), of the squared
    distance from the point to every triangle of one part's hierarchy: the nearest leaf box
    swept over the frame (:func:`swept_boxes`), or ``bound2`` if none is nearer (nodes are
    pruned there). No triangle is tested. Returns (bound, nodes visited)."""
    stack[0] = root
    sp = 1
    visited = 0
    best = bound2
    while sp > 0:
        sp -= 1
        nd = stack[sp]
        visited += 1
        d = swept_d2(mx, my, mz, nbl, nd)
        if d >= best:
            continue
        if links[nd, LINK_LEFT] < 0:
            best = d
            continue
        if sp + 2 > stack.shape[0]:
            best = 0.0  # (never: the stack holds 2 × the depth limit)
            continue
        stack[sp] = links[nd, LINK_LEFT]
        stack[sp + 1] = links[nd, LINK_RIGHT]
        sp += 2
    return best, visited
