"""The isolator's travel limit (Isolator.capacity) in every isolated analysis: the plate
alone (Coulomb exact, Bouc-Wen), the coupled plate + statue, the isolated spectrum and
variability, the CLI and the 3D scene; against hand-computed Coulomb cases."""
from __future__ import annotations

import json
import math
from dataclasses import replace

import numpy as np
import pytest

from statue2model.cli import main
from statue2model.hazard import motions
from statue2model.rocking.batch import outcome_label
from statue2model.rocking.model import RockingModel
from statue2model.errors import InputError
from statue2model.geometry.rocking_params import RockingParams
from statue2model.isolator import sweeps
from statue2model.isolator.coupled import simulate_coupled
from statue2model.isolator.device import Isolator, isolator_from_design
from statue2model.isolator.time_history import CAPACITY_EXCEEDED, simulate

G = 9.81
ISO = Isolator(R=0.30, r=0.0183, M=15.0, mu=0.01)
STRONG = RockingModel.housner(RockingParams.rectangular_block(b=0.2, h=0.25, m=10.0))   # lifts at 0.8 g


# ------------------------------------------------------------------ device
def test_capacity_field_and_design():
    assert math.isinf(ISO.capacity) and ISO.to_dict()["capacity"] is None
    assert Isolator(R=0.3, r=0.01, M=10, mu=0.01, capacity=0.2).to_dict()["capacity"] == 0.2
    for bad in (0.0, -0.1, float("nan")):
        with pytest.raises(InputError):
            Isolator(R=0.3, r=0.01, M=10, mu=0.01, capacity=bad)
    d = {"R": 0.3, "r": 0.01, "M": 10.0, "mu": 0.01}
    assert math.isinf(isolator_from_design(d).capacity)
    assert isolator_from_design({**d, "d_max": 0.15}).capacity == 0.15
    assert isolator_from_design({**d, "d_max": 0.15, "capacity": 0.12}).capacity == 0.12
    assert isolator_from_design(d, model="boucwen").model == "boucwen"
    with pytest.raises(InputError):
        isolator_from_design({"R": 0.3})


# ------------------------------------------------------------------ 1. free vibration (Coulomb)
def test_released_beyond_the_capacity_is_exceeded_at_t0():
    iso = replace(ISO, capacity=0.03)
    r = simulate(iso, motions.free(), u0=-0.04, t_end=2.0)
    assert r.capacity_exceeded and r.outcome == CAPACITY_EXCEEDED
    assert r.t_capacity == 0.0 and r.u_at_capacity == -0.04
    assert r.u[0] == -0.04 and np.all(np.isnan(r.u[1:]))
    d = r.to_dict()
    assert d["capacity_exceeded"] and d["t_capacity"] == 0.0 and d["capacity"] == 0.03


def test_released_below_the_capacity_with_friction_never_exceeds():
    iso = replace(ISO, capacity=0.05)
    r = simulate(iso, motions.free(), u0=0.0499, t_end=10.0)
    assert not r.capacity_exceeded and r.outcome == "ok" and r.t_capacity is None
    assert r.u_max == 0.0499 and np.all(np.isfinite(r.u))
    # each half cycle loses 2 mu R_hat: the peaks stay inside
    assert np.all(np.diff(np.abs(r.peaks_u)) < 0)


def test_free_vibration_with_friction_crosses_at_the_closed_form_time():
    """From u = 0 with v0 > 0 (s = +1): u = -a (1 - cos wt) + (v0/w) sin wt, a = mu g / w^2,
    so u = cap at w t = phi - acos((cap + a) / rho), rho = hypot(a, v0/w), phi = atan2(v0/w, a)."""
    iso = replace(ISO, capacity=0.04)
    w, a, v0 = iso.omega, iso.mu * iso.g / iso.omega**2, 0.3
    b = v0 / w
    t_ref = (math.atan2(b, a) - math.acos((iso.capacity + a) / math.hypot(a, b))) / w
    r = simulate(iso, motions.free(), v0=v0, t_end=3.0)
    assert r.outcome == CAPACITY_EXCEEDED
    assert r.t_capacity == pytest.approx(t_ref, abs=1e-12)
    assert r.u_at_capacity == pytest.approx(0.04, abs=1e-14)
    assert r.u_max == pytest.approx(0.04, abs=1e-14)
    t = r.t
    assert np.all(np.isfinite(r.u[t < t_ref])) and np.all(np.isnan(r.u[t > t_ref]))
    # and without the capacity: its peak (rho - a) is beyond it
    assert simulate(ISO, motions.free(), v0=v0, t_end=3.0).u_max == pytest.approx(math.hypot(a, b) - a)


