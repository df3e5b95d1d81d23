"""The page of ``statue2model validate``: how often each model was right on a shake-table campaign.

One self-contained HTML page (report/html.py) from the record pipeline/validate.py writes: the specimen and
the contact assumed, per model and outcome the scores (accuracy, precision, recall with their 95 % Wilson
intervals, the Brier score) and the confusion matrix, a figure of the observed outcome against the table's
PGA and PGV with each model's prediction, and the misses listed (the tests a model got wrong, with their PGA
and P).
"""
from __future__ import annotations

from pathlib import Path

from ..quantities import G  # m/s^2: the g every report prints
from .plots import _pyplot


def _rate(r: dict | None) -> str:
    if not r or r.get("value") is None:
        return f"- ({(r or {}).get('reason') or 'not defined'})"
    lo, hi = r["ci95"]
    return f"{r['value']:.2f} ({r['k']}/{r['n']}; 95 % {lo:.2f}-{hi:.2f})"


def plot_outcomes(result: dict, path: Path) -> Path:
    """Observed outcome (toppled 1 / not 0) against the table's PGA (left) and PGV (right); each model's
    prediction as a marker beside it."""
    plt = _pyplot()
    rows = result["rows"]
    fig, axes = plt.subplots(1, 2, figsize=(11, 4))
    for ax, key, label in ((axes[0], "pga_g", "PGA (g)"), (axes[1], "pgv", "PGV (m/s)")):
        x = [r[key] for r in rows]
        y = [1.0 if r["toppled"] else 0.0 for r in rows]
        ax.scatter(x, y, c="k", s=28, label="observed", zorder=3)
        for model, colour in (("2d", "tab:blue"), ("3d", "tab:red")):
            pts = [(r[key], r[f"p_topple_{model}"]) for r in rows if f"p_topple_{model}" in r]
            if pts:
                ax.scatter([p[0] for p in pts], [p[1] for p in pts], marker="x", c=colour, s=22,
                           label=f"P(topple) {model.upper()}", zorder=2)
        ax.axhline(0.5, color="0.6", lw=0.8, ls="--")
        ax.set_xlabel(label)
        ax.set_ylabel("toppled (observed) / P(topple) (models)")
        ax.set_ylim(-0.08, 1.08)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8, loc="center right")
    fig.suptitle(f"{result['campaign']}: {result['tests']} tests")
    fig.tight_layout()
    from ..io.files import atomic_write

    atomic_write(path, lambda p: fig.savefig(p, format="png", dpi=110))
    plt.close(fig)
    return path


def write_validation_page(result: dict, path, folder) -> Path:
    """validation.html (and validation.png beside it) in ``folder``."""
    from .html import render_report

    folder = Path(folder)
    fig = plot_outcomes(result, folder / "validation.png")
    sp, ct = result["specimen"], result["contact"]
    sections = []
    text = [f"Specimen {sp['scan']}: {sp['mass']:.2f} kg, the table's axis at {sp['direction_deg']:g} deg; along it "
            f"h {sp['h']:.4f} m, b_L {sp['b_L']:.4f} m, b_R {sp['b_R']:.4f} m (where the rays from G' leave the "
            f"footprint; obliquity {sp['obliquity_L']:.1f} / {sp['obliquity_R']:.1f} deg), uplift a_L "
            f"{sp['a_L'] / G:.3f} g, a_R {sp['a_R'] / G:.3f} g.",
            f"Contact: alpha {ct['alpha']:g}, restitution x {ct['e_factor']:g} ({ct['source']}). {result['decision']}."]
    if result.get("identification"):
        idn = result["identification"]
        text.append(f"Identified on campaign {idn['campaign']} ({idn['tests']} tests): alpha {idn['alpha']:g}, "
                    f"restitution x {idn['e_factor']:g}, balanced accuracy there {idn['balanced_accuracy']:.2f}, "
                    f"Brier {idn['brier']:.3f}. Rule: {idn['rule']}.")
    tables = []
    for model, ms in result["models"].items():
        for outcome in ("topple", "lift"):
            s = ms.get(outcome)
            if not s:
                continue
            tables.append({"title": f"{model.upper()}: {outcome} over {s['n']} tests ({ms['how']})",
                           "columns": ["score", "value"],
                           "rows": [["accuracy", _rate(s["accuracy"])], ["precision", _rate(s["precision"])],
                                    ["recall", _rate(s["recall"])],
                                    ["Brier score of P", "-" if s.get("brier") is None else f"{s['brier']:.3f}"],
                                    ["confusion: predicted yes", f"{s['tp']} observed yes, {s['fp']} observed no"],
                                    ["confusion: predicted no", f"{s['fn']} observed yes, {s['tn']} observed no"]]})
    sections.append({"id": "scores", "title": "Scores", "status": "done", "text": text, "tables": tables,
                     "figures": [{"path": fig.name, "caption": "observed outcome and each model's P(topple) against "
                                                               "the table's PGA and PGV"}]})
    miss_rows = []
    for model, ms in result["models"].items():
        for name in ms.get("misses", []):
            r = next(x for x in result["rows"] if x["name"] == name)
            miss_rows.append([model.upper(), name, "yes" if r["toppled"] else "no",
                              f"{r[f'p_topple_{model}']:.2f}", f"{r['pga_g']:.3f}", f"{r['pgv']:.3f}"])
    sections.append({"id": "misses", "title": "Misses", "status": "done",
                     "text": [f"{len(miss_rows)} test(s) where a model's topple prediction differs from what happened."],
                     "tables": [{"title": "The tests a model got wrong",
                                 "columns": ["model", "test", "toppled", "P(topple)", "PGA (g)", "PGV (m/s)"],
                                 "rows": miss_rows}] if miss_rows else []})
    test_rows = [[r["name"], "yes" if r["toppled"] else "no", f"{r['pga_g']:.3f}", f"{r['pgv']:.3f}",
                  "-" if "p_topple_2d" not in r else f"{r['p_topple_2d']:.2f}",
                  "-" if "p_topple_3d" not in r else f"{r['p_topple_3d']:.0f}"] for r in result["rows"]]
    sections.append({"id": "tests", "title": "Every test", "status": "done",
                     "tables": [{"title": "Tests", "columns": ["test", "toppled", "PGA (g)", "PGV (m/s)",
                                                               "P(topple) 2D", "toppled 3D"], "rows": test_rows}]})
    doc = {"title": f"statue2model validation: {result['campaign']}",
           "subtitle": f"{result['tests']} shake-table tests", "sections": sections}
    return render_report(doc, path, folder)
