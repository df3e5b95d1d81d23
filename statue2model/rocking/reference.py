"""The same rocking model written plainly with scipy.integrate.solve_ivp.

This is the baseline of the work-precision benchmark and an independent
cross-check of :mod:`statue2model.rocking.kernel` in the tests: it shares the
model (:class:`RockingModel`) and the motion objects but none of the solver code.
One ``solve_ivp`` call per phase of motion; impacts, region changes and
overturning are terminal events, peaks are non-terminal events; the stick phase
is scanned on a grid and refined with ``brentq``.

Example
-------
>>> from statue2model.geometry.rocking_params import RockingParams
>>> from statue2model.hazard import motions
>>> from statue2model.rocking import RockingModel
>>> model = RockingModel.housner(RockingParams.rectangular_block(0.0384, 0.2, 1.286), e_L=0.9, e_R=0.9)
>>> out = simulate_scipy(model, motions.free(), theta0=0.1, t_end=1.0)
>>> len(out["impact_times"]) >= 2
True
"""
from __future__ import annotations

import math

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

from .model import RockingModel
from ..hazard.motions import GroundMotion


def _accel_fn(motion: GroundMotion):
    """Vector-free u_g''(t) with plain numpy (no kernel code)."""
    if motion.kind == "none":
        return lambda t: 0.0, []
    t0, t1 = motion.start, motion.start + motion.duration
    if motion.kind == "harmonic":
        w = 2 * math.pi * motion.freq
        return (lambda t: motion.amp * math.sin(w * (t - t0) + motion.phase) if t0 <= t < t1 else 0.0), [t0, t1]
    if motion.kind == "rect":
        return (lambda t: motion.amp if t0 <= t < t1 else 0.0), [t0, t1]
    tt = t0 + motion.dt * np.arange(len(motion.samples))
    s = motion.samples
    return (lambda t: float(np.interp(t, tt, s, left=0.0, right=0.0)) if t < t1 else 0.0), [t0, t1]


