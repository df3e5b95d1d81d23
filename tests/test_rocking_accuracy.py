"""The rocking engine against references that share no code with it (MODEL.md section 3):
quadrature of the energy integral, the exact energy law of impacts, Housner's
closed forms, published pulse boundaries, and the Zeno sum."""
import math

import numpy as np
import pytest
from scipy import integrate

from statue2model.hazard import motions
from statue2model.rocking import RockingModel, simulate
from statue2model.geometry.rocking_params import RockingParams

G = 9.81
A1 = RockingParams.rectangular_block(0.0384, 0.2000, 1.286)
STATUE = RockingParams(m=19.6, h=0.3523, b_L=0.1995, b_R=0.0805, I_G=1.105)  # Table 24 geometry
TIGHT = 1e-12


def quarter_period_quadrature(p, delta, theta0):
    """t from rest at theta0 to theta = 0: integral of dtheta / theta'(theta), with
    theta'^2 = 2 p^2 [cos(delta - theta0) - cos(delta - theta)] written without cancellation
    and the 1/sqrt singularity at theta0 taken by QUADPACK's algebraic weight."""
    def g(th):
        x = theta0 - th
        if x == 0.0:
            return 1.0 / math.sqrt(2 * p**2 * math.sin(delta - theta0))
        return math.sqrt(x) / math.sqrt(4 * p**2 * math.sin(delta - 0.5 * (theta0 + th)) * math.sin(0.5 * x))
    val, err = integrate.quad(g, 0.0, theta0, weight="alg", wvar=(0.0, -0.5), epsabs=0, epsrel=1e-13, limit=200)
    return val


def cos_drop(delta, q):
    """cos(delta - q) - cos(delta) without cancellation for small q."""
    return 2.0 * math.sin(delta - 0.5 * q) * math.sin(0.5 * q)


@pytest.mark.parametrize("ratio", [0.05, 0.3, 0.7, 0.95])
@pytest.mark.parametrize("body", ["A1", "statue"])
def test_quarter_period_nonlinear_vs_quadrature(ratio, body):
    params = A1 if body == "A1" else STATUE
    model = RockingModel.housner(params, e_L=0.8, e_R=0.8)
    for side in (1, -1):
        delta = params.delta_R if side > 0 else params.delta_L
        p = params.p_R if side > 0 else params.p_L
        theta0 = side * ratio * delta
        r = simulate(model, motions.free(), theta0=theta0, rtol=TIGHT, t_end=5.0)
        ref = quarter_period_quadrature(p, delta, abs(theta0))
        assert r.impact_times[0] == pytest.approx(ref, rel=1e-8, abs=0)


def test_peak_decay_follows_the_energy_law_asymmetric():
    """eq. 43 read forwards: each peak follows from the previous one and e of that impact."""
    p = STATUE
    model = RockingModel.housner(p, e_L=0.93, e_R=0.81)
    r = simulate(model, motions.free(), theta0=0.8 * p.delta_R, rtol=TIGHT, t_end=4.0)
    assert r.peak_values.size >= 8
    delta = {"R": p.delta_R, "L": p.delta_L}
    d = {"R": p.d_R, "L": p.d_L}
    inertia = {"R": p.I_R, "L": p.I_L}
    e_landing = {"R": 0.93, "L": 0.81}  # rocking on R lands on the left edge: e_L
    for i in range(r.peak_values.size - 1):
        a, b = r.peak_sides[i], r.peak_sides[i + 1]
        assert a != b
        lhs = d[b] / inertia[b] * cos_drop(delta[b], r.peak_values[i + 1])
        rhs = e_landing[a] ** 2 * d[a] / inertia[a] * cos_drop(delta[a], r.peak_values[i])
        assert lhs == pytest.approx(rhs, rel=1e-8, abs=0)
    assert r.peak_values[-1] < 1e-6 * p.delta_L  # checked down to the Zeno tail


def test_peak_decay_symmetric_block_and_sides():
    model = RockingModel.housner(A1, e_L=0.9, e_R=0.9)
    r = simulate(model, motions.free(), theta0=-0.6 * A1.delta_L, rtol=TIGHT, t_end=3.0)
    delta = A1.delta_L
    c = [cos_drop(delta, th) for th in r.peak_values]
    for a, b in zip(c, c[1:]):
        assert b == pytest.approx(0.81 * a, rel=1e-8, abs=0)
    assert list(r.peak_sides[:4]) == ["L", "R", "L", "R"]


@pytest.mark.parametrize("ratio", [0.1, 0.5, 0.9, 0.99])
def test_linearised_period_vs_housner(ratio):
    model = RockingModel.housner(A1, e_L=1.0, e_R=1.0, linearised=True)
    theta0 = ratio * A1.delta_R
    r = simulate(model, motions.free(), theta0=theta0, rtol=TIGHT, t_end=3.0)
    T = 4.0 / A1.p_R * math.acosh(1.0 / (1.0 - ratio))
    assert 4 * r.impact_times[0] == pytest.approx(T, rel=1e-8)
    assert 2 * (r.impact_times[1] - r.impact_times[0]) == pytest.approx(T, rel=1e-8)
    assert r.peak_values[1] == pytest.approx(theta0, rel=1e-9)  # e = 1: no loss


def _boundary(make_motion, model, lo, hi, tol=1e-7):
    """Smallest amplitude A (in g delta) that overturns with no impact, by bisection."""
    params = model.params

    def overturns(A):
        r = simulate(model, make_motion(A * G * params.delta_R), rtol=1e-10)
        return r.overturned and r.impacts_before_overturn == 0

    assert not overturns(lo) and overturns(hi)
    while hi - lo > tol * hi:
        mid = 0.5 * (lo + hi)
        if overturns(mid):
            hi = mid
        else:
            lo = mid
    return 0.5 * (lo + hi)


