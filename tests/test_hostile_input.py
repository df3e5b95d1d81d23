"""Nothing from input is executed or trusted: hostile scan names, edited manifests,
odd output paths (issue [9], item 5)."""
from __future__ import annotations

import base64
import csv
import io
import json
import os
from html.parser import HTMLParser
from pathlib import Path

import pytest
import tomllib
import trimesh

from statue2model.io.csvsafe import csv_text, safe_cell, write_csv
from statue2model.fabrication.output import _csv_text
from statue2model.report.figure_paths import safe_figures
from statue2model.pipeline.config import ProjectConfig, load_config
from statue2model.report.page import build_doc
from statue2model.pipeline.run import (
    RunResult,
    run_collection,
    run_project,
    write_config,
)
from statue2model.report.html import render_html

HOSTILE = ("a,b", "=1+2", "@SUM(1+1)", "<img src=x onerror=alert(1)>", "-2+3")
FORMULA_START = ("=", "+", "-", "@", "\t", "\r")


def quiet(msg):
    pass


def box(path: Path) -> Path:
    trimesh.creation.box(extents=(0.3, 0.2, 1.0)).export(path)
    return path


class Tags(HTMLParser):
    """Every start tag with its attributes."""

    def __init__(self):
        super().__init__()
        self.tags: list[tuple[str, dict]] = []

    def handle_starttag(self, tag, attrs):
        self.tags.append((tag, dict(attrs)))

    handle_startendtag = handle_starttag


def tags_of(page: str) -> list[tuple[str, dict]]:
    p = Tags()
    p.feed(page)
    p.close()
    return p.tags


def assert_inert(page: str, sections: set[str]) -> None:
    """No event handler, no script but ours, images only as data: URIs, links only to sections."""
    tags = tags_of(page)
    for tag, attrs in tags:
        assert not [a for a in attrs if a.lower().startswith("on")], (tag, attrs)
        if tag == "img":
            assert attrs["src"].startswith(("data:image/png;base64,", "data:image/svg+xml;base64,")), attrs
        if tag == "a":
            assert attrs["href"][1:] in sections and attrs["href"][0] == "#", attrs
    assert [t for t, _ in tags].count("script") == 1
    assert {t for t, _ in tags} <= {"html", "head", "meta", "title", "style", "script", "body", "main", "header",
                                    "h1", "h2", "h3", "p", "div", "ul", "ol", "li", "a", "span", "strong", "nav",
                                    "section", "table", "caption", "thead", "tbody", "tr", "th", "td", "figure",
                                    "img", "figcaption", "footer"}


# --- a folder of scans with hostile names ---------------------------------------------------------
@pytest.fixture(scope="module")
def hostile_collection(tmp_path_factory):
    folder = tmp_path_factory.mktemp("scans")
    names = []
    for name in HOSTILE:
        try:
            box(folder / f"{name}.stl")
            names.append(name)
        except OSError:             # a file system that refuses the name
            pass
    out = tmp_path_factory.mktemp("collection")
    data = run_collection(folder, out, stages=["params"], say=quiet)
    return names, out, data


@pytest.mark.slow
def test_collection_csv_has_whole_rows_and_no_formulas(hostile_collection):
    names, out, _ = hostile_collection
    rows = list(csv.reader(io.StringIO((out / "collection.csv").read_text(encoding="utf-8"))))
    header, body = rows[0], rows[1:]
    assert len(body) == len(names) >= 4
    assert all(len(r) == len(header) for r in body)
    for r in body:
        for cell in r:
            if cell.startswith(FORMULA_START):
                float(cell)                          # only numbers may start with a sign
    scans = sorted(r[header.index("scan")] for r in body)
    assert scans == sorted(("'" + n if n[0] in "=@-" else n) + ".stl" for n in names)
    mass = header.index("mass [kg]")
    assert [float(r[mass]) for r in body] == pytest.approx([2650.0 * 0.3 * 0.2 * 1.0] * len(body), rel=1e-3)


def test_reports_of_hostile_names_hold_no_markup_from_them(hostile_collection):
    names, out, _ = hostile_collection
    for name in names:
        page = (out / name / "report.html").read_text(encoding="utf-8")
        assert_inert(page, {"params", "prototype", "isolator", "dynamics", "crosscheck", "all-warnings"})
        if "<" in name:
            assert name not in page and "&lt;img src=x onerror=alert(1)&gt;" in page


