"""Property-based tests of the 2D rocking engine (hypothesis) over wide input ranges.

Bodies are built from h and b = h tan(delta), delta in [0.01, 0.7] per side
(asymmetric allowed); alpha in [0.05, 1]; theta_L / theta_R from 1e-9 rad to
ten times delta; e in [0, 1] (constants or tables; 0 and 1 drawn often);
linearised now and then; pulses up to 5 g (some just above the uplift limit),
seeded records up to 60 s and 5 g; FREE_TAIL s simulated after the motion.

(a) a run ends: no exception, no hang (a step budget and the deadline bound it);
(b) free motion with impacts that cannot add energy (e_side <= sqrt(I_old / I_new)):
    the mechanical energy of the model never increases along the sampled history;
(c) |theta| <= delta_side everywhere (maxima, peaks, history) unless overturned;
(d) the results do not depend on the output sampling (dt_out None / 0.01 / 0.0037);
(e) a motion that never exceeds the uplift limits (often touching them exactly) does
    not lift a body at rest, through simulate() and through the batch kernel (the
    sweeps skip such rows, but the kernel must not need that).
Also: results are internally consistent (impact records, overturning side at delta,
sampled history within the maxima to 10 rtol delta).

Examples are derandomised (reproducible in CI); ``pytest -s`` prints how many ran.

Engine bugs found with these properties are pinned at the end of this file as
minimal reproducers (``test_regression_*``); all are fixed.
"""
from __future__ import annotations

import math
import time

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from statue2model.hazard import motions
from statue2model.rocking import RockingModel, simulate
from statue2model.rocking import kernel as K
from statue2model.rocking.model import Restitution
from statue2model.geometry.rocking_params import RockingParams

G = 9.81
DELTA_TOL = 1e-12          # (c): |theta| may pass delta by rounding only
ENERGY_RTOL = 1e-7         # (b): energy may grow by integration error only, relative to E(0)
FREE_RTOL = 1e-10          # (b): rtol for a swing of delta (see test_free_motion_never_gains_energy)
STEPS_PER_S = 100_000      # (a): step budget per simulated second (plus 200,000): more counts
                           # as a hang. Deterministic, unlike a wall-clock limit. A 1e-9 rad
                           # rolling transition is stiff (omega ~ 1e5 rad/s): with e = 1 the
                           # body chatters in it for good, at ~40,000 steps/s
DEADLINE_MS = 10_000       # (a): per example (three runs), after the warm-up
FREE_TAIL = 5.0            # s simulated after the motion (default 20 s: cost, not coverage)
N_EXAMPLES = {"pulses": 1000, "records": 600, "free": 1000, "quiet": 500}

COUNTS: dict[str, int] = {}


def _settings(name: str):
    return settings(max_examples=N_EXAMPLES[name], deadline=DEADLINE_MS, derandomize=True, database=None,
                    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large,
                                           HealthCheck.filter_too_much])


@pytest.fixture(scope="module", autouse=True)
def warm_up_and_report():
    """Load (or compile) the numba kernel for every motion kind and the batch path
    once, so that no example pays for it; report the examples at the end (-s)."""
    t0 = time.perf_counter()
    body = RockingParams.rectangular_block(0.05, 0.3, 2.0)
    model = RockingModel.imperfect(body, 0.5, 0.5, 0.01, 0.01, e_L=0.9, e_R=0.9)
    for motion in (motions.free(), motions.cosine_pulse(3.0, 2.0), motions.rect_pulse(3.0, 0.2),
                   motions.record(np.array([0.0, 3.0, -3.0, 0.0]), 0.1)):
        for dt_out in (None, 0.1):
            simulate(model, motion, theta0=0.01 if motion.kind == "none" else 0.0, t_end=1.0, dt_out=dt_out)
    _batch_moved(model, motions.cosine_pulse(0.1, 2.0), 1.0)
    t_warm = time.perf_counter() - t0
    t1 = time.perf_counter()
    yield
    print(f"\n[rocking properties] {sum(COUNTS.values())} hypothesis examples in {time.perf_counter() - t1:.1f} s "
          f"(warm-up {t_warm:.1f} s): " + ", ".join(f"{k} {v}" for k, v in sorted(COUNTS.items())))


