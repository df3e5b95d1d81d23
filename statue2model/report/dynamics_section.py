"""What the report shows of the dynamics stage: its summary, text, warnings, tables and figures
(the stage adds its ``data``), from a :class:`statue2model.assessment.analyses.DynamicsResults`,
its numbers and the fragility study's part (:mod:`statue2model.report.fragility_section`).

On the isolator (spectrum codes may be CAPACITY) 'overturns' and the lowest failing amplitude
or PGA count overturning or the isolator's capacity exceeded, the conservative failure.
"""
from __future__ import annotations

import numpy as np

from ..quantities import G  # m/s^2
from .stage_sections import fig

NO_PART = {"figures": [], "tables": [], "text": [], "warnings": []}


def capacity_text(iso) -> str:
    """The isolator's capacity (the largest plate displacement) in mm, or 'not checked'."""
    return f"{iso.capacity * 1000:.1f} mm" if iso is not None and np.isfinite(iso.capacity) else "not checked"


def spectrum_titles(pulse: str, sp, spi, iso, period) -> tuple[str, str | None]:
    """The titles of spectrum_fixed.png (spectrum ``sp``) and spectrum_isolated.png (``spi`` on
    ``iso`` of design period ``period``, s; None without an isolator)."""
    fixed = f"fixed base: one-{pulse} pulses ({sp.codes.size} runs)"
    if iso is None:
        return fixed, None
    return fixed, (f"on the isolator (T = {period:.2f} s, capacity {capacity_text(iso)}): one-{pulse} pulses "
                   f"({spi.codes.size} runs)")


def spectrum_row(sp, label: str) -> list[str]:
    """One row of the spectra table: moves, overturns (or exceeds the capacity), the lowest
    failing amplitude and the count of each outcome."""
    from ..isolator.sweeps import CAPACITY, is_failure
    from ..rocking.batch import OUTCOMES
    from ..rocking.spectrum import label as code_label

    n = sp.codes.size
    bad = is_failure(sp.codes)
    amin = sp.first_amp_where(bad)
    lowest = np.nanmin(amin) if np.any(np.isfinite(amin)) else None
    moved = (sp.codes >= 1) | (sp.codes == CAPACITY)
    extra = sorted(int(c) for c in np.unique(sp.codes[sp.codes < 0]))
    return [label, f"{np.sum(moved) / n * 100:.1f} %", f"{bad.sum() / n * 100:.1f} %",
            "-" if lowest is None else f"{lowest / G:.3f} g",
            ", ".join([f"{OUTCOMES[k]} {int(np.sum(sp.codes == k))}" for k in range(len(OUTCOMES))
                       if np.any(sp.codes == k)] + [f"{code_label(c)} {int(np.sum(sp.codes == c))}" for c in extra])]


def _spectra(r) -> dict:
    sp, spi, iso = r.spectrum, r.spectrum_isolated, r.iso
    figs = [fig("spectrum_fixed.png", f"Stability spectrum on a fixed base: one-{r.pulse} pulses, "
                                      f"{sp.codes.size} runs")]
    rows, warnings = [spectrum_row(sp, "fixed base")], []
    if iso is not None:
        if not np.isfinite(iso.capacity):
            warnings.append("The isolator design gives no capacity (largest plate displacement): the analyses on "
                            "the isolator do not check whether the balls stay in their grooves.")
        figs.append(fig("spectrum_isolated.png", f"Stability spectrum of the statue on the isolator (coupled plate "
                                                 f"+ statue), the same {spi.codes.size} pulses; 'isolator capacity "
                                                 f"exceeded': the plate moved more than {capacity_text(iso)}"))
        rows.append(spectrum_row(spi, "on the isolator"))
    freqs, amps = r.freqs, r.amps
    table = {"title": f"Stability spectra: {freqs[0]:g}-{freqs[-1]:g} Hz x {amps[0] / G:.3g}-{amps[-1] / G:.3g} g",
             "columns": ["base", "moves", "overturns (on the isolator: or exceeds its capacity)",
                         "lowest failing amplitude (overturning; on the isolator: or capacity exceeded)",
                         "outcomes"],
             "rows": rows}
    return {"figures": figs, "tables": [table], "text": [], "warnings": warnings}


