"""Limit states at the design level (assessment/limit_states.py, MODEL.md section 8): each demand
against references computed here by hand (the records' samples, the thesis statue's uplift
accelerations g b / h, Housner's rectangular-pulse overturning boundary, the pendulum's bound on
the felt acceleration, the design's own numbers), not against the module's own output."""
import json
import math

import numpy as np
import pytest

from statue2model.assessment import states
from statue2model.assessment.limit_states import LIMIT_STATES, LimitStates, contact_limits, evaluate
from statue2model.compute.executors import SerialExecutor
from statue2model.errors import InputError
from statue2model.geometry.rocking_params import RockingParams
from statue2model.hazard import motions
from statue2model.isolator.coupled import simulate_coupled
from statue2model.isolator.device import Isolator
from statue2model.isolator.time_history import simulate as plate_alone
from statue2model.rocking.engine import simulate
from statue2model.rocking.model import RockingModel

G = 9.81
THESIS = {"m": 12.074, "h": 0.3523, "b_L": 0.1995, "b_R": 0.0805, "I_G": 0.8}
A_L, A_R = G * 0.1995 / 0.3523, G * 0.0805 / 0.3523          # uplift accelerations g b / h, m/s^2


def thesis(imperfect: bool = False) -> RockingModel:
    p = RockingParams.from_dict(THESIS)
    return RockingModel.imperfect(p, 0.159, 0.175, 4.55e-3, 4.55e-3) if imperfect else RockingModel.housner(p)


def two_sided(peak_pos: float, peak_neg: float, dt: float = 0.01) -> motions.GroundMotion:
    """A 2 Hz sine train (3 cycles) whose largest sample is ``peak_pos`` and smallest ``-peak_neg``
    (m/s^2), exactly."""
    t = np.arange(0.0, 1.5 + dt / 2, dt)
    s = np.sin(2 * np.pi * 2.0 * t)
    acc = np.where(s > 0, peak_pos * s / s.max(), peak_neg * s / -s.min())      # x / x = 1 exactly
    return motions.record(acc, dt, label=f"sine +{peak_pos:.3g}/-{peak_neg:.3g}")


def strict(d: dict) -> dict:
    return json.loads(json.dumps(d, allow_nan=False))


# --- full contact ------------------------------------------------------------------------------
@pytest.mark.parametrize("factor, lifts", [(0.9, False), (1.1, True)])
def test_full_contact_against_the_uplift_acceleration_by_hand(factor, lifts):
    """Toward -x the thesis statue lifts on its right pivot at g b_R / h = 2.2416 m/s^2; a record
    reaching factor x that (and half of g b_L / h the other way) gives ratio = factor."""
    rec = two_sided(0.5 * A_L, factor * A_R)
    assert -rec.samples.min() == pytest.approx(factor * A_R, rel=1e-12)
    ls = evaluate(thesis(), [rec])
    fc = ls.row("full_contact", "fixed")
    assert fc.capacity == pytest.approx(A_R, rel=1e-12)
    assert fc.demand == pytest.approx(factor * A_R, rel=1e-12)
    assert fc.ratio == pytest.approx(factor, rel=1e-12)
    assert fc.details["ratio_left"] == pytest.approx(0.5, rel=1e-12)
    assert fc.details["side"].startswith("right pivot")
    assert ls.fixed[0].uplift is lifts                 # the time history agrees
    assert fc.exceeded is lifts and fc.n_exceeding == int(lifts)
    assert ls.first_exceeded["fixed"] == ("full_contact" if lifts else None)


def test_uncertain_base_lowers_the_contact_capacity_to_the_band_low_end():
    """alpha_side min(a_side, low): 0.175 x 1.0 toward -x, 0.159 x 1.0 toward +x."""
    model = thesis(imperfect=True)
    assert contact_limits(model) == pytest.approx((0.159 * A_L, 0.175 * A_R), rel=1e-12)
    up, dn = contact_limits(model, (1.0, 3.0))
    assert (up, dn) == pytest.approx((0.159, 0.175), rel=1e-12)
    rec = two_sided(0.1, 0.2)       # below the model's limits (0.883, 0.392) but above the band's
    ls = evaluate(model, [rec], uplift_band=(1.0, 3.0))
    fc = ls.row("full_contact", "fixed")
    assert not ls.fixed[0].uplift                     # the time history keeps the model's limits
    assert fc.ratio == pytest.approx(0.2 / 0.175, rel=1e-12) and fc.exceeded and fc.n_exceeding == 1
    assert "uplift band" in fc.definition and ls.to_dict()["uplift_band"] == [1.0, 3.0]


