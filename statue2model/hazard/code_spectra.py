"""Elastic acceleration response spectra for designing a seismic isolator.

Two codes, one spectral shape (SI units: accelerations in m/s^2, periods in s):

* Eurocode 8, EN 1998-1:2004 §3.2.2.2, horizontal elastic response spectrum,
  Type 1 and Type 2, ground types A-E with the recommended S, T_B, T_C, T_D of
  Tables 3.2 and 3.3 (:func:`ec8`);
* the Italian NTC 2018 (D.M. 17/01/2018) §3.2.3.2.1, from the site parameters
  a_g, F_0, T_C* with the stratigraphic (S_S, C_C, Tab. 3.2.IV) and
  topographic (S_T, Tab. 3.2.V) amplification (:func:`ntc2018`).

Both give, with eta = sqrt(10 / (5 + xi)) >= 0.55 (xi in percent) and
F0 = 2.5 for EC8::

    0   <= T <= T_B:  Se = a_g S [1 + T/T_B (eta F0 - 1)]
    T_B <= T <= T_C:  Se = a_g S eta F0
    T_C <= T <= T_D:  Se = a_g S eta F0 T_C / T
    T_D <= T:         Se = a_g S eta F0 T_C T_D / T^2

(the NTC first branch a_g S eta F0 [T/T_B + (1 - T/T_B)/(eta F0)] is the same
line). The last branch is used beyond 4 s as well.

Example
-------
>>> sp = ec8(0.3 * G, ground="B")           # Type 1, 5 % damping
>>> sp.code, sp.S, sp.T_B, sp.T_C, sp.T_D, sp.eta
('EC8-1', 1.2, 0.15, 0.5, 2.0, 1.0)
>>> [round(float(v), 4) for v in sp.Se([0.0, 0.15, 0.5, 1.0, 3.0]) / G]
[0.36, 0.9, 0.9, 0.45, 0.1]
>>> round(float(sp.SDe(3.0)), 4)            # spectral displacement at 3 s, m
0.2236
>>> ntc = parse_spectrum("ntc2018:ag=0.25g,F0=2.4,Tc=0.3,soil=B,topo=T1")
>>> round(ntc.S, 3), round(ntc.T_C, 4), round(ntc.T_D, 2)
(1.16, 0.4198, 2.6)
>>> round(float(ntc.Se(0.3) / G), 3)        # plateau: a_g S F0
0.696
>>> ec8(0.3 * G, ground="S1")
Traceback (most recent call last):
...
statue2model.errors.InputError: EC8 ground type 'S1' is not one of A, B, C, D, E (S1 and S2 need special studies)
"""
from __future__ import annotations

import math
from dataclasses import asdict, dataclass

import numpy as np

from ..errors import InputError, quoted

from ..quantities import G_STANDARD as G  # m/s^2 (standard gravity)

#: EN 1998-1:2004 recommended values, {spectrum type: {ground type: (S, T_B, T_C, T_D)}}
#: (Table 3.2 for Type 1, Table 3.3 for Type 2).
EC8_TABLE: dict[int, dict[str, tuple[float, float, float, float]]] = {
    1: {
        "A": (1.00, 0.15, 0.40, 2.0),
        "B": (1.20, 0.15, 0.50, 2.0),
        "C": (1.15, 0.20, 0.60, 2.0),
        "D": (1.35, 0.20, 0.80, 2.0),
        "E": (1.40, 0.15, 0.50, 2.0),
    },
    2: {
        "A": (1.00, 0.05, 0.25, 1.2),
        "B": (1.35, 0.05, 0.25, 1.2),
        "C": (1.50, 0.10, 0.25, 1.2),
        "D": (1.80, 0.10, 0.30, 1.2),
        "E": (1.60, 0.05, 0.25, 1.2),
    },
}

