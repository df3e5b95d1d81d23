"""The isolator's top plate under a ground motion, and the statue riding on it.

    M u_o'' + F(u_o, u_o') = -M u_g''          (eq. 20 / eq. 24)

u_o is the plate's displacement relative to the ground (m); the statue feels the
absolute plate acceleration a_abs = u_g'' + u_o''. The problem (an immutable
:class:`~statue2model.isolator.device.Isolator` and a
:class:`~statue2model.hazard.motions.GroundMotion`) is kept apart from the
solvers in kernel.py; :func:`simulate` returns an :class:`IsolatorResult`.

With a statue on top (:func:`statue2model.isolator.statue_on_plate.statue_on_plate`), plate and statue are integrated
together where the statue may lift (coupled.py: two degrees of freedom, the rocking
statue pushes the plate back); full contact is checked, not assumed. While the
statue stays in full contact the coupled model is exactly eq. 20 with M = m_o + m,
so a plate whose a_abs stays inside the statue's limits needs no 2-DOF run.

Capacity: the run watches |u_o| against ``iso.capacity`` (the largest displacement
before a ball leaves its groove or the top plate tips). ``end_stop="stop"`` (default):
the run ends when |u_o| passes it, with the outcome "isolator capacity exceeded" (a
failure, as bad as overturning; the kernel leaves the samples after it nan, and every file of a
history ends with the last finite sample and a line saying why: :meth:`IsolatorResult.history_csv`). ``end_stop="impact"``: the
top plate hits a rigid end stop there, u_o' -> -e u_o' with e = END_STOP_RESTITUTION
(0.5, an assumption: timber or steel stop, no measurement), and the run goes on; the
capacity is still reported as reached (first time, displacement, number of hits).
The crossing time is exact (kernel.py), not read at output samples.

Example
-------
>>> from statue2model.hazard import motions
>>> from statue2model.isolator.device import Isolator
>>> iso = Isolator(R=0.30, r=0.0183, M=21.664, mu=0.0114)
>>> res = simulate(iso, motions.free(), u0=0.05, t_end=6.0)
>>> np.round(res.peaks_u, 5)              # each half cycle loses 2 mu R_hat = 12.8 mm
array([-0.03715,  0.02431, -0.01146, -0.00138])
>>> round(float(res.peaks_t[0]), 4), round(iso.T / 2, 4)   # Coulomb friction leaves the period alone
(0.7529, 0.7529)
>>> cap = simulate(Isolator(R=0.30, r=0.0183, M=21.664, mu=0.0114, capacity=0.03), motions.free(), u0=-0.04)
>>> cap.outcome, cap.t_capacity, cap.u_at_capacity      # released beyond the capacity
('isolator capacity exceeded', 0.0, -0.04)
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..compute.compile import ensure_compiled
from ..hazard.motions import GroundMotion
from ..errors import InputError
from . import kernel as IK
from .device import Isolator

FREE_TIME = 10.0
END_STOPS = ("stop", "impact")
END_STOP_RESTITUTION = 0.5
"""Coefficient of restitution of the top plate on the end stop (end_stop="impact"): assumed."""
CAPACITY_EXCEEDED = "isolator capacity exceeded"


HISTORY_BYTES_PER_SAMPLE = 160
"""Bytes one output sample of :func:`simulate` may cost: 5 arrays of the plate and their time
index, and the statue's coupled run on them (:func:`statue2model.isolator.statue_on_plate.statue_on_plate`)."""


def check_end_stop(end_stop: str, e_stop: float) -> None:
    if end_stop not in END_STOPS:
        raise InputError(f"end_stop must be one of {', '.join(END_STOPS)}, got {end_stop!r}")
    if not (math.isfinite(e_stop) and 0 <= e_stop <= 1):
        raise InputError(f"end-stop restitution must be in [0, 1], got {e_stop!r}")


def capacity_dict(capacity: float, exceeded: bool, t_cap, u_cap, n_hits: int, end_stop: str, e_stop: float) -> dict:
    """The capacity fields of a result's to_dict (None for inf / not reached)."""
    return {"capacity": capacity if math.isfinite(capacity) else None, "capacity_exceeded": bool(exceeded),
            "t_capacity": t_cap, "u_at_capacity": u_cap, "capacity_hits": int(n_hits), "end_stop": end_stop,
            "end_stop_restitution": e_stop if end_stop == "impact" else None}


