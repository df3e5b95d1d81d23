"""Compiled integrator of the two-block rocking model (a statue on a pedestal; numba).

The mechanics are those of :mod:`statue2model.rocking.stack` (its module docstring: the
Lagrange equations of the four response patterns and four pivot combinations, the
transitions by the sign of the contact moments, the impacts with per-contact restitution
and momentum conservation, the Housner fallback, the Zeno rule, overturning per body);
this module integrates them without Python objects, the scipy implementation there
(``simulate_stack(..., method="scipy")``) being its reference.

Method
------
* Dormand-Prince 8(5,3) on the state y = (theta1, theta2, theta1', theta2'), with the
  tableau, error norm, step-size control, dense output and Illinois iteration of
  :mod:`statue2model.rocking.dop853` (as the coupled plate + statue kernel does), the
  tolerances of the scipy path (rtol; atol = rtol x (delta1, delta2, delta1 p1,
  delta2 p2)). Steps never cross a piece of the ground motion (a record's sample
  interval, a pulse's start and end: :func:`statue2model.rocking.kernel._piece`); unlike
  the scipy path the step length is carried across pieces (no restart per sample).
* The events of the scipy path (impact at s theta_i = -IMPACT_EPS delta_i, overturning:
  s2 theta2 = delta2 for the statue, the stack's centre of mass over the floor pivot for
  the pedestal, and the opening of a closed contact: s theta_j''(s) > acc_tol) are
  sampled at 1/8 of each accepted step on its dense output and located by the Illinois
  method to ~4 ulp in time; the state at an event is the dense output there (as
  scipy's). Peaks of |theta_i| are located the same way.
* The pattern choice at an event, at a piece boundary and at uplift (``_choose``), the
  impact law (``_impact``), the Zeno rule and the rest rule are those of stack.py,
  number for number where possible.
* At rest (both contacts closed) nothing is integrated: the next uplift is found in
  closed form per motion piece (:func:`statue2model.rocking.kernel._first_exceedance`)
  with the exact skip of the record pieces that cannot lift either body
  (:func:`statue2model.rocking.kernel._quiet_until`).

Arrays: the model vector P (indices below, packed by
:meth:`statue2model.rocking.stack.StackModel.kernel_vector`), the motion ``(kind, M,
samples)`` of :meth:`statue2model.hazard.motions.GroundMotion.kernel_args`, the history
``out`` (n, 6: theta1, theta2, theta1', theta2', pattern index, top_acc at k dt_out; n = 0:
none), the impacts ``imp`` (cap, 6: t, contact, landing side (-1 L, +1 R), |theta_i'|
before, energy before, after) and the statistics S (indices S_*).
"""
from __future__ import annotations

import math

import numpy as np
from numba import njit, prange
from numba import types as nt

from ..hazard.motion_kernel import M_HARMONIC, M_RECORD, MA, MT0, MT1, MW, SAMPLES
from ..hazard.motion_kernel import seg_acc as _sacc
from . import dop853 as D8
from . import kernel as K
from .dop853 import STATUS_MAX_STEPS, STATUS_OK, STATUS_STALLED  # noqa: F401  (re-exported)

_NS = D8.N_STAGES
_CX = D8.C
_NX = D8.N_STAGES_EXTENDED
_NI = D8.INTERPOLATOR_POWER
NY = 4

# --- model vector P (StackModel.kernel_vector) ---------------------------------------
(B1, H1, M1, I1, M2, I2, H2, BL2, BR2, X2, GR, D1P, D1N, D2P, D2N, P1, P2, E1P, E1N, E2P, E2N,
 BAR1, BAR2, LS_UP, LS_DN, LP_UP, LP_DN, REST_TOL, ACC_TOL) = range(29)
N_P = 29
"""D1P/D1N: the composite's delta_R / delta_L (the pedestal's overturning angle on its right /
left floor corner), D2P/D2N the statue's; E1P: e_floor after rocking on the right corner (the
landing on the left edge: e_L), E1N after the left; E2P, E2N the same of e_top; BAR1, BAR2 the
overturning barriers (J) of the composite and the statue; LS_UP, LS_DN the statue's uplift
limits (a_L, a_R), LP_UP, LP_DN the composite's; ACC_TOL the tolerance of the contact moments
(1e-9 g / min(h1, h2))."""

# --- statistics vector S ---------------------------------------------------------------
(S_QMAX1_R, S_QMAX1_L, S_QMAX2_R, S_QMAX2_L, S_T_UPLIFT1, S_T_UPLIFT2, S_N_IMP1, S_N_IMP2,
 S_OVERTURNED1, S_OVERTURNED2, S_T_OVERTURN1, S_T_OVERTURN2, S_OUTCOME, S_T_REST, S_PT_REST,
 S_PT_PEDESTAL, S_PT_STATUE, S_PT_BOTH, S_N_EVENTS, S_TRUNCATED, S_N_STEPS, S_N_REJECT, S_STATUS,
 S_T_FINAL, S_N_OUT, S_N_RHS, S_TMOD1, S_TMOD2, S_PATTERN) = range(29)
