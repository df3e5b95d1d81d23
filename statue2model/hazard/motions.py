"""Ground motions u_g''(t) (MODEL.md section 5): pulses, sine trains, records.

All accelerations are in m/s^2 and positive toward +x (a positive pulse tips the
body onto its left pivot, theta < 0). Times in s.

* :func:`cosine_pulse`, :func:`sine_pulse` - one cycle of a cos / a sin (w t),
  0 <= t <= 1/f (eq. 44); :func:`sine_train` - N cycles; :func:`rect_pulse`.
* :func:`read_record` - two-column time/acc CSV, one-column CSV with dt, or a
  PEER NGA ``.AT2`` file (in g); uniform sampling is required.
* :func:`synthetic_record` - a seeded Kanai-Tajimi accelerogram with an envelope.
* :meth:`GroundMotion.scaled_to_pga`, :meth:`GroundMotion.froude` - scaling.
* :func:`table_displacement` - baseline-corrected double integration to the
  displacement a shake table is driven with.
* :func:`parse_spec` - the command-line SPEC strings (``bundled:name=elcentro_1940_ns``:
  a record shipped with the package, :func:`statue2model.io.paths.bundled_record`).

Every acceleration read (a sample of a record file, a pulse amplitude, a PGA) must be finite
and at most :data:`A_MAX` (100 g) in magnitude, and a record's time step within the
possible range of :data:`statue2model.geometry.units.PLAUSIBLE` (1e-6 to 1 s): otherwise
an :class:`InputError` naming the file, the line and the value (no ground moves at 100 g;
such a number is a unit or a parsing mistake, and would stall the solvers).

Example
-------
>>> m = parse_spec("cosine:amp=0.3g,freq=2")[0]
>>> round(m.amp, 4), m.end, m.extremes()[0] == m.amp
(2.943, 0.5, True)
>>> m.froude(2.0).end                     # a 1:2 prototype: times / sqrt(2)
0.35355339059327373
"""
from __future__ import annotations

import math
import re
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from ..errors import InputError, quoted
from ..quantities import A_MAX, G, G_STANDARD, parse_accel, scale_ratio
from . import motion_kernel as MK



def check_acc(value: float, where: str) -> None:
    """Refuse one acceleration (m/s^2) that is not finite or exceeds :data:`A_MAX`;
    ``where`` names it ('rec.csv: line 12: acceleration')."""
    from ..geometry.units import check_plausible

    check_plausible("acceleration", value, where)


def check_dt(dt: float, where: str) -> None:
    """Refuse a record time step (s) that is not positive and finite, or outside the possible range."""
    from ..geometry.units import check_plausible

    if not (math.isfinite(dt) and dt > 0):
        raise InputError(f"{where} = {quoted(dt)}: the time step must be a positive number of seconds")
    check_plausible("time_step", dt, where)


def _check_samples(acc: np.ndarray, where: str, lines=None) -> None:
    """Refuse the first sample of ``acc`` (m/s^2) that is not finite or above :data:`A_MAX`,
    naming its line (``lines[i]``: the file line of sample i) or its index."""
    bad = ~np.isfinite(acc)
    bad[~bad] = np.abs(acc[~bad]) > A_MAX
    if np.any(bad):
        i = int(np.flatnonzero(bad)[0])
        at = f"line {lines[i]}" if lines is not None else f"sample {i}"
        if not np.isfinite(acc[i]):
            raise InputError(f"{where}: {at}: the acceleration is not a finite number ({float(acc[i])})")
        check_acc(float(acc[i]), f"{where}: {at}: acceleration")


