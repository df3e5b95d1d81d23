"""The self-contained HTML report, and headless Chromium's view of its figures."""
from __future__ import annotations

import re
import shutil
from pathlib import Path

import pytest

from statue2model.report.browser import (
    ENV_VAR,
    FigureCheck,
    check_figures,
    find_chromium,
    parse_figure_attributes,
    screenshot,
)
from statue2model.report.html import figure_count, render_html, render_report

SVG = (
    '<svg xmlns="http://www.w3.org/2000/svg" width="120" height="60" viewBox="0 0 120 60">'
    '<rect x="5" y="5" width="110" height="50" fill="#2a5d8f"/></svg>'
)


def _png(path: Path, fmt: str = "png") -> Path:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(3, 2), dpi=40)
    ax.plot([0, 1, 2, 3], [0, 1, 0.5, 1.5])
    fig.savefig(path, format=fmt)
    plt.close(fig)
    return path


@pytest.fixture(scope="module")
def figures(tmp_path_factory) -> Path:
    d = tmp_path_factory.mktemp("figs")
    _png(d / "curve.png")
    _png(d / "curve.jpg", fmt="jpeg")
    (d / "box.svg").write_text(SVG, encoding="utf-8")
    (d / "corrupt.png").write_bytes(b"this is not a PNG, just garbage bytes \x00\x01\x02" * 4)
    return d


def _doc(figs: list[dict]) -> dict:
    return {
        "title": "statue2model report: <dancing_girl>",
        "subtitle": "meshes/dancing_girl.ply, run 2026-11-21 10:00, statue2model 0.1.0",
        "summary": [("weakest direction", "90.0 deg"), ("uplift a_R", "0.276 g"), ("mass", 12.5)],
        "sections": [
            {
                "id": "params",
                "title": "Rocking parameters",
                "status": "done",
                "text": ["Injected: <script>alert('x')</script> & more", "second paragraph"],
                "tables": [
                    {
                        "title": "Checks",
                        "columns": ["quantity", "left", "right", "ok"],
                        "rows": [
                            ["alpha", 0.123456789, "0.25 rad", "pass"],
                            ["p", 2, 3.5, "fail"],
                            ["uplift", "yes", "n/a", True],
                            ["slides", "-", "-", False],
                        ],
                        "status_column": 3,
                    }
                ],
                "figures": figs,
            },
            {"id": "isolator", "title": "Isolator", "status": "skipped", "text": "not requested"},
            {"id": "fab", "title": "Prototype", "status": "cached"},
            {"id": "sim3d", "title": "3D check", "status": "failed", "text": ["pybullet crashed"]},
        ],
        "footer": "config: config.toml (resolved)",
    }


GOOD_FIGS = [
    {"path": "curve.png", "caption": "a PNG curve"},
    {"path": "box.svg", "caption": "an SVG box"},
    {"path": "curve.jpg", "caption": "a JPEG curve"},
]


