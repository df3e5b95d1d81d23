"""3D cross-check (PyBullet) of the 2D rocking model: scenes, ground motion, agreement levels.

Targets, not pinned levels (dt = 0.5 ms, 50 solver iterations; see docs/crosscheck.md); the
contact-based lift-off, the validity screen and the overturning boundary: test_crosscheck_validity.py.
"""
import json
import math

import numpy as np
import pytest

from statue2model.cli import main
from statue2model.crosscheck.contact import ContactSettings, effective_e, rolling_for_mu
from statue2model.crosscheck.boundary import overturn_grid
from statue2model.crosscheck.case import Case
from statue2model.crosscheck.restitution import calibrate_restitution, model_2d
from statue2model.crosscheck.statue_cases import free_rocking_cases, motion_cases, pulse_cases
from statue2model.crosscheck.statue_scene import (
    StatueScene,
    add_statue,
    inertia_check,
    simulate_statue,
)
from statue2model.crosscheck.world import SimSettings, World, step_mean_acc
from statue2model.hazard import motions
from statue2model.rocking import RockingModel, simulate
from statue2model.errors import InputError
from statue2model.geometry.rocking_params import RockingParams

SET = SimSettings(dt=5e-4)


@pytest.fixture(scope="module")
def statue():
    from statue2model.geometry.body import load_body
    from statue2model.io.paths import default_scan

    return StatueScene.from_body(load_body(default_scan()))


def test_inertia_from_our_mass_properties(statue):
    with World(SET) as w:
        w.plane(1.0)
        b = add_statue(w, statue, ContactSettings())
        chk = inertia_check(w, b, statue)
    assert chk["mass_rel_error"] < 1e-12
    assert chk["com_error_m"] < 1e-12
    assert chk["inertia_rel_error"] < 1e-9
    # the scene is turned so that the 2D params along +x are those of the weakest direction
    # (b_R by the ray from G', the extreme base point beyond it by < 0.1 mm: the edge is square to x)
    assert 0 <= statue.x_R - statue.com[0] - statue.params.b_R < 1e-4
    assert 0 <= statue.com[0] - statue.x_L - statue.params.b_L < 2e-3
    assert statue.hull[:, 2].min() == 0.0


def test_step_mean_acc_is_exact_for_cubics():
    m = motions.record([0.0, 1.0, 3.0, 2.0], dt=0.1)
    a = step_mean_acc(m, 0.0, 0.05, 6)
    # the record is piecewise linear with breakpoints on the step grid: Simpson is exact
    ref = [0.25, 0.75, 1.5, 2.5, 2.75, 2.25]
    assert np.allclose(a, ref, atol=1e-12)


def test_free_rocking_statue_agreement(statue):
    part = free_rocking_cases(statue, SET, ContactSettings(), t_end=1.0)
    cases, runs = part.cases, part.runs
    by = {c.quantity: c for c in cases}
    # targets: quarter period 1 % (measured 0.04 %), first rebound 5 % (measured 0.75 %); the statue's
    # pivot slips a few mm in 3D, so the screen may class them not applicable: the values still count here
    assert by["quarter period"].met and by["peak rotation"].met
    assert all(c.status in ("met", "not applicable") for c in cases)
    r = runs["free rocking"]
    assert r["finite"] and r["max_tilt_out"] < 0.01


def test_pulses_statue_agreement(statue):
    cases = pulse_cases(statue, SET, ContactSettings(), freq=1.5, factors=(0.8, 1.25), free_time=1.0).cases
    by = {c.name: c for c in cases}
    assert by["one-sine 1.5 Hz x0.8: overturn"].met and by["one-sine 1.5 Hz x0.8: overturn"].value_3d == 0.0
    assert by["one-sine 1.5 Hz x1.25: overturn"].met and by["one-sine 1.5 Hz x1.25: overturn"].value_3d == 1.0
    up = by["one-sine 1.5 Hz x0.8: lift-off time"]
    assert up.status == "met" and abs(up.value_3d - up.value_2d) < 0.005        # measured 0.08 ms
    # both read before their own first impact (before issue [11]: a peak after it, 5.7 %); measured 0.17 %
    assert by["one-sine 1.5 Hz x0.8: peak rotation before the first impact"].status == "met"


