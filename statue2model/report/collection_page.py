"""The collection page: a museum's objects in one self-contained HTML file, ranked by risk.

:func:`write_collection_page` writes ONE file (inline CSS and script, the report's
Content-Security-Policy: nothing is loaded from anywhere), with, from the top: the summary
(objects, assessed, needing protection, devices, sheets, plates), the ranking rule
(:data:`statue2model.assessment.collection.RANKING_RULE`), a filter (a text box matching
anywhere in a row, one checkbox per status) and the table, one row per object
(:func:`statue2model.assessment.collection.object_row`) in rank order. A click on a column's
header sorts by it (again: the other way); the object's name links to its report
(relative: the page works wherever the collection folder is copied). Status cells are
coloured as the per-object report's verdict box (ok green, warn amber, fail red); a row not
assessed shows why in place of its recommendation.

Every text from the inputs (scan names above all) is HTML-escaped, attributes quoted, and links
are relative paths percent-encoded: a scan named ``<script>`` shows as text.

Browser check contract: the load handler (and every sort or filter after it) writes on ``<body>``

* ``data-rows``: the number of rows, ``data-visible``: those shown by the filter,
* ``data-sorted-by`` (a column key, "rank" at load) and ``data-sort-dir`` (asc or desc),
* ``data-order``: a JSON list of the visible rows' object names, in their order on screen,
* ``data-filter``: the filter text, ``data-statuses``: a JSON list of the statuses ticked.

Column keys (``data-key`` of each header button): see :data:`COLUMNS`.

Example
-------
>>> import tempfile, pathlib
>>> from statue2model.assessment.collection import object_row, rank, summary
>>> rows = rank([object_row({"scan": "<script>alert(1)</script>.ply", "error": "scan not found"})])
>>> page = write_collection_page(rows, summary(rows), pathlib.Path(tempfile.mkdtemp()) / "index.html",
...                              title="Collection")
>>> text = page.read_text(encoding="utf-8")
>>> "<script>alert" in text, "&lt;script&gt;alert(1)&lt;/script&gt;" in text
(False, True)
"""
from __future__ import annotations

import html
import os
from pathlib import Path
from urllib.parse import quote

from ..assessment.collection import NOT_ASSESSED, RANKING_RULE, TIER_TEXT, TIERS, VALUE_RULE
from ..assessment.verdict import finite_number as _num
from ..io.files import atomic_write
from ..version import __version__
from .html import CSP, CSS

STATUS_ORDER = ("fail", "warn", "ok", NOT_ASSESSED)
"""The statuses in the filter, and their sort order (a sort by status puts the worst first)."""

COLUMNS = (
    ("rank", "Rank", "num"), ("object", "Object", "text"), ("where", "Where (room, floor, design PGA)", "text"),
    ("status", "Status (with the recommended action)", "num"),
    ("state", "Risk today: on its own base at the design level", "num"),
    ("uplift_g", "Uplift [g]", "num"),
    ("code", "Recommended action", "text"),
    ("device", "Device and cost", "text"),
    ("after", "Risk after: on the device", "num"),
    ("doubts", "Doubts", "text"),
)
"""(key, header, sort type) of the table's columns, in order: who, the risk today (fixed base: the state,
the governing limit state, P at the design PGA), the action (code and headline, the device), the risk
after it (on the device: the governing limit state and P(failure)), the doubts. Ten columns: the table
prints on A4 landscape with every object's recommendation."""
NUMBER_COLUMNS = {"rank", "uplift_g"}
NUM_ATTR = ' class="num"'

