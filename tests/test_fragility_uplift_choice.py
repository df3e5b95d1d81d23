"""The fixed-base uplift curve never contradicts the count of its exact thresholds (issue [25], item 1).

The rule (assessment/fragility_fit.py UPLIFT_RULE, docs/fragility.md): with the exact thresholds x*
of the runs and k = #(x* <= x), the lognormal fit is reported only where no threshold is tied and its P
lies inside the 95 % Wilson interval of k / n at the design PGA and at every level run; else the
empirical step CDF of x*, with the reason.
"""
from __future__ import annotations

import json
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from statue2model.assessment.fragility import (
    EMPIRICAL,
    EXACT,
    FragilityStudy,
    _json_ready,
    exact_uplift,
    uplift_thresholds,
    wilson_interval,
)
from statue2model.assessment.fragility_fit import FragilityCurve, distinct_thresholds
from statue2model.assessment.study import curve_entry
from statue2model.assessment.verdict import _curve_text
from statue2model.geometry.rocking_params import RockingParams
from statue2model.hazard import motions
from statue2model.rocking import RockingModel
from statue2model.rocking.sampling import latin_hypercube, nominal

G = 9.81
A_R = 2.7170168865411677           # the default scan's a_R (m/s^2)
DESIGN_PGA = 2.8194118749999997     # its design PGA


def _blank(levels, n_runs):
    """The counted-at-levels curve exact_uplift replaces (its counts stay the plot's points)."""
    lv = np.asarray(levels, dtype=float)
    return FragilityCurve("full_contact_fixed", lv, np.zeros(lv.size, int), np.full(lv.size, n_runs), math.nan,
                          math.nan, "ok")


def _uplift(x, levels, design_pga, n_boot=50):
    """exact_uplift on thresholds ``x`` (records, samples), every run counted: (curve, its entry at the design PGA)."""
    x = np.atleast_2d(np.asarray(x, dtype=float))
    valid = np.ones((*x.shape, len(levels)), dtype=bool)
    cv, _ = exact_uplift(_blank(levels, x.size), x, valid, FragilityStudy(n_boot=n_boot, seed=0), "records", {},
                         design_im=design_pga)
    return cv, curve_entry(cv, design_pga)


def _inside(p, k, n):
    lo, hi = wilson_interval(k, n)
    return lo - 1e-12 <= p <= hi + 1e-12


def test_the_default_scan_case_reads_the_count_not_the_lognormal():
    """4 of 7 thresholds tied at a_R, 6 of 7 below the design PGA (issue [25]): the lognormal gave P 0.47
    there, outside the Wilson interval of 6/7 (0.487-0.974) and unable to hold the tie; the curve reported
    is the empirical one, P = 6/7, and its status and text say why."""
    x = np.array([[A_R], [A_R], [2.70], [A_R], [2.80], [A_R], [3.65]])     # lognormal P 0.47 at the design PGA
    lv = np.geomspace(0.2, 3.0, 10) * G
    lx = np.log(x)
    p_lognormal = 0.5 * math.erfc(-math.log(DESIGN_PGA / math.exp(lx.mean())) / lx.std() / math.sqrt(2))
    assert not _inside(p_lognormal, 6, 7)                  # the defect: the lognormal contradicts the count
    cv, e = _uplift(x, lv, DESIGN_PGA)
    assert cv.status == EMPIRICAL and "4 of 7 thresholds are tied" in cv.choice["reason"]
    assert e["p_design"] == pytest.approx(6 / 7) and _inside(e["p_design"], 6, 7)
    assert e["p_design_count"]["k"] == 6 and e["p_design_count"]["n"] == 7
    assert e["p_design_ci"] == pytest.approx(list(wilson_interval(6, 7)))
    assert e["curve_kind"] == "empirical" and e["identified"] and e["beta"] is None
    assert "tied" in e["beta_reason"]
    text = _curve_text(e)
    assert text.startswith("empirical (4 of 7 thresholds are tied") and "6 of 7 thresholds" in text
    assert cv.choice["lognormal"]["median"] == pytest.approx(math.exp(lx.mean()))   # the rejected fit, kept
    d = json.loads(json.dumps(_json_ready(cv.to_dict())))          # fragility.json's curve reads back
    assert d["status"] == "empirical" and d["thresholds"] == sorted(x.ravel().tolist()) and d["beta"] is None
    back = FragilityCurve.from_dict(d)
    assert back.probability(DESIGN_PGA) == pytest.approx(6 / 7)
    assert json.loads(json.dumps(_json_ready(back.to_dict()))) == d


def test_a_lognormal_that_contradicts_the_count_without_ties_is_not_kept():
    """No tie, but the lognormal's P at the design PGA lies outside the Wilson interval of the count."""
    x = np.array([[2.60], [2.65], [2.70], [2.72], [2.75], [2.80], [4.5]])       # one far above
    lv = np.geomspace(0.2, 3.0, 10) * G
    cv, e = _uplift(x, lv, DESIGN_PGA)
    assert cv.status == EMPIRICAL and "outside the 95 % Wilson interval" in cv.choice["reason"]
    assert e["p_design"] == pytest.approx(6 / 7)


