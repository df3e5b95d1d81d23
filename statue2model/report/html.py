"""A self-contained HTML report: one file that opens in any browser, offline.

The report is described by plain data (built by the pipeline) and rendered by
:func:`render_report`. Everything the page needs is inside the one file: the CSS
is inline, every figure is embedded as a ``data:`` URI (PNG, JPEG, GIF, WebP as
base64; SVG as base64 ``image/svg+xml``), and a Content-Security-Policy meta tag
forbids the browser to load anything else, so the page never touches the network.

The document::

    doc = {
        "title": "statue2model report: dancing_girl",
        "subtitle": "meshes/dancing_girl.ply, ...",            # optional
        "verdict": {"recommendation": "isolate with ...",      # optional: the assessment box, first
                    "lines": ["Hazard: ...", "Fixed base: ..."],
                    "status": "ok",                         # ok | warn | fail (the box's colour)
                    "code": "ISOLATE", "headline": "Isolate it: ...", "bullets": ["..."],  # optional:
                    # with a headline the box holds it and the bullets; the recommendation (the
                    # reasoning), the lines and the basis go to an appendix at the end
                    "criteria": ["..."], "assumptions": ["..."], "limitations": ["..."]},  # optional
        "definitions": {"title": "How to read the margins",    # optional: under the verdict
                        "terms": {"uplift margin": "uplift acceleration / design PGA ...", ...}},
        "summary": [("weakest direction", "90.0 deg"), ...],    # optional key/value rows
        "warnings": [("params", "Rocking parameters", "units unsure: ..."), ...],
                                    # optional (section id, title, text) or plain text: a block at the top
        "sections": [
            {"id": "params",                # letters, digits, '-', '_', '.'; unique
             "title": "Rocking parameters",
             "status": "done",              # done | cached | skipped | failed | None
             "text": ["paragraph", ...],    # plain text (a single string is one paragraph)
             "warnings": ["...", ...],      # optional: shown under the heading, class "warning"
             "tables": [{"title": "...", "columns": ["quantity", "left", "right"],
                         "rows": [[...], ...],
                         "status_column": 3}],   # optional: colour pass/fail/yes/no/True/False
             "figures": [{"path": "props.png", "caption": "..."}]},
        ],
        "footer": "config: config.toml (resolved) ...",         # optional
    }

Rules:

* All text is HTML-escaped (attribute values too, and always quoted); the only
  URLs are ``#<section id>`` (ids are checked against the pattern above) and
  ``data:`` URIs of a fixed MIME type, so nothing in ``doc`` can inject markup.
* A figure may carry ``"root"``: a folder its file must resolve inside (symlinks
  followed), else it is not read and the page shows "figure refused: path outside
  the stage folder: name"; a figure with ``"refused": reason`` (set by the caller,
  e.g. :func:`statue2model.report.figure_paths.safe_figures`) is never read either.
  Refused figures are listed at the top and counted in ``data-figures-refused``
  (and in ``data-figures-missing``: they have no ``<img>``).
* Figure paths are absolute or relative to ``base_dir`` (default: the directory
  of the report file). A figure whose file is missing (or whose type cannot be
  embedded) becomes a visible "figure missing: name" note, is counted in
  ``<body data-figures-missing="N">`` and listed at the top of the page; it is
  not an exception.
* Table cells: ``float`` values are written with ``.6g``; cells that are numbers
  (or a number followed by a short unit, e.g. ``"0.276 g"``) are right-aligned.
  In the ``status_column``, ``pass``/``yes``/``ok``/``True`` get class ``cell-pass``
  (green) and ``fail``/``no``/``False`` class ``cell-fail`` (red); booleans
  show as ``yes``/``no``.
* Tables fit the page (no horizontal scroll bar at the width of an A4 page, 794 px,
  and nothing cut when printed): headers wrap, a cell holding a run of more than
  :data:`LONG_TOKEN` characters without a space (a path, a record spec) gets class
  ``long`` and may break inside it, a table of :data:`WIDE_COLUMNS` columns or more
  gets class ``wide`` (smaller font, tighter cells). The print style sets A4 pages
  with margins, repeats table headers on each page, keeps rows, figures and the
  verdict box whole and scales figures to the page.
* ``warnings`` (document) are listed at the top of the page, above the summary, in a
  ``<div class="warning warnings" id="all-warnings">``, each with a link to its section;
  a section's ``warnings`` show under its heading as ``<p class="warning">warning: ...</p>``.
* ``verdict`` is rendered first, above the warnings, as ``<div class="verdict
  verdict-<status>" id="verdict">``: the recommendation in bold, then one paragraph
  per line. Its optional ``criteria``, ``assumptions`` and ``limitations`` (lists of
  strings, :data:`VERDICT_SLOTS`) follow under the box in ``<div class="verdict-basis"
  id="verdict-basis">``, one headed list each; without them nothing is added. With a
  ``headline`` the box holds the code, the headline in bold and the ``bullets``; the
  recommendation (its reasoning), the lines and the basis go to the last section,
  ``<section id="verdict-reasoning" class="appendix">`` (page 1 reads as a verdict).
* ``definitions`` (e.g. :data:`statue2model.report.page.MARGINS`) follow as ``<div
  class="definitions" id="definitions">``: a heading and a two-column table, the term
  in a row header and its meaning beside it.
* Section ``status`` shows as a badge ``badge badge-<status>`` in the heading and
  in the table of contents.

Browser check contract (read by :mod:`statue2model.report.browser`): a small
inline script runs on the window ``load`` event and writes on ``<body>``

* ``data-figures-total``: the number of ``<img>`` elements,
* ``data-figures-loaded``: those with ``complete && naturalWidth > 0``,
* ``data-figures-broken``: a JSON list of the ``alt`` texts of the others
  (it also marks their ``<figure>`` with class ``broken`` so they show in red).

* ``data-verdict-height`` and ``data-verdict-first``: the rendered height (px) of the
  verdict box and whether it stands above the first section (only with a verdict).
* ``data-page-width`` and ``data-page-scroll-width``: the window's content width and
  the page's scroll width (px); ``data-overflowing``: a JSON list of what sticks out to
  the right (a table whose width exceeds its box, by its caption; any other element past
  the window's edge, as tag#id.class).

``data-figures-missing`` is written by the renderer itself (figures whose file
was absent, so no ``<img>`` exists for them).

Example
-------
>>> import tempfile, pathlib
>>> import matplotlib
>>> matplotlib.use("Agg")
>>> import matplotlib.pyplot as plt
>>> from statue2model.report.html import render_report, figure_count
>>> tmp = pathlib.Path(tempfile.mkdtemp())
>>> fig, ax = plt.subplots(figsize=(3, 2), dpi=50)
>>> _ = ax.plot([0, 1, 2], [0, 1, 0])
>>> fig.savefig(tmp / "curve.png"); plt.close(fig)
>>> doc = {
...     "title": "statue2model report: demo",
...     "summary": [("uplift a_R", "0.276 g")],
...     "sections": [{
...         "id": "params", "title": "Rocking parameters", "status": "done",
...         "text": ["Slenderness & size <from the scan>."],
...         "tables": [{"title": "Checks", "columns": ["quantity", "value", "ok"],
...                     "rows": [["alpha", 0.2345678901, "pass"], ["p", 2.1, False]],
...                     "status_column": 2}],
...         "figures": [{"path": "curve.png", "caption": "a curve"},
...                     {"path": "absent.png", "caption": "not drawn"}]}],
... }
>>> out = render_report(doc, tmp / "report.html")
>>> page = out.read_text(encoding="utf-8")
>>> 'src="data:image/png;base64,' in page, "&lt;from the scan&gt;" in page
(True, True)
>>> "figure missing: absent.png" in page, '<td class="num">0.234568</td>' in page
(True, True)
>>> '<td class="cell-pass">pass</td>' in page, '<td class="cell-fail">no</td>' in page
(True, True)
>>> figure_count(doc, base_dir=tmp)
FigureCount(total=2, missing=('absent.png',))
"""
from __future__ import annotations

