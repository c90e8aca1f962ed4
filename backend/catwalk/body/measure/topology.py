"""The mesh's connectivity for measuring, cached per face array (:func:`mesh_topology`): its
edges, each triangle's edges, the holes closed by fans (scans have them), the vertices' neighbours;
and two walks over it, a flood through allowed vertices (:func:`flood`) and the triangles within a
vertex set (:func:`tris_within`)."""

from __future__ import annotations

import hashlib
from dataclasses import dataclass

import numba
import numpy as np

from catwalk.errors import InputError


@dataclass(frozen=True)
class Topology:
    """A triangle mesh's connectivity, as the slicer walks it."""

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


def mesh_topology(faces: np.ndarray, nverts: int) -> Topology:
    """The topology of ``faces`` over ``nverts`` vertices (degenerate triangles dropped, holes
    closed by a fan from a new vertex at each boundary loop's mean), cached per face array."""
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
    topo = Topology(np.ascontiguousarray(f), edges, tri_edges, nverts, np.nonzero(used)[0],
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


@numba.njit(cache=True)
def flood(seed, allowed, ptr, nbr):
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
def tris_within(vmask, faces):
    """Triangles whose three vertices are all in the mask."""
    out = np.zeros(faces.shape[0], np.bool_)
    for f in range(faces.shape[0]):
        out[f] = vmask[faces[f, 0]] and vmask[faces[f, 1]] and vmask[faces[f, 2]]
    return out
