"""The isolator verified by time histories (isolator/verify.py): margins against a case solved by hand,
the statistic over a set, the collapse level, the cheapest device that passes, what would pass when
nothing does, and restraint."""
from __future__ import annotations

import json
import math
from types import SimpleNamespace

import numpy as np
import pytest

from statue2model.errors import InputError
from statue2model.geometry.rocking_params import RockingParams
from statue2model.hazard import motions
from statue2model.hazard.code_spectra import G as G0
from statue2model.hazard.code_spectra import ec8
from statue2model.isolator.bearing import SURFACES, ball_capacity
from statue2model.isolator.checks import DISPLACEMENT_MARGIN, GAMMA_X, SLC_MARGIN
from statue2model.isolator.design import COST_TOLERANCE, OPENING_STEP, SIZING_CLEARANCE
from statue2model.isolator.device import lever_arm
from statue2model.isolator.layout import LAYOUTS
from statue2model.isolator.verify import MU_STEP, RecordSet, friction_bounds, verify

G = 9.81
MU, MU_LOW, MU_HIGH = 0.0073, 0.004, 0.010
R, r = 1.0, 0.02                                          # one (R, r): the runs are solved by hand
OMEGA2 = G / (2 * (R - r))
T = 2 * math.pi / math.sqrt(OMEGA2)
AMPS = (0.20, 0.23, 0.26, 0.29, 0.32, 0.35, 0.38)         # m/s^2: seven records -> the mean
SPECTRUM = ec8(0.05 * G0, "A")                            # small: the records govern the travel
VENERE = RockingParams.from_dict({"m": 12.074, "h": 0.3523, "b_L": 0.1995, "b_R": 0.0805, "I_G": 0.7994})
ONE = dict(spectrum=SPECTRUM, R_grid=(R,), balls=(r,), layouts="ring4", surfaces="beech", materials="resin",
           thickness=0.03)
BEECH_40 = ball_capacity(0.040, SURFACES["beech"])         # 30 kg on four 40 mm balls, long-term


def _pulses(amps, scale=1.0):
    """Half-period rectangular pulses of amplitude A from rest. By hand (Coulomb, omega^2 = g / R_hat):
    the plate slides back against friction to u = -2 (A - mu g) / omega^2 at t = T/2, where it stops as
    the pulse ends; it then swings back less far, so the peak travel is 2 (A - mu g) / omega^2 and the
    peak absolute acceleration, just before the stop, omega^2 |u| + mu g = 2 A - mu g."""
    return [motions.rect_pulse(a * scale, T / 2) for a in amps]


def travel(a, mu):
    return 2 * (a - mu * G) / OMEGA2


def felt(a, mu):
    return 2 * a - mu * G


def mean(xs):
    return sum(xs) / len(xs)


@pytest.fixture(scope="module")
def venere():
    return verify(VENERE, records=_pulses(AMPS), mu=MU, mu_low=MU_LOW, mu_high=MU_HIGH, **ONE)


def test_friction_bounds_are_rounded_outward(venere):
    v = venere.verification
    lo, hi = v["mu_low"], v["mu_high"]
    assert lo <= MU_LOW and MU_LOW / lo < MU_STEP and hi >= MU_HIGH and hi / MU_HIGH < MU_STEP
    for x in (lo, hi):                                     # powers of 1.05 (6 digits)
        k = math.log(x) / math.log(MU_STEP)
        assert k == pytest.approx(round(k), abs=1e-4)


