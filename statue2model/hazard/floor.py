"""Floor spectra: the 5 %-damped acceleration spectrum at a storey of a building, for an
object standing on it (a statue on the second of three floors), from the ground spectrum.

z is the height of the floor the object stands on above the foundation, H the building's
height, n its storeys, T1 its fundamental period in the direction considered, T (T_a) the
object's period; alpha S = a_g S (m/s^2 here) is the soil-amplified design ground
acceleration; S_e(T, xi) is the ground spectrum at damping xi (percent). Three methods:

* ``"ec8"``: EN 1998-1:2004 4.3.5.2(3), eq. 4.25 (any building)::

      S_a(T) = a_g S [3 (1 + z/H) / (1 + (1 - T/T1)^2) - 0.5]  >=  a_g S

* ``"ntc2018-framed"``: Circolare 2019 (C.S.LL.PP. n. 7 of 21/01/2019, on NTC 2018 7.2.3),
  eq. C7.2.11 with Tab. C7.2.II, FOR FRAMED BUILDINGS ONLY (refused for any other)::

      T <  a T1:        S_a = a_g S (1 + z/H) a_p / (1 + (a_p - 1)(1 - T/(a T1))^2)  >=  a_g S
      a T1 <= T < b T1: S_a = a_g S (1 + z/H) a_p
      T >= b T1:        S_a = a_g S (1 + z/H) a_p / (1 + (a_p - 1)(1 - T/(b T1))^2)  >=  a_g S

  (a, b, a_p) = (0.8, 1.4, 5.0) for T1 < 0.5 s, (0.3, 1.2, 4.0) for 0.5 s <= T1 <= 1.0 s,
  (0.3, 1.0, 2.5) for T1 > 1.0 s.

* ``"ntc2018"`` (the default on an NTC ground spectrum): the Circolare's general formulation,
  eqs. C7.2.5-C7.2.10, valid for any typology (masonry included), first mode only (C7.2.5's
  square root of the sum of squares has one term), mode shape linear with height::

      psi_1(z) = z/H,  gamma_1 = 3n / (2n + 1)
      a_Z  = S_e(T1, xi_1) |gamma_1 psi_1(z)| sqrt(1 + 0.0004 xi_1^2)     (xi_1 in percent)
      A    = 1.1 xi_1^-0.5 eta(xi_a)                                      (xi_1 a FRACTION, below)
      T <  a T1:         S_eZ = A a_Z / (1 + (A - 1)(1 - T/(a T1))^1.6)
      a T1 <= T < b T1:  S_eZ = A a_Z
      T >= b T1:         S_eZ = A a_Z / (1 + (A - 1)(T/(b T1) - 1)^1.2)       a = 0.8, b = 1.1

  xi_1 is the building's damping (default 5 %), xi_a = 5 % the object's (eta(xi_a) = 1).
  *Reading of A.* The transcription we follow (docs MODEL.md section 7) writes "xi_k in
  percent" for A. Read literally, A = 1.1 / sqrt(5) = 0.49 at 5 %: below 1, so the resonant
  plateau A a_Z would lie below the floor's own peak acceleration a_Z (S_eZ(0) = a_Z), and
  the denominator of C7.2.8, 1 + (A - 1)(T/(b T1) - 1)^1.2, vanishes at T = 2.76 b T1 and
  turns negative beyond: physically impossible. We take xi_1 as a fraction in A:
  A = 1.1 / sqrt(0.05) = 4.92 at 5 %, consistent with a_p = 5 of C7.2.11. In the term
  sqrt(1 + 0.0004 xi_1^2) xi_1 stays in percent (1.005 at 5 %), the Circolare's convention.
  *Lower bound.* The Circolare keeps S_eZ not below the ground spectrum S_e(T, 5 %) for
  T > T1. We bound it by the ground spectrum at EVERY period, a conservative reading beyond
  the code: near the ground the first-mode term alone gives almost nothing (a_Z -> 0 as
  z -> 0), which cannot be, since a floor moves at least as the ground does.
  :meth:`FloorSpectrum.bound_governs` says where the bound governs.

Seismically isolated buildings: z = 0 (the Circolare's rule for C7.2.11; applied to eq. 4.25
too). The general formulation's linear first mode does not describe an isolated building,
so it is refused for one (use a floor spectrum from an analysis of the building).

:func:`floor_spectrum_for` takes a :class:`~statue2model.hazard.building.Building` and the
floor the object stands on; :func:`floor_spectrum` the bare z, H, T1 (the older form);
:func:`parse_floor` the command line's ``z=2,H=12,T1=0.4,n=3[,structure=masonry][,xi=5][,code=...]``.
A :class:`FloorSpectrum` has ``Se(T)``, ``SDe(T)``, ``xi`` and ``to_dict()`` like
:class:`~statue2model.hazard.code_spectra.ElasticSpectrum`, so it is a target wherever a
ground spectrum is (record matching, the isolator's design). Units: SI (m/s^2, m, s).

Example
-------
>>> from statue2model.hazard.building import Building
>>> from statue2model.hazard.code_spectra import G, ntc2018
>>> site = ntc2018(0.1 * G, 2.5, 0.3, soil="C")           # a_g S = 0.15 g, plateau 0.375 g on 0.16-0.47 s
>>> museum = Building(n=3, H=12.0, T1=0.3)                # masonry, 3 storeys
>>> fl = floor_spectrum_for(site, museum, floor=2)        # the general formulation (default on NTC)
>>> fl.method, round(fl.A, 3), round(fl.a_Z / G, 4)       # 1.1/sqrt(0.05); 0.375 (9/7)(2/3) sqrt(1.01)
('ntc2018', 4.919, 0.323)
>>> [round(float(v) / G, 4) for v in fl.Se([0.0, 0.3, 2.0])]   # a_Z; A a_Z; the ground's 0.375 g 0.469 s / 2 s
[0.323, 1.5891, 0.0879]
>>> fl.bound_intervals()                                  # where the ground spectrum governs (s)
[(0.84, 3.94)]
>>> floor_spectrum_for(site, museum, floor=2, method="ntc2018-framed")
Traceback (most recent call last):
...
statue2model.errors.InputError: floor spectrum: Circolare eq. C7.2.11 ('ntc2018-framed') is for framed buildings only, not masonry: use the general formulation, method 'ntc2018' (C7.2.5-C7.2.10)
>>> fl = floor_spectrum(site, z=2, H=3, T1=0.4, code="ec8")
>>> [round(float(v) / G, 4) for v in fl.Se([0.0, 0.4, 4.0])]   # 1 + 1.5 z/H; 3 (1 + z/H) - 0.5; a_g S
[0.3, 0.675, 0.15]
>>> parse_floor("z=2,H=3,T1=0.4,code=ec8", site).method
'ec8'
"""
from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from ..errors import InputError
from .building import FRAMED, STRUCTURES, Building, building_damping, storeys
from .code_spectra import G, ElasticSpectrum, _periods, damping_correction

