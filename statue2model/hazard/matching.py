"""Spectrum-compatible accelerogram sets, to the codes' rules (NTC 2018 §3.2.3.6 and §7.3.5,
EC8 EN 1998-1 §3.2.3.1.2 and §4.3.3.4.3; MODEL.md section 7).

:func:`match_set` makes N artificial records (default 7: with at least 7 the codes take the
MEAN of the effects) whose 5 %-damped pseudo-acceleration spectra match a target: a code
spectrum (:class:`~statue2model.hazard.code_spectra.ElasticSpectrum`) or a floor spectrum
(:mod:`statue2model.hazard.floor`); anything with ``Se(T)`` in m/s^2 (and ``to_dict()``)
will do. The method (SIMQKE, Gasparini & Vanmarcke 1976, as most codes' "artificial
accelerograms"): a record is an envelope times a stationary signal,

1. record i's stationary signal starts as Gaussian white noise
   (``numpy.random.default_rng(seed_i)``, seed_i = seed + i), high-passed (below);
   the envelope rises as (t / t1)^2 to t1 = 0.1 D, is 1 to t2 = 0.6 D (the
   pseudo-stationary part: 12.5 s of a 25 s record; the codes ask for at least 10 s)
   and decays exponentially to exactly 0 at D;
2. each iteration computes the spectra of all records
   (:func:`statue2model.hazard.response_spectra.psa`, exact for piecewise-linear input),
   multiplies the STATIONARY signal's Fourier amplitudes by the ratio target / computed,
   interpolated in log frequency between the matching periods (phases kept), and
   re-applies the envelope and the baseline (below): every record starts and ends at rest
   (a(0) = a(D) = 0, v(D) = u(D) = 0);
3. it stops when every record is within ``record_tol`` (5 %) of the target at every
   matching period, or after ``iterations``.

High-pass: the correction and the seed noise are cut below the frequency 1 / T_hi (T_hi the
band's upper end), with a cosine taper to nothing at 1 / (2 T_hi). Content at periods the
check does not cover adds displacement, not spectral fit: without the cut the EC8 ground C set
of 7 records of 25 s matched to 4.8 s had PGD 1.7-8 times the code's d_g (mean 4.3), cut at
1 / (1.5 T_hi) 1.4-3.1 (mean 2.1), cut at 1 / T_hi 1.0-2.0 (mean 1.5), the fit unchanged
(min mean/target 0.96; a cut at 1 / (0.8 T_hi) loses the band's end: 0.72-0.79 there).

Baseline: the acceleration minus env(t) (c0 + c1 t), with c0, c1 such that the velocity and
the displacement (trapezoidal integration) end at zero; weighted by the envelope, the
correction keeps a(0) = a(D) = 0.

The set is then checked as the codes ask (:meth:`RecordSet.rules`, every rule with its value,
limit and clause): the count (>= 7), each record's duration (>= 25 s) and pseudo-stationary
part (>= 10 s), the band (0.15 s to the largest of 2 s, 2 T1 of the building and 1.2 T_is of
an isolator: :func:`design_band`), the mean spectrum not more than 10 % below the target at
any period of the band (artificial records have NO upper bound: the -10 % / +30 % window is
NTC's rule for recorded motions, ``TOLERANCE_RECORDED``) and the mean PGA (the spectra's
T = 0 value) not below the target's Se(0) (EC8 §3.2.3.1.2(4)b; NTC has no such rule, and it
is checked on NTC sets too: the conservative reading). A set whose mean PGA falls short is
scaled up to it (``pga_scale``; no upper bound is broken). The check grid is twice as dense
as the matching one. The band may reach a fifth of the duration (5 s for 25 s records):
longer periods lose too much to the baseline correction, so :func:`duration_for_band` gives
the duration a band needs.

Peak control (floor spectra, :func:`controls_peak`; ``peak_control``). A record's PGA is its
spectrum at T = 0, which the band (from 0.15 s) does not check. Matched by shape alone, 7 records
of a floor spectrum had a mean PGA of 1.28 (the Venere Landolina's floor, Circolare C7.2.5-C7.2.10,
A = 4.92) to 1.77 (NTC framed, floor 3 of 4, T1 0.6 s) times its Se(0), the peak floor acceleration:
the resonant plateau (up to 5 x Se(0)) carries that much in-band content, and cutting every period
below 0.1 s still left 1.19-1.69 (so no high-frequency step can fix it). On a floor the matching
therefore clips each record's stationary signal, after each correction that left the set's mean peak
above Se(0), at Se(0) times the record's first-pass peak over the set's mean first-pass peak (the
records keep their own spread); the next correction restores the spectrum (alternating projections).
The set's mean PGA then ends within Se(0) .. (1 + PGA_TOL) Se(0) (``pga_cap``; the "mean PGA" rule
checks both ends) with the mean spectrum still within the band's rule (Venere: 1.000 x Se(0), mean /
target 0.955-1.044). The ground sets are not controlled (mean PGA 1.13-1.18 x a_g S, cut to about 1.0
by halving their content above 10 Hz: not changed here, see docs/records.md).

Realism (:meth:`RecordSet.realism`): each record's PGA, PGV, PGD, Arias intensity, D5-95 and
start/end values (:mod:`statue2model.hazard.record_measures`), and the set's mean PGD against
the design ground displacement d_g = 0.025 a_g S T_C T_D (EC8 §3.2.2.4; of the ground spectrum
under a floor spectrum: a floor moves with the ground at long periods). A set whose mean PGD
exceeds the spectrum's own long-period displacement (SDe at T_D, 2.5 d_g for F0 = 2.5: no
5 %-damped oscillator of the target moves that much) is physically implausible: ``plausible``
false and a warning naming its PGD.

A set on disk is a folder with its ``set.json`` (:func:`set_files` writes its
``files``, ``file_checks`` and ``units``; ``statue2model records`` writes it last, after
its records) and is read by :func:`read_record_set`: exactly the files set.json names,
in its order, each checked against the length and SHA-256 recorded when it was written;
a folder without set.json, a file missing or changed since, is refused with one line,
never filled in from whatever else lies in the folder.

Example
-------
>>> from statue2model.hazard.code_spectra import parse_spectrum
>>> target = parse_spectrum("ntc2018:ag=0.1g,F0=2.5,Tc=0.3,soil=C")
>>> s = match_set(target, n=7, seed=1)                    # 25 s records, 0.15-2 s
>>> s.met, len(s.records), s.seeds[:2], s.records[0].duration
(True, 7, (1, 2), 25.0)
>>> [(r["rule"], r["ok"]) for r in s.rules()][:3]
[('records', True), ('duration', True), ('stationary part', True)]
>>> s.check()["tolerance"], s.window
([-0.1, None], 'artificial records: mean >= 90 % of the target, no upper bound')
>>> float(s.records[0].samples[0]), float(s.records[0].samples[-1])      # at rest at both ends
(0.0, 0.0)
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property

import numpy as np

from ..errors import InputError
from .motions import GroundMotion, record
from .response_spectra import POINTS_PER_PERIOD, psa

TOLERANCE_ARTIFICIAL = (-0.10, None)
"""Artificial records (NTC 2018 §3.2.3.6, EC8 §3.2.3.1.2(4)c): the mean spectrum no more than
10 % below the target anywhere in the band; no upper bound."""
TOLERANCE_RECORDED = (-0.10, 0.30)
"""Recorded motions (NTC 2018 §3.2.3.6): the mean within -10 % / +30 % of the target."""
TOLERANCE = TOLERANCE_ARTIFICIAL
"""The window :func:`match_set` checks by default (its records are artificial)."""
N_MIN = 7
"""Records a design set needs for the MEAN of the effects (NTC §7.3.5, EC8 §4.3.3.4.3)."""
DURATION_MIN = 25.0
"""s, each record (NTC 2018 §3.2.3.6)."""
STATIONARY_MIN = 10.0
"""s, the pseudo-stationary part (NTC 2018 §3.2.3.6, EC8 §3.2.3.1.2(4)a)."""
BAND_START, BAND_END_MIN = 0.15, 2.0
"""s: the band starts at 0.15 s and reaches at least 2 s (NTC 2018 §3.2.3.6)."""
DEFAULT_BAND = (BAND_START, BAND_END_MIN)
"""Periods (s) the default check covers: the codes' band for a structure of T1 <= 1 s."""
N_MATCH = 60
"""Matching periods (log-spaced from half the band's start to 1.5 times its end)."""
HIGH_PASS = 1.0
"""The seed noise and the corrections are cut below 1 / (HIGH_PASS T_hi) Hz (module docstring)."""
PGA_TOL = 0.05
"""With peak control (floor spectra, :func:`controls_peak`) the set's mean PGA lies in Se(0) .. (1 +
PGA_TOL) Se(0) (the rule "mean PGA" checks both ends)."""


