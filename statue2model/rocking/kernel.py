"""Compiled integrator of the 2D rocking model (numba, no Python objects).

This module is the hot loop behind :func:`statue2model.rocking.engine.simulate`;
use that function, not these arrays, unless you are writing a new sweep.

Method
------
* Dormand-Prince 8(5,3) (the DOP853 tableau of scipy, read from scipy so the
  coefficients are not re-typed) with its own step-size control, on the state
  ``(theta, theta')``; the tableau, error norm, step-size controller, dense output,
  Illinois iteration, the loop's guard (max steps, stall) and the write-out of its
  counts are those of :mod:`statue2model.rocking.dop853`, shared with the coupled
  plate + statue kernel. The model vector P is packed by
  :meth:`statue2model.rocking.model.RockingModel.kernel_vector` (indices ``P2L`` ...
  ``EARLY`` below); the coupled kernel's vector starts with it.
* The right-hand side is smooth inside a *segment*: one side (pivot), one
  region of the rolling transition (|theta| below or above theta_L / theta_R)
  and one smooth piece of the ground motion (pulse on/off, one sample interval
  of a record). Steps never cross a segment boundary: motion breakpoints are
  step limits, theta-boundaries are events located inside the step.
* Events (impact at theta = 0, region change at |theta| = theta_side,
  overturning at |theta| = delta_side, and extrema of |theta|) are located on
  the 7th-order dense output of the step (3 extra stages, as in scipy's DOP853)
  by the Illinois method, to machine precision in time.
* Output samples are read from the same dense output; they never change the
  steps, so results are independent of the output grid.
* Stick (full contact) is not integrated: the next uplift is found in closed
  form on each motion segment (linear or harmonic). On a record, the pieces
  that cannot lift the body (both samples, scaled, within its uplift limits)
  are skipped at once from the record's suffix extremes (:func:`_quiet_until`):
  a body at rest on a quiet tail stops there; the same numbers as reading
  every piece.
* The helpers of the integration loop take the model vector and the motion
  piece as tuples, and no array that an inlined helper would receive: numba
  counts the references of such an array atomically, which took about half
  the time of a run (and more when threads share the array).
* sin and cos of the right-hand side (a third of a run's time through the C library) are
  computed inline by :func:`statue2model.rocking.sincos.sincos`, the library's numbers to the
  bit (no call, no registers saved around it); the step's error norm works on scalars.
* Zeno: after an impact whose next excursion would peak below
  ``rest_tol * delta`` the remaining geometric series of impacts is summed in
  closed form and the body returns to stick.

Sign convention: theta > 0 is rotation about the right (+x) pivot, side s = +1;
theta < 0 about the left pivot, s = -1. ``q = s * theta >= 0`` is the rotation
magnitude on the current side.
"""
from __future__ import annotations

import math

import numpy as np
from numba import njit, prange
from numba import types as nt

from ..hazard.motion_kernel import (  # noqa: F401  (re-exported: the motion encoding the kernels read)
    M_HARMONIC, M_NONE, M_RECORD, M_RECT, MA, MDT, MPH, MT0, MT1, MW, N_M, SAMPLES, as_samples, ground_acc,
    segment)
from ..hazard.motion_kernel import record_index
from ..hazard.motion_kernel import seg_acc as _acc
from . import dop853 as D8
from .sincos import sincos
from .dop853 import STATUS_MAX_STEPS, STATUS_OK, STATUS_STALLED  # noqa: F401  (re-exported)

_NS = D8.N_STAGES
_CX = D8.C
_AX = D8.A
_B = D8.B
_NX = D8.N_STAGES_EXTENDED
_NI = D8.INTERPOLATOR_POWER


# --- model vector P --------------------------------------------------------
# packed by RockingModel.kernel_vector (statue2model.rocking.model), the one place that
# fills it; the coupled plate + statue kernel's vector starts with it (isolator.coupled_kernel)
P2L, P2R, DL, DR, AL, AR, TL, TR, GRAV, LIN, LIM_UP, LIM_DN, REST_TOL, EARLY = range(14)
N_P = 14


# --- statistics vector S ----------------------------------------------------
(S_QMAX_R, S_QMAX_L, S_T_UPLIFT, S_N_IMP, S_OVERTURNED, S_T_OVERTURN, S_IMP_BEFORE_OT,
 S_T_REST, S_N_STEPS, S_N_REJECT, S_N_RHS, S_STATUS, S_FULL_UPLIFT, S_N_PEAKS, S_T_FINAL,
 S_OT_SIDE, S_N_OUT, S_N_UPLIFTS, S_MOVED, S_DECIDED) = range(20)
N_S = 20
STEP_STATS = (S_N_STEPS, S_N_REJECT, S_STATUS, S_T_FINAL, S_N_OUT)
"""Where dop853.write_stats puts the integrator's counts of a run."""

_EPS = D8.EPS

# --- argument types -------------------------------------------------------------
# Each entry point called from Python is compiled for one signature only (SIGNATURES
# below; statue2model/compute/compile.py compiles and caches them): float64 scalars,
# int64 integers, C-contiguous float64 arrays and read-only motion samples (as_samples).
# Constants passed to a compiled helper are typed (np.int64(0), bool(True)): numba would
# otherwise compile one copy of the helper per literal value.
F8, I8 = nt.float64, nt.int64
VEC = nt.Array(nt.float64, 1, "C")
MAT = nt.Array(nt.float64, 2, "C")
IVEC = nt.Array(nt.int64, 1, "C")


@njit(cache=True)
def _cross_above(x, r):
    # smallest X >= x where sin crosses r upward
    a = math.asin(r)
    k = math.ceil((x - a) / (2.0 * math.pi))
    return a + 2.0 * math.pi * k


@njit(cache=True)
def _cross_below(x, r):
    a = math.pi - math.asin(r)
    k = math.ceil((x - a) / (2.0 * math.pi))
    return a + 2.0 * math.pi * k


