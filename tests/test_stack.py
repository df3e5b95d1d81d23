"""A statue on a pedestal: the two-block rocking model (rocking/stack.py) against the single-body
engine in its two limits, energy conservation, rest, and the closed-form uplift thresholds.

No published two-block case with stated numbers was found for a reproduction (Psycharis 1990,
Spanos et al. 2001: their tables and figures were not available), so there is no such test."""
from __future__ import annotations

import math

import numpy as np
import pytest

from statue2model.errors import InputError
from statue2model.geometry.rocking_params import RockingParams
from statue2model.hazard import motions
from statue2model.quantities import G
from statue2model.rocking import RockingModel, simulate
from statue2model.rocking.sliding import Friction, simulate_sliding
from statue2model.rocking.stack import Pedestal, StackModel, free_energy, simulate_stack

STATUE = RockingParams.rectangular_block(b=0.1, h=0.5, m=200.0)        # a_L = a_R = 0.2 g
HEAVY = Pedestal(b=50.0, h=0.5, m=1e6)                                 # cannot move


@pytest.mark.parametrize("amp_g, freq, theta0, overturns", [
    (0.25, 2.0, 0.0, False),        # rocks, 92 impacts
    (0.30, 2.0, 0.0, True),         # overturns after one impact
    (0.30, 1.0, 0.0, True),         # overturns with no impact
    (0.0, 1.0, 0.1, False),         # free rocking from theta0 = 0.1 rad
])
def test_statue_on_an_immovable_pedestal_is_the_single_body(amp_g, freq, theta0, overturns):
    e = 0.9
    model = StackModel(STATUE, HEAVY, e_top=e)
    motion = motions.sine_pulse(amp_g * G, freq) if amp_g else motions.free()
    r = simulate_stack(model, motion, theta0=(0.0, theta0))
    ref = simulate(RockingModel.housner(STATUE, e_L=e, e_R=e), motion, theta0=theta0)
    assert not r.pedestal.uplift and r.pedestal.n_impacts == 0 and r.pedestal.theta_max == 0.0
    assert r.statue.theta_max_over_delta == pytest.approx(ref.theta_max_over_delta, rel=1e-4)
    assert r.statue.uplift_time == pytest.approx(ref.uplift_time, abs=1e-9)
    assert r.statue.n_impacts == ref.n_impacts
    assert r.statue.overturned == ref.overturned == overturns
    if overturns:
        assert r.statue.overturn_time == pytest.approx(ref.overturn_time, abs=1e-6)
        assert r.outcome == "statue overturns"
    else:
        assert r.outcome == "statue rocks" and r.t_rest is not None
    # the pedestal is at rest: its top moves with the ground
    a_g = motion.acc(r.t)
    assert np.allclose(r.top_acc, a_g, atol=1e-12)


SQUAT = RockingParams.rectangular_block(b=0.3, h=0.1, m=100.0)        # a = 3 g: never lifts here
SLENDER = Pedestal(b=0.3, h=1.0, m=300.0)


@pytest.mark.parametrize("amp_g, freq, theta1_0, overturns", [
    (0.30, 1.0, 0.0, False), (0.40, 1.0, 0.0, True), (0.0, 1.0, 0.1, False)])