@pytest.mark.parametrize("pt1", [0.5, 1.0, 2.0, 4.0])
def test_rectangular_pulse_boundary_linearised(pt1):
    model = RockingModel.housner(A1, e_L=0.9, e_R=0.9, linearised=True)
    t1 = pt1 / A1.p_R
    # a negative pulse tips the body onto its right pivot
    A = _boundary(lambda a: motions.rect_pulse(-a, t1), model, 1.0001, 1.0 / (1 - math.exp(-pt1)) * 1.2)
    assert A == pytest.approx(1.0 / (1.0 - math.exp(-pt1)), rel=1e-4)


@pytest.mark.parametrize("beta,A_ref", [(0.5, 1.1120), (1, 1.3569), (2, 2.0564), (4, 4.2503), (8, 12.139)])
def test_one_sine_boundary_linearised(beta, A_ref):
    model = RockingModel.housner(A1, e_L=0.9, e_R=0.9, linearised=True)
    f = beta * A1.p_R / (2 * math.pi)
    A = _boundary(lambda a: motions.sine_pulse(-a, f), model, A_ref * 0.97, A_ref * 1.03)
    assert A == pytest.approx(A_ref, rel=1e-4)


def test_similarity_law():
    """Linearised: theta/delta depends only on (A, beta, e)."""
    other = RockingParams.rectangular_block(0.25, 1.1, 900.0)
    out = []
    for params in (A1, other):
        model = RockingModel.housner(params, e_L=0.85, e_R=0.85, linearised=True)
        for A, beta in ((1.2, 1.0), (3.0, 3.0)):
            f = beta * params.p_R / (2 * math.pi)
            r = simulate(model, motions.sine_pulse(-A * G * params.delta_R, f), rtol=TIGHT,
                         t_end=6.0 / params.p_R * 2 * math.pi)
            out.append((r.theta_max_over_delta, r.n_impacts, (r.impact_times * params.p_R)[:3]))
    for a, b in zip(out[:2], out[2:]):
        assert a[0] == pytest.approx(b[0], rel=1e-8)
        assert a[1] == b[1]
        np.testing.assert_allclose(a[2], b[2], rtol=1e-8)


@pytest.mark.parametrize("e", [0.5, 0.8, 0.95])
def test_zeno_rest_time(e):
    """Free rocking comes to rest at the sum of the excursion times (linearised closed form)."""
    model = RockingModel.housner(A1, e_L=e, e_R=e, linearised=True)
    p, delta, ratio = A1.p_R, A1.delta_R, 0.6
    theta0 = ratio * delta
    r = simulate(model, motions.free(), theta0=theta0, rtol=1e-10, t_end=60.0)
    t = math.acosh(1 / (1 - ratio)) / p
    w = p * math.sqrt(delta**2 - (delta - theta0) ** 2)
    k = 1
    while e**k * w > 1e-15:
        t += 2 / p * math.atanh(e**k * w / (p * delta))
        k += 1
    assert r.t_rest == pytest.approx(t, rel=1e-2)
    assert r.stats["n_steps"] + r.stats["n_rejected"] < 40 * r.n_impacts + 100
    assert r.stats["t_final"] <= 60.0 and r.history is None


def test_rest_then_stick_then_uplift():
    """After coming to rest the body obeys the stick condition: a pulse below the
    uplift limit leaves it still, one above lifts it at once."""
    model = RockingModel.imperfect(A1, alpha_L=0.65, alpha_R=0.65, e_L=0.7, e_R=0.7)
    lim_up = model.uplift_limits[0]
    below = motions.rect_pulse(0.99 * lim_up, 0.5, start=8.0)
    r = simulate(model, below, theta0=0.5 * A1.delta_R, t_end=10.0, dt_out=0.01)
    assert r.t_rest is not None and r.t_rest < 8.0
    assert r.stats["n_uplifts"] == 1
    after = r.history["t"] > r.t_rest + 1e-9
    assert np.all(r.history["theta"][after] == 0.0) and np.all(r.history["phase"][after] == 0)
    above = motions.rect_pulse(1.01 * lim_up, 0.5, start=8.0)
    r2 = simulate(model, above, theta0=0.5 * A1.delta_R, t_end=10.0)
    assert r2.stats["n_uplifts"] == 2
    assert r2.theta_max_L > 0


def test_quiet_motion_is_not_integrated():
    model = RockingModel.imperfect(A1, alpha_L=0.65, alpha_R=0.65)
    lim = min(model.uplift_limits)
    r = simulate(model, motions.sine_train(0.999 * lim, 3.0, 20))
    assert r.uplift_time is None and r.outcome == "no motion" and r.stats["n_steps"] == 0


def test_uplift_at_the_reduced_limit():
    """A one-sine pulse lifts the imperfect body exactly when u_g'' first exceeds alpha a."""
    model = RockingModel.imperfect(A1, alpha_L=0.65, alpha_R=0.5)
    amp, f = 2.0 * model.uplift_limits[0], 2.0
    r = simulate(model, motions.sine_pulse(amp, f))
    t_up = math.asin(0.5) / (2 * math.pi * f)
    assert r.uplift_time == pytest.approx(t_up, rel=1e-12)
    r = simulate(model, motions.sine_pulse(-amp * model.uplift_limits[1] / model.uplift_limits[0], f))
    assert r.uplift_time == pytest.approx(t_up, rel=1e-12)
    assert r.theta_max_R > 0 and r.theta_max_L >= 0
