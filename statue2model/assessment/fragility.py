"""Fragility: the probability of failure against the intensity of the ground motion,
on a fixed base and on the isolator, fitted as lognormal curves.

A study runs every record (a list of :class:`~statue2model.hazard.motions.GroundMotion`)
scaled to every intensity level (PGA in m/s^2, or PGV in m/s) for every parameter
sample (:mod:`statue2model.rocking.sampling`): records x levels x samples runs. Each
run's outcome is a yes / no per *outcome*, each with its own curve, named ``<limit state>_<base>``
after the registry of :mod:`statue2model.assessment.states` (LIMIT_STATE_CURVES):

* ``full_contact_fixed`` - the body lifts on a fixed base (full contact lost): the scaled record reaches
  the sample's uplift limit on either side, alpha_L a_L toward +x or alpha_R a_R toward -x.
  Exactly the complement of the ``quiet`` test below (no integration needed);
* ``overturning_fixed`` - the body overturns on a fixed base (rocking kernel, run_batch);
* ``full_contact_isolated`` - on the isolator the top plate's peak absolute acceleration (what the
  statue feels) reaches the sample's weaker uplift limit min(alpha_L a_L, alpha_R a_R), or the
  plate passes the capacity (limit_states' full contact on the isolator: the sign of the peak
  is not kept, and the end stop's impact would jolt the statue);
* ``overturning_alone_isolated`` - it overturns on the isolator (coupled plate + statue,
  :func:`~statue2model.isolator.coupled.simulate_coupled`, end_stop "stop": a run that
  first exceeds the capacity stops there and is counted below, not here);
* ``capacity_isolated`` - the top plate passes the isolator's capacity (issue [8]);
* ``overturning_isolated`` - either of the two (the conservative failure on the isolator; the
  limit state "overturning" on the isolator, where reaching the capacity counts as overturned).

A sample may carry the isolator's friction (``mu``, rocking.sampling: its low and high bound);
the isolated runs of that sample use it.

Levels (``adaptive``, :class:`AdaptiveLevels`): the given levels are the coarse grid; then,
round after round, each curve that is not identified (:func:`identified_reason`: its median outside the levels
run, or its spread not identified, :func:`spread_reason` on its counts: a fit with fewer than
MIN_PARTIAL levels of partial failure fractions, or a
profile-likelihood or bootstrap band of beta with an end not identified or at a bound: the
bootstrap of the final fit, run in each round for the curves that pass the other tests) asks for levels at
m exp(-s), m, m exp(+s) around its fitted median m (s: its beta, at least 1/8 of its bracket's
width in ln IM, 1/4 for a step), each kept inside its bracket (the highest level below m with no
failure and the lowest above m with all failing; a side without one reaches 2 max(beta, 0.05)
beyond m or the levels: a median beyond the levels run takes levels there) by 1/8 of the
bracket's width and dropped when
within MIN_GAP (2 %) of a level its base ran or of one asked before; each base runs only its new
levels (the runs at old levels are kept), its curves asking in the order of ADAPT_ORDER, until
no curve asks, ``rounds`` rounds are done or ``max_added`` levels were added to the base. A curve
still not identified says why; curves without a fit (no failure, or all failed, in the levels)
ask for none: the range of the coarse grid is not extended.

Fit (Baker 2015, Earthquake Spectra 31(1)): at level x_j, z_j of n_j runs fail;
P(fail | x) = Phi(ln(x / theta) / beta), theta (median) and beta (dispersion) maximise
the binomial likelihood sum_j [z_j ln P_j + (n_j - z_j) ln(1 - P_j)] (a coarse grid, then
scipy.optimize TNC, bounded Newton with the analytic gradient, on ln theta, ln beta; beta
is bounded to [BETA_MIN, BETA_MAX]).
Runs where the rocking model does not apply (the body slides first,
:meth:`RockingModel.applicability`) or the solver did not finish are left out of n_j.
The spread is identified (:func:`spread_reason` is None) when the fit is "ok", at least
MIN_PARTIAL levels have a partial fraction of failures (0 < z_j < n_j), the profile-likelihood
band of beta (:func:`beta_profile_band`: the betas whose likelihood, maximised over the median,
is within chi2_1(confidence) / 2 of the maximum) has both ends inside (BETA_MIN, BETA_MAX), and
the bootstrap band of beta has both ends inside them too (the profile counts every run as
independent; the bootstrap resamples the records, whose samples move together: a band reaching
BETA_MIN says that resampled records fall back to a step). A probability from a fit whose spread is not
identified is not stored (``fitted`` null, with ``spread_reason``).
Status of a fit: "ok"; "step" (the failures are separated by one level: beta at BETA_MIN);
undefined (median and beta nan, written null with the reason of REASONS): "no failures"
(median above the levels), "all failed" (below them), "one level" (runs at one level
only: any spread fits one point, so neither median nor beta is identified), "no runs".
A fit needs runs at two levels or more, at least one failure and one survival.

Confidence bands: bootstrap (``n_boot`` replicates, ``seed``) over the records (the
dominant, independent input) when there are at least MIN_BOOT_RECORDS of them, else over
the parameter samples; each replicate re-fits the curves (all replicates of a curve at once:
:func:`fit_lognormal_many`, Newton on the convex probit likelihood in slope 1/beta and
intercept ln(theta)/beta: on 300 random count sets its likelihood was never below fit_lognormal's
by more than 1e-13, and up to 4e-5 above it where TNC stopped short); the bands are the
(1 - confidence)/2 and (1 + confidence)/2 percentiles of the fitted P at each level, of
the median, of beta and of the ratio of medians isolated / fixed (paired: the same
resample for both). They are sampling bands of the study, not model uncertainty.
A replicate without failures has its median above the levels run (P = 0 at every level),
one that failed everywhere below them (P = 1): they keep their place in the order of the
medians, and a band end that falls on one is not identified (null, with a note counting
them, ``median_ci_note``); replicates with one level of runs are left out (counted).
Only a curve whose own fit is defined has bands (else they are null, with its reason).

Early exit (fixed base; the outcome only): a run stops when it overturns; a run whose
motion never exceeds the uplift limits is not integrated (``quiet``); after the ground
is still, a run stops once it has peaked on both sides without any impact able to add
energy (the kernel's ``early_exit``). A body at rest skips, without a step, the record
pieces that cannot lift it: the stick search reads the record's suffix extremes (the
largest and smallest sample from there to the end, once per record), so a body at rest
whose remaining record stays within its uplift limits stops there at once, and one that
will lift again jumps to the piece before the next sample beyond them (exact: the same
numbers as reading every piece; a quiet tail costs nothing). A body still rocking is
integrated on (a sub-uplift ground motion can still pump it) until its outcome is decided
on energy (``kernel_vector(early_exit="outcome")``): its energy plus all the energy the
rest of the record could pump in stays below the overturning barrier (docs/fragility.md).
A record's runs of every parameter sample go to the kernel in one batch (each row with its
sample's restitution table), handed to numba's threads one run at a time.

Example
-------
>>> import numpy as np
>>> from statue2model.geometry.rocking_params import RockingParams
>>> from statue2model.hazard import motions
>>> from statue2model.rocking import RockingModel
>>> from statue2model.rocking.sampling import lognormal_factor
>>> block = RockingParams.rectangular_block(0.0384, 0.2, 1.286)
>>> model = RockingModel.housner(block, e_L=0.9, e_R=0.9)
>>> recs = [motions.synthetic_record(8.0, 0.01, 1.0, seed=s) for s in range(3)]
>>> res = run_fragility(model, recs, np.linspace(1.0, 12.0, 8), lognormal_factor(0.2, 10),
...                     FragilityStudy(n_boot=20))
>>> c = res.curves["overturning_fixed"]
>>> c.status, int(c.n_trials.sum()), bool(2.0 < c.median < 12.0)
('ok', 240, True)
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np

from ..compute.budget import check_bytes, check_runs
from ..errors import InputError
from ..rocking import kernel as K
from ..rocking.batch import run_batch
from ..rocking.engine import FREE_TIME
from ..rocking.model import RockingModel
from ..hazard.motions import GroundMotion
from ..rocking.sampling import ParameterSamples
from . import states
from .fragility_fit import (  # noqa: F401  (re-exported: the study's statistics live in fragility_fit.py)
    BETA_MAX,
    BETA_MIN,
    EMPIRICAL,
    EXACT,
    UPLIFT_RULE,
    MIN_PARTIAL,
    REASONS,
    FragilityCurve,
    _finite,
    choose_uplift_curve,
    distinct_thresholds,
    threshold_count,
    wilson_interval,
    beta_profile_band,
    fit_lognormal,
    fit_lognormal_many,
    identified_reason,
    lognormal_cdf,
    median_reason,
    partial_levels,
    spread_reason,
)

IMS = ("pga", "pgv")
FIXED = states.CURVES_FIXED
ISOLATED = states.CURVES_ISOLATED
LABELS = states.CURVE_LABELS
LIMIT_STATE_CURVES = {s.id: dict(s.curves) for s in states.REGISTRY if s.curves}
_C = states.curve
"""The curve of each limit state on each base (assessment/states.py: on the isolator a run that reached
the capacity counts as overturned, so overturning there is ``overturning_isolated``)."""
ADAPT_ORDER = states.ADAPT_ORDER
"""The order in which a base's curves ask for adaptive levels (the budget goes to the first). The
fixed-base uplift asks for none: it is fitted on each run's exact uplift PGA (:func:`exact_uplift`)."""
MIN_GAP = 0.02
"""An adaptive level within this distance in ln IM (2 %) of a level its base ran is not added."""
MIN_BOOT_RECORDS = 5
BYTES_PER_RUN = 800
"""Bytes one run of a study costs: its rows P, M, S in the batch (~360 B) and its outcomes."""
ISO_BYTES_PER_RUN = 64
"""Bytes one run on the isolator costs beyond the scaled record its task carries: its
outcomes (three int64) and its flags."""
TASK_BYTES_PER_RUN = 8 * (K.N_P + K.N_M + K.N_S)
"""Bytes a fixed-base run adds on an executor: the copies of its rows P, M sent to the
workers and its statistics S sent back."""
ROWS_PER_TASK = 1000
"""Rows of one executor task (fixed base): large enough to amortise the task, small enough
to balance the workers of a 200 000-run study."""


