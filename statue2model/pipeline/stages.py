"""The stages of a run, scan to report; each a plain function ``stage(ctx, d) -> manifest``.

``ctx`` (:class:`Context`) holds the scan, the configuration, the executor for
sweeps and the folders of the stages already done; ``d`` is the (temporary) folder
the stage writes into. The returned manifest is what the summary and the report
show of the stage (all JSON):

    summary  {label: value}          the stage's headline numbers
    tables   [{title, columns, rows, status_column}]
    figures  [{path (relative to the stage folder), caption}]
    text     [paragraph, ...]
    warnings [str, ...]              what the user must check (doubtful input, failed checks, skipped
                                     analyses); printed by the run, kept in run.json, shown in the report
    data     {...}                   numbers later stages or the collection table read

Stage        reads                      writes (in its folder)
params       [scan]                     props.json, props_rose.csv, props.png
prototype    [scan] [prototype]         layers/, sheets/ (CNC DXF + previews), bom.csv, assembly.txt,
                                        prototype.stl/.json, slice.json, layers.png
isolator     params, [model] [isolator] design.json, design.txt, plates/ (STL, 3MF, DXF, section)
dynamics     params, isolator,          spectrum_fixed|isolated.json/.png, variability.json/.png,
             [model] [dynamics]         history.json/.png
crosscheck   params, isolator,          crosscheck.json, overlay plots
             [scan] [crosscheck]
"""
from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..errors import InputError
from ..io.files import atomic_write, read_json, write_json
from .config import ProjectConfig, grid

from ..quantities import G  # m/s^2


@dataclass(frozen=True)
class Context:
    """What every stage may read. ``dirs``: stage name -> its complete folder;
    ``manifests``: stage name -> its manifest."""

    mesh: Path
    config: ProjectConfig
    executor: object = None
    dirs: dict = field(default_factory=dict)
    manifests: dict = field(default_factory=dict)
    say: Callable[[str], None] = lambda msg: None   # a progress line inside a long stage

    def load_body(self):
        from ..geometry.body import load_body

        s = self.config.scan
        return load_body(self.mesh, units=s.units, up=s.up, height=s.height,
                         density=None if s.mass is not None else s.density, mass=s.mass, base_tol=s.base_tol)

    def params(self):
        from ..geometry.rocking_params import RockingParams

        return RockingParams.from_dict(read_json(self.dirs["params"] / "props.json"))

    def model(self):
        from ..rocking.model import RockingModel

        m, p = self.config.model, self.params()
        mu_s = getattr(m, "mu_static", None)
        if m.kind == "housner":
            return RockingModel.housner(p, m.e_L, m.e_R, mu_static=mu_s)
        return RockingModel.imperfect(p, m.alpha_L, m.alpha_R, m.theta_L, m.theta_R, m.e_L, m.e_R, mu_static=mu_s)

    def design(self) -> dict | None:
        """The isolator design (dict) if the isolator stage ran and its design passed."""
        man = self.manifests.get("isolator")
        if not man or not man.get("data", {}).get("passed"):
            return None
        d = read_json(self.dirs["isolator"] / "design.json")
        return d if isinstance(d, dict) and d.get("passed") is True else None


def _fig(path: str, caption: str) -> dict:
    return {"path": path, "caption": caption}


def _fmt(x, nd=4):
    return "-" if x is None or (isinstance(x, float) and not np.isfinite(x)) else f"{x:.{nd}g}"