@njit(cache=True)
def _first_exceedance(ta, tb, seg, up, dn):
    """First t in [ta, tb) with u > up (returns (t, -1): tips to the left pivot)
    or u < -dn (returns (t, +1)); (inf, 0) if none."""
    ua = _acc(ta, seg)
    if ua > up:
        return ta, -1
    if ua < -dn:
        return ta, 1
    A = seg[3]
    if A == 0.0:
        c1 = seg[1]
        if tb == np.inf:
            ub = np.inf if c1 > 0.0 else -np.inf
        elif seg[7] == seg[7]:
            ub = seg[7]
        else:
            ub = _acc(tb, seg)
        if c1 > 0.0 and ub > up:
            t = seg[2] + (up - seg[0]) / c1
            if t < ta:
                t = ta
            if t < tb:
                return t, -1
        elif c1 < 0.0 and ub < -dn:
            t = seg[2] + (-dn - seg[0]) / c1
            if t < ta:
                t = ta
            if t < tb:
                return t, 1
        return np.inf, 0
    w = seg[4]
    xa = w * (ta - seg[5]) + seg[6]
    best = np.inf
    side = 0
    # u > up
    r = up / A
    if A > 0.0:
        x = _cross_above(xa, r) if r < 1.0 else np.inf
    else:
        x = _cross_below(xa, r) if r > -1.0 else np.inf
    if x < np.inf:
        t = seg[5] + (x - seg[6]) / w
        if t < best:
            best = t
            side = -1
    # u < -dn
    r = -dn / A
    if A > 0.0:
        x = _cross_below(xa, r) if r > -1.0 else np.inf
    else:
        x = _cross_above(xa, r) if r < 1.0 else np.inf
    if x < np.inf:
        t = seg[5] + (x - seg[6]) / w
        if t < best:
            best = t
            side = 1
    if best < ta:
        best = ta
    if best < tb:
        return best, side
    return np.inf, 0


@njit(cache=True, inline="always")
def _model_tuple(P):
    """The model vector P (N_P,) as a tuple: the helpers of the integration loop read the
    model from it (a tuple is a value: no reference counting, see :func:`_step`)."""
    return (P[0], P[1], P[2], P[3], P[4], P[5], P[6], P[7], P[8], P[9], P[10], P[11], P[12], P[13])


@njit(cache=True, error_model="numpy")
def _piece(t, kind, M, samples):
    """:func:`statue2model.hazard.motion_kernel.segment` as a value: (end of the piece, the
    piece (c0, c1, t0, A, w, ts, phi, u_end)), the same arithmetic number for number
    (tests/test_fragility_speed.py checks it bit for bit). A tuple and no raise path (the
    numpy error model: dt > 0 is checked where a record is made), so that numba counts no
    reference of M or samples here: an atomic operation on an array that every thread of a
    batch shares, once per step and per sample at rest."""
    nan = np.nan
    if kind == M_NONE:
        return np.inf, (0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, nan)
    ts = M[MT0]
    te = M[MT1]
    if t < ts:
        return ts, (0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, nan)
    if t >= te:
        return np.inf, (0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, nan)
    if kind == M_HARMONIC:
        return te, (0.0, 0.0, 0.0, M[MA], M[MW], ts, M[MPH], nan)
    if kind == M_RECT:
        return te, (M[MA], 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, nan)
    dt = M[MDT]
    n = samples.shape[0]
    k = record_index(t, ts, dt, n)
    tk = ts + k * dt
    piece = (M[MA] * samples[k], M[MA] * (samples[k + 1] - samples[k]) / dt, tk, 0.0, 0.0, 0.0, 0.0,
             M[MA] * samples[k + 1])
    if k == n - 2:
        return te, piece
    return ts + (k + 1) * dt, piece


@njit(cache=True)
def suffix_extremes(samples):
    """(hi, lo), each (n,): the largest and the smallest of samples[k:] (unscaled record
    accelerations), what :func:`_quiet_until` reads; computed once per record."""
    n = samples.shape[0]
    hi = np.empty(n)
    lo = np.empty(n)
    if n == 0:
        return hi, lo
    hi[n - 1] = samples[n - 1]
    lo[n - 1] = samples[n - 1]
    for k in range(n - 2, -1, -1):
        hi[k] = max(samples[k], hi[k + 1])
        lo[k] = min(samples[k], lo[k + 1])
    return hi, lo


@njit(cache=True, error_model="numpy")
def _quiet_until(tc, M, samples, hi, lo, up, dn):
    """A body at rest at tc, the start of a record piece the stick search is about to read:
    the start of the first piece from tc on that can lift it, or inf if none can (nor the
    still ground after the record). Exact: the stick search (_first_exceedance, piece by
    piece) finds no uplift in a piece that starts at its own start time (u there is c0 =
    gain x sample, to the bit) and whose two samples, times the gain, lie within
    [-dn, up]; so it would step through such pieces one by one and find nothing. ``hi``,
    ``lo``: :func:`suffix_extremes` of the samples (the gain's rounding is monotonic: the
    largest scaled sample is the gain times the largest sample; empty arrays: no skip). tc
    is returned unchanged when it is not a piece start of the record or the record ends
    oddly (te before the last sample)."""
    ts = M[MT0]
    te = M[MT1]
    dt = M[MDT]
    n = samples.shape[0]
    if not (tc >= ts and tc < te and dt > 0.0 and n >= 2 and hi.shape[0] == n and lo.shape[0] == n):
        return tc
    k = int(math.floor((tc - ts) / dt + 0.5))
    if k < 0 or k > n - 2 or ts + k * dt != tc:
        return tc
    g = M[MA]
    top = g * hi[k] if g >= 0.0 else g * lo[k]
    bottom = g * lo[k] if g >= 0.0 else g * hi[k]
    if top <= up and bottom >= -dn:
        # no sample from k on lifts it, and no interpolated value between them: nor the
        # ground at rest after the record (u = 0) when the limits are not negative
        if up >= 0.0 and dn >= 0.0:
            return np.inf
        return tc
    j = k
    while j < n:
        v = g * samples[j]
        if v > up or v < -dn:
            break
        j += 1
    # pieces k .. j-2 have both samples within the limits: the search may start at piece j - 1
    if j - 1 <= k:
        return tc
    t_j = ts + (j - 1) * dt
    if not t_j < te:
        return tc
    return t_j


# --- mechanics ---------------------------------------------------------------
@njit(cache=True, inline="always")
def _rhs(t, th, s, reg, P, seg):
    """theta'' on side s, region reg (0: rolling transition, 1: full contact at a pivot)."""
    u = _acc(t, seg) / P[GRAV]
    if s > 0:
        x = P[DR] - th
        al = P[AR] + (1.0 - P[AR]) * th / P[TR] if reg == 0 else 1.0
        if P[LIN] > 0.0:
            return -P[P2R] * (al * x + u)
        sn, cs = sincos(x)
        return -P[P2R] * (al * sn + u * cs)
    x = P[DL] + th
    al = P[AL] - (1.0 - P[AL]) * th / P[TL] if reg == 0 else 1.0
    if P[LIN] > 0.0:
        return P[P2L] * (al * x - u)
    sn, cs = sincos(x)
    return P[P2L] * (al * sn - u * cs)


