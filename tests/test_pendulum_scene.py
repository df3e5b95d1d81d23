"""The pendulum isolator scene (crosscheck.pendulum_scene) against hand values (MODEL.md sec. 4)
and against the ball scene."""
import math

import numpy as np
import pytest

pytest.importorskip("pybullet")

from statue2model.crosscheck.pendulum_scene import PendulumIsolator, simulate_pendulum  # noqa: E402
from statue2model.crosscheck.world import SimSettings  # noqa: E402
from statue2model.errors import InputError  # noqa: E402
from statue2model.hazard import motions  # noqa: E402

G = 9.80665
R_HAT = 2 * (0.30 - 0.0095)          # 0.581 m: MODEL.md sec. 4, T = 1.53 s
T_HAND = 2 * math.pi * math.sqrt(R_HAT / G)
U0 = 0.05


def _free(mu, cycles=3.1, settings=None):
    iso = PendulumIsolator(R_hat=R_HAT, mu=mu, m_o=50.0)
    return iso, simulate_pendulum(iso, motions.free(), None, settings or SimSettings(dt=1e-3), u0=U0,
                                  t_end=cycles * T_HAND, dt_out=1e-3)


@pytest.fixture(scope="module")
def free0():
    return _free(0.0)


def test_hand_period_value():
    assert T_HAND == pytest.approx(1.529, abs=2e-3)          # MODEL.md: T = 1.53 s


def test_free_vibration_period_and_energy(free0):
    iso, r = free0
    up = r.peaks_t[r.peaks_u > 0]                            # maxima: t = T, 2T, 3T
    assert up.size >= 3
    periods = np.diff(np.concatenate([[0.0], up]))
    assert np.all(np.abs(periods / T_HAND - 1) < 0.01)
    # energy: kinetic (central differences) + potential m g z, kept within 1 % over 3 cycles
    v = np.gradient(r.u, r.t)
    E = 0.5 * v**2 + G * r.z
    E0 = G * (R_HAT - math.sqrt(R_HAT**2 - U0**2))
    assert np.all(np.abs(E[1:-1] / E0 - 1) < 0.01)
    assert np.all(np.abs(np.abs(r.peaks_u) / U0 - 1) < 0.01)


def test_plate_level_and_rise(free0):
    iso, r = free0
    assert r.tilt_max < 1e-6
    rise = R_HAT - np.sqrt(R_HAT**2 - r.u**2 - r.uy**2)     # R_hat (1 - cos phi)
    assert np.max(np.abs(r.z - rise)) <= 1e-4 * rise.max()
    assert r.z.max() == pytest.approx(R_HAT - math.sqrt(R_HAT**2 - U0**2), rel=1e-3)
    assert np.all(np.abs(r.N / (50.0 * G) - 1) < 0.02)       # N = m_o (g + z''), z'' <= v^2 / R_hat


def test_friction_decay_per_cycle():
    mu = 0.005
    iso, r = _free(mu, cycles=2.1)
    up = r.peaks_u[r.peaks_u > 0]
    decay = np.diff(np.concatenate([[U0], up]))              # eq. 51: u_j - u_{j+2} = 4 mu g / omega^2
    assert up.size >= 2
    assert np.all(np.abs(-decay / (4 * mu * R_HAT) - 1) < 0.05)


def test_capacity_stop():
    iso = PendulumIsolator(R_hat=R_HAT, mu=0.0, m_o=50.0, capacity=0.04)
    m = motions.sine_pulse(3.0, 1.0)
    r = simulate_pendulum(iso, m, None, SimSettings(dt=2e-3), t_end=3.0)
    assert r.outcome == "isolator capacity exceeded"
    assert abs(r.u_at_capacity) > 0.04 and abs(r.u_at_capacity) < 0.041
    assert r.t[-1] == pytest.approx(r.t_capacity) and r.t_capacity < 3.0
    assert r.to_dict()["capacity_exceeded"] is True


def test_from_design_and_bad_input():
    iso = PendulumIsolator.from_design({"R": 2.0, "r": 0.025, "mu": 0.0073, "m_o": 16.1, "capacity": 0.35,
                                        "side": 0.9, "thickness": 0.03})
    assert iso.R_hat == pytest.approx(3.95) and iso.capacity == 0.35 and iso.m_o == 16.1
    with pytest.raises(InputError, match="not an isolator design"):
        PendulumIsolator.from_design({"R": 2.0})
    with pytest.raises(InputError, match="mu"):
        PendulumIsolator(R_hat=0.5, mu=-0.1, m_o=1.0)