# --- overturning -------------------------------------------------------------------------------
def test_overturning_record_against_housners_rectangular_pulse_boundary():
    """Linearised slender block, rectangular pulse of t1 = 0.2 s: it overturns when a / (g delta)
    > 1 / (1 - exp(-p t1)) (MODEL.md section 3), with p^2 = 3 g / (4 R) for a rectangle."""
    b, h = 0.0384, 0.2
    R = math.hypot(b, h)
    p, delta = math.sqrt(3 * G / (4 * R)), math.atan(b / h)
    A_min = 1.0 / (1.0 - math.exp(-p * 0.2))                           # 1.4297
    model = RockingModel.housner(RockingParams.rectangular_block(b=b, h=h, m=1.286), e_L=0.9, e_R=0.9,
                                 linearised=True)
    over = motions.rect_pulse(1.2 * A_min * G * delta, 0.2)
    safe = motions.rect_pulse(0.8 * A_min * G * delta, 0.2)
    ls = evaluate(model, [safe, over])
    ot, rk = ls.row("overturning", "fixed"), ls.row("rocking", "fixed")
    assert [r.overturned for r in ls.fixed] == [False, True]
    assert ot.exceeded and ot.n_exceeding == 1 and ot.demand == pytest.approx(0.5) and ot.ratio == 1.0
    assert ot.per_record == (0.0, 1.0)
    # rocking: the overturned record counts as 1; with 2 records the demand is the most unfavourable
    assert ls.statistic == "max" and rk.per_record[1] == 1.0 and rk.demand == 1.0 and rk.exceeded
    assert 0.0 < rk.per_record[0] < 1.0
    # full contact: the linearised uplift limit g delta, both pulses lift the block
    fc = ls.row("full_contact", "fixed")
    assert fc.capacity == pytest.approx(G * delta, rel=1e-12) and fc.ratio == pytest.approx(1.2 * A_min)
    assert ls.first_exceeded == {"fixed": "full_contact"}
    assert ls.governing["fixed"].name == "full_contact"          # ratio 1.72 > overturning 1 = rocking 1


# --- the mean over the set ---------------------------------------------------------------------
def test_the_demand_is_the_mean_of_the_per_record_values():
    model = thesis(imperfect=True)
    iso = Isolator(R=0.30, r=0.0183, M=21.664, mu=0.0114, capacity=0.5)
    recs = [motions.synthetic_record(6.0, 0.01, pga, seed=s) for s, pga in enumerate(np.linspace(0.2, 1.4, 7))]
    ls = evaluate(model, recs, iso=iso, executor=SerialExecutor())
    assert ls.statistic == "mean" and ls.n_records == 7
    pos = np.array([r.samples.max() for r in recs])
    neg = np.array([-r.samples.min() for r in recs])
    fc = ls.row("full_contact", "fixed")
    # toward -x the statue is weaker (0.175 x 2.2416 = 0.392 m/s^2 vs 0.159 x 5.5552 = 0.883 m/s^2)
    assert fc.details["demand_left"] == pytest.approx(pos.mean(), rel=1e-12)
    assert fc.details["demand_right"] == pytest.approx(neg.mean(), rel=1e-12)
    assert fc.capacity == pytest.approx(0.175 * A_R, rel=1e-12)
    assert fc.ratio == pytest.approx(max(pos.mean() / (0.159 * A_L), neg.mean() / (0.175 * A_R)), rel=1e-12)
    assert fc.n_exceeding == int(np.sum(np.maximum(pos / (0.159 * A_L), neg / (0.175 * A_R)) >= 1))
    # the rocking demand is the mean of the engine's per-record peaks
    tod = [simulate(model, r, rtol=1e-7) for r in recs]
    ref = np.mean([1.0 if r.overturned else r.theta_max_over_delta for r in tod])
    assert ls.row("rocking", "fixed").demand == pytest.approx(ref, rel=1e-12)
    assert ls.row("rocking", "fixed").details["impacts"] == pytest.approx(np.mean([r.n_impacts for r in tod]))
    # on the isolator: felt acceleration and travel, each record run on its own
    co = [simulate_coupled(iso, model, r, rtol=1e-7) for r in recs]
    assert ls.row("full_contact", "isolated").demand == pytest.approx(np.mean([c.acc_abs_max for c in co]),
                                                                      rel=1e-12)
    cap = ls.row("capacity", "isolated")
    travel = np.mean([c.u_max for c in co])
    assert cap.details["travel"] == pytest.approx(travel, rel=1e-12)
    assert cap.demand == pytest.approx(1.5 * travel + 0.0114 * 2 * (0.30 - 0.0183), rel=1e-12)
    assert cap.capacity == 0.5 and cap.ratio == pytest.approx(cap.demand / 0.5)


