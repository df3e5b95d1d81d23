"""The assessment that opens every run: hazard, fixed base, isolator, one recommendation,
from the stages' numbers; and the box that shows it first in the report (headless Chromium)."""
import json
import re

import pytest

from statue2model.pipeline.config import ProjectConfig
from statue2model.assessment.verdict import VerdictInputs, hazard, recommend, verdict
from statue2model.pipeline.assess import assess
from statue2model.report.browser import body_attributes, dump_dom
from statue2model.report.html import render_report

G = 9.81
PARAMS = {"status": "done", "data": {"a_min": 2.71, "a_L": 4.16, "a_R": 2.71, "h": 0.73, "b_L": 0.31, "b_R": 0.20}}


def _design(tmp_path, **kw):
    """A design.json as isolator/design.py writes it (schema isolator_design/4: travel_need, th_margins, layout,
    surface, cost, verification)."""
    d = {"passed": True, "R": 0.9, "r": 0.0095, "n_grooves": 3, "T": 2.68, "capacity": 0.30, "d_design": 0.15,
         "travel_need": 0.15, "a_design": 1.2 - 0.0073 * G, "mu": 0.0073, "checks": [], "layout": "ring3",
         "surface": "pom", "surface_name": "POM-C sheet (acetal copolymer)", "ball_material": "steel", "side": 0.6,
         "cost": 250.0, "th_margins": {"travel": 2.0, "acceleration": 2.26, "bearing": 1.5, "travel_slc": 1.7,
                                        "bearing_slc": 2.0, "reserve": None},
         "verification": {"sets": [{"name": "design", "travel": 0.09, "felt": 1.2, "need": 0.15},
                                   {"name": "extra 1", "travel": 0.08, "felt": 1.1, "need": 0.14},
                                   {"name": "extra 2", "travel": 0.085, "felt": 1.15, "need": 0.145}],
                          "slc": {"rule": "the design spectrum x gamma_x 1.2 (EN 1998-1 10.3(2))"}, "reserve": None}}
    d.update(kw)
    (tmp_path / "isolator").mkdir(exist_ok=True)
    (tmp_path / "isolator" / "design.json").write_text(json.dumps(d))
    return {"isolator": tmp_path / "isolator"}


def test_hazard_is_the_configured_design_spectrum():
    hz = hazard(ProjectConfig())
    assert hz["code"] == "EC8-1" and hz["soil"] == "C"
    assert hz["pga"] == pytest.approx(0.25 * 9.80665 * 1.15)     # a_g S
    assert "design PGA 0.287 g" in hz["text"]


def test_statue_that_lifts_and_an_isolator_that_protects(tmp_path):
    stages = {"params": PARAMS, "isolator": {"status": "done", "data": {}},
              "dynamics": {"status": "done", "data": {"first_overturn_pga_fixed": 0.7 * G,
                                                      "first_failure_pga_isolated": None}}}
    v = assess(stages, _design(tmp_path), ProjectConfig())
    assert v["fixed"]["lifts"] and v["fixed"]["uplift_margin"] == pytest.approx(2.71 / v["hazard"]["pga"])
    assert v["fixed"]["overturn_margin"] == pytest.approx(0.7 * G / v["hazard"]["pga"])
    assert v["isolated"]["travel_margin"] == pytest.approx(2.0)
    assert v["isolated"]["felt_margin"] == pytest.approx(2.71 / 1.2)       # the sets' largest felt acceleration
    assert v["recommendation"].startswith("isolate with the designed device")
    assert v["status"] == "ok"
    assert any(line.startswith("Hazard: EC8-1") for line in v["lines"])


def test_travel_demand_above_capacity_is_said_with_both_numbers(tmp_path):
    stages = {"params": PARAMS, "isolator": {"status": "done", "data": {}}}
    v = assess(stages, _design(tmp_path, capacity=0.21, travel_need=0.41), ProjectConfig())
    assert v["recommendation"] == ("the designed isolator does not protect at the design level: travel demand "
                                   "410 mm > capacity 210 mm")
    assert v["status"] == "fail"


def test_isolated_failure_below_the_design_pga_is_not_hidden(tmp_path):
    stages = {"params": PARAMS, "isolator": {"status": "done", "data": {}},
              "dynamics": {"status": "done", "data": {"first_failure_pga_isolated": 0.2 * G}}}
    v = assess(stages, _design(tmp_path), ProjectConfig())
    assert "on the isolator it fails from 0.200 g (overturned) under synthetic:" in v["recommendation"]
    assert "< design PGA 0.287 g" in v["recommendation"]


