"""Body measurements and landmarks from the surface alone (no rig), for any body or scan.

Input: a triangle mesh in glTF metres (+Y up, the body faces +Z, body's left = +X), as
:func:`catwalk.exchange.scan.load_scan` returns it. Everything is derived from planar sections of
the surface: a section is split into connected loops (through the mesh's edge connectivity),
and a girth is the perimeter of the convex hull of the torso's loop (a tape measure bridges
hollows), as ISO 8559-1 defines girths. The definitions are in ``docs/bodies-measure.md``.

The hot path is one numba kernel that slices many levels at once (:func:`_slice_kernel`).
Extrema (bust, waist, neck, wrist) are refined by golden-section search on exact sections, and
levels read off a profile (buttocks, bust point, breast fold, acromion) by a soft arg-min, so
that the numbers move smoothly with the shape (the body fitter takes finite differences).
Holes are closed by fans before slicing (scans have them).
"""

from __future__ import annotations

import hashlib
from dataclasses import dataclass

import numba
import numpy as np

from catwalk.errors import InputError

# ----------------------------------------------------------------------------------------------
# topology (cached per face array)


@dataclass(frozen=True)
class _Topology:
    faces: np.ndarray       # (F, 3) int64, degenerate triangles dropped
    edges: np.ndarray       # (E, 2) int64 unique undirected edges
    tri_edges: np.ndarray   # (F, 3) int64 edge ids of (v0v1, v1v2, v2v0)
    nverts: int
    used: np.ndarray        # sorted ids of the vertices that faces use
    all_tris: np.ndarray    # arange(F)
    emap: np.ndarray        # (E,) int64 scratch for the kernel, all -1
    n_orig: int             # vertices given; nverts - n_orig hole-filling fan centres follow
    fill_idx: np.ndarray    # boundary-loop vertices, loop after loop
    fill_start: np.ndarray  # start of each loop in fill_idx

    def adjacency(self) -> tuple[np.ndarray, np.ndarray]:
        """Vertex neighbours in CSR form (pointer, neighbours), computed once."""
        cached = _ADJ_CACHE.get(id(self))
        if cached is None or cached[0] is not self:
            e = self.edges
            both = np.concatenate([e, e[:, ::-1]])
            order = np.argsort(both[:, 0], kind="stable")
            nbr = np.ascontiguousarray(both[order, 1])
            ptr = np.zeros(self.nverts + 1, np.int64)
            np.cumsum(np.bincount(both[:, 0], minlength=self.nverts), out=ptr[1:])
            cached = (self, ptr, nbr)
            if len(_ADJ_CACHE) > 8:
                _ADJ_CACHE.clear()
            _ADJ_CACHE[id(self)] = cached
        return cached[1], cached[2]

    def extend(self, V: np.ndarray) -> np.ndarray:
        """The vertices plus the hole-filling fan centres (each loop's mean)."""
        if self.nverts == self.n_orig:
            return V
        sums = np.add.reduceat(V[self.fill_idx], self.fill_start, axis=0)
        counts = np.diff(np.append(self.fill_start, len(self.fill_idx)))
        return np.concatenate([V, sums / counts[:, None]])


_TOPO_CACHE: dict = {}
_ADJ_CACHE: dict = {}


