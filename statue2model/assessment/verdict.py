"""The assessment a conservator reads first: hazard, fixed base, isolator, recommendation.

Built from what the stages wrote (their manifests and the isolator's design.json),
so a run taken from the cache gets the same verdict. Every margin is a ratio
capacity / demand with what it compares, so > 1 means the statue is on the safe
side, < 1 that it is not:

    hazard     the design spectrum ([isolator] spectrum: code, ground or soil type,
               a_g) and its peak ground acceleration PGA = a_g S at the site; on an upper
               floor ([building]) the floor spectrum, whose Se(0), the peak floor
               acceleration, is then the design PGA of every check below
    fixed      lifts?    uplift acceleration (alpha-reduced for the imperfect model)
                         against the design PGA  (a quasi-static criterion: the ground
                         acceleration that starts rocking)
               overturns? the lowest PGA of the variability sweep at which the statue
                         overturned ([dynamics] motion scaled), against the design PGA
               slides?   with the design records' limit states: the sliding rows (the statue on
                         its support, the pedestal on the floor) exceeded; without them (quasi-
                         static): it would slide before it lifts (b/h > mu_s) AND the design PGA
                         reaches mu_s g (no regime is claimed that the design level does not reach)
    isolated   travel    the isolator's capacity against the design displacement demand
               felt      the uplift acceleration against what the statue feels on the
                         plate (the design's Se(T) + mu g)
               travel    margin = capacity / travel need, the need being the design's own
                         DISPLACEMENT_MARGIN x SDe(T) + mu R_hat (isolator/design.py: 1.5 for
                         gamma_x and the two components, mu R_hat the friction's resting offset)
               analyses  the lowest PGA at which the statue on the isolator overturned or
                         the isolator's capacity was exceeded, against the design PGA
    fragility  the dynamics stage's fragility study (assessment/study.py): median failure
               PGAs fixed and isolated with their bands, the probabilities at the design PGA,
               the isolator's ratio of medians (one line, :func:`fragility`)

The recommendation is one plain line; the same verdict goes to run.json, the console
summary and the top of report.html.

Example
-------
>>> v = verdict(VerdictInputs(hazard(None), {"a_min": 2.71, "a_L": 4.16, "a_R": 2.71, "h": 0.73,
...                                          "b_L": 0.31, "b_R": 0.20}))
>>> v["fixed"]["lifts"], round(v["hazard"]["pga"] / 9.81, 4), v["code"]
(True, 0.2874, 'RUN_ISOLATOR_STAGE')
>>> v["recommendation"]
'the statue lifts at the design level (uplift 0.276 g < design PGA 0.287 g) and no isolator was designed: run the isolator stage'

The pipeline's adapter, ``statue2model.pipeline.assess.assess(stages, dirs, cfg)``, reads the stages'
manifests and files into :class:`VerdictInputs` (typed: design.json as a DesignRecord, the limit
states as LimitStates) and calls :func:`verdict`.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from ..quantities import G
from . import states
from .recommendation import Code, Facts, bullets, g_text, headline, mm_text, prob_text, status_of
from .limit_states import LimitState, LimitStates
from .records import DesignRecord
DEFAULT_SPECTRUM = "ec8:ag=0.25g,ground=C,type=1"
ILLUSTRATION = " (illustration: one record scaled over PGA, not the basis of the recommendation)"
"""Appended to what the variability sweep (one record) says once the design set's limit states decide."""


def _n(x: float | None, spec: str = ".2f") -> str:
    """A number for a sentence: '-' when it is None or not finite (never 'nan' or 'inf')."""
    return "-" if x is None or not math.isfinite(x) else format(x, spec)


def _ratio(cap: float | None, demand: float | None) -> float | None:
    if cap is None or demand is None or demand <= 0 or not math.isfinite(demand):
        return None
    return cap / demand


def hazard(cfg) -> dict:
    """The design earthquake of the configuration where the object stands: the ground spectrum
    (code, ground/soil, a_g, S) and, on an upper floor ([building]), the floor spectrum with its
    building; ``pga`` (m/s^2) is the target's Se(0): a_g S on the ground, the peak floor
    acceleration on a floor (statue2model.hazard.site)."""
    from ..hazard.site import site_of

    hz = site_of(cfg, DEFAULT_SPECTRUM)
    text, sp = hz.spectrum, hz.ground
    fields = dict(kv.split("=", 1) for kv in text.split(":", 1)[-1].split(",") if "=" in kv)
    soil = fields.get("ground") or fields.get("soil") or "A"
    return {"spectrum": text, "code": sp.code, "soil": soil, "a_g": sp.a_g, "S": sp.S, "pga": hz.pga,
            "ground_pga": hz.ground_pga, "limit_state": sp.limit_state, "floor": hz.floor if hz.building else None,
            "on_floor": hz.on_floor, "building": None if hz.building is None else hz.building.to_dict(),
            "target": hz.target.to_dict(), "text": hz.text}