@dataclass(frozen=True)
class FragilityStudy:
    """How a study runs and is fitted: ``im`` "pga" (levels in m/s^2) or "pgv" (m/s);
    ``rtol`` of the solvers; ``free_time`` s simulated after each record; bootstrap
    ``n_boot`` replicates with ``seed`` and ``confidence`` (two-sided level of the bands);
    ``bootstrap``: "auto" (records if at least MIN_BOOT_RECORDS, else samples), "records"
    or "samples"."""

    im: str = "pga"
    rtol: float = 1e-7
    free_time: float = FREE_TIME
    n_boot: int = 200
    confidence: float = 0.90
    seed: int = 0
    bootstrap: str = "auto"

    def __post_init__(self):
        if self.im not in IMS:
            raise InputError(f"intensity measure must be one of {', '.join(IMS)}, got {self.im!r}")
        if not (1e-12 <= self.rtol <= 1e-3):
            raise InputError(f"rtol must lie in [1e-12, 1e-3], got {self.rtol}")
        if not (math.isfinite(self.free_time) and self.free_time >= 0):
            raise InputError(f"free_time must be >= 0 s, got {self.free_time}")
        if isinstance(self.n_boot, bool) or not isinstance(self.n_boot, (int, np.integer)) or \
                not 0 <= self.n_boot <= 100_000:
            raise InputError(f"n_boot must be a whole number in 0..100000, got {self.n_boot!r}")
        if not 0 < self.confidence < 1:
            raise InputError(f"confidence must lie in (0, 1), got {self.confidence}")
        if isinstance(self.seed, bool) or not isinstance(self.seed, (int, np.integer)) or self.seed < 0:
            raise InputError(f"seed must be a non-negative integer, got {self.seed!r}")
        if self.bootstrap not in ("auto", "records", "samples"):
            raise InputError(f"bootstrap must be auto, records or samples, got {self.bootstrap!r}")

    def to_dict(self) -> dict:
        return {"im": self.im, "rtol": self.rtol, "free_time_s": self.free_time, "n_boot": self.n_boot,
                "confidence": self.confidence, "seed": self.seed, "bootstrap": self.bootstrap}


@dataclass(frozen=True)
class AdaptiveLevels:
    """The budget of the adaptive levels (module docstring): at most ``rounds`` rounds, each
    curve asking for up to 3 levels a round, at most ``max_added`` levels added to each base."""

    rounds: int = 3
    max_added: int = 12

    def __post_init__(self):
        for name, lo, hi in (("rounds", 0, 20), ("max_added", 0, 200)):
            v = getattr(self, name)
            if isinstance(v, bool) or not isinstance(v, (int, np.integer)) or not lo <= v <= hi:
                raise InputError(f"adaptive levels: {name} must be a whole number in {lo}..{hi}, got {v!r}")

    def rule(self) -> str:
        """The rule in one paragraph (fragility.json's ``adaptive.rule``)."""
        return ("the given levels first; then, for at most {r} rounds, each curve whose spread is not identified "
                "(fewer than {p} levels with a partial fraction of failures, or a profile-likelihood or bootstrap band "
                "of beta with an end not identified or at a bound) asks for levels at m exp(-s), m, m exp(+s) around "
                "its fitted median m (a median outside the levels run counts as not identified; s its "
                "beta, at least 1/8 of its bracket's width in ln IM, 1/4 for a step), kept inside its bracket (the "
                "highest level below m with no failure, the lowest above m with all failing, a side without one "
                "open to 2 max(beta, 0.05) beyond m or the levels) by 1/8 of its width, "
                "dropped within {g:g} % of a level its base ran; each base runs only its new levels (in the order "
                "{o}), at most {m} added to a base; curves without a fit (no failure or all failed) ask for none"
                ).format(r=self.rounds, p=MIN_PARTIAL, g=100 * MIN_GAP, o=", ".join(ADAPT_ORDER), m=self.max_added)

    def to_dict(self) -> dict:
        return {"rounds": self.rounds, "max_added": self.max_added, "min_partial": MIN_PARTIAL,
                "min_gap_ln": MIN_GAP, "order": list(ADAPT_ORDER), "rule": self.rule()}


# --- intensity measures -------------------------------------------------------------
PGV_HIGHPASS = 0.1
"""Hz: a record lasting at least 1 / PGV_HIGHPASS s has its PGV read from its acceleration
high-passed there (zero-phase 4th-order Butterworth), the usual strong-motion processing: the
uncorrected integral of a synthetic record drifts (measured: final velocity 40-97 % of the peak on
seeds 0-2 of synthetic_record), which would inflate PGV; El Centro ends at rest (6e-5 m/s)."""