METHODS = ("ec8", "ntc2018-framed", "ntc2018")
"""The floor-spectrum methods (module docstring)."""

CLAUSES = {"ec8": "EN 1998-1:2004 4.3.5.2(3), eq. 4.25",
           "ntc2018-framed": "Circolare 2019 (NTC 2018 7.2.3) eq. C7.2.11, Tab. C7.2.II: framed buildings",
           "ntc2018": "Circolare 2019 (NTC 2018 7.2.3) eqs. C7.2.5-C7.2.10: general formulation, first mode"}
"""The clause each method follows."""

NAMES = {"ec8": "EC8 floor spectrum (EN 1998-1 eq. 4.25)",
         "ntc2018-framed": "NTC 2018 floor spectrum for framed buildings (Circolare eq. C7.2.11)",
         "ntc2018": "NTC 2018 floor spectrum, general formulation (Circolare eqs. C7.2.5-C7.2.10)"}
"""How :attr:`FloorSpectrum.text` names each method."""

NTC_FRAMED_TABLE = ((0.5, 0.8, 1.4, 5.0), (1.0, 0.3, 1.2, 4.0), (math.inf, 0.3, 1.0, 2.5))
"""Circolare 2019 Tab. C7.2.II: (T1 bound in s, a, b, a_p); the first row is T1 < 0.5 s, the
second 0.5 s <= T1 <= 1.0 s, the third T1 > 1.0 s."""

GENERAL_A, GENERAL_B = 0.8, 1.1
"""a and b of the general formulation (C7.2.6-C7.2.8)."""

OBJECT_XI = 5.0
"""The object's damping xi_a (percent) the floor spectra are for."""