@dataclass(frozen=True)
class VerdictInputs:
    """What the verdict decides on, typed. The pipeline's adapter (pipeline/assess.py ``assess``) builds
    it from the stages' manifests and files; a caller may build it by hand.

    hazard          :func:`hazard` of the configuration (the design target; ``pga`` in m/s^2)
    params          the params stage's data (a_min, b_L, b_R, h, ...; SI), None: it did not run
    alpha           the imperfect model's min(alpha_L, alpha_R) (1: Housner's)
    model_kind      "housner" or "imperfect"          mu_static   the static friction (None: not given)
    dynamics        the dynamics stage's data (first_*_pga, fragility_*), None: it did not run
    limit_states    the design record set's table (:class:`LimitStates`), None without it
    design          the isolator design (:class:`DesignRecord`), None without it
    classification  the 3D cross-check's classification over the design records, None without it
    record          the label of the dynamics stage's single record (the sweep's), None
    """

    hazard: dict
    params: dict | None
    alpha: float = 1.0
    model_kind: str = "housner"
    mu_static: float | None = None
    dynamics: dict | None = None
    limit_states: LimitStates | None = None
    design: DesignRecord | None = None
    classification: dict | None = None
    record: str | None = None


def verdict(inp: VerdictInputs) -> dict:
    """The verdict (see the module docstring) of the typed inputs ``inp``."""
    hz = inp.hazard
    pga = hz["pga"]
    out = {"hazard": hz, "fixed": {}, "isolated": {}, "lines": [], "recommendation": ""}
    params = inp.params
    if params is None:
        out["recommendation"] = "no verdict: the params stage did not run"
        out.update(code=Code.NO_VERDICT.value, headline=headline(Code.NO_VERDICT, Facts()), bullets=[],
                   status=status_of(Code.NO_VERDICT))
        return out
    alpha = inp.alpha
    uplift = alpha * params.get("a_min", params.get("a_R"))
    fixed = {"uplift": uplift, "alpha": alpha, "lifts": uplift <= pga, "uplift_margin": _ratio(uplift, pga)}
    b_over_h = min(params.get("b_L", math.inf), params.get("b_R", math.inf)) / params.get("h", math.nan)
    mu_s = inp.mu_static
    ls = inp.limit_states
    fixed["slides_first"] = bool(mu_s is not None and math.isfinite(b_over_h) and b_over_h > mu_s)
    slide_rows = [r for r in (_row(ls, states.SLIDING, "fixed"), _row(ls, states.PEDESTAL_SLIDING, "fixed"))
                  if r is not None]
    if slide_rows:
        fixed["slides"] = any(r.exceeded for r in slide_rows)
    else:
        fixed["slides"] = fixed["slides_first"] and pga >= mu_s * G
    dyn = inp.dynamics
    if dyn is not None:
        ot = dyn.get("first_overturn_pga_fixed")
        fixed["first_overturn_pga"] = ot
        fixed["overturn_margin"] = _ratio(ot, pga)
        fixed["overturns"] = ot is not None and ot <= pga
    out["fixed"] = fixed
    lines = [f"Hazard: {hz['text']}."]
    state = "lifts and rocks" if fixed["lifts"] else "stays in full contact"
    if fixed["slides_first"]:
        state += (f"; it would slide before it lifts (b/h {b_over_h:.2f} > mu_s {mu_s:.2f}), and the design PGA "
                  + ("reaches" if pga >= mu_s * G else "stays below") + f" mu_s g = {g_text(mu_s * G)}")
    line = (f"Fixed base: the statue {state} at the design level (uplift {g_text(uplift)} vs design PGA {g_text(pga)}, "
            f"margin {_n(fixed['uplift_margin'])})")
    sweep_note = ILLUSTRATION if ls else ""     # with the design set's limit states, a sweep only illustrates
    if "overturn_margin" in fixed:
        if fixed["first_overturn_pga"] is None:
            line += "; it did not overturn at any PGA of the variability sweep" + sweep_note
        else:
            line += (f"; it overturned from {g_text(fixed['first_overturn_pga'])} in the variability sweep "
                     f"(margin {_n(fixed['overturn_margin'])} on the design PGA)" + sweep_note)
    lines.append(line + ".")

    design = inp.design
    isolated = {}
    if design is not None:
        cap, demand, felt = design.capacity, design.travel_need, design.felt_or_spectral
        isolated = {"passed": design.passed, "conditional": False, "what_would_pass": design.wwp_text,
                    "reason_key": design.wwp_reason, "th_margins": design.th_margins or None, "capacity": cap,
                    "travel_demand": demand, "travel_margin": _ratio(cap, demand), "felt": felt,
                    "felt_margin": _ratio(uplift, felt), "T": design.T, "R": design.R, "r": design.r,
                    "n_grooves": design.n_grooves, "layout": design.layout, "surface": design.surface,
                    "cost": design.cost, "slc_rule": design.slc_rule, "reserve_pga": design.reserve_pga,
                    "sets": design.n_sets, "tail": design.tail}
        if dyn is not None:
            fail = dyn.get("first_failure_pga_isolated", dyn.get("first_overturn_pga_isolated"))
            isolated["first_failure_pga"] = fail
            isolated["failure_margin"] = _ratio(fail, pga)
            cap_pga = dyn.get("first_capacity_pga_isolated")
            isolated["failure_kind"] = ("isolator capacity exceeded" if fail is not None and cap_pga == fail
                                        else "overturned" if fail is not None else None)
            if inp.record is not None:
                isolated["record"] = inp.record
        if isolated["passed"]:
            th = isolated.get("th_margins") or {}
            line = (f"Isolator: {isolated['n_grooves']} {design.ball_material or ''} balls of "
                    f"{mm_text(2 * (isolated['r'] or 0), '.0f')} mm on {isolated['surface']}, plates "
                    f"{mm_text(design.side, '.0f')} mm square, T {_n(isolated['T'])} s, travel capacity "
                    f"{mm_text(cap)} mm, about {design.cost or 0:.0f} EUR; verified by time histories on "
                    f"{isolated['sets']} record sets: margins travel {_n(finite_number(th.get('travel')))}, felt "
                    f"acceleration {_n(finite_number(th.get('acceleration')))}, ball load "
                    f"{_n(finite_number(th.get('bearing')))} at the design level, travel "
                    f"{_n(finite_number(th.get('travel_slc')))} and ball load {_n(finite_number(th.get('bearing_slc')))}"
                    f" at the collapse level")
            if th.get("reserve") is not None:
                line += (f", travel {_n(finite_number(th.get('reserve')))} where half the records overturn the "
                         f"statue without it ({g_text(isolated['reserve_pga'])})")
                tail = isolated.get("tail") or {}
                if tail and not tail.get("dominates"):
                    n_rec = len(tail.get("fixed_sorted") or [])
                    line += (f"; below that its failure curve lies left of the fixed base's overturning curve: from "
                             f"{g_text(tail['worse_from'])} {tail['device_fails']} of {n_rec} records pass its travel "
                             f"capacity while {tail['fixed_fails']} overturn the statue without it")
            if "first_failure_pga" in isolated:
                f_ = isolated["first_failure_pga"]
                line += ("; no overturning and no capacity exceeded at any PGA of the sweep" if f_ is None else
                         f"; it overturned or exceeded the capacity from {g_text(f_)} in the sweep "
                         f"(margin {_n(isolated['failure_margin'])} on the design PGA)") + sweep_note
            lines.append(line + ".")
        else:
            isolated["reason"] = design.wwp_text or design.failure or design.failing_checks()
            lines.append(f"Isolator: {isolated['reason']}")
    out["isolated"] = isolated
    if ls:
        out["limit_states"] = ls.to_dict()
        lines.insert(1, limit_state_line(ls))
    fr = fragility(dyn, pga, design is not None)
    if fr:
        out["fragility"] = fr
        lines.append(fr["line"])
    out["lines"] = lines
    code, out["recommendation"] = (decide_from_limit_states(fixed, isolated, ls) if ls
                                   else decide(fixed, isolated, pga))
    cc = crosscheck_line(inp.classification)
    if cc:
        out["crosscheck"] = cc
        lines.append(cc["line"])
    # the 2D answer not confirmed by the 3D physics: the doubt is carried into the colour
    out["status"] = status_of(code, doubt=bool(cc and cc["missed"]))
    f = facts(hz, fixed, isolated, ls, fr, design)
    out.update(code=code.value, headline=headline(code, f), bullets=bullets(code, f))
    out.update(basis(ls, hz, inp.model_kind))
    return out