def test_block_quarter_period_converges_with_dt():
    sc = StatueScene.block(b=0.2, h=0.75, m=400.0, depth=0.5)
    p = sc.params
    th0 = 0.5 * p.delta_R
    q2 = simulate(RockingModel.housner(p), motions.free(), theta0=th0, t_end=1.0).impact_times[0]
    errs = []
    for dt in (1e-3, 2.5e-4):
        r = simulate_statue(sc, motions.free(), theta0=th0, t_end=0.5, settings=SimSettings(dt=dt), dt_out=dt)
        errs.append(abs(r.impact_times[0] - q2) / q2)
        assert np.abs(r.tilt_out).max() < 1e-6        # a symmetric block stays planar
    assert errs[1] < errs[0] and errs[1] < 5e-4      # measured 0.11 % and 0.03 %


def _driven_table_run(sc, motion, dt, t_end):
    """The same block on a heavy table whose position and velocity are prescribed every step."""
    from statue2model.crosscheck.statue_scene import inertia_frame
    from statue2model.crosscheck.world import matrix_from_quat

    t = np.arange(round(t_end / dt) + 1) * dt
    acc = motion.acc(t)
    vel = np.concatenate([[0.0], np.cumsum(0.5 * dt * (acc[1:] + acc[:-1]))])
    disp = np.concatenate([[0.0], np.cumsum(0.5 * dt * (vel[1:] + vel[:-1]))])
    out = []
    with World(SimSettings(dt=dt)) as w:
        p = w.p
        shape = w.call("createCollisionShape", p.GEOM_BOX, halfExtents=[3.0, 3.0, 0.1])
        table = w.call("createMultiBody", 1e7, shape, basePosition=[0, 0, -0.1])
        w.call("changeDynamics", table, -1, lateralFriction=1.0, restitution=0.0, linearDamping=0, angularDamping=0)
        body = add_statue(w, sc, ContactSettings())
        _, V = inertia_frame(sc.inertia)
        for k in range(t.size):
            R = matrix_from_quat(w.call("getBasePositionAndOrientation", body)[1]) @ V.T
            out.append(math.atan2(R[0, 2], R[2, 2]))
            if k == t.size - 1:
                break
            w.call("resetBasePositionAndOrientation", table, [disp[k], 0, -0.1], [0, 0, 0, 1])
            v_mid = vel[k] + 0.5 * dt * acc[k]
            w.call("resetBaseVelocity", table, [v_mid, 0, 0], [0, 0, 0])
            w.call("applyExternalForce", table, -1, [0, 0, 1e7 * 9.81], [0, 0, -0.1], p.WORLD_FRAME)
            w.step()
    return t, np.asarray(out)


def test_gravity_tilt_matches_a_driven_table():
    sc = StatueScene.block(b=0.1, h=0.5, m=100.0)
    p = sc.params
    m = motions.sine_pulse(1.3 * p.a_L, 2.0)
    dt = 5e-4
    t_tab, th_tab = _driven_table_run(sc, m, dt, 0.8)
    r = simulate_statue(sc, m, t_end=0.8, settings=SimSettings(dt=dt), dt_out=dt)
    peak = np.abs(th_tab).max()
    assert peak > 0.02
    n = min(len(th_tab), len(r.theta))
    t_imp = simulate(RockingModel.housner(p), m, t_end=0.8).impact_times[0]
    i = int(np.searchsorted(t_tab, t_imp)) - 2
    # measured: before the first impact both agree with each other (and with 2D) to ~3e-5 rad,
    # 0.05 % of the peak; after impacts they differ by 4 % of the peak (impact resolution, not the motion)
    assert np.abs(th_tab[:i] - r.theta[:i]).max() < 1e-4
    assert np.abs(th_tab[:n] - r.theta[:n]).max() < 0.06 * peak


def test_contact_mapping():
    assert rolling_for_mu(0.01, 0.02) == pytest.approx(2e-4)
    p = RockingParams.rectangular_block(0.0384, 0.2, 1.286)
    r = simulate(RockingModel.housner(p, e_L=0.9, e_R=0.9), motions.free(), theta0=0.1, t_end=2.0)
    assert effective_e(p, 0.1, r.peak_values[1], "R") == pytest.approx(0.9, rel=1e-6)
    with pytest.raises(InputError):
        ContactSettings(friction=-1.0)
    with pytest.raises(InputError):
        SimSettings(dt=0.0)
    with pytest.raises(InputError):
        SimSettings(solver_iterations=0)


def test_case_bookkeeping():
    c = Case.relative("x", "s", 2.0, 2.1, 0.01)
    assert not c.met and c.rel_error == pytest.approx(0.05)
    assert Case.absolute("u", "s", 1.0, 1.004, 0.005).met
    assert Case.equal("o", True, True).met and not Case.equal("o", True, False).met
    assert not Case.relative("y", "s", 1.0, None, 0.01).met


