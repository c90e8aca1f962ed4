"""Triangle-mesh topology shared by the scan loader, the scan registration, the rig, the walk
checks and the test scans: sides as integer keys, unique edges, vertex adjacency, triangles
sharing a side, folds, connected pieces, and a mesh without the vertices no triangle uses."""

from __future__ import annotations

import numpy as np


def edge_keys(faces: np.ndarray, n: int) -> np.ndarray:
    """Each triangle side (vertex k to k + 1) as one int64 ``min · n + max``: 3F keys, side k
    of triangle t at 3t + k, shared sides repeated."""
    f = np.asarray(faces, dtype=np.int64)
    a, b = f.ravel(), np.roll(f, -1, axis=1).ravel()
    return np.minimum(a, b) * n + np.maximum(a, b)


def unique_edges(faces: np.ndarray, n: int) -> np.ndarray:
    """(E, 2) the mesh's edges, each once, lower vertex first."""
    key = np.unique(edge_keys(faces, n))
    return np.stack([key // n, key % n], 1)


def vertex_adjacency(faces: np.ndarray, n: int):
    """(n, n) scipy CSR matrix, 1.0 where two vertices share an edge (symmetric)."""
    from scipy.sparse import coo_matrix  # deferred: scipy loads in ≈ 0.3 s; only this path needs it

    e = unique_edges(faces, n)
    both = np.concatenate([e, e[:, ::-1]])
    return coo_matrix((np.ones(len(both)), (both[:, 0], both[:, 1])), shape=(n, n)).tocsr()


def face_pairs(faces: np.ndarray, n: int) -> np.ndarray:
    """(P, 2) the triangles sharing each interior side."""
    key = edge_keys(faces, n)
    order = np.argsort(key, kind="stable")
    same = key[order][1:] == key[order][:-1]
    return np.stack([order[:-1][same] // 3, order[1:][same] // 3], 1)


def face_cross(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """(F, 3) each triangle's (b − a) × (c − a): its normal times twice its area."""
    f = np.asarray(faces)
    return np.cross(vertices[f[:, 1]] - vertices[f[:, 0]], vertices[f[:, 2]] - vertices[f[:, 0]])


def face_normals(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """(F, 3) unit triangle normals (zero for a degenerate triangle)."""
    c = face_cross(vertices, faces)
    return c / (np.linalg.norm(c, axis=1, keepdims=True) + 1e-30)


def smooth_pairs(v0: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """(P, 2) triangles sharing a side whose normals are less than 60° apart in ``v0``."""
    pairs = face_pairs(faces, len(v0))
    n0 = face_normals(v0, faces)
    return pairs[np.sum(n0[pairs[:, 0]] * n0[pairs[:, 1]], 1) > 0.5]


def folds(x: np.ndarray, v0: np.ndarray, faces: np.ndarray, smooth=None) -> np.ndarray:
    """Triangle pairs folded over in ``x`` (their normals more than 90° apart) that were
    smooth in ``v0`` (``smooth``: :func:`smooth_pairs` of it, when already made)."""
    smooth = smooth_pairs(v0, faces) if smooth is None else smooth
    n = face_normals(x, faces)
    return smooth[np.sum(n[smooth[:, 0]] * n[smooth[:, 1]], 1) < 0.0]


def components(faces: np.ndarray, n: int) -> tuple[int, np.ndarray]:
    """(count, label per vertex) of the pieces the triangles connect (an unused vertex is a
    piece of its own)."""
    from scipy.sparse import coo_matrix  # deferred: scipy loads in ≈ 0.3 s; only this path needs it
    from scipy.sparse.csgraph import (
        connected_components,  # deferred: scipy loads in ≈ 0.3 s; only this path needs it
    )  # deferred: scipy loads in ≈ 0.3 s; only this path needs it

    f = np.asarray(faces, dtype=np.int64)     # two sides a triangle connect its three corners
    graph = coo_matrix((np.ones(2 * len(f)), (np.r_[f[:, 0], f[:, 1]], np.r_[f[:, 1], f[:, 2]])),
                       shape=(n, n))
    return connected_components(graph, directed=False)


def compact(vertices: np.ndarray, faces: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The mesh without the vertices no triangle uses (faces renumbered)."""
    f = np.asarray(faces, dtype=np.int64)
    used = np.zeros(len(vertices), dtype=bool)
    used[f.ravel()] = True
    if used.all():
        return vertices, f
    remap = np.cumsum(used) - 1
    return np.asarray(vertices)[used], remap[f]
