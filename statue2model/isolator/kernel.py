"""Compiled integrators of the top plate (numba); see dynamics.py for the interface.

The ground acceleration is taken piece by piece from the rocking kernel's motion
representation (statue2model.rocking.kernel.segment): on each piece
f(t) = c0 + c1 (t - t0) + A sin(w (t - ts) + phi).

Coulomb (eq. 20): while sliding with velocity sign s, u'' + omega^2 u = -s mu g - f(t)
is linear with a closed-form solution on each piece, so the plate is advanced
exactly: reversals (u' = 0) are roots of the closed-form velocity, found by
sampling each piece at 1/16 of the shortest period and bisecting to machine
precision; where s u' > 0 at both ends of a sub-interval but s u'' turns from
negative to positive inside it, s u' is also checked at that minimum (closed form
on a record's piece, bisected under a sine), so a stop inside one record sample is
not missed. A stuck plate
(|omega^2 u + f| <= mu g) moves with the ground until f leaves that band, found
exactly as for the rocking uplift.

Bouc-Wen (eqs. 22-24, beta = gamma = 1/2, n = 1 or 2): while u' keeps its sign,
z is an exact function of u - u_r (the loading branch is an exponential (n = 1)
or a tanh (n = 2) towards sgn(u'); unloading is linear with slope 1/u_y), so
|z| <= 1 by construction and the stiff z equation never has to be stepped. The
remaining 2-state equation u'' = -omega^2 u - (1 - 1/q) mu g z(u) - f(t) is
integrated with an adaptive Dormand-Prince 5(4) step that never crosses a motion
breakpoint or an output time; a reversal is located by bisection on the step.

Capacity (both models): between two reversals u is monotonic, so |u| passes the
capacity ``cap`` inside a piece (Coulomb) or a step (Bouc-Wen) exactly when it is
beyond it at the piece's end (or at the reversal); the crossing time is then
bisected to machine precision on the closed form (Coulomb) or on the step
length (Bouc-Wen). Outputs are not involved, and with cap = inf the only extra
work is one comparison per piece or step. ``stop`` = 0: the run ends there
(samples after it are nan); ``stop`` = 1: the top plate hits a rigid end stop,
u' -> -e_stop u' (a Newton impact), and the run goes on; when the rebound would
rise less than REST_TOL x cap against a force that pushes the plate back onto
the stop, it stays on the stop (u' = 0) until the force pulls it away (the
one-sided counterpart of a stuck plate, found exactly as that).

Peak absolute acceleration (stats[I_AMAX]) over the continuous solution, not at
output samples: while the plate moves one way, a_abs = -(omega^2 u + s mu g)
(Coulomb) or -(omega^2 u + (1 - 1/q) mu g z) (Bouc-Wen) is monotonic, so its
extremes are at the ends of the phase (reversals, stick/slide changes, steps); while
stuck (or on the end stop) a_abs = u_g'', whose largest |.| on [t, t_stop] is taken at
the ends and at the sine's crests inside (:func:`_max_abs_f`), with t_stop the exact
unstick time, also when that falls inside a record sample. So |a_abs| never exceeds
omega^2 max|u| + mu g (the static friction bound), the end stop's reaction apart.
"""
from __future__ import annotations

import math

import numpy as np
from numba import njit

from ..hazard import motion_kernel as MK
from ..rocking import kernel as K

# statistics vector (I_TCAP, I_UCAP: first time and displacement at which |u| reached the
# capacity, nan if never; I_NHITS: capacity crossings, i.e. end-stop impacts with stop = 1)
(I_UMAX, I_AMAX, I_NSTEPS, I_NREJ, I_TFINAL, I_NPEAKS, I_STATUS, I_TSLIDE, I_TCAP, I_UCAP, I_NHITS) = range(11)
N_I = 11
REST_TOL = 1e-9
"""A rebound that would rise less than REST_TOL x capacity leaves the plate on the end stop."""