@dataclass(frozen=True, eq=False)
class GroundMotion:
    """One ground-acceleration history (immutable).

    kind: "none", "harmonic" (amp sin(2 pi freq (t - start) + phase) on
    [start, start + duration)), "rect" (amp on [start, start + duration)) or
    "record" (samples every dt from start, linear in between, zero outside).
    """

    kind: str = "none"
    amp: float = 0.0
    freq: float = 0.0
    phase: float = 0.0
    start: float = 0.0
    duration: float = 0.0
    dt: float = 0.0
    samples: np.ndarray | None = None
    label: str = "free"
    froude_scale: float = 1.0       # lambda of the 1:lambda prototype it is scaled for (1: full scale)

    @property
    def end(self) -> float:
        """Time (s) after which the ground is at rest."""
        return self.start + self.duration if self.kind != "none" else 0.0

    def extremes(self) -> tuple[float, float]:
        """(largest, smallest) u_g'' in m/s^2 (0 included: the ground is at rest outside)."""
        if self.kind == "none":
            return 0.0, 0.0
        if self.kind == "rect":
            return max(self.amp, 0.0), min(self.amp, 0.0)
        if self.kind == "harmonic":
            # at least one full cycle or a fraction of it: sample exactly at the turning points
            w = 2 * math.pi * self.freq
            x0, x1 = self.phase, self.phase + w * self.duration
            vals = [math.sin(x0), math.sin(x1)]
            k0 = math.ceil((x0 - math.pi / 2) / math.pi)
            for k in range(k0, k0 + 3):
                xk = math.pi / 2 + k * math.pi
                if x0 <= xk <= x1:
                    vals.append(math.sin(xk))
            vals = [self.amp * v for v in vals] + [0.0]
            return max(vals), min(vals)
        s = self.samples
        return max(float(s.max()), 0.0), min(float(s.min()), 0.0)

    @property
    def pga(self) -> float:
        hi, lo = self.extremes()
        return max(hi, -lo)

    def acc(self, t) -> np.ndarray:
        """u_g''(t) in m/s^2 for an array of times (right-continuous at breakpoints): the compiled
        ground motion's values (hazard/motion_kernel.py ground_acc), a record's on whole arrays
        (:func:`_record_acc`, the same arithmetic, ~1/20 of the cost of a compiled call a point)."""
        t = np.asarray(t, dtype=float)
        kind, M, samples = self.kernel_args()
        if kind == MK.M_RECORD:
            return _record_acc(t, M, samples)
        from ..compute.compile import ensure_compiled

        ensure_compiled()
        return np.vectorize(lambda x: MK.ground_acc(x, kind, M, samples), otypes=[float])(t)

    def kernel_args(self) -> tuple[int, np.ndarray, np.ndarray]:
        """(kind, M, samples) of the kernels (samples read-only: :func:`kernel.as_samples`)."""
        M = np.zeros(MK.N_M)
        M[MK.MT0] = self.start
        M[MK.MT1] = self.start + self.duration
        if self.kind == "none":
            return MK.M_NONE, M, MK.as_samples(np.zeros(2))
        M[MK.MA] = self.amp
        if self.kind == "harmonic":
            M[MK.MW] = 2 * math.pi * self.freq
            M[MK.MPH] = self.phase
            return MK.M_HARMONIC, M, MK.as_samples(np.zeros(2))
        if self.kind == "rect":
            return MK.M_RECT, M, MK.as_samples(np.zeros(2))
        M[MK.MA] = 1.0
        M[MK.MDT] = self.dt
        return MK.M_RECORD, M, MK.as_samples(self.samples)

    def scaled(self, factor: float) -> "GroundMotion":
        """Accelerations times ``factor``."""
        if self.kind == "record":
            return replace(self, samples=self.samples * factor)
        return replace(self, amp=self.amp * factor)

    def scaled_to_pga(self, pga: float) -> "GroundMotion":
        """Scale so that max |u_g''| = pga (m/s^2)."""
        if not (math.isfinite(pga) and pga > 0):
            raise InputError(f"target PGA must be a positive finite acceleration, got {pga}")
        check_acc(pga, "target PGA")
        if self.pga == 0:
            raise InputError(f"motion {quoted(self.label)} is zero everywhere: it cannot be scaled to a PGA")
        return self.scaled(pga / self.pga)

    def froude(self, lam: float) -> "GroundMotion":
        """The motion for a 1:lam prototype: same accelerations, times / sqrt(lam)."""
        if not (math.isfinite(lam) and lam > 0):
            raise InputError(f"scale factor lambda must be positive, got {lam}")
        r = math.sqrt(lam)
        return replace(self, start=self.start / r, duration=self.duration / r, dt=self.dt / r,
                       freq=self.freq * r, label=f"{self.label} (1:{lam:g})", froude_scale=self.froude_scale * lam)

    def sampled(self, dt: float | None = None) -> tuple[np.ndarray, np.ndarray]:
        """(t, u_g'') on a uniform grid from 0 to the end (default dt: the record's
        own samples, from its start; otherwise 1 ms). A sample at the end time holds
        the last value of the motion (its left limit), so that the samples joined
        linearly reproduce the motion."""
        if self.kind == "record" and dt is None:
            return self.start + self.dt * np.arange(len(self.samples)), self.samples.copy()
        if dt is None:
            dt = 1e-3
        if not (math.isfinite(dt) and dt > 0):
            raise InputError(f"sampling time step dt must be positive, got {dt}")
        from ..compute.budget import check_history, num

        # t, u and the table's velocity, displacement and their temporaries: about 10 arrays
        check_history(self.end, dt, 80, what="its samples", head=f"{self.label}: {num(self.end)} s sampled "
                      f"every {num(dt)} s", fix="use a coarser dt")
        n = max(int(math.ceil(self.end / dt - 1e-9)), 1)
        t = np.arange(n + 1) * dt
        u = self.acc(t)
        if self.kind != "none":
            u[np.abs(t - self.end) <= 1e-9 * dt] = self._last_value()
        return t, u

    def _last_value(self) -> float:
        """lim u_g''(t) for t -> end from below."""
        if self.kind == "harmonic":
            return self.amp * math.sin(2 * math.pi * self.freq * self.duration + self.phase)
        if self.kind == "rect":
            return self.amp
        if self.kind == "record":
            return float(self.samples[-1])
        return 0.0

    def to_dict(self) -> dict:
        d = {"kind": self.kind, "label": self.label, "start_s": self.start, "end_s": self.end,
             "pga_m_s2": self.pga}
        if self.kind in ("harmonic", "rect"):
            d["amp_m_s2"] = self.amp
        if self.kind == "harmonic":
            d.update(freq_hz=self.freq, phase_rad=self.phase)
        if self.kind == "record":
            d.update(dt_s=self.dt, n_samples=int(len(self.samples)))
        if self.froude_scale != 1.0:
            d["froude_scale"] = f"1:{self.froude_scale:g}"
        return d


