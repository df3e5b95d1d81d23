"""The fragility study's part of the dynamics section of the report: one table per limit state
(full contact, overturning, the isolator's capacity; fixed base and isolated rows, and on the
isolator a row per friction bound when the samples vary it), the figure and the text, from a
:class:`statue2model.assessment.study.StudyRun`. Six columns a table (an A4 page): base, median
PGA, its band, beta with its band, P at the design PGA, failed / runs. A probability whose fit
does not identify the spread is never printed: the cell says "not identified" and why, in short,
and the text below the tables gives the whole reason.

Example
-------
>>> band_text([None, 6.0], [1.0, 9.81]), band_text([4.905, float("inf")], [1.0, 9.81])
('below 0.102 g - 0.612 g', '0.500 g - above 1.000 g')
>>> short_reason("not identified: spread not identified: 1 level with a partial fraction of failures")
'not identified: 1 partial level'
"""
from __future__ import annotations

import math

from ..assessment import states
from ..assessment.fragility import LABELS
from ..quantities import G  # m/s^2

TITLES = {s.id: s.title for s in states.REGISTRY}
BASES = {"fixed": "fixed base", "isolated": "isolated"}


def records_title(rs, target) -> str:
    """The title of the spectra figure (records/spectra.png) of RecordSet ``rs`` matched to ``target``."""
    return f"{len(rs.records)} records matched to {getattr(target, 'code', None) or getattr(target, 'method', 'the target')}"


def short_reason(why: str | None) -> str:
    """A table cell's short form of a p_design_reason (the text keeps the whole reason)."""
    w = (why or "").lower()
    if "no failure" in w:
        return "not identified: no failure" + (f" in {why.rsplit('(', 1)[-1].rstrip(')')}" if "(" in why else "")
    if "failure at every level" in w:
        return "not identified: failed at every level"
    if "jump between adjacent levels" in w:
        return "not identified: a step between levels"
    if "partial fraction" in w:
        k = w.split("spread not identified: ", 1)[-1].split(" ", 1)[0]
        return f"not identified: {k} partial level" + ("" if k == "1" else "s")
    if "profile-likelihood" in w:
        return "not identified: beta's band is open"
    if "band has an end" in w:
        return "not identified: beta's bootstrap band is open"
    if "step" in w:
        return "not identified: a step"
    return "not identified" if why else "-"


def _beta_text(e: dict) -> str:
    if e.get("curve_kind") == "empirical":
        return "- (empirical curve)"
    if e.get("beta") is None:
        return "not identified"
    ci = e.get("beta_ci") or e.get("beta_profile")
    if ci and all(x is not None for x in ci):
        return f"{e['beta']:.3f} [{ci[0]:.3f}-{ci[1]:.3f}]"
    return f"{e['beta']:.3f}"


def _p_text(e: dict) -> str:
    p = e.get("p_design")
    if p is None:
        return short_reason(e.get("p_design_reason"))
    txt = "< 0.001" if p < 1e-3 else "> 0.999" if p > 0.999 else f"{p:.3f}"
    c, ci = e.get("p_design_count"), e.get("p_design_ci")
    if c and ci and None not in ci:
        txt += f" ({c['k']} / {c['n']}; {ci[0]:.2f}-{ci[1]:.2f})"
    return txt


def _row(name: str, e: dict, levels) -> list:
    med = e.get("median")
    return [name, "-" if med is None else f"{med / G:.3f} g", band_text(e.get("median_ci"), levels) if med else "-",
            _beta_text(e), _p_text(e),
            f"{e['n_fail']} / {e['n_trials']} ({e['n_levels']} levels, {e['partial_levels']} partial)"]