@njit(cache=True)
def _grow(a, n):
    if n < a.shape[0]:
        return a
    b = np.empty(2 * a.shape[0] + 16)
    b[: a.shape[0]] = a
    return b


@njit(cache=True)
def _push_peak(pk_t, pk_u, n, t, u):
    """Append the peak (t, u) at index n, growing the arrays; returns them and n + 1."""
    pk_t = _grow(pk_t, n)
    pk_u = _grow(pk_u, n)
    pk_t[n] = t
    pk_u[n] = u
    return pk_t, pk_u, n + 1


# ---------------------------------------------------------------- Coulomb, exact
@njit(cache=True)
def _coulomb_coeffs(ta, ua, va, s, seg, om, mug, out):
    """out = [p0, p1, B, res, C, D]: u(t) = p0 + p1 (t - t0) + harmonic(t) + C cos(om (t-ta)) + D sin(om (t-ta))."""
    c0, c1, A, w = seg[0], seg[1], seg[3], seg[4]
    om2 = om * om
    p1 = -c1 / om2
    p0 = (-s * mug - c0) / om2
    B = 0.0
    res = 0.0
    if A != 0.0:
        if abs(w - om) > 1e-9 * om:
            B = -A / (om2 - w * w)
        else:
            res = A / (2.0 * om)
    out[0] = p0
    out[1] = p1
    out[2] = B
    out[3] = res
    P, dP, _ = _part(ta, seg, out)
    out[4] = ua - P
    out[5] = (va - dP) / om


@njit(cache=True)
def _part(t, seg, cf):
    """Particular solution and its first two derivatives at t."""
    t0, w, ts, ph = seg[2], seg[4], seg[5], seg[6]
    P = cf[0] + cf[1] * (t - t0)
    dP = cf[1]
    ddP = 0.0
    if cf[2] != 0.0:
        x = w * (t - ts) + ph
        P += cf[2] * math.sin(x)
        dP += cf[2] * w * math.cos(x)
        ddP -= cf[2] * w * w * math.sin(x)
    elif cf[3] != 0.0:
        tau = t - ts
        x = w * tau + ph
        c = math.cos(x)
        sn = math.sin(x)
        P += cf[3] * tau * c
        dP += cf[3] * (c - w * tau * sn)
        ddP += cf[3] * (-2.0 * w * sn - w * w * tau * c)
    return P, dP, ddP


@njit(cache=True)
def _coulomb_state(t, ta, seg, cf, om):
    P, dP, ddP = _part(t, seg, cf)
    x = om * (t - ta)
    c = math.cos(x)
    sn = math.sin(x)
    u = P + cf[4] * c + cf[5] * sn
    v = dP + om * (-cf[4] * sn + cf[5] * c)
    a = ddP - om * om * (cf[4] * c + cf[5] * sn)
    return u, v, a


@njit(cache=True)
def _coulomb_bisect(lo, hi, t, seg, cf, om, s, level, on_v):
    """Bisect [lo, hi] (absolute times) to machine precision for the first time at which
    s x passes ``level``: x = v (before it: s v > level) when ``on_v``, else x = u (before
    it: s u <= level). Returns the upper end."""
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if mid <= lo or mid >= hi:
            break
        um, vm, _ = _coulomb_state(mid, t, seg, cf, om)
        x = vm if on_v else um
        if (s * x > level) == on_v:
            lo = mid
        else:
            hi = mid
    return hi


@njit(cache=True)
def _coulomb_min_v(lo, hi, t, seg, cf, om, s):
    """The time of the minimum of s u' on [lo, hi] (absolute times), where s u'' < 0 at lo
    and > 0 at hi. Without a sine in the ground motion (a record, a constant) u'' is the
    free oscillation's alone, -om^2 rho cos(x - theta) with x = om (t - ta): the zero in
    between in closed form; else bisection to machine precision on the sign of s u''."""
    if cf[2] == 0.0 and cf[3] == 0.0:
        th = math.atan2(cf[5], cf[4])
        xl = om * (lo - t)
        k = math.ceil((xl - th - 0.5 * math.pi) / math.pi)
        tm = t + (th + 0.5 * math.pi + k * math.pi) / om
        return min(max(tm, lo), hi)
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if mid <= lo or mid >= hi:
            break
        _, _, am = _coulomb_state(mid, t, seg, cf, om)
        if s * am < 0.0:
            lo = mid
        else:
            hi = mid
    return hi


