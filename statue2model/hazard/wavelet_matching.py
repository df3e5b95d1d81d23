"""Spectrum-compatible record sets by wavelet matching in the time domain (reqpy-M).

:func:`match_set_wavelet` makes the same kind of set as
:func:`statue2model.hazard.matching.match_set` (a
:class:`~statue2model.hazard.matching.RecordSet`, checked the same way) with the
continuous-wavelet-transform method of Suarez & Montejo (2005) and Montejo & Suarez (2013),
as implemented by reqpy-M (MIT, L. A. Montejo; the optional extra ``[records]``):

1. seed i is the seed of :func:`~statue2model.hazard.matching.match_set`: Gaussian noise
   (``numpy.random.default_rng(seed + i)``) high-passed below 1 / (1.5 T_hi)
   (:func:`~statue2model.hazard.matching.high_pass`, T_hi the band's end) times
   :func:`~statue2model.hazard.matching.envelope`; or a record of the user's (``records=``).
   The high-pass matters: the periods beyond the matched ones keep the seed's content, and
   a white seed's long periods, scaled up with the rest, doubled the PGD of a floor-spectrum set;
2. reqpy splits the seed into ``scales`` detail functions (one per period, log-spaced from
   2 dt to at least 10 s), multiplies each by target / computed PSA and sums them again,
   ``iterations`` times, keeping the iteration of least RMS misfit; the matched periods run
   from 2 dt (the Nyquist period: there the spectrum is the PGA, so the set's PGA follows the
   target's Se(0)) to 1.5 times the band's end. A detail function is a wavelet in time, so
   the correction stays where the seed's motion is: no long-period drift is spread over the
   record, which keeps the peak ground displacement near the code's d_g
   (:func:`~statue2model.hazard.record_measures.design_ground_displacement`);
3. the end: reqpy's baseline (``baseline``, default ``"sixth_order"``: the USGS 6th-order
   polynomial fitted to the displacement, removed as its second derivative), a half-cosine
   taper over the first and last ``taper`` s (a(0) = a(end) = 0: no jump for a shake table)
   and reqpy's ``baselinecorrect`` (Suarez & Montejo 2007: it rescales the
   accelerations near the ends, so a(0) stays 0) to end at rest again;
4. as :func:`~statue2model.hazard.matching.match_set`, a set whose mean PGA falls short of
   Se(0) is scaled up to it (EC8 3.2.3.1.2(4)b, ``pga_scale``).

The set's rules, check and realism (``RecordSet.rules()``, ``check()``, ``realism()``) are
statue2model's, with its own response spectra
(:func:`~statue2model.hazard.response_spectra.psa`, exact for piecewise-linear input), never
reqpy's. Cost: about 1.3 s per 25 s record at the defaults (``scales`` 200, ``iterations`` 20),
and ``8 scales n (iterations + 3)`` bytes while a record of n samples is matched (90 MB for
25 s at 0.01 s). docs/records.md compares the two methods.

Example
-------
Three records (a design set has 7) for EC8 ground C, a_g 0.25 g, over 0.15-4.8 s (1.2 T_is
of a 3.99 s isolator):

>>> from statue2model.hazard.code_spectra import ec8, G
>>> s = match_set_wavelet(ec8(0.25 * G, "C"), n=3, seed=1, duration=25, dt=0.01, band=(0.15, 4.8))
>>> s.check()["fit_met"], len(s.records), s.seeds, s.records[0].dt, len(s.records[0].samples)
(True, 3, (1, 2, 3), 0.01, 2501)
>>> [(r["rule"], r["ok"]) for r in s.rules()][:3]
[('records', False), ('duration', True), ('stationary part', True)]
>>> m = s.measures()
>>> all(x["a_start_over_pga"] == 0 and abs(x["v_end_m_s"]) < 1e-3 and abs(x["d_end_m"]) < 1e-3 for x in m)
True
>>> r = s.realism()                                       # d_g = 0.025 a_g S T_C T_D = 0.085 m
>>> round(r["d_g_m"], 3), r["mean_pgd_over_d_g"] < 1.5, r["plausible"]
(0.085, True, True)
"""
from __future__ import annotations

