"""Benchmark: spectrum-compatible record sets by the Fourier method (SIMQKE-like,
statue2model.hazard.matching.match_set) and by wavelet matching (reqpy-M,
statue2model.hazard.wavelet_matching.match_set_wavelet), side by side in one run.

Targets (7 records of 25 s, 12.5 s pseudo-stationary, dt 0.01 s, seeds 1-7, the same noise):
  * EC8 type 1, ground C, a_g 0.25 g, band 0.15-4.8 s (1.2 T_is of the default isolator,
    T_is = 3.99 s);
  * the same on ground A;
  * NTC 2018, ag 0.2 g, F0 2.4, Tc* 0.3 s, soil C, band 0.15-2 s;
  * a floor spectrum (storey 2 of a 3-storey building of T1 0.4 s over NTC ag 0.1 g, soil C),
    band 0.15-2 s, d_g of the ground.

Per method: the fit (min and max of the mean spectrum / target over the band, records
individually within 0.9-1.3), the realism (PGA / Se(0), PGV, PGD and PGD / d_g with
d_g = 0.025 a_g S T_C T_D, |a(0)| / PGA, |a(end)| / PGA, final v and u, D5-95, Arias) and the
time taken; a column for the Fourier set scaled so that its mean PGA >= Se(0) (EC8
3.2.3.1.2(4)b; factor 1 when it already is), and the ratio wavelet / Fourier.

    .venv/bin/python benchmarks/bench_matching_methods.py [--records N]

Needs the [records] extra (reqpy-M). About a minute (the wavelet sets' 21 records take most
of it; the Fourier times are the best of two runs). The progress bars go to stderr.
"""
from __future__ import annotations

import argparse
import math
import time

import numpy as np

from statue2model.hazard.code_spectra import G, ec8, parse_spectrum
from statue2model.hazard.floor import parse_floor
from statue2model.hazard.matching import match_set
from statue2model.hazard.record_measures import design_ground_displacement, record_measures
from statue2model.hazard.response_spectra import psa
from statue2model.hazard.wavelet_matching import match_set_wavelet

DURATION, DT, SEED = 25.0, 0.01, 1
TARGETS = [
    ("EC8 C", "EC8 type 1, ground C, a_g 0.25 g, band 0.15-4.8 s", ec8(0.25 * G, "C"), (0.15, 4.8)),
    ("EC8 A", "EC8 type 1, ground A, a_g 0.25 g, band 0.15-4.8 s", ec8(0.25 * G, "A"), (0.15, 4.8)),
    ("NTC C", "NTC 2018 ag 0.2 g, F0 2.4, Tc* 0.3 s, soil C, band 0.15-2 s",
     parse_spectrum("ntc2018:ag=0.2g,F0=2.4,Tc=0.3,soil=C"), (0.15, 2.0)),
    ("floor", "floor spectrum: storey 2 of 3 (H 3 storeys, T1 0.4 s) over NTC ag 0.1 g, F0 2.5, Tc* 0.3 s, "
     "soil C, band 0.15-2 s", parse_floor("z=2,H=3,T1=0.4,n=3", parse_spectrum("ntc2018:ag=0.1g,F0=2.5,Tc=0.3,soil=C")),
     (0.15, 2.0)),
]
T_LONG = 10.0
"""s: the mean spectral displacement there, against d_g (beyond every band: what the method
leaves at long periods, where a record's SD tends to its PGD)."""


def ground(target):
    """The ground spectrum under ``target`` (a floor spectrum's ``ground``; d_g is the ground's)."""
    return getattr(target, "ground", None) or target


def summary(s, target, seconds: float, factor: float = 1.0) -> dict:
    """The table's figures of RecordSet ``s``, its records multiplied by ``factor``."""
    se0 = float(target.Se(np.array([0.0]))[0])
    dg = design_ground_displacement(ground(target))
    ms = [record_measures(m) for m in s.records]
    k = np.array([[m[key] for key in ("pga_m_s2", "pgv_m_s", "pgd_m", "arias_m_s")] for m in ms]) * factor
    k[:, 3] *= factor                                     # Arias goes as a^2
    band = s.in_band
    sd_long = (np.mean([psa(m.samples, m.dt, [T_LONG], s.xi)[0] for m in s.records]) * factor
               * (T_LONG / (2 * math.pi)) ** 2)
    each = s.spectra[:, band] * factor / s.target[band]   # each record / target over the band
    mean = each.mean(axis=0)
    return {
        "time, s": seconds,
        "mean/target, min over band": mean.min(),
        "mean/target, max over band": mean.max(),
        "records each within 0.9-1.3": int(np.sum((each.min(axis=1) >= 0.9) & (each.max(axis=1) <= 1.3))),
        "records each >= 0.9": int(np.sum(each.min(axis=1) >= 0.9)),
        "PGA / Se(0), mean": k[:, 0].mean() / se0,
        "PGA / Se(0), max": k[:, 0].max() / se0,
        "PGV m/s, mean": k[:, 1].mean(),
        "PGV m/s, max": k[:, 1].max(),
        "PGD m, mean": k[:, 2].mean(),
        "PGD m, max": k[:, 2].max(),
        "PGD / d_g, mean": k[:, 2].mean() / dg,
        "PGD / d_g, max": k[:, 2].max() / dg,
        f"SD({T_LONG:g} s) / d_g, mean": sd_long / dg,
        "Arias m/s, mean": k[:, 3].mean(),
        "|a(0)| / PGA, max": max(m["a_start_over_pga"] for m in ms),
        "|a(end)| / PGA, max": max(m["a_end_over_pga"] for m in ms),
        "|v(end)| m/s, max": max(abs(m["v_end_m_s"]) for m in ms) * factor,
        "|u(end)| m, max": max(abs(m["d_end_m"]) for m in ms) * factor,
        "D5-95 s, mean": float(np.mean([m["d5_95_s"] for m in ms])),
        "D5-95 s, min": float(np.min([m["d5_95_s"] for m in ms])),
        "PGA scale the method applied": float(getattr(s, "pga_scale", 1.0)),
    }