def test_no_design_in_range_names_the_failing_check(tmp_path):
    checks = [{"name": "travel within capacity", "passed": False, "required": True, "value": 0.41, "limit": 0.21,
               "unit": "m"}]
    stages = {"params": PARAMS, "isolator": {"status": "done", "data": {}}}
    v = assess(stages, _design(tmp_path, passed=False, checks=checks), ProjectConfig())
    assert v["recommendation"] == "no isolator in range works: travel within capacity: 0.41 vs 0.21 m"
    assert v["status"] == "fail"


def test_no_design_in_range_says_what_would_pass(tmp_path):
    """The design's one sentence (design.what_would_pass) is the reason, in the lines and the recommendation."""
    text = ("It lifts at so little acceleration (0.005 g) that the balls' own rolling resistance would rock it "
            "before the plate moves; restrain it instead.")
    stages = {"params": PARAMS, "isolator": {"status": "done", "data": {}}}
    v = assess(stages, _design(tmp_path, passed=False, failure="rolling friction below ...",
                               what_would_pass={"reason": "friction", "restrain": True, "text": text}), ProjectConfig())
    assert v["recommendation"] == "no isolator in range works: " + text and v["status"] == "fail"
    assert f"Isolator: {text}" in v["lines"] and v["isolated"]["what_would_pass"] == text


def test_a_passing_design_is_described_with_its_verification(tmp_path):
    v = _with_ls(tmp_path, _ls())
    line = next(ln for ln in v["lines"] if ln.startswith("Isolator:"))
    assert line.startswith("Isolator: 3 steel balls of 19 mm on POM-C sheet (acetal copolymer), plates 600 mm square, "
                           "T 2.68 s, travel capacity 300 mm, about 250 EUR; verified by time histories on 3 record "
                           "sets: margins travel 2.00, felt acceleration 2.26, ball load 1.50 at the design level, "
                           "travel 1.70 and ball load 2.00 at the collapse level")
    iso = v["isolated"]
    assert (iso["layout"], iso["cost"], iso["sets"], iso["travel_margin"]) == ("ring3", 250.0, 3, pytest.approx(2.0))
    assert iso["slc_rule"].startswith("the design spectrum x gamma_x")
    assert v["recommendation"].startswith("isolate with the designed device (about 250 EUR): over the 7 design records")


def test_statue_that_does_not_lift_needs_no_isolator():
    strong = {"status": "done", "data": {"a_min": 0.5 * G, "h": 0.3, "b_L": 0.15, "b_R": 0.15}}
    v = assess({"params": strong}, {}, ProjectConfig())
    assert not v["fixed"]["lifts"]
    assert v["recommendation"].startswith("no isolator needed at the design level")


def test_imperfect_model_reduces_the_uplift_acceleration():
    from dataclasses import replace

    cfg = ProjectConfig()
    cfg = replace(cfg, model=replace(cfg.model, kind="imperfect", alpha_L=0.5, alpha_R=0.5))
    v = assess({"params": PARAMS}, {}, cfg)
    assert v["fixed"]["uplift"] == pytest.approx(0.5 * 2.71)


def test_sliding_body_is_not_given_rocking_advice():
    fixed = {"slides": True, "lifts": True, "uplift": 1.0, "uplift_margin": 0.5}
    assert recommend(fixed, {}, 3.0).startswith("the statue would slide before it lifts")


def test_no_sliding_regime_claimed_that_the_design_level_does_not_reach():
    """Issue [25] item 4: a squat box (b/h 0.8 > mu_s 0.4) under a design PGA below mu_s g is not
    said to slide; at a PGA above mu_s g it is (quasi-static, without the design records)."""
    squat = {"a_min": 0.8 * G, "a_L": 0.8 * G, "a_R": 0.8 * G, "h": 0.25, "b_L": 0.2, "b_R": 0.2}
    low = verdict(VerdictInputs({**hazard(None), "pga": 0.3 * G}, squat, mu_static=0.4))
    assert low["fixed"]["slides_first"] and not low["fixed"]["slides"] and low["code"] == "NO_ISOLATOR"
    assert "stays below mu_s g" in low["lines"][1]
    high = verdict(VerdictInputs({**hazard(None), "pga": 0.5 * G}, squat, mu_static=0.4))
    assert high["fixed"]["slides"] and high["code"] == "SLIDES" and "reaches mu_s g" in high["lines"][1]


