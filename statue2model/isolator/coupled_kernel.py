"""Compiled integrator of the coupled plate + statue system (numba); see coupled.py
for the mechanics and the interface.

State y = (u, u', theta, theta'); discrete mode md = (plate sign, u_r, z_r, rocking?,
side, region). Method:

* Dormand-Prince 8(5,3) (scipy's DOP853 tableau) on the 4-state system with
  scipy's error norm; the tableau, error norm, step-size controller, dense output,
  Illinois iteration, the loop's guard (max steps, stall) and the write-out of its
  counts are those of rocking/dop853.py, shared with the rocking kernel. Steps never
  cross a ground-motion breakpoint (hazard.motion_kernel.segment).
* The parameter vector Q is the rocking model's vector P (rocking/kernel.py, indices
  P2L ... EARLY, packed by RockingModel.kernel_vector) followed by the plate's entries
  and the statue's geometry (Q_OM2 ... Q_ESTOP); the statue's entries are read at
  the rocking kernel's indices.
* Events are located on the 7th-order dense output of each accepted step (sign
  changes sampled at 1/8 of the step, then the Illinois method to ~4 ulp in
  time); the state at the event is recomputed by a fresh step to the event time
  (and the step is retried shorter when that disagrees with the dense output):
  plate reversal u' = 0, plate unstick (Coulomb), statue uplift (a_abs leaves the
  limits), impact theta = 0, rolling-transition boundary |theta| = theta_side,
  overturning |theta| = delta_side, and the plate passing its capacity
  sgn(u') u = cap (inactive, no cost, when cap = inf). Peaks of |theta| are located
  the same way.
* At the capacity: Q_STOP = 0 ends the run (status like overturning, phase 4);
  Q_STOP = 1 is an impact of the top plate on a rigid end stop, u'+ = -e_stop u'-:
  the jump dv = u'+ - u'- of the plate is an impulse of the absolute plate
  acceleration, so the statue's theta' jumps by A1 dv (theta'' = A0 + A1 a,
  integrated across the impulse on its current pivot); a statue in full contact
  is lifted by it on the side the impulse tips it to (unless that excursion would
  peak below rest_tol delta: then it stays in contact and moves with the plate).
  A plate whose rebound would rise less than kernel.REST_TOL cap against a force
  pushing it back rests on the stop (md[MD_PIN] = side; u' = 0) until the force
  pulls it away: a one-sided stuck plate (Coulomb: beyond mu g; Bouc-Wen: any
  force away from the stop, z fixed meanwhile).
* A Coulomb plate stuck under a statue in full contact is not integrated: the
  next unstick / uplift is found in closed form on each motion piece (as in the
  plate and rocking kernels).
* Bouc-Wen z is never integrated: z = z_map(z_r, u - u_r, sgn u', u_y, n) on a
  branch of constant sgn(u') (isolator/kernel.py), so |z| <= 1 by construction.
* Output samples are read from the dense output: they never change the steps.
"""
from __future__ import annotations

import math

import numpy as np
from numba import njit

from ..rocking import dop853 as D8
from ..hazard import motion_kernel as MK
from ..rocking import kernel as K
from ..rocking.dop853 import STATUS_MAX_STEPS, STATUS_OK, STATUS_STALLED  # noqa: F401  (re-exported)
from ..rocking.kernel import AL, AR, DL, DR, GRAV, LIM_DN, LIM_UP, N_P, P2L, P2R, REST_TOL, TL, TR
from . import kernel as IK

_NS = D8.N_STAGES
_CX = D8.C
_NX = D8.N_STAGES_EXTENDED
_NI = D8.INTERPOLATOR_POWER
_EPS = D8.EPS
NY = 4

# --- parameter vector Q -------------------------------------------------------
# Q[:N_P]: the rocking model's vector P (rocking.kernel indices P2L ... EARLY, packed by
# RockingModel.kernel_vector; LIN and EARLY are 0 and unused here); then, from N_P on:
# the plate (omega^2, mu g, Bouc-Wen?, (1 - 1/q) mu g, u_y, n), m / M, the statue's
# d_L, d_R and h, the capacity, the end stop (0 stop, 1 impact) and its restitution
(Q_OM2, Q_MUG, Q_BW, Q_CZ, Q_UY, Q_NBW, Q_MR, Q_RL, Q_RR, Q_H, Q_CAP, Q_STOP, Q_ESTOP) = range(N_P, N_P + 13)
N_Q = N_P + 13

# --- mode vector md -----------------------------------------------------------
(MD_PS, MD_UR, MD_ZR, MD_ROCK, MD_SIDE, MD_REG, MD_PIN) = range(7)
N_MD = 7

# --- events -------------------------------------------------------------------
(EV_REV, EV_UNSTICK_P, EV_UNSTICK_N, EV_UPLIFT_L, EV_UPLIFT_R, EV_LO, EV_HI, EV_CAP) = range(8)
N_EV = 8