import base64
import html
import math
import numbers
import os
import re
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from ..io.files import atomic_write

STATUSES = ("done", "cached", "skipped", "failed")

MIME_TYPES = {
    ".png": "image/png",
    ".jpg": "image/jpeg",
    ".jpeg": "image/jpeg",
    ".svg": "image/svg+xml",
    ".gif": "image/gif",
    ".webp": "image/webp",
}

_PASS = {"pass", "passed", "yes", "ok", "true"}
_FAIL = {"fail", "failed", "no", "false"}

_ID_RE = re.compile(r"^[A-Za-z][A-Za-z0-9_.-]*$")
# A number, optionally followed by one short unit token: "0.276", "-1.5e-3", "90.0 deg", "12 %", "3.2 m/s^2".
_NUM_RE = re.compile(
    r"^[-+\u2212]?(?:\d[\d,_]*(?:\.\d*)?|\.\d+)(?:[eE][-+]?\d+)?(?:\s?[^\s\d][^\s]{0,11})?$"
    r"|^[-+]?(?:nan|inf|infinity)$",
    re.IGNORECASE,
)

# A table with this many columns or more is set in a smaller font with tighter cells (class "wide").
WIDE_COLUMNS = 6
# A cell whose text holds a run of more characters than this without a space may break inside it.
LONG_TOKEN = 14
# The verdict's optional slots, rendered in this order under its box (each a list of strings).
VERDICT_SLOTS = (("criteria", "Criteria"), ("assumptions", "Assumptions"), ("limitations", "Limitations"))