def test_fewer_than_seven_records_take_the_most_unfavourable():
    recs = [two_sided(a, a) for a in (0.5, 1.0, 1.5)]
    ls = evaluate(thesis(), recs)
    fc = ls.row("full_contact", "fixed")
    assert ls.statistic == "max" and fc.demand == pytest.approx(1.5) and fc.ratio == pytest.approx(1.5 / A_R)
    assert any("fewer than 7" in w for w in ls.warnings)


# --- on the isolator ---------------------------------------------------------------------------
def test_long_period_isolator_filters_the_ground():
    """T = 2 pi sqrt(2 (R - r) / g) = 3.99 s: the statue feels less than the ground's peak, and never
    more than the pendulum and friction can push, omega^2 max|u| + mu g."""
    model = thesis()
    iso = Isolator(R=2.0, r=0.0183, M=21.664, mu=0.0073)
    assert iso.T == pytest.approx(2 * math.pi * math.sqrt(2 * (2.0 - 0.0183) / G)) == pytest.approx(3.994, abs=1e-3)
    recs = [motions.synthetic_record(8.0, 0.01, 3.0, seed=s) for s in range(3)]      # 1.34 x g b_R / h
    ls = evaluate(model, recs, iso=iso)
    omega2 = G / (2 * (2.0 - 0.0183))
    for r, rec in zip(ls.isolated, recs):
        assert r.acc_felt < rec.pga
        assert r.acc_felt <= omega2 * r.u_max + 0.0073 * G + 1e-9
        assert not r.uplift
        alone = plate_alone(iso, rec)                                  # the statue stays in full contact
        assert r.acc_felt == pytest.approx(alone.acc_abs_max, rel=1e-9)
    fixed, isolated = ls.row("full_contact", "fixed"), ls.row("full_contact", "isolated")
    assert fixed.exceeded and fixed.n_exceeding == 3 and not isolated.exceeded
    assert isolated.demand < fixed.demand         # 3 records: both the most unfavourable record's


def test_friction_bounds_take_each_quantity_at_the_bound_that_governs():
    """With mu_bounds every record runs on the isolator at both bounds; each quantity is the worse
    of the two plate-alone runs (the statue stays in full contact: the plate alone is exact), and the
    capacity row's friction offset uses the upper bound."""
    model = thesis()
    iso = Isolator(R=2.0, r=0.0183, M=21.664, mu=0.0073)
    recs = [motions.synthetic_record(8.0, 0.01, 3.0, seed=s) for s in range(2)]
    ls = evaluate(model, recs, iso=iso, mu_bounds=(0.002, 0.03))
    for r, rec in zip(ls.isolated, recs):
        lo, hi = plate_alone(Isolator(R=2.0, r=0.0183, M=21.664, mu=0.002), rec), \
            plate_alone(Isolator(R=2.0, r=0.0183, M=21.664, mu=0.03), rec)
        assert r.u_max == pytest.approx(max(lo.u_max, hi.u_max), rel=1e-6)
        assert r.acc_felt == pytest.approx(max(lo.acc_abs_max, hi.acc_abs_max), rel=1e-6)
    cap = ls.row("capacity", "isolated")
    assert cap.details["mu_bounds"] == [0.002, 0.03]
    # 2 records: the most unfavourable (max), not the mean
    assert cap.demand == pytest.approx(1.5 * max(r.u_max for r in ls.isolated) + 0.03 * iso.R_hat, rel=1e-9)
    with pytest.raises(InputError, match="mu_bounds"):
        evaluate(model, recs, iso=iso, mu_bounds=(0.03, 0.002))