def fragility_section(run) -> dict:
    """{'figures', 'tables', 'text', 'warnings'} of a StudyRun ``run``."""
    from ..assessment.study import adaptive_summary, limit_state_data, limit_state_ratios

    res, lv, pga, rs = run.result, run.levels, run.pga, run.records
    warnings, text, tables = [], [], []
    states = limit_state_data(res, pga)
    ratios = limit_state_ratios(res) if run.isolated else {}
    conf = f"{run.study.confidence:.0%}"
    cols = ["base", "median PGA", f"{conf} band", f"beta [{conf} band]", f"P at the design PGA {pga / G:.3f} g",
            "failed / runs (levels)"]
    why_lines = []
    for ls, bases in states.items():
        rows = []
        for base, e in bases.items():
            rows.append(_row(BASES[base], e, e["levels"] or lv))
            if e.get("curve_kind") == "empirical":
                c = e.get("p_design_count") or {}
                why_lines.append(f"{TITLES[ls]}, {BASES[base]}: the empirical curve of the exact uplift thresholds, "
                                 f"not the lognormal ({e.get('choice_reason')}); P at the design PGA is the share "
                                 f"of thresholds at or below it, {c.get('k')} of {c.get('n')}, with its 95 % Wilson "
                                 "interval (the rule: docs/fragility.md).")
            if e.get("p_design") is None:
                why_lines.append(f"{TITLES[ls]}, {BASES[base]} ({LABELS.get(e['curve'], e['curve'])}): "
                                 f"P at the design PGA {e['p_design_reason']}.")
            for word, b in (e.get("by_mu") or {}).items():
                med = b.get("median")
                rows.append([f"  mu {word} {b['mu']:.4g} ({b['n_samples']} samples)",
                             "-" if med is None else f"{med / G:.3f} g", "-",
                             "not identified" if b.get("beta") is None else f"{b['beta']:.3f}",
                             _p_text(b), "-"])
        title = f"Fragility, {TITLES[ls]}"
        r = ratios.get(ls)
        if r and r.get("value") is not None:
            ci = r.get("ci")
            title += (f": median isolated / fixed {r['value']:.2f}"
                      + (f" ({ci[0]:.2f}-{ci[1]:.2f})" if ci and None not in ci else ""))
        tables.append({"title": title, "columns": cols, "rows": rows})
    n_rec = len(rs.records)
    text.append(f"Fragility per limit state (the limit states of the design check): {n_rec} records matched to the "
                f"design spectrum x {run.samples.n} parameter sample(s), on a fixed base ({run.n_runs} runs)"
                + (f" and on the isolator ({run.n_runs_isolated} runs)" if run.isolated else "")
                + f"; lognormal fits by maximum likelihood with bootstrap bands over the {res.bootstrap_unit}; "
                f"uncertain parameters: {run.varied}.")
    ad = adaptive_summary(res)
    if ad:
        added = ", ".join(f"{n} on the {BASES[s]}" for s, n in (ad.get("added") or {}).items())
        text.append(f"Levels: the coarse grid of {len(res.adaptive.get('initial_levels') or [])} PGAs "
                    f"({lv[0] / G:.3f}-{lv[-1] / G:.3f} g in all), then {ad['rounds_run']} of at most "
                    f"{ad['rounds_budget']} rounds of levels added around each curve's median until its spread is "
                    f"identified: {added or 'none added'} (the rule: {ad['rule']}).")
    text.extend(why_lines)
    text.append("A probability at the design PGA is given only where the fit identifies the spread (at least two "
                "levels with a partial fraction of failures and a closed band of beta); elsewhere the table says "
                "why it is not known. The fixed-base uplift stands on each run's exact uplift PGA: its lognormal is kept "
                "only where no threshold is tied and its P lies within the 95 % Wilson interval of the count of "
                "thresholds at the design PGA and at every level run; else the table gives the empirical share "
                "(k / n; its Wilson interval).")
    figs = [{"path": "fragility.png", "caption": "Fragility per limit state (one panel each; fixed base red, isolated "
             "blue): markers the fraction exceeding the limit state at each level run, lines the lognormal fits "
             "where the spread is identified with their bootstrap bands shaded, diamonds the median with its band "
             "where it is not; a step: the empirical curve of the fixed-base uplift thresholds where the lognormal "
             "is not kept, shaded its 95 % Wilson band; dashed: the design PGA"}]
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