# --- statistics vector S ------------------------------------------------------
(S_UMAX, S_AMAX, S_NSTEPS, S_NREJ, S_TFINAL, S_STATUS, S_T_UPLIFT, S_N_IMP, S_OVERTURNED,
 S_T_OVERTURN, S_IMP_BEFORE_OT, S_OT_SIDE, S_QMAX_R, S_QMAX_L, S_FULL_UPLIFT, S_N_UPLIFTS,
 S_N_PEAKS, S_N_UPEAKS, S_N_OUT, S_N_ZENO, S_N_RHS, S_T_CAP, S_U_CAP, S_N_HITS, S_CAP_STOP) = range(25)
N_S = 25
STEP_STATS = (S_NSTEPS, S_NREJ, S_STATUS, S_TFINAL, S_N_OUT)
"""Where dop853.write_stats puts the integrator's counts of a run."""

# impact record columns: t, landing side (-1 left edge, +1 right edge), theta'-, theta'+, u'-, u'+
N_IMP_COLS = 6


@njit(cache=True, inline="always")
def _sgn(x):
    return 1.0 if x > 0.0 else (-1.0 if x < 0.0 else 0.0)


@njit(cache=True)
def _acc_dot(t, seg):
    """d/dt of the ground acceleration on one piece."""
    d = seg[1]
    if seg[3] != 0.0:
        d += seg[3] * seg[4] * math.cos(seg[4] * (t - seg[5]) + seg[6])
    return d


@njit(cache=True)
def _statue_terms(th, side, reg, Q):
    """theta'' = A0 + A1 a (a: absolute plate acceleration) and x_rel'' = c theta'' + d theta'^2."""
    if side > 0:
        x = Q[DR] - th
        al = Q[AR] + (1.0 - Q[AR]) * th / Q[TR] if reg == 0 else 1.0
        sx = math.sin(x)
        cx = math.cos(x)
        return -Q[P2R] * al * sx, -Q[P2R] * cx / Q[GRAV], Q[Q_RR] * cx, Q[Q_RR] * sx
    x = Q[DL] + th
    al = Q[AL] - (1.0 - Q[AL]) * th / Q[TL] if reg == 0 else 1.0
    sx = math.sin(x)
    cx = math.cos(x)
    return Q[P2L] * al * sx, -Q[P2L] * cx / Q[GRAV], Q[Q_RL] * cx, -Q[Q_RL] * sx


@njit(cache=True)
def _zeta(u, md, Q):
    """Bouc-Wen z on the current branch (0 for Coulomb)."""
    if Q[Q_BW] == 0.0:
        return 0.0
    ps = md[MD_PS]
    if ps == 0.0:
        return md[MD_ZR]
    return IK.z_map(md[MD_ZR], u - md[MD_UR], ps, Q[Q_UY], int(Q[Q_NBW]))


@njit(cache=True)
def _plate_force(u, md, Q):
    """Restoring force of the balls per unit supported mass, F_r / M (m/s^2)."""
    if Q[Q_BW] == 0.0:
        return Q[Q_OM2] * u + md[MD_PS] * Q[Q_MUG]
    return Q[Q_OM2] * u + Q[Q_CZ] * _zeta(u, md, Q)


@njit(cache=True)
def _stuck(md, Q):
    """The plate does not move relative to the ground: a stuck Coulomb plate, or any plate
    resting on its end stop."""
    return (Q[Q_BW] == 0.0 and md[MD_PS] == 0.0) or md[MD_PIN] != 0.0


@njit(cache=True)
def _hold_bounds(u, md, Q):
    """(up, dn): the stuck plate (statue in full contact) stays while -dn <= f <= up
    (f: ground acceleration); one-sided on the end stop."""
    pin = md[MD_PIN]
    if pin == 0.0:
        return Q[Q_MUG] - Q[Q_OM2] * u, Q[Q_MUG] + Q[Q_OM2] * u
    c = Q[Q_OM2] * u
    fr = Q[Q_MUG]
    if Q[Q_BW] != 0.0:
        c += Q[Q_CZ] * md[MD_ZR]
        fr = 0.0
    if pin > 0.0:
        return fr - c, np.inf
    return np.inf, fr + c


@njit(cache=True)
def _accs(t, u, th, om, md, Q, seg):
    """(u'', theta'', a_abs) of the coupled system."""
    f = MK.seg_acc(t, seg)
    if md[MD_ROCK] == 0.0:
        if _stuck(md, Q):
            return 0.0, 0.0, f
        a = -_plate_force(u, md, Q)
        return a - f, 0.0, a
    A0, A1, c, d = _statue_terms(th, md[MD_SIDE], md[MD_REG], Q)
    if _stuck(md, Q):
        return 0.0, A0 + A1 * f, f
    mr = Q[Q_MR]
    a = (-_plate_force(u, md, Q) - mr * (c * A0 + d * om * om)) / (1.0 + mr * c * A1)
    return a - f, A0 + A1 * a, a


@njit(cache=True)
def _demand(t, u, th, om, md, Q, seg):
    """D: friction force per unit M needed to keep a Coulomb plate stuck (u'' = 0):
    D = -(omega^2 u + f + (m/M) x_rel''); the plate stays stuck while |D| <= mu g."""
    f = MK.seg_acc(t, seg)
    xdd = 0.0
    if md[MD_ROCK] != 0.0:
        A0, A1, c, d = _statue_terms(th, md[MD_SIDE], md[MD_REG], Q)
        xdd = c * (A0 + A1 * f) + d * om * om
    return -(Q[Q_OM2] * u + f + Q[Q_MR] * xdd)