def controls_peak(target) -> bool:
    """True when :func:`match_set` holds the set's mean PGA at the target's Se(0) by default: a floor
    spectrum (:class:`~statue2model.hazard.floor.FloorSpectrum`), whose resonant plateau (A a_Z, up to
    about 5 x the peak floor acceleration) lifts the PGA of records matched to it by shape alone to
    1.3-1.8 x Se(0) (module docstring, "Peak control")."""
    from .floor import FloorSpectrum

    return isinstance(target, FloorSpectrum)


def band_for_period(T1: float) -> tuple[float, float]:
    """EC8 §3.2.3.1.2 (4)c: the band 0.2 T1 .. 2 T1 of a structure of period T1 (s).

    >>> band_for_period(0.5)
    (0.1, 1.0)
    """
    _period("the structure's period T1", T1)
    return 0.2 * T1, 2.0 * T1


def _period(name: str, T) -> float:
    if isinstance(T, bool) or not (isinstance(T, (int, float)) and math.isfinite(T) and T > 0):
        raise InputError(f"{name} must be a positive number of s, got {T!r}")
    return float(T)


def design_band(T1: float | None = None, T_is: float | None = None,
                code: str | None = None) -> tuple[tuple[float, float], str]:
    """The band a design set is checked over: 0.15 s (NTC 2018 §3.2.3.6) to the largest of 2 s,
    2 T1 (a building's period, when the object stands in one) and the isolator's end (an isolator's
    period T_is, when one is designed): 1.2 T_is on an NTC site (§3.2.3.6, isolated structures),
    2 T_is on an EC8 site (EN 1998-1 §3.2.3.1.2(4)c, 0.2 T1-2 T1 with T1 = T_is: section 10 gives
    no other band for isolated structures); ``code`` "EC8..." or anything else (NTC's rule).
    Returns the band and the reason in words.

    >>> design_band()
    ((0.15, 2.0), '0.15 s to 2 s')
    >>> design_band(T1=0.6, T_is=3.99)
    ((0.15, 4.788), '0.15 s to max(2 s, 2 T1 = 1.2 s, 1.2 T_is = 4.788 s)')
    >>> design_band(T_is=3.0, code="EC8-1")[0]
    (0.15, 6.0)
    """
    parts, hi = ["2 s"], BAND_END_MIN
    if T1 is not None:
        v = 2.0 * _period("the building's period T1", T1)
        parts.append(f"2 T1 = {v:.4g} s")
        hi = max(hi, v)
    if T_is is not None:
        ec8 = str(code or "").upper().startswith("EC8")
        k = 2.0 if ec8 else 1.2
        v = k * _period("the isolator's period T_is", T_is)
        parts.append(f"{k:g} T_is = {v:.4g} s" + (" (EC8 3.2.3.1.2(4)c with T1 = T_is)" if ec8 else ""))
        hi = max(hi, v)
    why = f"{BAND_START:g} s to " + (parts[0] if len(parts) == 1 else f"max({', '.join(parts)})")
    return (BAND_START, round(hi, 6)), why


