"""Run the 2D rocking model: :func:`simulate` -> :class:`RockingResult`.

The problem (a :class:`~statue2model.rocking.model.RockingModel` and a
:class:`~statue2model.hazard.motions.GroundMotion`) is kept apart from the
solver (:mod:`statue2model.rocking.kernel`) and from the result.

Example
-------
>>> from statue2model.geometry.rocking_params import RockingParams
>>> from statue2model.hazard import motions
>>> from statue2model.rocking import RockingModel
>>> block = RockingParams.rectangular_block(b=0.0384, h=0.2, m=1.286)
>>> model = RockingModel.housner(block, e_L=0.9, e_R=0.9)
>>> r = simulate(model, motions.free(), theta0=0.1)
>>> r.n_impacts > 20, r.t_rest is not None, r.overturned
(True, True, False)
>>> simulate(model, motions.cosine_pulse(0.5 * 9.81, 2.0)).outcome
'overturn mode 2'

A plastic impact (e = 0, a squat body: eq. 15 < 0) ends the rocking at the first impact:

>>> plastic = RockingModel.housner(block, e_L=0.0, e_R=0.0)
>>> r = simulate(plastic, motions.free(), theta0=0.1)
>>> r.n_impacts, r.t_rest == float(r.impact_times[0])
(1, True)
"""
from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from ..compute.budget import check_history
from ..compute.compile import ensure_compiled
from ..errors import InputError
from . import kernel as K
from .model import RockingModel
from ..hazard.motions import GroundMotion

FREE_TIME = 20.0  # s of free motion simulated after the ground stops, by default
HISTORY_BYTES_PER_SAMPLE = 72
"""Bytes one history sample costs :func:`simulate`: t and (theta, theta', phase) while integrating,
the same again in the result, and the time index (9 float64)."""
NOT_APPLICABLE = "not applicable (slides before it rocks)"
"""The outcome of a run in which the body slides before it rocks (see RockingModel.applicability)."""


@dataclass(frozen=True, eq=False)
class RockingResult:
    """What one run of the rocking model gives (SI units, angles in rad).

    theta_max_L / theta_max_R: largest |theta| on the left / right pivot;
    theta_max_over_delta: max over both sides of theta_max_side / delta_side (1 at
    overturning); uplift_time: first uplift (None if the body never moves);
    impact_times, impact_speeds (|theta'| before impact), impact_sides ("L":
    landing on the left edge); overturned, overturn_mode (thesis numbering: 1 + the
    number of impacts before overturning), overturn_time, overturn_side;
    t_rest: time the body came back to rest for good (None if it never moved,
    overturned or still moves at t_end); peak_times, peak_values (|theta| at each
    extremum), peak_sides; history (t, theta, theta', phase) when requested,
    phase 0 stick, 1 rolling transition, 2 rocking; stats: solver counters.
    applicable: False if the body slides before it rocks and the ground exceeds the
    friction (:meth:`RockingModel.applicability`); the numbers are then those of a base
    that cannot slide and ``outcome`` says 'not applicable'; why: the reason.
    """

    model: RockingModel
    motion: GroundMotion
    theta0: float
    omega0: float
    t_end: float
    theta_max_L: float
    theta_max_R: float
    uplift_time: float | None
    impact_times: np.ndarray
    impact_speeds: np.ndarray
    impact_sides: np.ndarray
    overturned: bool
    impacts_before_overturn: int | None
    overturn_time: float | None
    overturn_side: str | None
    t_rest: float | None
    full_uplift: bool
    peak_times: np.ndarray
    peak_values: np.ndarray
    peak_sides: np.ndarray
    history: dict | None
    stats: dict
    applicable: bool = True
    why: str = ""

    @property
    def n_impacts(self) -> int:
        return int(self.stats["n_impacts"])

    @property
    def overturn_mode(self) -> int | None:
        return None if self.impacts_before_overturn is None else self.impacts_before_overturn + 1

    @property
    def theta_max_over_delta_L(self) -> float:
        return self.theta_max_L / self.model.params.delta_L

    @property
    def theta_max_over_delta_R(self) -> float:
        return self.theta_max_R / self.model.params.delta_R

    @property
    def theta_max_over_delta(self) -> float:
        return max(self.theta_max_over_delta_L, self.theta_max_over_delta_R)

    @property
    def outcome(self) -> str:
        """'no motion', 'rolling' (never past theta_side), 'rocking' or 'overturn mode k';
        NOT_APPLICABLE if the body slides before it rocks under this motion."""
        if not self.applicable:
            return NOT_APPLICABLE
        return outcome_name(self.uplift_time is not None, self.full_uplift or self.model.kind == "housner",
                            self.overturned, self.impacts_before_overturn)

    def to_dict(self, history: bool = False) -> dict:
        def opt(x):
            return None if x is None else float(x)

        d = {
            "theta_max_L": self.theta_max_L, "theta_max_R": self.theta_max_R,
            "theta_max_over_delta": self.theta_max_over_delta,
            "theta_max_over_delta_L": self.theta_max_over_delta_L,
            "theta_max_over_delta_R": self.theta_max_over_delta_R,
            "uplift_time": opt(self.uplift_time), "n_impacts": self.n_impacts,
            "impact_times": self.impact_times.tolist(), "impact_speeds": self.impact_speeds.tolist(),
            "impact_sides": self.impact_sides.tolist(),
            "overturned": self.overturned, "overturn_mode": self.overturn_mode,
            "impacts_before_overturn": self.impacts_before_overturn,
            "overturn_time": opt(self.overturn_time), "overturn_side": self.overturn_side,
            "t_rest": opt(self.t_rest), "outcome": self.outcome,
            "applicable": self.applicable, "why": self.why, "notes": self.model.notes,
            "peaks": {"t": self.peak_times.tolist(), "theta_abs": self.peak_values.tolist(),
                      "side": self.peak_sides.tolist()},
            "t_end": self.t_end, "theta0": self.theta0, "omega0": self.omega0,
            "model": self.model.to_dict(), "motion": self.motion.to_dict(), "solver": self.stats,
        }
        if history and self.history is not None:
            d["history"] = {k: v.tolist() for k, v in self.history.items()}
        return d

    def history_csv(self) -> str:
        if self.history is None:
            raise ValueError("run without dt_out: no history")
        from ..io.csvsafe import csv_text, num_cell

        h = self.history      # every cell through the CSV guard: none is ever nan or inf
        return csv_text(("t_s", "theta_rad", "theta_dot_rad_s", "phase"),
                        ((num_cell(t, ".9g"), num_cell(a, ".12g"), num_cell(b, ".12g"), num_cell(p, ".0f"))
                         for t, a, b, p in zip(h["t"], h["theta"], h["theta_dot"], h["phase"])))