# --- constructors --------------------------------------------------------------
def _check_amp_freq(amp, freq):
    if not math.isfinite(amp):
        raise InputError(f"pulse amplitude must be finite, got {amp}")
    check_acc(amp, "pulse amplitude")
    if not (math.isfinite(freq) and freq > 0):
        raise InputError(f"pulse frequency must be a positive number of Hz, got {freq}")


def free() -> GroundMotion:
    """No ground motion (free rocking from initial conditions)."""
    return GroundMotion()


def cosine_pulse(amp: float, freq: float, start: float = 0.0) -> GroundMotion:
    """u_g'' = amp cos(2 pi freq (t - start)) for one period 1/freq (eq. 44)."""
    _check_amp_freq(amp, freq)
    return GroundMotion("harmonic", amp, freq, math.pi / 2, start, 1.0 / freq, label=f"one-cosine {freq:g} Hz")


def sine_pulse(amp: float, freq: float, start: float = 0.0) -> GroundMotion:
    """u_g'' = amp sin(2 pi freq (t - start)) for one period 1/freq."""
    _check_amp_freq(amp, freq)
    return GroundMotion("harmonic", amp, freq, 0.0, start, 1.0 / freq, label=f"one-sine {freq:g} Hz")


def sine_train(amp: float, freq: float, cycles: float, start: float = 0.0) -> GroundMotion:
    """``cycles`` periods of amp sin(2 pi freq (t - start))."""
    _check_amp_freq(amp, freq)
    if not (math.isfinite(cycles) and cycles > 0):
        raise InputError(f"number of cycles must be positive, got {cycles}")
    return GroundMotion("harmonic", amp, freq, 0.0, start, cycles / freq, label=f"{cycles:g} sines {freq:g} Hz")


def rect_pulse(amp: float, dur: float, start: float = 0.0) -> GroundMotion:
    """u_g'' = amp for ``dur`` seconds."""
    if not math.isfinite(amp):
        raise InputError(f"pulse amplitude must be finite, got {amp}")
    check_acc(amp, "pulse amplitude")
    if not (math.isfinite(dur) and dur > 0):
        raise InputError(f"pulse duration must be positive, got {dur}")
    return GroundMotion("rect", amp, 0.0, 0.0, start, dur, label=f"rectangular {dur:g} s")


