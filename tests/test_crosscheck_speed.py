"""The statue scene's fast path (issue 16, item 8): a reused PyBullet client gives the same run as a
fresh one, and the lift-off read from the stored heights follows the step-by-step rule."""
import numpy as np
import pytest

pytest.importorskip("pybullet")

from statue2model.crosscheck import world as W
from statue2model.crosscheck.statue_scene import (
    LIFT_HEIGHT,
    LIFT_STEPS,
    StatueScene,
    _lift_off_time,
    simulate_statue,
)
from statue2model.crosscheck.world import SimSettings
from statue2model.hazard import motions


def test_reused_client_gives_the_same_run(monkeypatch):
    blk = StatueScene.block(b=0.1, h=0.5, m=100.0)
    m = motions.sine_pulse(4.0, 3.0)
    s = SimSettings(dt=1e-3)
    a = simulate_statue(blk, m, t_end=0.6, settings=s, dt_out=s.dt)
    b = simulate_statue(blk, m, t_end=0.6, settings=s, dt_out=s.dt)       # on the client a left
    monkeypatch.setattr(W, "MAX_IDLE_CLIENTS", 0)
    W._IDLE.clear()
    c = simulate_statue(blk, m, t_end=0.6, settings=s, dt_out=s.dt)       # a fresh client
    assert a.uplift_time is not None and a.theta_max_R > 1e-3
    for r in (b, c):
        assert np.array_equal(r.theta, a.theta) and np.array_equal(r.yaw, a.yaw)
        assert (r.uplift_time, r.unload_time, r.max_pivot_slip) == (a.uplift_time, a.unload_time, a.max_pivot_slip)


def _lift_off_loop(lift, dt):
    """The step-by-step rule simulate_statue used to apply during the run."""
    run, t0, prev = 0, None, lift[0]
    for k in range(1, len(lift)):
        if lift[k] > LIFT_HEIGHT:
            if run == 0:
                t0 = k * dt - dt * (lift[k] - LIFT_HEIGHT) / (lift[k] - prev) if lift[k] > prev else k * dt
            run += 1
            if run >= LIFT_STEPS:
                return t0
        else:
            run = 0
        prev = lift[k]
    return None


def test_lift_off_time_matches_the_step_rule():
    rng = np.random.default_rng(3)
    dt = 1e-3
    short = [0.0] + [3e-4] * (LIFT_STEPS - 1) + [0.0] * 5 + [1e-4, 5e-4] + [6e-4] * LIFT_STEPS
    assert _lift_off_time(np.array(short), dt) == pytest.approx(_lift_off_loop(short, dt))
    assert _lift_off_time(np.array(short), dt) == pytest.approx((LIFT_STEPS + 5 + 1) * dt - dt * 3e-4 / 4e-4)
    assert _lift_off_time(np.array([0.0] + [3e-4] * (LIFT_STEPS - 1)), dt) is None
    for _ in range(200):
        lift = rng.uniform(0, 4e-4, rng.integers(2, 40))
        got, want = _lift_off_time(lift, dt), _lift_off_loop(list(lift), dt)
        assert (got is None) == (want is None) and (got is None or got == pytest.approx(want, abs=1e-15))