def outcome_name(moved: bool, full_uplift: bool, overturned: bool, impacts_before_overturn) -> str:
    if overturned:
        return f"overturn mode {min(int(impacts_before_overturn), 2) + 1}"
    if not moved:
        return "no motion"
    return "rocking" if full_uplift else "rolling"


def _check_run(model: RockingModel, theta0: float, omega0: float, rtol: float):
    if not isinstance(model, RockingModel):
        raise InputError("model must be a RockingModel")
    for name, v in (("theta0", theta0), ("omega0", omega0)):
        if not math.isfinite(v):
            raise InputError(f"{name} must be finite, got {v}")
    p = model.params
    if theta0 > 0 and theta0 >= p.delta_R or theta0 < 0 and -theta0 >= p.delta_L:
        raise InputError(f"initial rotation theta0 = {theta0} rad is beyond the overturning angle "
                         f"(delta_R = {p.delta_R:.4g}, delta_L = {p.delta_L:.4g})")
    if not (1e-14 <= rtol <= 1e-2):
        raise InputError(f"rtol must lie in [1e-14, 1e-2], got {rtol}")


def simulate(model: RockingModel, motion: GroundMotion, *, theta0: float = 0.0, omega0: float = 0.0,
             t_end: float | None = None, rtol: float = 1e-8, dt_out: float | None = None,
             max_records: int = 10_000, rest_tol: float = 1e-9, max_steps: int = 20_000_000) -> RockingResult:
    """Integrate the rocking model under ``motion`` from (theta0, omega0) at t = 0.

    t_end defaults to the end of the motion + 20 s; the run stops earlier at
    overturning, or once the body is at rest and the motion cannot lift it again.
    ``rtol`` is the local error tolerance (relative; absolute tolerances are rtol
    times delta and delta p). ``dt_out`` > 0 asks for a history sampled every
    dt_out seconds (the samples do not change the solution). ``max_records``
    bounds the impacts and peaks kept (all are counted).
    """
    theta0, omega0 = float(theta0), float(omega0)
    _check_run(model, theta0, omega0, rtol)
    if t_end is None:
        t_end = motion.end + FREE_TIME
    if not (math.isfinite(t_end) and t_end > 0):
        raise InputError(f"t_end must be a positive time in s, got {t_end}")
    P = model.kernel_vector(rest_tol)
    eLw, eLe = model.e_L.arrays()
    eRw, eRe = model.e_R.arrays()
    kind, M, samples = motion.kernel_args()
    if dt_out is not None:
        if not (math.isfinite(dt_out) and dt_out > 0):
            raise InputError(f"dt_out must be a positive time step, got {dt_out}")
        n = check_history(t_end, dt_out, HISTORY_BYTES_PER_SAMPLE)      # before any allocation
        out_t = np.arange(n) * dt_out
    else:
        out_t = np.empty(0)
    out_y = np.empty((out_t.size, 3))
    imp = np.empty((max_records, 3))
    peaks = np.empty((max_records, 3))
    S = np.zeros(K.N_S)
    hi, lo = motion.extremes()
    applicable, why = model.applicability(hi, -lo)
    quiet = theta0 == 0.0 and omega0 == 0.0 and quiet_ground(model, hi, lo)
    if quiet:
        # the ground never exceeds the uplift limits: nothing to integrate
        S[K.S_T_UPLIFT] = S[K.S_T_OVERTURN] = S[K.S_T_REST] = np.nan
        S[K.S_T_FINAL] = t_end
        S[K.S_N_OUT] = out_t.size
        out_y[:] = 0.0
    else:
        ensure_compiled()
        K.simulate_kernel(P, eLw, eLe, eRw, eRe, kind, M, samples, theta0, omega0, 0.0, float(t_end),
                          float(rtol), int(max_steps), out_t, out_y, imp, peaks, S)
    if S[K.S_STATUS] == K.STATUS_MAX_STEPS:
        raise RuntimeError(f"rocking solver stopped after {max_steps} steps at t = {S[K.S_T_FINAL]:.6g} s")
    if S[K.S_STATUS] == K.STATUS_STALLED:
        raise RuntimeError(f"rocking solver made no progress at t = {S[K.S_T_FINAL]:.6g} s")
    r = _result(model, motion, theta0, omega0, float(t_end), S, out_t, out_y, imp, peaks)
    return r if applicable else replace(r, applicable=False, why=why)