def pgv(motion: GroundMotion) -> float:
    """Peak ground velocity (m/s): trapezoidal integration from rest; a record of at least
    1 / PGV_HIGHPASS s is high-passed first (see PGV_HIGHPASS), a shorter one is taken as given;
    |amp| dur for a rectangular pulse."""
    if motion.kind == "none":
        return 0.0
    if motion.kind == "rect":
        return abs(motion.amp) * motion.duration
    if motion.kind == "record":
        a = np.asarray(motion.samples, dtype=float)
        if a.size * motion.dt >= 1.0 / PGV_HIGHPASS and PGV_HIGHPASS < 0.5 / motion.dt:
            from scipy import signal

            a = signal.sosfiltfilt(signal.butter(4, PGV_HIGHPASS, "highpass", fs=1.0 / motion.dt, output="sos"), a)
        v = np.concatenate([[0.0], np.cumsum(0.5 * (a[1:] + a[:-1]) * motion.dt)])
        return float(np.max(np.abs(v)))
    t = np.linspace(motion.start, motion.end, 4001)
    a = motion.acc(t)
    v = np.concatenate([[0.0], np.cumsum(0.5 * (a[1:] + a[:-1]) * np.diff(t))])
    return float(np.max(np.abs(v)))


def intensity(motion: GroundMotion, im: str) -> float:
    """The record's own intensity: PGA (m/s^2) or PGV (m/s)."""
    return float(motion.pga) if im == "pga" else pgv(motion)


@dataclass(frozen=True, eq=False)
class FragilityResult:
    """A study's outcome. ``fails[name]``: (records, samples, levels) bool, ``valid``:
    (records, samples, levels) bool (runs counted: applicable and finished; one array
    per side, "fixed" and "isolated"); ``curves[name]``: FragilityCurve; ``ratio``:
    {"overturning": ..., "overturning_alone": ..., "full_contact": ...} each {"value", "ci"}: median
    isolated / median fixed of that limit state (overturning on the isolator counts the capacity
    exceeded, "overturning_alone" does not; "full_contact": uplift on the isolator against uplift on a
    fixed base). ``ran``: side -> (L,)
    bool, the levels each base ran (with adaptive levels a base need not run every level of
    ``levels``, the union; its arrays are False there); ``adaptive``: the rule and its rounds
    (None: the levels as given)."""

    im: str
    levels: np.ndarray
    record_labels: list
    record_im: np.ndarray
    samples: ParameterSamples
    study: FragilityStudy
    fails: dict
    valid: dict
    curves: dict
    ratio: dict
    bootstrap_unit: str
    model: RockingModel
    isolator: object = None
    stats: dict = field(default_factory=dict)
    ran: dict | None = None
    adaptive: dict | None = None

    @property
    def unit(self) -> str:
        return "m/s2" if self.im == "pga" else "m/s"

    def levels_run(self, side: str) -> np.ndarray:
        """The levels base ``side`` ("fixed" or "isolated") ran."""
        if self.ran is None or side not in self.ran:
            return self.levels
        return self.levels[self.ran[side]]

    def to_dict(self) -> dict:
        per_record = {name: {"n_fail": f.sum(axis=1), "n_trials": self.valid[_side(name)].sum(axis=1)}
                      for name, f in self.fails.items()}
        return {"im": self.im, "unit": self.unit, "levels": self.levels, "study": self.study.to_dict(),
                "bootstrap_unit": self.bootstrap_unit, "n_records": len(self.record_labels),
                "records": [{"label": lab, self.im: float(v)} for lab, v in zip(self.record_labels, self.record_im)],
                "samples": self.samples.to_dict(), "model": self.model.to_dict(),
                "isolator": None if self.isolator is None else self.isolator.to_dict(),
                "levels_run": {side: self.levels_run(side) for side in self.valid},
                "adaptive": self.adaptive, "limit_states": {
                    ls: {base: k for base, k in bases.items() if k in self.curves}
                    for ls, bases in LIMIT_STATE_CURVES.items()},
                "curves": {k: c.to_dict() for k, c in self.curves.items()}, "ratio_of_medians": self.ratio,
                "per_record": per_record, "stats": self.stats}

    def csv_rows(self) -> tuple[list, list]:
        """(header, rows): one row per outcome and level; an undefined number is an empty cell
        (never nan or inf), the curve's ``reason`` says why."""
        header = ["outcome", f"{self.im}_{self.unit.replace('/', '_')}", "n_fail", "n_trials", "fraction",
                  "fitted_p", "band_lo", "band_hi", "median", "beta", "status", "reason"]
        rows = []
        for c in self.curves.values():
            spread = c.spread
            fit = np.full(c.levels.shape, np.nan) if spread else c.probability(c.levels)
            blo = np.full(c.levels.shape, np.nan) if c.band_lo is None else c.band_lo
            bhi = np.full(c.levels.shape, np.nan) if c.band_hi is None else c.band_hi
            for j, x in enumerate(c.levels):
                rows.append([c.outcome, f"{x:.9g}", int(c.n_fail[j]), int(c.n_trials[j]), _g(c.fraction[j]),
                             _g(fit[j]), _g(blo[j]), _g(bhi[j]), _g(c.median), _g(c.beta), c.status,
                             c.reason or spread or ""])
        return header, rows

    def write_csv(self, path):
        from ..io.csvsafe import write_csv

        header, rows = self.csv_rows()
        return write_csv(path, header, rows)

    def write_json(self, path):
        from ..io.files import write_json

        return write_json(path, self.to_dict())

    def summary_lines(self) -> list[str]:
        """One line per curve and ratio; an undefined number is '-' or its reason, never nan or inf."""
        u = self.unit
        out = []
        for c in self.curves.values():
            if c.fitted:
                if not self.study.n_boot:
                    mci = bci = ""
                elif not any(math.isfinite(x) for x in c.median_ci):
                    mci, bci = f" ({c.median_ci_note or 'no band'})", ""
                else:
                    mci = f" [{_band(c.median_ci, '.4g')}]" + (f" ({c.median_ci_note})" if c.median_ci_note else "")
                    bci = f" [{_band(c.beta_ci, '.3f')}]" if any(math.isfinite(x) for x in c.beta_ci) else ""
                spread = c.spread
                btxt = f"beta {c.beta:.3f}{bci}" if spread is None else spread
                if c.status == EMPIRICAL:
                    btxt = f"empirical: the step CDF of {len(c.thresholds)} exact thresholds ({c.choice.get('reason')})"
                out.append(f"{LABELS[c.outcome]}: median {c.median:.4g} {u}{mci}, {btxt}")
            else:
                out.append(f"{LABELS[c.outcome]}: not fitted ({c.reason}) in {c.levels[0]:.4g}..{c.levels[-1]:.4g} "
                           f"{u}")
        for k, r in self.ratio.items():
            if r["value"] is not None:
                ci = r["ci"]
                band = f" [{_band(ci, '.3g')}]" if any(x is not None for x in ci) else ""
                note = f" ({r['ci_note']})" if r.get("ci_note") else ""
                out.append(f"isolator benefit ({k}): median isolated / fixed = {r['value']:.3g}{band}{note}")
            else:
                out.append(f"isolator benefit ({k}): median isolated / fixed undefined ({r['note']})")
        return out


def _g(v) -> str:
    return "" if v is None or not np.isfinite(v) else f"{v:.6g}"


def _band(ci, spec: str) -> str:
    """'lo, hi' of a band whose ends may be None / non-finite (not identified): such an end is '-'."""
    return ", ".join("-" if v is None or not np.isfinite(v) else format(float(v), spec) for v in ci)


def _side(name: str) -> str:
    return "fixed" if name in FIXED else "isolated"


def _json_ready(x):
    """A copy of nested dicts / lists with numpy numbers and arrays as plain Python ones."""
    if isinstance(x, dict):
        return {k: _json_ready(v) for k, v in x.items()}
    if isinstance(x, (list, tuple, np.ndarray)):
        return [_json_ready(v) for v in x]
    if isinstance(x, (np.integer,)):
        return int(x)
    if isinstance(x, (float, np.floating)):
        return _finite(x)
    return x