N_S = 29
"""Per body (1 the pedestal, 2 the statue): peak |theta| on each side (rad), first uplift time
(nan: never), impacts, overturned (0/1) and when (nan); the outcome code (:data:`OUTCOMES`);
t_rest (nan: none; see StackResult.t_rest); seconds in each pattern; events; the event guard
ended the run (0/1); the integrator's counts (steps, rejected, status, final time, output
samples, right-hand sides); peak |theta| / delta of each body (StackResult's
theta_max_over_delta); the pattern index at the end."""
STEP_STATS = (S_N_STEPS, S_N_REJECT, S_STATUS, S_T_FINAL, S_N_OUT)

OUTCOMES = ("no motion", "statue rocks", "pedestal rocks", "both rock", "statue overturns", "stack overturns")
"""The outcome codes S[S_OUTCOME] (StackResult.outcome without the guard's note)."""

OPEN_EPS = 1e-10
IMPACT_EPS = 1e-12
N_EV = 8
"""Events: 0 impact of the pedestal, 1 overturning of the stack, 2 impact of the statue, 3 its
overturning, 4/5 the pedestal lifts on its right / left corner, 6/7 the statue on its right /
left pivot. g crosses from <= 0 to > 0 (-1: inactive)."""

F8, I8 = nt.float64, nt.int64
VEC = nt.Array(nt.float64, 1, "C")
MAT = nt.Array(nt.float64, 2, "C")


@njit(cache=True, inline="always")
def _ptuple(P):
    return (P[0], P[1], P[2], P[3], P[4], P[5], P[6], P[7], P[8], P[9], P[10], P[11], P[12], P[13], P[14],
            P[15], P[16], P[17], P[18], P[19], P[20], P[21], P[22], P[23], P[24], P[25], P[26], P[27], P[28])


# --- mechanics (stack._Mech) -------------------------------------------------------------
@njit(cache=True)
def _vectors(th1, th2, s1, s2, P):
    """(w1x, w1y, ux, uy, w2x, w2y, |a1|^2, |c|^2, |a2|^2) of stack._Mech.vectors."""
    if s1 == 0:
        s1 = 1
    if s2 == 0:
        s2 = 1
    b1 = P[B1]
    b2 = P[BR2] if s2 > 0 else P[BL2]
    a1x = -s1 * b1
    a1y = P[H1]
    cx = P[X2] + s2 * b2 - s1 * b1
    cy = 2 * P[H1]
    a2x = -s2 * b2
    a2y = P[H2]
    c1 = math.cos(th1)
    n1 = math.sin(th1)
    c12 = math.cos(th1 + th2)
    n12 = math.sin(th1 + th2)
    w1x = a1x * c1 + a1y * n1
    w1y = -a1x * n1 + a1y * c1
    ux = cx * c1 + cy * n1
    uy = -cx * n1 + cy * c1
    w2x = a2x * c12 + a2y * n12
    w2y = -a2x * n12 + a2y * c12
    return w1x, w1y, ux, uy, w2x, w2y, a1x * a1x + a1y * a1y, cx * cx + cy * cy, a2x * a2x + a2y * a2y


@njit(cache=True)
def _system(th1, th2, w1d, w2d, s1, s2, a, P):
    """(M11, M12, M22, F1, F2): M q'' = F (stack._Mech.system)."""
    w1x, w1y, ux, uy, w2x, w2y, A1, C, A2 = _vectors(th1, th2, s1, s2, P)
    m1 = P[M1]
    m2 = P[M2]
    g = P[GR]
    k = ux * w2x + uy * w2y
    kp = ux * w2y - uy * w2x
    I1P = P[I1] + m1 * A1
    I2P = P[I2] + m2 * A2
    M11 = I1P + m2 * C + I2P + 2 * m2 * k
    M12 = I2P + m2 * k
    V1 = m1 * (a * w1y - g * w1x) + m2 * (a * (uy + w2y) - g * (ux + w2x))
    V2 = m2 * (a * w2y - g * w2x)
    F1 = -V1 - m2 * kp * (2 * w1d * w2d + w2d * w2d)
    F2 = -V2 + m2 * kp * w1d * w1d
    return M11, M12, I2P, F1, F2


@njit(cache=True)
def _acc(th1, th2, w1d, w2d, s1, s2, a, P):
    """(theta1'', theta2'') of the pattern (s1, s2) (0: that contact closed)."""
    if s1 == 0 and s2 == 0:
        return 0.0, 0.0
    M11, M12, M22, F1, F2 = _system(th1, th2, w1d, w2d, s1, s2, a, P)
    if s2 == 0:
        return F1 / M11, 0.0
    if s1 == 0:
        return 0.0, F2 / M22
    det = M11 * M22 - M12 * M12
    return (M22 * F1 - M12 * F2) / det, (M11 * F2 - M12 * F1) / det


@njit(cache=True)
def _com_x(th1, th2, s1, s2, P):
    w1x, w1y, ux, uy, w2x, w2y, _, _, _ = _vectors(th1, th2, s1, s2, P)
    s = s1 if s1 != 0 else 1
    return s * (P[M1] * w1x + P[M2] * (ux + w2x)) / (P[M1] + P[M2])


