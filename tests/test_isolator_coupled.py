"""The coupled plate + statue model (isolator/coupled.py): limits against the plate
alone and the fixed-base rocking engine, conservation laws, an independent
solve_ivp reference, and bad input."""
from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from statue2model.hazard import motions
from statue2model.rocking.engine import simulate as rock
from statue2model.rocking.kernel import ground_acc
from statue2model.rocking.model import RockingModel
from statue2model.errors import InputError
from statue2model.geometry.rocking_params import RockingParams
from statue2model.isolator.coupled import simulate_coupled
from statue2model.isolator.device import Isolator
from statue2model.isolator.time_history import simulate

G = 9.81
BLOCK = RockingParams.rectangular_block(b=0.05, h=0.25, m=10.0)


def _rel(a, b):
    return float(np.max(np.abs(a - b)) / np.max(np.abs(b)))


# ------------------------------------------------------------------ 1. no uplift
@pytest.mark.parametrize("model_name", ["coulomb", "boucwen"])
def test_no_uplift_is_the_plate_alone(model_name):
    iso = Isolator(R=0.30, r=0.0183, M=15.0, mu=0.01, model=model_name)
    motion = motions.cosine_pulse(0.3 * G, 1.0)
    strong = RockingModel.housner(RockingParams.rectangular_block(b=0.2, h=0.25, m=10.0))
    plate = simulate(iso, motion, t_end=6.0)
    res = simulate_coupled(iso, strong, motion, t_end=6.0)
    assert not res.uplift and res.outcome == "no motion" and res.n_impacts == 0
    assert not res.theta.any()
    if model_name == "coulomb":
        assert res.stats["coupled_integration"] is False          # screened: nothing to integrate
        assert np.array_equal(res.u, plate.u) and np.array_equal(res.acc_abs, plate.acc_abs)
    else:                                                         # Bouc-Wen: always integrated
        assert res.stats["coupled_integration"] is True
        assert _rel(res.u, plate.u) < 2e-8
    # forced through the 2-DOF integrator: the statue never lifts, the plate obeys eq. 20
    forced = simulate_coupled(iso, strong, motion, t_end=6.0, screen=False)
    assert forced.stats["coupled_integration"] and not forced.uplift
    assert _rel(forced.u, plate.u) < 2e-8
    assert _rel(forced.acc_abs, plate.acc_abs) < 2e-8
    assert forced.u_max == pytest.approx(plate.u_max, rel=1e-8)
    assert forced.acc_abs_max == pytest.approx(plate.acc_abs_max, rel=1e-8)
    assert np.allclose(forced.peaks_u_t, plate.peaks_t, rtol=0, atol=1e-8)


def test_before_the_first_uplift_the_plate_is_the_plate_alone():
    iso = Isolator(R=0.30, r=0.0183, M=15.0, mu=0.01)
    model = RockingModel.imperfect(BLOCK, alpha_L=0.5, alpha_R=0.5, e_L=0.9, e_R=0.9)
    motion = motions.cosine_pulse(0.25 * G, 1.5)
    plate = simulate(iso, motion, t_end=4.0, dt_out=0.001)
    res = simulate_coupled(iso, model, motion, t_end=4.0, dt_out=0.001)
    assert res.uplift and res.stats["coupled_integration"]
    k = int(res.t_uplift / 0.001)
    assert 10 < k
    assert _rel(res.u[:k], plate.u[:k]) < 1e-8
    # the uplift is where the plate's absolute acceleration first crosses a limit
    up, dn = model.uplift_limits
    a = plate.acc_abs
    first = np.flatnonzero((a > up) | (a < -dn))[0]
    assert plate.t[first - 1] <= res.t_uplift <= plate.t[first]
    # after the uplift the statue pushes the plate: the histories part
    assert _rel(res.u, plate.u) > 1e-4