# --- the study's budget ----------------------------------------------------------------------
def study_bytes(n_records: int, n_levels: int, n_samples: int, record_samples: int, isolated: bool,
                executor: bool = False) -> float:
    """Peak bytes of a study, estimated from its sizes alone (before any record is made):
    the records (8 B a sample, twice: one more while a record is made or filtered for its
    PGV), BYTES_PER_RUN each fixed-base run (+ TASK_BYTES_PER_RUN on an executor), and on
    the isolator the records scaled to every level (the R x L tasks carry them) plus
    ISO_BYTES_PER_RUN each run."""
    R, L, S, N = (float(x) for x in (n_records, n_levels, n_samples, max(float(record_samples), 1.0)))
    runs = R * L * S
    b = 16.0 * R * N + runs * (BYTES_PER_RUN + (TASK_BYTES_PER_RUN if executor else 0))
    if isolated:
        b += 8.0 * R * L * N + runs * ISO_BYTES_PER_RUN
    return b


def check_study(n_records: int, n_levels: int, n_samples: int, record_samples: int, isolated: bool,
                executor: bool = False) -> None:
    """Refuse (one-line InputError with the estimate and the limit) a study beyond the run
    cap or the memory budget (:mod:`statue2model.compute.budget`), from its sizes alone: call
    it before the records are made (the CLI does, from --records, --levels and --samples)."""
    R, L, S = int(n_records), int(n_levels), int(n_samples)
    n_runs = R * L * S * (2 if isolated else 1)
    what = f"{R} records x {L} levels x {S} samples = {n_runs} runs" + (" (fixed and isolated)" if isolated else "")
    fix = "use fewer records, levels or samples"
    check_runs(n_runs, BYTES_PER_RUN, what, fix)
    check_bytes(study_bytes(R, L, S, record_samples, isolated, executor),
                what + f" on records of {float(record_samples):.6g} samples", fix + ", or shorter records")


# --- running the study ----------------------------------------------------------------------
def _check_inputs(model, records, levels, samples, study):
    if not isinstance(model, RockingModel):
        raise InputError("model must be a RockingModel")
    if isinstance(records, GroundMotion):
        records = [records]
    records = list(records)
    if not records or not all(isinstance(r, GroundMotion) for r in records):
        raise InputError("records must be a non-empty list of GroundMotion")
    if not isinstance(samples, ParameterSamples):
        raise InputError("samples must be ParameterSamples (statue2model.rocking.sampling)")
    lv = np.asarray(levels, dtype=float).ravel()
    if lv.size == 0 or not np.all(np.isfinite(lv)) or np.any(lv <= 0):
        raise InputError(f"intensity levels must be finite and > 0 ({'m/s^2' if study.im == 'pga' else 'm/s'})")
    if np.any(np.diff(lv) <= 0):
        raise InputError("intensity levels must be strictly increasing")
    ims = np.array([intensity(r, study.im) for r in records])
    for r, v in zip(records, ims):
        if not v > 0:
            raise InputError(f"record {r.label!r} has zero {study.im.upper()}: it cannot be scaled")
    return records, lv, ims


def _n_samples(motion: GroundMotion) -> int:
    return 0 if getattr(motion, "samples", None) is None else int(np.size(motion.samples))


def _rows_task(task: tuple) -> np.ndarray:
    """One block of fixed-base rows on a worker: (P, tables, lengths, table_row, kinds, M,
    samples, hi, lo, t_end, rtol, max_steps) -> statistics (rows, N_S). Module level: it pickles."""
    from ..rocking.batch import _run_rows

    return _run_rows(task)


def _fixed(model, records, gains, samples, study, executor, max_steps, keep_stats=False):
    """(fails, valid, n_integrated, lifts): (R, S, L) bool arrays of the fixed-base runs (``lifts``:
    the scaled record reaches an uplift limit, the complement of ``quiet``); with ``keep_stats`` a
    fifth item, the runs' statistics (R, S, L, N_S) (kernel.S_*; a run not integrated has zeros
    and nan there, as run_batch leaves it)."""
    from ..rocking.batch import restitution_tables, suffix_extremes

    R, L = gains.shape
    S_n = samples.n
    models = samples.models(model)
    fac = samples.im_factors()
    fails = np.zeros((R, S_n, L), dtype=bool)
    lifts = np.zeros((R, S_n, L), dtype=bool)
    valid = np.ones((R, S_n, L), dtype=bool)
    stats = np.zeros((R, S_n, L, K.N_S)) if keep_stats else None
    # the distinct restitution tables: a record's runs of every sample go in one batch, each
    # row with its sample's table
    groups: dict = {}
    for m in models:
        groups.setdefault((m.e_L, m.e_R), len(groups))
    table_of = np.array([groups[(m.e_L, m.e_R)] for m in models], dtype=np.int64)
    distinct = [None] * len(groups)
    for s_, m in enumerate(models):
        if distinct[table_of[s_]] is None:
            distinct[table_of[s_]] = m
    tables, lengths = restitution_tables(distinct)
    Pall = np.array([m.kernel_vector(early_exit="outcome") for m in models])
    lims = np.array([m.uplift_limits for m in models])
    slides = any(m.slides_first for m in models)
    ss = np.repeat(np.arange(S_n), L)
    ll = np.tile(np.arange(L), S_n)
    P = Pall[ss]
    rows_table = table_of[ss]
    n = ss.size
    jobs = []          # (record, M, t_end, todo (rows integrated), samples)
    n_int = 0
    for r, rec in enumerate(records):
        kind, M0, smp = rec.kernel_args()
        hi, lo = rec.extremes()
        g = gains[r, ll] * fac[ss]
        M = np.tile(M0, (n, 1))
        M[:, K.MA] *= g
        quiet = (g * hi <= lims[ss, 0]) & (-g * lo <= lims[ss, 1])
        lifts[r, ss, ll] = ~quiet
        na = np.array([not models[s_].applicability(gk * hi, -gk * lo)[0] for s_, gk in zip(ss, g)]) \
            if slides else np.zeros(n, dtype=bool)
        valid[r, ss, ll] = ~na
        todo = np.flatnonzero(~(quiet | na))
        n_int += int(todo.size)
        jobs.append((r, kind, M, np.full(n, rec.end + study.free_time), todo, smp))
    if executor is None:
        from ..compute.executors import progress_bar

        bar = progress_bar("fragility, fixed base", len(jobs), unit="record")
        try:
            for (r, kind, M, t_end, todo, smp) in jobs:
                quiet = np.ones(n, dtype=bool)
                quiet[todo] = False
                S = run_batch(distinct, P, np.full(n, kind, dtype=np.int64), M, smp, t_end, rtol=study.rtol,
                              quiet=quiet, max_steps=max_steps, table_row=rows_table)
                fails[r, ss, ll] = S[:, K.S_OVERTURNED] > 0
                if keep_stats:
                    stats[r, ss, ll] = S
                bar.update(1)
        finally:
            bar.close()
    else:
        from ..compute.compile import ensure_compiled

        ensure_compiled()
        tasks, where = [], []
        for (r, kind, M, t_end, todo, smp) in jobs:
            smp = K.as_samples(smp)
            s_hi, s_lo = suffix_extremes(smp)
            for a in range(0, todo.size, ROWS_PER_TASK):
                k = todo[a:a + ROWS_PER_TASK]
                tasks.append((np.ascontiguousarray(P[k]), tables, lengths, rows_table[k],
                              np.full(k.size, kind, dtype=np.int64), np.ascontiguousarray(M[k]), smp, s_hi, s_lo,
                              t_end[k], float(study.rtol), int(max_steps)))
                where.append((r, ss[k], ll[k]))
        if keep_stats:
            stats[...] = 0.0
            stats[..., K.S_T_UPLIFT] = stats[..., K.S_T_OVERTURN] = stats[..., K.S_T_REST] = np.nan
            for (r, kind, M, t_end, todo, smp) in jobs:
                stats[r, ss, ll, K.S_T_FINAL] = t_end
        for (r, sk, lk), S in zip(where, executor.map(_rows_task, tasks, desc="fragility, fixed base")):
            bad = S[:, K.S_STATUS] != K.STATUS_OK
            if np.any(bad):
                raise RuntimeError(f"rocking solver did not finish {int(bad.sum())} of {S.shape[0]} runs")
            fails[r, sk, lk] = S[:, K.S_OVERTURNED] > 0
            if keep_stats:
                stats[r, sk, lk] = S
    return (fails, valid, n_int, lifts, stats) if keep_stats else (fails, valid, n_int, lifts)