REASONS = {"friction": "the balls' own rolling resistance would rock it", "pit": "the balls would not leave "
           "the pits their weight presses into the grooves before it rocks", "acceleration": "even the softest "
           "device passes it more acceleration than lifts it", "plate_size": "the device it needs is larger "
           "than a panel", "reserve": "the device it needs to keep a reserve is larger than a panel",
           "ball_load": "it is too heavy for the groove surfaces in range", "other": "no device in range passes "
           "every check"}
"""The short plain words of each reason no device works (isolator/design.py what_would_pass's ``reason``)."""


def facts(hz: dict, fixed: dict, isolated: dict, ls: LimitStates | None, fr: dict | None,
          design: DesignRecord | None) -> Facts:
    """The numbers of the headline and bullets (recommendation.Facts), taken from the same rows the
    reasoning prints: with the design records, full contact's capacity (the low end of the contact
    band) is the uplift, the rows' counts are the records'."""
    fc = _row(ls, "full_contact", "fixed") if ls else None
    ot = _row(ls, "overturning", "fixed") if ls else None
    uplift = fc.capacity if fc else finite_number(fixed.get("uplift"))

    def count(r):
        return None if r is None else r.n_exceeding

    device, travel_margin, felt_ratio, gov, gov_k = "", None, None, "", None
    if isolated and isolated.get("passed") and design is not None:
        device = (f"{isolated.get('n_grooves')} {design.ball_material or ''} balls of "
                  f"{mm_text(2 * (isolated.get('r') or 0))} mm on {isolated.get('surface')}, plates "
                  f"{mm_text(design.side)} mm square").replace("  ", " ")
        if isolated.get("cost"):
            device += f", about {isolated['cost']:.0f} EUR"
        cap = _row(ls, "capacity", "isolated") if ls else None
        r = None if cap is None else cap.ratio
        if r is not None and r > 0:
            travel_margin = 1.0 / r - 1.0
        elif finite_number(isolated.get("travel_margin")) is not None:
            travel_margin = isolated["travel_margin"] - 1.0
        ifc = _row(ls, "full_contact", "isolated") if ls else None
        felt_ratio = None if ifc is None else ifc.ratio
        bad = [r_ for r_ in (ls.base_rows("isolated") if ls else ()) if r_.exceeded]
        if bad:
            worst = max(bad, key=lambda r_: r_.ratio or 0.0)
            gov, gov_k = worst.title, count(worst)
    lsf = (fr or {}).get("limit_states") or {}
    p_over = finite_number(((lsf.get("overturning") or {}).get("fixed") or {}).get("p_design"))
    p_fail = finite_number(((lsf.get("overturning") or {}).get("isolated") or {}).get("p_design"))
    if not lsf and fr:
        p_over, p_fail = finite_number(fr.get("p_design_fixed")), finite_number(fr.get("p_design_isolated"))
    slide_rows = [r for r in (_row(ls, states.SLIDING, "fixed"), _row(ls, states.PEDESTAL_SLIDING, "fixed"))
                  if r is not None] if ls else []
    sl = max(slide_rows, key=lambda r: (r.exceeded, r.ratio if r.ratio is not None else math.inf), default=None)
    on_pedestal = _row(ls, states.PEDESTAL_SLIDING, "fixed") is not None if ls else False
    slide_what = ("" if sl is None else "the pedestal slides on the floor" if sl.name == states.PEDESTAL_SLIDING
                  else "it slides on the pedestal's top" if on_pedestal else "it slides on the floor")
    pot = _row(ls, states.PEDESTAL_OVERTURNING, "fixed") if ls else None
    return Facts(pga=finite_number(hz.get("pga")), hazard=_hazard_words(hz), uplift=uplift,
                 slide=None if sl is None else finite_number(sl.demand),
                 slide_cap=None if sl is None else finite_number(sl.capacity), k_slide=count(sl),
                 slide_what=slide_what, k_ped_over=count(pot),
                 n=ls.n_records if ls else None, k_lift=count(fc), k_over=count(ot),
                 device=device, cost=isolated.get("cost")
                 if isolated else None, travel_margin=travel_margin, iso_governing=gov, iso_k=gov_k,
                 iso_felt_ratio=felt_ratio, p_over_fixed=p_over, p_fail_isolated=p_fail if isolated else None,
                 reason=REASONS.get(isolated.get("reason_key") or "", "") if isolated and not isolated.get("passed")
                 else "")


