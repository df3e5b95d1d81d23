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

import re

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


def crosscheck_section(comp, paths: dict, *, isolator_wanted: bool, design, isolator_enabled: bool) -> dict:
    """The stage manifest (summary, text, warnings, figures, tables, data) of a comparison
    ``comp`` whose files are ``paths`` (name -> path, 'json' included). ``isolator_wanted``:
    the isolator scenes were asked for; ``design``: the passing isolator design or None;
    ``isolator_enabled``: the isolator stage is on (else skipping its scenes is no warning)."""
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
             "(PyBullet) of the same statue, isolator and ground motions, case by case."),
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
