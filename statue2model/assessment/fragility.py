"""Fragility: the probability of failure against the intensity of the ground motion,
on a fixed base and on the isolator, fitted as lognormal curves.

A study runs every record (a list of :class:`~statue2model.hazard.motions.GroundMotion`)
scaled to every intensity level (PGA in m/s^2, or PGV in m/s) for every parameter
sample (:mod:`statue2model.rocking.sampling`): records x levels x samples runs. Each
run's outcome is a yes / no per *outcome*, each with its own curve:

* ``overturn`` - the body overturns on a fixed base (rocking kernel, run_batch);
* ``overturn_isolated`` - it overturns on the isolator (coupled plate + statue,
  :func:`~statue2model.isolator.coupled.simulate_coupled`, end_stop "stop": a run that
  first exceeds the capacity stops there and is counted below, not here);
* ``capacity_exceeded`` - the top plate passes the isolator's capacity (issue [8]);
* ``failure_isolated`` - either of the two (the conservative failure on the isolator).

Fit (Baker 2015, Earthquake Spectra 31(1)): at level x_j, z_j of n_j runs fail;
P(fail | x) = Phi(ln(x / theta) / beta), theta (median) and beta (dispersion) maximise
the binomial likelihood sum_j [z_j ln P_j + (n_j - z_j) ln(1 - P_j)] (a coarse grid, then
scipy.optimize TNC, bounded Newton with the analytic gradient, on ln theta, ln beta; beta
is bounded to [BETA_MIN, BETA_MAX]).
Runs where the rocking model does not apply (the body slides first,
:meth:`RockingModel.applicability`) or the solver did not finish are left out of n_j.
Status of a fit: "ok"; "step" (the failures are separated by one level: beta at BETA_MIN);
undefined (median and beta nan, written null with the reason of REASONS): "no failures"
(median above the levels), "all failed" (below them), "one level" (runs at one level
only: any spread fits one point, so neither median nor beta is identified), "no runs".
A fit needs runs at two levels or more, at least one failure and one survival.

Confidence bands: bootstrap (``n_boot`` replicates, ``seed``) over the records (the
dominant, independent input) when there are at least MIN_BOOT_RECORDS of them, else over
the parameter samples; each replicate re-fits the curves; the bands are the
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
>>> c = res.curves["overturn"]
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

IMS = ("pga", "pgv")
FIXED = ("overturn",)
LABELS = {"overturn": "overturning, fixed base", "overturn_isolated": "overturning on the isolator",
          "capacity_exceeded": "isolator capacity exceeded",
          "failure_isolated": "failure on the isolator (overturning or capacity)"}
BETA_MIN, BETA_MAX = 1e-3, 5.0
REASONS = {"no runs": "no run counted at any level", "no failures": "no failure at any level",
           "all failed": "failure at every level", "one level": "one level: spread not identified"}
"""Why a fit's median and beta are undefined, by status (the text written beside a null)."""
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


# --- the lognormal fit ----------------------------------------------------------------
def _nll(ln_theta, ln_beta, lnx, z, n):
    """Negative binomial log-likelihood; ln_theta, ln_beta broadcast against (..., 1)."""
    from scipy.special import log_ndtr

    u = (lnx - ln_theta) / np.exp(ln_beta)
    return -(z * log_ndtr(u) + (n - z) * log_ndtr(-u)).sum(axis=-1)


def _nll_grad(q, lnx, z, n):
    """The negative log-likelihood at q = (ln theta, ln beta) and its gradient."""
    from scipy.special import log_ndtr

    beta = math.exp(q[1])
    u = (lnx - q[0]) / beta
    lp, lm = log_ndtr(u), log_ndtr(-u)
    lphi = -0.5 * u * u - 0.5 * math.log(2 * math.pi)
    dll = z * np.exp(lphi - lp) - (n - z) * np.exp(lphi - lm)      # d(log-likelihood)/du
    f = -(z * lp + (n - z) * lm).sum()
    return f, np.array([(dll / beta).sum(), (dll * u).sum()])