@pytest.fixture(scope="module")
def good_report(figures, tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp("good") / "report.html"
    return render_report(_doc(GOOD_FIGS), out, base_dir=figures)


@pytest.fixture(scope="module")
def bad_report(figures, tmp_path_factory) -> Path:
    figs = [
        {"path": str(figures / "curve.png"), "caption": "a PNG curve"},  # absolute path
        {"path": "corrupt.png", "caption": "garbage bytes"},
        {"path": "nowhere.png", "caption": "never drawn"},
    ]
    out = tmp_path_factory.mktemp("bad") / "report.html"
    return render_report(_doc(figs), out, base_dir=figures)


# ---- the HTML itself ---------------------------------------------------------------------------


def test_self_contained(good_report):
    page = good_report.read_text(encoding="utf-8")
    assert "http://" not in page and "https://" not in page
    assert not re.search(r"""(?:src|href)\s*=\s*["']?(?:https?:|//)""", page, re.IGNORECASE)
    srcs = re.findall(r"""<img\b[^>]*\bsrc="([^"]*)\"""", page)
    assert len(srcs) == 3 and all(s.startswith("data:") for s in srcs)
    assert any(s.startswith("data:image/png;base64,") for s in srcs)
    assert any(s.startswith("data:image/svg+xml;base64,") for s in srcs)
    assert any(s.startswith("data:image/jpeg;base64,") for s in srcs)
    # no stylesheet, font or script is loaded from anywhere, and the policy forbids it
    assert not re.search(r"<link\b|@import|url\(|<script\b[^>]*\bsrc", page, re.IGNORECASE)
    assert "default-src 'none'" in page
    assert "max-width: 100%" in page
    # every href points inside the page
    assert all(h.startswith("#") for h in re.findall(r'href="([^"]*)"', page))
    assert not list(good_report.parent.glob("*.part"))


def test_text_is_escaped(good_report):
    page = good_report.read_text(encoding="utf-8")
    assert "&lt;script&gt;alert(&#x27;x&#x27;)&lt;/script&gt; &amp; more" in page
    assert "<script>alert" not in page
    assert page.count("<script") == 1  # our own load handler only
    assert "statue2model report: &lt;dancing_girl&gt;" in page


def test_structure_badges_and_cells(good_report):
    page = good_report.read_text(encoding="utf-8")
    for sid in ("params", "isolator", "fab", "sim3d"):
        assert f'id="{sid}"' in page and f'href="#{sid}"' in page
    for status in ("done", "skipped", "cached", "failed"):
        assert f'class="badge badge-{status}"' in page
    assert '<td class="cell-pass">pass</td>' in page
    assert '<td class="cell-fail">fail</td>' in page
    assert '<td class="cell-pass">yes</td>' in page  # True
    assert '<td class="cell-fail">no</td>' in page  # False
    # numbers right-aligned, text not
    assert '<td class="num">0.123457</td>' in page
    assert '<td class="num">0.25 rad</td>' in page
    assert '<td class="num">2</td>' in page
    assert "<td>alpha</td>" in page and "<td>n/a</td>" in page
    assert '<td class="num">0.276 g</td>' in page  # summary
    assert "<figcaption>an SVG box</figcaption>" in page
    assert 'data-figures-missing="0"' in page


def test_missing_figure_is_noted(bad_report, figures):
    page = bad_report.read_text(encoding="utf-8")
    assert "figure missing: nowhere.png" in page
    assert "1 figure missing: nowhere.png" in page
    assert 'data-figures-missing="1"' in page
    doc = _doc([{"path": "curve.png"}, {"path": "nowhere.png"}, {"path": "notes.txt"}])
    assert figure_count(doc, base_dir=figures).total == 3
    assert figure_count(doc, base_dir=figures).missing == ("nowhere.png", "notes.txt")


def test_default_base_dir_is_the_report_dir(figures):
    out = figures / "r.html"
    render_report({"title": "t", "sections": [{"id": "a", "title": "A", "figures": [{"path": "box.svg"}]}]}, out)
    page = out.read_text(encoding="utf-8")
    assert "data:image/svg+xml;base64," in page and 'data-figures-missing="0"' in page


@pytest.mark.parametrize(
    "doc, match",
    [
        ({"sections": []}, "title"),
        ({"title": "t", "sections": [{"id": "a", "title": "A"}, {"id": "a", "title": "B"}]}, "duplicate"),
        ({"title": "t", "sections": [{"id": "a b", "title": "A"}]}, "id"),
        ({"title": "t", "sections": [{"id": "a", "title": "A", "status": "ok"}]}, "status"),
        ({"title": "t", "sections": [{"id": "a", "title": "A",
                                       "tables": [{"columns": ["x", "y"], "rows": [[1]]}]}]}, "1 cells for 2"),
        ({"title": "t", "sections": [{"id": "a", "title": "A",
                                       "tables": [{"columns": ["x"], "rows": [[1]], "status_column": 1}]}]}, "status_column"),
        ({"title": "t", "definitions": {"title": "How to read", "terms": "margin = capacity / demand"},
          "sections": []}, "definitions"),
    ],
)
def test_malformed_doc_raises(tmp_path, doc, match):
    with pytest.raises(ValueError, match=match):
        render_report(doc, tmp_path / "r.html")
    assert not (tmp_path / "r.html").exists()


def test_parse_figure_attributes():
    dom = ('<html><head></head><body data-figures-missing="1" data-figures-total="2" data-figures-loaded="1" '
           'data-figures-broken="[&quot;a &amp; b&quot;]"><p>x</p></body></html>')
    assert parse_figure_attributes(dom) == FigureCheck(2, 1, ("a & b",), 1)
    with pytest.raises(RuntimeError, match="load handler"):
        parse_figure_attributes("<html><body></body></html>")


def test_find_chromium_env(monkeypatch, tmp_path):
    monkeypatch.setenv(ENV_VAR, str(tmp_path / "no-such-browser"))
    with pytest.raises(RuntimeError, match=ENV_VAR):
        find_chromium()


def test_failing_browser_is_one_line_error(good_report):
    false = shutil.which("false")
    if false is None:
        pytest.skip("no 'false' command")
    with pytest.raises(RuntimeError, match=r"^false exited with status 1 on report.html: \(no message\)$"):
        check_figures(good_report, browser=false)


# ---- headless Chromium -------------------------------------------------------------------------


@pytest.mark.slow
def test_browser_loads_all_figures(chromium, good_report):
    check = check_figures(good_report, browser=chromium)
    assert check == FigureCheck(total=3, loaded=3, broken=(), missing=0)
    assert check.ok


def test_browser_reports_broken_figure(chromium, bad_report):
    check = check_figures(bad_report, browser=chromium)
    assert check.total == 2  # the missing file has no <img>
    assert check.loaded == 1
    assert check.broken == ("garbage bytes",)
    assert check.missing == 1
    assert not check.ok


def test_browser_needs_the_load_handler(chromium, tmp_path):
    plain = tmp_path / "plain.html"
    plain.write_text("<!DOCTYPE html><html><body><p>no script</p></body></html>", encoding="utf-8")
    with pytest.raises(RuntimeError, match="load handler did not run"):
        check_figures(plain, browser=chromium)
    with pytest.raises(RuntimeError, match="no such report file"):
        check_figures(tmp_path / "absent.html", browser=chromium)


def test_screenshot(chromium, good_report, tmp_path):
    png = screenshot(good_report, tmp_path / "shot.png", width=800, height=600, browser=chromium)
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert not [p for p in tmp_path.iterdir() if p.name != "shot.png"]


# ---- a report a consultancy would sign off (#27, item 5) ----------------------------------------

LONG = "synthetic:duration=20,pga=0.4g,seed=1/records/record_with_a_long_name_{}.csv"


def _wide_doc(fig_dir: Path) -> dict:
    """A report as the pipeline builds it: verdict with its criteria, the margins' definitions, long
    summary values, a dynamics-like table with long headers, a 10-column table of long strings
    (every cell tagged R<row>C<col>) and a figure far wider than the page."""
    from statue2model.report.page import MARGINS, MARGINS_TITLE

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(20, 3), dpi=100)          # 2000 px wide
    ax.plot([0, 1, 2, 3], [0, 1, 0.5, 1.5])
    fig.savefig(fig_dir / "wide.png")
    plt.close(fig)
    cols = [f"column {c} with a header that is long (unit m/s^2)" for c in range(10)]
    rows = [[f"R{r}C{c} {LONG.format(f'{r}_{c}')} and more words" for c in range(10)] for r in range(4)]
    return {
        "title": "statue2model report: dancing_girl",
        "subtitle": "dancing_girl.ply, 2026-11-26 10:00, statue2model 0.1.0",
        "verdict": {"recommendation": "the designed isolator does not protect at the design level: on the isolator "
                                      "it fails from 0.250 g (isolator capacity exceeded) under "
                                      "synthetic:duration=20,pga=0.4g,seed=1 < design PGA 0.287 g",
                    "lines": ["Hazard: EC8-1 spectrum 'ec8:ag=0.25g,ground=C,type=1': a_g 0.250 g, S 1.15."],
                    "status": "fail", "criteria": ["every margin >= 1"], "assumptions": ["rigid body"],
                    "limitations": ["one horizontal component at a time"]},
        "definitions": {"title": MARGINS_TITLE, "terms": MARGINS},
        "summary": [("lowest failing PGA (isolated: overturning or capacity exceeded)", "0.250 g (capacity exceeded)"),
                    ("record", LONG.format("summary"))],
        "warnings": [("dynamics", "2D analyses", "plate passes the capacity " + LONG.format("warning"))],
        "sections": [
            {"id": "dynamics", "title": "2D analyses: fixed base and isolator", "status": "done",
             "text": ["Variability on the isolator (variability.json: isolated.run, not_run_pga_m_s2)."],
             "tables": [
                 {"title": "Stability spectra: 0.5-10 Hz x 0.02-1 g",
                  "columns": ["base", "moves", "overturns (on the isolator: or exceeds its capacity)",
                              "lowest failing amplitude (overturning; on the isolator: or capacity exceeded)",
                              "outcomes"],
                  "rows": [["fixed base", "72.5 %", "8.2 %", "0.347 g",
                            "no motion 440, rocking 1029, overturn mode 1 11, overturn mode 2 114"],
                           ["on the isolator", "4.3 %", "4.3 %", "0.146 g",
                            "no motion 1531, isolator capacity exceeded 69"]]},
                 {"title": "Ten columns of long strings", "columns": cols, "rows": rows}],
             "figures": [{"path": "wide.png", "caption": "a figure 2000 px wide"}]},
        ],
        "footer": "The resolved configuration is config.toml beside this report.",
    }