def test_a_lognormal_that_agrees_with_the_count_is_kept():
    """No tie and a lognormal that agrees with the count at the design PGA and at every level: kept
    (status exact), with the count and its interval beside it."""
    n = 20
    from scipy.stats import norm

    x = (3.0 * np.exp(0.3 * norm.ppf((np.arange(n) + 0.5) / n)))[:, None]   # lognormal quantiles
    lv = np.geomspace(1.0, 8.0, 9)
    cv, e = _uplift(x, lv, DESIGN_PGA)
    assert cv.status == EXACT and cv.choice["curve"] == EXACT and cv.choice["reason"] is None
    assert cv.choice["max_tie"] == 1 and DESIGN_PGA in cv.choice["checked_at"]
    k = int(np.sum(x <= DESIGN_PGA))
    assert e["curve_kind"] == "lognormal" and e["p_design_count"]["k"] == k and e["p_design_count"]["n"] == n
    assert e["p_design"] == pytest.approx(float(cv.probability(DESIGN_PGA))) and _inside(e["p_design"], k, n)
    assert e["beta"] == pytest.approx(float(np.log(x).std()))
    # a reader's own design level is checked too: far in the tail the lognormal still agrees, or is replaced
    for pga in (1.5, 2.5, 3.0, 4.0, 6.0):
        e2 = curve_entry(cv, pga)
        c = e2["p_design_count"]
        assert _inside(e2["p_design"], c["k"], c["n"]), (pga, e2["p_design"], c)


def test_samples_that_do_not_move_the_threshold_count_once():
    """Samples that vary only e or mu leave each record's threshold: the count is over records, and the
    ties are the records', not the samples' replicas."""
    x = np.repeat(np.array([[A_R], [2.9], [3.0], [3.1], [3.2]]), 7, axis=1)
    assert distinct_thresholds(x).tolist() == [A_R, 2.9, 3.0, 3.1, 3.2]
    lv = np.geomspace(0.2, 3.0, 10) * G
    cv, e = _uplift(x, lv, DESIGN_PGA)
    assert cv.choice["max_tie"] == 1 and cv.choice["n_runs"] == 35 and e["p_design_count"]["n"] == 5


# --- the property: over rectangular blocks and asymmetric bodies under records ------------------
RECORDS = [motions.synthetic_record(6.0, 0.01, 2.0, seed=s) for s in range(7)]


@settings(max_examples=60, deadline=None, derandomize=True)
@given(b_L=st.floats(0.03, 0.5), ratio=st.floats(0.3, 1.0), h=st.floats(0.2, 1.5),
       n_rec=st.integers(3, 7), vary=st.booleans(), where=st.floats(-1.5, 1.5), at_tie=st.booleans())
def test_p_at_the_design_pga_lies_in_the_binomial_interval_of_the_count(b_L, ratio, h, n_rec, vary, where, at_tie):
    """Every printed P at the design PGA of the fixed-base uplift (the entry's p_design, the verdict's
    text) lies within the Wilson interval of the count of exact thresholds at or below it: rectangular
    (ratio 1) and asymmetric bases, one sample or a Latin hypercube that moves the uplift limits, the
    design PGA anywhere around the thresholds (on a tied value too)."""
    p = RockingParams.from_dict({"m": 50.0, "h": h, "b_L": b_L, "b_R": ratio * b_L, "I_G": 50.0 * h * h / 3})
    model = RockingModel.housner(p)
    recs = RECORDS[:n_rec]
    ims = np.array([float(r.pga) for r in recs])
    samples = (latin_hypercube({"alpha_R": (0.8, 1.0), "alpha_L": (0.8, 1.0)}, 4, seed=1) if vary else nominal(1))
    x = uplift_thresholds(RockingModel.imperfect(p, 0.9, 0.9) if vary else model, recs, samples, ims)
    t = distinct_thresholds(x)
    pga = float(t[len(t) // 2]) if at_tie else float(np.exp(np.log(t).mean() + where * max(np.log(t).std(), 0.05)))
    lv = np.geomspace(t.min() / 3, t.max() * 3, 8)
    cv, e = _uplift(x, lv, pga, n_boot=0)
    k, n = int(np.sum(t <= pga)), t.size
    assert e["p_design"] is not None and _inside(e["p_design"], k, n), (e["p_design"], k, n, cv.status)
    c = e["p_design_count"]
    assert c["n"] == n and c["k"] == k
    assert f"{e['p_design']:.2f}"[:3] in _curve_text(e) or "P at the design PGA" in _curve_text(e)
    # the curve reported agrees with the count at every level run as well
    for level in lv:
        k = int(np.sum(t <= level))
        assert _inside(float(cv.probability(level)), k, t.size), (level, cv.status)