def test_a_statue_that_cannot_rock_makes_one_composite_body(amp_g, freq, theta1_0, overturns):
    e = 0.9
    model = StackModel(SQUAT, SLENDER, e_floor=e)
    comp = model.composite
    # the composite by hand: G at h_c above the floor, I about it by the parallel-axis theorem
    m1, m2 = 300.0, 100.0
    hc = (m1 * 1.0 + m2 * 2.1) / (m1 + m2)
    ic = m1 * (0.3**2 + 1.0**2) / 3 + m1 * (hc - 1.0) ** 2 + m2 * (0.3**2 + 0.1**2) / 3 + m2 * (2.1 - hc) ** 2
    assert (comp.m, comp.h, comp.b_L, comp.b_R) == pytest.approx((400.0, hc, 0.3, 0.3), rel=1e-14)
    assert comp.I_G == pytest.approx(ic, rel=1e-14)
    motion = motions.sine_pulse(amp_g * G, freq) if amp_g else motions.free()
    r = simulate_stack(model, motion, theta0=(theta1_0, 0.0))
    ref = simulate(RockingModel.housner(comp, e_L=e, e_R=e), motion, theta0=theta1_0)
    assert not r.statue.uplift and r.statue.n_impacts == 0
    assert r.pedestal.theta_max_over_delta == pytest.approx(ref.theta_max_over_delta, rel=1e-4)
    assert r.pedestal.uplift_time == pytest.approx(ref.uplift_time, abs=1e-9)
    assert r.pedestal.n_impacts == ref.n_impacts
    assert r.pedestal.overturned == ref.overturned == overturns
    assert r.outcome == ("stack overturns" if overturns else "pedestal rocks")


@pytest.mark.parametrize("method", ["scipy", "compiled"])
def test_energy_is_constant_between_impacts_and_never_grows_at_one(method):
    """Free motion of a stack started in the both-rock pattern: the mechanical energy stays
    constant between impacts (to 1e-6 relative) and no impact adds energy (both integrators)."""
    model = StackModel(RockingParams.rectangular_block(b=0.15, h=0.6, m=200.0), Pedestal(0.3, 0.6, 300.0))
    r = simulate_stack(model, motions.free(), theta0=(0.03, 0.08), dt_out=1e-3, rtol=1e-10, method=method)
    assert r.pattern_times["both"] > 0.5 and r.pattern_times["statue"] > 1.0
    assert r.statue.uplift and r.pedestal.uplift and not (r.statue.overturned or r.pedestal.overturned)
    E = np.array([free_energy(model, s) for s in zip(r.theta1, r.theta2, r.omega1, r.omega2)])
    E0 = E[0]
    assert E0 > 0
    edges = [0.0] + [i.t for i in r.impacts] + [math.inf]
    checked = 0
    for a, b in zip(edges[:-1], edges[1:]):
        seg = E[(r.t > a) & (r.t < b)]
        if seg.size > 2 and seg.max() > 1e-3 * E0:
            assert (seg.max() - seg.min()) / E0 < 1e-6
            checked += 1
    assert checked > 20
    assert all(i.energy_after <= i.energy_before * (1 + 1e-12) for i in r.impacts)
    assert {i.contact for i in r.impacts} == {1, 2}
    assert r.t_rest is not None and abs(E[-1]) < 1e-9 * E0        # came to rest


def test_below_both_uplift_limits_nothing_moves():
    model = StackModel(STATUE, Pedestal(0.3, 0.5, 300.0))
    lim = model.uplift_limits
    assert min(min(v) for v in lim.values()) == pytest.approx(0.2 * G)
    r = simulate_stack(model, motions.sine_train(0.199 * G, 2.0, 3))
    assert r.outcome == "no motion" and not r.statue.uplift and not r.pedestal.uplift
    assert r.statue.theta_max == r.pedestal.theta_max == 0.0 and len(r.impacts) == 0
    assert not np.any(r.theta1) and not np.any(r.theta2)
    assert r.pattern_times["rest"] == pytest.approx(r.t_end)


def _ramp(peak):
    """u_g'' growing linearly from 0 to ``peak`` over 10 s (a record, linear between samples)."""
    return motions.record(np.linspace(0.0, peak, 1001), 0.01)