@pytest.fixture(scope="module")
def wide_report(tmp_path_factory) -> Path:
    d = tmp_path_factory.mktemp("wide")
    return render_report(_wide_doc(d), d / "report.html", base_dir=d)


def test_wide_tables_are_marked_for_wrapping(wide_report):
    page = wide_report.read_text(encoding="utf-8")
    assert page.count('<table class="data wide">') == 1           # the 10-column table only
    assert page.count('<table class="data">') == 1                # the 5-column one keeps the normal font
    assert '<td class="long">R0C0 ' in page                       # a long token may break inside
    assert "<td>no motion 1531, isolator capacity exceeded 69</td>" in page   # ordinary words wrap between words
    assert "@page { size: A4;" in page and "@media print" in page
    assert "td.long { overflow-wrap: anywhere; }" in page


def test_tables_fit_an_a4_window(chromium, wide_report, tmp_path):
    from statue2model.report.browser import A4_WIDTH_PX, check_layout

    layout = check_layout(wide_report, width=A4_WIDTH_PX, browser=chromium)
    assert layout.width <= A4_WIDTH_PX and layout.scroll_width <= layout.width, layout
    assert layout.overflowing == () and layout.ok
    # the check can fail: the same page with cells that may not wrap needs a scroll bar
    stiff = tmp_path / "stiff.html"
    stiff.write_text(wide_report.read_text(encoding="utf-8").replace(
        "</style>", "th, td { white-space: nowrap !important; overflow-wrap: normal !important; }</style>", 1),
        encoding="utf-8")
    bad = check_layout(stiff, width=A4_WIDTH_PX, browser=chromium)
    assert not bad.ok and "table: Ten columns of long strings" in bad.overflowing
    assert "table: Stability spectra: 0.5-10 Hz x 0.02-1 g" in bad.overflowing


