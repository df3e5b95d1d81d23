"""A shake-table campaign, and how often a model's predictions were right (``statue2model validate``).

A campaign is a TOML file; every path in it is relative to its folder and must stay inside it (a path that
is absolute or leaves the folder is refused: a campaign file is input, not a set of instructions):

    name = "my rock"                    # optional
    tests = "tests.csv"                 # columns: name, file, toppled (0/1); optional lifted (0/1), peak_rotation (rad)
    [specimen]
    scan = "rock.stl"                   # the scanned object
    mass = 12.3                         # kg, optional (else density x volume)
    density = 2650                      # kg/m^3, optional
    units = "mm"                        # the scan's units (auto, m, mm, cm, in)
    up = "z"                            # the scan's up axis (auto, x, y, z, -x, -y, -z)
    direction = 0                       # degrees: the table's axis in the scan's frame
    [motion]
    columns = [1, 2]                    # time and acceleration columns (1-based); or dt = 0.005 with column = 1
    units = "g"                         # "g" or "m/s^2"
    sign = 1                            # +1 / -1: the table's positive direction against the scan's +x
    band = [0.1, 25.0]                  # Hz, zero-phase band-pass (optional)
    skip = 1                            # header lines (optional: the leading lines that are not numbers)

Scores (:func:`scores`), per model and outcome (toppled; lifted where the campaign records it): the confusion
counts, accuracy, precision and recall, each with its 95 % Wilson interval (:func:`wilson`; a rate whose
denominator is 0 is None with the reason), and the Brier score of P(outcome), mean (P - observed)^2.

>>> wilson(8, 10)
(0.4902, 0.9433)
>>> s = scores([True, True, False, False], [True, False, False, True], [0.9, 0.4, 0.1, 0.6])
>>> s["tp"], s["fn"], s["fp"], s["tn"], s["accuracy"]["value"], s["recall"]["value"], round(s["brier"], 4)
(1, 1, 1, 1, 0.5, 0.5, 0.185)
"""
from __future__ import annotations

import csv
import io
import math
from dataclasses import dataclass
from pathlib import Path

from ..errors import InputError
from ..io.tomlfile import parse_toml
from ..hazard.lab import LabFormat

MAX_TESTS = 100_000
"""Tests a campaign may list."""
Z95 = 1.959963984540054
"""The normal quantile of a two-sided 95 % interval."""


@dataclass(frozen=True)
class Specimen:
    """The tested object: its scan (a path inside the campaign folder), mass (kg) or density (kg/m^3) when
    given, the scan's units and up axis, and the table's axis in the scan's frame (deg)."""

    scan: Path
    mass: float | None = None
    density: float | None = None
    units: str = "auto"
    up: str = "auto"
    direction: float = 0.0


@dataclass(frozen=True)
class Test:
    """One test: its name, motion file, whether the specimen toppled (and lifted, and its peak rotation in rad,
    where recorded)."""

    name: str
    file: Path
    toppled: bool
    lifted: bool | None = None
    peak_rotation: float | None = None


@dataclass(frozen=True)
class Campaign:
    """A campaign file read (module docstring)."""

    path: Path
    name: str
    specimen: Specimen
    motion: LabFormat
    tests: tuple

    @property
    def folder(self) -> Path:
        return self.path.parent


def _inside(folder: Path, text, what: str) -> Path:
    """The path ``text`` relative to ``folder``, refused when absolute, empty or leaving the folder."""
    if not isinstance(text, str) or not text.strip():
        raise InputError(f"{what} must be a file name relative to the campaign's folder, got {text!r}")
    p = Path(text)
    if p.is_absolute():
        raise InputError(f"{what} {text!r} is an absolute path: a campaign names its files relative to its folder")
    full = (folder / p).resolve()
    try:
        full.relative_to(folder.resolve())
    except ValueError:
        raise InputError(f"{what} {text!r} leaves the campaign's folder") from None
    return full


