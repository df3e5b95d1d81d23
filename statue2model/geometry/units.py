"""Length units of a scan: what the file's numbers most likely mean.

Scans arrive in metres, millimetres, centimetres or inches with nothing in the
file to say which. The largest extent of a free-standing museum object is
between 5 cm and 4 m, so the plausible units are those that put it in that range;
when several do, metres, then millimetres, then centimetres, then inches are
preferred and the choice is flagged as unsure.

Example
-------
>>> from statue2model.geometry.units import detect_units
>>> detect_units(1.80).units, detect_units(494.0).units
('m', 'mm')
>>> detect_units(100.0).sure
False
"""
from __future__ import annotations

from dataclasses import dataclass

from ..errors import InputError

UNIT_SCALE = {"m": 1.0, "mm": 1e-3, "cm": 1e-2, "in": 0.0254}
"""Metres per file unit."""

PLAUSIBLE_SIZE = (0.05, 4.0)
"""Largest extent (m) of the objects this tool is for; outside it a warning."""

POSSIBLE_SIZE = (0.01, 20.0)
"""Largest extent (m) beyond which explicit units are taken to be a mistake."""


@dataclass(frozen=True)
class UnitChoice:
    units: str
    scale: float  # metres per file unit
    sure: bool
    note: str


def detect_units(extent: float) -> UnitChoice:
    """Choose units for a scan whose largest bounding-box extent is ``extent`` file units."""
    lo, hi = PLAUSIBLE_SIZE
    fits = [u for u, s in UNIT_SCALE.items() if lo <= extent * s <= hi]
    if len(fits) == 1:
        u = fits[0]
        return UnitChoice(u, UNIT_SCALE[u], True, f"units detected as {u} (largest extent {extent * UNIT_SCALE[u]:.3f} m)")
    if fits:
        u = fits[0]
        others = ", ".join(f"{o} ({extent * UNIT_SCALE[o]:.3g} m)" for o in fits[1:])
        return UnitChoice(
            u, UNIT_SCALE[u], False,
            f"units unsure: assumed {u} (largest extent {extent * UNIT_SCALE[u]:.3g} m), "
            f"but {others} would also fit; pass --units or --height",
        )
    return UnitChoice(
        "m", 1.0, False,
        f"units unsure: no unit gives a plausible size (largest extent {extent:.4g} file units); "
        "assumed metres; pass --units or --height",
    )


def resolve_units(units: str, extent: float) -> UnitChoice:
    """Units from the user's ``units`` ('auto' or one of UNIT_SCALE) for a scan of ``extent``."""
    if units == "auto":
        return detect_units(extent)
    if units not in UNIT_SCALE:
        raise InputError(f"unknown units '{units}': use one of auto, {', '.join(UNIT_SCALE)}")
    size = extent * UNIT_SCALE[units]
    lo, hi = POSSIBLE_SIZE
    if not lo <= size <= hi:
        guess = detect_units(extent)
        raise InputError(
            f"with --units {units} the object would be {size:.4g} m across, which is not plausible; "
            f"check --units (the file looks like {guess.units})"
        )
    plo, phi = PLAUSIBLE_SIZE
    note = f"units {units} as given (largest extent {size:.3f} m)"
    if not plo <= size <= phi:
        return UnitChoice(units, UNIT_SCALE[units], False, note + "; unusual size for a museum object")
    return UnitChoice(units, UNIT_SCALE[units], True, note)