@njit(cache=True)
def _max_abs_f(ta, tb, seg, t_piece_end):
    """max |f| on [ta, tb] for one piece that ends at ``t_piece_end`` (tb <= t_piece_end): its
    ends and the sine's crests inside. At tb = t_piece_end a record's exact sample (seg[7]) is
    used; a tb inside the piece (a stuck phase that ends mid-sample) takes the piece's line
    at tb, never the next sample's value (a state no longer valid then)."""
    fb = seg[7] if (tb >= t_piece_end and seg[7] == seg[7]) else MK.seg_acc(tb, seg)
    m = max(abs(MK.seg_acc(ta, seg)), abs(fb))
    if seg[3] != 0.0 and seg[1] == 0.0:
        w, ts, ph = seg[4], seg[5], seg[6]
        xa = w * (ta - ts) + ph
        k = math.ceil((xa - 0.5 * math.pi) / math.pi)
        x = 0.5 * math.pi + k * math.pi
        if ts + (x - ph) / w <= tb:
            m = max(m, abs(seg[0]) + abs(seg[3]))
    return m


@njit(cache=True)
def _stop_rebound(t, v, s, e_stop, cap, F, kind, M, samples, seg):
    """After an end-stop impact at u = s cap with velocity v (sign s): (new velocity, stays on
    the stop?). ``F``: the restoring force per unit mass on the way back (sign -s), so the
    relative acceleration there is -F - u_g''; the plate stays on the stop when that pushes
    it back and the rebound (e_stop v) would rise less than REST_TOL cap, or e_stop v = 0."""
    v_new = -e_stop * v
    if v_new == 0.0:
        return 0.0, True
    MK.segment(t, kind, M, samples, seg)
    a_in = -F - MK.seg_acc(t, seg)
    if s * a_in > 0.0 and v_new * v_new / (2.0 * abs(a_in)) < REST_TOL * cap:
        return 0.0, True
    return v_new, False


