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
from dataclasses import dataclass

import numba
import numpy as np

from catwalk.geometry.triangles import closest_on_triangle


@dataclass
class Hierarchy:
    """Flat arrays for several parts' hierarchies.

    ``bounds`` (K,6) node boxes (lo xyz, hi xyz); ``links`` (K,4) (left, right, start, count):
    children (−1 in leaves) and a leaf's slice of ``tris`` (global face indices);
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
        return self.links[:, 0]


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
        inner = links[:, 0] >= 0
        links[inner, :2] += n_nodes
        links[~inner, 2] += n_refs
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
    returns (nodes, triangle references), or (−1, −1) when a buffer was too small."""
    n = ids.shape[0]
    # the stack: per entry its ids' slice of scratch, box, depth, and the parent to link
    max_stack = 2 * max_depth + 4
    st_start = np.empty(max_stack, np.int64)
    st_len = np.empty(max_stack, np.int64)
    st_box = np.empty((max_stack, 6))
    st_depth = np.empty(max_stack, np.int64)
    st_parent = np.empty(max_stack, np.int64)  # −1: root; else the node whose *right* child
    if 4 * n > scratch.shape[0]:
        return -1, -1
    for k in range(n):
        scratch[k] = ids[k]
    sp = 0
    st_start[0] = 0
    st_len[0] = n
    for q in range(3):
        st_box[0, q] = np.inf
        st_box[0, 3 + q] = -np.inf
    for k in range(n):
        t = ids[k]
        for q in range(3):
            st_box[0, q] = min(st_box[0, q], tlo[t, q])
            st_box[0, 3 + q] = max(st_box[0, 3 + q], thi[t, q])
    st_depth[0] = 0
    st_parent[0] = -1
    sp = 1
    nn = 0
    nr = 0
    blo = np.empty(3)
    bhi = np.empty(3)
    ax0 = 0
    ax1 = 0
    best_axis = 0
    while sp > 0:
        sp -= 1
        s0 = st_start[sp]
        m = st_len[sp]
        depth = st_depth[sp]
        parent = st_parent[sp]
        # scratch above this list and the live lists below it on the stack is free again
        top = s0 + m
        if sp > 0:
            top = max(top, st_start[sp - 1] + st_len[sp - 1])
        for q in range(3):
            blo[q] = st_box[sp, q]
            bhi[q] = st_box[sp, 3 + q]
        if nn >= bounds.shape[0]:
            return -1, -1
        idx = nn
        nn += 1
        if parent >= 0:
            links[parent, 1] = idx
        for q in range(3):
            bounds[idx, q] = np.inf
            bounds[idx, 3 + q] = -np.inf
        for k in range(s0, s0 + m):
            t = scratch[k]
            for q in range(3):
                bounds[idx, q] = min(bounds[idx, q], tlo[t, q])
                bounds[idx, 3 + q] = max(bounds[idx, 3 + q], thi[t, q])
        links[idx, 0] = -1
        links[idx, 1] = -1
        links[idx, 2] = 0
        links[idx, 3] = 0
        axis = -1
        mid = 0.0
        if m > leaf_size and depth < max_depth:
            # halve the node's box across its largest dimension; if that copies too many
            # triangles into both halves, the axis that copies fewest (big nodes must split)
            best_sum = m * 3
            best_mid = 0.0
            first = True
            for rank in range(3):
                # axes by decreasing extent
                a = 0
                ea = -1.0
                for q in range(3):
                    e = bounds[idx, 3 + q] - bounds[idx, q]
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
                md = 0.5 * (bounds[idx, a] + bounds[idx, 3 + a])
                nl = 0
                nrr = 0
                for k in range(s0, s0 + m):
                    t = scratch[k]
                    r = thi[t, a] > md
                    if r:
                        nrr += 1
                    if tlo[t, a] < md or not r:
                        nl += 1
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
        if axis < 0:
            if nr + m > tris.shape[0]:
                return -1, -1
            links[idx, 2] = nr
            links[idx, 3] = m
            for k in range(s0, s0 + m):
                tris[nr] = scratch[k]
                nr += 1
            continue
        # children's id lists go on top of scratch: left, then right
        if top + 2 * m > scratch.shape[0] or sp + 2 > max_stack:
            return -1, -1
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
        # push right first (popped after the whole left subtree), then left (next node)
        st_start[sp] = rs
        st_len[sp] = top - rs
        for q in range(3):
            st_box[sp, q] = blo[q]
            st_box[sp, 3 + q] = bhi[q]
        st_box[sp, axis] = mid
        st_depth[sp] = depth + 1
        st_parent[sp] = idx
        sp += 1
        st_start[sp] = ls
        st_len[sp] = rs - ls
        for q in range(3):
            st_box[sp, q] = blo[q]
            st_box[sp, 3 + q] = bhi[q]
        st_box[sp, 3 + axis] = mid
        st_depth[sp] = depth + 1
        st_parent[sp] = -1
        sp += 1
        links[idx, 0] = idx + 1
    return nn, nr




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
        if links[nd, 0] < 0:
            room += 3 * links[nd, 3]
    for i in range(faces.shape[0]):
        for q in range(3):
            nv = max(nv, faces[i, q] + 1)
    seen = np.full(nv, -1, np.int64)   # the last leaf a vertex was taken for
    out = np.empty(room, np.int64)
    m = 0
    for nd in range(k):
        start[nd] = m
        if links[nd, 0] >= 0:
            continue
        s = links[nd, 2]
        first = m
        for t in range(links[nd, 3]):
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
    """``nb[:, 12]``: how far any vertex of the node moves over the frame relative to the
    reference displacement ``ref``, as the norm of the per-axis maxima — a bound on how
    fast the node's (blended) box, and any of its triangles, approaches a point that moves
    with ``ref``."""
    for nd in range(last - 1, first - 1, -1):
        if links[nd, 0] < 0:
            mx = 0.0
            my = 0.0
            mz = 0.0
            for s in range(lv_start[nd], lv_start[nd + 1]):
                v = lv[s]
                mx = max(mx, abs(vp[v, 3] - vp[v, 0] - ref[0]))
                my = max(my, abs(vp[v, 4] - vp[v, 1] - ref[1]))
                mz = max(mz, abs(vp[v, 5] - vp[v, 2] - ref[2]))
            nb[nd, 12] = math.sqrt(mx * mx + my * my + mz * mz) * (1.0 + 1e-6) + 1e-9
        else:
            nb[nd, 12] = max(nb[links[nd, 0], 12], nb[links[nd, 1], 12])