def _hazard_words(hz: dict) -> str:
    """'EC8, ground C' or 'NTC 2018, soil B, on floor 2 of 4': the design target in a few words."""
    code = {"ec8": "EC8", "ntc": "NTC 2018"}.get(str(hz.get("code") or "").lower(), str(hz.get("code") or ""))
    soil = hz.get("soil")
    out = f"{code}, ground {soil}" if code and soil else code
    if hz.get("on_floor") and hz.get("floor") is not None:
        out += f", on floor {hz['floor']}"
    return out


def basis(ls: LimitStates | None, hz: dict, kind: str = "housner") -> dict:
    """The verdict box's criteria, assumptions and limitations (lists of sentences): what the
    recommendation was decided on and what it does not cover."""
    n = ls.n_records if ls else None
    if ls:
        criteria = [" ".join(RULE.split()),
                    f"Each limit state's demand is the {ls.statistic} over the {n} design records "
                    "(NTC 2018 7.3.5, EN 1998-1 4.3.3.4.3); a limit state is exceeded at demand / capacity >= 1, "
                    "overturning when any record overturns."]
    else:
        criteria = ["Without the dynamics stage: the quasi-static uplift check (uplift acceleration against the "
                    "design PGA) and the isolator design's spectral checks only."]
    assumptions = [
        f"The design target: {hz.get('text', 'the design spectrum')}.",
        "The design records are artificial, matched to the design target to the codes' rules "
        "(dynamics/records/set.json lists each rule and each record's PGA, PGV, PGD).",
        "The statue is a rigid body rocking in the plane of the excitation direction (2D model, "
        + ("imperfect model with the identified alpha and theta" if kind == "imperfect" else
           "Housner's model with the angular-momentum restitution of eq. 15") + "); sliding is computed apart (exact rigid-plastic sliding with static and kinetic Coulomb friction, "
        "no slide-rock coupling), and a body that would slide before it lifts (b/h > mu_s) has its rocking "
        "numbers flagged per record.",
        "The isolator is the thesis' rolling-ball device with the measured rolling friction; the ball load it "
        "carries is compared with the thesis' tests on beech grooves (ch. 6.4)."]
    limitations = [
        "One horizontal direction at a time; vertical ground motion and torsion are not modelled (the 3D "
        "cross-check, when run, says where the 2D model and 3D contact physics agree).",
        "Results of a single record (the variability sweep, the example history) are illustrations, not the "
        "basis of the recommendation.",
        "Material damage at the contact (chipping, the statue's own strength) is not assessed; uplift is treated "
        "as damage to be avoided (the thesis' full-contact objective)."]
    return {"criteria": criteria, "assumptions": assumptions, "limitations": limitations}


