"""Sweeps of the statue on the isolator: stability spectrum and variability over PGA.

Every point is one coupled plate + statue run (:func:`~statue2model.isolator.coupled.
simulate_coupled`: the plate alone first, the 2-DOF system only where the statue
may lift), so the results sit beside the fixed-base ones of
:mod:`statue2model.rocking.spectrum` and :mod:`statue2model.rocking.sweeps`
with the same outcome classes, plus two codes of their own: FAILED = -1 for a point
the solver could not finish (counted apart) and CAPACITY = -3 ("isolator capacity
exceeded": the plate passed ``iso.capacity``; a failure, as bad as overturning).
Points run through an executor (:mod:`statue2model.compute.executors`), one frequency row
or one PGA per task; ``None`` runs them here, one after the other. The numbers do
not depend on the executor.

The variability runs its PGAs in increasing order and stops at the first one that
exceeds the capacity: the higher PGAs are not run (``run`` False, code CAPACITY,
responses nan; the JSON lists them as ``not_run_pga_m_s2``).

With ``end_stop="impact"`` (see isolator/time_history.py) the runs go on after the
capacity with an end-stop impact: the codes are then the statue's outcomes and the
variability does not stop.

Example
-------
>>> import numpy as np
>>> from statue2model.geometry.rocking_params import RockingParams
>>> from statue2model.rocking import RockingModel
>>> from statue2model.isolator.device import Isolator
>>> statue = RockingParams.rectangular_block(0.0384, 0.2, 1.286)
>>> iso = Isolator(R=0.9, r=0.0095, M=statue.m + 15.0, mu=0.0073)
>>> sp = isolated_spectrum(iso, RockingModel.housner(statue), [1.0, 4.0], [0.1 * 9.81, 1.0 * 9.81])
>>> [[label(c) for c in row] for row in sp.codes]   # rows: 1 Hz, 4 Hz; columns: 0.1 g, 1 g
[['no motion', 'overturn mode 2'], ['no motion', 'no motion']]
>>> from dataclasses import replace
>>> sp = isolated_spectrum(replace(iso, capacity=0.10), RockingModel.housner(statue), [1.0], [0.1 * 9.81, 1.0 * 9.81])
>>> [label(c) for c in sp.codes[0]]                 # 1 g at 1 Hz moves the plate more than 100 mm
['no motion', 'isolator capacity exceeded']
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..hazard import motions
from ..rocking.batch import CAPACITY_CODE, OUTCOMES, outcome_label
from ..rocking.model import RockingModel
from ..rocking.spectrum import PULSES, StabilitySpectrum
from ..rocking.sweeps import SweepResult
from ..errors import InputError
from .coupled import FREE_TIME, simulate_coupled
from .device import Isolator
from .time_history import CAPACITY_EXCEEDED, END_STOP_RESTITUTION, check_end_stop

_PULSE = {"cosine": motions.cosine_pulse, "sine": motions.sine_pulse}


FAILED = -1          # outcome code of a point whose integration did not finish (a solver hard point)
CAPACITY = CAPACITY_CODE   # outcome code of a point whose plate passed the isolator's capacity (-3)
MAX_STEPS = 2_000_000
_QUIET = (0, 0.0, 0.0, 0.0, False, 0, 0.0, 0.0, float("nan"))


def label(code: int) -> str:
    """The name of an isolated outcome code (OUTCOMES, CAPACITY, FAILED)."""
    return outcome_label(int(code))


def is_failure(codes) -> np.ndarray:
    """Overturning or capacity exceeded (the conservative failure of an isolated run)."""
    codes = np.asarray(codes)
    return (codes >= 3) | (codes == CAPACITY)


@dataclass(frozen=True, eq=False)
class IsolatedSpectrum(StabilitySpectrum):
    """A StabilitySpectrum of the statue on the isolator: codes may also be CAPACITY
    and FAILED; ``capacity`` (m, inf: not checked), ``end_stop``."""

    capacity: float = float("inf")
    end_stop: str = "stop"

    def min_failure_amp(self) -> np.ndarray:
        """Smallest amplitude of the grid that overturns or exceeds the capacity, per
        frequency (nan if none): the conservative counterpart of min_overturning_amp."""
        return self.first_amp_where(is_failure(self.codes))

    def counts(self) -> dict:
        out = super().counts()
        for code in (CAPACITY, FAILED):
            n = int(np.sum(self.codes == code))
            if n:
                out[label(code)] = n
        return out

    def to_dict(self) -> dict:
        cap = self.capacity if np.isfinite(self.capacity) else None
        return {**super().to_dict(), "capacity_m": cap, "end_stop": self.end_stop,
                "extra_codes": {str(CAPACITY): label(CAPACITY), str(FAILED): label(FAILED)},
                "capacity_exceeded_count": int(np.sum(self.codes == CAPACITY)),
                "failure_fraction": float(np.mean(is_failure(self.codes))),
                "min_failure_amp_m_s2": self.min_failure_amp()}


@dataclass(frozen=True, eq=False)
class IsolatedSweep(SweepResult):
    """A SweepResult of the statue on the isolator. ``run`` (n,) bool: False for the PGAs
    not run because a lower PGA already exceeded the capacity (code CAPACITY, nan
    responses); ``capacity`` (m), ``end_stop``; t_capacity (n,) s (nan where not reached)."""

    run: np.ndarray = None
    t_capacity: np.ndarray = None
    capacity: float = float("inf")
    end_stop: str = "stop"

    def first_capacity_pga(self) -> float | None:
        """The lowest PGA (m/s^2) at which the capacity was exceeded (None if none)."""
        i = np.flatnonzero((self.codes == CAPACITY) & self.run)
        return float(self.values[i].min()) if i.size else None

    def first_failure_pga(self) -> float | None:
        """The lowest PGA that overturned the statue or exceeded the capacity (None if none)."""
        i = np.flatnonzero(is_failure(self.codes) & self.run)
        return float(self.values[i].min()) if i.size else None

    def summary(self) -> dict:
        """As SweepResult's, over the PGAs that ran (nan responses left out)."""
        x = self.theta_max_over_delta
        ok = np.isfinite(x)
        out = {"n": int(ok.sum()), "n_overturned": int(self.overturned.sum()),
               "n_capacity_exceeded": int(np.sum((self.codes == CAPACITY) & self.run)),
               "n_not_run": int((~self.run).sum()), "n_failed": int(np.sum(self.codes == FAILED))}
        if not ok.any():
            nan = float("nan")
            return {**out, "mean": nan, "std": nan, "p05": nan, "p50": nan, "p95": nan, "max": nan}
        x = x[ok]
        return {**out, "mean": float(x.mean()), "std": float(x.std()), "p05": float(np.percentile(x, 5)),
                "p50": float(np.percentile(x, 50)), "p95": float(np.percentile(x, 95)), "max": float(x.max())}

    def to_dict(self) -> dict:
        cap = self.capacity if np.isfinite(self.capacity) else None
        d = super().to_dict()
        d["outcome"] = [label(c) if r else f"not run ({label(c)} at a lower PGA)"
                        for c, r in zip(self.codes, self.run)]
        return {**d, "run": self.run, "not_run_pga_m_s2": self.values[~self.run], "capacity_m": cap,
                "end_stop": self.end_stop, "t_capacity": self.t_capacity,
                "first_capacity_pga_m_s2": self.first_capacity_pga(),
                "first_failure_pga_m_s2": self.first_failure_pga()}