def duration_for_band(band: tuple[float, float], minimum: float = DURATION_MIN) -> float:
    """The record duration (s) a band needs: at least ``minimum`` and 5 times the band's end
    (rounded up to a whole second).

    >>> duration_for_band((0.15, 4.788)), duration_for_band((0.15, 6.0))
    (25.0, 30.0)
    """
    return float(max(minimum, math.ceil(5.0 * float(band[1]) - 1e-9)))


def envelope(t: np.ndarray, duration: float) -> np.ndarray:
    """Amplitude envelope on [0, duration]: (t / t1)^2 to t1 = 0.1 D, 1 to t2 = 0.6 D, then an
    exponential decay (to 5 % of the strong phase if it went on) shifted to reach exactly 0 at D."""
    t1, t2 = 0.1 * duration, 0.6 * duration
    decay = math.log(20.0) / (duration - t2)
    end = math.exp(-decay * (duration - t2))
    tail = np.maximum((np.exp(-decay * (t - t2)) - end) / (1.0 - end), 0.0)
    return np.where(t < t1, (t / t1) ** 2, np.where(t < t2, 1.0, tail))


def stationary_part(duration: float) -> float:
    """s, the envelope's constant part: 0.5 D."""
    return 0.5 * float(duration)


def baseline_correct(acc: np.ndarray, dt: float, env: np.ndarray) -> np.ndarray:
    """acc - env (c0 + c1 t) with v(end) = u(end) = 0 (trapezoidal rule); acc (n,) or (k, n)."""
    n = acc.shape[-1]
    t = np.arange(n) * dt

    def ends(x):   # (v(T), u(T)) of the trapezoidal double integration, along the last axis
        v = np.concatenate([np.zeros(x.shape[:-1] + (1,)), np.cumsum(0.5 * dt * (x[..., 1:] + x[..., :-1]), axis=-1)],
                           axis=-1)
        u_end = np.sum(0.5 * dt * (v[..., 1:] + v[..., :-1]), axis=-1)
        return v[..., -1], u_end

    b0, b1 = env, env * t
    A = np.array([ends(b0), ends(b1)]).T                  # columns: the two baselines
    rhs = np.stack(ends(acc), axis=-1)                     # (..., 2)
    c = np.linalg.solve(A, rhs[..., None])[..., 0] if rhs.ndim > 1 else np.linalg.solve(A, rhs)
    return acc - c[..., :1] * b0 - c[..., 1:2] * b1 if acc.ndim > 1 else acc - c[0] * b0 - c[1] * b1


def high_pass(f: np.ndarray, T_hi: float) -> np.ndarray:
    """Gain 1 at frequencies f >= 1 / (HIGH_PASS T_hi) Hz, a cosine taper to 0 at half that."""
    fc = 1.0 / (HIGH_PASS * T_hi)
    x = np.clip((f - 0.5 * fc) / (0.5 * fc), 0.0, 1.0)
    return 0.5 - 0.5 * np.cos(np.pi * x)


def _window_text(tol) -> str:
    lo, hi = tol
    if hi is None:
        return f"artificial records: mean >= {100 * (1 + lo):.0f} % of the target, no upper bound"
    return (f"recorded motions: mean within {100 * (1 + lo):.0f}-{100 * (1 + hi):.0f} % of the target"
            if tuple(tol) == TOLERANCE_RECORDED else
            f"mean within {100 * (1 + lo):.0f}-{100 * (1 + hi):.0f} % of the target (a window of your own)")


