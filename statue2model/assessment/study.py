"""The dynamics stage's fragility study: probability of failure against PGA, fixed base and isolated.

The records are the design record set (statue2model.hazard.matching.match_set) matched to the
project's design target (statue2model.hazard.site: the ``[isolator] spectrum`` on the ground, the
floor spectrum of ``[building]`` on an upper floor; the hazard of the verdict), ``[dynamics]
fragility_records`` records (7: the codes' mean of effects) of ``fragility_duration`` s (auto: 25 s,
or 5 times the band's end), seeds 1..N, checked over 0.15 s to the largest of 2 s, 2 T1 of the
building and 1.2 T_is of the isolator (:func:`match_records`; written by :func:`write_records` to
``dynamics/records/``: record_NN.csv, set.json with every rule of the code and each record's
realism figures; the stage draws spectra.png). Each is scaled to every PGA level (``fragility_levels``: "auto" = 10 levels,
geometric, 0.2-3 x the design PGA; or START:STOP:N, :func:`fragility_levels`) for every parameter
sample (the thesis' theta_R sweep, ``fragility_samples`` values, for the imperfect model; the
model as it is for Housner's, whose curves are then the record-to-record variability alone, said
in the text) and run on a fixed base and, with an isolator design, on the isolator
(statue2model.assessment.fragility.run_fragility), by :func:`run_study`. The stage writes
fragility.json, fragility.csv and fragility.png; the report's table, figure and text are
statue2model.report.fragility_section's; :meth:`StudyRun.data` gives the verdict's numbers:

    fragility_median_fixed        median PGA of overturning on a fixed base (m/s^2; None if not fitted)
    fragility_median_isolated     median PGA of failure on the isolator (overturning or capacity exceeded)
    fragility_median_ci_fixed/isolated  its bootstrap band [lo, hi] (an end None: not identified)
    fragility_p_design_fixed/isolated   the fitted probability at the design PGA
    fragility_ratio               median isolated / fixed, with its bootstrap interval fragility_ratio_ci
    fragility_status_fixed/isolated     the fit's status (assessment.fragility: ok, step, no failures, ...)

Every one of these that can be None has KEY_reason beside it: None when the value is defined
(and complete), else why ("no failure at any level", "one level: spread not identified", "upper
end not identified: 12 of 200 replicates had no failure ..."). No number here is ever nan or inf.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..errors import InputError

AUTO_LEVELS = (0.2, 3.0, 10)
"""'auto' PGA levels: (lowest, highest multiple of the design PGA, number), geometric."""


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
        raise InputError(f"{what} needs at least 3 PGAs > 0, got {text!r}")
    if np.any(np.diff(lv) <= 0):
        raise InputError(f"{what} must increase from START to STOP (each level above the one before), "
                         f"got {text!r}")
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
        """Runs per base: records x levels x samples."""
        return len(self.records.records) * self.levels.size * self.samples.n

    def data(self) -> dict:
        """The verdict's fragility_* numbers (module docstring) and the study's size and inputs."""
        data = fragility_data(self.result, self.pga, self.isolated)
        data.update(fragility_runs=self.n_runs, fragility_records_met=self.met, fragility_varied=self.varied)
        return data


def match_records(target, n: int, duration: float | None = None, T1: float | None = None,
                  T_is: float | None = None):
    """A RecordSet of ``n`` records (seeds 1..n) matched to ``target`` over the design band of a
    building of period ``T1`` and an isolator of period ``T_is`` (s, None: none), each of
    ``duration`` s (None: 25 s or 5 times the band's end; a shorter one is matched over what it
    can carry and the band rule says so)."""
    from ..hazard.matching import design_band, duration_for_band, match_set

    band, why = design_band(T1, T_is)
    dur = duration_for_band(band) if duration is None else float(duration)
    checked = band if band[1] <= dur / 5 else (band[0], dur / 5)
    return match_set(target, n=int(n), seed=1, duration=dur, dt=0.01, band=checked, required_band=band,
                     band_reason=why)


def design_set_data(rs) -> dict:
    """The stage's records_* numbers of the design record set ``rs`` (a RecordSet): its size, band,
    the rules it breaks, its tolerance window and its realism (mean PGD against d_g)."""
    real = rs.realism()
    return dict(records_n=len(rs.records), records_duration_s=max(m.duration for m in rs.records),
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


def run_study(model, iso, target, rs, levels_text: str, n_samples: int, rtol: float, executor=None) -> StudyRun:
    """Run the study of the module docstring on the records ``rs`` matched to ``target``: the
    thesis' theta_R sweep of ``n_samples`` values (imperfect model) or the model as it is
    (Housner's), at the levels of ``levels_text``, on a fixed base and on ``iso`` (or None)."""
    from ..rocking.sampling import nominal, thesis_theta_R
    from .fragility import FragilityStudy, run_fragility

    met = bool(rs.check()["met"])
    if model.kind == "imperfect":
        samples = thesis_theta_R(model, int(n_samples))
        varied = (f"theta_R over the thesis' range (Table 24: {samples.values['theta_R'].min():.4g}-"
                  f"{samples.values['theta_R'].max():.4g} rad, {samples.n} values)")
    else:
        samples = nominal(1)
        varied = ("no model parameter (Housner's model has no theta_R to vary): the curves are the "
                  "record-to-record variability alone")
    lv = levels_for(levels_text, float(np.asarray(target.Se(np.array([0.0])))[0]))
    study = FragilityStudy(im="pga", rtol=rtol, n_boot=200, seed=0)
    res = run_fragility(model, rs.records, lv, samples, study, isolator=iso, executor=executor)
    return StudyRun(target, rs, met, lv, samples, varied, study, res, iso is not None)


def spread_identified(cv) -> str | None:
    """None when the curve's dispersion beta is identified by its counts, else why not: a fit that
    is a step (failures from none to all between two adjacent levels: any beta up to the gap fits),
    no level with a partial fraction of failures, or a beta band with an end not identified. A
    probability at the design level from such a fit is not known and is not stored."""
    if not cv.fitted:
        return None
    partial = int(np.sum((cv.n_fail > 0) & (cv.n_fail < cv.n_trials)))
    if cv.status == "step" or partial == 0:
        lv = cv.levels
        frac = cv.fraction
        below = lv[frac == 0]
        above = lv[frac >= 1]
        gap = (f" (from none at {below.max() / 9.80665:.3f} g to all at {above.min() / 9.80665:.3f} g)"
               if below.size and above.size else "")
        return f"spread not identified: the failures jump between adjacent levels{gap}; beta is not known"
    lo, hi = (float(x) for x in cv.beta_ci)
    if not (math.isfinite(lo) and math.isfinite(hi)):
        return f"spread not identified: its band has an end not identified ({cv.beta_ci_note or 'bootstrap'})"
    return None


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
            spread = spread_identified(cv)
            p = _num(float(cv.probability(pga))) if cv.fitted and spread is None else None
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
                     f"fragility_p_design_{side}_reason": None if p is not None else why,
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
