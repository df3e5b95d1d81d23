"""Opening input files the user names (scans and what they refer to): regular files only.

A FIFO, a socket or a device named like a scan would block ``open`` forever or read
endlessly; a dangling symbolic link or a link loop is no file at all. :func:`input_problem`
says which in a few words, :func:`open_input` opens without ever blocking on such a file.

>>> import os, tempfile
>>> d = tempfile.mkdtemp()
>>> os.symlink("gone.stl", os.path.join(d, "x.stl"))
>>> input_problem(os.path.join(d, "x.stl"))
'a symbolic link to gone.stl, which does not exist'
>>> os.mkfifo(os.path.join(d, "f.stl"))
>>> input_problem(os.path.join(d, "f.stl"))
'not a regular file (a FIFO)'
"""
from __future__ import annotations

import errno
import os
import stat
from pathlib import Path

from ..errors import InputError, quoted

_KINDS = ((stat.S_ISDIR, "a folder"), (stat.S_ISFIFO, "a FIFO"), (stat.S_ISSOCK, "a socket"),
          (stat.S_ISCHR, "a character device"), (stat.S_ISBLK, "a block device"))


def _kind(mode: int) -> str:
    return next((name for test, name in _KINDS if test(mode)), "not a regular file")


def input_problem(path: str | os.PathLike) -> str | None:
    """Why ``path`` cannot be read as an input file (a few words), or None when it is a regular
    file (a symbolic link to one included). Never opens it."""
    path = Path(path)
    try:
        st = os.stat(path)
    except OSError as exc:
        if exc.errno == errno.ELOOP:
            return "a symbolic link loop"
        if path.is_symlink():
            try:
                target = os.readlink(path)
            except OSError:
                target = "?"
            return f"a symbolic link to {quoted(target, bare=True)}, which does not exist"
        if exc.errno == errno.ENOENT:
            return "not found"
        return os.strerror(exc.errno) if exc.errno else str(exc)
    if not stat.S_ISREG(st.st_mode):
        kind = _kind(st.st_mode)
        return f"not a regular file ({kind})" if kind != "not a regular file" else kind
    return None


def check_input(path: str | os.PathLike, what: str = "file") -> Path:
    """``path`` when it is a regular file, else an :class:`InputError` naming it and why."""
    problem = input_problem(path)
    if problem is not None:
        raise InputError(f"{what} {path}: {problem}")
    return Path(path)


def open_input(path: str | os.PathLike, what: str = "file"):
    """``path`` opened for reading bytes, when it is a regular file; else an :class:`InputError`
    (a FIFO is refused at once: opened without blocking, then checked on the open descriptor)."""
    try:
        fd = os.open(path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_CLOEXEC", 0))
    except OSError as exc:
        check_input(path, what)               # the reason in words (missing, a link loop, ...)
        raise InputError(f"cannot read {what} {path}: {exc.strerror or exc}") from None
    try:
        st = os.fstat(fd)
        if not stat.S_ISREG(st.st_mode):
            raise InputError(f"{what} {path}: not a regular file ({_kind(st.st_mode)})")
        if hasattr(os, "set_blocking"):
            os.set_blocking(fd, True)
        return open(path, "rb", opener=lambda _path, _flags: fd)     # the checked descriptor; named path
    except BaseException:
        os.close(fd)
        raise
