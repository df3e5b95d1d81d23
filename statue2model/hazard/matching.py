"""Spectrum-compatible accelerogram sets (EC8 §3.2.3.1.2, NTC 2018 §3.2.3.6).

:func:`match_set` makes N artificial records (default 7) whose 5 %-damped
pseudo-acceleration spectra match a target: a code spectrum
(:class:`~statue2model.hazard.code_spectra.ElasticSpectrum`) or a floor
spectrum (:class:`~statue2model.hazard.floor.FloorSpectrum`); anything with
``Se(T)`` in m/s^2 (and ``to_dict()``) will do. The method (SIMQKE, Gasparini &
Vanmarcke 1976, as most codes' "artificial accelerograms"):

1. record i starts as stationary Gaussian white noise (``numpy.random.default_rng(seed_i)``,
   seed_i = seed + i) times an envelope: quadratic rise to 0.1 D, constant to 0.6 D
   (the strong phase: 10 s of a 20 s record, EC8 asks for at least 10 s), exponential
   decay to 5 % at D;
2. each iteration computes the spectra of all records
   (:func:`statue2model.hazard.response_spectra.psa`, exact for piecewise-linear input), and
   multiplies each record's Fourier amplitudes by the ratio target / computed,
   interpolated in log frequency between the matching periods (phases kept), then
   re-applies the envelope and removes a baseline (below);
3. it stops when every record is within ``record_tol`` (5 %) of the target at every
   matching period, or after ``iterations``.

Baseline: the acceleration minus env(t) (c0 + c1 t), with c0, c1 such that the
velocity and the displacement (trapezoidal integration) end at zero: the records
start and end at rest, so a shake table can play them (see
:func:`~statue2model.hazard.motions.table_displacement`).

The set is then checked as the codes ask: its mean spectrum within -10 % / +30 %
(``tolerance``) of the target at every period of ``band`` (default 0.1-4 s, the
periods of the statue's rocking and of the isolator; EC8's 0.2 T1-2 T1 is
``band_for_period(T1)``), on a grid twice as dense as the matching one. The band
may reach a fifth of the duration (4 s for 20 s records): longer periods lose too
much to the baseline correction to be matched.

A set on disk is a folder with its ``set.json`` (:func:`set_files` writes its
``files``, ``file_checks`` and ``units``; ``statue2model records`` writes it last, after
its records) and is read by :func:`read_record_set`: exactly the files set.json names,
in its order, each checked against the length and SHA-256 recorded when it was written;
a folder without set.json, a file missing or changed since, is refused with one line,
never filled in from whatever else lies in the folder.

Example
-------
>>> from statue2model.hazard.code_spectra import parse_spectrum
>>> target = parse_spectrum("ntc2018:ag=0.1g,F0=2.5,Tc=0.3,soil=C")
>>> s = match_set(target, n=3, seed=1, duration=10, dt=0.01, band=(0.1, 1.5))
>>> s.met, len(s.records), s.seeds, s.records[0].dt
(True, 3, (1, 2, 3), 0.01)
>>> 0.9 <= s.check()["min_ratio"] and s.check()["max_ratio"] <= 1.3
True
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from .motions import GroundMotion, record
from .response_spectra import POINTS_PER_PERIOD, psa

TOLERANCE = (-0.10, 0.30)
"""Allowed deviation of the set's mean spectrum from the target (EC8 -10 %, NTC 2018 +30 %)."""
DEFAULT_BAND = (0.1, 4.0)
"""Periods (s) the default check covers: the default scan's rocking and isolator periods."""
N_MATCH = 60
"""Matching periods (log-spaced from half the band's start to 1.5 times its end)."""


def band_for_period(T1: float) -> tuple[float, float]:
    """EC8 §3.2.3.1.2 (4)c: the band 0.2 T1 .. 2 T1 of a structure of period T1 (s).

    >>> band_for_period(0.5)
    (0.1, 1.0)
    """
    if not (isinstance(T1, (int, float)) and math.isfinite(T1) and T1 > 0):
        raise InputError(f"the structure's period T1 must be a positive number of s, got {T1!r}")
    return 0.2 * T1, 2.0 * T1


