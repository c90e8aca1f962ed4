"""Planar sections of a mesh: the kernel that slices many levels at once (:func:`slice_kernel`),
each section split into connected loops with their hulls' statistics (:class:`Sections`), and a
slicer bound to one scalar field (:class:`Slicer`).

A section's loop (a component) has a row of statistics (``Sections.stats``, :data:`N_STATS`
columns): its convex hull's perimeter (:data:`PERIM`: the girth, a tape measure bridging
hollows), area (:data:`AREA`) and centroid x, z (:data:`CX`, :data:`CZ`), the loop's box
(:data:`XMIN`, :data:`XMAX`, :data:`ZMIN`, :data:`ZMAX`: the columns from XMIN to ZMAX, its
``box``) and its number of points (:data:`N_POINTS`).
"""

from __future__ import annotations

import numba
import numpy as np

from catwalk.body.measure.topology import Topology

PERIM, AREA, CX, CZ, XMIN, XMAX, ZMIN, ZMAX, N_POINTS = range(9)
N_STATS = 9


@numba.njit(cache=True)
def _find(parent, i):
    while parent[i] != i:
        parent[i] = parent[parent[i]]
        i = parent[i]
    return i


@numba.njit(cache=True)
def _upper_bound(a, x):
    """First index i with a[i] > x (a sorted ascending)."""
    lo = 0
    hi = a.shape[0]
    while lo < hi:
        mid = (lo + hi) >> 1
        if a[mid] > x:
            hi = mid
        else:
            lo = mid + 1
    return lo


@numba.njit(cache=True)
def _hull_stats(xs, zs, out):
    """Convex hull of 2D points: out = [perimeter, area, cx, cz] (centroid of the hull area,
    or the mean point for a degenerate hull)."""
    n = xs.shape[0]
    if n == 0:
        out[:] = 0.0
        return
    order = np.argsort(xs)
    for i in range(1, n):  # lexicographic: order ties in x by z (insertion sort, ties are rare)
        j = i
        while j > 0 and xs[order[j - 1]] == xs[order[j]] and zs[order[j - 1]] > zs[order[j]]:
            tmp = order[j - 1]
            order[j - 1] = order[j]
            order[j] = tmp
            j -= 1
    hx = np.empty(2 * n + 1)
    hz = np.empty(2 * n + 1)
    m = 0
    for ii in range(n):  # lower hull
        i = order[ii]
        while m >= 2 and ((hx[m - 1] - hx[m - 2]) * (zs[i] - hz[m - 2])
                          - (hz[m - 1] - hz[m - 2]) * (xs[i] - hx[m - 2])) <= 0.0:
            m -= 1
        hx[m] = xs[i]
        hz[m] = zs[i]
        m += 1
    lower = m + 1
    for ii in range(n - 2, -1, -1):  # upper hull
        i = order[ii]
        while m >= lower and ((hx[m - 1] - hx[m - 2]) * (zs[i] - hz[m - 2])
                              - (hz[m - 1] - hz[m - 2]) * (xs[i] - hx[m - 2])) <= 0.0:
            m -= 1
        hx[m] = xs[i]
        hz[m] = zs[i]
        m += 1
    m -= 1  # last point repeats the first
    per = 0.0
    area = 0.0
    cx = 0.0
    cz = 0.0
    for i in range(m):
        j = i + 1 if i + 1 < m else 0
        dx = hx[j] - hx[i]
        dz = hz[j] - hz[i]
        per += np.sqrt(dx * dx + dz * dz)
        cr = hx[i] * hz[j] - hx[j] * hz[i]
        area += cr
        cx += (hx[i] + hx[j]) * cr
        cz += (hz[i] + hz[j]) * cr
    area *= 0.5
    if abs(area) > 1e-14:
        cx /= 6.0 * area
        cz /= 6.0 * area
    else:
        cx = xs.mean()
        cz = zs.mean()
    out[0] = per
    out[1] = abs(area)
    out[2] = cx
    out[3] = cz



