"""The cross-check stage's part of the report: the table of 2D/3D cases, each with how it was
compared, its difference, its tolerance and, when it misses, why; where the two models agree; the
figures' captions; the summary line and warnings.

The stage (:func:`statue2model.pipeline.stages.crosscheck_stage`) runs the comparison and
hands the result here; nothing is computed, only typeset. The cases' own notes are written
for whoever works on the comparison; :func:`plain` words them for the engineer who reads
the report (no file paths, program options or solver jargon), keeping every number.

Example
-------
>>> plain("every engine step, unfiltered; engine dt 0.5 ms")
'peak over every 3D time step, unfiltered; 3D time step 0.5 ms'
>>> plain("Traced (benchmarks/bench_x.py, R 2 m): 1.27 with 8 mm facets (--groove tiles: convex)")
'A convergence study of the 3D model (R 2 m): 1.27 with 8 mm facets (convex)'
"""
from __future__ import annotations

import math
import re

from ..assessment import states
from ..crosscheck.output import summary as cc_summary
from .stage_sections import fig as _fig
from .stage_sections import fmt as _fmt

# Developer wording in the cases' notes -> the engineer's, applied in order (numbers are never touched).
_PLAIN = (
    (re.compile(r"\b(?:benchmarks|tests|statue2model|docs)/[\w./-]+\.(?:py|md)\b,?\s*"), ""),  # files in the repository
    (re.compile(r"--[a-z][a-z-]*(?: [a-z]+)?:\s*"), ""),                                   # a program option and its value
    (re.compile(r"\bTraced \("), "A convergence study of the 3D model ("),
    (re.compile(r"the contact solver's, not the friction mapping"),
     "from the 3D contact solver, not from the friction model"),
    (re.compile(r"\brollingFriction mapped, not calibrated\b"),
     "3D rolling resistance set from mu and the ball radius (c = mu r), not tuned to match the 2D decay"),
    (re.compile(r"\bevery engine step\b"), "peak over every 3D time step"),
    (re.compile(r"\braw per-step peaks\b"), "unfiltered peaks"),
    (re.compile(r"\bcomputed without --quick\b"), "computed by the full (not the quick) cross-check"),
    (re.compile(r"\bthe statistical check over records is --records N\b"),
     "the statistical check over many records is the cross-check's record ensemble"),
    (re.compile(r"\brtol (\S+)\.\.(\S+)"), r"an integration tolerance of \1 to \2"),
    (re.compile(r"\bfor dt and dt / 2\b"), "for the 3D time step and half of it"),
    (re.compile(r"\bengine dt\b"), "3D time step"),
    (re.compile(r"\bat dt (?=\d)"), "at a time step of "),
    (re.compile(r"\bdt (?=\d)"), "time step "),
    (re.compile(r"\bsolver iterations\b"), "contact-solver iterations"),
    (re.compile(r"\bcalibrated on the 3D scene\b"), "measured on the 3D scene"),
    (re.compile(r"\bcalibrated\b"), "fitted"),
)


def plain(text: str) -> str:
    """``text`` (a case's name, note or diagnosis) in the words of an engineer: repository paths and
    program options left out, solver jargon spelled out; every number is kept."""
    for pattern, repl in _PLAIN:
        text = pattern.sub(repl, text)
    return re.sub(r"\(\s+", "(", re.sub(r" {2,}", " ", text)).strip()


def _trace() -> str:
    """The convergence study quoted in the plate-acceleration cases' notes ('' if there is none)."""
    try:
        from ..crosscheck.isolator_cases import TRACE
    except ImportError:             # pragma: no cover - the stage imported it already
        return ""
    return TRACE


def _error_and_target(cd: dict) -> tuple[str, str]:
    """A case's difference and tolerance: percentages for relative cases, the unit's values for
    absolute ones, 'same' / 'differs' for a yes/no outcome."""
    err, target = cd.get("rel_error"), cd.get("target")
    if cd.get("kind") == "relative":
        return ("-" if err is None else f"{err * 100:.1f} %", "-" if target is None else f"{target * 100:.0f} %")
    if cd.get("kind") == "equal":
        return ("same" if err == 0 else "differs"), "same outcome"
    return _fmt(err), _fmt(target)


