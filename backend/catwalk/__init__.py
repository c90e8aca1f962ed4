"""catwalk: a shopper's body walks a catwalk in a simulated garment.

The public entry point is ``catwalk.tryon(body, garment, size=…, …) -> catwalk.TryOn``
(:mod:`catwalk.simulate.tryon`). The package is built in three floors (docs/architecture.md):
the applications (``cli/``, ``service/``, ``bench/``, ``loadtest/``) over the engine (``body``,
``motion``, ``cloth``, ``collide``, ``garment``, ``exchange``, ``catalogue``, ``render``,
``simulate``) over geometry and the base modules (``geometry/``, ``errors``, ``config``,
``fileio``, ``console``, ``assets``); a floor imports only the floors below it.
"""

__version__ = "0.1.0"

from catwalk.simulate.tryon import TryOn, tryon  # noqa: E402

__all__ = ["TryOn", "tryon", "__version__"]