@numba.njit(cache=True)
def slice_kernel(s, px, pz, edges, tri_verts, tri_edges, tris, levels, emap):
    """Slice the triangles ``tris`` of a mesh by the planes s = levels[k] (sorted ascending).

    A vertex is above a level when s >= level, so every crossed triangle has exactly two crossed
    edges; crossing points are joined into loops through the triangles. Returns
      X, Z        (P,) in-plane coordinates of the crossing points (level-major order)
      pcomp       (P,) component id of each point
      comp_level  (C,) level index of each component (components are level-major too)
      stats       (C, N_STATS): each component's row (the module's docstring)
    ``emap`` is scratch: one int64 per mesh edge, all -1 on entry and on return (it maps the
    edges in play to compact local ids, so no per-call array is as long as the mesh).
    """
    tl, nt, elist, nl = _triangles_in_range(s, tri_verts, tri_edges, tris, levels, emap)
    k0, cnt, estart, lvl_count, total = _edge_crossings(s, edges, elist, nl, levels)
    X, Z, pid = _crossing_points(s, px, pz, edges, elist, levels, (k0, cnt, estart),
                                 lvl_count, total)
    parent = _join_crossings(tl, nt, tri_edges, emap, (k0, cnt, estart), pid, total)
    for e in range(nl):
        emap[elist[e]] = -1
    pcomp, comp_level, order, ccount = _components(parent, lvl_count, total)
    return X, Z, pcomp, comp_level, _component_stats(X, Z, order, ccount)


@numba.njit(cache=True)
def _triangles_in_range(s, tri_verts, tri_edges, tris, levels, emap):
    """The triangles of ``tris`` that reach the levels' range (``tl``, ``nt`` of them) and
    their edges (``elist``, ``nl`` of them), each edge given its local id in ``emap``."""
    nk = levels.shape[0]
    elist = np.empty(3 * tris.shape[0], np.int64)
    nl = 0
    lmin = levels[0]
    lmax = levels[nk - 1]
    tl = np.empty(tris.shape[0], np.int64)
    nt = 0
    for f in tris:
        a = tri_verts[f, 0]
        b = tri_verts[f, 1]
        c = tri_verts[f, 2]
        lo = min(s[a], min(s[b], s[c]))
        hi = max(s[a], max(s[b], s[c]))
        if hi < lmin or lo >= lmax:
            continue
        tl[nt] = f
        nt += 1
        for j in range(3):
            e = tri_edges[f, j]
            if emap[e] < 0:
                emap[e] = nl
                elist[nl] = e
                nl += 1
    return tl, nt, elist, nl


@numba.njit(cache=True)
def _edge_crossings(s, edges, elist, nl, levels):
    """Per edge in play, the levels it crosses (``k0`` the first, ``cnt`` how many) and where
    its crossings start among all edges' (``estart``); the crossings per level, cumulated
    (``lvl_count``, levels + 1), and their ``total``."""
    nk = levels.shape[0]
    k0 = np.empty(nl, np.int64)
    cnt = np.empty(nl, np.int64)
    estart = np.empty(nl, np.int64)
    lvl_count = np.zeros(nk + 1, np.int64)
    total = 0
    for e in range(nl):
        a = edges[elist[e], 0]
        b = edges[elist[e], 1]
        lo = min(s[a], s[b])
        hi = max(s[a], s[b])
        i0 = _upper_bound(levels, lo)
        i1 = _upper_bound(levels, hi)
        k0[e] = i0
        cnt[e] = i1 - i0
        estart[e] = total
        total += i1 - i0
        for k in range(i0, i1):
            lvl_count[k + 1] += 1
    for k in range(nk):
        lvl_count[k + 1] += lvl_count[k]
    return k0, cnt, estart, lvl_count, total