def simulate_scipy(model: RockingModel, motion: GroundMotion, theta0: float = 0.0, omega0: float = 0.0,
                   t_end: float | None = None, method: str = "DOP853", rtol: float = 1e-8,
                   atol: float | None = None, dt_out: float | None = None, rest_tol: float = 1e-9) -> dict:
    """Returns a dict: theta_max_L, theta_max_R, impact_times, peak_values, overturned,
    impacts_before_overturn, uplift_time, t_rest, nfev, and (t, theta) samples if dt_out."""
    p = model.params
    g = p.g
    lin = model.linearised
    P2 = {1: p.p_R**2, -1: p.p_L**2}
    D = {1: p.delta_R, -1: p.delta_L}
    a_l, a_r = model.effective_alpha
    AL = {1: a_r, -1: a_l}
    TH = {1: model.theta_R if a_r < 1 else 0.0, -1: model.theta_L if a_l < 1 else 0.0}
    lim_up, lim_dn = model.uplift_limits
    acc, breaks = _accel_fn(motion)
    if t_end is None:
        t_end = motion.end + 20.0
    if atol is None:
        atol = rtol * min(p.delta_L, p.delta_R)
    out_t = np.arange(int(math.floor(t_end / dt_out + 1e-9)) + 1) * dt_out if dt_out else np.empty(0)
    out_th = np.zeros(out_t.size)

    def rhs_factory(s, reg):
        P, d, a0, tr = P2[s], D[s], AL[s], TH[s]

        def rhs(t, y):
            q = s * y[0]
            al = a0 + (1 - a0) * q / tr if reg == 0 else 1.0
            u = acc(t) / g
            x = d - q
            if lin:
                qdd = -P * (al * x + s * u)
            else:
                qdd = -P * (al * math.sin(x) + s * u * math.cos(x))
            return [y[1], s * qdd]
        return rhs

    def bounds(s, reg):
        tr, d = TH[s], D[s]
        if tr > 0:
            return (0.0, min(tr, d)) if reg == 0 else (min(tr, d), d)
        return 0.0, d

    res = {"theta_max_L": 0.0, "theta_max_R": 0.0, "impact_times": [], "peak_values": [], "overturned": False,
           "impacts_before_overturn": None, "uplift_time": None, "t_rest": None, "nfev": 0}
    t, th, om = 0.0, float(theta0), float(omega0)
    moving = th != 0 or om != 0
    s = -1 if (th < 0 or (th == 0 and om < 0)) else 1
    reg = 1
    if moving:
        res["uplift_time"] = 0.0
        lo, hi = bounds(s, 0)
        reg = 0 if TH[s] > 0 and abs(th) < hi else 1
        if om == 0:
            res["peak_values"].append(abs(th))
    if th > 0:
        res["theta_max_R"] = th
    elif th < 0:
        res["theta_max_L"] = -th
    io = 0
    while t < t_end:
        if not moving:
            # scan for the next uplift
            grid_dt = min(motion.dt if motion.kind == "record" else 1.0 / max(motion.freq, 1e-9) / 400,
                          motion.duration / 50 if motion.duration > 0 else 1.0)
            t_up = None
            ta = t
            over = lambda x: max(acc(x) - lim_up, -lim_dn - acc(x))  # noqa: E731
            if over(ta) > 0:
                t_up = ta
            else:
                stop = min(t_end, max(motion.end, t))
                while ta < stop:
                    tb = min(ta + grid_dt, stop)
                    if over(tb) > 0:
                        t_up = brentq(over, ta, tb, xtol=1e-15)
                        break
                    ta = tb
            while io < out_t.size and out_t[io] <= (t_up if t_up is not None else t_end):
                io += 1
            if t_up is None:
                break
            t = t_up
            u = acc(t + 1e-12)
            s = -1 if u > lim_up else 1
            th, om = 0.0, 0.0
            reg = 0 if TH[s] > 0 else 1
            moving = True
            if res["uplift_time"] is None:
                res["uplift_time"] = t
            res["t_rest"] = None
            continue
        lo, hi = bounds(s, reg)

        def ev_lo(t_, y, s=s, lo=lo):
            return s * y[0] - lo
        ev_lo.terminal, ev_lo.direction = True, -1

        def ev_hi(t_, y, s=s, hi=hi):
            return s * y[0] - hi
        ev_hi.terminal, ev_hi.direction = True, 1

        def ev_pk(t_, y, s=s):
            return s * y[1]
        ev_pk.terminal, ev_pk.direction = False, -1
        t_stop = t_end
        for b in breaks:
            if b > t + 1e-12:
                t_stop = min(t_stop, b)
                break
        sol = solve_ivp(rhs_factory(s, reg), (t, t_stop), [th, om], method=method, rtol=rtol,
                        atol=[atol, atol * math.sqrt(max(P2.values()))], events=[ev_lo, ev_hi, ev_pk],
                        dense_output=bool(out_t.size))
        res["nfev"] += sol.nfev
        t_new = sol.t[-1]
        key = "theta_max_R" if s > 0 else "theta_max_L"
        for tp, yp in zip(sol.t_events[2], sol.y_events[2]):
            q = s * yp[0]
            res["peak_values"].append(q)
            res[key] = max(res[key], q)
        res[key] = max(res[key], float(np.max(s * sol.y[0])))
        while io < out_t.size and out_t[io] <= t_new:
            out_th[io] = sol.sol(out_t[io])[0]
            io += 1
        th, om = sol.y[0, -1], sol.y[1, -1]
        t = t_new
        if sol.status == 1 and sol.t_events[1].size:
            if reg == 0 and hi < D[s]:
                reg, th = 1, s * hi
                continue
            res["overturned"] = True
            res["impacts_before_overturn"] = len(res["impact_times"])
            res[key] = D[s]
            break
        if sol.status == 1 and sol.t_events[0].size:
            if lo > 0:
                reg, th = 0, s * lo
                continue
            w = abs(om)
            e = float((model.e_L if s > 0 else model.e_R)(w))
            res["impact_times"].append(t)
            s = -s
            reg = 0 if TH[s] > 0 else 1
            th, om = 0.0, e * om
            qdd0 = s * rhs_factory(s, reg)(t, [0.0, 0.0])[1]
            c = -qdd0
            if c > 0 and (om == 0 or (e < 1 and om * om / (2 * c) < rest_tol * D[s])):
                t += (2 * abs(om) / c) / (1 - e) if om != 0 else 0.0
                moving = False
                th = om = 0.0
                res["t_rest"] = t
            continue
    res["impact_times"] = np.asarray(res["impact_times"])
    res["peak_values"] = np.asarray(res["peak_values"])
    if dt_out:
        res["t"], res["theta"] = out_t, out_th
    return res