# ------------------------------------------------------------------ 2. plate locked
def test_locked_plate_is_the_fixed_base_rocking_engine():
    """mu = 0.99: the plate never slides (e = 1: the impacts do not kick it either)."""
    iso = Isolator(R=0.30, r=0.0183, M=20.0, mu=0.99)
    model = RockingModel.imperfect(BLOCK, alpha_L=0.7, alpha_R=0.8, e_L=1.0, e_R=1.0)
    motion = motions.sine_pulse(0.2 * G, 2.0)
    dt = 0.002
    res = simulate_coupled(iso, model, motion, t_end=3.0, dt_out=dt)
    ref = rock(model, motion, t_end=3.0, dt_out=dt, rtol=1e-11)
    assert res.u_max == 0.0 and not np.any(res.v)
    assert res.outcome == ref.outcome == "rocking"
    assert res.n_impacts == ref.n_impacts >= 3
    assert res.t_uplift == pytest.approx(ref.uplift_time, abs=1e-9)
    assert np.max(np.abs(res.impacts[:, 0] - ref.impact_times)) < 1e-6
    assert res.theta_max_L == pytest.approx(ref.theta_max_L, rel=1e-6)
    assert res.theta_max_R == pytest.approx(ref.theta_max_R, rel=1e-6)
    assert np.max(np.abs(res.theta - ref.history["theta"])) < 1e-6 * BLOCK.delta_L
    assert np.array_equal(res.phase, ref.history["phase"])


def test_locked_plate_overturns_like_the_fixed_base():
    iso = Isolator(R=0.30, r=0.0183, M=20.0, mu=0.99)
    model = RockingModel.housner(BLOCK, e_L=1.0, e_R=1.0)
    motion = motions.sine_pulse(0.3 * G, 2.0)
    res = simulate_coupled(iso, model, motion, t_end=3.0)
    ref = rock(model, motion, t_end=3.0, rtol=1e-11)
    assert res.overturned and res.outcome == ref.outcome
    assert res.overturn_time == pytest.approx(ref.overturn_time, abs=1e-7)
    assert res.overturn_side == ref.overturn_side
    k = int(res.overturn_time / 0.005)
    assert np.isnan(res.theta[k + 1:]).all() and (res.phase[k + 1:] == 3).all()
    assert res.theta_max_over_delta == 1.0


# ------------------------------------------------------------------ 3. light statue
def test_light_statue_is_driven_by_the_plate():
    """m / M = 1e-6: the statue does not move the plate; it rocks under a_abs of the plate.
    (mu = 0 keeps a_abs = -omega^2 u smooth, so that its sampled record is exact to O(dt^2).)"""
    iso = Isolator(R=0.30, r=0.0183, M=10.0e6, mu=0.0)
    model = RockingModel.imperfect(BLOCK, alpha_L=0.5, alpha_R=0.5, e_L=0.9, e_R=0.9)
    motion = motions.sine_pulse(0.08 * G, 1.0)
    dt = 2e-4
    plate = simulate(iso, motion, t_end=3.0, dt_out=dt)
    res = simulate_coupled(iso, model, motion, t_end=3.0, dt_out=dt)
    ref = rock(model, motions.record(plate.acc_abs, dt), t_end=3.0, dt_out=dt, rtol=1e-11)
    assert res.uplift and res.outcome == ref.outcome == "rocking" and res.n_impacts == ref.n_impacts >= 10
    assert res.t_uplift == pytest.approx(ref.uplift_time, abs=1e-7)
    assert np.max(np.abs(res.impacts[:, 0] - ref.impact_times)) < 1e-5
    assert _rel(res.u, plate.u) < 1e-5
    n = len(ref.history["t"])                     # the engine stops once the body is at rest for good
    assert np.max(np.abs(res.theta[:n] - ref.history["theta"])) < 1e-5 * BLOCK.delta_L
    assert not np.any(res.theta[n:])
    assert res.theta_max_over_delta == pytest.approx(ref.theta_max_over_delta, abs=1e-5)


