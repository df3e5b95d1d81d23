"""The dynamics stage's fragility study: probability of failure against PGA, fixed base and isolated.

The records are the design record set (statue2model.hazard.matching.match_set) matched to the
project's design target (statue2model.hazard.site: the ``[isolator] spectrum`` on the ground, the
floor spectrum of ``[building]`` on an upper floor; the hazard of the verdict), ``[dynamics]
fragility_records`` records (7: the codes' mean of effects) of ``fragility_duration`` s (auto: 25 s,
or 5 times the band's end), seeds 1..N, checked over 0.15 s to the largest of 2 s, 2 T1 of the
building and 1.2 T_is of the isolator (:func:`match_records`; written by :func:`write_records` to
``dynamics/records/``: record_NN.csv, set.json with every rule of the code and each record's
realism figures; the stage draws spectra.png). Each is scaled to every PGA level (``fragility_levels``: "auto" = 10 levels,
geometric, 0.2-3 x the design PGA; or START:STOP:N, :func:`fragility_levels`): the coarse grid, to
which levels are added round by round around each curve's median until its spread is identified
(``fragility_rounds`` rounds at most, ADAPTIVE_MAX_ADDED levels a base at most: the rule of
statue2model.assessment.fragility.AdaptiveLevels, written in fragility.json's ``adaptive``; only the
new levels run, the runs at the old ones are kept) for every parameter sample
(:func:`study_design`, ``fragility_samples`` samples of one Latin hypercube:
theta_R over the thesis' range, the restitution e_L, e_R x 0.95-1.05, alpha_L, alpha_R x 0.9-1.1, and
the isolator's friction at its low and high bound, ``[isolator] mu_low`` / ``mu_high`` or mu times
Table 25's spread, 0.0039 / 0.0073 and 0.0108 / 0.0073; Housner's model has no theta_R or alpha: e and mu only, said in the text) and run on a
fixed base and, with an isolator design, on the isolator
(statue2model.assessment.fragility.run_fragility), by :func:`run_study`. The stage writes
fragility.json, fragility.csv and fragility.png; the report's tables, figure and text are
statue2model.report.fragility_section's; :meth:`StudyRun.data` gives the verdict's numbers:

    fragility_median_fixed        median PGA of overturning on a fixed base (m/s^2; None if not fitted)
    fragility_median_isolated     median PGA of failure on the isolator (overturning or capacity exceeded)
    fragility_median_ci_fixed/isolated  its bootstrap band [lo, hi] (an end None: not identified)
    fragility_p_design_fixed/isolated   the fitted probability at the design PGA (None unless the
                                  spread is identified and the median lies within the levels run:
                                  assessment.fragility.identified_reason)
    fragility_ratio               median isolated / fixed, with its bootstrap interval fragility_ratio_ci
    fragility_status_fixed/isolated     the fit's status (assessment.fragility: ok, step, no failures, ...)
    fragility_limit_states        {limit state: {base: entry}} for full_contact (curves
                                  full_contact_fixed, full_contact_isolated), overturning
                                  (overturning_fixed, overturning_isolated) and capacity
                                  (capacity_isolated): :func:`limit_state_data` (assessment/states.py)
    fragility_limit_state_ratios  {limit state: {value, ci, note, ci_note}}: median isolated / fixed
    fragility_adaptive            the adaptive levels: rounds run, levels added per base, identified curves
    fragility_runs, fragility_runs_isolated   runs on each base (records x levels run x samples)

Every one of these that can be None has KEY_reason beside it: None when the value is defined
(and complete), else why ("no failure at any level", "one level: spread not identified", "upper
end not identified: 12 of 200 replicates had no failure ..."). No number here is ever nan or inf.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..quantities import G  # m/s^2: the g every report prints
from ..errors import InputError, quoted
from ..isolator.friction import friction_bounds
from ..rocking.model import RockingModel
from ..rocking.sampling import (
    ALPHA_FACTOR,
    E_FACTOR,
    MU,
    THESIS_THETA_R,
    ParameterSamples,
    check_count,
    check_seed,
    nominal,
)
from . import states
from .states import BASES

AUTO_LEVELS = (0.2, 3.0, 10)
"""'auto' PGA levels: (lowest, highest multiple of the design PGA, number), geometric."""
ADAPTIVE_MAX_ADDED = 12
"""Levels the adaptive rounds may add to each base (fixed, isolated) at most."""


def fragility_levels(text: str, what: str = "[dynamics] fragility_levels") -> np.ndarray:
    """The PGA levels (m/s^2) of a fragility_levels grid ('START:STOP:N' or 'a,b,c', with units),
    refused in one line naming ``what`` unless there are at least 3, all > 0 and strictly
    increasing (a reversed grid would otherwise fail only after the study's records are built).

    >>> fragility_levels("0.1g:0.5g:3") / 9.81
    array([0.1, 0.3, 0.5])
    >>> fragility_levels("1g:0.1g:5")
    Traceback (most recent call last):
    ...
    statue2model.errors.InputError: [dynamics] fragility_levels must increase from START to STOP ...
    """
    from ..rocking.sweeps import linspace_spec

    lv = linspace_spec(text, what, accel=True)
    if lv.size < 3 or np.any(lv <= 0):
        raise InputError(f"{what} needs at least 3 PGAs > 0, got {quoted(text)}")
    if np.any(np.diff(lv) <= 0):
        raise InputError(f"{what} must increase from START to STOP (each level above the one before), "
                         f"got {quoted(text)}")
    return lv


def levels_for(text: str, pga: float) -> np.ndarray:
    """PGA levels (m/s^2) of ``text``: "auto" (AUTO_LEVELS x ``pga``) or START:STOP:N (accelerations)."""
    if str(text).strip().lower() == "auto":
        lo, hi, n = AUTO_LEVELS
        return pga * np.geomspace(lo, hi, n)
    return fragility_levels(text)


@dataclass(frozen=True)
class StudyRun:
    """One study of the module docstring: the design spectrum ``target``, the matched
    ``records`` (a RecordSet; ``met``: its mean within the tolerance), the PGA ``levels``
    (m/s^2), the parameter ``samples`` (``varied``: what they vary, in words), the ``study``
    settings, its FragilityResult ``result``, and whether it ran on an isolator too."""

    target: object
    records: object
    met: bool
    levels: np.ndarray
    samples: object
    varied: str
    study: object
    result: object
    isolated: bool

    @property
    def pga(self) -> float:
        """The design PGA of the target, Se(0) in m/s^2: a_g S on the ground, the peak floor acceleration on a floor."""
        return float(np.asarray(self.target.Se(np.array([0.0])))[0])

    @property
    def n_runs(self) -> int:
        """Runs on the fixed base: records x levels it ran x samples."""
        return len(self.records.records) * self.result.levels_run("fixed").size * self.samples.n

    @property
    def n_runs_isolated(self) -> int:
        """Runs on the isolator: records x levels it ran x samples (0 without one)."""
        if not self.isolated:
            return 0
        return len(self.records.records) * self.result.levels_run("isolated").size * self.samples.n

    def data(self) -> dict:
        """The verdict's fragility_* numbers (module docstring) and the study's size and inputs."""
        data = fragility_data(self.result, self.pga, self.isolated)
        data.update(fragility_runs=self.n_runs, fragility_runs_isolated=self.n_runs_isolated,
                    fragility_records_met=self.met, fragility_varied=self.varied,
                    fragility_limit_states=limit_state_data(self.result, self.pga),
                    fragility_limit_state_ratios=limit_state_ratios(self.result),
                    fragility_adaptive=adaptive_summary(self.result))
        return data


def match_records(target, n: int, duration: float | None = None, T1: float | None = None,
                  T_is: float | None = None, seed: int = 1, code: str | None = None):
    """A RecordSet of ``n`` records (seeds seed..seed + n - 1) matched to ``target`` over the design
    band of a building of period ``T1`` and an isolator of period ``T_is`` (s, None: none) on a site
    of ``code`` (hazard.matching.design_band: EC8 2 T_is, NTC 1.2 T_is), each of ``duration`` s (None:
    25 s or 5 times the band's end; a shorter one is matched over what it can carry and the band rule
    says so)."""
    from ..hazard.matching import design_band, duration_for_band, match_set

    band, why = design_band(T1, T_is, code)
    dur = duration_for_band(band) if duration is None else float(duration)
    checked = band if band[1] <= dur / 5 else (band[0], dur / 5)
    return match_set(target, n=int(n), seed=int(seed), duration=dur, dt=0.01, band=checked, required_band=band,
                     band_reason=why)


def design_set_data(rs) -> dict:
    """The stage's records_* numbers of the design record set ``rs`` (a RecordSet): its size, band,
    the rules it breaks, its tolerance window and its realism (mean PGD against d_g)."""
    real = rs.realism()
    return dict(records_n=len(rs.records), records_duration_s=max(m.duration for m in rs.records),
                records_mean_pga=float(np.mean([m.pga for m in rs.records])),
                records_band_s=list(rs.band), records_required_band_s=list(rs.required_band),
                records_met=bool(rs.check()["met"]), records_failed_rules=[r["rule"] for r in rs.rules() if not r["ok"]],
                records_window=rs.window, records_mean_pgd_m=real["mean_pgd_m"], records_d_g_m=real["d_g_m"],
                records_mean_pgd_over_d_g=real["mean_pgd_over_d_g"], records_plausible=real["plausible"],
                records_realism_warning=real["warning"])


def write_records(rd: Path, rs) -> None:
    """The records of RecordSet ``rs`` as ``rd``/record_NN.csv and the set.json naming them
    (readable by ``statue2model fragility --records``)."""
    from ..hazard.matching import set_files
    from ..hazard.motions import write_record_csv
    from ..io.files import write_json

    rd.mkdir(parents=True, exist_ok=True)
    for i, m in enumerate(rs.records):
        write_record_csv(rd / f"record_{i + 1:02d}.csv", m)
    names = [f"record_{i + 1:02d}.csv" for i in range(len(rs.records))]
    write_json(rd / "set.json", {**rs.to_dict(), **set_files(rd, names)})


E_RANGE = (0.95, 1.05)
"""``e_factor`` range of the default study: +-5 % about the model's e_L, e_R, the scatter of the
thesis' measured restitution about its mean (Table 23: e_R 0.911-0.947, e_L 0.909-0.992, mean
0.924 and 0.963: -1.4/+2.5 % and -5.6/+3.0 %); capped at e = 1."""
ALPHA_RANGE = (0.90, 1.10)
"""``alpha_factor`` range of the default study (imperfect model): +-10 % about the config's
alpha_L, alpha_R (Table 22 gives one identified value a side, no scatter: +-10 % is a stated
assumption, the benchmarks' range 0.143-0.175 and 0.158-0.193 about 0.159 and 0.175); capped at 1."""


def study_design(model: RockingModel, n: int, mu: float | None = None, mu_low: float | None = None,
                 mu_high: float | None = None, seed: int = 0) -> ParameterSamples:
    """The default fragility study's n samples (``method`` "lhs", ``seed``): one Latin hypercube
    (scipy.stats.qmc, seeded) over, jointly,

    * ``theta_R`` over the thesis' range THESIS_THETA_R x delta_R (imperfect model only);
    * ``e_factor`` over E_RANGE (both sides' restitution, capped at 1);
    * ``alpha_factor`` over ALPHA_RANGE (imperfect model only: Housner's has no alpha to reduce);
    * ``mu`` (with an isolator, ``mu`` not None): the friction at its LOW and HIGH bound
      (isolator/friction.py ``friction_bounds``), a two-level factor: the hypercube's column ranked, the lower
      ceil(n / 2) ranks at mu_low, the others at mu_high (balanced, deterministic for a seed).

    n = 1 is the model as it is (rocking.sampling ``nominal``, with ``mu`` as given): one sample varies nothing.

    >>> from statue2model.geometry.rocking_params import RockingParams
    >>> m = RockingModel.imperfect(RockingParams.rectangular_block(0.05, 0.25, 10.0), 0.5, 0.6)
    >>> d = study_design(m, 8, mu=0.01, mu_low=0.008, mu_high=0.015)
    >>> sorted(d.values), sorted(set(d.values["mu"].tolist())), int((d.values["mu"] == 0.008).sum())
    (['alpha_factor', 'e_factor', 'mu', 'theta_R'], [0.008, 0.015], 4)
    """
    from scipy.stats import qmc

    n = check_count(n, "number of samples")
    seed = check_seed(seed)
    if n == 1:
        return nominal(1) if mu is None else ParameterSamples({MU: np.array([float(mu)])}, 1, "nominal", None)
    ranges = {}
    if model.kind == "imperfect":
        d = model.params.delta_R
        ranges["theta_R"] = (THESIS_THETA_R[0] * d, THESIS_THETA_R[1] * d)
    ranges[E_FACTOR] = E_RANGE
    if model.kind == "imperfect":
        ranges[ALPHA_FACTOR] = ALPHA_RANGE
    dims = len(ranges) + (mu is not None)
    u = qmc.LatinHypercube(d=dims, seed=np.random.default_rng(seed)).random(n)
    vals = {name: lo + (hi - lo) * u[:, j] for j, (name, (lo, hi)) in enumerate(ranges.items())}
    if mu is not None:
        lo, hi, _ = friction_bounds(mu, mu_low, mu_high)
        rank = np.argsort(np.argsort(u[:, -1], kind="stable"), kind="stable")
        vals[MU] = np.where(rank < (n + 1) // 2, lo, hi)
    return ParameterSamples(vals, n, "lhs", seed)


def run_study(model, iso, target, rs, levels_text: str, n_samples: int, rtol: float, executor=None,
              mu_low: float | None = None, mu_high: float | None = None, rounds: int = 3,
              iso_model=None, support=None) -> StudyRun:
    """Run the study of the module docstring on the records ``rs`` matched to ``target``: the
    parameter samples of :func:`study_design` (``n_samples`` of them; the isolator's
    friction at ``mu_low`` and ``mu_high``, None: mu times Table 25's spread), the coarse levels of
    ``levels_text`` and up to ``rounds`` rounds of adaptive levels (0: the coarse levels only),
    on a fixed base and on ``iso`` (or None), carrying ``iso_model`` (None: ``model``); ``support``: the
    statue's support, for the curves of sliding (and of the pedestal's sliding and overturning)."""
    from ..rocking.sampling import describe
    from .fragility import AdaptiveLevels, FragilityStudy, run_fragility

    met = bool(rs.check()["met"])
    mu = None if iso is None else float(iso.mu)
    samples = study_design(model, int(n_samples), mu=mu, mu_low=mu_low, mu_high=mu_high, seed=0)
    src = friction_bounds(mu, mu_low, mu_high)[2] if mu is not None and samples.n > 1 else None
    varied = describe(samples, model, src) if samples.n > 1 else (
        "no parameter (one sample: the model as it is): the curves are the record-to-record variability alone")
    lv = levels_for(levels_text, float(np.asarray(target.Se(np.array([0.0])))[0]))
    study = FragilityStudy(im="pga", rtol=rtol, n_boot=200, seed=0)
    adaptive = AdaptiveLevels(rounds=int(rounds), max_added=ADAPTIVE_MAX_ADDED) if rounds else None
    res = run_fragility(model, rs.records, lv, samples, study, isolator=iso, executor=executor, adaptive=adaptive,
                        iso_model=iso_model, support=support,
                        design_im=float(np.asarray(target.Se(np.array([0.0])))[0]))
    return StudyRun(target, rs, met, res.levels, samples, varied, study, res, iso is not None)


def spread_identified(cv) -> str | None:
    """None when the curve's dispersion beta is identified by its counts, else why not
    (statue2model.assessment.fragility.spread_reason: a step, fewer than two levels with a partial
    fraction of failures, a profile-likelihood or bootstrap band of beta with an end not
    identified). A probability at the design level from such a fit is not known and is not stored."""
    from .fragility import spread_reason

    return spread_reason(cv)


def _num(v) -> float | None:
    """A finite float, or None."""
    return float(v) if v is not None and math.isfinite(v) else None


def fragility_data(res, pga: float, isolated: bool) -> dict:
    """The stage's fragility_* numbers of a FragilityResult ``res`` (module docstring): each value
    that can be undefined is None with ``KEY_reason`` beside it (None when it is defined)."""
    data = {"fragility_design_pga": float(pga)}
    for side in BASES:
        name = states.curve(states.OVERTURNING, side)
        cv = res.curves.get(name)
        if cv is None:
            why = "no isolator designed" if side == "isolated" else "not run"
            med = p = outside = None
            mci, ci_why = None, why
        else:
            from .fragility import median_reason

            why = cv.reason
            outside = median_reason(cv)          # the median beyond the levels run: no P from it
            med = _num(cv.median) if cv.fitted else None
            spread = spread_identified(cv)
            p = _num(float(cv.probability(pga))) if cv.fitted and spread is None and outside is None else None
            if cv.fitted and spread is not None:
                why = spread
            mci = [_num(x) for x in cv.median_ci] if cv.fitted else None
            if mci is not None and all(x is None for x in mci):
                mci = None
            ci_why = (cv.median_ci_note or (None if mci is not None and None not in mci else "no band"))
            if not cv.fitted:
                ci_why = f"median undefined ({why})"
        data.update({f"fragility_median_{side}": med, f"fragility_median_{side}_reason": why,
                     f"fragility_median_ci_{side}": mci, f"fragility_median_ci_{side}_reason": ci_why,
                     f"fragility_p_design_{side}": p,
                     f"fragility_p_design_{side}_reason": None if p is not None else (why or outside),
                     f"fragility_status_{side}": None if cv is None else cv.status})
    r = res.ratio.get(states.OVERTURNING) if isolated else None
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


def _range_text(levels) -> str:
    lv = np.asarray(levels, dtype=float)
    return f"{lv.min() / G:.3f}-{lv.max() / G:.3f} g" if lv.size else "no level"


def curve_entry(cv, pga: float) -> dict:
    """One limit state on one base of :func:`limit_state_data`: the curve ``cv`` (FragilityCurve) at
    the design PGA ``pga`` (m/s^2). Every number that can be undefined is None with its reason:

        curve, label, status     the outcome's name and words, the fit's status (ok, step, no failures, ...)
        levels, n_levels         the PGA levels (m/s^2) its base ran, how many
        partial_levels           levels with a partial fraction of failures (0 < failed < runs)
        n_fail, n_trials         failures and counted runs over all levels
        median, median_reason    the fitted median PGA (m/s^2; None without a fit); median_reason says
                                 why it is not identified (no fit, or it lies outside the levels run:
                                 an extrapolation of the fit), None when it is
        median_ci(_reason)       its bootstrap band [lo, hi] (an end None: not identified)
        beta, beta_reason        the dispersion; None unless the curve is identified, with why
        beta_ci, beta_profile    its bootstrap band and its profile-likelihood band (beta_profile_note)
        p_design(_reason)        P(exceeding | PGA = design PGA); None unless identified, with why
        identified               median and spread identified (assessment.fragility.identified_reason)
        spread_identified        the spread alone (assessment.fragility.spread_reason)
        p_design_count           a curve on exact thresholds (fixed-base uplift): {k, n, p = k / n, ci, method},
                                 the thresholds at or below the design PGA and their 95 % Wilson interval
                                 (None elsewhere); p_design always lies inside ci (fragility.UPLIFT_RULE)
        p_design_ci              the Wilson interval of an empirical curve's p_design (None elsewhere)
        curve_kind, choice_reason  "lognormal" or "empirical" (fragility.UPLIFT_RULE) and why the empirical

    A fixed-base uplift curve is re-chosen at ``pga`` first (fragility.choose_uplift_curve: a no-op when
    the study checked it there): the entry reads the curve the rule keeps.
    """
    from .fragility import EMPIRICAL, LABELS, choose_uplift_curve

    cv = choose_uplift_curve(cv, [pga])
    count = cv.count_at(pga) if cv.fitted else None
    kind = {"curve_kind": None if cv.thresholds is None else ("empirical" if cv.status == EMPIRICAL else "lognormal"),
            "choice_reason": (cv.choice or {}).get("reason"), "p_design_count": count,
            "p_design_ci": count["ci"] if count is not None and cv.status == EMPIRICAL else None}

    levels = [float(x) for x in cv.levels]
    base = {"curve": cv.outcome, "label": LABELS.get(cv.outcome, cv.outcome), "status": cv.status,
            "levels": levels, "n_levels": len(levels), "partial_levels": int(cv.partial),
            "n_fail": int(np.sum(cv.n_fail)), "n_trials": int(np.sum(cv.n_trials)), **kind}
    if not cv.fitted:
        why = f"{cv.reason} ({_range_text(cv.levels)})"
        return {**base, "median": None, "median_reason": why, "median_ci": None, "median_ci_reason": why,
                "beta": None, "beta_reason": why, "beta_ci": None, "beta_profile": None,
                "p_design": None, "p_design_reason": f"not identified: {why}", "identified": False,
                "spread_identified": False}
    from .fragility import median_reason

    outside = median_reason(cv)
    beta_why = spread_identified(cv)
    spread = outside or beta_why
    mci = [_num(x) for x in cv.median_ci]
    mci = None if all(x is None for x in mci) else mci
    ci_why = cv.median_ci_note or (None if mci is not None and None not in mci else "no band")
    prof = getattr(cv, "beta_profile", None)
    prof = None if prof is None else [_num(x) for x in prof]
    bci = [_num(x) for x in cv.beta_ci]
    bci = None if all(x is None for x in bci) else bci
    p = _num(float(cv.probability(pga))) if spread is None else None
    empirical = cv.status == EMPIRICAL
    return {**base, "median": _num(cv.median), "median_reason": outside, "median_ci": mci, "median_ci_reason": ci_why,
            "beta": _num(cv.beta) if spread is None else None,
            "beta_reason": f"an empirical curve has no beta ({kind['choice_reason']})" if empirical else spread,
            "beta_ci": bci if spread is None else None, "beta_profile": prof,
            "beta_profile_note": getattr(cv, "beta_profile_note", None),
            "p_design": p, "p_design_reason": None if p is not None else (
                spread if "not identified" in spread else f"not identified: {spread}"),
            "identified": spread is None, "spread_identified": beta_why is None}


def _by_mu(res, name: str, pga: float) -> dict | None:
    """The isolated curve ``name`` fitted on the samples at each friction bound (None when the
    samples do not vary mu): {"low"|"high": {mu, median, beta, status, p_design, p_design_reason}}."""
    from .fragility import FragilityCurve, fit_lognormal

    smp = getattr(res, "samples", None)
    mu = None if smp is None else smp.values.get("mu")
    if mu is None or np.unique(mu).size < 2 or name not in getattr(res, "fails", {}):
        return None
    side_ran = res.ran["isolated"] if getattr(res, "ran", None) else np.ones(res.levels.size, dtype=bool)
    f, v = res.fails[name], res.valid["isolated"]
    out = {}
    for word, value in (("low", float(mu.min())), ("high", float(mu.max()))):
        sel = mu == value
        z = (f & v)[:, sel, :].sum(axis=(0, 1))[side_ran]
        n = v[:, sel, :].sum(axis=(0, 1))[side_ran]
        lv = res.levels[side_ran]
        med, beta, st = fit_lognormal(lv, z, n)
        cv = FragilityCurve(name, lv, z.astype(int), n.astype(int), med, beta, st)
        e = curve_entry(cv, pga)
        out[word] = {"mu": value, "n_samples": int(sel.sum()), "median": e["median"],
                     "median_reason": e["median_reason"], "beta": e["beta"], "status": st,
                     "p_design": e["p_design"], "p_design_reason": e["p_design_reason"]}
    return out


def limit_state_data(res, pga: float) -> dict:
    """{limit state: {base: curve_entry}} of a FragilityResult ``res`` at the design PGA ``pga``
    (m/s^2): the curves of assessment.fragility.LIMIT_STATE_CURVES it has; an isolated entry also
    has ``by_mu``, the same curve on the samples at each friction bound (None when mu is not varied)."""
    from .fragility import LIMIT_STATE_CURVES

    out = {}
    for ls, bases in LIMIT_STATE_CURVES.items():
        row = {}
        for base, name in bases.items():
            cv = res.curves.get(name)
            if cv is None:
                continue
            row[base] = curve_entry(cv, pga)
            if base == "isolated":
                row[base]["by_mu"] = _by_mu(res, name, pga)
        if row:
            out[ls] = row
    return out


def limit_state_ratios(res) -> dict:
    """{limit state: {value, ci, note, ci_note}}: median isolated / median fixed of the limit states
    with both curves (fragility.json's ``ratio_of_medians``, named by the limit state)."""
    out = {}
    for ls in states.WITH_CURVES:
        r = res.ratio.get(ls)
        if r is None:
            continue
        value = _num(r.get("value"))
        ci = [_num(x) for x in (r.get("ci") or (None, None))]
        out[ls] = {"value": value, "ci": None if value is None or all(x is None for x in ci) else ci,
                   "note": r.get("note"), "ci_note": r.get("ci_note")}
    return out


def adaptive_summary(res) -> dict | None:
    """The adaptive levels in brief (None when the levels were taken as given): rounds run, the
    levels added per base, the levels each base ran, which curves are identified and why not."""
    a = getattr(res, "adaptive", None)
    if not a:
        return None
    return {"rounds_budget": a.get("rounds"), "max_added": a.get("max_added"),
            "rounds_run": len(a.get("rounds_run") or []), "added": a.get("added"),
            "levels_run": {side: [float(x) for x in res.levels_run(side)] for side in res.valid},
            "identified": a.get("identified"), "why_not": a.get("why_not"), "rule": a.get("rule")}
