"""catwalk: a shopper's body walks a catwalk in a simulated garment."""

__version__ = "0.1.0"
