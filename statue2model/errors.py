"""Errors that reach the user as one clear line.

Every problem with the user's input (a file, a unit, a parameter) is raised as
:class:`InputError`; the command line prints its message on one line and exits
with status 2. Anything else is a bug in statue2model.
"""


class InputError(ValueError):
    """Bad input: the message names the problem and, where possible, the fix."""
