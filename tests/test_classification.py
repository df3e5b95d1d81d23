"""2D against 3D as a classifier (statue2model/crosscheck/classification.py)."""
from __future__ import annotations

import json
import math

import pytest

from statue2model.crosscheck import classification as cl
from statue2model.errors import InputError

TRUTH = [True, True, False, False, True, False]          # 3D
PRED = [True, False, False, True, True, False]           # 2D: TP 0, 4; FN 1; FP 3; TN 2, 5


def test_counts_and_wilson_rates_by_hand():
    assert cl.confusion(TRUTH, PRED) == {"tp": 2, "fp": 1, "fn": 1, "tn": 2}
    a = cl.agreement(TRUTH, PRED, "overturning")
    # Wilson 95 %, z = 1.96: accuracy 4/6 -> [0.3000, 0.9032]; precision = recall = 2/3 -> [0.2077, 0.9385]
    assert (a.accuracy.k, a.accuracy.n) == (4, 6)
    assert (a.accuracy.lo, a.accuracy.hi) == (pytest.approx(0.3000, abs=1e-4), pytest.approx(0.9032, abs=1e-4))
    for r in (a.precision, a.recall):
        assert r.value == pytest.approx(2 / 3)
        assert (r.lo, r.hi) == (pytest.approx(0.2077, abs=1e-4), pytest.approx(0.9385, abs=1e-4))
    assert a.status == "missed" and a.runs_differ == (1, 3)
    assert "agreement not shown" in a.why and "runs that differ: [1, 3]" in a.why
    with pytest.raises(InputError):
        cl.confusion([True], [True, False])


def test_verdict_needs_enough_runs_and_says_undefined():
    # all 16 agree, none positive: accuracy lower bound 16 / (16 + 1.96^2) = 0.8064 >= 0.8, P and R undefined;
    # but no run says yes in either model: the check could not fail -> not testable, never met (issue [25])
    a = cl.agreement([False] * 16, [False] * 16, "full_contact")
    assert a.accuracy.lo == pytest.approx(16 / (16 + 1.959964**2), abs=1e-5) and a.status == "not testable"
    assert a.precision.value is None and a.precision.why == "undefined: the 2D model says yes in no run"
    assert a.recall.value is None and "3D scene says yes in no run" in a.recall.why
    assert a.why.startswith("not testable: no positive case in 16 runs") and not a.met
    # every run yes in both: no negative case, not testable either
    assert cl.agreement([True] * 20, [True] * 20, "overturning").status == "not testable"
    # one positive run (2D and 3D agree on it) among 19 negatives: testable, and met on accuracy
    c = cl.agreement([True] + [False] * 19, [True] + [False] * 19, "full_contact")
    assert c.status == "missed" and "recall 1/1" in c.why          # one positive cannot show recall >= 0.5
    # 15 runs with both kinds of case in full agreement: 0.796 < 0.8 -> not shown (too few runs)
    b = cl.agreement([True] * 8 + [False] * 7, [True] * 8 + [False] * 7, "full_contact")
    assert b.status == "missed" and "too few runs" in b.why
    # 2D never says yes where 3D does 8 times in 16: recall 0/8, [0, 0.324] < 0.5 -> disagreement shown
    c = cl.agreement([True] * 8 + [False] * 8, [False] * 16, "overturning")
    assert c.recall.hi == pytest.approx(0.3244, abs=1e-4) and "recall 0/8" in c.why and "disagreement shown" in c.why
    assert c.precision.value is None
    assert cl.agreement([], [], "full_contact").status == "not applicable"


def test_peak_comparison_and_levels():
    no = {"uplift": False, "overturned": False, "peak": 0.0}
    assert cl.peak_comparison(no, no)["status"] == cl.NEITHER_LIFTS
    up2 = {"uplift": True, "overturned": False, "peak": 0.2}
    up3 = {"uplift": True, "overturned": False, "peak": 0.3}
    assert cl.peak_comparison(up2, up3)["ratio"] == pytest.approx(1.5)
    ot = {"uplift": True, "overturned": True, "peak": math.inf}
    assert "3D overturns" in cl.peak_comparison(up2, ot)["status"]
    assert cl.default_levels(1.0, 4.0, factors=(0.5, 1.0, 2.0)) == [0.5, 1.0, 2.0, 4.0, 8.0]
    with pytest.raises(InputError):
        cl.default_levels(math.inf, None)


