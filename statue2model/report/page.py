"""The report of a run: the stages' manifests laid out as one self-contained HTML page
(:mod:`statue2model.report.html`), written to OUT/report.html.

Example
-------
>>> import tempfile, pathlib
>>> from statue2model.io.paths import default_scan
>>> from statue2model.pipeline.run import run_project
>>> res = run_project(default_scan(), pathlib.Path(tempfile.mkdtemp()), stages=["params"], say=lambda m: None)
>>> page = res.report.read_text()
>>> "Rocking parameters" in page and 'src="data:image/png;base64,' in page
True
>>> 'class="warnings"' in page                  # the bundled scan raises no warning
False

A manifest (stage.json) is input too: it may have been edited. Its figures are
embedded only when they resolve inside the stage's own folder under OUT
(:func:`statue2model.report.figure_paths.safe_figures`), else the page says "figure
refused"; a malformed table is left out with a note, never an exception.
"""
from __future__ import annotations

import math
import numbers
import time
from pathlib import Path

from ..version import __version__
from .figure_paths import safe_figures
from .html import VERDICT_SLOTS

TITLES = {"params": "Rocking parameters", "prototype": "Prototype: layers and sheets",
          "isolator": "Rolling-ball isolator", "dynamics": "2D analyses: fixed base and isolator",
          "crosscheck": "3D cross-check (PyBullet)"}
HEADLINE = {"params": ("mass", "h", "b_L / b_R", "uplift a_R", "weakest direction"),
            "isolator": ("design", "period T"),
            "dynamics": ("lowest overturning PGA (fixed)",
                         "lowest failing PGA (isolated: overturning or capacity exceeded)"),
            "crosscheck": ("2D/3D agreement",)}
STATUS = {"done": "done", "cached": "cached", "failed": "failed"}

MARGINS_TITLE = "How to read the margins"
MARGINS = {
    "margin": "capacity / demand, a pure number: above 1 the statue is on the safe side, below 1 it is not; "
              "1.00 is exactly at the limit. Both are in the same unit, stated with each margin.",
    "design PGA": "the peak ground acceleration of the design spectrum at the site, a_g S (in g); on an upper "
                  "floor, the peak floor acceleration Se(0) of the floor spectrum. Every PGA margin below "
                  "divides by it.",
    "uplift margin": "uplift acceleration / design PGA (g / g). The uplift acceleration is g b/h in the weakest "
                     "direction (times alpha for the imperfect-base model): the ground acceleration at which "
                     "the statue starts to rock. Below 1 the statue rocks at the design level, which is not by "
                     "itself a failure.",
    "overturning margin (fixed base)": "lowest PGA at which the statue overturned in the variability sweep of "
                                       "the record ([dynamics] motion, scaled) / design PGA (g / g).",
    "travel margin": "isolator travel capacity / design displacement demand SDe(T) (mm / mm). The capacity is "
                     "the plate displacement at which a ball leaves its groove or the top plate tips; the design "
                     "itself asks for more than SDe (a safety factor and the friction offset mu R_hat).",
    "felt-acceleration margin": "uplift acceleration / the acceleration the statue feels on the isolator, "
                                "Se(T) + mu g (g / g). Above 1 the statue stays in full contact on the plate.",
    "failure margin (on the isolator)": "lowest PGA at which the statue on the isolator overturned or the "
                                        "isolator's capacity was exceeded in the variability sweep / design PGA "
                                        "(g / g).",
    "ratio of medians (fragility)": "median failure PGA on the isolator / median overturning PGA on a fixed "
                                    "base (g / g), with its bootstrap band: above 1 the isolator raises the "
                                    "shaking needed to fail, below 1 it lowers it.",
    "P at the design PGA": "the fitted probability of failure (overturning, or on the isolator also capacity "
                           "exceeded) at the design PGA, from the lognormal fragility curve; 0 to 1.",
    "check ratio (isolator design checks)": "value / limit, the inverse of a margin: a check passes when it is "
                                            "at most 1.",
}
"""Every margin and ratio the assessment and the tables print, term -> what it compares and in which
units (capacity / demand, so > 1 is the safe side). The report shows it as "How to read the margins"
right under the verdict; other report modules may import it to define a term where they use it.

>>> MARGINS["travel margin"].split(" (")[0]
'isolator travel capacity / design displacement demand SDe(T)'
"""


