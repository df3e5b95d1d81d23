"""Where the statue overturns: the overturning amplitude and band edges of pulses, 2D against 3D.

* :func:`overturn_amplitude_2d`: the smallest amplitude of a one-sine (or one-cosine) pulse that
  overturns the 2D model;
* :func:`boundary_cases`: the overturning boundary of one-sine pulses at each frequency of a small
  grid, every band edge found by a fine 2D amplitude scan and bisection, the 3D edge bisected near
  it: ratio 3D / 2D within BOUNDARY_TARGET (10 %); a Comparison, its runs under
  ``runs['overturning boundaries']``;
* :func:`overturn_grid`: overturn / no-overturn of both on a one-cosine grid (the benchmark's).

Every search narrows its bracket with the one :func:`bisect` (the record ensemble's median
overturning PGA too, on a geometric midpoint: statue2model.crosscheck.ensemble).

Example
-------
>>> lo, hi = bisect(lambda a: a > 0.3, 0.0, 1.0, 1e-3)
>>> round(lo, 4), round(hi, 4)
(0.2998, 0.3)
"""
from __future__ import annotations

import math

import numpy as np

from ..hazard import motions
from ..rocking.engine import simulate as simulate_2d
from ..rocking.model import RockingModel
from .case import Case, Comparison
from .contact import ContactSettings
from .screen import contact_demand_2d, slip_of, validity_screen
from .statue_scene import StatueScene, simulate_statue
from .world import SimSettings

BOUNDARY_TARGET = 0.10
"""Target of each overturning-boundary ratio 3D / 2D (|ratio - 1|)."""
BOUNDARY_FREQS = {True: (1.0, 2.0), False: (0.75, 1.0, 1.5, 2.0, 3.0)}
"""Frequencies (Hz) of the overturning-boundary cases: quick and full."""


def bisect(changed, lo: float, hi: float, rtol: float, geometric: bool = False) -> tuple[float, float]:
    """The bracket [lo, hi] narrowed until hi - lo <= rtol x hi: the midpoint (arithmetic, or
    geometric sqrt(lo hi) if ``geometric``) replaces hi where ``changed(mid)`` holds (the outcome
    is the one at hi), else lo. Returns (lo, hi)."""
    while hi - lo > rtol * hi:
        mid = math.sqrt(lo * hi) if geometric else 0.5 * (lo + hi)
        if changed(mid):
            hi = mid
        else:
            lo = mid
    return lo, hi


def _edge(run, lo: float, hi: float, rtol: float) -> float:
    """The amplitude where run() changes between lo and hi (relative tolerance rtol): the middle of
    the bisected bracket."""
    o_lo = run(lo)
    lo, hi = bisect(lambda a: run(a) != o_lo, lo, hi, rtol)
    return 0.5 * (lo + hi)


def overturn_amplitude_2d(model: RockingModel, freq: float, kind: str = "sine", lo: float | None = None,
                          hi: float | None = None, tol: float = 1e-3, sign: float = 1.0,
                          free_time: float | None = None) -> float:
    """Smallest amplitude (m/s^2) of a one-sine (or one-cosine) pulse ``sign`` x amp of ``freq`` Hz
    that overturns the 2D model, by bisection (relative tolerance ``tol``) between ``lo`` (default the
    smaller uplift acceleration) and ``hi`` (20 x the larger); assumes one band. ``free_time``: s
    simulated after the pulse (default: the engine's). inf if ``hi`` does not overturn."""
    make = motions.sine_pulse if kind == "sine" else motions.cosine_pulse
    p = model.params
    lo = min(p.a_L, p.a_R) if lo is None else lo
    hi = 20 * max(p.a_L, p.a_R) if hi is None else hi

    def overturns(a: float) -> bool:
        m = make(sign * a, freq)
        return simulate_2d(model, m, **({} if free_time is None else {"t_end": m.end + free_time})).overturned

    if not overturns(hi):
        return math.inf
    return bisect(overturns, lo, hi, tol)[1]


