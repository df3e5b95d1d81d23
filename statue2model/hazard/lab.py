"""Shake-table records as labs write them: the table's acceleration read from a text file of columns.

A lab file is a text table, tab-, comma-, semicolon- or space-separated, with header lines (``skip`` of
them, or every leading line that is not numbers), one sample per line. :class:`LabFormat` says which
columns hold the time and the acceleration (1-based; or a time step ``dt`` and one column), the unit of
the acceleration ("g" or "m/s^2"), a ``sign`` (+1 or -1: the table's axis against the scan's +x) and an
optional zero-phase band-pass ``band`` = (f_lo, f_hi) Hz (a 4th-order Butterworth run forward and back,
scipy.signal.sosfiltfilt).

A time column rounded to a few significant digits (t = 1.23, 1.235, 1.24, ...) makes the steps jitter about
a constant dt (some even repeat a time). The reader fits dt and t0 to the column (least squares against the
sample index) and accepts the file when every time lies within half its own rounding unit (read from how it
is written) and a quarter step of the grid t0 + k dt (the jitter is then the rounding, said in ``notes``); it
refuses a file whose times go backwards, or lose the grid (a gap, a changed rate). The samples are taken on
the uniform grid.

>>> import tempfile, pathlib
>>> p = pathlib.Path(tempfile.mkdtemp()) / "t1.txt"
>>> rows = [f"{k * 0.005:.4g}\\t{0.1 * (k % 7 - 3):.3f}" for k in range(4000)]      # t rounded to 4 digits
>>> _ = p.write_text("time [s]\\tacc [g]\\n" + "\\n".join(rows) + "\\n")
>>> m, notes = read_lab_motion(p, LabFormat(columns=(1, 2), units="g"))
>>> round(m.dt, 6), round(m.pga / 9.81, 3), notes[0].startswith("time column")
(0.005, 0.3, True)
"""
from __future__ import annotations

import math
import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..errors import InputError
from ..quantities import G
from .motions import GroundMotion, check_dt, record

UNITS = {"g": G, "m/s^2": 1.0, "m/s2": 1.0}
"""Acceleration units a lab file may use, and their m/s^2."""
MAX_BYTES = 200 * 2 ** 20
"""A lab file larger than this (200 MiB) is refused before it is read."""
_SPLIT = re.compile(r"[\t,; ]+")


@dataclass(frozen=True)
class LabFormat:
    """How to read a lab file (module docstring): ``columns`` (time, acceleration), 1-based, or ``dt`` (s) with
    ``column`` the acceleration's; ``units`` "g" or "m/s^2"; ``sign`` +1 / -1; ``band`` (f_lo, f_hi) Hz or None;
    ``skip`` header lines (None: every leading line that is not numbers)."""

    columns: tuple | None = (1, 2)
    dt: float | None = None
    column: int = 1
    units: str = "g"
    sign: float = 1.0
    band: tuple | None = None
    skip: int | None = None

    def __post_init__(self):
        if self.units not in UNITS:
            raise InputError(f"[motion] units must be one of {', '.join(UNITS)}, got {self.units!r}")
        if self.sign not in (1, -1, 1.0, -1.0):
            raise InputError(f"[motion] sign must be +1 or -1, got {self.sign!r}")
        if self.dt is None:
            cols = self.columns
            if (not isinstance(cols, (tuple, list)) or len(cols) != 2
                    or not all(isinstance(c, int) and not isinstance(c, bool) and c >= 1 for c in cols)
                    or cols[0] == cols[1]):
                raise InputError(f"[motion] columns must be two different column numbers (1-based) [time, acc], "
                                 f"got {cols!r}")
        else:
            check_dt(float(self.dt), "[motion] dt")
            if not (isinstance(self.column, int) and self.column >= 1):
                raise InputError(f"[motion] column must be a column number (1-based), got {self.column!r}")
        if self.band is not None:
            lo, hi = (float(x) for x in self.band)
            if not (math.isfinite(lo) and math.isfinite(hi) and 0 <= lo < hi):
                raise InputError(f"[motion] band must be [f_lo, f_hi] Hz with 0 <= f_lo < f_hi, got {self.band!r}")
        if self.skip is not None and not (isinstance(self.skip, int) and self.skip >= 0):
            raise InputError(f"[motion] skip must be a whole number of header lines, got {self.skip!r}")


def _quantum(token: str) -> float:
    """The rounding unit of a number as written: 10^-(its decimals), with an exponent's shift (1.23e-1: 1e-3)."""
    t = token.strip().lower().replace("d", "e")
    mant, _, exp = t.partition("e")
    dec = len(mant.split(".")[1]) if "." in mant else 0
    try:
        shift = int(exp) if exp else 0
    except ValueError:
        shift = 0
    return 10.0 ** (shift - dec)


def _numbers(line: str) -> list[float] | None:
    parts = [p for p in _SPLIT.split(line.strip()) if p]
    try:
        return [float(p.replace("D", "E").replace("d", "e")) for p in parts] if parts else None
    except ValueError:
        return None


