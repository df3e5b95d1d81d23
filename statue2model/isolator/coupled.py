"""The statue rocking on the moving top plate: the coupled (two-way) 2-DOF model.

The plate and the statue are integrated together: full contact is checked, not
assumed, and the rocking statue pushes the plate back (a one-way model, the statue
driven by the plate-only acceleration, leaves that out; statue_on_plate reports both).

Unknowns (SI units): u, the top plate's displacement relative to the ground (m);
theta, the statue's rotation (rad; theta > 0 about the right pivot, x = +b_R,
MODEL.md section 2). Ground acceleration f(t) = u_g''; plate absolute
acceleration a = f + u''. Masses: M = iso.M supported (top plate m_o = M - m plus
statue m = model.params.m; M > m is required); W = M g.

Plate (MODEL.md section 4). Restoring force of the balls F_r:

    Coulomb   F_r = (W / R_hat) u + mu W sgn(u')     (stuck while u' = 0 and the static force fits in mu W)
    Bouc-Wen  F_r = a_bw k_i u + (1 - a_bw) F_y z,  a_bw = 1/q, k_i = q W / R_hat, F_y = mu W
              (z from kernel.z_map, exactly, along each branch of constant sgn(u'))

Statue (imperfect asymmetric model, eqs. 35-37), driven by a:

    theta > 0:  theta'' = -p_R^2 [alpha(theta) sin(delta_R - theta) + (a/g) cos(delta_R - theta)]
    theta < 0:  theta'' =  p_L^2 [alpha(theta) sin(delta_L + theta) - (a/g) cos(delta_L + theta)]
    full contact (theta = 0) while -alpha_R a_R <= a <= alpha_L a_L

Its centre of mass relative to the plate (R_i = sqrt(b_i^2 + h^2)):

    theta > 0:  x_rel =  b_R - R_R sin(delta_R - theta),
                x_rel'' = R_R cos(delta_R - theta) theta'' + R_R sin(delta_R - theta) theta'^2
    theta < 0:  x_rel = -b_L + R_L sin(delta_L + theta),
                x_rel'' = R_L cos(delta_L + theta) theta'' - R_L sin(delta_L + theta) theta'^2

Horizontal balance of plate + statue:

    M (f + u'') + m x_rel'' = -F_r

With theta'' = A0 + A1 a and x_rel'' = c theta'' + d theta'^2 this gives
a (M + m c A1) = -F_r - m (c A0 + d theta'^2); M + m c A1 >= m_o > 0 (because
m R^2 / I_pivot <= 1), so the solve is always well conditioned. While the statue
is in full contact x_rel'' = 0 and the plate obeys eq. 20 exactly. A stuck
Coulomb plate under a rocking statue stays stuck while
|k u + M f + m x_rel''(a = f)| <= mu W.

Modelling choices (assumptions):

* W = M g is kept constant: the vertical inertia of the rocking statue does not
  change the friction force mu W nor the pendulum stiffness W / R_hat.
* Impact at theta = 0: theta'+ = e theta'- (e of the landing side, possibly
  speed dependent, as in the rocking engine), and the horizontal momentum of plate
  + statue, M u' + m x_rel', is conserved through the impact: the balls transmit
  no impulsive horizontal force (not even a stuck Coulomb plate resists the
  impulse). Since x_rel' = h theta' at theta = 0 on both sides,
  u'+ = u'- - (m/M) h (e - 1) theta'-.
* Zeno (impacts accumulating, e < 1): once the next excursion would peak below
  rest_tol * delta, the impact is taken as plastic (e = 0): the statue returns to
  full contact at once and its remaining horizontal momentum goes to the plate
  (u'+ = u'- + (m/M) h theta'-). Re-uplift is decided by the limits on a.
* Overturning: |theta| reaches delta_side; the run stops there (samples after it
  are nan with phase 3).
* Linearised rocking models are not supported (InputError).
* Capacity (``iso.capacity``, ``end_stop``; dynamics.py): with "stop" the run ends when
  |u| passes the capacity (outcome "isolator capacity exceeded", samples after it nan
  with phase 4); with "impact" the top plate rebounds on a rigid end stop,
  u'+ = -e u'- (e = END_STOP_RESTITUTION, assumed), and the jump is an impulse of the
  plate's absolute acceleration: the statue's theta' jumps by A1 (u'+ - u'-) on its pivot
  (theta'' = A0 + A1 a integrated across the impulse), or a statue in full contact is
  lifted by it; acc_abs_max leaves the impulse itself out (it is infinite).

Screening (Coulomb plates): the plate alone is simulated first
(:func:`..rocking.engine.simulate`, exact); if its absolute acceleration stays inside the
statue's limits the statue never lifts and the coupled result is the plate result
(``stats['coupled_integration'] = False``). Otherwise the coupled system is
integrated from t = 0 (coupled_kernel.py); if the statue still never lifts, the
plate result is returned as well (``stats['uplift_found'] = False``). Bouc-Wen
plates are always integrated by coupled_kernel (whose plate part agrees with the
plate solver to ~1e-8 at rtol 1e-9 where that solver is right). With end_stop "impact",
a plate that reaches its capacity is always integrated with the statue (the impact
may lift it).

Example
-------
>>> from statue2model.hazard import motions
>>> from statue2model.rocking.model import RockingModel
>>> from statue2model.geometry.rocking_params import RockingParams
>>> from statue2model.isolator.device import Isolator
>>> block = RockingParams.rectangular_block(b=0.05, h=0.25, m=10.0)
>>> model = RockingModel.housner(block, e_L=0.9, e_R=0.9)
>>> iso = Isolator(R=0.30, r=0.0183, M=15.0, mu=0.01)
>>> quiet = simulate_coupled(iso, model, motions.sine_pulse(0.5, 1.0))
>>> quiet.uplift, quiet.outcome, quiet.stats["coupled_integration"]
(False, 'no motion', False)
>>> res = simulate_coupled(iso, model, motions.free(), theta0=0.05)   # free rocking pushes the plate
>>> res.uplift, res.n_impacts > 3, res.u_max > 1e-3
(True, True, True)
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..compute.compile import ensure_compiled
from ..rocking.engine import outcome_name
from ..rocking.model import RockingModel
from ..hazard.motions import GroundMotion
from ..errors import InputError
from . import coupled_kernel as CK
from . import time_history as ID
from .device import Isolator

FREE_TIME = ID.FREE_TIME


@dataclass(frozen=True, eq=False)
class CoupledResult(ID.CapacityTracked):
    """Time histories and peaks of the coupled plate + statue (SI units, rad).

    t, u, v, acc_abs, z : plate outputs every dt_out (acc_abs = f + u''; z: Bouc-Wen, 0 for Coulomb)
    theta, theta_dot, phase : statue outputs (phase 0 stick, 1 rolling transition, 2 rocking,
                          3 overturned; after overturning the state samples are nan)
    u_max, acc_abs_max  : max |u| (exact), max |a_abs| (over the steps' events and 1/8 samples)
    theta_max_L, theta_max_R : largest |theta| on each pivot (located peaks)
    impacts             : (n, 6) t, landing side (-1 left edge, +1 right), theta'-, theta'+, u'-, u'+
    peaks_t, peaks_theta, peaks_side : extrema of |theta|; peaks_u_t, peaks_u : plate reversals
    plate               : the plate-only IsolatorResult (None if not computed)
    t_capacity, u_at_capacity : first time and displacement at which |u| reached iso.capacity
                          (None if never); capacity_hits: end-stop impacts (end_stop "impact")
    """

    isolator: Isolator
    model: RockingModel
    motion: GroundMotion
    t: np.ndarray
    u: np.ndarray
    v: np.ndarray
    acc_abs: np.ndarray
    z: np.ndarray
    theta: np.ndarray
    theta_dot: np.ndarray
    phase: np.ndarray
    u_max: float
    acc_abs_max: float
    pga: float
    theta_max_L: float
    theta_max_R: float
    t_uplift: float | None
    impacts: np.ndarray
    n_impacts: int
    peaks_t: np.ndarray
    peaks_theta: np.ndarray
    peaks_side: np.ndarray
    peaks_u_t: np.ndarray
    peaks_u: np.ndarray
    overturned: bool
    overturn_time: float | None
    overturn_side: str | None
    impacts_before_overturn: int | None
    full_uplift: bool
    plate: object
    stats: dict
    t_capacity: float | None = None
    u_at_capacity: float | None = None
    capacity_hits: int = 0
    end_stop: str = "stop"
    end_stop_restitution: float = ID.END_STOP_RESTITUTION

    @property
    def uplift(self) -> bool:
        return self.t_uplift is not None

    @property
    def theta_max_over_delta(self) -> float:
        p = self.model.params
        return max(self.theta_max_L / p.delta_L, self.theta_max_R / p.delta_R)

    @property
    def efficiency(self) -> float:
        """Peak absolute plate acceleration / peak ground acceleration (Table 26)."""
        return self.acc_abs_max / self.pga if self.pga > 0 else float("nan")

    @property
    def outcome(self) -> str:
        """'no motion', 'rolling', 'rocking' or 'overturn mode k' (as the rocking engine), or
        'isolator capacity exceeded' when the run ended there (end_stop "stop")."""
        if self.capacity_exceeded and self.end_stop == "stop":
            return ID.CAPACITY_EXCEEDED
        return outcome_name(self.uplift, self.full_uplift or self.model.kind == "housner", self.overturned,
                            self.impacts_before_overturn)

    def to_dict(self, history: bool = False) -> dict:
        d = {
            "isolator": self.isolator.to_dict(), "model": self.model.to_dict(), "motion": self.motion.to_dict(),
            "u_max": self.u_max, "acc_abs_max": self.acc_abs_max, "pga": self.pga, "efficiency": self.efficiency,
            "uplift": self.uplift, "uplift_limits": list(self.model.uplift_limits), "t_uplift": self.t_uplift,
            "outcome": self.outcome, "theta_max_L": self.theta_max_L, "theta_max_R": self.theta_max_R,
            "theta_max_over_delta": self.theta_max_over_delta, "n_impacts": self.n_impacts,
            "impact_times": self.impacts[:, 0].tolist(), "overturned": self.overturned,
            "overturn_time": self.overturn_time, "overturn_side": self.overturn_side,
            "impacts_before_overturn": self.impacts_before_overturn,
            "peaks_u": self.peaks_u.tolist(), "peaks_u_t": self.peaks_u_t.tolist(),
            **ID.capacity_dict(self.capacity, self.capacity_exceeded, self.t_capacity, self.u_at_capacity,
                               self.capacity_hits, self.end_stop, self.end_stop_restitution),
            "solver": self.stats,
        }
        if history:     # up to the last finite sample: a stop (capacity, overturning) leaves nan after it
            keys = ("t", "u", "v", "acc_abs", "z", "theta", "theta_dot", "phase")
            n = ID.finite_length(*(getattr(self, k) for k in keys))
            d["history"] = {k: getattr(self, k)[:n].tolist() for k in keys}
            d["history_stopped"] = None if n == len(self.t) else self.outcome   # why it ends early
        return d


def _check(iso, model, motion, u0, v0, theta0, omega0, t_end, dt_out, rtol, rest_tol):
    if not isinstance(iso, Isolator):
        raise InputError("iso must be an Isolator")
    if not isinstance(model, RockingModel):
        raise InputError("model must be a RockingModel")
    if not isinstance(motion, GroundMotion):
        raise InputError("motion must be a GroundMotion")
    if model.linearised:
        raise InputError("the coupled plate + statue model needs the nonlinear rocking model (linearised=False)")
    m = model.params.m
    if not iso.M > m:
        raise InputError(f"the supported mass M = {iso.M:g} kg must exceed the statue's mass m = {m:g} kg "
                         "(M = top plate + statue)")
    for name, value in (("u0", u0), ("v0", v0), ("theta0", theta0), ("omega0", omega0)):
        if not math.isfinite(value):
            raise InputError(f"{name} must be finite, got {value}")
    p = model.params
    if theta0 > 0 and theta0 >= p.delta_R or theta0 < 0 and -theta0 >= p.delta_L:
        raise InputError(f"initial rotation theta0 = {theta0} rad is beyond the overturning angle "
                         f"(delta_R = {p.delta_R:.4g}, delta_L = {p.delta_L:.4g})")
    if not (math.isfinite(t_end) and t_end > 0):
        raise InputError(f"t_end must be a positive time in s, got {t_end}")
    if not (math.isfinite(dt_out) and dt_out > 0):
        raise InputError(f"dt_out must be a positive time step, got {dt_out}")
    if not (1e-14 <= rtol <= 1e-2):
        raise InputError(f"rtol must lie in [1e-14, 1e-2], got {rtol}")
    if not (math.isfinite(rest_tol) and 0 < rest_tol < 1):
        raise InputError(f"rest_tol must lie in (0, 1), got {rest_tol}")
    from ..compute.budget import check_history

    # plate (t, u, v, acc_abs, z) and statue (theta, theta', phase) outputs, and the plate screening run
    return check_history(t_end, dt_out, 128, what="the coupled history")


def parameter_vector(iso: Isolator, model: RockingModel, rest_tol: float = 1e-9, end_stop: str = "stop",
                     e_stop: float = ID.END_STOP_RESTITUTION) -> np.ndarray:
    """The flat parameter vector of coupled_kernel: the rocking model's kernel vector
    (:meth:`RockingModel.kernel_vector`, indices of statue2model.rocking.kernel) followed by
    the plate's entries and the statue's geometry (indices CK.Q_*)."""
    p = model.params
    Q = np.zeros(CK.N_Q)
    Q[:CK.N_P] = model.kernel_vector(rest_tol)
    Q[CK.Q_OM2] = iso.omega ** 2
    Q[CK.Q_MUG] = iso.mu * iso.g
    Q[CK.Q_BW] = 1.0 if iso.model == "boucwen" else 0.0
    if iso.model == "boucwen":
        Q[CK.Q_CZ] = (1.0 - 1.0 / iso.q) * iso.mu * iso.g
        Q[CK.Q_UY] = iso.mu * iso.g / (iso.q * iso.omega ** 2)
        Q[CK.Q_NBW] = iso.n
    Q[CK.Q_MR] = p.m / iso.M
    Q[CK.Q_RL], Q[CK.Q_RR] = p.d_L, p.d_R
    Q[CK.Q_H] = p.h
    Q[CK.Q_CAP] = iso.capacity
    Q[CK.Q_STOP] = 0.0 if end_stop == "stop" else 1.0
    Q[CK.Q_ESTOP] = e_stop
    return Q


def _from_plate(iso, model, motion, plate, n_out, stats) -> CoupledResult:
    zeros = np.zeros(n_out)
    e = np.empty(0)
    return CoupledResult(
        isolator=iso, model=model, motion=motion, t=plate.t, u=plate.u, v=plate.v, acc_abs=plate.acc_abs,
        z=plate.z, theta=zeros, theta_dot=zeros.copy(), phase=np.zeros(n_out, dtype=int),
        u_max=plate.u_max, acc_abs_max=plate.acc_abs_max, pga=plate.pga, theta_max_L=0.0, theta_max_R=0.0,
        t_uplift=None, impacts=np.empty((0, CK.N_IMP_COLS)), n_impacts=0, peaks_t=e, peaks_theta=e.copy(),
        peaks_side=np.empty(0, dtype="<U1"), peaks_u_t=plate.peaks_t, peaks_u=plate.peaks_u,
        overturned=False, overturn_time=None, overturn_side=None, impacts_before_overturn=None,
        full_uplift=False, plate=plate, stats=stats, t_capacity=plate.t_capacity, u_at_capacity=plate.u_at_capacity,
        capacity_hits=plate.capacity_hits, end_stop=plate.end_stop, end_stop_restitution=plate.end_stop_restitution)


def simulate_coupled(iso: Isolator, model: RockingModel, motion: GroundMotion, *, u0: float = 0.0,
                     v0: float = 0.0, theta0: float = 0.0, omega0: float = 0.0, t_end: float | None = None,
                     dt_out: float = 0.005, rtol: float = 1e-9, rest_tol: float = 1e-9, screen: bool = True,
                     max_records: int = 10_000, max_steps: int = 20_000_000, end_stop: str = "stop",
                     e_stop: float = ID.END_STOP_RESTITUTION) -> CoupledResult:
    """Integrate plate + statue from (u0, v0, theta0, omega0) at t = 0 to t_end
    (default: the end of the motion + 10 s, as the plate alone); stops at overturning.

    ``rtol``: local relative tolerance of the DOP853 steps (absolute tolerances:
    rtol x 1e-2 x the plate's displacement scale, rtol x delta for theta).
    ``screen``: run the plate alone first and skip the coupled integration if the
    statue cannot lift (see the module docstring); with ``screen=False`` the coupled
    system is always integrated and its own histories are returned. ``rest_tol``: Zeno threshold
    (fraction of delta), as in the rocking engine. ``end_stop``, ``e_stop``: what happens at
    ``iso.capacity`` (module docstring; "stop" ends the run there).
    """
    u0, v0, theta0, omega0 = float(u0), float(v0), float(theta0), float(omega0)
    if t_end is None:
        t_end = motion.end + FREE_TIME if isinstance(motion, GroundMotion) else float("nan")
    t_end = float(t_end)
    dt_out = float(dt_out)
    n_out = _check(iso, model, motion, u0, v0, theta0, omega0, t_end, dt_out, rtol, rest_tol)
    ID.check_end_stop(end_stop, e_stop)
    if end_stop == "impact" and abs(u0) > iso.capacity:
        raise InputError(f"u0 = {u0} m starts beyond the end stop at the capacity {iso.capacity} m")
    up, dn = model.uplift_limits
    plate = None
    still = theta0 == 0.0 and omega0 == 0.0
    # Screening by the plate alone, Coulomb only: its acc_abs_max is exact there (the
    # Bouc-Wen plate solver reads it at step ends only, so Bouc-Wen plates are always
    # integrated here).
    screen = screen and iso.model == "coulomb"
    if screen and still:
        plate = ID.simulate(iso, motion, u0=u0, v0=v0, t_end=t_end, dt_out=dt_out, rtol=rtol, end_stop=end_stop,
                            e_stop=e_stop)
        if plate.acc_abs_max < min(up, dn) * (1.0 - 1e-12) and not (plate.capacity_exceeded and end_stop == "impact"):
            return _from_plate(iso, model, motion, plate, n_out,
                               {"coupled_integration": False, "plate": plate.stats})
    Q = parameter_vector(iso, model, rest_tol, end_stop, e_stop)
    eLw, eLe = model.e_L.arrays()
    eRw, eRe = model.e_R.arrays()
    kind, Mv, samples = motion.kernel_args()
    p = model.params
    om = iso.omega
    scale_u = max(abs(u0), abs(v0) / om, motion.pga / om ** 2, iso.mu * iso.g / om ** 2,
                  p.m / iso.M * p.h * min(p.delta_L, p.delta_R), 1e-9)
    dmin = min(p.delta_L, p.delta_R)
    atol = np.array([1e-2 * rtol * scale_u, 1e-2 * rtol * scale_u * om, rtol * dmin,
                     rtol * dmin * max(p.p_L, p.p_R)])
    out = np.zeros((n_out, 7))
    imp = np.empty((max_records, CK.N_IMP_COLS))
    peaks = np.empty((max_records, 3))
    upeaks = np.empty((max_records, 2))
    S = np.zeros(CK.N_S)
    ensure_compiled()
    CK.simulate_kernel(Q, eLw, eLe, eRw, eRe, kind, Mv, samples, u0, v0, theta0, omega0, t_end, dt_out,
                       float(rtol), atol, int(max_steps), out, imp, peaks, upeaks, S)
    status = int(S[CK.S_STATUS])
    if status == CK.STATUS_MAX_STEPS:
        raise RuntimeError(f"coupled solver stopped after {max_steps} steps at t = {S[CK.S_TFINAL]:.6g} s")
    if status == CK.STATUS_STALLED:
        raise RuntimeError(f"coupled solver made no progress at t = {S[CK.S_TFINAL]:.6g} s")
    stats = {"coupled_integration": True, "steps": int(S[CK.S_NSTEPS]), "rejected": int(S[CK.S_NREJ]),
             "t_final": float(S[CK.S_TFINAL]), "n_uplifts": int(S[CK.S_N_UPLIFTS]),
             "n_zeno": int(S[CK.S_N_ZENO])}
    t_up = float(S[CK.S_T_UPLIFT])
    if not math.isfinite(t_up) and still and screen:
        stats["uplift_found"] = False
        if plate is None:
            plate = ID.simulate(iso, motion, u0=u0, v0=v0, t_end=t_end, dt_out=dt_out, rtol=rtol, end_stop=end_stop,
                                e_stop=e_stop)
        return _from_plate(iso, model, motion, plate, n_out, stats)
    n_imp = int(S[CK.S_N_IMP])
    npk = min(int(S[CK.S_N_PEAKS]), max_records)
    nupk = min(int(S[CK.S_N_UPEAKS]), max_records)
    overturned = bool(S[CK.S_OVERTURNED])
    hit = math.isfinite(S[CK.S_T_CAP])
    side = {1.0: "R", -1.0: "L"}
    return CoupledResult(
        isolator=iso, model=model, motion=motion, t=np.arange(n_out) * dt_out,
        u=out[:, 0].copy(), v=out[:, 1].copy(), acc_abs=out[:, 2].copy(), z=out[:, 3].copy(),
        theta=out[:, 4].copy(), theta_dot=out[:, 5].copy(), phase=out[:, 6].astype(int),
        u_max=float(S[CK.S_UMAX]), acc_abs_max=float(S[CK.S_AMAX]), pga=motion.pga,
        theta_max_L=float(S[CK.S_QMAX_L]), theta_max_R=float(S[CK.S_QMAX_R]),
        t_uplift=t_up if math.isfinite(t_up) else None,
        impacts=imp[:min(n_imp, max_records)].copy(), n_impacts=n_imp,
        peaks_t=peaks[:npk, 0].copy(), peaks_theta=peaks[:npk, 1].copy(),
        peaks_side=np.array([side[v] for v in peaks[:npk, 2]], dtype="<U1"),
        peaks_u_t=upeaks[:nupk, 0].copy(), peaks_u=upeaks[:nupk, 1].copy(),
        overturned=overturned, overturn_time=float(S[CK.S_T_OVERTURN]) if overturned else None,
        overturn_side=side.get(float(S[CK.S_OT_SIDE])) if overturned else None,
        impacts_before_overturn=int(S[CK.S_IMP_BEFORE_OT]) if overturned else None,
        full_uplift=bool(S[CK.S_FULL_UPLIFT]), plate=plate, stats=stats,
        t_capacity=float(S[CK.S_T_CAP]) if hit else None, u_at_capacity=float(S[CK.S_U_CAP]) if hit else None,
        capacity_hits=int(S[CK.S_N_HITS]), end_stop=end_stop, end_stop_restitution=float(e_stop))