@njit(cache=True)
def _top_point_acc(th1, w1d, a1, s1, P):
    if s1 == 0:
        s1 = 1
    cx = P[X2] - s1 * P[B1]
    cy = 2 * P[H1]
    c1 = math.cos(th1)
    n1 = math.sin(th1)
    rx = cx * c1 + cy * n1
    ry = -cx * n1 + cy * c1
    return a1 * ry - w1d * w1d * rx


@njit(cache=True)
def _energy(th1, th2, w1d, w2d, s1, s2, P):
    w1x, w1y, ux, uy, w2x, w2y, _, _, _ = _vectors(th1, th2, s1, s2, P)
    M11, M12, M22, _, _ = _system(th1, th2, 0.0, 0.0, s1, s2, 0.0, P)
    pot = P[GR] * (P[M1] * (w1y - P[H1]) + P[M2] * (uy + w2y - 2 * P[H1] - P[H2]))
    return 0.5 * (M11 * w1d * w1d + 2.0 * M12 * w1d * w2d + M22 * w2d * w2d) + pot


@njit(cache=True)
def _bmap(th1, th2, s1, s2, P, B):
    """B (6, 2): (vG1x, vG1y, w1, vG2x, vG2y, w2) per unit (theta1', theta2')."""
    w1x, w1y, ux, uy, w2x, w2y, _, _, _ = _vectors(th1, th2, s1, s2, P)
    B[0, 0] = w1y
    B[0, 1] = 0.0
    B[1, 0] = -w1x
    B[1, 1] = 0.0
    B[2, 0] = 1.0
    B[2, 1] = 0.0
    B[3, 0] = uy + w2y
    B[3, 1] = w2y
    B[4, 0] = -ux - w2x
    B[4, 1] = -w2x
    B[5, 0] = 1.0
    B[5, 1] = 1.0


@njit(cache=True, inline="always")
def _delta1(s, P):
    return P[D1P] if s > 0 else P[D1N]


@njit(cache=True, inline="always")
def _delta2(s, P):
    return P[D2P] if s > 0 else P[D2N]


@njit(cache=True, inline="always")
def _pattern_index(s1, s2):
    return (1 if s1 != 0 else 0) + (2 if s2 != 0 else 0)


# --- the pattern choice (stack._Run.choose) -------------------------------------------------
@njit(cache=True, inline="always")
def _opt(v, closed):
    """Index of the side v among the options of a contact: (0, 1, -1) when closed, (v) when open."""
    if not closed:
        return 0
    return 0 if v == 0 else (1 if v == 1 else 2)


@njit(cache=True)
def _choose(y, s1, s2, a, pref_i, pref_s, P, A):
    """The pattern at y under the ground acceleration a for the open contacts of (s1, s2) and
    the closed ones decided by their contact moments; pref_i (1, 2; 0: none), pref_s: the contact
    and side whose opening fired. A (3, 3, 2): work. Returns (c1, c2)."""
    tol = P[ACC_TOL]
    n1 = 1 if s1 != 0 else 3
    n2 = 1 if s2 != 0 else 3
    for i1 in range(n1):
        c1 = s1 if s1 != 0 else (0 if i1 == 0 else (1 if i1 == 1 else -1))
        for i2 in range(n2):
            c2 = s2 if s2 != 0 else (0 if i2 == 0 else (1 if i2 == 1 else -1))
            a1, a2 = _acc(y[0], y[1], y[2], y[3], c1, c2, a, P)
            A[i1, i2, 0] = a1
            A[i1, i2, 1] = a2
    for pref in range(2):
        for nopen in range(3):
            for i1 in range(n1):
                c1 = s1 if s1 != 0 else (0 if i1 == 0 else (1 if i1 == 1 else -1))
                for i2 in range(n2):
                    c2 = s2 if s2 != 0 else (0 if i2 == 0 else (1 if i2 == 1 else -1))
                    pr = 1
                    if pref_i == 1 and c1 == pref_s:
                        pr = 0
                    if pref_i == 2 and c2 == pref_s:
                        pr = 0
                    no = (1 if (c1 != 0 and s1 == 0) else 0) + (1 if (c2 != 0 and s2 == 0) else 0)
                    if pr != pref or no != nopen:
                        continue
                    ok = True
                    # contact 1 closed in pat
                    if s1 == 0:
                        if c1 != 0:
                            slack = tol if (pref_i == 1 and pref_s == c1) else -tol
                            if c1 * A[i1, i2, 0] <= -slack:
                                ok = False
                        else:
                            for s in (1, -1):
                                if s * A[_opt(s, True), i2, 0] > tol:
                                    ok = False
                    if ok and s2 == 0:
                        if c2 != 0:
                            slack = tol if (pref_i == 2 and pref_s == c2) else -tol
                            if c2 * A[i1, i2, 1] <= -slack:
                                ok = False
                        else:
                            for s in (1, -1):
                                if s * A[i1, _opt(s, True), 1] > tol:
                                    ok = False
                    if ok:
                        return c1, c2
    if pref_i == 1:
        return pref_s, s2
    if pref_i == 2:
        return s1, pref_s
    return s1, s2