def test_stress_high_pga_overturns_cleanly(statue):
    for pga in (2.0, 3.0):
        m = motions.synthetic_record(duration=4.0, pga=pga * 9.81, seed=3)
        r = simulate_statue(statue, m, settings=SimSettings(dt=1e-3), free_time=0.5)
        assert r.finite and r.overturned and r.outcome.startswith("overturn")   # 2 g: at 0.91 s (R)
        assert np.all(np.isfinite(r.theta))


@pytest.mark.slow
def test_stress_long_record(statue):
    m = motions.synthetic_record(duration=60.0, pga=0.35 * 9.81, seed=2)
    r = simulate_statue(statue, m, settings=SimSettings(dt=1e-3), free_time=0.5, dt_out=0.01)
    assert r.finite and np.all(np.isfinite(r.theta)) and r.outcome in ("rocking", "overturn (L)", "overturn (R)")
    assert r.t[-1] > 59.0 or r.overturned
    assert r.steps > 0 and r.real_time_factor > 1.0


def test_restitution_calibration_levels(statue):
    """The 3D scene's own e, measured on free rocking (eq. 43), per impact speed, against eq. 15."""
    cal = calibrate_restitution(statue, SET, ContactSettings(), releases=(0.1, 0.5))
    # target 5 % of eq. 15 for e_L (measured 0.02 % and 0.3 %); e_R at low speed (measured 1 %). The 3D
    # e_R falls at high impact speed (1.03 rad/s: 9.8 % below eq. 15), where the pivot slips: reported
    # by restitution_cases, not pinned here
    assert all(abs(v / cal["e_L_theory"] - 1) < 0.05 for v in cal["e_L_table"]["values"])
    assert abs(cal["e_R_table"]["values"][0] / cal["e_R_theory"] - 1) < 0.05
    m = model_2d(statue, cal)
    assert not m.e_R.is_constant and m.e_R(1.03) == pytest.approx(cal["e_R"], abs=1e-3)


@pytest.mark.slow
def test_overturn_grid_agrees_where_the_2d_model_holds(statue):
    """A 2 x 3 slice of the benchmark's grid: at 1-1.5 Hz (2D boundary 0.52-0.59 g, friction needed
    <= 0.7, valid) 2D and 3D agree; at 2.26 Hz the 2D boundary (5.6 g) needs infinite friction and a
    negative normal force (take-off): the 3D statue slides and yaws instead, and the point is flagged."""
    cal = calibrate_restitution(statue, SET, ContactSettings(), releases=(0.1, 0.3, 0.5, 0.7))
    g = overturn_grid(statue, model_2d(statue, cal), (1.0, 1.47, 2.26), (0.9, 1.1), SET, ContactSettings(),
                      free_time=2.0)
    assert g["total"] == 6 and g["total_valid"] == 4 and g["agree_valid"] == 4
    bad = [r for r in g["rows"] if r["freq"] == 2.26]
    assert all(not r["valid_2d"] and (r["n_min"] < 0 or r["mu_required"] > 1) for r in bad)
    assert all(r["finite"] for r in g["rows"])
    # the 3D statue hops and twists there (measured yaw 0.6-1.9 rad); slip is counted per contact episode
    assert max(r["max_yaw"] for r in bad) > math.radians(2)


@pytest.mark.slow
def test_record_peak_rotation_inside_the_models_spread(statue):
    """Synthetic record 0.5 g: the peak rotation depends on every impact, so each side reports its own
    spread (2D: e +-1 %, rtol; 3D: dt / 2) and the two ranges must overlap. Measured: 2D 0.0285 vs 3D
    0.0157 rad (45 %, spread 42 %) before the scan rested on its hull facet; 0.0158 vs 0.0155 rad
    (2.2 %, spread 8 %) after (a_R +0.25 %)."""
    cal = calibrate_restitution(statue, SET, ContactSettings())
    m = motions.synthetic_record(duration=8.0, pga=0.5 * 9.81, seed=1)
    cases = motion_cases(statue, m, SET, ContactSettings(), model=model_2d(statue, cal), calib=cal,
                         spread=True).cases
    pk = next(c for c in cases if c.quantity == "peak rotation" and c.spread)
    # a single chaotic history: its level is not pinned; the check is reported with both spreads
    # (agreement over records: the ensemble cases, issue [11] item 6)
    assert pk.status in ("met", "missed", "not applicable") and "overlap" in pk.why
    assert pk.spread["2D range"][0] <= pk.value_2d <= pk.spread["2D range"][1]
    diag = [c for c in cases if c.status == "diagnostic"]
    assert diag and all("3D's e" in c.name for c in diag if c.quantity == "peak rotation")
    up = next(c for c in cases if c.quantity == "lift-off time")
    assert abs(up.value_3d - up.value_2d) < 0.005              # target 5 ms


