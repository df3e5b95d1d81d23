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


# -- issue [23], item 1: what the 3D scenes skip must not change what they report -------------------

def test_record_acceleration_on_arrays_is_the_compiled_ground_motion_bit_for_bit():
    """GroundMotion.acc of a record (numpy, whole arrays) against the compiled kernel (ground_acc, a call a
    point) at every sample time, just below each, between, and outside the record."""
    from statue2model.hazard import motion_kernel as MK
    m = motions.parse_spec("synthetic:duration=3,pga=0.3g,seed=4")[0]
    for start in (0.0, 0.37):
        r = motions.record(m.samples, m.dt, start=start)
        ts = r.start + r.dt * np.arange(len(r.samples))
        t = np.concatenate([np.linspace(-0.1, r.end + 0.1, 5001), ts, np.nextafter(ts, -np.inf),
                            np.nextafter(ts, np.inf)])
        kind, M, samples = r.kernel_args()
        compiled = np.array([MK.ground_acc(x, kind, M, samples) for x in t])
        assert np.array_equal(r.acc(t), compiled)
        assert r.acc(float(t[7])) == compiled[7]                      # a scalar time too


def test_contact_patch_touches_the_floor_where_the_hull_does():
    """Tilted by less than the patch's tilt about any horizontal axis, the lowest point of the patch is the
    lowest point of the hull (the floor meets the same vertex); the patch is inside the hull and smaller."""
    from statue2model.crosscheck.statue_scene import PATCH_TILT, contact_patch, landing_angles

    rng = np.random.default_rng(3)
    # a tall body whose upper vertices overhang the base on +x: an arm at 0.3 m height, 0.25 m out
    base = np.array([[-0.1, -0.1, 0], [0.1, -0.1, 0], [0.1, 0.1, 0], [-0.1, 0.1, 0]], float)
    ring = [[0.08 * np.cos(a), 0.08 * np.sin(a), z] for a in np.linspace(0, 2 * np.pi, 20, endpoint=False)
            for z in (0.5, 1.0, 1.5)]
    hull = np.vstack([base, ring, [[0.35, 0.0, 0.3], [0.35, 0.02, 0.32]]])
    sc = StatueScene.block(b=0.1, h=0.75, m=50.0)
    from dataclasses import replace
    sc = replace(sc, hull=hull)
    ang = landing_angles(hull)
    assert ang[-2] == pytest.approx(np.arctan2(0.3, 0.25))
    tilt = PATCH_TILT * max(sc.params.delta_L, sc.params.delta_R)
    patch = contact_patch(sc)
    assert len(patch) < len(hull) / 2 and len(patch) >= 5
    assert ang[-1] > tilt and not any(np.array_equal(v, hull[-1]) for v in patch)    # not extreme: left out
    assert any(np.array_equal(v, hull[-2]) for v in patch)                         # the hull's largest x
    for _ in range(300):
        axis = np.array([*rng.normal(size=2), 0.0])
        axis /= np.linalg.norm(axis)
        phi = rng.uniform(0, 0.999 * tilt)
        K = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
        R = np.eye(3) + np.sin(phi) * K + (1 - np.cos(phi)) * K @ K
        assert (patch @ R.T)[:, 2].min() == pytest.approx((hull @ R.T)[:, 2].min(), abs=1e-12)


def test_unloading_read_only_above_the_gate_gives_the_same_time(monkeypatch):
    """The contacts read from UNLOAD_GATE x the least uplift acceleration on, or at every step: the same
    unloading time (a one-sine pulse that lifts the block)."""
    from statue2model.crosscheck import statue_scene as S

    blk = StatueScene.block(b=0.1, h=0.5, m=100.0)
    m = motions.sine_pulse(1.5 * 9.80665 * 0.1 / 0.5, 2.0)
    s = SimSettings(dt=1e-3)
    a = simulate_statue(blk, m, t_end=0.8, settings=s)
    monkeypatch.setattr(S, "UNLOAD_GATE", 0.0)
    b = simulate_statue(blk, m, t_end=0.8, settings=s)
    assert a.unload_time is not None and a.unload_time > 0.05
    assert a.unload_time == b.unload_time
    assert np.array_equal(a.theta, b.theta)