def test_report_prints_to_a4_pdf_with_every_cell(chromium, wide_report, tmp_path):
    from statue2model.report.browser import print_pdf

    pdf = print_pdf(wide_report, tmp_path / "report.pdf", browser=chromium)
    data = pdf.read_bytes()
    assert data[:5] == b"%PDF-" and len(data) > 20_000
    pages = re.findall(rb"/Type\s*/Page\b(?!s)", data)
    assert len(pages) >= 1
    boxes = {tuple(round(float(x)) for x in m.split()) for m in re.findall(rb"/MediaBox\s*\[([^\]]*)\]", data)}
    assert boxes == {(0, 0, 595, 842)}                             # A4 in points, from the page's @page rule
    pdftotext = shutil.which("pdftotext")
    if pdftotext is None:                                          # poppler-utils not installed: pages only
        return
    import subprocess

    text = subprocess.run([pdftotext, "-raw", str(pdf), "-"], capture_output=True, text=True, check=True).stdout
    for r in range(4):
        for c in range(10):
            assert f"R{r}C{c}" in text, f"cell R{r}C{c} is cut off the printed page"
    squeezed = re.sub(r"\s+", "", text)
    assert LONG.format("3_9") in squeezed                          # the last cell's long string, whole
    assert "How to read the margins" in text and "travel margin" in text


