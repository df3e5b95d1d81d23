"""Values with units, parsed once for the command line and the project file alike.

Every function takes the text a user typed (or a number from a project file) and returns
SI units, or raises :class:`~statue2model.errors.InputError` whose message names the
problem; the command line wraps them as argparse types (:mod:`statue2model.cli.argtypes`),
the project file calls them directly (:mod:`statue2model.pipeline.config`). Nothing here
imports anything of the package but its errors, so every layer may use it.

Constants
---------
G           9.81 m/s^2: the g of an acceleration written '0.3g' (SPEC strings, grids, project
            files), of the model's gravity and of every 'g' printed in a report
G_STANDARD  9.80665 m/s^2: standard gravity, the g of accelerogram files (PEER NGA) and of
            the codes' spectra

These are the only places g is written: no other module types 9.81 or 9.80665
(tests/test_states.py; a doctest may), so a printed 'g' is always G.

Example
-------
>>> length("9mm"), length("0.5 mm"), length("9")
(0.009, 0.0005, 0.009)
>>> sheet_size("2500x1250mm")
(2.5, 1.25)
>>> scale_ratio("1:2"), scale_ratio("1/4"), scale_ratio("0.5"), scale_ratio(0.25), scale_ratio("1")
(2.0, 4.0, 2.0, 4.0, 1.0)
>>> scale_ratio("2")
Traceback (most recent call last):
...
statue2model.errors.InputError: scale 2 is ambiguous: write 1:2 (prototype half the size) or 0.5
>>> scale_text(2.0), scale_text(2.5), scale_ratio(scale_text(1 / 0.3)) == 1 / 0.3
('1:2', '1:2.5', True)
>>> parse_accel("0.3g"), parse_accel("2.5 m/s^2"), parse_accel("0")
(2.943, 2.5, 0.0)
>>> parse_accel("0.3", key="amp")
Traceback (most recent call last):
...
statue2model.errors.InputError: amp=0.3 has no unit: write amp=0.3g or amp=2.94m/s2
"""
from __future__ import annotations

import math

from .errors import InputError, quoted

G = 9.81
"""m/s^2 per g of an acceleration written '0.3g', of the model's gravity and of the reports."""

G_STANDARD = 9.80665
"""Standard gravity (m/s^2): the g of accelerogram files (PEER NGA) and of the code spectra."""

A_MAX = 100 * G
"""Largest |acceleration| (m/s^2) accepted anywhere: 100 g; no ground motion reaches it."""

ACCEL_UNITS = (("m/s^2", 1.0), ("m/s**2", 1.0), ("m/s²", 1.0), ("m/s2", 1.0), ("g", None))
"""Unit spellings of an acceleration (case-insensitive) -> factor to m/s^2 (None: g)."""

PER_METRE = {"mm": 1000.0, "cm": 100.0, "m": 1.0, "in": 1 / 0.0254}
"""Length units of :func:`length` and :func:`sheet_size` -> how many make a metre."""


def positive(name: str, value) -> float:
    """``value`` as a float when it is a positive finite number (not a bool), else one line naming
    ``name``.

    >>> positive("height", "11.5")
    11.5
    """
    if isinstance(value, bool):
        raise InputError(f"{name} must be a positive number, got {quoted(value)}")
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise InputError(f"{name} must be a positive number, got {quoted(value)}") from None
    if not (math.isfinite(v) and v > 0):
        raise InputError(f"{name} must be a positive finite number, got {quoted(value)}")
    return v


def positive_float(text) -> float:
    """A positive finite number (the text or a number)."""
    try:
        value = float(text)
    except ValueError:
        raise InputError(f"not a number: {quoted(text)}") from None
    if not (math.isfinite(value) and value > 0):
        raise InputError(f"must be a positive finite number, got {quoted(text, bare=True)}")
    return value


def finite_float(text) -> float:
    """A finite number (the text or a number)."""
    try:
        value = float(text)
    except ValueError:
        raise InputError(f"not a number: {quoted(text)}") from None
    if not math.isfinite(value):
        raise InputError(f"must be a finite number, got {quoted(text, bare=True)}")
    return value


def _split_unit(text: str, default: str) -> tuple[str, float]:
    t = text.strip().lower()
    for unit in sorted(PER_METRE, key=len, reverse=True):
        if t.endswith(unit):
            return t[: -len(unit)].strip(), PER_METRE[unit]
    if t and (t[-1].isalpha()):
        raise InputError(f"unknown length unit in {quoted(text)} (use mm, cm, m or in)")
    return t, PER_METRE[default]