# ------------------------------------------------------------------ 2. harmonic drive (mu = 0)
def _steady_state_case():
    """Undamped plate (mu = 0) under u_g'' = A sin(W t), W = 0.5 omega, started on the steady
    state u_p = -A sin(W t) / (omega^2 - W^2): u = u_p exactly, amplitude X = A / |omega^2 - W^2|."""
    iso = Isolator(R=0.30, r=0.0183, M=15.0, mu=0.0)
    w = iso.omega
    W = 0.5 * w
    A = 0.2 * G
    X = A / abs(w * w - W * W)
    motion = motions.sine_train(A, W / (2 * math.pi), 4)
    v0 = -A * W / (w * w - W * W)
    return iso, motion, X, W, v0


def test_harmonic_steady_state_is_the_analytic_one():
    iso, motion, X, W, v0 = _steady_state_case()
    r = simulate(iso, motion, v0=v0, t_end=motion.end, dt_out=0.001)
    assert np.allclose(r.u, -X * np.sin(W * r.t), rtol=0, atol=1e-12 * X)
    assert r.u_max == pytest.approx(X, rel=1e-12)


def test_harmonic_capacity_just_above_and_just_below_the_amplitude():
    iso, motion, X, W, v0 = _steady_state_case()
    above = simulate(replace(iso, capacity=X * (1 + 1e-6)), motion, v0=v0, t_end=motion.end)
    assert not above.capacity_exceeded and above.outcome == "ok"
    cap = 0.99 * X
    below = simulate(replace(iso, capacity=cap), motion, v0=v0, t_end=motion.end)
    t_ref = math.asin(cap / X) / W            # |u| = X |sin W t| first reaches cap (u < 0 there)
    assert below.outcome == CAPACITY_EXCEEDED
    assert abs(below.t_capacity - t_ref) < 1e-6
    assert below.u_at_capacity == pytest.approx(-cap, rel=1e-12)


def test_bouc_wen_crossing_is_located_inside_the_step():
    """Bouc-Wen: the crossing is bisected on the adaptive step; the plate solver and the
    coupled integrator (DOP853 event) agree, and both are far from any output sample."""
    iso = Isolator(R=0.30, r=0.0183, M=15.0, mu=0.01, model="boucwen", capacity=0.05)
    motion = motions.cosine_pulse(0.3 * G, 1.0)
    p = simulate(iso, motion, t_end=4.0, dt_out=0.1)
    c = simulate_coupled(iso, STRONG, motion, t_end=4.0, dt_out=0.1, rtol=1e-10)
    assert p.outcome == c.outcome == CAPACITY_EXCEEDED
    assert abs(p.t_capacity - c.t_capacity) < 1e-7
    assert abs(abs(p.u_at_capacity) - 0.05) < 1e-12
    assert 0.05 < p.t_capacity % 0.1 < 0.095 or 0.005 < p.t_capacity % 0.1 < 0.05


# ------------------------------------------------------------------ end stop (impact)
def test_end_stop_impact_times_and_count():
    """mu = 0, free, from u = 0 with v0: first hit at asin(w cap / v0) / w with speed
    v1 = sqrt(v0^2 - w^2 cap^2); rebound -e v1 from +cap: amplitude A2 = hypot(cap, e v1 / w),
    u = A2 cos(w tau + phi), phi = atan2(e v1 / w, cap), the next hit (-cap) at tau = (pi - 2 phi) / w."""
    iso = Isolator(R=0.30, r=0.0183, M=15.0, mu=0.0, capacity=0.04)
    w, v0, e, cap = iso.omega, 0.3, 0.5, 0.04
    t1 = math.asin(w * cap / v0) / w
    v1 = math.sqrt(v0**2 - (w * cap) ** 2)
    phi = math.atan2(e * v1 / w, cap)
    t2 = t1 + (math.pi - 2 * phi) / w
    r = simulate(iso, motions.free(), v0=v0, t_end=t2 + 0.01, dt_out=1e-4, end_stop="impact", e_stop=e)
    assert r.outcome == "end-stop impact" and r.capacity_exceeded and r.capacity_hits == 2
    assert r.t_capacity == pytest.approx(t1, abs=1e-12)
    after = (r.t > t1) & (r.t < t2)                           # between the hits: the rebound's sinusoid
    A2, tau = math.hypot(cap, e * v1 / w), r.t[after] - t1
    assert np.allclose(r.u[after], A2 * np.cos(w * tau + phi), rtol=0, atol=1e-12)
    assert np.allclose(r.v[after], -A2 * w * np.sin(w * tau + phi), rtol=0, atol=1e-11)
    assert np.all(np.isfinite(r.u)) and r.u_max == pytest.approx(cap, abs=1e-14)
    r2 = simulate(iso, motions.free(), v0=v0, t_end=t2 - 1e-6, end_stop="impact", e_stop=e)
    assert r2.capacity_hits == 1
    with pytest.raises(InputError):
        simulate(iso, motions.free(), v0=v0, end_stop="bounce")
    with pytest.raises(InputError):
        simulate(iso, motions.free(), u0=0.05, end_stop="impact")