PAGE_CSS = """
main { max-width: none; }
.tiles { display: flex; flex-wrap: wrap; gap: .5rem; margin: 1rem 0; }
.tile { border: 1px solid var(--line); border-radius: 6px; padding: .35rem .7rem; background: var(--bg-alt);
        max-width: 15rem; font-size: .85rem; line-height: 1.25; }
.tile .n { display: block; font-size: 1.35rem; font-weight: 700; }
.tile .what { color: var(--muted); }
.rule { border: 1px solid var(--line); border-radius: 6px; padding: .5rem 1rem; margin: 1rem 0; font-size: .92rem; }
.rule h2 { font-size: 1rem; margin: 0 0 .3rem; border: 0; padding: 0; }
.controls { display: flex; flex-wrap: wrap; gap: .5rem 1.25rem; align-items: center; margin: 1rem 0 .5rem; }
.controls input[type=search] { font: inherit; padding: .25rem .5rem; min-width: 18rem; border: 1px solid var(--line);
                               border-radius: 4px; }
.controls label { white-space: nowrap; }
#collection { font-size: .8rem; width: 100%; }
#collection th, #collection td { padding: .3rem .4rem; }
#collection th button { font: inherit; font-weight: 600; background: none; border: 0; padding: 0; cursor: pointer;
                        text-align: left; color: inherit; }
#collection th[aria-sort=ascending] button::after { content: " \\25B2"; }
#collection th[aria-sort=descending] button::after { content: " \\25BC"; }
#collection td.rec { min-width: 14rem; }
#collection td.rec .code { font: .72rem ui-monospace, monospace; color: var(--muted); display: block; }
#collection td.num { white-space: normal; }
#collection td.dev { min-width: 9rem; }
#collection td.obj { font-weight: 600; }
td.st-ok { color: var(--ok); background: var(--ok-bg); font-weight: 600; }
td.st-warn { color: var(--warn); background: var(--warn-bg); font-weight: 600; }
td.st-fail { color: var(--bad); background: var(--bad-bg); font-weight: 600; }
td.st-na { color: var(--bad); font-weight: 600; }
td.reason { color: var(--bad); }
.muted { color: var(--muted); }
@media print { @page { size: A4 landscape; } .controls { display: none; }
               #collection th button::after { content: none !important; } #collection { font-size: .68rem; }
               #collection td.rec, #collection td.dev { min-width: 0; } }
"""

SCRIPT = """
(function () {
  var body, table, input;
  function rows() { return Array.prototype.slice.call(table.tBodies[0].rows); }
  function record() {
    var shown = rows().filter(function (r) { return !r.hidden; });
    body.dataset.rows = String(rows().length);
    body.dataset.visible = String(shown.length);
    body.dataset.order = JSON.stringify(shown.map(function (r) { return r.dataset.object; }));
  }
  function value(row, i, type) {
    var v = row.cells[i].getAttribute("data-v");
    if (v === null || v === "") return null;
    return type === "num" ? parseFloat(v) : v.toLowerCase();
  }
  function sortBy(key, dir) {
    var ths = Array.prototype.slice.call(table.tHead.rows[0].cells), i = -1, type = "text";
    ths.forEach(function (th, j) {
      if (th.dataset.key === key) {
        i = j; type = th.dataset.type; th.setAttribute("aria-sort", dir === "asc" ? "ascending" : "descending");
      }
      else th.removeAttribute("aria-sort");
    });
    if (i < 0) return;
    var sign = dir === "asc" ? 1 : -1, tb = table.tBodies[0];
    rows().map(function (r, k) { return [r, value(r, i, type), parseInt(r.dataset.rank, 10) || k]; })
      .sort(function (a, b) {
        if (a[1] === null && b[1] === null) return a[2] - b[2];
        if (a[1] === null) return 1;                  /* unknown last, either way */
        if (b[1] === null) return -1;
        if (a[1] < b[1]) return -sign;
        if (a[1] > b[1]) return sign;
        return a[2] - b[2];
      })
      .forEach(function (t) { tb.appendChild(t[0]); });
    body.dataset.sortedBy = key;
    body.dataset.sortDir = dir;
    record();
  }
  function filter() {
    var q = input.value.trim().toLowerCase(), on = {};
    var boxes = Array.prototype.slice.call(document.querySelectorAll("input.status-filter"));
    boxes.forEach(function (b) { on[b.value] = b.checked; });
    rows().forEach(function (r) {
      r.hidden = !(on[r.dataset.status] && (!q || r.textContent.toLowerCase().indexOf(q) >= 0));
    });
    body.dataset.filter = q;
    body.dataset.statuses = JSON.stringify(boxes.filter(function (b) { return b.checked; })
                                                .map(function (b) { return b.value; }));
    record();
  }
  window.addEventListener("load", function () {
    body = document.body; table = document.getElementById("collection"); input = document.getElementById("filter");
    Array.prototype.forEach.call(table.tHead.rows[0].cells, function (th) {
      var b = th.querySelector("button");
      if (!b) return;
      b.addEventListener("click", function () {
        var dir = body.dataset.sortedBy === th.dataset.key && body.dataset.sortDir === "asc" ? "desc" : "asc";
        sortBy(th.dataset.key, dir);
      });
    });
    input.addEventListener("input", filter);
    Array.prototype.forEach.call(document.querySelectorAll("input.status-filter"), function (b) {
      b.addEventListener("change", filter);
    });
    filter();
    sortBy("rank", "asc");
  });
})();
"""


def _esc(text) -> str:
    return html.escape(str(text), quote=True)