# --- the impact (stack._Run.impact) -----------------------------------------------------------
@njit(cache=True)
def _other_rate(y, t1, t2, j, qi, P, Bn, Dv, vold):
    """(rate of coordinate j after an impact of the other contact, its mass term M_jj) with pivots (t1, t2):
    coordinate j's generalised momentum (Bn[:, j] D . v_old, the bodies' velocities before) conserved, the
    impacting coordinate at ``qi``."""
    M11, M12, M22, _, _ = _system(y[0], y[1], 0.0, 0.0, t1, t2, 0.0, P)
    _bmap(y[0], y[1], t1, t2, P, Bn)
    pj = 0.0
    for r in range(6):
        pj += Bn[r, j - 1] * Dv[r] * vold[r]
    Mjj = M11 if j == 1 else M22
    return (pj - M12 * qi) / Mjj, Mjj


@njit(cache=True)
def _impact(y, s1, s2, i, a, P, B, Bn, Dv, vold):
    """Impact of contact i at y (theta_i set to 0 here): y's velocities updated in place.
    Returns (new s1, new s2, energy before, energy after, |theta_i'| before)."""
    y[i - 1] = 0.0
    s_old = s1 if i == 1 else s2
    w0 = y[2]
    w1 = y[3]
    wi = w0 if i == 1 else w1
    if i == 1:
        e = P[E1P] if s_old > 0 else P[E1N]
    else:
        e = P[E2P] if s_old > 0 else P[E2N]
    n1 = -s_old if i == 1 else s1
    n2 = -s_old if i == 2 else s2
    j = 2 if i == 1 else 1
    Dv[0] = P[M1]
    Dv[1] = P[M1]
    Dv[2] = P[I1]
    Dv[3] = P[M2]
    Dv[4] = P[M2]
    Dv[5] = P[I2]
    _bmap(y[0], y[1], s1, s2, P, B)
    for r in range(6):
        vold[r] = B[r, 0] * w0 + B[r, 1] * w1
    E_old = _energy(y[0], y[1], w0, w1, s1, s2, P)
    q0 = 0.0
    q1 = 0.0
    qi = e * wi
    sj = s2 if i == 1 else s1
    if sj != 0:
        qj = _other_rate(y, n1, n2, j, qi, P, Bn, Dv, vold)[0]
    else:
        qj = 0.0
        for s in (1, -1):
            t1 = s if j == 1 else n1
            t2 = s if j == 2 else n2
            wj, Mjj = _other_rate(y, t1, t2, j, qi, P, Bn, Dv, vold)
            if s * wj > 0 and 0.5 * Mjj * wj * wj > OPEN_EPS * (P[BAR1] if j == 1 else P[BAR2]):
                qj = wj
                n1 = t1
                n2 = t2
                break
    if i == 1:
        q0 = qi
        q1 = qj
    else:
        q0 = qj
        q1 = qi
    E_new = _energy(y[0], y[1], q0, q1, n1, n2, P)
    if E_new > E_old * (1 + 1e-12) + 1e-300:
        # Housner's plastic law for the assembly: the generalised-momentum projection
        _bmap(y[0], y[1], n1, n2, P, Bn)
        r00 = 0.0
        r01 = 0.0
        r11 = 0.0
        f0 = 0.0
        f1 = 0.0
        for r in range(6):
            r00 += Bn[r, 0] * Dv[r] * Bn[r, 0]
            r01 += Bn[r, 0] * Dv[r] * Bn[r, 1]
            r11 += Bn[r, 1] * Dv[r] * Bn[r, 1]
            f0 += Bn[r, 0] * Dv[r] * vold[r]
            f1 += Bn[r, 1] * Dv[r] * vold[r]
        if n1 != 0 and n2 != 0:
            det = r00 * r11 - r01 * r01
            q0 = (r11 * f0 - r01 * f1) / det
            q1 = (r00 * f1 - r01 * f0) / det
        elif n1 != 0:
            q0 = f0 / r00
            q1 = 0.0
        else:
            q0 = 0.0
            q1 = f1 / r11
        E_new = _energy(y[0], y[1], q0, q1, n1, n2, P)
    y[2] = q0
    y[3] = q1
    # Zeno: close contact i when its next excursion would be negligible
    a1, a2 = _acc(y[0], y[1], y[2], y[3], n1, n2, a, P)
    ni = n1 if i == 1 else n2
    c = -ni * (a1 if i == 1 else a2)
    wp = abs(y[1 + i])
    delta = _delta1(ni, P) if i == 1 else _delta2(ni, P)
    if wp == 0.0 or (c > 0.0 and wp * wp / (2.0 * c) < P[REST_TOL] * delta):
        y[1 + i] = 0.0
        if i == 1:
            n1 = 0
        else:
            n2 = 0
    return n1, n2, E_old, E_new, abs(wi)


# --- DOP853 on the 4 states ------------------------------------------------------------------
@njit(cache=True)
def _rhs(t, y, s1, s2, P, sg, dy):
    a1, a2 = _acc(y[0], y[1], y[2], y[3], s1, s2, _sacc(t, sg), P)
    dy[0] = y[2]
    dy[1] = y[3]
    dy[2] = a1
    dy[3] = a2