#: NTC 2018 Tab. 3.2.IV, {subsoil category: (S_S lower bound, S_S = c0 - c1 F0 a_g/g, upper bound,
#: C_C = coefficient * (T_C*)^exponent)} as (lo, c0, c1, hi, cc_coefficient, cc_exponent).
NTC_SOIL: dict[str, tuple[float, float, float, float, float, float]] = {
    "A": (1.00, 1.00, 0.00, 1.00, 1.00, 0.00),
    "B": (1.00, 1.40, 0.40, 1.20, 1.10, -0.20),
    "C": (1.00, 1.70, 0.60, 1.50, 1.05, -0.33),
    "D": (0.90, 2.40, 1.50, 1.80, 1.25, -0.50),
    "E": (1.00, 2.00, 1.10, 1.60, 1.15, -0.40),
}

#: NTC 2018 Tab. 3.2.V, topographic amplification S_T (the value at the crest for T2-T4).
NTC_TOPOGRAPHY: dict[str, float] = {"T1": 1.0, "T2": 1.2, "T3": 1.2, "T4": 1.4}

ETA_MIN = 0.55  # lower bound of the damping correction factor (EC8 eq. 3.6, NTC eq. 3.2.6)


def _finite(name: str, value, positive: bool = True) -> float:
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise InputError(f"{name} must be a number, got {quoted(value)}") from None
    if not math.isfinite(v) or (positive and v <= 0) or (not positive and v < 0):
        kind = "positive" if positive else "non-negative"
        raise InputError(f"{name} must be a {kind} finite number, got {quoted(value)}")
    return v


def damping_correction(xi: float = 5.0) -> float:
    """eta = sqrt(10 / (5 + xi)) with xi the viscous damping ratio in percent, not below 0.55.

    >>> damping_correction(5.0), damping_correction(50.0)
    (1.0, 0.55)
    """
    xi = _finite("damping ratio xi (percent)", xi, positive=False)
    return max(ETA_MIN, math.sqrt(10.0 / (5.0 + xi)))


@dataclass(frozen=True)
class ElasticSpectrum:
    """A horizontal elastic acceleration response spectrum (EC8 / NTC 2018 shape).

    code: "EC8-1", "EC8-2" or "NTC2018"; a_g: design ground acceleration on type A
    ground, m/s^2; S: soil factor (S_S S_T for NTC); eta: damping correction; F0:
    plateau amplification (2.5 for EC8); T_B, T_C, T_D: corner periods, s; xi:
    damping ratio in percent; limit_state: the NTC limit state the site parameters belong
    to (SLO, SLD, SLV, SLC, or SLA, the damage to artistic contents of the Linee Guida for
    cultural heritage), a label carried into the reports (None if not given).
    """

    code: str
    a_g: float
    S: float
    eta: float
    F0: float
    T_B: float
    T_C: float
    T_D: float
    xi: float = 5.0
    limit_state: str | None = None

    def __post_init__(self):
        for name in ("a_g", "S", "eta", "F0", "T_B", "T_C", "T_D"):
            object.__setattr__(self, name, _finite(name, getattr(self, name)))
        object.__setattr__(self, "xi", _finite("xi", self.xi, positive=False))
        if not self.T_B < self.T_C < self.T_D:
            raise InputError(f"corner periods must satisfy T_B < T_C < T_D, got "
                             f"T_B={self.T_B:g}, T_C={self.T_C:g}, T_D={self.T_D:g}")

    @property
    def plateau(self) -> float:
        """Se on [T_B, T_C] = a_g S eta F0, m/s^2."""
        return self.a_g * self.S * self.eta * self.F0

    def Se(self, T) -> np.ndarray:
        """Elastic pseudo-acceleration Se(T), m/s^2, for periods T >= 0 (s); same shape as T."""
        T = _periods(T)
        top = self.plateau
        with np.errstate(divide="ignore", invalid="ignore"):
            out = np.where(T <= self.T_B,
                           self.a_g * self.S * (1.0 + T / self.T_B * (self.eta * self.F0 - 1.0)),
                           np.where(T <= self.T_C, top,
                                    np.where(T <= self.T_D, top * self.T_C / T,
                                             top * self.T_C * self.T_D / T ** 2)))
        return out

    def SDe(self, T) -> np.ndarray:
        """Elastic displacement spectrum Se T^2 / (4 pi^2), m; same shape as T."""
        T = _periods(T)
        return self.Se(T) * T ** 2 / (4.0 * math.pi ** 2)

    def to_dict(self) -> dict:
        """The fields as plain Python values (JSON-ready)."""
        return asdict(self)


