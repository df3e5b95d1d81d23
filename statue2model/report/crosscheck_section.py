"""The cross-check stage's part of the report: the table of 2D/3D cases, each with its error,
target and, when it misses, why; the figures' captions; the summary line and warnings.

The stage (:func:`statue2model.pipeline.stages.crosscheck_stage`) runs the comparison and
hands the result here; nothing is computed, only typeset.
"""
from __future__ import annotations

from ..crosscheck.output import summary as cc_summary
from .stage_sections import fig as _fig
from .stage_sections import fmt as _fmt


def _error_and_target(cd: dict) -> tuple[str, str]:
    """A case's error and target, as percentages for relative cases."""
    err, target = cd.get("rel_error"), cd.get("target")
    if cd.get("kind") == "relative":
        return ("-" if err is None else f"{err * 100:.1f} %", "-" if target is None else f"{target * 100:.0f} %")
    return _fmt(err), _fmt(target)


def _why_missed(cd: dict) -> str:
    """The case's own diagnosis when it misses its target (or is a diagnostic / not applicable);
    the bare numbers when it has none."""
    if cd.get("status", "met" if cd.get("met") else "missed") == "met":
        return ""
    if cd.get("status") in ("diagnostic", "not applicable"):
        return cd.get("why") or cd.get("status")
    why = "; ".join(x for x in (cd.get("why"), cd.get("note")) if x)
    if why:
        return why
    err, target = _error_and_target(cd)
    return f"2D and 3D differ by {err} (target {target}); no cause was diagnosed for this case"


def crosscheck_section(comp, paths: dict, *, isolator_wanted: bool, design, isolator_enabled: bool) -> dict:
    """The stage manifest (summary, text, warnings, figures, tables, data) of a comparison
    ``comp`` whose files are ``paths`` (name -> path, 'json' included). ``isolator_wanted``:
    the isolator scenes were asked for; ``design``: the passing isolator design or None;
    ``isolator_enabled``: the isolator stage is on (else skipping its scenes is no warning)."""
    rows = []
    for case in comp.cases:
        cd = case.to_dict()
        rows.append([cd["name"], cd.get("unit", ""), _fmt(cd.get("value_2d")), _fmt(cd.get("value_3d")),
                     *_error_and_target(cd), {"met": "pass", "missed": "fail"}.get(cd["status"], cd["status"]),
                     _why_missed(cd)])
    s = cc_summary(comp.cases)
    figs = [_fig(p.name, f"2D (reduced model) and 3D (PyBullet) time histories: {name}")
            for name, p in paths.items() if name != "json"]
    text = [("Each case compares one quantity of the 2D model with the 3D contact simulation of the same scene; "
            "a case meets its target when the difference is within the stated tolerance.")]
    warnings = []
    if s["unmet"]:
        warnings.append("2D/3D cases outside their target: " + "; ".join(map(str, s["unmet"])))
    if isolator_wanted and design is None and isolator_enabled:
        warnings.append("The isolator scenes of the 3D cross-check were skipped: no passing isolator design.")
    elif isolator_wanted and design is None:
        text.append("The isolator scenes were skipped: no passing isolator design ([isolator] enabled = false).")
    return {"summary": {"2D/3D agreement": f"{s['n_met']} of {s['n_cases']} applicable checks within target"
                                           f" ({s['n_not_applicable']} not applicable, {s['n_diagnostic']} "
                                           "diagnostics not counted)"},
            "text": text, "warnings": warnings, "figures": figs,
            "tables": [{"title": "2D model against 3D physics", "columns": ["case", "unit", "2D", "3D", "error",
                                                                            "target", "met", "why (when missed)"],
                        "rows": rows, "status_column": 6}],
            "data": {"n_cases": s["n_cases"], "n_met": s["n_met"]}}
