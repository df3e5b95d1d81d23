"""Dormand-Prince 8(5,3) machinery shared by the compiled integrators (numba).

The rocking kernel (:mod:`statue2model.rocking.kernel`, state (theta, theta'))
and the coupled plate + statue kernel (:mod:`statue2model.isolator.coupled_kernel`,
state (u, u', theta, theta')) step the same method: scipy's DOP853 tableau with
its error norm, step-size controller and 7th-order dense output (3 extra
stages), and locate events on that dense output by the Illinois method. Their
right-hand sides, events and discrete modes differ; the pieces here do not
depend on them:

* the tableau (read from scipy, not re-typed): :data:`A`, :data:`B`, :data:`C`,
  :data:`E3`, :data:`E5`, :data:`D`;
* :func:`stage_state`: the state at which stage i is evaluated, from the stages
  before it; :func:`combine`: the 8th-order end point of a step;
* :func:`error_norm` (scipy's), :func:`factor_reject` / :func:`factor_accept`
  (the step-size controller);
* :func:`dense_coeffs`, :func:`dense_eval`, :func:`dense`: the dense output;
* :func:`secant` / :func:`illinois`: one Illinois iteration on a bracket;
* the guard of the integration loop and its statistics: :func:`guard` (the
  max-steps and stall checks, status :data:`STATUS_OK` / :data:`STATUS_MAX_STEPS`
  / :data:`STATUS_STALLED`), :func:`next_step` (the step after an accepted one),
  :func:`shortest` (a step too short to retry), :func:`event_xtol` (the tolerance
  of an event's location), :func:`write_stats` (the counts of a run into its
  statistics vector, at the kernel's own indices).

Arrays: stages ``Ks`` (N_STAGES_EXTENDED, ny), rows 0..N_STAGES-1 the stages of a
step, row N_STAGES the slope at its end, the 3 rows after it the dense-output
stages; dense-output coefficients ``F`` (INTERPOLATOR_POWER, ny); states (ny,).
A kernel evaluates its own right-hand side at ``stage_state``'s result and
writes the slopes into ``Ks[i]``. Every function is inlined into its caller
(``inline="always"``), so numba's cache of a kernel module holds this code:
statue2model.compute.compile.DEPENDS lists this module for each of them.
"""
from __future__ import annotations

import math

import numpy as np
from numba import njit
from scipy.integrate._ivp import dop853_coefficients as _dop

N_STAGES = _dop.N_STAGES
"""Stages of one step (12)."""
N_STAGES_EXTENDED = _dop.N_STAGES_EXTENDED
"""Rows of the stage array: the step's stages, the slope at its end and the 3 dense-output stages (16)."""
INTERPOLATOR_POWER = _dop.INTERPOLATOR_POWER
"""Coefficients of the dense output per state component (7)."""
A = np.ascontiguousarray(_dop.A, dtype=np.float64)     # with the 3 extra stages of the dense output
B = np.ascontiguousarray(_dop.B, dtype=np.float64)
C = np.ascontiguousarray(_dop.C, dtype=np.float64)
E3 = np.ascontiguousarray(_dop.E3, dtype=np.float64)
E5 = np.ascontiguousarray(_dop.E5, dtype=np.float64)
D = np.ascontiguousarray(_dop.D, dtype=np.float64)

EPS = 2.220446049250313e-16
"""Machine epsilon of float64."""
STATUS_OK, STATUS_MAX_STEPS, STATUS_STALLED = 0, 1, 2
"""How a run ended: it reached its end (or an event ended it), it took ``max_steps``
steps (accepted + rejected), or its time stood still for :data:`MAX_STALL` passes."""
MAX_STALL = 10000
"""Passes of the integration loop without progress in time after which a run has stalled."""


@njit(cache=True, inline="always")
def stage_state(i, y, h, Ks, ytmp):
    """ytmp = y + h sum_j A[i, j] Ks[j]: the state of stage i (its time: t + C[i] h)."""
    for c in range(y.shape[0]):
        acc = 0.0
        for j in range(i):
            a = A[i, j]
            if a != 0.0:
                acc += a * Ks[j, c]
        ytmp[c] = y[c] + h * acc


@njit(cache=True, inline="always")
def combine(y, h, Ks, yn):
    """yn = y(t + h) = y + h sum_j B[j] Ks[j] (Ks rows 0..N_STAGES-1 filled)."""
    for c in range(y.shape[0]):
        acc = 0.0
        for j in range(N_STAGES):
            acc += B[j] * Ks[j, c]
        yn[c] = y[c] + h * acc


@njit(cache=True, inline="always")
def error_norm(h, y, yn, Ks, atol, rtol):
    """scipy's DOP853 error norm of a step of length h from y to yn (Ks row N_STAGES:
    the slope at yn); atol (ny,) absolute tolerances, rtol relative. The step is
    accepted when it is <= 1 (nan rejects)."""
    ny = y.shape[0]
    e5 = 0.0
    e3 = 0.0
    for c in range(ny):
        a5 = 0.0
        a3 = 0.0
        for j in range(N_STAGES + 1):
            a5 += E5[j] * Ks[j, c]
            a3 += E3[j] * Ks[j, c]
        sc = atol[c] + rtol * max(abs(y[c]), abs(yn[c]))
        e5 += (a5 / sc) ** 2
        e3 += (a3 / sc) ** 2
    if e5 == 0.0 and e3 == 0.0:
        return 0.0
    return abs(h) * e5 / math.sqrt((e5 + 0.01 * e3) * ny)