CSP = "default-src 'none'; img-src data:; style-src 'unsafe-inline'; script-src 'unsafe-inline'"

CSS = """
:root { --fg:#1d232a; --muted:#5b6570; --line:#d5dae0; --bg-alt:#f5f7f9; --accent:#2a5d8f;
        --ok:#1b7f3b; --ok-bg:#e3f4e8; --bad:#b3261e; --bad-bg:#fbe5e3; --warn:#8a5a00; --warn-bg:#fff3d6; }
* { box-sizing: border-box; }
html { font-size: 16px; }
body { margin: 0; color: var(--fg); background: #fff; line-height: 1.5; overflow-wrap: break-word;
       font-family: system-ui, -apple-system, "Segoe UI", Roboto, "DejaVu Sans", Helvetica, Arial, sans-serif; }
main { max-width: 62rem; margin: 0 auto; padding: 2rem 1.5rem 3rem; }
header h1 { font-size: 1.7rem; margin: 0 0 .25rem; line-height: 1.25; }
.subtitle { color: var(--muted); margin: 0 0 1.25rem; }
h2 { font-size: 1.3rem; margin: 2.25rem 0 .75rem; padding-bottom: .3rem; border-bottom: 2px solid var(--line); }
h3 { font-size: 1rem; margin: 1.25rem 0 .5rem; }
p { margin: .5rem 0; }
a { color: var(--accent); text-decoration: none; }
a:hover { text-decoration: underline; }
table { border-collapse: collapse; margin: .5rem 0 1.25rem; font-size: .92rem; max-width: 100%; }
caption { text-align: left; font-weight: 600; padding: 0 0 .35rem; }
th, td { padding: .3rem .75rem; border-bottom: 1px solid var(--line); text-align: left; vertical-align: top;
         overflow-wrap: break-word; hyphens: manual; }
thead th { border-bottom: 2px solid var(--fg); font-weight: 600; vertical-align: bottom; }
tbody tr:nth-child(even) { background: var(--bg-alt); }
.num { text-align: right; font-variant-numeric: tabular-nums; white-space: nowrap; }
thead th.num { white-space: normal; }
th.long, td.long { overflow-wrap: anywhere; }
table.wide { font-size: .78rem; }
table.wide th, table.wide td { padding: .25rem .3rem; }
.table-wrap { max-width: 100%; overflow-x: auto; }
table.summary th { font-weight: 500; color: var(--muted); padding-left: 0; }
table.summary td, table.summary td.num { font-weight: 600; text-align: left; white-space: normal; }
td.cell-pass { color: var(--ok); background: var(--ok-bg); font-weight: 600; }
td.cell-fail { color: var(--bad); background: var(--bad-bg); font-weight: 600; }
.badge { display: inline-block; font-size: .72rem; font-weight: 600; letter-spacing: .03em; text-transform: uppercase;
         padding: .08rem .5rem; border-radius: 999px; border: 1px solid currentColor; vertical-align: middle;
         margin-left: .4rem; }
.badge-done { color: var(--ok); background: var(--ok-bg); }
.badge-cached { color: var(--accent); background: #e4eef8; }
.badge-skipped { color: var(--muted); background: var(--bg-alt); }
.badge-failed { color: var(--bad); background: var(--bad-bg); }
nav.toc { background: var(--bg-alt); border: 1px solid var(--line); border-radius: 6px; padding: .75rem 1.25rem; margin: 1rem 0; }
nav.toc h2 { font-size: 1rem; margin: 0 0 .35rem; border: 0; padding: 0; }
nav.toc ol { margin: 0; padding-left: 1.4rem; }
nav.toc li { margin: .15rem 0; }
figure { margin: 1rem 0 1.5rem; max-width: 100%; }
figure img { display: block; max-width: 100%; height: auto; border: 1px solid var(--line); }
figcaption { color: var(--muted); font-size: .9rem; margin-top: .35rem; }
figure.broken img { min-height: 2rem; min-width: 8rem; outline: 2px solid var(--bad); }
figure.broken figcaption::before { content: "figure failed to load: "; color: var(--bad); font-weight: 600; }
.missing, .warning { color: var(--warn); background: var(--warn-bg); border-left: 4px solid var(--warn);
                     padding: .5rem .75rem; font-size: .92rem; }
.missing { margin: 1rem 0; }
.verdict { border: 2px solid var(--accent); border-radius: 6px; padding: .75rem 1rem; margin: 1rem 0; }
.verdict h2 { margin: 0 0 .4rem; border: 0; padding: 0; font-size: 1.15rem; }
.verdict p { margin: .3rem 0; }
.verdict .recommendation { font-weight: 700; font-size: 1.05rem; }
.verdict .code { font: .8rem ui-monospace, monospace; color: var(--muted); margin-left: .5rem; }
.verdict ul.bullets { margin: .3rem 0; padding-left: 1.25rem; }
.verdict .key-figure figure { margin: .4rem 0 0; }
.verdict .key-figure img { max-height: 9cm; width: auto; max-width: 100%; }
.verdict-ok { border-color: var(--ok); background: var(--ok-bg); }
.verdict-warn { border-color: var(--warn); background: var(--warn-bg); }
.verdict-fail { border-color: var(--bad); background: var(--bad-bg); }
.verdict-basis { margin: -.5rem 0 1rem; padding: .5rem 1rem; border: 1px solid var(--line); border-top: 0;
                 border-radius: 0 0 6px 6px; font-size: .92rem; }
.verdict-basis h3 { font-size: .95rem; margin: .5rem 0 .2rem; }
.verdict-basis ul { margin: 0 0 .3rem; padding-left: 1.25rem; }
.definitions { margin: 1rem 0; border: 1px solid var(--line); border-radius: 6px; padding: .5rem 1rem; }
.definitions h2 { font-size: 1rem; margin: 0 0 .35rem; border: 0; padding: 0; }
.definitions table { margin: 0; font-size: .88rem; width: 100%; }
.definitions th { width: 28%; font-weight: 600; padding-left: 0; }
.definitions tbody tr:nth-child(even) { background: none; }
.warnings { margin: 1rem 0; }
.warnings p { margin: 0; }
.warnings ul { margin: .35rem 0 0; padding-left: 1.25rem; }
footer { margin-top: 3rem; padding-top: .75rem; border-top: 1px solid var(--line); color: var(--muted); font-size: .85rem; }
footer p { margin: .2rem 0; }
@media screen and (max-width: 52rem) { main { padding: 1.25rem .75rem 2rem; } }
@page { size: A4; margin: 16mm 14mm 18mm 14mm; }
@media print {
  html { font-size: 10pt; }
  main { max-width: none; margin: 0; padding: 0; }
  a { color: inherit; }
  .table-wrap { overflow: visible; }
  table { font-size: .9rem; }
  table.wide { font-size: .78rem; }
  th, td { padding: .2rem .45rem; }
  table.wide th, table.wide td { padding: .15rem .3rem; }
  thead { display: table-header-group; }
  tr, th, td { break-inside: avoid; }
  caption, h2, h3 { break-after: avoid; }
  figure, .verdict, nav.toc, p.warning, p.missing, .verdict-basis li { break-inside: avoid; }
  figure img { max-height: 230mm; width: auto; object-fit: contain; }
  tbody tr:nth-child(even) { background: none; }
  .badge, .verdict, td.cell-pass, td.cell-fail, .warning, .missing { -webkit-print-color-adjust: exact; print-color-adjust: exact; }
}
"""

