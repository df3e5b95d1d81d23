"""Argument types shared by the command-line modules (argparse ``type=`` callables), and
:func:`join_dash_values`, which lets options take values that start with '-' (``--up -y``)."""
from __future__ import annotations

import argparse
import math


def positive_float(text: str) -> float:
    """A positive finite number, or an argparse error naming the problem."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a number: {text!r}") from None
    if not (math.isfinite(value) and value > 0):
        raise argparse.ArgumentTypeError(f"must be a positive finite number, got {text}")
    return value


def finite_float(text: str) -> float:
    """A finite number, or an argparse error naming the problem."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a number: {text!r}") from None
    if not math.isfinite(value):
        raise argparse.ArgumentTypeError(f"must be a finite number, got {text}")
    return value


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

    from ..errors import InputError
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


_PER_METRE = {"mm": 1000.0, "cm": 100.0, "m": 1.0, "in": 1 / 0.0254}


def _split_unit(text: str, default: str) -> tuple[str, float]:
    t = text.strip().lower()
    for unit in sorted(_PER_METRE, key=len, reverse=True):
        if t.endswith(unit):
            return t[: -len(unit)].strip(), _PER_METRE[unit]
    if t and (t[-1].isalpha()):
        raise argparse.ArgumentTypeError(f"unknown length unit in {text!r} (use mm, cm, m or in)")
    return t, _PER_METRE[default]


def length(text: str) -> float:
    """A non-negative length with a unit ('9mm', '0.5 mm', '1.2cm', '0.009m', '0.35in'),
    returned in metres; a bare number is taken as millimetres.

    >>> length("9mm"), length("0.5 mm"), length("9")
    (0.009, 0.0005, 0.009)
    """
    number, per_metre = _split_unit(text, "mm")
    try:
        value = float(number)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a length: {text!r} (e.g. 9mm)") from None
    if not (math.isfinite(value) and value >= 0):
        raise argparse.ArgumentTypeError(f"must be a non-negative finite length, got {text}")
    return value / per_metre


def sheet_size(text: str) -> tuple[float, float]:
    """Panel size 'WxH' with one unit for both ('2500x1250mm', '2.5x1.25m'; bare numbers are mm),
    returned as (W, H) in metres.

    >>> sheet_size("2500x1250mm")
    (2.5, 1.25)
    """
    number, per_metre = _split_unit(text, "mm")
    parts = number.replace("*", "x").split("x")
    try:
        w, h = (float(p) for p in parts)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a sheet size: {text!r} (e.g. 2500x1250mm)") from None
    if not all(math.isfinite(v) and v > 0 for v in (w, h)):
        raise argparse.ArgumentTypeError(f"sheet sides must be positive, got {text}")
    return w / per_metre, h / per_metre


def scale_ratio(text: str | float) -> float:
    """Model scale as '1:2', '1/2' or a ratio prototype/statue '0.5' (a string, or a number
    from a project file); returns lambda (prototype length = real length / lambda).

    A bare number above 1 is refused: '2' could mean 1:2 or 2:1 (one meaning everywhere).

    >>> scale_ratio("1:2"), scale_ratio("1/4"), scale_ratio("0.5"), scale_ratio(0.25), scale_ratio("1")
    (2.0, 4.0, 2.0, 4.0, 1.0)
    >>> scale_ratio("2")
    Traceback (most recent call last):
    ...
    argparse.ArgumentTypeError: scale 2 is ambiguous: write 1:2 (prototype half the size) or 0.5
    """
    t = str(text).strip().replace("/", ":")
    try:
        if ":" in t:
            a, b = (float(p) for p in t.split(":"))
            lam = b / a
        else:
            ratio = float(t)
            if math.isfinite(ratio) and ratio > 1:
                raise argparse.ArgumentTypeError(
                    f"scale {ratio:g} is ambiguous: write 1:{ratio:g} (prototype "
                    f"{'half' if ratio == 2 else f'1/{ratio:g} of'} the size) or {1 / ratio:.4g}")
            lam = 1.0 / ratio
    except (ValueError, ZeroDivisionError):
        raise argparse.ArgumentTypeError(f"not a scale: {text!r} (e.g. 1:2)") from None
    if not (math.isfinite(lam) and lam > 0):
        raise argparse.ArgumentTypeError(f"not a scale: {text!r} (e.g. 1:2)")
    return lam


def scale_text(lam: float) -> str:
    """lambda -> the scale as written ('1:2'); reads back with :func:`scale_ratio` to the same float.

    >>> scale_text(2.0), scale_text(2.5), scale_ratio(scale_text(1 / 0.3)) == 1 / 0.3
    ('1:2', '1:2.5', True)
    """
    s = f"{lam:.15g}"
    if float(s) != lam:
        s = repr(float(lam))
    return f"1:{s}"


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
    from ..pipeline.run import MESH_SUFFIXES

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
    if path.suffix.lower() not in MESH_SUFFIXES:
        raise InputError(f"{source}: expected a scan ({', '.join(MESH_SUFFIXES)}) or a PARAMS.json")
    return path, None