@numba.njit(cache=True)
def _crossing_points(s, px, pz, edges, elist, levels, crossings, lvl_count, total):
    """The crossing points, level after level (X, Z in the plane) and each edge crossing's
    point (``pid``, in the edges' order)."""
    k0, cnt, estart = crossings
    fill = lvl_count[:levels.shape[0]].copy()
    X = np.empty(total)
    Z = np.empty(total)
    pid = np.empty(total, np.int64)
    for e in range(k0.shape[0]):
        if cnt[e] == 0:
            continue
        a = edges[elist[e], 0]
        b = edges[elist[e], 1]
        sa = s[a]
        ds = s[b] - sa
        for j in range(cnt[e]):
            k = k0[e] + j
            t = (levels[k] - sa) / ds
            p = fill[k]
            fill[k] += 1
            X[p] = px[a] + t * (px[b] - px[a])
            Z[p] = pz[a] + t * (pz[b] - pz[a])
            pid[estart[e] + j] = p
    return X, Z, pid


@numba.njit(cache=True)
def _join_crossings(tl, nt, tri_edges, emap, crossings, pid, total):
    """The crossing points joined into loops through the triangles (a union-find forest,
    ``parent``, each root its set's smallest point)."""
    k0, cnt, estart = crossings
    parent = np.arange(total)
    for ti in range(nt):
        f = tl[ti]
        e0 = emap[tri_edges[f, 0]]
        e1 = emap[tri_edges[f, 1]]
        e2 = emap[tri_edges[f, 2]]
        lo = min(k0[e0], min(k0[e1], k0[e2]))
        hi = max(k0[e0] + cnt[e0], max(k0[e1] + cnt[e1], k0[e2] + cnt[e2]))
        for k in range(lo, hi):
            # exactly two of the three edges cross level k: join their points
            in0 = k0[e0] <= k < k0[e0] + cnt[e0]
            in1 = k0[e1] <= k < k0[e1] + cnt[e1]
            if in0:
                pa = pid[estart[e0] + k - k0[e0]]
                eb = e1 if in1 else e2
            else:
                pa = pid[estart[e1] + k - k0[e1]]
                eb = e2
            pb = pid[estart[eb] + k - k0[eb]]
            ra = _find(parent, pa)
            rb = _find(parent, pb)
            if ra != rb:
                if ra < rb:
                    parent[rb] = ra
                else:
                    parent[ra] = rb
    return parent


@numba.njit(cache=True)
def _components(parent, lvl_count, total):
    """The loops: each point's component (``pcomp``, numbered in order of their first point:
    level-major), each component's level, the points component after component (``order``)
    and where each component's start there (``ccount``, components + 1)."""
    pcomp = np.empty(total, np.int64)
    rootid = np.full(total, -1, np.int64)
    nc = 0
    for p in range(total):
        r = _find(parent, p)
        if rootid[r] < 0:
            rootid[r] = nc
            nc += 1
        pcomp[p] = rootid[r]
    comp_level = np.empty(nc, np.int64)
    ccount = np.zeros(nc + 1, np.int64)
    k = 0
    for p in range(total):
        while p >= lvl_count[k + 1]:
            k += 1
        comp_level[pcomp[p]] = k
        ccount[pcomp[p] + 1] += 1
    for c in range(nc):
        ccount[c + 1] += ccount[c]
    cfill = ccount[:nc].copy()
    order = np.empty(total, np.int64)
    for p in range(total):
        c = pcomp[p]
        order[cfill[c]] = p
        cfill[c] += 1
    return pcomp, comp_level, order, ccount


@numba.njit(cache=True)
def _component_stats(X, Z, order, ccount):
    """Each component's row of statistics (the module's docstring)."""
    nc = ccount.shape[0] - 1
    stats = np.zeros((nc, N_STATS))
    hs = np.zeros(4)
    for c in range(nc):
        idx = order[ccount[c]:ccount[c + 1]]
        xs = X[idx]
        zs = Z[idx]
        _hull_stats(xs, zs, hs)
        stats[c, PERIM] = hs[0]
        stats[c, AREA] = hs[1]
        stats[c, CX] = hs[2]
        stats[c, CZ] = hs[3]
        stats[c, XMIN] = xs.min()
        stats[c, XMAX] = xs.max()
        stats[c, ZMIN] = zs.min()
        stats[c, ZMAX] = zs.max()
        stats[c, N_POINTS] = idx.shape[0]
    return stats