@numba.njit(cache=True, _nrt=False)
def refit_frame(vp, col, lv_start, lv, links, nb, first, last):
    """Refit nodes [first, last) (one part) to the body at one frame: node boxes
    ``nb[:, 6·col : 6·col + 6]`` (lo, hi) from the positions ``vp[:, 3·col : 3·col + 3]``
    (leaves over their distinct vertices ``lv``, see :func:`leaf_vertices`; inner nodes the
    union of their children). The collider keeps a node's boxes at the previous (col 0) and
    the current frame (col 1): the box at any time between them is their blend."""
    o = 6 * col
    c3 = 3 * col
    for nd in range(last - 1, first - 1, -1):
        if links[nd, 0] < 0:
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
            nb[nd, o] = lx
            nb[nd, o + 1] = ly
            nb[nd, o + 2] = lz
            nb[nd, o + 3] = hx
            nb[nd, o + 4] = hy
            nb[nd, o + 5] = hz
        else:
            l = links[nd, 0]
            r = links[nd, 1]
            for q in range(3):
                nb[nd, o + q] = min(nb[l, o + q], nb[r, o + q])
                nb[nd, o + 3 + q] = max(nb[l, o + 3 + q], nb[r, o + 3 + q])


#: the columns of the nodes' table the searches read (``nbl`` (K,16) float64): the box at the
#: search's time (lo 0–2, hi 3–5) and its centre (6–8), by :func:`blend_at`; the box swept
#: over the frame in the frame moving with the reference displacement (lo 9–11, hi 12–14)
#: and the node's speed (15), by :func:`swept_boxes`
NODE_COLUMNS = 16