import math
import warnings

import numpy as np

from ..errors import InputError, missing_extra
from ..quantities import G_STANDARD
from .matching import (DEFAULT_BAND, TOLERANCE, RecordSet, check_band, check_tolerance, envelope, high_pass,
                       pga_scale, stationary_part, target_facts, target_values)
from .motions import GroundMotion, record
from .response_spectra import psa

EXTRA = "records"
"""The optional extra of statue2model that installs reqpy-M."""
PACKAGE = "reqpy-M"
SCALES = 200
"""Wavelet scales (periods) of the decomposition: fewer match single records less evenly."""
ITERATIONS = 20
"""Matching iterations (reqpy keeps the one of least RMS misfit)."""
TAPER = 1.0
"""Half-cosine taper at each end, s."""
BASELINE = "sixth_order"
"""reqpy's baseline after matching (then the tapers and ``baselinecorrect``): ``sixth_order``;
``piecewise`` (a spline on the velocity, knots at Arias-intensity percentiles) gave 10-20 %
less PGD on white-noise seeds but cuts the long periods of a record whose energy comes in a short
burst (El Centro 1940 matched to EC8 C: mean / target 0.61 at 3.8 s); ``classic``; ``none``."""
BASELINES = ("sixth_order", "piecewise", "classic", "none")
CHECK_POINTS = 120
"""Periods of the check grid over the band (log-spaced)."""
REST_TOL = 1e-3
"""Largest final |v| / PGV and |u| / PGD of a record said to end at rest."""


class WaveletRecordSet(RecordSet):
    """A :class:`~statue2model.hazard.matching.RecordSet` whose ``to_dict()`` names its method."""

    def to_dict(self) -> dict:
        d = super().to_dict()
        d["method"] = ("CWT spectral matching (reqpy-M, Suarez & Montejo 2005, Montejo & Suarez 2013) of enveloped "
                       "Gaussian noise or given records; reqpy baseline, end tapers, Suarez & Montejo "
                       "2007 baseline correction")
        return d


def _reqpy():
    try:
        import reqpy_M
    except ImportError as exc:
        raise missing_extra(EXTRA, "wavelet spectrum matching", exc) from None
    return reqpy_M


def _positive(name: str, v) -> float:
    if isinstance(v, bool) or not isinstance(v, (int, float, np.integer, np.floating)) or not (
            math.isfinite(v) and v > 0):
        raise InputError(f"wavelet record set: {name} must be a positive number, got {v!r}")
    return float(v)


def _count(name: str, v, lo: int, hi: int) -> int:
    if isinstance(v, bool) or not isinstance(v, (int, np.integer)) or not lo <= v <= hi:
        raise InputError(f"wavelet record set: {name} must be an integer from {lo} to {hi}, got {v!r}")
    return int(v)


def _taper(n: int, k: int) -> np.ndarray:
    w = np.ones(n)
    ramp = 0.5 * (1.0 - np.cos(np.pi * np.arange(k) / k))
    w[:k] = ramp
    w[n - k:] = ramp[::-1]
    return w


