"""The building an object stands in, as a floor spectrum needs it (:mod:`statue2model.hazard.floor`).

A :class:`Building` is n storeys of equal height over H metres, of one structural type,
with its fundamental period T1 in the direction considered (given, or estimated), its
viscous damping xi (percent, 5 by default) and whether it is seismically isolated. The
object stands on floor ``floor`` (0 = the ground floor, n = the roof), at
z = floor H / n above the foundation.

Structural types: "masonry" (most museums: masonry palazzi), "concrete-frame",
"steel-frame" (the two *framed* types, the only ones the Circolare's simplified floor
formula C7.2.11 is for) and "other".

Period estimate (when T1 is not given), EN 1998-1:2004 4.3.3.2.2(3) eq. 4.6, the same as
NTC 2008 eq. 7.3.5 and the Circolare 2019 (C7.3.3.2), for buildings up to 40 m::

    T1 = C_t H^(3/4)    C_t = 0.085 steel frames, 0.075 concrete frames, 0.050 any other

Example
-------
>>> b = Building(n=3, H=11.5)                   # the thesis' museum: masonry, 11.5 m (ch. 6.3.2)
>>> round(b.period, 3), b.period_estimated, b.framed     # 0.050 * 11.5^0.75; the thesis says 0.32 s
(0.312, True, False)
>>> Building(n=3, H=12.0).z(2)                  # the second of three floors: 2 * 12 / 3
8.0
>>> Building(n=3, H=12.0, structure="timber")
Traceback (most recent call last):
...
statue2model.errors.InputError: building structure 'timber' is not one of masonry, concrete-frame, steel-frame, other
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ..quantities import positive as _positive

STRUCTURES = ("masonry", "concrete-frame", "steel-frame", "other")
"""The structural types a Building may have."""

FRAMED = ("concrete-frame", "steel-frame")
"""The framed types (Circolare 2019 eq. C7.2.11 is for these only)."""

C_T = {"steel-frame": 0.085, "concrete-frame": 0.075, "masonry": 0.050, "other": 0.050}
"""C_t of EN 1998-1 eq. 4.6 (s / m^(3/4)) by structural type."""

ESTIMATE_MAX_HEIGHT = 40.0
"""m: EN 1998-1 eq. 4.6 holds for buildings up to 40 m high."""


def estimated_period(H: float, structure: str = "masonry") -> float:
    """T1 = C_t H^(3/4) (s) of a building H metres high (EN 1998-1 eq. 4.6).

    >>> round(estimated_period(12.0), 4), round(estimated_period(12.0, "concrete-frame"), 4)
    (0.3224, 0.4836)
    """
    structure = _structure(structure)
    H = _positive("building height H (m)", H)
    if H > ESTIMATE_MAX_HEIGHT:
        raise InputError(f"building height H = {H:g} m: the estimate T1 = C_t H^(3/4) holds up to "
                         f"{ESTIMATE_MAX_HEIGHT:g} m; give the building's period T1")
    return C_T[structure] * H ** 0.75


def _structure(value) -> str:
    key = str(value).strip().lower()
    if key not in STRUCTURES:
        raise InputError(f"building structure {value!r} is not one of {', '.join(STRUCTURES)}")
    return key


def _integer(value) -> int | None:
    """value as an int if it is a whole number (int, numpy integer or integral float), else None."""
    if isinstance(value, bool):
        return None
    if isinstance(value, (int, np.integer)):
        return int(value)
    if isinstance(value, float) and math.isfinite(value) and value == int(value):
        return int(value)
    return None


def storeys(value, what: str = "number of storeys n") -> int:
    """A number of storeys: an integer >= 1."""
    n = _integer(value)
    if n is None or n < 1:
        raise InputError(f"{what} must be a whole number >= 1, got {value!r}")
    return n


def building_damping(value) -> float:
    """A building's viscous damping ratio in percent: 0 < xi < 100."""
    if isinstance(value, bool):
        raise InputError(f"building damping xi must be a percentage between 0 and 100 (e.g. 5), got {value!r}")
    try:
        xi = float(value)
    except (TypeError, ValueError):
        raise InputError(f"building damping xi must be a percentage between 0 and 100 (e.g. 5), "
                         f"got {value!r}") from None
    if not (math.isfinite(xi) and 0 < xi < 100):
        raise InputError(f"building damping xi must be a percentage between 0 and 100 (e.g. 5), got {value!r}")
    return xi


@dataclass(frozen=True)
class Building:
    """A building of ``n`` storeys of equal height over ``H`` m, period ``T1`` s (None: the
    estimate C_t H^(3/4)), ``structure`` one of STRUCTURES, damping ``xi`` in percent,
    ``isolated`` True for a seismically isolated building."""

    n: int
    H: float
    T1: float | None = None
    structure: str = "masonry"
    xi: float = 5.0
    isolated: bool = False

    def __post_init__(self):
        object.__setattr__(self, "n", storeys(self.n))
        object.__setattr__(self, "H", _positive("building height H (m)", self.H))
        object.__setattr__(self, "structure", _structure(self.structure))
        object.__setattr__(self, "xi", building_damping(self.xi))
        if not isinstance(self.isolated, (bool, np.bool_)):
            raise InputError(f"building: isolated must be True or False, got {self.isolated!r}")
        object.__setattr__(self, "isolated", bool(self.isolated))
        if self.T1 is None:
            estimated_period(self.H, self.structure)          # refuses a building too tall for the estimate
        else:
            object.__setattr__(self, "T1", _positive("building period T1 (s)", self.T1))

    @property
    def framed(self) -> bool:
        """True for a concrete or steel frame."""
        return self.structure in FRAMED

    @property
    def C_t(self) -> float:
        """C_t of EN 1998-1 eq. 4.6 for this structural type."""
        return C_T[self.structure]

    @property
    def period(self) -> float:
        """T1 (s): the one given, else C_t H^(3/4)."""
        return self.T1 if self.T1 is not None else estimated_period(self.H, self.structure)

    @property
    def period_estimated(self) -> bool:
        """True when :attr:`period` is the estimate C_t H^(3/4)."""
        return self.T1 is None

    def z(self, floor) -> float:
        """Height (m) above the foundation of floor ``floor`` (0 = ground floor, n = roof): floor H / n."""
        k = _integer(floor)
        if k is None or not 0 <= k <= self.n:
            raise InputError(f"floor must be a whole number from 0 (the ground floor) to {self.n} "
                             f"(the roof of {self.n} storeys), got {floor!r}")
        return k * self.H / self.n

    def to_dict(self) -> dict:
        """JSON-ready: every field, the period used and where it comes from."""
        return {"n": self.n, "H_m": self.H, "T1_s": self.period,
                "T1_source": f"C_t H^(3/4), C_t {self.C_t:g} (EN 1998-1 eq. 4.6)" if self.period_estimated
                else "given", "structure": self.structure, "framed": self.framed, "xi_percent": self.xi,
                "isolated": self.isolated}