# --- strategies ------------------------------------------------------------------
@st.composite
def bodies(draw):
    h = draw(st.floats(0.05, 5.0))
    d_R = draw(st.floats(0.01, 0.7))
    d_L = draw(st.one_of(st.just(d_R), st.floats(0.01, 0.7)))
    b_R, b_L = h * math.tan(d_R), h * math.tan(d_L)
    m = draw(st.floats(0.1, 1e4))
    k = draw(st.floats(0.3, 3.0))   # I_G relative to a homogeneous block of the mean width
    return RockingParams(m=m, h=h, b_L=b_L, b_R=b_R, I_G=k * m * ((0.5 * (b_L + b_R)) ** 2 + h * h) / 3.0)


def theta_side(draw, delta):
    kind = draw(st.sampled_from(["tiny", "small", "fraction", "huge"]))
    if kind == "tiny":
        return 1e-9
    if kind == "small":
        return 10.0 ** draw(st.floats(-9.0, -4.0))
    if kind == "fraction":
        return draw(st.floats(1e-3, 1.0)) * delta
    return draw(st.floats(1.0, 10.0, exclude_min=True)) * delta


def restitution(draw, e_max=1.0):
    kind = draw(st.sampled_from(["float", "float", "max", "zero", "table"]))
    if kind == "max":
        return e_max
    if kind == "zero":
        return 0.0
    if kind == "table":
        n = draw(st.integers(2, 4))
        speeds = np.cumsum(draw(st.lists(st.floats(0.01, 2.0), min_size=n, max_size=n)))
        return Restitution.table(speeds, draw(st.lists(st.floats(0.0, e_max), min_size=n, max_size=n)))
    return draw(st.floats(0.0, e_max))


@st.composite
def models(draw, body=None, e_max_L=1.0, e_max_R=1.0):
    p = draw(bodies()) if body is None else body
    linearised = draw(st.integers(0, 4)) == 0
    e_L, e_R = restitution(draw, e_max_L), restitution(draw, e_max_R)
    if draw(st.integers(0, 4)) == 0:
        model = RockingModel.housner(p, e_L=e_L, e_R=e_R, linearised=linearised)
    else:
        model = RockingModel.imperfect(p, draw(st.floats(0.05, 1.0)), draw(st.floats(0.05, 1.0)),
                                       theta_side(draw, p.delta_L), theta_side(draw, p.delta_R),
                                       e_L=e_L, e_R=e_R, linearised=linearised)
    return model


def amplitude(draw, model):
    """Absolute (up to 5 g either way), relative to the uplift limit of the pushed side,
    or just above it (a grazing uplift: the body lifts with almost no energy)."""
    kind = draw(st.sampled_from(["absolute", "relative", "relative", "grazing"]))
    if kind == "absolute":
        return draw(st.floats(-5.0 * G, 5.0 * G))
    sign = draw(st.sampled_from([-1.0, 1.0]))
    limit = model.uplift_limits[0 if sign > 0 else 1]
    factor = 1.0 + 10.0 ** -draw(st.integers(1, 12)) if kind == "grazing" else draw(st.floats(0.5, 4.0))
    return sign * min(factor * limit, 5.0 * G)


@st.composite
def pulses(draw, model):
    kind = draw(st.sampled_from(["cosine", "sine", "sines", "rect"]))
    amp = amplitude(draw, model)
    if kind == "rect":
        return motions.rect_pulse(amp, draw(st.floats(0.005, 2.0)), start=draw(st.sampled_from([0.0, 0.3])))
    freq = draw(st.floats(0.2, 20.0))
    if kind == "cosine":
        return motions.cosine_pulse(amp, freq)
    if kind == "sine":
        return motions.sine_pulse(amp, freq, start=draw(st.sampled_from([0.0, 0.25])))
    return motions.sine_train(amp, freq, draw(st.floats(0.5, 6.0)))