def _seeds(records, n, seed, duration, dt, band_end):
    """[(label, seed number, samples)] of the seeds."""
    if records is None:
        n = _count("number of records", n, 1, 100)
        if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
            raise InputError(f"wavelet record set: seed must be a non-negative integer, got {seed!r}")
        if band_end > duration / 5 * (1 + 1e-9):
            raise InputError(f"wavelet record set: a {duration:g} s record cannot be matched up to {band_end:g} s: "
                             f"use a duration of at least {5 * band_end:g} s or a band ending at {duration / 5:g} s "
                             "or less")
        npts = int(round(duration / dt)) + 1
        env = envelope(np.arange(npts) * dt, duration)
        nfft = 1 << int(math.ceil(math.log2(2 * npts)))
        gain = high_pass(np.fft.rfftfreq(nfft, dt), band_end)      # match_set's seed: high-passed noise

        def noise(k):
            x = np.random.default_rng(k).standard_normal(npts)
            return np.fft.irfft(np.fft.rfft(x, nfft) * gain, nfft)[:npts] * env

        return [(f"wavelet-matched seed {int(seed) + i}", int(seed) + i, noise(int(seed) + i)) for i in range(n)]
    try:
        given = list(records)
    except TypeError:
        raise InputError("wavelet record set: records must be a list of sampled records (GroundMotion)") from None
    if not 1 <= len(given) <= 100:
        raise InputError(f"wavelet record set: give 1 to 100 records, got {len(given)}")
    out = []
    for i, m in enumerate(given):
        if not isinstance(m, GroundMotion) or m.kind != "record" or m.samples is None:
            raise InputError(f"wavelet record set: records[{i}] is not a sampled record (GroundMotion of kind record)")
        if getattr(m, "froude_scale", 1.0) != 1.0:
            raise InputError(f"wavelet record set: records[{i}] ({m.label}) is Froude-scaled for a 1:"
                             f"{m.froude_scale:g} prototype: match the full-scale record to the full-scale target")
        if abs(m.dt - dt) > 1e-9 * dt:
            raise InputError(f"wavelet record set: records[{i}] ({m.label}) is sampled every {m.dt:g} s, not dt "
                             f"{dt:g} s: resample it or pass dt={m.dt:g}")
        if band_end > m.duration / 5 * (1 + 1e-9):
            raise InputError(f"wavelet record set: records[{i}] ({m.label}) lasts {m.duration:g} s, too short to be "
                             f"matched up to {band_end:g} s: pad it to {5 * band_end:g} s or end the band at "
                             f"{m.duration / 5:g} s")
        out.append((f"wavelet-matched {m.label}", i, np.asarray(m.samples, dtype=float)))
    return out