@numba.njit(cache=True, _nrt=False)
def swept_boxes(nb, ref, first, last, nbl):
    """Nodes [first, last) (one part) over the frame, once it is refitted: the boxes swept
    over it in the frame moving by ``ref`` (``nbl[:, 9:15]``: no triangle of the node comes
    nearer, at any time of the frame, to a point's position in that moving frame;
    :func:`swept_d2`) and the speeds (``nb[:, 12]`` → ``nbl[:, 15]``)."""
    for nd in range(first, last):
        for q in range(3):
            nbl[nd, 9 + q] = min(nb[nd, q], nb[nd, 6 + q] - ref[q])
            nbl[nd, 12 + q] = max(nb[nd, 3 + q], nb[nd, 9 + q] - ref[q])
        nbl[nd, 15] = nb[nd, 12]


@numba.njit(cache=True, _nrt=False, inline="always")
def box_d2(px, py, pz, nbl, nd):
    """Squared distance from p to node nd's box at the table's time (:func:`blend_at`: the
    blend of its two frames' boxes, which holds every triangle of the node at that time).
    Branch-free (max/min selects): the walks' box tests are otherwise bound by mispredicted
    branches."""
    x = max(max(nbl[nd, 0] - px, px - nbl[nd, 3]), 0.0)
    y = max(max(nbl[nd, 1] - py, py - nbl[nd, 4]), 0.0)
    z = max(max(nbl[nd, 2] - pz, pz - nbl[nd, 5]), 0.0)
    return x * x + y * y + z * z


@numba.njit(cache=True, _nrt=False, inline="always")
def swept_d2(mx, my, mz, nbl, nd):
    """Squared distance from the point (mx, my, mz), given in the frame moving with the
    reference displacement (p − alpha·ref for p at time alpha), to node nd's box swept over
    the frame (:func:`swept_boxes`; branch-free)."""
    x = max(max(nbl[nd, 9] - mx, mx - nbl[nd, 12]), 0.0)
    y = max(max(nbl[nd, 10] - my, my - nbl[nd, 13]), 0.0)
    z = max(max(nbl[nd, 11] - mz, mz - nbl[nd, 14]), 0.0)
    return x * x + y * y + z * z


@numba.njit(cache=True, _nrt=False)
def blend_at(vp, nb, first, last, vidx, alpha, nbl, vpl):
    """One part's pose at time ``alpha`` of the frame, as :func:`closest_triangle_t` reads
    it: its nodes [first, last) in ``nbl`` (:data:`NODE_COLUMNS`) — the box blended between
    the frame's two in ``nb`` (lo 0–2, hi 3–5; :func:`box_d2`) and its centre (6–8, by which
    the walk orders a node's children) — and its vertices ``vidx`` in ``vpl`` (N,3), blended
    between the two frames' positions in ``vp`` (N,6). Blended once for the many searches
    at one time (the object pass's at one substep) instead of inside every node visit and
    triangle test."""
    b = 1.0 - alpha
    for nd in range(first, last):
        for q in range(3):
            nbl[nd, q] = b * nb[nd, q] + alpha * nb[nd, 6 + q]
            nbl[nd, 3 + q] = b * nb[nd, 3 + q] + alpha * nb[nd, 9 + q]
            nbl[nd, 6 + q] = 0.5 * (b * (nb[nd, q] + nb[nd, 3 + q])
                                    + alpha * (nb[nd, 6 + q] + nb[nd, 9 + q]))
    for k in range(vidx.shape[0]):
        v = vidx[k]
        vpl[v, 0] = b * vp[v, 0] + alpha * vp[v, 3]
        vpl[v, 1] = b * vp[v, 1] + alpha * vp[v, 4]
        vpl[v, 2] = b * vp[v, 2] + alpha * vp[v, 5]


