"""Cloth solvers beside the paper's explicit one (:mod:`catwalk.cloth.solver`), each in its own
folder (``solvers/<name>/{kernels,solver}.py``)."""
