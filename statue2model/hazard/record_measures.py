"""What an engineer checks an accelerogram against before trusting it: its peaks, its energy,
its strong-motion duration and whether it starts and ends at rest.

:func:`record_measures` gives, for one sampled record (acceleration a in m/s^2 every dt s,
velocity v and displacement u by the trapezoidal rule from rest, the same integration as
:func:`statue2model.hazard.motions.table_displacement`):

    pga_m_s2         max |a|
    pgv_m_s          max |v|
    pgd_m            max |u|
    arias_m_s        Arias intensity I_A = pi / (2 g) * integral of a^2 dt
    d5_95_s          significant duration: the time between 5 % and 95 % of I_A
    a_start_over_pga |a(0)| / PGA (a record that starts with a jump has 0.1 or more)
    a_end_over_pga   |a(end)| / PGA
    v_end_m_s        v at the end (0 for a record that ends at rest)
    d_end_m          u at the end (0 for a record that ends where it started)

:func:`design_ground_displacement` is EC8 (EN 1998-1 3.2.2.4) and NTC 2018 (3.2.3.3) d_g =
0.025 a_g S T_C T_D of a code ground spectrum: the peak ground displacement the spectrum
implies. A record set whose PGDs are several times d_g carries long-period content the site's
hazard does not (an artefact of matching), and drives an isolator's travel too far.

Example
-------
>>> import numpy as np
>>> from statue2model.hazard.motions import record
>>> t = np.arange(0, 10.0001, 0.01)
>>> r = record_measures(record(np.sin(2 * np.pi * t), 0.01))    # ten one-second cycles of 1 m/s^2
>>> round(r["pga_m_s2"], 3), r["a_start_over_pga"], round(r["d5_95_s"], 2)      # 90 % of the energy: 9 s
(1.0, 0.0, 9.0)
>>> round(r["arias_m_s"], 4), round(math.pi / (2 * 9.80665) * 5, 4)             # pi/(2g) * T/2
(0.8009, 0.8009)
>>> round(r["v_end_m_s"], 6), round(r["d_end_m"], 2)        # v = (1 - cos)/2 pi: u(10) = 10/(2 pi) m
(0.0, 1.59)
>>> from statue2model.hazard.code_spectra import ec8
>>> round(design_ground_displacement(ec8(0.25 * 9.80665, "C")), 4)      # a_g S T_C T_D / 40
0.0846
"""
from __future__ import annotations

import math

import numpy as np

from ..errors import InputError
from ..quantities import G_STANDARD

MEASURES = ("pga_m_s2", "pgv_m_s", "pgd_m", "arias_m_s", "d5_95_s", "a_start_over_pga", "a_end_over_pga",
            "v_end_m_s", "d_end_m")
"""The keys of :func:`record_measures`, in the order a table prints them."""


def _cumtrapz(x: np.ndarray, dt: float) -> np.ndarray:
    return np.concatenate([[0.0], np.cumsum(0.5 * dt * (x[1:] + x[:-1]))])


def measures_of(acc, dt: float) -> dict:
    """:func:`record_measures` of samples ``acc`` (m/s^2, (n,) with n >= 2) every ``dt`` s."""
    a = np.asarray(acc, dtype=float)
    if a.ndim != 1 or a.size < 2 or not np.all(np.isfinite(a)):
        raise InputError("record measures need at least 2 finite samples")
    if not (math.isfinite(dt) and dt > 0):
        raise InputError(f"record measures: dt must be a positive number of s, got {dt!r}")
    v = _cumtrapz(a, dt)
    u = _cumtrapz(v, dt)
    pga = float(np.max(np.abs(a)))
    e = _cumtrapz(a * a, dt)
    arias = math.pi / (2.0 * G_STANDARD) * float(e[-1])
    if e[-1] > 0:
        t = np.arange(a.size) * dt
        t5, t95 = np.interp([0.05 * e[-1], 0.95 * e[-1]], e, t)
        d595 = float(t95 - t5)
    else:
        d595 = 0.0
    return {"pga_m_s2": pga, "pgv_m_s": float(np.max(np.abs(v))), "pgd_m": float(np.max(np.abs(u))),
            "arias_m_s": arias, "d5_95_s": d595,
            "a_start_over_pga": abs(float(a[0])) / pga if pga > 0 else 0.0,
            "a_end_over_pga": abs(float(a[-1])) / pga if pga > 0 else 0.0,
            "v_end_m_s": float(v[-1]), "d_end_m": float(u[-1])}


def record_measures(motion) -> dict:
    """The measures of the module docstring for a sampled GroundMotion (kind "record")."""
    if getattr(motion, "kind", None) != "record" or motion.samples is None:
        raise InputError(f"record measures need a sampled record, got a {getattr(motion, 'kind', '?')} motion")
    return measures_of(motion.samples, motion.dt)


def design_ground_displacement(spectrum) -> float | None:
    """d_g = 0.025 a_g S T_C T_D (m) of a code ground spectrum (EC8 3.2.2.4, NTC 2018 3.2.3.3);
    None for a target without them (a floor spectrum: the codes give no floor displacement)."""
    try:
        a_g, S, T_C, T_D = (float(getattr(spectrum, k)) for k in ("a_g", "S", "T_C", "T_D"))
    except (AttributeError, TypeError, ValueError):
        return None
    return 0.025 * a_g * S * T_C * T_D
