"""3D cross-check that can fail (issue [11] items 1-4): contact-based lift-off against closed forms,
the validity screen (a squat block slides: 2D not applicable; a slender one agrees), the overturning
boundary ratio, and the status bookkeeping (checks vs diagnostics vs not applicable)."""
import math

import numpy as np
import pytest

from statue2model.crosscheck.contact import ContactSettings
from statue2model.crosscheck.output import summary, table
from statue2model.crosscheck.boundary import BOUNDARY_TARGET, boundary_cases
from statue2model.crosscheck.case import Case
from statue2model.crosscheck.restitution import calibrate_restitution, restitution_cases, user_model
from statue2model.crosscheck.screen import screen
from statue2model.crosscheck.statue_cases import LIFT_TARGET, lift_angle, liftoff_time_2d, pulse_cases
from statue2model.crosscheck.statue_scene import (
    LIFT_HEIGHT,
    StatueScene,
    simulate_statue,
)
from statue2model.crosscheck.world import SimSettings
from statue2model.hazard import motions
from statue2model.rocking import RockingModel, simulate

SET = SimSettings(dt=5e-4)
SLENDER = StatueScene.block(b=0.1, h=0.5, m=100.0)          # b / h = 0.2, a = 0.2 g


def rect_delay(params, amp: float, height: float = LIFT_HEIGHT) -> float:
    """Closed form: time from the start of a rectangular pulse of amplitude ``amp`` > g b / h until the
    non-pivot base edge is ``height`` above the floor. About the pivot, psi = |theta| small:
    psi'' = c + k psi with c = p^2 (A/g cos delta - sin delta), k = p^2 (A/g sin delta + cos delta)
    (MODEL.md eq. 35 linearised in psi), so psi = c / k (cosh(sqrt(k) t) - 1)."""
    p, d = params.p_L**2, params.delta_L
    c = p * (amp / params.g * math.cos(d) - math.sin(d))
    k = p * (amp / params.g * math.sin(d) + math.cos(d))
    return math.acosh(1.0 + k * lift_angle(params, height) / c) / math.sqrt(k)


def test_liftoff_under_a_rectangular_pulse_against_the_closed_form():
    p = SLENDER.params
    t0, amp = 0.1, 2.0 * p.a_L
    m = motions.rect_pulse(amp, 0.3, start=t0)
    r = simulate_statue(SLENDER, m, t_end=0.4, settings=SET, dt_out=1e-3)
    delay = rect_delay(p, amp)
    assert 0.01 < delay < 0.05                               # 27 ms: the geometric detection delay
    t_closed = t0 + delay
    t2 = liftoff_time_2d(user_model(SLENDER), m, 0.4)
    assert t2 == pytest.approx(t_closed, abs=2e-4)           # the 2D reading is the closed form
    assert r.uplift_time == pytest.approx(t_closed, abs=2e-3)
    # the force criterion: the non-pivot side unloads at the pulse's start (rigid: exactly t0)
    assert t0 - 1e-9 <= r.unload_time <= t0 + 2e-3
    assert simulate(user_model(SLENDER), m, t_end=0.4).uplift_time == pytest.approx(t0, abs=1e-9)


def test_no_liftoff_below_g_b_over_h():
    """A body that never lifts in 2D must not lift in 3D (the old |theta| > 1e-5 rad did after 1.5 ms)."""
    p = SLENDER.params
    m = motions.rect_pulse(0.8 * p.a_L, 0.3, start=0.05)
    r = simulate_statue(SLENDER, m, t_end=0.4, settings=SET, dt_out=1e-3)
    assert simulate(user_model(SLENDER), m, t_end=0.4).uplift_time is None
    assert r.uplift_time is None and r.max_lift < LIFT_HEIGHT
    # (the force criterion, a diagnostic only, does fire here: the step load makes the contact
    # springs overshoot, unloading the far side for a moment - why the geometric height is the check)


def test_liftoff_under_a_sine_pulse_first_reaches_g_b_over_h():
    """One-sine pulse A sin(2 pi f t): the 2D body lifts when A sin(2 pi f t) first reaches g b / h
    (closed form); the 3D lift-off at the contact height agrees with the 2D one at that height."""
    p = SLENDER.params
    amp, f = 1.5 * p.a_L, 2.0
    m = motions.sine_pulse(amp, f)
    t_up = math.asin(p.a_L / amp) / (2 * math.pi * f)
    assert simulate(user_model(SLENDER), m, t_end=m.end).uplift_time == pytest.approx(t_up, abs=1e-6)
    r = simulate_statue(SLENDER, m, t_end=m.end, settings=SET, dt_out=1e-3)
    t2 = liftoff_time_2d(user_model(SLENDER), m, m.end)
    assert t2 > t_up and abs(r.uplift_time - t2) < LIFT_TARGET       # measured 0.4-1.6 ms
    assert t_up - 0.01 < r.unload_time < t_up + 0.002                # force criterion: no later than 2 ms