def _iso_task(task: tuple) -> np.ndarray:
    """One (record, level) on the isolator: (iso, models, motion, factors, t_end, rtol, mus) ->
    (samples, 4) int: overturned, capacity exceeded, finished, uplift (the plate's peak absolute
    acceleration reaches the sample's weaker uplift limit, or the capacity is exceeded). ``mus``:
    each sample's friction (None: the isolator's). The plate alone is run once per distinct scaled
    motion and friction (Coulomb: exact while the statue stays in contact); the coupled system
    only for the samples the plate's absolute acceleration can lift (those lift, by definition)."""
    from dataclasses import replace

    from ..isolator import time_history as ID
    from ..isolator.coupled import simulate_coupled

    iso, models, motion, factors, t_end, rtol, *rest = task
    mus = rest[0] if rest and rest[0] is not None else [iso.mu] * len(models)
    out = np.zeros((len(models), 4), dtype=np.int64)
    plates: dict = {}
    isos: dict = {}
    for s, (m, f, mu) in enumerate(zip(models, factors, mus)):
        mo = motion.scaled(float(f))
        dev = isos.setdefault(float(mu), iso if float(mu) == iso.mu else replace(iso, mu=float(mu)))
        screen = dev.model == "coulomb"
        limit = min(m.uplift_limits)
        if screen:
            key = (float(f), float(mu))
            if key not in plates:
                plates[key] = ID.simulate(dev, mo, t_end=t_end, dt_out=t_end, rtol=rtol)
            pl = plates[key]
            if pl.acc_abs_max < limit * (1.0 - 1e-12):
                cap = int(pl.capacity_exceeded)
                out[s] = (0, cap, 1, cap)
                continue
        try:
            r = simulate_coupled(dev, m, mo, t_end=t_end, dt_out=t_end, rtol=rtol, screen=False,
                                 max_records=1, max_steps=2_000_000)
        except RuntimeError:
            out[s] = (0, 0, 0, 0)
            continue
        cap = bool(r.capacity_exceeded)
        up = screen or cap or r.acc_abs_max >= limit * (1.0 - 1e-12)
        out[s] = (int(r.overturned and not cap), int(cap), 1, int(up))
    return out


def _isolated(iso, model, records, gains, samples, study, executor):
    """(overturned, capacity exceeded, finished, uplift): (R, S, L) bool arrays on the isolator."""
    from ..isolator.device import Isolator

    if not isinstance(iso, Isolator):
        raise InputError("isolator must be an Isolator (statue2model.isolator.device)")
    if model.linearised:
        raise InputError("the isolated runs need the nonlinear rocking model (linearised=False)")
    if not iso.M > model.params.m:
        raise InputError(f"the isolator's supported mass M = {iso.M:g} kg must exceed the statue's mass "
                         f"m = {model.params.m:g} kg")
    R, L = gains.shape
    models = samples.models(model)
    fac = samples.im_factors()
    mus = samples.mu_values(iso.mu)
    mus = None if np.all(mus == iso.mu) else mus
    tasks = [(iso, models, rec.scaled(float(gains[r, j])), fac, rec.end + study.free_time, study.rtol, mus)
             for r, rec in enumerate(records) for j in range(L)]
    if executor is None:
        from ..compute.executors import progress_bar

        bar, res = progress_bar("fragility, isolated", len(tasks), unit="run"), []
        try:
            for t in tasks:
                res.append(_iso_task(t))
                bar.update(1)
        finally:
            bar.close()
    else:
        res = executor.map(_iso_task, tasks, desc="fragility, isolated")
    arr = np.array(res).reshape(R, L, samples.n, 4).transpose(0, 2, 1, 3)
    return arr[..., 0] > 0, arr[..., 1] > 0, arr[..., 2] > 0, arr[..., 3] > 0