@njit(cache=True, error_model="numpy")
def _step(t, th, om, f0, h, s, reg, P, seg, Ks):
    """One DOP853 step of length h; returns (theta, theta') at t + h. Ks (_NX, 2):
    the stages (theta', theta''). P and seg are tuples (:func:`_model_tuple`, :func:`_piece`).

    The stages written out, the sums over the nonzero coefficients of the tableau _AX (every
    one, in the order of the columns) and then over _B (every column), on scalars: the
    arithmetic of the loop ``for j in range(i): if _AX[i, j] != 0: dth += _AX[i, j] Ks[j, 0]``
    (D8.stage_state, D8.combine) to the bit (tests/test_fragility_speed.py checks it), about
    8 % faster a step. The helpers take no array: numba counts the references of an array each
    time an inlined helper receives one, an atomic operation (with the stages in such a helper
    that took about half the time of a run)."""
    k0 = om
    g0 = f0
    Ks[0, 0] = k0
    Ks[0, 1] = g0
    dth = 0.0 + _AX[1, 0] * k0
    dom = 0.0 + _AX[1, 0] * g0
    k1 = om + h * dom
    g1 = _rhs(t + _CX[1] * h, th + h * dth, s, reg, P, seg)
    Ks[1, 0] = k1
    Ks[1, 1] = g1
    dth = 0.0 + _AX[2, 0] * k0 + _AX[2, 1] * k1
    dom = 0.0 + _AX[2, 0] * g0 + _AX[2, 1] * g1
    k2 = om + h * dom
    g2 = _rhs(t + _CX[2] * h, th + h * dth, s, reg, P, seg)
    Ks[2, 0] = k2
    Ks[2, 1] = g2
    dth = 0.0 + _AX[3, 0] * k0 + _AX[3, 2] * k2
    dom = 0.0 + _AX[3, 0] * g0 + _AX[3, 2] * g2
    k3 = om + h * dom
    g3 = _rhs(t + _CX[3] * h, th + h * dth, s, reg, P, seg)
    Ks[3, 0] = k3
    Ks[3, 1] = g3
    dth = 0.0 + _AX[4, 0] * k0 + _AX[4, 2] * k2 + _AX[4, 3] * k3
    dom = 0.0 + _AX[4, 0] * g0 + _AX[4, 2] * g2 + _AX[4, 3] * g3
    k4 = om + h * dom
    g4 = _rhs(t + _CX[4] * h, th + h * dth, s, reg, P, seg)
    Ks[4, 0] = k4
    Ks[4, 1] = g4
    dth = 0.0 + _AX[5, 0] * k0 + _AX[5, 3] * k3 + _AX[5, 4] * k4
    dom = 0.0 + _AX[5, 0] * g0 + _AX[5, 3] * g3 + _AX[5, 4] * g4
    k5 = om + h * dom
    g5 = _rhs(t + _CX[5] * h, th + h * dth, s, reg, P, seg)
    Ks[5, 0] = k5
    Ks[5, 1] = g5
    dth = 0.0 + _AX[6, 0] * k0 + _AX[6, 3] * k3 + _AX[6, 4] * k4 + _AX[6, 5] * k5
    dom = 0.0 + _AX[6, 0] * g0 + _AX[6, 3] * g3 + _AX[6, 4] * g4 + _AX[6, 5] * g5
    k6 = om + h * dom
    g6 = _rhs(t + _CX[6] * h, th + h * dth, s, reg, P, seg)
    Ks[6, 0] = k6
    Ks[6, 1] = g6
    dth = 0.0 + _AX[7, 0] * k0 + _AX[7, 3] * k3 + _AX[7, 4] * k4 + _AX[7, 5] * k5 + _AX[7, 6] * k6
    dom = 0.0 + _AX[7, 0] * g0 + _AX[7, 3] * g3 + _AX[7, 4] * g4 + _AX[7, 5] * g5 + _AX[7, 6] * g6
    k7 = om + h * dom
    g7 = _rhs(t + _CX[7] * h, th + h * dth, s, reg, P, seg)
    Ks[7, 0] = k7
    Ks[7, 1] = g7
    dth = 0.0 + _AX[8, 0] * k0 + _AX[8, 3] * k3 + _AX[8, 4] * k4 + _AX[8, 5] * k5 + _AX[8, 6] * k6
    dth = dth + _AX[8, 7] * k7
    dom = 0.0 + _AX[8, 0] * g0 + _AX[8, 3] * g3 + _AX[8, 4] * g4 + _AX[8, 5] * g5 + _AX[8, 6] * g6
    dom = dom + _AX[8, 7] * g7
    k8 = om + h * dom
    g8 = _rhs(t + _CX[8] * h, th + h * dth, s, reg, P, seg)
    Ks[8, 0] = k8
    Ks[8, 1] = g8
    dth = 0.0 + _AX[9, 0] * k0 + _AX[9, 3] * k3 + _AX[9, 4] * k4 + _AX[9, 5] * k5 + _AX[9, 6] * k6
    dth = dth + _AX[9, 7] * k7 + _AX[9, 8] * k8
    dom = 0.0 + _AX[9, 0] * g0 + _AX[9, 3] * g3 + _AX[9, 4] * g4 + _AX[9, 5] * g5 + _AX[9, 6] * g6
    dom = dom + _AX[9, 7] * g7 + _AX[9, 8] * g8
    k9 = om + h * dom
    g9 = _rhs(t + _CX[9] * h, th + h * dth, s, reg, P, seg)
    Ks[9, 0] = k9
    Ks[9, 1] = g9
    dth = 0.0 + _AX[10, 0] * k0 + _AX[10, 3] * k3 + _AX[10, 4] * k4 + _AX[10, 5] * k5 + _AX[10, 6] * k6
    dth = dth + _AX[10, 7] * k7 + _AX[10, 8] * k8 + _AX[10, 9] * k9
    dom = 0.0 + _AX[10, 0] * g0 + _AX[10, 3] * g3 + _AX[10, 4] * g4 + _AX[10, 5] * g5 + _AX[10, 6] * g6
    dom = dom + _AX[10, 7] * g7 + _AX[10, 8] * g8 + _AX[10, 9] * g9
    k10 = om + h * dom
    g10 = _rhs(t + _CX[10] * h, th + h * dth, s, reg, P, seg)
    Ks[10, 0] = k10
    Ks[10, 1] = g10
    dth = 0.0 + _AX[11, 0] * k0 + _AX[11, 3] * k3 + _AX[11, 4] * k4 + _AX[11, 5] * k5 + _AX[11, 6] * k6
    dth = dth + _AX[11, 7] * k7 + _AX[11, 8] * k8 + _AX[11, 9] * k9 + _AX[11, 10] * k10
    dom = 0.0 + _AX[11, 0] * g0 + _AX[11, 3] * g3 + _AX[11, 4] * g4 + _AX[11, 5] * g5 + _AX[11, 6] * g6
    dom = dom + _AX[11, 7] * g7 + _AX[11, 8] * g8 + _AX[11, 9] * g9 + _AX[11, 10] * g10
    k11 = om + h * dom
    g11 = _rhs(t + _CX[11] * h, th + h * dth, s, reg, P, seg)
    Ks[11, 0] = k11
    Ks[11, 1] = g11
    bth = 0.0 + _B[0] * k0 + _B[1] * k1 + _B[2] * k2 + _B[3] * k3 + _B[4] * k4 + _B[5] * k5 + _B[6] * k6
    bth = bth + _B[7] * k7 + _B[8] * k8 + _B[9] * k9 + _B[10] * k10 + _B[11] * k11
    bom = 0.0 + _B[0] * g0 + _B[1] * g1 + _B[2] * g2 + _B[3] * g3 + _B[4] * g4 + _B[5] * g5 + _B[6] * g6
    bom = bom + _B[7] * g7 + _B[8] * g8 + _B[9] * g9 + _B[10] * g10 + _B[11] * g11
    return th + h * bth, om + h * bom