SCRIPT = """
window.addEventListener("load", function () {
  var imgs = Array.prototype.slice.call(document.images), broken = [];
  imgs.forEach(function (img) {
    if (!(img.complete && img.naturalWidth > 0)) {
      broken.push(img.alt);
      if (img.parentNode && img.parentNode.classList) img.parentNode.classList.add("broken");
    }
  });
  document.body.dataset.figuresTotal = String(imgs.length);
  document.body.dataset.figuresLoaded = String(imgs.length - broken.length);
  document.body.dataset.figuresBroken = JSON.stringify(broken);
  var v = document.getElementById("verdict"), first = document.querySelector("section");
  if (v) {
    var box = v.getBoundingClientRect();
    document.body.dataset.verdictHeight = String(Math.round(box.height));
    document.body.dataset.verdictFirst = String(!first || box.top < first.getBoundingClientRect().top);
  }
  var root = document.documentElement, edge = root.clientWidth + 1, wide = [];
  Array.prototype.forEach.call(document.querySelectorAll("main *"), function (el) {
    var over = el.getBoundingClientRect().right > edge;
    if (el.tagName === "TABLE") over = over || el.scrollWidth > el.parentNode.clientWidth;
    else if (el.closest("table")) return;
    if (!over) return;
    var cap = el.tagName === "TABLE" ? el.querySelector("caption") : null;
    wide.push(cap ? "table: " + cap.textContent : el.tagName.toLowerCase() + (el.id ? "#" + el.id : "") +
              (el.className && typeof el.className === "string" ? "." + el.className.split(" ").join(".") : ""));
  });
  document.body.dataset.pageWidth = String(root.clientWidth);
  document.body.dataset.pageScrollWidth = String(root.scrollWidth);
  document.body.dataset.overflowing = JSON.stringify(wide.slice(0, 50));
});
"""