@dataclass(frozen=True, eq=False)
class RecordSet:
    """A spectrum-compatible set. records: the accelerograms (m/s^2, every dt s);
    periods: (n_T,) the check grid, s; spectra: (n_records, n_T) their PSA, m/s^2;
    target: (n_T,) the target there; band (s) and tolerance (fractions below, above or None)
    of the check; required_band: the band the code asks for (:func:`design_band`) and
    band_reason its reason; stationary_s: each record's pseudo-stationary part, s;
    pga_scale: the factor applied so the mean PGA reaches Se(0) (1: none); d_g: the
    target's design ground displacement, m (None if it has none); pga_cap: the largest mean
    PGA / Se(0) the matching held the set to (1 + PGA_TOL with peak control; None: not held)."""

    records: tuple[GroundMotion, ...]
    seeds: tuple[int, ...]
    periods: np.ndarray
    spectra: np.ndarray
    target: np.ndarray
    band: tuple[float, float]
    tolerance: tuple
    xi: float
    iterations: int
    target_info: dict
    target_pga: float = float("nan")
    required_band: tuple[float, float] = DEFAULT_BAND
    band_reason: str = "0.15 s to 2 s"
    stationary_s: float = float("nan")
    pga_scale: float = 1.0
    d_g: float | None = None
    sd_plateau: float | None = None
    kind: str = "artificial"
    pga_cap: float | None = None

    @property
    def mean(self) -> np.ndarray:
        """(n_T,) the set's mean spectrum, m/s^2."""
        return self.spectra.mean(axis=0)

    @property
    def in_band(self) -> np.ndarray:
        lo, hi = self.band
        return (self.periods >= lo * (1 - 1e-9)) & (self.periods <= hi * (1 + 1e-9))

    @property
    def window(self) -> str:
        """The tolerance window in words, named for what it is (artificial vs recorded)."""
        return _window_text(self.tolerance)

    def check(self) -> dict:
        """The tolerance check over the band: min and max of mean / target and their periods;
        ``met``: every rule of :meth:`rules` holds; ``fit_met``: the tolerance alone."""
        T = self.periods[self.in_band]
        ratio = self.mean[self.in_band] / self.target[self.in_band]
        i, j = int(np.argmin(ratio)), int(np.argmax(ratio))
        lo_tol, hi_tol = self.tolerance
        lo = 1 + lo_tol
        over = (ratio[j] - (1 + hi_tol)) / hi_tol if hi_tol is not None else -math.inf
        worst = i if (lo - ratio[i]) / (-lo_tol) >= over else j
        fit = bool(ratio[i] >= lo and (hi_tol is None or ratio[j] <= 1 + hi_tol))
        return {"met": all(r["ok"] for r in self.rules()), "fit_met": fit,
                "band_s": list(self.band), "tolerance": [lo_tol, hi_tol], "window": self.window,
                "min_ratio": float(ratio[i]), "period_of_min_s": float(T[i]),
                "max_ratio": float(ratio[j]), "period_of_max_s": float(T[j]),
                "worst_ratio": float(ratio[worst]), "period_of_worst_s": float(T[worst]),
                "mean_pga_over_target_pga": float(np.mean([m.pga for m in self.records]) / self.target_pga)}

    @property
    def met(self) -> bool:
        return self.check()["met"]

    def rules(self) -> list[dict]:
        """Every rule of the codes for a design set, each {"rule", "clause", "required", "value", "ok"}."""
        T = self.periods[self.in_band]
        ratio = self.mean[self.in_band] / self.target[self.in_band]
        lo_tol, hi_tol = self.tolerance
        durations = [m.duration for m in self.records]
        pga_ratio = float(np.mean([m.pga for m in self.records]) / self.target_pga)
        rb = self.required_band
        below = float(ratio.min())
        out = [
            {"rule": "records", "clause": "NTC 2018 7.3.5, EC8 4.3.3.4.3 (the mean of the effects)",
             "required": f">= {N_MIN}", "value": len(self.records), "ok": len(self.records) >= N_MIN},
            {"rule": "duration", "clause": "NTC 2018 3.2.3.6", "required": f">= {DURATION_MIN:g} s each",
             "value": f"{min(durations):g} s" + ("" if min(durations) == max(durations) else f"-{max(durations):g} s"),
             "ok": min(durations) >= DURATION_MIN - 1e-9},
            {"rule": "stationary part", "clause": "NTC 2018 3.2.3.6, EC8 3.2.3.1.2(4)a",
             "required": f">= {STATIONARY_MIN:g} s", "value": f"{self.stationary_s:g} s",
             "ok": bool(self.stationary_s >= STATIONARY_MIN - 1e-9)},
            {"rule": "band", "clause": "NTC 2018 3.2.3.6 (" + self.band_reason + ")",
             "required": f"{rb[0]:g}-{rb[1]:.4g} s", "value": f"{self.band[0]:g}-{self.band[1]:.4g} s",
             "ok": bool(self.band[0] <= rb[0] * (1 + 1e-9) and self.band[1] >= rb[1] * (1 - 1e-9))},
            {"rule": "mean spectrum not below the target", "clause": "NTC 2018 3.2.3.6, EC8 3.2.3.1.2(4)c",
             "required": f">= {1 + lo_tol:.2f} x target over the band ({self.window})",
             "value": f"{below:.3f} at {float(T[int(np.argmin(ratio))]):.3g} s", "ok": bool(below >= 1 + lo_tol)},
            {"rule": "mean PGA", "clause": "EC8 3.2.3.1.2(4)b (checked on NTC sets too)"
             + ("; at most (1 + PGA_TOL) Se(0): peak control of a floor set" if self.pga_cap is not None else ""),
             "required": ">= Se(0) = a_g S (x the floor's amplification on a floor)"
             + (f" and <= {self.pga_cap:.2f} x Se(0)" if self.pga_cap is not None else ""),
             "value": f"{pga_ratio:.3f} x Se(0)" + (f" (set scaled x{self.pga_scale:.3f} to reach it)"
                                                     if self.pga_scale > 1 else ""),
             "ok": bool(pga_ratio >= 1 - 1e-9 and (self.pga_cap is None or pga_ratio <= self.pga_cap + 1e-9))}]
        if hi_tol is not None:
            above = float(ratio.max())
            out.append({"rule": "mean spectrum not above the target", "clause": "NTC 2018 3.2.3.6 (recorded motions)",
                        "required": f"<= {1 + hi_tol:.2f} x target over the band",
                        "value": f"{above:.3f} at {float(T[int(np.argmax(ratio))]):.3g} s",
                        "ok": bool(above <= 1 + hi_tol)})
        return out

    @cached_property
    def _measures(self) -> tuple:
        from .record_measures import record_measures

        return tuple(record_measures(m) for m in self.records)

    def measures(self) -> list[dict]:
        """Each record's realism figures (:func:`statue2model.hazard.record_measures.record_measures`),
        computed once per set (the records are immutable); fresh dicts each call."""
        return [dict(m) for m in self._measures]

    def realism(self, measures: list[dict] | None = None) -> dict:
        """The set's PGD against d_g (module docstring): mean and max PGD, their ratio to d_g, the
        limit (the target's long-period spectral displacement), ``plausible`` and a ``warning``."""
        ms = self.measures() if measures is None else measures
        pgd = np.array([m["pgd_m"] for m in ms])
        pgv = np.array([m["pgv_m_s"] for m in ms])
        out = {"mean_pgd_m": float(pgd.mean()), "max_pgd_m": float(pgd.max()), "mean_pgv_m_s": float(pgv.mean()),
               "max_pgv_m_s": float(pgv.max()), "d_g_m": self.d_g, "d_g_clause": "EC8 3.2.2.4 / NTC 2018 3.2.3.3: "
               "d_g = 0.025 a_g S T_C T_D of the ground spectrum",
               "limit_m": self.sd_plateau, "mean_pgd_over_d_g": None, "plausible": True, "warning": None}
        if self.d_g:
            out["mean_pgd_over_d_g"] = float(pgd.mean() / self.d_g)
            limit = self.sd_plateau if self.sd_plateau else 2.5 * self.d_g
            out["limit_m"] = float(limit)
            if pgd.mean() > limit:
                out["plausible"] = False
                out["warning"] = (f"the records' mean PGD {pgd.mean():.3f} m is {pgd.mean() / self.d_g:.1f} x the "
                                  f"design ground displacement d_g = {self.d_g:.3f} m and above the spectrum's own "
                                  f"long-period displacement {limit:.3f} m: physically implausible (long-period content "
                                  f"the site's hazard does not have); their displacement demand on an isolator is "
                                  f"overstated")
        return out

    def to_dict(self) -> dict:
        """JSON-ready: the target, the seeds, the rules, the check, each record's realism figures."""
        ms = self.measures()
        per = []
        for s, m, sp, me in zip(self.seeds, self.records, self.spectra, ms):
            r = sp[self.in_band] / self.target[self.in_band]
            per.append({"seed": int(s), "n_samples": int(len(m.samples)), "dt_s": m.dt, "duration_s": m.duration,
                        "min_ratio": float(r.min()), "max_ratio": float(r.max()), **me})
        return {"target": self.target_info, "kind": self.kind, "n_records": len(self.records),
                "seeds": [int(s) for s in self.seeds], "damping_ratio": self.xi, "iterations": self.iterations,
                "method": "SIMQKE: high-passed Gaussian noise under an envelope, its Fourier amplitudes corrected by "
                          "target/computed spectral ratios, the envelope and an envelope-weighted linear baseline "
                          "re-applied each iteration (records at rest at both ends)",
                "duration_s": max(m.duration for m in self.records), "stationary_s": self.stationary_s,
                "required_band_s": list(self.required_band), "band_reason": self.band_reason,
                "pga_scale": self.pga_scale, "pga_cap": self.pga_cap, "rules": self.rules(), "check": self.check(),
                "realism": self.realism(ms), "mean_pga_m_s2": float(np.mean([m.pga for m in self.records])),
                "records": per, "periods_s": self.periods.tolist(), "target_m_s2": self.target.tolist(),
                "mean_m_s2": self.mean.tolist()}