def test_verdict_box_is_rendered_first_in_the_browser(chromium, tmp_path):
    doc = {"title": "statue2model report: demo",
           "verdict": {"recommendation": "isolate with <the> designed device", "status": "ok",
                       "lines": ["Hazard: EC8-1 spectrum", "Fixed base: the statue lifts"]},
           "summary": [("uplift a_R", "0.276 g")],
           "sections": [{"id": "params", "title": "Rocking parameters", "status": "done", "text": ["x"]}]}
    path = render_report(doc, tmp_path / "report.html", base_dir=tmp_path)
    dom = dump_dom(path, browser=chromium)
    attrs = body_attributes(dom)
    assert int(attrs["data-verdict-height"]) > 40
    assert attrs["data-verdict-first"] == "true"
    assert "Recommendation: isolate with &lt;the&gt; designed device" in dom


def test_fragility_line_of_the_assessment():
    """The dynamics stage's fragility numbers become one assessment line: medians with their bands,
    the probabilities at the design PGA (tiny ones as '< 0.01'), the isolator's ratio of medians."""
    from statue2model.assessment.verdict import fragility

    dyn = {"fragility_runs": 70, "fragility_median_fixed": 0.632 * 9.81, "fragility_median_ci_fixed": [6.0, 6.45],
           "fragility_p_design_fixed": 4e-6, "fragility_median_isolated": 0.572 * 9.81,
           "fragility_median_ci_isolated": [4.8, 6.2], "fragility_p_design_isolated": 0.3,
           "fragility_ratio": 0.905, "fragility_ratio_ci": [0.76, 1.02], "fragility_status_fixed": "ok"}
    f = fragility(dyn, 0.287 * 9.81, True)
    assert "0.632 g (0.612 g-0.657 g)" in f["line"] and "at the design PGA < 0.01" in f["line"]
    assert "P(failure) at the design PGA 0.30" in f["line"] and "multiplies the median by 0.91 (0.76-1.02)" in f["line"]
    assert "isolator" not in fragility(dyn, 0.287 * 9.81, False)["line"]
    none = fragility({**dyn, "fragility_median_fixed": None, "fragility_status_fixed": "no failures"}, 2.8, False)
    assert "not fitted (no failures)" in none["line"]
    assert fragility({}, 2.8, True) == {} and fragility(None, 2.8, True) == {}


# --- the recommendation from the limit states over the design record set (#27) -----------------
def _row(name, base, demand, capacity, unit, exceeded, k=0):
    from statue2model.assessment.limit_states import TITLES

    return {"name": name, "title": TITLES[name], "base": base, "demand": demand, "capacity": capacity,
            "ratio": demand / capacity, "unit": unit, "exceeded": exceeded, "n_exceeding": k}


def _ls(fixed_fc=3.1, iso_fc=0.5, travel=0.29, ball=100.0, overturn_fixed=0):
    rows = [_row("full_contact", "fixed", fixed_fc, 2.71, "m/s^2", fixed_fc >= 2.71, 5 if fixed_fc >= 2.71 else 0),
            _row("rocking", "fixed", 0.1, 1.0, "", False),
            _row("overturning", "fixed", overturn_fixed / 7, 1 / 7, "", overturn_fixed > 0, overturn_fixed),
            _row("full_contact", "isolated", iso_fc, 2.71, "m/s^2", iso_fc >= 2.71),
            _row("rocking", "isolated", 0.0, 1.0, "", False),
            _row("overturning", "isolated", 0.0, 1 / 7, "", False),
            _row("capacity", "isolated", travel, 0.35, "m", travel > 0.35, 1 if travel > 0.35 else 0),
            _row("bearing", "isolated", ball, 115.0, "N", ball > 115.0, 7 if ball > 115 else 0)]
    return {"n_records": 7, "statistic": "mean", "rows": rows}