def record(acc, dt: float, start: float = 0.0, label: str = "record") -> GroundMotion:
    """A uniformly sampled accelerogram (m/s^2), linear between samples."""
    acc = np.array(acc, dtype=float).ravel()  # a copy: the caller's array may change later
    if acc.size < 2:
        raise InputError(f"{label}: a record needs at least 2 samples, got {acc.size}")
    _check_samples(acc, label)
    if not (math.isfinite(dt) and dt > 0):
        raise InputError(f"{label}: time step dt must be positive, got {dt}")
    check_dt(dt, f"{label}: time step dt")
    if not math.isfinite(start) or start < 0:
        raise InputError(f"{label}: start time must be >= 0, got {start}")
    acc.setflags(write=False)
    return GroundMotion("record", 1.0, 0.0, 0.0, float(start), dt * (acc.size - 1), float(dt), acc, label)


def synthetic_record(duration: float = 20.0, dt: float = 0.01, pga: float = 0.3 * G, seed: int = 0,
                     f_g: float = 2.5, zeta_g: float = 0.6) -> GroundMotion:
    """A reproducible artificial accelerogram: white noise through a Kanai-Tajimi
    filter (ground frequency f_g Hz, damping zeta_g), shaped by a rise / strong /
    decay envelope, linear baseline removed, scaled to ``pga`` (m/s^2)."""
    from scipy import signal

    for name, value in (("duration", duration), ("dt", dt), ("pga", pga), ("f_g", f_g), ("zeta_g", zeta_g)):
        if not (math.isfinite(value) and value > 0):
            raise InputError(f"synthetic record: {name} must be positive, got {value}")
    check_acc(pga, "synthetic record: pga")
    check_dt(dt, "synthetic record: dt")
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
        raise InputError(f"synthetic record: seed must be a non-negative integer, got {quoted(seed)}")
    from ..compute.budget import check_history, num

    # the noise, its filtered copy, t, the envelope and the baseline: about 8 arrays of n samples
    check_history(duration, dt, 64, what="its samples", head=f"a synthetic record of {num(duration)} s at "
                  f"dt {num(dt)} s", fix="use a shorter duration or a coarser dt")
    n = int(round(duration / dt)) + 1
    if n < 10:
        raise InputError(f"synthetic record: duration {duration:g} s is shorter than 10 time steps of {dt:g} s")
    rng = np.random.default_rng(seed)
    w = rng.standard_normal(n)
    wg = 2 * math.pi * f_g
    b, a = signal.bilinear([2 * zeta_g * wg, wg**2], [1.0, 2 * zeta_g * wg, wg**2], fs=1.0 / dt)
    x = signal.lfilter(b, a, w)
    t = np.arange(n) * dt
    t1, t2 = 0.1 * duration, 0.45 * duration
    env = np.where(t < t1, (t / t1) ** 2, np.where(t < t2, 1.0, np.exp(-3.0 * (t - t2) / (duration - t2))))
    x = x * env
    x = x - np.polyval(np.polyfit(t, x, 1), t) * env
    x[0] = 0.0
    x *= pga / np.max(np.abs(x))
    return record(x, dt, label=f"synthetic KT seed {seed}")


# --- files -----------------------------------------------------------------------
_NUM = re.compile(r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eEdD][-+]?\d+)?")


def _read_at2(path: Path) -> GroundMotion:
    lines = path.read_text(encoding="utf-8-sig", errors="replace").splitlines()   # with or without a BOM
    head = None
    for i, line in enumerate(lines[:10]):
        if re.search(r"NPTS", line, re.I) and re.search(r"DT", line, re.I):
            head = i
            break
    if head is None:
        raise InputError(f"{path}: not a PEER NGA .AT2 file (no 'NPTS= ..., DT= ...' line in its header)")
    m_n = re.search(r"NPTS\s*=\s*(\d+)", lines[head], re.I)
    m_dt = re.search(r"DT\s*=\s*(" + _NUM.pattern + ")", lines[head], re.I)
    m_old = re.match(r"\s*(\d+)[\s,]+(" + _NUM.pattern + r")[\s,]+NPTS\s*,\s*DT", lines[head], re.I)
    if m_n and m_dt:  # NGA-West2: "NPTS=  5000, DT=   .0050 SEC"
        npts_s, dt_s = m_n.group(1), m_dt.group(1)
    elif m_old:  # NGA-West1: "  3000    .01000    NPTS, DT"
        npts_s, dt_s = m_old.group(1), m_old.group(2)
    else:
        raise InputError(f"{path}: cannot read NPTS and DT from header line {head + 1}: {quoted(lines[head].strip())}")
    npts, dt = int(npts_s), float(dt_s.replace("D", "E").replace("d", "e"))
    check_dt(dt, f"{path}: line {head + 1}: DT")
    values, where = [], []
    for j, line in enumerate(lines[head + 1:], start=head + 2):
        for tok in line.split():
            try:
                values.append(float(tok.replace("D", "E").replace("d", "e")))
            except ValueError:
                raise InputError(f"{path}: line {j}: {quoted(tok)} is not a number") from None
            where.append(j)
    if len(values) != npts:
        raise InputError(f"{path}: header says NPTS={npts} but the file holds {len(values)} values")
    acc = np.asarray(values) * G_STANDARD
    _check_samples(acc, str(path), where)
    return record(acc, dt, label=path.name)