def _periods(T) -> np.ndarray:
    try:
        arr = np.asarray(T, dtype=float)
    except (TypeError, ValueError):
        raise InputError(f"periods must be numbers, got {quoted(T)}") from None
    bad = ~np.isfinite(arr) | (arr < 0)
    if np.any(bad):
        raise InputError(f"periods must be finite and >= 0 s, got {quoted(float(arr[bad].flat[0]))}")
    return arr


def ec8(a_g: float, ground: str = "A", spectrum_type: int = 1, xi: float = 5.0) -> ElasticSpectrum:
    """EN 1998-1:2004 horizontal elastic spectrum (§3.2.2.2) with the recommended
    Table 3.2 (Type 1) / 3.3 (Type 2) values; a_g in m/s^2 (already times gamma_I)."""
    a_g = _finite("design ground acceleration a_g (m/s^2)", a_g)
    key = str(ground).strip().upper()
    if key not in EC8_TABLE[1]:
        raise InputError(f"EC8 ground type {quoted(ground)} is not one of A, B, C, D, E "
                         f"(S1 and S2 need special studies)")
    if isinstance(spectrum_type, bool) or spectrum_type not in (1, 2):
        raise InputError(f"EC8 spectrum type must be 1 or 2, got {quoted(spectrum_type)}")
    S, T_B, T_C, T_D = EC8_TABLE[int(spectrum_type)][key]
    return ElasticSpectrum(f"EC8-{int(spectrum_type)}", a_g, S, damping_correction(xi), 2.5,
                           T_B, T_C, T_D, float(xi))


def ntc_soil(soil: str, a_g: float, F0: float, Tc_star: float) -> tuple[float, float]:
    """(S_S, C_C) of NTC 2018 Tab. 3.2.IV for subsoil category A-E; a_g in m/s^2.

    >>> ntc_soil("C", 0.1 * G, 2.5, 0.3)[0]     # 1.70 - 0.60 * 2.5 * 0.1 = 1.55 > 1.50
    1.5
    """
    key = str(soil).strip().upper()
    if key not in NTC_SOIL:
        raise InputError(f"NTC subsoil category {quoted(soil)} is not one of A, B, C, D, E "
                         f"(other sites need a specific local response analysis)")
    a_g = _finite("a_g (m/s^2)", a_g)
    F0 = _finite("F0", F0)
    Tc_star = _finite("Tc* (s)", Tc_star)
    lo, c0, c1, hi, cc, ex = NTC_SOIL[key]
    S_S = min(hi, max(lo, c0 - c1 * F0 * a_g / G))
    return S_S, cc * Tc_star ** ex


NTC_LIMIT_STATES = ("SLO", "SLD", "SLV", "SLC", "SLA")


def ntc2018(a_g: float, F0: float, Tc_star: float, soil: str = "A", topography: str = "T1",
            xi: float = 5.0, limit_state: str | None = None) -> ElasticSpectrum:
    """NTC 2018 §3.2.3.2.1 horizontal elastic spectrum from the site parameters
    a_g (m/s^2), F0 and T_C* (s): S = S_S S_T, T_C = C_C T_C*, T_B = T_C / 3,
    T_D = 4.0 a_g/g + 1.6. ``limit_state`` (NTC_LIMIT_STATES) names the state whose return
    period the given a_g, F0, T_C* are the site's for (they come from the national hazard
    grid for that state; this function does not look them up)."""
    if limit_state is not None:
        limit_state = str(limit_state).strip().upper()
        if limit_state not in NTC_LIMIT_STATES:
            raise InputError(f"NTC limit state {quoted(limit_state)} is not one of {', '.join(NTC_LIMIT_STATES)}")
    a_g = _finite("design ground acceleration a_g (m/s^2)", a_g)
    S_S, C_C = ntc_soil(soil, a_g, F0, Tc_star)
    topo = str(topography).strip().upper()
    if topo not in NTC_TOPOGRAPHY:
        raise InputError(f"NTC topographic category {quoted(topography)} is not one of T1, T2, T3, T4")
    T_C = C_C * float(Tc_star)
    return ElasticSpectrum("NTC2018", a_g, S_S * NTC_TOPOGRAPHY[topo], damping_correction(xi), float(F0),
                           T_C / 3.0, T_C, 4.0 * a_g / G + 1.6, float(xi), limit_state)