@njit(cache=True, inline="always")
def factor_reject(err):
    """Factor of the step length after a rejected step (err > 1)."""
    return max(0.2, 0.9 * err ** (-1.0 / 8.0))


@njit(cache=True, inline="always")
def factor_accept(err):
    """Factor of the next step's length after an accepted step (err <= 1), in [0.2, 10]."""
    return 10.0 if err == 0.0 else min(10.0, max(0.2, 0.9 * err ** (-1.0 / 8.0)))


@njit(cache=True, inline="always")
def dense_coeffs(y, yn, h, Ks, F):
    """Dense-output coefficients F of the step y -> yn of length h (Ks: all
    N_STAGES_EXTENDED rows filled)."""
    for c in range(y.shape[0]):
        dlt = yn[c] - y[c]
        F[0, c] = dlt
        F[1, c] = h * Ks[0, c] - dlt
        F[2, c] = 2.0 * dlt - h * (Ks[N_STAGES, c] + Ks[0, c])
        for r in range(INTERPOLATOR_POWER - 3):
            acc = 0.0
            for j in range(N_STAGES_EXTENDED):
                acc += D[r, j] * Ks[j, c]
            F[3 + r, c] = h * acc


@njit(cache=True, inline="always")
def dense_eval(x, F, c, y0):
    """Component c of the dense output at x (fraction of the step, 0..1); y0 = y[c] at
    the step's start."""
    v = 0.0
    for i in range(INTERPOLATOR_POWER):
        v += F[INTERPOLATOR_POWER - 1 - i, c]
        if i % 2 == 0:
            v *= x
        else:
            v *= 1.0 - x
    return v + y0


@njit(cache=True, inline="always")
def dense(x, F, y, out):
    """out = the dense output at x (fraction of the step); y: the state at its start."""
    for c in range(y.shape[0]):
        out[c] = dense_eval(x, F, c, y[c])


@njit(cache=True, inline="always")
def secant(xa, fa, xb, fb):
    """The next point of the Illinois method in the bracket [xa, xb] (the secant, or
    the midpoint when the secant leaves the open bracket)."""
    x = (xa * fb - xb * fa) / (fb - fa)
    if not (xa < x < xb):
        x = 0.5 * (xa + xb)
    return x


@njit(cache=True, inline="always")
def illinois(xa, fa, xb, fb, side, x, fx, to_b):
    """Shrink the bracket with the value fx at x: x replaces xb when to_b (fx has the
    sign of fb), else xa; the value kept at the other end is halved when the same end
    moved twice in a row. side: -1 (xb moved last), +1 (xa), 0 (none yet).
    Returns (xa, fa, xb, fb, side)."""
    if to_b:
        xb = x
        fb = fx
        if side == -1:
            fa *= 0.5
        side = -1
    else:
        xa = x
        fa = fx
        if side == 1:
            fb *= 0.5
        side = 1
    return xa, fa, xb, fb, side


@njit(cache=True, inline="always")
def guard(t, t_last, stall, n_tries, max_steps):
    """The check at the top of each pass of an integration loop at time t: t_last, the
    latest time reached, and stall, the passes since it was reached, are updated;
    n_tries = steps accepted + rejected so far. Returns (status, t_last, stall): the
    loop goes on while status is STATUS_OK; STATUS_STALLED after more than MAX_STALL
    passes at one time, STATUS_MAX_STEPS once n_tries reaches max_steps."""
    if t > t_last:
        t_last = t
        stall = 0
    else:
        stall += 1
        if stall > MAX_STALL:
            return STATUS_STALLED, t_last, stall
    if n_tries >= max_steps:
        return STATUS_MAX_STEPS, t_last, stall
    return STATUS_OK, t_last, stall


@njit(cache=True, inline="always")
def next_step(h, err, hits, h_try):
    """Length of the step after an accepted step of length h with error norm err (<= 1):
    h factor_accept(err), but not shorter than the proposed length h_try when the step was
    cut short to end on a breakpoint (hits)."""
    h_next = h * factor_accept(err)
    if hits and h_next < h_try:
        h_next = h_try
    return h_next


@njit(cache=True, inline="always")
def shortest(h, t):
    """True if a step of length h at time t is the shortest taken (1e-12 max(1, |t|)): it
    is not retried shorter."""
    return h <= 1e-12 * max(1.0, abs(t))


@njit(cache=True, inline="always")
def event_xtol(t, h):
    """Tolerance, as a fraction of a step of length h at time t, of an event located on
    its dense output: 4 ulp of max(1, |t|) in time."""
    return 4.0 * EPS * max(1.0, abs(t)) / h


@njit(cache=True, inline="always")
def write_stats(S, slots, n_steps, n_rejected, status, t_final, n_out):
    """The integrator's counts of a run into its statistics vector S: ``slots`` = the
    kernel's indices of (steps accepted, steps rejected, status, final time (s), output
    samples written)."""
    S[slots[0]] = n_steps
    S[slots[1]] = n_rejected
    S[slots[2]] = status
    S[slots[3]] = t_final
    S[slots[4]] = n_out