def _value(cd: dict, key: str) -> str:
    """A case's 2D or 3D value: yes / no for an outcome, else the number."""
    v = cd.get(key)
    if cd.get("kind") == "equal" and v is not None:
        return "yes" if v else "no"
    return _fmt(v)


def _why_missed(cd: dict, note_explains: bool) -> str:
    """Why the case misses its target, or why it is not counted (a diagnostic, not applicable);
    '' when it is met. ``note_explains``: the diagnosis is the convergence study under the table."""
    status = cd.get("status", "met" if cd.get("met") else "missed")
    if status == "met":
        return ""
    if status in ("diagnostic", "not applicable"):
        return plain(cd.get("why") or "") or ("shown, not counted" if status == "diagnostic" else status)
    if cd.get("why"):
        return plain(cd["why"])
    if note_explains:
        return "the 3D contact between balls and grooves gives short impulses: see the convergence study above"
    if cd.get("kind") == "equal":
        return (f"the outcomes differ (2D {_value(cd, 'value_2d')}, 3D {_value(cd, 'value_3d')}): see how it was "
                "compared; no other cause was found")
    err, target = _error_and_target(cd)
    return f"2D and 3D differ by {err} (tolerance {target}); no cause was found for this case"


def _agreement(cases) -> str:
    """Where the models agree: per compared quantity, the checks within tolerance."""
    by, order = {}, []
    for c in cases:
        if c.status not in ("met", "missed"):
            continue
        q = plain(c.quantity or c.name)
        if q not in by:
            by[q] = [0, 0]
            order.append(q)
        by[q][0] += c.status == "met"
        by[q][1] += 1
    agree = [f"{q} ({by[q][0]} of {by[q][1]})" if by[q][1] > 1 else q for q in order if by[q][0] == by[q][1]]
    part = [f"{q} ({by[q][0]} of {by[q][1]} within)" for q in order if by[q][0] < by[q][1]]
    out = []
    if agree:
        out.append("The models agree within tolerance on: " + ", ".join(agree) + ".")
    if part:
        out.append("They differ on: " + ", ".join(part) + "; the table says why.")
    return " ".join(out)