def _bool01(value: str, what: str) -> bool:
    v = str(value).strip().lower()
    if v in ("1", "true", "yes", "y"):
        return True
    if v in ("0", "false", "no", "n"):
        return False
    raise InputError(f"{what} must be 0 or 1, got {value!r}")


def load_campaign(path) -> Campaign:
    """The campaign file at ``path`` (module docstring), its tests read and checked; one-line InputErrors."""
    path = Path(path)
    if not path.is_file():
        raise InputError(f"campaign file not found: {path}")
    try:
        text = path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        raise InputError(f"cannot read campaign file {path}: {exc}") from None
    data = parse_toml(text, f"campaign file {path}")
    folder = path.resolve().parent
    where = f"campaign {path.name}"
    unknown = set(data) - {"name", "tests", "specimen", "motion"}
    if unknown:
        raise InputError(f"{where}: unknown key(s) {', '.join(sorted(unknown))} (name, tests, [specimen], [motion])")
    sp = data.get("specimen")
    if not isinstance(sp, dict):
        raise InputError(f"{where}: a [specimen] table with its scan is needed")
    bad = set(sp) - {"scan", "mass", "density", "units", "up", "direction"}
    if bad:
        raise InputError(f"{where}: unknown key(s) in [specimen]: {', '.join(sorted(bad))}")

    def num(table, key, what, positive=True):
        v = table.get(key)
        if v is None:
            return None
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v) or (positive and v <= 0):
            raise InputError(f"{where}: {what} must be a {'positive ' if positive else ''}number, got {v!r}")
        return float(v)

    specimen = Specimen(scan=_inside(folder, sp.get("scan"), f"{where}: [specimen] scan"),
                        mass=num(sp, "mass", "[specimen] mass"), density=num(sp, "density", "[specimen] density"),
                        units=str(sp.get("units", "auto")), up=str(sp.get("up", "auto")),
                        direction=num(sp, "direction", "[specimen] direction", positive=False) or 0.0)
    if not specimen.scan.is_file():
        raise InputError(f"{where}: the scan {sp.get('scan')!r} is not a file in the campaign's folder")
    mo = data.get("motion") or {}
    if not isinstance(mo, dict):
        raise InputError(f"{where}: [motion] must be a table")
    bad = set(mo) - {"columns", "dt", "column", "units", "sign", "band", "skip"}
    if bad:
        raise InputError(f"{where}: unknown key(s) in [motion]: {', '.join(sorted(bad))}")
    try:
        fmt = LabFormat(columns=None if "dt" in mo else tuple(mo.get("columns", (1, 2))), dt=mo.get("dt"),
                        column=mo.get("column", 1), units=str(mo.get("units", "g")), sign=mo.get("sign", 1),
                        band=tuple(mo["band"]) if mo.get("band") is not None else None, skip=mo.get("skip"))
    except (TypeError, ValueError) as exc:
        raise InputError(f"{where}: [motion]: {exc}") from None
    except InputError as exc:
        raise InputError(f"{where}: {exc}") from None
    tests_path = _inside(folder, data.get("tests", "tests.csv"), f"{where}: tests")
    tests = _read_tests(tests_path, folder, where)
    name = data.get("name") or path.stem
    if not isinstance(name, str):
        raise InputError(f"{where}: name must be a string")
    return Campaign(path.resolve(), name[:200], specimen, fmt, tests)