def _with_ls(tmp_path, ls, sweep_failure=None):
    stages = {"params": PARAMS, "isolator": {"status": "done", "data": {}},
              "dynamics": {"status": "done", "data": {"first_overturn_pga_fixed": 0.7 * G,
                                                      "first_failure_pga_isolated": sweep_failure,
                                                      "limit_states": ls}}}
    return assess(stages, _design(tmp_path), ProjectConfig())


def _consistent(v):
    """Every claim of the recommendation against the limit-state rows it rests on."""
    rows = {(r["base"], r["name"]): r for r in v["limit_states"]["rows"]}
    rec = v["recommendation"]
    iso_bad = [r for (b, n), r in rows.items() if b == "isolated" and r["exceeded"]]     # the ball load too
    if rec.startswith("no isolator needed"):
        assert not rows["fixed", "full_contact"]["exceeded"] and not rows["fixed", "overturning"]["exceeded"]
    if "stays in full contact on a fixed base" in rec:       # never while single records lift it
        assert not rows["fixed", "full_contact"]["n_exceeding"]
    if rec.startswith("isolate"):
        assert rec.startswith("isolate with")          # no conditional recommendation any more
        assert not iso_bad and rows["fixed", "full_contact"]["exceeded"]
    if "does not protect" in rec:
        assert iso_bad and all(f"{r['title']} exceeded" in rec for r in iso_bad)
    for r in rows.values():       # a ratio the sentence prints is the row's
        if f"ratio {r['ratio']:.2f}" not in rec:
            continue
        assert r["ratio"] == pytest.approx(float(f"{r['ratio']:.2f}"), abs=0.005)


def _plain(v):
    """The headline rules (issue [21]): at most 40 words, no formula, no '=', no config key; the code is
    a known one; 3 to 6 bullets whose counts are the limit-state rows'."""
    from statue2model.assessment.recommendation import CODES, Code, words

    code, head, bl = Code(v["code"]), v["headline"], v["bullets"]
    assert code in CODES and v["status"] in ("ok", "warn", "fail")
    assert words(head) <= 40, head
    assert not re.search(r"[=\[\]]|\bvs\b|\bratio\b|R_hat|\bmu\b|\balpha\b|\b[a-z]+_[a-z_]+\b", head), head
    assert 2 <= len(bl) <= 6, bl
    rows = {(r["base"], r["name"]): r for r in (v.get("limit_states") or {}).get("rows") or ()}
    fc, ot = rows.get(("fixed", "full_contact")), rows.get(("fixed", "overturning"))
    n = (v.get("limit_states") or {}).get("n_records")
    for text in [head, *bl]:                 # a count the words print is the row's
        for k, what in re.findall(r"(\d+) of \d+ design records (lift|overturn)s? ", text):
            row = fc if what == "lift" else ot
            assert int(k) == row["n_exceeding"], text
        assert f"of {n} design records" in text or "design records" not in text or "all" in text, text
    # one design PGA per object in every sentence (on a floor: the floor's, the ground's is "ground PGA")
    pga = f"{v['hazard']['pga'] / G:.3f}"
    said = " ".join([v["recommendation"], *v["lines"], *bl])
    assert set(re.findall(r"design PGA (\d+\.\d+) g", said)) <= {pga}, said
    assert f"peak ground acceleration {pga} g at the object" in " ".join(bl)
    if fc is not None:                       # the uplift the bullets print is full contact's capacity
        assert "It lifts from %.3f g" % (fc["capacity"] / G) in " ".join(bl)


@pytest.mark.parametrize("case, start, state", [
    (dict(fixed_fc=2.0), "no isolator needed at the design level: over the 7 design records", "ok"),
    (dict(), "isolate with the designed device (about 250 EUR): over the 7 design records", "ok"),
    (dict(ball=1039.0), "the designed isolator does not protect at the design level: ball load on the grooves "
                        "exceeded (1039 N vs 115 N, ratio 9.03)", "fail"),
    (dict(travel=0.40), "the designed isolator does not protect at the design level: isolator travel capacity "
                        "exceeded (400 mm vs 350 mm, ratio 1.14; 1 of 7 records)", "fail"),
    (dict(iso_fc=2.9), "the designed isolator does not protect at the design level: full contact (no uplift) "
                       "exceeded", "fail")])
def test_recommendation_follows_the_limit_states(tmp_path, case, start, state):
    v = _with_ls(tmp_path, _ls(**case))
    assert v["recommendation"].startswith(start), v["recommendation"]
    assert v["status"] == state
    _consistent(v)
    _plain(v)
    assert v["lines"][1].startswith("Design level (mean over the 7 design records")