@njit(cache=True)
def _rhs(t, y, md, Q, seg, dy):
    udd, thdd, _ = _accs(t, y[0], y[2], y[3], md, Q, seg)
    dy[0] = y[1]
    dy[1] = udd
    dy[2] = y[3]
    dy[3] = thdd


@njit(cache=True)
def _bounds(side, reg, Q):
    """(lo, hi) of q = side * theta in region reg."""
    tr = Q[TR] if side > 0 else Q[TL]
    d = Q[DR] if side > 0 else Q[DL]
    if tr > 0.0:
        if reg == 0:
            return 0.0, min(tr, d)
        return min(tr, d), d
    return 0.0, d


@njit(cache=True)
def _start_region(side, Q):
    tr = Q[TR] if side > 0 else Q[TL]
    return 0.0 if tr > 0.0 else 1.0


@njit(cache=True)
def _events(t, y, md, Q, seg, g):
    """Event functions: an event happens where g crosses from <= 0 to > 0 (-1: inactive)."""
    for i in range(N_EV):
        g[i] = -1.0
    ps = md[MD_PS]
    rock = md[MD_ROCK] != 0.0
    stuck = _stuck(md, Q)
    if ps != 0.0:
        g[EV_REV] = -ps * y[1]
    if stuck and rock:
        D = _demand(t, y[0], y[2], y[3], md, Q, seg)
        pin = md[MD_PIN]
        fr = Q[Q_MUG]
        if pin != 0.0 and Q[Q_BW] != 0.0:
            D -= Q[Q_CZ] * md[MD_ZR]
            fr = 0.0
        if pin <= 0.0:
            g[EV_UNSTICK_P] = D - fr
        if pin >= 0.0:
            g[EV_UNSTICK_N] = -D - fr
    if ps != 0.0 and Q[Q_CAP] < np.inf:
        g[EV_CAP] = ps * y[0] - Q[Q_CAP]
    if not rock and not stuck:
        a = -_plate_force(y[0], md, Q)
        g[EV_UPLIFT_L] = a - Q[LIM_UP]
        g[EV_UPLIFT_R] = -a - Q[LIM_DN]
    if rock:
        s = md[MD_SIDE]
        lo, hi = _bounds(s, md[MD_REG], Q)
        q = s * y[2]
        g[EV_LO] = lo - q
        g[EV_HI] = q - hi


# --- DOP853 on 4 states (rocking/dop853.py) ----------------------------------------
@njit(cache=True)
def _stage(i, t, y, h, md, Q, seg, Ks, ytmp, dy):
    D8.stage_state(i, y, h, Ks, ytmp)
    _rhs(t + _CX[i] * h, ytmp, md, Q, seg, dy)
    for c in range(NY):
        Ks[i, c] = dy[c]


@njit(cache=True)
def _step(t, y, f0, h, md, Q, seg, Ks, yn, ytmp, dy):
    """One DOP853 step of length h from (t, y) with slope f0; yn = y(t + h)."""
    for c in range(NY):
        Ks[0, c] = f0[c]
    for i in range(1, _NS):
        _stage(i, t, y, h, md, Q, seg, Ks, ytmp, dy)
    D8.combine(y, h, Ks, yn)


@njit(cache=True)
def _error_norm(h, y, yn, Ks, atol, rtol):
    return D8.error_norm(h, y, yn, Ks, atol, rtol)


@njit(cache=True)
def _dense_coeffs(t, y, yn, h, md, Q, seg, Ks, F, ytmp, dy):
    for i in range(_NS + 1, _NX):
        _stage(i, t, y, h, md, Q, seg, Ks, ytmp, dy)
    D8.dense_coeffs(y, yn, h, Ks, F)


@njit(cache=True)
def _dense(x, F, y, out):
    D8.dense(x, F, y, out)


@njit(cache=True)
def _event_at(k, x, t, h, F, y, md, Q, seg, yx, g):
    _dense(x, F, y, yx)
    _events(t + x * h, yx, md, Q, seg, g)
    return g[k]


@njit(cache=True)
def _locate(k, xa, ga, xb, gb, t, h, F, y, md, Q, seg, yx, g, xtol):
    """Illinois on the dense output: the crossing of event k in [xa, xb] (ga <= 0 < gb).
    Returns the end of the final bracket on the far side (g > 0 there)."""
    side = 0
    for _ in range(200):
        if xb - xa <= xtol:
            break
        x = D8.secant(xa, ga, xb, gb)
        gx = _event_at(k, x, t, h, F, y, md, Q, seg, yx, g)
        xa, ga, xb, gb, side = D8.illinois(xa, ga, xb, gb, side, x, gx, gx > 0.0)
    return xb


