"""The isolator verified by time histories (isolator/verify.py): margins against a case solved by hand,
the choice by the balance of margins, what would pass when nothing does, and restraint."""
from __future__ import annotations

import json
import math
from types import SimpleNamespace

import pytest

from statue2model.errors import InputError
from statue2model.geometry.rocking_params import RockingParams
from statue2model.hazard import motions
from statue2model.hazard.code_spectra import G as G0
from statue2model.hazard.code_spectra import ec8
from statue2model.isolator.design import BALL_LOAD_TESTED, DISPLACEMENT_MARGIN, OPENING_STEP, SIZING_CLEARANCE
from statue2model.isolator.verify import Margins, Verified, friction_bounds, rank, verify

G = 9.81
MU, MU_LOW, MU_HIGH = 0.0073, 0.004, 0.010
R, r = 1.0, 0.02                                          # one (R, r): the runs are solved by hand
OMEGA2 = G / (2 * (R - r))
T = 2 * math.pi / math.sqrt(OMEGA2)
AMPS = (0.20, 0.23, 0.26, 0.29, 0.32, 0.35, 0.38)         # m/s^2: seven records -> the mean
SPECTRUM = ec8(0.05 * G0, "A")                            # small: the records govern the travel
VENERE = RockingParams.from_dict({"m": 12.074, "h": 0.3523, "b_L": 0.1995, "b_R": 0.0805, "I_G": 0.7994})
ONE = dict(spectrum=SPECTRUM, R_grid=(R,), balls=(r,), n_grooves=4, thickness=0.03)


def _pulses(amps):
    """Half-period rectangular pulses of amplitude A from rest. By hand (Coulomb, omega^2 = g / R_hat):
    the plate slides back against friction to u = -2 (A - mu g) / omega^2 at t = T/2, where it stops as
    the pulse ends; it then swings back less far, so the peak travel is 2 (A - mu g) / omega^2 and the
    peak absolute acceleration, just before the stop, omega^2 |u| + mu g = 2 A - mu g."""
    return [motions.rect_pulse(a, T / 2) for a in amps]


def travel(a, mu):
    return 2 * (a - mu * G) / OMEGA2


def felt(a, mu):
    return 2 * a - mu * G


@pytest.fixture(scope="module")
def venere():
    return verify(VENERE, records=_pulses(AMPS), mu=MU, mu_low=MU_LOW, mu_high=MU_HIGH, **ONE)


def test_margins_of_a_case_solved_by_hand(venere):
    d = venere
    mean = lambda xs: sum(xs) / len(xs)                                       # noqa: E731
    u = mean([travel(a, MU_LOW) for a in AMPS])          # the lower bound travels further ...
    a = mean([felt(a, MU_LOW) for a in AMPS])            # ... and, on a pulse, also feels more
    assert u > mean([travel(a, MU_HIGH) for a in AMPS]) and a > mean([felt(a, MU_HIGH) for a in AMPS])
    need = DISPLACEMENT_MARGIN * u + MU_HIGH * 2 * (R - r)
    v = d.verification
    assert v["statistic"] == "mean" and v["records"]["count"] == 7
    assert v["demand"]["travel"] == pytest.approx(u, rel=1e-7) and v["demand"]["felt"] == pytest.approx(a, rel=1e-7)
    th = {c.key: c for c in d.checks if c.key.startswith("th_")}
    assert th["th_travel"].value == pytest.approx(need, rel=1e-7) and th["th_travel"].required
    # the opening is cut to the larger need: here the time histories' (the spectrum's is smaller)
    assert v["demand"]["capacity_sized_on"] == "time histories" and v["demand"]["spectral_need"] < need
    # cut for the need plus SIZING_CLEARANCE, the opening radius rounded up to OPENING_STEP (groove rim:
    # capacity = a R_hat / R): never the need to the last digit
    assert d.capacity_limited_by == "groove rim"
    assert d.opening_radius / OPENING_STEP == pytest.approx(round(d.opening_radius / OPENING_STEP), abs=1e-9)
    assert need * (1 + SIZING_CLEARANCE) <= d.capacity <= need * (1 + SIZING_CLEARANCE) + OPENING_STEP * 2 * (R - r) / R
    a_lim = min(VENERE.a_L, VENERE.a_R)                  # alpha 1, no band
    W = (VENERE.m + d.m_o) * G
    m = d.th_margins
    assert m["travel"] == pytest.approx(d.capacity / need, rel=1e-5) and m["travel"] >= 1 + SIZING_CLEARANCE - 1e-6
    assert m["acceleration"] == pytest.approx(a_lim / a, rel=1e-5)          # (6 digits, as design.json)
    assert m["bearing"] == pytest.approx(BALL_LOAD_TESTED / (W / 4), rel=1e-5)   # 20 mm balls: no scaling
    assert d.passed and d.what_would_pass is None
    # the spectral felt acceleration stays in the table, advisory: the time histories decide
    assert not next(c for c in d.checks if c.key == "acceleration").required
    dd = d.to_dict()
    json.dumps(dd, allow_nan=False)
    assert dd["th_margins"] == pytest.approx(m) and dd["verification"]["mu_low"] == MU_LOW
    assert dd["candidates"]["rows"][0]["margins"] == pytest.approx(m, rel=1e-5)
    assert "time-history verification" in d.report() and "balance" in d.report()