def quiet_ground(model, hi: float, lo: float) -> bool:
    """Whether a ground acceleration that stays within ``lo`` .. ``hi`` (m/s^2, ``motion.extremes()``)
    never reaches ``model``'s uplift limits: a body at rest then stays at rest, and its run is not
    integrated (:func:`simulate`; the batch callers mark such rows ``quiet``)."""
    lim_up, lim_dn = model.uplift_limits
    return hi <= lim_up and lo >= -lim_dn


def _opt(x):
    return None if not np.isfinite(x) else float(x)


def _result(model, motion, theta0, omega0, t_end, S, out_t, out_y, imp, peaks) -> RockingResult:
    n_imp = int(S[K.S_N_IMP])
    ni = min(n_imp, imp.shape[0])
    npk = min(int(S[K.S_N_PEAKS]), peaks.shape[0])
    overturned = bool(S[K.S_OVERTURNED])
    n_out = int(S[K.S_N_OUT])
    history = None
    if out_t.size:
        history = {"t": out_t[:n_out].copy(), "theta": out_y[:n_out, 0].copy(),
                   "theta_dot": out_y[:n_out, 1].copy(), "phase": out_y[:n_out, 2].astype(int)}
    side = {1.0: "R", -1.0: "L"}
    stats = {"n_impacts": n_imp, "n_steps": int(S[K.S_N_STEPS]), "n_rejected": int(S[K.S_N_REJECT]),
             "n_rhs": int(S[K.S_N_RHS]), "n_uplifts": int(S[K.S_N_UPLIFTS]), "t_final": float(S[K.S_T_FINAL])}
    return RockingResult(
        model=model, motion=motion, theta0=theta0, omega0=omega0, t_end=t_end,
        theta_max_L=float(S[K.S_QMAX_L]), theta_max_R=float(S[K.S_QMAX_R]),
        uplift_time=_opt(S[K.S_T_UPLIFT]),
        impact_times=imp[:ni, 0].copy(), impact_speeds=imp[:ni, 1].copy(),
        impact_sides=np.array([side[v] for v in imp[:ni, 2]], dtype="<U1"),
        overturned=overturned,
        impacts_before_overturn=int(S[K.S_IMP_BEFORE_OT]) if overturned else None,
        overturn_time=_opt(S[K.S_T_OVERTURN]) if overturned else None,
        overturn_side=side.get(float(S[K.S_OT_SIDE])) if overturned else None,
        t_rest=_opt(S[K.S_T_REST]),
        full_uplift=bool(S[K.S_FULL_UPLIFT]),
        peak_times=peaks[:npk, 0].copy(), peak_values=peaks[:npk, 1].copy(),
        peak_sides=np.array([side[v] for v in peaks[:npk, 2]], dtype="<U1"),
        history=history, stats=stats)
