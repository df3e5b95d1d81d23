"""The isolated classification (crosscheck/isolated_runs.py, set_classification.py) and the exact isolator
scene's statue readings (pendulum_scene: mount 'rigid', lift-off and slip relative to the plate).

A rectangular block (b 0.1 m, h 0.5 m, 100 kg: lifts at g b / h = 0.2 g on a fixed base) on a stiff
isolator (R_hat 0.3 m, T 1.10 s, capacity 30 mm), 8 short records x 2 levels: 16 runs of ~0.05 s each."""
from __future__ import annotations

import json
import math
from dataclasses import replace

import numpy as np
import pytest

pytest.importorskip("pybullet")

from statue2model.compute.executors import SerialExecutor  # noqa: E402
from statue2model.crosscheck import classification as cl  # noqa: E402
from statue2model.crosscheck.isolated_runs import Coupled2D, isolator_2d, outcome_3d_isolated  # noqa: E402
from statue2model.crosscheck.pendulum_scene import PendulumIsolator, simulate_pendulum  # noqa: E402
from statue2model.crosscheck.restitution import user_model  # noqa: E402
from statue2model.crosscheck.statue_scene import StatueScene  # noqa: E402
from statue2model.hazard import motions  # noqa: E402
from statue2model.quantities import G  # noqa: E402


@pytest.fixture(scope="module")
def block():
    return StatueScene.block(b=0.1, h=0.5, m=100.0)


@pytest.fixture(scope="module")
def recs():
    from statue2model.crosscheck.ensemble import records

    return records(8, durations=(2.0, 3.0))


def _iso(block, mu=0.01, cap=0.03):
    return PendulumIsolator(R_hat=0.3, mu=mu, m_o=20.0, capacity=cap, side=0.6, statue=block)


def test_pendulum_knows_its_device_and_mass(block):
    iso = _iso(block)
    assert iso.R == pytest.approx(0.15 + 0.0095) and iso.M == pytest.approx(120.0)
    d = iso.to_dict()
    assert d["statue_mass"] == pytest.approx(100.0) and "statue" not in d and d["model"] == "pendulum"
    two = isolator_2d(iso)
    assert two.R_hat == pytest.approx(0.3) and two.M == pytest.approx(120.0) and two.capacity == 0.03


def test_rigid_mount_is_the_plate_carrying_the_statue_mass(block):
    """mount='rigid': the statue's mass joins the plate (what the 2D plate model assumes): the same run as
    a plate of m_o + m, to the engine's round-off."""
    m = motions.synthetic_record(duration=2.0, pga=0.15 * G, seed=3)
    iso = _iso(block, cap=None)
    rigid = simulate_pendulum(iso, m, block, t_end=2.5, mount="rigid")
    heavy = simulate_pendulum(replace(iso, m_o=120.0, statue=None), m, None, t_end=2.5)
    assert rigid.theta is None and np.allclose(rigid.u, heavy.u, atol=1e-9, rtol=0)
    from statue2model.isolator.time_history import simulate as plate_2d      # and both are the 2D plate

    r2 = plate_2d(isolator_2d(iso), m, t_end=2.5, dt_out=5e-3)
    assert rigid.u_max == pytest.approx(r2.u_max, rel=0.01)
    with pytest.raises(Exception, match="mount"):
        simulate_pendulum(iso, m, block, t_end=0.1, mount="glued")


def test_statue_lift_off_is_read_relative_to_the_plate(block):
    """A plate held by friction (mu 0.5: it never slides below 0.5 g) carries the block as a fixed base:
    a 0.3 g one-sine pulse lifts it (0.2 g needed), a 0.1 g one does not; the plate's own rise never
    reads as lift-off."""
    iso = _iso(block, mu=0.5, cap=None)
    lifted = outcome_3d_isolated((iso, motions.sine_pulse(0.3 * G, 2.0), None, None, 1.0))
    still = outcome_3d_isolated((iso, motions.sine_pulse(0.1 * G, 2.0), None, None, 1.0))
    assert lifted["uplift"] and lifted["max_lift"] > 2e-4 and not lifted["capacity"]
    assert not still["uplift"] and still["max_lift"] < 2e-4 and still["peak"] < 0.01
    assert math.isfinite(still["slip"]) and still["slip"] < 1e-3


