"""Sweeps of one record or one parameter: the response as a distribution.

* :func:`variability` - maximum rotation |theta|max/delta of one record scaled
  to a range of PGA values (thesis Fig. 70-75).
* :func:`parameter_sweep` - the same motion for many values of one model
  parameter (e.g. 49 values of theta_R, Table 24), with the distribution of the
  peak response.

Where the body slides before it rocks (:attr:`RockingModel.slides_first`) and a run's
ground acceleration exceeds mu_s g, the run is not integrated: code NOT_APPLICABLE_CODE,
|theta|max/delta nan, left out of the summary.

Example
-------
>>> import numpy as np
>>> from statue2model.geometry.rocking_params import RockingParams
>>> from statue2model.hazard import motions
>>> from statue2model.rocking import RockingModel
>>> a1 = RockingParams.rectangular_block(0.0384, 0.2, 1.286)
>>> model = RockingModel.imperfect(a1, 0.65, 0.65, e_L=0.93, e_R=0.93)
>>> rec = motions.synthetic_record(10.0, 0.01, 1.0, seed=3)
>>> v = variability(model, rec, np.linspace(0.5, 3.0, 6))
>>> bool(v.theta_max_over_delta[0] == 0.0), bool(v.theta_max_over_delta[-1] > 0)
(True, True)
>>> s = parameter_sweep(model, rec.scaled_to_pga(2.0), "theta_R", np.linspace(0.5, 1.5, 5) * model.theta_R)
>>> sorted(s.summary())
['max', 'mean', 'n', 'n_not_applicable', 'n_overturned', 'p05', 'p50', 'p95', 'std']
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..compute.budget import check_runs
from ..errors import InputError, quoted
from . import kernel as K
from .batch import NOT_APPLICABLE_CODE, outcome_codes, run_batch
from .engine import FREE_TIME, simulate
from .spectrum import BYTES_PER_RUN, label
from .model import RockingModel
from ..hazard.motions import GroundMotion

SWEEP_BYTES_PER_RUN = 1024
"""Bytes one value of :func:`parameter_sweep` costs: its own RockingModel and its rows (about 700 B
measured) and its output."""
SWEEPABLE = ("alpha_L", "alpha_R", "alpha", "theta_L", "theta_R", "theta", "e_L", "e_R", "e")


@dataclass(frozen=True, eq=False)
class SweepResult:
    """One response per swept value: ``values`` (n,) of ``name`` (PGA in m/s^2 for
    a variability sweep), theta_max_over_delta, theta_max_L, theta_max_R (rad),
    overturned (bool), codes (into OUTCOMES, or NOT_APPLICABLE_CODE: nan responses), n_impacts
    (until the outcome was decided); why: '' or why some runs are not applicable."""

    name: str
    values: np.ndarray
    theta_max_over_delta: np.ndarray
    theta_max_L: np.ndarray
    theta_max_R: np.ndarray
    overturned: np.ndarray
    codes: np.ndarray
    n_impacts: np.ndarray
    model: RockingModel
    motion: GroundMotion
    why: str = ""

    @property
    def applicable(self) -> np.ndarray:
        """(n,) bool: False where the body slides before it rocks."""
        return np.asarray(self.codes) != NOT_APPLICABLE_CODE

    def summary(self) -> dict:
        """Distribution of |theta|max/delta over the sweep's applicable runs (overturned runs
        count as 1; nan if none applies); n_not_applicable: the runs left out."""
        x = self.theta_max_over_delta[self.applicable]
        n_na = int(self.values.size - x.size)
        if x.size == 0:
            nan = float("nan")
            return {"n": 0, "mean": nan, "std": nan, "p05": nan, "p50": nan, "p95": nan, "max": nan,
                    "n_overturned": 0, "n_not_applicable": n_na}
        return {"n": int(x.size), "mean": float(x.mean()), "std": float(x.std()),
                "p05": float(np.percentile(x, 5)), "p50": float(np.percentile(x, 50)),
                "p95": float(np.percentile(x, 95)), "max": float(x.max()),
                "n_overturned": int(self.overturned.sum()), "n_not_applicable": n_na}

    def applicable_only(self) -> "SweepResult":
        """The same sweep without its not-applicable runs (e.g. to plot it)."""
        from dataclasses import replace

        k = self.applicable
        return replace(self, values=self.values[k], theta_max_over_delta=self.theta_max_over_delta[k],
                       theta_max_L=self.theta_max_L[k], theta_max_R=self.theta_max_R[k],
                       overturned=self.overturned[k], codes=self.codes[k], n_impacts=self.n_impacts[k])

    def to_dict(self) -> dict:
        return {"name": self.name, "values": self.values, "theta_max_over_delta": self.theta_max_over_delta,
                "theta_max_L": self.theta_max_L, "theta_max_R": self.theta_max_R,
                "overturned": self.overturned, "outcome": [label(c) for c in self.codes],
                "applicable": self.applicable, "why": self.why, "notes": self.model.notes,
                "n_impacts": self.n_impacts, "summary": self.summary(),
                "model": self.model.to_dict(), "motion": self.motion.to_dict()}

    def to_csv(self) -> str:
        """One row per value; a response not computed (nan: not applicable) is an empty cell."""
        def c(x):
            return f"{x:.9g}" if np.isfinite(x) else ""

        lines = [f"{self.name},theta_max_over_delta,theta_max_L_rad,theta_max_R_rad,overturned,outcome,n_impacts"]
        for i in range(self.values.size):
            lines.append(f"{c(self.values[i])},{c(self.theta_max_over_delta[i])},{c(self.theta_max_L[i])},"
                         f"{c(self.theta_max_R[i])},{int(self.overturned[i])},{label(self.codes[i])},"
                         f"{int(self.n_impacts[i])}")
        return "\n".join(lines) + "\n"


def _result(name, values, S, model, motion, codes, na=None, why: str = "") -> SweepResult:
    """``na``: (n,) bool, runs in which the body slides before it rocks (not integrated)."""
    p = model.params
    tl, tr = S[:, K.S_QMAX_L].copy(), S[:, K.S_QMAX_R].copy()
    tmd = np.maximum(tl / p.delta_L, tr / p.delta_R)
    if na is not None and np.any(na):
        codes = codes.copy()
        codes[na] = NOT_APPLICABLE_CODE
        tl[na] = tr[na] = tmd[na] = np.nan
    else:
        why = ""
    return SweepResult(name, np.asarray(values, dtype=float), tmd, tl, tr, S[:, K.S_OVERTURNED] > 0, codes,
                       S[:, K.S_N_IMP].astype(int), model, motion, why)


def variability(model: RockingModel, motion: GroundMotion, pgas, rtol: float = 1e-7,
                free_time: float = FREE_TIME, progress: bool = False, executor=None) -> SweepResult:
    """|theta|max/delta of ``motion`` scaled to each PGA in ``pgas`` (m/s^2).
    ``executor``: None runs in this process (numba threads), or an
    :class:`~statue2model.compute.executors.Executor` (same result)."""
    pgas = np.asarray(pgas, dtype=float).ravel()
    if pgas.size == 0 or not np.all(np.isfinite(pgas)) or np.any(pgas < 0):
        raise InputError("PGA values must be finite and >= 0 (m/s^2)")
    if motion.pga == 0:
        raise InputError(f"motion {quoted(motion.label)} is zero everywhere")
    check_runs(pgas.size, BYTES_PER_RUN, f"{pgas.size} PGA levels", "use fewer PGA values")
    kind, M0, samples = motion.kernel_args()
    n = pgas.size
    M = np.tile(M0, (n, 1))
    gain = pgas / motion.pga
    M[:, K.MA] *= gain
    hi, lo = motion.extremes()
    lim_up, lim_dn = model.uplift_limits
    quiet = (gain * hi <= lim_up) & (-gain * lo <= lim_dn)
    na = np.array([not model.applicability(k * hi, -k * lo)[0] for k in gain])
    P = np.tile(model.kernel_vector(early_exit=True), (n, 1))
    S = run_batch(model, P, np.full(n, kind), M, samples, np.full(n, motion.end + free_time), rtol=rtol,
                  quiet=quiet | na, progress="variability" if progress else None, executor=executor)
    return _result("pga_m_s2", pgas, S, model, motion, outcome_codes(S, model.kind == "imperfect"), na,
                   model.sliding_note())


def _models(model: RockingModel, name: str, values) -> list[RockingModel]:
    if name not in SWEEPABLE:
        raise InputError(f"cannot sweep {quoted(name)}; choose one of {', '.join(SWEEPABLE)}")
    out = []
    for v in values:
        if name in ("alpha", "theta", "e"):
            out.append(model.with_(**{f"{name}_L": v, f"{name}_R": v}))
        else:
            out.append(model.with_(**{name: v}))
    return out


def _simulate_row(task: tuple) -> np.ndarray:
    """One run of the restitution sweep: ``task`` = (model, motion, t_end s, rtol);
    returns its statistics row (N_S,) (the entries :func:`_result` reads).
    Module level so that an executor can pickle it."""
    m, motion, t_end, rtol = task
    r = simulate(m, motion, t_end=t_end, rtol=rtol, max_records=1)
    row = np.zeros(K.N_S)
    row[K.S_QMAX_L], row[K.S_QMAX_R] = r.theta_max_L, r.theta_max_R
    row[K.S_OVERTURNED] = r.overturned
    row[K.S_IMP_BEFORE_OT] = r.impacts_before_overturn or 0
    row[K.S_N_IMP] = r.n_impacts
    row[K.S_MOVED] = r.uplift_time is not None
    row[K.S_FULL_UPLIFT] = r.full_uplift
    return row


def parameter_sweep(model: RockingModel, motion: GroundMotion, name: str, values, rtol: float = 1e-7,
                    free_time: float = FREE_TIME, progress: bool = False, executor=None) -> SweepResult:
    """Run ``motion`` once per value of parameter ``name`` (one of SWEEPABLE;
    "alpha", "theta", "e" set both sides). ``executor``: None runs in this
    process, or an :class:`~statue2model.compute.executors.Executor` (same result)."""
    values = np.asarray(values, dtype=float).ravel()
    if values.size == 0 or not np.all(np.isfinite(values)):
        raise InputError(f"sweep values of {name} must be finite numbers")
    check_runs(values.size, SWEEP_BYTES_PER_RUN, f"{values.size} values of {name}", "use fewer values")
    models = _models(model, name, values)
    n = values.size
    t_end = motion.end + free_time
    hi, lo = motion.extremes()
    na = np.array([not m.applicability(hi, -lo)[0] for m in models], dtype=bool)
    if name.startswith("e"):
        # restitution tables are shared by a batch: run one by one
        tasks = [(m, motion, t_end, rtol) for m in models]     # e does not change the sliding check
        if executor is None:
            rows = [_simulate_row(task) for task in tasks]
        else:
            rows = executor.map(_simulate_row, tasks, desc=f"sweep {name}" if progress else None)
        S = np.stack(rows) if rows else np.zeros((0, K.N_S))
    else:
        kind, M0, samples = motion.kernel_args()
        P = np.stack([m.kernel_vector(early_exit=True) for m in models])
        quiet = np.array([hi <= m.uplift_limits[0] and -lo <= m.uplift_limits[1] for m in models]) | na
        S = run_batch(model, P, np.full(n, kind), np.tile(M0, (n, 1)), samples, np.full(n, t_end), rtol=rtol,
                      quiet=quiet, progress=f"sweep {name}" if progress else None, executor=executor)
    codes = outcome_codes(S, any(m.kind == "imperfect" for m in models))
    why = next((m.sliding_note() for m, x in zip(models, na) if x), "")
    return _result(name, values, S, model, motion, codes, na, why)


def linspace_spec(text: str, what: str, accel: bool = False) -> np.ndarray:
    """'START:STOP:N' -> N equally spaced values (inclusive, N in 1..1e6); 'a,b,c' -> a
    list. With ``accel``, values carry a unit ('0.05g:1g:20', '0.5m/s2:9m/s2:20'), returned in m/s^2."""
    from ..quantities import parse_accel

    conv = (lambda v: parse_accel(v, what)) if accel else float
    text = str(text)
    try:
        if ":" in text:
            a, b, n = text.split(":")
            n = int(n)
            if not 1 <= n <= 1_000_000:
                raise ValueError
            out = np.linspace(conv(a), conv(b), n)
        else:
            out = np.array([conv(x) for x in text.split(",") if x.strip()])
    except InputError:          # an acceleration's own message (e.g. no unit)
        raise
    except ValueError:
        raise InputError(f"{what}: expected START:STOP:N (N in 1..1e6) or a comma list of numbers, "
                         f"got {quoted(text)}") from None
    if out.size == 0 or not np.all(np.isfinite(out)):
        raise InputError(f"{what}: values must be finite numbers, got {quoted(text)}")
    return out


