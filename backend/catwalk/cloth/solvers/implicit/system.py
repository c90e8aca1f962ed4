"""The implicit solver's constant system matrix and its quadratic bending energy.

Implicit Euler as a minimisation (Liu, Bargteil, O'Brien & Kavan 2013; Bouaziz et al. 2014):
x_{n+1} minimises ½·(x − y)ᵀM(x − y)/h² + E(x) with y = x_n + h·v_n. Its Newton matrix changes
with the springs' directions; the matrix here does not:

    A = M·(1/h² + air/h) + Σ_springs (k + c/h)·AₛᵀAₛ + B_bend

(Aₛ the spring's difference operator x_b − x_a; k its stiffness, c its damping along it, taken
in every direction: an upper bound of each spring's Hessian, so that the iteration
x ← x − A⁻¹·∇g(x) does not overshoot; B_bend the quadratic bending energy's Hessian, which is
exact). The same n × n matrix serves x, y and z.

B_bend the quadratic bending's constant Hessian: :mod:`catwalk.cloth.bending`.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from catwalk.cloth.model import ClothModel


def laplacian(n: int, a: np.ndarray, b: np.ndarray, w: np.ndarray) -> sp.csc_matrix:
    """Σ wₛ·AₛᵀAₛ over the pairs (a, b): the weighted graph Laplacian (n × n)."""
    r = np.concatenate([a, b, a, b])
    c = np.concatenate([a, b, b, a])
    v = np.concatenate([w, w, -w, -w])
    return sp.coo_matrix((v, (r, c)), shape=(n, n)).tocsc()


def system_matrix(model: ClothModel, h: float, springs: np.ndarray, bend: sp.csc_matrix | None,
                  air: float, pinned: np.ndarray | None = None) -> sp.csc_matrix:
    """A (above) for step ``h`` over the springs ``springs`` (indices), with the bending
    Hessian ``bend`` (or None); ``pinned`` points' rows and columns are replaced by the
    identity (their motion is prescribed)."""
    n = model.n_points
    s = np.asarray(springs)
    w = model.spring_k[s] + model.spring_c[s] / h
    a = sp.diags(model.mass * (1.0 / (h * h) + air / h)) + \
        laplacian(n, model.spring_a[s], model.spring_b[s], w)
    if bend is not None:
        a = a + bend
    a = a.tocsc()
    if pinned is not None and np.any(pinned):
        keep = sp.diags((~pinned).astype(np.float64))
        a = (keep @ a @ keep + sp.diags(pinned.astype(np.float64))).tocsc()
    a.sum_duplicates()
    a.eliminate_zeros()
    return a