def test_margins_of_a_case_solved_by_hand(venere):
    d = venere
    v = d.verification
    lo, hi = v["mu_low"], v["mu_high"]
    u = mean([travel(a, lo) for a in AMPS])              # the lower bound travels further ...
    a = mean([felt(a, lo) for a in AMPS])                # ... and, on a pulse, also feels more
    assert u > mean([travel(a, hi) for a in AMPS]) and a > mean([felt(a, hi) for a in AMPS])
    R_hat = 2 * (R - r)
    need = DISPLACEMENT_MARGIN * u + hi * R_hat
    assert v["statistic"] == "mean" and v["records"]["count"] == 7
    (s,) = v["sets"]
    assert s["name"] == "design" and s["records"] == 7
    assert s["travel"] == pytest.approx(u, rel=1e-7) and s["felt"] == pytest.approx(a, rel=1e-7)
    assert s["need"] == pytest.approx(need, rel=1e-7)
    # the collapse level: the design set x gamma_x 1.2 (EC8, no SLC spectrum given)
    u_slc = mean([travel(GAMMA_X * a, lo) for a in AMPS])
    a_slc = mean([felt(GAMMA_X * a, lo) for a in AMPS])
    need_slc = SLC_MARGIN * u_slc + hi * R_hat
    assert v["slc"]["scale"] == GAMMA_X and v["slc"]["travel"] == pytest.approx(u_slc, rel=1e-7)
    assert v["slc"]["felt"] == pytest.approx(a_slc, rel=1e-7) and v["slc"]["need"] == pytest.approx(need_slc, rel=1e-7)
    th = {c.key: c for c in d.checks if c.key.startswith("th_")}
    assert th["th_travel"].value == pytest.approx(need, rel=1e-7) and th["th_travel"].required
    assert th["th_travel_slc"].value == pytest.approx(need_slc, rel=1e-7) and th["th_travel_slc"].level == "SLC"
    assert th["th_acceleration"].value == pytest.approx(a, rel=1e-7)
    # the opening is cut to the larger time-history need (here the SLC one), plus SIZING_CLEARANCE, the opening
    # radius rounded up to OPENING_STEP (groove rim: capacity = a R_hat / R): never the need to the last digit
    governing = max(need, need_slc)
    assert need_slc > need and d.travel_need == pytest.approx(governing, rel=1e-9)
    assert d.capacity_limited_by == "groove rim"
    assert d.opening_radius / OPENING_STEP == pytest.approx(round(d.opening_radius / OPENING_STEP), abs=1e-9)
    assert governing * (1 + SIZING_CLEARANCE) <= d.capacity <= \
        governing * (1 + SIZING_CLEARANCE) + OPENING_STEP * R_hat / R + 1e-12
    a_lim = min(VENERE.a_L, VENERE.a_R)                  # alpha 1
    M = VENERE.m + d.m_o
    W = M * G
    m = d.th_margins
    assert m["travel"] == pytest.approx(d.capacity / need, rel=1e-5)          # (6 digits, as design.json)
    assert m["travel_slc"] == pytest.approx(d.capacity / need_slc, rel=1e-5) and m["travel_slc"] >= 1 + SIZING_CLEARANCE - 1e-5
    assert m["acceleration"] == pytest.approx(a_lim / a, rel=1e-5)
    assert m["bearing"] == pytest.approx(BEECH_40.load / (W / 4), rel=1e-5)    # 40 mm balls: the calibration
    # the most loaded ball at SLC, by hand: W / 4 + M a_SLC l / spread (ring4: spread = sqrt 2 x spacing)
    l = lever_arm(VENERE.m, VENERE.h, d.m_o, d.thickness)
    assert LAYOUTS["ring4"].spread(d.spacing) == pytest.approx(math.sqrt(2) * d.spacing)
    P_dyn = W / 4 + M * a_slc * l / (math.sqrt(2) * d.spacing)
    assert m["bearing_slc"] == pytest.approx(BEECH_40.short / P_dyn, rel=1e-5)
    assert m["reserve"] is None and v["reserve"] is None                        # no fixed-base model given
    assert d.passed and d.what_would_pass is None and all(x >= 1 for x in m.values() if x is not None)
    # the spectral felt acceleration stays in the table, advisory: the time histories decide
    spectral = next(c for c in d.checks if c.key == "acceleration")
    assert not spectral.required and "advisory" in str(spectral.why)
    dd = d.to_dict()
    json.dumps(dd, allow_nan=False)
    assert dd["verification"]["mu_low"] == lo
    for got in (dd["th_margins"], dd["candidates"]["rows"][0]["margins"]):
        assert set(got) == set(m) and got["reserve"] is None
        assert {k: x for k, x in got.items() if x is not None} == pytest.approx(
            {k: x for k, x in m.items() if x is not None}, rel=1e-5)
    rep = d.report()
    assert "time-history verification" in rep and "the mean over each set" in rep and "set design" in rep


def test_fewer_than_seven_records_take_the_most_unfavourable():
    d = verify(VENERE, records=_pulses((0.2, 0.3)), mu=MU, mu_low=MU_LOW, mu_high=MU_HIGH, **ONE)
    v = d.verification
    assert v["statistic"] == "max" and v["records"]["count"] == 2
    assert v["sets"][0]["travel"] == pytest.approx(travel(0.3, v["mu_low"]), rel=1e-7)
    assert v["sets"][0]["felt"] == pytest.approx(felt(0.3, v["mu_low"]), rel=1e-7)
    assert d.passed and all(x >= 1 for x in d.th_margins.values() if x is not None)


