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
