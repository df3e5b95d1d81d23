"""The compiled two-block kernel (rocking/stack_kernel.py) against the scipy path of
rocking/stack.py (``method="scipy"``, the reference), on the cases of tests/test_stack.py:
the single-body limits, free motion of both blocks, pulses that rock or overturn each body,
a synthetic record under which a slender pedestal lifts; its energy balance; the batch
entry against single runs, bit for bit.

Where the two paths may part: scipy looks for an event's sign change only at the ends of
its steps, the kernel at 1/8 of each step; a pedestal that rocks by a few microradians
under a record may cross theta1 = 0 and come back inside one scipy step (an impact scipy
misses). The cases here are chosen where neither misses one (the peaks then agree to ~1e-9)."""
from __future__ import annotations


import numpy as np
import pytest

from statue2model.errors import InputError
from statue2model.geometry.rocking_params import RockingParams
from statue2model.hazard import motions
from statue2model.quantities import G
from statue2model.rocking import RockingModel, simulate
from statue2model.rocking import stack_kernel as SK
from statue2model.rocking.stack import Pedestal, StackModel, simulate_stack, simulate_stack_batch

STATUE = RockingParams.rectangular_block(b=0.1, h=0.5, m=200.0)        # a_L = a_R = 0.2 g
HEAVY = Pedestal(b=50.0, h=0.5, m=1e6)                                 # cannot move
SQUAT = RockingParams.rectangular_block(b=0.3, h=0.1, m=100.0)         # never lifts here
SLENDER = Pedestal(b=0.3, h=1.0, m=300.0)
TALL = StackModel(RockingParams.rectangular_block(b=0.15, h=0.6, m=200.0), SLENDER)   # the pedestal lifts first
TALL2 = StackModel(RockingParams.rectangular_block(b=0.2, h=0.5, m=200.0), SLENDER)   # the statue seldom lifts


def _both(model, motion, **kw):
    return simulate_stack(model, motion, method="compiled", **kw), simulate_stack(model, motion, method="scipy", **kw)


def _same(rc, rs, rel=1e-6, t_abs=1e-6):
    """Same outcome, flags, impact counts; peaks to ``rel``; times to ``t_abs``."""
    assert rc.outcome == rs.outcome
    for b in ("statue", "pedestal"):
        c, s = getattr(rc, b), getattr(rs, b)
        assert c.uplift == s.uplift and c.overturned == s.overturned and c.n_impacts == s.n_impacts, b
        assert c.theta_max_over_delta == pytest.approx(s.theta_max_over_delta, rel=rel, abs=1e-12), b
        assert c.theta_max == pytest.approx(s.theta_max, rel=rel, abs=1e-12), b
        if s.uplift:
            assert c.uplift_time == pytest.approx(s.uplift_time, abs=t_abs), b
        if s.overturned:
            assert c.overturn_time == pytest.approx(s.overturn_time, abs=t_abs), b
    assert (rc.t_rest is None) == (rs.t_rest is None)
    if rs.t_rest is not None:
        assert rc.t_rest == pytest.approx(rs.t_rest, abs=t_abs)
    for k, v in rs.pattern_times.items():
        assert rc.pattern_times[k] == pytest.approx(v, abs=1e-6), k
    assert len(rc.impacts) == len(rs.impacts)
    top = max((i.speed for i in rs.impacts), default=0.0)
    for a, b in zip(rc.impacts, rs.impacts):
        assert (a.contact, a.side) == (b.contact, b.side) and a.t == pytest.approx(b.t, abs=t_abs)
        assert a.speed == pytest.approx(b.speed, abs=rel * top)


@pytest.mark.parametrize("amp_g, freq, theta0", [(0.25, 2.0, 0.0), (0.30, 2.0, 0.0), (0.30, 1.0, 0.0),
                                                 (0.0, 1.0, 0.1)])
def test_statue_on_an_immovable_pedestal(amp_g, freq, theta0):
    model = StackModel(STATUE, HEAVY, e_top=0.9)
    motion = motions.sine_pulse(amp_g * G, freq) if amp_g else motions.free()
    rc, rs = _both(model, motion, theta0=(0.0, theta0))
    _same(rc, rs)
    ref = simulate(RockingModel.housner(STATUE, e_L=0.9, e_R=0.9), motion, theta0=theta0)
    assert rc.statue.theta_max_over_delta == pytest.approx(ref.theta_max_over_delta, rel=1e-4)
    assert rc.statue.n_impacts == ref.n_impacts and rc.statue.overturned == ref.overturned
    assert np.array_equal(rc.t, rs.t)
    assert np.allclose(rc.theta2, rs.theta2, atol=1e-7) and np.allclose(rc.top_acc, motion.acc(rc.t), atol=1e-12)


