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
from statue2model.report.html import figure_count, render_report

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
