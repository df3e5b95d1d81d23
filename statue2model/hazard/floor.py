"""Floor spectra: the acceleration spectrum at a storey of a building, for an object
standing on it (a statue on the second of three floors), from the ground spectrum.

Two code formulae for non-structural elements, both 5 % damped, both driven by the
ground spectrum only through alpha S = a_g S / g (the soil-amplified design ground
acceleration); z is the height of the floor the object stands on, H the building's
height above the foundation (only z/H matters: storeys or metres), T1 the building's
fundamental period in the direction considered, Ta the object's period:

* EC8 (EN 1998-1:2004 §4.3.5.2(3), eq. 4.25), ``code="ec8"``::

      Sa(Ta) = a_g S [3 (1 + z/H) / (1 + (1 - Ta/T1)^2) - 0.5]  >=  a_g S

* NTC 2018 §7.2.3, in the simplified form of its Circolare (C.S.LL.PP. n. 7 of
  21/01/2019, §C7.2.3, eqs. C7.2.11 and Tab. C7.2.I), ``code="ntc2018"``::

      Ta <  a T1:         Sa = a_g S (1 + z/H) a_p / (1 + (a_p - 1) (1 - Ta/(a T1))^2)
      a T1 <= Ta < b T1:  Sa = a_g S (1 + z/H) a_p
      Ta >= b T1:         Sa = a_g S (1 + z/H) a_p / (1 + (a_p - 1) (1 - Ta/(b T1))^2)

  with (a, b, a_p) = (0.8, 1.4, 5.0) for T1 <= 0.5 s, (0.3, 1.2, 4.0) for
  0.5 < T1 <= 1.0 s, (0.3, 1.0, 2.5) for T1 > 1.0 s. (The decree's own text asks
  for "formulae of proven validity"; these are the Circolare's. Check the table
  against the text in force before using the result in a design.)

At Ta = 0 both give the floor's peak acceleration: a_g S (1 + 1.5 z/H) (EC8) and
a_g S (1 + z/H) (NTC). A :class:`FloorSpectrum` has ``Se(T)`` and ``to_dict()`` like
:class:`~statue2model.hazard.code_spectra.ElasticSpectrum`, so it is a target
for :func:`statue2model.hazard.matching.match_set`. Units: SI (m/s^2, s).

Example
-------
>>> from statue2model.hazard.code_spectra import G, ntc2018
>>> ground = ntc2018(0.1 * G, 2.5, 0.3, soil="C")           # a_g S = 0.15 g
>>> fl = floor_spectrum(ground, z=2, H=3, T1=0.4, code="ec8")
>>> [round(float(v) / G, 4) for v in fl.Se([0.0, 0.4, 4.0])]   # 1 + 1.5 z/H; 3 (1 + z/H) - 0.5; floor
[0.3, 0.675, 0.15]
>>> fl = floor_spectrum(ground, z=2, H=3, T1=0.4)             # the ground spectrum's code: NTC
>>> [round(float(v) / G, 4) for v in fl.Se([0.0, 0.32, 0.5])]  # (1 + z/H); a_p (1 + z/H) on [aT1, bT1]
[0.25, 1.25, 1.25]
>>> parse_floor("z=2,H=3,T1=0.4,code=ec8", ground).code
'ec8'
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from .code_spectra import ElasticSpectrum, _periods

CODES = ("ec8", "ntc2018")

#: Circolare 2019 Tab. C7.2.I: (upper bound of T1 in s, a, b, a_p)
NTC_FLOOR_TABLE = ((0.5, 0.8, 1.4, 5.0), (1.0, 0.3, 1.2, 4.0), (math.inf, 0.3, 1.0, 2.5))


def ntc_floor_coefficients(T1: float) -> tuple[float, float, float]:
    """(a, b, a_p) of Tab. C7.2.I for a building of fundamental period T1 (s).

    >>> ntc_floor_coefficients(0.4), ntc_floor_coefficients(0.8), ntc_floor_coefficients(1.5)
    ((0.8, 1.4, 5.0), (0.3, 1.2, 4.0), (0.3, 1.0, 2.5))
    """
    for top, a, b, ap in NTC_FLOOR_TABLE:
        if T1 <= top:
            return a, b, ap
    raise InputError(f"building period T1 must be finite, got {T1!r}")  # pragma: no cover


@dataclass(frozen=True)
class FloorSpectrum:
    """Acceleration spectrum (5 % damping) at height z of a building of height H and
    fundamental period T1 (s), on a site of design ground acceleration a_g S (m/s^2)."""

    code: str
    a_g_S: float
    z: float
    H: float
    T1: float
    ground: ElasticSpectrum | None = None

    def __post_init__(self):
        if self.code not in CODES:
            raise InputError(f"floor spectrum code {self.code!r} is not one of {', '.join(CODES)}")
        for name in ("a_g_S", "H", "T1"):
            v = getattr(self, name)
            if not (isinstance(v, (int, float)) and math.isfinite(v) and v > 0):
                raise InputError(f"floor spectrum: {name} must be a positive finite number, got {v!r}")
        if not (isinstance(self.z, (int, float)) and math.isfinite(self.z) and 0 <= self.z <= self.H):
            raise InputError(f"floor spectrum: z must be between 0 (the ground) and H = {self.H:g} "
                             f"(the top), got {self.z!r}")

    @property
    def xi(self) -> float:
        """Damping ratio in percent (both formulae are for 5 %)."""
        return 5.0

    def Se(self, T) -> np.ndarray:
        """Floor pseudo-acceleration Sa(Ta), m/s^2, for periods Ta >= 0 s; same shape as T."""
        Ta = _periods(T)
        r = self.z / self.H
        if self.code == "ec8":
            sa = self.a_g_S * (3.0 * (1.0 + r) / (1.0 + (1.0 - Ta / self.T1) ** 2) - 0.5)
            return np.maximum(sa, self.a_g_S)
        a, b, ap = ntc_floor_coefficients(self.T1)
        top = self.a_g_S * (1.0 + r) * ap
        lo = top / (1.0 + (ap - 1.0) * (1.0 - Ta / (a * self.T1)) ** 2)
        hi = top / (1.0 + (ap - 1.0) * (1.0 - Ta / (b * self.T1)) ** 2)
        return np.where(Ta < a * self.T1, lo, np.where(Ta < b * self.T1, top, hi))

    def to_dict(self) -> dict:
        d = {"kind": "floor", "code": self.code, "a_g_S_m_s2": self.a_g_S, "z": self.z, "H": self.H,
             "z_over_H": self.z / self.H, "T1_s": self.T1}
        if self.ground is not None:
            d["ground"] = self.ground.to_dict()
        return d


def floor_spectrum(ground: ElasticSpectrum, z: float, H: float, T1: float, code: str | None = None) -> FloorSpectrum:
    """The floor spectrum at height z (same unit as H) of a building of fundamental
    period T1 (s) on the site of ``ground``; ``code`` "ec8" or "ntc2018" (default: the
    ground spectrum's code)."""
    if not isinstance(ground, ElasticSpectrum):
        raise InputError(f"floor spectrum: the ground spectrum must be an ElasticSpectrum, got {ground!r}")
    if code is None:
        code = "ntc2018" if ground.code == "NTC2018" else "ec8"
    code = str(code).strip().lower()
    return FloorSpectrum(code, ground.a_g * ground.S, _num("z", z), _num("H", H), _num("T1", T1), ground)


def _num(key: str, value) -> float:
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise InputError(f"floor spectrum: {key} must be a number, got {value!r}") from None
    if not math.isfinite(v):
        raise InputError(f"floor spectrum: {key} must be finite, got {value!r}")
    return v


def parse_floor(text: str, ground: ElasticSpectrum) -> FloorSpectrum:
    """``z=2,H=3,T1=0.4[,code=ec8|ntc2018]`` (z and H in storeys or metres, T1 in s;
    keys case-insensitive) on the site of ``ground``."""
    values: dict[str, str] = {}
    for item in str(text).split(","):
        key, eq, value = item.partition("=")
        key, value = key.strip().lower(), value.strip()
        if not eq or not key or not value:
            raise InputError(f"floor: {item.strip()!r} is not of the form key=value (e.g. z=2,H=3,T1=0.4)")
        if key not in ("z", "h", "t1", "code"):
            raise InputError(f"floor: unknown key {key!r} (use z, H, T1, code)")
        if key in values:
            raise InputError(f"floor: key {key!r} is given twice")
        values[key] = value
    missing = [k for k in ("z", "h", "t1") if k not in values]
    if missing:
        raise InputError(f"floor {text!r} lacks {', '.join(k if k == 'z' else k.upper() for k in missing)}")
    return floor_spectrum(ground, values["z"], values["h"], values["t1"], values.get("code"))
