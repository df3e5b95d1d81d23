"""Fragility per limit state, fixed vs isolated, with the spread identified (issue #27 item 2):
assessment/fragility.py (uplift outcomes, adaptive levels, identification), assessment/study.py
(the limit-state entries), rocking/sampling.py (the default study's parameter design).

Hand references:
* uplift on a fixed base is the record reaching the uplift limit: a block with b_L = 0.10, b_R = 0.05,
  h = 0.25 lifts on its left pivot at g b_L / h = 3.924 m/s^2 (ground toward +x) and on its right
  pivot at g b_R / h = 1.962 m/s^2 (toward -x): a positive rectangular pulse of peak L lifts it iff
  L > 3.924, a one-sine pulse (peaks +L and -L) iff L > 1.962;
* a slender block under a rectangular pulse overturns iff IM x eps >= a* = g delta / (1 - exp(-p t_p))
  (MODEL.md section 3, linearised): with eps the samples' im_factor the failures at each level are
  counted by hand.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

from statue2model.assessment.fragility import (
    BETA_MIN,
    AdaptiveLevels,
    FragilityCurve,
    FragilityStudy,
    _fixed,
    beta_profile_band,
    fit_lognormal,
    fit_lognormal_many,
    identified_reason,
    run_fragility,
)
from statue2model.assessment.study import curve_entry, fragility_data, limit_state_data
from statue2model.geometry.rocking_params import RockingParams
from statue2model.hazard import motions
from statue2model.rocking import RockingModel
from statue2model.rocking import kernel as K
from statue2model.assessment.study import ALPHA_RANGE, E_RANGE, study_design
from statue2model.rocking.sampling import THESIS_THETA_R, lognormal_factor, nominal

G = 9.81
ASYM = RockingParams.from_dict({"m": 10.0, "h": 0.25, "b_L": 0.10, "b_R": 0.05, "I_G": 0.3, "g": G})
BLOCK = RockingParams.rectangular_block(0.0384, 0.2, 1.286)


# --- 1. uplift on a fixed base: the complement of the quiet test ---------------------------------
def test_uplift_fixed_is_the_record_reaching_the_uplift_limit_on_either_side():
    model = RockingModel.housner(ASYM, e_L=0.8, e_R=0.8)
    a_L, a_R = model.uplift_limits
    assert (round(a_L, 3), round(a_R, 3)) == (3.924, 1.962)                 # g b / h, by hand
    levels = np.array([1.5, 2.5, 3.5, 4.5])                                 # m/s^2 peaks
    rect = run_fragility(model, [motions.rect_pulse(1.0, 0.3)], levels, nominal(1), FragilityStudy(n_boot=0))
    sine = run_fragility(model, [motions.sine_pulse(1.0, 2.0)], levels, nominal(1), FragilityStudy(n_boot=0))
    assert rect.curves["full_contact_fixed"].n_fail.tolist() == [0, 0, 0, 1]           # +x only: needs > 3.924
    assert sine.curves["full_contact_fixed"].n_fail.tolist() == [0, 1, 1, 1]           # -x peak: needs > 1.962
    # the same decision as the integration: the kernel's uplift time is finite exactly where it lifts
    rec = motions.sine_pulse(1.0, 2.0)
    gains = levels[None, :] / rec.pga
    fails, valid, n_int, lifts, st = _fixed(model, [rec], gains, nominal(1), FragilityStudy(n_boot=0), None,
                                            20_000_000, keep_stats=True)
    assert lifts[0, 0].tolist() == [False, True, True, True]
    assert np.array_equal(np.isfinite(st[0, 0, :, K.S_T_UPLIFT]), lifts[0, 0])


# --- 2. adaptive levels identify a spread the coarse grid shows as a step ------------------------
@pytest.fixture(scope="module")
def step_case():
    """A slender block, a rectangular pulse, 40 stratified lognormal im_factors of beta 0.05: on the
    coarse grid a* x [0.6, 0.85, 1.2, 1.7] no sample fails at 0.85 a* (eps would need >= 1.18, the
    largest is exp(0.05 x 2.24) = 1.12) and all fail at 1.2 a* (eps >= 0.83, the smallest is 0.89)."""
    model = RockingModel.housner(BLOCK, e_L=0.9, e_R=0.9, linearised=True)
    tp = 0.25
    a_star = BLOCK.g * BLOCK.delta_L / (1.0 - math.exp(-BLOCK.p_L * tp))
    coarse = a_star * np.array([0.6, 0.85, 1.2, 1.7])
    smp = lognormal_factor(0.05, 40, seed=3)
    study = FragilityStudy(n_boot=50, free_time=5.0)
    rec = [motions.rect_pulse(1.0, tp)]
    plain = run_fragility(model, rec, coarse, smp, study)
    adapt = run_fragility(model, rec, coarse, smp, study, adaptive=AdaptiveLevels(rounds=3, max_added=12))
    return a_star, coarse, smp, plain, adapt


def test_coarse_grid_gives_a_step_and_no_probability(step_case):
    a_star, coarse, smp, plain, _ = step_case
    c = plain.curves["overturning_fixed"]
    assert c.n_fail.tolist() == [0, 0, 40, 40] and c.status == "step"
    why = identified_reason(c)
    assert "jump between adjacent levels" in why
    e = curve_entry(c, 0.9 * a_star)
    assert e["p_design"] is None and e["p_design_reason"].startswith("spread not identified")
    assert e["beta"] is None and e["identified"] is False and e["partial_levels"] == 0
    data = fragility_data(plain, 0.9 * a_star, False)
    assert data["fragility_p_design_fixed"] is None and "jump" in data["fragility_p_design_fixed_reason"]
    d = plain.to_dict()["curves"]["overturning_fixed"]
    assert d["fitted"] is None and d["identified"] is False and "jump" in d["spread_reason"]


def test_adaptive_levels_fill_the_step_and_identify_the_spread(step_case):
    a_star, coarse, smp, _, res = step_case
    c = res.curves["overturning_fixed"]
    added = np.setdiff1d(res.levels_run("fixed"), coarse)
    assert res.adaptive["added"]["fixed"] == added.size
    asked = {k: [x for r in res.adaptive["rounds_run"] for x in r["asked"].get(k, [])] for k in ("overturning_fixed", "full_contact_fixed")}
    assert len(asked["overturning_fixed"]) >= 2
    assert all(coarse[1] < x < coarse[2] for x in asked["overturning_fixed"])      # inside the step's gap
    # the uplift curve's own step: the linearised block lifts at g delta_L = 1.861 m/s^2 x 1 / eps,
    # between the coarse levels 0.6 a* and 0.85 a*: its levels went there
    assert round(BLOCK.g * BLOCK.delta_L, 3) == 1.861 and coarse[0] < 1.861 < coarse[1]
    assert all(coarse[0] < x < coarse[1] for x in asked["full_contact_fixed"])
    assert identified_reason(c) is None and c.partial >= 2
    eps = smp.im_factors()
    assert c.n_fail.tolist() == [int((x * eps >= a_star).sum()) for x in c.levels]     # by hand
    assert abs(c.median / a_star - 1) < 0.01
    assert 0.03 < c.beta < 0.08                                             # eps: beta 0.05
    # the old levels were not run again: each base's runs are records x levels run x samples
    assert res.stats["runs_fixed"] == 1 * len(res.levels_run("fixed")) * 40
    e = curve_entry(c, 0.9 * a_star)
    assert e["p_design"] is not None and 0 <= e["p_design"] < 0.05 and e["p_design_reason"] is None
    assert res.adaptive["identified"]["overturning_fixed"] is True and "rule" in res.adaptive


def test_no_partial_level_reports_none_with_its_reason():
    lv = np.array([1.0, 2.0, 4.0, 8.0])
    c = FragilityCurve("overturning_fixed", lv, np.array([0, 0, 7, 7]), np.full(4, 7), 2.8, BETA_MIN, "step")
    e = curve_entry(c, 2.0)
    assert e["p_design"] is None and e["beta"] is None
    assert "from none at 0.204 g to all at 0.408 g" in e["p_design_reason"]
    one = FragilityCurve("overturning_fixed", lv, np.array([0, 3, 7, 7]), np.full(4, 7), 2.0, 0.2, "ok")
    assert "1 level with a partial fraction" in curve_entry(one, 2.0)["p_design_reason"]
    none = FragilityCurve("overturning_fixed", lv, np.zeros(4, dtype=int), np.full(4, 7), float("nan"), float("nan"),
                          "no failures")
    e = curve_entry(none, 2.0)
    assert e["p_design"] is None and e["median"] is None and "no failure at any level (0.102-0.815 g)" in \
        e["p_design_reason"]


def test_profile_band_and_many_fit_agree_with_brute_force():
    """The profile band's ends against a brute-force profile (scipy on a fine beta grid, done once:
    0.2832, 0.3999); the vectorised fit's likelihood against fit_lognormal's on random counts."""
    (lo, hi), note = beta_profile_band([1.0, 1.5, 2.0, 3.0, 4.0], [0, 10, 25, 40, 50], [50] * 5)
    assert abs(lo - 0.2832) < 1e-3 and abs(hi - 0.3999) < 1e-3 and note is None
    from scipy.stats import norm

    from statue2model.assessment.fragility_fit import _nll

    rng = np.random.default_rng(7)
    lv = np.geomspace(1.0, 8.0, 8)
    n = np.full((30, lv.size), 20)
    Z = rng.binomial(n, norm.cdf(np.log(lv / 3.0) / 0.4))
    med, beta, st = fit_lognormal_many(lv, Z, n)
    for i in range(Z.shape[0]):
        m1, b1, s1 = fit_lognormal(lv, Z[i], n[i])
        assert st[i] == s1
        assert _nll(math.log(med[i]), math.log(beta[i]), np.log(lv), Z[i], n[i]) <= \
            _nll(math.log(m1), math.log(b1), np.log(lv), Z[i], n[i]) + 1e-9


# --- 3. the default study's parameter samples -------------------------------------------------------
def test_parameter_samples_cover_the_stated_ranges():
    model = RockingModel.imperfect(ASYM, 0.159, 0.175)
    s = study_design(model, 7, mu=0.0073)
    v = s.values
    d = ASYM.delta_R
    for name, (lo, hi) in (("theta_R", (THESIS_THETA_R[0] * d, THESIS_THETA_R[1] * d)), ("e_factor", E_RANGE),
                           ("alpha_factor", ALPHA_RANGE)):
        x = v[name]
        step = (hi - lo) / 7                                               # one stratum of the hypercube
        assert lo <= x.min() < lo + step and hi - step < x.max() <= hi, name
    lo, hi = sorted(set(v["mu"].tolist()))
    assert (round(lo, 6), round(hi, 6)) == (0.0039, 0.0108)              # Table 25's spread about 0.0073
    assert int((v["mu"] == lo).sum()) == 4                                 # ceil(7 / 2) at the low bound
    given = study_design(model, 7, mu=0.0073, mu_low=0.005, mu_high=0.012).values["mu"]
    assert sorted(set(given.tolist())) == [0.005, 0.012]
    ms = s.models(model)
    for m, ef, af in zip(ms, v["e_factor"], v["alpha_factor"]):
        assert m.alpha_L == pytest.approx(min(1.0, 0.159 * af)) and m.alpha_R == pytest.approx(min(1.0, 0.175 * af))
        assert m.e_L.values[0] == pytest.approx(min(1.0, model.e_L.values[0] * ef))
    housner = study_design(RockingModel.housner(ASYM), 5, mu=0.0073).values
    assert sorted(housner) == ["e_factor", "mu"]                           # no theta_R or alpha to vary
    assert study_design(model, 1).values == {}                             # one sample: the model as it is


# --- 4. the isolator lifts the uplift median -------------------------------------------------------------
def test_isolated_uplift_median_above_the_fixed_one_for_a_well_isolated_block():
    """A squat symmetric block lifts at g b / h = 2.943 m/s^2 whatever the record (its PGA is its peak on
    one side): the fixed uplift curve is a step there. On a 3 s isolator (R_hat 2.36 m, mu 0.01) the
    plate feels far less than the ground: its uplift median lies above the fixed one."""
    from statue2model.isolator.device import Isolator

    p = RockingParams.rectangular_block(0.09, 0.3, 50.0)
    model = RockingModel.housner(p, e_L=0.8, e_R=0.8)
    iso = Isolator(R=1.2, r=0.02, M=70.0, mu=0.01, capacity=1.0)
    recs = [motions.synthetic_record(5.0, 0.01, 1.0, seed=s) for s in range(3)]
    levels = np.array([2.0, 2.5, 2.8, 3.1, 4.0, 6.0, 9.0, 13.0, 18.0])
    res = run_fragility(model, recs, levels, nominal(1), FragilityStudy(n_boot=0), isolator=iso)
    fixed, isolated = res.curves["full_contact_fixed"], res.curves["full_contact_isolated"]
    assert fixed.n_fail.tolist() == [0, 0, 0, 3, 3, 3, 3, 3, 3]            # lifts above 2.943 m/s^2
    assert 2.8 < fixed.median < 3.1
    assert isolated.fitted and isolated.median > 1.5 * fixed.median
    ls = limit_state_data(res, 2.5)
    assert set(ls) == {"full_contact", "overturning", "capacity"}
    assert ls["full_contact"]["fixed"]["curve"] == "full_contact_fixed" and ls["full_contact"]["isolated"]["curve"] == \
        "full_contact_isolated" and ls["overturning"]["isolated"]["curve"] == "overturning_isolated"
    assert set(ls["capacity"]) == {"isolated"}


def test_fragility_rounds_is_checked_when_the_project_file_is_read():
    from statue2model.errors import InputError
    from statue2model.pipeline.config import load_config_text

    assert load_config_text("[dynamics]\nfragility_rounds = 0\n").dynamics.fragility_rounds == 0
    with pytest.raises(InputError, match=r"fragility_rounds must be in 0\.\.10, got 11"):
        load_config_text("[dynamics]\nfragility_rounds = 11\n")


def test_fixed_base_uplift_is_fitted_on_each_records_exact_uplift_pga():
    """Uplift on a fixed base needs no levels: record r scaled to PGA x lifts the block iff
    x max(u_g'') / PGA_r > g b_L / h or x max(-u_g'') / PGA_r > g b_R / h. Hand values from the
    records' own extremes: the median is the geometric mean of the thresholds, beta their log
    standard deviation; a symmetric block lifts at g b / h under every record (a deterministic step)."""
    from statue2model.assessment.fragility import EMPIRICAL, EXACT
    from statue2model.rocking.sampling import nominal

    recs = [motions.synthetic_record(6.0, 0.01, 2.0, seed=s) for s in range(6)]
    lv = np.geomspace(0.5, 8.0, 6)
    asym = RockingModel.housner(RockingParams.from_dict({"m": 10.0, "h": 0.25, "b_L": 0.10, "b_R": 0.05,
                                                          "I_G": 0.3}))
    res = run_fragility(asym, recs, lv, nominal(1), FragilityStudy(n_boot=50))
    up = res.curves["full_contact_fixed"]
    aL, aR = 9.81 * 0.10 / 0.25, 9.81 * 0.05 / 0.25
    x = []
    for rec in recs:
        acc = np.asarray(rec.samples)
        pga = float(np.max(np.abs(acc)))
        x.append(pga * min(aL / acc.max(), aR / -acc.min()))
    # records whose peak is on the weaker side tie at a_R: the lognormal (kept in ``choice``) is not
    # reported, the empirical step CDF of the thresholds is (fragility_fit.UPLIFT_RULE)
    tied = sum(math.isclose(v, aR, rel_tol=1e-9) for v in x)
    assert up.status == (EMPIRICAL if tied > 1 else EXACT) and up.spread is None
    assert up.choice["lognormal"]["median"] == pytest.approx(math.exp(np.mean(np.log(x))), rel=1e-9)
    assert up.choice["lognormal"]["beta"] == pytest.approx(max(np.std(np.log(x)), BETA_MIN), rel=1e-9)
    assert sorted(up.thresholds) == pytest.approx(sorted(x), rel=1e-12)
    entry = limit_state_data(res, 2.0)["full_contact"]["fixed"]
    assert entry["identified"] and entry["p_design"] == pytest.approx(float(up.probability(2.0)))
    assert entry["p_design"] == pytest.approx(sum(v <= 2.0 for v in x) / len(x)) or up.status == EXACT
    # the counts per level are the same outcome: every level above the largest threshold lifts every run
    assert all(f == n for f, n, level in zip(up.n_fail, up.n_trials, lv) if level > max(x))
    sym = RockingModel.housner(RockingParams.rectangular_block(0.05, 0.25, 10.0))
    cs = run_fragility(sym, recs, lv, nominal(1), FragilityStudy(n_boot=20)).curves["full_contact_fixed"]
    assert cs.median == pytest.approx(9.81 * 0.05 / 0.25, rel=1e-9) and cs.status == EMPIRICAL
    assert cs.choice["reason"].startswith("all 6 thresholds are equal") and "deterministic step" in cs.choice["reason"]
    assert float(cs.probability(0.99 * cs.median)) < 1e-6 and float(cs.probability(1.01 * cs.median)) > 1 - 1e-6


def test_probit_likelihood_alone_equals_the_terms_with_derivatives():
    """_probit_ll (the line searches' likelihood) is bit for bit the first of _probit_terms's outputs."""
    import numpy as np

    from statue2model.assessment.fragility_fit import _probit_ll, _probit_terms

    rng = np.random.default_rng(5)
    u = rng.normal(0.0, 4.0, (50, 9))
    u[0, :3] = (0.0, -40.0, 40.0)
    n = rng.integers(1, 15, (50, 9)).astype(float)
    z = np.floor(rng.uniform(0.0, 1.0, (50, 9)) * (n + 1))
    assert np.array_equal(_probit_ll(u, z, n), _probit_terms(u, z, n)[0])