@numba.njit(cache=True, _nrt=False)
def closest_triangle_t(px, py, pz, vpl, lf, alpha, rx, ry, rz, nbl, links, tris, root,
                       best_d2, best_t, stack, inv_t, spd):
    """Closest triangle to p among one part's hierarchy at time ``alpha``, if nearer than
    √best_d2, with the part's pose at that time and its nodes' bounds over the frame
    (``nbl`` (K,16), :data:`NODE_COLUMNS`: the node boxes blended at ``alpha`` — tighter than
    the box swept over the frame: a fast limb is pruned where it is at that time — the
    centres children are ordered by, the boxes swept over the frame and the nodes' speeds;
    :func:`blend_at`, :func:`swept_boxes`) and ``vpl`` (N,3) the vertices at ``alpha``.
    ``lf`` (R,3) int32 the vertices of each reference of ``tris`` (a leaf's are read in
    sequence, not through the faces).
    Returns (best_d2, best_t, nodes
    visited, triangles tested, frame_d2): frame_d2 is a lower bound of the squared distance,
    for the whole frame and in the frame moving by the reference displacement (rx, ry, rz),
    from the point to every triangle of the part (over the leaves visited and the subtrees
    pruned).

    ``spd`` (2,) accumulates, for the point's speed bound after the search (see
    :func:`catwalk.collide.kernels.object_space.object_pass`): spd[0] the max over pruned nodes of
    m − d·``inv_t`` (m the node's speed ``nb[:, 12]``, d its box distance now, inv_t 1 / the
    rest of the frame), spd[1] the max speed of the leaves visited."""
    stack[0] = root
    sp = 1
    visited = 0
    tested = 0
    frame_d2 = np.inf
    # the point in the frame moving with the reference displacement (the swept boxes')
    mx = px - alpha * rx
    my = py - alpha * ry
    mz = pz - alpha * rz
    while sp > 0:
        sp -= 1
        nd = stack[sp]
        visited += 1
        d = box_d2(px, py, pz, nbl, nd)
        if d >= best_d2:
            ds = swept_d2(mx, my, mz, nbl, nd)
            if ds < frame_d2:
                frame_d2 = ds
            sv = nbl[nd, 15] - math.sqrt(d) * inv_t
            if sv > spd[0]:
                spd[0] = sv
            continue
        if links[nd, 0] >= 0:
            if sp + 2 > stack.shape[0]:
                frame_d2 = 0.0  # (never: the stack holds 2 × the depth limit)
                continue
            l = links[nd, 0]
            r = links[nd, 1]
            cl = 0.0
            cr = 0.0
            for q in range(3):
                c = px if q == 0 else (py if q == 1 else pz)
                e = nbl[l, 6 + q] - c
                cl += e * e
                e = nbl[r, 6 + q] - c
                cr += e * e
            if cl < cr:
                stack[sp] = r
                stack[sp + 1] = l
            else:
                stack[sp] = l
                stack[sp + 1] = r
            sp += 2
            continue
        ds = swept_d2(mx, my, mz, nbl, nd)
        if ds < frame_d2:
            frame_d2 = ds
        if nbl[nd, 15] > spd[1]:
            spd[1] = nbl[nd, 15]
        for s in range(links[nd, 2], links[nd, 2] + links[nd, 3]):
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
            v, w = closest_on_triangle(px, py, pz, ax, ay, az, bx, by, bz, cx, cy, cz)
            qx = ax + v * (bx - ax) + w * (cx - ax) - px
            qy = ay + v * (by - ay) + w * (cy - ay) - py
            qz = az + v * (bz - az) + w * (cz - az) - pz
            d = qx * qx + qy * qy + qz * qz
            if d < best_d2:
                best_d2 = d
                best_t = tris[s]
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
        if h.links[nd, 0] >= 0:
            stack.append((int(h.links[nd, 0]), d + 1))
            stack.append((int(h.links[nd, 1]), d + 1))
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
        if links[nd, 0] < 0:
            best = d
            continue
        if sp + 2 > stack.shape[0]:
            best = 0.0  # (never: the stack holds 2 × the depth limit)
            continue
        stack[sp] = links[nd, 0]
        stack[sp + 1] = links[nd, 1]
        sp += 2
    return best, visited