@st.composite
def records(draw, model):
    """Seeded accelerograms up to 60 s and 5 g: white noise, a random walk, or a
    Kanai-Tajimi synthetic record; some scaled to a multiple of the uplift limit."""
    seed = draw(st.integers(0, 2**31 - 1))
    duration = draw(st.floats(10.0, 60.0)) if draw(st.integers(0, 4)) == 0 else draw(st.floats(0.2, 10.0))
    dt = draw(st.sampled_from([0.005, 0.01, 0.02, 0.05]))
    if draw(st.booleans()):
        pga = draw(st.floats(0.01, 5.0)) * G
    else:
        pga = min(draw(st.floats(0.5, 4.0)) * max(model.uplift_limits), 5.0 * G)
    kind = draw(st.sampled_from(["white", "walk", "synthetic"]))
    n = max(round(duration / dt) + 1, 10)
    if kind == "synthetic":
        return motions.synthetic_record(dt * (n - 1), dt, pga, seed=seed)
    x = np.random.default_rng(seed).standard_normal(n)
    if kind == "walk":
        x = np.cumsum(x)
    x -= x.mean()
    x *= pga / np.max(np.abs(x))
    return motions.record(x, dt, start=draw(st.sampled_from([0.0, 0.5])), label=f"{kind} seed {seed}")


# --- the energy of the model (MODEL.md section 2) --------------------------------------
def _i1(q):
    """q sin q + cos q - 1, without cancellation."""
    if q < 1e-2:
        q2 = q * q
        return q2 * (0.5 - q2 / 8.0 + q2 * q2 / 144.0)
    return q * math.sin(q) + math.cos(q) - 1.0


def _i2(q):
    """sin q - q cos q, without cancellation."""
    if q < 1e-2:
        q2 = q * q
        return q * q2 * (1.0 / 3.0 - q2 / 30.0 + q2 * q2 / 840.0)
    return math.sin(q) - q * math.cos(q)


def _f0(q, d, lin):
    """int_0^q sin(d - x) dx (linearised: of d - x)."""
    return q * (d - 0.5 * q) if lin else 2.0 * math.sin(d - 0.5 * q) * math.sin(0.5 * q)


def _f1(q, d, lin):
    """int_0^q x sin(d - x) dx (linearised: x (d - x))."""
    return q * q * (0.5 * d - q / 3.0) if lin else math.sin(d) * _i1(q) - math.cos(d) * _i2(q)


def potential(model: RockingModel, side: int, q: float) -> float:
    """V_s(q) = m g d_s int_0^q alpha_s(x) sin(delta_s - x) dx: the potential of the free
    equation of motion I_s q'' = -m g d_s alpha_s(q) sin(delta_s - q)."""
    p = model.params
    d = p.delta_R if side > 0 else p.delta_L
    a = model.alpha_R if side > 0 else model.alpha_L
    th = (model.theta_R if side > 0 else model.theta_L) if a < 1.0 else 0.0
    mgd = p.m * p.g * (p.d_R if side > 0 else p.d_L)
    lin = model.linearised
    if th <= 0.0:
        return mgd * _f0(q, d, lin)
    if q <= th:
        return mgd * (a * _f0(q, d, lin) + (1.0 - a) / th * _f1(q, d, lin))
    vt = a * _f0(th, d, lin) + (1.0 - a) / th * _f1(th, d, lin)
    return mgd * (vt + _f0(q, d, lin) - _f0(th, d, lin))


def energy(model: RockingModel, theta: float, theta_dot: float) -> float:
    """Mechanical energy, 0 at rest; nan at theta = 0 in motion (at the instant of an
    impact the pivot, hence the inertia, is ambiguous)."""
    if theta == 0.0:
        return 0.0 if theta_dot == 0.0 else math.nan
    p = model.params
    side = 1 if theta > 0 else -1
    return 0.5 * (p.I_R if side > 0 else p.I_L) * theta_dot**2 + potential(model, side, abs(theta))