def envelope(t: np.ndarray, duration: float) -> np.ndarray:
    """Amplitude envelope on [0, duration]: (t / t1)^2 to t1 = 0.1 D, 1 to t2 = 0.6 D,
    then exp decay to 0.05 at D."""
    t1, t2 = 0.1 * duration, 0.6 * duration
    decay = math.log(20.0) / (duration - t2)
    return np.where(t < t1, (t / t1) ** 2, np.where(t < t2, 1.0, np.exp(-decay * (t - t2))))


def baseline_correct(acc: np.ndarray, dt: float, env: np.ndarray) -> np.ndarray:
    """acc - env (c0 + c1 t) with v(end) = u(end) = 0 (trapezoidal rule); acc (n,) or (k, n)."""
    n = acc.shape[-1]
    t = np.arange(n) * dt

    def ends(x):   # (v(T), u(T)) of the trapezoidal double integration, along the last axis
        v = np.concatenate([np.zeros(x.shape[:-1] + (1,)), np.cumsum(0.5 * dt * (x[..., 1:] + x[..., :-1]), axis=-1)],
                           axis=-1)
        u_end = np.sum(0.5 * dt * (v[..., 1:] + v[..., :-1]), axis=-1)
        return v[..., -1], u_end

    b0, b1 = env, env * t
    A = np.array([ends(b0), ends(b1)]).T                  # columns: the two baselines
    rhs = np.stack(ends(acc), axis=-1)                     # (..., 2)
    c = np.linalg.solve(A, rhs[..., None])[..., 0] if rhs.ndim > 1 else np.linalg.solve(A, rhs)
    return acc - c[..., :1] * b0 - c[..., 1:2] * b1 if acc.ndim > 1 else acc - c[0] * b0 - c[1] * b1


@dataclass(frozen=True, eq=False)
class RecordSet:
    """A spectrum-compatible set. records: the accelerograms (m/s^2, every dt s);
    periods: (n_T,) the check grid, s; spectra: (n_records, n_T) their PSA, m/s^2;
    target: (n_T,) the target there; band (s) and tolerance (fractions) of the check."""

    records: tuple[GroundMotion, ...]
    seeds: tuple[int, ...]
    periods: np.ndarray
    spectra: np.ndarray
    target: np.ndarray
    band: tuple[float, float]
    tolerance: tuple[float, float]
    xi: float
    iterations: int
    target_info: dict
    target_pga: float = float("nan")

    @property
    def mean(self) -> np.ndarray:
        """(n_T,) the set's mean spectrum, m/s^2."""
        return self.spectra.mean(axis=0)

    @property
    def in_band(self) -> np.ndarray:
        lo, hi = self.band
        return (self.periods >= lo * (1 - 1e-9)) & (self.periods <= hi * (1 + 1e-9))

    def check(self) -> dict:
        """The tolerance check over the band: min and max of mean / target and their periods
        (``met``); also the set's mean PGA over the target's Se(0), which EC8 §3.2.3.1.2 (4)b
        wants >= 1 for a ground spectrum (reported, not part of ``met``)."""
        T = self.periods[self.in_band]
        ratio = self.mean[self.in_band] / self.target[self.in_band]
        i, j = int(np.argmin(ratio)), int(np.argmax(ratio))
        lo, hi = 1 + self.tolerance[0], 1 + self.tolerance[1]
        worst = i if (lo - ratio[i]) / (-self.tolerance[0]) >= (ratio[j] - hi) / self.tolerance[1] else j
        return {"met": bool(ratio[i] >= lo and ratio[j] <= hi),
                "band_s": list(self.band), "tolerance": list(self.tolerance),
                "min_ratio": float(ratio[i]), "period_of_min_s": float(T[i]),
                "max_ratio": float(ratio[j]), "period_of_max_s": float(T[j]),
                "worst_ratio": float(ratio[worst]), "period_of_worst_s": float(T[worst]),
                "mean_pga_over_target_pga": float(np.mean([m.pga for m in self.records]) / self.target_pga)}

    @property
    def met(self) -> bool:
        return self.check()["met"]

    def to_dict(self) -> dict:
        """JSON-ready: the target, the seeds, the check, each record's PGA and worst ratio."""
        per = []
        for s, m, sp in zip(self.seeds, self.records, self.spectra):
            r = sp[self.in_band] / self.target[self.in_band]
            per.append({"seed": int(s), "pga_m_s2": m.pga, "n_samples": int(len(m.samples)), "dt_s": m.dt,
                        "min_ratio": float(r.min()), "max_ratio": float(r.max())})
        return {"target": self.target_info, "n_records": len(self.records), "seeds": [int(s) for s in self.seeds],
                "damping_ratio": self.xi, "iterations": self.iterations,
                "method": "SIMQKE: enveloped Gaussian noise, Fourier amplitudes corrected by target/computed "
                          "spectral ratios, envelope-weighted linear baseline correction",
                "check": self.check(), "mean_pga_m_s2": float(np.mean([m.pga for m in self.records])),
                "records": per, "periods_s": self.periods.tolist(), "target_m_s2": self.target.tolist(),
                "mean_m_s2": self.mean.tolist()}