def test_end_stop_rest_against_a_steady_push():
    """A rectangular ground pulse pushing the plate onto the stop: the rebounds die out and the
    plate rests on the stop (finite hits, no stall), then comes back when the push ends."""
    iso = replace(ISO, capacity=0.02)
    motion = motions.rect_pulse(-0.5 * G, 1.0)          # pushes the plate to +u
    r = simulate(iso, motion, t_end=3.0, dt_out=0.001, end_stop="impact")
    assert r.capacity_exceeded and 2 <= r.capacity_hits < 100
    on = (r.t > 0.6) & (r.t < 0.99)
    assert np.all(r.u[on] == pytest.approx(0.02, abs=1e-12)) and np.all(r.v[on] == 0.0)
    assert np.abs(r.u[r.t > 1.5]).max() < 0.02


# ------------------------------------------------------------------ 3. coupled model
def test_coupled_without_uplift_crosses_with_the_plate_alone():
    iso = replace(ISO, capacity=0.05)
    motion = motions.cosine_pulse(0.3 * G, 1.0)
    plate = simulate(iso, motion, t_end=6.0)
    screened = simulate_coupled(iso, STRONG, motion, t_end=6.0)
    forced = simulate_coupled(iso, STRONG, motion, t_end=6.0, screen=False, rtol=1e-10)
    assert plate.outcome == screened.outcome == forced.outcome == CAPACITY_EXCEEDED
    assert not forced.uplift and forced.stats["coupled_integration"]
    assert screened.t_capacity == plate.t_capacity
    assert abs(forced.t_capacity - plate.t_capacity) < 1e-8
    assert forced.u_at_capacity == pytest.approx(plate.u_at_capacity, abs=1e-9)
    after = forced.t > forced.t_capacity
    assert np.all(np.isnan(forced.u[after])) and np.all(forced.phase[after] == 4)
    d = forced.to_dict()
    assert d["outcome"] == CAPACITY_EXCEEDED and d["capacity_exceeded"] and d["t_capacity"] == forced.t_capacity


def test_coupled_end_stop_impact_kicks_the_statue():
    """The end-stop impulse tips a statue in full contact: theta' jumps by A1 dv."""
    iso = replace(ISO, capacity=0.05)
    motion = motions.cosine_pulse(0.3 * G, 1.0)
    r = simulate_coupled(iso, STRONG, motion, t_end=3.0, end_stop="impact")
    assert r.capacity_exceeded and r.capacity_hits >= 1 and r.outcome != CAPACITY_EXCEEDED
    assert r.uplift and r.t_uplift == pytest.approx(r.t_capacity, abs=1e-12)
    assert np.all(np.isfinite(r.u[~np.isnan(r.theta)]))


# ------------------------------------------------------------------ 4. spectrum
def test_isolated_spectrum_capacity_code_where_the_plate_alone_passes_it():
    cap = 0.06
    iso = replace(ISO, capacity=cap)
    freqs, amps = [0.5, 1.0, 4.0], [0.05 * G, 0.2 * G, 0.5 * G]
    sp = sweeps.isolated_spectrum(iso, STRONG, freqs, amps, free_time=2.0)
    for i, f in enumerate(freqs):
        for j, a in enumerate(amps):
            u = simulate(ISO, motions.cosine_pulse(a, f), t_end=1 / f + 2.0).u_max      # no capacity
            assert (sp.codes[i, j] == sweeps.CAPACITY) == (u > cap), (f, a, u)
    assert sp.codes[0, -1] == sweeps.CAPACITY and sp.codes[-1, 0] == 0      # low f, high amp / the other corner
    assert outcome_label(sweeps.CAPACITY) == "isolator capacity exceeded" == sweeps.label(-3)
    d = sp.to_dict()
    assert d["counts"]["isolator capacity exceeded"] == d["capacity_exceeded_count"] == int((sp.codes == -3).sum())
    assert d["capacity_m"] == cap and "isolator capacity exceeded" in sp.to_csv()
    assert np.isfinite(sp.min_failure_amp()[0])


def test_spectrum_plot_has_a_capacity_class(tmp_path):
    from statue2model.report.dynamics_plots import plot_spectrum

    sp = sweeps.isolated_spectrum(replace(ISO, capacity=0.06), STRONG, [0.5, 4.0], [0.05 * G, 0.5 * G],
                                  free_time=1.0)
    assert plot_spectrum(sp, tmp_path / "s.png").stat().st_size > 1000


# ------------------------------------------------------------------ 5. variability
class _ThreeWorkers:
    workers = 3

    def map(self, fn, items, desc=None):
        return [fn(x) for x in items]