@njit(cache=True)
def coulomb(om, mug, kind, M, samples, u0, v0, t_end, dt_out, cap, stop, e_stop, out_u, out_v, out_a, pk_t, pk_u,
            stats):
    """Advance the Coulomb plate exactly; fill outputs at k dt_out; return (n_peaks, pk_t, pk_u).
    ``cap``: capacity |u| (inf: none); ``stop`` 0: end the run there, 1: end-stop impact with
    restitution ``e_stop`` (see the module docstring)."""
    seg = np.empty(8)
    cf = np.empty(6)
    n_out = out_u.shape[0]
    t = 0.0
    u = u0
    v = v0
    n_pk = np.int64(0)
    umax = abs(u0)
    amax = 0.0
    k_out = 0
    steps = 0
    t_slide = 0.0
    om2 = om * om
    t_cap = np.nan
    u_cap = np.nan
    n_hits = 0
    stopped = False
    pin = 0.0              # +-1: resting on the end stop at u = pin cap
    # initial phase
    if v != 0.0:
        s = 1.0 if v > 0.0 else -1.0
    else:
        s = 0.0
    if abs(u0) > cap:      # released beyond the capacity
        t_cap = 0.0
        u_cap = u0
        n_hits = 1
        stopped = True
        t_end = 0.0
    while t < t_end and steps < 10_000_000:
        steps += 1
        t_piece_end = MK.segment(t, kind, M, samples, seg)
        tb = min(t_piece_end, t_end)
        if s == 0.0:
            # stuck: moves with the ground until |om^2 u + f| > mu g (on the end stop: only
            # away from it)
            up = mug - om2 * u
            dn = mug + om2 * u
            if pin > 0.0:
                dn = np.inf
            elif pin < 0.0:
                up = np.inf
            te, side = K._first_exceedance(t, tb, seg, up, dn)
            t_stop = min(te, tb)
            while k_out < n_out and k_out * dt_out < t_stop:
                tk = k_out * dt_out
                out_u[k_out] = u
                out_v[k_out] = 0.0
                out_a[k_out] = MK.seg_acc(tk, seg)
                k_out += 1
            amax = max(amax, _max_abs_f(t, t_stop, seg, t_piece_end))
            if te < tb or (te == tb and side != 0):
                t = te
                s = float(side)
                pin = 0.0
                continue
            if t_piece_end == np.inf and kind != MK.M_NONE and abs(om2 * u) <= mug:
                # the ground is at rest for good and the plate is stuck: done
                t = t_end
                break
            if t_piece_end == np.inf:
                t = t_end
                break
            t = tb
            continue
        # sliding with sign s
        _coulomb_coeffs(t, u, v, s, seg, om, mug, cf)
        # sample the velocity to find the first reversal in (t, tb]
        span = tb - t
        period = 2.0 * math.pi / om
        if seg[3] != 0.0:
            period = min(period, 2.0 * math.pi / seg[4])
        h = period / 16.0
        nsub = max(math.ceil(span / h), 1) if span < np.inf else 1
        h = span / nsub
        t_rev = np.inf
        lo = t
        v_lo = v
        a_lo = -om2 * u - s * mug - MK.seg_acc(t, seg)
        for i in range(1, nsub + 1):
            ti = t + i * h if i < nsub else tb
            _, vi, ai = _coulomb_state(ti, t, seg, cf, om)
            if s * vi <= 0.0:
                t_rev = _coulomb_bisect(lo, ti, t, seg, cf, om, s, 0.0, bool(True))
                break
            if s * v_lo > 0.0 and s * a_lo < 0.0 and s * ai > 0.0:
                # s u' has a minimum inside (lo, ti): if it reaches 0 there, the plate stops
                # inside the sub-interval although s u' > 0 at both ends (a phase starting
                # from rest, u' = 0 and u'' ~ 0 at lo, is not such a minimum)
                tm = _coulomb_min_v(lo, ti, t, seg, cf, om, s)
                _, vm, _ = _coulomb_state(tm, t, seg, cf, om)
                if s * vm <= 0.0:
                    t_rev = _coulomb_bisect(lo, tm, t, seg, cf, om, s, 0.0, bool(True))
                    break
            lo = ti
            v_lo = vi
            a_lo = ai
        t_stop = min(t_rev, tb)
        u_end, v_end, _ = _coulomb_state(t_stop, t, seg, cf, om)
        hit = False
        if s * u_end > cap:
            # u is monotonic on [t, t_stop]: bisect s u = cap to machine precision
            t_stop = _coulomb_bisect(t, t_stop, t, seg, cf, om, s, cap, bool(False))
            u_end, v_end, _ = _coulomb_state(t_stop, t, seg, cf, om)
            hit = True
        while k_out < n_out and k_out * dt_out < t_stop:
            tk = k_out * dt_out
            uk, vk, ak = _coulomb_state(tk, t, seg, cf, om)
            out_u[k_out] = uk
            out_v[k_out] = vk
            out_a[k_out] = ak + MK.seg_acc(tk, seg)
            k_out += 1
        # |a_abs| = |om^2 u + s mu g| is monotonic while sliding: its extremes are at the ends
        amax = max(amax, abs(om2 * u + s * mug), abs(om2 * u_end + s * mug))
        umax = max(umax, abs(u_end))
        t_slide += t_stop - t
        t = t_stop
        u = u_end
        if hit:
            if n_hits == 0:
                t_cap = t
                u_cap = u
            n_hits += 1
            if stop == 0:
                v = v_end
                stopped = True
                break
            u = s * cap
            v, rest = _stop_rebound(t, v_end, s, e_stop, cap, om2 * u - s * mug, kind, M, samples, seg)
            if rest:
                pin = s
                s = 0.0
            else:
                s = -s
            continue
        if t_rev <= tb and t_rev < np.inf:
            v = 0.0
            pk_t, pk_u, n_pk = _push_peak(pk_t, pk_u, n_pk, t, u)
            MK.segment(t, kind, M, samples, seg)
            d = -om2 * u - MK.seg_acc(t, seg)
            if abs(d) <= mug * (1.0 + 1e-12):
                s = 0.0
            else:
                s = 1.0 if d > 0.0 else -1.0
        else:
            v = v_end
    while stopped and k_out < n_out:     # the run ended at the capacity: nothing after it
        if k_out == 0 and t == 0.0:
            out_u[0] = u0
            out_v[0] = v0
            MK.segment(0.0, kind, M, samples, seg)
            out_a[0] = -(om2 * u0 + s * mug) if s != 0.0 else MK.seg_acc(0.0, seg)
        else:
            out_u[k_out] = np.nan
            out_v[k_out] = np.nan
            out_a[k_out] = np.nan
        k_out += 1
    while k_out < n_out:       # samples at t_end itself (or after the plate came to rest for good)
        tk = k_out * dt_out
        out_u[k_out] = u
        out_v[k_out] = 0.0 if s == 0.0 else v
        if s == 0.0:
            MK.segment(tk, kind, M, samples, seg)
            out_a[k_out] = MK.seg_acc(tk, seg)
        else:
            out_a[k_out] = -(om2 * u + s * mug)
        k_out += 1
    stats[I_UMAX] = umax
    stats[I_AMAX] = amax
    stats[I_NSTEPS] = steps
    stats[I_TFINAL] = t
    stats[I_NPEAKS] = n_pk
    stats[I_TSLIDE] = t_slide
    stats[I_TCAP] = t_cap
    stats[I_UCAP] = u_cap
    stats[I_NHITS] = n_hits
    return n_pk, pk_t, pk_u