# --- params ---------------------------------------------------------------------------------------
def params_stage(ctx: Context, d: Path) -> dict:
    from ..geometry.props import write_props

    body = ctx.load_body()
    p = body.rocking(ctx.config.scan.direction)
    rose = body.rose()
    write_props(d / "props.json", body, p, rose)
    mp = body.mass
    rows = [["h (height of G)", _fmt(p.h), "", "m"], ["I_G (about G)", _fmt(p.I_G, 5), "", "kg m^2"],
            ["b (G to pivot, in plan)", _fmt(p.b_L), _fmt(p.b_R), "m"],
            ["delta = atan(b/h)", _fmt(p.delta_L), _fmt(p.delta_R), "rad"],
            ["p (frequency parameter)", _fmt(p.p_L), _fmt(p.p_R), "rad/s"],
            ["a = g b/h (uplift)", f"{p.a_L:.4f} ({p.a_L / p.g:.3f} g)", f"{p.a_R:.4f} ({p.a_R / p.g:.3f} g)", "m/s^2"],
            ["e (eq. 15)", _fmt(p.e_L), _fmt(p.e_R), "-"]]
    summary = {"mass": f"{mp.mass:.4g} kg", "height": f"{body.height:.4f} m", "volume": f"{mp.volume:.5g} m^3",
               "direction": f"{p.direction_deg:.2f} deg", "h": f"{p.h:.4f} m", "b_L / b_R": f"{p.b_L:.4f} / {p.b_R:.4f} m",
               "uplift a_R": f"{p.a_R:.4f} m/s^2 ({p.a_R / p.g:.3f} g)",
               "weakest direction": f"{rose.weakest_deg:.2f} deg ({rose.a_min / p.g:.3f} g)"}
    text = [(f"Scan {Path(body.source).name}: units {body.units}, up {body.up}, scale x{body.scale:g}, "
            f"density {mp.density:.1f} kg/m^3.")]
    return {"summary": summary, "text": text, "warnings": list(body.warnings),
            "tables": [{"title": f"Rocking parameters along {p.direction_deg:.2f} deg",
                        "columns": ["quantity", "left (L)", "right (R)", "unit"], "rows": rows}],
            "figures": [_fig("props.png", "Footprint (contact polygons, hull, centre of mass, pivots) and the "
                                          "vulnerability rose: uplift acceleration against the excitation direction")],
            "data": {"m": mp.mass, "h": p.h, "b_L": p.b_L, "b_R": p.b_R, "I_G": p.I_G, "a_L": p.a_L, "a_R": p.a_R,
                     "direction_deg": p.direction_deg, "weakest_deg": rose.weakest_deg, "a_min": rose.a_min,
                     "height": body.height, "volume": mp.volume}}


# --- prototype ------------------------------------------------------------------------------------
def prototype_stage(ctx: Context, d: Path) -> dict:
    from ..fabrication.output import comparison_rows, write_slice
    from ..fabrication.prototype import ERROR_LIMIT, LABELS
    from ..fabrication.slicing import slice_body
    from ..fabrication.spec import SliceSpec
    from ..report.pipeline_plots import plot_layers

    c = ctx.config.prototype
    spec = SliceSpec(scale=c.scale, board=c.board, glue=c.glue, tool=c.tool, rod=c.rod, clearance=c.clearance,
                     wall=c.wall, sheet=tuple(c.sheet), margin=c.margin, edge=c.edge, policy=c.policy,
                     compensate=c.compensate, tolerance=c.tolerance, feed=c.feed, pass_depth=c.pass_depth,
                     osb_density=c.board_density, glue_density=c.glue_density, rod_density=c.rod_density)
    body = ctx.load_body()
    ctx.say(f"slicing at 1:{spec.scale:g} into {spec.board * 1000:g} mm boards, rods, labels, nesting ...")
    res = slice_body(body, spec, direction_deg=ctx.config.scan.direction, front_deg=c.front)
    ctx.say(f"writing the CNC files of {len(res.parts)} parts on {res.nesting.n_sheets} sheet(s) ...")
    write_slice(res, d, previews=c.previews)
    plot_layers(res, d / "layers.png")
    cmp_ = res.comparison
    rows = [[r["quantity"], r["built"], r["scan"], r["error"], r["status"], r["cause"]] for r in comparison_rows(res)]
    figs = [_fig("layers.png", "Boards in plan (colour: layer) with the rod holes, and the stack in elevation")]
    if c.previews:
        for k in range(res.nesting.n_sheets):
            figs.append(_fig(f"sheets/sheet_{k + 1:02d}.png", f"Sheet {k + 1} of {res.nesting.n_sheets}: nested "
                                                              "parts, rod holes and engraved labels"))
    worst, err = cmp_.largest()
    summary = {"scale": f"1:{spec.scale:g}", "layers": f"{res.n_layers} x {spec.board * 1000:g} mm "
               f"(+{spec.glue * 1000:g} mm glue)", "parts / sheets": f"{len(res.parts)} / {res.nesting.n_sheets}",
               "prototype mass": f"{res.proto_mass.mass:.2f} kg",
               "largest parameter error": f"{abs(err) * 100:.2f} % ({LABELS[worst]})"}
    text = [(f"{res.n_layers} boards, {len(res.rods.rods)} alignment rods, material use "
            f"{res.nesting.material_use * 100:.1f} %. CNC files: layers/*.dxf (one per layer), sheets/*.dxf "
            "(nested panels, mm, R2010), bom.csv, assembly.txt.")]
    if res.warnings:
        text.append(f"{len(res.warnings)} warning(s), all in slice.json: " + "; ".join(res.warnings[:3])
                    + ("; ..." if len(res.warnings) > 3 else ""))
    return {"summary": summary, "text": text, "figures": figs, "warnings": list(res.warnings),
            "tables": [{"title": "Prototype as built against the scaled scan",
                        "columns": ["quantity", "as built", "scaled scan", "error",
                                    f"check (+-{ERROR_LIMIT * 100:g} %)", "likely cause"],
                        "rows": rows, "status_column": 4}],
            "data": {"n_layers": res.n_layers, "n_sheets": res.nesting.n_sheets, "proto_mass": res.proto_mass.mass,
                     "errors": cmp_.to_dict(), "failing": cmp_.failing()}}