def run_fragility(model: RockingModel, records, levels, samples: ParameterSamples, study: FragilityStudy | None = None,
                  isolator=None, executor=None, max_steps: int = 20_000_000,
                  adaptive: AdaptiveLevels | None = None, iso_model: RockingModel | None = None,
                  support=None, design_im: float | None = None) -> FragilityResult:
    """Run and fit a fragility study (module docstring): ``records`` a list of GroundMotion
    (each scaled so that its IM equals each of ``levels``: m/s^2 for PGA, m/s for PGV, times
    the sample's im_factor), ``samples`` the parameter samples, ``isolator`` an Isolator for
    the isolated curves (None: fixed base only). ``executor``: None runs here (numba threads
    for the fixed base, one after the other on the isolator), or an Executor (SerialExecutor,
    ProcessExecutor, DaskExecutor); the numbers are bit-identical either way. ``adaptive``: an
    AdaptiveLevels budget, the levels added round by round around each curve's median until its
    spread is identified (module docstring); None runs ``levels`` as given. ``iso_model``: the body on the
    isolator (None: ``model``; the stack as one body when the device carries the pedestal). ``support``:
    what the statue stands on (assessment/support.py Support): adds the curves of its sliding and, with a
    pedestal, of the pedestal's sliding and overturning (:func:`_support_fails`). ``design_im``: the design
    level (the study's IM), where the fixed-base uplift's choice of curve is checked besides the levels
    (:func:`exact_uplift`; None: the levels only, a reader checks its own level with choose_uplift_curve)."""
    study = FragilityStudy() if study is None else study
    iso_model = model if iso_model is None else iso_model
    if not isinstance(study, FragilityStudy):
        raise InputError("study must be a FragilityStudy")
    if adaptive is not None and not isinstance(adaptive, AdaptiveLevels):
        raise InputError("adaptive must be an AdaptiveLevels (or None)")
    records, lv, ims = _check_inputs(model, records, levels, samples, study)
    if isolator is not None:
        from ..isolator.device import Isolator

        if not isinstance(isolator, Isolator):
            raise InputError("isolator must be an Isolator (statue2model.isolator.device)")
    R, L, S_n = len(records), lv.size, samples.n
    extra = adaptive.max_added if adaptive is not None else 0
    check_study(R, L + extra, S_n, max(_n_samples(r) for r in records), isolator is not None, executor is not None)
    t0 = time.perf_counter()
    stats = {"runs_fixed": 0, "integrated_fixed": 0, "wall_fixed_s": 0.0}
    if isolator is not None:
        stats.update(runs_isolated=0, failed_isolated=0, wall_isolated_s=0.0)
    sides = ("fixed", "isolated") if isolator is not None else ("fixed",)

    def run_side(side, x):
        """{outcome: (R, S, len(x))}, valid (R, S, len(x)) of base ``side`` at levels ``x``."""
        gains = x[None, :] / ims[:, None]          # (R, L): scale of each record at each level
        t = time.perf_counter()
        if side == "fixed":
            f, v, n_int, lifts = _fixed(model, records, gains, samples, study, executor, max_steps)
            stats["runs_fixed"] += R * x.size * S_n
            stats["integrated_fixed"] += n_int
            out = {_C(states.FULL_CONTACT, "fixed"): lifts & v, _C(states.OVERTURNING, "fixed"): f}
            if support is not None:
                sup = _support_fails(support, records, gains, S_n, executor)
                out.update({k: a & v for k, a in sup.items()})
                stats["runs_support"] = stats.get("runs_support", 0) + R * x.size
            stats["wall_fixed_s"] += time.perf_counter() - t
            return out, v
        ot, cap, ok, up = _isolated(isolator, iso_model, records, gains, samples, study, executor)
        stats["runs_isolated"] += R * x.size * S_n
        stats["failed_isolated"] += int((~ok).sum())
        stats["wall_isolated_s"] += time.perf_counter() - t
        return {_C(states.FULL_CONTACT, "isolated"): up, states.OVERTURNING_ALONE_ISOLATED: ot,
                _C(states.CAPACITY, "isolated"): cap, _C(states.OVERTURNING, "isolated"): ot | cap}, ok

    unit = study.bootstrap
    if unit == "auto":
        unit = "records" if R >= MIN_BOOT_RECORDS else "samples"
    fails, valid, ran = {}, {}, {}
    for side in sides:
        out, v = run_side(side, lv)
        fails.update(out)
        valid[side] = v
        ran[side] = np.ones(lv.size, dtype=bool)
    log = None
    if adaptive is not None:
        log = {**adaptive.to_dict(), "initial_levels": lv.copy(), "rounds_run": []}
        added = {side: 0 for side in sides}
        for rnd in range(adaptive.rounds):
            asks, why = {}, {}
            curves = _point_curves(lv, fails, valid, ran)
            cheap = {k for k, c in curves.items() if c.status == "ok" and c.partial >= MIN_PARTIAL}
            if cheap and study.n_boot:       # their bootstrap band, as the final fit will have it
                curves.update(_fit_all(lv, fails, valid, study, unit, ran, only=cheap)[0])
            for k in ADAPT_ORDER:
                if k not in curves:
                    continue
                side = _side(k)
                x = propose_levels(curves[k], study.confidence)
                have = list(lv[ran[side]]) + asks.get(side, [])
                new = [v for v in x if all(abs(math.log(v / h)) >= MIN_GAP for h in have)]
                room = adaptive.max_added - added[side] - len(asks.get(side, []))
                new = new[:max(room, 0)]
                if new:
                    asks.setdefault(side, []).extend(new)
                    why[k] = new
            if not asks:
                break
            entry = {"round": rnd + 1, "asked": {k: np.array(v) for k, v in why.items()}, "ran": {}}
            for side, x in asks.items():
                x = np.sort(np.array(x))
                out, v = run_side(side, x)
                lv, fails, valid, ran = _merge(lv, fails, valid, ran, side, x, out, v)
                added[side] += x.size
                entry["ran"][side] = x
            log["rounds_run"].append(entry)
        log["added"] = dict(added)
    curves, ratio = _fit_all(lv, fails, valid, study, unit, ran)
    if "full_contact_fixed" in curves:
        curves["full_contact_fixed"], ratio = exact_uplift(curves["full_contact_fixed"], uplift_thresholds(model, records, samples, ims),
                                               valid["fixed"], study, unit, ratio, curves.get("full_contact_isolated"),
                                               design_im=design_im)
    if log is not None:
        log["identified"] = {k: bool(c.fitted and c.spread is None) for k, c in curves.items()}
        log["why_not"] = {k: (c.reason or c.spread) for k, c in curves.items()
                          if not (c.fitted and c.spread is None)}
        log = _json_ready(log)
    stats["wall_s"] = time.perf_counter() - t0
    return FragilityResult(study.im, lv, [r.label for r in records], ims, samples, study, fails, valid, curves,
                           ratio, unit, model, isolator, stats, ran, log)


def support_record(item: tuple):
    """One (record, level) of the support's curves: ``item`` = (support, motion) -> its SupportRecord (module
    level: an executor can map it)."""
    support, motion = item
    return support.run(motion)


def _support_fails(support, records, gains, S_n, executor) -> dict:
    """{curve: (R, S, L) bool} of the statue's support at each record's scale ``gains`` (R, L): the statue
    slides beyond its capacity toward either side (on a pedestal, past the top's edge: it falls off), and with a
    pedestal the pedestal slides beyond its allowance or overturns (assessment/support.py; one run per record
    and level, the same for every parameter sample: the friction and the pedestal are not sampled)."""
    R, L = gains.shape
    items = [(support, rec.scaled(float(gains[r, j]))) for r, rec in enumerate(records) for j in range(L)]
    if executor is None:
        runs = [support_record(it) for it in items]
    else:
        runs = executor.map(support_record, items, desc=f"fragility: support, {len(items)} runs")
    cap, pcap = support.capacity, support.pedestal_capacity
    keys = [_C(states.SLIDING, "fixed")]
    if support.stack is not None:
        keys += [_C(states.PEDESTAL_SLIDING, "fixed"), _C(states.PEDESTAL_OVERTURNING, "fixed")]
    out = {k: np.zeros((R, S_n, L), dtype=bool) for k in keys}
    for n, sr in enumerate(runs):
        r, j = divmod(n, L)
        out[keys[0]][r, :, j] = sr.slide_pos >= cap[0] or sr.slide_neg >= cap[1]
        if support.stack is not None:
            out[keys[1]][r, :, j] = sr.ped_slide_pos >= pcap[0] or sr.ped_slide_neg >= pcap[1]
            out[keys[2]][r, :, j] = sr.ped_overturned
    return out


def uplift_thresholds(model, records, samples, ims) -> np.ndarray:
    """(records, samples) PGA (in the study's IM, m/s^2 for PGA) at which each record, scaled to it
    (times the sample's im_factor), first lifts the sample's model on a fixed base:

        x* = IM_r / f_s x min(lim_up,s / max u_g'', lim_down,s / max -u_g'')

    (inf on a side the record never pushes). It is exactly the fixed-base uplift outcome of the study
    (the complement of its ``quiet`` test: uplift at level x iff x > x*), with no levels needed: the
    uplift of a rigid block starts when the ground acceleration reaches the uplift limit on its side.

    >>> from statue2model.geometry.rocking_params import RockingParams
    >>> from statue2model.hazard import motions
    >>> from statue2model.rocking import RockingModel
    >>> from statue2model.rocking.sampling import nominal
    >>> m = RockingModel.housner(RockingParams.rectangular_block(0.05, 0.25, 10.0))   # lifts at 1.962 m/s^2
    >>> rec = motions.sine_pulse(3.0, 2.0)                                            # +-3 m/s^2, PGA 3
    >>> [round(float(x), 4) for x in uplift_thresholds(m, [rec], nominal(1), np.array([3.0]))[0]]
    [1.962]
    """
    lims = np.array([m.uplift_limits for m in samples.models(model)], dtype=float)      # (S, 2)
    fac = samples.im_factors()
    out = np.empty((len(records), samples.n))
    for r, rec in enumerate(records):
        hi, lo = (float(v) for v in rec.extremes())
        up = lims[:, 0] / hi if hi > 0 else np.full(samples.n, np.inf)
        dn = lims[:, 1] / -lo if lo < 0 else np.full(samples.n, np.inf)
        out[r] = float(ims[r]) / fac * np.minimum(up, dn)
    return out