def test_verdict_slots_render_under_the_box(tmp_path):
    d = tmp_path
    page = render_report(_wide_doc(d), d / "r.html", base_dir=d).read_text(encoding="utf-8")
    box, basis = page.index('id="verdict"'), page.index('id="verdict-basis"')
    defs, warns = page.index('id="definitions"'), page.index('id="all-warnings"')
    assert box < basis < defs < warns
    assert '<h3>Criteria</h3><ul class="verdict-criteria"><li>every margin &gt;= 1</li></ul>' in page
    assert '<h3>Assumptions</h3><ul class="verdict-assumptions"><li>rigid body</li></ul>' in page
    assert '<h3>Limitations</h3><ul class="verdict-limitations"><li>one horizontal component at a time</li></ul>' in page
    doc = _wide_doc(d)
    for key in ("criteria", "assumptions", "limitations"):
        del doc["verdict"][key]
    plain = render_report(doc, d / "p.html", base_dir=d).read_text(encoding="utf-8")
    assert "verdict-basis" not in plain.split("<style>")[0] + plain.split("</style>")[1]


def test_build_doc_passes_the_verdict_slots_and_the_margins(tmp_path):
    from statue2model.pipeline.config import ProjectConfig
    from statue2model.pipeline.run import RunResult
    from statue2model.report.page import MARGINS, build_doc

    verdict = {"recommendation": "isolate with the designed device", "lines": ["Hazard: x"], "status": "ok",
               "criteria": ["travel margin >= 1"], "assumptions": "one string is one item", "hazard": {}}
    res = RunResult(mesh=tmp_path / "m.stl", out=tmp_path, config=ProjectConfig(), stages={}, verdict=verdict)
    doc = build_doc(res)
    assert doc["verdict"] == {"recommendation": "isolate with the designed device", "lines": ["Hazard: x"],
                              "status": "ok", "criteria": ["travel margin >= 1"],
                              "assumptions": ["one string is one item"]}
    assert doc["definitions"]["title"] == "How to read the margins" and doc["definitions"]["terms"] == MARGINS
    page = render_html(doc, tmp_path)
    assert page.index('id="verdict"') < page.index('id="definitions"')
    assert "<th scope=\"row\">travel margin</th>" in page
    res = RunResult(mesh=tmp_path / "m.stl", out=tmp_path, config=ProjectConfig(), stages={})
    assert build_doc(res)["definitions"] is None                   # no verdict, no margins to read