def _p(p, lo, hi) -> str:
    p, lo, hi = _num(p), _num(lo), _num(hi)
    if p is None:
        return "-"

    def f(x):
        return "< 0.01" if x < 0.005 else "> 0.99" if x > 0.995 else f"{x:.2f}"
    if lo is None or hi is None or f(lo) == f(hi):
        return f(p)
    return f"{f(p)} ({f(lo)} to {f(hi)})"


def _td(text: str, sort=None, cls: str = "", raw: bool = False, title: str = "") -> str:
    v = "" if sort is None else (f"{sort:.12g}" if isinstance(sort, float) else str(sort))
    c = f' class="{cls}"' if cls else ""
    t = f' title="{_esc(title)}"' if title else ""
    return f'<td{c}{t} data-v="{_esc(v)}">{text if raw else _esc(text)}</td>'


def _risk(head: str, r: dict, base: str, probs) -> str:
    """One risk cell (HTML): ``head``, the governing limit state of ``base`` with its demand/capacity,
    the probabilities ``probs`` ((row key, label), ...) at the design PGA."""
    parts = [f"<strong>{_esc(head)}</strong>"] if head else []
    g, ratio = r.get(f"governing_{base}"), _num(r.get(f"governing_{base}_ratio"))
    if g is not None:
        text = f"{g}: {ratio:.2f}" if ratio is not None else str(g)
        if r.get(f"governing_{base}_text"):
            text += f" ({r[f'governing_{base}_text']})"
        parts.append(_esc(text))
    for key, label in probs:
        p = _p(r.get(f"p_{key}"), r.get(f"p_{key}_lo"), r.get(f"p_{key}_hi"))
        if p != "-":
            parts.append(_esc(f"{label} {p}"))
    return "<br>".join(parts) or "-"


def _row_html(r: dict) -> str:
    status = r.get("status") if r.get("status") in STATUS_ORDER else NOT_ASSESSED
    assessed = bool(r.get("assessed"))
    name = str(r.get("object", ""))
    link = r.get("link")
    obj = (f'<a href="{_esc(quote(str(link), safe="/"))}">{_esc(name)}</a>' if link else _esc(name))
    st_cls = {"ok": "st-ok", "warn": "st-warn", "fail": "st-fail"}.get(status, "st-na")
    state = r.get("state") if r.get("state") in TIERS else NOT_ASSESSED
    where = str(r.get("where") or "-")
    if _num(r.get("value")) is not None:
        where += f"; value {_num(r.get('value')):g}" + (f", risk x value {_num(r.get('risk_x_value')):.3g}"
                                                        if _num(r.get("risk_x_value")) is not None else "")
    cells = [_td(str(r.get("rank", "")), r.get("rank"), "num"), _td(obj, name, "obj", raw=True),
             _td(where, where), _td(status, STATUS_ORDER.index(status), st_cls)]
    if not assessed:
        cells.append(_td("not assessed: " + str(r.get("reason") or "unknown"), 0, "reason"))
        cells += [_td("-") for _ in range(len(COLUMNS) - 6)]
        cells.append(_td("fix the scan first", None, "rec"))
    else:
        state_text = state + ("" if r.get("basis") != "quasi-static" else " (quasi-static)")
        cells.append(_td(_risk(state_text, r, "fixed", (("overturning_fixed", "P(overturn)"),
                                                        ("full_contact_fixed", "P(uplift)"))),
                         TIERS.index(state), raw=True, title=TIER_TEXT.get(state, state)))
        u = _num(r.get("uplift_g"))
        cells.append(_td("-" if u is None else f"{u:.3f}", u, "num"))
        code, head = str(r.get("code") or ""), str(r.get("headline") or r.get("recommendation") or "-")
        cells.append(_td((f'<span class="code">{_esc(code)}</span> ' if code else "") + _esc(head), code, "rec",
                         raw=True, title=str(r.get("recommendation") or "")))
        s_ = r.get("sheets")
        dev = str(r.get("device") or "-") + ("" if s_ is None else f"; prototype {s_} sheet{'s' if s_ != 1 else ''}")
        cells.append(_td(dev, r.get("device_state") or "", "dev", title=r.get("device_note") or ""))
        if r.get("governing_isolated") is None and _num(r.get("p_overturning_isolated")) is None:
            cells.append(_td("-"))
        else:
            cells.append(_td(_risk("", r, "isolated", (("overturning_isolated", "P(failure)"),)),
                             _num(r.get("governing_isolated_ratio")), raw=True))
        doubts = "; ".join(str(d) for d in r.get("doubts") or ()) or "-"
        cells.append(_td(doubts, "" if doubts == "-" else doubts))
    return (f'<tr data-status="{_esc(status)}" data-object="{_esc(name)}" data-rank="{_esc(r.get("rank", ""))}">'
            + "".join(cells) + "</tr>")