_CELL_SEP = re.compile(r"[,;\s]+")


FROUDE_HEADER = "# statue2model: Froude-scaled for a 1:{lam:g} prototype"
"""The first line of a record file written for a prototype (:func:`write_record_csv`); read back
by :func:`read_record` into ``froude_scale``, so the record never drives a full-size model unseen."""
_FROUDE_RE = re.compile(r"#\s*statue2model:\s*Froude-scaled for a 1:([0-9.eE+-]+) prototype")


def _read_csv(path: Path, dt: float | None, units: str, components: int = 1) -> tuple[GroundMotion, ...]:
    """The record's horizontal components (``components``: the most accepted, 1 or 2)."""
    ms = _read_csv_samples(path, dt, units, components)
    with open(path, encoding="utf-8-sig", errors="replace") as f:
        first = f.readline()
    hit = _FROUDE_RE.match(first.strip())
    if hit:
        try:
            lam = float(hit.group(1))
        except ValueError:
            lam = math.nan
        if not (math.isfinite(lam) and lam > 0):
            raise InputError(f"{path}: its header names a prototype scale 1:{hit.group(1)} that is not a number > 0")
        ms = tuple(replace(m, froude_scale=lam) for m in ms)
    return ms


def _read_csv_samples(path: Path, dt: float | None, units: str, components: int = 1) -> tuple[GroundMotion, ...]:
    rows, line_no = [], []
    # utf-8-sig: a byte-order mark (Excel's "CSV UTF-8") would otherwise make the first number a header
    for j, line in enumerate(path.read_text(encoding="utf-8-sig", errors="replace").splitlines(), start=1):
        line = line.strip()
        if not line or line.startswith("#"):
            continue
        row = [c for c in (c.strip("\"'") for c in _CELL_SEP.split(line)) if c]
        if not row:
            continue
        try:
            rows.append([float(c) for c in row])
        except ValueError:
            if rows:
                raise InputError(f"{path}: line {j}: not a number: {quoted(line)}") from None
            continue  # a header line before the data
        line_no.append(j)
    if not rows:
        raise InputError(f"{path}: no numeric data")
    ragged = [i for i, r in enumerate(rows) if len(r) != len(rows[0])]
    if ragged:
        i = ragged[0]
        raise InputError(f"{path}: line {line_no[i]} has {len(rows[i])} columns, line {line_no[0]} has "
                         f"{len(rows[0])}: rows have different numbers of columns")
    data = np.asarray(rows)
    factor = G_STANDARD if units == "g" else 1.0
    if data.shape[1] == 1:
        if dt is None:
            raise InputError(f"{path}: one column of accelerations needs the time step: add dt=S to the spec")
        check_dt(dt, f"{path}: dt")
        _check_samples(data[:, 0] * factor, str(path), line_no)
        return (record(data[:, 0] * factor, dt, label=path.name),)
    if data.shape[1] == 3 and components == 1:
        raise InputError(f"{path}: 3 columns (time and two horizontal components): this command takes one "
                         "component; give a file with time, acc (the 3D cross-check reads both: "
                         "statue2model crosscheck --only-motion)")
    if data.shape[1] not in (2, 3):
        raise InputError(f"{path}: expected 1 column (acc), 2 columns (time, acc) or 3 (time, a_x, a_y), "
                         f"found {data.shape[1]}")
    t = data[:, 0]
    for col in range(1, data.shape[1]):
        _check_samples(data[:, col] * factor, str(path), line_no)
    if not np.all(np.isfinite(t)):
        raise InputError(f"{path}: the time column holds a non-finite value")
    steps = np.diff(t)
    if steps.size == 0:
        raise InputError(f"{path}: a record needs at least 2 samples")
    step = float(np.median(steps))
    if step <= 0 or np.any(steps <= 0):
        raise InputError(f"{path}: time does not increase (line {line_no[int(np.argmax(steps <= 0)) + 1]})")
    bad = np.abs(steps - step) > 1e-3 * step + 1e-9
    if np.any(bad):
        i = int(np.argmax(bad))
        raise InputError(f"{path}: irregular time step (dt = {steps[i]:g} s at line {line_no[i + 1]}, "
                         f"elsewhere {step:g} s); resample it to a uniform step")
    if dt is not None and abs(dt - step) > 1e-3 * step:
        raise InputError(f"{path}: dt={dt:g} contradicts the time column (step {step:g} s)")
    if t[0] < 0:
        raise InputError(f"{path}: the record starts at a negative time ({t[0]:g} s)")
    step = (t[-1] - t[0]) / (len(t) - 1)
    check_dt(step, f"{path}: time step (the time column)")
    if data.shape[1] == 2:
        return (record(data[:, 1] * factor, step, start=float(t[0]), label=path.name),)
    return tuple(record(data[:, c] * factor, step, start=float(t[0]), label=f"{path.name} {ax}")
                 for c, ax in ((1, "x"), (2, "y")))


