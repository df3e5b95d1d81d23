"""What a run may ask of the machine: a memory budget and a cap on the number of runs.

Every entry point that allocates in proportion to the user's numbers (a history of
``t_end / dt_out`` samples, a spectrum grid of ``freqs x amps`` runs, a sweep of
``levels`` runs over a record of ``samples``) estimates its size first, with the
functions below, and refuses with an :class:`~statue2model.errors.InputError` that
gives the estimate and the option that reduces it, before anything is allocated:
a request beyond the machine ends as one clear line, never as a ``MemoryError``.

* ``MEMORY_BUDGET``: min(4 GiB, half the physical memory), bytes.
* ``MAX_RUNS``: 10^7 integrations in one sweep (about a day of computing on one core).
* ``MAX_SAMPLES``: 5 x 10^7 samples in one time history or one record.
* ``MAX_SECONDS``: a day of computing on one core for one request whose time is
  estimated from its work (a record set: :func:`record_set_seconds`).

The estimates cover the peak, not only the result: a spectrum-compatible record set
(:func:`record_set_bytes`) counts the FFT work arrays of an iteration and the re-sampled
inputs and outputs of the response-spectrum filters over its period grid; a fragility
study (``statue2model.assessment.fragility.check_study``) its records, the rows of its runs
and the records scaled for the isolated runs. They are checked before anything is
allocated, generated or integrated.

Example
-------
>>> human_bytes(4 * 2**40)
'4 TiB'
>>> check_bytes(1000, "a small history", "nothing")
>>> check_history(1e9, 0.01, 40, t_name="--t-end", dt_name="--dt-out")
Traceback (most recent call last):
...
statue2model.errors.InputError: --t-end 1e9 s with output every 0.01 s needs 3.6 TiB for the history (budget ...): use a coarser --dt-out or a shorter --t-end
"""
from __future__ import annotations

import math
import os

from ..errors import InputError

GiB = 2 ** 30


def physical_memory() -> int | None:
    """Bytes of physical memory of this machine (None if the system does not say)."""
    try:
        pages, size = os.sysconf("SC_PHYS_PAGES"), os.sysconf("SC_PAGE_SIZE")
    except (AttributeError, ValueError, OSError):  # pragma: no cover - Windows
        return None
    return int(pages) * int(size) if pages > 0 and size > 0 else None


