"""Object space: the paper's per-limb hierarchy (§4 "Object-space details") and its kernels.

Each part's triangles go into a binary hierarchy that halves the node's box with a plane across
its largest dimension (spatial median, no search for the best split: body triangles are small
and evenly spread). A triangle spanning the plane goes into *both* halves; no triangle is split.
The topology is built once from the rest pose; each frame only the bounds are refitted, over the
*swept* triangles (the union of their boxes at the previous and the current frame), so one refit
bounds the body at every substep in between.

All parts' hierarchies live in one set of flat arrays (:class:`Hierarchy`); nodes are in
pre-order, so children come after parents and a refit walks a part's node range backwards.
"""

from __future__ import annotations

from dataclasses import dataclass

import numba
import numpy as np


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


@numba.njit(cache=True, _nrt=False)
def refit(v0, v1, faces, bounds, links, tris, first, last):
    """Refit nodes [first, last) (one part) to the triangles swept from ``v0`` to ``v1``."""
    for nd in range(last - 1, first - 1, -1):
        if links[nd, 0] < 0:
            for q in range(3):
                bounds[nd, q] = np.inf
                bounds[nd, 3 + q] = -np.inf
            for s in range(links[nd, 2], links[nd, 2] + links[nd, 3]):
                t = tris[s]
                for c in range(3):
                    vi = faces[t, c]
                    for q in range(3):
                        a = v0[vi, q]
                        b = v1[vi, q]
                        if a > b:
                            a, b = b, a
                        if a < bounds[nd, q]:
                            bounds[nd, q] = a
                        if b > bounds[nd, 3 + q]:
                            bounds[nd, 3 + q] = b
        else:
            l = links[nd, 0]
            r = links[nd, 1]
            for q in range(3):
                bounds[nd, q] = min(bounds[l, q], bounds[r, q])
                bounds[nd, 3 + q] = max(bounds[l, 3 + q], bounds[r, 3 + q])


@numba.njit(cache=True, _nrt=False)
def box_dist2(px, py, pz, bounds, nd):
    """Squared distance from p to node nd's box (0 inside)."""
    d = 0.0
    for q in range(3):
        c = px if q == 0 else (py if q == 1 else pz)
        x = bounds[nd, q] - c
        if x > 0.0:
            d += x * x
        else:
            x = c - bounds[nd, 3 + q]
            if x > 0.0:
                d += x * x
    return d


@numba.njit(cache=True, _nrt=False)
def closest_on_triangle(px, py, pz, ax, ay, az, bx, by, bz, cx, cy, cz):
    """Barycentric (v, w) of the point of triangle abc closest to p (Ericson 2005, §5.1.5):
    the point is a + v·(b − a) + w·(c − a)."""
    abx = bx - ax
    aby = by - ay
    abz = bz - az
    acx = cx - ax
    acy = cy - ay
    acz = cz - az
    apx = px - ax
    apy = py - ay
    apz = pz - az
    d1 = abx * apx + aby * apy + abz * apz
    d2 = acx * apx + acy * apy + acz * apz
    if d1 <= 0.0 and d2 <= 0.0:
        return 0.0, 0.0
    bpx = px - bx
    bpy = py - by
    bpz = pz - bz
    d3 = abx * bpx + aby * bpy + abz * bpz
    d4 = acx * bpx + acy * bpy + acz * bpz
    if d3 >= 0.0 and d4 <= d3:
        return 1.0, 0.0
    vc = d1 * d4 - d3 * d2
    if vc <= 0.0 and d1 >= 0.0 and d3 <= 0.0:
        return d1 / (d1 - d3), 0.0
    cpx = px - cx
    cpy = py - cy
    cpz = pz - cz
    d5 = abx * cpx + aby * cpy + abz * cpz
    d6 = acx * cpx + acy * cpy + acz * cpz
    if d6 >= 0.0 and d5 <= d6:
        return 0.0, 1.0
    vb = d5 * d2 - d1 * d6
    if vb <= 0.0 and d2 >= 0.0 and d6 <= 0.0:
        return 0.0, d2 / (d2 - d6)
    va = d3 * d6 - d5 * d4
    if va <= 0.0 and (d4 - d3) >= 0.0 and (d5 - d6) >= 0.0:
        w = (d4 - d3) / ((d4 - d3) + (d5 - d6))
        return 1.0 - w, w
    den = va + vb + vc
    if not (den > 0.0):
        return 0.0, 0.0
    den = 1.0 / den
    return vb * den, vc * den