def read_record(path, dt: float | None = None, units: str | None = None) -> GroundMotion:
    """Read an accelerogram file. ``.AT2`` files are in g; CSV files in m/s^2
    unless ``units="g"``. A CSV of time and two horizontal components is refused with a
    pointer to :func:`read_record_components`."""
    return read_record_components(path, dt, units, components=1)[0]


def read_record_components(path, dt: float | None = None, units: str | None = None,
                           components: int = 2) -> tuple[GroundMotion, ...]:
    """The horizontal components of an accelerogram file: one (``.AT2``, a one- or two-column CSV) or,
    with ``components=2``, two from a CSV of three columns (time, a_x, a_y; x and y in the scan's
    frame, as the excitation direction is)."""
    path = Path(path)
    if not path.is_file():
        raise InputError(f"motion file not found: {path}")
    if isinstance(units, str):
        units = units.strip().lower()
    if units not in (None, "g", "m/s2"):
        raise InputError(f"motion units must be g or m/s2, got {quoted(units)}")
    if path.stat().st_size == 0:
        raise InputError(f"motion file is empty: {path}")
    if path.suffix.lower() == ".at2":
        if dt is not None:
            raise InputError(f"{path}: an .AT2 file gives its own DT; drop dt= from the spec")
        return (_read_at2(path),)
    return _read_csv(path, dt, units or "m/s2", components)


def along(ax: GroundMotion, ay: GroundMotion, direction_deg: float) -> tuple[GroundMotion, GroundMotion]:
    """Two horizontal records (x, y; same sampling) resolved along the excitation direction (degrees
    from +x toward +y) and across it: (a_x cos + a_y sin, -a_x sin + a_y cos)."""
    if ax.kind != "record" or ay.kind != "record" or ax.dt != ay.dt or ax.samples.size != ay.samples.size \
            or ax.start != ay.start:
        raise InputError("the two horizontal components must be records of the same sampling")
    c, s_ = math.cos(math.radians(direction_deg)), math.sin(math.radians(direction_deg))
    a_par = c * ax.samples + s_ * ay.samples
    a_perp = -s_ * ax.samples + c * ay.samples
    base = ax.label.removesuffix(" x")
    return tuple(replace(ax, samples=_frozen(a), label=f"{base} {what} {direction_deg:.1f} deg")
                 for a, what in ((a_par, "along"), (a_perp, "across")))


def _frozen(a: np.ndarray) -> np.ndarray:
    a = np.array(a, dtype=float)
    a.setflags(write=False)
    return a


def write_record_csv(path, motion: GroundMotion, dt: float | None = None) -> Path:
    """Write (time, acc) as a two-column CSV readable by :func:`read_record`."""
    from ..io.files import atomic_write

    t, u = motion.sampled(dt)
    head = (FROUDE_HEADER.format(lam=motion.froude_scale) + " (times / sqrt(lambda), accelerations unchanged)\n"
            if motion.froude_scale != 1.0 else "")
    from ..io.csvsafe import number_columns_text

    text = head + number_columns_text(("time_s", "acc_m_s2"), (t, u), (".9g", ".9g"))
    return atomic_write(path, lambda p: p.write_text(text))