def test_records_that_lift_while_the_mean_holds_are_said_with_a_warning(tmp_path):
    """Maria on the default hazard: the mean peak toward the weaker side 0.318 g < 0.351 g, but 2 of
    the 7 records lift her on their own: the code's check holds, the doubt is carried."""
    ls = _ls(fixed_fc=2.5)
    ls["rows"][0]["n_exceeding"] = 2
    v = _with_ls(tmp_path, ls)
    assert v["recommendation"].startswith("no isolator needed by the codes' mean of effects, but 2 of 7 design "
                                          "records lift the statue on their own")
    assert "ratio 0.92" in v["recommendation"] and v["status"] == "warn"
    _consistent(v)
    _plain(v)
    assert v["code"] == "NO_ISOLATOR_BUT_RECORDS_LIFT" and "2 of 7 design records lift it" in v["headline"]
    ls["rows"][0]["n_exceeding"] = 1
    one = _with_ls(tmp_path, ls)
    assert "1 of 7 design records lifts it on its own" in one["headline"]
    _plain(one)


def test_recommendation_is_the_same_for_any_sweep(tmp_path):
    """One record scaled over PGA (the variability sweep) is an illustration: failing at 0.25 g in it
    or not at all does not change the recommendation, which rests on the design set."""
    a = _with_ls(tmp_path, _ls(), sweep_failure=0.25 * G)
    b = _with_ls(tmp_path, _ls(), sweep_failure=None)
    assert a["recommendation"] == b["recommendation"] and a["status"] == b["status"] == "ok"
    assert any("illustration: one record scaled over PGA" in ln for ln in a["lines"])


def test_an_uncertain_base_contact_is_carried_with_its_size(tmp_path):
    ls = _ls()
    ls["uplift_band"] = [2.60, 2.90]
    v = _with_ls(tmp_path, ls)
    assert "between 0.265 g and 0.296 g" in v["lines"][1] and "checked against the low end" in v["lines"][1]


def test_no_probability_from_an_unidentified_spread():
    """Failures that jump from none to all between adjacent levels fit any small beta: the
    probability at the design PGA is not stored and the verdict says why."""
    import numpy as np

    from statue2model.assessment.fragility import FragilityCurve
    from statue2model.assessment.study import spread_identified

    lv = np.array([0.1, 0.2, 0.3, 0.4]) * 9.80665
    step = FragilityCurve("overturn", lv, np.array([0, 0, 7, 7]), np.full(4, 7), 2.5 * G, 0.02, "step",
                          (2.4 * G, 2.6 * G), (0.01, 0.05))
    assert "jump between adjacent levels (from none at 0.200 g to all at 0.300 g)" in spread_identified(step)
    smooth = FragilityCurve("overturn", lv, np.array([0, 2, 5, 7]), np.full(4, 7), 2.5 * G, 0.3, "ok",
                            (2.3 * G, 2.7 * G), (0.2, 0.45))
    assert spread_identified(smooth) is None
    dyn = {"fragility_runs": 70, "fragility_median_fixed": 2.5 * G, "fragility_p_design_fixed": None,
           "fragility_p_design_fixed_reason": spread_identified(step)}
    from statue2model.assessment.verdict import fragility

    line = fragility(dyn, 0.287 * 9.80665, False)["line"]
    assert "P(overturning) at the design PGA not known (spread not identified" in line and "< 0.01" not in line


def test_the_verdict_box_states_its_criteria_assumptions_and_limitations(tmp_path):
    v = _with_ls(tmp_path, _ls())
    assert any("mean over the 7 design records" in c for c in v["criteria"])
    assert any("no isolator needed when the statue stays in full contact" in c for c in v["criteria"])
    assert any(v["hazard"]["text"] in a for a in v["assumptions"])
    assert any("illustrations" in x for x in v["limitations"])
    from statue2model.report.html import render_report

    box = {k: v[k] for k in ("recommendation", "status", "lines", "criteria", "assumptions", "limitations")}
    page = render_report({"title": "t", "verdict": box, "sections": []}, tmp_path / "r.html").read_text()
    assert "Criteria" in page and "Limitations" in page and "rigid body rocking" in page