def test_potential_matches_quadrature():
    """The closed-form potential used by (b), against adaptive quadrature."""
    from scipy import integrate

    body = RockingParams(m=3.0, h=0.4, b_L=0.4 * math.tan(0.3), b_R=0.4 * math.tan(0.12), I_G=0.2)
    for lin in (False, True):
        for th in (1e-9, 1e-4, 0.05, 0.5):
            model = RockingModel.imperfect(body, 0.2, 0.7, th, th, linearised=lin)
            for side, d, a in ((1, body.delta_R, 0.7), (-1, body.delta_L, 0.2)):
                mgd = body.m * body.g * (body.d_R if side > 0 else body.d_L)
                for q in (1e-10, 1e-6, 0.3 * th, th, 0.5 * d, 0.99 * d):
                    def f(x, a=a, th=th, d=d, lin=lin):
                        al = a + (1 - a) * x / th if x < th else 1.0
                        return al * ((d - x) if lin else math.sin(d - x))
                    parts = [(0.0, min(q, th)), (min(q, th), q)]
                    ref = mgd * sum(integrate.quad(f, lo, hi, epsabs=0, epsrel=1e-13, limit=200)[0]
                                    for lo, hi in parts if hi > lo)
                    assert potential(model, side, q) == pytest.approx(ref, rel=1e-10, abs=0)


def _run(model, motion, t_end=None, **kw):
    """simulate() with a step budget that stands for 'no hang'."""
    if t_end is None:
        t_end = motion.end + FREE_TAIL
    return simulate(model, motion, t_end=t_end, max_steps=int(200_000 + STEPS_PER_S * t_end), **kw)


# --- checks --------------------------------------------------------------------------
def _check_result(r, rtol):
    """(c) and the internal consistency of one result."""
    p = r.model.params
    ni = min(r.n_impacts, len(r.impact_times))
    assert len(r.impact_times) == ni and np.all(np.diff(r.impact_times) >= 0)
    assert np.all(r.impact_times <= r.stats["t_final"]) and np.all(r.impact_speeds >= 0)
    if r.overturned:
        side_max = r.theta_max_R if r.overturn_side == "R" else r.theta_max_L
        assert side_max == (p.delta_R if r.overturn_side == "R" else p.delta_L)
        return
    assert r.theta_max_R <= p.delta_R + DELTA_TOL and r.theta_max_L <= p.delta_L + DELTA_TOL
    for v, s in zip(r.peak_values, r.peak_sides):
        assert v <= (p.delta_R if s == "R" else p.delta_L) + DELTA_TOL
    if r.history is not None:
        th, om = r.history["theta"], r.history["theta_dot"]
        assert np.all(np.isfinite(th)) and np.all(np.isfinite(om))
        assert np.all(th <= p.delta_R + DELTA_TOL) and np.all(-th <= p.delta_L + DELTA_TOL)
        # the samples agree with the maxima to the solver's absolute tolerance (rtol delta):
        # the dense output may wiggle inside a step whose end slopes bracket no extremum
        assert np.max(th, initial=0.0) <= r.theta_max_R + 10 * rtol * p.delta_R
        assert np.max(-th, initial=0.0) <= r.theta_max_L + 10 * rtol * p.delta_L


def _same(a, b):
    """(d): every outcome and event of two runs of one problem is identical."""
    assert a.theta_max_L == b.theta_max_L and a.theta_max_R == b.theta_max_R
    assert a.n_impacts == b.n_impacts
    np.testing.assert_array_equal(a.impact_times, b.impact_times)
    np.testing.assert_array_equal(a.impact_speeds, b.impact_speeds)
    np.testing.assert_array_equal(a.peak_values, b.peak_values)
    assert a.overturned == b.overturned and a.overturn_time == b.overturn_time
    assert a.uplift_time == b.uplift_time and a.t_rest == b.t_rest
    assert a.stats["n_steps"] == b.stats["n_steps"]


def _run_three(model, motion, **kw):
    """(a), (c), (d): the same run without output and on two output grids."""
    runs = [_run(model, motion, dt_out=dt, **kw) for dt in (None, 0.01, 0.0037)]
    for r in runs:
        _check_result(r, kw.get("rtol", 1e-8))
    _same(runs[0], runs[1])
    _same(runs[0], runs[2])
    return runs


def _batch_moved(model, motion, t_end) -> bool:
    """Run through the parallel batch kernel (parameter sweeps call it without the
    'quiet' shortcut of simulate()); True if the body lifted."""
    from statue2model.rocking.batch import run_batch

    kind, M, samples = motion.kernel_args()
    S = run_batch(model, model.kernel_vector()[None, :], np.array([kind]), M[None, :], samples,
                  np.array([float(t_end)]))
    return bool(S[0, K.S_MOVED]) or not math.isnan(S[0, K.S_T_UPLIFT])


