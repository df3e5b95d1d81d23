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