def _budget() -> int:
    phys = physical_memory()
    return min(4 * GiB, phys // 2) if phys else 4 * GiB


MEMORY_BUDGET = _budget()
"""Largest allocation a run may ask for, bytes: min(4 GiB, half the physical memory)."""
MAX_RUNS = 10 ** 7
"""Most integrations in one sweep (spectrum cells, sweep values x levels)."""
MAX_SAMPLES = 50_000_000
"""Most samples in one time history or one ground-motion record."""
MAX_SECONDS = 86_400.0
"""Longest estimated computing time of one request (a day on one core), s."""
FILTER_SAMPLES_PER_S = 2.0e7
"""Samples per second of one response-spectrum filter pass (scipy lfilter, then |u| and its
maximum) on one core: a low estimate (this machine: about 4.5e7 for lfilter alone)."""
FFT_POINTS_PER_S = 2.0e7
"""Work units per second of FFTs on one core, a unit being nfft log2(nfft) / 10 for one
transform of nfft points (a low estimate: this machine does a 2^21-point pair in 0.13 s)."""


def human_bytes(n: float) -> str:
    """``3.6 TiB``, ``512 MiB``, ``80 B`` (binary units, 2 significant digits)."""
    n = float(n)
    for unit in ("B", "KiB", "MiB", "GiB", "TiB", "PiB", "EiB"):
        if n < 1024 or unit == "EiB":
            return f"{n:.2g} {unit}" if unit != "B" else f"{int(n)} B"
        n /= 1024
    return f"{n:.2g} EiB"  # pragma: no cover


def num(x: float) -> str:
    """A number as a user would type it: ``1e9``, ``0.01``, ``2.5e-05``."""
    return f"{x:g}".replace("e+0", "e").replace("e+", "e").replace("e-0", "e-")


def check_bytes(nbytes: float, what: str, fix: str) -> None:
    """Refuse (InputError) when ``nbytes`` exceeds MEMORY_BUDGET: '``what`` needs X
    (budget Y): ``fix``'."""
    if not nbytes <= MEMORY_BUDGET:          # also catches nan
        raise InputError(f"{what} needs {human_bytes(nbytes)} (budget {human_bytes(MEMORY_BUDGET)}): {fix}")


def history_samples(t_end: float, dt_out: float) -> float:
    """Samples of a history from 0 to ``t_end`` every ``dt_out`` s (a float: may be huge)."""
    return math.floor(t_end / dt_out + 1e-9) + 1.0


def check_history(t_end: float, dt_out: float, bytes_per_sample: float, *, t_name: str = "t_end",
                  dt_name: str = "dt_out", what: str = "the history", head: str | None = None,
                  fix: str | None = None) -> int:
    """Refuse a history of ``t_end / dt_out`` samples of ``bytes_per_sample`` bytes
    beyond the budget (or beyond MAX_SAMPLES samples); returns the number of samples.
    ``t_name``, ``dt_name``: how the caller's user names the two options (or give the
    message's ``head`` and ``fix`` whole)."""
    n = history_samples(t_end, dt_out)
    head = head or f"{t_name} {num(t_end)} s with output every {num(dt_out)} s"
    fix = fix or f"use a coarser {dt_name} or a shorter {t_name}"
    if not n * bytes_per_sample <= MEMORY_BUDGET:
        raise InputError(f"{head} needs {human_bytes(n * bytes_per_sample)} for {what} "
                         f"(budget {human_bytes(MEMORY_BUDGET)}): {fix}")
    if n > MAX_SAMPLES:
        raise InputError(f"{head} gives {n:.3g} samples in {what} (at most {MAX_SAMPLES:.0e}): {fix}")
    return int(n)


def check_runs(n_runs: float, bytes_per_run: float, what: str, fix: str) -> None:
    """Refuse a sweep of ``n_runs`` integrations beyond MAX_RUNS or whose arrays
    (``bytes_per_run`` each) exceed the budget; ``what`` names the sweep, e.g.
    '--freq x --amp: 100000 x 100000 = 1e+10 runs'."""
    if not n_runs <= MAX_RUNS:
        raise InputError(f"{what} is more than {MAX_RUNS:.0e} runs (days of computing; it would also need "
                         f"{human_bytes(n_runs * bytes_per_run)}, budget {human_bytes(MEMORY_BUDGET)}): {fix}")
    check_bytes(n_runs * bytes_per_run, what, fix)


def check_seconds(seconds: float, what: str, fix: str) -> None:
    """Refuse (InputError) work estimated at more than MAX_SECONDS of computing: '``what``
    would take about X (at most Y): ``fix``'."""
    if not seconds <= MAX_SECONDS:
        raise InputError(f"{what} would take about {human_seconds(seconds)} of computing (at most "
                         f"{human_seconds(MAX_SECONDS)}): {fix}")


def human_seconds(s: float) -> str:
    """``45 s``, ``12 min``, ``3.5 h``, ``2.1 days``."""
    s = float(s)
    if not math.isfinite(s):
        return "forever"
    if s < 90:
        return f"{s:.0f} s"
    if s < 5400:
        return f"{s / 60:.0f} min"
    if s < 2 * 86400:
        return f"{s / 3600:.2g} h"
    return f"{s / 86400:.2g} days"


def record_set_bytes(n_records: int, npts: int, nfft: int, tail: int, k_max: int) -> float:
    """Peak bytes of matching ``n_records`` records of ``npts`` samples to a spectrum
    (:func:`statue2model.hazard.matching.match_set`), the largest of its steps:

    * an iteration's FFT step: the stationary signals and the set (8 n npts each), the
      correction factors (8 n F, F = nfft / 2 + 1), the records' spectra and the corrected
      spectra (16 n F each), then the inverse's output (8 n nfft) in their place;
    * a response spectrum (:func:`statue2model.hazard.response_spectra.psa`): the stationary
      signals, the enveloped signals and the baseline-corrected set (8 n npts each, the
      envelope re-applied every iteration) and the set again inside psa, the set
      followed by ``tail`` zeros (8 n N', N' = npts + tail), re-sampled ``k_max`` times
      finer for the shortest periods (M = (N' - 1) k_max + 1 samples: the linear
      interpolation holds four (n, M) arrays at once, plus its (M,) index and weight
      arrays), then the filter's output and its magnitude (8 n M each);
    * the start: the noise rows, their stack and the enveloped set (8 n npts each).
    """
    n, N, F = float(n_records), float(npts), float(nfft // 2 + 1)
    Np = N + float(tail)
    M = (Np - 1.0) * max(1, int(k_max)) + 1.0
    fft = 16 * n * N + 8 * n * F + 32 * n * F
    spectrum = 32 * n * N + 8 * n * Np + (32 * n * M + 32 * M if k_max > 1 else 16 * n * Np)
    start = 24 * n * N
    return max(fft, spectrum, start)


def record_set_seconds(n_records: int, npts: int, nfft: int, tail: int, ks, iterations: int,
                       ks_check=()) -> float:
    """Computing time of a record set at most (s): the response spectra of the first pass
    and of every iteration (each a filter pass over the n records, N' = npts + tail
    samples re-sampled k_j times, at every matching period j: ``ks``), their FFT steps,
    and the final check's spectra (``ks_check``), at FILTER_SAMPLES_PER_S and FFT_POINTS_PER_S."""
    n, Np = float(n_records), float(npts + tail)
    psa = n * Np * float(sum(int(k) for k in ks)) / FILTER_SAMPLES_PER_S
    fft = 2 * n * float(nfft) * max(1.0, math.log2(nfft)) / 10.0 / FFT_POINTS_PER_S
    final = n * Np * float(sum(int(k) for k in ks_check)) / FILTER_SAMPLES_PER_S
    return (iterations + 1) * psa + iterations * fft + final