HISTORY_HEADER = ("t_s", "u_m", "v_m_s", "a_abs_m_s2", "z")
"""The columns of :meth:`IsolatorResult.history_csv` (SI units; z: the Bouc-Wen variable)."""
STOPPED_PREFIX = "# stopped: "
"""How a history file says its run ended early (a comment line after its last finite sample;
readers of histories, :func:`statue2model.rocking.identify.read_time_series`, skip it)."""


def finite_length(*arrays) -> int:
    """The number of leading samples at which every one of ``arrays`` is finite: a run that stopped
    (capacity, overturning) leaves nan after its stop, and a history is written up to there.

    >>> finite_length(np.array([0.0, 1.0, np.nan, 2.0]), np.zeros(4))
    2
    """
    ok = np.logical_and.reduce([np.isfinite(np.asarray(a, dtype=float)) for a in arrays])
    return int(ok.size if ok.all() else np.argmin(ok))


def stop_line(outcome: str, t_stop, u_stop, n_kept: int, n_all: int) -> str:
    """The comment line that ends a stopped history: why, when, where, and what was left out."""
    where = f" at t = {t_stop:.6g} s" if t_stop is not None and math.isfinite(t_stop) else ""
    if u_stop is not None and math.isfinite(u_stop):
        where += f" (u = {u_stop:.6g} m)"
    return (f"{STOPPED_PREFIX}{outcome}{where}; the history ends with its last finite sample "
            f"({n_kept} of {n_all} samples; none after the stop)")


class CapacityTracked:
    """What every isolated result says of the travel limit: ``capacity`` (m, the
    isolator's) and ``capacity_exceeded`` (whether ``t_capacity`` was reached)."""

    @property
    def capacity(self) -> float:
        return self.isolator.capacity

    @property
    def capacity_exceeded(self) -> bool:
        return self.t_capacity is not None


@dataclass(frozen=True)
class IsolatorResult(CapacityTracked):
    """Time history and peaks of the top plate (SI units).

    t, u, v, acc_abs, z : outputs every dt_out (z: Bouc-Wen variable, 0 for Coulomb)
    peaks_t, peaks_u    : successive displacement peaks (reversals u' = 0)
    u_max, acc_abs_max  : exact maxima of |u| and |a_abs| over the run
    pga                 : max |u_g''|
    capacity_exceeded   : |u| passed iso.capacity; t_capacity, u_at_capacity: when and where
                          first (None if not); capacity_hits: end-stop impacts (end_stop
                          "impact"; 1 with "stop", where the run ended at t_capacity)
    """

    isolator: Isolator
    motion: GroundMotion
    t: np.ndarray
    u: np.ndarray
    v: np.ndarray
    acc_abs: np.ndarray
    z: np.ndarray
    peaks_t: np.ndarray
    peaks_u: np.ndarray
    u_max: float
    acc_abs_max: float
    pga: float
    stats: dict
    t_capacity: float | None = None
    u_at_capacity: float | None = None
    capacity_hits: int = 0
    end_stop: str = "stop"
    end_stop_restitution: float = END_STOP_RESTITUTION

    @property
    def outcome(self) -> str:
        """"isolator capacity exceeded" if the run ended there (end_stop "stop"), "end-stop
        impact" if the plate hit the end stop and went on (end_stop "impact"), else "ok"."""
        if not self.capacity_exceeded:
            return "ok"
        return CAPACITY_EXCEEDED if self.end_stop == "stop" else "end-stop impact"

    @property
    def efficiency(self) -> float:
        """Peak absolute acceleration isolated / fixed (the fixed statue feels the ground): Table 26."""
        return self.acc_abs_max / self.pga if self.pga > 0 else float("nan")

    def history_csv(self) -> str:
        """t, u, v, a_abs, z every dt_out (:data:`HISTORY_HEADER`, SI units), readable by `isolator identify`:
        a run that stopped at the capacity ends with its last finite sample and a comment line saying why
        (:func:`stop_line`); no cell is ever nan or inf."""
        from ..io.csvsafe import csv_text, num_cell

        cols = (self.t, self.u, self.v, self.acc_abs, self.z)
        n = finite_length(*cols)
        text = csv_text(HISTORY_HEADER, ([num_cell(x) for x in row] for row in zip(*(c[:n] for c in cols))))
        if n < len(self.t):
            why = self.outcome if self.capacity_exceeded else "non-finite state"
            text += stop_line(why, self.t_capacity, self.u_at_capacity, n, len(self.t)) + "\n"
        return text

    def to_dict(self) -> dict:
        return {
            "isolator": self.isolator.to_dict(), "motion": self.motion.to_dict(), "outcome": self.outcome,
            "u_max": self.u_max, "acc_abs_max": self.acc_abs_max, "pga": self.pga,
            "efficiency": self.efficiency, "peaks": self.peaks_u.tolist(), "peaks_t": self.peaks_t.tolist(),
            **capacity_dict(self.capacity, self.capacity_exceeded, self.t_capacity, self.u_at_capacity,
                            self.capacity_hits, self.end_stop, self.end_stop_restitution),
            "solver": self.stats,
        }


