"""Sliding of one rigid body on its support (rocking/sliding.py; issue [22], item 2, first part):
the exact stick-slip integration against closed forms and an independent fine-step integrator."""
from __future__ import annotations

import math

import numpy as np
import pytest

from statue2model.errors import InputError
from statue2model.hazard import motions
from statue2model.quantities import G
from statue2model.rocking.sliding import Friction, simulate_sliding, slides_first


@pytest.mark.parametrize("A_g, mu_s, mu_k, t1", [(0.3, 0.25, 0.2, 0.5), (0.8, 0.5, 0.5, 0.2), (0.45, 0.4, 0.1, 1.0)])
def test_a_rectangular_pulse_against_the_closed_form(A_g, mu_s, mu_k, t1):
    """Constant A > mu_s g for t1: the support runs from under the body at the relative acceleration
    A - mu_k g, then the body decelerates at mu_k g: u_end = -(A - mu_k g) t1^2 / 2 - v1^2 / (2 mu_k g),
    v1 = (A - mu_k g) t1, at rest at t1 + v1 / (mu_k g)."""
    A, c = A_g * G, mu_k * G
    r = simulate_sliding(Friction(mu_s, mu_k), motions.rect_pulse(A, t1))
    v1 = (A - c) * t1
    u_end = -(A - c) * t1 ** 2 / 2 - v1 ** 2 / (2 * c)
    assert r.u_end == pytest.approx(u_end, rel=1e-9) and r.u_max == pytest.approx(-u_end, rel=1e-9)
    assert r.t_rest == pytest.approx(t1 + v1 / c, rel=1e-9) and r.n_slides == 1 and r.t_first == 0.0


def test_below_the_static_friction_nothing_moves():
    r = simulate_sliding(Friction(0.25, 0.2), motions.sine_pulse(0.249 * G, 1.5))
    assert not r.slides and r.u_max == 0.0 and r.n_slides == 0


def fine_step_sliding(friction, motion, dt=2e-5):
    """An independent integrator: fixed small steps of the same stick-slip law (no closed form); (peak
    |u|, final u). benchmarks/bench_sliding.py times it beside ours."""
    t = np.arange(0.0, motion.end + 3.0, dt)
    a = motion.acc(t)
    mus, c = friction.mu_s * G, friction.mu_k * G
    u = v = 0.0
    umax = 0.0
    for ak in a.tolist():
        if v == 0.0:
            if abs(ak) <= mus:
                continue
            s = -math.copysign(1.0, ak)
        else:
            s = math.copysign(1.0, v)
        vn = v - (ak + s * c) * dt
        if v != 0.0 and vn * v <= 0.0:              # it stops within the step
            u += v * dt / 2
            v = 0.0
        else:
            u += (v + vn) * dt / 2
            v = vn
        umax = max(umax, abs(u))
    return umax, u


def test_a_record_against_an_independent_fine_step_integrator():
    rec = motions.synthetic_record(duration=8.0, dt=0.01, pga=0.45 * G, seed=3)
    f = Friction(0.3, 0.25)
    r = simulate_sliding(f, rec)
    umax, uend = fine_step_sliding(f, rec)
    assert r.slides and r.n_slides >= 2
    assert r.u_max == pytest.approx(umax, rel=2e-3, abs=1e-5) and r.u_end == pytest.approx(uend, rel=2e-3, abs=1e-5)


def test_the_regime_before_lift_off_and_bad_friction():
    assert slides_first(Friction(0.3, 0.25), 0.8) and not slides_first(Friction(0.9, 0.7), 0.8)
    with pytest.raises(InputError, match="exceeds the static"):
        Friction(0.2, 0.3)
    with pytest.raises(InputError, match="mu_s must be a number"):
        Friction(float("nan"), 0.1)


def test_sides_and_no_frictionless_support():
    """u_pos / u_neg: the peaks toward each side (a pulse toward +x slides the body toward -x); a support
    without kinetic friction is refused (the body would never stop: no finite displacement)."""
    r = simulate_sliding(Friction(0.25, 0.2), motions.rect_pulse(0.3 * G, 0.5))
    assert r.u_pos == 0.0 and r.u_neg == pytest.approx(r.u_max) and r.u_neg == pytest.approx(-r.u_end)
    two = motions.record([0.0] + [0.5 * G] * 100 + [-0.5 * G] * 300 + [0.0], 0.005)
    r2 = simulate_sliding(Friction(0.2, 0.2), two)
    assert r2.u_pos > 0 and r2.u_neg > 0 and r2.u_max == max(r2.u_pos, r2.u_neg)
    with pytest.raises(InputError, match="mu_k"):
        Friction(0.2, 0.0)


def test_steps_at_rest_skipped_on_whole_arrays_change_nothing(monkeypatch):
    """simulate_sliding passes the steps a body at rest cannot leave rest in (_next_moving_step, on whole
    arrays) without its loop: the results are bit for bit those of the loop through every step, also with
    samples exactly at +-mu_s g, a record starting late, t_end inside or past the motion, and pulses."""
    from statue2model.rocking import sliding

    rng = np.random.default_rng(7)
    cases = []
    for k in range(12):
        mu_s = float(rng.uniform(0.05, 0.5))
        f = Friction(mu_s, mu_s * float(rng.uniform(0.6, 1.0)))
        acc = rng.normal(0.0, 0.4 * mu_s * G, 600)
        acc[rng.integers(0, 600, 30)] = mu_s * G * rng.choice([-1.0, 1.0], 30)      # exactly at the limit
        acc[100:110] = mu_s * G                                                      # a plateau on it
        rec = motions.record(acc, 0.01, start=0.3 if k % 2 else 0.0)
        for t_end in (None, 2.5, 20.0):
            cases.append((f, rec, t_end))
        cases.append((f, motions.rect_pulse(float(rng.uniform(0.5, 2.0)) * mu_s * G, 0.4), None))
    fast = [simulate_sliding(f, m, t_end=t_end) for f, m, t_end in cases]
    monkeypatch.setattr(sliding, "_next_moving_step", lambda t, a, mus, stop_at: np.arange(t.size - 1))
    slow = [simulate_sliding(f, m, t_end=t_end) for f, m, t_end in cases]
    assert [r.__dict__ for r in fast] == [r.__dict__ for r in slow]
    assert sum(r.n_slides for r in fast) > 20            # the cases do slide