def _row(ls: LimitStates | None, name: str, base: str) -> LimitState | None:
    """The row of ``name`` on ``base``, None when the table has none."""
    if ls is None:
        return None
    return next((r for r in ls.rows if r.name == name and r.base == base), None)


def _rv(r: LimitState | None) -> str:
    """'demand vs capacity (ratio r, k of n records)' of a limit-state row, in its unit."""
    if r is None:
        return "-"
    u = r.unit

    def q(x):
        x = finite_number(x)
        return "-" if x is None else (g_text(x) if u == "m/s^2" else f"{mm_text(x)} mm" if u == "m" else
                                      f"{x:.0f} N" if u == "N" else f"{x:.3g}")
    ratio = finite_number(r.ratio)
    return f"{q(r.demand)} vs {q(r.capacity)}, ratio {'-' if ratio is None else f'{ratio:.2f}'}"


def limit_state_line(ls: LimitStates) -> str:
    """The verdict's line on the limit states at the design level (the design record set)."""
    n, stat = ls.n_records, ls.statistic
    parts = []
    for base, label in (("fixed", "Fixed base"), ("isolated", "On the isolator")):
        rows = ls.base_rows(base)
        if not rows:
            continue
        bits = []
        for r in rows:
            rule = {"mean": f"the {stat}", "any": "any record", "static": "static"}[states.get(r.name).rule]
            bits.append(f"{r.title} {'EXCEEDED' if r.exceeded else 'holds'} ({_rv(r)}; {r.n_exceeding} of {n} records "
                        f"exceed it alone; judged on {rule})")
        parts.append(f"{label}: " + "; ".join(bits))
    band = ls.uplift_band
    doubt = ""
    if band and None not in band:
        doubt = (f" The base contact is uncertain: the weakest uplift acceleration lies between {g_text(band[0])} and "
                 f"{g_text(band[1])} (half and double the contact tolerance); full contact is checked against the low end.")
    return (f"Design level ({stat} over the {n} design records matched to the design target, NTC 2018 7.3.5 / "
            f"EC8 4.3.3.4.3): " + ". ".join(parts) + "." + doubt)


RULE = """The recommendation, from the limit states at the design level (the design record set):
with a pedestal that overturns with the statue, anchor or widen the pedestal first (an isolator
under the statue does not hold it);
no isolator needed when the statue stays in full contact on a fixed base (and does not overturn),
said with a warning when single records lift it while the mean holds, and restrain it instead
when it (or its pedestal) slides beyond the allowance;
else, with a passing isolator design, isolate when on the isolator full contact, rocking,
overturning and the travel capacity all hold; the ball load on the grooves is then a condition
of the recommendation when it is exceeded; any of the others exceeded: the designed isolator
does not protect. Results of one record (the variability sweep, the synthetic or El Centro
history) are illustrations and never enter the rule."""


def recommend_from_limit_states(fixed: dict, isolated: dict, ls: LimitStates) -> str:
    """One plain line from the limit-state table ``ls`` by :data:`RULE`."""
    return decide_from_limit_states(fixed, isolated, ls)[1]


