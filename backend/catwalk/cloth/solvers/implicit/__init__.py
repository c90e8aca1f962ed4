"""The implicit cloth solver on a prefactored system (issue 43): implicit Euler as a
minimisation over a matrix factored once per garment (:mod:`.solver`, :mod:`.system`,
:mod:`.factor`, :mod:`.kernels`)."""

from catwalk.cloth.solvers.implicit.solver import ImplicitSolver

__all__ = ["ImplicitSolver"]