def _design_isolator(statue, **kw):
    from statue2model.crosscheck.isolator_scene import IsolatorScene
    from statue2model.isolator.plates import PlateGeometry

    h = 0.30238660547079826
    geom = PlateGeometry(side=0.8880228222042936, thickness=0.03, R=0.9, depth=0.008255974701743884,
                         groove_centres=((-h, -h), (h, -h), (h, h), (-h, h)), ball_radius=0.0095)
    return IsolatorScene(geom=geom, mu=0.0073, m_o=16.560275187869248, statue=statue, **kw)


@pytest.mark.slow
def test_isolated_statue_levels(statue):
    """Statue on the designed isolator (R 0.9 m, r 9.5 mm, m_o 16.6 kg), 4 s record at 0.2 g, grooves as
    the 4 mm lattice, statue fixed to the plate (one rigid body: the 2D plate model's assumption).
    Measured: 20 Hz peaks 2D 0.334, 3D 1.062 m/s^2 (before: 2.86 with the 128-segment mesh and the
    free-standing statue); raw 0.325 / 1.66; displacement 0.0459 / 0.0455 m (0.9 %; before 8.3 %)."""
    from statue2model.crosscheck.isolator_cases import isolated_statue_cases

    iso = _design_isolator(statue)
    m = motions.synthetic_record(duration=4.0, pga=0.2 * 9.81, seed=1)
    part = isolated_statue_cases(iso, m, SET, ContactSettings(), free_time=0.5)
    cases, hist, runs = part.cases, part.histories, part.runs
    by = {c.name: c for c in cases}
    acc = by["isolated statue: peak plate acceleration"]
    assert acc.value_2d == pytest.approx(0.334, rel=0.02) and acc.value_3d < 1.4
    assert by["isolated statue: peak plate acceleration (raw)"].value_3d < 2.5
    # measured 0.9 %, and 10.5 % since the scan rests on its hull facet (a_R +0.25 %)
    assert by["isolated statue: peak plate displacement"].rel_error < 0.15
    assert by["isolated statue: statue overturns"].met
    assert runs["isolated statue"]["finite"] and "isolated statue: plate acceleration (low-passed)" in hist


@pytest.mark.slow
def test_plate_noise_floor_at_rest(statue):
    """No ground motion: the plate carrying the 407 kg statue. With the 128-segment CNC mesh its 20 Hz
    acceleration was 0.72 m/s^2 rms (peaks 2.6); with the 4 mm lattice grooves 0.040 rms (peak 0.17),
    free-standing statue (without the statue 0.005)."""
    from statue2model.crosscheck.isolator_cases import plate_at_rest

    r = plate_at_rest(_design_isolator(statue), SET, ContactSettings(), t_end=2.0, mount="contact")
    assert r["outcome"] == "ok" and r["rms_filtered"] < 0.12 and r["peak_filtered"] < 0.6


@pytest.mark.slow
def test_stress_statue_overturns_off_the_plate():
    from dataclasses import replace

    from statue2model.crosscheck.isolator_scene import IsolatorScene, simulate_isolator

    blk = StatueScene.block(b=0.05, h=0.4, m=40.0)
    iso = replace(IsolatorScene.simple(R=0.3, r=0.0095, mu=0.01, m_o=30.0, travel=0.05, segments=32), statue=blk)
    r = simulate_isolator(iso, motions.sine_pulse(0.6 * 9.81, 3.0), t_end=2.0, settings=SimSettings(dt=1e-3))
    assert r.finite and r.statue_overturned and r.outcome == "statue overturned"      # at 0.98 s
    assert np.all(np.isfinite(r.u)) and any("overturned" in n for n in r.notes)
    r = simulate_isolator(iso, motions.sine_pulse(1.0 * 9.81, 3.0), t_end=2.0, settings=SimSettings(dt=1e-3))
    assert r.finite and r.outcome == "ball left its groove"                            # at 0.215 s