@njit(cache=True, error_model="numpy", inline="always")
def _error_terms(Ks, c, sc):
    """(squared E5 error, squared E3 error) of component ``c`` of the step (0: theta, 1: theta'), each
    scaled by ``sc``: D8.error_norm's sums over the stages, in its order."""
    a5 = 0.0
    a3 = 0.0
    for j in range(_NS + 1):
        a5 += D8.E5[j] * Ks[j, c]
        a3 += D8.E3[j] * Ks[j, c]
    return (a5 / sc) ** 2, (a3 / sc) ** 2


@njit(cache=True, error_model="numpy")
def _error_norm(h, th, om, thn, omn, Ks, atol_t, atol_o, rtol):
    """D8.error_norm of the step (th, om) -> (thn, omn) (absolute tolerances atol_t of theta,
    atol_o of theta'), on scalars: its operations in its order (every term of E5 and E3, theta
    then theta'), to the bit, without the work rows it reads (their writes and views cost about
    a third of it)."""
    w5, w3 = _error_terms(Ks, 0, atol_t + rtol * max(abs(th), abs(thn)))
    e5 = 0.0 + w5
    e3 = 0.0 + w3
    w5, w3 = _error_terms(Ks, 1, atol_o + rtol * max(abs(om), abs(omn)))
    e5 += w5
    e3 += w3
    if e5 == 0.0 and e3 == 0.0:
        return 0.0
    return abs(h) * e5 / math.sqrt((e5 + 0.01 * e3) * 2)


@njit(cache=True, error_model="numpy")
def _dense_coeffs(t, th, om, thn, omn, h, s, reg, P, seg, Ks, Y, F):
    """Dense-output coefficients F (_NI, 2) of the accepted step (Ks rows 0..12 hold
    its stages, row 12 the slope at t + h); 3 more right-hand sides."""
    Y[0, 0] = th
    Y[0, 1] = om
    for i in range(_NS + 1, _NX):        # the 3 dense-output stages: the loop form of _step's sums
        dth = 0.0
        dom = 0.0
        for j in range(i):
            a = _AX[i, j]
            if a != 0.0:
                dth += a * Ks[j, 0]
                dom += a * Ks[j, 1]
        Ks[i, 0] = om + h * dom
        Ks[i, 1] = _rhs(t + _CX[i] * h, th + h * dth, s, reg, P, seg)
    Y[1, 0] = thn
    Y[1, 1] = omn
    D8.dense_coeffs(Y[0], Y[1], h, Ks, F)


@njit(cache=True, error_model="numpy")
def _root_dense(what, target, s, xa, Fa, xb, Fb, F, th, om, xtol):
    """Root in [xa, xb] (fractions of the step) of s*theta(x) - target (what=0) or
    s*theta'(x) (what=1) on the dense output; Fa, Fb of opposite signs (Illinois)."""
    side = 0
    x = xb
    for _ in range(200):
        x = D8.secant(xa, Fa, xb, Fb)
        if what == 0:
            fx = s * D8.dense_eval(x, F, 0, th) - target
        else:
            fx = s * D8.dense_eval(x, F, 1, om)
        if fx == 0.0:
            return x
        xa, Fa, xb, Fb, side = D8.illinois(xa, Fa, xb, Fb, side, x, fx, (fx > 0.0) == (Fb > 0.0))
        if xb - xa <= xtol:
            break
    return x


@njit(cache=True, inline="always")
def _interp_e(w, tw, te):
    n = tw.shape[0]
    if n == 1 or w <= tw[0]:
        return te[0]
    if w >= tw[n - 1]:
        return te[n - 1]
    lo = 0
    hi = n - 1
    while hi - lo > 1:
        mid = (lo + hi) // 2
        if tw[mid] <= w:
            lo = mid
        else:
            hi = mid
    f = (w - tw[lo]) / (tw[hi] - tw[lo])
    return te[lo] + f * (te[hi] - te[lo])


@njit(cache=True, inline="always")
def _bounds(s, reg, P):
    """(lo, hi) of q = s*theta in region reg of side s."""
    tr = P[TR] if s > 0 else P[TL]
    d = P[DR] if s > 0 else P[DL]
    if tr > 0.0:
        if reg == 0:
            return 0.0, min(tr, d)
        return min(tr, d), d
    return 0.0, d


@njit(cache=True, inline="always")
def _start_region(s, P):
    tr = P[TR] if s > 0 else P[TL]
    return 0 if tr > 0.0 else 1


@njit(cache=True, inline="always")
def _fill_still(out_t, out_y, io, t_until):
    """Output samples up to t_until of a body at rest; returns the next index."""
    n = out_t.shape[0]
    while io < n and out_t[io] <= t_until:
        out_y[io, 0] = 0.0
        out_y[io, 1] = 0.0
        out_y[io, 2] = 0.0
        io += 1
    return io


