"""The isolator's top plate under a ground motion, and the statue riding on it.

    M u_o'' + F(u_o, u_o') = -M u_g''          (eq. 20 / eq. 24)

u_o is the plate's displacement relative to the ground (m); the statue feels the
absolute plate acceleration a_abs = u_g'' + u_o''. The problem (an immutable
:class:`~statue2model.isolator.device.Isolator` and a
:class:`~statue2model.dynamics.motions.GroundMotion`) is kept apart from the
solvers in kernel.py; :func:`simulate` returns an :class:`IsolatorResult`.

With a statue on top (:func:`statue_on_plate`), its uplift limits are checked
against a_abs (full contact is checked, not assumed). Where a_abs crosses them,
the statue's rocking is integrated with the rocking engine under a_abs as its
ground motion: the second degree of freedom, driven by the plate. The statue's
rocking is not fed back into the plate (its horizontal reaction changes by far
less than the plate's inertia while it only starts to rock; see the limits in
the README).

Example
-------
>>> from statue2model.dynamics import motions
>>> from statue2model.isolator.device import Isolator
>>> iso = Isolator(R=0.30, r=0.0183, M=21.664, mu=0.0114)
>>> res = simulate(iso, motions.free(), u0=0.05, t_end=6.0)
>>> np.round(res.peaks_u, 5)              # each half cycle loses 2 mu R_hat = 12.8 mm
array([-0.03715,  0.02431, -0.01146, -0.00138])
>>> round(float(res.peaks_t[0]), 4), round(iso.T / 2, 4)   # Coulomb friction leaves the period alone
(0.7529, 0.7529)
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..dynamics.motions import GroundMotion
from ..errors import InputError
from . import kernel as IK
from .device import Isolator

FREE_TIME = 10.0


@dataclass(frozen=True)
class IsolatorResult:
    """Time history and peaks of the top plate (SI units).

    t, u, v, acc_abs, z : outputs every dt_out (z: Bouc-Wen variable, 0 for Coulomb)
    peaks_t, peaks_u    : successive displacement peaks (reversals u' = 0)
    u_max, acc_abs_max  : exact maxima of |u| and |a_abs| over the run
    pga                 : max |u_g''|
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

    @property
    def efficiency(self) -> float:
        """Peak absolute acceleration isolated / fixed (the fixed statue feels the ground): Table 26."""
        return self.acc_abs_max / self.pga if self.pga > 0 else float("nan")

    def to_dict(self) -> dict:
        return {
            "isolator": self.isolator.to_dict(), "motion": self.motion.to_dict(),
            "u_max": self.u_max, "acc_abs_max": self.acc_abs_max, "pga": self.pga,
            "efficiency": self.efficiency, "peaks": self.peaks_u.tolist(), "peaks_t": self.peaks_t.tolist(),
            "solver": self.stats,
        }


def simulate(iso: Isolator, motion: GroundMotion, *, u0: float = 0.0, v0: float = 0.0,
             t_end: float | None = None, dt_out: float = 0.005, rtol: float = 1e-9) -> IsolatorResult:
    """Integrate the top plate from (u0, v0) at t = 0 to t_end (default: the end of
    the motion + 10 s). Coulomb: exact closed form; Bouc-Wen: adaptive 5(4) steps
    at relative tolerance ``rtol`` (see kernel.py)."""
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
    n_out = int(math.floor(t_end / dt_out + 1e-9)) + 1
    if n_out > 50_000_000:
        raise InputError(f"{n_out} output samples: raise dt_out")
    kind, M, samples = motion.kernel_args()
    out_u = np.zeros(n_out)
    out_v = np.zeros(n_out)
    out_a = np.zeros(n_out)
    out_z = np.zeros(n_out)
    stats = np.zeros(IK.N_I)
    pk_t = np.empty(64)
    pk_u = np.empty(64)
    om = iso.omega
    mug = iso.mu * iso.g
    if iso.model == "coulomb":
        n_pk, pk_t, pk_u = IK.coulomb(om, mug, kind, M, samples, float(u0), float(v0), float(t_end), float(dt_out),
                                      out_u, out_v, out_a, pk_t, pk_u, stats)
    else:
        scale = max(abs(u0), abs(v0) / om, motion.pga / om**2, iso.u_y)
        n_pk, pk_t, pk_u = IK.boucwen(om, mug, float(iso.q), int(iso.n), kind, M, samples, float(u0), float(v0),
                                      float(t_end), float(dt_out), float(rtol), 1e-3 * rtol * scale,
                                      out_u, out_v, out_a, out_z, pk_t, pk_u, stats)
    t = np.arange(n_out) * dt_out
    return IsolatorResult(
        isolator=iso, motion=motion, t=t, u=out_u, v=out_v, acc_abs=out_a, z=out_z,
        peaks_t=pk_t[:n_pk].copy(), peaks_u=pk_u[:n_pk].copy(),
        u_max=float(stats[IK.I_UMAX]), acc_abs_max=float(stats[IK.I_AMAX]), pga=motion.pga,
        stats={"steps": int(stats[IK.I_NSTEPS]), "rejected": int(stats[IK.I_NREJ]), "t_final": float(stats[IK.I_TFINAL]),
               "sliding_time": float(stats[IK.I_TSLIDE])},
    )


@dataclass(frozen=True)
class StatueOnPlate:
    """The statue on the moving plate: uplift check and, where needed, its rocking."""

    plate: IsolatorResult
    limit_pos: float      # a_abs above this tips the statue (alpha_L a_L), m/s^2
    limit_neg: float      # a_abs below minus this tips it the other way (alpha_R a_R)
    uplift: bool
    rocking: object       # RockingResult of the statue under a_abs, or None
    fixed_rocking: object  # RockingResult without the isolator, or None

    def to_dict(self) -> dict:
        out = {
            "uplift": self.uplift, "uplift_limits": [self.limit_pos, self.limit_neg],
            "acc_abs_max": self.plate.acc_abs_max, "pga": self.plate.pga, "efficiency": self.plate.efficiency,
            "margin": min(self.limit_pos - float(self.plate.acc_abs.max()),
                          self.limit_neg + float(self.plate.acc_abs.min())),
        }
        if self.rocking is not None:
            out["rocking_on_plate"] = {"outcome": self.rocking.outcome,
                                       "theta_max_over_delta": self.rocking.theta_max_over_delta}
        if self.fixed_rocking is not None:
            out["rocking_fixed_base"] = {"outcome": self.fixed_rocking.outcome,
                                         "theta_max_over_delta": self.fixed_rocking.theta_max_over_delta}
        return out


def statue_on_plate(plate: IsolatorResult, rocking_model, compare_fixed: bool = True) -> StatueOnPlate:
    """Check the statue (a RockingModel) against the plate's absolute acceleration;
    integrate its rocking under that acceleration where a limit is crossed."""
    from ..dynamics import motions
    from ..dynamics.engine import simulate as rock

    up, dn = rocking_model.uplift_limits
    a = plate.acc_abs
    uplift = bool(a.max() > up or a.min() < -dn or plate.acc_abs_max > max(up, dn))
    rocking = None
    if uplift:
        dt = float(plate.t[1] - plate.t[0])
        rocking = rock(rocking_model, motions.record(a, dt, label="isolated plate"), t_end=float(plate.t[-1]))
    fixed = rock(rocking_model, plate.motion) if compare_fixed and plate.motion.kind != "none" else None
    return StatueOnPlate(plate=plate, limit_pos=up, limit_neg=dn, uplift=uplift, rocking=rocking, fixed_rocking=fixed)