@njit(cache=True)
def _step(t, y, f0, h, s1, s2, P, sg, Ks, yn, ytmp, dy):
    """One DOP853 step of length h from (t, y) with slope f0; yn = y(t + h)."""
    for c in range(NY):
        Ks[0, c] = f0[c]
    for i in range(1, _NS):
        D8.stage_state(i, y, h, Ks, ytmp)
        _rhs(t + _CX[i] * h, ytmp, s1, s2, P, sg, dy)
        for c in range(NY):
            Ks[i, c] = dy[c]
    D8.combine(y, h, Ks, yn)


@njit(cache=True)
def _dense_coeffs(t, y, yn, h, s1, s2, P, sg, Ks, F, ytmp, dy):
    for i in range(_NS + 1, _NX):
        D8.stage_state(i, y, h, Ks, ytmp)
        _rhs(t + _CX[i] * h, ytmp, s1, s2, P, sg, dy)
        for c in range(NY):
            Ks[i, c] = dy[c]
    D8.dense_coeffs(y, yn, h, Ks, F)


@njit(cache=True)
def _events(t, y, s1, s2, P, sg, g):
    for k in range(N_EV):
        g[k] = -1.0
    a = _sacc(t, sg)
    tol = P[ACC_TOL]
    if s1 != 0:
        g[0] = -(s1 * y[0] + IMPACT_EPS * _delta1(s1, P))
        g[1] = _com_x(y[0], y[1], s1, s2, P)
    else:
        a1, _ = _acc(y[0], y[1], y[2], y[3], 1, s2, a, P)
        g[4] = a1 - tol
        a1, _ = _acc(y[0], y[1], y[2], y[3], -1, s2, a, P)
        g[5] = -a1 - tol
    if s2 != 0:
        g[2] = -(s2 * y[1] + IMPACT_EPS * _delta2(s2, P))
        g[3] = s2 * y[1] - _delta2(s2, P)
    else:
        _, a2 = _acc(y[0], y[1], y[2], y[3], s1, 1, a, P)
        g[6] = a2 - tol
        _, a2 = _acc(y[0], y[1], y[2], y[3], s1, -1, a, P)
        g[7] = -a2 - tol


@njit(cache=True)
def _locate(k, xa, ga, xb, gb, t, h, F, y, s1, s2, P, sg, yx, g, xtol):
    """Illinois on the dense output: the crossing of event k in [xa, xb] (ga <= 0 < gb); returns
    the end of the final bracket on the far side (g > 0 there)."""
    side = 0
    for _ in range(200):
        if xb - xa <= xtol:
            break
        x = D8.secant(xa, ga, xb, gb)
        D8.dense(x, F, y, yx)
        _events(t + x * h, yx, s1, s2, P, sg, g)
        gx = g[k]
        xa, ga, xb, gb, side = D8.illinois(xa, ga, xb, gb, side, x, gx, gx > 0.0)
    return xb


@njit(cache=True)
def _locate_peak(c, xa, fa, xb, fb, s, F, y, yx, xtol):
    """Root of s y[c](x) in [xa, xb] (fa > 0 >= fb) on the dense output (Illinois)."""
    side = 0
    x = xb
    for _ in range(200):
        if xb - xa <= xtol:
            break
        x = D8.secant(xa, fa, xb, fb)
        D8.dense(x, F, y, yx)
        fx = s * yx[c]
        xa, fa, xb, fb, side = D8.illinois(xa, fa, xb, fb, side, x, fx, fx <= 0.0)
    return x


@njit(cache=True)
def _write(io, t, y, s1, s2, P, sg, out):
    a = _sacc(t, sg)
    out[io, 0] = y[0]
    out[io, 1] = y[1]
    out[io, 2] = y[2]
    out[io, 3] = y[3]
    out[io, 4] = _pattern_index(s1, s2)
    if s1 != 0:
        a1, _ = _acc(y[0], y[1], y[2], y[3], s1, s2, a, P)
        out[io, 5] = a + _top_point_acc(y[0], y[2], a1, s1, P)
    else:
        out[io, 5] = a


@njit(cache=True)
def _fill_still(io, t_until, inclusive, dt_out, y, s1, s2, P, kind, M, samples, out):
    """History samples of a still state up to t_until (excluded, or included)."""
    n = out.shape[0]
    while io < n and (io * dt_out < t_until or (inclusive and io * dt_out <= t_until)):
        to = io * dt_out
        _, sg = K._piece(to, kind, M, samples)
        _write(io, to, y, s1, s2, P, sg, out)
        io += 1
    return io


@njit(cache=True)
def _note_peak(q, y, s1, s2):
    if s1 > 0:
        q[0] = max(q[0], abs(y[0]))
    elif s1 < 0:
        q[1] = max(q[1], abs(y[0]))
    if s2 > 0:
        q[2] = max(q[2], abs(y[1]))
    elif s2 < 0:
        q[3] = max(q[3], abs(y[1]))


@njit(cache=True)
def _note_uplift(t, s1, s2, S):
    if s1 != 0 and S[S_T_UPLIFT1] != S[S_T_UPLIFT1]:
        S[S_T_UPLIFT1] = t
    if s2 != 0 and S[S_T_UPLIFT2] != S[S_T_UPLIFT2]:
        S[S_T_UPLIFT2] = t


@njit(cache=True)
def _add_time(S, s1, s2, dt):
    S[S_PT_REST + _pattern_index(s1, s2)] += dt