def _variability_rows(r, data: dict) -> list[list[str]]:
    sw, swi = r.variability, r.variability_isolated
    ot_f = data["first_overturn_pga_fixed"]
    rows = [["fixed base", "none" if ot_f is None else f"{ot_f / G:.3f} g", "-",
             f"{sw.summary()['p50']:.3f}", f"{sw.summary()['max']:.3f}"]]
    if swi is not None:
        ot_i, cap_i = data["first_overturn_only_pga_isolated"], data["first_capacity_pga_isolated"]
        fail_i, s_i = data["first_failure_pga_isolated"], swi.summary()
        what = ("" if fail_i is None else " (capacity exceeded)" if fail_i == cap_i and fail_i != ot_i else
                " (overturning)")
        rows.append(["on the isolator", "none" if fail_i is None else f"{fail_i / G:.3f} g{what}",
                     "none" if cap_i is None else f"{cap_i / G:.3f} g", f"{s_i['p50']:.3f}", f"{s_i['max']:.3f}"])
    return rows


def _variability(r, data: dict, rows: list) -> dict:
    swi, pgas = r.variability_isolated, r.pgas
    text = []
    if swi is not None and not swi.run.all():
        text.append(f"Variability on the isolator: the capacity ({capacity_text(r.iso)}) was exceeded at "
                    f"{data['first_capacity_pga_isolated'] / G:.3f} g, so the {int((~swi.run).sum())} higher PGAs "
                    "were not run (variability.json: isolated.run, not_run_pga_m_s2).")
    figs = [fig("variability.png", f"Variability: {r.motion.label} scaled to {pgas.size} PGAs, fixed base "
                                   "and on the isolator" + ("" if swi is None or swi.run.all() else
                                                            " (on the isolator: stopped at the first PGA "
                                                            "that exceeds the capacity)"))]
    table = {"title": f"Variability over PGA {pgas[0] / G:.3g}-{pgas[-1] / G:.3g} g",
             "columns": ["base", "lowest failing PGA of the grid (overturning; on the isolator: or capacity "
                         "exceeded)", "capacity exceeded from", "median |theta|max/delta",
                         "max |theta|max/delta"],
             "rows": rows}
    return {"figures": figs, "tables": [table], "text": text, "warnings": []}


def travel_text(r) -> str:
    """The plate's largest travel in the time history, of the capacity (and when it was exceeded)."""
    coupled = r.history_coupled
    travel = (f"{coupled.u_max * 1000:.1f} mm of {capacity_text(r.iso)}" if np.isfinite(r.iso.capacity) else
              f"{coupled.u_max * 1000:.1f} mm (capacity not checked)")
    if coupled.capacity_exceeded:
        travel += f"; exceeded at t = {coupled.t_capacity:.3f} s"
    return travel


def _history(r) -> dict:
    fixed, coupled, motion = r.history, r.history_coupled, r.motion
    rows = [["fixed base", fixed.outcome, f"{fixed.theta_max_over_delta:.4f}", f"{motion.pga / G:.3f} g", "-", "-"]]
    warnings = []
    if r.iso is not None:
        rows.append(["on the isolator", coupled.outcome, f"{coupled.theta_max_over_delta:.4f}",
                     f"{coupled.acc_abs_max / G:.3f} g", f"{coupled.efficiency:.3f}", travel_text(r)])
        if coupled.capacity_exceeded:
            warnings.append(f"On the isolator under {motion.label}: the plate passes the capacity "
                            f"{capacity_text(r.iso)} at t = {coupled.t_capacity:.3f} s (a ball leaves its groove or "
                            "the top plate tips); the run stops there: a failure, as bad as overturning.")
    figs = [fig("history.png", f"Time history under {motion.label}: rotation on a fixed base and on the "
                               "isolator; ground and plate accelerations")]
    table = {"title": f"Time history: {motion.label}",
             "columns": ["base", "outcome", "|theta|max/delta", "peak acceleration felt", "efficiency",
                         "plate travel (of the capacity)"],
             "rows": rows}
    return {"figures": figs, "tables": [table], "text": [], "warnings": warnings}


def _skipped(r, isolated_wanted: bool, isolator_enabled: bool) -> dict:
    out = {"text": [], "warnings": []}
    if isolated_wanted and r.iso is None and isolator_enabled:
        out["warnings"].append("The analyses on the isolator were skipped: no passing isolator design "
                               "(see the isolator section).")
    elif isolated_wanted and r.iso is None:
        out["text"].append("The analyses on the isolator were skipped: no passing isolator design ([isolator] "
                           "enabled = false).")
    return out