def test_every_set_must_hold_and_the_opening_is_cut_for_the_worst():
    """A further set of stronger pulses asks more travel than the design set: the travel check and its
    margin read the worst set, and the opening is cut for it."""
    extra = RecordSet("stronger", tuple(_pulses(AMPS, scale=1.1)), seeds="8-14")
    d = verify(VENERE, records=_pulses(AMPS), mu=MU, mu_low=MU_LOW, mu_high=MU_HIGH, extra_sets=[extra], **ONE)
    v = d.verification
    lo, hi = v["mu_low"], v["mu_high"]
    names = [s["name"] for s in v["sets"]]
    assert names == ["design", "stronger"] and v["sets"][1]["seeds"] == "8-14"
    u2 = mean([travel(1.1 * a, lo) for a in AMPS])
    assert v["sets"][1]["travel"] == pytest.approx(u2, rel=1e-7)
    need2 = DISPLACEMENT_MARGIN * u2 + hi * 2 * (R - r)
    assert need2 > v["sets"][0]["need"] and need2 > v["slc"]["need"]          # the stronger set governs
    th = next(c for c in d.checks if c.key == "th_travel")
    assert th.value == pytest.approx(need2, rel=1e-7) and "set stronger" in str(th.why)
    assert d.capacity >= need2 * (1 + SIZING_CLEARANCE) and d.passed
    assert d.th_margins["travel"] == pytest.approx(d.capacity / need2, rel=1e-5)
    assert d.th_margins["acceleration"] == pytest.approx(min(VENERE.a_L, VENERE.a_R) /
                                                         mean([felt(1.1 * a, lo) for a in AMPS]), rel=1e-5)


def test_a_real_search_follows_the_criterion():
    recs = [motions.synthetic_record(duration=10.0, pga=0.6, seed=s) for s in (1, 2)]
    d = verify(VENERE, records=recs, mu=MU, spectrum=SPECTRUM, thickness=0.03, R_grid=(0.4, 0.8, 1.2, 2.0),
               balls=(0.02, 0.03), surfaces="beech", layouts=("ring3", "ring4"))
    rows = d.candidates["rows"]
    verified = [row for row in rows if "margins" in row]                     # the rows that were run
    passing = [row for row in verified if row["passed"]]
    assert d.passed and rows[0]["passed"] and rows[0] is verified[0] and len(verified) >= 2
    assert d.verification["statistic"] == "max" and d.verification["candidates_passing"] == len(passing)
    cheapest = min(row["cost"] for row in passing)
    assert d.cost <= cheapest * (1 + COST_TOLERANCE) + 0.01
    band = [row for row in passing if row["cost"] <= cheapest * (1 + COST_TOLERANCE)]
    assert all(row["worst_ratio"] >= rows[0]["worst_ratio"] - 1e-6 for row in band)
    for row in verified:
        assert row["passed"] == all(ck[3] for ck, k in zip(row["checks"], d.candidates["checks"]) if k["required"])
    assert all(m >= 1 for m in d.th_margins.values() if m is not None)
    # the opening is cut to at least the time histories' need
    th = {c.key: c for c in d.checks}
    assert d.capacity >= max(th["th_travel"].value, th["th_travel_slc"].value)


HEAVY = RockingParams.from_dict({"m": 60.0, "h": 0.5, "b_L": 0.3, "b_R": 0.3, "I_G": 60 * 0.35})


def test_a_failing_ball_load_says_so_and_a_load_test_that_carries_it_passes():
    d = verify(HEAVY, records=_pulses(AMPS), mu=MU, mu_low=MU_LOW, mu_high=MU_HIGH, **ONE)
    assert not d.passed and d.th_margins["bearing"] < 1 <= d.th_margins["acceleration"]
    W = (HEAVY.m + d.m_o) * G
    P = W / 4
    assert d.th_margins["bearing"] == pytest.approx(BEECH_40.load / P, rel=1e-5)
    load = next(c for c in d.checks if c.key == "ball_load")
    assert not load.passed and load.value == pytest.approx(P) and load.limit == pytest.approx(BEECH_40.load)
    assert d.failure.startswith("load per ball within what the grooves carry")
    w = d.what_would_pass
    assert w["reason"] == "ball_load" and not w["restrain"] and f"{P:.0f} N per ball" in w["text"]
    assert d.to_dict()["what_would_pass"] == w
    # a load test (N on a 40 mm ball, short-term) whose long-term value carries it lets the same grooves pass
    X = 1.01 * P * 1.6
    ok = verify(HEAVY, records=_pulses(AMPS), mu=MU, mu_low=MU_LOW, mu_high=MU_HIGH, ball_capacity=X, **ONE)
    P_ok = (HEAVY.m + ok.m_o) * G / 4
    assert ok.passed and ok.th_margins["bearing"] == pytest.approx(X / 1.6 / P_ok, rel=1e-4)


