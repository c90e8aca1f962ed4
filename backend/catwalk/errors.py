"""Errors a user can fix (bad input, bad parameters). The CLI prints them and exits 2."""


class CatwalkError(Exception):
    """A problem with the user's input: the message says what is wrong and where."""


class InputError(CatwalkError):
    """A file or parameter that cannot be used."""