def exact_uplift(cv, x, valid, study, unit, ratio, iso_cv=None, design_im=None):
    """The fixed-base uplift curve refitted on the exact thresholds ``x`` (records, samples) of
    :func:`uplift_thresholds` (runs the study counted, ``valid`` at any level): the lognormal's
    maximum-likelihood fit to exact values, median exp(mean ln x*), beta the standard deviation of
    ln x*; equal thresholds (a symmetric base under records that push both ways to their PGA) are a
    deterministic threshold: beta 0 there (BETA_MIN in the fit: P steps from 0 to 1 at x*). Its band:
    the bootstrap over the records (or samples) of the same estimates. The counts per level stay
    (the plot's points; they are the same outcome).

    The curve reported is chosen by UPLIFT_RULE (:func:`choose_uplift_curve`, checked at the levels and at
    ``design_im``): the lognormal only where no threshold is tied and its P lies inside the 95 % Wilson
    interval of the count of thresholds at or below each level; else the empirical step CDF of the
    thresholds (:func:`distinct_thresholds`), status EMPIRICAL, with the reason in ``choice``. The ratio
    "full_contact" is re-taken on the chosen curve's median, without a band (the isolated median's band
    is in its own row). Returns (curve, ratio)."""
    ok = valid.any(axis=2)                       # runs counted at some level (applicable)
    x = np.where(ok, x, np.nan)
    fin = np.isfinite(x)
    if fin.sum() < 2:
        return cv, ratio
    lx = np.log(x[fin])
    med, beta = float(np.exp(lx.mean())), float(lx.std())
    note = None
    if beta < BETA_MIN:
        beta, note = BETA_MIN, "a deterministic threshold: every run lifts at the same PGA"
    rng = np.random.default_rng(study.seed)
    axis_n = x.shape[0] if unit == "records" else x.shape[1]
    meds, betas = [], []
    for _ in range(study.n_boot if axis_n >= 2 else 0):
        pick = rng.integers(0, axis_n, axis_n)
        xb = x[pick] if unit == "records" else x[:, pick]
        lb = np.log(xb[np.isfinite(xb)])
        if lb.size >= 2:
            meds.append(float(np.exp(lb.mean())))
            betas.append(max(float(lb.std()), BETA_MIN))
    lo_q, hi_q = 50 * (1 - study.confidence), 50 * (1 + study.confidence)
    mci = tuple(float(v) for v in np.percentile(meds, [lo_q, hi_q])) if meds else (float("nan"),) * 2
    bci = tuple(float(v) for v in np.percentile(betas, [lo_q, hi_q])) if betas else (float("nan"),) * 2
    band = np.full((2, cv.levels.size), np.nan)
    if meds:
        P = np.array([lognormal_cdf(cv.levels, m_, b_) for m_, b_ in zip(meds, betas)])
        band = np.percentile(P, [lo_q, hi_q], axis=0)
    exact = FragilityCurve(cv.outcome, cv.levels, cv.n_fail, cv.n_trials, med, beta, EXACT, median_ci=mci,
                           beta_ci=bci, band_lo=band[0], band_hi=band[1],
                           median_ci_note=None if meds else "no band: one unit to resample", beta_ci_note=note,
                           beta_profile=(float(beta), float(beta)),
                           beta_profile_note="exact thresholds: beta is their log standard deviation, no profile",
                           thresholds=distinct_thresholds(x),
                           choice={"confidence": float(study.confidence), "n_runs": int(fin.sum())})
    exact = choose_uplift_curve(exact, [] if design_im is None else [float(design_im)])
    med = exact.median
    ratio = dict(ratio)
    if iso_cv is not None and "full_contact" in ratio:
        value = iso_cv.median / med if iso_cv.fitted and math.isfinite(iso_cv.median) else None
        ratio["full_contact"] = {**ratio["full_contact"], "value": value, "ci": [None, None],
                           "ci_note": "no band: the fixed-base uplift median is exact per record; the isolated "
                                      "median's band is in its own row"}
    return exact, ratio


def _merge(lv, fails, valid, ran, side, x, out, v):
    """The arrays with base ``side``'s runs at the new levels ``x`` (outcomes ``out``, ``v``) put in
    the union of the levels; the other base has not run a level that is new to the union."""
    union = np.union1d(lv, x)
    old_at = np.searchsorted(union, lv)
    new_at = np.searchsorted(union, x)
    shape = lambda a: a.shape[:2] + (union.size,)      # noqa: E731
    f2, v2, r2 = {}, {}, {}
    for k, a in fails.items():
        b = np.zeros(shape(a), dtype=bool)
        b[..., old_at] = a
        if k in out:
            b[..., new_at] = out[k]
        f2[k] = b
    for sd, a in valid.items():
        b = np.zeros(shape(a), dtype=bool)
        b[..., old_at] = a
        if sd == side:
            b[..., new_at] = v
        v2[sd] = b
    for sd, m in ran.items():
        b = np.zeros(union.size, dtype=bool)
        b[old_at] = m
        if sd == side:
            b[new_at] = True
        r2[sd] = b
    return union, f2, v2, r2


def _point_curves(lv, fails, valid, ran) -> dict:
    """name -> FragilityCurve with the point fit only (no bands), on the levels its base ran."""
    out = {}
    for k, f in fails.items():
        side = _side(k)
        m = ran[side]
        z = (f & valid[side]).sum(axis=(0, 1))[m]
        n = valid[side].sum(axis=(0, 1))[m]
        med, beta, st = fit_lognormal(lv[m], z, n)
        out[k] = FragilityCurve(k, lv[m], z.astype(int), n.astype(int), med, beta, st)
    return out


def propose_levels(cv, confidence: float = 0.90) -> list:
    """The levels curve ``cv`` asks for in a round of adaptive levels (module docstring): [] when
    its spread is identified or it has no fit, else up to three, m exp(-s), m, m exp(+s), inside
    its bracket (IM units; not yet checked against the levels already run).

    >>> lv = np.array([1.0, 2.0, 4.0, 8.0])
    >>> c = FragilityCurve("overturn", lv, np.array([0, 0, 7, 7]), np.full(4, 7), 2.8, 1e-3, "step")
    >>> [round(float(x), 3) for x in propose_levels(c)]       # a step: 2.8 x 2^(-1/4), 2.8, 2.8 x 2^(1/4)
    [2.355, 2.8, 3.33]
    """
    if not cv.fitted or identified_reason(cv, confidence) is None:
        return []
    lv = np.asarray(cv.levels, dtype=float)
    with np.errstate(invalid="ignore", divide="ignore"):
        frac = np.where(cv.n_trials > 0, cv.n_fail / np.maximum(cv.n_trials, 1), np.nan)
    m = float(cv.median)
    below = lv[(lv < m) & (frac == 0)]
    above = lv[(lv > m) & (frac >= 1)]
    # a side without such a level (the median beyond the levels run, or no level all failing /
    # none failing on that side) is open: the bracket reaches 2 s0 beyond the median or the levels
    s0 = 2.0 * max(float(cv.beta), 0.05)
    x0 = float(below.max()) if below.size else min(float(lv.min()), m) * math.exp(-s0)
    x1 = float(above.min()) if above.size else max(float(lv.max()), m) * math.exp(s0)
    if not x1 > x0:
        return []
    w = math.log(x1 / x0)
    s = w / 4 if cv.status == "step" else max(float(cv.beta), w / 8)
    lo, hi = x0 * math.exp(w / 8), x1 * math.exp(-w / 8)
    out = []
    for v in (m * math.exp(-s), m, m * math.exp(s)):
        v = min(max(v, lo), hi)
        if all(abs(math.log(v / o)) >= MIN_GAP for o in out):
            out.append(v)
    return out