def fit_lognormal(levels, n_fail, n_trials) -> tuple[float, float, str]:
    """(median, beta, status) of the maximum-likelihood lognormal curve through the binomial
    counts (see the module docstring); median and beta are nan unless status is "ok" or "step"
    (the others' reasons: REASONS). Identified only with runs at two levels or more, at least
    one failure and one survival.

    >>> fit_lognormal([5.0], [3], [7])           # one point: any beta passes through it
    (nan, nan, 'one level')
    >>> fit_lognormal([1.0, 2.0, 4.0], [0, 0, 0], [7, 7, 7])[2], REASONS["no failures"]
    ('no failures', 'no failure at any level')
    """
    from scipy.optimize import minimize

    x = np.asarray(levels, dtype=float)
    z = np.asarray(n_fail, dtype=float)
    n = np.asarray(n_trials, dtype=float)
    keep = n > 0
    x, z, n = x[keep], z[keep], n[keep]
    nan = float("nan")
    if x.size == 0:
        return nan, nan, "no runs"
    if z.sum() == 0:
        return nan, nan, "no failures"
    if z.sum() == n.sum():
        return nan, nan, "all failed"
    if np.unique(x).size < 2:
        return nan, nan, "one level"
    lnx = np.log(x)
    lo, hi = lnx.min() - 3.0, lnx.max() + 3.0
    bl, bh = math.log(BETA_MIN), math.log(BETA_MAX)
    gt = np.linspace(lo, hi, 61)[:, None, None]
    gb = np.linspace(bl, bh, 31)[None, :, None]
    f = _nll(gt, gb, lnx, z, n)
    i, j = np.unravel_index(np.argmin(f), f.shape)
    start = np.array([gt[i, 0, 0], gb[0, j, 0]])
    res = minimize(_nll_grad, start, args=(lnx, z, n), jac=True, method="TNC",
                   bounds=[(lo, hi), (bl, bh)], options={"ftol": 1e-14, "gtol": 1e-10})
    q = res.x if res.fun <= f[i, j] else start
    beta = float(np.exp(q[1]))
    return float(np.exp(q[0])), beta, ("step" if beta <= BETA_MIN * 1.0001 else "ok")


def lognormal_cdf(x, median: float, beta: float) -> np.ndarray:
    """Phi(ln(x / median) / beta); nan if the curve is undefined."""
    from scipy.stats import norm

    x = np.asarray(x, dtype=float)
    if not (math.isfinite(median) and math.isfinite(beta)):
        return np.full(x.shape, np.nan)
    return norm.cdf(np.log(x / median) / beta)


@dataclass(frozen=True, eq=False)
class FragilityCurve:
    """One outcome: counts per level, the fit, its bootstrap bands (``confidence`` level).
    levels (L,) in the IM's unit; n_fail, n_trials (L,) int; median (IM unit), beta; status
    (``reason``: why median and beta are nan, None when fitted); median_ci, beta_ci: (lo, hi),
    an end nan when not identified, ``median_ci_note`` / ``beta_ci_note`` saying why (or
    what the band was computed on); band_lo, band_hi (L,): P at each level (nan when the
    curve is undefined); ``boot_undefined``: replicates per undefined status."""

    outcome: str
    levels: np.ndarray
    n_fail: np.ndarray
    n_trials: np.ndarray
    median: float
    beta: float
    status: str
    median_ci: tuple = (float("nan"), float("nan"))
    beta_ci: tuple = (float("nan"), float("nan"))
    band_lo: np.ndarray = None
    band_hi: np.ndarray = None
    median_ci_note: str | None = None
    beta_ci_note: str | None = None
    boot_undefined: dict = field(default_factory=dict)

    @property
    def fitted(self) -> bool:
        """Whether median and beta are defined (status "ok" or "step")."""
        return self.status in ("ok", "step")

    @property
    def reason(self) -> str | None:
        """Why the fit is undefined (REASONS), None when it is defined."""
        return None if self.fitted else REASONS.get(self.status, self.status)

    @property
    def fraction(self) -> np.ndarray:
        with np.errstate(invalid="ignore", divide="ignore"):
            return np.where(self.n_trials > 0, self.n_fail / np.maximum(self.n_trials, 1), np.nan)

    def probability(self, x) -> np.ndarray:
        """The fitted P(failure | IM = x)."""
        return lognormal_cdf(x, self.median, self.beta)

    def to_dict(self) -> dict:
        """JSON-ready; an undefined number is None with its reason beside it (``reason`` for the
        fit, its fitted P and bands; ``median_ci_note``, ``beta_ci_note`` for a band end)."""
        return {"outcome": self.outcome, "label": LABELS[self.outcome], "median": _finite(self.median),
                "beta": _finite(self.beta), "status": self.status, "reason": self.reason,
                "median_ci": [_finite(x) for x in self.median_ci], "median_ci_note": self.median_ci_note,
                "beta_ci": [_finite(x) for x in self.beta_ci], "beta_ci_note": self.beta_ci_note,
                "bootstrap_undefined": dict(self.boot_undefined),
                "levels": self.levels, "n_fail": self.n_fail, "n_trials": self.n_trials,
                "fraction": self.fraction, "fitted": self.probability(self.levels),
                "band_lo": self.band_lo, "band_hi": self.band_hi}