@dataclass(frozen=True)
class FigureCount:
    """Figures referenced by a report document, and those whose file is missing."""

    total: int
    missing: tuple[str, ...]


def _esc(text: Any) -> str:
    return html.escape(str(text), quote=True)


def _format_value(value: Any) -> str:
    """The text of a table or summary cell."""
    if value is None:
        return ""
    if isinstance(value, (bool, np.bool_)):
        return "yes" if value else "no"
    if isinstance(value, numbers.Integral):
        return str(int(value))
    if isinstance(value, numbers.Real):
        v = float(value)
        return str(v) if not math.isfinite(v) else f"{v:.6g}"
    return str(value)


def _is_numeric(value: Any, text: str) -> bool:
    if isinstance(value, (bool, np.bool_)):
        return False
    if isinstance(value, numbers.Real):
        return True
    return isinstance(value, str) and bool(_NUM_RE.match(text.strip()))


def _status_class(value: Any) -> str | None:
    if isinstance(value, (bool, np.bool_)):
        return "cell-pass" if value else "cell-fail"
    key = str(value).strip().lower()
    if key in _PASS:
        return "cell-pass"
    if key in _FAIL:
        return "cell-fail"
    return None


def _paragraphs(text: Any) -> list[str]:
    if text is None:
        return []
    if isinstance(text, str):
        return [text]
    return [str(t) for t in text]


def _resolve(path: str | os.PathLike, base_dir: Path) -> Path:
    p = Path(path)
    return p if p.is_absolute() else base_dir / p


def _figure_problem(path: Path) -> str | None:
    """Why a figure file cannot be embedded, or None."""
    if path.suffix.lower() not in MIME_TYPES:
        return f"unsupported figure type {path.suffix or '(none)'}"
    if not path.is_file():
        return "missing"
    return None


REFUSED_OUTSIDE = "path outside the stage folder"


def _contained(path: Path, root: str | os.PathLike) -> tuple[Path | None, str | None]:
    """(the resolved ``path``, None) when it is an existing file inside ``root`` (symlinks
    followed), else (None, why): "missing" or a refusal."""
    try:
        real_root = Path(root).resolve(strict=True)
        real = path.resolve(strict=True)
    except FileNotFoundError:
        return None, "missing"
    except (OSError, RuntimeError):
        return None, "unreadable figure path"
    if real == real_root or not real.is_relative_to(real_root):
        return None, REFUSED_OUTSIDE
    return real, None


def _figure_state(fig: Mapping[str, Any], base_dir: Path) -> tuple[Path, str | None, str | None]:
    """(path to read, problem, refusal) of one figure entry: ``refused`` (set by the
    caller) and ``root`` (the folder the file must resolve inside) are honoured."""
    path = _resolve(fig["path"], base_dir)
    if fig.get("refused"):
        return path, None, str(fig["refused"])
    if fig.get("root") is not None:
        if path.suffix.lower() not in MIME_TYPES:
            return path, _figure_problem(path), None
        real, why = _contained(path, fig["root"])
        if why == "missing":
            return path, "missing", None
        if why is not None:
            return path, None, why
        path = real
    return path, _figure_problem(path), None


def figure_count(doc: Mapping[str, Any], base_dir: str | os.PathLike | None = None) -> FigureCount:
    """How many figures ``doc`` references, and the names of those that cannot be embedded.

    ``base_dir`` resolves relative figure paths (default: the current directory; pass
    the report's directory to match :func:`render_report`).
    """
    base = Path(base_dir) if base_dir is not None else Path.cwd()
    total, missing = 0, []
    for section in doc.get("sections", ()):
        for fig in section.get("figures", ()) or ():
            total += 1
            path, problem, refused = _figure_state(fig, base)
            if problem is not None or refused is not None:
                missing.append(path.name)
    return FigureCount(total, tuple(missing))