def _target_values(target, T: np.ndarray) -> np.ndarray:
    if not callable(getattr(target, "Se", None)):
        raise InputError(f"the target spectrum must have an Se(T) method, got {type(target).__name__}")
    v = np.asarray(target.Se(T), dtype=float)
    if v.shape != T.shape or not np.all(np.isfinite(v)) or np.any(v <= 0):
        raise InputError("the target spectrum must be positive and finite over the matching periods")
    return v


def match_set(target, n: int = 7, seed: int = 1, duration: float = 20.0, dt: float = 0.01,
              band: tuple[float, float] = DEFAULT_BAND, tolerance: tuple[float, float] = TOLERANCE,
              iterations: int = 20, record_tol: float = 0.05) -> RecordSet:
    """N records of ``duration`` s every ``dt`` s matched to ``target`` (see the module
    docstring). Damping: the target's ``xi`` (percent) if it has one, else 5 %. Reproducible:
    record i depends only on (target, seed + i, duration, dt, band, iterations)."""
    if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or not 1 <= n <= 100:
        raise InputError(f"number of records must be an integer from 1 to 100, got {n!r}")
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
        raise InputError(f"seed must be a non-negative integer, got {seed!r}")
    for name, v in (("duration", duration), ("dt", dt)):
        if not (isinstance(v, (int, float)) and math.isfinite(v) and v > 0):
            raise InputError(f"record set: {name} must be a positive number of s, got {v!r}")
    try:
        lo, hi = (float(b) for b in band)
    except (TypeError, ValueError):
        raise InputError(f"record set: band must be two periods (s), got {band!r}") from None
    if not (math.isfinite(lo) and math.isfinite(hi) and 0 < lo < hi):
        raise InputError(f"record set: band must be two periods 0 < T0 < T1 (s), got {band!r}")
    if lo < 4 * dt:
        raise InputError(f"record set: dt {dt:g} s is too coarse for periods from {lo:g} s: use dt <= {lo / 4:g} s "
                         f"or a band starting at {4 * dt:g} s or more")
    if hi > duration / 5 * (1 + 1e-9):   # longer periods lose too much to the baseline correction
        raise InputError(f"record set: a {duration:g} s record cannot be matched up to {hi:g} s: use a "
                         f"duration of at least {5 * hi:g} s or a band ending at {duration / 5:g} s or less")
    tol = tuple(float(x) for x in tolerance)
    if not (len(tol) == 2 and -1 < tol[0] < 0 < tol[1]):
        raise InputError(f"record set: tolerance must be (minus, plus) fractions like (-0.1, 0.3), got {tolerance!r}")
    from ..compute import budget

    head = f"a set of {n} records of {duration:g} s at dt {dt:g} s"
    fix = "use fewer records, a shorter duration or a coarser dt"
    budget.check_history(duration, dt, 0, what="each record", head=head, fix=fix)
    xi = float(getattr(target, "xi", 5.0)) / 100.0
    T_match = np.geomspace(max(0.5 * lo, 4 * dt), min(1.5 * hi, duration / 2), N_MATCH)
    T_check = np.geomspace(lo, hi, 2 * N_MATCH)
    npts = int(round(duration / dt)) + 1
    nfft = 1 << int(math.ceil(math.log2(2 * npts)))
    # the peak memory and the time, before anything is allocated (compute/budget.py)
    ks, ks_check = (np.maximum(1, np.ceil(POINTS_PER_PERIOD * dt / T).astype(int)) for T in (T_match, T_check))
    tail = int(math.ceil(0.5 * T_match.max() / dt)) + 2
    budget.check_bytes(budget.record_set_bytes(n, npts, nfft, tail, int(ks.max())), head + " (FFT work arrays and "
                       f"response spectra at {N_MATCH} periods)", fix)
    budget.check_seconds(budget.record_set_seconds(n, npts, nfft, tail, ks, iterations, ks_check),
                         head + f" with up to {iterations} iterations", fix + ", or fewer iterations")
    S_match, S_check = _target_values(target, T_match), _target_values(target, T_check)

    t = np.arange(npts) * dt
    env = envelope(t, duration)
    seeds = tuple(int(seed) + i for i in range(n))
    acc = np.stack([np.random.default_rng(s).standard_normal(npts) for s in seeds]) * env
    f = np.fft.rfftfreq(nfft, dt)
    logf = np.log(np.maximum(f, f[1] * 0.5))
    logf_match = np.log(1.0 / T_match[::-1])                 # ascending frequencies
    from ..compute.executors import progress_bar

    bar = progress_bar(f"matching {n} records", iterations + 2, unit="spectra")   # shown for long work
    try:
        # first pass: scale every record so its spectrum matches on average
        acc *= np.median(S_match / psa(acc, dt, T_match, xi), axis=-1, keepdims=True)
        bar.update(1)
        done = 0
        for done in range(1, iterations + 1):
            acc = baseline_correct(acc, dt, env)
            ratio = S_match / psa(acc, dt, T_match, xi)        # (n, n_T)
            bar.update(1)
            if np.all(np.abs(ratio - 1) <= record_tol):
                break
            R = np.stack([np.interp(logf, logf_match, r[::-1]) for r in ratio])
            acc = np.fft.irfft(np.fft.rfft(acc, nfft, axis=-1) * R, nfft, axis=-1)[:, :npts]
        acc = baseline_correct(acc, dt, env)
        spectra = psa(acc, dt, T_check, xi)
    finally:
        bar.close()
    info = target.to_dict() if callable(getattr(target, "to_dict", None)) else {"kind": type(target).__name__}
    records = tuple(record(a, dt, label=f"matched seed {s}") for a, s in zip(acc, seeds))
    return RecordSet(records, seeds, T_check, spectra, S_check, (lo, hi), tol, xi, done, info,
                     float(_target_values(target, np.array([0.0]))[0]))


