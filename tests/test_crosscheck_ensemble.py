"""2D vs 3D over an ensemble of records (statue2model/crosscheck/ensemble.py)."""
from __future__ import annotations

import math

import pytest

from statue2model.crosscheck import ensemble as ens
from statue2model.errors import InputError


def test_wilson_known_values():
    lo, hi = ens.wilson(8, 20)                   # R: prop.test(8, 20, correct = FALSE)$conf.int
    assert (lo, hi) == (pytest.approx(0.2188, abs=1e-4), pytest.approx(0.6134, abs=1e-4))
    lo, hi = ens.wilson(0, 20)
    assert lo == 0.0 and hi == pytest.approx(0.1611, abs=1e-4)
    assert ens.wilson(20, 20)[1] == 1.0
    with pytest.raises(InputError):
        ens.wilson(3, 2)


def test_median_ci_order_statistics_and_overturned_runs():
    x = list(range(1, 21))
    assert ens.median_ci(x) == (10.5, 6.0, 15.0)            # ranks 6 and 15 of 20: coverage 95.9 %
    med, lo, hi = ens.median_ci([0.1] * 9 + [math.inf] * 11)   # most runs overturn: the median overturns
    assert math.isinf(med) and lo == 0.1 and math.isinf(hi)


def test_level_result_fails_and_says_why():
    o2 = [False] * 16 + [True] * 4
    o3 = [False] * 10 + [True] * 10
    q2 = [0.2] * 16 + [math.inf] * 4
    q3 = [0.3] * 10 + [math.inf] * 10
    r = ens.level_result(5.0, o2, q2, o3, q3, [20], 0.15, 0.20, seeds=range(20), reasons={20: ["3D pivot slips 9 mm"]})
    assert not r["prob_met"] and "3D overturns more often: 3D 10/20 vs 2D 4/20" in r["why"]
    assert r["differ"] == list(range(10, 16))
    assert "1 of 21 records left out by the validity screen" in r["why"] and "seed 20: 3D pivot slips" in r["why"]
    assert not r["median_met"] and "median record overturns the 3D body only" in r["why"]
    ok = ens.level_result(5.0, o2, q2, o2, [0.21] * 16 + [math.inf] * 4, [], 0.15, 0.20)
    assert ok["prob_met"] and ok["median_met"] and ok["why"] == ""


@pytest.mark.slow
def test_small_ensemble_agrees_and_a_wrong_e_fails():
    pytest.importorskip("pybullet")
    from statue2model.crosscheck.restitution import model_2d
    from statue2model.crosscheck.statue_scene import StatueScene

    sc = StatueScene.block(b=0.1, h=0.5, m=100.0)
    kw = dict(n_records=20, levels=(0.8,), durations=(2.0, 3.0), free_time=1.0)
    ok = ens.ensemble_cases(sc, **kw)
    cases, res = ok.comparison.cases, ok.results
    lev = res["levels"][0]
    assert 0.0 <= lev["p_2d"] <= 1.0 and 0.0 <= lev["p_3d"] <= 1.0 and len(cases) == 2
    assert lev["ci_2d"][0] <= lev["p_2d"] <= lev["ci_2d"][1]
    # the same 3D runs judged against a 2D model with a wrong restitution (e x 0.6): the target fails
    wrong = model_2d(sc, scale=0.6)
    wrong_e = ens.ensemble_cases(sc, model=wrong, pga_ref=res["pga_ref"], runs_3d=res["runs_3d"], **kw)
    bad, res2 = wrong_e.comparison.cases, wrong_e.results
    assert not all(c.met for c in bad)
    assert res2["levels"][0]["why"]


@pytest.mark.slow
def test_ensemble_uses_the_standard_screen_a_squat_block_is_not_applicable():
    """The ensemble screens each record with screen.screen_values (the standard cases' limits): a squat
    block (b = h) needs more friction than the scene has, every record is screened and the level is
    'not applicable', never a NO."""
    pytest.importorskip("pybullet")
    from statue2model.crosscheck.statue_scene import StatueScene

    sc = StatueScene.block(b=0.3, h=0.3, m=100.0)
    squat = ens.ensemble_cases(sc, n_records=3, levels=(1.0,), durations=(1.5,), free_time=0.5, workers=1)
    cases, res = squat.comparison.cases, squat.results
    assert [c.status for c in cases] == ["not applicable", "not applicable"]
    lev = res["levels"][0]
    assert not lev["applicable"] and len(lev["screened"]) >= 2 and "friction" in lev["why"]
    assert "not applicable" in ens.level_table(res)