# --- (a), (c), (d) -------------------------------------------------------------------
@st.composite
def pulse_cases(draw):
    model = draw(models())
    return model, draw(pulses(model))


@st.composite
def record_cases(draw):
    model = draw(models())
    return model, draw(records(model))


@pytest.mark.slow
@_settings("pulses")
@given(pulse_cases())
def test_pulses_end_bounded_and_independent_of_sampling(case):
    model, motion = case
    _run_three(model, motion)
    COUNTS["pulses"] = COUNTS.get("pulses", 0) + 1


@pytest.mark.slow
@_settings("records")
@given(record_cases())
def test_records_end_bounded_and_independent_of_sampling(case):
    model, motion = case
    _run_three(model, motion)
    COUNTS["records"] = COUNTS.get("records", 0) + 1


# --- (b) ---------------------------------------------------------------------------------
@st.composite
def free_cases(draw):
    p = draw(bodies())
    # no impact adds energy: landing on the left edge (after rocking on the right pivot)
    # scales the energy by e_L^2 I_L / I_R, landing on the right edge by e_R^2 I_R / I_L
    e_max_L = min(1.0, math.sqrt(p.I_R / p.I_L))
    e_max_R = min(1.0, math.sqrt(p.I_L / p.I_R))
    model = draw(models(body=p, e_max_L=e_max_L, e_max_R=e_max_R))
    side = draw(st.sampled_from([-1, 1]))
    delta = p.delta_R if side > 0 else p.delta_L
    theta0 = side * draw(st.floats(1e-3, 0.99)) * delta
    omega0 = 0.0
    if draw(st.booleans()):
        omega0 = draw(st.floats(-1.0, 1.0)) * (p.p_R if side > 0 else p.p_L) * delta
    return model, theta0, omega0


@pytest.mark.slow
@_settings("free")
@given(free_cases())
def test_free_motion_never_gains_energy(case):
    model, theta0, omega0 = case
    assert not model.energy_gain_possible
    # The solver's tolerance is absolute, rtol delta (and rtol delta p): a swing of
    # amplitude q is integrated to a relative rtol delta / q, so its energy drifts by
    # that much per flight (with the default rtol 1e-8, ~1e-7 E(0) in one flight).
    # Scale rtol with the amplitude so that 1e-7 E(0) stays well above the drift.
    # With e at its no-gain bound the drift accumulates over the flights (one step
    # each, whatever rtol: the impact state comes from the dense output), hence an
    # allowance growing with the impacts already made.
    p = model.params
    delta, pp = (p.delta_R, p.p_R) if theta0 > 0 else (p.delta_L, p.p_L)
    rtol = FREE_RTOL * min(1.0, max(abs(theta0), abs(omega0) / pp) / delta)
    r = _run_three(model, motions.free(), theta0=theta0, omega0=omega0, t_end=8.0, rtol=rtol)[2]
    h = r.history
    E0 = energy(model, theta0, omega0)
    E = np.array([energy(model, a, b) for a, b in zip(h["theta"], h["theta_dot"])])
    assert E[0] == pytest.approx(E0, rel=1e-12)
    ok = ~np.isnan(E)
    E, t, th, phase = E[ok], h["t"][ok], h["theta"][ok], h["phase"][ok]
    excess = (E - np.minimum.accumulate(E)) / E0
    n_before = np.searchsorted(r.impact_times, t, side="right")
    k = int(np.argmax(excess / (1.0 + n_before / 10.0)))
    assert excess[k] <= ENERGY_RTOL * (1.0 + n_before[k] / 10.0), (
        f"energy grows by {excess[k]:.3g} E0 at t = {t[k]:.6g} s (theta = {th[k]:.6g}, phase {phase[k]}; "
        f"{n_before[k]} impacts before)")
    COUNTS["free"] = COUNTS.get("free", 0) + 1


