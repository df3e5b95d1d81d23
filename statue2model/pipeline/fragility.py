"""The dynamics stage's fragility study: probability of failure against PGA, fixed base and isolated.

The records are a spectrum-compatible set (statue2model.dynamics.matching.match_set) matched to the
design spectrum of the project (``[isolator] spectrum``, the hazard of the verdict), ``[dynamics]
fragility_records`` records of ``fragility_duration`` s, seeds 1..N (written to
``dynamics/records/``: record_NN.csv, set.json, spectra.png). Each is scaled to every PGA level
(``fragility_levels``: "auto" = 10 levels, geometric, 0.2-3 x the design PGA; or START:STOP:N) for
every parameter sample (the thesis' theta_R sweep, ``fragility_samples`` values, for the imperfect
model; the model as it is for Housner's, whose curves are then the record-to-record variability
alone, said in the text) and run on a fixed base and, with an isolator design, on the isolator
(statue2model.dynamics.fragility.run_fragility). Writes fragility.json, fragility.csv and
fragility.png; returns the report's table, figure, text and the verdict's numbers:

    fragility_median_fixed        median PGA of overturning on a fixed base (m/s^2; None if not fitted)
    fragility_median_isolated     median PGA of failure on the isolator (overturning or capacity exceeded)
    fragility_p_design_fixed/isolated   the fitted probability at the design PGA
    fragility_ratio               median isolated / fixed, with its bootstrap interval
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np

G = 9.81
AUTO_LEVELS = (0.2, 3.0, 10)
"""'auto' PGA levels: (lowest, highest multiple of the design PGA, number), geometric."""


def levels_for(text: str, pga: float) -> np.ndarray:
    """PGA levels (m/s^2) of ``text``: "auto" (AUTO_LEVELS x ``pga``) or START:STOP:N (accelerations)."""
    if str(text).strip().lower() == "auto":
        lo, hi, n = AUTO_LEVELS
        return pga * np.geomspace(lo, hi, n)
    from .config import grid

    return grid(text, "[dynamics] fragility_levels", accel=True)


def fragility_section(ctx, d: Path, model, iso, design_spectrum_text: str, executor=None) -> dict:
    """Run the study of the module docstring; returns {'figures', 'tables', 'text', 'warnings', 'data'}."""
    from ..dynamics.fragility import LABELS, FragilityStudy, run_fragility
    from ..dynamics.matching import match_set, plot_spectra
    from ..dynamics.motions import write_record_csv
    from ..dynamics.sampling import nominal, thesis_theta_R
    from ..io.files import write_json
    from ..isolator.design_spectrum import parse_spectrum

    c = ctx.config.dynamics
    target = parse_spectrum(design_spectrum_text)
    pga = target.a_g * target.S
    dur = float(c.fragility_duration)
    rs = match_set(target, n=int(c.fragility_records), seed=1, duration=dur, dt=0.01, band=(0.1, dur / 5))
    rd = d / "records"
    rd.mkdir(parents=True, exist_ok=True)
    for i, m in enumerate(rs.records):
        write_record_csv(rd / f"record_{i + 1:02d}.csv", m)
    write_json(rd / "set.json", rs.to_dict())
    plot_spectra(rs, rd / "spectra.png", f"{len(rs.records)} records matched to {target.code}")
    warnings, text = [], []
    met = bool(rs.check()["met"])
    if not met:
        warnings.append("Fragility records: the set's mean spectrum is outside the tolerance of the design spectrum "
                        "(records/set.json); the curves use it anyway.")
    if model.kind == "imperfect":
        samples = thesis_theta_R(model, int(c.fragility_samples))
        varied = (f"theta_R over the thesis' range (Table 24: {samples.values['theta_R'].min():.4g}-"
                  f"{samples.values['theta_R'].max():.4g} rad, {samples.n} values)")
    else:
        samples = nominal(1)
        varied = ("no model parameter (Housner's model has no theta_R to vary): the curves are the "
                  "record-to-record variability alone")
    lv = levels_for(c.fragility_levels, pga)
    study = FragilityStudy(im="pga", rtol=ctx.config.model.rtol, n_boot=200, seed=0)
    res = run_fragility(model, rs.records, lv, samples, study, isolator=iso, executor=executor)
    res.write_json(d / "fragility.json")
    res.write_csv(d / "fragility.csv")
    res.plot(d / "fragility.png")

    def fit(name):
        cv = res.curves.get(name)
        if cv is None or cv.status not in ("ok", "step"):
            return None, None, cv
        return float(cv.median), float(cv.probability(pga)), cv

    m_f, p_f, cf = fit("overturn")
    m_i, p_i, ci = fit("failure_isolated")
    ratio = res.ratio.get("failure") if iso is not None else None
    rows = []
    for name in res.curves:
        m, p_at, cv = fit(name)
        med = "-" if m is None else f"{m / G:.3f} g"
        band = ("-" if m is None or not all(map(math.isfinite, cv.median_ci)) else
                f"{cv.median_ci[0] / G:.3f}-{cv.median_ci[1] / G:.3f} g")
        p_at = "-" if p_at is None else f"{p_at:.3f}"
        rows.append([LABELS[name], cv.status, med, band, "-" if not math.isfinite(cv.beta) else f"{cv.beta:.3f}",
                     p_at, f"{int(cv.n_fail.sum())} / {int(cv.n_trials.sum())}"])
    n_runs = len(rs.records) * lv.size * samples.n
    title = (f"Fragility: {len(rs.records)} records matched to the design spectrum x {lv.size} PGA levels "
             f"({lv[0] / G:.3f}-{lv[-1] / G:.3f} g) x {samples.n} sample(s) = {n_runs} runs per base")
    tables = [{"title": title, "columns": ["failure", "fit", "median PGA", f"{study.confidence:.0%} band",
                                           "dispersion beta", f"P at the design PGA {pga / G:.3f} g",
                                           "failed / runs"], "rows": rows}]
    text.append(f"Fragility: the probability of failure against PGA, lognormal fits by maximum likelihood with "
                f"bootstrap bands over the {res.bootstrap_unit}; uncertain parameters: {varied}.")
    if ratio is not None and ratio.get("value") is not None:
        lo, hi = ratio["ci"]
        text.append(f"The isolator multiplies the median failure PGA by {ratio['value']:.2f}"
                    + (f" ({lo:.2f}-{hi:.2f})" if lo is not None and hi is not None else "") + ".")
    figs = [{"path": "fragility.png", "caption": title + "; markers: fraction failed at each level, lines: "
             "lognormal fits, shaded: bootstrap bands"},
            {"path": "records/spectra.png", "caption": "The fragility records' spectra against the design spectrum"}]
    data = {"fragility_median_fixed": m_f, "fragility_median_isolated": m_i, "fragility_p_design_fixed": p_f,
            "fragility_p_design_isolated": p_i, "fragility_design_pga": pga,
            "fragility_ratio": None if ratio is None else ratio.get("value"),
            "fragility_ratio_ci": None if ratio is None else ratio.get("ci"),
            "fragility_median_ci_fixed": None if cf is None or m_f is None else [float(x) for x in cf.median_ci],
            "fragility_median_ci_isolated": None if ci is None or m_i is None else [float(x) for x in ci.median_ci],
            "fragility_status_fixed": None if cf is None else cf.status,
            "fragility_status_isolated": None if ci is None else ci.status,
            "fragility_runs": n_runs, "fragility_records_met": met, "fragility_varied": varied}
    return {"figures": figs, "tables": tables, "text": text, "warnings": warnings, "data": data}