def test_agrees_with_ball_scene():
    """Free vibration, one cycle (the ball lattice scene, ~1 s): period within 1 %,
    decay of the first cycle within 5 % of the pendulum scene's."""
    from statue2model.crosscheck.isolator_scene import IsolatorScene, simulate_isolator

    mu = 0.005
    ball = IsolatorScene.simple(R=0.30, r=0.0095, mu=mu, m_o=50.0, travel=0.05)
    pend = PendulumIsolator(R_hat=ball.R_hat, mu=mu, m_o=50.0)
    t_end = 1.05 * T_HAND
    rb = simulate_isolator(ball, motions.free(), u0=U0, t_end=t_end, dt_out=1e-3)
    rp = simulate_pendulum(pend, motions.free(), None, SimSettings(), u0=U0, t_end=t_end, dt_out=1e-3)
    tb, tp = rb.peaks_t[rb.peaks_u > 0][0], rp.peaks_t[rp.peaks_u > 0][0]
    assert tb == pytest.approx(tp, rel=0.01)
    db, dp = U0 - rb.peaks_u[rb.peaks_u > 0][0], U0 - rp.peaks_u[rp.peaks_u > 0][0]
    assert db == pytest.approx(dp, rel=0.05)


def test_a_record_matches_the_2d_plate_model():
    """Under a record the exact-kinematics plate is the 2D plate model (isolator/time_history: the same
    translating pendulum with Coulomb friction mu W): peak travel within 1 %, peak absolute acceleration
    low-passed at 20 Hz within 2 % (measured 0.1 % and 0.3 % on the default design; the ball scenes'
    facet contact is 27-87 % off in acceleration, benchmarks/bench_pendulum_scene.py)."""
    from statue2model.crosscheck.isolator_cases import lowpass
    from statue2model.isolator.device import Isolator
    from statue2model.isolator.time_history import simulate as plate_2d

    m = motions.synthetic_record(duration=4.0, pga=0.1 * G, seed=1)
    iso2 = Isolator(R=0.30, r=0.0095, M=50.0, mu=0.01)
    r2 = plate_2d(iso2, m, t_end=4.5, dt_out=5e-4)
    dt = 2e-3
    r3 = simulate_pendulum(PendulumIsolator(R_hat=R_HAT, mu=0.01, m_o=50.0), m, None, SimSettings(dt=dt), t_end=4.5,
                           stop_at_capacity=False)
    assert r3.u_max == pytest.approx(r2.u_max, rel=0.01)
    a2 = float(np.abs(lowpass(r2.acc_abs, 5e-4)).max())
    a3 = float(np.abs(lowpass(r3.acc_step, dt)).max())
    assert a3 == pytest.approx(a2, rel=0.02)


def test_agrees_with_ball_scene_on_a_record():
    """Under a record (4 s at 0.2 g, seed 1; plate alone, 50 kg on four 9.5 mm balls - 0.2 % of the plate's
    mass, which the pendulum leaves out) the ball scene on tangent tiles (1 r, dt 0.5 ms, 50 solver iterations:
    ~0.7 s CPU) and the pendulum scene agree: peak travel within 5 %, peak plate acceleration low-passed at
    20 Hz within 10 % (the issue's tolerances). Measured 0.973 and 1.005; converged tiles (dt 0.25 ms, 200
    iterations) 0.991 and 0.979; the 4 mm lattice 0.984 and 0.942 (2.8 s CPU). At 0.1 g (15 mm travel, under
    two tiles) the tiles' staircase restoring force shows: converged 1.047 and 1.167."""
    from statue2model.crosscheck.isolator_cases import lowpass
    from statue2model.crosscheck.isolator_scene import IsolatorScene, simulate_isolator

    mu, dt = 0.01, 5e-4
    m = motions.synthetic_record(duration=4.0, pga=0.2 * G, seed=1)
    ball = IsolatorScene.simple(R=0.30, r=0.0095, mu=mu, m_o=50.0, travel=0.05, groove="tiles")
    rb = simulate_isolator(ball, m, t_end=4.5, settings=SimSettings(dt=dt, solver_iterations=50),
                           stop_at_capacity=False)
    rp = simulate_pendulum(PendulumIsolator(R_hat=ball.R_hat, mu=mu, m_o=50.0), m, None, SimSettings(dt=dt),
                           t_end=4.5, stop_at_capacity=False)
    assert rb.outcome == "ok" and rp.outcome == "ok"
    assert rp.u_max > 0.03                                  # a record that moves the plate over several tiles
    assert rb.u_max == pytest.approx(rp.u_max, rel=0.05)
    ab = float(np.abs(lowpass(rb.acc_step, dt)).max())
    ap = float(np.abs(lowpass(rp.acc_step, dt)).max())
    assert ab == pytest.approx(ap, rel=0.10)