# ------------------------------------------------------------------ 4. conservation
def _energy_momentum(res, iso, p):
    """Total energy (J) and horizontal momentum (kg m/s) of plate + statue, ground at rest."""
    m, M = p.m, iso.M
    th, w, v, u = res.theta, res.theta_dot, res.v, res.u
    R = np.where(th >= 0, p.d_R, p.d_L)
    dl = np.where(th >= 0, p.delta_R, p.delta_L)
    I = np.where(th >= 0, p.I_R, p.I_L)
    xdot = R * np.cos(dl - np.abs(th)) * w
    yG = R * np.cos(dl - np.abs(th))
    E = 0.5 * M * v**2 + m * v * xdot + 0.5 * I * w**2 + 0.5 * iso.k * u**2 + m * p.g * yG
    P = M * v + m * xdot
    return E, P


@pytest.mark.parametrize("theta0, u0", [(0.15, 0.0), (0.0, 0.03), (-0.1, 0.02)])
def test_energy_is_conserved_without_friction_and_damping(theta0, u0):
    iso = Isolator(R=0.30, r=0.0183, M=14.0, mu=0.0)
    p = BLOCK
    model = RockingModel.housner(p, e_L=1.0, e_R=1.0)
    res = simulate_coupled(iso, model, motions.free(), theta0=theta0, u0=u0, t_end=4.0, dt_out=0.001, screen=False)
    E, _ = _energy_momentum(res, iso, p)
    E_rest = p.m * p.g * p.h
    assert res.uplift == (theta0 != 0.0)
    assert np.max(np.abs(E - E[0])) < 1e-7 * (E[0] - E_rest)
    if theta0:
        assert res.n_impacts >= 4
        assert res.u_max > 1e-3              # the rocking statue moves the plate


def test_momentum_through_an_impact():
    """e < 1: u' jumps by -(m/M) h (e - 1) theta'- at every impact; between samples the
    horizontal momentum changes only by the impulse of the spring force -k u."""
    iso = Isolator(R=0.30, r=0.0183, M=14.0, mu=0.0)
    p = BLOCK
    e = 0.8
    model = RockingModel.housner(p, e_L=e, e_R=e)
    dt = 2e-4
    res = simulate_coupled(iso, model, motions.free(), theta0=0.15, t_end=1.5, dt_out=dt)
    imp = res.impacts
    assert len(imp) >= 3
    ok = imp[:, 3] != 0.0                    # the last one ends the Zeno series: a plastic impact
    assert ok[:-1].all() and res.stats["n_zeno"] == 1
    assert np.allclose(imp[ok, 3], e * imp[ok, 2], rtol=1e-15, atol=0)
    assert np.allclose(imp[ok, 5] - imp[ok, 4], -(p.m / iso.M) * p.h * (e - 1.0) * imp[ok, 2], rtol=1e-12, atol=1e-15)
    assert np.allclose(imp[~ok, 5] - imp[~ok, 4], (p.m / iso.M) * p.h * imp[~ok, 2], rtol=1e-12, atol=1e-15)
    _, P = _energy_momentum(res, iso, p)
    # Simpson on the (smooth) displacement: P(t) - P(0) = -k int_0^t u
    i = int(imp[1, 0] / dt) + 10                       # past two impacts, on an even sample
    i += i % 2
    u = res.u[: i + 1]
    integral = dt / 3 * (u[0] + u[-1] + 4 * u[1:-1:2].sum() + 2 * u[2:-1:2].sum())
    assert P[i] - P[0] == pytest.approx(-iso.k * integral, rel=1e-6)
    # the momentum jump itself is visible in the samples around the first impact
    j = int(imp[0, 0] / dt)
    jump = (P[j + 1] - P[j]) + iso.k * 0.5 * (u[j] + u[j + 1]) * dt
    assert abs(jump) < 1e-6 * abs(P).max()