# --- (e) ---------------------------------------------------------------------------------
@st.composite
def quiet_cases(draw):
    """Motions whose extremes reach at most the uplift limits (often exactly)."""
    model = draw(models())
    up, dn = model.uplift_limits
    frac_up = draw(st.one_of(st.just(1.0), st.floats(0.0, 1.0)))
    frac_dn = draw(st.one_of(st.just(1.0), st.floats(0.0, 1.0)))
    kind = draw(st.sampled_from(["cosine", "sine", "sines", "rect", "record"]))
    if kind == "record":
        seed = draw(st.integers(0, 2**31 - 1))
        x = np.random.default_rng(seed).standard_normal(draw(st.integers(10, 3000)))
        x = np.where(x > 0, x / x.max() * frac_up * up, x / -x.min() * frac_dn * dn)
        return model, motions.record(x, draw(st.sampled_from([0.005, 0.01, 0.02])))
    if kind == "rect":
        amp = frac_up * up if draw(st.booleans()) else -frac_dn * dn
        return model, motions.rect_pulse(amp, draw(st.floats(0.01, 3.0)))
    amp = min(frac_up * up, frac_dn * dn)
    freq = draw(st.floats(0.2, 20.0))
    if kind == "cosine":
        return model, motions.cosine_pulse(amp, freq)
    if kind == "sine":
        return model, motions.sine_pulse(amp, freq)
    return model, motions.sine_train(amp, freq, draw(st.floats(0.5, 6.0)))


@pytest.mark.slow
@_settings("quiet")
@given(quiet_cases())
def test_motion_below_the_uplift_limits_never_lifts(case):
    model, motion = case
    hi, lo = motion.extremes()
    up, dn = model.uplift_limits
    assert hi <= up and lo >= -dn
    r = simulate(model, motion, dt_out=0.01)
    assert r.uplift_time is None and r.n_impacts == 0 and r.theta_max_L == r.theta_max_R == 0.0
    # a body whose uplift needs more than mu_static g slides above mu_static g: not 'no motion'
    slides = model.slides_first and max(hi, -lo) > model.mu_static * model.params.g
    assert r.applicable == (not slides)
    assert r.outcome == ("not applicable (slides before it rocks)" if slides else "no motion")
    assert not np.any(r.history["theta"]) and not np.any(r.history["theta_dot"])
    assert not np.any(r.history["phase"])
    assert not _batch_moved(model, motion, motion.end + 1.0)
    COUNTS["quiet"] = COUNTS.get("quiet", 0) + 1


# --- engine bugs found by the properties above: minimal reproducers -------------------------
BLOCK = RockingParams.rectangular_block(0.05, 0.3, 2.0)   # delta = 0.165, a = 1.635 m/s^2


def test_regression_uplift_at_a_limit_that_is_only_touched():
    """Open (found by (e)). A record sample equal to the uplift limit, reached on a
    rising segment, lifts the body: _first_exceedance now requires u(tb) > up, but
    u(tb) = c0 + c1 (tb - t0) rounds one ulp above the sample (tb - t0 = dt + 4e-18).
    simulate() reports uplift at the touch (0.035 s) instead of the real exceedance
    (0.1475 s, on the other side) and 2 uplifts instead of 1; the batch kernel lifts
    the body under a motion that never exceeds the limits (the sweeps now skip such
    rows, which hides it there)."""
    model = RockingModel.housner(BLOCK, e_L=0.5, e_R=0.5)
    lim = model.uplift_limits[0]
    x = np.zeros(41)
    x[7] = lim            # touches +limit at t = 0.035 s
    x[30] = -2.0 * lim    # exceeds -limit from t = 0.1475 s
    r = simulate(model, motions.record(x, 0.005))
    assert r.uplift_time == pytest.approx(0.1475, abs=1e-12) and r.stats["n_uplifts"] == 1
    touch = np.zeros(9)
    touch[7] = lim
    assert not _batch_moved(model, motions.record(touch, 0.005), 1.0)