@dataclass(frozen=True, eq=False)
class FragilityResult:
    """A study's outcome. ``fails[name]``: (records, samples, levels) bool, ``valid``:
    (records, samples, levels) bool (runs counted: applicable and finished; one array
    per side, "fixed" and "isolated"); ``curves[name]``: FragilityCurve; ``ratio``:
    {"overturn": ..., "failure": ...} each {"value", "ci"}: median isolated / median fixed
    (overturning on the isolator, resp. any isolated failure, against fixed-base overturning)."""

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

    @property
    def unit(self) -> str:
        return "m/s2" if self.im == "pga" else "m/s"

    def to_dict(self) -> dict:
        per_record = {name: {"n_fail": f.sum(axis=1), "n_trials": self.valid[_side(name)].sum(axis=1)}
                      for name, f in self.fails.items()}
        return {"im": self.im, "unit": self.unit, "levels": self.levels, "study": self.study.to_dict(),
                "bootstrap_unit": self.bootstrap_unit, "n_records": len(self.record_labels),
                "records": [{"label": lab, self.im: float(v)} for lab, v in zip(self.record_labels, self.record_im)],
                "samples": self.samples.to_dict(), "model": self.model.to_dict(),
                "isolator": None if self.isolator is None else self.isolator.to_dict(),
                "curves": {k: c.to_dict() for k, c in self.curves.items()}, "ratio_of_medians": self.ratio,
                "per_record": per_record, "stats": self.stats}

    def csv_rows(self) -> tuple[list, list]:
        """(header, rows): one row per outcome and level; an undefined number is an empty cell
        (never nan or inf), the curve's ``reason`` says why."""
        header = ["outcome", f"{self.im}_{self.unit.replace('/', '_')}", "n_fail", "n_trials", "fraction",
                  "fitted_p", "band_lo", "band_hi", "median", "beta", "status", "reason"]
        rows = []
        for c in self.curves.values():
            fit = c.probability(c.levels)
            blo = np.full(c.levels.shape, np.nan) if c.band_lo is None else c.band_lo
            bhi = np.full(c.levels.shape, np.nan) if c.band_hi is None else c.band_hi
            for j, x in enumerate(c.levels):
                rows.append([c.outcome, f"{x:.9g}", int(c.n_fail[j]), int(c.n_trials[j]), _g(c.fraction[j]),
                             _g(fit[j]), _g(blo[j]), _g(bhi[j]), _g(c.median), _g(c.beta), c.status,
                             c.reason or ""])
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
                out.append(f"{LABELS[c.outcome]}: median {c.median:.4g} {u}{mci}, beta {c.beta:.3f}{bci}"
                           f"{' (a step: failures separated by one level)' if c.status == 'step' else ''}")
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


def _finite(v):
    """v as a float, or None when it is not finite (JSON: inf has no spelling; null)."""
    return float(v) if v is not None and np.isfinite(v) else None


def _g(v) -> str:
    return "" if v is None or not np.isfinite(v) else f"{v:.6g}"


def _band(ci, spec: str) -> str:
    """'lo, hi' of a band whose ends may be None / non-finite (not identified): such an end is '-'."""
    return ", ".join("-" if v is None or not np.isfinite(v) else format(float(v), spec) for v in ci)