# ------------------------------------------------------------------ 5. independent reference
def reference(iso, model, motion, t_end, rtol=1e-11):
    """The coupled system with scipy solve_ivp (DOP853, terminal events), written from the
    equations, phase by phase. Bouc-Wen z is integrated as an ODE state. Returns
    (theta_max_L, theta_max_R, u_max, impact times, overturning time or None)."""
    p = model.params
    m, M, g = p.m, iso.M, p.g
    mr = m / M
    om2, mug = iso.omega**2, iso.mu * iso.g
    bw = iso.model == "boucwen"
    q = iso.q
    uy = iso.u_y
    aL, aR = model.effective_alpha
    TL, TR = model.theta_L, model.theta_R
    up, dn = model.uplift_limits
    t_break = [motion.start, motion.end] if motion.kind != "none" else []
    kind, Mv, samples = motion.kernel_args()

    cap = [np.inf]            # each phase sees the ground's left limit at its end (no jump inside)

    def acc(t):
        return ground_acc(min(t, cap[0]), kind, Mv, samples)

    def statue(th, side, reg):
        if side > 0:
            x = p.delta_R - th
            al = aR + (1 - aR) * th / TR if reg == 0 else 1.0
            return -p.p_R**2 * al * math.sin(x), -p.p_R**2 * math.cos(x) / g, p.d_R * math.cos(x), p.d_R * math.sin(x)
        x = p.delta_L + th
        al = aL - (1 - aL) * th / TL if reg == 0 else 1.0
        return p.p_L**2 * al * math.sin(x), -p.p_L**2 * math.cos(x) / g, p.d_L * math.cos(x), -p.d_L * math.sin(x)

    def force(y, ps):
        if bw:
            return om2 * y[0] + (1 - 1 / q) * mug * y[4]
        return om2 * y[0] + ps * mug

    def accs(t, y, mode):
        ps, rocking, side, reg = mode
        f = float(acc(t))
        if not rocking:
            if ps == 0 and not bw:
                return 0.0, 0.0, f
            a = -force(y, ps)
            return a - f, 0.0, a
        A0, A1, c, d = statue(y[2], side, reg)
        if ps == 0 and not bw:
            return 0.0, A0 + A1 * f, f
        a = (-force(y, ps) - mr * (c * A0 + d * y[3] ** 2)) / (1 + mr * c * A1)
        return a - f, A0 + A1 * a, a

    def demand(t, y, mode):
        _, rocking, side, reg = mode
        f = float(acc(t))
        xdd = 0.0
        if rocking:
            A0, A1, c, d = statue(y[2], side, reg)
            xdd = c * (A0 + A1 * f) + d * y[3] ** 2
        return -(om2 * y[0] + f + mr * xdd)

    def bounds(side, reg):
        T = TR if side > 0 else TL
        D = p.delta_R if side > 0 else p.delta_L
        if T > 0 and aR < 1 and aL < 1:
            return (0.0, T) if reg == 0 else (T, D)
        return 0.0, D

    t = 0.0
    y = np.zeros(5)
    mode = [0, False, 1, 1]
    d0 = demand(0.0, y, mode)
    mode[0] = 0 if abs(d0) <= mug else int(np.sign(d0))   # Bouc-Wen: 0 = at rest, no force
    qmax = {1: 0.0, -1: 0.0}
    umax = 0.0
    impacts = []
    t_over = None
    while t < t_end - 1e-12:
        t_stop = min([b for b in t_break if b > t + 1e-12] + [t_end])
        cap[0] = np.nextafter(t_stop, -np.inf)
        if bw and mode[0] == 0 and y[1] == 0.0:
            mode[0] = int(np.sign(accs(t, y, (1,) + tuple(mode[1:]))[0]))
        ps, rocking, side, reg = mode
        mode_t = tuple(mode)

        def rhs(tt, yy, mode_t=mode_t):
            udd, thdd, _ = accs(tt, yy, mode_t)
            dz = 0.0
            if bw:
                dz = (1 - abs(yy[4]) * (0.5 + 0.5 * np.sign(yy[1] * yy[4]))) * yy[1] / uy
            return [yy[1], udd, yy[3], thdd, dz]

        evs = []
        # (an event function that is 0 at the start and moves in its direction would fire at once)
        if ps != 0:
            evs.append(("rev", lambda tt, yy: yy[1], -ps))
        if bw and ps * y[4] < 0.0:
            evs.append(("z0", lambda tt, yy: yy[4], ps))
        if ps == 0 and not bw:
            evs.append(("unstick+", lambda tt, yy, m_=mode_t: demand(tt, yy, m_) - mug, 1))
            evs.append(("unstick-", lambda tt, yy, m_=mode_t: -demand(tt, yy, m_) - mug, 1))
        if not rocking:
            evs.append(("upL", lambda tt, yy, m_=mode_t: accs(tt, yy, m_)[2] - up, 1))
            evs.append(("upR", lambda tt, yy, m_=mode_t: -accs(tt, yy, m_)[2] - dn, 1))
        else:
            lo, hi = bounds(side, reg)
            evs.append(("lo", lambda tt, yy, s_=side, lo=lo: s_ * yy[2] - lo, -1))
            evs.append(("hi", lambda tt, yy, s_=side, hi=hi: s_ * yy[2] - hi, 1))
            evs.append(("peak", lambda tt, yy, s_=side: s_ * yy[3], -1))
        funcs = []
        for name, fn, direction in evs:
            fn.terminal = name != "peak"
            fn.direction = direction
            funcs.append(fn)
        due = [e[0] for e in evs if e[0] != "peak" and e[2] * e[1](t, y) > 0]   # already past: apply now
        if due:
            name = due[0]
        else:
            sol = solve_ivp(rhs, (t, t_stop), y, method="DOP853", rtol=rtol, atol=1e-14, events=funcs)
            umax = max(umax, float(np.max(np.abs(sol.y[0]))))
            if rocking:
                qmax[side] = max(qmax[side], float(np.max(side * sol.y[2])))
                k = next(i for i, e in enumerate(evs) if e[0] == "peak")
                for yy in sol.y_events[k]:
                    qmax[side] = max(qmax[side], side * yy[2])
            t = sol.t[-1]
            y = sol.y[:, -1].copy()
            if sol.status != 1:
                continue
            fired = [(sol.t_events[i][-1], evs[i][0], i) for i in range(len(evs))
                     if evs[i][0] != "peak" and len(sol.t_events[i])]
            t_first = min(f[0] for f in fired)      # ties: plate events first (the order of evs)
            _, name, i = min((f for f in fired if f[0] <= t_first + 1e-12), key=lambda f: f[2])
            y = sol.y_events[i][-1].copy()
        if name == "rev":
            y[1] = 0.0
            if bw:
                udd = accs(t, y, (1,) + mode_t[1:])[0]
                mode[0] = int(np.sign(udd)) or -ps
            else:
                mode[0] = 0
                d = demand(t, y, tuple(mode))
                if abs(d) > mug:
                    mode[0] = int(np.sign(d))
        elif name == "z0":
            y[4] = 0.0
        elif name.startswith("unstick"):
            mode[0] = 1 if name == "unstick+" else -1
        elif name in ("upL", "upR"):
            mode[1], mode[2] = True, -1 if name == "upL" else 1
            mode[3] = 0 if (model.kind == "imperfect") else 1
            y[2] = y[3] = 0.0
        elif name == "hi":
            if reg == 0:
                mode[3] = 1
                y[2] = side * bounds(side, 0)[1]          # exactly on the boundary
            else:
                qmax[side] = bounds(side, reg)[1]
                t_over = t
                break
        elif name == "lo":
            if reg == 1 and bounds(side, 1)[0] > 0:
                mode[3] = 0
                y[2] = side * bounds(side, 1)[0]
            else:
                e = (model.e_L if side > 0 else model.e_R)(abs(y[3]))
                impacts.append(t)
                y[1] -= mr * p.h * (e - 1) * y[3]
                y[3] *= e
                y[2] = 0.0
                mode[2] = -side
                mode[3] = 0 if model.kind == "imperfect" else 1
                if not bw:
                    mode[0] = int(np.sign(y[1]))
                    if mode[0] == 0:
                        d = demand(t, y, tuple(mode))
                        mode[0] = int(np.sign(d)) if abs(d) > mug else 0
                elif np.sign(y[1]) != 0:
                    mode[0] = int(np.sign(y[1]))
    return qmax[-1], qmax[1], umax, np.array(impacts), t_over