# --- the run ------------------------------------------------------------------------------
@njit(cache=True)
def simulate_stack_kernel(P, kind, M, samples, y0, t_end, rtol, max_events, max_steps, dt_out, out, imp, S):
    """Integrate one run from the state y0 (4,) at t = 0 to t_end (or the first overturning);
    see the module docstring for the arrays. Returns the number of history samples written."""
    s_hi, s_lo = K.suffix_extremes(samples)
    return _simulate(_ptuple(P), kind, M, samples, s_hi, s_lo, y0, t_end, rtol, max_events, max_steps, dt_out,
                     out, imp, S)


@njit(cache=True, error_model="numpy")
def _simulate(P, kind, M, samples, s_hi, s_lo, y0, t_end, rtol, max_events, max_steps, dt_out, out, imp, S):
    for i in range(N_S):
        S[i] = 0.0
    S[S_T_UPLIFT1] = np.nan
    S[S_T_UPLIFT2] = np.nan
    S[S_T_OVERTURN1] = np.nan
    S[S_T_OVERTURN2] = np.nan
    S[S_T_REST] = np.nan
    Ks = np.empty((_NX, NY))
    F = np.empty((_NI, NY))
    y = np.empty(NY)
    yn = np.empty(NY)
    yx = np.empty(NY)
    ytmp = np.empty(NY)
    dy = np.empty(NY)
    f0 = np.empty(NY)
    g = np.empty(N_EV)
    gp = np.empty((9, N_EV))
    A = np.empty((3, 3, 2))
    B = np.empty((6, 2))
    Bn = np.empty((6, 2))
    Dv = np.empty(6)
    vold = np.empty(6)
    qmax = np.zeros(4)
    atol = np.empty(NY)
    d1 = min(P[D1P], P[D1N])
    d2 = min(P[D2P], P[D2N])
    atol[0] = rtol * d1
    atol[1] = rtol * d2
    atol[2] = rtol * d1 * P[P1]
    atol[3] = rtol * d2 * P[P2]
    hmax = np.inf
    if kind == M_HARMONIC and M[MW] > 0.0:
        hmax = 2.0 * math.pi / (50.0 * M[MW])
    h0 = 0.01 / P[P2]
    n_out = out.shape[0]
    cap_imp = imp.shape[0]
    m_end = M[MT1]
    for c in range(NY):
        y[c] = y0[c]
    s1 = 0
    if y[0] != 0.0:
        s1 = 1 if y[0] > 0 else -1
    elif y[2] != 0.0:
        s1 = 1 if y[2] > 0 else -1
    s2 = 0
    if y[1] != 0.0:
        s2 = 1 if y[1] > 0 else -1
    elif y[3] != 0.0:
        s2 = 1 if y[3] > 0 else -1
    t = 0.0
    seg_end, sg = K._piece(t, kind, M, samples)
    s1, s2 = _choose(y, s1, s2, _sacc(t, sg), 0, 0, P, A)
    _note_uplift(0.0, s1, s2, S)
    _note_peak(qmax, y, s1, s2)
    moved = s1 != 0 or s2 != 0
    t_rest = np.nan
    truncated = False
    n_events = 0
    n_imp = 0
    n_i1 = 0
    n_i2 = 0
    nsteps = 0
    nrej = 0
    nrhs = 0
    io = 0
    status = STATUS_OK
    ot = 0
    h = h0
    fresh = True          # f0 must be computed at t
    t_last = -1.0
    stall = 0
    up = min(P[LS_UP], P[LP_UP])
    dn = min(P[LS_DN], P[LP_DN])
    while t < t_end:
        if n_events >= max_events:
            truncated = True
            break
        status, t_last, stall = D8.guard(t, t_last, stall, nsteps + nrej, max_steps)
        if status != STATUS_OK:
            break
        if s1 == 0 and s2 == 0:
            # --- at rest: the next uplift in closed form
            if moved and t_rest != t_rest:
                t_rest = t
            t_up = np.inf
            side = 0
            tc = t
            while tc < t_end:
                tb, sgc = K._piece(tc, kind, M, samples)
                t_up, side = K._first_exceedance(tc, min(tb, t_end), sgc, up, dn)
                if side != 0 or tb == np.inf:
                    break
                tc = tb
                if kind == M_RECORD:
                    tc = K._quiet_until(tc, M, samples, s_hi, s_lo, up, dn)
                    if tc == np.inf:
                        t_up = np.inf
                        break
            if side == 0 or t_up >= t_end:
                S[S_PT_REST] += t_end - t
                io = _fill_still(io, t_end, True, dt_out, y, s1, s2, P, kind, M, samples, out)
                t = t_end
                break
            S[S_PT_REST] += t_up - t
            io = _fill_still(io, t_up, False, dt_out, y, s1, s2, P, kind, M, samples, out)
            t = t_up
            seg_end, sg = K._piece(t, kind, M, samples)
            a = _sacc(t, sg)
            if a > 0:
                ps = -1
                which = 1 if P[LP_UP] <= P[LS_UP] else 2
            else:
                ps = 1
                which = 1 if P[LP_DN] <= P[LS_DN] else 2
            s1, s2 = _choose(y, s1, s2, a, which, ps, P, A)
            if s1 == 0 and s2 == 0:
                # touched the limit without passing it: look a little later
                t_next = t_end
                if 0.0 < M[MT0] < t_end and t < M[MT0]:
                    t_next = M[MT0]
                elif 0.0 < m_end < t_end and t < m_end:
                    t_next = m_end
                t = min(t + max(1e-9, 1e-12 * t), t_next)
                continue
            n_events += 1
            _note_uplift(t, s1, s2, S)
            moved = True
            t_rest = np.nan
            h = h0
            fresh = True
            continue
        # --- one adaptive step of the pattern (s1, s2)
        seg_end, sg = K._piece(t, kind, M, samples)
        t_lim = min(seg_end, t_end)
        if fresh:
            _rhs(t, y, s1, s2, P, sg, f0)
            nrhs += 1
            fresh = False
        hh = min(h, t_lim - t, hmax)
        hits = hh == t_lim - t
        _step(t, y, f0, hh, s1, s2, P, sg, Ks, yn, ytmp, dy)
        tn = t_lim if hits else t + hh
        _rhs(tn, yn, s1, s2, P, sg, dy)
        for c in range(NY):
            Ks[_NS, c] = dy[c]
        nrhs += _NS
        err = D8.error_norm(hh, y, yn, Ks, atol, rtol)
        if err != err or (err > 1.0 and not D8.shortest(hh, t)):
            h = hh * D8.factor_reject(err) if err == err else 0.25 * hh
            nrej += 1
            continue
        if err > 1.0:
            err = 1.0       # the shortest step: accepted
        h_next = D8.next_step(hh, err, hits, h)
        if hits and hmax < np.inf and h_next > hmax:
            h_next = hmax
        nsteps += 1
        _dense_coeffs(t, y, yn, hh, s1, s2, P, sg, Ks, F, ytmp, dy)
        nrhs += 3
        # events sampled at j / 8 of the step
        _events(t, y, s1, s2, P, sg, g)
        for k in range(N_EV):
            gp[0, k] = g[k]
        for j in range(1, 9):
            if j < 8:
                D8.dense(j / 8.0, F, y, yx)
                _events(t + j / 8.0 * hh, yx, s1, s2, P, sg, g)
            else:
                _events(tn, yn, s1, s2, P, sg, g)
            for k in range(N_EV):
                gp[j, k] = g[k]
        xtol = D8.event_xtol(t, hh)
        x_ev = 2.0
        k_ev = -1
        for k in range(N_EV):
            for j in range(1, 9):
                if gp[j, k] > 0.0:
                    if gp[j - 1, k] <= 0.0 and (j - 1) / 8.0 < x_ev:
                        xr = _locate(k, (j - 1) / 8.0, gp[j - 1, k], j / 8.0, gp[j, k], t, hh, F, y, s1, s2, P, sg,
                                     yx, g, xtol)
                        if xr < x_ev:
                            x_ev = xr
                            k_ev = k
                    break
        x_end = 1.0
        if k_ev >= 0 and x_ev < 1.0:
            x_end = x_ev
        t_ev = t + x_ev * hh if (k_ev >= 0 and x_ev < 1.0) else tn
        # peaks of |theta_i| in [0, x_end]
        for c in range(2):
            sc = s1 if c == 0 else s2
            if sc == 0:
                continue
            fp = sc * y[2 + c]
            xp = 0.0
            for j in range(1, 9):
                xj = j / 8.0
                if xj > x_end:
                    xj = x_end
                if xj == 1.0:
                    fj = sc * yn[2 + c]
                else:
                    D8.dense(xj, F, y, yx)
                    fj = sc * yx[2 + c]
                if fp > 0.0 and fj <= 0.0:
                    xr = _locate_peak(2 + c, xp, fp, xj, fj, sc, F, y, yx, xtol)
                    D8.dense(xr, F, y, yx)
                    qv = abs(yx[c])
                    kq = 2 * c + (0 if sc > 0 else 1)
                    if qv > qmax[kq]:
                        qmax[kq] = qv
                xp = xj
                fp = fj
                if xj >= x_end:
                    break
        # history samples in [t, t_ev)
        while io < n_out and io * dt_out < t_ev:
            to = io * dt_out
            D8.dense((to - t) / hh, F, y, yx)
            _write(io, to, yx, s1, s2, P, sg, out)
            io += 1
        _add_time(S, s1, s2, t_ev - t)
        if k_ev < 0:
            t = tn
            for c in range(NY):
                y[c] = yn[c]
                f0[c] = Ks[_NS, c]
            h = h_next
            _note_peak(qmax, y, s1, s2)
            if hits:
                fresh = True
                if t >= t_end:
                    break
                if s1 == 0 or s2 == 0:
                    # the ground may have jumped (a pulse's end): the pattern again
                    seg_end, sg = K._piece(t, kind, M, samples)
                    s1, s2 = _choose(y, s1, s2, _sacc(t, sg), 0, 0, P, A)
                    _note_uplift(t, s1, s2, S)
            continue
        # --- the event
        t = t_ev
        if x_ev >= 1.0:
            for c in range(NY):
                y[c] = yn[c]
        else:
            D8.dense(x_ev, F, y, yx)
            for c in range(NY):
                y[c] = yx[c]
        h = max(h_next, 1e-3 * hh)
        fresh = True
        _note_peak(qmax, y, s1, s2)
        n_events += 1
        if k_ev == 1 or k_ev == 3:
            ot = 1 if k_ev == 1 else 2
            break
        seg_end, sg = K._piece(t, kind, M, samples)
        a = _sacc(t, sg)
        if k_ev == 0 or k_ev == 2:
            ci = 1 if k_ev == 0 else 2
            s_old = s1 if ci == 1 else s2
            for rep in range(2):
                n1, n2, e_old, e_new, w_old = _impact(y, s1, s2, ci, a, P, B, Bn, Dv, vold)
                if n_imp < cap_imp:
                    imp[n_imp, 0] = t
                    imp[n_imp, 1] = ci
                    imp[n_imp, 2] = -1.0 if s_old > 0 else 1.0
                    imp[n_imp, 3] = w_old
                    imp[n_imp, 4] = e_old
                    imp[n_imp, 5] = e_new
                n_imp += 1
                if ci == 1:
                    n_i1 += 1
                else:
                    n_i2 += 1
                s1, s2 = n1, n2
                # the other contact, open but at its closing point, driven into it by this impact: it
                # impacts at once (stack.py _Run.impact: its event would start on the wrong side)
                cj = 2 if ci == 1 else 1
                sj = s2 if cj == 2 else s1
                if rep == 1 or sj == 0:
                    break
                dj = _delta1(sj, P) if cj == 1 else _delta2(sj, P)
                if not (sj * y[cj - 1] <= IMPACT_EPS * dj and sj * y[cj + 1] < 0.0):
                    break
                ci = cj
                s_old = sj
            s1, s2 = _choose(y, s1, s2, a, 0, 0, P, A)
        else:
            ci = 1 if k_ev < 6 else 2
            side = 1 if (k_ev == 4 or k_ev == 6) else -1
            s1, s2 = _choose(y, s1, s2, a, ci, side, P, A)
        _note_uplift(t, s1, s2, S)
        if s1 == 0 and s2 == 0 and t >= m_end:
            t_rest = t
            io = _fill_still(io, t_end, True, dt_out, y, s1, s2, P, kind, M, samples, out)
            S[S_PT_REST] += t_end - t
            t = t_end
            break
    # --- statistics
    S[S_QMAX1_R] = qmax[0]
    S[S_QMAX1_L] = qmax[1]
    S[S_QMAX2_R] = qmax[2]
    S[S_QMAX2_L] = qmax[3]
    S[S_TMOD1] = max(qmax[0] / P[D1P], qmax[1] / P[D1N])
    S[S_TMOD2] = max(qmax[2] / P[D2P], qmax[3] / P[D2N])
    S[S_N_IMP1] = n_i1
    S[S_N_IMP2] = n_i2
    if ot == 1:
        S[S_OVERTURNED1] = 1.0
        S[S_T_OVERTURN1] = t
    elif ot == 2:
        S[S_OVERTURNED2] = 1.0
        S[S_T_OVERTURN2] = t
    up1 = S[S_T_UPLIFT1] == S[S_T_UPLIFT1]
    up2 = S[S_T_UPLIFT2] == S[S_T_UPLIFT2]
    if ot == 2:
        code = 4
    elif ot == 1:
        code = 5
    elif up1 and up2:
        code = 3
    elif up2:
        code = 1
    elif up1:
        code = 2
    else:
        code = 0
    S[S_OUTCOME] = code
    if ot == 0 and (up1 or up2) and s1 == 0 and s2 == 0:
        S[S_T_REST] = t_rest
    S[S_N_EVENTS] = n_events
    S[S_TRUNCATED] = 1.0 if truncated else 0.0
    S[S_N_RHS] = nrhs
    S[S_PATTERN] = _pattern_index(s1, s2)
    D8.write_stats(S, STEP_STATS, nsteps, nrej, status, t, io)
    return io