# --- the 2D model with the right parameters standing in for the 3D scene (no PyBullet): the verdict logic on a
# --- systematic error of alpha, 16 runs of 2D only.

def _stand_in_3d(task):
    from statue2model.crosscheck.restitution import user_model

    scene, motion, settings, contact, free_time = task
    return cl.outcome_2d(user_model(scene), motion, free_time)


@pytest.fixture(scope="module")
def block():
    from statue2model.crosscheck.statue_scene import StatueScene

    return StatueScene.block(b=0.1, h=0.5, m=100.0)          # lifts at g b / h = 0.2 g


@pytest.fixture(scope="module")
def recs():
    from statue2model.crosscheck.ensemble import records

    return records(8, durations=(2.0, 3.0))


def test_wrong_alpha_fails_uplift_against_a_stand_in(block, recs):
    from statue2model.compute.executors import SerialExecutor
    from statue2model.crosscheck.restitution import user_model
    from statue2model.rocking.model import RockingModel

    kw = dict(levels=(0.16 * 9.81, 0.19 * 9.81), executor=SerialExecutor(), run_3d=_stand_in_3d, free_time=1.0)
    right = cl.classify_ensemble(block, user_model(block), recs, **kw)
    # nothing lifts in either model below g b / h: agreement there could not fail (issue [25])
    assert right.states["full_contact"].status == "not testable" and right.states["full_contact"].tn == 16
    # alpha 0.6: starts to lift at 0.12 g (then rolls over its 14 mrad transition), so most runs at 0.16-0.19 g
    # lift in 2D, none in the stand-in (below g b / h nothing can lift)
    wrong = cl.classify_ensemble(block, RockingModel.imperfect(block.params, 0.6, 0.6), recs, **kw)
    u = wrong.states["full_contact"]
    assert u.fp >= 12 and u.fp + u.tn == 16 and u.tp == u.fn == 0
    assert u.status == "missed" and "disagreement shown" in u.why
    differ = [r for r in wrong.runs if "full_contact" in r["why"]]
    assert len(differ) == u.fp and all("2D lifts off, 3D does not" in r["why"]["full_contact"] for r in differ)
    assert all(r["peak"]["status"] == cl.NEITHER_LIFTS for r in right.runs)


# --- the real 3D scene (PyBullet): a rectangular block, 8 short records x 2 levels around its 2D overturning
# --- median (6.2 m/s^2), 16 3D runs of ~30 ms each, reused for the wrong model.

@pytest.fixture(scope="module")
def ensemble_3d(block, recs):
    pytest.importorskip("pybullet")
    from statue2model.compute.executors import SerialExecutor
    from statue2model.crosscheck.restitution import user_model

    return cl.classify_ensemble(block, user_model(block), recs, levels=(5.0, 7.8), executor=SerialExecutor(),
                                free_time=1.0)


def test_3d_overturning_agrees_and_a_wrong_e_fails(block, recs, ensemble_3d):
    from statue2model.crosscheck.restitution import user_model

    right = ensemble_3d
    ot = right.states["overturning"]
    assert ot.status == "met" and ot.tp >= 4, right.table()
    assert right.states["capacity"].status == "not applicable" and "no isolator" in right.states["capacity"].why
    # e = 0.3 instead of eq. 15's 0.94: the 2D block loses its energy at every impact and no longer overturns
    wrong = cl.classify_ensemble(block, user_model(block, 0.3, 0.3), recs, levels=(5.0, 7.8), free_time=1.0,
                                 reuse_3d=right)
    w = wrong.states["overturning"]
    assert w.status == "missed" and w.fn >= 4 and "3D overturns, 2D does not" in wrong.table()


def test_result_is_json_ready(ensemble_3d):
    d = ensemble_3d.to_dict()
    text = json.dumps(d, allow_nan=False)                    # no nan / inf anywhere
    assert d["reference"].startswith("3D scene taken as the reference")
    assert len(d["runs"]) == 16 and d["info"]["n_counted"] + len(d["info"]["excluded_runs"]) == 16
    assert any(r["out_3d"]["peak"] is None for r in d["runs"])          # an overturned run's inf peak -> null
    assert d["fragility"]["overturning"]["2d"]["status"] in ("ok", "step", "all failed", "no failures", "one level")
    assert "uplift" in text