@njit(cache=True, inline="always")
def _dense_poor_at_mid(t, th, om, f0, h, s, reg, P, seg, Ks, F, atol_t, atol_o, rtol):
    """True if the step's dense output (coefficients F) misses a step taken directly to mid-step by
    more than 10 x the tolerance, in theta or theta' (one step of _NS - 1 evaluations; Ks is overwritten)."""
    thv, omv = _step(t, th, om, f0, 0.5 * h, s, reg, P, seg, Ks)
    return abs(thv - D8.dense_eval(0.5, F, 0, th)) > 10.0 * (atol_t + rtol * abs(thv)) or \
        abs(omv - D8.dense_eval(0.5, F, 1, om)) > 10.0 * (atol_o + rtol * abs(omv))


@njit(cache=True, error_model="numpy")
def _remaining_abs_acc(M, samples):
    """(n,) bound of the ground motion still to come from sample k: |gain| x the integral of |a| from
    t_k to the end, m/s, for a record that is linear between samples (the integral of |a| over
    one interval is at most dt (|a_k| + |a_k+1|) / 2)."""
    n = samples.shape[0]
    out = np.zeros(n)
    g = abs(M[MA]) * M[MDT] * 0.5
    for k in range(n - 2, -1, -1):
        out[k] = out[k + 1] + g * (abs(samples[k]) + abs(samples[k + 1]))
    return out


@njit(cache=True, inline="always")
def _energy_bound(th, om, s, P):
    """sqrt of an upper bound of the mechanical energy per unit pivot inertia, 1/s: 1/2 theta'^2
    + p^2 U(q) with U(q) = int_0^q alpha sin(delta - x) dx <= cos(delta - q) - cos(delta) (alpha <= 1;
    linearised: delta q - q^2 / 2)."""
    q = s * th
    if s > 0:
        p2, d = P[P2R], P[DR]
    else:
        p2, d = P[P2L], P[DL]
    if P[LIN] > 0.0:
        u = d * q - 0.5 * q * q
    else:
        u = math.cos(d - q) - math.cos(d)
    return math.sqrt(max(0.0, 0.5 * om * om + p2 * u))


@njit(cache=True, inline="always")
def _barrier(P):
    """sqrt of a lower bound, over both sides, of the energy per unit inertia that overturning
    needs: p^2 alpha (1 - cos delta) (linearised: p^2 alpha delta^2 / 2), 1/s."""
    if P[LIN] > 0.0:
        r = P[P2R] * P[AR] * 0.5 * P[DR] * P[DR]
        left = P[P2L] * P[AL] * 0.5 * P[DL] * P[DL]
    else:
        r = P[P2R] * P[AR] * (1.0 - math.cos(P[DR]))
        left = P[P2L] * P[AL] * (1.0 - math.cos(P[DL]))
    return math.sqrt(max(0.0, min(r, left)))


@njit(cache=True)
def simulate_kernel(P, eLw, eLe, eRw, eRe, kind, M, samples, theta0, omega0, t0, t_end,
                    rtol, max_steps, out_t, out_y, imp, peaks, S):
    """Integrate one run. Arrays written: out_y (len(out_t), 3) = theta, theta',
    phase (0 stick, 1 rolling transition, 2 rocking, 3 overturned); imp (cap, 3) =
    time, |theta'| before impact, landing side (-1 left edge, +1 right edge);
    peaks (cap, 3) = time, |theta| peak, side; S: statistics (indices S_*).
    Returns the number of output samples written."""
    s_hi, s_lo = suffix_extremes(samples)
    return _simulate(P, eLw, eLe, eRw, eRe, kind, M, samples, s_hi, s_lo, theta0, omega0, t0, t_end,
                     rtol, max_steps, out_t, out_y, imp, peaks, S)