def overturn_grid(scene: StatueScene, model: RockingModel, freqs, factors, settings: SimSettings,
                  contact: ContactSettings, free_time: float = 3.0, progress=None) -> dict:
    """Overturn / no-overturn of the 2D ``model`` and the 3D scene on a one-cosine grid: for each
    frequency (Hz) the amplitudes ``factors`` x the 2D minimum overturning amplitude (frequencies
    without 2D overturning below 20 a_uplift are skipped). Every point also gets the 2D model's
    contact demand (:func:`~statue2model.crosscheck.screen.contact_demand_2d`): it is *valid* (its
    rocking-only assumption holds for the 3D contact) if the friction it needs stays below the 3D
    friction coefficient (contact.friction squared: PyBullet multiplies the two bodies') and the
    normal force stays positive. Returns {'rows': [...], 'agree', 'total', 'agree_valid',
    'total_valid', 'skipped'}."""
    mu_3d = contact.friction**2
    rows, skipped = [], []
    for f in freqs:
        f = float(f)
        a_ot = overturn_amplitude_2d(model, f, "cosine")
        if not math.isfinite(a_ot):
            skipped.append(f)
            continue
        for fac in factors:
            m = motions.cosine_pulse(float(fac) * a_ot, f)
            r2 = simulate_2d(model, m, t_end=m.end + free_time)
            d = contact_demand_2d(model, m, m.end + free_time)
            r3 = simulate_statue(scene, m, settings=settings, contact=contact, free_time=free_time, dt_out=0.01)
            valid = d["mu_required"] <= mu_3d and d["n_min"] > 0
            rows.append({"freq": f, "factor": float(fac), "amp_g": float(fac) * a_ot / model.params.g,
                         "overturn_2d": bool(r2.overturned), "overturn_3d": bool(r3.overturned),
                         "agree": bool(r2.overturned) == bool(r3.overturned), "valid_2d": bool(valid),
                         "mu_required": d["mu_required"], "n_min": d["n_min"],
                         "max_pivot_slip": r3.max_pivot_slip, "max_yaw": float(np.abs(r3.yaw).max(initial=0.0)),
                         "max_flight": r3.max_flight, "finite": r3.finite})
        if progress:
            progress(f)
    val = [r for r in rows if r["valid_2d"]]
    return {"rows": rows, "agree": sum(r["agree"] for r in rows), "total": len(rows),
            "agree_valid": sum(r["agree"] for r in val), "total_valid": len(val), "skipped": skipped,
            "mu_3d": mu_3d}


def _edges(amps, outs) -> list[tuple[float, float, str]]:
    """Brackets (a_lo, a_hi, 'up' | 'down') where the outcome changes along the amplitude scan
    ('up': no overturn below, overturn above)."""
    return [(float(amps[i]), float(amps[i + 1]), "up" if outs[i + 1] else "down")
            for i in range(len(amps) - 1) if outs[i] != outs[i + 1]]


def overturn_edges_2d(model: RockingModel, freq: float, lo: float, hi: float, n: int = 120,
                      free_time: float = 2.0, rtol: float = 1e-3) -> list[tuple[float, str]]:
    """Every overturning band edge of one-sine pulses of ``freq`` Hz between amplitudes ``lo`` and
    ``hi`` (m/s^2) for the 2D model: a scan of ``n`` amplitudes, then bisection of each change.
    Returns [(amplitude, 'up' | 'down'), ...] ('up': overturns just above)."""
    def run(a):
        m = motions.sine_pulse(a, freq)
        return bool(simulate_2d(model, m, t_end=m.end + free_time).overturned)

    amps = np.linspace(lo, hi, n)
    outs = [run(a) for a in amps]
    return [(_edge(run, a, b, rtol), d) for a, b, d in _edges(amps, outs)]


