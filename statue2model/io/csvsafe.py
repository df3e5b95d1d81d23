"""CSV files that a spreadsheet opens as plain data: quoted by the csv module, and
cells that a spreadsheet would run as a formula neutralised.

A cell that starts with ``=``, ``+``, ``-``, ``@``, a tab, a carriage return or a
line feed (also after leading spaces) is prefixed with a single quote ``'``, as
OWASP advises against CSV injection; numbers (``-1.5``, ``2e-3``) stay numbers, and
a non-finite number (a float nan or inf) is an empty cell: no file holds one. Commas,
quotes and newlines inside a cell are quoted by :mod:`csv`, so
every row has the header's number of cells.

Example
-------
>>> import csv, io, tempfile, pathlib
>>> safe_cell("=1+2"), safe_cell("@SUM(1+1)"), safe_cell(-1.5), safe_cell("-0.25"), safe_cell(None)
("'=1+2", "'@SUM(1+1)", -1.5, '-0.25', '')
>>> safe_cell(float("nan")), safe_cell(float("-inf"))
('', '')
>>> num_cell(0.1 + 0.2, ".6g"), num_cell(float("nan")), num_cell(float("inf"))
('0.3', '', '')
>>> path = write_csv(pathlib.Path(tempfile.mkdtemp()) / "t.csv", ["scan", "h [m]"], [["a,b", 1.25]])
>>> list(csv.reader(io.StringIO(path.read_text())))
[['scan', 'h [m]'], ['a,b', '1.25']]
"""
from __future__ import annotations

import csv
import io
import math
import numbers
import os
import re
from collections.abc import Iterable, Sequence
from pathlib import Path
from typing import Any

from .files import atomic_write

TRIGGERS = ("=", "+", "-", "@", "\t", "\r", "\n")
_NUMBER = re.compile(r"^[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?$|^[-+]?(?:nan|inf|infinity)$", re.IGNORECASE)


def safe_cell(value: Any) -> Any:
    """``value`` as a CSV cell that no spreadsheet evaluates: None -> "", numbers
    unchanged, text that could start a formula prefixed with ``'``."""
    if value is None:
        return ""
    if isinstance(value, numbers.Real) and not isinstance(value, numbers.Integral) and not math.isfinite(value):
        return ""
    if isinstance(value, (bool, numbers.Number)):
        return value
    text = str(value)
    if _NUMBER.match(text):
        return text
    if text.lstrip(" ").startswith(TRIGGERS):
        return "'" + text
    return text


def num_cell(value: Any, spec: str = ".10g") -> str:
    """A number formatted with ``spec`` for a CSV cell, or "" (an empty cell) when it is None or not
    finite: the writers of time histories format their numbers with it, so none writes nan or inf."""
    if value is None:
        return ""
    x = float(value)
    return format(x, spec) if math.isfinite(x) else ""


def csv_text(header: Sequence[Any], rows: Iterable[Sequence[Any]]) -> str:
    """The CSV text (header line, then one line per row, ``\\n`` line ends) with every cell
    passed through :func:`safe_cell`; a row of another length than the header is an error."""
    header = list(header)
    buf = io.StringIO()
    writer = csv.writer(buf, lineterminator="\n")
    writer.writerow([safe_cell(h) for h in header])
    for i, row in enumerate(rows):
        row = list(row)
        if len(row) != len(header):
            raise ValueError(f"CSV row {i} has {len(row)} cells for {len(header)} columns")
        writer.writerow([safe_cell(v) for v in row])
    return buf.getvalue()


def number_columns_text(header: Sequence[Any], columns: Sequence[Any], specs: Sequence[str]) -> str:
    """``csv_text(header, rows)`` of rows of :func:`num_cell` cells (column k formatted with ``specs[k]``),
    built directly: a formatted number (digits, sign, point, exponent) or an empty cell needs neither a
    spreadsheet guard nor CSV quoting, so the text is the cells joined by commas, line by line."""
    cols = [[format(x, spec) if math.isfinite(x) else "" for x in map(float, col)] for col, spec in zip(columns, specs)]
    n = {len(c) for c in cols}
    if len(cols) != len(list(header)) or len(n) > 1:
        raise ValueError(f"{len(cols)} columns of {sorted(n)} cells for {len(list(header))} headers")
    return csv_text(header, ()) + "".join(",".join(row) + "\n" for row in zip(*cols))


def write_csv(path: str | os.PathLike, header: Sequence[Any], rows: Iterable[Sequence[Any]]) -> Path:
    """Write :func:`csv_text` to ``path`` atomically (UTF-8) and return the path."""
    text = csv_text(header, rows)
    return atomic_write(path, lambda p: p.write_text(text, encoding="utf-8", newline=""))


__all__ = ["TRIGGERS", "csv_text", "num_cell", "number_columns_text", "safe_cell", "write_csv"]