def target_values(target, T: np.ndarray, where: str = "over the matching periods") -> np.ndarray:
    """``target.Se(T)`` (m/s^2), refused in one line unless it is positive and finite ``where``."""
    if not callable(getattr(target, "Se", None)):
        raise InputError(f"the target spectrum must have an Se(T) method, got {type(target).__name__}")
    v = np.asarray(target.Se(T), dtype=float)
    if v.shape != T.shape or not np.all(np.isfinite(v)) or np.any(v <= 0):
        raise InputError(f"the target spectrum must be positive and finite {where}")
    return v


def pga_scale(peaks, target_pga: float) -> float:
    """The factor that lifts a set whose records peak at ``peaks`` (m/s^2) to a mean PGA of at
    least ``target_pga`` (EC8 3.2.3.1.2(4)b: the mean at T = 0 not below Se(0)); 1 if it is there."""
    scale = target_pga / float(np.mean(peaks))
    return scale * (1 + 1e-12) if scale > 1 else 1.0


def target_facts(target) -> tuple[dict, float | None, float | None]:
    """(``target.to_dict()``, the ground's d_g in m, the ground's SDe at T_D in m) of a target
    spectrum: the ground is the target itself or a floor spectrum's ``ground`` (None: not a code
    ground spectrum)."""
    from .record_measures import design_ground_displacement

    info = target.to_dict() if callable(getattr(target, "to_dict", None)) else {"kind": type(target).__name__}
    ground = getattr(target, "ground", None) or target
    T_D = getattr(ground, "T_D", None)
    sd = (None if T_D is None or not callable(getattr(ground, "Se", None)) else
          float(ground.Se(np.array([float(T_D)]))[0]) * float(T_D) ** 2 / (4 * math.pi ** 2))
    return info, design_ground_displacement(ground), sd