def test_slender_block_agrees():
    """Slender block: every check of the pulses is met (lift-off within 5 ms, peaks within 5 %), none
    is screened out, and the peak before the first impact is read before the impact in both."""
    part = pulse_cases(SLENDER, SET, ContactSettings(), freq=2.0, free_time=1.0)
    cases, runs = part.cases, part.runs
    checks = [c for c in cases if c.counted]
    assert checks and all(c.status == "met" for c in checks), table(cases)
    assert not any(c.status == "not applicable" for c in cases)
    by = {c.name: c for c in cases}
    assert abs(by["one-sine 2 Hz x0.8: lift-off time"].value_3d - by["one-sine 2 Hz x0.8: lift-off time"].value_2d) \
        < LIFT_TARGET
    first = by["one-sine 2 Hz x0.8: peak rotation before the first impact"]
    peak = by["one-sine 2 Hz x0.8: peak rotation"]
    assert first.value_2d < 0.5 * peak.value_2d              # the small first excursion, not the later peak
    scr = runs["one-sine 2 Hz x0.8"]["screen"]
    assert scr["applicable"] and scr["mu_required"] < 1 and scr["slip_mm"] < 0.1 and scr["yaw_deg"] < 0.01


def test_squat_block_slides_and_is_not_applicable():
    """b / h = 1 on a floor of friction 0.25 (0.5 per body): a pulse above g b / h slides the block;
    the screen classes every check 'not applicable' with the numbers instead of NO."""
    squat = StatueScene.block(b=0.3, h=0.3, m=200.0)
    contact = ContactSettings(friction=0.5)
    m = motions.sine_pulse(1.3 * 9.81, 2.0)
    r3 = simulate_statue(squat, m, settings=SET, contact=contact, free_time=0.5, dt_out=1e-3)
    scr = screen(user_model(squat), m, r3, contact, m.end + 0.5)
    assert not scr["applicable"]
    assert scr["mu_required"] > 0.9 and scr["mu_scene"] == pytest.approx(0.25)
    assert scr["slip_mm"] > 50                                 # it slides (measured ~0.2 m)
    assert any("friction" in x for x in scr["reasons"]) and any("slips" in x for x in scr["reasons"])
    c = Case.equal("squat: overturn", False, r3.overturned).screened(scr)
    assert c.status == "not applicable" and "2D not applicable" in c.why and not c.counted


def test_status_bookkeeping_counts_only_applicable_checks():
    ok = Case.relative("a", "s", 1.0, 1.001, 0.01)
    bad = Case.relative("b", "s", 1.0, 1.5, 0.01)
    diag = Case.relative("c", "s", 1.0, 1.5, 0.01).as_diagnostic("2D given 3D's e")
    na = bad.screened({"applicable": False, "reasons": ["3D pivot slips 9.0 mm > 2 mm"]})
    assert (ok.status, bad.status, diag.status, na.status) == ("met", "missed", "diagnostic", "not applicable")
    s = summary([ok, bad, diag, na])
    assert s["n_cases"] == 2 and s["n_met"] == 1 and s["unmet"] == ["b"]
    assert s["n_not_applicable"] == 1 and s["n_diagnostic"] == 1
    txt = table([ok, bad, diag, na])
    assert "n/a: slides / twists: 2D not applicable: 3D pivot slips 9.0 mm" in txt and "diag" in txt
    assert ok.to_dict()["status"] == "met"
    with pytest.raises(ValueError):
        Case("x", "x", 1.0, 1.0, 0.0, 0.1, True, status="maybe")


def test_restitution_cases_of_a_block_against_eq15():
    """Symmetric block: both sides' calibrated e at each release are cases against eq. 15 (5 %)."""
    cal = calibrate_restitution(SLENDER, SET, ContactSettings(), releases=(0.2, 0.6), t_end=1.0)
    cases = restitution_cases(SLENDER, cal, ContactSettings())
    assert len(cases) == 4 and {c.quantity for c in cases} == {"restitution e_L", "restitution e_R"}
    assert all(c.status == "met" and c.rel_error < 0.05 for c in cases), table(cases)


def test_overturning_boundary_ratio_of_a_slender_block():
    """The lowest one-sine overturning amplitude at 1 Hz in 2D and 3D: ratio within 10 %."""
    part = boundary_cases(SLENDER, user_model(SLENDER), (1.0,), SET, ContactSettings(), n3=4,
                          free_time=1.5, max_edges=1)
    cases, runs = part.cases, part.runs["overturning boundaries"]
    c = cases[0]
    assert c.name == "overturning boundary 1 Hz" and c.status == "met" and c.rel_error < BOUNDARY_TARGET
    assert c.value_2d > SLENDER.params.a_L / 9.81                # above the static uplift (0.2 g)
    assert runs["1 Hz"]["edges_2d_g"][0][1] == "up"