def test_capacity_exceeded_outright_and_counted_as_a_loss():
    """A 10 mm stroke under 1.5 m/s^2 records: every run stops at the capacity, so the peak travel
    is the capacity and the demand 1.5 x 0.01 + mu R_hat."""
    model = thesis()
    iso = Isolator(R=0.30, r=0.0183, M=21.664, mu=0.0114, capacity=0.01)
    recs = [motions.synthetic_record(6.0, 0.01, 1.5, seed=s) for s in range(2)]
    ls = evaluate(model, recs, iso=iso)
    cap = ls.row("capacity", "isolated")
    assert all(r.capacity_exceeded for r in ls.isolated)
    assert cap.demand == pytest.approx(1.5 * 0.01 + 0.0114 * 2 * (0.30 - 0.0183), rel=1e-9)
    assert cap.exceeded and cap.n_exceeding == 2
    assert ls.row("overturning", "isolated").n_exceeding == 2           # the conservative reading
    assert ls.row("full_contact", "isolated").exceeded
    assert ls.first_exceeded["isolated"] == "full_contact"


def test_ball_load_against_the_designs_surface():
    """W / n against the long-term capacity of a ball on the design's groove surface (design.json
    ``ball_capacity.per_ball``, isolator/bearing.py): 25 mm balls on beech, below the calibration ball, carry
    30 kg / 4 on a 40 mm ball scaled by (D / 40 mm)^2 (the relative dent), / 1.6 for creep."""
    from statue2model.isolator.bearing import SURFACES, ball_capacity

    model = thesis()
    cap = ball_capacity(0.025, SURFACES["beech"])
    allow = 30 * G / 4 * (0.025 / 0.040) ** 2 / 1.6               # 17.96 N
    assert cap.load == pytest.approx(allow, rel=1e-9)
    d = {"R": 0.30, "r": 0.0125, "M": 21.664, "mu": 0.0073, "n_grooves": 3, "capacity": 0.1, "margin": 1.5,
         "R_hat": 2 * (0.30 - 0.0125), "passed": True,
         "ball_capacity": {"per_ball": cap.load, "criterion": cap.criterion, "source": cap.source, "surface": "beech"}}
    ls = evaluate(model, [two_sided(0.3, 0.3)], design=d)
    b = ls.row("bearing", "isolated")
    W = 21.664 * G
    assert b.demand == pytest.approx(W / 3, rel=1e-12) and b.capacity == pytest.approx(allow, rel=1e-9)
    assert b.exceeded and b.ratio == pytest.approx(W / 3 / allow, rel=1e-9) and b.n_exceeding == 1
    assert b.details["n_balls_needed"] == math.ceil(W / allow)
    assert b.details["surface"] == "beech" and b.details["criterion"].startswith("relative dent")
    assert any("rubber layer" in o for o in b.details["options"])
    assert any("harder groove" in o for o in b.details["options"])
    assert ls.governing["isolated"].name == "bearing"
    # a design that does not pass its own checks is analysed, with a warning
    failing = evaluate(model, [two_sided(0.3, 0.3)], design={**d, "passed": False})
    assert "the isolator design does not pass its own required checks" in failing.warnings


def test_json_has_no_nan_and_says_why_a_number_is_missing():
    iso = Isolator(R=0.30, r=0.0183, M=21.664, mu=0.0114)           # capacity inf: not checked, no design
    ls = evaluate(thesis(), [two_sided(0.2, 0.2)], iso=iso)
    d = strict(ls.to_dict())
    rows = {(r["base"], r["name"]): r for r in d["rows"]}
    assert [n for b, n in rows if b == "isolated"] == [s.id for s in states.on_base("isolated")]
    assert rows["isolated", "capacity"]["capacity"] is None and "not given" in rows["isolated", "capacity"]["reason"]
    assert rows["isolated", "bearing"]["ratio"] is None and "number of balls" in rows["isolated", "bearing"]["reason"]
    assert d["fixed_records"][0]["t_uplift"] is None
    assert d["governing"]["isolated"] in LIMIT_STATES
    for r in d["rows"]:
        assert r["definition"] and r["unit"]