# ---------------------------------------------------------------- Bouc-Wen
@njit(cache=True)
def z_map(z_r, du, s, u_y, n):
    """z after the plate moves by du (sign s) from z_r, exactly (beta = gamma = 1/2)."""
    x = abs(du) / u_y
    y0 = s * z_r
    if y0 < 0.0:
        if x <= -y0:
            return s * (y0 + x)
        x -= -y0
        y0 = 0.0
    if n == 1:
        y = 1.0 - (1.0 - y0) * math.exp(-x)
    else:
        if y0 >= 1.0:
            y = 1.0
        else:
            y = math.tanh(math.atanh(y0) + x)
    return s * y


@njit(cache=True)
def _bw_acc(t, u, seg, om2, cz, u_r, z_r, s, u_y, n):
    z = z_map(z_r, u - u_r, s, u_y, n)
    return -om2 * u - cz * z - MK.seg_acc(t, seg), z


# Dormand-Prince 5(4)
_C = np.array([0.0, 1 / 5, 3 / 10, 4 / 5, 8 / 9, 1.0, 1.0])
_A = np.array([
    [0, 0, 0, 0, 0, 0],
    [1 / 5, 0, 0, 0, 0, 0],
    [3 / 40, 9 / 40, 0, 0, 0, 0],
    [44 / 45, -56 / 15, 32 / 9, 0, 0, 0],
    [19372 / 6561, -25360 / 2187, 64448 / 6561, -212 / 729, 0, 0],
    [9017 / 3168, -355 / 33, 46732 / 5247, 49 / 176, -5103 / 18656, 0],
    [35 / 384, 0, 500 / 1113, 125 / 192, -2187 / 6784, 11 / 84],
])
_B5 = np.array([35 / 384, 0, 500 / 1113, 125 / 192, -2187 / 6784, 11 / 84, 0])
_B4 = np.array([5179 / 57600, 0, 7571 / 16695, 393 / 640, -92097 / 339200, 187 / 2100, 1 / 40])