def test_fewer_than_seven_records_take_the_most_unfavourable():
    d = verify(VENERE, records=_pulses((0.2, 0.3)), mu=MU, mu_low=MU_LOW, mu_high=MU_HIGH, **ONE)
    assert d.verification["statistic"] == "max"
    assert d.verification["demand"]["travel"] == pytest.approx(travel(0.3, MU_LOW), rel=1e-7)


def _entry(R, acc, bearing, m_o, travel=1.0, ok=True):
    c = SimpleNamespace(R=R, r=0.02, side=0.5, thickness=0.03, n_grooves=4, m_o=m_o)
    return Verified(c, Margins(travel, acc, bearing), (), ok, 0.1)


def test_the_choice_is_the_best_balance_of_margins_not_the_longest_period():
    longest = _entry(2.0, acc=5.0, bearing=1.2, m_o=10.0)     # balance 1.2
    best = _entry(1.0, acc=2.5, bearing=2.0, m_o=12.0)        # balance 2.0, the best
    near = _entry(0.6, acc=1.9, bearing=2.1, m_o=11.0)        # balance 1.9: within 10 %, and lighter
    short = _entry(0.4, acc=0.9, bearing=3.0, m_o=5.0)        # the lightest, but fails on acceleration
    order = rank([longest, best, near, short])
    assert [e.candidate.R for e in order] == [0.6, 1.0, 2.0, 0.4]
    # outside the 10 % the balance decides, not the plate
    far = _entry(0.6, acc=1.7, bearing=2.1, m_o=11.0)         # balance 1.7 < 0.9 x 2.0
    assert [e.candidate.R for e in rank([longest, best, far])] == [1.0, 0.6, 2.0]
    # a travel margin at 1 (the sizing) does not flatten the balance; below 1 it fails and counts
    assert Margins(1.0, 3.0, 2.0).balance == 2.0 and Margins(0.8, 3.0, 2.0).balance == 0.8


def test_a_real_search_follows_the_criterion():
    recs = [motions.synthetic_record(duration=10.0, pga=0.6, seed=s) for s in (1, 2)]
    d = verify(VENERE, records=recs, mu=MU, spectrum=SPECTRUM, thickness=0.03, R_grid=(0.4, 0.8, 1.2, 2.0),
               balls=(0.02, 0.03))
    rows = [row for row in d.candidates["rows"] if row["passed"]]
    assert d.passed and len(rows) > 1 and d.candidates["rows"][0]["passed"]
    top = max(row["balance"] for row in rows)
    near = [row for row in rows if row["balance"] >= 0.9 * top]
    assert d.m_o == pytest.approx(min(row["m_o"] for row in near), abs=1e-3)
    assert all(min(row["margins"]["acceleration"], row["margins"]["bearing"]) == pytest.approx(row["balance"])
               for row in rows)


HEAVY = RockingParams.from_dict({"m": 60.0, "h": 0.5, "b_L": 0.3, "b_R": 0.3, "I_G": 60 * 0.35})