@pytest.mark.parametrize("statue, pedestal, x2, first", [
    (RockingParams(m=200.0, h=0.6, b_L=0.12, b_R=0.2, I_G=20.0), Pedestal(0.35, 0.6, 300.0), 0.05,
     ("statue", "pedestal")),     # 0.2 g < 0.343 g toward +x; 0.333 g > 0.306 g toward -x
    (RockingParams(m=100.0, h=0.15, b_L=0.25, b_R=0.2, I_G=3.0), Pedestal(0.3, 1.0, 300.0), 0.08,
     ("pedestal", "pedestal")),
])
def test_the_first_body_to_lift_and_when_against_the_closed_form(statue, pedestal, x2, first):
    """From rest the statue lifts at g b/h (on its left pivot toward +x), the pedestal carrying the
    statue at g b_eff / h_c with b_eff the distance from the stack's centre of mass to the floor corner."""
    model = StackModel(statue, pedestal, x2=x2)
    m1, m2 = pedestal.m, statue.m
    xc = m2 * x2 / (m1 + m2)
    hc = (m1 * pedestal.h + m2 * (2 * pedestal.h + statue.h)) / (m1 + m2)
    closed = {"statue": (G * statue.b_L / statue.h, G * statue.b_R / statue.h),
              "pedestal": (G * (pedestal.b + xc) / hc, G * (pedestal.b - xc) / hc)}
    for body in closed:
        assert model.uplift_limits[body] == pytest.approx(closed[body], rel=1e-14)
    assert model.first_to_lift == first
    peak = 1.5 * max(max(v) for v in closed.values())
    for k, sign in ((0, 1.0), (1, -1.0)):
        r = simulate_stack(model, _ramp(sign * peak), t_end=12.0)
        who = first[k]
        t_expect = 10.0 * closed[who][k] / peak
        res = r.statue if who == "statue" else r.pedestal
        other = r.pedestal if who == "statue" else r.statue
        assert res.uplift_time == pytest.approx(t_expect, abs=1e-9)
        assert other.uplift_time is None or other.uplift_time > res.uplift_time
        # it lifts on the pivot away from the ground's acceleration
        theta = r.theta2 if who == "statue" else r.theta1
        moving = theta[np.abs(theta) > 0]
        assert np.sign(moving[0]) == -sign


def test_the_pedestal_top_history_feeds_the_sliding_routine():
    model = StackModel(RockingParams.rectangular_block(b=0.15, h=0.6, m=200.0), Pedestal(0.3, 0.6, 300.0))
    r = simulate_stack(model, motions.sine_pulse(0.3 * G, 1.5), dt_out=2e-3)
    assert r.pedestal.uplift
    top = r.top_motion()
    assert top.kind == "record" and top.dt == pytest.approx(2e-3) and top.samples.size == r.t.size
    rocking = r.pattern % 2 == 1             # the pedestal rocks: its top moves more than the ground
    assert np.any(rocking) and np.max(np.abs(r.top_acc[rocking] - motions.sine_pulse(0.3 * G, 1.5).acc(
        r.t[rocking]))) > 0.01
    s = simulate_sliding(Friction(0.3, 0.25), top)
    assert math.isfinite(s.u_max)


def test_inputs_are_checked():
    with pytest.raises(InputError, match="right pivot"):
        StackModel(STATUE, Pedestal(0.15, 0.5, 100.0), x2=0.1)
    with pytest.raises(InputError, match="left pivot"):
        StackModel(STATUE, Pedestal(0.15, 0.5, 100.0), x2=-0.1)
    with pytest.raises(InputError, match="depth"):
        Pedestal.box(0.6, 0.0, 1.0, 100.0)
    with pytest.raises(InputError, match="pedestal m"):
        Pedestal(0.3, 0.5, float("nan"))
    with pytest.raises(InputError, match="e_top"):
        StackModel(STATUE, Pedestal(0.3, 0.5, 100.0), e_top=1.2)
    with pytest.raises(InputError, match="overturning angle"):
        simulate_stack(StackModel(STATUE, Pedestal(0.3, 0.5, 100.0)), motions.free(), theta0=(0.0, 0.3))
    m = StackModel(STATUE, Pedestal(0.3, 0.5, 100.0), e_floor=(0.8, 0.7))
    assert m.e_floor == (0.8, 0.7) and m.e_top == (STATUE.e_L, STATUE.e_R)