def ntc_framed_coefficients(T1: float) -> tuple[float, float, float]:
    """(a, b, a_p) of Tab. C7.2.II for a framed building of fundamental period T1 (s).

    >>> ntc_framed_coefficients(0.4), ntc_framed_coefficients(0.5), ntc_framed_coefficients(1.0)
    ((0.8, 1.4, 5.0), (0.3, 1.2, 4.0), (0.3, 1.2, 4.0))
    >>> ntc_framed_coefficients(1.5)
    (0.3, 1.0, 2.5)
    """
    if not (isinstance(T1, (int, float)) and math.isfinite(T1) and T1 > 0):
        raise InputError(f"building period T1 must be a positive finite number of s, got {T1!r}")
    if T1 < 0.5:
        return NTC_FRAMED_TABLE[0][1:]
    if T1 <= 1.0:
        return NTC_FRAMED_TABLE[1][1:]
    return NTC_FRAMED_TABLE[2][1:]


def general_amplification(xi: float = 5.0) -> float:
    """A = 1.1 xi^-0.5 eta(xi_a) of C7.2.10 with the building's damping xi (given in percent)
    used as a FRACTION (module docstring: the literal percent reading gives A < 1) and the
    object's xi_a = 5 % (eta = 1).

    >>> round(general_amplification(5.0), 4), round(general_amplification(2.0), 4)   # 1.1/sqrt(0.05)
    (4.9193, 7.7782)
    """
    xi = building_damping(xi)
    return 1.1 / math.sqrt(xi / 100.0) * damping_correction(OBJECT_XI)