@pytest.mark.slow
def test_cli_crosscheck_params_quick(tmp_path, capsys):
    params = tmp_path / "p.json"
    params.write_text(json.dumps({"m": 100.0, "h": 0.5, "b_L": 0.12, "b_R": 0.1, "I_G": 100 * (0.11**2 + 0.25) / 3}))
    out = tmp_path / "cc"
    rc = main(["crosscheck", str(params), "--motion", "sine:amp=0.4g,freq=2", "--out", str(out), "--quick",
               "--dt", "1e-3"])
    assert rc == 0
    data = json.loads((out / "crosscheck.json").read_text())
    keys = {"name", "quantity", "value_2d", "value_3d", "rel_error", "target", "met"}
    assert data["cases"] and all(keys <= set(c) for c in data["cases"])
    q = next(c for c in data["cases"] if c["quantity"] == "quarter period")
    assert q["met"]
    assert list(out.glob("*.png"))


@pytest.mark.parametrize("argv, msg", [
    (["crosscheck", "nope.ply", "--motion", "free:theta0=0.1", "--out", "X"], "file not found"),
    (["crosscheck", "{params}", "--motion", "bogus:x=1", "--out", "X"], "unknown motion kind"),
    (["crosscheck", "{params}", "--motion", "free:theta0=0.1", "--out", "X", "--dt", "1"], "time step"),
    (["crosscheck", "{params}", "--motion", "free:theta0=0.1", "--out", "X", "--isolator", "{params}"],
     "not an isolator design"),
])
def test_cli_bad_input_one_line(tmp_path, capsys, argv, msg):
    params = tmp_path / "p.json"
    params.write_text(json.dumps({"m": 100.0, "h": 0.5, "b_L": 0.12, "b_R": 0.1, "I_G": 10.0}))
    argv = [a.replace("{params}", str(params)).replace("X", str(tmp_path / "o")) for a in argv]
    assert main(argv) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("statue2model: error:") and msg in err[0]


# ----------------------------------------------------------------------------- isolator

@pytest.mark.slow
def test_isolator_free_vibration_levels():
    """Small isolator (R 0.3 m, 4 mm lattice grooves): the mapped rolling friction c = mu r gives the
    decay 4 mu R_hat within 0.4 % (with the 64-segment CNC mesh: +20 %, 10.2 % after calibration)."""
    from statue2model.crosscheck.isolator_scene import IsolatorScene
    from statue2model.crosscheck.isolator_cases import isolator_free_cases

    sc = IsolatorScene.simple(R=0.3, r=0.0095, mu=0.01, m_o=50.0, travel=0.05)
    free = isolator_free_cases(sc, SET, ContactSettings(), cycles=2.2)
    cases, runs, cal = free.comparison.cases, free.comparison.runs, free.calibration
    by = {c.name: c for c in cases}
    period = by["isolator free vibration: period"]
    assert period.met and period.rel_error < 0.01                    # measured 0.1 %
    mapped = by["isolator free vibration: decay per cycle (c = mu r)"]
    assert mapped.met and mapped.rel_error < 0.03                    # measured 0.4 %
    assert abs(cal["mu0_equivalent"]) < 0.0005                        # measured 0.00013
    assert cal["mu_3d"] == 0.01                                       # no calibration needed
    assert all(r["finite"] and r["outcome"] == "ok" for r in runs.values())


@pytest.mark.slow
def test_groove_loss_converges_with_dt():
    """At mu = 0 the 4 mm lattice grooves lose 0.29 mm per cycle at dt 0.5 ms and -0.14 mm at 0.25 ms
    (the 64-segment CNC mesh: 7.3 and 3.3 mm): the loss is numerical and goes to zero with dt."""
    from statue2model.crosscheck.isolator_scene import IsolatorScene, simulate_isolator

    sc = IsolatorScene.simple(R=0.3, r=0.0095, mu=0.0, m_o=50.0, travel=0.05)
    ms = {w: sc.plate_mesh(w) for w in ("bottom", "top")}
    loss = {}
    for dt in (5e-4, 2.5e-4):
        r = simulate_isolator(sc, motions.free(), u0=0.06, t_end=1.7, settings=SimSettings(dt=dt), meshes=ms)
        assert r.finite and r.peaks_u.size >= 2
        loss[dt] = 0.06 - abs(r.peaks_u[1])
    assert abs(loss[5e-4]) < 0.0008 and abs(loss[2.5e-4]) < 0.0004