# --- an edited manifest ---------------------------------------------------------------------------
def test_edited_manifest_cannot_embed_files_outside_the_stage_folder(tmp_path):
    scan = box(tmp_path / "box.stl")
    out = tmp_path / "out"
    run_project(scan, out, stages=["params"], report=False, say=quiet)
    secret = b"\x89PNG\r\n\x1a\nSECRET-BYTES-0123456789" * 3
    (tmp_path / "secret.png").write_bytes(secret)
    stage = out / "params"
    (stage / "link.png").symlink_to(tmp_path / "secret.png")
    (stage / "dangling.png").symlink_to(tmp_path / "later.png")
    man = json.loads((stage / "stage.json").read_text())
    assert [f["path"] for f in man["figures"]] == ["props.png"]
    man["figures"] += [{"path": "../../../../etc/hostname", "caption": "etc"},
                       {"path": "../secret.png", "caption": "up"},
                       {"path": str(tmp_path / "secret.png"), "caption": "absolute"},
                       {"path": "link.png", "caption": "symlink out"},
                       {"path": "sub/../../secret.png", "caption": "sneaky"},
                       {"path": 42, "caption": "not a path"},
                       {"path": "dangling.png", "caption": "dangling"}]
    (stage / "stage.json").write_text(json.dumps(man))          # same key: taken from the cache
    (tmp_path / "later.png").write_bytes(secret)                 # the dangling link's target appears
    res = run_project(scan, out, stages=["params"], say=quiet)
    assert res.stages["params"]["status"] == "cached"
    page = res.report.read_text(encoding="utf-8")
    assert base64.b64encode(secret).decode() not in page and b"SECRET".hex() not in page
    if Path("/etc/hostname").is_file() and Path("/etc/hostname").read_bytes().strip():
        assert base64.b64encode(Path("/etc/hostname").read_bytes()).decode() not in page
    assert page.count("figure refused: path outside the stage folder") == 6
    assert page.count("figure refused: malformed figure entry") == 1
    # props.png still shown: in its section and as page 1's key figure beside the verdict
    assert page.count('src="data:image/png;base64,') == 2
    assert 'data-figures-refused="7"' in page and 'data-figures-missing="7"' in page
    assert "7 figures refused" in page
    assert_inert(page, {"params", "prototype", "isolator", "dynamics", "crosscheck"})


def test_safe_figures_and_a_stage_folder_that_links_out_of_the_run(tmp_path):
    outside = tmp_path / "elsewhere"
    outside.mkdir()
    (outside / "p.png").write_bytes(b"\x89PNG\r\n\x1a\nX")
    (outside / "sub").mkdir()
    (outside / "sub" / "q.png").write_bytes(b"\x89PNG\r\n\x1a\nY")
    figs = safe_figures({"figures": [{"path": "p.png", "caption": "c"}, {"path": "sub/q.png"},
                                     {"path": "none.png"}, {"path": ".."}, {"path": "."}, "text"]}, outside)
    assert [f.get("refused") for f in figs] == [None, None, None, "path outside the stage folder",
                                                "path outside the stage folder", "malformed figure entry"]
    assert figs[0]["path"] == str((outside / "p.png").resolve())
    # OUT/params is a link to a folder outside OUT: nothing of it is embedded
    out = tmp_path / "out"
    out.mkdir()
    (out / "params").symlink_to(outside, target_is_directory=True)
    man = {"status": "cached", "seconds": 1.0, "summary": {}, "figures": [{"path": "p.png", "caption": "c"}]}
    res = RunResult(mesh=tmp_path / "m.stl", out=out, config=ProjectConfig(), stages={"params": man})
    doc = build_doc(res)
    assert doc["sections"][0]["figures"][0]["refused"] == "path outside the stage folder"
    page = render_html(doc, out)
    assert "data:image" not in page and "figure refused" in page


def test_malformed_manifest_tables_are_left_out_not_fatal(tmp_path):
    man = {"status": "done", "seconds": 1.0, "summary": {"x": 1}, "text": "one paragraph",
           "tables": [{"title": "ok", "columns": ["a", "b"], "rows": [[1, 2]]},
                      {"title": "bad", "columns": ["a"], "rows": [[1, 2]]},
                      {"title": "bad sc", "columns": ["a"], "rows": [[1]], "status_column": "<x>"}, "junk"]}
    res = RunResult(mesh=tmp_path / "m.stl", out=tmp_path, config=ProjectConfig(), stages={"params": man})
    doc = build_doc(res)
    assert [t["title"] for t in doc["sections"][0]["tables"]] == ["Summary", "ok"]
    assert "3 tables left out: malformed in params/stage.json" in doc["sections"][0]["text"]
    assert "one paragraph" in doc["sections"][0]["text"]
    render_html(doc, tmp_path)


