"""The compiled form of a ground motion that every kernel reads (numba, no Python objects).

A motion is passed to a kernel as ``(kind, M, samples)``: ``kind`` one of M_NONE,
M_HARMONIC, M_RECT, M_RECORD; ``M`` the parameter vector (indices MA..MDT below);
``samples`` the record's accelerations (m/s^2, read-only float64, :func:`as_samples`).
:meth:`statue2model.hazard.motions.GroundMotion.kernel_args` builds the three;
:func:`segment` gives the smooth piece of the motion that holds a time, so that the
integrators (:mod:`statue2model.rocking.kernel`, :mod:`statue2model.isolator.kernel`,
:mod:`statue2model.isolator.coupled_kernel`) never step across a breakpoint.
"""
from __future__ import annotations

import math

import numpy as np
from numba import njit
from numba import types as nt

# --- motion: kind and parameter vector M -----------------------------------
M_NONE, M_HARMONIC, M_RECT, M_RECORD = 0, 1, 2, 3
# M = [amp (or gain of a record), omega, phase, t_start, t_stop, dt]
MA, MW, MPH, MT0, MT1, MDT = range(6)
N_M = 6

SAMPLES = nt.Array(nt.float64, 1, "C", readonly=True)
"""numba type of the samples argument (read-only, so records and pulses share one signature)."""


def as_samples(samples) -> np.ndarray:
    """Motion samples (m/s^2, shape (n,)) as every kernel takes them: float64,
    C-contiguous and read-only (a read-only view, no copy, when the array already is
    float64 and contiguous), so a record and a pulse share one compiled signature."""
    a = np.ascontiguousarray(samples, dtype=np.float64)
    if a.flags.writeable:
        a = a.view()
        a.flags.writeable = False
    return a


@njit(cache=True, inline="always")
def record_index(t, ts, dt, n):
    """The index k of the record piece [ts + k dt, ts + (k + 1) dt) that holds t, clamped to
    0..n - 2 and corrected by one where the floor of (t - ts) / dt rounded across a sample time
    (scalars only: the kernels' helpers take no array)."""
    k = int(math.floor((t - ts) / dt))
    if k < 0:
        k = 0
    if k > n - 2:
        k = n - 2
    if t < ts + k * dt and k > 0:
        k -= 1
    if t >= ts + (k + 1) * dt and k < n - 2:
        k += 1
    return k


@njit(cache=True)
def segment(t, kind, M, samples, seg):
    """Fill ``seg`` = [c0, c1, t0, A, w, ts, phi, u_end] for the smooth piece of the
    motion that holds t (right-continuous); u(t) = c0 + c1 (t - t0) + A sin(w (t - ts) + phi);
    u_end is a record sample's exact value at the end of the piece (nan otherwise).
    Return the end of that piece (inf if none)."""
    for i in range(8):
        seg[i] = 0.0
    seg[7] = np.nan
    if kind == M_NONE:
        return np.inf
    ts = M[MT0]
    te = M[MT1]
    if t < ts:
        return ts
    if t >= te:
        return np.inf
    if kind == M_HARMONIC:
        seg[3] = M[MA]
        seg[4] = M[MW]
        seg[5] = ts
        seg[6] = M[MPH]
        return te
    if kind == M_RECT:
        seg[0] = M[MA]
        return te
    # record: samples at ts + k dt, linear in between
    dt = M[MDT]
    n = samples.shape[0]
    k = record_index(t, ts, dt, n)
    tk = ts + k * dt
    seg[0] = M[MA] * samples[k]
    seg[1] = M[MA] * (samples[k + 1] - samples[k]) / dt
    seg[2] = tk
    seg[7] = M[MA] * samples[k + 1]  # the exact value at the end of the piece
    if k == n - 2:
        return te
    return ts + (k + 1) * dt


@njit(cache=True, inline="always")
def seg_acc(t, seg):
    u = seg[0] + seg[1] * (t - seg[2])
    if seg[3] != 0.0:
        u += seg[3] * math.sin(seg[4] * (t - seg[5]) + seg[6])
    return u


@njit(cache=True)
def ground_acc(t, kind, M, samples):
    """Ground acceleration u_g''(t) in m/s^2 (right-continuous at breakpoints)."""
    seg = np.empty(8)
    segment(t, kind, M, samples, seg)
    return seg_acc(t, seg)