def build_doc(res) -> dict:
    """The report document (see statue2model.report.html) of a RunResult."""
    sections, summary, warnings = [], [], []
    for name, man in res.stages.items():
        status = man.get("status", "not run")
        sec = {"id": name, "title": TITLES.get(name, name), "status": STATUS.get(status, "skipped"),
               "text": _texts(man.get("text")), "warnings": [str(w) for w in man.get("warnings", ()) or ()],
               "tables": [], "figures": []}
        warnings += [(name, sec["title"], w) for w in sec["warnings"]]
        if status in ("done", "cached"):
            rows = [[k, _text(v)] for k, v in man.get("summary", {}).items()]
            t = man.get("seconds")
            note = f"computed in {t:.1f} s" + (" (taken from the cache)" if status == "cached" else "")
            sec["text"].insert(0, f"{note}; files in {name}/.")
            if rows:
                sec["tables"].append({"title": "Summary", "columns": ["quantity", "value"], "rows": rows})
            tables, bad = _tables(man.get("tables"))
            sec["tables"] += tables
            sec["text"] += [f"{bad} table{'s' if bad != 1 else ''} left out: malformed in {name}/stage.json"] if bad else []
            sec["figures"] = _figures(man, Path(res.out), name)
            for k in HEADLINE.get(name, ()):
                if k in man.get("summary", {}):
                    summary.append((k, _text(man["summary"][k])))
        else:
            sec["text"].insert(0, f"stage {status}")
        sections.append(sec)
    verdict = getattr(res, "verdict", None) or None
    vdoc = None if not verdict else _verdict(verdict)
    if vdoc is not None and vdoc.get("headline"):
        key = key_figure(sections)
        if key is not None:
            vdoc["figure"] = key
    return {"title": f"statue2model report: {res.mesh.stem}",
            "verdict": vdoc,
            "definitions": None if not verdict else {"title": MARGINS_TITLE, "terms": dict(MARGINS)},
            "subtitle": f"{res.mesh.name}, {time.strftime('%Y-%m-%d %H:%M')}, statue2model {__version__}, "
                        f"stages {res.seconds:.1f} s",
            "summary": summary, "warnings": warnings, "sections": sections,
            "footer": "The resolved configuration is config.toml beside this report (statue2model run MESH "
                      "--config config.toml repeats the run); run.json holds every stage's numbers."}


KEY_FIGURES = (("dynamics", "fragility"), ("params", "props"))
"""The figure shown with the verdict on page 1, the first found: (section, a word of its file name)."""


def key_figure(sections: list[dict]) -> dict | None:
    """The page-1 figure (:data:`KEY_FIGURES`): the fragility curves per limit state, else the
    rocking parameters' figure; a copy of that section's figure entry, None when neither is there."""
    by_id = {s["id"]: s for s in sections}
    for sid, word in KEY_FIGURES:
        for fig in (by_id.get(sid) or {}).get("figures") or ():
            if word in Path(str(fig.get("path", ""))).name and not fig.get("refused"):
                return dict(fig)
    return None


def _verdict(verdict: dict) -> dict:
    """The verdict box of the report: the recommendation, the lines, the status and, when the verdict
    has them, its criteria, assumptions and limitations (lists of strings, shown under the box).

    >>> _verdict({"recommendation": "r", "lines": ["a"], "criteria": ["margin >= 1"], "hazard": {}})
    {'recommendation': 'r', 'lines': ['a'], 'status': 'warn', 'criteria': ['margin >= 1']}
    """
    out = {"recommendation": verdict["recommendation"], "lines": verdict["lines"],
           "status": verdict.get("status", "warn")}
    for key in ("code", "headline"):
        if isinstance(verdict.get(key), str) and verdict[key]:
            out[key] = verdict[key]
    if isinstance(verdict.get("bullets"), list) and verdict["bullets"]:
        out["bullets"] = [str(b) for b in verdict["bullets"]]
    for key, _ in VERDICT_SLOTS:
        items = verdict.get(key)
        if items:
            out[key] = [items] if isinstance(items, str) else [str(x) for x in items]
    return out


def _cell(v):
    """A table cell of a manifest: a non-finite number reads '-' (never 'nan' or 'inf'); anything
    else is kept as it is (None: an empty cell).

    >>> import numpy as np
    >>> _cell(float("inf")), _cell(np.float32("nan")), _cell(None), _cell(0.25), _cell("ok")
    ('-', '-', None, 0.25, 'ok')
    """
    if isinstance(v, numbers.Real) and not isinstance(v, numbers.Integral) and not math.isfinite(float(v)):
        return "-"
    return v


def _text(v) -> str:
    """A summary value as text: None and a non-finite number read '-'."""
    return "-" if v is None else str(_cell(v))


def _texts(text) -> list[str]:
    if text is None:
        return []
    return [text] if isinstance(text, str) else [str(t) for t in text] if isinstance(text, list) else [str(text)]


def _tables(tables) -> tuple[list[dict], int]:
    """(the well-formed tables of a manifest, how many were left out)."""
    good, bad = [], 0
    for t in tables if isinstance(tables, list) else ():
        cols, rows = (t.get("columns"), t.get("rows", [])) if isinstance(t, dict) else (None, None)
        sc = t.get("status_column") if isinstance(t, dict) else None
        ok = (isinstance(cols, list) and isinstance(rows, list)
              and all(isinstance(r, list) and len(r) == len(cols) for r in rows)
              and (sc is None or (type(sc) is int and 0 <= sc < len(cols))))
        if ok:
            good.append({"title": str(t.get("title") or ""), "columns": cols,
                         "rows": [[_cell(c) for c in r] for r in rows], "status_column": sc})
        else:
            bad += 1
    return good, bad


def _figures(man: dict, out: Path, name: str) -> list[dict]:
    """The stage's figures, each embedded only if it resolves inside OUT/<name>/
    (itself a folder inside OUT, not a link out of it)."""
    folder = out / name
    try:
        inside = not folder.is_symlink() and (not folder.exists()
                                              or folder.resolve(strict=True).parent == out.resolve(strict=True))
    except (OSError, RuntimeError):
        inside = False
    figs = safe_figures(man, folder)
    if inside:
        return figs
    return [{"path": str(f.get("path")), "caption": f.get("caption", ""), "refused": "path outside the stage folder"}
            for f in figs]


def write_html(res) -> Path:
    from .html import render_report

    return render_report(build_doc(res), Path(res.out) / "report.html", base_dir=Path(res.out))