@njit(cache=True)
def _locate_peak(xa, fa, xb, fb, s, F, y, yx, xtol):
    """Root of s theta'(x) in [xa, xb] (fa > 0 >= fb) on the dense output (Illinois)."""
    side = 0
    x = xb
    for _ in range(200):
        if xb - xa <= xtol:
            break
        x = D8.secant(xa, fa, xb, fb)
        _dense(x, F, y, yx)
        fx = s * yx[3]
        xa, fa, xb, fb, side = D8.illinois(xa, fa, xb, fb, side, x, fx, fx <= 0.0)
    return x


@njit(cache=True)
def _record_output(io, t, y, md, Q, seg, out):
    _, _, a = _accs(t, y[0], y[2], y[3], md, Q, seg)
    out[io, 0] = y[0]
    out[io, 1] = y[1]
    out[io, 2] = a
    out[io, 3] = _zeta(y[0], md, Q)
    out[io, 4] = y[2]
    out[io, 5] = y[3]
    if md[MD_ROCK] == 0.0:
        out[io, 6] = 0.0
    else:
        out[io, 6] = 1.0 if md[MD_REG] == 0.0 else 2.0


@njit(cache=True)
def _plate_after_jump(t, y, md, Q, seg, ps_old):
    """Plate mode after an impact changed u' (or after a reversal, u' = 0)."""
    v = y[1]
    bw = Q[Q_BW] != 0.0
    if v != 0.0:
        s = _sgn(v)
        if bw and s != ps_old:
            z = _zeta(y[0], md, Q)
            md[MD_UR] = y[0]
            md[MD_ZR] = z
        md[MD_PS] = s
        return
    # at rest relative to the ground: reversal / stick decision
    if not bw:
        md[MD_PS] = 0.0
        D = _demand(t, y[0], y[2], y[3], md, Q, seg)
        if abs(D) > Q[Q_MUG] * (1.0 + 1e-12):
            md[MD_PS] = _sgn(D)
        return
    z = _zeta(y[0], md, Q)
    md[MD_UR] = y[0]
    md[MD_ZR] = z
    md[MD_PS] = 1.0
    udd, _, _ = _accs(t, y[0], y[2], y[3], md, Q, seg)
    if udd != 0.0:
        md[MD_PS] = _sgn(udd)
    elif ps_old != 0.0:
        md[MD_PS] = -ps_old
    else:
        fd = _acc_dot(t, seg)
        md[MD_PS] = -_sgn(fd) if fd != 0.0 else 1.0