def match_set(target, n: int = N_MIN, seed: int = 1, duration: float = DURATION_MIN, dt: float = 0.01,
              band: tuple[float, float] = DEFAULT_BAND, tolerance: tuple = TOLERANCE,
              iterations: int = 20, record_tol: float = 0.05, required_band: tuple[float, float] | None = None,
              band_reason: str | None = None, peak_control: bool | None = None) -> RecordSet:
    """N records of ``duration`` s every ``dt`` s matched to ``target`` (see the module
    docstring) and checked over ``band`` against ``required_band`` (default: ``band`` itself)
    within ``tolerance`` (fractions (below, above or None)). Damping: the target's ``xi``
    (percent) if it has one, else 5 %. Reproducible: record i depends only on (target,
    seed + i, duration, dt, band, iterations, peak control).

    ``peak_control`` (None: on for a floor spectrum, :func:`controls_peak`): each iteration clips
    record i's stationary signal at Se(0) x its first-pass peak / the set's mean first-pass peak, so
    the set's mean PGA ends within ``PGA_TOL`` above Se(0) (module docstring, "Peak control")."""
    if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or not 1 <= n <= 100:
        raise InputError(f"number of records must be an integer from 1 to 100, got {n!r}")
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
        raise InputError(f"seed must be a non-negative integer, got {seed!r}")
    for name, v in (("duration", duration), ("dt", dt)):
        if isinstance(v, bool) or not (isinstance(v, (int, float)) and math.isfinite(v) and v > 0):
            raise InputError(f"record set: {name} must be a positive number of s, got {v!r}")
    lo, hi = check_band(band, dt)
    if hi > duration / 5 * (1 + 1e-9):   # longer periods lose too much to the baseline correction
        raise InputError(f"record set: a {duration:g} s record cannot be matched up to {hi:g} s: use a "
                         f"duration of at least {5 * hi:g} s or a band ending at {duration / 5:g} s or less")
    tol = check_tolerance(tolerance)
    rb = (lo, hi) if required_band is None else tuple(float(x) for x in required_band)
    from ..compute import budget

    head = f"a set of {n} records of {duration:g} s at dt {dt:g} s"
    fix = "use fewer records, a shorter duration or a coarser dt"
    budget.check_history(duration, dt, 0, what="each record", head=head, fix=fix)
    xi = float(getattr(target, "xi", 5.0)) / 100.0
    control = controls_peak(target) if peak_control is None else bool(peak_control)
    T_match = np.geomspace(max(0.5 * lo, 4 * dt), min(1.5 * hi, duration / 2), N_MATCH)
    T_check = np.geomspace(lo, hi, 2 * N_MATCH)
    npts = int(round(duration / dt)) + 1
    nfft = 1 << int(math.ceil(math.log2(2 * npts)))
    # the peak memory and the time, before anything is allocated (compute/budget.py)
    ks, ks_check = (np.maximum(1, np.ceil(POINTS_PER_PERIOD * dt / T).astype(int)) for T in (T_match, T_check))
    tail = int(math.ceil(0.5 * T_match.max() / dt)) + 2
    budget.check_bytes(budget.record_set_bytes(n, npts, nfft, tail, int(ks.max())), head + " (FFT work arrays and "
                       f"response spectra at {N_MATCH} periods)", fix)
    budget.check_seconds(budget.record_set_seconds(n, npts, nfft, tail, ks, iterations, ks_check),
                         head + f" with up to {iterations} iterations", fix + ", or fewer iterations")
    S_match, S_check = target_values(target, T_match), target_values(target, T_check)

    t = np.arange(npts) * dt
    env = envelope(t, duration)
    seeds = tuple(int(seed) + i for i in range(n))
    f = np.fft.rfftfreq(nfft, dt)
    H = high_pass(f, hi)
    logf = np.log(np.maximum(f, f[1] * 0.5))
    logf_match = np.log(1.0 / T_match[::-1])                 # ascending frequencies

    def filtered(x, gain):
        return np.fft.irfft(np.fft.rfft(x, nfft, axis=-1) * gain, nfft, axis=-1)[:, :npts]

    # the stationary signals: high-passed white noise
    s = filtered(np.stack([np.random.default_rng(k).standard_normal(npts) for k in seeds]), H)
    from ..compute.executors import progress_bar

    bar = progress_bar(f"matching {n} records", iterations + 2, unit="spectra")   # shown for long work
    try:
        # first pass: scale every record so its spectrum matches on average
        s *= np.median(S_match / psa(s * env, dt, T_match, xi), axis=-1, keepdims=True)
        bar.update(1)
        target_pga = float(target_values(target, np.array([0.0]))[0])
        caps = None
        if control:   # each record's peak held at Se(0) x its own first-pass peak / the set's mean one
            first = np.max(np.abs(baseline_correct(s * env, dt, env)), axis=-1)
            caps = (target_pga * first / first.mean())[:, None]
        done = 0
        for done in range(1, iterations + 1):
            acc = baseline_correct(s * env, dt, env)
            ratio = S_match / psa(acc, dt, T_match, xi)        # (n, n_T)
            bar.update(1)
            if np.all(np.abs(ratio - 1) <= record_tol) and (
                    caps is None or np.mean(np.max(np.abs(acc), axis=-1)) <= target_pga * (1 + PGA_TOL)):
                break
            R = np.stack([np.interp(logf, logf_match, r[::-1]) for r in ratio])
            s = filtered(s, R * H)
            if caps is not None and np.mean(np.max(np.abs(s * env), axis=-1)) > target_pga:
                s = np.clip(s, -caps, caps)             # only a set whose peaks overshoot Se(0) is clipped
        acc = baseline_correct(s * env, dt, env)
        scale = pga_scale(np.max(np.abs(acc), axis=-1), target_pga)
        acc = acc * scale
        spectra = psa(acc, dt, T_check, xi)
    finally:
        bar.close()
    records = tuple(record(a, dt, label=f"matched seed {k}") for a, k in zip(acc, seeds))
    info, d_g, sd_plateau = target_facts(target)
    return RecordSet(records, seeds, T_check, spectra, S_check, (lo, hi), tol, xi, done, info, target_pga,
                     rb, band_reason or f"{rb[0]:g} s to {rb[1]:.4g} s", stationary_part(duration), float(scale),
                     d_g, sd_plateau, pga_cap=1 + PGA_TOL if control else None)