def boundary_cases(scene: StatueScene, model: RockingModel, freqs, settings: SimSettings,
                   contact: ContactSettings, *, n3: int = 6, n2: int = 120, span=(0.6, 1.8), max_edges: int = 4,
                   free_time: float = 2.0, rtol: float = 0.01, progress=None) -> Comparison:
    """The overturning boundary of one-sine pulses in 2D and 3D at each frequency of ``freqs`` (Hz).

    2D: the lowest overturning amplitude a1 (geometric scan from the uplift acceleration to 20 x it),
    then every band edge in ``span`` x a1 from a fine scan (``n2`` amplitudes) and bisection. 3D: a
    coarse scan (``n3`` amplitudes over the same range) for its own edges, and for each of the first
    ``max_edges`` 2D edges a bracket at (1 -+ BOUNDARY_TARGET) x the edge, bisected (``rtol``) when the
    3D outcome changes the same way inside it; else the nearest 3D edge of the coarse scan, if any.
    One case per 2D edge: the ratio 3D / 2D (target BOUNDARY_TARGET), screened with the 2D demand just
    below and above the edge and the 3D runs of the bracket. Returns their Comparison (no histories;
    runs['overturning boundaries'][f'{f:g} Hz']: the edges, scans and 3D run count of each frequency)."""
    p = model.params
    cases, out = [], {}
    a_up = min(p.a_L, p.a_R)
    for f in freqs:
        f = float(f)
        cache = {}

        def run3(a, f=f, cache=cache):
            if a not in cache:
                m = motions.sine_pulse(a, f)
                cache[a] = simulate_statue(scene, m, settings=settings, contact=contact, free_time=free_time,
                                           dt_out=0.01)
            return bool(cache[a].overturned)

        def ot2(a, f=f):
            m = motions.sine_pulse(a, f)
            return bool(simulate_2d(model, m, t_end=m.end + free_time).overturned)

        scan = np.geomspace(a_up, 20 * a_up, 160)
        first = next((a for a in scan if ot2(a)), None)
        if first is None:
            out[f"{f:g} Hz"] = {"skipped": "no 2D overturning below 20 x the uplift acceleration"}
            continue
        lo, hi = span[0] * first, span[1] * first
        e2 = overturn_edges_2d(model, f, lo, hi, n=n2, free_time=free_time)
        amps3 = np.linspace(lo, hi, n3)
        e3_coarse = _edges(amps3, [run3(a) for a in amps3])
        rows = []
        for k, (a2, d) in enumerate(e2[:max_edges]):
            b_lo, b_hi = a2 * (1 - BOUNDARY_TARGET), a2 * (1 + BOUNDARY_TARGET)
            o_lo, o_hi = run3(b_lo), run3(b_hi)
            if o_lo != o_hi and (o_hi if d == "up" else o_lo):
                a3, how = _edge(run3, b_lo, b_hi, rtol), "bisected inside +-10 % of the 2D edge"
            else:
                same = [0.5 * (x + y) for x, y, dd in e3_coarse if dd == d]
                a3 = min(same, key=lambda x: abs(x - a2)) if same else None
                how = ("nearest 3D edge of the coarse scan (none inside +-10 %)" if same else
                       f"no 3D '{d}' edge in {lo / p.g:.3f}-{hi / p.g:.3f} g")
            d_lo = contact_demand_2d(model, motions.sine_pulse(0.99 * a2, f), 1 / f + free_time)
            d_hi = contact_demand_2d(model, motions.sine_pulse(1.01 * a2, f), 1 / f + free_time)
            worst = d_lo if (d_lo["mu_required"] > d_hi["mu_required"]) else d_hi
            rs = [cache[b_lo], cache[b_hi]]
            slip = max(slip_of(r) for r in rs)
            yaw = max(float(np.abs(r.yaw).max(initial=0.0)) for r in rs)
            scr = validity_screen(worst["mu_required"], min(d_lo["n_min"], d_hi["n_min"]), slip, yaw,
                                  contact.friction**2)
            name = (f"overturning boundary {f:g} Hz" if k == 0 else
                    f"overturning band edge {k + 1} ({d}) {f:g} Hz")
            ratio = a3 / a2 if a3 is not None else None
            c = Case(name, "overturning amplitude", a2 / p.g, None if a3 is None else a3 / p.g,
                     abs(ratio - 1) if ratio is not None else math.inf, BOUNDARY_TARGET,
                     ratio is not None and abs(ratio - 1) <= BOUNDARY_TARGET, "relative", "g",
                     note=f"one-sine pulse, 2D: fine scan + bisection; 3D: {how}; ratio 3D / 2D = "
                          + ("-" if ratio is None else f"{ratio:.3f}"))
            cases.append(c.screened(scr))
            rows.append({"edge": d, "a_2d_g": a2 / p.g, "a_3d_g": None if a3 is None else a3 / p.g,
                         "ratio": ratio, "screen": scr})
        out[f"{f:g} Hz"] = {"edges_2d_g": [(a / p.g, d) for a, d in e2],
                            "edges_3d_coarse_g": [(0.5 * (x + y) / p.g, d) for x, y, d in e3_coarse],
                            "scan_g": [lo / p.g, hi / p.g], "n3": n3, "runs_3d": len(cache), "cases": rows,
                            "wall_time_3d_s": sum(r.wall_time for r in cache.values())}
        if progress:
            progress(f)
    return Comparison(tuple(cases), runs={"overturning boundaries": out})