def _side(name: str) -> str:
    return "fixed" if name in FIXED else "isolated"


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
    """(fails, valid, n_integrated): (R, S, L) bool arrays of the fixed-base runs; with
    ``keep_stats`` a fourth item, the runs' statistics (R, S, L, N_S) (kernel.S_*; a run
    not integrated has zeros and nan there, as run_batch leaves it)."""
    from ..rocking.batch import restitution_tables, suffix_extremes

    R, L = gains.shape
    S_n = samples.n
    models = samples.models(model)
    fac = samples.im_factors()
    fails = np.zeros((R, S_n, L), dtype=bool)
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
    return (fails, valid, n_int, stats) if keep_stats else (fails, valid, n_int)


def _iso_task(task: tuple) -> np.ndarray:
    """One (record, level) on the isolator: (iso, models, motion, factors, t_end, rtol) ->
    (samples, 3) int: overturned, capacity exceeded, finished. The plate alone is run once
    per distinct scaled motion (Coulomb: exact while the statue stays in contact); the
    coupled system only for the samples the plate's absolute acceleration can lift."""
    from ..isolator import time_history as ID
    from ..isolator.coupled import simulate_coupled

    iso, models, motion, factors, t_end, rtol = task
    out = np.zeros((len(models), 3), dtype=np.int64)
    plates: dict = {}
    for s, (m, f) in enumerate(zip(models, factors)):
        mo = motion.scaled(float(f))
        screen = iso.model == "coulomb"
        if screen:
            if f not in plates:
                plates[f] = ID.simulate(iso, mo, t_end=t_end, dt_out=t_end, rtol=rtol)
            pl = plates[f]
            if pl.acc_abs_max < min(m.uplift_limits) * (1.0 - 1e-12):
                out[s] = (0, int(pl.capacity_exceeded), 1)
                continue
        try:
            r = simulate_coupled(iso, m, mo, t_end=t_end, dt_out=t_end, rtol=rtol, screen=False,
                                 max_records=1, max_steps=2_000_000)
        except RuntimeError:
            out[s] = (0, 0, 0)
            continue
        cap = bool(r.capacity_exceeded)
        out[s] = (int(r.overturned and not cap), int(cap), 1)
    return out