@pytest.mark.slow
def test_statue_restitution_each_side_each_release_is_a_case():
    from statue2model.geometry.body import load_body
    from statue2model.io.paths import default_scan

    st = StatueScene.from_body(load_body(default_scan()))
    cal = calibrate_restitution(st, SET, ContactSettings(), releases=(0.1, 0.5))
    cases = restitution_cases(st, cal, ContactSettings())
    assert len(cases) == 4 and all(c.counted or c.status == "not applicable" for c in cases)
    eL = [c for c in cases if c.quantity == "restitution e_L"]
    assert all(c.status == "met" for c in eL)                   # measured 0.3-0.5 % from eq. 15
    # e_R at the higher impact speed: its miss (if any) is reported with its numbers, not hidden
    for c in cases:
        assert c.status == "met" or c.why
        assert np.isfinite(c.value_3d)


@pytest.mark.parametrize("sign", [1.0, -1.0])
def test_contact_landing_matches_quarter_period(sign):
    """The first impact read from the contacts (the raised side's base edge back on the floor) of a
    block released from rest at theta0 = +-0.5 delta is the free rocking's quarter period: the 2D
    model's exact first impact (and, looser, the linearised closed form), within 2 engine steps."""
    p = SLENDER.params
    th0 = sign * 0.5 * p.delta_R
    q2 = simulate(RockingModel.housner(p), motions.free(), theta0=th0, t_end=1.0).impact_times[0]
    alpha = p.delta_R
    q_lin = math.acosh(1.0 / (1.0 - abs(th0) / alpha)) / p.p_R        # linearised, eq. for theta(t)
    assert abs(q2 - q_lin) / q2 < 0.02                                 # the closed form, measured 0.11 %
    r = simulate_statue(SLENDER, motions.free(), theta0=th0, t_end=0.5, settings=SET, dt_out=SET.dt)
    assert r.impact_times.size == 1
    assert abs(r.impact_times[0] - q2) < 2 * SET.dt                   # measured 0.32 ms (dt 0.5 ms)
    # the diagnostic (sign change of theta) sees the same impact, a fraction of a step later
    assert abs(r.sign_change_times[0] - r.impact_times[0]) < SET.dt


def test_no_rotation_peak_is_compared_where_neither_model_lifts_off():
    """A squat body in full contact: 3D reads ~1e-4 rad of contact compliance, 2D exactly 0; the peak
    rotation is 'not applicable' with that reason, never a 100 % miss."""
    from types import SimpleNamespace

    from statue2model.crosscheck.statue_cases import no_lift_case

    r2 = SimpleNamespace(uplift_time=None, theta_max_L=0.0, theta_max_R=0.0, overturned=False)
    r3 = SimpleNamespace(uplift_time=None, theta_max_L=1.1e-4, theta_max_R=-0.6e-4, overturned=False)
    c = no_lift_case("El Centro", r2, r3)
    assert c.status == "not applicable" and not c.counted
    assert c.name == "El Centro: peak rotation" and c.value_3d == pytest.approx(1.1e-4)
    assert c.why.startswith("not applicable: neither model lifts off") and "1.10e-04 rad" in c.why


def test_a_hair_of_2d_uplift_below_the_lift_height_is_not_compared():
    """A squat block under a sine a hair above g b / h: 2D passes its exact uplift instant (a few
    1e-5 rad), neither lifts its edge 0.2 mm. One criterion decides: 'lifts off' is no in both and the
    peak rotation is 'not applicable', never a miss of 2D's hair against 3D's compliance (before the
    fix: 10.9 % NO for 2.8e-5 rad)."""
    from statue2model.crosscheck.statue_cases import motion_cases

    squat = StatueScene.block(b=0.2, h=0.25, m=160.0)         # b / h = 0.8
    model = user_model(squat)
    m = motions.sine_pulse(1.006 * 0.8 * 9.81, 1.5)
    comp = motion_cases(squat, m, SimSettings(dt=2e-3), ContactSettings(), free_time=0.5, model=model)
    by = {c.name.split(": ", 1)[1]: c for c in comp.cases}
    assert simulate(model, m, t_end=m.end + 0.5).uplift_time is not None     # 2D passes its exact uplift
    assert by["lifts off"].value_2d == 0 and by["lifts off"].value_3d == 0
    peak = by["peak rotation"]
    assert peak.status == "not applicable" and not peak.counted and 0 < peak.value_2d < lift_angle(model.params)
    assert "neither model lifts off" in peak.why
    row = next(line for line in table(comp.cases).splitlines() if ": peak rotation " in line)
    assert " - " in row and "n/a: not applicable" in row and "NO" not in row
