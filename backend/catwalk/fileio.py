"""Writing output files atomically: nothing half-written is ever left behind."""

from __future__ import annotations

import contextlib
import os
import tempfile
from pathlib import Path

from catwalk.errors import InputError


def check_writable(path: str | os.PathLike, flag: str) -> None:
    """Refuse, before any long work, an output ``path`` that could not be written: not a
    folder or another existing non-file (a device, a pipe), and its nearest existing ancestor
    a folder this process can make a file in — tried by making (and removing) one, since
    permissions do not tell (root may write anywhere by them, yet nothing can be made under
    ``/sys`` or on a read-only mount). The missing folders below it are made when the file is
    written. Raises :class:`~catwalk.errors.InputError` naming ``flag`` (the option that gave
    the path)."""
    shown = Path(path)
    try:
        path = shown.resolve()
        if path.is_dir():
            raise InputError(f"{flag} {shown}: is a folder, not a file")
        if path.exists() and not path.is_file():
            raise InputError(f"{flag} {shown}: exists and is not a regular file")
        parent = path.parent
        while not parent.exists():
            parent = parent.parent
    except OSError as exc:
        raise InputError(f"{flag} {shown}: cannot be written ({exc.strerror or exc})") from None
    if not parent.is_dir():
        raise InputError(f"{flag} {shown}: {parent} is not a writable folder (it is a file)")
    try:
        fd, probe = tempfile.mkstemp(dir=parent, prefix=".catwalk-probe-")
    except OSError as exc:
        raise InputError(f"{flag} {shown}: {parent} is not a writable folder "
                         f"({exc.strerror or exc})") from None
    os.close(fd)
    os.unlink(probe)


@contextlib.contextmanager
def atomic_path(path: str | os.PathLike, flag: str | None = None):
    """Yield a temporary path beside ``path``; rename it into place only on success. The
    folders it makes for ``path`` are removed again when it fails. A path that cannot be
    written raises :class:`~catwalk.errors.InputError` (naming ``flag`` when given)."""
    path = Path(path)
    what = f"{flag} {path}" if flag else str(path)
    made = []   # the folders this call makes, outermost last
    try:
        folder = path.parent
        while not folder.exists() and folder != folder.parent:
            made.append(folder)
            folder = folder.parent
        path.parent.mkdir(parents=True, exist_ok=True)
        fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.",
                                   suffix=path.suffix)
    except OSError as exc:
        _remove_folders(made)
        raise InputError(f"{what}: cannot be written ({exc.strerror or exc})") from None
    os.close(fd)
    umask = os.umask(0)
    os.umask(umask)
    os.chmod(tmp, 0o666 & ~umask)  # mkstemp makes 0600; give the file normal permissions
    try:
        yield Path(tmp)
        try:
            os.replace(tmp, path)
        except OSError as exc:
            raise InputError(f"{what}: cannot be written ({exc.strerror or exc})") from None
    except BaseException:
        with contextlib.suppress(FileNotFoundError):
            os.unlink(tmp)
        _remove_folders(made)
        raise


def _remove_folders(folders: list[Path]) -> None:
    for folder in folders:   # innermost first; only if still empty
        with contextlib.suppress(OSError):
            folder.rmdir()