def _read_tests(path: Path, folder: Path, where: str) -> tuple:
    if not path.is_file():
        raise InputError(f"{where}: the tests file {path.name!r} is not a file in the campaign's folder")
    try:
        text = path.read_text(encoding="utf-8-sig")
    except (OSError, UnicodeDecodeError) as exc:
        raise InputError(f"{where}: cannot read {path.name}: {exc}") from None
    sample = text[:4096]
    delim = "\t" if sample.count("\t") > sample.count(",") else ","
    rows = list(csv.reader(io.StringIO(text), delimiter=delim))
    rows = [r for r in rows if any(c.strip() for c in r)]
    if not rows:
        raise InputError(f"{where}: {path.name} is empty")
    head = [c.strip().lower() for c in rows[0]]
    for col in ("name", "file", "toppled"):
        if col not in head:
            raise InputError(f"{where}: {path.name} needs the columns name, file, toppled (found {', '.join(head)})")
    if len(rows) - 1 > MAX_TESTS:
        raise InputError(f"{where}: {path.name} lists {len(rows) - 1} tests, more than {MAX_TESTS}")
    ix = {c: head.index(c) for c in head}
    out, names = [], set()
    for n, r in enumerate(rows[1:], start=2):
        def cell(c, r=r):
            i = ix.get(c)
            return r[i].strip() if i is not None and i < len(r) else ""

        name = cell("name")
        if not name:
            raise InputError(f"{where}: {path.name} line {n}: a test needs a name")
        if name in names:
            raise InputError(f"{where}: {path.name} line {n}: test {name!r} is listed twice")
        names.add(name)
        file = _inside(folder, cell("file"), f"{where}: {path.name} line {n}: file")
        toppled = _bool01(cell("toppled"), f"{where}: {path.name} line {n}: toppled")
        lifted = _bool01(cell("lifted"), f"{where}: {path.name} line {n}: lifted") if cell("lifted") else None
        peak = None
        if cell("peak_rotation"):
            try:
                peak = float(cell("peak_rotation"))
            except ValueError:
                raise InputError(f"{where}: {path.name} line {n}: peak_rotation must be a number (rad)") from None
            if not (math.isfinite(peak) and peak >= 0):
                raise InputError(f"{where}: {path.name} line {n}: peak_rotation must be >= 0 rad")
        out.append(Test(name[:200], file, toppled, lifted, peak))
    if not out:
        raise InputError(f"{where}: {path.name} lists no test")
    return tuple(out)


# --- scores ----------------------------------------------------------------------------------------
def wilson(k: int, n: int, z: float = Z95) -> tuple[float, float] | None:
    """The Wilson score interval (lo, hi) of k successes in n trials (None for n = 0), to 4 digits."""
    if n <= 0:
        return None
    p = k / n
    den = 1 + z * z / n
    mid = (p + z * z / (2 * n)) / den
    half = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / den
    return round(max(0.0, mid - half), 4), round(min(1.0, mid + half), 4)


def _rate(k: int, n: int, why: str) -> dict:
    if n == 0:
        return {"value": None, "k": 0, "n": 0, "ci95": None, "reason": why}
    return {"value": k / n, "k": k, "n": n, "ci95": list(wilson(k, n)), "reason": None}


def scores(observed, predicted, prob=None) -> dict:
    """Confusion counts, accuracy, precision, recall (each with its Wilson interval) and the Brier score of
    ``prob`` (P of the outcome; None: not scored), over paired lists of booleans."""
    obs, pred = [bool(x) for x in observed], [bool(x) for x in predicted]
    if len(obs) != len(pred):
        raise ValueError("observed and predicted differ in length")
    tp = sum(o and p for o, p in zip(obs, pred))
    fp = sum(p and not o for o, p in zip(obs, pred))
    fn = sum(o and not p for o, p in zip(obs, pred))
    tn = len(obs) - tp - fp - fn
    out = {"n": len(obs), "tp": tp, "fp": fp, "fn": fn, "tn": tn,
           "accuracy": _rate(tp + tn, len(obs), "no test"),
           "precision": _rate(tp, tp + fp, "the model predicts the outcome in no test"),
           "recall": _rate(tp, tp + fn, "the outcome was observed in no test")}
    if prob is not None:
        pr = [float(x) for x in prob]
        out["brier"] = sum((p - float(o)) ** 2 for p, o in zip(pr, obs)) / len(obs) if obs else None
    return out