@numba.njit(cache=True, _nrt=False)
def closest_triangle(px, py, pz, vb, faces, alpha, bounds, links, tris, root, best_d2,
                     best_t, stack):
    """Closest triangle to p among one part's hierarchy at time ``alpha``, if nearer than
    √best_d2. ``vb`` (N, ≥6): each vertex's position at the previous frame (columns 0–2)
    and the current one (3–5) (the collider passes float32: it stays in cache).
    Returns (best_d2, best_t, nodes visited, triangles tested, leaf_d2): leaf_d2 is a lower
    bound of the squared distance from p to every leaf's box in this hierarchy (the
    nearest leaf box visited, else the initial best_d2) — boxes are swept over the frame, so
    no triangle of the part comes nearer than that at any time of the frame.

    Hot loop: written out by hand (numba calls between kernels cost more than the work)."""
    stack[0] = root
    sp = 1
    visited = 0
    tested = 0
    leaf_d2 = best_d2
    b = 1.0 - alpha
    while sp > 0:
        sp -= 1
        nd = stack[sp]
        visited += 1
        d = 0.0
        x = bounds[nd, 0] - px
        if x > 0.0:
            d += x * x
        else:
            x = px - bounds[nd, 3]
            if x > 0.0:
                d += x * x
        x = bounds[nd, 1] - py
        if x > 0.0:
            d += x * x
        else:
            x = py - bounds[nd, 4]
            if x > 0.0:
                d += x * x
        x = bounds[nd, 2] - pz
        if x > 0.0:
            d += x * x
        else:
            x = pz - bounds[nd, 5]
            if x > 0.0:
                d += x * x
        if d >= best_d2:
            continue
        if links[nd, 0] >= 0:
            if sp + 2 > stack.shape[0]:
                continue
            # push both; the child whose box centre is nearer goes last (popped first)
            l = links[nd, 0]
            r = links[nd, 1]
            cl = 0.0
            cr = 0.0
            for q in range(3):
                c = px if q == 0 else (py if q == 1 else pz)
                e = 0.5 * (bounds[l, q] + bounds[l, 3 + q]) - c
                cl += e * e
                e = 0.5 * (bounds[r, q] + bounds[r, 3 + q]) - c
                cr += e * e
            if cl < cr:
                stack[sp] = r
                stack[sp + 1] = l
            else:
                stack[sp] = l
                stack[sp + 1] = r
            sp += 2
            continue
        if d < leaf_d2:
            leaf_d2 = d
        for s in range(links[nd, 2], links[nd, 2] + links[nd, 3]):
            t = tris[s]
            ia = faces[t, 0]
            ib = faces[t, 1]
            ic = faces[t, 2]
            ax = b * vb[ia, 0] + alpha * vb[ia, 3]
            ay = b * vb[ia, 1] + alpha * vb[ia, 4]
            az = b * vb[ia, 2] + alpha * vb[ia, 5]
            bx = b * vb[ib, 0] + alpha * vb[ib, 3]
            by = b * vb[ib, 1] + alpha * vb[ib, 4]
            bz = b * vb[ib, 2] + alpha * vb[ib, 5]
            cx = b * vb[ic, 0] + alpha * vb[ic, 3]
            cy = b * vb[ic, 1] + alpha * vb[ic, 4]
            cz = b * vb[ic, 2] + alpha * vb[ic, 5]
            # the triangle's box first: cheap, rejects most
            d = 0.0
            x = min(ax, min(bx, cx)) - px
            if x > 0.0:
                d += x * x
            else:
                x = px - max(ax, max(bx, cx))
                if x > 0.0:
                    d += x * x
            x = min(ay, min(by, cy)) - py
            if x > 0.0:
                d += x * x
            else:
                x = py - max(ay, max(by, cy))
                if x > 0.0:
                    d += x * x
            x = min(az, min(bz, cz)) - pz
            if x > 0.0:
                d += x * x
            else:
                x = pz - max(az, max(bz, cz))
                if x > 0.0:
                    d += x * x
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
                best_t = t
    return best_d2, best_t, visited, tested, leaf_d2


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
