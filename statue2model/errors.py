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
