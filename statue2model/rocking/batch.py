"""Many runs of the rocking model at once (statistics only), in parallel threads
of this process or on the workers of an :class:`~statue2model.compute.executors.Executor`.

Each row i is one run: model vector ``P[i]``, motion ``kinds[i]``, ``M[i]``
(all rows share one record's ``samples`` and the restitution tables of one
model), end time ``t_end[i]``. Rows whose motion never exceeds the uplift
limits are not integrated at all. Returns the statistics matrix (n, N_S) of
:mod:`statue2model.rocking.kernel` (indices ``kernel.S_*``).

Rows are independent and each is integrated deterministically, so the matrix is
bit-identical whether the rows run in numba's threads here or in blocks on an
executor's workers.
"""
from __future__ import annotations

import numpy as np

from ..compute.compile import ensure_compiled
from . import kernel as K
from .model import RockingModel


def run_batch(model: RockingModel, P: np.ndarray, kinds: np.ndarray, M: np.ndarray, samples: np.ndarray,
              t_end: np.ndarray, rtol: float = 1e-8, quiet: np.ndarray | None = None,
              progress: str | None = None, chunk: int = 500, max_steps: int = 20_000_000,
              executor=None) -> np.ndarray:
    """Run every row; ``quiet[i]`` True marks rows known not to move (skipped).
    ``progress``: a label to show a progress bar (tqdm, on stderr), or None.

    ``executor``: None runs the rows here, ``chunk`` rows at a time, each block in
    numba's parallel threads; an :class:`~statue2model.compute.executors.Executor` runs
    blocks of rows (:func:`~statue2model.compute.executors.chunks`, about 4 per worker)
    on its workers, one numba thread each (``chunk`` is then unused). Same result."""
    ensure_compiled()          # here, before any worker starts: they load the kernels from the cache
    n = P.shape[0]
    S = np.zeros((n, K.N_S))
    S[:, K.S_T_UPLIFT] = S[:, K.S_T_OVERTURN] = S[:, K.S_T_REST] = np.nan
    S[:, K.S_T_FINAL] = t_end
    todo = np.arange(n) if quiet is None else np.flatnonzero(~quiet)
    eLw, eLe = model.e_L.arrays()
    eRw, eRe = model.e_R.arrays()
    P = np.ascontiguousarray(P, dtype=float)
    M = np.ascontiguousarray(M, dtype=float)
    kinds = np.ascontiguousarray(kinds, dtype=np.int64)
    t_end = np.ascontiguousarray(np.broadcast_to(t_end, (n,)), dtype=float)
    samples = K.as_samples(samples)
    if executor is not None:
        from ..compute.executors import chunks

        blocks = [todo[c] for c in chunks(todo.size, executor)]
        tasks = [(P[idx], eLw, eLe, eRw, eRe, kinds[idx], M[idx], samples, t_end[idx], float(rtol), int(max_steps))
                 for idx in blocks]
        for idx, Sc in zip(blocks, executor.map(_run_rows, tasks, desc=progress)):
            S[idx] = Sc
        return _checked(S)
    _threading_layer()
    bar = None
    if progress:
        from tqdm import tqdm

        bar = tqdm(total=n, desc=progress, unit="run", leave=False)
        bar.update(n - todo.size)
    for start in range(0, todo.size, chunk):
        idx = todo[start:start + chunk]
        Sc = np.zeros((idx.size, K.N_S))
        K.simulate_batch(P[idx], eLw, eLe, eRw, eRe, kinds[idx], M[idx], samples, 0.0, 0.0, t_end[idx],
                         float(rtol), int(max_steps), Sc)
        S[idx] = Sc
        if bar is not None:
            bar.update(idx.size)
    if bar is not None:
        bar.close()
    return _checked(S)


def _run_rows(task: tuple) -> np.ndarray:
    """One block of rows on a worker: ``task`` = (P, eLw, eLe, eRw, eRe, kinds, M,
    samples, t_end, rtol, max_steps) of those rows (shapes as in :func:`run_batch`);
    returns their statistics (rows, N_S). Module level so that it pickles."""
    P, eLw, eLe, eRw, eRe, kinds, M, samples, t_end, rtol, max_steps = task
    ensure_compiled()
    _threading_layer()
    Sc = np.zeros((P.shape[0], K.N_S))
    samples = K.as_samples(samples)        # read-only again (unpickled arrays are writable)
    K.simulate_batch(P, eLw, eLe, eRw, eRe, kinds, M, samples, 0.0, 0.0, t_end, rtol, max_steps, Sc)
    return Sc


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