def crosscheck_section(comp, paths: dict, *, isolator_wanted: bool, design, isolator_enabled: bool,
                       isolator_model: str | None = None) -> dict:
    """The stage manifest (summary, text, warnings, figures, tables, data) of a comparison
    ``comp`` whose files are ``paths`` (name -> path, 'json' included). ``isolator_wanted``:
    the isolator scenes were asked for; ``design``: the passing isolator design or None;
    ``isolator_enabled``: the isolator stage is on (else skipping its scenes is no warning);
    ``isolator_model``: how the 3D scene models the isolator, in words (None: no isolator scene)."""
    trace = _trace()
    rows, traced = [], False
    for case in comp.cases:
        cd = case.to_dict()
        note = cd.get("note") or ""
        in_note = bool(trace) and trace in note
        if in_note:
            note = note.replace(trace, "").strip().rstrip(";").strip()
            traced = True
        rows.append([plain(cd["name"]), cd.get("unit", ""), _value(cd, "value_2d"), _value(cd, "value_3d"),
                     *_error_and_target(cd), {"met": "pass", "missed": "fail"}.get(cd["status"], cd["status"]),
                     plain(note), _why_missed(cd, in_note)])
    s = cc_summary(comp.cases)
    figs = [_fig(p.name, f"Time histories of the 2D model and the 3D simulation: {plain(name)}")
            for name, p in paths.items() if name != "json"]
    text = [("What was compared: the 2D models this report's analyses use (the statue rocking about its base "
             "edges; the isolator's plate rolling on its balls) against a 3D rigid-body contact simulation "
             "(PyBullet) of the same statue, isolator and ground motions, case by case"
             + (f"; the isolator in 3D: {plain(isolator_model)}" if isolator_model else "")
             + "."),
            ("Tolerance: a relative case is met when |3D - 2D| / |2D| is within its tolerance, an absolute "
             "case when |3D - 2D| is within the tolerance in the case's unit, a yes/no case when both models "
             "give the same outcome. A diagnostic (e.g. the 2D model given the restitution measured in 3D) "
             "explains a difference and is not counted; a case is not applicable when the 3D body slides or "
             "twists, which the 2D rocking model does not describe.")]
    agreement = _agreement(comp.cases)
    if agreement:
        text.append(agreement)
    if traced:
        study = plain(trace)
        text.append("Why the unfiltered peak plate accelerations differ: " + study[:1].lower() + study[1:])
    warnings = []
    if s["unmet"]:
        warnings.append("2D/3D cases outside their tolerance: " + "; ".join(plain(str(u)) for u in s["unmet"]))
    if isolator_wanted and design is None and isolator_enabled:
        warnings.append("The isolator scenes of the 3D cross-check were skipped: no passing isolator design.")
    elif isolator_wanted and design is None:
        text.append("The isolator scenes were skipped: no passing isolator design ([isolator] enabled = false).")
    return {"summary": {"2D/3D agreement": f"{s['n_met']} of {s['n_cases']} applicable checks within tolerance"
                                           f" ({s['n_not_applicable']} not applicable, {s['n_diagnostic']} "
                                           "diagnostics not counted)"},
            "text": text, "warnings": warnings, "figures": figs,
            "tables": [{"title": "2D model against 3D physics",
                        "columns": ["case", "unit", "2D", "3D", "difference", "tolerance", "result",
                                    "how compared", "why missed / not counted"],
                        "rows": rows, "status_column": 6}],
            "data": {"n_cases": s["n_cases"], "n_met": s["n_met"]}}


_STATE_WORDS = {s.id: s.noun for s in states.REGISTRY}


def _rate_text(r: dict) -> str:
    """A rate of classification.Rate.to_dict as 'value [lo-hi]' (or 'undefined ...')."""
    if r.get("value") is None:
        return plain(r.get("why") or "undefined")
    return f"{r['value']:.2f} [{r['lo']:.2f}-{r['hi']:.2f}]"