def decide_from_limit_states(fixed: dict, isolated: dict, ls: LimitStates) -> tuple[Code, str]:
    """(the recommendation code, its reasoning in one line) from the limit-state table ``ls`` by
    :data:`RULE`."""
    n = ls.n_records
    slid = [r for r in (_row(ls, states.SLIDING, "fixed"), _row(ls, states.PEDESTAL_SLIDING, "fixed"))
            if r is not None and r.exceeded]
    if fixed.get("slides") and not slid and _row(ls, states.SLIDING, "fixed") is None:
        return Code.SLIDES, ("the statue would slide before it lifts and the design PGA reaches its friction; this "
                             "table has no sliding row: run the dynamics stage again to measure how far it slides")
    pot = _row(ls, states.PEDESTAL_OVERTURNING, "fixed")
    if pot is not None and pot.exceeded:
        return Code.PEDESTAL_OVERTURNS, (f"the pedestal overturns with the statue in {pot.n_exceeding} of {n} design "
                                         "records: anchor the pedestal to the floor or widen its base; an isolator "
                                         "under the statue does not hold the pedestal")
    fc, ot = _row(ls, states.FULL_CONTACT, "fixed"), _row(ls, states.OVERTURNING, "fixed")
    if fc is not None and not fc.exceeded and not (ot is not None and ot.exceeded):
        if slid:
            return Code.SLIDES, ("it stays in full contact but slides beyond what it may at the design level: " + "; ".join(
                f"{r.title} ({_rv(r)}; {r.n_exceeding} of {n} records; {r.details.get('capacity_source', '')})"
                for r in slid) + ": restrain it (a stop or an anchorage) or give it room; rocking needs no isolator")
        k = fc.n_exceeding
        if k:
            return Code.NO_ISOLATOR_BUT_RECORDS_LIFT, (f"no isolator needed by the codes' mean of effects, but {k} of {n} design records lift the statue "
                    f"on their own: over the {n} records the mean peak ground acceleration toward its weaker side "
                    f"stays below its uplift ({_rv(fc)}), so the code's check holds; a record like those {k} would "
                    "rock it (see the fragility of full contact), a reason to consider isolating it")
        return Code.NO_ISOLATOR, (f"no isolator needed at the design level: over the {n} design records the statue "
                                  f"stays in full contact on a fixed base (peak ground acceleration {_rv(fc)})")
    lifts = (f"the statue lifts on a fixed base at the design level ({_rv(fc)}; "
             f"{'-' if fc is None else fc.n_exceeding} of {n} records"
             + (f", overturning in {ot.n_exceeding}" if ot is not None and ot.exceeded else "") + ")")
    if not isolated:
        return Code.RUN_ISOLATOR_STAGE, f"{lifts} and no isolator was designed: run the isolator stage"
    if not isolated.get("passed"):
        return Code.NO_DEVICE_IN_RANGE, f"no isolator in range works: {isolated.get('reason') or 'see the isolator checks'}"
    if _row(ls, states.FULL_CONTACT, "isolated") is None:
        return Code.RUN_ISOLATED_DYNAMICS, (f"{lifts}; the isolator was designed but not analysed over the design records (the dynamics stage "
                "ran without it): run the dynamics stage with [dynamics] isolated = true")
    # every state on the device but the ball load, which is said on its own below
    bad = [r for r in (_row(ls, s.id, "isolated") for s in states.on_base("isolated") if s.id != states.BEARING)
           if r is not None and r.exceeded]
    if bad:
        return Code.DEVICE_DOES_NOT_PROTECT, ("the designed isolator does not protect at the design level: " + "; ".join(
            f"{r.title} exceeded ({_rv(r)}; {r.n_exceeding} of {n} records)" for r in bad))
    ifc, cap = _row(ls, states.FULL_CONTACT, "isolated"), _row(ls, states.CAPACITY, "isolated")
    ok = (f"over the {n} design records the statue stays in full contact on it (felt acceleration {_rv(ifc)}) "
          f"and the plate's travel stays within its capacity (travel with margin {_rv(cap)})")
    bearing = _row(ls, states.BEARING, "isolated")
    if bearing is not None and bearing.exceeded:
        return Code.DEVICE_DOES_NOT_PROTECT, (f"the designed isolator does not protect at the design level: "
                                              f"{bearing.title} exceeded ({_rv(bearing)})")
    cost = isolated.get("cost")
    return Code.ISOLATE, "isolate with the designed device" + (f" (about {cost:.0f} EUR)" if cost else "") + f": {ok}"


def fragility(dyn: dict | None, pga: float, isolated: bool) -> dict:
    """The fragility study's numbers for the verdict (the dynamics stage's fragility_* data): median
    failure PGAs, the probability at the design PGA, the isolator's ratio of medians, and one line."""
    if not dyn or not dyn.get("fragility_runs"):
        return {}
    mf, mi = finite_number(dyn.get("fragility_median_fixed")), finite_number(dyn.get("fragility_median_isolated"))
    pf, pi = finite_number(dyn.get("fragility_p_design_fixed")), finite_number(dyn.get("fragility_p_design_isolated"))

    def p_text(what, p, side):
        if p is not None:
            return f", P({what}) at the design PGA {prob_text(p)}"
        why = dyn.get(f"fragility_p_design_{side}_reason")
        return f", P({what}) at the design PGA not known ({why})" if why else ""

    def med(m, side):
        if m is None:
            why = dyn.get(f"fragility_median_{side}_reason") or dyn.get(f"fragility_status_{side}") or "undefined"
            return f"not fitted ({why})"
        ci = dyn.get(f"fragility_median_ci_{side}") or [None, None]
        lo, hi = (finite_number(x) for x in (list(ci) + [None, None])[:2])
        if lo is not None and hi is not None:
            return f"{g_text(m)} ({g_text(lo)}-{g_text(hi)})"
        why = dyn.get(f"fragility_median_ci_{side}_reason")
        if lo is None and hi is None:
            return g_text(m) + (f" ({why})" if why else "")
        end = f"band from {g_text(lo)}" if lo is not None else f"band up to {g_text(hi)}"
        return f"{g_text(m)} ({end}" + (f"; {why})" if why else ")")

    fl = dyn.get("fragility_limit_states")
    if isinstance(fl, dict) and fl:
        return {"median_fixed": mf, "median_isolated": mi, "p_design_fixed": pf, "p_design_isolated": pi,
                "ratio": finite_number(dyn.get("fragility_ratio")), "ratio_ci": dyn.get("fragility_ratio_ci"),
                "limit_states": fl, "line": limit_state_fragility_line(dyn, fl, isolated)}
    line = (f"Fragility ({dyn['fragility_runs']} runs per base over records matched to the design spectrum): "
            f"median overturning PGA on a fixed base {med(mf, 'fixed')}" + p_text("overturning", pf, "fixed"))
    r = finite_number(dyn.get("fragility_ratio"))
    if isolated:
        line += (f"; on the isolator, median failure PGA (overturning or capacity exceeded) {med(mi, 'isolated')}"
                 + p_text("failure", pi, "isolated"))
        if r is not None:
            ci = [finite_number(x) for x in (list(dyn.get("fragility_ratio_ci") or []) + [None, None])[:2]]
            why = dyn.get("fragility_ratio_ci_reason")
            line += f"; the isolator multiplies the median by {r:.2f}" + (
                f" ({ci[0]:.2f}-{ci[1]:.2f})" if None not in ci else f" ({why})" if why else "")
    return {"median_fixed": mf, "median_isolated": mi, "p_design_fixed": pf, "p_design_isolated": pi,
            "ratio": r, "ratio_ci": dyn.get("fragility_ratio_ci"), "line": line + "."}


