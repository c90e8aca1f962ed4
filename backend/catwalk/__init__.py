"""catwalk: a shopper's body walks a catwalk in a simulated garment.

The public entry point is ``catwalk.tryon(body, garment, size=…, …) -> catwalk.TryOn``
(:mod:`catwalk.simulate.tryon`); it is imported on first use, so ``import catwalk`` stays light.
"""

__version__ = "0.1.0"

__all__ = ["TryOn", "tryon", "__version__"]


def __getattr__(name: str):
    if name in ("tryon", "TryOn"):
        from catwalk.simulate import tryon as _module

        return getattr(_module, name)
    raise AttributeError(f"module 'catwalk' has no attribute {name!r}")