def add_classification(section: dict, sc, note: str | None = None) -> dict:
    """Add to the stage manifest ``section`` the 2D/3D classification over the design records
    (crosscheck.set_classification.SetClassification ``sc``, or None with ``note`` saying why it was
    not made): a table (one row per base and limit state: counts, accuracy, precision and recall with
    95 % intervals, the 2D and 3D medians, the result and why), a text on the rule, the summary line
    and a warning for every limit state missed. Returns ``section``."""
    if sc is None or sc.skipped:
        why = plain(note or "") if sc is None else plain(sc.skipped)
        section["text"].append("The 2D/3D classification over the design records was not made: " + why)
        section["warnings"].append("3D classification over the design records not made: " + why)
        return section
    rows, missed, heads = [], [], []
    for key, base, cl in (("fixed", "fixed base", sc.fixed), ("isolated", "on the isolator", sc.isolated)):
        if cl is None:
            continue
        d = cl.to_dict()
        frm = sc.levels_from.get(key, {})
        heads.append(f"{base}: {d['info']['n_counted']} of {d['info']['n_runs']} runs counted "
                     f"({d['info']['n_records']} records x {len(d['info']['levels_g'])} PGA levels, "
                     f"{', '.join(f'{x:.3f}' for x in d['info']['levels_g'])} g: "
                     f"{', '.join(f'{f:g}' for f in frm.get('factors', []))} x each 2D fragility anchor, "
                     + ", ".join(f"{w} {a:.3f} g" for a, w in zip(frm.get("anchors_g", []), frm.get("what", [])))
                     + ")")
        for state, a in d["states"].items():
            f = d["fragility"].get(state, {})
            m2, m3 = (f.get(k, {}).get("median_g") for k in ("2d", "3d"))
            status = a["status"]
            rows.append([base, _STATE_WORDS.get(state, state), f"{a['tp']}/{a['fp']}/{a['fn']}/{a['tn']}",
                         _rate_text(a["accuracy"]) if status != "not applicable" else "-",
                         _rate_text(a["precision"]) if status != "not applicable" else "-",
                         _rate_text(a["recall"]) if status != "not applicable" else "-",
                         "-" if m2 is None else f"{m2:.3f}", "-" if m3 is None else f"{m3:.3f}",
                         {"met": "pass", "missed": "fail"}.get(status, status), plain(a.get("why") or "")])
            if status == "missed":
                missed.append(f"{base}, {_STATE_WORDS.get(state, state)}: {plain(a.get('why') or '')}")
    rule = sc.fixed.info.get("rule", "")
    section["text"].append(
        "Over the design records: every record of the design set scaled to PGA levels around the 2D fragility "
        "curves (their medians; where every studied level fails, the lowest; where none does, the highest), run "
        "in the 2D model and in 3D (3D taken as the reference). Per limit state, TP/FP/FN/TN count "
        "the runs where both say yes / only 2D / only 3D / neither; accuracy, precision and recall with their "
        f"95 % intervals. Rule: {plain(rule)}. Runs in which the 3D body slides or twists beyond the validity "
        "screen are counted (a real statue does too) and listed per limit state. " + "; ".join(heads)
        + ". The medians in this table are fitted "
        "to these runs alone, with uplift read in both models as the base edge lifted "
        f"{sc.fixed.info.get('lift_height_m', 2e-4) * 1000:g} mm (what the 3D contact resolves), on these few "
        "levels: they compare the two models with each other; the assessment's fragility medians (2D analyses) "
        "read uplift at its exact onset over many more levels and stay the ones to use.")
    b = sc.budget or {}
    if b.get("budget_s") and b.get("estimate_s"):
        est = ", ".join(f"{v:.0f} s at {k} x the anchors" for k, v in b["estimate_s"].items())
        section["text"].append(f"Time budget {b['budget_s']:g} s on {b.get('workers', 1)} workers: estimated {est} "
                               f"(one timed 3D run per base); run at {', '.join(f'{f:g}' for f in b['factors'])} x.")
    if note:
        section["text"].append(plain(note))
    section["tables"].append({"title": "2D model against 3D physics over the design records (yes/no per limit state)",
                              "columns": ["base", "limit state", "TP/FP/FN/TN", "accuracy", "precision", "recall",
                                          "2D median g (these runs)", "3D median g (these runs)", "result", "why"],
                              "rows": rows, "status_column": 8})
    n_met = sum(r[8] == "pass" for r in rows)
    n_app = sum(r[8] in ("pass", "fail") for r in rows)
    n_untested = sum(r[8] == "not testable" for r in rows)
    section["summary"]["2D/3D over the design records"] = (f"{n_met} of {n_app} testable limit states agree"
                                                          + (f" (missed: {len(missed)})" if missed else "")
                                                          + (f"; {n_untested} not testable (no positive or no "
                                                             "negative case)" if n_untested else ""))
    section["warnings"] += [f"2D/3D classification over the design records missed: {m}" for m in missed]
    data = section.setdefault("data", {})
    data["classification"] = {
        key: {st: {"status": a.status, "accuracy": a.accuracy.value, "accuracy_lo": a.accuracy.lo,
                   "n": a.accuracy.n, "why": a.why} for st, a in cl.states.items()}
        for key, cl in (("fixed", sc.fixed), ("isolated", sc.isolated)) if cl is not None}
    return section