SUMMARY_LABELS = (("objects", "objects"), ("assessed", "assessed"), ("not_assessed", "not assessed: fix the scan"),
                  ("needing_protection", "need protection (by their recommendation code)"),
                  ("to_consider", "no isolator needed by the mean, but single records lift them"),
                  ("devices_passed", "isolators that pass every check"),
                  ("devices_conditional", "isolators conditional on the ball load"),
                  ("no_device", "need protection, no device in range"),
                  ("prototype_sheets", "prototype sheets to cut"),
                  ("isolator_plates", "isolator plates to cut (2 per passing device)"),
                  ("devices_cost", "EUR: the passing devices' prices"))


def render_collection_page(rows: list[dict], summary: dict, *, title: str, config_text: str | None = None) -> str:
    """The page as a string (see :func:`write_collection_page`)."""
    def count(key):
        v = summary.get(key, 0)
        return f"{v:.0f}" if isinstance(v, float) else v

    summ = "".join(f'<div class="tile" id="sum-{key}"><span class="n">{_esc(count(key))}</span> '
                   f'<span class="what">{_esc(label)}</span></div>' for key, label in SUMMARY_LABELS if key in summary)
    boxes = "".join(f'<label><input type="checkbox" class="status-filter" id="status-{_esc(s.replace(" ", "-"))}" '
                    f'value="{_esc(s)}" checked> {_esc(s)}</label>' for s in STATUS_ORDER)
    head = "".join(f'<th scope="col" data-key="{k}" data-type="{t}"{NUM_ATTR if k in NUMBER_COLUMNS else ""}>'
                   f'<button type="button">{_esc(label)}</button></th>' for k, label, t in COLUMNS)
    body_rows = "\n".join(_row_html(r) for r in rows)
    n = len(rows)
    config = (f"<details><summary>Configuration of the run</summary><pre>{_esc(config_text)}</pre></details>"
              if config_text else "")
    return "\n".join([
        "<!DOCTYPE html>", '<html lang="en">', "<head>", '<meta charset="utf-8">',
        f'<meta http-equiv="Content-Security-Policy" content="{CSP}">',
        '<meta name="viewport" content="width=device-width, initial-scale=1">',
        '<meta name="generator" content="statue2model">', f"<title>{_esc(title)}</title>",
        f"<style>{CSS}{PAGE_CSS}</style>", f"<script>{SCRIPT}</script>", "</head>",
        f'<body data-rows="{n}">', "<main>",
        f"<header><h1>{_esc(title)}</h1><p class=\"subtitle\">{n} object{'s' if n != 1 else ''}, most urgent first; "
        f"each name opens the object's report. statue2model {_esc(__version__)}.</p></header>",
        f'<div class="tiles" id="summary">{summ}</div>',
        f'<div class="rule" id="ranking-rule"><h2>How the objects are ranked</h2><p>{_esc(RANKING_RULE)}</p>'
        + (f"<p>{_esc(VALUE_RULE)}</p>" if any(_num(r.get("value")) is not None for r in rows) else "") +
        "<p>P: the fragility study's probability at the design PGA; in brackets, its band from the confidence "
        "interval of the fitted median. Demand/capacity: the largest over the limit states at the design level "
        "(mean over the design records); &gt; 1 means the limit state is exceeded.</p></div>",
        f'<div class="controls"><label for="filter">Filter</label>'
        f'<input type="search" id="filter" placeholder="name, recommendation, doubt ..." autocomplete="off">'
        f"{boxes}</div>",
        f'<div class="table-wrap"><table id="collection"><thead><tr>{head}</tr></thead>',
        f"<tbody>\n{body_rows}\n</tbody></table></div>",
        config, "</main>", "</body>", "</html>", ""])


def write_collection_page(rows: list[dict], summary: dict, path: str | os.PathLike, *, title: str,
                          config_text: str | None = None) -> Path:
    """Write the collection page of the ranked ``rows`` (:func:`statue2model.assessment.collection.rank`)
    and their ``summary`` to ``path`` (atomically; module docstring), ``config_text`` (the run's
    config.toml) in a closed box at the end. Links are the rows' ``link``: relative to the folder the
    page is written in."""
    text = render_collection_page(rows, summary, title=title, config_text=config_text)
    return atomic_write(Path(path), lambda p: p.write_text(text, encoding="utf-8"))


__all__ = ["COLUMNS", "STATUS_ORDER", "render_collection_page", "write_collection_page"]