@pytest.mark.parametrize("amp_g, freq, theta1_0", [(0.30, 1.0, 0.0), (0.40, 1.0, 0.0), (0.0, 1.0, 0.1)])
def test_a_statue_that_cannot_rock_makes_one_composite_body(amp_g, freq, theta1_0):
    model = StackModel(SQUAT, SLENDER, e_floor=0.9)
    motion = motions.sine_pulse(amp_g * G, freq) if amp_g else motions.free()
    rc, rs = _both(model, motion, theta0=(theta1_0, 0.0))
    _same(rc, rs)
    ref = simulate(RockingModel.housner(model.composite, e_L=0.9, e_R=0.9), motion, theta0=theta1_0)
    assert rc.pedestal.theta_max_over_delta == pytest.approx(ref.theta_max_over_delta, rel=1e-4)
    assert rc.pedestal.n_impacts == ref.n_impacts and rc.pedestal.overturned == ref.overturned


@pytest.mark.parametrize("model, amp_g, freq, outcome", [
    (StackModel(STATUE, Pedestal(0.3, 0.5, 300.0)), 0.25, 2.0, "statue rocks"),
    (StackModel(STATUE, Pedestal(0.3, 0.5, 300.0)), 0.30, 2.0, "statue overturns"),
    (TALL, 0.20, 1.0, "both rock"),
    (TALL, 0.30, 1.0, "statue overturns"),
    (TALL, 0.25, 0.5, "stack overturns"),
    (TALL2, 0.25, 1.0, "pedestal rocks"),
    (TALL2, 0.30, 1.0, "stack overturns"),
])
def test_pulses_that_rock_or_overturn_each_body(model, amp_g, freq, outcome):
    rc, rs = _both(model, motions.sine_pulse(amp_g * G, freq))
    assert rs.outcome == outcome
    _same(rc, rs)
    n = min(rc.t.size, rs.t.size)
    assert abs(rc.t.size - rs.t.size) <= 1
    scale = max(np.max(np.abs(rs.top_acc[:n])), 1.0)
    assert np.max(np.abs(rc.top_acc[:n] - rs.top_acc[:n])) < 1e-5 * scale


def test_a_record_under_which_a_slender_pedestal_lifts():
    rec = motions.synthetic_record(duration=20, dt=0.01, pga=0.4 * G, seed=1)
    rc, rs = _both(TALL, rec)
    assert rc.pedestal.uplift and rc.pedestal.n_impacts > 20 and rc.pattern_times["both"] > 1.0
    _same(rc, rs)
    assert rc.pedestal.theta_max_over_delta == pytest.approx(rs.pedestal.theta_max_over_delta, rel=1e-8)
    n = min(rc.t.size, rs.t.size)
    assert np.max(np.abs(rc.theta1[:n] - rs.theta1[:n])) < 1e-8
    assert np.max(np.abs(rc.top_acc[:n] - rs.top_acc[:n])) < 1e-6 * np.max(np.abs(rs.top_acc))
    assert np.array_equal(rc.pattern[:n], rs.pattern[:n])


def test_free_motion_of_both_blocks_as_the_reference():
    """The both-rock free motion of tests/test_stack.py's energy test (run there by both integrators): the
    compiled kernel gives the scipy reference's peaks, impacts and outcome."""
    model = StackModel(RockingParams.rectangular_block(b=0.15, h=0.6, m=200.0), Pedestal(0.3, 0.6, 300.0))
    r = simulate_stack(model, motions.free(), theta0=(0.03, 0.08), dt_out=1e-3, rtol=1e-10)
    rs = simulate_stack(model, motions.free(), theta0=(0.03, 0.08), dt_out=1e-3, rtol=1e-10, method="scipy")
    assert {i.contact for i in r.impacts} == {1, 2}
    _same(r, rs)


def test_the_first_body_to_lift_from_rest():
    """A ramp (a record) toward +x and -x: the first body lifts at its closed-form limit, as in the scipy path."""
    statue = RockingParams(m=200.0, h=0.6, b_L=0.12, b_R=0.2, I_G=20.0)
    model = StackModel(statue, Pedestal(0.35, 0.6, 300.0), x2=0.05)
    for sign in (1.0, -1.0):
        ramp = motions.record(np.linspace(0.0, sign * 0.6 * G, 1001), 0.01)
        rc, rs = _both(model, ramp, t_end=12.0)
        _same(rc, rs, t_abs=1e-9)


