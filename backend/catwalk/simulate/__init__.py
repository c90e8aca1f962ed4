"""The try-on: dress a body in a garment, then walk it (paper §5–6).

:func:`catwalk.simulate.tryon.tryon` is the whole try-on in one call (also ``catwalk.tryon``);
:func:`dress` sews and settles a garment on a body; :func:`walking.walk` plays a motion with the
dressed garment following; both take a :class:`Settings` (presets ``fast``, ``balanced``,
``accurate``), a ``progress(stage, i, total)`` callback and a ``cancel()`` check.
"""

from catwalk.errors import Cancelled
from catwalk.simulate.dressing import Dressed, DressingError, dress
from catwalk.simulate.settings import PRESETS, Settings, preset

__all__ = ["Cancelled", "Dressed", "DressingError", "PRESETS", "Settings", "dress", "preset"]