def check_band(band, dt: float, what: str = "record set") -> tuple[float, float]:
    """(T0, T1) of ``band`` as floats, refused in one line unless 0 < T0 < T1 and T0 >= 4 dt (the
    shortest period a record sampled every ``dt`` s resolves)."""
    try:
        lo, hi = (float(b) for b in band)
    except (TypeError, ValueError):
        raise InputError(f"{what}: band must be two periods (s), got {band!r}") from None
    if not (math.isfinite(lo) and math.isfinite(hi) and 0 < lo < hi):
        raise InputError(f"{what}: band must be two periods 0 < T0 < T1 (s), got {band!r}")
    if lo < 4 * dt:
        raise InputError(f"{what}: dt {dt:g} s is too coarse for periods from {lo:g} s: use dt <= {lo / 4:g} s "
                         f"or a band starting at {4 * dt:g} s or more")
    return lo, hi


def check_tolerance(tolerance, what: str = "record set") -> tuple:
    """(below, above or None) fractions, refused in one line unless -1 < below < 0 < above."""
    try:
        lo_t, hi_t = tolerance
        lo_t = float(lo_t)
        hi_t = None if hi_t is None else float(hi_t)
    except (TypeError, ValueError):
        lo_t, hi_t = math.nan, None
    if not (-1 < lo_t < 0 and (hi_t is None or 0 < hi_t < math.inf)):
        raise InputError(f"{what}: tolerance must be (below, above) fractions like (-0.1, None) or (-0.1, 0.3), "
                         f"got {tolerance!r}")
    return lo_t, hi_t


# --- a set on disk: set.json names its records ------------------------------------------------
SET_FILE = "set.json"
RECORD_SUFFIXES = (".csv", ".at2")
"""Record files a set may name: CSV (time s, acceleration) and PEER .AT2 (in g)."""