def _one(iso: Isolator, model: RockingModel, motion, t_end: float, rtol: float, end_stop: str,
         e_stop: float) -> tuple:
    """(code, theta_max/delta, theta_max_L, theta_max_R, overturned, n_impacts, a_abs max, u max,
    t_capacity); a point the solver cannot finish in MAX_STEPS steps gets code FAILED and NaNs,
    so one hard point does not stop a sweep; a plate that passes the capacity (end_stop "stop")
    gets code CAPACITY and the responses up to that time."""
    nan = float("nan")
    try:
        r = simulate_coupled(iso, model, motion, t_end=t_end, dt_out=0.01, rtol=rtol, max_steps=MAX_STEPS,
                             end_stop=end_stop, e_stop=e_stop)
    except RuntimeError:
        return (FAILED, nan, nan, nan, False, 0, nan, nan, nan)
    out = r.outcome
    code = CAPACITY if out == CAPACITY_EXCEEDED else OUTCOMES.index(out)
    return (code, r.theta_max_over_delta, r.theta_max_L, r.theta_max_R, bool(r.overturned),
            int(r.n_impacts), r.acc_abs_max, r.u_max, nan if r.t_capacity is None else r.t_capacity)


def _spectrum_row(task) -> list[tuple]:
    """One frequency of the spectrum (module level: runs in worker processes)."""
    iso, model, pulse, freq, amps, free_time, rtol, end_stop, e_stop = task
    make = _PULSE[pulse]
    return [_one(iso, model, make(a, freq), 1.0 / freq + free_time, rtol, end_stop, e_stop) if a > 0 else _QUIET
            for a in amps]


def _pga_point(task) -> tuple:
    iso, model, motion, pga, free_time, rtol, end_stop, e_stop = task
    if pga == 0:
        return _QUIET
    return _one(iso, model, motion.scaled_to_pga(pga), motion.end + free_time, rtol, end_stop, e_stop)