@njit(cache=True)
def _dp_step(t, u, v, h, seg, om2, cz, u_r, z_r, s, u_y, n, ku, kv):
    for i in range(7):
        ui = u
        vi = v
        for j in range(i):
            ui += h * _A[i, j] * ku[j]
            vi += h * _A[i, j] * kv[j]
        ku[i] = vi
        kv[i], _ = _bw_acc(t + _C[i] * h, ui, seg, om2, cz, u_r, z_r, s, u_y, n)
    u5 = u
    v5 = v
    eu = 0.0
    ev = 0.0
    for i in range(7):
        u5 += h * _B5[i] * ku[i]
        v5 += h * _B5[i] * kv[i]
        eu += h * (_B5[i] - _B4[i]) * ku[i]
        ev += h * (_B5[i] - _B4[i]) * kv[i]
    return u5, v5, eu, ev


@njit(cache=True)
def _dp_bisect(lo, hi, iters, t, u, v, seg, om2, cz, u_r, z_r, s, u_y, n, ku, kv, level, on_v):
    """The same bisection as :func:`_coulomb_bisect` on the step length of one
    Dormand-Prince step from (t, u, v), at most ``iters`` halvings. Returns the upper end."""
    for _ in range(iters):
        mid = 0.5 * (lo + hi)
        if mid <= lo or mid >= hi:
            break
        um, vm, _, _ = _dp_step(t, u, v, mid, seg, om2, cz, u_r, z_r, s, u_y, n, ku, kv)
        x = vm if on_v else um
        if (s * x > level) == on_v:
            lo = mid
        else:
            hi = mid
    return hi


