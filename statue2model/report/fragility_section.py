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
    failed = [r for r in rs.rules() if not r["ok"]]
    if failed:
        warnings.append("Design record set: " + "; ".join(f"{r['rule']} {r['value']} (required {r['required']}, "
                                                            f"{r['clause']})" for r in failed)
                        + " (records/set.json); the curves use it anyway.")
    real = rs.realism()
    if real["warning"]:
        warnings.append(f"Design record set: {real['warning']}.")
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
    tables.append(records_rules_table(rs))
    tables.append(records_realism_table(rs, real))
    figs = [{"path": "fragility.png", "caption": title + "; markers: fraction failed at each level, lines: "
             "lognormal fits, shaded: bootstrap bands"},
            {"path": "records/spectra.png", "caption": "The fragility records' spectra against the design spectrum"}]
    return {"figures": figs, "tables": tables, "text": text, "warnings": warnings}


def records_rules_table(rs) -> dict:
    """Every code rule of the design record set ``rs`` with its value, requirement and clause."""
    rows = [[r["rule"], str(r["value"]), r["required"], r["clause"], "ok" if r["ok"] else "FAIL"] for r in rs.rules()]
    return {"title": f"Design record set: {len(rs.records)} artificial records against the code's rules ({rs.window})",
            "columns": ["rule", "value", "required", "clause", "status"], "rows": rows, "status_column": 4}


def records_realism_table(rs, real: dict) -> dict:
    """Each record's realism figures (PGA, PGV, PGD and PGD / d_g, Arias, D5-95, start and end)."""
    d_g = real["d_g_m"]
    rows = []
    for i, m in enumerate(rs.measures()):
        rows.append([f"record_{i + 1:02d}", f"{m['pga_m_s2'] / G:.3f} g", f"{m['pgv_m_s']:.3f}", f"{m['pgd_m']:.3f}",
                     "-" if not d_g else f"{m['pgd_m'] / d_g:.2f}", f"{m['arias_m_s']:.3f}", f"{m['d5_95_s']:.1f}",
                     f"{m['a_start_over_pga']:.3f}", f"{m['v_end_m_s']:.1e}", f"{m['d_end_m']:.1e}"])
    title = ("Design record set, realism: " + (f"mean PGD {real['mean_pgd_m']:.3f} m = {real['mean_pgd_over_d_g']:.2f}"
             f" x d_g {d_g:.3f} m (EC8 3.2.2.4), limit {real['limit_m']:.3f} m: "
             + ("plausible" if real["plausible"] else "IMPLAUSIBLE") if d_g else "no d_g for this target"))
    return {"title": title, "columns": ["record", "PGA", "PGV m/s", "PGD m", "PGD / d_g", "Arias m/s", "D5-95 s",
                                        "|a(0)| / PGA", "v(end) m/s", "d(end) m"], "rows": rows}


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