FRAGILITY_TITLES = {s.id: s.fragility_title for s in states.REGISTRY if s.curves}


_BASE = {"fixed": "fixed base", "isolated": "on the isolator"}
_STATE = {s.id: s.noun for s in states.REGISTRY}


def crosscheck_line(cls: dict | None) -> dict | None:
    """The 3D cross-check's classification over the design records (crosscheck stage data
    ``classification``: base -> limit state -> status, accuracy, its lower bound, runs, why) as one
    line of the verdict: where the 2D model's yes/no agrees with the 3D physics and, with its size,
    where agreement is not shown. None without a classification.

    >>> c = crosscheck_line({"fixed": {"full_contact": {"status": "met", "accuracy": 1.0, "accuracy_lo": 0.95, "n": 70},
    ...                      "overturning": {"status": "missed", "accuracy": 0.7, "accuracy_lo": 0.58, "n": 70,
    ...                                      "why": "recall 2/9"}}})
    >>> c["missed"], c["line"].split(": ")[1]
    (['fixed base overturning'], 'the 2D model agrees with the 3D physics on fixed base uplift (accuracy 1.00, lower bound 0.95, 70 runs); NOT shown on fixed base overturning (accuracy 0.70, lower bound 0.58, 70 runs')
    """
    if not cls:
        return None
    met, missed, parts_met, parts_missed, untested = [], [], [], [], []
    for base, by_state in cls.items():
        for st, a in (by_state or {}).items():
            name = f"{_BASE.get(base, base)} {_STATE.get(st, st)}"
            if a.get("status") == "not testable":
                untested.append(f"{name} ({a.get('n', 0)} runs: {a.get('why') or 'no positive or no negative case'})")
                continue
            if a.get("status") not in ("met", "missed"):
                continue
            size = (f"accuracy {_n(a.get('accuracy'))}, lower bound {_n(a.get('accuracy_lo'))}, "
                    f"{a.get('n', 0)} runs")
            if a["status"] == "met":
                met.append(name)
                parts_met.append(f"{name} ({size})")
            else:
                missed.append(name)
                parts_missed.append(f"{name} ({size}: {a.get('why') or 'agreement not shown'})")
    if not (met or missed or untested):
        return None
    line = "3D cross-check over the design records: "
    line += ("the 2D model agrees with the 3D physics on " + ", ".join(parts_met)) if met else "no limit state agrees"
    if missed:
        line += "; NOT shown on " + "; ".join(parts_missed) + ": the 2D answer there is not confirmed by 3D"
    if untested:
        line += "; not testable on " + "; ".join(untested)
    return {"line": line + ".", "met": met, "missed": missed, "untested": untested}


def _curve_text(c: dict) -> str:
    """'median 0.287 g (0.276 g-0.310 g), beta 0.11, P at the design PGA 0.51' of one limit-state curve
    (the study's fragility_limit_states entry); every undefined number says why instead."""
    m = finite_number(c.get("median"))
    if m is None:
        return f"median not fitted ({c.get('median_reason') or c.get('status') or 'undefined'})"
    lo, hi = (finite_number(x) for x in (list(c.get("median_ci") or []) + [None, None])[:2])
    band = f" ({g_text(lo)}-{g_text(hi)})" if lo is not None and hi is not None else (
        f" (band: {c.get('median_ci_reason')})" if c.get("median_ci_reason") else "")
    b = finite_number(c.get("beta"))
    beta = f", beta {b:.2f}" if b is not None else f", beta not identified ({c.get('beta_reason') or 'see fragility.json'})"
    p = finite_number(c.get("p_design"))
    pt = (f", P at the design PGA {prob_text(p)}" if p is not None else
          f", P at the design PGA not known ({c.get('p_design_reason') or 'not identified'})")
    count = c.get("p_design_count") if isinstance(c.get("p_design_count"), dict) else None
    if c.get("curve_kind") == "empirical" and p is not None and count:
        ci = [finite_number(x) for x in (list(count.get("ci") or []) + [None, None])[:2]]
        within = f", 95 % Wilson {ci[0]:.2f}-{ci[1]:.2f}" if None not in ci else ""
        return (f"empirical ({c.get('choice_reason') or 'the lognormal is not kept'}): median {g_text(m)}{band}, "
                f"P at the design PGA {prob_text(p)} ({count.get('k')} of {count.get('n')} thresholds at or below "
                f"it{within})")
    return f"median {g_text(m)}{band}{beta}{pt}"