@njit(cache=True, parallel=True)
def simulate_stack_batch(Pm, scale, kind, M, samples, s_hi, s_lo, y0, t_end, rtol, max_events, max_steps, Sm):
    """Run len(Pm) simulations in parallel (statistics only): row i the model vector Pm[i]
    under the motion (kind, M, samples) with its amplitude (a record's gain) times scale[i].
    ``s_hi``, ``s_lo``: :func:`statue2model.rocking.kernel.suffix_extremes` of the samples."""
    n = Pm.shape[0]
    for i in prange(n):
        Mi = M.copy()
        Mi[MA] = M[MA] * scale[i]
        out = np.empty((0, 6))
        imp = np.empty((0, 6))
        _simulate(_ptuple(Pm[i]), kind, Mi, samples, s_hi, s_lo, y0, t_end, rtol, max_events, max_steps, 1.0, out,
                  imp, Sm[i])


SIGNATURES = {
    "simulate_stack_kernel": (VEC, I8, VEC, SAMPLES, VEC, F8, F8, I8, I8, F8, MAT, MAT, VEC),
    "simulate_stack_batch": (MAT, VEC, I8, VEC, SAMPLES, VEC, VEC, VEC, F8, F8, I8, I8, MAT),
}
"""The one argument-type signature of each entry point (see statue2model.compute.compile)."""