def read_lab_motion(path, fmt: LabFormat, label: str | None = None) -> tuple[GroundMotion, list[str]]:
    """The table's acceleration in ``path`` as a GroundMotion (m/s^2, along the scan's +x) and the notes on
    what was done to it (module docstring); one-line InputErrors name the file and the line."""
    path = Path(path)
    name = label or path.name
    try:
        size = path.stat().st_size
    except OSError as exc:
        raise InputError(f"motion file {path}: {exc.strerror or exc}") from None
    if not path.is_file():
        raise InputError(f"motion file {path} is not a file")
    if size > MAX_BYTES:
        raise InputError(f"motion file {path} holds {size / 2 ** 20:.0f} MiB: more than a lab record "
                         f"({MAX_BYTES / 2 ** 20:.0f} MiB at most)")
    try:
        lines = path.read_text(encoding="utf-8", errors="replace").splitlines()
    except OSError as exc:
        raise InputError(f"motion file {path}: {exc.strerror or exc}") from None
    start = fmt.skip
    if start is None:
        start = next((i for i, line in enumerate(lines) if _numbers(line) is not None), len(lines))
    need = max(fmt.columns) if fmt.dt is None else fmt.column
    t, q, a = [], [], []
    for i in range(start, len(lines)):
        if not lines[i].strip():
            continue
        v = _numbers(lines[i])
        if v is None:
            raise InputError(f"motion file {path}: line {i + 1} is not numbers: {lines[i][:60]!r}")
        if len(v) < need:
            raise InputError(f"motion file {path}: line {i + 1} has {len(v)} column(s), {need} needed")
        if fmt.dt is None:
            t.append(v[fmt.columns[0] - 1])
            q.append(_quantum([p for p in _SPLIT.split(lines[i].strip()) if p][fmt.columns[0] - 1]))
            a.append(v[fmt.columns[1] - 1])
        else:
            a.append(v[fmt.column - 1])
    if len(a) < 2:
        raise InputError(f"motion file {path}: {len(a)} sample(s); a record needs at least 2")
    acc = np.asarray(a, dtype=float) * UNITS[fmt.units] * float(fmt.sign)
    if not np.all(np.isfinite(acc)):
        raise InputError(f"motion file {path}: a sample is not a finite number (line "
                         f"{start + 1 + int(np.flatnonzero(~np.isfinite(acc))[0])})")
    notes = []
    if fmt.dt is None:
        dt, note = _uniform_step(np.asarray(t, dtype=float), path, np.asarray(q, dtype=float))
        if note:
            notes.append(note)
    else:
        dt = float(fmt.dt)
    if fmt.band is not None:
        acc = band_pass(acc, dt, fmt.band, path)
        notes.append(f"zero-phase band-pass {fmt.band[0]:g}-{fmt.band[1]:g} Hz (4th-order Butterworth, forward and "
                     "back)")
    return record(acc, dt, label=name), notes


def _uniform_step(t: np.ndarray, path, quantum: np.ndarray | None = None) -> tuple[float, str | None]:
    """(dt, note) of a time column: the least-squares step of t against the sample index; each time may lie off
    that grid by half its own rounding unit (``quantum``, from how it is written) and a quarter step; farther is
    a gap or a change of rate."""
    steps = np.diff(t)
    if np.any(steps < 0):
        k = int(np.flatnonzero(steps < 0)[0])
        raise InputError(f"motion file {path}: the time goes back at sample {k + 2} ({t[k]:g} then {t[k + 1]:g} s)")
    if not t[-1] > t[0]:
        raise InputError(f"motion file {path}: the time column does not advance")
    k = np.arange(len(t), dtype=float)
    dt, t0 = (float(x) for x in np.polyfit(k, t, 1))
    check_dt(dt, f"motion file {path}: time step")
    q = np.zeros_like(t) if quantum is None else quantum
    off = np.abs(t - (t0 + dt * k))
    tol = 0.5 * q + 0.25 * dt + 1e-12
    if np.any(off > tol):
        i = int(np.argmax(off > tol))
        raise InputError(f"motion file {path}: the time leaves the uniform grid of dt {dt:g} s at sample {i + 1} "
                         f"({t[i]:g} s against {t0 + dt * i:g} s): a gap or a change of rate")
    jitter = float(np.abs(steps - dt).max())
    if jitter > 1e-6 * dt:
        return dt, (f"time column: steps jitter about dt {dt:.6g} s by up to {jitter:.3g} s (the times are rounded, "
                    f"to {q.max():g} s at most); taken on the uniform grid")
    return dt, None


def band_pass(acc: np.ndarray, dt: float, band, path="record") -> np.ndarray:
    """The zero-phase 4th-order Butterworth band-pass of ``acc`` sampled every ``dt`` s over ``band`` Hz (f_lo 0:
    a low-pass)."""
    from scipy import signal

    lo, hi = float(band[0]), float(band[1])
    nyq = 0.5 / dt
    if hi >= nyq:
        raise InputError(f"motion file {path}: band end {hi:g} Hz is at or above the Nyquist frequency {nyq:g} Hz")
    sos = (signal.butter(4, [lo / nyq, hi / nyq], btype="bandpass", output="sos") if lo > 0 else
           signal.butter(4, hi / nyq, btype="lowpass", output="sos"))
    if acc.size <= 3 * 2 * sos.shape[0] + 1:
        raise InputError(f"motion file {path}: too short ({acc.size} samples) to band-pass")
    return signal.sosfiltfilt(sos, acc)
