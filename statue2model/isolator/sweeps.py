"""Sweeps of the statue on the isolator: stability spectrum and variability over PGA.

Every point is one coupled plate + statue run (:func:`~statue2model.isolator.coupled.
simulate_coupled`: the plate alone first, the 2-DOF system only where the statue
may lift), so the results sit beside the fixed-base ones of
:mod:`statue2model.dynamics.spectrum` and :mod:`statue2model.dynamics.sweeps`
with the same outcome classes (and code FAILED = -1 for a point the solver could not
finish, counted apart). Points run through an executor
(:mod:`statue2model.executors`), one frequency row or one PGA per task; ``None``
runs them here, one after the other. The numbers do not depend on the executor.

Example
-------
>>> import numpy as np
>>> from statue2model.geometry.rocking_params import RockingParams
>>> from statue2model.dynamics import RockingModel
>>> from statue2model.isolator.device import Isolator
>>> statue = RockingParams.rectangular_block(0.0384, 0.2, 1.286)
>>> iso = Isolator(R=0.9, r=0.0095, M=statue.m + 15.0, mu=0.0073)
>>> sp = isolated_spectrum(iso, RockingModel.housner(statue), [1.0, 4.0], [0.1 * 9.81, 1.0 * 9.81])
>>> [[OUTCOMES[c] for c in row] for row in sp.codes]   # rows: 1 Hz, 4 Hz; columns: 0.1 g, 1 g
[['no motion', 'overturn mode 2'], ['no motion', 'no motion']]
"""
from __future__ import annotations

import numpy as np

from ..dynamics import motions
from ..dynamics.batch import OUTCOMES
from ..dynamics.model import RockingModel
from ..dynamics.spectrum import PULSES, StabilitySpectrum
from ..dynamics.sweeps import SweepResult
from ..errors import InputError
from .coupled import FREE_TIME, simulate_coupled
from .device import Isolator

_PULSE = {"cosine": motions.cosine_pulse, "sine": motions.sine_pulse}


FAILED = -1          # outcome code of a point whose integration did not finish (a solver hard point)
MAX_STEPS = 2_000_000


def _one(iso: Isolator, model: RockingModel, motion, t_end: float, rtol: float) -> tuple:
    """(code, theta_max/delta, theta_max_L, theta_max_R, overturned, n_impacts, a_abs max, u max);
    a point the solver cannot finish in MAX_STEPS steps gets code FAILED and NaNs, so
    one hard point does not stop a sweep."""
    try:
        r = simulate_coupled(iso, model, motion, t_end=t_end, dt_out=0.01, rtol=rtol, max_steps=MAX_STEPS)
    except RuntimeError:
        nan = float("nan")
        return (FAILED, nan, nan, nan, False, 0, nan, nan)
    return (OUTCOMES.index(r.outcome), r.theta_max_over_delta, r.theta_max_L, r.theta_max_R, bool(r.overturned),
            int(r.n_impacts), r.acc_abs_max, r.u_max)


def _spectrum_row(task) -> list[tuple]:
    """One frequency of the spectrum (module level: runs in worker processes)."""
    iso, model, pulse, freq, amps, free_time, rtol = task
    make = _PULSE[pulse]
    return [_one(iso, model, make(a, freq), 1.0 / freq + free_time, rtol) if a > 0 else
            (0, 0.0, 0.0, 0.0, False, 0, 0.0, 0.0) for a in amps]


def _pga_point(task) -> tuple:
    iso, model, motion, pga, free_time, rtol = task
    if pga == 0:
        return (0, 0.0, 0.0, 0.0, False, 0, 0.0, 0.0)
    return _one(iso, model, motion.scaled_to_pga(pga), motion.end + free_time, rtol)


def _map(executor, fn, tasks, desc):
    if executor is None:
        return [fn(t) for t in tasks]
    return executor.map(fn, tasks, desc=desc)


def isolated_spectrum(iso: Isolator, model: RockingModel, freqs, amps, pulse: str = "cosine",
                      rtol: float = 1e-8, free_time: float = FREE_TIME, executor=None) -> StabilitySpectrum:
    """Outcome of the statue (``model``) on the isolator ``iso`` for a one-``pulse``
    of every (frequency Hz, amplitude m/s^2); a StabilitySpectrum (its ``model`` is
    the statue's), with ``n_integrated`` the number of points run."""
    if pulse not in PULSES:
        raise InputError(f"pulse must be one of {', '.join(PULSES)}, got {pulse!r}")
    freqs = np.asarray(freqs, dtype=float).ravel()
    amps = np.asarray(amps, dtype=float).ravel()
    if freqs.size == 0 or amps.size == 0 or np.any(freqs <= 0) or np.any(amps < 0):
        raise InputError("the isolated spectrum needs frequencies > 0 Hz and amplitudes >= 0")
    rows = _map(executor, _spectrum_row, [(iso, model, pulse, float(f), amps, free_time, rtol) for f in freqs],
                "isolated spectrum")
    arr = np.array([[p[:6] for p in row] for row in rows], dtype=float)
    return StabilitySpectrum(model, pulse, freqs, amps, arr[..., 0].astype(np.int64), arr[..., 1],
                             arr[..., 5].astype(int), int(np.sum(amps > 0) * freqs.size))


def isolated_variability(iso: Isolator, model: RockingModel, motion, pgas, rtol: float = 1e-8,
                         free_time: float = FREE_TIME, executor=None) -> tuple[SweepResult, np.ndarray]:
    """|theta|max/delta of the statue on the isolator with ``motion`` scaled to each
    PGA (m/s^2); also returns the peak absolute plate acceleration per PGA (m/s^2)."""
    pgas = np.asarray(pgas, dtype=float).ravel()
    if pgas.size == 0 or not np.all(np.isfinite(pgas)) or np.any(pgas < 0):
        raise InputError("PGA values must be finite and >= 0 (m/s^2)")
    if motion.pga == 0:
        raise InputError(f"motion {motion.label!r} is zero everywhere")
    pts = _map(executor, _pga_point, [(iso, model, motion, float(a), free_time, rtol) for a in pgas],
               "isolated variability")
    a = np.array(pts, dtype=float)
    sw = SweepResult("pga_m_s2", pgas, a[:, 1], a[:, 2], a[:, 3], a[:, 4] > 0, a[:, 0].astype(np.int64),
                     a[:, 5].astype(int), model, motion)
    return sw, a[:, 6]