@njit(cache=True)
def simulate_kernel(Q, eLw, eLe, eRw, eRe, kind, M, samples, u0, v0, theta0, omega0, t_end, dt_out,
                    rtol, atol, max_steps, out, imp, peaks, upeaks, S):
    """Integrate the coupled system from t = 0. out (n_out, 7): u, u', a_abs, z, theta,
    theta', phase at k dt_out; imp (cap, 6), peaks (cap, 3: t, |theta|, side),
    upeaks (cap, 2: t, u at reversals); S: statistics (S_*). Returns the number of
    output samples written."""
    for i in range(N_S):
        S[i] = 0.0
    S[S_T_UPLIFT] = np.nan
    S[S_T_OVERTURN] = np.nan
    seg = np.empty(8)
    Ks = np.empty((_NX, NY))
    F = np.empty((_NI, NY))
    y = np.empty(NY)
    yn = np.empty(NY)
    ye = np.empty(NY)
    yx = np.empty(NY)
    ytmp = np.empty(NY)
    dy = np.empty(NY)
    f0 = np.empty(NY)
    g = np.empty(N_EV)
    g0 = np.empty(N_EV)
    gp = np.empty((9, N_EV))
    md = np.zeros(N_MD)
    n_out = out.shape[0]
    cap_pk = peaks.shape[0]
    bw = Q[Q_BW] != 0.0
    om2 = Q[Q_OM2]
    t = 0.0
    y[0] = u0
    y[1] = v0
    y[2] = theta0
    y[3] = omega0
    # --- initial modes
    MK.segment(t, kind, M, samples, seg)
    md[MD_UR] = u0
    md[MD_ZR] = 0.0
    if theta0 != 0.0 or omega0 != 0.0:
        s = 1.0
        if theta0 < 0.0 or (theta0 == 0.0 and omega0 < 0.0):
            s = -1.0
        md[MD_ROCK] = 1.0
        md[MD_SIDE] = s
        _, hi0 = _bounds(s, 0.0, Q)
        tr = Q[TR] if s > 0 else Q[TL]
        md[MD_REG] = 0.0 if (tr > 0.0 and s * theta0 < hi0) else 1.0
        if md[MD_REG] == 1.0 and tr > 0.0:
            S[S_FULL_UPLIFT] = 1.0
        S[S_T_UPLIFT] = 0.0
        S[S_N_UPLIFTS] = 1.0
        if omega0 == 0.0:
            if cap_pk > 0:
                peaks[0, 0] = 0.0
                peaks[0, 1] = abs(theta0)
                peaks[0, 2] = s
            S[S_N_PEAKS] = 1.0
    else:
        md[MD_SIDE] = 1.0
        md[MD_REG] = 1.0
    if v0 != 0.0:
        md[MD_PS] = _sgn(v0)
    else:
        _plate_after_jump(t, y, md, Q, seg, 0.0)
    qmax_r = theta0 if theta0 > 0.0 else 0.0
    qmax_l = -theta0 if theta0 < 0.0 else 0.0
    umax = abs(u0)
    amax = 0.0
    n_imp = np.int64(0)
    n_pk = int(S[S_N_PEAKS])
    n_upk = np.int64(0)
    nsteps = 0
    nrej = 0
    status = STATUS_OK
    overturned = False
    capstop = False
    S[S_T_CAP] = np.nan
    S[S_U_CAP] = np.nan
    if abs(u0) > Q[Q_CAP]:      # released beyond the capacity
        S[S_T_CAP] = 0.0
        S[S_U_CAP] = u0
        S[S_N_HITS] = 1.0
        S[S_CAP_STOP] = 1.0
        capstop = True
        _record_output(np.int64(0), 0.0, y, md, Q, seg, out)
        t_end = 0.0
    pmax = math.sqrt(max(Q[P2L], Q[P2R]))
    h = min(0.05 / pmax, 0.02 / math.sqrt(om2))
    io = 1 if capstop else 0
    suppress = -1
    nudge = 0.0
    t_last = -1.0
    stall = 0
    while t < t_end:
        status, t_last, stall = D8.guard(t, t_last, stall, nsteps + nrej, max_steps)
        if status != STATUS_OK:
            break
        seg_end = MK.segment(t, kind, M, samples, seg)
        t_lim = min(seg_end, t_end)
        rock = md[MD_ROCK] != 0.0
        # ---------------- Coulomb plate stuck, statue in full contact: closed form
        if not rock and _stuck(md, Q):
            up, dn = _hold_bounds(y[0], md, Q)
            te_p, side_p = K._first_exceedance(t, t_lim, seg, up, dn)
            te_s, side_s = K._first_exceedance(t, t_lim, seg, Q[LIM_UP], Q[LIM_DN])
            t_stop = min(te_p, te_s, t_lim)
            while io < n_out and io * dt_out < t_stop:
                _record_output(io, io * dt_out, y, md, Q, seg, out)
                io += 1
            amax = max(amax, IK._max_abs_f(t, t_stop, seg, seg_end))
            if side_p != 0 and te_p <= te_s and te_p < t_lim:
                t = te_p
                md[MD_PS] = float(side_p)
                if md[MD_PIN] != 0.0:
                    md[MD_PIN] = 0.0
                    md[MD_UR] = y[0]
                continue
            if side_s != 0 and te_s < t_lim:
                s = float(side_s)
                reg = _start_region(s, Q)
                t_up = te_s
                A0, A1, _, _ = _statue_terms(0.0, s, reg, Q)
                thdd = A0 + A1 * MK.seg_acc(t_up, seg)
                nud = 4.0 * _EPS * max(1.0, abs(t_up))
                while s * thdd <= 0.0 and t_up < t_lim:
                    t_up += nud
                    nud *= 4.0
                    thdd = A0 + A1 * MK.seg_acc(t_up, seg)
                if s * thdd <= 0.0:
                    t = t_lim
                    continue
                while io < n_out and io * dt_out < t_up:
                    _record_output(io, io * dt_out, y, md, Q, seg, out)
                    io += 1
                t = t_up
                md[MD_ROCK] = 1.0
                md[MD_SIDE] = s
                md[MD_REG] = reg
                y[2] = 0.0
                y[3] = 0.0
                if S[S_N_UPLIFTS] == 0.0:
                    S[S_T_UPLIFT] = t
                S[S_N_UPLIFTS] += 1.0
                if reg == 1.0 and (Q[TR] if s > 0 else Q[TL]) > 0.0:
                    S[S_FULL_UPLIFT] = 1.0
                continue
            t = t_lim
            continue
        # ---------------- Bouc-Wen plate at rest with no force: wait for the ground
        if bw and md[MD_PS] == 0.0 and md[MD_PIN] == 0.0:
            _plate_after_jump(t, y, md, Q, seg, 0.0)
        # ---------------- events already due at t (a motion breakpoint, rounding)
        _events(t, y, md, Q, seg, g0)
        due = np.int64(-1)
        for k in range(N_EV):
            if g0[k] > 0.0 and k != suppress:
                due = k
                break
        if due >= 0:
            ok = _apply(due, t, y, md, Q, seg, eLw, eLe, eRw, eRe, imp, upeaks, S, n_imp, n_upk)
            n_imp = int(S[S_N_IMP])
            n_upk = int(S[S_N_UPEAKS])
            umax = max(umax, abs(y[0]))
            if ok == 2:
                overturned = True
                break
            if ok == 3:
                capstop = True
                break
            if ok == 0:
                suppress = due
                nudge = 4.0 * _EPS * max(1.0, abs(t)) if nudge == 0.0 else 4.0 * nudge
            else:
                suppress = -1
                nudge = 0.0
            continue
        # ---------------- one adaptive step
        _rhs(t, y, md, Q, seg, f0)
        hh = min(h, t_lim - t)
        if nudge > 0.0:
            hh = min(hh, nudge)
        hits = hh == t_lim - t
        _step(t, y, f0, hh, md, Q, seg, Ks, yn, ytmp, dy)
        tn = t_lim if hits else t + hh
        _rhs(tn, yn, md, Q, seg, dy)
        for c in range(NY):
            Ks[_NS, c] = dy[c]
        err = _error_norm(hh, y, yn, Ks, atol, rtol)
        if not (err <= 1.0):
            h = hh * D8.factor_reject(err) if err == err else 0.25 * hh
            nrej += 1
            continue
        h_next = D8.next_step(hh, err, hits, h)
        floor = D8.shortest(hh, t)
        _dense_coeffs(t, y, yn, hh, md, Q, seg, Ks, F, ytmp, dy)
        # sample events and the statue's angular velocity at x = j / 8
        for k in range(N_EV):
            gp[0, k] = g0[k]
        for j in range(1, 9):
            if j < 8:
                _dense(j / 8.0, F, y, yx)
                _events(t + j / 8.0 * hh, yx, md, Q, seg, g)
            else:
                _events(tn, yn, md, Q, seg, g)
            for k in range(N_EV):
                gp[j, k] = g[k]
        xtol = D8.event_xtol(t, hh)
        x_ev = 2.0
        k_ev = np.int64(-1)
        for k in range(N_EV):
            if k == suppress:
                continue
            for j in range(1, 9):
                if gp[j, k] > 0.0:
                    if gp[j - 1, k] <= 0.0 and (j - 1) / 8.0 < x_ev:
                        xr = _locate(k, (j - 1) / 8.0, gp[j - 1, k], j / 8.0, gp[j, k], t, hh, F, y, md, Q, seg,
                                     yx, g, xtol)
                        if xr < x_ev:
                            x_ev = xr
                            k_ev = k
                    break
        retry = False
        if k_ev >= 0:
            if x_ev >= 1.0:
                x_ev = 1.0
                for c in range(NY):
                    ye[c] = yn[c]
            else:
                _dense(x_ev, F, y, yx)
                _step(t, y, f0, x_ev * hh, md, Q, seg, Ks, ye, ytmp, dy)
                for c in range(NY):
                    if not floor and abs(ye[c] - yx[c]) > 10.0 * (atol[c] + rtol * abs(ye[c])):
                        retry = True
                # the fresh step overwrote the stages: rebuild the dense output for the outputs below
                _step(t, y, f0, hh, md, Q, seg, Ks, yn, ytmp, dy)
                _rhs(tn, yn, md, Q, seg, dy)
                for c in range(NY):
                    Ks[_NS, c] = dy[c]
                _dense_coeffs(t, y, yn, hh, md, Q, seg, Ks, F, ytmp, dy)
        if retry:
            h = 0.25 * hh
            nrej += 1
            continue
        nsteps += 1
        x_end = x_ev if k_ev >= 0 else 1.0
        t_ev = t + x_ev * hh if (k_ev >= 0 and x_ev < 1.0) else tn
        # peaks of |theta| inside [0, x_end]
        if rock:
            s = md[MD_SIDE]
            fp = s * y[3]
            xp = 0.0
            for j in range(1, 9):
                xj = j / 8.0
                if xj > x_end:
                    xj = x_end
                if xj == 1.0:
                    fj = s * yn[3]
                else:
                    _dense(xj, F, y, yx)
                    fj = s * yx[3]
                if fp > 0.0 and fj <= 0.0:
                    xr = _locate_peak(xp, fp, xj, fj, s, F, y, yx, xtol)
                    _dense(xr, F, y, yx)
                    qv = s * yx[2]
                    if n_pk < cap_pk:
                        peaks[n_pk, 0] = t + xr * hh
                        peaks[n_pk, 1] = qv
                        peaks[n_pk, 2] = s
                    n_pk += 1
                    if s > 0 and qv > qmax_r:
                        qmax_r = qv
                    if s < 0 and qv > qmax_l:
                        qmax_l = qv
                xp = xj
                fp = fj
                if xj >= x_end:
                    break
        # largest |a_abs| seen (samples of the step), outputs in [t, t_ev)
        for j in range(9):
            xj = j / 8.0
            if xj > x_end:
                break
            _dense(xj, F, y, yx)
            _, _, a = _accs(t + xj * hh, yx[0], yx[2], yx[3], md, Q, seg)
            amax = max(amax, abs(a))
        if k_ev >= 0:
            _, _, a = _accs(t_ev, ye[0], ye[2], ye[3], md, Q, seg)
            amax = max(amax, abs(a))
        while io < n_out and io * dt_out < t_ev:
            to = io * dt_out
            _dense((to - t) / hh, F, y, yx)
            _record_output(io, to, yx, md, Q, seg, out)
            io += 1
        suppress = -1
        nudge = 0.0
        if k_ev < 0:
            t = tn
            for c in range(NY):
                y[c] = yn[c]
            h = h_next
        else:
            t = t_ev
            for c in range(NY):
                y[c] = ye[c]
            h = max(h_next, 1e-3 * hh)
            ok = _apply(k_ev, t, y, md, Q, seg, eLw, eLe, eRw, eRe, imp, upeaks, S, n_imp, n_upk)
            n_imp = int(S[S_N_IMP])
            n_upk = int(S[S_N_UPEAKS])
            if ok == 2:
                overturned = True
            elif ok == 3:
                capstop = True
            elif ok == 0:
                suppress = k_ev
                nudge = 4.0 * _EPS * max(1.0, abs(t))
        umax = max(umax, abs(y[0]))
        _, _, a = _accs(t, y[0], y[2], y[3], md, Q, seg)
        amax = max(amax, abs(a))
        if md[MD_ROCK] != 0.0:
            q = md[MD_SIDE] * y[2]
            if md[MD_SIDE] > 0 and q > qmax_r:
                qmax_r = q
            if md[MD_SIDE] < 0 and q > qmax_l:
                qmax_l = q
        if overturned or capstop:
            break
    if capstop or overturned:           # the run ended early: samples after it are nan, phase 4 or 3
        if not capstop:
            if md[MD_SIDE] > 0:
                qmax_r = Q[DR]
            else:
                qmax_l = Q[DL]
        while io < n_out and io * dt_out < t:
            io += 1
        phase = 4.0 if capstop else 3.0
        while io < n_out:
            for c in range(6):
                out[io, c] = np.nan
            out[io, 6] = phase
            io += 1
    elif status == STATUS_OK:
        MK.segment(t, kind, M, samples, seg)
        while io < n_out and io * dt_out <= t_end * (1.0 + 1e-12):
            _record_output(io, io * dt_out, y, md, Q, seg, out)
            io += 1
    S[S_UMAX] = umax
    S[S_AMAX] = amax
    S[S_QMAX_R] = qmax_r
    S[S_QMAX_L] = qmax_l
    S[S_N_PEAKS] = n_pk
    S[S_CAP_STOP] = 1.0 if capstop else 0.0
    D8.write_stats(S, STEP_STATS, nsteps, nrej, status, t, io)
    return io


