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

Plausible ranges of inputs
--------------------------
:data:`PLAUSIBLE` is the one table of the ranges a number the user gives (a height, a
groove radius, a mass, an acceleration, a time step, ...) is checked against, and
:func:`check_plausible` the one check: outside the *possible* range the number cannot be
physical and is refused (InputError); between it and the *plausible* range it is
accepted with a warning; either message names the unit the number was probably typed in.

>>> check_plausible("height", 1800.0)
Traceback (most recent call last):
...
statue2model.errors.InputError: height = 1800 m is implausible for a statue height; did you mean 1800 mm (1.8 m)?
>>> check_plausible("height", 1.8) is None
True
>>> check_plausible("groove_radius", 300.0, "--R")
Traceback (most recent call last):
...
statue2model.errors.InputError: --R = 300 m is implausible for a groove radius of curvature; did you mean 300 mm (0.3 m) or 300 cm (3 m)?
>>> check_plausible("groove_radius", 5.0, "--R")
'--R = 5 m is unusual for a groove radius of curvature (0.1 to 3 m); did you mean 5 in (0.127 m)?'
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ..quantities import A_MAX, G  # the g of '0.3g': '100g' (A_MAX) is at the limit
from .massprops import PLAUSIBLE_DENSITY, POSSIBLE_DENSITY

UNIT_SCALE = {"m": 1.0, "mm": 1e-3, "cm": 1e-2, "in": 0.0254}
"""Metres per file unit, in order of preference."""


@dataclass(frozen=True)
class Plausible:
    """The range of one input quantity, in SI units (``unit``).

    low, high           : plausible; outside it the value is accepted with a warning
    hard_low, hard_high : possible; outside it the value cannot be physical: refused
    typed               : other units the number is often typed in, (name, SI value of 1 of them):
                          the messages name those that would make it plausible
    """

    what: str
    unit: str
    low: float
    high: float
    hard_low: float
    hard_high: float
    typed: tuple[tuple[str, float], ...] = ()


_LENGTH_TYPOS = (("mm", 1e-3), ("cm", 1e-2), ("in", 0.0254))
_MASS_TYPOS = (("g", 1e-3), ("t", 1e3), ("lb", 0.45359237))
_ACC_TYPOS = (("cm/s^2 (gal)", 1e-2), ("mm/s^2", 1e-3))