def test_grid_mesh_on_the_sphere():
    from statue2model.crosscheck.grooves import grid_cap

    R, d = 0.3, 0.012
    v, f = grid_cap(R, d, 0.004)
    dist = np.sqrt(v[:, 0] ** 2 + v[:, 1] ** 2 + (v[:, 2] - (R - d)) ** 2)
    assert np.abs(dist - R).max() < 1e-12 and v[:, 2].min() == pytest.approx(-d, abs=2e-5)
    n = np.cross(v[f[:, 1]] - v[f[:, 0]], v[f[:, 2]] - v[f[:, 0]])
    assert np.all(n[:, 2] > 0)                                       # all facing the ball


def test_groove_tiles_tangent_and_maximal_coordinates():
    """groove 'tiles': every tile's contact face lies in the sphere's tangent plane at its centre; the
    scene runs with maximal coordinates (the top plate keeps its mass: changeDynamics with
    localInertiaDiagonal alone zeroed it, NaN at the first step) and keeps the period 2 pi sqrt(R_hat/g)."""
    from dataclasses import replace

    from statue2model.crosscheck.grooves import tile_cap
    from statue2model.crosscheck.isolator_scene import IsolatorScene, simulate_isolator

    R, d = 0.3, 0.012
    tiles = tile_cap(R, d, 0.01)
    c = np.array([0.0, 0.0, R - d])
    face = tiles[:, 0::2]                                           # the 4 corners of the contact face
    nrm = np.cross(face[:, 1] - face[:, 0], face[:, 2] - face[:, 0])
    nrm /= np.linalg.norm(nrm, axis=1)[:, None]
    dist = np.abs(np.einsum("ij,ij->i", c - face[:, 0], nrm))      # centre to the face's plane
    assert np.abs(dist - R).max() < 1e-9 and len(tiles) > 20
    sc = replace(IsolatorScene.simple(R=0.3, r=0.0095, mu=0.0, m_o=50.0, travel=0.05, groove="tiles"), tile=0.019)
    T = 2 * np.pi * np.sqrt(sc.R_hat / 9.81)
    r = simulate_isolator(sc, motions.free(), u0=0.06, t_end=0.6 * T, dt_out=0.002,
                          settings=SimSettings(dt=5e-4, maximal_coordinates=True))
    assert r.finite and r.outcome == "ok" and r.peaks_t.size >= 1
    assert abs(2 * r.peaks_t[0] - T) / T < 0.03                     # measured 0.7 %
    with pytest.raises(InputError):
        IsolatorScene.simple(R=0.3, r=0.0095, mu=0.0, m_o=50.0, groove="bogus")


def test_stress_ball_at_the_rim():
    from statue2model.crosscheck.isolator_scene import IsolatorScene, simulate_isolator

    sc = IsolatorScene.simple(R=0.3, r=0.0095, mu=0.01, m_o=50.0, travel=0.05, segments=64)
    r = simulate_isolator(sc, motions.sine_pulse(3.0, 1.0), u0=0.08, t_end=2.0, settings=SimSettings(dt=1e-3))
    assert r.finite and r.ball_left_groove and r.outcome == "ball left its groove"
    with pytest.raises(InputError):
        simulate_isolator(sc, motions.free(), u0=0.2, t_end=1.0)


@pytest.mark.slow
def test_free_standing_statue_checked_against_the_coupled_model(statue):
    """mount 'contact' with the user's model: the 2D side of 'statue overturns' and 'capacity exceeded'
    is the coupled plate + statue model, and the counted case is the failure itself. A 10 mm capacity
    under a 0.2 g record: both models fail by the capacity; the fails case is met."""
    from dataclasses import replace

    from statue2model.crosscheck.isolator_cases import isolated_statue_cases
    from statue2model.crosscheck.restitution import user_model

    iso = replace(_design_isolator(statue, groove="tiles"), capacity=0.01)
    m = motions.synthetic_record(duration=4.0, pga=0.2 * 9.81, seed=1)
    cases = isolated_statue_cases(iso, m, SimSettings(maximal_coordinates=True), ContactSettings(),
                                  free_time=0.5, mount="contact", label="free", model=user_model(statue)).cases
    by = {c.name: c for c in cases}
    fails = by["free: fails (overturns or capacity exceeded)"]
    assert fails.counted and fails.met and fails.value_2d == 1.0 and fails.value_3d == 1.0
    assert "coupled 2D model" in by["free: statue overturns"].note
    cap = by["free: isolator capacity exceeded"]
    assert cap.value_2d == 1.0 and cap.value_3d == 1.0
    assert cap.status == "met" and by["free: statue overturns"].status == "met"      # both agree: counted