def set_files(folder, names, units: str = "m/s2") -> dict:
    """The keys of set.json that name a set's records ``names`` (files in ``folder``, in
    the set's order): ``files`` (the names), ``file_checks`` ({name: {"bytes", "sha256"}}
    of each file as written now) and ``units`` of the CSV records (m/s2 or g)."""
    from pathlib import Path

    from ..io.files import file_sha256

    folder = Path(folder)
    names = [str(n) for n in names]
    return {"files": names, "units": units,
            "file_checks": {n: {"bytes": (folder / n).stat().st_size, "sha256": file_sha256(folder / n)}
                            for n in names}}


def read_record_set(folder, units: str | None = None, option: str = "--records") -> tuple[list[GroundMotion], dict]:
    """The records of the set in ``folder``: the files its set.json names (``files``, in
    that order), each checked: a plain name in the folder (.csv or .AT2), present, and of
    the length and SHA-256 that ``file_checks`` records (every named file must have one
    when set.json has ``file_checks``; a set.json written by hand may list only ``files``,
    then each is checked to be there). CSV units: ``units``, else set.json's ``units``,
    else m/s2 (a conflict is refused). Returns (records, info): info holds the set.json
    data and ``ignored``, the record files of the folder set.json does not name (not used).
    Refusals are one-line InputErrors naming ``option`` and the folder."""
    from pathlib import Path

    from ..io.files import file_sha256, read_json
    from .motions import read_record

    folder = Path(folder)
    where = f"{option} {folder}"
    if not folder.is_dir():
        raise InputError(f"{where}: not a folder of records")
    sj = folder / SET_FILE
    if not sj.is_file():
        raise InputError(f"{where}: the folder has no {SET_FILE}: a record set is read from the {SET_FILE} that "
                         "`statue2model records` writes after its records (the files it names, with their hashes), "
                         "never from whatever files lie in the folder; for records of your own, list them in "
                         f"{sj} as {{\"files\": [\"a.AT2\", \"b.csv\"]}}")
    data = read_json(sj)
    files = data.get("files") if isinstance(data, dict) else None
    if not isinstance(files, list) or not files or not all(isinstance(n, str) for n in files):
        raise InputError(f"{where}: {SET_FILE} names no record files (a list \"files\" of file names)")
    for n in files:
        if Path(n).name != n or n in (".", "..") or Path(n).suffix.lower() not in RECORD_SUFFIXES:
            raise InputError(f"{where}: {SET_FILE} names {n!r}: a record is a .csv or .AT2 file in the set's folder")
    if len(set(files)) != len(files):
        raise InputError(f"{where}: {SET_FILE} names a file twice")
    n_said = data.get("n_records")
    if n_said is not None and n_said != len(files):
        raise InputError(f"{where}: {SET_FILE} is inconsistent: n_records {n_said!r} but {len(files)} files")
    checks = data.get("file_checks")
    if checks is not None and not isinstance(checks, dict):
        raise InputError(f"{where}: {SET_FILE}: file_checks is not a table of file checks")
    missing = [n for n in files if not (folder / n).is_file()]
    if missing:
        raise InputError(f"{where}: the set is incomplete: {SET_FILE} names {len(files)} records, "
                         f"{len(missing)} missing ({', '.join(missing[:4])}{', ...' if len(missing) > 4 else ''}); "
                         "write the set again (`statue2model records`)")
    if checks is not None:
        changed = []
        for n in files:
            c = checks.get(n)
            if not isinstance(c, dict) or "sha256" not in c or "bytes" not in c:
                raise InputError(f"{where}: {SET_FILE} records no length and hash of {n}: the set is incomplete; "
                                 "write the set again (`statue2model records`)")
            if (folder / n).stat().st_size != c["bytes"] or file_sha256(folder / n) != c["sha256"]:
                changed.append(n)
        if changed:
            raise InputError(f"{where}: {', '.join(changed[:4])}{', ...' if len(changed) > 4 else ''} changed after "
                             f"{SET_FILE} was written (length or SHA-256 differs): not the set it describes; write "
                             "the set again (`statue2model records`)")
    said = data.get("units")
    if said is not None and said not in ("m/s2", "g"):
        raise InputError(f"{where}: {SET_FILE}: units must be m/s2 or g, got {said!r}")
    if units is not None and said is not None and units != said:
        raise InputError(f"{where}: --units {units} but {SET_FILE} says the records are in {said}")
    csv_units = units or said
    records = [read_record(folder / n, units=None if n.lower().endswith(".at2") else csv_units) for n in files]
    said_scale = data.get("froude_scale")
    if said_scale:      # the set says it is for a prototype: every record carries it
        from dataclasses import replace

        from ..quantities import scale_ratio

        try:
            lam = scale_ratio(said_scale)
        except InputError:
            raise InputError(f"{where}: {SET_FILE}: froude_scale {said_scale!r} is not a scale like 1:2") from None
        records = [r if r.froude_scale == lam else replace(r, froude_scale=lam) for r in records]
    ignored = sorted(p.name for p in folder.iterdir()
                     if p.suffix.lower() in RECORD_SUFFIXES and p.name not in set(files))
    return records, {**data, "ignored": ignored}
