"""Reading TOML input (project files, campaign files) with one-line errors.

>>> parse_toml("x = 1", "project.toml")
{'x': 1}
>>> parse_toml("x = " + "[" * 100000 + "]" * 100000, "project.toml")
Traceback (most recent call last):
...
statue2model.errors.InputError: project.toml is not valid TOML: its arrays or inline tables are nested too deeply to read
"""
from __future__ import annotations

import sys

from ..errors import InputError

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib


def parse_toml(text: str, what: str) -> dict:
    """The TOML ``text`` of input ``what`` (named in the message) as a dict, or a one-line
    :class:`InputError`: invalid TOML, or nested so deeply (``[[[[...]]]]`` a thousand levels)
    that the parser, which recurses once per level, runs out of Python's recursion limit."""
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise InputError(f"{what} is not valid TOML: {exc}") from None
    except RecursionError:
        raise InputError(f"{what} is not valid TOML: its arrays or inline tables are nested too deeply "
                         "to read") from None
