"""The design record set and the limit states over it, for the dynamics section of the report:
the code's rules with their values, each record's realism figures, and the limit-state table (the
demand at the design level as the mean over the set, its capacity and their ratio).

Example
-------
>>> from statue2model.hazard.code_spectra import parse_spectrum
>>> from statue2model.hazard.matching import match_set
>>> rs = match_set(parse_spectrum("ec8:ag=0.25g,ground=C"), n=7)
>>> rules_table(rs)["rows"][0][:2], rules_table(rs)["columns"][-1]
(['records', '7'], 'status')
"""
from __future__ import annotations

from ..quantities import G  # m/s^2


def rules_table(rs) -> dict:
    """Every code rule of the design record set ``rs`` with its value, requirement and clause."""
    rows = [[r["rule"], str(r["value"]), r["required"], r["clause"], "ok" if r["ok"] else "FAIL"] for r in rs.rules()]
    return {"title": f"Design record set: {len(rs.records)} artificial records against the code's rules ({rs.window})",
            "columns": ["rule", "value", "required", "clause", "status"], "rows": rows, "status_column": 4}


def realism_table(rs, real: dict) -> dict:
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


def _v(x, unit: str) -> str:
    if x is None:
        return "-"
    if unit == "m/s^2":
        return f"{x / G:.3f} g"
    if unit == "m":
        return f"{x * 1000:.0f} mm"
    if unit == "N":
        return f"{x:.0f} N"
    return f"{x:.3g}"


def limit_state_table(ls: dict) -> dict:
    """The limit states of ``ls`` (LimitStates.to_dict()): base, state, demand, capacity, ratio,
    records exceeding, status; the definitions follow in the text."""
    rows = []
    n = ls["n_records"]
    for r in ls["rows"]:
        rows.append([r["base"], r["title"], _v(r["demand"], r["unit"]), _v(r["capacity"], r["unit"]),
                     "-" if r["ratio"] is None else f"{r['ratio']:.2f}", f"{r['n_exceeding']} / {n}",
                     "EXCEEDED" if r["exceeded"] else "ok"])
    return {"title": f"Limit states at the design level: the {ls['statistic']} over the {n} design records "
                     f"(ratio = demand / capacity; exceeded at 1)",
            "columns": ["base", "limit state", "demand", "capacity", "ratio", "records exceeding", "status"],
            "rows": rows, "status_column": 6}


def design_set_section(rs, ls: dict) -> dict:
    """{'tables', 'text', 'warnings', 'figures'} of the design record set ``rs`` and its limit
    states ``ls`` (a LimitStates.to_dict())."""
    warnings, text = [], []
    failed = [r for r in rs.rules() if not r["ok"]]
    if failed:
        warnings.append("Design record set: " + "; ".join(f"{r['rule']} {r['value']} (required {r['required']}, "
                                                            f"{r['clause']})" for r in failed)
                        + " (records/set.json); the analyses use it anyway.")
    real = rs.realism()
    if real["warning"]:
        warnings.append(f"Design record set: {real['warning']}.")
    warnings.extend(f"Limit states: {w}" for w in ls.get("warnings") or ())
    text.append(f"Limit states ({ls['rule']}):")
    seen = set()
    for r in ls["rows"]:
        if r["name"] not in seen:
            seen.add(r["name"])
            text.append(f"{r['title']}: {r['definition']}")
    figs = [{"path": "records/spectra.png", "caption": "The design record set's spectra against the design target"}]
    return {"tables": [limit_state_table(ls), rules_table(rs), realism_table(rs, real)], "text": text,
            "warnings": warnings, "figures": figs}