@pytest.mark.parametrize("model_name", ["coulomb", "boucwen"])
def test_against_an_independent_solve_ivp_reference(model_name):
    """A one-cosine pulse: the plate unsticks, the statue lifts while the plate slides,
    the plate reverses under the rocking statue, three impacts, the rolling transition
    both ways, overturning (mode 3)."""
    iso = Isolator(R=0.30, r=0.0183, M=16.0, mu=0.012, model=model_name, q=30.0)
    model = RockingModel.imperfect(BLOCK, alpha_L=0.6, alpha_R=0.6, e_L=0.85, e_R=0.85)
    motion = motions.cosine_pulse(0.3 * G, 1.0, start=0.1)
    t_end = 1.5
    res = simulate_coupled(iso, model, motion, t_end=t_end, rtol=1e-10)
    qL, qR, umax, imp, t_over = reference(iso, model, motion, t_end)
    assert res.uplift and res.n_impacts == len(imp) == 3
    assert res.outcome == "overturn mode 3" and t_over is not None
    assert res.overturn_time == pytest.approx(t_over, abs=1e-8)
    assert np.max(np.abs(res.impacts[:, 0] - imp)) < 1e-8
    assert res.theta_max_L == pytest.approx(qL, rel=1e-6)
    assert res.theta_max_R == pytest.approx(qR, rel=1e-6)
    assert res.u_max == pytest.approx(umax, rel=1e-6)
    assert len(res.peaks_u) >= 1                     # the plate reversed while the statue rocked