def test_a_moving_plate_never_reads_as_lift_off():
    """A squat block (b 0.3 m, h 0.5 m: lifts at 0.6 g) on a free-rolling plate (mu 0.005) under a 0.3 g
    record: the plate travels and rises (its rise is 10 x the lift-off height), the block stays on it."""
    from statue2model.crosscheck.statue_scene import LIFT_HEIGHT

    squat = StatueScene.block(b=0.3, h=0.5, m=100.0)
    iso = PendulumIsolator(R_hat=0.3, mu=0.005, m_o=20.0, side=0.9, statue=squat)
    r = simulate_pendulum(iso, motions.synthetic_record(duration=4.0, pga=0.3 * G, seed=1), squat, t_end=4.5)
    assert r.u_max > 0.05 and r.z.max() > 10 * LIFT_HEIGHT
    assert r.max_lift < LIFT_HEIGHT and r.uplift_time is None and r.finite


def test_isolated_uplift_a_wrong_alpha_fails(block, recs):
    """A plate held until mu g = 0.12 g carries the block (lifts at 0.2 g) into rocking at 3-5 m/s^2: the
    right 2D model classifies uplift like 3D in at least 15 of 16 runs; alpha 0.6 (lifts at 0.12 g) says
    yes where 3D says no in >= 10 runs: disagreement shown, and the why quotes the plate's acceleration."""
    from statue2model.rocking.model import RockingModel

    iso = _iso(block, mu=0.12, cap=0.05)
    kw = dict(levels=(3.0, 5.0), free_time=1.0, base="isolated", run_2d=Coupled2D(isolator_2d(iso)))
    right = cl.classify_ensemble(iso, user_model(block), recs, executor=SerialExecutor(), run_3d=outcome_3d_isolated,
                                 **kw)
    u = right.states["full_contact"]
    assert u.tp >= 3 and u.fp + u.fn <= 1, right.table()
    wrong = cl.classify_ensemble(iso, RockingModel.imperfect(block.params, 0.6, 0.6), recs, reuse_3d=right, **kw)
    w = wrong.states["full_contact"]
    assert w.status == "missed" and w.fp >= 10 and "disagreement shown" in w.why
    assert "the plate's peak absolute acceleration 2D" in wrong.table()


def test_isolated_capacity_agrees_and_a_wrong_capacity_fails(block, recs):
    """The right 2D device classifies the capacity like the 3D scene in all 16 runs (rule met); a 2D
    device with twice the capacity misses the runs that pass 30 mm in 3D (recall < 0.5 shown or not
    shown, missed either way) - the check can fail."""
    iso = _iso(block)
    kw = dict(levels=(1.5, 3.0), free_time=1.0, base="isolated")
    right = cl.classify_ensemble(iso, user_model(block), recs, executor=SerialExecutor(),
                                 run_2d=Coupled2D(isolator_2d(iso)), run_3d=outcome_3d_isolated, **kw)
    c = right.states["capacity"]
    assert c.status == "met" and c.tp >= 5 and c.fp == c.fn == 0, right.table()
    assert right.fragility["capacity"]["ratio_3d_2d"] == pytest.approx(1.0, rel=0.05)
    wrong = cl.classify_ensemble(iso, user_model(block), recs, reuse_3d=right,
                                 run_2d=Coupled2D(replace(isolator_2d(iso), capacity=0.06)), **kw)
    w = wrong.states["capacity"]
    assert w.status == "missed" and w.fn >= 3 and "3D reaches the capacity, 2D does not" in wrong.table()
    assert "peak plate travel 2D" in wrong.table()


def test_budget_too_small_skips_and_says_why(block, recs):
    """One timed 3D run per base gives the estimate; a budget under the quick levels' estimate runs nothing
    and says so; the quick levels cost less than the full ones (3 vs 5 factors per median)."""
    from statue2model.crosscheck.set_classification import QUICK_FACTORS, classify_design_set

    sc = classify_design_set(block, user_model(block), recs, [(2.0, "uplift"), (6.0, "overturn")],
                             iso_scene=_iso(block), anchors_isolated=[(2.5, "capacity")], executor=SerialExecutor(),
                             free_time=1.0, budget_s=1e-3)
    assert sc.fixed is None and sc.isolated is None and not sc.met
    assert "over the budget of 0.001 s" in sc.skipped and "ensemble_budget" in sc.skipped
    est = sc.budget["estimate_s"]
    full, quick = est["0.5,0.8,1,1.25,2"], est[",".join(f"{f:g}" for f in QUICK_FACTORS)]
    assert 0 < quick < full and set(sc.budget["wall_per_simulated_s"]) == {"fixed", "isolated"}
    assert json.dumps(sc.to_dict(), allow_nan=False)