def _topology(faces: np.ndarray, nverts: int) -> _Topology:
    faces = np.ascontiguousarray(faces, dtype=np.int64)
    key = (faces.shape, nverts, hashlib.blake2b(faces.tobytes(), digest_size=16).digest())
    topo = _TOPO_CACHE.get(key)
    if topo is not None:
        return topo
    if faces.ndim != 2 or faces.shape[1] != 3 or faces.shape[0] == 0:
        raise InputError("measure: the mesh has no triangles")
    if faces.min() < 0 or faces.max() >= nverts:
        raise InputError("measure: a face refers to a vertex that does not exist")
    ok = (faces[:, 0] != faces[:, 1]) & (faces[:, 1] != faces[:, 2]) & (faces[:, 2] != faces[:, 0])
    f = faces[ok]
    # close the holes (scans have them): a fan from a new vertex at each boundary loop's mean
    loops = _boundary_loops(f, nverts)
    fill_idx = np.concatenate(loops) if loops else np.zeros(0, np.int64)
    fill_start = np.cumsum([0] + [len(lp) for lp in loops])[:-1].astype(np.int64)
    if loops:
        fans = []
        for li, lp in enumerate(loops):
            c = nverts + li
            fans.append(np.stack([np.roll(lp, -1), lp, np.full(len(lp), c)], axis=1))
        f = np.concatenate([f, *fans]).astype(np.int64)
    n_orig = nverts
    nverts = nverts + len(loops)
    e = np.concatenate([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]])
    e.sort(axis=1)
    keyed = e[:, 0] * nverts + e[:, 1]
    uniq, inv = np.unique(keyed, return_inverse=True)
    edges = np.stack([uniq // nverts, uniq % nverts], axis=1).astype(np.int64)
    tri_edges = inv.reshape(3, -1).T.astype(np.int64).copy()
    used = np.zeros(nverts, bool)
    used[f.ravel()] = True
    used[n_orig:] = False  # fan centres do not count as surface (height, feet)
    topo = _Topology(np.ascontiguousarray(f), edges, tri_edges, nverts, np.nonzero(used)[0],
                     np.arange(len(f), dtype=np.int64), np.full(len(edges), -1, np.int64),
                     n_orig, fill_idx, fill_start)
    if len(_TOPO_CACHE) > 8:
        _TOPO_CACHE.clear()
    _TOPO_CACHE[key] = topo
    return topo


def _boundary_loops(f: np.ndarray, n: int) -> list[np.ndarray]:
    """Closed loops of boundary edges (edges of one triangle only), as vertex arrays in the
    direction the triangles give them. Runs once per topology (cached)."""
    d = np.concatenate([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]])
    key = np.minimum(d[:, 0], d[:, 1]) * n + np.maximum(d[:, 0], d[:, 1])
    _, inv, counts = np.unique(key, return_inverse=True, return_counts=True)
    b = d[counts[inv] == 1]
    if not len(b):
        return []
    nxt: dict[int, list[int]] = {}
    for a, c in b.tolist():
        nxt.setdefault(a, []).append(c)
    loops = []
    for start in list(nxt):
        while nxt.get(start):
            loop = [start]
            cur = nxt[start].pop()
            while cur != start and nxt.get(cur) and len(loop) <= len(b):
                loop.append(cur)
                cur = nxt[cur].pop()
            if cur == start and len(loop) >= 3:
                loops.append(np.asarray(loop, dtype=np.int64))
    return loops


# ----------------------------------------------------------------------------------------------
# the slicing kernel


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
def _slice_kernel(s, px, pz, edges, tri_verts, tri_edges, tris, levels, emap):
    """Slice the triangles ``tris`` of a mesh by the planes s = levels[k] (sorted ascending).

    A vertex is above a level when s >= level, so every crossed triangle has exactly two crossed
    edges; crossing points are joined into loops through the triangles. Returns
      X, Z        (P,) in-plane coordinates of the crossing points (level-major order)
      pcomp       (P,) component id of each point
      comp_level  (C,) level index of each component (components are level-major too)
      stats       (C, 9): hull perimeter, hull area, hull centroid x, z, xmin, xmax, zmin, zmax,
                  number of points
    ``emap`` is scratch: one int64 per mesh edge, all -1 on entry and on return (it maps the
    edges in play to compact local ids, so no per-call array is as long as the mesh).
    """
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
    fill = lvl_count[:nk].copy()
    X = np.empty(total)
    Z = np.empty(total)
    pid = np.empty(total, np.int64)
    for e in range(nl):
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
    for e in range(nl):
        emap[elist[e]] = -1
    # components, numbered in order of their first point (level-major)
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
    stats = np.zeros((nc, 9))
    hs = np.zeros(4)
    for c in range(nc):
        idx = order[ccount[c]:ccount[c + 1]]
        xs = X[idx]
        zs = Z[idx]
        _hull_stats(xs, zs, hs)
        stats[c, 0] = hs[0]
        stats[c, 1] = hs[1]
        stats[c, 2] = hs[2]
        stats[c, 3] = hs[3]
        stats[c, 4] = xs.min()
        stats[c, 5] = xs.max()
        stats[c, 6] = zs.min()
        stats[c, 7] = zs.max()
        stats[c, 8] = idx.shape[0]
    return X, Z, pcomp, comp_level, stats


# ----------------------------------------------------------------------------------------------
# sections in Python: a slicer bound to one scalar field, and the sections it returns


class _Sections:
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
        return self.stats[c, 0]

    def centroid(self, c):
        return self.stats[c, 2], self.stats[c, 3]

    def inside(self, c, box, margin=0.0):
        """Is the hull centroid of component c inside box = (xmin, xmax, zmin, zmax)?"""
        cx, cz = self.stats[c, 2], self.stats[c, 3]
        return (box[0] - margin <= cx <= box[1] + margin
                and box[2] - margin <= cz <= box[3] + margin)

    def box(self, c):
        return self.stats[c, 4:8].copy()


class _Slicer:
    """Slices one mesh by the level sets of a per-vertex scalar ``s`` (a plane's normal
    coordinate); ``px, pz`` are the in-plane coordinates carried to the section points."""

    def __init__(self, topo: _Topology, s, px, pz, tri_mask=None):
        if len(s) != topo.nverts or len(px) != topo.nverts or len(pz) != topo.nverts:
            raise ValueError("slicer: one value per vertex (hole fans included) is needed")
        self.topo = topo
        self.s = np.ascontiguousarray(s, dtype=np.float64)
        self.px = np.ascontiguousarray(px, dtype=np.float64)
        self.pz = np.ascontiguousarray(pz, dtype=np.float64)
        self.tris = topo.all_tris if tri_mask is None else np.nonzero(tri_mask)[0]
        self.tlo = None

    def with_bands(self) -> _Slicer:
        """Sort the triangles by their lowest s, so that each call only visits the triangles
        that can reach its levels (worth it for many calls with few levels)."""
        lo, hi = _tri_range(self.s, self.topo.faces)
        lo, hi = lo[self.tris], hi[self.tris]
        order = np.argsort(lo, kind="stable")
        self.tris = np.ascontiguousarray(self.tris[order])
        self.tlo = lo[order]
        self.hmax = float((hi - lo).max()) if len(lo) else 0.0
        return self

    def slice(self, levels) -> _Sections:
        levels = np.ascontiguousarray(levels, dtype=np.float64)
        tris = self.tris
        if self.tlo is not None:
            # a triangle reaches a level L when lo < L <= hi, and hi <= lo + hmax
            i0 = np.searchsorted(self.tlo, levels[0] - self.hmax, side="left")
            i1 = np.searchsorted(self.tlo, levels[-1], side="left")
            tris = tris[i0:i1]
        out = _slice_kernel(self.s, self.px, self.pz, self.topo.edges, self.topo.faces,
                            self.topo.tri_edges, tris, levels, self.topo.emap)
        return _Sections(levels, *out)


@numba.njit(cache=True)
def _flood(seed, allowed, ptr, nbr):
    """Vertices reachable from ``seed`` through edges between allowed vertices."""
    seen = np.zeros(allowed.shape[0], np.bool_)
    stack = np.empty(allowed.shape[0], np.int64)
    seen[seed] = True
    stack[0] = seed
    top = 1
    while top > 0:
        top -= 1
        v = stack[top]
        for j in range(ptr[v], ptr[v + 1]):
            w = nbr[j]
            if allowed[w] and not seen[w]:
                seen[w] = True
                stack[top] = w
                top += 1
    return seen


@numba.njit(cache=True)
def _tris_within(vmask, faces):
    """Triangles whose three vertices are all in the mask."""
    out = np.zeros(faces.shape[0], np.bool_)
    for f in range(faces.shape[0]):
        out[f] = vmask[faces[f, 0]] and vmask[faces[f, 1]] and vmask[faces[f, 2]]
    return out


@numba.njit(cache=True)
def _tri_range(s, faces):
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


def _parabola_vertex(y, g, i):
    """Refine an extremum of samples g(y) at interior index i by a parabola through i-1, i, i+1.
    Returns (y*, g*); at an end of the range the sample itself."""
    n = len(g)
    if i <= 0 or i >= n - 1:
        return float(y[i]), float(g[i])
    g0, g1, g2 = g[i - 1], g[i], g[i + 1]
    den = g0 - 2.0 * g1 + g2
    if abs(den) < 1e-15:
        return float(y[i]), float(g1)
    d = 0.5 * (g0 - g2) / den
    d = max(-1.0, min(1.0, d))
    h = y[i + 1] - y[i]
    return float(y[i] + d * h), float(g1 - 0.25 * (g0 - g2) * d)


def _soft_arg(y, f, tau, lo, hi, taper=0.015):
    """Soft arg-min of samples f(y) over the window [lo, hi]: the mean level weighted by
    exp(-(f - min f) / tau), the weights tapering to zero over ``taper`` at the window's ends.
    Unlike a hard arg-min it moves continuously as the profile and the window change (two
    near-equal minima average instead of jumping)."""
    wt = np.clip((y - lo) / taper, 0.0, 1.0) * np.clip((hi - y) / taper, 0.0, 1.0)
    inside = wt > 0
    if not inside.any():
        return float(0.5 * (lo + hi))
    w = wt * np.exp(-(f - f[inside].min()) / tau)
    return float(np.sum(w * y) / np.sum(w))


# ----------------------------------------------------------------------------------------------
# the measurement


def _largest(sec: _Sections, k: int, box=None, margin=0.01, exclude=()):
    best, bp = -1, -1.0
    for c in sec.comps(k):
        if c in exclude:
            continue
        if box is not None and not sec.inside(c, box, margin):
            continue
        if sec.stats[c, 0] > bp:
            best, bp = c, sec.stats[c, 0]
    return best


def _fail(what: str) -> InputError:
    return InputError(
        f"measure: {what}; the body must stand upright in glTF axes (+Y up, facing +Z), "
        "legs apart and arms hanging clear of the torso (A-pose)")


class _Body:
    """One measurement in progress (keeps the slicers and the coarse horizontal sections)."""

    K = 160  # coarse horizontal levels over the height

    def __init__(self, V: np.ndarray, topo: _Topology):
        self.V = V
        self.topo = topo
        y = V[topo.used, 1]
        self.ymin = float(y.min())
        self.ymax = float(y.max())
        self.H = self.ymax - self.ymin
        self.hs = _Slicer(topo, V[:, 1], V[:, 0], V[:, 2]).with_bands()
        K = self.K
        self.levels = self.ymin + self.H * (np.arange(K) + 0.5) / K
        self.sec = self.hs.slice(self.levels)
        self.dy = self.H / K

    # -- structure: torso chain, crotch, armpits ------------------------------------------------
    def structure(self):
        sec, K = self.sec, self.K
        k_start = int(0.58 * K)
        t0 = _largest(sec, k_start)
        if t0 < 0:
            raise _fail("no surface at mid-height")
        torso = np.full(K, -1)
        torso[k_start] = t0
        crotch_k = None
        for k in range(k_start - 1, -1, -1):
            prev = torso[k + 1]
            box = sec.box(prev)
            pprev = sec.stats[prev, 0]
            cand = [c for c in sec.comps(k)
                    if sec.inside(c, box, 0.01) and sec.stats[c, 0] > 0.15 * pprev]
            if not cand:
                break
            cand.sort(key=lambda c: -sec.stats[c, 0])
            if len(cand) >= 2:
                pcx = sec.stats[prev, 2]
                xa, xb = sec.stats[cand[0], 2], sec.stats[cand[1], 2]
                if (xa - pcx) * (xb - pcx) < 0:
                    crotch_k = k
                    break
            torso[k] = cand[0]
        if crotch_k is None:
            raise _fail("no crotch found (the legs never separate)")
        seen = {1: False, -1: False}
        armpit_k: dict[int, int] = {}
        top_k = K - 1
        for k in range(k_start + 1, K):
            prev = torso[k - 1]
            c = _largest(sec, k, sec.box(prev), 0.01)
            if c < 0:
                top_k = k - 1
                break
            torso[k] = c
            tb = sec.box(c)
            for side in (1, -1):
                if side in armpit_k:
                    continue
                arm = self._arm_comp(sec, k, c, tb, side)
                if arm >= 0:
                    seen[side] = True
                elif seen[side]:
                    armpit_k[side] = k
        if len(armpit_k) < 2:
            raise _fail("no armpits found (an arm never separates from the torso)")
        self.torso = torso
        self.top_k = top_k
        self.crotch_k = crotch_k
        self.armpit_k = armpit_k

    @staticmethod
    def _arm_comp(sec, k, torso_c, tb, side, min_perim=0.03):
        best, bp = -1, -1.0
        for a in sec.comps(k):
            if a == torso_c or sec.stats[a, 0] < min_perim:
                continue
            ax = sec.stats[a, 2]
            if (side > 0 and ax > tb[1]) or (side < 0 and ax < tb[0]):
                if sec.stats[a, 0] > bp:
                    best, bp = a, sec.stats[a, 0]
        return best

    def _bisect(self, lo, hi, pred, rounds=2, n=16):
        """pred(sections, k) is truthy at lo and not at hi: the switching level, to 1/n**rounds
        of the interval (each round slices n + 1 levels in one call)."""
        for _ in range(rounds):
            lv = np.linspace(lo, hi, n + 1)
            sec = self.hs.slice(lv)
            j = 0
            while j < n - 1 and pred(sec, j + 1):
                j += 1
            lo, hi = lv[j], lv[j + 1]
        return 0.5 * (lo + hi)

    def crotch(self):
        k = self.crotch_k
        above = self.torso[k + 1]
        box = self.sec.box(above)
        pmin = 0.15 * self.sec.stats[above, 0]
        pcx = self.sec.stats[above, 2]

        def legs(s1, k=0):
            cand = [c for c in s1.comps(k)
                    if s1.inside(c, box, 0.01) and s1.stats[c, 0] > pmin]
            if len(cand) < 2:
                return None
            cand.sort(key=lambda c: -s1.stats[c, 0])
            a, b = cand[0], cand[1]
            if (s1.stats[a, 2] - pcx) * (s1.stats[b, 2] - pcx) >= 0:
                return None
            return s1, a, b

        yc = self._bisect(self.levels[k], self.levels[k + 1], lambda s1, i: legs(s1, i))
        got = legs(self.hs.slice(np.array([yc - 1e-4]))) or legs(self.sec, k)
        s1, a, b = got
        if s1.stats[a, 2] < s1.stats[b, 2]:
            a, b = b, a  # a = left leg (+x)
        x = 0.5 * (s1.stats[a, 4] + s1.stats[b, 5])
        z = 0.5 * (s1.stats[a, 3] + s1.stats[b, 3])
        self.crotch_y = yc
        self.crotch_pt = np.array([x, yc, z])

    def armpits(self):
        self.armpit_pt = {}
        for side, k in self.armpit_k.items():
            below_t = self.torso[k - 1]
            box = self.sec.box(below_t)

            def arm(s1, i=0, side=side, box=box):
                t = _largest(s1, i, box, 0.01)
                if t < 0:
                    return None
                a = self._arm_comp(s1, i, t, s1.box(t), side)
                return None if a < 0 else (s1, t, a)

            ya = self._bisect(self.levels[k - 1], self.levels[k], lambda s1, i: arm(s1, i))
            got = arm(self.hs.slice(np.array([ya - 1e-4]))) or arm(self.sec, k - 1)
            s1, t, a = got
            if side > 0:
                x = 0.5 * (s1.stats[t, 5] + s1.stats[a, 4])
            else:
                x = 0.5 * (s1.stats[t, 4] + s1.stats[a, 5])
            z = 0.5 * (s1.stats[t, 3] + s1.stats[a, 3])
            self.armpit_pt[side] = np.array([x, ya, z])
        self.armpit_y = min(p[1] for p in self.armpit_pt.values())

    # -- torso girths --------------------------------------------------------------------------
    def _coarse_box(self, y):
        k = int(np.clip(np.round((y - self.ymin) / self.dy - 0.5), 0, self.K - 1))
        c = self.torso[k]
        if c < 0:
            return None
        return self.sec.box(c)

    def torso_at(self, levels):
        """Torso loop at arbitrary levels: (girth, stats rows) per level."""
        levels = np.atleast_1d(np.asarray(levels, dtype=np.float64))
        s1 = self.hs.slice(levels)
        g = np.full(len(levels), np.nan)
        rows = np.full((len(levels), 9), np.nan)
        for i, h in enumerate(levels):
            box = self._coarse_box(h)
            c = _largest(s1, i, box, 0.02)
            if c >= 0:
                g[i] = s1.stats[c, 0]
                rows[i] = s1.stats[c]
        return g, rows

    def _refine_extremum(self, y_c, sign, half=1.5, n=9, lo=None, hi=None, width=False):
        """Refine a max (sign=+1) or min (sign=-1) of the torso girth (or, with ``width``, of
        its left-right width) near y_c (within [lo, hi] if given): a grid, then a
        golden-section search on the exact section, so the extremum moves continuously with
        the shape. Returns (level, girth there, the loop's stats row)."""
        a = y_c - half * self.dy if lo is None else lo
        b = y_c + half * self.dy if hi is None else hi
        lv = np.linspace(a, b, n)

        def value(g, rows):
            return rows[:, 5] - rows[:, 4] if width else g

        g, rows = self.torso_at(lv)
        g = value(g, rows)
        gg = np.where(np.isnan(g), -np.inf, sign * g)
        # the grid's local maxima; search the best two exactly (two peaks may swap places)
        left = np.concatenate([[-np.inf], gg[:-1]])
        right = np.concatenate([gg[1:], [-np.inf]])
        peaks = np.nonzero((gg >= left) & (gg >= right) & np.isfinite(gg))[0]
        if not len(peaks):
            peaks = np.array([int(np.argmax(gg))])
        peaks = peaks[np.argsort(-gg[peaks])][:2]
        if len(peaks) == 2 and gg[peaks[1]] < gg[peaks[0]] - 0.003:
            peaks = peaks[:1]  # a runner-up 3 mm behind on the grid cannot win

        def f(y):
            v = value(*self.torso_at([y]))[0]
            return -np.inf if np.isnan(v) else sign * v

        best_y, best_f = None, -np.inf
        for i in peaks:
            y = _golden_max(f, lv[max(i - 1, 0)], lv[min(i + 1, n - 1)])
            fy = f(y)
            if fy > best_f:
                best_y, best_f = y, fy
        g1, r1 = self.torso_at([best_y])
        return best_y, float(g1[0]), r1[0]

    def girths(self, sex):
        sec = self.sec
        ks = np.arange(self.crotch_k + 1, min(self.armpit_k.values()))
        ks = ks[self.torso[ks] >= 0]
        ys = self.levels[ks]
        st = sec.stats[self.torso[ks]]
        g, zmin, zmax = st[:, 0], st[:, 6], st[:, 7]
        span = self.armpit_y - self.crotch_y
        out = {}
        lm = {}

        def centre(y, row):
            return [float(row[2]), float(y), float(row[3])]

        # hips: level of greatest buttock prominence (most posterior torso point)
        y_hip = _soft_arg(ys, zmin, 0.003, self.crotch_y, self.crotch_y + 0.4 * span)
        gh, rh = self.torso_at([y_hip])
        out["hips"] = float(gh[0])
        lm["hips"] = centre(y_hip, rh[0])
        # bust point level: the uppermost peak of front protrusion below the armpits (the bust
        # points sit at 85-95 % of the way from crotch to armpits; an obese belly makes a second,
        # lower and often larger peak at 45-67 %; no peak above 72 %: 90 %), refined by a soft
        # arg-max around it
        top = self.armpit_y - 0.01
        cand = np.nonzero((ys >= self.crotch_y + 0.72 * span) & (ys <= top))[0]
        peaks = [i for i in cand if 0 < i < len(ys) - 1
                 and zmax[i] >= zmax[i - 1] and zmax[i] >= zmax[i + 1]]
        if peaks:
            y_peak = ys[max(peaks)]
            y_bp = _soft_arg(ys, -zmax, 0.002, max(y_peak - 0.04, self.crotch_y + 0.55 * span),
                             min(y_peak + 0.04, top))
        else:
            y_bp = self.crotch_y + 0.9 * span
        hi = min(y_bp + 0.03, self.armpit_y - 0.015)
        lo = min(y_bp - 0.03, hi - 0.01)
        y_b, gbust, r1 = self._refine_extremum(y_bp, 1.0, n=13, lo=lo, hi=hi)
        out["bust"] = out["chest"] = gbust
        lm["bust"] = centre(y_b, r1)
        # underbust: the fold under the breast = least front protrusion just below the bust point
        y_top_waist = y_bp - 0.04
        if sex != "male":
            if True:
                # the fold's minimum is sharp and the girth steep around it: use a fine profile
                a, b = y_bp - 0.06 * self.H, y_bp - 0.005
                fy = np.linspace(a, b, max(8, int((b - a) / 0.002) + 1))
                _g, frows = self.torso_at(fy)
                fz = np.where(np.isnan(frows[:, 7]), np.inf, frows[:, 7])
                y_ub = _soft_arg(fy, fz, 0.001, a, b)
                gu, ru = self.torso_at([y_ub])
                out["underbust"] = float(gu[0])
                lm["underbust"] = centre(y_ub, ru[0])
                y_top_waist = min(y_top_waist, y_ub - 0.01)
            # bust points: on each side, the most forward point of the breast, by a soft
            # arg-max (τ = 2 mm) of the surface's forward protrusion within 5 cm of the bust
            # level (the breast's front is nearly flat across: a plain maximum, or one slice's,
            # jumps by centimetres when the surface is remeshed or smoothed)
            V = self.V
            near = (np.abs(V[:, 1] - y_b) < 0.05) & (V[:, 2] > r1[3])
            for side, name in ((1, "bust_point_left"), (-1, "bust_point_right")):
                dx = side * (V[:, 0] - r1[2])
                P = V[near & (dx > 0.01) & (dx < 0.16)]
                if len(P) < 3:
                    raise _fail("no bust point found")
                w = np.exp((P[:, 2] - P[:, 2].max()) / 0.002)
                lm[name] = [float(t) for t in (w[:, None] * P).sum(axis=0) / w.sum()]
            out["bust_span"] = abs(lm["bust_point_left"][0] - lm["bust_point_right"][0])
        # waist: least torso girth between the hips and the underbust / bust
        m = (ys > y_hip + 0.02) & (ys < y_top_waist)
        idx = np.nonzero(m)[0]
        if not len(idx):
            raise _fail("no waist between the hips and the bust")
        i = idx[int(np.argmin(g[idx]))]
        y_w, gw, rw = self._refine_extremum(ys[i], -1.0)
        out["waist"] = gw
        lm["waist"] = centre(y_w, rw)
        self.bust_y = y_b
        return out, lm

    # -- neck and shoulders --------------------------------------------------------------------
    def neck(self):
        ks = np.arange(max(self.armpit_k.values()), self.top_k + 1)
        ks = ks[(self.torso[ks] >= 0) & (self.levels[ks] <= self.ymax - 0.10 * self.H)]
        if not len(ks):
            raise _fail("no neck found")
        g = self.sec.stats[self.torso[ks], 0]
        i = int(np.argmin(g))
        y_n, gn, rn = self._refine_extremum(self.levels[ks[i]], -1.0)
        self.neck_y = y_n
        self.neck_row = rn
        return gn

    def shoulders(self):
        V, topo = self.V, self.topo
        y_lo = self.armpit_y - 0.06 * self.H
        y_hi = self.neck_y
        tlo, thi = _tri_range(V[:, 1], topo.faces)
        band = (tlo >= y_lo) & (thi <= y_hi)
        vb = (V[:, 1] >= y_lo) & (V[:, 1] <= y_hi)
        xs_band = V[vb, 0]
        vs = _Slicer(topo, V[:, 0], V[:, 1], V[:, 2], tri_mask=band).with_bands()
        self.acromion = {}
        self.side_neck = {}
        for side in (1, -1):
            xn = self.neck_row[5] if side > 0 else self.neck_row[4]
            xfar = xs_band.max() if side > 0 else xs_band.min()
            reach = min(0.13 * self.H, abs(xfar - xn) - 0.002)
            if reach <= 0.02:
                raise _fail("no shoulder found")
            xl = xn + side * np.linspace(0.002, reach, 64)
            order = np.argsort(xl)
            lv = xl[order]
            s1 = vs.slice(lv)
            ytop = np.full(len(lv), np.nan)
            ztop = np.full(len(lv), np.nan)
            b = np.searchsorted(s1.comp_level, np.arange(len(lv) + 1))
            pb = np.searchsorted(s1.pcomp, b) if len(s1.pcomp) else b
            for i in range(len(lv)):
                if pb[i + 1] > pb[i]:
                    seg = slice(pb[i], pb[i + 1])
                    j = pb[i] + int(np.argmax(s1.X[seg]))
                    # y: the top of the section; z: the hull centre of the loop holding it
                    # (continuous in the shape, unlike the z of the single highest point)
                    ytop[i] = s1.X[j]
                    ztop[i] = s1.stats[s1.pcomp[j], 3]
            inv = np.empty_like(order)
            inv[order] = np.arange(len(order))
            ytop, ztop = ytop[inv], ztop[inv]  # ordered from the neck outwards
            ok = ~np.isnan(ytop)
            n_ok = int(np.argmin(ok)) if not ok.all() else len(ok)
            if n_ok < 8:
                raise _fail("no shoulder contour found")
            xd = np.abs(xl[:n_ok] - xn)
            yt = ytop[:n_ok]
            zt = ztop[:n_ok]
            # acromion: the convex corner of the upper contour (farthest above the chord), on
            # the stretch from 5 cm inside to 10 cm outside the armpit (a bulky trapezius
            # makes the whole contour a dome, so the neck is kept out of the chord)
            xa = abs(self.armpit_pt[side][0] - xn)
            x0 = float(np.clip(xa - 0.05, xd[0], xd[-1] - 0.02))
            x1 = float(np.clip(xa + 0.10, x0 + 0.02, xd[-1]))
            p0 = np.array([x0, np.interp(x0, xd, yt)])
            p1 = np.array([x1, np.interp(x1, xd, yt)])
            chord = (p1 - p0) / np.linalg.norm(p1 - p0)

            def above(x, y, p0=p0, chord=chord):
                return chord[0] * (y - p0[1]) - chord[1] * (x - p0[0])

            # soft arg-max over the outline samples (a rounded shoulder has a broad corner;
            # averaging keeps scan noise from throwing it about)
            da = _soft_arg(xd, -above(xd, yt), 0.003, x0, x1, taper=0.01)
            ya = float(np.interp(da, xd, yt))
            za = float(np.interp(da, xd, zt))
            self.acromion[side] = np.array([xn + side * da, ya, za])
            # side neck point: going out from the neck, where the outline's descent first
            # flattens below 45 degrees (the neck's wall meets the shoulder slope)
            dd = xd[0]
            ia = int(np.searchsorted(xd, da))
            st = 3  # slopes over ~1 cm, so that scan noise does not fake a flat spot
            if ia > st:
                slope = -(yt[st: ia + 1] - yt[: ia + 1 - st]) / (xd[st: ia + 1] - xd[: ia + 1 - st])
                xm = 0.5 * (xd[st: ia + 1] + xd[: ia + 1 - st])
                below = np.nonzero(slope < 1.0)[0]
                if len(below):
                    j = int(below[0])
                    if j == 0:
                        dd = xm[0]
                    else:  # interpolate the crossing of slope = 1
                        t = (slope[j - 1] - 1.0) / (slope[j - 1] - slope[j])
                        dd = float(xm[j - 1] + t * (xm[j] - xm[j - 1]))
            self.side_neck[side] = np.array([xn + side * dd, float(np.interp(dd, xd, yt)),
                                             float(np.interp(dd, xd, zt))])

    def shoulder_width(self):
        """Tape length across the back from acromion to acromion, in the plane through both
        acromions that contains the front-back (z) direction."""
        A_l, A_r = self.acromion[1], self.acromion[-1]
        eu = A_l - A_r
        eu /= np.linalg.norm(eu)
        n = np.cross(eu, [0.0, 0.0, 1.0])
        n /= np.linalg.norm(n)
        if n[1] < 0:
            n = -n
        ew = np.cross(n, eu)  # in-plane, ~ +z or -z
        if ew[2] < 0:
            ew = -ew
        V = self.V
        mask = _tri_range(V[:, 1], self.topo.faces)[0] >= self.armpit_y
        sl = _Slicer(self.topo, V @ n, V @ eu, V @ ew, tri_mask=mask)
        s0 = float(A_l @ n)
        s1 = sl.slice(np.array([s0]))
        ul, ur = float(A_l @ eu), float(A_r @ eu)
        keep = (s1.X > ur) & (s1.X < ul)
        u = np.concatenate([[ur], s1.X[keep], [ul]])
        w = np.concatenate([[float(A_r @ ew)], s1.Z[keep], [float(A_l @ ew)]])
        return _lower_chain_length(u, w)

    # -- arms and legs -------------------------------------------------------------------------
    def arms(self):
        V, topo = self.V, self.topo
        y_cut = self.armpit_y - 0.005
        below = V[:, 1] < y_cut
        ptr, nbr = topo.adjacency()
        used = topo.used
        foot = used[np.argmin(V[used, 1])]
        self.wrist, self.elbow, self.arm_length, self.upper_arm = {}, {}, {}, {}
        for side in (1, -1):
            ap = self.armpit_pt[side]
            # the arm: the surface below the armpits reachable from its most lateral vertex
            # without going above them (it must not reach the feet: then it touches the body)
            sx = np.where(below, side * V[:, 0], -np.inf)
            sx[topo.n_orig:] = -np.inf  # seed on the given surface, not on a hole's fan
            seed = int(np.argmax(sx))
            if not np.isfinite(sx[seed]) or side * (V[seed, 0] - self.crotch_pt[0]) <= 0:
                raise _fail("no arm found below the armpit")
            in_arm = _flood(seed, below, ptr, nbr)
            if in_arm[foot]:
                raise _fail("an arm touches the body below the armpit")
            av = np.nonzero(in_arm)[0]
            P = V[av]
            tip = P[np.argmax(np.einsum("ij,ij->i", P - ap, P - ap))]
            c = P.mean(axis=0)
            _, _, vt = np.linalg.svd(P - c, full_matrices=False)
            d = vt[0]
            if d @ (tip - ap) < 0:
                d = -d
            e1 = np.array([d[1], -d[0], 0.0])  # d x z
            if e1 @ e1 < 1e-12:
                e1 = np.array([0.0, d[2], -d[1]])  # d x x
            e1 /= np.sqrt(e1 @ e1)
            e2 = np.array([d[1] * e1[2] - d[2] * e1[1], d[2] * e1[0] - d[0] * e1[2],
                           d[0] * e1[1] - d[1] * e1[0]])
            tmask = _tris_within(in_arm, topo.faces)
            sl = _Slicer(topo, V @ d, V @ e1, V @ e2, tri_mask=tmask).with_bands()
            t_tip = float(tip @ d)
            lv = t_tip - self.H * np.linspace(0.16, 0.06, 26)
            s1 = sl.slice(lv)
            gw = np.full(len(lv), np.inf)
            for i in range(len(lv)):
                cs = s1.comps(i)
                if len(cs):
                    gw[i] = s1.stats[cs, 0].max()
            i = int(np.argmin(gw))
            if not np.isfinite(gw[i]):
                raise _fail("no wrist found")

            def neg_girth(t, sl=sl):
                s2 = sl.slice(np.array([t]))
                cs = s2.comps(0)
                return -float(s2.stats[cs, 0].max()) if len(cs) else -np.inf

            tw = _golden_max(neg_girth, lv[max(i - 1, 0)], lv[min(i + 1, len(lv) - 1)])
            W = self._axis_point(sl, tw, d, e1, e2)
            A = self.acromion[side]
            t_a = float(A @ d)
            t_e = tw - 0.48 * (tw - t_a)
            E = self._axis_point(sl, t_e, d, e1, e2)
            if E is None:
                E = A + (t_e - t_a) / max(tw - t_a, 1e-9) * (W - A)
            self.wrist[side] = W
            self.elbow[side] = E
            self.arm_length[side] = float(np.linalg.norm(E - A) + np.linalg.norm(W - E))
            # upper-arm girth: the greatest girth across the arm between 40 % and 90 % of the
            # way from the acromion to the elbow (above that, sections run into the cut under
            # the armpit and come out short)
            t_e = float(E @ d)
            lu = t_a + (t_e - t_a) * np.linspace(UPPER_ARM_RANGE[0], UPPER_ARM_RANGE[1], 12)
            s3 = sl.slice(lu)
            gu = np.array([s3.stats[s3.comps(i), 0].max() if len(s3.comps(i)) else -np.inf
                           for i in range(len(lu))])
            i = int(np.argmax(gu))
            if not np.isfinite(gu[i]):
                raise _fail("no upper arm found")
            tu = _golden_max(lambda t, sl=sl: -neg_girth(t, sl), lu[max(i - 1, 0)],
                             lu[min(i + 1, len(lu) - 1)])
            self.upper_arm[side] = max(-neg_girth(tu), float(gu[i]))

    @staticmethod
    def _axis_point(sl, t, d, e1, e2):
        s1 = sl.slice(np.array([t]))
        cs = s1.comps(0)
        if not len(cs):
            return None
        c = cs[int(np.argmax(s1.stats[cs, 0]))]
        u, w = s1.stats[c, 2], s1.stats[c, 3]
        return t * d + u * e1 + w * e2

    def legs(self):
        sec = self.sec
        k = self.crotch_k
        # the two leg loops just below the crotch
        above = self.torso[k + 1]
        box = sec.box(above)
        cand = [c for c in sec.comps(k) if sec.inside(c, box, 0.01)]
        cand.sort(key=lambda c: -sec.stats[c, 0])
        a, b = cand[0], cand[1]
        if sec.stats[a, 2] < sec.stats[b, 2]:
            a, b = b, a
        self.knee, self.ankle = {}, {}
        for side, c0 in ((1, a), (-1, b)):
            chain = np.full(k + 1, -1)
            chain[k] = c0
            for kk in range(k - 1, -1, -1):
                prev = chain[kk + 1]
                px, pz = sec.stats[prev, 2], sec.stats[prev, 3]
                best, bd = -1, np.inf
                for c in sec.comps(kk):
                    if sec.stats[c, 0] < 0.05 or not sec.inside(c, sec.box(prev), 0.02):
                        continue
                    dd = (sec.stats[c, 2] - px) ** 2 + (sec.stats[c, 3] - pz) ** 2
                    if dd < bd:
                        best, bd = c, dd
                if best < 0:
                    break
                chain[kk] = best
            ks = np.nonzero(chain >= 0)[0]
            ys = self.levels[ks]
            st = sec.stats[chain[ks]]
            m = (ys >= self.ymin + 0.03 * self.H) & (ys <= self.ymin + 0.15 * self.H)
            idx = np.nonzero(m)[0]
            if not len(idx):
                raise _fail("no ankle found")
            i = idx[int(np.argmin(st[idx, 0]))]
            y_g, _ = _parabola_vertex(ys, -st[:, 0], i)  # least ankle girth, above the malleoli
            ax = float(np.interp(y_g, ys, st[:, 2]))
            az = float(np.interp(y_g, ys, st[:, 3]))
            y_a = min(y_g, self.ymin + 0.042 * self.H)  # the ankle joint (malleolus height)
            self.ankle[side] = np.array([ax, y_a, az])
            y_k = y_g + 0.53 * (self.crotch_y - y_g)
            self.knee[side] = np.array([float(np.interp(y_k, ys, st[:, 2])), y_k,
                                        float(np.interp(y_k, ys, st[:, 3]))])


#: where the upper-arm girth is looked for: fractions of the way from the acromion to the elbow
UPPER_ARM_RANGE = (0.4, 0.9)


def _golden_max(f, a, b, iters=12):
    """Golden-section search for the maximum of f on [a, b]."""
    r = 0.6180339887498949
    c = b - r * (b - a)
    d = a + r * (b - a)
    fc, fd = f(c), f(d)
    for _ in range(iters):
        if fc >= fd:
            b, d, fd = d, c, fc
            c = b - r * (b - a)
            fc = f(c)
        else:
            a, c, fc = c, d, fd
            d = a + r * (b - a)
            fd = f(d)
    return 0.5 * (a + b)


def _lower_chain_length(u, w):
    """Length of the lower convex hull (smallest w) of the points, from min u to max u."""
    order = np.lexsort((w, u))
    pu, pw = u[order], w[order]
    hu, hw = [], []
    for a, b in zip(pu.tolist(), pw.tolist(), strict=True):
        while len(hu) >= 2 and ((hu[-1] - hu[-2]) * (b - hw[-2])
                                - (hw[-1] - hw[-2]) * (a - hu[-2])) <= 0.0:
            hu.pop()
            hw.pop()
        hu.append(a)
        hw.append(b)
    return float(np.sum(np.hypot(np.diff(hu), np.diff(hw))))


def measure_body(vertices, faces, sex: str | None = None) -> dict:
    """Measurements (metres) and landmarks of a standing body in glTF axes.

    ``sex`` is ``"female"``, ``"male"`` or None; it only decides whether an underbust is
    reported (not for men). ``bust`` and ``chest`` are the same number. See
    ``docs/bodies-measure.md`` for the definitions.
    """
    V = np.asarray(vertices, dtype=np.float64)
    if V.ndim != 2 or V.shape[1] != 3 or len(V) < 4:
        raise InputError("measure: vertices must be an (N, 3) array")
    if not np.isfinite(V).all():
        raise InputError("measure: vertex coordinates contain NaN or infinity")
    if sex not in (None, "female", "male"):
        raise InputError(f"measure: sex must be 'female' or 'male', not {sex!r}")
    topo = _topology(np.asarray(faces), len(V))
    V = topo.extend(V)
    b = _Body(V, topo)
    if not 0.5 <= b.H <= 2.6:
        raise InputError(f"measure: the body is {b.H:.3f} m tall; expected a standing adult "
                         "in metres (0.5–2.6 m)")
    b.structure()
    b.crotch()
    b.armpits()
    girths, lm = b.girths(sex)
    neck = b.neck()
    b.shoulders()
    sw = b.shoulder_width()
    b.arms()
    b.legs()

    def p(a):
        return [float(t) for t in a]

    out = {
        "height": b.H,
        "bust": girths["bust"],
        "chest": girths["chest"],
        "underbust": girths.get("underbust"),
        "bust_span": girths.get("bust_span"),
        "waist": girths["waist"],
        "hips": girths["hips"],
        "inseam": float(b.crotch_y - b.ymin),
        "shoulder_width": float(sw),
        "arm_length": 0.5 * (b.arm_length[1] + b.arm_length[-1]),
        "upper_arm_girth": 0.5 * (b.upper_arm[1] + b.upper_arm[-1]),
        "neck_girth": float(neck),
    }
    if sex == "male":
        out.pop("underbust")
        out.pop("bust_span")
        for k in ("underbust", "bust_point_left", "bust_point_right"):
            lm.pop(k, None)
    landmarks = {
        "neck_base": p(0.5 * (b.side_neck[1] + b.side_neck[-1])),
        "neck_side_left": p(b.side_neck[1]),
        "neck_side_right": p(b.side_neck[-1]),
        "shoulder_left": p(b.acromion[1]),
        "shoulder_right": p(b.acromion[-1]),
        "armpit_left": p(b.armpit_pt[1]),
        "armpit_right": p(b.armpit_pt[-1]),
        **lm,
        "crotch": p(b.crotch_pt),
        "elbow_left": p(b.elbow[1]),
        "elbow_right": p(b.elbow[-1]),
        "wrist_left": p(b.wrist[1]),
        "wrist_right": p(b.wrist[-1]),
        "knee_left": p(b.knee[1]),
        "knee_right": p(b.knee[-1]),
        "ankle_left": p(b.ankle[1]),
        "ankle_right": p(b.ankle[-1]),
        "neck": [float(b.neck_row[2]), float(b.neck_y), float(b.neck_row[3])],
        "top_of_head": p(V[topo.used[np.argmax(V[topo.used, 1])]]),
    }
    out["landmarks"] = landmarks
    return out
