"""The try-on: dress a body in a garment, then walk it (paper §5–6).

:func:`catwalk.simulate.tryon.tryon` is the whole try-on in one call (also ``catwalk.tryon``);
:func:`dress` sews and settles a garment on a body; :func:`walking.walk` plays a motion with the
dressed garment following; both take a :class:`Settings` (presets ``fast``, ``balanced``,
``accurate``), a ``progress(stage, i, total)`` callback and a ``cancel()`` check.
"""

import importlib

from catwalk.errors import Cancelled

# loaded when first asked for: a reader of the simulation's results (``simulate.frames``, the
# file writers) does not load the dressing, the cloth solver and the collider with it
_LAZY = {"Dressed": "dressing", "DressingError": "dressing", "dress": "dressing",
         "PRESETS": "settings", "Settings": "settings", "preset": "settings"}

__all__ = ["Cancelled", "Dressed", "DressingError", "PRESETS", "Settings", "dress", "preset"]


def __getattr__(name: str):
    if name in _LAZY:
        return getattr(importlib.import_module(f"catwalk.simulate.{_LAZY[name]}"), name)
    raise AttributeError(f"module 'catwalk.simulate' has no attribute {name!r}")