def add_stack_classification(section: dict, sc, note: str | None = None) -> dict:
    """Add to the stage manifest ``section`` the 2D/3D classification of the statue on its pedestal
    (crosscheck.stack_classification.StackClassification ``sc``, or None with ``note`` saying why it
    was not made): a table (one row per body and outcome: both yes / 2D only / 3D only / both no per
    record group and in all, the agreement with its 95 % interval, the verdict and why), a text on what
    was run and the rule, the summary line and a warning for every outcome that disagrees. Returns
    ``section``."""
    if sc is None:
        why = plain(note or "")
        section["text"].append("The 2D/3D classification of the statue on its pedestal was not made: " + why)
        section["warnings"].append("3D classification of the statue on its pedestal not made: " + why)
        return section
    d = sc.to_dict()
    info = d["info"]
    groups = list(d["by_group"])
    rows, disagree = [], []
    for key, a in d["outcomes"].items():
        per = "; ".join(f"{g}: {'/'.join(str(x) for x in d['by_group'][g][key])}" for g in groups) if len(groups) > 1 else ""
        ag = a["agreement"]
        why = a["why"] or ""
        if a["runs_differ"]:
            first = next(r["why"][key] for r in d["runs"] if key in r["why"])
            why = "; ".join(w for w in (why, f"runs that differ: {a['runs_differ']}; first: {first}") if w)
        rows.append([a["body"], a["outcome"],
                     f"{a['both_yes']}/{a['only_2d']}/{a['only_3d']}/{a['both_no']}", per,
                     "-" if ag["value"] is None else f"{ag['value']:.2f} [{ag['lo']:.2f}-{ag['hi']:.2f}]",
                     "yes" if a["shown_95"] else "no", a["verdict"], plain(why)])
        if a["verdict"] == "disagrees":
            disagree.append(f"{a['body']} {a['outcome']}: {plain(a['why'])}")
    scene = info.get("scene_3d", {})
    up = info.get("uplift_g", {})
    counted = ", ".join(f"{d['by_group'][g]['n']} {g}" for g in groups)
    section["text"].append(
        f"The statue on its pedestal ({scene.get('pedestal', 'pedestal')}, {scene.get('pedestal_mass', 0):g} kg; "
        f"friction {scene.get('mu_top', 0):g} on its top, {scene.get('mu_floor', 0):g} on the floor): "
        f"{info['n_counted']} of {info['n_runs']} runs counted ({counted})"
        ", each run in the 2D models the assessment uses (the two-block rocking model, the single-body model while "
        "the pedestal stays in full contact, the rigid-plastic sliding of the statue on the top and of the pedestal "
        "on the floor) and in a 3D contact simulation of the same stack (3D taken as the reference). Per body and "
        "outcome the table counts the runs where both say yes / only 2D / only 3D / neither. The statue lifts at "
        f"{min(up.get('statue', [math.nan])):.3f} g, the stack (the pedestal with the statue on it) at "
        f"{min(up.get('pedestal', [math.nan])):.3f} g. Rule: {plain(d['rule'])}; an outcome that no run (or every "
        "run) shows in both models is not testable, never counted as agreeing. '95 %' says whether the "
        "agreement is also shown at 95 % confidence (the accuracy's lower bound >= 0.8, which needs >= 16 "
        "agreeing runs). The 2D model lets a body either rock or slide, never both; a run where the 3D body "
        "does both says so in its why.")
    if note:
        section["text"].append(plain(note))
    section["tables"].append({"title": "Statue on its pedestal: 2D model against 3D physics (yes/no per body and outcome)",
                              "columns": ["body", "outcome", "both yes/2D only/3D only/both no",
                                          "per record group", "agreement", "95 %", "verdict", "why"],
                              "rows": rows, "status_column": 6})
    n_ok = sum(r[6] == "agrees" for r in rows)
    n_test = sum(not r[6].startswith("not testable") for r in rows)
    section["summary"]["2D/3D, statue on its pedestal"] = (
        f"{n_ok} of {n_test} testable outcomes agree ({len(rows) - n_test} not testable)")
    section["warnings"] += [f"2D/3D classification of the statue on its pedestal disagrees: {m}" for m in disagree]
    section.setdefault("data", {})["stack_classification"] = {
        k: {"verdict": a["verdict"], "counts": [a["both_yes"], a["only_2d"], a["only_3d"], a["both_no"]],
            "agreement": a["agreement"]["value"]} for k, a in d["outcomes"].items()}
    return section