# --- shake-table input -----------------------------------------------------------------
def table_displacement(motion: GroundMotion, dt: float | None = None):
    """Baseline-corrected double integration for a shake table.

    The acceleration is corrected by a linear baseline c0 + c1 t chosen so that
    the table ends at rest where it started (v(T) = 0 and u(T) = 0), then
    integrated twice (trapezoidal rule). Returns (t, acc, vel, disp) in s, m/s^2,
    m/s, m.
    """
    t, a = motion.sampled(dt)
    if not np.any(a):  # no motion: the table stays put
        zero = np.zeros_like(t)
        return t, zero, zero.copy(), zero.copy()
    if len(t) < 3:
        raise InputError(f"motion {quoted(motion.label)} is too short to drive a table: it needs at least 3 samples")
    h = np.diff(t)

    def integrate(x):
        return np.concatenate([[0.0], np.cumsum(0.5 * h * (x[1:] + x[:-1]))])

    tt = t - t[0]
    v = integrate(a)
    u = integrate(v)
    # u(T) of the baselines 1 and t (integrated the same way, so the correction is exact)
    one = np.ones_like(t)
    v1, v2 = integrate(one), integrate(tt)
    u1, u2 = integrate(v1), integrate(v2)
    A = np.array([[v1[-1], v2[-1]], [u1[-1], u2[-1]]])
    c = np.linalg.solve(A, [v[-1], u[-1]])
    a_c = a - c[0] - c[1] * tt
    v_c = v - c[0] * v1 - c[1] * v2
    u_c = u - c[0] * u1 - c[1] * u2
    return t, a_c, v_c, u_c


# --- SPEC strings ------------------------------------------------------------------
def _num(key: str, text: str, positive: bool = False) -> float:
    try:
        value = float(text)
    except ValueError:
        raise InputError(f"motion spec: {key} must be a number, got {quoted(text)}") from None
    if not math.isfinite(value) or (positive and value <= 0):
        raise InputError(f"motion spec: {key} must be a {'positive ' if positive else ''}finite number, got {quoted(text)}")
    return value


