"""The cross-check's files and text: DIR/crosscheck.json, the summary counts and the plain-text table.

crosscheck.json: {"cases": [{name, quantity, value_2d, value_3d, rel_error, target,
met, status, screen, kind, unit, note, why}, ...], "summary": {n_cases, n_met, unmet: [...],
n_not_applicable, n_diagnostic, not_applicable: [...]}, "plots": {history name: PNG file name},
"runs": {3D run details}, "scene", "settings", "contact"}; written atomically. The overlay plots
it names (one PNG per time history, :func:`plot_files`) are drawn by the caller
(statue2model.report.crosscheck_plots, which writes both): this package does not draw.

Example
-------
>>> from statue2model.crosscheck.case import Case, Comparison
>>> import tempfile, json, numpy as np, pathlib
>>> d = pathlib.Path(tempfile.mkdtemp())
>>> c = Comparison(cases=(Case.relative("q", "s", 1.0, 1.001, 0.01),),
...                histories={"q": {"t2": np.arange(3.0), "y2": np.zeros(3), "t3": np.arange(3.0),
...                                 "y3": np.zeros(3), "label": "theta (rad)"}})
>>> paths = write_report(c, d)
>>> data = json.loads((d / "crosscheck.json").read_text())
>>> data["cases"][0]["met"], data["plots"]
(True, {'q': 'q.png'})
"""
from __future__ import annotations

import re
from pathlib import Path

from ..io.files import prepare_dir, write_json


def _slug(name: str) -> str:
    return re.sub(r"[^a-z0-9]+", "_", name.lower()).strip("_")[:60] or "case"


def plot_files(histories: dict) -> dict[str, str]:
    """The PNG file name of each time history's overlay plot: {history name: 'slug.png'}."""
    return {name: f"{_slug(name)}.png" for name in histories}


def summary(cases) -> dict:
    """Counts of the checks only: cases with status 'met' or 'missed' (n_cases, n_met, unmet);
    diagnostics and not-applicable cases are listed apart, never counted as met or not met."""
    checks = [c for c in cases if c.status in ("met", "missed")]
    unmet = [c.name for c in checks if c.status == "missed"]
    na = [c.name for c in cases if c.status == "not applicable"]
    return {"n_cases": len(checks), "n_met": len(checks) - len(unmet), "unmet": unmet,
            "n_not_applicable": len(na), "not_applicable": na,
            "n_diagnostic": sum(c.status == "diagnostic" for c in cases)}


def write_report(comparison, out_dir, extra: dict | None = None) -> dict[str, Path]:
    """Write crosscheck.json into ``out_dir`` (its ``plots``: :func:`plot_files` of the comparison's
    histories, which the caller draws). Returns {'json': its path}."""
    out = prepare_dir(out_dir)
    data = {"cases": [c.to_dict() for c in comparison.cases], "summary": summary(comparison.cases),
            "plots": plot_files(comparison.histories), "runs": comparison.runs}
    data.update(extra or {})
    return {"json": write_json(out / "crosscheck.json", data)}


def table(cases) -> str:
    """The cases as a readable table; the last column is the status (yes / NO for checks, "n/a" with
    the screen's reason for a case where 2D does not apply, "diag" for a diagnostic)."""
    lines = [f"{'case':58s} {'2D':>12s} {'3D':>12s} {'error':>9s} {'target':>8s}  met"]
    for c in cases:
        def fmt(v):
            return "-" if v is None else f"{v:.6g}"
        err = ("-" if c.kind == "equal" or (c.status == "not applicable" and not c.rel_error < 1e3) else
               f"{c.rel_error * 100:.2f}%" if c.rel_error < 1e3 else "inf")
        tgt = "same" if c.kind == "equal" else (f"{c.target * 100:g}%" if c.kind == "relative" else f"{c.target:g}{c.unit}")
        st = {"met": "yes", "missed": "NO", "diagnostic": "diag (not counted)"}.get(c.status)
        if st is None:
            st = "n/a: " + (c.why or "2D not applicable")
        lines.append(f"{c.name[:58]:58s} {fmt(c.value_2d):>12s} {fmt(c.value_3d):>12s} {err:>9s} {tgt:>8s}  {st}")
    return "\n".join(lines)