def test_every_margin_of_the_verdict_is_defined():
    """Each *_margin the assessment computes has its entry in page.MARGINS (a new margin needs one)."""
    import statue2model.assessment.verdict as verdict_module
    from statue2model.report.page import MARGINS

    term = {"uplift_margin": "uplift margin", "overturn_margin": "overturning margin (fixed base)",
            "travel_margin": "travel margin", "felt_margin": "felt-acceleration margin",
            "failure_margin": "failure margin (on the isolator)"}
    source = Path(verdict_module.__file__).read_text(encoding="utf-8")
    keys = set(re.findall(r"""["'](\w+_margin)["']""", source))
    assert keys == set(term), keys
    for key in keys:
        assert term[key] in MARGINS
    assert "ratio of medians (fragility)" in MARGINS and "design PGA" in MARGINS
    for text in MARGINS.values():
        assert text.strip() and "  " not in text


# ---- the 3D cross-check section in an engineer's words ------------------------------------------

def _numbers(text: str) -> list[str]:
    return re.findall(r"\d+(?:\.\d+)?", text)


def test_crosscheck_section_has_no_developer_notes():
    from statue2model.crosscheck.case import Case, Comparison
    from statue2model.crosscheck.isolator_cases import TRACE
    from statue2model.report.crosscheck_section import crosscheck_section

    raw_note = ("every engine step, unfiltered; raw per-step peaks 2D 0.941, 3D 4.238 m/s^2 (ball-facet contact "
                "impulses); 5 ms window mean 2D 0.941, 3D 2.157; compared: both low-passed at 20 Hz; engine dt "
                "0.5 ms, 50 solver iterations, grooves: a 4 mm lattice. " + TRACE)
    cases = (Case.relative("isolator free vibration: decay per cycle (c = mu r)", "m", 0.1153, 0.1195, 0.10,
                           note="rollingFriction mapped, not calibrated", quantity="friction decay per cycle"),
             Case.relative("isolated statue: peak plate acceleration (raw)", "m/s^2", 0.9414, 4.238, 0.10,
                           note=raw_note, quantity="peak plate acceleration"),
             Case("synthetic KT seed 1: peak rotation", "peak rotation", 0.02, 0.03, 0.5, 0.05, False,
                  "relative", "rad", "", "3D peak 0.0300 rad against 2D 0.0200 rad: one record's peak is "
                  "sensitive to every impact (the models' own spread is computed without --quick; the "
                  "statistical check over records is --records N)"),
             Case.equal("one-sine: overturn", True, True, quantity="overturn"),
             Case.equal("one-sine: overturn (2D given 3D's e)", True, True).as_diagnostic(
                 "2D given 3D's e (the restitution calibrated on the 3D scene): a diagnostic, not a check"))
    man = crosscheck_section(Comparison(cases), {"json": Path("crosscheck.json"), "free rocking": Path("f.png")},
                             isolator_wanted=False, design=None, isolator_enabled=True)
    table = man["tables"][0]
    cells = [str(c) for row in table["rows"] for c in row]
    everything = "\n".join([*man["text"], *man["warnings"], *cells, *table["columns"],
                            *(f["caption"] for f in man["figures"]), *map(str, man["summary"].values())])
    for marker in (".py", "benchmarks/", "rollingFriction", "Traced", "TODO", "calibrat", "engine", "--quick",
                   "--records", "--groove", "per-step", "PyBullet) time histories"):
        assert marker not in everything, marker
    assert not re.search(r"(?<![\w+-])--[a-z]", everything)
    # every number of the notes is still there, the convergence study once, under its own heading
    kept = _numbers(everything)
    for n in _numbers(raw_note) + _numbers("3D peak 0.0300 rad against 2D 0.0200 rad"):
        assert n in kept, n
    study = [t for t in man["text"] if t.startswith("Why the unfiltered peak plate accelerations differ")]
    assert len(study) == 1 and sum(TRACE[-40:] in c for c in cells) == 0    # not repeated in the table
    assert "benchmarks" not in study[0] and "0.97 / 1.10 / 1.87 / 4.03" in study[0]
    # what was compared and the tolerance; the differences computed by hand
    assert table["columns"] == ["case", "unit", "2D", "3D", "difference", "tolerance", "result", "how compared",
                                "why missed / not counted"]
    decay, raw, peak, ot, diag = table["rows"]
    assert decay[4:7] == ["3.6 %", "10 %", "pass"]                  # |0.1195 - 0.1153| / 0.1153 = 3.64 %
    assert raw[4:7] == ["350.2 %", "10 %", "fail"]                  # (4.238 - 0.9414) / 0.9414 = 350.18 %
    assert "see the convergence study above" in raw[8]
    assert peak[8].startswith("3D peak 0.0300 rad against 2D 0.0200 rad") and "full (not the quick)" in peak[8]
    assert ot[2:7] == ["yes", "yes", "same", "same outcome", "pass"]
    assert diag[6] == "diagnostic" and "measured on the 3D scene" in diag[8]
    assert any(t.startswith("What was compared") for t in man["text"])
    assert any(t.startswith("Tolerance:") for t in man["text"])
    agree = next(t for t in man["text"] if t.startswith("The models agree"))
    assert "friction decay per cycle" in agree and "overturn" in agree
    assert "They differ on: peak plate acceleration (0 of 1 within), peak rotation (0 of 1 within)" in agree