def test_a_failing_ball_load_says_which_capacity_radius_or_count_would_pass():
    d = verify(HEAVY, records=_pulses(AMPS), mu=MU, mu_low=MU_LOW, mu_high=MU_HIGH, **ONE)
    assert not d.passed and d.th_margins["bearing"] < 1 <= d.th_margins["acceleration"]
    assert d.failure.startswith("load per ball within what the grooves carry")
    W = (HEAVY.m + d.m_o) * G
    P = W / 4
    w = d.what_would_pass
    assert w["load_per_ball"] == pytest.approx(P, rel=1e-5)
    assert w["ball_capacity_needed"] == pytest.approx(P, rel=1e-5)           # 20 mm balls: the convention itself
    assert w["ball_radius_needed"] == pytest.approx(0.02 * math.sqrt(P / BALL_LOAD_TESTED), rel=1e-5)
    assert w["balls_needed"] == math.ceil(W / BALL_LOAD_TESTED) and not w["restrain"]
    assert "load-test" in w["text"] and d.to_dict()["what_would_pass"] == w
    # a load test that carries it (N per 20 mm ball) lets the same device pass
    ok = verify(HEAVY, records=_pulses(AMPS), mu=MU, mu_low=MU_LOW, mu_high=MU_HIGH, ball_capacity=1.01 * P, **ONE)
    assert ok.passed and ok.th_margins["bearing"] == pytest.approx(1.01, rel=1e-3)


def test_a_statue_that_cannot_stay_in_contact_is_to_be_restrained():
    d = verify(VENERE, records=_pulses(AMPS), mu=MU, mu_low=MU_LOW, mu_high=MU_HIGH, a_lim=0.3,
               a_lim_why="a low test limit", spectrum=SPECTRUM, R_grid=(0.5, R), balls=(r,), n_grooves=4,
               thickness=0.03)
    assert not d.passed and d.th_margins["acceleration"] < 1
    w = d.what_would_pass
    assert w["restrain"] and w["text"].startswith("restrain the statue")
    assert w["best_acceleration_margin"] < 1 and d.verification["a_lim"] == 0.3


def test_bad_verification_inputs():
    with pytest.raises(InputError, match="mu_low 0.01 <= mu 0.0073"):
        verify(VENERE, records=_pulses(AMPS[:1]), mu=MU, mu_low=0.01, **ONE)
    with pytest.raises(InputError, match="at least one design record"):
        verify(VENERE, records=[], mu=MU, **ONE)
    with pytest.raises(InputError, match="ball capacity"):
        verify(VENERE, records=_pulses(AMPS[:1]), mu=MU, ball_capacity=-5.0, **ONE)
    assert friction_bounds(0.0073) == pytest.approx((0.0039, 0.0108))


def test_the_project_file_keys():
    from statue2model.pipeline.config import load_config, load_config_text

    assert (load_config(None).isolator.mu_low, load_config(None).isolator.ball_capacity) == (None, None)
    cfg = load_config_text('[isolator]\nmu_low = 0.005\nmu_high = 0.01\nball_capacity = 300\n', "p")
    assert (cfg.isolator.mu_low, cfg.isolator.mu_high, cfg.isolator.ball_capacity) == (0.005, 0.01, 300.0)
    for text, words in (('[isolator]\nmu_low = 0.01\n', "mu_low (0.01) must not exceed mu"),
                        ('[isolator]\nball_capacity = 0\n', "ball_capacity must be a positive load")):
        with pytest.raises(InputError, match=words.replace("(", r"\(").replace(")", r"\)")):
            load_config_text(text, "p")


def test_the_bearing_limit_state_takes_the_designs_ball_capacity():
    from statue2model.assessment.limit_states import _isolated_rows
    from statue2model.isolator.device import Isolator

    iso = Isolator(R=1.0, r=0.03, M=100.0, mu=MU, capacity=0.3)
    rec = SimpleNamespace(acc_felt=0.5, capacity_exceeded=False, uplift=False, pga=1.0, theta_max_over_delta=0.0,
                          overturned=False, n_impacts=0, u_max=0.1)
    design = {"n_grooves": 4, "capacity": 0.3, "mu": MU, "R_hat": iso.R_hat, "margin": 1.5,
              "ball_capacity": {"tested_load": 400.0, "tested_radius": 0.02, "source": "a test"}}
    row = next(x for x in _isolated_rows([rec], (2.0, 2.0), iso, design, "max") if x.name == "bearing")
    assert row.capacity == pytest.approx(400.0 * (0.03 / 0.02) ** 2)            # 900 N, not the beech 165 N
    assert row.demand == pytest.approx(100.0 * G / 4) and not row.exceeded
