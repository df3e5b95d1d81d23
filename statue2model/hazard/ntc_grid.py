"""The site parameters a_g, F0, T_C* of an Italian site from the national hazard grid, as NTC
2018 (D.M. 17/01/2018) par. 3.2 asks: the grid and its rules are those of NTC 2008
(D.M. 14/01/2008) Allegato A ("Pericolosita' sismica") and Allegato B, Tabella 1 (INGV: a_g,
F0, T_C* at 10751 points about 5.5 km apart, for the nine return periods of RETURN_PERIODS).

Allegato A's rules, as this module applies them (SI units; a_g in m/s^2 on type A ground):

* return period of a limit state (NTC 2018 par. 3.2.1, eq. C3.2.1 of the Circolare 2019)::

      T_R = -V_R / ln(1 - P_VR),   V_R = V_N c_u

* in space (Allegato A eq. 2): the value at the site is the inverse-distance weighted mean of
  its value at the (four) grid points around it, p = sum(p_i / d_i) / sum(1 / d_i), d_i the
  great-circle distance (the weights depend on ratios only: any consistent distance will do);
  a site on a grid point takes that point's value;
* in return period (Allegato A eq. 1), between the tabulated T_R1 < T_R < T_R2::

      log p = log p1 + log(p2 / p1) log(T_R / T_R1) / log(T_R2 / T_R1)

  applied to the site's values at T_R1 and T_R2 (space first, then time). Return periods
  outside 30-2475 years are refused (the grid does not reach them).

Allegato B prints a_g in g/10 (tenths of g); :class:`GridPoint` holds it in g as
:attr:`GridPoint.from_table` reads a row of that table.

:data:`PAOLO_ORSI_CELL`: the four grid points around the Museo Archeologico Regionale "Paolo
Orsi" in Syracuse (Viale Teocrito 66, about 37.0756 N, 15.2866 E; :data:`PAOLO_ORSI`), where
the thesis' Venere Landolina stands (ch. 6.3.2), as printed in Tabella 1 (IDs 49645, 49646,
49867, 49868; copied from a machine-readable copy of the table, the file data/spettri2008.csv
of the public repository marcogiulivo27/SpettriNTCweb, and checked against the table's
layout: IDs east +1, north -222).

Example
-------
>>> T_R = return_period(V_N=50, c_u=1.5, P_VR=0.63)      # SLD of a class III building: 75 years
>>> round(T_R, 1)
75.4
>>> ag, F0, Tc = site_parameters(PAOLO_ORSI_CELL, *PAOLO_ORSI, T_R)
>>> round(ag / G, 4), round(F0, 3), round(Tc, 3)
(0.0669, 2.511, 0.286)
>>> sp = site_spectrum(PAOLO_ORSI_CELL, *PAOLO_ORSI, T_R, soil="C", topography="T1", limit_state="SLA")
>>> sp.code, sp.limit_state, round(sp.S, 2), round(sp.T_C, 3)
('NTC2018', 'SLA', 1.5, 0.454)
>>> site_parameters(PAOLO_ORSI_CELL, *PAOLO_ORSI, 3000.0)
Traceback (most recent call last):
...
statue2model.errors.InputError: return period T_R = 3000 years is outside the hazard grid's 30-2475 years (NTC 2008 Allegato A)
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from ..errors import InputError
from ..quantities import positive as _positive
from .code_spectra import G, ElasticSpectrum, ntc2018

RETURN_PERIODS = (30, 50, 72, 101, 140, 201, 475, 975, 2475)
"""Years: the return periods of Allegato B, Tabella 1."""

EARTH_RADIUS = 6371.0
"""km: mean radius of the Earth, for the great-circle distances of the weights."""


@dataclass(frozen=True)
class GridPoint:
    """One point of the hazard grid: ``id`` (Tabella 1's ID), ``lon``, ``lat`` (degrees E, N)
    and, for each of RETURN_PERIODS, ``ag`` (g, on type A ground), ``F0`` and ``Tc`` (T_C*, s)."""

    id: int
    lon: float
    lat: float
    ag: tuple[float, ...]
    F0: tuple[float, ...]
    Tc: tuple[float, ...]

    def __post_init__(self):
        lon, lat = float(self.lon), float(self.lat)
        if not (math.isfinite(lon) and math.isfinite(lat) and -180 <= lon <= 180 and -90 <= lat <= 90):
            raise InputError(f"grid point {self.id}: longitude/latitude ({self.lon!r}, {self.lat!r}) are not degrees")
        object.__setattr__(self, "lon", lon)
        object.__setattr__(self, "lat", lat)
        for name in ("ag", "F0", "Tc"):
            values = tuple(_positive(f"grid point {self.id}: {name}", v) for v in getattr(self, name))
            if len(values) != len(RETURN_PERIODS):
                raise InputError(f"grid point {self.id}: {name} needs {len(RETURN_PERIODS)} values (one per return "
                                 f"period {', '.join(map(str, RETURN_PERIODS))} years), got {len(values)}")
            object.__setattr__(self, name, values)

    @classmethod
    def from_table(cls, id: int, lon: float, lat: float, values) -> "GridPoint":
        """A point from a row of Tabella 1 as printed: ID, LON, LAT, then a_g (in g/10), F0,
        T_C* for each return period in turn (27 numbers).

        >>> p = GridPoint.from_table(1, 15.0, 37.0, [0.5, 2.5, 0.25] * 9)
        >>> p.ag[0], p.F0[0], p.Tc[0]
        (0.05, 2.5, 0.25)
        """
        v = [float(x) for x in values]
        if len(v) != 3 * len(RETURN_PERIODS):
            raise InputError(f"grid point {id}: a row of Tabella 1 has {3 * len(RETURN_PERIODS)} values after "
                             f"ID, LON, LAT (a_g, F0, T_C* per return period), got {len(v)}")
        return cls(int(id), lon, lat, tuple(x / 10.0 for x in v[0::3]), tuple(v[1::3]), tuple(v[2::3]))


def return_period(V_N: float, c_u: float, P_VR: float) -> float:
    """T_R = -V_N c_u / ln(1 - P_VR) (years) of a limit state with probability of exceedance
    P_VR (0-1) in the reference period V_R = V_N c_u (NTC 2018 par. 2.4.3 and 3.2.1); NTC 2018
    Tab. 3.2.I: P_VR = 0.81 SLO, 0.63 SLD, 0.10 SLV, 0.05 SLC.

    >>> round(return_period(50, 1.0, 0.10), 1)          # SLV of an ordinary building: the 475 years
    474.6
    """
    V_R = _positive("nominal life V_N (years)", V_N) * _positive("class-of-use coefficient c_u", c_u)
    p = _positive("probability of exceedance P_VR", P_VR)
    if not p < 1:
        raise InputError(f"probability of exceedance P_VR must be between 0 and 1, got {P_VR!r}")
    return -V_R / math.log1p(-p)


def distance_km(lon1: float, lat1: float, lon2: float, lat2: float) -> float:
    """Great-circle distance (km) between two points given in degrees (haversine formula).

    >>> round(distance_km(15.0, 37.0, 15.0, 38.0), 2)   # one degree of latitude
    111.19
    """
    p1, p2 = math.radians(lat1), math.radians(lat2)
    h = (math.sin((p2 - p1) / 2.0) ** 2
         + math.cos(p1) * math.cos(p2) * math.sin(math.radians(lon2 - lon1) / 2.0) ** 2)
    return 2.0 * EARTH_RADIUS * math.asin(min(1.0, math.sqrt(h)))


def weights(points, lon: float, lat: float) -> list[float]:
    """The inverse-distance weights (summing to 1) of ``points`` at the site (Allegato A eq. 2);
    a site on a grid point gives that point weight 1."""
    pts = list(points)
    if not pts or not all(isinstance(p, GridPoint) for p in pts):
        raise InputError("hazard grid: give the grid points around the site (GridPoint objects)")
    d = [distance_km(p.lon, p.lat, float(lon), float(lat)) for p in pts]
    if not all(math.isfinite(x) for x in d):
        raise InputError(f"hazard grid: the site ({lon!r}, {lat!r}) is not a longitude and latitude in degrees")
    on = [i for i, x in enumerate(d) if x < 1e-9]
    if on:
        return [1.0 if i == on[0] else 0.0 for i in range(len(pts))]
    inv = [1.0 / x for x in d]
    total = sum(inv)
    return [w / total for w in inv]


def _at(points, w, k: int) -> tuple[float, float, float]:
    return (sum(wi * p.ag[k] for wi, p in zip(w, points)), sum(wi * p.F0[k] for wi, p in zip(w, points)),
            sum(wi * p.Tc[k] for wi, p in zip(w, points)))


def site_parameters(points, lon: float, lat: float, T_R: float) -> tuple[float, float, float]:
    """(a_g in m/s^2, F0, T_C* in s) at the site (lon, lat in degrees) for return period ``T_R``
    (years), from the grid points around it (Allegato A eqs. 2 and 1; module docstring)."""
    pts = list(points)
    T_R = _positive("return period T_R (years)", T_R)
    lo, hi = RETURN_PERIODS[0], RETURN_PERIODS[-1]
    if not lo <= T_R <= hi:
        raise InputError(f"return period T_R = {T_R:g} years is outside the hazard grid's {lo}-{hi} years "
                         f"(NTC 2008 Allegato A)")
    w = weights(pts, lon, lat)
    if T_R in RETURN_PERIODS:
        ag, F0, Tc = _at(pts, w, RETURN_PERIODS.index(T_R))
        return ag * G, F0, Tc
    k = max(i for i, t in enumerate(RETURN_PERIODS) if t < T_R)
    t1, t2 = RETURN_PERIODS[k], RETURN_PERIODS[k + 1]
    f = math.log(T_R / t1) / math.log(t2 / t1)
    p1, p2 = _at(pts, w, k), _at(pts, w, k + 1)
    ag, F0, Tc = (math.exp(math.log(a) + math.log(b / a) * f) for a, b in zip(p1, p2))
    return ag * G, F0, Tc


def site_spectrum(points, lon: float, lat: float, T_R: float, soil: str = "A", topography: str = "T1",
                  xi: float = 5.0, limit_state: str | None = None) -> ElasticSpectrum:
    """The NTC 2018 elastic spectrum (:func:`statue2model.hazard.code_spectra.ntc2018`) of the site
    for return period ``T_R`` (years), subsoil category ``soil``, topography ``topography``."""
    ag, F0, Tc = site_parameters(points, lon, lat, T_R)
    return ntc2018(ag, F0, Tc, soil, topography, xi, limit_state)


def _cell() -> tuple[GridPoint, ...]:
    rows = (  # ID, LON, LAT, then a_g (g/10), F0, T_C* at 30, 50, 72, 101, 140, 201, 475, 975, 2475 years
        (49867, 15.23836, 37.07074, (0.38845, 2.4978, 0.24727, 0.55757, 2.4927, 0.26732, 0.6912, 2.5161, 0.28241,
                                     0.87773, 2.3933, 0.30627, 1.113, 2.3223, 0.3182, 1.4072, 2.3156, 0.3343,
                                     2.2831, 2.2504, 0.41653, 3.2287, 2.3728, 0.46252, 5.1656, 2.3414, 0.54185)),
        (49868, 15.30073, 37.0697, (0.35773, 2.5439, 0.24257, 0.5069, 2.51, 0.26461, 0.6259, 2.5211, 0.28337,
                                    0.76696, 2.4963, 0.29606, 0.97555, 2.3679, 0.3272, 1.2517, 2.3289, 0.33965,
                                    2.0265, 2.277, 0.42054, 2.9049, 2.3669, 0.45959, 4.6392, 2.3449, 0.53195)),
        (49645, 15.23965, 37.12073, (0.39915, 2.5052, 0.25051, 0.57017, 2.5003, 0.26946, 0.7053, 2.5149, 0.2836,
                                     0.89395, 2.3932, 0.30807, 1.1305, 2.3248, 0.31926, 1.4264, 2.3158, 0.33608,
                                     2.3066, 2.2591, 0.41965, 3.2857, 2.3602, 0.46506, 5.2347, 2.3341, 0.54246)),
        (49646, 15.30205, 37.11969, (0.36869, 2.5477, 0.24614, 0.51878, 2.5052, 0.2677, 0.6398, 2.5178, 0.28474,
                                     0.77856, 2.4754, 0.31259, 0.98794, 2.3738, 0.32883, 1.2649, 2.335, 0.34194,
                                     2.0386, 2.2894, 0.42371, 2.9496, 2.3521, 0.4611, 4.6274, 2.3659, 0.53292)),
    )
    return tuple(GridPoint.from_table(i, lon, lat, v) for i, lon, lat, v in rows)


PAOLO_ORSI_CELL = _cell()
"""The four grid points (Tabella 1) around the Paolo Orsi museum, Syracuse (module docstring)."""

PAOLO_ORSI = (15.2866, 37.0756)
"""(longitude E, latitude N) of the Paolo Orsi museum, Viale Teocrito 66, Syracuse (approximate)."""