def _seed(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise InputError(f"motion spec: seed must be a non-negative integer, got {quoted(text)}") from None
    if value < 0:
        raise InputError(f"motion spec: seed must be a non-negative integer, got {quoted(text)}")
    return value


_SPEC_KEYS = {
    "free": ({"theta0"}, set()),
    "cosine": ({"amp", "freq"}, {"start"}),
    "sine": ({"amp", "freq"}, {"start"}),
    "rect": ({"amp", "dur"}, {"start"}),
    "sines": ({"amp", "freq", "cycles"}, {"start"}),
    "file": ({"path"}, {"dt", "pga", "scale", "units"}),
    "synthetic": (set(), {"duration", "dt", "pga", "seed", "fg"}),
    "bundled": ({"name"}, {"pga", "scale"}),
}


def _froude_scale(text: str) -> float:
    """lambda of ``scale=1:2`` (or the ratio ``0.5``) in a motion spec; a bare 2 is refused
    as everywhere else (1:2 or 2:1?)."""
    try:
        return scale_ratio(text)
    except InputError as exc:
        raise InputError(f"scale={text}: {exc}") from None


def parse_spec(spec: str, base_dir=None) -> tuple[GroundMotion, float]:
    """Parse a SPEC string into (motion, theta0). See the module docstring and
    ``statue2model rock --help`` for the forms."""
    motions_, theta0 = parse_spec_components(spec, base_dir, components=1)
    return motions_[0], theta0


def parse_spec_components(spec: str, base_dir=None, components: int = 2) -> tuple[tuple[GroundMotion, ...], float]:
    """Parse a SPEC string into (the horizontal components, theta0): two where ``components`` is 2 and
    the spec is a file of time, a_x, a_y (``pga=`` then scales both by one factor, so that the larger
    component's peak is the PGA); one otherwise."""
    if ":" in spec:
        kind, _, rest = spec.partition(":")
    else:
        kind, rest = spec, ""
    kind = kind.strip().lower()
    if kind not in _SPEC_KEYS:
        raise InputError(f"unknown motion kind {quoted(kind)} in {quoted(spec)}; use one of {', '.join(_SPEC_KEYS)}")
    args: dict[str, str] = {}
    for part in filter(None, (p.strip() for p in rest.split(","))):
        key, eq, value = part.partition("=")
        if not eq:
            raise InputError(f"motion spec {quoted(spec)}: expected key=value, got {quoted(part)}")
        key = key.strip().lower()
        if key in args:
            raise InputError(f"motion spec {quoted(spec)}: {quoted(key)} given twice")
        args[key] = value.strip()
    need, optional = _SPEC_KEYS[kind]
    missing = need - set(args)
    if missing:
        raise InputError(f"motion spec {quoted(spec)}: missing {', '.join(sorted(missing))}")
    extra = set(args) - need - optional
    if extra:
        raise InputError(f"motion spec {quoted(spec)}: unknown key(s) {quoted(', '.join(sorted(extra)), bare=True)}")
    start = _num("start", args["start"]) if "start" in args else 0.0
    if start < 0:
        raise InputError(f"motion spec {quoted(spec)}: start must be >= 0")
    if kind == "free":
        theta0 = _num("theta0", args["theta0"])
        return (free(),), theta0
    if kind in ("cosine", "sine", "sines"):
        amp = parse_accel(args["amp"], "pulse amplitude", key="amp")
        freq = _num("freq", args["freq"], positive=True)
        if kind == "cosine":
            return (cosine_pulse(amp, freq, start),), 0.0
        if kind == "sine":
            return (sine_pulse(amp, freq, start),), 0.0
        return (sine_train(amp, freq, _num("cycles", args["cycles"], positive=True), start),), 0.0
    if kind == "rect":
        return (rect_pulse(parse_accel(args["amp"], "pulse amplitude", key="amp"),
                           _num("dur", args["dur"], positive=True), start),), 0.0
    if kind == "synthetic":
        motion = synthetic_record(duration=_num("duration", args.get("duration", "20"), True),
                                  dt=_num("dt", args.get("dt", "0.01"), True),
                                  pga=parse_accel(args.get("pga", "0.3g"), "pga", key="pga"),
                                  seed=_seed(args.get("seed", "0")),
                                  f_g=_num("fg", args.get("fg", "2.5"), True))
        return (motion,), 0.0
    if kind == "bundled":     # a record shipped in the package data (statue2model/data/records)
        from ..io.paths import bundled_record

        ms = (read_record(bundled_record(args["name"])),)
    else:
        path = Path(args["path"])
        if base_dir is not None and not path.is_absolute():
            path = Path(base_dir) / path
        ms = read_record_components(path, dt=_num("dt", args["dt"], True) if "dt" in args else None,
                                    units=args.get("units"), components=components)
    if "pga" in args:
        big = max(ms, key=lambda m: m.pga)
        factor = big.scaled_to_pga(parse_accel(args["pga"], "pga", key="pga")).pga / big.pga
        ms = tuple(m.scaled(factor) for m in ms)
    if "scale" in args:
        lam = _froude_scale(args["scale"])
        ms = tuple(m.froude(lam) for m in ms)
    return ms, 0.0


def _record_acc(t: np.ndarray, M: np.ndarray, samples: np.ndarray) -> np.ndarray:
    """u_g''(t), m/s^2, of a record's kernel arguments (``M``, ``samples``) at the times ``t`` (s): the
    compiled ground motion's arithmetic (hazard/motion_kernel.py: segment, record_index, seg_acc) on
    whole arrays, the same values bit for bit (tests/test_crosscheck_speed.py)."""
    out = np.zeros(t.shape)
    ts, te, dt, a = M[MK.MT0], M[MK.MT1], M[MK.MDT], M[MK.MA]
    n = samples.shape[0]
    on = (t >= ts) & (t < te)
    tt = t[on]
    k = np.clip(np.floor((tt - ts) / dt).astype(np.int64), 0, n - 2)
    down = (tt < ts + k * dt) & (k > 0)
    k[down] -= 1
    up = (tt >= ts + (k + 1) * dt) & (k < n - 2)
    k[up] += 1
    tk = ts + k * dt
    out[on] = a * samples[k] + a * (samples[k + 1] - samples[k]) / dt * (tt - tk)
    return out