def _validate(doc: Mapping[str, Any]) -> None:
    if not isinstance(doc, Mapping):
        raise TypeError(f"report document must be a mapping, not {type(doc).__name__}")
    if not doc.get("title"):
        raise ValueError("report document needs a 'title'")
    for w in doc.get("warnings", ()) or ():
        if not (isinstance(w, str) or (isinstance(w, (list, tuple)) and len(w) == 3)):
            raise ValueError(f"report warning {w!r} must be text or (section id, title, text)")
    defs = doc.get("definitions")
    if defs:
        terms = defs.get("terms") if isinstance(defs, Mapping) else None
        ok = isinstance(terms, Mapping) or (isinstance(terms, (list, tuple))
                                             and all(isinstance(t, (list, tuple)) and len(t) == 2 for t in terms))
        if not ok:
            raise ValueError("report definitions need 'terms': a mapping or (term, meaning) pairs")
    seen: set[str] = set()
    for i, section in enumerate(doc.get("sections", ())):
        sid = section.get("id")
        if not isinstance(sid, str) or not _ID_RE.fullmatch(sid):
            raise ValueError(f"section {i}: id {sid!r} must start with a letter and hold only letters, digits, '-', '_', '.'")
        if sid in seen:
            raise ValueError(f"section {i}: duplicate id {sid!r}")
        seen.add(sid)
        if not section.get("title"):
            raise ValueError(f"section {sid!r}: needs a 'title'")
        status = section.get("status")
        for w in section.get("warnings", ()) or ():
            if not isinstance(w, str):
                raise ValueError(f"section {sid!r}: a warning must be text, not {type(w).__name__}")
        if status is not None and status not in STATUSES:
            raise ValueError(f"section {sid!r}: status {status!r} is not one of {', '.join(STATUSES)}")
        for j, table in enumerate(section.get("tables", ()) or ()):
            columns = table.get("columns")
            rows = table.get("rows", ())
            width = len(columns) if columns else None
            for k, row in enumerate(rows):
                if width is not None and len(row) != width:
                    raise ValueError(
                        f"section {sid!r}, table {j}: row {k} has {len(row)} cells for {width} columns"
                    )
            sc = table.get("status_column")
            bad_index = not isinstance(sc, int) or isinstance(sc, bool) or sc < 0 or (width is not None and sc >= width)
            if sc is not None and bad_index:
                raise ValueError(f"section {sid!r}, table {j}: status_column {sc!r} is not a column index")
        for fig in section.get("figures", ()) or ():
            if "path" not in fig:
                raise ValueError(f"section {sid!r}: a figure has no 'path'")


def _warning_source(sid: Any, title: Any, ids: set) -> str:
    """'stage: ' for a top-level warning, a link to its section when there is one ('' for none)."""
    if not (title or sid):
        return ""
    label = _esc(title or sid)
    return (f'<a href="#{_esc(sid)}">{label}</a>' if sid in ids else label) + ": "


def _badge(status: str | None) -> str:
    return "" if status is None else f' <span class="badge badge-{status}">{_esc(status)}</span>'


def _has_long_token(text: str) -> bool:
    """The text holds a run without white space longer than :data:`LONG_TOKEN` characters (a path, a
    record spec, a formula): its cell may break inside that run, else it would widen the table.

    >>> _has_long_token("synthetic:duration=20,pga=0.4g,seed=1"), _has_long_token("overturns at 0.250 g")
    (True, False)
    """
    return any(len(word) > LONG_TOKEN for word in text.split())


def _class_attr(classes: list[str], text: str) -> str:
    """`` class="..."`` of a table cell (``long`` added for a long token), or ''."""
    classes = [*classes, "long"] if _has_long_token(text) else classes
    return f' class="{" ".join(classes)}"' if classes else ""


def _table(table: Mapping[str, Any]) -> str:
    columns = table.get("columns") or None
    rows = [list(r) for r in table.get("rows", ())]
    status_col = table.get("status_column")
    ncol = len(columns) if columns else max((len(r) for r in rows), default=0)
    texts = [[_format_value(v) for v in row] for row in rows]
    numeric = [[_is_numeric(v, t) for v, t in zip(row, trow)] for row, trow in zip(rows, texts)]
    # a header is right-aligned over a column whose non-empty cells are all numbers
    col_numeric = []
    for c in range(ncol):
        cells = [(n[c], t[c]) for n, t in zip(numeric, texts) if c < len(t) and t[c] != ""]
        col_numeric.append(bool(cells) and all(n for n, _ in cells) and c != status_col)

    wide = " wide" if ncol >= WIDE_COLUMNS else ""
    out = [f'<div class="table-wrap"><table class="data{wide}">']
    if table.get("title"):
        out.append(f"<caption>{_esc(table['title'])}</caption>")
    if columns:
        heads = "".join(
            f'<th scope="col"{_class_attr(["num"] if col_numeric[c] else [], str(h))}>{_esc(h)}</th>'
            for c, h in enumerate(columns)
        )
        out.append(f"<thead><tr>{heads}</tr></thead>")
    out.append("<tbody>")
    for row, trow, nrow in zip(rows, texts, numeric):
        cells = []
        for c, (value, text, is_num) in enumerate(zip(row, trow, nrow)):
            classes = []
            if c == status_col:
                sc = _status_class(value)
                if sc:
                    classes.append(sc)
            elif is_num:
                classes.append("num")
            cells.append(f"<td{_class_attr(classes, text)}>{_esc(text)}</td>")
        out.append("<tr>" + "".join(cells) + "</tr>")
    out.append("</tbody></table></div>")
    return "".join(out)


