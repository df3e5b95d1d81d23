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

A stage conducts: it calls the analyses (geometry/, fabrication/, isolator/, assessment/), writes
their files and hands the plain results to report/ for the figures and for the summary, text,
warnings and tables (report/stage_sections.py, dynamics_section.py, fragility_section.py); it
builds only ``data`` itself.

Stage        reads                      writes (in its folder)
params       [scan]                     props.json, props_rose.csv, props.png, body.npz (the Body)
prototype    [scan] [prototype]         layers/, sheets/ (CNC DXF + previews), bom.csv, assembly.txt,
                                        prototype.stl/.json, slice.json, layers.png
isolator     params, [model] [isolator] design.json, design.txt, plates/ (STL, 3MF, DXF, section)
dynamics     params, isolator,          spectrum_fixed|isolated.json/.png, variability.json/.png,
             [model] [dynamics]         history.json/.png, fragility.json/.csv/.png, records/
crosscheck   params, isolator,          crosscheck.json, overlay plots, classification.json (2D/3D over
             dynamics, [model]          the design records, around the dynamics stage's fragility medians),
             [scan] [crosscheck]        with a [pedestal] stack_classification.json (the statue on it, 2D/3D
             [sliding] [pedestal]       per body and outcome, the design records as matched and scaled)
"""
from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

from ..assessment import states
from ..io.files import atomic_write, read_json, write_json
from .config import STAGE_NAMES, ProjectConfig, site


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
    bodies: dict = field(default_factory=dict)     # the run's Body, shared by its stages (body_cache.py)
    mesh_sha256: str | None = None                 # the scan's hash, computed once by the run
    record_sets: dict = field(default_factory=dict)  # the run's record sets by their matching arguments
    supports: dict = field(default_factory=dict)     # the statue's Support by its rocking parameters (support())

    def load_body(self, store: Path | None = None):
        """The Body of the scan with the [scan] settings, built once per run (pipeline/body_cache.py):
        kept in ``bodies`` for the next stage, read from the params stage's body.npz when that stage
        is complete and its manifest lists the file; ``store``: the folder to write body.npz into
        (the params stage's)."""
        from .body_cache import BODY_FILE, load_body

        s = self.config.scan
        listed = (self.manifests.get("params") or {}).get("files") or {}
        return load_body(self.mesh, dict(units=s.units, up=s.up, height=s.height,
                                         density=None if s.mass is not None else s.density, mass=s.mass,
                                         base_tol=s.base_tol),
                         scan_sha256=self.mesh_sha256, memory=self.bodies, cached=self.dirs.get("params"),
                         cached_sha256=listed.get(BODY_FILE) if isinstance(listed, dict) else None, store=store)

    def params(self):
        from ..geometry.rocking_params import RockingParams

        return RockingParams.from_dict(read_json(self.dirs["params"] / "props.json"))

    def model(self):
        from ..rocking.model import RockingModel

        m, p = self.config.model, self.params()
        mu_s = self.config.sliding.mu_statue
        if m.kind == "housner":
            return RockingModel.housner(p, m.e_L, m.e_R, mu_static=mu_s)
        return RockingModel.imperfect(p, m.alpha_L, m.alpha_R, m.theta_L, m.theta_R, m.e_L, m.e_R, mu_static=mu_s)

    def support(self, params=None):
        """What the statue stands on (assessment/support.py): its friction on the floor or on the
        [pedestal], the sliding capacities, and the two-block model with a pedestal."""
        p = self.params() if params is None else params
        if p not in self.supports:          # built once per run: a pedestal's scan and the overhang read files
            self.supports[p] = self._support(p)
        return self.supports[p]

    def _support(self, p):
        from ..assessment.support import FLOOR_ALLOWANCE, Support, edge_distances
        from ..rocking.sliding import Friction

        sl, pd = self.config.sliding, self.config.pedestal
        friction = Friction(sl.mu_statue, sl.kinetic_ratio * sl.mu_statue)
        floor_cap = FLOOR_ALLOWANCE if sl.allowance is None else sl.allowance
        floor_words = (f"the default floor allowance {FLOOR_ALLOWANCE:g} m" if sl.allowance is None else
                       f"the allowance {sl.allowance:g} m ([sliding] allowance)")
        if pd.size is None and pd.file is None:
            return Support(friction, (floor_cap, floor_cap), floor_words)
        from ..rocking.stack import StackModel

        pedestal = self.pedestal(p.direction_deg)
        x2 = pd.position[0] + (p.b_L - p.b_R) / 2          # G from the axis: the base's centre at position
        stack = StackModel(p, pedestal, x2=x2)
        edge = edge_distances(p.b_L, p.b_R, x2, pedestal.b)
        if sl.allowance is None:
            cap, words = edge, "the distance from its base to the pedestal top's edge"
        else:
            cap = tuple(min(e, sl.allowance) for e in edge)
            words = f"the smaller of the pedestal top's edge and the allowance {sl.allowance:g} m"
        notes = ()
        over = self.overhang(p.direction_deg, x2, pedestal)
        if over > 1e-3:
            notes = (f"the statue's base overhangs the pedestal's top by {over * 1000:.0f} mm (across the excitation "
                     "direction, or along it where its pivots are not its base's extremes): the 2D model stands it on "
                     "its pivots along the direction only; give a larger pedestal or check [pedestal] position",)
        return Support(friction, cap, words, stack, Friction(sl.mu_pedestal, sl.kinetic_ratio * sl.mu_pedestal),
                       (floor_cap, floor_cap), floor_words, edge=sl.allowance is None or sl.allowance >= min(edge),
                       notes=notes)

    def overhang(self, direction_deg: float, x2: float, pedestal) -> float:
        """m: how far the statue's base (its footprint's contact hull) passes the pedestal's top in any
        direction: the hull about the centre of mass, turned so the excitation runs along x, with G at
        (x2, [pedestal] position y) on a top of the pedestal's width and depth; 0 when it stands whole."""
        import numpy as np

        body = self.load_body()
        pd = self.config.pedestal
        a = np.radians(direction_deg)
        xy = np.asarray(body.footprint.hull, dtype=float) - np.asarray(body.mass.com, dtype=float)[:2]
        u = xy[:, 0] * np.cos(a) + xy[:, 1] * np.sin(a)
        v = -xy[:, 0] * np.sin(a) + xy[:, 1] * np.cos(a)
        depth = pd.size[1] if pd.size is not None else 2 * pedestal.b
        out = max(float(np.max(np.abs(x2 + u))) - pedestal.b, float(np.max(np.abs(pd.position[1] + v))) - depth / 2)
        return max(out, 0.0)

    def iso_model(self):
        """The body the isolator carries: the statue's model, or with ``[isolator] under = "pedestal"`` the
        stack as one rigid body (rocking/stack.py StackModel.composite, Housner's model with its eq. 15
        restitution): the device is designed for its mass and checked against :meth:`iso_limits`."""
        model = self.model()
        if self.config.isolator.under != "pedestal":
            return model
        from ..rocking.model import RockingModel

        return RockingModel.housner(self.support(model.params).stack.composite,
                                    mu_static=self.config.sliding.mu_pedestal)

    def iso_limits(self, band=None) -> tuple[float, float]:
        """(toward +x, toward -x) m/s^2: what the body on the isolator may feel before something lifts: the
        statue's contact limits (the low end of ``band`` when the contact is uncertain) and, with the pedestal
        on the device, the stack's too (the smaller of the two on each side)."""
        from ..assessment.limit_states import contact_limits

        lim = contact_limits(self.model(), band)
        if self.config.isolator.under != "pedestal":
            return lim
        comp = self.iso_model().uplift_limits
        return (min(lim[0], comp[0]), min(lim[1], comp[1]))

    def iso_min_side(self) -> float:
        """m: the smallest top plate that carries the pedestal: its base's larger side and a margin each side
        (isolator/design.py EDGE), so the pedestal stands whole on the plate."""
        from ..isolator.design import EDGE

        ped = self.support(self.params()).stack.pedestal
        pd = self.config.pedestal
        depth = pd.size[1] if pd.size is not None else 2 * ped.b
        return max(2 * ped.b, depth) + 2 * EDGE

    def pedestal(self, direction_deg: float):
        """The [pedestal] as the 2D model's block (rocking/stack.py Pedestal): its box, or a scan of it read as
        a statue's scan is (the same loader, repairs and mass properties) and taken as its equivalent box along
        ``direction_deg``: width b_L + b_R of its base through its centre of mass, its height, its mass."""
        from ..rocking.stack import Pedestal

        pd = self.config.pedestal
        if pd.file is None:
            return Pedestal.box(pd.size[0], pd.size[1], pd.size[2], pd.mass)
        from ..geometry.body import load_body

        body = load_body(pd.file, units=pd.units, up=pd.up, density=None if pd.mass is not None else pd.density,
                         mass=pd.mass)
        q = body.rocking(direction_deg)
        return Pedestal.box(q.b_L + q.b_R, q.b_L + q.b_R, body.height, body.mass.mass)

    def design(self) -> dict | None:
        """The isolator design (dict) if the isolator stage ran and its design passed every required check
        (the ball load among them), else None."""
        if not self.manifests.get("isolator"):
            return None
        d = read_json(self.dirs["isolator"] / "design.json")
        if not isinstance(d, dict):
            return None
        return d if d.get("passed") is True else None


# --- params ---------------------------------------------------------------------------------------
def params_stage(ctx: Context, d: Path) -> dict:
    from ..geometry.props import write_props
    from ..report.plots import plot_footprint_and_rose
    from ..report.stage_sections import params_section

    body = ctx.load_body(store=d)
    p = body.rocking(ctx.config.scan.direction)
    rose = body.rose()
    write_props(d / "props.json", body, p, rose)
    plot_footprint_and_rose(body, p, rose, d / "props.png")
    mp = body.mass
    return {**params_section(body, p, rose),
            "data": {"m": mp.mass, "h": p.h, "b_L": p.b_L, "b_R": p.b_R, "I_G": p.I_G, "a_L": p.a_L, "a_R": p.a_R,
                     "direction_deg": p.direction_deg, "weakest_deg": rose.weakest_deg, "a_min": rose.a_min,
                     "height": body.height, "volume": mp.volume,
                     # what the collection's doubts read, as facts (never the warnings' words)
                     "units": body.units, "units_sure": bool(body.units_sure),
                     "contact_uncertain": bool(body.base is not None and body.base.uncertain),
                     "contact_band": (None if body.base is None or not body.base.uncertain else
                                      [min(float(c.a_min) for c in body.base.cases),
                                       max(float(c.a_min) for c in body.base.cases)])}}


# --- prototype ------------------------------------------------------------------------------------
def prototype_stage(ctx: Context, d: Path) -> dict:
    from ..fabrication.output import write_slice
    from ..fabrication.slicing import slice_body
    from ..fabrication.spec import SliceSpec
    from ..report.fabrication_plots import plot_sheet
    from ..report.pipeline_plots import plot_layers
    from ..report.stage_sections import prototype_progress, prototype_section

    c = ctx.config.prototype
    spec = SliceSpec(scale=c.scale, board=c.board, glue=c.glue, tool=c.tool, rod=c.rod, clearance=c.clearance,
                     wall=c.wall, sheet=tuple(c.sheet), margin=c.margin, edge=c.edge, policy=c.policy,
                     compensate=c.compensate, tolerance=c.tolerance, feed=c.feed, pass_depth=c.pass_depth,
                     osb_density=c.board_density, glue_density=c.glue_density, rod_density=c.rod_density)
    body = ctx.load_body()
    ctx.say(prototype_progress(spec))
    res = slice_body(body, spec, direction_deg=ctx.config.scan.direction, front_deg=c.front)
    ctx.say(prototype_progress(spec, res))
    write_slice(res, d, preview=plot_sheet if c.previews else None)
    plot_layers(res, d / "layers.png")
    cmp_ = res.comparison
    return {**prototype_section(res, c.previews),
            "data": {"n_layers": res.n_layers, "n_sheets": res.nesting.n_sheets, "proto_mass": res.proto_mass.mass,
                     "errors": cmp_.to_dict(), "failing": cmp_.failing()}}


# --- isolator -------------------------------------------------------------------------------------
EXTRA_SEEDS = 100
"""The isolator's further record sets take seeds k x 100 + 1 .. (k = 1, 2, ...): independent of the design set's."""


def isolator_stage(ctx: Context, d: Path) -> dict:
    """The cheapest isolator that passes every check (isolator/verify.py): designed on the [isolator] input,
    verified by time histories on the run's design record set and ``[isolator] extra_sets`` further sets of
    other seeds, at the collapse level (hazard/levels.py) and with a reserve up to where the statue
    overturns on a fixed base, against the statue's uplift limit (the low end of the base-contact band when
    the params stage flagged the contact uncertain). With ``[isolator] under = "pedestal"`` the device carries
    the stack (Context.iso_model: its mass loads the balls) and holds the smaller of the statue's and the
    stack's uplift limits (Context.iso_limits); the reserve stays the statue's. Writes design.json, design.txt, bom.csv and, for a
    passing design, plates/ (CNC DXF, STL, 3MF, the drawing)."""
    from ..hazard.levels import collapse_site
    from ..hazard.motions import parse_spec
    from ..isolator.plates import PlateGeometry, write_plates
    from ..isolator.prices import write_bom
    from ..isolator.verify import verify
    from ..report.isolator_plots import plot_plates_figures
    from ..report.stage_sections import isolator_section

    c, m = ctx.config.isolator, ctx.config.model
    alpha = (m.alpha_L, m.alpha_R) if m.kind == "imperfect" else (1.0, 1.0)
    rs, _ = _design_set(ctx)
    hz = site(ctx.config)
    band = _uplift_band(ctx)
    model = ctx.iso_model()
    a_lim = min(ctx.iso_limits(band))
    why = ("min over the sides of alpha_side min(a_side, the low end of the uncertain base's uplift band "
           f"{band[0]:.4g}-{band[1]:.4g} m/s^2)" if band is not None else "min(alpha_L a_L, alpha_R a_R)")
    if c.under == "pedestal":
        why += " of the statue, and of the stack (statue and pedestal as one body) it carries, the smaller"
    n = len(rs.records)
    info = {"source": "design set", "rules_met": bool(rs.check()["met"]), "band_s": list(rs.band),
            "band_reason": rs.to_dict().get("band_reason"), "seeds": f"1-{n}",
            "duration_s": max(r.duration for r in rs.records)}
    extra = _extra_sets(ctx, c.extra_sets)
    slc, slc_why = (None, None)
    if c.spectrum:
        slc_hz, slc_why = collapse_site(hz, c.slc_spectrum)
        slc = slc_hz.target
    res = verify(model.params, records=rs.records, extra_sets=extra, fixed_model=ctx.model(), design_pga=hz.pga,
                 rtol=m.rtol, mu=c.mu, mu_low=c.mu_low, mu_high=c.mu_high, a_lim=a_lim, a_lim_why=why,
                 records_info=info, spectrum=hz.target if c.spectrum else None, slc=slc, slc_why=slc_why,
                 motion=parse_spec(c.motion)[0] if c.motion else None, target=c.target, alpha=alpha,
                 n_grooves=c.grooves, layouts=c.layout, surfaces=c.surface, materials=c.ball_material,
                 thickness=c.thickness, side_max=c.side_max, fuse_release=c.fuse_release,
                 ball_capacity=c.ball_capacity, price_table=dict(c.prices), executor=ctx.executor,
                 **({"min_side": ctx.iso_min_side()} if c.under == "pedestal" else {}))
    dd = res.to_dict()
    dd["carries"] = {"under": c.under, "mass": model.params.m,
                     "what": "the statue" if c.under == "statue" else "the statue on its pedestal (one body)"}
    write_json(d / "design.json", dd)
    atomic_write(d / "design.txt", lambda f: f.write_text(res.report() + "\n"))
    if res.passed:
        write_bom(d / "bom.csv", res.bom)
        geom = PlateGeometry.from_design(dd)
        write_plates(geom, d / "plates", segments=c.segments)
        plot_plates_figures(geom, d / "plates", design=dd)
    v = res.verification
    return {**isolator_section(res),
            "data": {"passed": res.passed, "R": res.R, "r": res.r, "T": res.T, "M": res.M, "mu": res.mu,
                     "side": res.side, "n_grooves": res.n_grooves, "layout": res.layout, "surface": res.surface,
                     "cost": res.cost if res.passed else None, "a_design": res.a_design,
                     "d_design": res.d_design, "capacity": res.capacity, "travel_need": res.travel_need,
                     "failure": res.failure, "th_margins": res.th_margins, "what_would_pass": res.what_would_pass,
                     "mu_low": v["mu_low"], "mu_high": v["mu_high"], "a_lim": v["a_lim"],
                     "ball_capacity": dd["ball_capacity"], "th_records": v["records"]["count"],
                     "sets": len(v.get("sets") or []), "slc": v.get("slc"), "reserve": v.get("reserve"),
                     "advisory_not_met": [c.name for c in res.checks if not c.required and not c.passed]}}


def _extra_sets(ctx: Context, n_sets: int) -> list:
    """The isolator's further record sets: the design set's target, band and size, set k with seeds
    k x EXTRA_SEEDS + 1 .. (isolator.verify.RecordSet, with its rules and band), matched on the run's executor."""
    from ..isolator.verify import RecordSet

    if n_sets < 1:
        return []
    seeds = [k * EXTRA_SEEDS + 1 for k in range(1, n_sets + 1)]
    tasks = [_match_args(ctx, seed) for seed in seeds]
    ex = ctx.executor
    sets = ([_match_task(t) for t in tasks] if ex is None or getattr(ex, "workers", 1) < 2 else
            list(ex.map(_match_task, tasks, desc="isolator: further record sets")))
    out = []
    for seed, rs in zip(seeds, sets):
        n = len(rs.records)
        out.append(RecordSet(f"seeds {seed}-{seed + n - 1}", tuple(rs.records), f"{seed}-{seed + n - 1}",
                             {"rules_met": bool(rs.check()["met"]), "band_s": list(rs.band),
                              "band_reason": rs.to_dict().get("band_reason")}))
    return out


def _match_args(ctx: Context, seed: int) -> tuple:
    from ..isolator.design import longest_period

    c = ctx.config.dynamics
    hz = site(ctx.config)
    return (hz.target, c.fragility_records, c.fragility_duration, hz.building_period if hz.on_floor else None,
            longest_period() if enabled("isolator", ctx.config) else None, seed, hz.ground.code)


def _match_task(args):
    """match_records(*args), or the same set kept by an earlier run (pipeline/record_cache.py: matched
    once per user and code, not once per run). Module level: runs on a worker."""
    from .record_cache import matched

    return matched(args, _match_now)


def _match_now(args):
    """match_records(*args): the set matched now."""
    from ..assessment.study import match_records

    target, n, duration, T1, T_is, seed, code = args
    return match_records(target, n, duration, T1=T1, T_is=T_is, seed=seed, code=code)


# --- dynamics -------------------------------------------------------------------------------------
def dynamics_stage(ctx: Context, d: Path) -> dict:
    from ..assessment.analyses import DynamicsResults, histories, spectra, variabilities, variability_dict
    from ..assessment.limit_states import evaluate
    from ..assessment.study import design_set_data
    from ..hazard.motions import parse_spec
    from ..isolator.device import isolator_from_design
    from ..report.dynamics_plots import plot_spectrum
    from ..report.design_set_section import design_set_section
    from ..report.dynamics_section import dynamics_section, spectrum_titles
    from ..report.fragility_section import fragility_section
    from ..report.pipeline_plots import plot_history_pair, plot_variability_pair
    from ..rocking.sweeps import linspace_spec

    c, rtol, ex = ctx.config.dynamics, ctx.config.model.rtol, ctx.executor
    model, motion = ctx.model(), parse_spec(c.motion)[0]
    iso_model = ctx.iso_model()
    freqs, amps = linspace_spec(c.freq, "[dynamics] freq"), linspace_spec(c.amp, "[dynamics] amp", accel=True)
    pgas = linspace_spec(c.pga, "[dynamics] pga", accel=True)
    design = ctx.design() if c.isolated else None
    iso = isolator_from_design(design) if design else None
    period = design["T"] if iso is not None else None
    sp, spi = spectra(model, iso, freqs, amps, c.pulse, rtol, ex, iso_model=iso_model)
    for name, result, title in zip(("fixed", "isolated"), (sp, spi), spectrum_titles(c.pulse, sp, spi, iso, period)):
        if result is not None:
            write_json(d / f"spectrum_{name}.json", result.to_dict())
            plot_spectrum(result, d / f"spectrum_{name}.png", title)
    sw, swi, acc_i = variabilities(model, iso, motion, pgas, rtol, ex, iso_model=iso_model)
    write_json(d / "variability.json", variability_dict(sw, swi, acc_i))
    plot_variability_pair(sw, swi, acc_i, d / "variability.png")
    r = DynamicsResults(model, motion, iso, period, c.pulse, freqs, amps, pgas, sp, spi, sw, swi, acc_i,
                        *histories(model, iso, motion, rtol, iso_model=iso_model))
    data = r.data()
    rs, target = _design_set(ctx, d)
    ls = evaluate(model, rs.records, iso=iso, design=design, rtol=rtol, uplift_band=_uplift_band(ctx),
                  executor=ex, support=ctx.support(model.params), iso_model=iso_model,
                  iso_limits=ctx.iso_limits(_uplift_band(ctx)))
    write_json(d / "limit_states.json", ls.to_dict())
    data["limit_states"] = ls.to_dict()
    data.update(design_set_data(rs))
    study = _fragility_study(ctx, d, model, iso, rs, target) if c.fragility else None
    if study is not None:
        data.update(study.data())
    write_json(d / "history.json", r.history_dict())
    plot_history_pair(r.history, r.history_plate, r.history_coupled, d / "history.png")
    section = dynamics_section(r, data, study and fragility_section(study), c.isolated,
                               enabled("isolator", ctx.config))
    extra = design_set_section(rs, data["limit_states"])
    for key in ("tables", "text", "warnings", "figures"):
        section[key] = list(extra[key]) + list(section.get(key) or [])
    return {**section, "data": data}


def _match(ctx: Context, seed: int = 1):
    """A record set of the project's design target (the site's ground or floor spectrum), over the band of the
    building's period and, when the isolator stage is enabled, of every period its search can pick (the site's
    code: EC8 2 T_is, NTC 1.2 T_is of the longest, hazard/matching.py design_band), seeds seed.. . Matched
    once per run: the stages of one run share it (``ctx.record_sets``, by the matching's arguments)."""
    args = _match_args(ctx, seed)
    key = repr(args)
    if key not in ctx.record_sets:
        ctx.record_sets[key] = _match_task(args)
    return ctx.record_sets[key]


def _design_set(ctx: Context, d: Path | None = None):
    """The design record set (assessment/study.py, hazard/matching.py; :func:`_match`, seeds 1..N): one set,
    deterministic by its seeds, for the isolator's verification and the dynamics stage. ``d``: writes
    d/records/ (record_NN.csv, set.json, spectra.png); None writes nothing. Returns (RecordSet, target)."""
    from ..assessment.study import write_records

    hz = site(ctx.config)
    rs = _match(ctx)
    if d is not None:
        from ..report.fragility_section import records_title
        from ..report.hazard_plots import plot_spectra

        write_records(d / "records", rs)
        plot_spectra(rs, d / "records" / "spectra.png", records_title(rs, hz.target))
    return rs, hz.target


def _slc_pga(ctx: Context) -> float | None:
    """The design target's PGA at the collapse level (SLC, hazard/levels.py) when the isolator designs on a
    spectrum, else None."""
    from ..hazard.levels import collapse_site

    ic = ctx.config.isolator
    if not (ic.enabled and ic.spectrum):
        return None
    return collapse_site(site(ctx.config), ic.slc_spectrum)[0].pga


def _uplift_band(ctx: Context):
    """(low, high) of the weakest uplift acceleration a_min (m/s^2) at half and at double the base's
    contact tolerance when the params stage flagged the contact uncertain, else None."""
    base = read_json(ctx.dirs["params"] / "props.json").get("base") or {}
    rows = base.get("sensitivity") or []
    if not base.get("uncertain") or not rows:
        return None
    values = [float(r["a_min"]) for r in rows]
    return min(values), max(values)


def _fragility_study(ctx: Context, d: Path, model, iso, rs, target):
    """The dynamics stage's fragility study (assessment/study.py) on the design record set ``rs``:
    the isolator's friction at its bounds ([isolator] mu_low, mu_high; auto: mu times Table 25's
    spread, isolator.friction.friction_bounds), ``fragility_rounds`` rounds of adaptive
    levels; writes fragility.json, .csv and .png (one panel per limit state, the design PGA marked)."""
    from ..assessment.study import run_study
    from ..report.fragility_plots import plot_fragility

    c = ctx.config.dynamics
    ic = ctx.config.isolator
    study = run_study(model, iso, target, rs, c.fragility_levels, c.fragility_samples, ctx.config.model.rtol,
                      ctx.executor, mu_low=ic.mu_low, mu_high=ic.mu_high, rounds=c.fragility_rounds,
                      iso_model=ctx.iso_model(), support=ctx.support(model.params))
    study.result.write_json(d / "fragility.json")
    study.result.write_csv(d / "fragility.csv")
    plot_fragility(study.result, d / "fragility.png", design_im=study.pga, slc_im=_slc_pga(ctx))
    return study


def crosscheck_stage(ctx: Context, d: Path) -> dict:
    from ..crosscheck.contact import ContactSettings
    from ..crosscheck.isolator_scene import IsolatorScene
    from ..crosscheck.compare import compare
    from ..crosscheck.isolator_cases import groove_label
    from ..crosscheck.pendulum_scene import PendulumIsolator
    from ..crosscheck.statue_scene import StatueScene
    from ..crosscheck.world import SimSettings
    from ..hazard.motions import parse_spec
    from ..crosscheck.output import write_report
    from ..report.crosscheck_plots import plot_histories
    from ..report.crosscheck_section import crosscheck_section

    c = ctx.config.crosscheck
    motion = parse_spec(c.motion)[0]
    scene = StatueScene.from_body(ctx.load_body(), ctx.config.scan.direction)
    design = ctx.design() if c.isolator else None
    iso = None
    if design and c.groove == "exact":
        iso = PendulumIsolator.from_design(design, statue=scene)
    elif design:
        iso = IsolatorScene.from_design(design, statue=scene, grid=c.grid or None,
                                        groove="tiles" if c.groove == "tiles" else None)
    settings, contact = SimSettings(dt=c.dt, solver_iterations=c.iterations), ContactSettings()
    statue_settings = SimSettings(dt=c.statue_dt, solver_iterations=c.iterations)
    comp = compare(scene, motion, iso_scene=iso, settings=settings, statue_settings=statue_settings,
                   contact=contact, pulse_freq=c.pulse_freq,
                   quick=c.quick, e_L=ctx.config.model.e_L, e_R=ctx.config.model.e_R,
                   progress=lambda msg: ctx.say(f"3D: {msg} ..."))
    paths = plot_histories(comp.histories, d) | write_report(comp, d, {"scene": {"name": scene.name, "params": scene.params.to_dict()},
                                       "settings": settings.to_dict(), "statue_settings": statue_settings.to_dict(),
                                       "contact": contact.to_dict(),
                                       "motion": motion.to_dict()})
    section = crosscheck_section(comp, paths, isolator_wanted=c.isolator, design=design,
                                 isolator_enabled=enabled("isolator", ctx.config),
                                 isolator_model=None if iso is None else
                                 "the plate as a translating spherical pendulum (its exact kinematics), rolling "
                                 "resistance mu N, no ball contacts" if isinstance(iso, PendulumIsolator) else
                                 f"balls on grooves modelled as {groove_label(iso)}")
    if c.ensemble:
        from ..report.crosscheck_section import add_classification

        add_classification(section, *_set_classification(ctx, d, scene, iso, statue_settings, contact))
    if ctx.config.pedestal.size is not None:
        from ..report.crosscheck_section import add_stack_classification

        add_stack_classification(section, *_stack_classification(ctx, d, scene, statue_settings))
    return section


def _stack_classification(ctx: Context, d: Path, scene, settings):
    """The 2D/3D classification of the statue on its [pedestal] (crosscheck/stack_classification.py) over
    the design record set as matched and scaled to the other side of the pedestal's uplift: its mean PGA
    LIFT_RATIO x the stack's uplift acceleration when the matched records' is below it (the pedestal's
    outcomes then have positive cases), QUIET_RATIO x when above (negative cases); writes
    d/stack_classification.json. The 3D stack: the box pedestal with [sliding] mu_statue on its top and
    mu_pedestal on the floor, the statue's centre of mass at the 2D model's x2 from the pedestal's axis
    (the same G offset), across the excitation the centre of its base at [pedestal] position[1]. Returns
    (StackClassification or None, why it was not made or a note)."""
    import math

    from ..crosscheck.stack_classification import FREE_TIME_3D, LIFT_RATIO, QUIET_RATIO, classify_stack, lift_factor
    from ..crosscheck.stack_scene import StackScene
    from ..errors import InputError
    from ..quantities import G

    pd, sl = ctx.config.pedestal, ctx.config.sliding
    support = ctx.support(ctx.params())
    stack = support.stack
    base = scene.hull[scene.hull[:, 2] == 0.0]
    off_y = pd.position[1] + float(scene.com[1]) - 0.5 * float(base[:, 1].min() + base[:, 1].max())
    try:
        st3 = StackScene.box(scene, pd.size[0], pd.size[1], pd.size[2], pd.mass, offset_x=stack.x2, offset_y=off_y,
                             mu_top=sl.mu_statue, mu_floor=sl.mu_pedestal)
    except InputError as exc:
        return None, f"the 3D stack could not be built: {exc}"
    rs, _ = _design_set(ctx)
    recs = list(rs.records)
    motions, groups = list(recs), ["as matched"] * len(recs)
    a_up = min(stack.composite.a_L, stack.composite.a_R)
    mean = sum(r.pga for r in recs) / len(recs)
    ratio = LIFT_RATIO if mean < a_up else QUIET_RATIO     # the other side of the pedestal's uplift
    f = lift_factor(stack, recs, ratio)
    if math.isfinite(f) and abs(f - 1.0) > 0.05:
        motions += [r.scaled(f) for r in recs]
        groups += [f"x {f:.3g}"] * len(recs)
        note = (f"The design records (mean PGA {mean / G:.3f} g) were run as matched and scaled by {f:.3g} (mean PGA "
                f"{ratio:g} x the stack's uplift acceleration {a_up / G:.3f} g, "
                + ("so that the pedestal lifts" if ratio > 1 else "below it: the pedestal stays on the floor")
                + "): the pedestal's outcomes then have cases on both sides.")
    else:
        note = (f"The design records' mean PGA {mean / G:.3f} g is already about {ratio:g} x the stack's uplift "
                f"acceleration {a_up / G:.3f} g: run as matched only.")
    budget = ctx.config.crosscheck.ensemble_budget
    workers = max(1, int(getattr(ctx.executor, "workers", 2) or 1))
    est = sum(m.end + FREE_TIME_3D for m in motions) / 50.0 / workers     # ~50 x real time, measured 60-90
    if budget is not None and est > budget:
        return None, (f"the {len(motions)} 3D stack runs would take about {est:.0f} s on {workers} workers, over the "
                      f"budget of {budget:g} s ([crosscheck] ensemble_budget)")
    try:
        sc = classify_stack(support, st3, motions, model=ctx.model(), groups=groups, settings=settings,
                            executor=ctx.executor, workers=2,
                            progress=lambda msg: ctx.say(f"3D: {msg} ..."))
    except InputError as exc:
        return None, str(exc)
    write_json(d / "stack_classification.json", sc.to_dict())
    return sc, note


def _set_classification(ctx: Context, d: Path, scene, iso, settings, contact):
    """The 2D/3D classification over the design record set (crosscheck/set_classification.py) around the
    dynamics stage's 2D fragility medians; writes d/classification.json. Returns (SetClassification or
    None, why it was not made or None)."""
    from ..crosscheck.pendulum_scene import PendulumIsolator
    from ..crosscheck.set_classification import QUICK_FACTORS, anchors, classify_design_set
    from ..crosscheck.classification import FACTORS
    from ..errors import InputError

    frag = ctx.dirs.get("dynamics") and ctx.dirs["dynamics"] / "fragility.json"
    if not frag or not frag.is_file():
        return None, ("the classification over the design records needs the dynamics stage's fragility curves: "
                      "run the dynamics stage with [dynamics] fragility = true")
    fj = read_json(frag)
    if not isinstance(fj, dict) or fj.get("im", "pga") != "pga" or not isinstance(fj.get("curves"), dict):
        return None, f"the dynamics stage's {frag.name} holds no PGA fragility curves to put the levels around"
    curves, levels = fj["curves"], fj.get("levels") or []
    # the levels around the classified limit states' curves (assessment/states.py; on the isolator
    # overturning alone, not the capacity's, which capacity_isolated anchors)
    fixed = anchors(curves, [states.curve(k, "fixed") for k in states.CLASSIFIED if states.curve(k, "fixed")],
                    levels)
    isolated = anchors(curves, [states.OVERTURNING_ALONE_ISOLATED if k == states.OVERTURNING
                                else states.curve(k, "isolated") for k in states.CLASSIFIED], levels)
    notes = []
    if iso is not None and not isinstance(iso, PendulumIsolator):
        notes.append("the isolated classification runs on the exact isolator scene only ([crosscheck] groove = "
                     "\"exact\")")
        iso = None
    elif iso is not None and not isolated:
        notes.append("no isolated classification: the dynamics stage studied no isolated fragility curve "
                     "([dynamics] isolated = false)")
        iso = None
    rs, _ = _design_set(ctx)
    factors = QUICK_FACTORS if ctx.config.crosscheck.quick else FACTORS
    try:
        sc = classify_design_set(scene, ctx.model(), rs, fixed, iso_scene=iso, anchors_isolated=isolated,
                                 settings=settings, contact=contact, executor=ctx.executor, factors=factors,
                                 budget_s=ctx.config.crosscheck.ensemble_budget,
                                 progress=lambda msg: ctx.say(f"3D: classification over the design records, {msg} ..."))
    except InputError as exc:           # the case-by-case cross-check above stands without it
        return None, str(exc)
    iso_note = "; ".join(notes) or None
    write_json(d / "classification.json", sc.to_dict())
    return sc, iso_note


def _one_blas_thread(stage):
    """``stage`` with the BLAS of this process on one thread, as every sweep's task already is
    (compute/executors.py). What these stages compute here themselves goes through BLAS only in products
    of coordinates (a plate's mesh, a figure's paths), which one thread gives bit for bit as two; but a
    second thread spins for a while after each product: about 0.3 s of CPU of the default run. (The
    params stage keeps the default: its mass properties' sums follow the thread count, and its numbers
    stay those of earlier runs.)"""
    def run(ctx: Context, d: Path) -> dict:
        from threadpoolctl import threadpool_limits

        with threadpool_limits(limits=1, user_api="blas"):
            return stage(ctx, d)

    run.__name__, run.__doc__ = stage.__name__, stage.__doc__
    return run


STAGES = {"params": params_stage, "prototype": prototype_stage, "isolator": _one_blas_thread(isolator_stage),
          "dynamics": _one_blas_thread(dynamics_stage), "crosscheck": crosscheck_stage}
assert tuple(STAGES) == STAGE_NAMES, "a stage is named in config.STAGE_NAMES and run here"
# stage -> (stages it needs, stages it reads when they are enabled, config sections it reads)
DEPENDS = {"params": ((), (), ("scan",)), "prototype": ((), (), ("scan", "prototype")),
           "isolator": (("params",), (), ("model", "sliding", "pedestal", "isolator", "building",
                                          "dynamics:fragility_records,fragility_duration")),
           "dynamics": (("params",), ("isolator",), ("model", "sliding", "pedestal", "isolator", "building",
                                                      "dynamics")),
           "crosscheck": (("params",), ("isolator", "dynamics"),
                          ("model", "sliding", "pedestal", "scan", "crosscheck", "building",
                           "dynamics:fragility_records,fragility_duration"))}


def enabled(name: str, cfg: ProjectConfig) -> bool:
    sec = {"prototype": cfg.prototype, "isolator": cfg.isolator, "dynamics": cfg.dynamics,
           "crosscheck": cfg.crosscheck}.get(name)
    return True if sec is None else bool(sec.enabled)