def test_below_both_uplift_limits_nothing_moves():
    r = simulate_stack(StackModel(STATUE, Pedestal(0.3, 0.5, 300.0)), motions.sine_train(0.199 * G, 2.0, 3))
    assert r.outcome == "no motion" and r.statue.theta_max == r.pedestal.theta_max == 0.0 and not r.impacts
    assert r.pattern_times["rest"] == pytest.approx(r.t_end) and not np.any(r.theta1) and not np.any(r.theta2)
    assert r.t_rest is None and r.stats["n_steps"] == 0


def test_the_batch_is_the_single_runs_bit_for_bit():
    rec = motions.synthetic_record(duration=10, dt=0.01, pga=0.4 * G, seed=1)
    models = [TALL, StackModel(STATUE, Pedestal(0.3, 0.5, 300.0)), StackModel(SQUAT, SLENDER),
              StackModel(STATUE, Pedestal(0.3, 0.5, 300.0), e_top=0.8)]
    for motion in (rec, motions.sine_pulse(G, 1.5)):
        scales = [1.0, 1.0, 1.0, 1.0] if motion.kind == "record" else [0.3, 0.25, 0.45, 0.35]
        S = simulate_stack_batch(models, motion, scales=scales)
        S2 = simulate_stack_batch(np.array([m.kernel_vector() for m in models]), motion, scales=scales)
        assert np.array_equal(S, S2, equal_nan=True)
        for i, m in enumerate(models):
            r = simulate_stack(m, motion.scaled(scales[i]) if motion.kind != "record" else motion)
            row = S[i]
            assert row[SK.S_TMOD2] == r.statue.theta_max_over_delta
            assert row[SK.S_TMOD1] == r.pedestal.theta_max_over_delta
            assert row[SK.S_N_IMP2] == r.statue.n_impacts and row[SK.S_N_IMP1] == r.pedestal.n_impacts
            assert SK.OUTCOMES[int(row[SK.S_OUTCOME])] == r.outcome
            assert row[SK.S_T_FINAL] == r.stats["t_final"] and row[SK.S_N_STEPS] == r.stats["n_steps"]
            t_up = r.statue.uplift_time
            assert (np.isnan(row[SK.S_T_UPLIFT2]) and t_up is None) or row[SK.S_T_UPLIFT2] == t_up
    # a record's scale is its gain: the same as the scaled record to rounding
    S = simulate_stack_batch([TALL], rec, scales=[0.8])
    r = simulate_stack(TALL, rec.scaled(0.8))
    assert SK.OUTCOMES[int(S[0, SK.S_OUTCOME])] == r.outcome
    assert S[0, SK.S_TMOD1] == pytest.approx(r.pedestal.theta_max_over_delta, rel=1e-6)


def test_inputs_are_checked():
    model = StackModel(STATUE, Pedestal(0.3, 0.5, 100.0))
    with pytest.raises(InputError, match="method"):
        simulate_stack(model, motions.free(), method="euler")
    with pytest.raises(InputError, match="overturning angle"):
        simulate_stack(model, motions.free(), theta0=(0.0, 0.3))
    with pytest.raises(InputError, match="columns"):
        simulate_stack_batch(np.zeros((2, 3)), motions.free())
    with pytest.raises(InputError, match="StackModel"):
        simulate_stack_batch([1.0], motions.free())


def test_no_body_passes_its_overturning_angle_without_overturning():
    """A regression (found by the 2D/3D stack classification, issue [22]): an impact of one contact that drove the
    other, open at its closing point, into its pivot left the body rocking about the pivot it had passed (its
    impact event started on the wrong side and never fired): the statue then 'rotated' to 50 delta without
    overturning, and the stack was said to overturn. A body's peak theta / delta stays <= 1 unless it overturned,
    on 40 records (compiled) and 3 of those that failed (scipy)."""
    p = RockingParams(m=407.37, h=0.7316, b_L=0.3094, b_R=0.2026, I_G=98.3)     # the default scan, about
    m = StackModel(p, Pedestal.box(0.6, 0.7, 1.0, 250.0), x2=(p.b_L - p.b_R) / 2)
    bad = []
    for method, seeds in (("compiled", range(1, 41)), ("scipy", (2, 4, 9))):
        for seed in seeds:
            r = simulate_stack(m, motions.synthetic_record(duration=20, dt=0.01, pga=0.3 * G, seed=seed), method=method)
            bad += [(method, seed, name, b.theta_max_over_delta) for name, b in (("statue", r.statue),
                    ("pedestal", r.pedestal)) if not b.overturned and b.theta_max_over_delta > 1 + 1e-6]
    assert not bad