def _figure(fig: Mapping[str, Any], base_dir: Path) -> tuple[str, str | None, str | None]:
    """(html, name of the figure if it is missing, name of the figure if it was refused)."""
    path, problem, refused = _figure_state(fig, base_dir)
    caption = str(fig.get("caption") or "")
    if refused is not None:
        note = f'<p class="missing refused">figure refused: {_esc(refused)}: {_esc(path.name)}'
        if caption:
            note += f" ({_esc(caption)})"
        return note + "</p>", None, path.name
    if problem is not None:
        what = "figure missing" if problem == "missing" else f"figure missing ({problem})"
        note = f'<p class="missing">{_esc(what)}: {_esc(path.name)}'
        if caption:
            note += f" ({_esc(caption)})"
        return note + "</p>", path.name, None
    mime = MIME_TYPES[path.suffix.lower()]
    data = base64.b64encode(path.read_bytes()).decode("ascii")
    alt = caption or path.name
    parts = [f'<figure><img src="data:{mime};base64,{data}" alt="{_esc(alt)}" loading="eager">']
    if caption:
        parts.append(f"<figcaption>{_esc(caption)}</figcaption>")
    parts.append("</figure>")
    return "".join(parts), None, None


def _verdict_basis(verdict: Mapping[str, Any]) -> str:
    """The verdict's criteria, assumptions and limitations (its keys in :data:`VERDICT_SLOTS`, each a
    list of strings) as one block under its box; '' when it has none of them."""
    parts = []
    for key, title in VERDICT_SLOTS:
        items = [p for p in _paragraphs(verdict.get(key)) if p.strip()]
        if items:
            lis = "".join(f"<li>{_esc(p)}</li>" for p in items)
            parts.append(f'<h3>{title}</h3><ul class="verdict-{key}">{lis}</ul>')
    return f'<div class="verdict-basis" id="verdict-basis">{"".join(parts)}</div>' if parts else ""


def _definitions(defs: Mapping[str, Any] | None) -> str:
    """The document's ``definitions`` block ({"title": ..., "terms": {term: meaning}}) as a two-column
    table: the term in a row header, its meaning beside it; '' for none."""
    if not defs:
        return ""
    terms = defs.get("terms") or {}
    pairs = list(terms.items()) if isinstance(terms, Mapping) else [tuple(t) for t in terms]
    if not pairs:
        return ""
    rows = "".join(f'<tr><th scope="row">{_esc(k)}</th><td>{_esc(v)}</td></tr>' for k, v in pairs)
    title = _esc(defs.get("title") or "Definitions")
    return (f'<div class="definitions" id="definitions"><h2>{title}</h2>'
            f"<table><tbody>{rows}</tbody></table></div>")