def test_a_statue_that_cannot_stay_in_contact_is_to_be_restrained():
    """An uplift limit of 0.5 m/s^2: above the pits' roll-out (0.44 m/s^2) and the friction, below what the
    records pass on (0.54 m/s^2 at R = 1 m)."""
    d = verify(VENERE, records=_pulses(AMPS), mu=MU, mu_low=MU_LOW, mu_high=MU_HIGH, a_lim=0.5,
               a_lim_why="a low test limit", **{**ONE, "R_grid": (0.5, R)})
    assert not d.passed and d.th_margins["acceleration"] < 1
    assert any(c.key == "th_acceleration" and not c.passed for c in d.checks)
    w = d.what_would_pass
    assert w["reason"] == "acceleration" and w["restrain"] and "restrain it instead" in w["text"]
    assert d.verification["a_lim"] == 0.5 and "a low test limit" in d.verification["a_lim_why"]
    assert all(c.passed for c in d.checks if c.key in ("friction", "pit"))


def test_a_statue_whose_uplift_is_below_the_friction_is_to_be_restrained():
    d = verify(VENERE, records=_pulses(AMPS), mu=MU, mu_low=MU_LOW, mu_high=MU_HIGH, alpha=(0.02, 0.02), **ONE)
    assert not d.passed and d.what_would_pass["reason"] == "friction" and d.what_would_pass["restrain"]


def test_bad_verification_inputs():
    with pytest.raises(InputError, match="mu_low 0.01 <= mu 0.0073"):
        verify(VENERE, records=_pulses(AMPS[:1]), mu=MU, mu_low=0.01, **ONE)
    with pytest.raises(InputError, match="at least one design record"):
        verify(VENERE, records=[], mu=MU, **ONE)
    with pytest.raises(InputError, match="friction bound mu_high must be in"):
        verify(VENERE, records=_pulses(AMPS[:1]), mu=MU, mu_low=0.004, mu_high=0.7, **ONE)
    with pytest.raises(InputError, match="ball capacity") as e:
        verify(VENERE, records=_pulses(AMPS[:1]), mu=MU, ball_capacity=-5.0, **ONE)
    assert "\n" not in str(e.value)
    with pytest.raises(InputError, match="thickness"):
        verify(VENERE, records=_pulses(AMPS[:1]), mu=MU, **{**ONE, "thickness": 0.5})
    assert friction_bounds(0.0073) == pytest.approx((0.0039, 0.0108))


def test_the_project_file_keys():
    from statue2model.pipeline.config import load_config, load_config_text

    assert (load_config(None).isolator.mu_low, load_config(None).isolator.ball_capacity) == (None, None)
    cfg = load_config_text('[isolator]\nmu_low = 0.005\nmu_high = 0.01\nball_capacity = 300\nsurface = "beech"\n',
                           "p")
    assert (cfg.isolator.mu_low, cfg.isolator.mu_high, cfg.isolator.ball_capacity) == (0.005, 0.01, 300.0)
    for text, words in (('[isolator]\nmu = 0.0073\nmu_low = 0.01\n', "mu_low (0.01) must not exceed mu"),
                        ('[isolator]\nmu_low = 0.004\n', "give mu_low and mu_high together, or mu"),
                        ('[isolator]\nball_capacity = 0\n', "ball_capacity = 0 N is implausible"),
                        ('[isolator]\nball_capacity = 300\n', "a load test of one groove surface")):
        with pytest.raises(InputError, match=words.replace("(", r"\(").replace(")", r"\)")):
            load_config_text(text, "p")