PLAUSIBLE: dict[str, Plausible] = {
    # the statue: largest extent of a scan with explicit units, or the height it is rescaled to
    "height": Plausible("statue height", "m", 0.1, 4.0, 0.01, 20.0, _LENGTH_TYPOS),
    "mass": Plausible("statue mass", "kg", 0.1, 50e3, 1e-3, 1e6, _MASS_TYPOS),
    "density": Plausible("solid object's density", "kg/m^3", *PLAUSIBLE_DENSITY, *POSSIBLE_DENSITY,
                         (("g/cm^3", 1000.0), ("lb/ft^3", 16.0185))),
    "base_tol": Plausible("contact tolerance of the base", "m", 0.0, 0.01, 0.0, 0.1, _LENGTH_TYPOS),
    # the rolling-ball isolator (the thesis: R 0.30 m, r 9.5-18.3 mm, M 10-22 kg, 20-50 mm plates)
    "groove_radius": Plausible("groove radius of curvature", "m", 0.1, 3.0, 0.005, 20.0, _LENGTH_TYPOS),
    "ball_radius": Plausible("ball radius", "m", 0.002, 0.1, 0.0005, 0.5, _LENGTH_TYPOS),
    "supported_mass": Plausible("supported mass (top plate + statue)", "kg", 0.5, 50e3, 1e-3, 1e6, _MASS_TYPOS),
    "capacity": Plausible("isolator capacity (largest plate displacement)", "m", 0.005, 1.0, 1e-4, 10.0,
                          _LENGTH_TYPOS),
    "plate_thickness": Plausible("isolator plate thickness", "m", 0.01, 0.2, 0.01, 0.2, _LENGTH_TYPOS),
    # a load test of a groove surface, N on the thesis' 40 mm ball (beech 73.6; a flat hardened steel race
    # about 11.5 kN at ISO 76's dent): above 60 kN no surface a ball rolls on
    "ball_capacity": Plausible("load a ball carries on the grooves (N on a 40 mm ball)", "N", 10.0, 25e3, 0.1,
                               60e3, (("kN", 1e3), ("kgf", 9.80665))),
    # ground motions: the largest recorded PGA is about 4 g; 100 g is no ground motion
    "acceleration": Plausible("ground acceleration", "m/s^2", 0.0, 5 * G, 0.0, A_MAX, _ACC_TYPOS),
    "time_step": Plausible("record's time step", "s", 1e-4, 0.05, 1e-6, 1.0, (("ms", 1e-3),)),
    # --- the project file's other physical keys (pipeline/config.py RANGES names each key's row) ---
    # the isolator: rolling friction of balls in grooves (the thesis: 0.004-0.02, Tables 19, 25); 0.5 is sliding
    "rolling_friction": Plausible("rolling friction coefficient", "-", 0.001, 0.05, 0.0, 0.5),
    "plate_side": Plausible("largest plate side (the CNC bed)", "m", 1.0, 2.5, 0.3, 3.0, _LENGTH_TYPOS),
    "plate_acceleration": Plausible("plate acceleration limit", "m/s^2", 0.01 * G, 0.5 * G, 1e-3 * G, 5 * G,
                                    _ACC_TYPOS),
    "fuse_release": Plausible("fuse release acceleration", "m/s^2", 0.02 * G, 0.3 * G, 1e-3 * G, 2 * G, _ACC_TYPOS),
    # friction of the statue on its support, the pedestal on the floor (stone, marble, bronze on wood or stone
    # 0.3-0.7; Monaco et al. 2020, Kafali et al. 2007: MU_SOURCES)
    "static_friction": Plausible("static friction coefficient", "-", 0.3, 0.7, 0.05, 2.0),
    "kinetic_ratio": Plausible("ratio mu_k / mu_s", "-", 0.6, 0.9, 0.01, 1.0),
    "allowance": Plausible("sliding allowance", "m", 0.005, 0.3, 1e-4, 10.0, _LENGTH_TYPOS),
    "pedestal_side": Plausible("pedestal side or height", "m", 0.2, 3.0, 0.01, 20.0, _LENGTH_TYPOS),
    "pedestal_mass": Plausible("pedestal mass", "kg", 5.0, 20e3, 0.1, 1e6, _MASS_TYPOS),
    # the building (EN 1998-1 4.3.3.2.2; a storey is 2-10 m: a museum hall's is at most about 6 m)
    "building_height": Plausible("building height (foundation to roof)", "m", 3.0, 60.0, 2.0, 1000.0, _LENGTH_TYPOS),
    "storeys": Plausible("number of storeys", "-", 1.0, 20.0, 1.0, 200.0),
    "storey_height": Plausible("storey height (building height / storeys)", "m", 2.5, 6.0, 2.0, 10.0),
    "building_period": Plausible("building period T1", "s", 0.05, 2.0, 0.01, 10.0, (("ms", 1e-3),)),
    "building_damping": Plausible("building damping", "%", 2.0, 10.0, 0.1, 50.0),
    # the 2D rocking model
    "alpha": Plausible("reduced uplift acceleration ratio alpha", "-", 0.5, 1.0, 1e-3, 1.0),
    "restitution": Plausible("coefficient of restitution", "-", 0.5, 1.0, 0.0, 1.0),
    "transition_rotation": Plausible("rolling-transition rotation", "rad", 1e-4, 0.05, 1e-7, 0.5),
    "pulse_frequency": Plausible("pulse frequency", "Hz", 0.1, 20.0, 1e-3, 100.0),
    # the prototype (the possible ranges are fabrication/spec.py SliceSpec's, so a file fails at load)
    "board": Plausible("board thickness", "m", 0.003, 0.025, 0.001, 0.1, _LENGTH_TYPOS),
    "glue": Plausible("glue film thickness", "m", 0.0, 0.001, 0.0, 0.005, _LENGTH_TYPOS),
    "tool": Plausible("cutter diameter", "m", 0.001, 0.012, 1e-4, 0.05, _LENGTH_TYPOS),
    "rod": Plausible("alignment rod diameter", "m", 0.003, 0.02, 5e-4, 0.1, _LENGTH_TYPOS),
    "clearance": Plausible("hole clearance", "m", 0.0, 0.001, 0.0, 0.005, _LENGTH_TYPOS),
    "wall": Plausible("minimum wall", "m", 0.002, 0.03, 0.0, 0.1, _LENGTH_TYPOS),
    "margin": Plausible("nesting margin", "m", 0.0, 0.02, 0.0, 0.1, _LENGTH_TYPOS),
    "edge": Plausible("sheet edge margin", "m", 0.0, 0.05, 0.0, 0.2, _LENGTH_TYPOS),
    "tolerance": Plausible("outline tolerance", "m", 1e-6, 5e-4, 1e-7, 0.001, _LENGTH_TYPOS),
    "sheet_side": Plausible("sheet side", "m", 0.5, 3.1, 0.05, 10.0, _LENGTH_TYPOS),
    "feed": Plausible("cutting feed", "m/s", 0.005, 0.2, 1e-5, 2.0, (("mm/min", 1.0 / 60000.0),)),
    "pass_depth": Plausible("depth per pass", "m", 0.001, 0.025, 1e-4, 0.1, _LENGTH_TYPOS),
    "board_density": Plausible("board density", "kg/m^3", 300.0, 1000.0, 50.0, 3000.0),
    "glue_density": Plausible("glue density", "kg/m^3", 900.0, 1500.0, 0.0, 3000.0),
    "rod_density": Plausible("rod density (0: the rods are pulled out)", "kg/m^3", 0.0, 9000.0, 0.0, 25000.0),
    "grid": Plausible("groove lattice spacing (0: the CNC mesh)", "m", 0.0, 0.01, 0.0, 0.05, _LENGTH_TYPOS),
}
"""quantity -> its :class:`Plausible` range: the one table of :func:`check_plausible`.
(Prototype boards, tools and sheets have their ranges in :class:`~statue2model.fabrication.spec.SliceSpec`;
densities are checked by :func:`~statue2model.geometry.massprops.check_density_mass` with these numbers.)"""

