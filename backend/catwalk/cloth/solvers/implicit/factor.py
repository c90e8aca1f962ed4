"""The system matrix's sparse Cholesky factor, made once per garment by a library.

The implicit solver's matrix A (:mod:`catwalk.cloth.solvers.implicit.system`) does not change
while the garment is worn, so it is factored once: a fill-reducing order P (METIS's nested
dissection through pymetis; or SuperLU's minimum degree on A + Aᵀ, reverse Cuthill–McKee or
none), then SuperLU (scipy's ``splu``) on P·A·Pᵀ in its symmetric mode with no pivoting
(``permc_spec="NATURAL"``, ``diag_pivot_thresh=0``, no equilibration): for a symmetric
positive definite matrix that is the LDLᵀ factorisation — SuperLU's unit lower L and
U = D·Lᵀ —, taken here as the Cholesky factor L·√D in CSC arrays, the diagonal first in each
column. The solves over those arrays are numba kernels
(:func:`catwalk.cloth.solvers.implicit.kernels.solve_soa`); :class:`Factor` keeps the order
for a matrix of the same pattern (a new h, other pinned points: only the numeric part again).

scipy is imported at the top: the implicit solver's package is imported only where it is
used (:func:`catwalk.simulate.walking.cloth_solver`)."""

from __future__ import annotations

import numpy as np
import pymetis
import scipy.sparse as sp
from scipy.sparse.csgraph import reverse_cuthill_mckee
from scipy.sparse.linalg import splu

from catwalk.cloth.solvers.implicit.kernels import solve_soa
from catwalk.errors import InputError

ORDERS = ("metis", "mmd", "rcm", "natural")


def fill_reducing_order(a: sp.csc_matrix, order: str = "metis") -> np.ndarray:
    """A fill-reducing permutation of the symmetric matrix ``a`` (``perm[k]``: the row of
    ``a`` that becomes row k): ``metis`` (METIS's nested dissection through pymetis),
    ``mmd`` (SuperLU's multiple minimum degree on A + Aᵀ), ``rcm`` (reverse Cuthill–McKee)
    or ``natural``. Factor sizes on the paper's dress: ``tools/profile/implicit_phases.py``."""
    n = a.shape[0]
    if order == "metis":
        g = sp.csr_matrix(a, copy=True)
        g.setdiag(0)
        g.eliminate_zeros()
        adjacency = pymetis.CSRAdjacency(g.indptr.astype(np.int32), g.indices.astype(np.int32))
        perm, _ = pymetis.nested_dissection(adjacency)
        return np.asarray(perm, np.int64)
    if order == "natural":
        return np.arange(n, dtype=np.int64)
    if order == "rcm":
        return np.asarray(reverse_cuthill_mckee(a.tocsr(), symmetric_mode=True), np.int64)
    if order == "mmd":
        lu = splu(a.tocsc(), permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0,
                  options={"SymmetricMode": True})
        perm = np.empty(n, np.int64)
        perm[np.asarray(lu.perm_c, np.int64)] = np.arange(n)   # perm_c[i]: where column i goes
        return perm
    raise InputError(f"order must be one of {', '.join(ORDERS)}, got {order!r}")


def column_chains(lp: np.ndarray, li: np.ndarray, longest: int = 3) -> np.ndarray:
    """L's columns in runs of 1 to ``longest`` (≤ 3) consecutive columns, each column's
    pattern the previous one's without its diagonal (what the solve's
    :func:`~catwalk.cloth.solvers.implicit.kernels.solve_soa` takes a run at a time): (m, 2)
    int64 rows (first column, length)."""
    n = len(lp) - 1
    cnt = np.diff(lp)
    nests = np.zeros(n, bool)   # column j + 1 continues column j's run
    if n > 1:
        second = np.where(cnt[:-1] > 1, li[np.minimum(lp[:-2] + 1, len(li) - 1)], -1)
        nests[:-1] = (cnt[:-1] == cnt[1:] + 1) & (second == np.arange(1, n))
    out = []
    j = 0
    while j < n:
        c = 1
        while c < longest and j + c < n and nests[j + c - 1]:
            c += 1
        out.append((j, c))
        j += c
    return np.asarray(out, np.int64).reshape(-1, 2)


class Factor:
    """The Cholesky factor of a symmetric positive definite sparse matrix ``a`` (n × n), made
    by SuperLU after the fill-reducing ``order``: A = Pᵀ·L·Lᵀ·P with L in CSC arrays ``lp``,
    ``li``, ``lx`` (the diagonal first in each column) and ``perm[k]`` the row of A that is
    row k of P·A·Pᵀ. ``reuse``: a factor of a matrix of the same pattern, whose order is then
    taken again. :meth:`solve` solves for (n, 3) right-hand sides; ``nnz`` is L's size."""

    def __init__(self, a, order: str = "metis", reuse: Factor | None = None):
        a = sp.csc_matrix(a, dtype=np.float64)
        n = a.shape[0]
        if a.shape != (n, n):
            raise InputError(f"the system matrix must be square, got {a.shape}")
        a.sum_duplicates()
        a.sort_indices()
        pattern = (a.indptr, a.indices)
        if reuse is not None and reuse.n == n and reuse.order == order and \
                np.array_equal(reuse.pattern[0], pattern[0]) and \
                np.array_equal(reuse.pattern[1], pattern[1]):
            perm = reuse.perm
        else:
            perm = fill_reducing_order(a, order)
        self.n, self.order, self.perm, self.pattern = n, order, perm, pattern
        c = a[perm][:, perm].tocsc()
        try:
            lu = splu(c, permc_spec="NATURAL", diag_pivot_thresh=0.0,
                      options={"SymmetricMode": True, "Equil": False})
        except RuntimeError as exc:   # an exactly singular pivot
            raise InputError(f"the system matrix is not positive definite ({exc})") from None
        d = lu.U.diagonal()
        if not (np.array_equal(lu.perm_r, np.arange(n)) and np.array_equal(lu.perm_c, np.arange(n))
                and np.all(d > 0.0)):
            raise InputError("the system matrix is not positive definite (SuperLU pivoted or "
                             "met a pivot ≤ 0)")
        low = sp.csc_matrix(lu.L) @ sp.diags(np.sqrt(d))    # L·√D
        low = sp.csc_matrix(low)
        low.sort_indices()                                     # the diagonal first
        self.lp = low.indptr.astype(np.int64)
        self.li = low.indices.astype(np.int32)
        self.lx = np.ascontiguousarray(low.data, dtype=np.float64)
        self.chains = column_chains(self.lp, self.li)
        self._w = np.empty(3 * n)

    @property
    def nnz(self) -> int:
        return int(self.lp[-1])

    def solve(self, b: np.ndarray, out: np.ndarray | None = None) -> np.ndarray:
        """A⁻¹·b for ``b`` (n, 3) (``out`` may be ``b``)."""
        soa = np.ascontiguousarray(np.asarray(b, dtype=np.float64).T)
        solve_soa(self.lp, self.li, self.lx, self.perm, self.chains, soa, soa, self._w)
        out = np.empty_like(b, dtype=np.float64) if out is None else out
        out[:] = soa.T
        return out