@njit(cache=True, error_model="numpy")
def _simulate(Pvec, eLw, eLe, eRw, eRe, kind, M, samples, s_hi, s_lo, theta0, omega0, t0, t_end,
              rtol, max_steps, out_t, out_y, imp, peaks, S):
    """:func:`simulate_kernel` given the record's :func:`suffix_extremes` ``s_hi``, ``s_lo``
    (computed once for all the runs of a batch)."""
    P = _model_tuple(Pvec)
    for i in range(N_S):
        S[i] = 0.0
    S[S_T_UPLIFT] = np.nan
    S[S_T_OVERTURN] = np.nan
    S[S_T_REST] = np.nan
    S[S_OT_SIDE] = 0.0
    Ks = np.empty((_NX, 2))
    Y = np.empty((2, 2))             # states at the start and the end of a step
    F = np.empty((_NI, 2))
    n_out = out_t.shape[0]
    cap_imp = imp.shape[0]
    cap_pk = peaks.shape[0]
    io = 0
    while io < n_out and out_t[io] < t0:
        io += 1
    dmin = min(P[DL], P[DR])
    atol_t = rtol * dmin
    atol_o = rtol * dmin * math.sqrt(max(P[P2L], P[P2R]))
    h = 0.05 / math.sqrt(max(P[P2L], P[P2R]))
    t = t0
    th = theta0
    om = omega0
    moving = (theta0 != 0.0) or (omega0 != 0.0)
    s = 1
    if theta0 < 0.0 or (theta0 == 0.0 and omega0 < 0.0):
        s = -1
    reg = 1
    if moving:
        lo0, hi0 = _bounds(s, 0, P)
        reg = 0 if (P[TR] if s > 0 else P[TL]) > 0.0 and s * th < hi0 else 1
        S[S_T_UPLIFT] = t0
        S[S_MOVED] = 1.0
        if reg == 1 and (P[TR] if s > 0 else P[TL]) > 0.0:
            S[S_FULL_UPLIFT] = 1.0
        S[S_N_UPLIFTS] = 1.0
        if omega0 == 0.0 and cap_pk > 0:
            peaks[0, 0] = t0
            peaks[0, 1] = abs(theta0)
            peaks[0, 2] = s
        if omega0 == 0.0:
            S[S_N_PEAKS] = 1.0
    qmax_r = theta0 if theta0 > 0.0 else 0.0
    qmax_l = -theta0 if theta0 < 0.0 else 0.0
    n_imp = 0
    n_pk = int(S[S_N_PEAKS])
    nsteps = 0
    nrej = 0
    nrhs = 0
    status = STATUS_OK
    seg_end, sg = _piece(t, kind, M, samples)
    f0 = _rhs(t, th, s, reg, P, sg)
    nrhs += 1
    if moving and reg == 1 and (P[TR] if s > 0 else P[TL]) > 0.0 and s * th == _bounds(s, 0, P)[1] \
            and (s * om < 0.0 or (om == 0.0 and s * f0 < 0.0)):
        # starts exactly at theta_side moving inward: it is in the rolling transition
        reg = 0
        S[S_FULL_UPLIFT] = 0.0
        f0 = _rhs(t, th, s, reg, P, sg)
        nrhs += 1
    overturned = False
    early = P[EARLY] > 0.0
    t_quiet = M[MT1] if kind != M_NONE else t0
    # early exit on energy (records, P[EARLY] = 2: the outcome only, the maxima need not be final):
    # |d sqrt(E/I)/dt| <= p^2 |a_g| / (g sqrt 2) and impacts
    # (e <= 1) only take energy away, so once sqrt(E/I) + that times the remaining integral of
    # |a_g| is below the overturning barrier the body cannot overturn any more: decided
    bounded = P[EARLY] > 1.5 and kind == M_RECORD
    if bounded:
        for k in range(eLe.shape[0]):
            if eLe[k] > 1.0:
                bounded = False
        for k in range(eRe.shape[0]):
            if eRe[k] > 1.0:
                bounded = False
    if bounded:
        a_rem = _remaining_abs_acc(M, samples)
        k_pump = max(P[P2L], P[P2R]) / (P[GRAV] * math.sqrt(2.0))
        barrier = _barrier(P) * (1.0 - 1e-9)
    else:
        a_rem = np.zeros(1)
        k_pump = 0.0
        barrier = 0.0
    seen_r = False
    seen_l = False
    t_last = t
    stall = 0
    while t < t_end:
        status, t_last, stall = D8.guard(t, t_last, stall, nsteps + nrej, max_steps)
        if status != STATUS_OK:
            break
        if not moving:
            # stick: find the next uplift without integrating
            t_up = np.inf
            side = 0
            tc = t
            while tc < t_end:
                tb, sg = _piece(tc, kind, M, samples)
                t_up, side = _first_exceedance(tc, min(tb, t_end), sg, P[LIM_UP], P[LIM_DN])
                if side != 0 or tb == np.inf:
                    break
                tc = tb
                if kind == M_RECORD:
                    # skip the pieces that cannot lift it (exact), or stop: none can
                    tc = _quiet_until(tc, M, samples, s_hi, s_lo, P[LIM_UP], P[LIM_DN])
                    if tc == np.inf:
                        t_up = np.inf
                        break
            if side == 0 or t_up >= t_end:
                io = _fill_still(out_t, out_y, io, t_end)
                t = t_end
                break
            io = _fill_still(out_t, out_y, io, t_up)
            # the limit and the equation of motion agree only to rounding: lift once
            # the equation of motion itself pushes the body off (q'' > 0)
            s = side
            reg = _start_region(s, P)
            seg_end, sg = _piece(t_up, kind, M, samples)
            f0 = _rhs(t_up, 0.0, s, reg, P, sg)
            nrhs += 1
            nudge = 4.0 * _EPS * max(1.0, abs(t_up))
            while s * f0 <= 0.0 and t_up < min(seg_end, t_end):
                t_up += nudge
                nudge *= 4.0
                f0 = _rhs(t_up, 0.0, s, reg, P, sg)
                nrhs += 1
            if s * f0 <= 0.0:
                t = min(seg_end, t_end)
                continue
            t = t_up
            th = 0.0
            om = 0.0
            moving = True
            if S[S_MOVED] == 0.0:
                S[S_T_UPLIFT] = t
                S[S_MOVED] = 1.0
            S[S_N_UPLIFTS] += 1.0
            continue
        # --- one adaptive step inside the current segment
        t_lim = min(seg_end, t_end)
        if t_lim - t <= 0.0:
            if t >= t_end:
                break
            seg_end, sg = _piece(t, kind, M, samples)
            f0 = _rhs(t, th, s, reg, P, sg)
            nrhs += 1
            continue
        h_try = h
        if h > t_lim - t:
            h = t_lim - t
        hits = True if h == t_lim - t else False
        thn, omn = _step(t, th, om, f0, h, s, reg, P, sg, Ks)
        tn = t_lim if hits else t + h
        fn = _rhs(tn, thn, s, reg, P, sg)
        Ks[_NS, 0] = omn
        Ks[_NS, 1] = fn
        nrhs += _NS
        err = _error_norm(h, th, om, thn, omn, Ks, atol_t, atol_o, rtol)
        if not (err <= 1.0):  # also rejects nan
            h *= D8.factor_reject(err)
            nrej += 1
            if h < 1e-14 * max(1.0, abs(t)):
                h = 1e-14 * max(1.0, abs(t))
            continue
        if hits and h * 10.0 < h_try:
            h_next = h_try      # what D8.next_step gives (its factor is at most 10), without its power
        else:
            h_next = D8.next_step(h, err, hits, h_try)
        dense = False
        xtol = D8.event_xtol(t, h)
        floor = D8.shortest(h, t)  # shortest step: no more retries
        nsteps += 1
        q0 = s * th
        qn = s * thn
        lo, hi = _bounds(s, reg, P)
        d0 = s * om
        if d0 == 0.0:
            d0 = s * f0
        dn_ = s * omn
        # a run that started at rest and whose end point fell below the base: shrink
        if q0 == lo and lo == 0.0 and om == 0.0 and qn < lo:
            h *= 0.25
            nrej += 1
            if h < 1e-13 * max(1.0, abs(t)):
                # never lifted: back to stick just after t
                moving = False
                t = t + 1e-12 * max(1.0, abs(t))
            continue
        # extremum of q inside the step
        validated = False     # the dense output checked against a direct step inside this step
        x_e = -1.0
        q_e = 0.0
        is_peak = False
        xe0 = 0.0
        Fe0 = d0
        xe1 = 1.0
        Fe1 = dn_
        found = (d0 > 0.0 and dn_ <= 0.0) or (d0 < 0.0 and dn_ >= 0.0)
        scan = not found and f0 * fn <= 0.0
        if scan:
            # theta' cannot reach zero inside the step when it stays, at both ends, above
            # twice h times the largest theta'' of the step's stages (13 points of it)
            amax = 0.0
            for k in range(_NS + 1):
                amax = max(amax, abs(Ks[k, 1]))
            scan = min(abs(d0), abs(dn_)) <= 2.0 * h * amax
        if scan:
            # theta'' changes sign: theta' may cross zero and come back inside the step
            if not dense:
                _dense_coeffs(t, th, om, thn, omn, h, s, reg, P, sg, Ks, Y, F)
                nrhs += 3
                dense = True
            xp = 0.0
            Fp = d0
            twice = False
            for k in range(1, 9):
                xk = k / 8.0
                Fk = s * D8.dense_eval(xk, F, 1, om) if k < 8 else dn_
                if (Fp > 0.0 and Fk <= 0.0) or (Fp < 0.0 and Fk >= 0.0):
                    if not found:
                        found = True
                        xe0, Fe0, xe1, Fe1 = xp, Fp, xk, Fk
                    elif not floor:
                        twice = True
                        break
                xp = xk
                Fp = Fk
            if twice:
                # two extrema in one step: retry shorter, one extremum per step
                nsteps -= 1
                nrej += 1
                h *= 0.25
                continue
        if found:
            is_peak = Fe0 > 0.0
            if Fe1 == 0.0:
                x_e = xe1 * h
                if xe1 == 1.0:
                    q_e = qn
                else:
                    q_e = s * D8.dense_eval(xe1, F, 0, th)
            else:
                if not dense:
                    _dense_coeffs(t, th, om, thn, omn, h, s, reg, P, sg, Ks, Y, F)
                    nrhs += 3
                    dense = True
                xr = _root_dense(np.int64(1), 0.0, s, xe0, Fe0, xe1, Fe1, F, th, om, xtol)
                x_e = xr * h
                q_e = s * D8.dense_eval(xr, F, 0, th)
        # which boundary event comes first
        ev = 0  # 0 none, -1 leaves through lo, +1 through hi
        xa = 0.0
        xb = h
        if x_e >= 0.0 and is_peak and q_e > hi:
            ev = 1
            xb = x_e
        elif x_e >= 0.0 and (not is_peak) and q_e < lo:
            ev = -1
            xb = x_e
        else:
            if x_e >= 0.0:
                xa = x_e
            if qn < lo:
                ev = -1
            elif qn > hi:
                ev = 1
        x_ev = h
        th_ev = thn
        om_ev = omn
        retry = False
        if ev != 0:
            target = lo if ev < 0 else hi
            if xa == 0.0:
                Fa = q0 - target
            else:
                Fa = q_e - target
            if xb == h:
                Fb = qn - target
            else:
                Fb = q_e - target
            if Fa == 0.0:
                if xa == 0.0 and not floor:
                    # it starts on that boundary moving inward, yet ends outside with no
                    # extremum seen: the step missed one; retry shorter
                    retry = True
                x_ev = xa
                th_ev = th if xa == 0.0 else s * q_e
                om_ev = om
            elif Fb == 0.0:
                x_ev = xb
                th_ev = thn
                om_ev = omn
            else:
                if not dense:
                    _dense_coeffs(t, th, om, thn, omn, h, s, reg, P, sg, Ks, Y, F)
                    nrhs += 3
                    dense = True
                xr = _root_dense(np.int64(0), target, s, xa / h, Fa, xb / h, Fb, F, th, om, xtol)
                x_ev = xr * h
                th_ev = D8.dense_eval(xr, F, 0, th)
                om_ev = D8.dense_eval(xr, F, 1, om)
                # check the dense output against a step taken to the event
                thv, omv = _step(t, th, om, f0, x_ev, s, reg, P, sg, Ks)
                nrhs += _NS - 1
                validated = True
                if not floor and (abs(thv - th_ev) > 10.0 * (atol_t + rtol * abs(thv)) or
                                  abs(omv - om_ev) > 10.0 * (atol_o + rtol * abs(omv))):
                    retry = True
                th_ev = thv
                om_ev = omv
        if x_e >= 0.0 and x_e < h and not retry and not floor:
            thv, omv = _step(t, th, om, f0, x_e, s, reg, P, sg, Ks)
            nrhs += _NS - 1
            validated = True
            if abs(s * thv - q_e) > 10.0 * (atol_t + rtol * abs(thv)) or abs(omv) > 10.0 * (atol_o + rtol * abs(om)):
                retry = True
            else:
                q_e = s * thv
        t_ev = t + x_ev if x_ev < h else tn
        checked = validated
        poor = False
        if not retry and not floor and reg == 0 and dense and not validated:
            # in the rolling transition (stiff when theta_side is small) the dense output
            # may be poor while the end point passes: where the step's extremum scan read it
            # and no step to an extremum or an event has checked it already, check it at
            # mid-step (a fixed point) and retry shorter if it is poor.
            # Output samples never change the solution: they get their own check below.
            retry = _dense_poor_at_mid(t, th, om, f0, h, s, reg, P, sg, Ks, F, atol_t, atol_o, rtol)
            nrhs += _NS - 1
            checked = True
        if retry:
            nsteps -= 1
            nrej += 1
            h *= 0.25
            continue
        if x_e >= 0.0 and is_peak and q_e <= hi and not (ev == -1 and xb == x_e):
            if n_pk < cap_pk:
                peaks[n_pk, 0] = t + x_e
                peaks[n_pk, 1] = q_e
                peaks[n_pk, 2] = s
            n_pk += 1
            if s > 0 and q_e > qmax_r:
                qmax_r = q_e
            if s < 0 and q_e > qmax_l:
                qmax_l = q_e
            if t + x_e >= t_quiet:
                if s > 0:
                    seen_r = True
                else:
                    seen_l = True
                if early and seen_r and seen_l:
                    # free motion that loses energy at every impact: later peaks are
                    # smaller on both sides, so the outcome and the maxima are final
                    S[S_DECIDED] = 1.0
                    t = t + x_e
                    break
        # output samples in (t, t_ev]
        while io < n_out and out_t[io] <= t_ev:
            xo = out_t[io] - t
            if xo == x_ev:
                tho, omo = th_ev, om_ev
            elif xo == h:
                tho, omo = thn, omn
            else:
                if not dense:
                    _dense_coeffs(t, th, om, thn, omn, h, s, reg, P, sg, Ks, Y, F)
                    nrhs += 3
                    dense = True
                if reg == 0 and not checked:
                    # the same mid-step check, for the output only (no retry): a poor dense
                    # output is replaced by steps taken to each sample
                    poor = _dense_poor_at_mid(t, th, om, f0, h, s, reg, P, sg, Ks, F, atol_t, atol_o, rtol)
                    nrhs += _NS - 1
                    checked = True
                if reg == 0 and poor:
                    tho, omo = _step(t, th, om, f0, xo, s, reg, P, sg, Ks)
                    nrhs += _NS - 1
                else:
                    tho = D8.dense_eval(xo / h, F, 0, th)
                    omo = D8.dense_eval(xo / h, F, 1, om)
            out_y[io, 0] = tho
            out_y[io, 1] = omo
            out_y[io, 2] = 1.0 if reg == 0 else 2.0
            io += 1
        if ev == 0:
            t = tn
            th = thn
            om = omn
            f0 = fn
            if qn > 0.0:
                if s > 0 and qn > qmax_r:
                    qmax_r = qn
                if s < 0 and qn > qmax_l:
                    qmax_l = qn
            h = h_next
            if hits and bounded and t >= M[MT0]:
                kk = int(math.floor((t - M[MT0]) / M[MDT] + 0.5)) - 1     # from the sample before t
                if kk < 0:
                    kk = 0
                rem = a_rem[kk] if kk < a_rem.shape[0] else 0.0
                # the energy bound is >= 0: with k_pump rem alone at the barrier the test fails
                if k_pump * rem < barrier and _energy_bound(th, om, s, P) + k_pump * rem < barrier:
                    S[S_DECIDED] = 1.0
                    break
            if hits and t < t_end:
                seg_end, sg = _piece(t, kind, M, samples)
                f0 = _rhs(t, th, s, reg, P, sg)
                nrhs += 1
            continue
        # apply the event
        t = t_ev
        h = max(h_next, 1e-3 * h)
        if ev > 0:
            if reg == 0 and hi < (P[DR] if s > 0 else P[DL]):
                reg = 1
                S[S_FULL_UPLIFT] = 1.0
                th = s * hi
                om = om_ev
            else:
                # overturning: |theta| reaches delta
                th = s * hi
                om = om_ev
                if s > 0:
                    qmax_r = hi
                else:
                    qmax_l = hi
                overturned = True
                S[S_OVERTURNED] = 1.0
                S[S_T_OVERTURN] = t
                S[S_IMP_BEFORE_OT] = n_imp
                S[S_OT_SIDE] = s
                break
        else:
            if lo > 0.0:
                reg = 0
                th = s * lo
                om = om_ev
            else:
                # impact at theta = 0: lands on the other edge
                w = abs(om_ev)
                if s > 0:
                    e = _interp_e(w, eLw, eLe)
                    land = -1
                else:
                    e = _interp_e(w, eRw, eRe)
                    land = 1
                if n_imp < cap_imp:
                    imp[n_imp, 0] = t
                    imp[n_imp, 1] = w
                    imp[n_imp, 2] = land
                n_imp += 1
                s = -s
                reg = _start_region(s, P)
                th = 0.0
                om = e * om_ev
                seg_end, sg = _piece(t, kind, M, samples)
                # Zeno: sum the remaining impacts in closed form once they are negligible
                c = -s * _rhs(t, 0.0, s, reg, P, sg)
                nrhs += 1
                wp = abs(om)
                dside = P[DR] if s > 0 else P[DL]
                if c > 0.0 and (wp == 0.0 or wp * wp / (2.0 * c) < P[REST_TOL] * dside):
                    # the next excursions peak below rest_tol * delta: at rest (for e < 1
                    # after the geometric series of their durations, else after one)
                    if wp == 0.0:
                        t_rest = t
                    elif e < 1.0:
                        t_rest = t + (2.0 * wp / c) / (1.0 - e)
                    else:
                        t_rest = t + 2.0 * wp / c
                    io = _fill_still(out_t, out_y, io, t_rest)
                    t = t_rest
                    th = 0.0
                    om = 0.0
                    moving = False
                    S[S_T_REST] = t
                    continue
        S[S_T_REST] = np.nan
        seg_end, sg = _piece(t, kind, M, samples)
        f0 = _rhs(t, th, s, reg, P, sg)
        nrhs += 1
    if overturned:
        S[S_T_REST] = np.nan
    elif moving or S[S_DECIDED] > 0.0:
        S[S_T_REST] = np.nan
    S[S_QMAX_R] = qmax_r
    S[S_QMAX_L] = qmax_l
    S[S_N_IMP] = n_imp
    S[S_N_RHS] = nrhs
    S[S_N_PEAKS] = n_pk
    D8.write_stats(S, STEP_STATS, nsteps, nrej, status, t, io)
    return io