# --- command-line form ---------------------------------------------------------------
def _accel(key: str, text: str) -> float:
    from ..quantities import parse_accel     # one reading of an acceleration: 0.25g or 2.45m/s2

    value = parse_accel(text, f"spectrum: {key}", key=key, g=G)
    if not value > 0:
        raise InputError(f"spectrum: {key} must be a positive finite acceleration, got {quoted(text)}")
    return value


def _number(key: str, text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise InputError(f"spectrum: {key} must be a number, got {quoted(text)}") from None
    if not math.isfinite(value):
        raise InputError(f"spectrum: {key} must be finite, got {quoted(text)}")
    return value


_KEYS = {"ec8": ({"ag"}, {"ground", "type", "xi"}),
         "ntc2018": ({"ag", "f0", "tc"}, {"soil", "topo", "xi", "ls"})}


def parse_spectrum(text: str) -> ElasticSpectrum:
    """A spectrum from its command-line form, e.g. "ec8:ag=0.25g,ground=C,type=1,xi=5" or
    "ntc2018:ag=0.2g,F0=2.4,Tc=0.3,soil=B,topo=T1,ls=SLV" (ag with a unit, g or m/s2;
    keys are case-insensitive; ls: the NTC limit state the site parameters are for).

    >>> parse_spectrum("ntc2018:ag=0.1g,F0=2.5,Tc=0.3,soil=C,ls=sla").limit_state
    'SLA'
    """
    if not isinstance(text, str):
        raise InputError(f"spectrum must be a string like 'ec8:ag=0.25g,ground=C', got {quoted(text)}")
    code, sep, rest = text.partition(":")
    code = code.strip().lower()
    if code not in _KEYS:
        raise InputError(f"unknown spectrum code {quoted(code)} in {quoted(text)} (use ec8 or ntc2018)")
    if not sep or not rest.strip():
        raise InputError(f"spectrum {quoted(text)} has no parameters (e.g. {code}:ag=0.25g)")
    required, optional = _KEYS[code]
    values: dict[str, str] = {}
    for item in rest.split(","):
        key, eq, value = item.partition("=")
        key, value = key.strip().lower(), value.strip()
        if not eq or not key or not value:
            raise InputError(f"spectrum: {quoted(item.strip())} is not of the form key=value")
        if key not in required | optional:
            raise InputError(f"spectrum: unknown key {quoted(key)} for {code} "
                             f"(use {', '.join(sorted(required | optional))})")
        if key in values:
            raise InputError(f"spectrum: key {quoted(key)} is given twice")
        values[key] = value
    missing = sorted(required - values.keys())
    if missing:
        raise InputError(f"spectrum {quoted(text)} lacks {', '.join(missing)}")
    a_g = _accel("ag", values["ag"])
    xi = _number("xi", values.get("xi", "5"))
    if code == "ec8":
        kind = values.get("type", "1")
        if kind not in ("1", "2"):
            raise InputError(f"spectrum: type must be 1 or 2, got {quoted(kind)}")
        return ec8(a_g, values.get("ground", "A"), int(kind), xi)
    return ntc2018(a_g, _number("F0", values["f0"]), _number("Tc", values["tc"]),
                   values.get("soil", "A"), values.get("topo", "T1"), xi, values.get("ls"))
