"""Stability spectrum: the outcome of a pulse over a (frequency, amplitude) grid
(thesis ch. 4.2.1, Fig. 65-68).

Outcome classes: no motion (below the uplift limit), rolling (lifted but never
past theta_side), rocking, overturn mode 1, 2, 3 (0, 1, >= 2 impacts before
overturning). A body that slides before it rocks (uplift needs more than the static
friction mu_s g, :attr:`RockingModel.slides_first`) gets code NOT_APPLICABLE (-2,
"not applicable (slides before it rocks)") at every amplitude above mu_s g; those
points are not integrated (theta_max_over_delta nan).

Example
-------
>>> import numpy as np
>>> from statue2model.geometry.rocking_params import RockingParams
>>> from statue2model.rocking import RockingModel
>>> a1 = RockingParams.rectangular_block(0.0384, 0.2, 1.286)
>>> model = RockingModel.imperfect(a1, 0.65, 0.65, 0.13 * a1.delta_L, 0.13 * a1.delta_R, e_L=0.93, e_R=0.93)
>>> sp = stability_spectrum(model, np.linspace(1, 6, 6), np.linspace(0.05, 1.0, 8) * 9.81)
>>> sp.codes.shape, sp.codes[:, 0].tolist()          # 0.05 g is below 0.65 a = 0.125 g
((6, 8), [0, 0, 0, 0, 0, 0])
>>> sp.outcome(2.0, 1.0 * 9.81)
'overturn mode 1'
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from . import kernel as K
from .batch import NOT_APPLICABLE_CODE, OUTCOMES, outcome_codes, outcome_label, run_batch
from .engine import FREE_TIME, NOT_APPLICABLE
from .model import RockingModel

PULSES = {"cosine": math.pi / 2, "sine": 0.0}
BYTES_PER_RUN = 640
"""Bytes one grid point costs a spectrum: its rows of the batch (about 380 B measured) and its
JSON and CSV output (about 200 B)."""


def check_grid(n_freqs: int, n_amps: int, what: str = "the spectrum grid (frequencies x amplitudes)",
               fix: str = "use fewer frequencies or amplitudes") -> None:
    """Refuse, before any allocation, a grid of ``n_freqs x n_amps`` runs beyond
    :data:`~statue2model.compute.budget.MAX_RUNS` or the memory budget (InputError naming
    ``what`` and ``fix``)."""
    from ..compute.budget import check_runs

    n = float(n_freqs) * float(n_amps)
    check_runs(n, BYTES_PER_RUN, f"{what}: {n_freqs} x {n_amps} = {n:.3g} runs", fix)


@dataclass(frozen=True, eq=False)
class StabilitySpectrum:
    """freqs (n_f,) Hz, amps (n_a,) m/s^2, codes (n_f, n_a) into OUTCOMES,
    theta_max_over_delta, n_impacts (n_f, n_a); pulse name; the model.

    Runs stop as soon as their outcome is decided (see ``early_exit`` of
    :meth:`RockingModel.kernel_vector`), so n_impacts counts the impacts until then.
    ``why``: '' or why some points are NOT_APPLICABLE_CODE (the body slides first)."""

    model: RockingModel
    pulse: str
    freqs: np.ndarray
    amps: np.ndarray
    codes: np.ndarray
    theta_max_over_delta: np.ndarray
    n_impacts: np.ndarray
    n_integrated: int
    why: str = ""

    @property
    def applicable(self) -> np.ndarray:
        """(n_f, n_a) bool: False where the body slides before it rocks."""
        return self.codes != NOT_APPLICABLE_CODE

    def outcome(self, freq: float, amp: float) -> str:
        i = int(np.argmin(np.abs(self.freqs - freq)))
        j = int(np.argmin(np.abs(self.amps - amp)))
        return label(self.codes[i, j])

    def first_amp_where(self, mask: np.ndarray) -> np.ndarray:
        """Smallest amplitude of the grid where ``mask`` (n_freqs, n_amps) holds, per
        frequency (nan if nowhere)."""
        hit = mask.any(axis=1)
        out = np.full(self.freqs.size, np.nan)
        out[hit] = self.amps[np.argmax(mask[hit], axis=1)]
        return out

    def min_overturning_amp(self) -> np.ndarray:
        """Smallest amplitude of the grid that overturns, per frequency (nan if none)."""
        return self.first_amp_where(self.codes >= 3)

    def counts(self) -> dict:
        out = {name: int(np.sum(self.codes == k)) for k, name in enumerate(OUTCOMES)}
        n_na = int(np.sum(self.codes == NOT_APPLICABLE_CODE))
        if n_na:
            out[NOT_APPLICABLE] = n_na
        return out

    def to_dict(self) -> dict:
        return {"pulse": self.pulse, "freqs_hz": self.freqs, "amps_m_s2": self.amps,
                "outcomes": list(OUTCOMES), "codes": self.codes, "theta_max_over_delta": self.theta_max_over_delta,
                "n_impacts": self.n_impacts, "counts": self.counts(), "n_runs": int(self.codes.size),
                "n_integrated": self.n_integrated, "min_overturning_amp_m_s2": self.min_overturning_amp(),
                "applicable": bool(self.applicable.all()), "not_applicable_code": NOT_APPLICABLE_CODE,
                "n_not_applicable": int((~self.applicable).sum()), "why": self.why,
                "notes": self.model.notes, "model": self.model.to_dict()}

    def to_csv(self) -> str:
        lines = ["freq_hz,amp_m_s2,amp_g,outcome_code,outcome,theta_max_over_delta,n_impacts"]
        g = self.model.params.g
        for i, f in enumerate(self.freqs):
            for j, a in enumerate(self.amps):
                c = int(self.codes[i, j])
                tmd = self.theta_max_over_delta[i, j]          # nan (not integrated): an empty cell
                lines.append(f"{f:.6g},{a:.6g},{a / g:.6g},{c},{label(c)},"
                             f"{f'{tmd:.6g}' if np.isfinite(tmd) else ''},{int(self.n_impacts[i, j])}")
        return "\n".join(lines) + "\n"


def label(code: int) -> str:
    """The name of an outcome code, NOT_APPLICABLE included."""
    return NOT_APPLICABLE if code == NOT_APPLICABLE_CODE else outcome_label(code)


def stability_spectrum(model: RockingModel, freqs, amps, pulse: str = "cosine", rtol: float = 1e-7,
                       free_time: float = FREE_TIME, progress: bool = False, executor=None) -> StabilitySpectrum:
    """Run one pulse (``cosine`` or ``sine``, amplitude > 0 toward +x) for every
    (freq, amp) pair; ``free_time`` s of free motion follow each pulse.
    ``executor``: None runs in this process (numba threads), or an
    :class:`~statue2model.compute.executors.Executor` (same result, see :func:`run_batch`)."""
    if pulse not in PULSES:
        raise InputError(f"pulse must be one of {', '.join(PULSES)}, got {pulse!r}")
    freqs = np.asarray(freqs, dtype=float).ravel()
    amps = np.asarray(amps, dtype=float).ravel()
    if freqs.size == 0 or amps.size == 0:
        raise InputError("the spectrum grid is empty")
    if not (np.all(np.isfinite(freqs)) and np.all(freqs > 0)):
        raise InputError("pulse frequencies must be positive numbers of Hz")
    if not (np.all(np.isfinite(amps)) and np.all(amps >= 0)):
        raise InputError("pulse amplitudes must be >= 0 (m/s^2)")
    check_grid(freqs.size, amps.size)
    F, A = np.meshgrid(freqs, amps, indexing="ij")
    n = F.size
    M = np.zeros((n, K.N_M))
    M[:, K.MA] = A.ravel()
    M[:, K.MW] = 2 * np.pi * F.ravel()
    M[:, K.MPH] = PULSES[pulse]
    M[:, K.MT1] = 1.0 / F.ravel()
    kinds = np.full(n, K.M_HARMONIC)
    P = np.tile(model.kernel_vector(early_exit=True), (n, 1))
    lim_up, lim_dn = model.uplift_limits
    quiet = (A.ravel() <= lim_up) & (A.ravel() <= lim_dn)  # a full cycle reaches +amp and -amp
    na = np.array([not model.applicability(a, a)[0] for a in amps])      # slides before it rocks
    na = np.broadcast_to(na, F.shape).ravel()
    quiet = quiet | na
    S = run_batch(model, P, kinds, M, np.zeros(2), M[:, K.MT1] + free_time, rtol=rtol, quiet=quiet,
                  progress="spectrum" if progress else None, executor=executor)
    codes = outcome_codes(S, model.kind == "imperfect")
    codes[na] = NOT_APPLICABLE_CODE
    tmd = np.maximum(S[:, K.S_QMAX_L] / model.params.delta_L, S[:, K.S_QMAX_R] / model.params.delta_R)
    tmd[na] = np.nan
    return StabilitySpectrum(model, pulse, freqs, amps, codes.reshape(F.shape), tmd.reshape(F.shape),
                             S[:, K.S_N_IMP].reshape(F.shape).astype(int), int(n - quiet.sum()),
                             model.sliding_note() if na.any() else "")