@njit(cache=True)
def boucwen(om, mug, q, n, kind, M, samples, u0, v0, t_end, dt_out, rtol, atol_u, cap, stop, e_stop,
            out_u, out_v, out_a, out_z, pk_t, pk_u, stats):
    """Advance the Bouc-Wen plate (adaptive steps); capacity ``cap``, ``stop`` and ``e_stop``
    as for :func:`coulomb`."""
    seg = np.empty(8)
    ku = np.empty(7)
    kv = np.empty(7)
    om2 = om * om
    cz = (1.0 - 1.0 / q) * mug
    u_y = mug / (q * om2)           # mu W / (q k) = mu g / (q omega^2)
    atol_v = atol_u * om
    n_out = out_u.shape[0]
    t = 0.0
    u = u0
    v = v0
    u_r = u0
    z_r = 0.0
    s = 1.0 if v0 > 0.0 else (-1.0 if v0 < 0.0 else 0.0)
    n_pk = np.int64(0)
    umax = abs(u0)
    amax = 0.0
    k_out = 0
    steps = 0
    rej = 0
    h = min(2.0 * math.pi / om / 50.0, max(dt_out, 1e-6))
    t_cap = np.nan
    u_cap = np.nan
    n_hits = 0
    stopped = False
    pin = 0.0              # +-1: resting on the end stop at u = pin cap
    if abs(u0) > cap:      # released beyond the capacity
        t_cap = 0.0
        u_cap = u0
        n_hits = 1
        stopped = True
    else:
        # a_abs(0) = -(omega^2 u0 + cz z0) with z0 = 0: the steps below see a_abs at their ends
        # only (exact between reversals, where a_abs is monotonic), never at the start
        amax = abs(om2 * u0)
    while not stopped:
        t_piece_end = MK.segment(t, kind, M, samples, seg)
        if pin != 0.0:
            # on the end stop (u' = 0, z fixed): until the force pulls the plate away from it
            c = om2 * u + cz * z_r
            t_next = min(t_piece_end, t_end)
            te, side = K._first_exceedance(t, t_next, seg, -c if pin > 0.0 else np.inf,
                                           c if pin < 0.0 else np.inf)
            t_stop = min(te, t_next)
            while k_out < n_out and k_out * dt_out < t_stop:
                out_u[k_out] = u
                out_v[k_out] = 0.0
                out_a[k_out] = MK.seg_acc(k_out * dt_out, seg)
                out_z[k_out] = z_r
                k_out += 1
            amax = max(amax, _max_abs_f(t, t_stop, seg, t_piece_end))
            if te <= t_next and side != 0:
                t = te
                s = float(side)
                u_r = u
                pin = 0.0
                continue
            t = t_next
            if t >= t_end or t_piece_end == np.inf:
                break
            continue
        if s == 0.0:
            a0, _ = _bw_acc(t, u, seg, om2, cz, u_r, z_r, 1.0, u_y, n)
            if a0 == 0.0:
                # at rest with no net force (u, z fixed while v = 0): the force's slope
                # -f'(t) decides which way the plate starts
                a0 = -(seg[1] + seg[3] * seg[4] * math.cos(seg[4] * (t - seg[5]) + seg[6]))
            if a0 != 0.0:
                s = 1.0 if a0 > 0.0 else -1.0
                u_r = u
            else:
                t_next = min(t_piece_end, t_end)
                while k_out < n_out and k_out * dt_out <= t_next:
                    out_u[k_out] = u
                    out_v[k_out] = 0.0
                    out_a[k_out] = 0.0
                    out_z[k_out] = z_r
                    k_out += 1
                if t_next >= t_end or t_piece_end == np.inf:
                    break
                t = t_next
                continue
        # outputs at t
        while k_out < n_out and k_out * dt_out <= t + 1e-12 * max(1.0, t):
            a_rel, z = _bw_acc(t, u, seg, om2, cz, u_r, z_r, s, u_y, n)
            out_u[k_out] = u
            out_v[k_out] = v
            out_a[k_out] = a_rel + MK.seg_acc(t, seg)
            out_z[k_out] = z
            k_out += 1
        if t >= t_end or steps > 50_000_000:
            break
        t_next_out = k_out * dt_out if k_out < n_out else np.inf
        t_lim = min(t_piece_end, t_end, t_next_out)
        hh = min(h, t_lim - t)
        if hh <= 0.0:
            t = t_lim
            continue
        u5, v5, eu, ev = _dp_step(t, u, v, hh, seg, om2, cz, u_r, z_r, s, u_y, n, ku, kv)
        steps += 1
        err = max(abs(eu) / (atol_u + rtol * max(abs(u), abs(u5))), abs(ev) / (atol_v + rtol * max(abs(v), abs(v5))))
        if not (err <= 1.0):
            rej += 1
            fac = 0.1 if math.isnan(err) else 0.9 * err ** -0.2
            h = hh * max(0.1, min(0.9, fac))
            continue
        fac = 0.9 * err ** -0.2 if err > 0.0 else 5.0
        h_new = hh * max(0.2, min(5.0, fac))
        x_far = 0.0                 # capacity passed inside the step, before any reversal: in (0, x_far]
        hi_rev = hh
        if s * v5 < 0.0:
            # the largest s u of the step is at its reversal
            hi = _dp_bisect(0.0, hh, np.int64(100), t, u, v, seg, om2, cz, u_r, z_r, s, u_y, n, ku, kv, 0.0,
                            bool(True))
            hi_rev = hi
            um, _, _, _ = _dp_step(t, u, v, hi, seg, om2, cz, u_r, z_r, s, u_y, n, ku, kv)
            if s * um > cap:
                x_far = hi
        elif s * u5 > cap:
            x_far = hh
        if x_far > 0.0:
            hi = _dp_bisect(0.0, x_far, np.int64(200), t, u, v, seg, om2, cz, u_r, z_r, s, u_y, n, ku, kv, cap,
                            bool(False))
            um, vm, _, _ = _dp_step(t, u, v, hi, seg, om2, cz, u_r, z_r, s, u_y, n, ku, kv)
            t = t + hi
            z_e = z_map(z_r, um - u_r, s, u_y, n)
            umax = max(umax, abs(um))
            a_e, _ = _bw_acc(t, um, seg, om2, cz, u_r, z_r, s, u_y, n)
            amax = max(amax, abs(a_e + MK.seg_acc(t, seg)))
            if n_hits == 0:
                t_cap = t
                u_cap = um
            n_hits += 1
            if stop == 0:
                u = um
                v = vm
                stopped = True
                break
            u = s * cap
            u_r = u
            z_r = z_e
            v, rest = _stop_rebound(t, vm, s, e_stop, cap, om2 * u + cz * z_e, kind, M, samples, seg)
            if rest:
                pin = s
                s = 0.0
            else:
                s = -s
            h = max(h_new, 1e-12)
            continue
        if s * v5 < 0.0:
            # reversal inside the step (located above by bisection on the sign of v)
            hi = hi_rev
            um, vm, _, _ = _dp_step(t, u, v, hi, seg, om2, cz, u_r, z_r, s, u_y, n, ku, kv)
            t = t + hi
            z_e = z_map(z_r, um - u_r, s, u_y, n)
            u = um
            v = 0.0
            pk_t, pk_u, n_pk = _push_peak(pk_t, pk_u, n_pk, t, u)
            umax = max(umax, abs(u))
            u_r = u
            z_r = z_e
            MK.segment(t, kind, M, samples, seg)
            a_e, _ = _bw_acc(t, u, seg, om2, cz, u_r, z_r, -s, u_y, n)
            s = 1.0 if a_e > 0.0 else (-1.0 if a_e < 0.0 else 0.0)
            amax = max(amax, abs(a_e + MK.seg_acc(t, seg)))
            h = max(h_new, 1e-12)
            continue
        t = t + hh
        u = u5
        v = v5
        umax = max(umax, abs(u))
        a_rel, _ = _bw_acc(t, u, seg, om2, cz, u_r, z_r, s, u_y, n)
        amax = max(amax, abs(a_rel + MK.seg_acc(t, seg)))
        h = h_new
    if stopped:      # the run ended at the capacity: nothing after it
        if k_out == 0:
            MK.segment(0.0, kind, M, samples, seg)
            a_rel, z = _bw_acc(0.0, u0, seg, om2, cz, u0, 0.0, s if s != 0.0 else 1.0, u_y, n)
            out_u[0] = u0
            out_v[0] = v0
            out_a[0] = a_rel + MK.seg_acc(0.0, seg)
            out_z[0] = z
            k_out = 1
        while k_out < n_out:
            out_u[k_out] = np.nan
            out_v[k_out] = np.nan
            out_a[k_out] = np.nan
            out_z[k_out] = np.nan
            k_out += 1
    stats[I_UMAX] = umax
    stats[I_AMAX] = amax
    stats[I_NSTEPS] = steps
    stats[I_NREJ] = rej
    stats[I_TFINAL] = t
    stats[I_NPEAKS] = n_pk
    stats[I_TCAP] = t_cap
    stats[I_UCAP] = u_cap
    stats[I_NHITS] = n_hits
    return n_pk, pk_t, pk_u


SIGNATURES = {
    "coulomb": (K.F8, K.F8, K.I8, K.VEC, MK.SAMPLES, K.F8, K.F8, K.F8, K.F8, K.F8, K.I8, K.F8,
                K.VEC, K.VEC, K.VEC, K.VEC, K.VEC, K.VEC),
    "boucwen": (K.F8, K.F8, K.F8, K.I8, K.I8, K.VEC, MK.SAMPLES, K.F8, K.F8, K.F8, K.F8, K.F8, K.F8, K.F8, K.I8,
                K.F8, K.VEC, K.VEC, K.VEC, K.VEC, K.VEC, K.VEC, K.VEC),
}
"""The one argument-type signature of each entry point (types of rocking.kernel; see
statue2model.compute.compile)."""