@pytest.mark.parametrize("excess", [1e-6, 1e-9])
def test_regression_grazing_uplift_with_e_1_never_ends(excess):
    """Open (found by (a) and the stress script). A pulse just above the uplift limit
    lifts the body with almost no energy; with e = 1 nothing is lost at the impacts, so
    the body chatters about theta = 0 with |theta'| ~ 1e-20 rad/s and ever shorter
    flights (the Zeno sum is only taken for e < 1). excess 1e-6: 2e7 steps reach
    t = 5e-4 s, then RuntimeError after ~1 min; excess 1e-9: 'made no progress at
    t = 1.46e-05 s'. Motion that small is rest (rest_tol delta), whatever e."""
    model = RockingModel.housner(BLOCK, e_L=1.0, e_R=1.0)
    motion = motions.cosine_pulse(-(1.0 + excess) * model.uplift_limits[1], 2.0)
    r = simulate(model, motion, max_steps=300_000)
    assert r.stats["t_final"] == r.t_end and not r.overturned


def test_regression_extremum_inside_a_step_is_missed():
    """Open (found by the history-vs-maxima check of (c)). Along a record the ground
    acceleration is linear in each sample interval, so theta' can change sign twice
    inside one step (a maximum, then a minimum). Both end slopes then have the same
    sign and the peak is not seen: theta_max_R = 4.76214e-4 rad at any rtol, whereas
    the engine's own history (dt_out 1e-4) reaches 4.76432e-4 at t = 0.1963 s and the
    solve_ivp reference (simulate_scipy, rtol 1e-12) gives 4.764319e-4."""
    body = RockingParams(m=1.0, h=5.0, b_L=2.5, b_R=0.05, I_G=2.5)
    model = RockingModel.housner(body, e_L=0.5, e_R=0.5)
    x = np.random.default_rng(0).standard_normal(41)
    x -= x.mean()
    x *= 2.560551802490236 / np.abs(x).max()
    r = simulate(model, motions.record(x, 0.005), t_end=3.0, dt_out=1e-4)
    assert r.theta_max_R >= np.max(r.history["theta"]) - 10 * 1e-8 * body.delta_R


def test_regression_quiet_run_history_is_uninitialised():
    """Fixed in e4b1cb8 (found by (c)/(d)). simulate() skipped a motion below the uplift
    limits but returned its output buffer (np.empty) as the history: theta, theta' and
    phase were whatever memory held."""
    r = simulate(RockingModel.housner(BLOCK), motions.cosine_pulse(0.1, 2.0), dt_out=0.01)
    assert r.uplift_time is None
    assert not np.any(r.history["theta"]) and not np.any(r.history["theta_dot"])
    assert not np.any(r.history["phase"])


def test_regression_nan_step_accepted_in_a_short_linearised_transition():
    """Fixed in e4b1cb8 (found by (a)). A step that entered a very short rolling
    transition (theta_side = 1e-9, stiff) with the step size of the rocking phase
    overflowed; its error norm was nan, which
    ``err > 1.0`` accepted; the state became nan, h shrank to 0 and
    ``xtol = ... / h`` raised ZeroDivisionError."""
    body = RockingParams.rectangular_block(0.25, 0.5, 1.0)
    model = RockingModel.imperfect(body, 0.5, 0.5, 1e-9, 1e-9, e_L=0.5, e_R=0.5, linearised=True)
    r = simulate(model, motions.free(), theta0=0.5 * body.delta_R, max_steps=2_000_000)
    assert r.n_impacts > 0 and not r.overturned


@pytest.mark.parametrize("model,motion", [
    # classical model, e = 1, a synthetic record: stalls at t = 0.8227 s
    (RockingModel.housner(BLOCK, e_L=1.0, e_R=1.0), motions.synthetic_record(10.0, 0.01, 9.81, seed=1)),
    # short rolling transition, e = 1: stalls at t = 0.8439 s
    (RockingModel.imperfect(BLOCK, 0.05, 0.05, 1e-9, 1e-9, e_L=1.0, e_R=1.0),
     motions.synthetic_record(20.0, 0.01, 0.3 * 9.81, seed=1)),
], ids=["housner-e1", "transition-e1"])
def test_regression_event_at_step_start_stalls(model, motion):
    """Fixed in e4b1cb8 (found by (a)). The body starts a step on a boundary (theta = 0
    after an impact, or |theta| = theta_side) moving into its region, but the step's end
    lands beyond that boundary with no extremum seen (q' changed sign twice inside the
    step: a record's slope, or a stiff transition). ``Fa == 0`` then placed the event at
    the start of the step: a zero-time impact / region change, and the same again on the
    other side, forever; the stall guard ended the run with RuntimeError 'made no progress'."""
    r = simulate(model, motion, max_steps=2_000_000)
    assert r.stats["t_final"] == r.t_end or r.overturned