def _isolated(iso, model, records, gains, samples, study, executor):
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
    tasks = [(iso, models, rec.scaled(float(gains[r, j])), fac, rec.end + study.free_time, study.rtol)
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
    arr = np.array(res).reshape(R, L, samples.n, 3).transpose(0, 2, 1, 3)
    return arr[..., 0] > 0, arr[..., 1] > 0, arr[..., 2] > 0


def run_fragility(model: RockingModel, records, levels, samples: ParameterSamples, study: FragilityStudy | None = None,
                  isolator=None, executor=None, max_steps: int = 20_000_000) -> FragilityResult:
    """Run and fit a fragility study (module docstring): ``records`` a list of GroundMotion
    (each scaled so that its IM equals each of ``levels``: m/s^2 for PGA, m/s for PGV, times
    the sample's im_factor), ``samples`` the parameter samples, ``isolator`` an Isolator for
    the isolated curves (None: fixed base only). ``executor``: None runs here (numba threads
    for the fixed base, one after the other on the isolator), or an Executor (SerialExecutor,
    ProcessExecutor, DaskExecutor); the numbers are bit-identical either way."""
    study = FragilityStudy() if study is None else study
    if not isinstance(study, FragilityStudy):
        raise InputError("study must be a FragilityStudy")
    records, lv, ims = _check_inputs(model, records, levels, samples, study)
    if isolator is not None:
        from ..isolator.device import Isolator

        if not isinstance(isolator, Isolator):
            raise InputError("isolator must be an Isolator (statue2model.isolator.device)")
    R, L, S_n = len(records), lv.size, samples.n
    check_study(R, L, S_n, max(_n_samples(r) for r in records), isolator is not None, executor is not None)
    gains = lv[None, :] / ims[:, None]          # (R, L): scale of each record at each level
    t0 = time.perf_counter()
    fails, valid = {}, {}
    f, v, n_int = _fixed(model, records, gains, samples, study, executor, max_steps)
    fails["overturn"], valid["fixed"] = f, v
    t_fixed = time.perf_counter() - t0
    stats = {"runs_fixed": R * L * S_n, "integrated_fixed": n_int, "wall_fixed_s": t_fixed}
    if isolator is not None:
        t1 = time.perf_counter()
        ot, cap, ok = _isolated(isolator, model, records, gains, samples, study, executor)
        fails.update(overturn_isolated=ot, capacity_exceeded=cap, failure_isolated=ot | cap)
        valid["isolated"] = ok
        stats.update(runs_isolated=R * L * S_n, failed_isolated=int((~ok).sum()),
                     wall_isolated_s=time.perf_counter() - t1)
    unit = study.bootstrap
    if unit == "auto":
        unit = "records" if R >= MIN_BOOT_RECORDS else "samples"
    curves, ratio = _fit_all(lv, fails, valid, study, unit)
    stats["wall_s"] = time.perf_counter() - t0
    return FragilityResult(study.im, lv, [r.label for r in records], ims, samples, study, fails, valid, curves,
                           ratio, unit, model, isolator, stats)


def _fit_all(lv, fails, valid, study, unit):
    axis = 1 if unit == "records" else 0          # summed away: the other unit is resampled
    # counts per resampling unit: (units, L)
    z = {k: (f & valid[_side(k)]).sum(axis=axis) for k, f in fails.items()}
    n = {k: valid[_side(k)].sum(axis=axis) for k in fails}
    fits = {k: fit_lognormal(lv, z[k].sum(0), n[k].sum(0)) for k in fails}
    pairs = [("overturn", "overturn_isolated", "overturn"), ("failure", "failure_isolated", "overturn")]
    rng = np.random.default_rng(study.seed)
    n_units = next(iter(z.values())).shape[0]
    n_boot = study.n_boot if n_units >= 2 else 0     # one unit: every replicate the same, no band
    no_band = None
    if study.n_boot and not n_boot:
        no_band = (f"no band: the bootstrap over the {unit} has one unit to resample; use at least "
                   f"{MIN_BOOT_RECORDS} records or 2 parameter samples")
    # each replicate's (median, beta): a replicate with no failure keeps its median's place above
    # the levels (inf), one that failed everywhere below them (0); "one level" / "no runs": nan
    boot = {k: np.full((n_boot, 2), np.nan) for k in fails}
    from ..compute.executors import progress_bar

    bar = progress_bar("fragility, bootstrap", n_boot, unit="replicate")
    for b in range(n_boot):
        bar.update(1)
        pick = rng.integers(0, n_units, n_units)
        for k in fails:
            med, beta, st = fit_lognormal(lv, z[k][pick].sum(0), n[k][pick].sum(0))
            if st == "no failures":
                med = np.inf
            elif st == "all failed":
                med = 0.0
            boot[k][b] = (med, beta)
    bar.close()
    lo_q, hi_q = 50 * (1 - study.confidence), 50 * (1 + study.confidence)
    curves = {}
    for k in fails:
        med, beta, st = fits[k]
        bands = np.full((2, lv.size), np.nan)
        mci = bci = (float("nan"), float("nan"))
        mnote = bnote = no_band
        undefined = {}
        if st not in ("ok", "step"):
            mnote = bnote = None if not study.n_boot else f"no band: the median is undefined ({REASONS[st]})"
        elif n_boot:
            bm, bb = boot[k][:, 0], boot[k][:, 1]
            undefined = {"replicates": n_boot, "no failures": int(np.sum(bm == np.inf)),
                         "all failed": int(np.sum(bm == 0.0)), "not identified": int(np.sum(np.isnan(bm)))}
            ordered = ~np.isnan(bm)              # fitted, or above / below the levels
            if ordered.any():
                P = np.empty((int(ordered.sum()), lv.size))
                for i, (m_b, b_b) in enumerate(zip(bm[ordered], bb[ordered])):
                    P[i] = lognormal_cdf(lv, m_b, b_b) if 0.0 < m_b < np.inf else (0.0 if m_b == np.inf else 1.0)
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
        curves[k] = FragilityCurve(k, lv, z[k].sum(0).astype(int), n[k].sum(0).astype(int), med, beta, st,
                                   mci, bci, bands[0], bands[1], mnote, bnote, undefined)
    ratio = {}
    for name, iso_k, fix_k in pairs:
        if iso_k not in fails:
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