# --- isolator -------------------------------------------------------------------------------------
def isolator_stage(ctx: Context, d: Path) -> dict:
    from ..hazard.motions import parse_spec
    from ..isolator.design import design
    from ..hazard.code_spectra import parse_spectrum
    from ..isolator.plates import PlateGeometry, write_plates

    c, m = ctx.config.isolator, ctx.config.model
    alpha = (m.alpha_L, m.alpha_R) if m.kind == "imperfect" else (1.0, 1.0)
    res = design(ctx.params(), mu=c.mu, spectrum=parse_spectrum(c.spectrum) if c.spectrum else None,
                 motion=parse_spec(c.motion)[0] if c.motion else None, target=c.target, alpha=alpha,
                 n_grooves=c.grooves, thickness=c.thickness, fuse_release=c.fuse_release)
    dd = res.to_dict()
    write_json(d / "design.json", dd)
    atomic_write(d / "design.txt", lambda f: f.write_text(res.report() + "\n"))
    figs, text, warnings = [], [], []
    if res.passed:
        write_plates(PlateGeometry.from_design(dd), d / "plates", segments=c.segments)
        figs.append(_fig("plates/plates_section.png", "Section through the bottom and top plates, a groove and "
                                                      "its ball (dimensions in mm)"))
        text.append("CNC files: plates/bottom_plate.dxf, plates/top_plate.dxf (outline CUT_OUTSIDE, groove "
                    "openings POCKET, centres DRILL), solids as STL and 3MF.")
    else:
        warnings.append(f"No isolator in range works: {res.failure}. No plates were written, and the analyses "
                        "on the isolator are skipped.")
    warnings += [f"advisory check not met: {ck.name} ({ck.why})" for ck in res.checks
                 if not ck.required and not ck.passed]
    rows = [[ck.name, _fmt(ck.value), _fmt(ck.limit), ck.unit, _fmt(ck.ratio, 3),
             "pass" if ck.passed else ("fail" if ck.required else "note"), ck.why] for ck in res.checks]
    summary = {"design": "PASS" if res.passed else "FAIL",
               "grooves / balls": f"R {res.R:.3f} m, r {res.r:.4f} m, {res.n_grooves} grooves",
               "period T": f"{res.T:.2f} s",
               "plate": f"{res.side:.3f} x {res.side:.3f} x {res.thickness:.3f} m",
               "plate acceleration": f"{res.a_design:.4f} m/s^2 (limit {res.a_lim:.4f} m/s^2)",
               "travel": f"{res.d_design:.4f} m x {res.margin:g} + mu R_hat = {res.travel_need:.4f} m "
                         f"(capacity {res.capacity:.4f} m, {res.capacity_limited_by})"}
    text.append(f"Chosen among {res.candidates.get('passing', 0)} passing of {res.candidates_tried} candidates: "
                f"{res.criterion}.")
    return {"summary": summary, "text": text + list(res.notes), "warnings": warnings, "figures": figs,
            "tables": [{"title": "Design checks (each passes when value <= limit; ratio = value / limit)",
                        "columns": ["check", "value", "limit", "unit", "ratio", "result", "why"],
                        "rows": rows, "status_column": 5}],
            "data": {"passed": res.passed, "R": res.R, "r": res.r, "T": res.T, "M": res.M, "mu": res.mu,
                     "side": res.side, "n_grooves": res.n_grooves, "a_design": res.a_design,
                     "d_design": res.d_design, "capacity": res.capacity, "travel_need": res.travel_need,
                     "failure": res.failure}}


