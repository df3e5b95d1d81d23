"""The dynamics stage's fragility study: probability of failure against PGA, fixed base and isolated.

The records are a spectrum-compatible set (statue2model.hazard.matching.match_set) matched to the
design spectrum of the project (``[isolator] spectrum``, the hazard of the verdict), ``[dynamics]
fragility_records`` records of ``fragility_duration`` s, seeds 1..N (written to
``dynamics/records/``: record_NN.csv, set.json, spectra.png). Each is scaled to every PGA level
(``fragility_levels``: "auto" = 10 levels, geometric, 0.2-3 x the design PGA; or START:STOP:N) for
every parameter sample (the thesis' theta_R sweep, ``fragility_samples`` values, for the imperfect
model; the model as it is for Housner's, whose curves are then the record-to-record variability
alone, said in the text) and run on a fixed base and, with an isolator design, on the isolator
(statue2model.assessment.fragility.run_fragility). Writes fragility.json, fragility.csv and
fragility.png; returns the report's table, figure, text and the verdict's numbers:

    fragility_median_fixed        median PGA of overturning on a fixed base (m/s^2; None if not fitted)
    fragility_median_isolated     median PGA of failure on the isolator (overturning or capacity exceeded)
    fragility_median_ci_fixed/isolated  its bootstrap band [lo, hi] (an end None: not identified)
    fragility_p_design_fixed/isolated   the fitted probability at the design PGA
    fragility_ratio               median isolated / fixed, with its bootstrap interval fragility_ratio_ci
    fragility_status_fixed/isolated     the fit's status (dynamics.fragility: ok, step, no failures, ...)

Every one of these that can be None has KEY_reason beside it: None when the value is defined
(and complete), else why ("no failure at any level", "one level: spread not identified", "upper
end not identified: 12 of 200 replicates had no failure ..."). No number here is ever nan or inf.
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from ..quantities import G  # m/s^2
AUTO_LEVELS = (0.2, 3.0, 10)
"""'auto' PGA levels: (lowest, highest multiple of the design PGA, number), geometric."""


def levels_for(text: str, pga: float) -> np.ndarray:
    """PGA levels (m/s^2) of ``text``: "auto" (AUTO_LEVELS x ``pga``) or START:STOP:N (accelerations)."""
    if str(text).strip().lower() == "auto":
        lo, hi, n = AUTO_LEVELS
        return pga * np.geomspace(lo, hi, n)
    from ..pipeline.config import fragility_levels

    return fragility_levels(text)


def fragility_section(ctx, d: Path, model, iso, design_spectrum_text: str, executor=None) -> dict:
    """Run the study of the module docstring; returns {'figures', 'tables', 'text', 'warnings', 'data'}."""
    from .fragility import LABELS, FragilityStudy, run_fragility
    from ..hazard.matching import match_set, plot_spectra, set_files
    from ..hazard.motions import write_record_csv
    from ..rocking.sampling import nominal, thesis_theta_R
    from ..io.files import write_json
    from ..hazard.code_spectra import parse_spectrum

    c = ctx.config.dynamics
    target = parse_spectrum(design_spectrum_text)
    pga = target.a_g * target.S
    dur = float(c.fragility_duration)
    rs = match_set(target, n=int(c.fragility_records), seed=1, duration=dur, dt=0.01, band=(0.1, dur / 5))
    rd = d / "records"
    rd.mkdir(parents=True, exist_ok=True)
    for i, m in enumerate(rs.records):
        write_record_csv(rd / f"record_{i + 1:02d}.csv", m)
    names = [f"record_{i + 1:02d}.csv" for i in range(len(rs.records))]
    write_json(rd / "set.json", {**rs.to_dict(), **set_files(rd, names)})     # readable by fragility --records
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
        if cv is None or not cv.fitted:
            return None, None, cv
        return float(cv.median), float(cv.probability(pga)), cv

    m_f, p_f, cf = fit("overturn")
    m_i, p_i, ci = fit("failure_isolated")
    ratio = res.ratio.get("failure") if iso is not None else None
    rows = []
    for name in res.curves:
        m, p_at, cv = fit(name)
        med = "-" if m is None else f"{m / G:.3f} g"
        rows.append([LABELS[name], cv.status if cv.fitted else f"not fitted: {cv.reason}", med,
                     band_text(cv.median_ci if m is not None else None, lv),
                     "-" if m is None else f"{cv.beta:.3f}", "-" if p_at is None else f"{p_at:.3f}",
                     f"{int(cv.n_fail.sum())} / {int(cv.n_trials.sum())}"])
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
                    + (f" ({lo:.2f}-{hi:.2f})" if lo is not None and hi is not None else
                       f" ({ratio['ci_note']})" if ratio.get("ci_note") else "") + ".")
    elif ratio is not None:
        text.append(f"The isolator's ratio of median failure PGAs is {ratio['note']}.")
    figs = [{"path": "fragility.png", "caption": title + "; markers: fraction failed at each level, lines: "
             "lognormal fits, shaded: bootstrap bands"},
            {"path": "records/spectra.png", "caption": "The fragility records' spectra against the design spectrum"}]
    data = fragility_data(res, pga, iso is not None)
    data.update(fragility_runs=n_runs, fragility_records_met=met, fragility_varied=varied)
    return {"figures": figs, "tables": tables, "text": text, "warnings": warnings, "data": data}


def _num(v) -> float | None:
    """A finite float, or None."""
    return float(v) if v is not None and math.isfinite(v) else None


def fragility_data(res, pga: float, isolated: bool) -> dict:
    """The stage's fragility_* numbers of a FragilityResult ``res`` (module docstring): each value
    that can be undefined is None with ``KEY_reason`` beside it (None when it is defined)."""
    data = {"fragility_design_pga": float(pga)}
    for side, name in (("fixed", "overturn"), ("isolated", "failure_isolated")):
        cv = res.curves.get(name)
        if cv is None:
            why = "no isolator designed" if side == "isolated" else "not run"
            med = p = None
            mci, ci_why = None, why
        else:
            why = cv.reason
            med = _num(cv.median) if cv.fitted else None
            p = _num(float(cv.probability(pga))) if cv.fitted else None
            mci = [_num(x) for x in cv.median_ci] if cv.fitted else None
            if mci is not None and all(x is None for x in mci):
                mci = None
            ci_why = (cv.median_ci_note or (None if mci is not None and None not in mci else "no band"))
            if not cv.fitted:
                ci_why = f"median undefined ({why})"
        data.update({f"fragility_median_{side}": med, f"fragility_median_{side}_reason": why,
                     f"fragility_median_ci_{side}": mci, f"fragility_median_ci_{side}_reason": ci_why,
                     f"fragility_p_design_{side}": p, f"fragility_p_design_{side}_reason": why,
                     f"fragility_status_{side}": None if cv is None else cv.status})
    r = res.ratio.get("failure") if isolated else None
    if r is None:
        data.update(fragility_ratio=None, fragility_ratio_reason="no isolator designed", fragility_ratio_ci=None,
                    fragility_ratio_ci_reason="no isolator designed")
    else:
        value = _num(r.get("value"))
        rci = [_num(x) for x in r.get("ci") or (None, None)]
        rci = None if value is None or all(x is None for x in rci) else rci
        data.update(fragility_ratio=value, fragility_ratio_reason=None if value is not None else r.get("note"),
                    fragility_ratio_ci=rci,
                    fragility_ratio_ci_reason=(r.get("ci_note") or (None if rci is not None else "no band")))
    return data


def band_text(ci, levels) -> str:
    """A median's band as table text (g): 'lo-hi g'; an end not identified reads 'below X' /
    'above Y' (the lowest / highest of ``levels``, m/s^2: a finite upper end means a missing lower
    one fell on a replicate that failed everywhere, and vice versa); '-' when there is no band.

    >>> band_text([None, 6.0], [1.0, 9.81]), band_text([4.905, float("inf")], [1.0, 9.81])
    ('below 0.102 g - 0.612 g', '0.500 g - above 1.000 g')
    """
    if ci is None:
        return "-"
    lo, hi = (_num(x) for x in ci)
    if lo is None and hi is None:
        return "-"
    a = f"{lo / G:.3f}" if lo is not None else f"below {levels[0] / G:.3f}"
    b = f"{hi / G:.3f}" if hi is not None else f"above {levels[-1] / G:.3f}"
    return f"{a}-{b} g" if lo is not None and hi is not None else f"{a} g - {b} g"