def _fit_all(lv, fails, valid, study, unit, ran=None, only=None):
    """(curves, ratio) of the outcomes ``fails`` (see FragilityResult) on the levels each base ran
    (``ran``; None: all); ``only``: fit and bootstrap just these curves (the adaptive rounds)."""
    axis = 1 if unit == "records" else 0          # summed away: the other unit is resampled
    ran = ran or {}
    if only is not None:
        fails = {k: f for k, f in fails.items() if k in only}
    mask = {k: ran.get(_side(k), np.ones(lv.size, dtype=bool)) for k in fails}
    lvk = {k: lv[mask[k]] for k in fails}
    # counts per resampling unit: (units, L_k), on the levels each curve's base ran
    z = {k: (f & valid[_side(k)]).sum(axis=axis)[:, mask[k]] for k, f in fails.items()}
    n = {k: valid[_side(k)].sum(axis=axis)[:, mask[k]] for k in fails}
    fits = {k: fit_lognormal(lvk[k], z[k].sum(0), n[k].sum(0)) for k in fails}
    # (ratio key, isolated curve, fixed curve): the ratios of medians are named by the limit state
    pairs = states.RATIOS
    rng = np.random.default_rng(study.seed)
    n_units = next(iter(valid.values())).shape[axis ^ 1]
    n_boot = study.n_boot if n_units >= 2 else 0     # one unit: every replicate the same, no band
    no_band = None
    if study.n_boot and not n_boot:
        no_band = (f"no band: the bootstrap over the {unit} has one unit to resample; use at least "
                   f"{MIN_BOOT_RECORDS} records or 2 parameter samples")
    # each replicate's (median, beta): a replicate with no failure keeps its median's place above
    # the levels (inf), one that failed everywhere below them (0); "one level" / "no runs": nan
    boot = {k: np.full((n_boot, 2), np.nan) for k in fails}
    picks = np.array([rng.integers(0, n_units, n_units) for _ in range(n_boot)], dtype=np.int64).reshape(
        n_boot, n_units)
    if n_boot:
        for k in fails:
            start = fits[k][:2] if fits[k][2] in ("ok", "step") else None
            med, beta, st = fit_lognormal_many(lvk[k], z[k][picks].sum(1), n[k][picks].sum(1), start=start)
            st = np.array(st)
            med = np.where(st == "no failures", np.inf, np.where(st == "all failed", 0.0, med))
            boot[k][:, 0], boot[k][:, 1] = med, beta
    lo_q, hi_q = 50 * (1 - study.confidence), 50 * (1 + study.confidence)
    curves = {}
    for k in fails:
        med, beta, st = fits[k]
        lvc = lvk[k]
        bands = np.full((2, lvc.size), np.nan)
        mci = bci = (float("nan"), float("nan"))
        mnote = bnote = no_band
        undefined = {}
        if st not in ("ok", "step"):
            mnote = bnote = None if not study.n_boot else f"no band: the median is undefined ({REASONS[st]})"
        elif n_boot:
            bm, bb = boot[k][:, 0], boot[k][:, 1]
            undefined = {"replicates": n_boot, "no failures": int(np.sum(bm == np.inf)),
                         "all failed": int(np.sum(bm == 0.0)), "not identified": int(np.sum(np.isnan(bm))),
                         "steps": int(np.sum(bb <= BETA_MIN * 1.0001))}
            ordered = ~np.isnan(bm)              # fitted, or above / below the levels
            if ordered.any():
                from scipy.special import ndtr

                m_b, b_b = bm[ordered][:, None], bb[ordered][:, None]
                inner = (m_b > 0) & (m_b < np.inf)
                with np.errstate(invalid="ignore", divide="ignore"):
                    u = np.log(lvc[None, :] / np.where(inner, m_b, 1.0)) / np.where(inner, b_b, 1.0)
                P = np.where(inner, ndtr(u), np.where(m_b == np.inf, 0.0, 1.0))
                bands = np.percentile(P, [lo_q, hi_q], axis=0)
            mci, mnote = _ordered_ci(bm, lo_q, hi_q, n_boot,
                                     hi_why="{k} of {n} replicates had no failure (median above the levels run)",
                                     lo_why="{k} of {n} replicates failed at every level (median below the levels)",
                                     out_why="runs at one level only")
            fb = bb[np.isfinite(bb)]
            if fb.size:
                bci = tuple(float(x) for x in np.percentile(fb, [lo_q, hi_q]))
            bnote = None if fb.size == n_boot else (
                f"on the {fb.size} of {n_boot} replicates with a fitted curve" if fb.size else
                "no band: no replicate has a fitted curve")
        zk, nk = z[k].sum(0).astype(int), n[k].sum(0).astype(int)
        prof, pnote = beta_profile_band(lvc, zk, nk, study.confidence)
        curves[k] = FragilityCurve(k, lvc, zk, nk, med, beta, st, mci, bci, bands[0], bands[1], mnote, bnote,
                                   undefined, prof, pnote)
    ratio = {}
    for name, iso_k, fix_k in pairs:
        if iso_k not in fails or fix_k not in fails:
            continue
        ci_, cf_ = curves[iso_k], curves[fix_k]
        value = ci_.median / cf_.median if ci_.fitted and cf_.fitted else None
        ci, ci_note = (float("nan"), float("nan")), no_band
        if value is None:
            ci_note = None if not study.n_boot else "no band: the ratio is undefined"
        elif n_boot:
            with np.errstate(invalid="ignore", divide="ignore"):
                rr = boot[iso_k][:, 0] / boot[fix_k][:, 0]     # inf / 0 order like the medians; nan: unknown
            ci, ci_note = _ordered_ci(rr, lo_q, hi_q, n_boot,
                                      hi_why="in {k} of {n} replicates the isolated median lies above the levels "
                                             "run or the fixed one below them",
                                      lo_why="in {k} of {n} replicates the fixed median lies above the levels run "
                                             "or the isolated one below them",
                                      out_why="both medians above, or both below, the levels run")
        why = [f"isolated {ci_.reason}" if ci_.reason else "", f"fixed base {cf_.reason}" if cf_.reason else ""]
        ratio[name] = {"value": value, "ci": [_finite(x) for x in ci], "isolated": iso_k, "fixed": fix_k,
                       "note": None if value is not None else
                       "undefined: " + ", ".join(w for w in why if w) + " in the levels run",
                       "ci_note": ci_note}
    return curves, ratio


def _ordered_ci(values, lo_q, hi_q, n_boot, hi_why: str, lo_why: str,
                out_why: str = "fit not identified") -> tuple[tuple, str | None]:
    """((lo, hi), note): the percentile band of bootstrap ``values`` that may hold +inf (above the
    levels run) and 0 (below them), ordered as such; nan values (not identified) are left out. An
    end that falls on inf or 0 is not identified: nan, and the note counts the replicates there
    (``hi_why`` / ``lo_why`` formatted with k, n); the note also counts those left out (``out_why``)."""
    v = np.asarray(values, dtype=float)
    keep = v[~np.isnan(v)]
    notes = []
    if keep.size < v.size:
        notes.append(f"{v.size - keep.size} of {n_boot} replicates left out ({out_why})")
    if not keep.size:
        return (float("nan"), float("nan")), "no band: no replicate identified"
    ends = [float(x) for x in np.percentile(keep, [lo_q, hi_q], method="inverted_cdf")]
    for i, which in enumerate(("lower", "upper")):
        if ends[i] == np.inf:
            notes.append(f"{which} end not identified: " + hi_why.format(k=int(np.sum(keep == np.inf)), n=n_boot))
        elif not ends[i] > 0:
            notes.append(f"{which} end not identified: " + lo_why.format(k=int(np.sum(keep == 0.0)), n=n_boot))
        if not 0 < ends[i] < np.inf:
            ends[i] = float("nan")
    lo, hi = ends
    return (lo, hi), ("; ".join(notes) or None)
