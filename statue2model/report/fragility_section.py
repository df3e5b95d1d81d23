"""The fragility study's part of the dynamics section of the report: its table, figures, text and
warnings, from a :class:`statue2model.assessment.study.StudyRun`.

Example
-------
>>> band_text([None, 6.0], [1.0, 9.81]), band_text([4.905, float("inf")], [1.0, 9.81])
('below 0.102 g - 0.612 g', '0.500 g - above 1.000 g')
"""
from __future__ import annotations

import math

from ..assessment.fragility import LABELS
from ..quantities import G  # m/s^2


def records_title(rs, target) -> str:
    """The title of the spectra figure (records/spectra.png) of RecordSet ``rs`` matched to ``target``."""
    return f"{len(rs.records)} records matched to {getattr(target, 'code', None) or getattr(target, 'method', 'the target')}"


def fragility_section(run) -> dict:
    """{'figures', 'tables', 'text', 'warnings'} of a StudyRun ``run``."""
    res, lv, pga, rs = run.result, run.levels, run.pga, run.records
    warnings, text = [], []
    ratio = res.ratio.get("failure") if run.isolated else None
    rows = []
    for name, cv in res.curves.items():
        m, p_at = (float(cv.median), float(cv.probability(pga))) if cv.fitted else (None, None)
        rows.append([LABELS[name], cv.status if cv.fitted else f"not fitted: {cv.reason}",
                     "-" if m is None else f"{m / G:.3f} g", band_text(cv.median_ci if m is not None else None, lv),
                     "-" if m is None else f"{cv.beta:.3f}", "-" if p_at is None else f"{p_at:.3f}",
                     f"{int(cv.n_fail.sum())} / {int(cv.n_trials.sum())}"])
    title = (f"Fragility: {len(rs.records)} records matched to the design spectrum x {lv.size} PGA levels "
             f"({lv[0] / G:.3f}-{lv[-1] / G:.3f} g) x {run.samples.n} sample(s) = {run.n_runs} runs per base")
    tables = [{"title": title, "columns": ["failure", "fit", "median PGA", f"{run.study.confidence:.0%} band",
                                           "dispersion beta", f"P at the design PGA {pga / G:.3f} g",
                                           "failed / runs"], "rows": rows}]
    text.append(f"Fragility: the probability of failure against PGA, lognormal fits by maximum likelihood with "
                f"bootstrap bands over the {res.bootstrap_unit}; uncertain parameters: {run.varied}.")
    if ratio is not None and ratio.get("value") is not None:
        lo, hi = ratio["ci"]
        text.append(f"The isolator multiplies the median failure PGA by {ratio['value']:.2f}"
                    + (f" ({lo:.2f}-{hi:.2f})" if lo is not None and hi is not None else
                       f" ({ratio['ci_note']})" if ratio.get("ci_note") else "") + ".")
    elif ratio is not None:
        text.append(f"The isolator's ratio of median failure PGAs is {ratio['note']}.")
    figs = [{"path": "fragility.png", "caption": title + "; markers: fraction failed at each level, lines: "
             "lognormal fits, shaded: bootstrap bands"}]
    return {"figures": figs, "tables": tables, "text": text, "warnings": warnings}


def _num(v) -> float | None:
    """A finite float, or None."""
    return float(v) if v is not None and math.isfinite(v) else None


def band_text(ci, levels) -> str:
    """A median's band as table text (g): 'lo-hi g'; an end not identified reads 'below X' /
    'above Y' (the lowest / highest of ``levels``, m/s^2: a finite upper end means a missing lower
    one fell on a replicate that failed everywhere, and vice versa); '-' when there is no band.

    >>> band_text(None, [1.0]), band_text([float("nan"), None], [1.0, 9.81])
    ('-', '-')
    """
    if ci is None:
        return "-"
    lo, hi = (_num(x) for x in ci)
    if lo is None and hi is None:
        return "-"
    a = f"{lo / G:.3f}" if lo is not None else f"below {levels[0] / G:.3f}"
    b = f"{hi / G:.3f}" if hi is not None else f"above {levels[-1] / G:.3f}"
    return f"{a}-{b} g" if lo is not None and hi is not None else f"{a} g - {b} g"