# --- dynamics -------------------------------------------------------------------------------------
def _spectrum_rows(sp, label):
    """One row of the spectra table. Isolated spectra (codes may be CAPACITY): 'overturns'
    and the lowest amplitude count overturning or capacity exceeded, the conservative failure."""
    from ..rocking.batch import OUTCOMES
    from ..rocking.spectrum import label as code_label
    from ..isolator.sweeps import CAPACITY, is_failure

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


def _first_overturn(sw) -> float | None:
    i = np.flatnonzero(sw.overturned)
    return float(sw.values[i[0]]) if i.size else None


def dynamics_stage(ctx: Context, d: Path) -> dict:
    from ..rocking.engine import simulate as rock
    from ..hazard.motions import parse_spec
    from ..rocking.spectrum import stability_spectrum
    from ..rocking.sweeps import variability
    from ..isolator.coupled import simulate_coupled
    from ..isolator.device import isolator_from_design
    from ..isolator.time_history import simulate as plate_run
    from ..isolator.sweeps import CAPACITY, FAILED, is_failure, isolated_spectrum, isolated_variability
    from ..report.dynamics_plots import plot_spectrum
    from ..report.pipeline_plots import plot_history_pair, plot_variability_pair

    c = ctx.config.dynamics
    model = ctx.model()
    rtol = ctx.config.model.rtol
    freqs, amps = grid(c.freq, "[dynamics] freq"), grid(c.amp, "[dynamics] amp", accel=True)
    pgas = grid(c.pga, "[dynamics] pga", accel=True)
    motion = parse_spec(c.motion)[0]
    ex = {"executor": ctx.executor} if ctx.executor is not None else {}
    design = ctx.design() if c.isolated else None
    iso = isolator_from_design(design) if design else None

    figs, tables, text, data, warnings = [], [], [], {}, []
    sp = stability_spectrum(model, freqs, amps, pulse=c.pulse, rtol=rtol, **ex)
    write_json(d / "spectrum_fixed.json", sp.to_dict())
    plot_spectrum(sp, d / "spectrum_fixed.png", f"fixed base: one-{c.pulse} pulses ({sp.codes.size} runs)")
    figs.append(_fig("spectrum_fixed.png", f"Stability spectrum on a fixed base: one-{c.pulse} pulses, "
                                           f"{sp.codes.size} runs"))
    spec_rows = [_spectrum_rows(sp, "fixed base")]
    cap_txt = "not checked"
    if iso is not None:
        cap = iso.capacity
        cap_txt = f"{cap * 1000:.1f} mm" if np.isfinite(cap) else "not checked"
        data["capacity_isolator"] = cap if np.isfinite(cap) else None
        if not np.isfinite(cap):
            warnings.append("The isolator design gives no capacity (largest plate displacement): the analyses on "
                            "the isolator do not check whether the balls stay in their grooves.")
        spi = isolated_spectrum(iso, model, freqs, amps, pulse=c.pulse, rtol=rtol, executor=ctx.executor)
        write_json(d / "spectrum_isolated.json", spi.to_dict())
        plot_spectrum(spi, d / "spectrum_isolated.png",
                      f"on the isolator (T = {design['T']:.2f} s, capacity {cap_txt}): one-{c.pulse} pulses "
                      f"({spi.codes.size} runs)")
        figs.append(_fig("spectrum_isolated.png", f"Stability spectrum of the statue on the isolator (coupled plate "
                                                  f"+ statue), the same {spi.codes.size} pulses; 'isolator capacity "
                                                  f"exceeded': the plate moved more than {cap_txt}"))
        spec_rows.append(_spectrum_rows(spi, "on the isolator"))
        n_cap_sp = int(np.sum(spi.codes == CAPACITY))
        # conservative: overturning or capacity exceeded (the key the collection table reads)
        data["spectrum_overturn_fraction_isolated"] = float(np.mean(is_failure(spi.codes)))
        data["spectrum_failure_fraction_isolated"] = data["spectrum_overturn_fraction_isolated"]
        data["spectrum_overturn_only_fraction_isolated"] = float(np.mean(spi.codes >= 3))
        data["capacity_exceeded_fraction_isolated"] = float(n_cap_sp / spi.codes.size)
    data["spectrum_overturn_fraction_fixed"] = float(np.mean(sp.codes >= 3))
    tables.append({"title": f"Stability spectra: {freqs[0]:g}-{freqs[-1]:g} Hz x {amps[0] / G:.3g}-{amps[-1] / G:.3g} g",
                   "columns": ["base", "moves", "overturns (on the isolator: or exceeds its capacity)",
                               "lowest failing amplitude (overturning; on the isolator: or capacity exceeded)",
                               "outcomes"],
                   "rows": spec_rows})

    sw = variability(model, motion, pgas, rtol=rtol, **ex)
    swi = acc_i = None
    if iso is not None:
        swi, acc_i = isolated_variability(iso, model, motion, pgas, rtol=rtol, executor=ctx.executor)
    write_json(d / "variability.json", {"fixed": sw.to_dict(), "isolated": None if swi is None else
                                        {**swi.to_dict(), "plate_acc_abs_max": acc_i}})
    plot_variability_pair(sw, swi, acc_i, d / "variability.png")
    figs.append(_fig("variability.png", f"Variability: {motion.label} scaled to {pgas.size} PGAs, fixed base "
                                        "and on the isolator" + ("" if swi is None or swi.run.all() else
                                                                 " (on the isolator: stopped at the first PGA "
                                                                 "that exceeds the capacity)")))
    ot_f = _first_overturn(sw)
    var_rows = [["fixed base", "none" if ot_f is None else f"{ot_f / G:.3f} g", "-",
                 f"{sw.summary()['p50']:.3f}", f"{sw.summary()['max']:.3f}"]]
    ot_i = cap_i = fail_i = None
    if swi is not None:
        ot_i, cap_i, fail_i = _first_overturn(swi), swi.first_capacity_pga(), swi.first_failure_pga()
        s_i = swi.summary()
        what = ("" if fail_i is None else " (capacity exceeded)" if fail_i == cap_i and fail_i != ot_i else
                " (overturning)")
        var_rows.append(["on the isolator", "none" if fail_i is None else f"{fail_i / G:.3f} g{what}",
                         "none" if cap_i is None else f"{cap_i / G:.3f} g", f"{s_i['p50']:.3f}", f"{s_i['max']:.3f}"])
        if not swi.run.all():
            text.append(f"Variability on the isolator: the capacity ({cap_txt}) was exceeded at "
                        f"{cap_i / G:.3f} g, so the {int((~swi.run).sum())} higher PGAs were not run "
                        "(variability.json: isolated.run, not_run_pga_m_s2).")
    tables.append({"title": f"Variability over PGA {pgas[0] / G:.3g}-{pgas[-1] / G:.3g} g",
                   "columns": ["base", "lowest failing PGA of the grid (overturning; on the isolator: or capacity "
                               "exceeded)", "capacity exceeded from", "median |theta|max/delta",
                               "max |theta|max/delta"],
                   "rows": var_rows})
    # first_overturn_pga_isolated: the conservative value (overturning or capacity exceeded),
    # the key the collection table reads; the separate ones beside it
    data.update(first_overturn_pga_fixed=ot_f, first_overturn_pga_isolated=fail_i, first_failure_pga_isolated=fail_i,
                first_overturn_only_pga_isolated=ot_i, first_capacity_pga_isolated=cap_i)
    if swi is not None:
        data["capacity_exceeded_points_isolated"] = {
            "spectrum": n_cap_sp, "variability": int(np.sum((swi.codes == CAPACITY) & swi.run)),
            "variability_not_run": int((~swi.run).sum())}

    fixed = rock(model, motion, rtol=rtol, dt_out=0.005)
    plate = coupled = None
    hist = {"fixed": fixed.to_dict()}
    hrows = [["fixed base", fixed.outcome, f"{fixed.theta_max_over_delta:.4f}", f"{motion.pga / G:.3f} g", "-",
              "-"]]
    if iso is not None:
        plate = plate_run(iso, motion, dt_out=0.005)
        coupled = simulate_coupled(iso, model, motion, t_end=float(plate.t[-1]), dt_out=0.005, rtol=rtol)
        hist["isolated"] = coupled.to_dict()
        travel = (f"{coupled.u_max * 1000:.1f} mm of {cap_txt}" if np.isfinite(iso.capacity) else
                  f"{coupled.u_max * 1000:.1f} mm (capacity not checked)")
        if coupled.capacity_exceeded:
            travel += f"; exceeded at t = {coupled.t_capacity:.3f} s"
        hrows.append(["on the isolator", coupled.outcome, f"{coupled.theta_max_over_delta:.4f}",
                      f"{coupled.acc_abs_max / G:.3f} g", f"{coupled.efficiency:.3f}", travel])
        data.update(efficiency=coupled.efficiency, outcome_isolated=coupled.outcome,
                    capacity_exceeded_history=coupled.capacity_exceeded, t_capacity_history=coupled.t_capacity,
                    u_max_history=coupled.u_max)
        if coupled.capacity_exceeded:
            warnings.append(f"On the isolator under {motion.label}: the plate passes the capacity {cap_txt} at "
                            f"t = {coupled.t_capacity:.3f} s (a ball leaves its groove or the top plate tips); "
                            "the run stops there: a failure, as bad as overturning.")
    data.update(outcome_fixed=fixed.outcome, theta_max_over_delta_fixed=fixed.theta_max_over_delta)
    if c.fragility:
        from ..assessment.study import fragility_section
        from ..assessment.verdict import DEFAULT_SPECTRUM

        fr = fragility_section(ctx, d, model, iso, ctx.config.isolator.spectrum or DEFAULT_SPECTRUM, ctx.executor)
        figs += fr["figures"]
        tables += fr["tables"]
        text += fr["text"]
        warnings += fr["warnings"]
        data.update(fr["data"])
    write_json(d / "history.json", hist)
    plot_history_pair(fixed, plate, coupled, d / "history.png")
    figs.append(_fig("history.png", f"Time history under {motion.label}: rotation on a fixed base and on the "
                                    "isolator; ground and plate accelerations"))
    tables.append({"title": f"Time history: {motion.label}",
                   "columns": ["base", "outcome", "|theta|max/delta", "peak acceleration felt", "efficiency",
                               "plate travel (of the capacity)"],
                   "rows": hrows})
    if c.isolated and iso is None and enabled("isolator", ctx.config):
        warnings.append("The analyses on the isolator were skipped: no passing isolator design "
                        "(see the isolator section).")
    elif c.isolated and iso is None:
        text.append("The analyses on the isolator were skipped: no passing isolator design ([isolator] "
                    "enabled = false).")
    runs = [("fixed-base spectrum", sp.codes), ("fixed-base variability", sw.codes)]
    if iso is not None:
        runs += [("isolated spectrum", spi.codes), ("isolated variability", swi.codes)]
    for what, codes in runs:
        if codes is not None and np.any(codes == FAILED):
            warnings.append(f"{what}: the solver could not finish {int(np.sum(codes == FAILED))} of {codes.size} "
                            "runs (counted as 'solver failed', not as an outcome)")
    lim_up, lim_dn = model.uplift_limits
    text.insert(0, f"Rocking model: {model.kind}; the statue lifts at +{lim_up / G:.4f} g / -{lim_dn / G:.4f} g.")
    if iso is not None:
        text.insert(1, f"On the isolator, every run watches the plate displacement against the capacity ({cap_txt}: "
                       "the largest before a ball leaves its groove or the top plate tips); a run that passes it "
                       "stops with the outcome 'isolator capacity exceeded', counted as a failure like "
                       "overturning: the isolated 'overturns' and 'lowest failing PGA' figures are the lower of "
                       "the two.")
    summary = {"spectrum overturns (fixed)": f"{data['spectrum_overturn_fraction_fixed'] * 100:.1f} % of pulses",
               "lowest overturning PGA (fixed)": var_rows[0][1],
               f"{motion.label} (fixed)": f"{fixed.outcome}, |theta|max/delta {fixed.theta_max_over_delta:.3g}"}
    if iso is not None:
        summary["spectrum overturns or exceeds capacity (isolated)"] = (
            f"{data['spectrum_overturn_fraction_isolated'] * 100:.1f} % of pulses (overturn "
            f"{data['spectrum_overturn_only_fraction_isolated'] * 100:.1f} %, capacity exceeded "
            f"{data['capacity_exceeded_fraction_isolated'] * 100:.1f} %: {n_cap_sp} pulses)")
        summary["lowest failing PGA (isolated: overturning or capacity exceeded)"] = var_rows[1][1]
        summary["isolator capacity"] = cap_txt
        summary[f"{motion.label} (isolated)"] = (f"{coupled.outcome}, efficiency {coupled.efficiency:.3f}, "
                                                 f"plate travel {travel}")
    if data.get("fragility_runs"):
        for side, key in (("fixed", "fragility: median overturning PGA (fixed)"),
                          ("isolated", "fragility: median failure PGA (isolated)")):
            med = data.get(f"fragility_median_{side}")
            if side == "fixed" or iso is not None:
                summary[key] = (f"not fitted ({data.get(f'fragility_median_{side}_reason') or 'undefined'})"
                                if med is None else f"{med / G:.3f} g")
    return {"summary": summary, "text": text, "warnings": warnings, "tables": tables, "figures": figs, "data": data}