# --- a set on disk: set.json names its records ------------------------------------------------
SET_FILE = "set.json"
RECORD_SUFFIXES = (".csv", ".at2")
"""Record files a set may name: CSV (time s, acceleration) and PEER .AT2 (in g)."""


def set_files(folder, names, units: str = "m/s2") -> dict:
    """The keys of set.json that name a set's records ``names`` (files in ``folder``, in
    the set's order): ``files`` (the names), ``file_checks`` ({name: {"bytes", "sha256"}}
    of each file as written now) and ``units`` of the CSV records (m/s2 or g)."""
    from pathlib import Path

    from ..io.files import file_sha256

    folder = Path(folder)
    names = [str(n) for n in names]
    return {"files": names, "units": units,
            "file_checks": {n: {"bytes": (folder / n).stat().st_size, "sha256": file_sha256(folder / n)}
                            for n in names}}


def read_record_set(folder, units: str | None = None, option: str = "--records") -> tuple[list[GroundMotion], dict]:
    """The records of the set in ``folder``: the files its set.json names (``files``, in
    that order), each checked: a plain name in the folder (.csv or .AT2), present, and of
    the length and SHA-256 that ``file_checks`` records (every named file must have one
    when set.json has ``file_checks``; a set.json written by hand may list only ``files``,
    then each is checked to be there). CSV units: ``units``, else set.json's ``units``,
    else m/s2 (a conflict is refused). Returns (records, info): info holds the set.json
    data and ``ignored``, the record files of the folder set.json does not name (not used).
    Refusals are one-line InputErrors naming ``option`` and the folder."""
    from pathlib import Path

    from ..io.files import file_sha256, read_json
    from .motions import read_record

    folder = Path(folder)
    where = f"{option} {folder}"
    if not folder.is_dir():
        raise InputError(f"{where}: not a folder of records")
    sj = folder / SET_FILE
    if not sj.is_file():
        raise InputError(f"{where}: the folder has no {SET_FILE}: a record set is read from the {SET_FILE} that "
                         "`statue2model records` writes after its records (the files it names, with their hashes), "
                         "never from whatever files lie in the folder; for records of your own, list them in "
                         f"{sj} as {{\"files\": [\"a.AT2\", \"b.csv\"]}}")
    data = read_json(sj)
    files = data.get("files") if isinstance(data, dict) else None
    if not isinstance(files, list) or not files or not all(isinstance(n, str) for n in files):
        raise InputError(f"{where}: {SET_FILE} names no record files (a list \"files\" of file names)")
    for n in files:
        if Path(n).name != n or n in (".", "..") or Path(n).suffix.lower() not in RECORD_SUFFIXES:
            raise InputError(f"{where}: {SET_FILE} names {n!r}: a record is a .csv or .AT2 file in the set's folder")
    if len(set(files)) != len(files):
        raise InputError(f"{where}: {SET_FILE} names a file twice")
    n_said = data.get("n_records")
    if n_said is not None and n_said != len(files):
        raise InputError(f"{where}: {SET_FILE} is inconsistent: n_records {n_said!r} but {len(files)} files")
    checks = data.get("file_checks")
    if checks is not None and not isinstance(checks, dict):
        raise InputError(f"{where}: {SET_FILE}: file_checks is not a table of file checks")
    missing = [n for n in files if not (folder / n).is_file()]
    if missing:
        raise InputError(f"{where}: the set is incomplete: {SET_FILE} names {len(files)} records, "
                         f"{len(missing)} missing ({', '.join(missing[:4])}{', ...' if len(missing) > 4 else ''}); "
                         "write the set again (`statue2model records`)")
    if checks is not None:
        changed = []
        for n in files:
            c = checks.get(n)
            if not isinstance(c, dict) or "sha256" not in c or "bytes" not in c:
                raise InputError(f"{where}: {SET_FILE} records no length and hash of {n}: the set is incomplete; "
                                 "write the set again (`statue2model records`)")
            if (folder / n).stat().st_size != c["bytes"] or file_sha256(folder / n) != c["sha256"]:
                changed.append(n)
        if changed:
            raise InputError(f"{where}: {', '.join(changed[:4])}{', ...' if len(changed) > 4 else ''} changed after "
                             f"{SET_FILE} was written (length or SHA-256 differs): not the set it describes; write "
                             "the set again (`statue2model records`)")
    said = data.get("units")
    if said is not None and said not in ("m/s2", "g"):
        raise InputError(f"{where}: {SET_FILE}: units must be m/s2 or g, got {said!r}")
    if units is not None and said is not None and units != said:
        raise InputError(f"{where}: --units {units} but {SET_FILE} says the records are in {said}")
    csv_units = units or said
    records = [read_record(folder / n, units=None if n.lower().endswith(".at2") else csv_units) for n in files]
    ignored = sorted(p.name for p in folder.iterdir()
                     if p.suffix.lower() in RECORD_SUFFIXES and p.name not in set(files))
    return records, {**data, "ignored": ignored}