def length(text: str) -> float:
    """A non-negative length with a unit ('9mm', '0.5 mm', '1.2cm', '0.009m', '0.35in'),
    returned in metres; a bare number is taken as millimetres."""
    number, per_metre = _split_unit(text, "mm")
    try:
        value = float(number)
    except ValueError:
        raise InputError(f"not a length: {quoted(text)} (e.g. 9mm)") from None
    if not (math.isfinite(value) and value >= 0):
        raise InputError(f"must be a non-negative finite length, got {quoted(text, bare=True)}")
    return value / per_metre


def sheet_size(text: str) -> tuple[float, float]:
    """Panel size 'WxH' with one unit for both ('2500x1250mm', '2.5x1.25m'; bare numbers are
    mm), returned as (W, H) in metres."""
    number, per_metre = _split_unit(text, "mm")
    parts = number.replace("*", "x").split("x")
    try:
        w, h = (float(p) for p in parts)
    except ValueError:
        raise InputError(f"not a sheet size: {quoted(text)} (e.g. 2500x1250mm)") from None
    if not all(math.isfinite(v) and v > 0 for v in (w, h)):
        raise InputError(f"sheet sides must be positive, got {quoted(text, bare=True)}")
    return w / per_metre, h / per_metre


def scale_ratio(text: str | float) -> float:
    """Model scale as '1:2', '1/2' or a ratio prototype/statue '0.5' (a string, or a number
    from a project file); returns lambda (prototype length = real length / lambda).

    A bare number above 1 is refused: '2' could mean 1:2 or 2:1 (one meaning everywhere)."""
    t = str(text).strip().replace("/", ":")
    try:
        if ":" in t:
            a, b = (float(p) for p in t.split(":"))
            lam = b / a
        else:
            ratio = float(t)
            lam = None if math.isfinite(ratio) and ratio > 1 else 1.0 / ratio
    except (ValueError, ZeroDivisionError):
        raise InputError(f"not a scale: {quoted(text)} (e.g. 1:2)") from None
    if lam is None:
        raise InputError(
            f"scale {ratio:g} is ambiguous: write 1:{ratio:g} (prototype "
            f"{'half' if ratio == 2 else f'1/{ratio:g} of'} the size) or {1 / ratio:.4g}")
    if not (math.isfinite(lam) and lam > 0):
        raise InputError(f"not a scale: {quoted(text)} (e.g. 1:2)")
    return lam


def scale_text(lam: float) -> str:
    """lambda -> the scale as written ('1:2'); reads back with :func:`scale_ratio` to the same float."""
    s = f"{lam:.15g}"
    if float(s) != lam:
        s = repr(float(lam))
    return f"1:{s}"


def parse_accel(text: str, what: str = "acceleration", key: str | None = None, g: float = G) -> float:
    """'0.3g' (times ``g`` = 9.81) or '2.94m/s2' ('m/s^2', 'm/s**2', 'm/s²') -> m/s^2.

    A number without a unit is refused (it once meant m/s^2 and read as 'no motion' to
    whoever meant g); only 0 may go without one. ``key`` names the value in the
    message as the user wrote it (``amp=0.3``); ``what`` names it otherwise. Above
    :data:`A_MAX` (100 g) it is refused."""
    raw = str(text).strip()
    s = raw.lower()
    factor = None
    for unit, f in ACCEL_UNITS:
        if s.endswith(unit):
            s, factor = s[: -len(unit)].strip(), (g if f is None else f)
            break
    try:
        value = float(s) * (1.0 if factor is None else factor)
    except ValueError:
        raise InputError(f"{what} must be a number with a unit (0.3g or 2.94m/s2), got {quoted(text)}") from None
    if not math.isfinite(value):
        raise InputError(f"{what} must be finite, got {quoted(text)}")
    raw = quoted(raw, bare=True)       # as the messages below show it
    if factor is None and value != 0:
        name = f"{key}=" if key else ""
        head = f"{name}{raw}" if key else f"{what}: {raw}"
        raise InputError(f"{head} has no unit: write {name}{raw}g or {name}{value * g:.3g}m/s2")
    if abs(value) > A_MAX:
        raise InputError(f"{f'{key}={raw}' if key else f'{what} {raw}'} is {abs(value) / g:.4g} g: no ground "
                         f"motion reaches {A_MAX / G:g} g (check the unit)")
    return value