def test_variability_stops_at_the_first_exceeding_pga():
    cap = 0.05
    iso = replace(ISO, capacity=cap)
    motion = motions.cosine_pulse(G, 1.0)
    pgas = np.array([0.3, 0.05, 0.2, 0.1, 0.15, 0.25, 0.0]) * G          # not sorted
    free = 2.0
    umax = {float(a): simulate(ISO, motion.scaled_to_pga(a), t_end=motion.end + free).u_max for a in pgas if a > 0}
    first = min(a for a, u in umax.items() if u > cap)
    sw, acc = sweeps.isolated_variability(iso, STRONG, motion, pgas, free_time=free)
    assert sw.first_capacity_pga() == first == sw.first_failure_pga()
    for k, a in enumerate(pgas):
        if a < first:
            assert sw.run[k] and sw.codes[k] != sweeps.CAPACITY and np.isfinite(sw.theta_max_over_delta[k])
        elif a == first:
            assert sw.run[k] and sw.codes[k] == sweeps.CAPACITY and np.isfinite(acc[k])
        else:
            assert not sw.run[k] and sw.codes[k] == sweeps.CAPACITY and np.isnan(sw.theta_max_over_delta[k])
    d = sw.to_dict()
    assert sorted(d["not_run_pga_m_s2"].tolist()) == sorted(a for a in pgas if a > first)
    n_above = int(np.sum(pgas > first))
    assert n_above >= 2 and np.sum(pgas[pgas > 0] < first) >= 1            # the case tests both sides
    assert d["first_capacity_pga_m_s2"] == first and sum(not x for x in d["run"]) == n_above
    assert any(o.startswith("not run") for o in d["outcome"])
    s = sw.summary()
    assert s["n_not_run"] == n_above and s["n_capacity_exceeded"] == 1 and np.isfinite(s["p50"])
    # the same numbers with an executor of three workers (rounds of three PGAs)
    sw3, acc3 = sweeps.isolated_variability(iso, STRONG, motion, pgas, free_time=free, executor=_ThreeWorkers())
    assert np.array_equal(sw3.codes, sw.codes) and np.array_equal(sw3.run, sw.run)
    assert np.array_equal(acc3, acc, equal_nan=True)
    # no capacity: every PGA runs, as before
    sw0, _ = sweeps.isolated_variability(ISO, STRONG, motion, pgas, free_time=free)
    assert sw0.run.all() and not np.any(sw0.codes == sweeps.CAPACITY)


# ------------------------------------------------------------------ CLI and 3D
def test_cli_simulate_capacity(tmp_path, capsys):
    design = tmp_path / "design.json"
    design.write_text(json.dumps({"R": 0.3, "r": 0.0183, "M": 21.664, "mu": 0.0114, "capacity": 0.2}))
    out = tmp_path / "sim.json"
    assert main(["isolator", "simulate", "--design", str(design), "--motion", "cosine:amp=0.4g,freq=0.5",
                 "--json", str(out)]) == 0
    text = capsys.readouterr().out
    assert "isolator capacity exceeded" in text and "200.0 mm" in text
    d = json.loads(out.read_text())
    assert d["capacity_exceeded"] and d["capacity"] == 0.2 and d["outcome"] == "isolator capacity exceeded"
    assert main(["isolator", "simulate", "--design", str(design), "--capacity", "900mm", "--motion",
                 "cosine:amp=0.4g,freq=0.5", "--json", str(out)]) == 0
    assert "within the capacity 900.0 mm" in capsys.readouterr().out
    assert main(["isolator", "simulate", "--r", "0.0183", "--mass", "21", "--mu", "0.01", "--motion",
                 "cosine:amp=0.4g,freq=0.5", "--json", str(out)]) == 2
    assert "needs --R" in capsys.readouterr().err


def test_3d_scene_reports_the_capacity():
    from statue2model.crosscheck.isolator_scene import IsolatorScene, simulate_isolator
    from statue2model.crosscheck.world import SimSettings

    sc = replace(IsolatorScene.simple(R=0.3, r=0.0095, mu=0.01, m_o=30.0, travel=0.05, segments=32), capacity=0.03)
    motion = motions.sine_pulse(0.3 * G, 2.0)
    r3 = simulate_isolator(sc, motion, t_end=0.6, settings=SimSettings(dt=1e-3))
    r2 = simulate(Isolator(R=0.3, r=0.0095, M=30.0, mu=0.01, capacity=0.03), motion, t_end=0.6)
    assert r3.outcome == "isolator capacity exceeded" and r3.capacity_exceeded
    assert abs(r3.u_at_capacity) > 0.03 and r3.to_dict()["t_capacity"] == r3.t_capacity
    assert r2.capacity_exceeded and abs(r3.t_capacity - r2.t_capacity) < 0.02
    assert r3.t[-1] <= r3.t_capacity + 1e-9                       # the run stopped there
