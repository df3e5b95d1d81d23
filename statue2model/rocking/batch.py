"""Many runs of the rocking model at once (statistics only), in parallel threads
of this process or on the workers of an :class:`~statue2model.compute.executors.Executor`.

Each row i is one run: model vector ``P[i]``, motion ``kinds[i]``, ``M[i]``
(all rows share one record's ``samples``), end time ``t_end[i]``, and the restitution
tables of one model, or of the model ``table_row[i]`` of a list (a batch may mix the
samples of e). Rows whose motion never exceeds the uplift limits are not integrated at
all. Returns the statistics matrix (n, N_S) of :mod:`statue2model.rocking.kernel`
(indices ``kernel.S_*``).

Rows are independent and each is integrated deterministically, so the matrix is
bit-identical whether the rows run in numba's threads here (handed out one at a time:
the runs' lengths differ tenfold) or in blocks on an executor's workers.

>>> import numpy as np
>>> from statue2model.geometry.rocking_params import RockingParams
>>> from statue2model.hazard import motions
>>> from statue2model.rocking import RockingModel
>>> block = RockingParams.rectangular_block(0.0384, 0.2, 1.286)       # lifts at 0.192 g
>>> models = [RockingModel.housner(block, e_L=e, e_R=e) for e in (0.8, 0.9)]
>>> kind, M, smp = motions.sine_pulse(3.0, 2.0).kernel_args()
>>> S = run_batch(models, np.array([m.kernel_vector() for m in models]), [kind] * 2, np.tile(M, (2, 1)),
...               smp, [8.0, 8.0], table_row=[0, 1])
>>> S.shape, bool(S[0, K.S_N_IMP] > 0)
((2, 20), True)
"""
from __future__ import annotations

import numpy as np

from ..compute.compile import ensure_compiled
from ..errors import InputError
from . import kernel as K
from .model import RockingModel

THREAD_CHUNK = 1
"""Rows a numba thread takes at a time (dynamic scheduling): a run lasts from a few steps
(overturning at once) to thousands (rocking through the record), so fixed halves of a
block leave one thread idle."""


def restitution_tables(models) -> tuple[np.ndarray, np.ndarray]:
    """(tables, lengths) of the kernel's simulate_batch for a list of models: rows 4j .. 4j+3
    of ``tables`` are model j's e_L table (|theta'| rad/s, e) and e_R table, padded with
    zeros to the longest, ``lengths`` (4 len(models),) their lengths."""
    arrs = []
    for m in models:
        arrs.extend(m.e_L.arrays())
        arrs.extend(m.e_R.arrays())
    width = max(a.size for a in arrs)
    tables = np.zeros((len(arrs), width))
    for i, a in enumerate(arrs):
        tables[i, :a.size] = a
    return tables, np.array([a.size for a in arrs], dtype=np.int64)