def limit_state_fragility_line(dyn: dict, fl: dict, isolated: bool) -> str:
    """The verdict's fragility line, per limit state (full contact first, MODEL.md section 8), fixed
    base and isolated, from the study's fragility_limit_states; what the samples varied and the runs."""
    runs = f"{dyn.get('fragility_runs')} runs on a fixed base" + (
        f", {dyn.get('fragility_runs_isolated')} on the isolator" if isolated and dyn.get("fragility_runs_isolated") else "")
    parts = []
    ratios = dyn.get("fragility_limit_state_ratios") or {}
    for name in states.WITH_CURVES:
        sides = fl.get(name) or {}
        bits = []
        if sides.get("fixed"):
            bits.append("fixed base " + _curve_text(sides["fixed"]))
        if isolated and sides.get("isolated"):
            what = "on the isolator (overturning or capacity exceeded) " if name == "overturning" else "on the isolator "
            bits.append(what + _curve_text(sides["isolated"]))
            r = ratios.get(name) or {}
            v = finite_number(r.get("value"))
            if v is not None:
                ci = [finite_number(x) for x in (list(r.get("ci") or []) + [None, None])[:2]]
                bits.append(f"the isolator multiplies the median by {v:.2f}"
                            + (f" ({ci[0]:.2f}-{ci[1]:.2f})" if None not in ci else ""))
        if bits:
            parts.append(f"{FRAGILITY_TITLES[name]}: " + ", ".join(bits))
    varied = dyn.get("fragility_varied")
    pga, mean_pga = finite_number(dyn.get("fragility_design_pga")), finite_number(dyn.get("records_mean_pga"))
    read = ""
    if pga is not None and mean_pga is not None:
        read = (f" The curves scale each record to a PGA; P is read at the design PGA {g_text(pga)}, while the design "
                f"records as matched have PGAs averaging {g_text(mean_pga)} ({mean_pga / pga:.2f} x; EC8 asks the mean "
                "for at least a_g S): the limit states above, taken on the records as matched, can be more severe "
                "than P at the design PGA suggests.")
    return (f"Fragility per limit state over the design records ({runs}" + (f"; varied: {varied}" if varied else "")
            + "): " + "; ".join(parts) + "." + read)


def finite_number(x) -> float | None:
    """x as a float when it is a finite number (not a bool), else None (a manifest is input: it may
    hold anything).

    >>> finite_number("2.5"), finite_number(float("inf")), finite_number(True), finite_number(None)
    (2.5, None, None, None)
    """
    if isinstance(x, bool):
        return None
    try:
        x = float(x)
    except (TypeError, ValueError):
        return None
    return x if math.isfinite(x) else None


def recommend(fixed: dict, isolated: dict, pga: float) -> str:
    """One plain line: what to do (quasi-static: without the design records' limit states)."""
    return decide(fixed, isolated, pga)[1]


def decide(fixed: dict, isolated: dict, pga: float) -> tuple[Code, str]:
    """(the recommendation code, its reasoning in one line) without the design records' limit states:
    the quasi-static uplift check and the isolator design's own checks."""
    if fixed.get("slides"):
        return Code.SLIDES, ("the statue would slide before it lifts and the design PGA reaches its friction: run "
                             "the dynamics stage to measure how far it slides (restrain it if beyond its allowance)")
    def ok_margin(m):
        return m is not None and m >= 1.0
    if not fixed["lifts"] and not fixed.get("overturns", False):
        return Code.NO_ISOLATOR, (f"no isolator needed at the design level: the statue stays in full contact (uplift margin "
                f"{_n(fixed['uplift_margin'])})")
    if not isolated:
        return Code.RUN_ISOLATOR_STAGE, (f"the statue lifts at the design level (uplift {g_text(fixed['uplift'])} < design PGA {g_text(pga)}) and no "
                "isolator was designed: run the isolator stage")
    if not isolated.get("passed"):
        return Code.NO_DEVICE_IN_RANGE, f"no isolator in range works: {isolated.get('reason') or 'see the isolator checks'}"
    travel, felt = isolated.get("travel_margin"), isolated.get("felt_margin")
    fail_margin = isolated.get("failure_margin")
    swept_ok = "first_failure_pga" not in isolated or isolated["first_failure_pga"] is None or ok_margin(fail_margin)
    if ok_margin(travel) and ok_margin(felt) and swept_ok:
        return Code.ISOLATE, (f"isolate with the designed device: travel margin {_n(travel)}, the statue stays in full contact "
                f"(felt-acceleration margin {_n(felt)})")
    why = []
    if not ok_margin(travel):
        why.append(f"travel demand {mm_text(isolated['travel_demand'])} mm > capacity "
                   f"{mm_text(isolated['capacity'])} mm")
    if not ok_margin(felt):
        why.append(f"the statue feels {g_text(isolated['felt'])} > its uplift {g_text(fixed['uplift'])}")
    if not swept_ok:
        kind = f" ({isolated['failure_kind']})" if isolated.get("failure_kind") else ""
        record = f" under {isolated['record']}" if isolated.get("record") else ""
        why.append(f"on the isolator it fails from {g_text(isolated['first_failure_pga'])}{kind}{record} "
                   f"< design PGA {g_text(pga)}")
    return Code.DEVICE_DOES_NOT_PROTECT, "the designed isolator does not protect at the design level: " + "; ".join(why)