def test_regression_dense_output_of_a_short_transition_is_wild():
    """Fixed in e4b1cb8 (found by (c)). In a stiff rolling transition (theta_L = 2e-7 rad)
    a step passed the error test on its end point, but its dense output was far off inside
    the step: the history sample at t = 1.3394 s was -1.8e-6 rad (theta' = 1.5e-2 rad/s)
    where the run at rtol 1e-12 gives -1.0e-8 rad (theta' = -6.9e-7 rad/s): 760 times the
    absolute tolerance rtol delta. An impact located on that same dense output
    (t = 1.33963 s, speed 1.5e-5 rad/s) was not in the reference run either."""
    body = RockingParams(m=1.0, h=0.05, b_L=0.012042048889593277, b_R=0.012042048889593277,
                         I_G=0.0007095269202290994)
    model = RockingModel.imperfect(body, 0.17619859805364724, 0.3717886782646817, 1.957893150799985e-07, 1e-09,
                                   e_L=1.0, e_R=0.0)
    motion = motions.synthetic_record(10.0, 0.05, 1.248165005066772, seed=3608)
    r = simulate(model, motion, t_end=1.4, dt_out=0.0037)
    ref = simulate(model, motion, t_end=1.4, dt_out=0.0037, rtol=1e-12)
    k = 362   # t = 1.3394 s
    assert abs(r.history["theta"][k] - ref.history["theta"][k]) < 100 * 1e-8 * body.delta_L


def test_regression_batch_lifts_at_the_exact_limit():
    """Fixed in e4b1cb8 for the sweeps (found by (e)). A record whose peak equals the
    uplift limit exactly never lifts the body in simulate() (shortcut), but the kernel,
    then used unguarded by parameter_sweep, found an 'exceedance' by rounding and lifted
    it: the sweep reported 'rocking' where the single run reports 'no motion'. (The
    kernel still lifts: test_bug_uplift_at_a_limit_that_is_only_touched.)"""
    from statue2model.rocking.sweeps import parameter_sweep

    model = RockingModel.housner(BLOCK, e_L=0.5, e_R=0.5)
    x = np.zeros(9)
    x[7] = model.uplift_limits[0]          # the peak, at t = 0.035 s
    rec = motions.record(x, 0.005)
    assert simulate(model, rec).outcome == "no motion"
    assert parameter_sweep(model, rec, "theta_R", [0.0]).codes[0] == 0


@pytest.mark.parametrize("side", [1, -1])
def test_regression_release_exactly_at_theta_side(side):
    """Fixed while landing the isolator (found by (b)). A body released from rest at
    exactly theta_R (the end of the rolling transition) started in the full-contact
    region, fell inward at once, and was taken for a body 'falling below the base':
    the step shrank to 1e-13 s and the run restarted, for good (1,000,000 steps by
    t = 1.9e-6 s). It now starts in the transition, and its energy is conserved
    (e = 1, no loss): every peak returns to theta_R on the side it was released."""
    body = RockingParams(m=1.0, h=1.0, b_L=0.5463024898437905, b_R=0.5463024898437905,
                         I_G=0.4328154701365083)
    model = RockingModel.imperfect(body, 1.0 if side > 0 else 0.5, 0.5 if side > 0 else 1.0,
                                   1e-9 if side > 0 else 0.25, 0.25 if side > 0 else 1e-9,
                                   e_L=1.0, e_R=1.0)
    r = simulate(model, motions.free(), theta0=side * 0.25, t_end=8.0, rtol=1e-10, max_steps=100_000,
                 dt_out=0.01)
    assert r.stats["t_final"] == 8.0
    assert r.history["phase"][1] == 1               # rolling transition, not full contact
    same = r.peak_sides == ("R" if side > 0 else "L")
    assert same.sum() >= 3
    assert np.allclose(r.peak_values[same], 0.25, rtol=1e-7)