@dataclass(frozen=True)
class FloorSpectrum:
    """The 5 %-damped acceleration spectrum at height ``z`` of a building of height ``H`` (same
    unit; metres when it comes from a Building), ``n`` storeys, period ``T1`` (s), damping
    ``building_xi`` (percent), on the site of ``ground``; ``method`` one of METHODS.
    ``structure`` (one of STRUCTURES, or None when not given), ``floor`` (the storey, when
    known) and ``T1_estimated`` are carried into the description."""

    method: str
    ground: ElasticSpectrum
    z: float
    H: float
    T1: float
    n: int | None = None
    structure: str | None = None
    building_xi: float = 5.0
    isolated: bool = False
    floor: int | None = None
    T1_estimated: bool = False

    def __post_init__(self):
        method = str(self.method).strip().lower()
        if method not in METHODS:
            raise InputError(f"floor spectrum method {self.method!r} is not one of {', '.join(METHODS)}")
        object.__setattr__(self, "method", method)
        if not isinstance(self.ground, ElasticSpectrum):
            raise InputError(f"floor spectrum: the ground spectrum must be an ElasticSpectrum, got {self.ground!r}")
        for name in ("H", "T1"):
            v = getattr(self, name)
            if isinstance(v, bool) or not (isinstance(v, (int, float)) and math.isfinite(v) and v > 0):
                raise InputError(f"floor spectrum: {name} must be a positive finite number, got {v!r}")
            object.__setattr__(self, name, float(v))
        z = self.z
        if isinstance(z, bool) or not (isinstance(z, (int, float)) and math.isfinite(z) and 0 <= z <= self.H):
            raise InputError(f"floor spectrum: z must be between 0 (the ground) and H = {self.H:g} "
                             f"(the top), got {z!r}")
        object.__setattr__(self, "z", float(z))
        if self.n is not None:
            object.__setattr__(self, "n", storeys(self.n))
        if self.structure is not None:
            s = str(self.structure).strip().lower()
            if s not in STRUCTURES:
                raise InputError(f"building structure {self.structure!r} is not one of {', '.join(STRUCTURES)}")
            object.__setattr__(self, "structure", s)
        object.__setattr__(self, "building_xi", building_damping(self.building_xi))
        if not isinstance(self.isolated, (bool, np.bool_)):
            raise InputError(f"floor spectrum: isolated must be True or False, got {self.isolated!r}")
        object.__setattr__(self, "isolated", bool(self.isolated))
        if method == "ntc2018-framed" and self.structure is not None and self.structure not in FRAMED:
            raise InputError(f"floor spectrum: Circolare eq. C7.2.11 ('ntc2018-framed') is for framed buildings "
                             f"only, not {self.structure}: use the general formulation, method 'ntc2018' "
                             f"(C7.2.5-C7.2.10)")
        if method == "ntc2018":
            if self.n is None:
                raise InputError("floor spectrum: the general formulation (method 'ntc2018', Circolare C7.2.5-"
                                 "C7.2.10) needs the building's number of storeys n (e.g. n=3)")
            if self.isolated:
                raise InputError("floor spectrum: the general formulation (method 'ntc2018') assumes a first mode "
                                 "linear with height, which an isolated building does not have: use 'ntc2018-"
                                 "framed' or 'ec8' (z = 0), or a floor spectrum from an analysis of the building")

    # --- the parameters ---------------------------------------------------------------
    @property
    def xi(self) -> float:
        """Damping ratio (percent) of the spectrum: the object's, 5 %."""
        return OBJECT_XI

    @property
    def clause(self) -> str:
        """The clause the method follows."""
        return CLAUSES[self.method]

    @property
    def z_over_H(self) -> float:
        """z/H as the formula uses it: 0 for an isolated building."""
        return 0.0 if self.isolated else self.z / self.H

    @property
    def a_g_S(self) -> float:
        """alpha S = a_g S of the ground spectrum, m/s^2."""
        return self.ground.a_g * self.ground.S

    @property
    def coefficients(self) -> tuple[float, float, float] | None:
        """(a, b, a_p) of Tab. C7.2.II ("ntc2018-framed"), (a, b, A) of the general formulation,
        None for EC8."""
        if self.method == "ntc2018-framed":
            return ntc_framed_coefficients(self.T1)
        if self.method == "ntc2018":
            return GENERAL_A, GENERAL_B, self.A
        return None

    @property
    def gamma_1(self) -> float | None:
        """First-mode participation factor 3n / (2n + 1) of a mode linear with height (general formulation)."""
        return 3.0 * self.n / (2.0 * self.n + 1.0) if self.n is not None else None

    @property
    def A(self) -> float | None:
        """A of C7.2.10 (general formulation), see :func:`general_amplification`."""
        return general_amplification(self.building_xi) if self.method == "ntc2018" else None

    @property
    def a_Z(self) -> float | None:
        """a_Z = S_e(T1, xi_1) |gamma_1 z/H| sqrt(1 + 0.0004 xi_1^2), m/s^2 (general formulation):
        the floor's first-mode peak acceleration."""
        if self.method != "ntc2018":
            return None
        ground_1 = replace(self.ground, eta=damping_correction(self.building_xi), xi=self.building_xi)
        return (float(ground_1.Se(self.T1)) * abs(self.gamma_1 * self.z_over_H)
                * math.sqrt(1.0 + 0.0004 * self.building_xi ** 2))

    # --- the spectrum -----------------------------------------------------------------
    def formula(self, T) -> np.ndarray:
        """The method's expression without its lower bound, m/s^2, for periods T >= 0 s."""
        T = _periods(T)
        r = self.z_over_H
        if self.method == "ec8":
            return self.a_g_S * (3.0 * (1.0 + r) / (1.0 + (1.0 - T / self.T1) ** 2) - 0.5)
        if self.method == "ntc2018-framed":
            a, b, ap = ntc_framed_coefficients(self.T1)
            top = self.a_g_S * (1.0 + r) * ap
            lo = top / (1.0 + (ap - 1.0) * (1.0 - T / (a * self.T1)) ** 2)
            hi = top / (1.0 + (ap - 1.0) * (1.0 - T / (b * self.T1)) ** 2)
            return np.where(T < a * self.T1, lo, np.where(T < b * self.T1, top, hi))
        a, b, A = GENERAL_A * self.T1, GENERAL_B * self.T1, self.A
        top = A * self.a_Z
        lo = top / (1.0 + (A - 1.0) * np.clip(1.0 - T / a, 0.0, None) ** 1.6)
        hi = top / (1.0 + (A - 1.0) * np.clip(T / b - 1.0, 0.0, None) ** 1.2)
        return np.where(T < a, lo, np.where(T < b, top, hi))

    def lower_bound(self, T) -> np.ndarray:
        """What the spectrum may not fall below, m/s^2: a_g S (eq. 4.25, C7.2.11); the ground
        spectrum S_e(T, 5 %) at every period (general formulation; module docstring)."""
        T = _periods(T)
        if self.method == "ntc2018":
            return replace(self.ground, eta=damping_correction(OBJECT_XI), xi=OBJECT_XI).Se(T)
        return np.full(T.shape, self.a_g_S)

    def Se(self, T) -> np.ndarray:
        """Floor pseudo-acceleration, m/s^2, for periods T >= 0 s (5 % damping); same shape as T."""
        return np.maximum(self.formula(T), self.lower_bound(T))

    def SDe(self, T) -> np.ndarray:
        """Floor displacement spectrum Se T^2 / (4 pi^2), m, relative to the floor; same shape as T."""
        T = _periods(T)
        return self.Se(T) * T ** 2 / (4.0 * math.pi ** 2)

    def bound_governs(self, T) -> np.ndarray:
        """True at the periods where the lower bound, not the formula, gives Se.

        For the general formulation the Circolare bounds it only for T > T1; where this is
        True at T <= T1 our reading (bounded at every period) is above the code's."""
        T = _periods(T)
        return self.lower_bound(T) > self.formula(T)

    def bound_intervals(self, T_max: float = 4.0, step: float = 0.01) -> list[tuple[float, float]]:
        """The period ranges (s) in [0, T_max] where :meth:`bound_governs`, on a grid of ``step`` s."""
        grid = np.round(np.arange(0.0, T_max + 0.5 * step, step), 10)
        on = np.concatenate([[False], self.bound_governs(grid), [False]]).astype(int)
        starts, ends = np.flatnonzero(np.diff(on) == 1), np.flatnonzero(np.diff(on) == -1) - 1
        return [(float(grid[i]), float(grid[j])) for i, j in zip(starts, ends)]

    @property
    def pfa(self) -> float:
        """Peak floor acceleration Se(0), m/s^2."""
        return float(self.Se(0.0))

    @property
    def pga(self) -> float:
        """Peak acceleration of the input this target stands for (records matched to it have it), m/s^2:
        the peak floor acceleration Se(0), as a ground spectrum's is a_g S."""
        return self.pfa

    # --- description ------------------------------------------------------------------
    @property
    def text(self) -> str:
        """One line: the method and its clause, the floor, the building, the peak floor acceleration."""
        where = (f"floor {self.floor} of {self.n}" if self.floor is not None and self.n is not None
                 else f"z {self.z:g} of H {self.H:g}" + (f", {self.n} storeys" if self.n is not None else ""))
        where += f" (z/H {self.z / self.H:.3f}" + (", taken as 0: isolated building)" if self.isolated else ")")
        building = ", ".join(x for x in (self.structure, "isolated" if self.isolated else None) if x)
        period = f"T1 {self.T1:.3f} s" + (" (C_t H^3/4)" if self.T1_estimated else "")
        damping = f", xi_1 {self.building_xi:g} %" if self.method == "ntc2018" else ""
        return (f"{NAMES[self.method]}, {where}, " + (f"{building}, " if building else "")
                + f"{period}{damping}: peak floor acceleration {self.pfa / G:.3f} g")

    def to_dict(self) -> dict:
        """JSON-ready: every parameter, the method, its clause, the derived coefficients."""
        d = {"kind": "floor", "method": self.method, "clause": self.clause, "text": self.text, "xi": self.xi,
             "z": self.z, "H": self.H, "z_over_H": self.z / self.H, "z_over_H_used": self.z_over_H,
             "n": self.n, "floor": self.floor, "T1_s": self.T1, "T1_estimated": self.T1_estimated,
             "structure": self.structure, "building_xi_percent": self.building_xi, "isolated": self.isolated,
             "a_g_S_m_s2": self.a_g_S, "pfa_m_s2": self.pfa}
        if self.method == "ntc2018-framed":
            a, b, ap = ntc_framed_coefficients(self.T1)
            d.update(a=a, b=b, a_p=ap, lower_bound="a_g S")
        elif self.method == "ntc2018":
            d.update(a=GENERAL_A, b=GENERAL_B, A=self.A, A_if_xi_read_in_percent=1.1 / math.sqrt(self.building_xi),
                     A_reading="xi_1 as a fraction in A (the literal percent reading gives A < 1: impossible)",
                     gamma_1=self.gamma_1, psi_1=self.z_over_H, a_Z_m_s2=self.a_Z,
                     lower_bound="the ground spectrum S_e(T, 5 %) at every period (the Circolare: for T > T1)")
        else:
            d.update(lower_bound="a_g S")
        d["lower_bound_governs_s"] = [list(iv) for iv in self.bound_intervals()]
        d["ground"] = self.ground.to_dict()
        return d