def fmt(x) -> str:
    if isinstance(x, (int, np.integer)):
        return f"{int(x):d}"
    if x == 0:
        return "0"
    return f"{x:.3g}" if abs(x) >= 1e-3 else f"{x:.1e}"


def ratio(a, b) -> str:
    if isinstance(a, (int, np.integer)) and isinstance(b, (int, np.integer)):
        return f"{a}/{b}"
    if abs(b) < 1e-9 or abs(a) < 1e-9:
        return "-"
    return f"{a / b:.2f}"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--records", type=int, default=7, help="records per set (default 7)")
    n = ap.parse_args().records
    t0 = time.perf_counter()
    import reqpy_M  # noqa: F401  (its import, ~1 s with numba and matplotlib, kept out of the timings)

    print(f"reqpy-M {reqpy_M.__version__} imported in {time.perf_counter() - t0:.1f} s")
    print(f"{n} records of {DURATION:g} s at dt {DT:g} s, seeds {SEED}-{SEED + n - 1} (the same noise for both)\n")
    rows = []
    for label, name, target, band in TARGETS:
        t_f = math.inf
        for _ in range(2):          # the best of two: the first also fills the response-spectrum filter cache
            t = time.perf_counter()
            fourier = match_set(target, n=n, seed=SEED, duration=DURATION, dt=DT, band=band)
            t_f = min(t_f, time.perf_counter() - t)
        t = time.perf_counter()
        wavelet = match_set_wavelet(target, n=n, seed=SEED, duration=DURATION, dt=DT, band=band)
        t_w = time.perf_counter() - t
        se0 = float(target.Se(np.array([0.0]))[0])
        f_pga = float(np.mean([m.pga for m in fourier.records]))
        scale = max(1.0, se0 / f_pga)
        a, b, w = summary(fourier, target, t_f), summary(fourier, target, t_f, scale), summary(wavelet, target, t_w)
        g = ground(target)
        print(f"== {name}: Se(0) = {se0 / G:.4f} g, d_g = {design_ground_displacement(g):.4f} m "
              f"(of the ground; its spectral displacement at T_D {float(g.SDe(g.T_D)):.4f} m)")
        head = ("", "Fourier", "Fourier, PGA >= Se(0)", "wavelet (reqpy)", "wavelet / Fourier")
        print(f"{head[0]:30s} {head[1]:>10s} {head[2]:>22s} {head[3]:>16s} {head[4]:>18s}")
        for key in a:
            print(f"{key:30s} {fmt(a[key]):>10s} {fmt(b[key]):>22s} {fmt(w[key]):>16s} {ratio(w[key], a[key]):>18s}")
        print(f"(Fourier's mean PGA is {f_pga / se0:.3f} Se(0): "
              + ("already >= Se(0), the scaled column is the same set)" if scale == 1.0 else
                 f"scaled x{scale:.3f})") + "\n")
        rows.append((label, a, w))
    print("== summary: wavelet / Fourier")
    print(f"{'target':12s} {'fit min F':>9s} {'fit min W':>9s} {'PGD/d_g F':>9s} {'PGD/d_g W':>9s} "
          f"{'PGV F':>7s} {'PGV W':>7s} {'time F s':>8s} {'time W s':>8s} {'time W/F':>8s}")
    for label, a, w in rows:
        print(f"{label:12s} {a['mean/target, min over band']:9.3f} {w['mean/target, min over band']:9.3f} "
              f"{a['PGD / d_g, mean']:9.2f} {w['PGD / d_g, mean']:9.2f} {a['PGV m/s, mean']:7.3f} "
              f"{w['PGV m/s, mean']:7.3f} {a['time, s']:8.2f} {w['time, s']:8.2f} "
              f"{w['time, s'] / a['time, s']:8.0f}")
    print(f"\ntotal {time.perf_counter() - t0:.0f} s")
    assert all(math.isfinite(v) for _, a, w in rows for v in (*a.values(), *w.values()))


if __name__ == "__main__":
    main()