PLAUSIBLE_SIZE = (PLAUSIBLE["height"].low, PLAUSIBLE["height"].high)
"""Largest extent (m) of the objects this tool is for: with units 'auto', a unit must put the scan in it."""

POSSIBLE_SIZE = (PLAUSIBLE["height"].hard_low, PLAUSIBLE["height"].hard_high)
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



def _num(x: float) -> str:
    return f"{x:.4g}"


def _a(what: str) -> str:
    return ("an " if what[0] in "aeiou" else "a ") + what


def _meant(r: Plausible, value: float) -> str:
    """'; did you mean 1800 mm (1.8 m)?' for the units that make ``value`` plausible, else ''."""
    fits = [f"{_num(abs(value))} {name} ({_num(abs(value) * k)} {r.unit})" for name, k in r.typed
            if r.low <= abs(value) * k <= r.high]
    return f"; did you mean {' or '.join(fits)}?" if fits else ""


def check_plausible(quantity: str, value: float, name: str | None = None) -> str | None:
    """Check ``value`` (SI units) of ``quantity`` (a key of :data:`PLAUSIBLE`; the magnitude
    for an acceleration) against its range: an :class:`InputError` outside the possible range,
    a warning text outside the plausible one, else None. ``name`` is how the user wrote the
    input ('--height', '[scan] height'; default: the quantity's key; '': the value alone)."""
    r = PLAUSIBLE[quantity]
    name = quantity if name is None else name
    v = float(value)
    unit = "" if r.unit == "-" else f" {r.unit}"             # a ratio or a count has no unit
    shown = f"{name} = {_num(v)}{unit}" if name else f"{_num(v)}{unit}"
    if not np.isfinite(v):
        raise InputError(f"{shown}: not a finite number")
    mag = abs(v) if quantity == "acceleration" else v
    if not r.hard_low <= mag <= r.hard_high:
        span = f"{_num(r.hard_low)} to " if r.hard_low > 0 else "at most "
        hint = _meant(r, v) or f" (possible: {span}{_num(r.hard_high)}{unit})"
        raise InputError(f"{shown} is implausible for {_a(r.what)}{hint}")
    if not r.low <= mag <= r.high:
        return f"{shown} is unusual for {_a(r.what)} ({_num(r.low)} to {_num(r.high)}{unit}){_meant(r, v)}"
    return None