def test_on_a_floor_the_design_pga_is_one_number(tmp_path):
    """An object on an upper floor: the floor's peak acceleration is the design PGA of every sentence;
    the ground's is called the ground PGA (issue [21]: 'design PGA' meant two numbers on two lines)."""
    from dataclasses import replace

    from statue2model.pipeline.config import BuildingConfig

    cfg = replace(ProjectConfig(), building=replace(BuildingConfig(), floor=2, storeys=3, height=10.0))
    stages = {"params": PARAMS, "isolator": {"status": "done", "data": {}},
              "dynamics": {"status": "done", "data": {"first_overturn_pga_fixed": 0.7 * G, "limit_states": _ls()}}}
    v = assess(stages, _design(tmp_path), cfg)
    assert v["hazard"]["on_floor"] and v["hazard"]["pga"] > v["hazard"]["ground_pga"]
    assert "ground PGA" in v["lines"][0] and "the design PGA at the object" in v["lines"][0]
    _plain(v)


def test_a_headline_never_passes_forty_words():
    """Every code with every detail at its longest (a long limit-state title, long reasons, 7 of 7 records
    lifting and overturning, a price and a margin): at most 40 words, details dropped in order."""
    from statue2model.assessment.recommendation import MAX_WORDS, Code, Facts, headline, words
    from statue2model.assessment.verdict import REASONS

    longest = max(REASONS.values(), key=words)
    f = Facts(pga=2.8, uplift=1.4, n=7, k_lift=7, k_over=7, cost=123456.0, travel_margin=0.22,
              iso_governing="rocking without overturning", iso_k=7, reason=longest + " " + longest)
    for code in Code:
        h = headline(code, f)
        assert words(h) <= MAX_WORDS, (code, words(h), h)
    iso = headline(Code.ISOLATE, Facts(n=7, k_lift=6, cost=9011.0, travel_margin=0.22))
    assert "about 9011 EUR" in iso and "22 % travel to spare" in iso                # fits: every detail kept


def test_a_classification_that_cannot_fail_is_not_said_to_agree():
    """Issue [25] item 2: on the isolator no run lifts or overturns in either model; the verdict's line says
    'not testable' with the reason, and does not count it among the limit states that agree."""
    from statue2model.assessment.verdict import crosscheck_line
    from statue2model.crosscheck.classification import agreement

    none = agreement([False] * 70, [False] * 70, "overturning")
    cls = {"isolated": {"overturning": {"status": none.status, "accuracy": none.accuracy.value,
                                        "accuracy_lo": none.accuracy.lo, "n": 70, "why": none.why}}}
    c = crosscheck_line(cls)
    assert c["met"] == [] and c["untested"] and "agrees" not in c["line"].split(";")[0].replace("no limit state agrees", "")
    assert "not testable on" in c["line"] and "no positive case in 70 runs" in c["line"]


def test_every_row_states_its_rule_beside_its_count():
    """Issue [25] item 3: full contact is judged on the mean of the records, overturning on any single one; each
    row says its rule (limit_states.json ``rule``, the verdict's line) beside the count of single records exceeding
    it, and the bullet under the headline says both rules where it gives the counts."""
    from statue2model.assessment import states
    from statue2model.assessment.recommendation import Code, Facts, bullets
    from statue2model.assessment.verdict import limit_state_line
    from statue2model.assessment.limit_states import evaluate
    from statue2model.geometry.rocking_params import RockingParams
    from statue2model.hazard import motions
    from statue2model.rocking.model import RockingModel

    assert {s.id: s.rule for s in states.REGISTRY}["overturning"] == "any"
    assert states.get("full_contact").rule == "mean" and states.get("bearing").rule == "static"
    block = RockingParams.rectangular_block(b=0.05, h=0.25, m=10.0)
    ls = evaluate(RockingModel.housner(block), [motions.sine_pulse((1.5 + 0.1 * k), 2.0) for k in range(7)])
    assert [r["rule"] for r in ls.to_dict()["rows"]] == ["mean", "mean", "any"]
    line = limit_state_line(ls)
    assert "exceed it alone; judged on the mean)" in line and "judged on any record)" in line
    b = bullets(Code.NO_ISOLATOR_BUT_RECORDS_LIFT, Facts(pga=3.0, uplift=2.0, n=7, k_lift=2, k_over=0))
    assert any("full contact on the mean of the 7 records, overturning on any one" in x for x in b)