def _map(executor, fn, tasks, desc):
    if executor is None:
        return [fn(t) for t in tasks]
    return executor.map(fn, tasks, desc=desc)


def isolated_spectrum(iso: Isolator, model: RockingModel, freqs, amps, pulse: str = "cosine",
                      rtol: float = 1e-8, free_time: float = FREE_TIME, executor=None, end_stop: str = "stop",
                      e_stop: float = END_STOP_RESTITUTION) -> IsolatedSpectrum:
    """Outcome of the statue (``model``) on the isolator ``iso`` for a one-``pulse``
    of every (frequency Hz, amplitude m/s^2); an IsolatedSpectrum (a StabilitySpectrum,
    its ``model`` the statue's), with ``n_integrated`` the number of points run. Points
    whose plate passes ``iso.capacity`` get code CAPACITY (end_stop "stop")."""
    if pulse not in PULSES:
        raise InputError(f"pulse must be one of {', '.join(PULSES)}, got {pulse!r}")
    check_end_stop(end_stop, e_stop)
    freqs = np.asarray(freqs, dtype=float).ravel()
    amps = np.asarray(amps, dtype=float).ravel()
    if freqs.size == 0 or amps.size == 0 or np.any(freqs <= 0) or np.any(amps < 0):
        raise InputError("the isolated spectrum needs frequencies > 0 Hz and amplitudes >= 0")
    rows = _map(executor, _spectrum_row, [(iso, model, pulse, float(f), amps, free_time, rtol, end_stop,
                                           float(e_stop)) for f in freqs], "isolated spectrum")
    arr = np.array([[p[:6] for p in row] for row in rows], dtype=float)
    return IsolatedSpectrum(model, pulse, freqs, amps, arr[..., 0].astype(np.int64), arr[..., 1],
                            arr[..., 5].astype(int), int(np.sum(amps > 0) * freqs.size), capacity=iso.capacity,
                            end_stop=end_stop)


def isolated_variability(iso: Isolator, model: RockingModel, motion, pgas, rtol: float = 1e-8,
                         free_time: float = FREE_TIME, executor=None, end_stop: str = "stop",
                         e_stop: float = END_STOP_RESTITUTION) -> tuple[IsolatedSweep, np.ndarray]:
    """|theta|max/delta of the statue on the isolator with ``motion`` scaled to each
    PGA (m/s^2); also returns the peak absolute plate acceleration per PGA (m/s^2).
    Stops at the first PGA (in increasing order) whose plate passes ``iso.capacity``
    (end_stop "stop"): the higher PGAs are not run (module docstring). With an
    executor, PGAs run in rounds of one per worker, and the results past the first
    exceeding PGA are dropped, so the numbers do not depend on the executor."""
    check_end_stop(end_stop, e_stop)
    pgas = np.asarray(pgas, dtype=float).ravel()
    if pgas.size == 0 or not np.all(np.isfinite(pgas)) or np.any(pgas < 0):
        raise InputError("PGA values must be finite and >= 0 (m/s^2)")
    if motion.pga == 0:
        raise InputError(f"motion {motion.label!r} is zero everywhere")
    order = np.argsort(pgas, kind="stable")
    can_stop = end_stop == "stop" and np.isfinite(iso.capacity)
    batch = pgas.size if not can_stop else (1 if executor is None else max(1, int(getattr(executor, "workers", 1))))
    nan = float("nan")
    pts = [None] * pgas.size
    stop_at = None
    for start in range(0, pgas.size, batch):
        idx = order[start:start + batch]
        res = _map(executor, _pga_point, [(iso, model, motion, float(pgas[i]), free_time, rtol, end_stop,
                                           float(e_stop)) for i in idx], "isolated variability")
        for i, r in zip(idx, res):
            pts[i] = r
        if can_stop:
            hit = [k for k, r in enumerate(res) if r[0] == CAPACITY]
            if hit:
                stop_at = start + hit[0]
                break
    run = np.ones(pgas.size, dtype=bool)
    if stop_at is not None:
        for i in order[stop_at + 1:]:
            run[i] = False
            pts[i] = (CAPACITY, nan, nan, nan, False, 0, nan, nan, nan)
    a = np.array(pts, dtype=float)
    sw = IsolatedSweep("pga_m_s2", pgas, a[:, 1], a[:, 2], a[:, 3], a[:, 4] > 0, a[:, 0].astype(np.int64),
                       a[:, 5].astype(int), model, motion, run=run, t_capacity=a[:, 8], capacity=iso.capacity,
                       end_stop=end_stop)
    return sw, a[:, 6]