# --- every string that reaches HTML stays escaped --------------------------------------------------
def test_every_field_of_a_report_document_is_escaped(tmp_path):
    evil = '"><img src=x onerror=alert(1)><script>alert(2)</script>\'<a href="javascript:x">'
    doc = {"title": evil, "subtitle": evil,
           "verdict": {"recommendation": evil, "lines": [evil], "status": evil},
           "summary": [(evil, evil)],
           "warnings": [evil, ("s1", evil, evil), (evil, evil, evil)],
           "sections": [{"id": "s1", "title": evil, "status": "done", "text": [evil], "warnings": [evil],
                         "tables": [{"title": evil, "columns": [evil, "v"], "rows": [[evil, evil]],
                                     "status_column": 1}],
                         "figures": [{"path": "x.png", "caption": evil}, {"path": evil, "caption": evil},
                                     {"path": "y.png", "caption": evil, "refused": evil}]}],
           "footer": evil}
    page = render_html(doc, tmp_path)
    assert_inert(page, {"s1"})
    assert "javascript:" not in [a.get("href") for _, a in tags_of(page)]
    assert 'class="verdict verdict-warn"' in page
    for sid in ("params\n", "a b", '"x', "1a"):
        with pytest.raises(ValueError):
            render_html({"title": "t", "sections": [{"id": sid, "title": "t"}]})
    with pytest.raises(ValueError):
        render_html({"title": "t", "sections": [{"id": "s", "title": "t", "status": evil}]})


# --- TOML ------------------------------------------------------------------------------------------
def test_a_newline_in_the_output_path_cannot_add_configuration(tmp_path):
    cfg = ProjectConfig()
    weird = "x\n[run]\nworkers = 3\r\n\x01\x7f\u2028'\"\\"
    try:
        out = tmp_path / weird
        out.mkdir()
    except OSError:
        out = None
    if out is not None:                                          # through a whole run
        run_project(box(tmp_path / "box.stl"), out, cfg, stages=["params"], report=False, say=quiet)
        path = out / "config.toml"
    else:
        path = write_config(cfg, tmp_path / "config.toml", Path("/m") / weird, Path("/o") / weird)
    text = path.read_bytes().decode("utf-8")                      # no newline translation
    assert tomllib.loads(text) == tomllib.loads(cfg.to_toml())    # no key added, none changed
    assert load_config(path).to_dict() == cfg.to_dict()
    assert load_config(path).run.workers is None
    lines = text.split("\n")
    assert all(line.startswith("#") for line in lines[:2]) and lines[2] == ""
    assert "workers = 3" not in lines and "\r" not in text and "\x01" not in text and "\x7f" not in text
    assert lines[1].count("$'") == (2 if out is not None else 3) and "\\n[run]\\nworkers = 3\\r\\n" in lines[1]


# --- CSV -------------------------------------------------------------------------------------------
def test_safe_cell_neutralises_formulas_and_keeps_numbers(tmp_path):
    assert [safe_cell(v) for v in ("=1+2", "+1+2", "-2+3", "@SUM(1)", "\t=1", "\r=1", "  =1", "a=1")] == \
           ["'=1+2", "'+1+2", "'-2+3", "'@SUM(1)", "'\t=1", "'\r=1", "'  =1", "a=1"]
    assert [safe_cell(v) for v in (-1.5, "-1.5", "+2e-3", "-inf", "nan", 3, True, None)] == \
           [-1.5, "-1.5", "+2e-3", "-inf", "nan", 3, True, ""]
    path = write_csv(tmp_path / "t.csv", ["name", "n"], [['a,"b"\nc', -1], ["=cmd|' /C calc'!A0", 2.5]])
    assert list(csv.reader(io.StringIO(path.read_text(encoding="utf-8"), newline=""))) == \
           [["name", "n"], ['a,"b"\nc', "-1"], ["'=cmd|' /C calc'!A0", "2.5"]]
    with pytest.raises(ValueError):
        csv_text(["a", "b"], [[1]])


def test_bill_of_materials_csv_is_quoted_and_neutralised():
    text = _csv_text([{"item": "=HYPERLINK(\"x\")", "parts": "a, b", "quantity": 2, "cut_m": 1.25},
                      {"item": "total", "parts": "", "quantity": 3, "cut_m": -0.5}])
    assert list(csv.reader(io.StringIO(text))) == [["item", "parts", "quantity", "cut_m"],
                                                   ["'=HYPERLINK(\"x\")", "a, b", "2", "1.25"],
                                                   ["total", "", "3", "-0.5"]]


def test_no_partial_files_left(tmp_path):
    write_csv(tmp_path / "a.csv", ["x"], [[1]])
    assert sorted(os.listdir(tmp_path)) == ["a.csv"]