@njit(cache=True)
def _apply(k, t, y, md, Q, seg, eLw, eLe, eRw, eRe, imp, upeaks, S, n_imp, n_upk):
    """Apply event k at (t, y). Returns 1 (applied), 0 (not consistent yet: retry a
    little later) or 2 (overturned)."""
    ps_old = md[MD_PS]
    mr = Q[Q_MR]
    if k == EV_REV:
        y[1] = 0.0
        if n_upk < upeaks.shape[0]:
            upeaks[n_upk, 0] = t
            upeaks[n_upk, 1] = y[0]
        S[S_N_UPEAKS] = n_upk + 1
        _plate_after_jump(t, y, md, Q, seg, ps_old)
        return 1
    if k == EV_UNSTICK_P or k == EV_UNSTICK_N:
        s = 1.0 if k == EV_UNSTICK_P else -1.0
        pin = md[MD_PIN]
        md[MD_PIN] = 0.0
        md[MD_PS] = s
        udd, _, _ = _accs(t, y[0], y[2], y[3], md, Q, seg)
        if s * udd <= 0.0:
            md[MD_PS] = 0.0
            md[MD_PIN] = pin
            return 0
        if pin != 0.0:
            md[MD_UR] = y[0]
        return 1
    if k == EV_CAP:
        return _end_stop(t, y, md, Q, seg, S)
    if k == EV_UPLIFT_L or k == EV_UPLIFT_R:
        s = -1.0 if k == EV_UPLIFT_L else 1.0
        md[MD_ROCK] = 1.0
        md[MD_SIDE] = s
        md[MD_REG] = _start_region(s, Q)
        y[2] = 0.0
        y[3] = 0.0
        _, thdd, _ = _accs(t, y[0], 0.0, 0.0, md, Q, seg)
        if s * thdd <= 0.0:
            md[MD_ROCK] = 0.0
            return 0
        if S[S_N_UPLIFTS] == 0.0:
            S[S_T_UPLIFT] = t
        S[S_N_UPLIFTS] += 1.0
        if md[MD_REG] == 1.0 and (Q[TR] if s > 0 else Q[TL]) > 0.0:
            S[S_FULL_UPLIFT] = 1.0
        return 1
    s = md[MD_SIDE]
    lo, hi = _bounds(s, md[MD_REG], Q)
    if k == EV_HI:
        dside = Q[DR] if s > 0 else Q[DL]
        if md[MD_REG] == 0.0 and hi < dside:
            md[MD_REG] = 1.0
            y[2] = s * hi
            S[S_FULL_UPLIFT] = 1.0
            return 1
        y[2] = s * hi
        S[S_OVERTURNED] = 1.0
        S[S_T_OVERTURN] = t
        S[S_IMP_BEFORE_OT] = n_imp
        S[S_OT_SIDE] = s
        return 2
    # EV_LO
    if lo > 0.0:
        md[MD_REG] = 0.0
        y[2] = s * lo
        return 1
    # impact at theta = 0: lands on the other edge; the horizontal momentum
    # M u' + m h theta' of plate + statue is kept (no impulsive force from the balls)
    w_m = y[3]
    v_m = y[1]
    if s > 0:
        e = K._interp_e(abs(w_m), eLw, eLe)
        land = -1.0
    else:
        e = K._interp_e(abs(w_m), eRw, eRe)
        land = 1.0
    w_p = e * w_m
    v_p = v_m - mr * Q[Q_H] * (e - 1.0) * w_m
    s = -s
    md[MD_SIDE] = s
    md[MD_REG] = _start_region(s, Q)
    y[2] = 0.0
    y[3] = w_p
    y[1] = v_p
    # Zeno: the next excursions would peak below rest_tol * delta -> a plastic impact (e = 0)
    _, thdd, _ = _accs(t, y[0], 0.0, w_p, md, Q, seg)
    c = -s * thdd
    dside = Q[DR] if s > 0 else Q[DL]
    zeno = c > 0.0 and (w_p == 0.0 or w_p * w_p / (2.0 * c) < Q[REST_TOL] * dside)
    if zeno:
        w_p = 0.0
        v_p = v_m + mr * Q[Q_H] * w_m
        y[3] = 0.0
        y[1] = v_p
        md[MD_ROCK] = 0.0
        S[S_N_ZENO] += 1.0
    if n_imp < imp.shape[0]:
        imp[n_imp, 0] = t
        imp[n_imp, 1] = land
        imp[n_imp, 2] = w_m
        imp[n_imp, 3] = w_p
        imp[n_imp, 4] = v_m
        imp[n_imp, 5] = v_p
    S[S_N_IMP] = n_imp + 1
    pin = md[MD_PIN]
    if pin != 0.0:
        if pin * y[1] >= 0.0:       # pushed onto the end stop: it takes the push
            y[1] = 0.0
            return 1
        md[MD_PIN] = 0.0            # pulled away from it
        md[MD_UR] = y[0]
    if y[1] != v_m or md[MD_PS] == 0.0 or y[1] == 0.0:
        _plate_after_jump(t, y, md, Q, seg, ps_old)
    return 1


