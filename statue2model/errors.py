"""Errors that reach the user as one clear line.

Every problem with the user's input (a file, a unit, a parameter) is raised as
:class:`InputError`; the command line prints its message on one line and exits
with status 2. An output that cannot be written (disk full, quota, permission,
read-only file system, name too long) is an :class:`OutputError`: one line naming
the file, exit status 3. Anything else is a bug in statue2model.
"""


class InputError(ValueError):
    """Bad input: the message names the problem and, where possible, the fix."""


class OutputError(InputError):
    """An output file or folder could not be written (an ``OSError`` of the system):
    the message names the file and the reason; the command line exits with status 3."""


class MissingExtra(InputError):
    """A feature whose optional dependency (an *extra* of the package) is not installed."""


EXTRAS = {"pointcloud": "open3d", "physics": "pybullet", "cluster": "dask[distributed]", "records": "reqpy-M"}


def missing_extra(extra: str, what: str, exc: BaseException | None = None) -> MissingExtra:
    """The one-line error for ``what`` needing the extra ``extra`` (see :data:`EXTRAS`).

    >>> print(missing_extra("physics", "the 3D cross-check"))
    the 3D cross-check needs the [physics] extra (pybullet), which is not installed: run 'bash .ci/install --extras physics' in the statue2model checkout, or 'pip install "statue2model[physics]"'
    """
    why = f"; {exc}" if exc is not None and not isinstance(exc, ModuleNotFoundError) else ""
    return MissingExtra(
        f"{what} needs the [{extra}] extra ({EXTRAS[extra]}), which is not installed{why}: run "
        f"'bash .ci/install --extras {extra}' in the statue2model checkout, or 'pip install \"statue2model[{extra}]\"'")


QUOTED_CHARS = 60
"""Characters of a user's value quoted in a message (:func:`quoted`): the rest is cut, its length said."""


def quoted(value, limit: int = QUOTED_CHARS, *, bare: bool = False) -> str:
    """A user's value as an error message quotes it: its ``repr``, cut to about ``limit``
    characters with its length said, so a message stays one short line whatever the input
    (a 50 MB string, a list of a million items, a deeply nested array). Every message that
    echoes a value read from the user's input goes through this. ``bare``: a string without
    quotes when it is printable (a name shown as ``[section]``).

    >>> quoted("mm"), quoted(0.5), quoted([1, 2])
    ("'mm'", '0.5', '[1, 2]')
    >>> quoted("x" * 1000)
    "'xxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxx'... (1000 characters)"
    >>> quoted(list(range(10**6)))
    '[0, 1, 2, 3, 4, 5, ...] (1000000 items)'
    """
    if isinstance(value, str):
        head = value[:limit]
        text = head if bare and head.isprintable() else repr(head)
        return text if len(value) <= limit else f"{text}... ({len(value)} characters)"
    import reprlib

    r = reprlib.Repr()              # bounded: never builds the whole text of a huge or deep value
    r.maxstring = r.maxother = limit
    text = r.repr(value)
    size = f" ({len(value)} items)" if isinstance(value, (list, tuple, dict, set)) and "..." in text else ""
    return (text if len(text) <= limit else text[:limit] + "...") + size