def default_method(ground: ElasticSpectrum) -> str:
    """"ntc2018" (the general formulation) on an NTC ground spectrum, "ec8" on an EC8 one."""
    return "ntc2018" if ground.code == "NTC2018" else "ec8"


def _method(ground, method) -> str:
    if not isinstance(ground, ElasticSpectrum):
        raise InputError(f"floor spectrum: the ground spectrum must be an ElasticSpectrum, got {ground!r}")
    return default_method(ground) if method is None else str(method).strip().lower()


def floor_spectrum_for(ground: ElasticSpectrum, building: Building, floor: int,
                       method: str | None = None) -> FloorSpectrum | ElasticSpectrum:
    """The spectrum on floor ``floor`` (0 = ground floor) of ``building`` on the site of ``ground``;
    ``method`` one of METHODS (default: :func:`default_method`). On floor 0 of a building that
    is not isolated the object stands on the ground: the result is ``ground`` itself (the
    formulas at z = 0 would still amplify it around T1, a resonance that does not reach the
    foundation). An isolated building's floors all take z = 0 (Circolare, C7.2.11)."""
    if not isinstance(building, Building):
        raise InputError(f"floor spectrum: building must be a Building, got {building!r}")
    fl = FloorSpectrum(_method(ground, method), ground, building.z(floor), building.H, building.period,
                       building.n, building.structure, building.xi, building.isolated, int(floor),
                       building.period_estimated)
    if fl.z == 0.0 and not building.isolated:
        return ground
    return fl


