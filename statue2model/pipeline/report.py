"""The report of a run: the stages' manifests laid out as one self-contained HTML page
(:mod:`statue2model.report.html`), written to OUT/report.html.

Example
-------
>>> import tempfile, pathlib
>>> from statue2model.paths import default_scan
>>> from statue2model.pipeline.run import run_project
>>> res = run_project(default_scan(), pathlib.Path(tempfile.mkdtemp()), stages=["params"], say=lambda m: None)
>>> page = res.report.read_text()
>>> "Rocking parameters" in page and 'src="data:image/png;base64,' in page
True
>>> 'class="warnings"' in page                  # the bundled scan raises no warning
False
"""
from __future__ import annotations

import time
from pathlib import Path

from .. import __version__

TITLES = {"params": "Rocking parameters", "prototype": "Prototype: layers and sheets",
          "isolator": "Rolling-ball isolator", "dynamics": "2D analyses: fixed base and isolator",
          "crosscheck": "3D cross-check (PyBullet)"}
HEADLINE = {"params": ("mass", "h", "b_L / b_R", "uplift a_R", "weakest direction"),
            "isolator": ("design", "period T"),
            "dynamics": ("lowest overturning PGA (fixed)",
                         "lowest failing PGA (isolated: overturning or capacity exceeded)"),
            "crosscheck": ("2D/3D agreement",)}
STATUS = {"done": "done", "cached": "cached", "failed": "failed"}


def build_doc(res) -> dict:
    """The report document (see statue2model.report.html) of a RunResult."""
    sections, summary, warnings = [], [], []
    for name, man in res.stages.items():
        status = man.get("status", "not run")
        sec = {"id": name, "title": TITLES.get(name, name), "status": STATUS.get(status, "skipped"),
               "text": list(man.get("text", [])), "warnings": [str(w) for w in man.get("warnings", ()) or ()],
               "tables": [], "figures": []}
        warnings += [(name, sec["title"], w) for w in sec["warnings"]]
        if status in ("done", "cached"):
            rows = [[k, str(v)] for k, v in man.get("summary", {}).items()]
            t = man.get("seconds")
            note = f"computed in {t:.1f} s" + (" (taken from the cache)" if status == "cached" else "")
            sec["text"].insert(0, f"{note}; files in {name}/.")
            if rows:
                sec["tables"].append({"title": "Summary", "columns": ["quantity", "value"], "rows": rows})
            sec["tables"] += man.get("tables", [])
            sec["figures"] = [{"path": f"{name}/{f['path']}", "caption": f["caption"]} for f in man.get("figures", [])]
            for k in HEADLINE.get(name, ()):
                if k in man.get("summary", {}):
                    summary.append((k, str(man["summary"][k])))
        else:
            sec["text"].insert(0, f"stage {status}")
        sections.append(sec)
    verdict = getattr(res, "verdict", None) or None
    return {"title": f"statue2model report: {res.mesh.stem}",
            "verdict": None if not verdict else {"recommendation": verdict["recommendation"],
                                                 "lines": verdict["lines"], "status": verdict.get("status", "warn")},
            "subtitle": f"{res.mesh.name}, {time.strftime('%Y-%m-%d %H:%M')}, statue2model {__version__}, "
                        f"stages {res.seconds:.1f} s",
            "summary": summary, "warnings": warnings, "sections": sections,
            "footer": "The resolved configuration is config.toml beside this report (statue2model run MESH "
                      "--config config.toml repeats the run); run.json holds every stage's numbers."}


def write_html(res) -> Path:
    from ..report.html import render_report

    return render_report(build_doc(res), Path(res.out) / "report.html", base_dir=Path(res.out))
