"""Many runs of the rocking model at once (statistics only), in parallel threads.

Each row i is one run: model vector ``P[i]``, motion ``kinds[i]``, ``M[i]``
(all rows share one record's ``samples`` and the restitution tables of one
model), end time ``t_end[i]``. Rows whose motion never exceeds the uplift
limits are not integrated at all. Returns the statistics matrix (n, N_S) of
:mod:`statue2model.dynamics.kernel` (indices ``kernel.S_*``).
"""
from __future__ import annotations

import numpy as np

from . import kernel as K
from .model import RockingModel


def run_batch(model: RockingModel, P: np.ndarray, kinds: np.ndarray, M: np.ndarray, samples: np.ndarray,
              t_end: np.ndarray, rtol: float = 1e-8, quiet: np.ndarray | None = None,
              progress: str | None = None, chunk: int = 500, max_steps: int = 20_000_000) -> np.ndarray:
    """Run every row; ``quiet[i]`` True marks rows known not to move (skipped).
    ``progress``: a label to show a progress bar (tqdm, on stderr), or None."""
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
    samples = np.ascontiguousarray(samples, dtype=float)
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
    bad = S[:, K.S_STATUS] != K.STATUS_OK
    if np.any(bad):
        raise RuntimeError(f"rocking solver did not finish {int(bad.sum())} of {n} runs")
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