def test_the_bearing_limit_state_takes_the_designs_ball_capacity():
    from statue2model.assessment.limit_states import _isolated_rows
    from statue2model.isolator.device import Isolator

    iso = Isolator(R=1.0, r=0.03, M=100.0, mu=MU, capacity=0.3)
    rec = SimpleNamespace(acc_felt=0.5, capacity_exceeded=False, uplift=False, pga=1.0, theta_max_over_delta=0.0,
                          overturned=False, n_impacts=0, u_max=0.1)
    cap = ball_capacity(0.06, SURFACES["steel_race"], R=1.0)                       # a steel race: kN per ball
    design = {"n_grooves": 4, "capacity": 0.3, "mu": MU, "R_hat": iso.R_hat, "margin": 1.5,
              "ball_capacity": {"per_ball": cap.load, "criterion": cap.criterion, "source": cap.source,
                                "surface": "steel_race"}}
    row = next(x for x in _isolated_rows([rec], (2.0, 2.0), iso, design, "max") if x.name == "bearing")
    assert row.capacity == pytest.approx(cap.load)                             # not the beech 57 N
    assert row.demand == pytest.approx(100.0 * G / 4) and not row.exceeded
    assert row.details["criterion"] == cap.criterion and row.details["surface"] == "steel_race"


def test_the_reserve_keeps_the_travel_up_to_where_the_fixed_base_overturns():
    """With the fixed-base model: each design record's lowest overturning scale (capped at RESERVE_LEVEL x the
    design PGA); at their geometric mean every record scaled, the median travel x 1.05 + mu_high R_hat fits."""
    from statue2model.isolator.checks import RESERVE_LEVEL, RESERVE_MARGIN
    from statue2model.rocking.model import RockingModel

    recs = [motions.synthetic_record(duration=10.0, pga=2.0, seed=s) for s in (1, 2, 3)]
    d = verify(VENERE, records=recs, mu=MU, spectrum=SPECTRUM, thickness=0.03, R_grid=(0.4, 0.8), balls=(0.02,),
               surfaces="beech", layouts=("ring4", "ring8"), fixed_model=RockingModel.housner(VENERE))
    res = d.verification["reserve"]
    pga0 = mean([m.pga for m in recs])
    assert res["design_pga"] == pytest.approx(pga0) and res["level"] == RESERVE_LEVEL
    th = res["thresholds"]
    assert all(t <= RESERVE_LEVEL * pga0 * (1 + 1e-9) for t in th)
    assert all(o == (t < RESERVE_LEVEL * pga0 * (1 - 1e-9)) for o, t in zip(res["overturns"], th))
    geo = math.exp(mean([math.log(t) for t in th]))
    assert res["pga"] == pytest.approx(min(geo, RESERVE_LEVEL * pga0), rel=1e-9)
    per = sorted(res["travel_per_record"])
    assert res["travel"] == pytest.approx(per[1], rel=1e-12)                      # the median of three
    hi = d.verification["mu_high"]
    assert res["need"] == pytest.approx(RESERVE_MARGIN * per[1] + hi * d.R_hat, rel=1e-9)
    reserve = next(c for c in d.checks if c.key == "reserve")
    assert reserve.required and reserve.level == "reserve" and reserve.value == pytest.approx(res["need"])
    assert d.th_margins["reserve"] == pytest.approx(d.capacity / res["need"], rel=1e-5)
    assert d.passed and all(m >= 1 for m in d.th_margins.values()) and any(res["overturns"])
    assert d.capacity >= max(c.value for c in d.checks if c.key in ("th_travel", "th_travel_slc", "reserve"))


def test_screen_one_record_equals_the_whole_grid_bit_for_bit():
    """_Screen._at on one record's grid (nested lists, the floor's reserve term) gives bit for bit the
    element of the whole grid's value, and the period's position given or not changes nothing."""
    from statue2model.isolator.verify import _Screen

    rng = np.random.default_rng(3)
    for n_T in (1, 2, 5):
        sc = object.__new__(_Screen)
        sc.T = np.linspace(0.8, 3.1, n_T)
        sc.mu = np.geomspace(1e-4, 0.02, 6)
        sc.u = rng.uniform(0.0, 0.5, (n_T, 6, 7))
        sc._log_mu, sc._j = np.log(sc.mu), np.arange(6)
        sc._u_record = [sc.u[:, :, i].tolist() for i in range(7)]
        for T, mu in zip(rng.uniform(0.5, 3.5, 40), np.exp(rng.uniform(math.log(1e-5), math.log(0.05), 40))):
            whole = sc._at(sc.u, T, mu)
            assert np.array_equal(whole, sc._at(sc.u, T, mu, sc._x(T)))
            assert [sc._at(sc._u_record[i], T, mu) for i in range(7)] == whole.tolist()