def floor_spectrum(ground: ElasticSpectrum, z: float, H: float, T1: float, code: str | None = None,
                   n: int | None = None, structure: str | None = None, xi: float = 5.0,
                   isolated: bool = False) -> FloorSpectrum:
    """The floor spectrum at height z (same unit as H: storeys or metres) of a building of
    fundamental period T1 (s) on the site of ``ground``; ``code`` one of METHODS (default:
    :func:`default_method`; "ntc2018" is the general formulation, which needs ``n``);
    ``structure`` one of STRUCTURES (C7.2.11 refuses one that is not a frame), ``xi`` the
    building's damping in percent."""
    return FloorSpectrum(_method(ground, code), ground, _num("z", z), _num("H", H), _num("T1", T1), n, structure,
                         xi, isolated)


def _num(key: str, value) -> float:
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise InputError(f"floor spectrum: {key} must be a number, got {value!r}") from None
    if not math.isfinite(v):
        raise InputError(f"floor spectrum: {key} must be finite, got {value!r}")
    return v


_FLOOR_KEYS = ("z", "h", "t1", "n", "structure", "xi", "code")


def parse_floor(text: str, ground: ElasticSpectrum) -> FloorSpectrum:
    """``z=2,H=12,T1=0.4[,n=3][,structure=masonry][,xi=5][,code=ec8|ntc2018|ntc2018-framed]`` on
    the site of ``ground`` (z and H in storeys or metres, T1 in s, xi the building's damping in
    percent; keys case-insensitive). code=ntc2018 is the general formulation (the default on an
    NTC spectrum), which needs n.

    >>> from statue2model.hazard.code_spectra import ntc2018
    >>> parse_floor("z=2,H=3,T1=0.4", ntc2018(0.1 * G, 2.5, 0.3, soil="C"))
    Traceback (most recent call last):
    ...
    statue2model.errors.InputError: floor 'z=2,H=3,T1=0.4': the general formulation (code=ntc2018, the default on an NTC spectrum) needs the number of storeys: add n (e.g. z=2,H=3,T1=0.4,n=3)
    """
    values: dict[str, str] = {}
    for item in str(text).split(","):
        key, eq, value = item.partition("=")
        key, value = key.strip().lower(), value.strip()
        if not eq or not key or not value:
            raise InputError(f"floor: {item.strip()!r} is not of the form key=value (e.g. z=2,H=3,T1=0.4,n=3)")
        if key not in _FLOOR_KEYS:
            raise InputError(f"floor: unknown key {key!r} (use z, H, T1, n, structure, xi, code)")
        if key in values:
            raise InputError(f"floor: key {key!r} is given twice")
        values[key] = value
    missing = [k for k in ("z", "h", "t1") if k not in values]
    if missing:
        raise InputError(f"floor {text!r} lacks {', '.join(k if k == 'z' else k.upper() for k in missing)}")
    method = _method(ground, values.get("code"))
    if method == "ntc2018" and "n" not in values:
        raise InputError(f"floor {text!r}: the general formulation (code=ntc2018, the default on an NTC spectrum) "
                         f"needs the number of storeys: add n (e.g. {text.strip()},n=3)")
    n = None
    if "n" in values:
        try:
            n = int(values["n"])
        except ValueError:
            raise InputError(f"floor: n must be a whole number of storeys, got {values['n']!r}") from None
    xi = values.get("xi", "5")
    try:
        xi = float(xi)
    except ValueError:
        raise InputError(f"floor: xi must be the building's damping in percent, got {xi!r}") from None
    return floor_spectrum(ground, values["z"], values["h"], values["t1"], method, n, values.get("structure"), xi)