def _error_and_target(cd: dict) -> tuple[str, str]:
    """A case's error and target, as percentages for relative cases."""
    err, target = cd.get("rel_error"), cd.get("target")
    if cd.get("kind") == "relative":
        return ("-" if err is None else f"{err * 100:.1f} %", "-" if target is None else f"{target * 100:.0f} %")
    return _fmt(err), _fmt(target)


# --- crosscheck -----------------------------------------------------------------------------------
def _why_missed(cd: dict) -> str:
    """The case's own diagnosis when it misses its target (or is a diagnostic / not applicable);
    the bare numbers when it has none."""
    if cd.get("status", "met" if cd.get("met") else "missed") == "met":
        return ""
    if cd.get("status") in ("diagnostic", "not applicable"):
        return cd.get("why") or cd.get("status")
    why = "; ".join(x for x in (cd.get("why"), cd.get("note")) if x)
    if why:
        return why
    err, target = _error_and_target(cd)
    return f"2D and 3D differ by {err} (target {target}); no cause was diagnosed for this case"



def crosscheck_stage(ctx: Context, d: Path) -> dict:
    from ..crosscheck.contact import ContactSettings
    from ..crosscheck.isolator_scene import IsolatorScene
    from ..crosscheck.output import summary as cc_summary
    from ..crosscheck.output import write_report
    from ..crosscheck.compare import compare
    from ..crosscheck.statue_scene import StatueScene
    from ..crosscheck.world import SimSettings
    from ..hazard.motions import parse_spec

    c = ctx.config.crosscheck
    motion = parse_spec(c.motion)[0]
    scene = StatueScene.from_body(ctx.load_body(), ctx.config.scan.direction)
    design = ctx.design() if c.isolator else None
    iso = (IsolatorScene.from_design(design, statue=scene, grid=c.grid or None,
                                     groove="tiles" if c.groove == "tiles" else None) if design else None)
    settings, contact = SimSettings(dt=c.dt, solver_iterations=c.iterations), ContactSettings()
    statue_settings = SimSettings(dt=c.statue_dt, solver_iterations=c.iterations)
    comp = compare(scene, motion, iso_scene=iso, settings=settings, statue_settings=statue_settings,
                   contact=contact, pulse_freq=c.pulse_freq,
                   quick=c.quick, e_L=ctx.config.model.e_L, e_R=ctx.config.model.e_R,
                   progress=lambda msg: ctx.say(f"3D: {msg} ..."))
    paths = write_report(comp, d, {"scene": {"name": scene.name, "params": scene.params.to_dict()},
                                   "settings": settings.to_dict(), "statue_settings": statue_settings.to_dict(),
                                   "contact": contact.to_dict(),
                                   "motion": motion.to_dict()})
    rows = []
    for case in comp.cases:
        cd = case.to_dict()
        rows.append([cd["name"], cd.get("unit", ""), _fmt(cd.get("value_2d")), _fmt(cd.get("value_3d")),
                     *_error_and_target(cd), {"met": "pass", "missed": "fail"}.get(cd["status"], cd["status"]),
                     _why_missed(cd)])
    s = cc_summary(comp.cases)
    figs = [_fig(p.name, f"2D (reduced model) and 3D (PyBullet) time histories: {name}")
            for name, p in paths.items() if name != "json"]
    text = [("Each case compares one quantity of the 2D model with the 3D contact simulation of the same scene; "
            "a case meets its target when the difference is within the stated tolerance.")]
    warnings = []
    if s["unmet"]:
        warnings.append("2D/3D cases outside their target: " + "; ".join(map(str, s["unmet"])))
    if c.isolator and design is None and enabled("isolator", ctx.config):
        warnings.append("The isolator scenes of the 3D cross-check were skipped: no passing isolator design.")
    elif c.isolator and design is None:
        text.append("The isolator scenes were skipped: no passing isolator design ([isolator] enabled = false).")
    return {"summary": {"2D/3D agreement": f"{s['n_met']} of {s['n_cases']} applicable checks within target"
                                           f" ({s['n_not_applicable']} not applicable, {s['n_diagnostic']} "
                                           "diagnostics not counted)"},
            "text": text, "warnings": warnings, "figures": figs,
            "tables": [{"title": "2D model against 3D physics", "columns": ["case", "unit", "2D", "3D", "error",
                                                                            "target", "met", "why (when missed)"],
                        "rows": rows, "status_column": 6}],
            "data": {"n_cases": s["n_cases"], "n_met": s["n_met"]}}


STAGES = {"params": params_stage, "prototype": prototype_stage, "isolator": isolator_stage,
          "dynamics": dynamics_stage, "crosscheck": crosscheck_stage}
# stage -> (stages it needs, stages it reads when they are enabled, config sections it reads)
DEPENDS = {"params": ((), (), ("scan",)), "prototype": ((), (), ("scan", "prototype")),
           "isolator": (("params",), (), ("model", "isolator")),
           "dynamics": (("params",), ("isolator",), ("model", "dynamics")),
           "crosscheck": (("params",), ("isolator",), ("scan", "crosscheck"))}


def enabled(name: str, cfg: ProjectConfig) -> bool:
    sec = {"prototype": cfg.prototype, "isolator": cfg.isolator, "dynamics": cfg.dynamics,
           "crosscheck": cfg.crosscheck}.get(name)
    return True if sec is None else bool(sec.enabled)


def check_stage_names(names) -> list[str]:
    bad = [n for n in names if n not in STAGES]
    if bad:
        raise InputError(f"unknown stage(s) {', '.join(bad)}; stages are {', '.join(STAGES)}")
    return list(names)