def match_set_wavelet(target, n: int = 7, seed: int = 1, duration: float = 25.0, dt: float = 0.01,
                      band: tuple[float, float] = DEFAULT_BAND, tolerance: tuple = TOLERANCE,
                      records=None, scales: int = SCALES, iterations: int = ITERATIONS, taper: float = TAPER,
                      baseline: str = BASELINE, required_band: tuple[float, float] | None = None,
                      band_reason: str | None = None) -> RecordSet:
    """N records of ``duration`` s every ``dt`` s wavelet-matched to ``target`` (anything with
    ``Se(T)`` in m/s^2; see the module docstring), checked over ``band`` (s) against
    ``tolerance`` (fractions) like :func:`~statue2model.hazard.matching.match_set`.

    ``records``: a list of sampled GroundMotions (every ``dt`` s, each at least 5 times the
    band's end long) to match instead of noise; then ``n``, ``seed`` and ``duration`` are not
    used, the set's ``seeds`` are the records' indices and its ``stationary_s`` is nan (not
    known: that rule is reported as not met; JSON writes it as null). Damping: the target's ``xi``
    (percent) if it has one, else 5 %. Reproducible: record i depends only on (target,
    seed + i, duration, dt, band, scales, iterations, taper)."""
    dt = _positive("dt (s)", dt)
    duration = _positive("duration (s)", duration)
    lo, hi = check_band(band, dt, "wavelet record set")
    tol = check_tolerance(tolerance, "wavelet record set")
    try:
        rb = (lo, hi) if required_band is None else tuple(float(x) for x in required_band)
    except (TypeError, ValueError):
        rb = ()
    if len(rb) != 2 or not 0 < rb[0] < rb[1] < math.inf:
        raise InputError(f"wavelet record set: required_band must be two periods 0 < T0 < T1 (s), "
                         f"got {required_band!r}")
    scales = _count("scales", scales, 20, 1000)
    iterations = _count("iterations", iterations, 1, 100)
    taper = _positive("taper (s)", taper)
    if baseline not in BASELINES:
        raise InputError(f"wavelet record set: baseline must be one of {', '.join(BASELINES)}, got {baseline!r}")
    seeds = _seeds(records, n, seed, duration, dt, hi)
    n_max = max(len(a) for _, _, a in seeds)
    if taper > 0.1 * (n_max - 1) * dt:
        raise InputError(f"wavelet record set: a taper of {taper:g} s is more than a tenth of the records")
    from ..compute import budget

    n_even = n_max + n_max % 2
    budget.check_bytes(8.0 * scales * n_even * (iterations + 3), f"wavelet matching of {n_max}-sample records "
                       f"with {scales} scales and {iterations} iterations", "use fewer scales or iterations, a "
                       "shorter duration or a coarser dt")
    # measured: 1.5-2 s for a 25 s record at dt 0.01 s (2502 samples), 200 scales, 20 iterations
    budget.check_seconds(len(seeds) * 1.5e-7 * scales * n_even * (iterations + 5), f"wavelet matching of "
                         f"{len(seeds)} records of {n_max} samples", "use fewer records, scales or iterations, a "
                         "shorter duration or a coarser dt")
    xi = float(getattr(target, "xi", 5.0)) / 100.0
    T_end = 1.5 * hi                                           # matched up to here
    T_grid = np.geomspace(dt, 1.2 * max(10.0, n_even * dt / 4, T_end), 400)   # covers reqpy's scales
    where = "from 0 s to the longest matched period"
    S_grid = target_values(target, T_grid, where) / G_STANDARD             # reqpy works in g
    T_check = np.geomspace(lo, hi, CHECK_POINTS)
    S_check = target_values(target, T_check, where)
    target_pga = float(target_values(target, np.array([0.0]), where)[0])
    rq = _reqpy()
    from ..compute.executors import progress_bar

    out = []
    bar = progress_bar(f"wavelet-matching {len(seeds)} records", len(seeds), unit="records")
    try:
        for label, _, s in seeds:
            npts = len(s)
            t = np.arange(npts) * dt
            with warnings.catch_warnings(record=True) as caught:   # reqpy's notes on clamped ranges, convergence
                warnings.simplefilter("always")
                r = rq.generate_single_component_compatible_record(
                    s / G_STANDARD, 1.0 / dt, T_grid, S_grid, T1PSA=2 * dt, T2PSA=T_end, zi=xi,
                    baseline_method=baseline, NS=scales, nit=iterations)
                a = np.asarray(r["sc"], dtype=float)[:npts] * _taper(npts, max(1, int(round(taper / dt))))
                a, v, u = rq.baselinecorrect(a, t)
            a = np.asarray(a, dtype=float) * G_STANDARD
            v, u = np.asarray(v) * G_STANDARD, np.asarray(u) * G_STANDARD
            if not np.all(np.isfinite(a)) or not np.any(a):
                raise InputError(f"wavelet record set: {label}: the matching gave no finite record (target or seed "
                                 "unsuitable)")
            if abs(v[-1]) > REST_TOL * np.max(np.abs(v)) or abs(u[-1]) > REST_TOL * np.max(np.abs(u)):
                notes = "; ".join(sorted({str(w.message) for w in caught}))[:200]
                raise InputError(f"wavelet record set: {label} does not end at rest after the baseline correction "
                                 f"({notes or 'no convergence'}): use a longer duration")
            out.append((label, a))
            bar.update(1)
    finally:
        bar.close()
    # EC8 3.2.3.1.2(4)b: the set's mean PGA not below Se(0), as match_set does
    scale = pga_scale([np.max(np.abs(a)) for _, a in out], target_pga)
    motions = tuple(record(a * scale, dt, label=label) for label, a in out)
    spectra = np.stack([psa(m.samples, dt, T_check, xi) for m in motions])
    info, d_g, sd_plateau = target_facts(target)
    stationary = stationary_part(duration) if records is None else math.nan
    return WaveletRecordSet(records=motions, seeds=tuple(sd for _, sd, _ in seeds), periods=T_check,
                            spectra=spectra, target=S_check, band=(lo, hi), tolerance=tol, xi=xi,
                            iterations=iterations, target_info=info, target_pga=target_pga, required_band=rb,
                            band_reason=band_reason or f"{rb[0]:g} s to {rb[1]:.4g} s", stationary_s=stationary,
                            pga_scale=float(scale), d_g=d_g, sd_plateau=sd_plateau)