def test_page_one_holds_the_headline_the_bullets_and_the_key_figure(chromium, tmp_path):
    """Printed (Chromium, A4): page 1 holds the title, the code, the headline, the bullets and the key
    figure; the long reasoning, the lines and the basis are in the appendix at the end (issue [21])."""
    import subprocess

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from statue2model.report.browser import print_pdf

    fig, ax = plt.subplots(figsize=(15, 5), dpi=100)
    ax.plot([0, 1, 2, 3], [0, 0.2, 0.9, 1.0])
    fig.savefig(tmp_path / "fragility.png")
    plt.close(fig)
    head = ("Isolate it: on the designed device (about 9,011 EUR) it stays in full contact under the design "
            "earthquake, with 22 % travel to spare; without it, 6 of 7 design records lift it.")
    bullets = ["Design earthquake: peak ground acceleration 0.287 g at the object (EC8-1, ground C).",
               "It lifts from 0.277 g of ground acceleration; 6 of 7 design records lift it on its own base.",
               "On the device: travel margin 22 %."]
    long = "the reasoning with every check and formula, " * 40
    doc = {"title": "statue2model report: statue", "subtitle": "statue.ply",
           "verdict": {"recommendation": long, "lines": [long] * 8, "status": "ok", "code": "ISOLATE",
                       "headline": head, "bullets": bullets, "criteria": [long], "assumptions": [long],
                       "figure": {"path": "fragility.png", "caption": "Fragility per limit state"}},
           "warnings": [("params", "Rocking parameters", "a warning " * 30)] * 8,
           "sections": [{"id": "params", "title": "Rocking parameters", "status": "done",
                         "text": ["numbers " * 200], "figures": []}]}
    page = render_report(doc, tmp_path / "report.html", base_dir=tmp_path)
    html = page.read_text(encoding="utf-8")
    assert html.index('id="verdict"') < html.index('id="all-warnings"') < html.index('id="verdict-reasoning"')
    pdf = print_pdf(page, tmp_path / "report.pdf", browser=chromium)
    pdftotext = shutil.which("pdftotext")
    if pdftotext is None:
        pytest.skip("pdftotext (poppler-utils) is needed to read the printed page")
    one = subprocess.run([pdftotext, "-f", "1", "-l", "1", "-raw", str(pdf), "-"], capture_output=True, text=True,
                         check=True).stdout
    squeezed = re.sub(r"\s+", " ", one)
    assert "ISOLATE" in one and head in squeezed, one
    for b in bullets:
        assert b in squeezed, b
    assert "Fragility per limit state" in one                          # the key figure's caption
    assert "Appendix: the reasoning" not in one and "the reasoning with every check" not in one
    every = subprocess.run([pdftotext, "-raw", str(pdf), "-"], capture_output=True, text=True, check=True).stdout
    assert "Appendix: the reasoning" in every
