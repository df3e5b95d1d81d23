"""Argument types shared by the command-line modules (argparse ``type=`` callables): thin
wrappers over :mod:`statue2model.quantities` that turn its InputError into an argparse error
with the same message; and :func:`join_dash_values`, which lets options take values that start
with '-' (``--up -y``)."""
from __future__ import annotations

import argparse
import functools

from .. import quantities as Q
from ..errors import InputError


def argtype(parse):
    """``parse`` (a function of :mod:`statue2model.quantities`) as an argparse type: its
    InputError becomes an ArgumentTypeError with the same message.

    >>> argtype(Q.scale_ratio)("2")
    Traceback (most recent call last):
    ...
    argparse.ArgumentTypeError: scale 2 is ambiguous: write 1:2 (prototype half the size) or 0.5
    """
    @functools.wraps(parse)
    def convert(text):
        try:
            return parse(text)
        except InputError as exc:
            raise argparse.ArgumentTypeError(str(exc)) from None

    return convert


positive_float = argtype(Q.positive_float)
finite_float = argtype(Q.finite_float)
length = argtype(Q.length)
sheet_size = argtype(Q.sheet_size)
scale_ratio = argtype(Q.scale_ratio)


def plausible(quantity: str, parse=positive_float, option: str = ""):
    """An argparse type: ``parse`` the text, then check the value against its range in
    :data:`statue2model.geometry.units.PLAUSIBLE` (``quantity`` a key of it): a value that
    cannot be physical is an argparse error naming the unit it was probably typed in, an
    unusual one is taken with a warning on stderr (naming ``option``, e.g. '--R').

    >>> plausible("groove_radius")("0.3")
    0.3
    >>> plausible("groove_radius")("300")
    Traceback (most recent call last):
    ...
    argparse.ArgumentTypeError: 300 m is implausible for a groove radius of curvature; did you mean 300 mm (0.3 m) or 300 cm (3 m)?
    """
    import sys

    from ..geometry.units import check_plausible

    def convert(text: str) -> float:
        value = parse(text)
        try:
            note = check_plausible(quantity, value, "")
        except InputError as exc:
            raise argparse.ArgumentTypeError(str(exc)) from None
        if note:
            print(f"statue2model: warning: {option + ' ' if option else ''}{note}", file=sys.stderr)
        return value

    convert.__name__ = quantity.replace("_", " ")       # argparse's "invalid <name> value"
    return convert


DASH_VALUES = {"--up": ("-x", "-y", "-z")}
"""Options whose values may start with '-' (argparse would take ``-y`` for an option)."""


def join_dash_values(argv: list[str], options: dict = DASH_VALUES) -> list[str]:
    """``[..., '--up', '-y', ...]`` -> ``[..., '--up=-y', ...]`` for the values of ``options``
    (option -> the values starting with '-' it takes), so argparse reads them as values.
    Everything after a bare ``--`` is left alone.

    >>> join_dash_values(["props", "m.stl", "--up", "-y", "--json", "o.json"])
    ['props', 'm.stl', '--up=-y', '--json', 'o.json']
    >>> join_dash_values(["props", "--up", "z", "--", "--up", "-y"])
    ['props', '--up', 'z', '--', '--up', '-y']
    """
    out: list[str] = []
    i = 0
    while i < len(argv):
        a = argv[i]
        if a == "--":
            return out + list(argv[i:])
        if a in options and i + 1 < len(argv) and argv[i + 1] in options[a]:
            out.append(f"{a}={argv[i + 1]}")
            i += 2
            continue
        out.append(a)
        i += 1
    return out


def scan_or_params(source: str):
    """(path, params): ``source`` a scan (params None: the caller loads the body) or a PARAMS.json
    of `statue2model props` (its RockingParams); an InputError naming the file otherwise."""
    from pathlib import Path

    from ..errors import InputError
    from ..geometry.scan import SCAN_SUFFIXES

    path = Path(source)
    if not path.is_file():
        raise InputError(f"file not found: {source}")
    if path.suffix.lower() == ".json":
        from ..geometry.rocking_params import RockingParams
        from ..io.files import read_json

        data = read_json(path)
        if not isinstance(data, dict):
            raise InputError(f"{source}: not a JSON object of rocking parameters")
        try:
            return path, RockingParams.from_dict(data)
        except (KeyError, TypeError, ValueError) as exc:
            raise InputError(f"{source} does not hold rocking parameters ({exc})") from None
    if path.suffix.lower() not in SCAN_SUFFIXES:
        raise InputError(f"{source}: expected a scan ({', '.join(SCAN_SUFFIXES)}) or a PARAMS.json")
    return path, None