@njit(cache=True)
def _end_stop(t, y, md, Q, seg, S):
    """The plate reaches its capacity at (t, y) moving outward (sign md[MD_PS]). Returns 3
    (the run ends: Q_STOP = 0) or 1 (end-stop impact applied, see the module docstring)."""
    sig = md[MD_PS]
    if S[S_N_HITS] == 0.0:
        S[S_T_CAP] = t
        S[S_U_CAP] = y[0]
    S[S_N_HITS] += 1.0
    if Q[Q_STOP] == 0.0:
        S[S_CAP_STOP] = 1.0
        return 3
    bw = Q[Q_BW] != 0.0
    v_m = y[1]
    z = _zeta(y[0], md, Q)
    y[0] = sig * Q[Q_CAP]
    v_p = -Q[Q_ESTOP] * v_m
    dv = v_p - v_m
    # the statue: theta' jumps by A1 dv (on its pivot), or the impulse lifts it
    if md[MD_ROCK] != 0.0:
        _, A1, _, _ = _statue_terms(y[2], md[MD_SIDE], md[MD_REG], Q)
        y[3] += A1 * dv
    elif dv != 0.0:
        s = -1.0 if dv > 0.0 else 1.0
        reg = _start_region(s, Q)
        A0, A1, _, _ = _statue_terms(0.0, s, reg, Q)
        w = A1 * dv
        md[MD_ROCK] = 1.0
        md[MD_SIDE] = s
        md[MD_REG] = reg
        ps_keep = md[MD_PS]
        md[MD_PS] = -sig
        _, thdd, _ = _accs(t, y[0], 0.0, w, md, Q, seg)
        md[MD_PS] = ps_keep
        c = -s * thdd
        dside = Q[DR] if s > 0 else Q[DL]
        if c > 0.0 and w * w / (2.0 * c) < Q[REST_TOL] * dside:
            md[MD_ROCK] = 0.0          # too small to count: the statue moves with the plate
        else:
            y[2] = 0.0
            y[3] = w
            if S[S_N_UPLIFTS] == 0.0:
                S[S_T_UPLIFT] = t
            S[S_N_UPLIFTS] += 1.0
            if reg == 1.0 and (Q[TR] if s > 0 else Q[TL]) > 0.0:
                S[S_FULL_UPLIFT] = 1.0
    # the plate: a new branch moving back (Bouc-Wen z from here), or resting on the stop
    if bw:
        md[MD_UR] = y[0]
        md[MD_ZR] = z
    md[MD_PS] = -sig
    y[1] = v_p
    udd, _, _ = _accs(t, y[0], y[2], y[3], md, Q, seg)
    if v_p == 0.0 or (sig * udd > 0.0 and v_p * v_p / (2.0 * abs(udd)) < IK.REST_TOL * Q[Q_CAP]):
        y[1] = 0.0
        md[MD_PS] = 0.0
        md[MD_PIN] = sig
    return 1


SIGNATURES = {
    "simulate_kernel": (K.VEC, K.VEC, K.VEC, K.VEC, K.VEC, K.I8, K.VEC, MK.SAMPLES, K.F8, K.F8, K.F8, K.F8, K.F8,
                        K.F8, K.F8, K.VEC, K.I8, K.MAT, K.MAT, K.MAT, K.MAT, K.VEC),
}
"""The one argument-type signature of the entry point (types of rocking.kernel; see
statue2model.compute.compile)."""