def simulate(iso: Isolator, motion: GroundMotion, *, u0: float = 0.0, v0: float = 0.0,
             t_end: float | None = None, dt_out: float = 0.005, rtol: float = 1e-9, end_stop: str = "stop",
             e_stop: float = END_STOP_RESTITUTION) -> IsolatorResult:
    """Integrate the top plate from (u0, v0) at t = 0 to t_end (default: the end of
    the motion + 10 s). Coulomb: exact closed form; Bouc-Wen: adaptive 5(4) steps
    at relative tolerance ``rtol`` (see kernel.py). ``end_stop``: what happens where
    |u| passes ``iso.capacity`` ("stop": the run ends, "impact": the plate rebounds
    with restitution ``e_stop``; module docstring)."""
    if t_end is None:
        t_end = motion.end + FREE_TIME
    for name, value in (("u0", u0), ("v0", v0)):
        if not math.isfinite(value):
            raise InputError(f"{name} must be finite, got {value}")
    if not (math.isfinite(t_end) and t_end > 0):
        raise InputError(f"t_end must be positive, got {t_end}")
    if not (math.isfinite(dt_out) and dt_out > 0):
        raise InputError(f"dt_out must be positive, got {dt_out}")
    if not (0 < rtol < 1):
        raise InputError(f"rtol must be in (0, 1), got {rtol}")
    check_end_stop(end_stop, e_stop)
    cap = float(iso.capacity)
    if end_stop == "impact" and abs(u0) > cap:
        raise InputError(f"u0 = {u0} m starts beyond the end stop at the capacity {cap} m")
    stop = 0 if end_stop == "stop" else 1
    from ..compute.budget import check_history

    # the outputs (t, u, v, acc_abs, z), their copies in the result and the coupled run of a statue on it
    n_out = check_history(t_end, dt_out, HISTORY_BYTES_PER_SAMPLE, what="the plate history")
    kind, M, samples = motion.kernel_args()
    out_u = np.zeros(n_out)
    out_v = np.zeros(n_out)
    out_a = np.zeros(n_out)
    out_z = np.zeros(n_out)
    stats = np.zeros(IK.N_I)
    pk_t = np.empty(64)
    pk_u = np.empty(64)
    om = float(iso.omega)
    mug = float(iso.mu * iso.g)
    ensure_compiled()
    if iso.model == "coulomb":
        n_pk, pk_t, pk_u = IK.coulomb(om, mug, kind, M, samples, float(u0), float(v0), float(t_end), float(dt_out),
                                      cap, stop, float(e_stop), out_u, out_v, out_a, pk_t, pk_u, stats)
    else:
        scale = max(abs(u0), abs(v0) / om, motion.pga / om**2, iso.u_y)
        n_pk, pk_t, pk_u = IK.boucwen(om, mug, float(iso.q), int(iso.n), kind, M, samples, float(u0), float(v0),
                                      float(t_end), float(dt_out), float(rtol), 1e-3 * rtol * scale,
                                      cap, stop, float(e_stop), out_u, out_v, out_a, out_z, pk_t, pk_u, stats)
    t = np.arange(n_out) * dt_out
    hit = math.isfinite(stats[IK.I_TCAP])
    return IsolatorResult(
        isolator=iso, motion=motion, t=t, u=out_u, v=out_v, acc_abs=out_a, z=out_z,
        peaks_t=pk_t[:n_pk].copy(), peaks_u=pk_u[:n_pk].copy(),
        u_max=float(stats[IK.I_UMAX]), acc_abs_max=float(stats[IK.I_AMAX]), pga=motion.pga,
        stats={"steps": int(stats[IK.I_NSTEPS]), "rejected": int(stats[IK.I_NREJ]), "t_final": float(stats[IK.I_TFINAL]),
               "sliding_time": float(stats[IK.I_TSLIDE])},
        t_capacity=float(stats[IK.I_TCAP]) if hit else None, u_at_capacity=float(stats[IK.I_UCAP]) if hit else None,
        capacity_hits=int(stats[IK.I_NHITS]), end_stop=end_stop, end_stop_restitution=float(e_stop),
    )