def test_bad_input_is_one_line():
    model = thesis()
    with pytest.raises(InputError, match="no records"):
        evaluate(model, [])
    with pytest.raises(InputError, match="uplift_band"):
        evaluate(model, [two_sided(0.1, 0.1)], uplift_band=(3.0, 1.0))
    with pytest.raises(InputError, match="not the design's"):
        evaluate(model, [two_sided(0.1, 0.1)], iso=Isolator(R=0.3, r=0.0183, M=21.0, mu=0.01),
                 design={"R": 0.3, "r": 0.0183, "M": 22.0, "mu": 0.01})


# --- a real design set on the bundled scan -----------------------------------------------------
@pytest.mark.slow
def test_design_record_set_on_the_default_scan():
    from statue2model.geometry.body import load_body
    from statue2model.hazard.code_spectra import parse_spectrum
    from statue2model.hazard.matching import match_set
    from statue2model.io.paths import default_scan
    from statue2model.isolator.design import design

    p = load_body(default_scan()).rocking(None)
    model = RockingModel.housner(p)
    target = parse_spectrum("ec8:ag=0.25g,ground=C")
    d = design(p, mu=0.0073, spectrum=target, thickness=0.03, fuse_release=0.075 * G).to_dict()   # as the pipeline
    rs = match_set(target, n=7, band=(0.15, 4.788))
    ls = evaluate(model, rs.records, design=d)
    assert ls.n_records == 7 and ls.statistic == "mean" and len(ls.rows) == 8
    pos = np.mean([r.samples.max() for r in rs.records])
    neg = np.mean([-r.samples.min() for r in rs.records])
    fc = ls.row("full_contact", "fixed")
    ratio = max(pos / (G * p.b_L / p.h), neg / (G * p.b_R / p.h))
    assert fc.ratio == pytest.approx(ratio, rel=1e-9)
    cap = ls.row("capacity", "isolated")
    assert cap.capacity == d["capacity"] and cap.details["margin"] == 1.5
    assert cap.details["friction_offset"] == pytest.approx(0.0073 * d["R_hat"], rel=1e-12)
    b = ls.row("bearing", "isolated")
    assert b.demand == pytest.approx(d["M"] * G / d["n_grooves"], rel=1e-12)
    iso_fc = ls.row("full_contact", "isolated")
    assert iso_fc.demand < 0.5 * fc.demand                              # the isolator works
    strict(ls.to_dict())
    print("\n" + ls.table())


def test_the_table_reads_back_typed_and_refuses_a_stray_name():
    """limit_states.json read back (issue [21]: typed records across the rooms): LimitStates.from_dict of
    to_dict gives the same file, with the isolator's rows, a non-finite per-record number and the band; a
    row spelled outside the registry or with a bad count is refused by name."""
    iso = Isolator(R=2.0, r=0.0183, M=21.664, mu=0.0073, capacity=0.05)
    recs = [motions.synthetic_record(8.0, 0.01, 3.0, seed=s) for s in range(3)]
    ls = evaluate(thesis(), recs, iso=iso, uplift_band=(2.0, 2.5))
    d = strict(ls.to_dict())
    back = LimitStates.from_dict(d)
    assert strict(back.to_dict()) == d
    assert back.row("full_contact", "fixed") == ls.row("full_contact", "fixed")
    assert back.governing == ls.governing and back.first_exceeded == ls.first_exceeded
    # the verdict's copy without the per-record tables keeps its rows and bases
    slim = LimitStates.from_dict({k: v for k, v in d.items() if k not in ("fixed_records", "isolated_records")})
    assert slim.rows == back.rows and set(slim.governing) == {"fixed", "isolated"}
    bad = {**d, "rows": [{**d["rows"][0], "name": "uplift"}]}
    with pytest.raises(InputError, match="unknown limit state 'uplift'"):
        LimitStates.from_dict(bad)
    with pytest.raises(InputError, match="n_exceeding must be a count"):
        LimitStates.from_dict({**d, "rows": [{**d["rows"][0], "n_exceeding": -1}]})
    with pytest.raises(InputError, match="demand must be a number"):
        LimitStates.from_dict({**d, "rows": [{**d["rows"][0], "demand": "high"}]})