@njit(cache=True, parallel=True)
def simulate_batch(Pm, tables, lengths, table_row, kinds, Mm, samples, s_hi, s_lo, theta0, omega0, t_end,
                   rtol, max_steps, Sm):
    """Run len(Pm) simulations in parallel (statistics only): row i uses model Pm[i], the
    restitution tables number j = table_row[i] of ``tables`` (its rows 4j .. 4j+3: e_L's
    |theta'| in rad/s and e_L, e_R's |theta'| and e_R, each ``lengths[4j + c]`` long; see
    :func:`statue2model.rocking.batch.restitution_tables`), motion (kinds[i], Mm[i], samples)
    and end time t_end[i]. ``s_hi``, ``s_lo``: :func:`suffix_extremes` of the samples (a body
    at rest skips the record pieces that cannot lift it, exactly), or empty arrays: the stick
    search then reads every piece (the same result; the path before the skip, for tests)."""
    n = Pm.shape[0]
    out_t = np.empty(0)
    for i in prange(n):
        j = 4 * table_row[i]
        eLw = tables[j, :lengths[j]].copy()
        eLe = tables[j + 1, :lengths[j + 1]].copy()
        eRw = tables[j + 2, :lengths[j + 2]].copy()
        eRe = tables[j + 3, :lengths[j + 3]].copy()
        out_y = np.empty((0, 3))
        imp = np.empty((0, 3))
        peaks = np.empty((0, 3))
        _simulate(Pm[i], eLw, eLe, eRw, eRe, kinds[i], Mm[i], samples, s_hi, s_lo, theta0, omega0,
                  0.0, t_end[i], rtol, max_steps, out_t, out_y, imp, peaks, Sm[i])


SIGNATURES = {
    "ground_acc": (F8, I8, VEC, SAMPLES),
    "simulate_kernel": (VEC, VEC, VEC, VEC, VEC, I8, VEC, SAMPLES, F8, F8, F8, F8, F8, I8, VEC, MAT, MAT, MAT, VEC),
    "simulate_batch": (MAT, MAT, IVEC, IVEC, IVEC, MAT, SAMPLES, VEC, VEC, F8, F8, VEC, F8, I8, MAT),
}
"""The one argument-type signature of each entry point (see statue2model.compute.compile)."""