def suffix_extremes(samples: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(hi, lo): the largest and smallest of samples[k:] for each k (m/s^2), what the kernel's
    stick search reads to skip the record pieces that cannot lift a body at rest."""
    a = np.asarray(samples, dtype=float)
    if a.size == 0:
        return np.zeros(0), np.zeros(0)
    return (np.ascontiguousarray(np.maximum.accumulate(a[::-1])[::-1]),
            np.ascontiguousarray(np.minimum.accumulate(a[::-1])[::-1]))


def run_batch(model, P: np.ndarray, kinds: np.ndarray, M: np.ndarray, samples: np.ndarray,
              t_end: np.ndarray, rtol: float = 1e-8, quiet: np.ndarray | None = None,
              progress: str | None = None, chunk: int = 500, max_steps: int = 20_000_000,
              executor=None, table_row=None, skip_quiet: bool = True) -> np.ndarray:
    """Run every row; ``quiet[i]`` True marks rows known not to move (skipped).
    ``model``: a RockingModel (its restitution for every row) or a list of them, row i
    taking the restitution of ``model[table_row[i]]`` (P holds each row's model vector).
    ``progress``: a label to show a progress bar (tqdm, on stderr), or None.
    ``skip_quiet`` False: a body at rest reads every record piece (the path before the
    exact skip of the pieces that cannot lift it; the same numbers, for tests).

    ``executor``: None runs the rows here in numba's parallel threads (one block, or
    ``chunk`` rows at a time when a progress bar is shown); an
    :class:`~statue2model.compute.executors.Executor` runs blocks of rows
    (:func:`~statue2model.compute.executors.chunks`, about 4 per worker) on its workers,
    one numba thread each (``chunk`` is then unused). Same result."""
    ensure_compiled()          # here, before any worker starts: they load the kernels from the cache
    n = P.shape[0]
    models = [model] if isinstance(model, RockingModel) else list(model)
    if not models or not all(isinstance(m, RockingModel) for m in models):
        raise InputError("run_batch: model must be a RockingModel or a non-empty list of them")
    if table_row is None:
        if len(models) != 1:
            raise InputError(f"run_batch: table_row (the model of each row) is needed with {len(models)} models")
        table_row = np.zeros(n, dtype=np.int64)
    table_row = np.ascontiguousarray(np.broadcast_to(table_row, (n,)), dtype=np.int64)
    if n and (table_row.min() < 0 or table_row.max() >= len(models)):
        raise InputError(f"run_batch: table_row must lie in 0..{len(models) - 1}")
    S = np.zeros((n, K.N_S))
    S[:, K.S_T_UPLIFT] = S[:, K.S_T_OVERTURN] = S[:, K.S_T_REST] = np.nan
    S[:, K.S_T_FINAL] = t_end
    todo = np.arange(n) if quiet is None else np.flatnonzero(~np.asarray(quiet, dtype=bool))
    tables, lengths = restitution_tables(models)
    P = np.ascontiguousarray(P, dtype=float)
    M = np.ascontiguousarray(M, dtype=float)
    kinds = np.ascontiguousarray(np.broadcast_to(kinds, (n,)), dtype=np.int64)
    t_end = np.ascontiguousarray(np.broadcast_to(t_end, (n,)), dtype=float)
    samples = K.as_samples(samples)
    hi, lo = suffix_extremes(samples) if skip_quiet else (np.zeros(0), np.zeros(0))
    if executor is not None:
        from ..compute.executors import chunks

        blocks = [todo[c] for c in chunks(todo.size, executor)]
        tasks = [(P[idx], tables, lengths, table_row[idx], kinds[idx], M[idx], samples, hi, lo, t_end[idx],
                  float(rtol), int(max_steps)) for idx in blocks]
        for idx, Sc in zip(blocks, executor.map(_run_rows, tasks, desc=progress)):
            S[idx] = Sc
        return _checked(S)
    bar = None
    step = todo.size
    if progress:
        from tqdm import tqdm

        bar = tqdm(total=n, desc=progress, unit="run", leave=False)
        bar.update(n - todo.size)
        step = max(1, int(chunk))
    for start in range(0, todo.size, max(step, 1)):
        idx = todo[start:start + step]
        S[idx] = _simulate_rows(P[idx], tables, lengths, table_row[idx], kinds[idx], M[idx], samples, hi, lo,
                                t_end[idx], float(rtol), int(max_steps))
        if bar is not None:
            bar.update(idx.size)
    if bar is not None:
        bar.close()
    return _checked(S)


def _simulate_rows(P, tables, lengths, table_row, kinds, M, samples, hi, lo, t_end, rtol, max_steps) -> np.ndarray:
    """The kernel's simulate_batch on these rows in numba's threads, handed out THREAD_CHUNK
    rows at a time; returns their statistics (rows, N_S)."""
    from numba import parallel_chunksize

    _threading_layer()
    Sc = np.zeros((P.shape[0], K.N_S))
    if P.shape[0]:
        with parallel_chunksize(THREAD_CHUNK):
            K.simulate_batch(P, tables, lengths, table_row, kinds, M, samples, hi, lo, 0.0, 0.0, t_end, rtol,
                             max_steps, Sc)
    return Sc


def _run_rows(task: tuple) -> np.ndarray:
    """One block of rows on a worker: ``task`` = (P, tables, lengths, table_row, kinds, M,
    samples, hi, lo, t_end, rtol, max_steps) of those rows (shapes as in :func:`run_batch`;
    tables, lengths: :func:`restitution_tables`; hi, lo: :func:`suffix_extremes` or empty);
    returns their statistics (rows, N_S). Module level so that it pickles."""
    P, tables, lengths, table_row, kinds, M, samples, hi, lo, t_end, rtol, max_steps = task
    ensure_compiled()
    samples = K.as_samples(samples)        # read-only again (unpickled arrays are writable)
    return _simulate_rows(P, tables, lengths, table_row, kinds, M, samples, np.ascontiguousarray(hi),
                          np.ascontiguousarray(lo), t_end, rtol, max_steps)


def _checked(S: np.ndarray) -> np.ndarray:
    bad = S[:, K.S_STATUS] != K.STATUS_OK
    if np.any(bad):
        raise RuntimeError(f"rocking solver did not finish {int(bad.sum())} of {S.shape[0]} runs")
    return S


def _threading_layer() -> None:
    """Use OpenMP threads for the parallel batch unless the user chose a layer
    (numba's default would first try a TBB that may be too old and warn)."""
    from numba import config

    if config.THREADING_LAYER == "default":
        config.THREADING_LAYER = "omp"


def outcome_codes(S: np.ndarray, has_transition: bool) -> np.ndarray:
    """0 no motion, 1 rolling, 2 rocking, 3/4/5 overturn mode 1/2/3 (0, 1, >= 2 impacts)."""
    code = np.zeros(S.shape[0], dtype=np.int64)
    moved = S[:, K.S_MOVED] > 0
    full = (S[:, K.S_FULL_UPLIFT] > 0) | (not has_transition)
    code[moved & ~full] = 1
    code[moved & full] = 2
    ot = S[:, K.S_OVERTURNED] > 0
    code[ot] = 3 + np.minimum(S[ot, K.S_IMP_BEFORE_OT], 2).astype(np.int64)
    return code


OUTCOMES = ("no motion", "rolling", "rocking", "overturn mode 1", "overturn mode 2", "overturn mode 3")

NOT_APPLICABLE_CODE = -2
"""Outcome code of a run in which the body slides before it rocks (engine.NOT_APPLICABLE):
the rocking model does not apply there; set by the spectrum and the sweeps, never by the kernel."""


CAPACITY_CODE = -3
"""Outcome code of an isolated run in which the plate passed the isolator's capacity
(isolator/sweeps.py CAPACITY): "isolator capacity exceeded", a failure like overturning."""


def outcome_label(code: int) -> str:
    """The name of an outcome code; CAPACITY_CODE: "isolator capacity exceeded"; another
    negative code marks a run the solver could not finish (isolated sweeps), "solver failed"."""
    if code >= 0:
        return OUTCOMES[int(code)]
    return "isolator capacity exceeded" if code == CAPACITY_CODE else "solver failed"
