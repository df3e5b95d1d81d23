"""Length units of a scan: what the file's numbers most likely mean.

Scans arrive in metres, millimetres, centimetres or inches with nothing in the
file to say which. The largest extent of a free-standing museum object is
between 10 cm and 4 m (:data:`PLAUSIBLE_SIZE`: smaller objects are not what
rocking assessments are for, and a 7 cm reading is the typical sign of inches or cm
taken as mm), so the plausible units are those
that put it in that range:

* one unit fits: it is taken, and the choice is sure;
* several fit: metres, then millimetres, then centimetres, then inches are
  preferred, and the note ('units unsure: ...') gives the size under every unit
  that fits; a result under 15 cm in mm that inches would make a plausible size
  is flagged 'could be inches' (or cm);
* none fits: :class:`InputError`, with the size each unit would give; the user
  passes ``--units`` (checked against the wider :data:`POSSIBLE_SIZE`) or ``--height``.

Example
-------
>>> from statue2model.geometry.units import detect_units
>>> detect_units(1.80).units, detect_units(494.0).units
('m', 'mm')
>>> detect_units(100.0).sure
False
>>> detect_units(130.0).note  # doctest: +ELLIPSIS
'units unsure: assumed mm (0.13 m across); cm would give 1.3 m, in would give 3.3 m; could be inches or cm: ...'
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError

UNIT_SCALE = {"m": 1.0, "mm": 1e-3, "cm": 1e-2, "in": 0.0254}
"""Metres per file unit, in order of preference."""

PLAUSIBLE_SIZE = (0.1, 4.0)
"""Largest extent (m) of the objects this tool is for: with units 'auto', a unit must put the scan in it."""

POSSIBLE_SIZE = (0.01, 20.0)
"""Largest extent (m) beyond which explicit units are taken to be a mistake."""

SMALL_IN_MM = 0.15
"""Largest extent (m) under mm below which a plausible size in inches is pointed out."""


@dataclass(frozen=True)
class UnitChoice:
    units: str
    scale: float  # metres per file unit
    sure: bool
    note: str


def detect_units(extent: float) -> UnitChoice:
    """Choose units for a scan whose largest bounding-box extent is ``extent`` file units.

    Raises InputError when no unit gives a plausible size (see the module docstring).
    """
    extent = float(extent)
    lo, hi = PLAUSIBLE_SIZE
    if not (np.isfinite(extent) and extent > 0):
        raise InputError(f"the scan has no size (largest extent {extent:g} file units)")
    fits = [u for u, s in UNIT_SCALE.items() if lo <= extent * s <= hi]
    if not fits:
        each = ", ".join(f"{extent * s:.3g} m in {u}" for u, s in UNIT_SCALE.items())
        raise InputError(
            f"the scan is {extent:.3g} file units across: {each}; none is a plausible size "
            f"for a museum object ({lo:g}-{hi:g} m); pass --units or --height"
        )
    u = fits[0]
    size = extent * UNIT_SCALE[u]
    if len(fits) == 1:
        return UnitChoice(u, UNIT_SCALE[u], True, f"units detected as {u} (largest extent {size:.3f} m)")
    others = ", ".join(f"{o} would give {extent * UNIT_SCALE[o]:.3g} m" for o in fits[1:])
    note = f"units unsure: assumed {u} ({size:.3g} m across); {others}; "
    if u == "mm" and size < SMALL_IN_MM and "in" in fits:
        note += f"could be inches{' or cm' if 'cm' in fits else ''}: a {size * 100:.3g} cm object is unusually small for a scan; "
    return UnitChoice(u, UNIT_SCALE[u], False, note + "pass --units or --height")


def resolve_units(units: str, extent: float, *, strict: bool = True) -> UnitChoice:
    """Units from the user's ``units`` ('auto' or one of UNIT_SCALE) for a scan of ``extent``.

    strict : with 'auto', refuse a scan that no unit makes plausible (the default). With
             False such a scan gets a provisional scale that makes it 1 m across (sure=False),
             for callers that rescale it anyway (to a known height).
    """
    if units == "auto":
        if strict:
            return detect_units(extent)
        try:
            return detect_units(extent)
        except InputError as exc:
            if not (np.isfinite(extent) and extent > 0):
                raise
            return UnitChoice("m", 1.0 / float(extent), False, f"provisional scale 1 m across ({exc})")
    if units not in UNIT_SCALE:
        raise InputError(f"unknown units '{units}': use one of auto, {', '.join(UNIT_SCALE)}")
    size = extent * UNIT_SCALE[units]
    lo, hi = POSSIBLE_SIZE
    if not lo <= size <= hi:
        try:
            hint = f" (the file looks like {detect_units(extent).units})"
        except InputError:
            hint = " (no unit makes it a plausible size: check the file)"
        raise InputError(
            f"with --units {units} the object would be {size:.4g} m across, which is not plausible; "
            f"check --units{hint}"
        )
    plo, phi = PLAUSIBLE_SIZE
    note = f"units {units} as given (largest extent {size:.3f} m)"
    if not plo <= size <= phi:
        return UnitChoice(units, UNIT_SCALE[units], False, note + "; unusual size for a museum object")
    return UnitChoice(units, UNIT_SCALE[units], True, note)