def render_html(doc: Mapping[str, Any], base_dir: str | os.PathLike | None = None) -> str:
    """The report page as a string (see :func:`render_report`; ``base_dir`` defaults to the current directory)."""
    _validate(doc)
    base = Path(base_dir) if base_dir is not None else Path.cwd()
    sections = list(doc.get("sections", ()))

    body: list[str] = []
    missing: list[str] = []
    refused: list[str] = []
    for section in sections:
        sid = section["id"]
        part = [f'<section id="{_esc(sid)}">', f"<h2>{_esc(section['title'])}{_badge(section.get('status'))}</h2>"]
        part += [f'<p class="warning">warning: {_esc(w)}</p>' for w in _paragraphs(section.get("warnings"))]
        part += [f"<p>{_esc(p)}</p>" for p in _paragraphs(section.get("text"))]
        part += [_table(t) for t in section.get("tables", ()) or ()]
        for fig in section.get("figures", ()) or ():
            markup, miss, refuse = _figure(fig, base)
            part.append(markup)
            if miss is not None:
                missing.append(miss)
            if refuse is not None:
                refused.append(refuse)
        part.append("</section>")
        body.append("\n".join(part))

    head = [f"<h1>{_esc(doc['title'])}</h1>"]
    if doc.get("subtitle"):
        head.append(f'<p class="subtitle">{_esc(doc["subtitle"])}</p>')

    top: list[str] = []
    appendix = ""
    verdict = doc.get("verdict")
    if verdict:
        status = verdict.get("status", "warn")
        status = status if status in ("ok", "warn", "fail") else "warn"
        lines = "".join(f"<p>{_esc(p)}</p>" for p in _paragraphs(verdict.get("lines")))
        rec = f'<p class="reasoning">Reasoning: {_esc(verdict.get("recommendation", ""))}</p>'
        if verdict.get("headline"):
            # page 1: the headline and its numbers; the reasoning and every line in the appendix
            code = f' <span class="code">{_esc(verdict["code"])}</span>' if verdict.get("code") else ""
            items = "".join(f"<li>{_esc(b)}</li>" for b in _paragraphs(verdict.get("bullets")))
            fig = ""
            if isinstance(verdict.get("figure"), Mapping) and verdict["figure"].get("path"):
                fig, miss, refuse = _figure(verdict["figure"], base)
                fig = f'<div class="key-figure">{fig}</div>'
                missing += [miss] if miss is not None and miss not in missing else []
                refused += [refuse] if refuse is not None and refuse not in refused else []
            top.append(f'<div class="verdict verdict-{status}" id="verdict"><h2>Assessment{code}</h2>'
                       f'<p class="recommendation headline">{_esc(verdict["headline"])}</p>'
                       + (f'<ul class="bullets">{items}</ul>' if items else "") + fig + "</div>")
            appendix = (f'<section id="verdict-reasoning" class="appendix"><h2>Appendix: the reasoning</h2>'
                        f"{rec}{lines}{_verdict_basis(verdict)}</section>")
        else:
            top.append(f'<div class="verdict verdict-{status}" id="verdict"><h2>Assessment</h2>'
                       f'<p class="recommendation">Recommendation: {_esc(verdict.get("recommendation", ""))}</p>'
                       f"{lines}</div>")
            top.append(_verdict_basis(verdict))
    top.append(_definitions(doc.get("definitions")))
    warnings = [(None, None, w) if isinstance(w, str) else tuple(w) for w in doc.get("warnings", ()) or ()]
    if warnings:
        ids = {s["id"] for s in sections}
        items = "".join(
            f"<li>{_warning_source(sid, title, ids)}{_esc(text)}</li>" for sid, title, text in warnings
        )
        n = len(warnings)
        top.append(
            f'<div class="warning warnings" id="all-warnings"><p><strong>{n} warning{"s" if n != 1 else ""}: '
            f"check these before trusting the numbers</strong></p><ul>{items}</ul></div>"
        )
    summary = list(doc.get("summary", ()) or ())
    if summary:
        rows = "".join(
            f'<tr><th scope="row">{_esc(k)}</th>'
            f'<td{_class_attr(["num"] if _is_numeric(v, _format_value(v)) else [], _format_value(v))}>'
            f"{_esc(_format_value(v))}</td></tr>" for k, v in summary
        )
        top.append(f'<table class="summary"><tbody>{rows}</tbody></table>')
    if missing:
        n = len(missing)
        top.append(
            f'<p class="warning">{n} figure{"s" if n != 1 else ""} missing: {_esc(", ".join(missing))}</p>'
        )
    if refused:
        n = len(refused)
        top.append(
            f'<p class="warning">{n} figure{"s" if n != 1 else ""} refused (not a file the stage wrote inside '
            f'its folder): {_esc(", ".join(refused))}</p>'
        )
    if sections:
        items = "".join(
            f'<li><a href="#{_esc(s["id"])}">{_esc(s["title"])}</a>{_badge(s.get("status"))}</li>' for s in sections
        )
        top.append(f'<nav class="toc"><h2>Contents</h2><ol>{items}</ol></nav>')

    footer = "".join(f"<p>{_esc(p)}</p>" for p in _paragraphs(doc.get("footer")))
    return "\n".join(
        [
            "<!DOCTYPE html>",
            '<html lang="en">',
            "<head>",
            '<meta charset="utf-8">',
            f'<meta http-equiv="Content-Security-Policy" content="{CSP}">',
            '<meta name="viewport" content="width=device-width, initial-scale=1">',
            '<meta name="generator" content="statue2model">',
            f"<title>{_esc(doc['title'])}</title>",
            f"<style>{CSS}</style>",
            f"<script>{SCRIPT}</script>",
            "</head>",
            f'<body data-figures-missing="{len(missing) + len(refused)}" data-figures-refused="{len(refused)}">',
            "<main>",
            "<header>" + "".join(head) + "</header>",
            *[t for t in top if t],
            *body,
            appendix,
            f"<footer>{footer}</footer>" if footer else "",
            "</main>",
            "</body>",
            "</html>",
            "",
        ]
    )


def render_report(
    doc: Mapping[str, Any], out_path: str | os.PathLike, base_dir: str | os.PathLike | None = None
) -> Path:
    """Write the report described by ``doc`` to ``out_path`` (atomically) and return the path.

    Relative figure paths are resolved against ``base_dir`` (default: the directory
    of ``out_path``). Raises ``ValueError`` for a malformed ``doc`` (missing title,
    bad or duplicate section id, unknown status, row/column count mismatch); a
    missing figure file is only noted in the page.
    """
    out = Path(out_path)
    base = Path(base_dir) if base_dir is not None else (out.parent if str(out.parent) else Path("."))
    text = render_html(doc, base)
    return atomic_write(out, lambda p: p.write_text(text, encoding="utf-8"))


__all__ = ["STATUSES", "FigureCount", "figure_count", "render_html", "render_report"]
