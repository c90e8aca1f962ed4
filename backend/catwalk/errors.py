"""catwalk's errors, by whose they are.

- :class:`InputError`: the user's fault — a bad file, an unknown size, a parameter out of range.
  The message names the input or parameter (never a CLI flag); ``field`` names the parameter
  when there is one. The CLI exits 2; the service answers HTTP 4xx.
  :class:`NotFound` is the input error of an id that names nothing (HTTP 404).
- :class:`SimulationError`: the simulation failed on good input — the dressing did not
  converge, the cloth exploded. The CLI exits 3; the service marks the job failed with the
  message as its reason.
- :class:`Cancelled`: the caller asked the work to stop. The CLI exits 130.
- :class:`SetupError`: the installation is incomplete (assets or Node tools missing, a download
  failed). The CLI exits 1; the service reports itself not ready.
"""

from __future__ import annotations


class CatwalkError(Exception):
    """Base of catwalk's own errors: the message says what is wrong and where."""


class InputError(CatwalkError):
    """A file or parameter that cannot be used. ``field``: the parameter it concerns."""

    def __init__(self, message: str, field: str | None = None):
        super().__init__(message)
        self.field = field


class NotFound(InputError):
    """An id that names nothing (a body, a try-on, a garment): the service answers 404."""

    def __init__(self, what: str, ident: str, field: str | None = None):
        super().__init__(f"no {what} with id {str(ident)[:80]!r}", field)


class SimulationError(CatwalkError):
    """The simulation could not produce a result from good input."""


class Cancelled(CatwalkError):
    """The caller's cancel check returned True."""


class SetupError(CatwalkError):
    """Something catwalk needs is not installed or could not be fetched."""