def test_results_do_not_depend_on_the_output_grid():
    statue = RockingParams.from_dict({"m": 12.074, "h": 0.3523, "b_L": 0.1995, "b_R": 0.0805, "I_G": 0.8})
    model = RockingModel.imperfect(statue, alpha_L=0.175, alpha_R=0.175, e_L=0.9, e_R=0.9)
    iso = Isolator(R=0.30, r=0.02, M=16.433, mu=0.0073, model="boucwen")
    motion = motions.synthetic_record(duration=10.0, pga=0.32 * G, seed=4)
    a = simulate_coupled(iso, model, motion, dt_out=0.005)
    b = simulate_coupled(iso, model, motion, dt_out=0.001)
    assert a.outcome == b.outcome == "rocking" and a.n_impacts == b.n_impacts > 50 and a.stats["n_zeno"] >= 1
    assert np.array_equal(a.impacts, b.impacts)
    assert (a.theta_max_L, a.theta_max_R, a.u_max) == (b.theta_max_L, b.theta_max_R, b.u_max)
    assert np.array_equal(a.theta, b.theta[::5]) and np.array_equal(a.u, b.u[::5])
    # the statue (12 kg on a 16.4 kg plate) pushes the plate back: the one-way model is off
    plate = simulate(iso, motion, dt_out=0.005)
    assert not np.allclose(a.u, plate.u, rtol=0, atol=1e-3 * a.u_max)


# ------------------------------------------------------------------ 6. bad input
def test_bad_input():
    iso = Isolator(R=0.30, r=0.0183, M=15.0, mu=0.01)
    model = RockingModel.housner(BLOCK)
    free = motions.free()
    with pytest.raises(InputError, match="must exceed"):
        simulate_coupled(Isolator(R=0.30, r=0.0183, M=10.0, mu=0.01), model, free, theta0=0.1)
    for kwargs in ({"t_end": -1.0}, {"t_end": float("nan")}, {"dt_out": -0.01}, {"u0": float("nan")},
                   {"theta0": float("inf")}, {"omega0": float("nan")}, {"theta0": 1.0}, {"rtol": 0.5}):
        with pytest.raises(InputError):
            simulate_coupled(iso, model, free, **kwargs)
    with pytest.raises(InputError, match="linearised"):
        simulate_coupled(iso, RockingModel.housner(BLOCK, linearised=True), free, theta0=0.1)
    with pytest.raises(InputError):
        simulate_coupled(iso, "not a model", free)