def _solver_warnings(r) -> list[str]:
    from ..isolator.sweeps import FAILED

    runs = [("fixed-base spectrum", r.spectrum.codes), ("fixed-base variability", r.variability.codes)]
    if r.iso is not None:
        runs += [("isolated spectrum", r.spectrum_isolated.codes), ("isolated variability",
                                                                    r.variability_isolated.codes)]
    return [f"{what}: the solver could not finish {int(np.sum(codes == FAILED))} of {codes.size} "
            "runs (counted as 'solver failed', not as an outcome)"
            for what, codes in runs if codes is not None and np.any(codes == FAILED)]


def _intro(r) -> list[str]:
    lim_up, lim_dn = r.model.uplift_limits
    text = [f"Rocking model: {r.model.kind}; the statue lifts at +{lim_up / G:.4f} g / -{lim_dn / G:.4f} g."]
    if r.iso is not None:
        text.append(f"On the isolator, every run watches the plate displacement against the capacity "
                    f"({capacity_text(r.iso)}: the largest before a ball leaves its groove or the top plate tips); a "
                    "run that passes it stops with the outcome 'isolator capacity exceeded', counted as a failure "
                    "like overturning: the isolated 'overturns' and 'lowest failing PGA' figures are the lower of "
                    "the two.")
    return text


def _summary(r, data: dict, var_rows: list) -> dict:
    fixed, coupled, label = r.history, r.history_coupled, r.motion.label
    summary = {"spectrum overturns (fixed)": f"{data['spectrum_overturn_fraction_fixed'] * 100:.1f} % of pulses",
               "lowest overturning PGA (fixed)": var_rows[0][1],
               f"{label} (fixed)": f"{fixed.outcome}, |theta|max/delta {fixed.theta_max_over_delta:.3g}"}
    if r.iso is not None:
        n_cap_sp = data["capacity_exceeded_points_isolated"]["spectrum"]
        summary["spectrum overturns or exceeds capacity (isolated)"] = (
            f"{data['spectrum_overturn_fraction_isolated'] * 100:.1f} % of pulses (overturn "
            f"{data['spectrum_overturn_only_fraction_isolated'] * 100:.1f} %, capacity exceeded "
            f"{data['capacity_exceeded_fraction_isolated'] * 100:.1f} %: {n_cap_sp} pulses)")
        summary["lowest failing PGA (isolated: overturning or capacity exceeded)"] = var_rows[1][1]
        summary["isolator capacity"] = capacity_text(r.iso)
        summary[f"{label} (isolated)"] = (f"{coupled.outcome}, efficiency {coupled.efficiency:.3f}, "
                                          f"plate travel {travel_text(r)}")
    if data.get("fragility_runs"):
        for side, key in (("fixed", "fragility: median overturning PGA (fixed)"),
                          ("isolated", "fragility: median failure PGA (isolated)")):
            med = data.get(f"fragility_median_{side}")
            if side == "fixed" or r.iso is not None:
                summary[key] = (f"not fitted ({data.get(f'fragility_median_{side}_reason') or 'undefined'})"
                                if med is None else f"{med / G:.3f} g")
    return summary


def dynamics_section(r, data: dict, fragility: dict | None = None, isolated_wanted: bool = False,
                     isolator_enabled: bool = True) -> dict:
    """{summary, text, warnings, tables, figures} of the dynamics stage: DynamicsResults ``r``,
    its numbers ``data`` (with the fragility study's), the fragility part (or None: not run);
    ``isolated_wanted``: [dynamics] isolated; ``isolator_enabled``: the isolator stage is on."""
    var_rows = _variability_rows(r, data)
    spectra, var, hist = _spectra(r), _variability(r, data, var_rows), _history(r)
    frag, skipped = fragility or NO_PART, _skipped(r, isolated_wanted, isolator_enabled)
    return {"summary": _summary(r, data, var_rows),
            "text": _intro(r) + var["text"] + frag["text"] + skipped["text"],
            "warnings": (spectra["warnings"] + hist["warnings"] + frag["warnings"] + skipped["warnings"]
                         + _solver_warnings(r)),
            "tables": spectra["tables"] + var["tables"] + frag["tables"] + hist["tables"],
            "figures": spectra["figures"] + var["figures"] + frag["figures"] + hist["figures"]}