class Sections:
    """The result of slicing at ``levels``: components (loops) per level with hull stats."""

    def __init__(self, levels, X, Z, pcomp, comp_level, stats):
        self.levels = levels
        self.X = X
        self.Z = Z
        self.pcomp = pcomp
        self.comp_level = comp_level
        self.stats = stats
        self._bounds = np.searchsorted(comp_level, np.arange(len(levels) + 1))

    def comps(self, k: int) -> np.ndarray:
        return np.arange(self._bounds[k], self._bounds[k + 1])

    def points(self, c: int) -> tuple[np.ndarray, np.ndarray]:
        m = self.pcomp == c
        return self.X[m], self.Z[m]

    def perim(self, c):
        return self.stats[c, PERIM]

    def centroid(self, c):
        return self.stats[c, CX], self.stats[c, CZ]

    def inside(self, c, box, margin=0.0):
        """Is the hull centroid of component c inside box = (xmin, xmax, zmin, zmax)?"""
        cx, cz = self.stats[c, CX], self.stats[c, CZ]
        return (box[0] - margin <= cx <= box[1] + margin
                and box[2] - margin <= cz <= box[3] + margin)

    def box(self, c):
        """Component c's box (xmin, xmax, zmin, zmax)."""
        return self.stats[c, XMIN:ZMAX + 1].copy()


class Slicer:
    """Slices one mesh by the level sets of a per-vertex scalar ``s`` (a plane's normal
    coordinate); ``px, pz`` are the in-plane coordinates carried to the section points."""

    def __init__(self, topo: Topology, s, px, pz, tri_mask=None):
        if len(s) != topo.nverts or len(px) != topo.nverts or len(pz) != topo.nverts:
            raise ValueError("slicer: one value per vertex (hole fans included) is needed")
        self.topo = topo
        self.s = np.ascontiguousarray(s, dtype=np.float64)
        self.px = np.ascontiguousarray(px, dtype=np.float64)
        self.pz = np.ascontiguousarray(pz, dtype=np.float64)
        self.tris = topo.all_tris if tri_mask is None else np.nonzero(tri_mask)[0]
        self.tlo = None

    def with_bands(self) -> Slicer:
        """Sort the triangles by their lowest s, so that each call only visits the triangles
        that can reach its levels (worth it for many calls with few levels)."""
        lo, hi = tri_range(self.s, self.topo.faces)
        lo, hi = lo[self.tris], hi[self.tris]
        order = np.argsort(lo, kind="stable")
        self.tris = np.ascontiguousarray(self.tris[order])
        self.tlo = lo[order]
        self.hmax = float((hi - lo).max()) if len(lo) else 0.0
        return self

    def slice(self, levels) -> Sections:
        levels = np.ascontiguousarray(levels, dtype=np.float64)
        tris = self.tris
        if self.tlo is not None:
            # a triangle reaches a level L when lo < L <= hi, and hi <= lo + hmax
            i0 = np.searchsorted(self.tlo, levels[0] - self.hmax, side="left")
            i1 = np.searchsorted(self.tlo, levels[-1], side="left")
            tris = tris[i0:i1]
        out = slice_kernel(self.s, self.px, self.pz, self.topo.edges, self.topo.faces,
                           self.topo.tri_edges, tris, levels, self.topo.emap)
        return Sections(levels, *out)


@numba.njit(cache=True)
def tri_range(s, faces):
    """Per-triangle min and max of a vertex scalar."""
    n = faces.shape[0]
    lo = np.empty(n)
    hi = np.empty(n)
    for f in range(n):
        a = s[faces[f, 0]]
        b = s[faces[f, 1]]
        c = s[faces[f, 2]]
        lo[f] = min(a, min(b, c))
        hi[f] = max(a, max(b, c))
    return lo, hi


def largest(sec: Sections, k: int, box=None, margin=0.01, exclude=()):
    """The loop of greatest girth at level k (with its centroid in ``box`` grown by
    ``margin``, if given; not one of ``exclude``), or −1."""
    best, bp = -1, -1.0
    for c in sec.comps(k):
        if c in exclude:
            continue
        if box is not None and not sec.inside(c, box, margin):
            continue
        if sec.stats[c, PERIM] > bp:
            best, bp = c, sec.stats[c, PERIM]
    return best
