"""The isolator design verified by time histories (issue #27; MODEL.md sections 4, 7, 8).

The spectral search of :func:`statue2model.isolator.design.design` sizes every candidate on
Se(T) and SDe(T). Here each candidate is run on a set of design records (the run's design
set: >= 7 records matched to the design target, hazard/matching.py) and passes only when,
over the set, its travel, the statue's felt acceleration and the ball load all keep their
margin. SI units throughout.

Runs. The top plate alone (time_history.simulate, the Coulomb model: exact while the statue
stays in full contact, which is what a passing device must ensure; the coupled 2-DOF run is
only needed where the statue lifts) for every distinct (R, r) on every record, once with
``mu_low`` and once with ``mu_high`` (the plate's motion does not depend on its mass, the
number of grooves or the board: one run serves every candidate of that (R, r)). Bound
analyses as EN 15129 §4.2 and ASCE 7-16 §17.2.8.4 ask: the lower friction bound normally
gives the largest travel and the upper one the largest force; both are run on every record,
so each demand takes the bound that governs it (the envelope; with a long pulse the lower
bound also gives the larger felt acceleration, as the spring then carries more).

    peak travel  u_max = max |u_o| (relative to the ground, m), per record and bound
    felt         a_max = max |u_g'' + u_o''| (the top plate's absolute acceleration, m/s^2)

The demand over the records is their MEAN with at least N_MIN = 7 records (NTC 2018 §7.3.5,
EN 1998-1 §4.3.3.4.3), else the most unfavourable record (the max); the larger of the two
bounds' statistics is kept.

Margins (each limit / demand; > 1 passes, below 1 it fails by that factor):

    travel        capacity / (DISPLACEMENT_MARGIN u + mu_high R_hat)
    acceleration  a_lim / a
    bearing       P_20 (r / 0.02 m)^2 / (W / n)

u, a: the statistic over the records; DISPLACEMENT_MARGIN 1.5 and the friction offset
mu R_hat (where friction may leave the plate resting off centre, taken at mu_high) as the
spectral travel need has them (design.py); a_lim: the statue's uplift limit, the low end of
the base-contact band when the contact is flagged uncertain (the caller passes it); P_20:
the grooves' per-ball capacity on a 20 mm ball (design.py). The capacity is sized so that it
covers the larger of the spectral need and the time-history need: the opening is cut to
that travel plus SIZING_CLEARANCE (1 %), the opening rounded up to 0.5 mm (design.py,
``travel_floor``), so the travel margin is >= 1.01 wherever the plate and its tipping allow:
never a margin resting on the last digit.

A candidate passes when every spectral required check passes except the spectral felt
acceleration Se(T) <= a_lim and the ball load (REPLACED: the time-history acceleration and
bearing margins take their place; the spectral acceleration stays in the table, advisory),
and all three margins are >= 1.

Choice (CRITERION): the best balance of margins, not the longest period by rule. The
balance is the smaller of the acceleration margin (the period sets it) and the bearing
margin (the balls and their number set it); the travel margin must reach 1 but does not
enter the balance of a passing candidate, being fixed by the sizing (see above: the
smallest of all three would be 1 for almost every candidate and choose nothing). Among the
passing candidates whose balance is within BALANCE_TOLERANCE (10 %) of the best one, the
lightest top plate; then the larger balance, the smaller side, the thinner board, 3 grooves
before 4, the larger ball. When none passes, the nearest is shown (the candidates that pass
the device checks first, then the largest balance, the travel margin counted there when
below 1), ``failure`` says in one sentence per failing check what fails and by how much, and
``what_would_pass`` says what would: the per-ball capacity the grooves would need (so that a
harder surface, an insert or a rubber layer can be load-tested against it), the ball radius
or the number of balls at the given capacity, the travel capacity and plate size, a longer
period; or that the statue should be restrained when no device in range keeps it in full
contact (the acceleration margin below 1 at every (R, r), the longest period included).

Pruning: only the (R, r) of the candidates that pass the device checks are run (a larger
travel only makes those checks harder), plus the longest period in range (for the
"restrain" answer) and, when nothing passes them, the nearest candidate's. On the default
scan (7 records of 25 s, 2 bounds, ~200 pairs) the runs take about 2 s on one core.

Example
-------
>>> from statue2model.geometry.rocking_params import RockingParams
>>> from statue2model.hazard.code_spectra import ec8
>>> from statue2model.hazard import motions
>>> statue = RockingParams.from_dict({"m": 12.074, "h": 0.3523, "b_L": 0.1995, "b_R": 0.0805, "I_G": 0.8})
>>> recs = [motions.synthetic_record(duration=10.0, pga=0.5, seed=s) for s in (1, 2)]
>>> d = verify(statue, records=recs, mu=0.0073, spectrum=ec8(0.05 * 9.80665, "A"), thickness=0.03,
...            R_grid=(0.4, 0.8), balls=(0.02,))
>>> d.passed, d.R, d.verification["statistic"], sorted(d.th_margins)
(True, 0.8, 'max', ['acceleration', 'bearing', 'travel'])
>>> all(m >= 1 for m in d.th_margins.values()), d.what_would_pass is None
(True, True)
"""
from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from ..errors import InputError
from ..hazard.matching import N_MIN
from ..hazard.motions import GroundMotion
from .design import (
    BALL_TESTED,
    BALLS,
    DISPLACEMENT_MARGIN,
    R_GRID,
    SHOWN_FAILING,
    SHOWN_PASSING,
    Check,
    design,
    failure_text,
)
from .device import G, Isolator

REPLACED = ("acceleration", "ball_load")
"""Spectral checks the time-history margins replace (felt acceleration, bearing)."""
BALANCE_TOLERANCE = 0.10
"""Candidates whose balance is within 10 % of the best count as equally balanced (CRITERION)."""
TOL = 1e-9
"""A margin counts as reached from 1 - TOL (the opening is cut to the need: capacity / need = 1 to
rounding)."""
DT_OUT = 1.0
"""s, the plate runs' output step: only their exact peaks are used."""
CRITERION = ("the best balance of margins, not the longest period by rule: the balance is the smaller of the "
             "acceleration margin a_lim / a and the bearing margin P / (W / n) (the travel margin must reach 1 "
             "but is fixed by the sizing, the opening being cut to the larger of the spectral and time-history "
             f"needs); among the passing candidates within {BALANCE_TOLERANCE:.0%} of the best balance, the "
             "lightest top plate; then the larger balance, the smaller side, the thinner board, 3 grooves before "
             "4, the larger ball")
DEFINITIONS = {
    "travel": f"capacity / ({DISPLACEMENT_MARGIN:g} x u + mu_high R_hat), u the statistic over the records of the "
              "plate's peak travel relative to the ground (the larger of the two friction bounds; mu_low governs), "
              f"{DISPLACEMENT_MARGIN:g} the design's displacement margin and mu_high R_hat where friction may leave "
              "the plate off centre",
    "acceleration": "a_lim / a, a the statistic over the records of the top plate's peak absolute acceleration "
                    "(what the statue feels; the larger of the two friction bounds), a_lim the statue's uplift "
                    "limit (the low end of the base-contact band when the contact is uncertain)",
    "bearing": f"P / (W / n), P the grooves' per-ball capacity P_20 (r / {BALL_TESTED:g} m)^2, W the weight on the "
               "n balls",
}


def friction_bounds(mu: float) -> tuple[float, float]:
    """(mu_low, mu_high) by default: ``mu`` times Table 25's measured spread (one rule for the
    verification and the fragility study: statue2model.rocking.sampling.friction_bounds, whose
    MU_LOW_FACTOR 0.0039 / 0.0073 and MU_HIGH_FACTOR 0.0108 / 0.0073 it states; about the property
    modification factors EN 15129 / ASCE 7-16 17.2.8.4 apply to friction, 0.5-0.6 and 1.5-1.8).

    >>> [round(x, 4) for x in friction_bounds(0.0073)]
    [0.0039, 0.0108]
    """
    from ..rocking.sampling import friction_bounds as bounds

    lo, hi, _ = bounds(mu)
    return lo, hi


@dataclass(frozen=True)
class PlateDemand:
    """Peaks of the top plate of one (R, r) on each record: travel (m) and felt acceleration
    (m/s^2) at the lower (``_low``) and upper (``_high``) friction bound."""

    R: float
    r: float
    travel_low: tuple
    travel_high: tuple
    felt_low: tuple
    felt_high: tuple
    statistic: str

    @property
    def T(self) -> float:
        return 2 * math.pi * math.sqrt(2 * (self.R - self.r) / G)

    def _stat(self, values) -> float:
        v = np.asarray(values, dtype=float)
        return float(v.mean() if self.statistic == "mean" else v.max())

    @property
    def travel(self) -> float:
        """The statistic over the records, the larger of the two bounds' (m)."""
        return max(self._stat(self.travel_low), self._stat(self.travel_high))

    @property
    def felt(self) -> float:
        """The statistic over the records, the larger of the two bounds' (m/s^2)."""
        return max(self._stat(self.felt_low), self._stat(self.felt_high))

    def to_dict(self) -> dict:
        return {"R": self.R, "r": self.r, "T": self.T, "statistic": self.statistic,
                "travel": self.travel, "travel_low": self._stat(self.travel_low),
                "travel_high": self._stat(self.travel_high), "felt": self.felt,
                "felt_low": self._stat(self.felt_low), "felt_high": self._stat(self.felt_high),
                "travel_per_record_low": list(self.travel_low), "felt_per_record_high": list(self.felt_high)}


def _peaks(task) -> list:
    """Per (R, r) of the task: ((travel, felt) per record at mu_low, the same at mu_high)."""
    from .time_history import simulate

    pairs, records, mu_low, mu_high, g = task
    out = []
    for R, r in pairs:
        both = []
        for mu in (mu_low, mu_high):
            iso = Isolator(R=R, r=r, M=1.0, mu=mu, g=g)
            runs = [simulate(iso, rec, dt_out=DT_OUT) for rec in records]
            both.append((tuple(x.u_max for x in runs), tuple(x.acc_abs_max for x in runs)))
        out.append(tuple(both))
    return out


def plate_demands(pairs, records, mu_low: float, mu_high: float, g: float = G, executor=None) -> dict:
    """{(R, r): PlateDemand} of the top plate alone (Coulomb, exact) on every record at both
    friction bounds; the plate's motion depends on neither its mass nor the number of balls.
    ``executor`` (compute/executors.py) runs blocks of pairs on its workers (None: here); the
    numbers do not depend on it.

    A half-period rectangular pulse of amplitude A from rest drives a frictionless plate to
    2 A / omega^2 and back (felt 2 A):

    >>> from statue2model.hazard import motions
    >>> iso = Isolator(R=1.0, r=0.02, M=1.0, mu=0.0)
    >>> pulse = motions.rect_pulse(1.0, iso.T / 2)
    >>> d = plate_demands([(1.0, 0.02)], [pulse], 0.0, 0.0)[1.0, 0.02]
    >>> round(d.travel * iso.omega ** 2, 6), round(d.felt, 6)
    (2.0, 2.0)
    """
    statistic = "mean" if len(records) >= N_MIN else "max"
    pairs, records = list(pairs), list(records)
    if executor is None or getattr(executor, "workers", 1) < 2 or len(pairs) < 2:
        peaks = _peaks((pairs, records, mu_low, mu_high, g))
    else:
        from ..compute.executors import chunks

        blocks = chunks(len(pairs), executor, per_worker=2, min_chunk=8)
        tasks = [([pairs[i] for i in b], records, mu_low, mu_high, g) for b in blocks]
        peaks = [p for part in executor.map(_peaks, tasks, desc="isolator: time histories") for p in part]
    return {(R, r): PlateDemand(R, r, low[0], high[0], low[1], high[1], statistic)
            for (R, r), (low, high) in zip(pairs, peaks)}


@dataclass(frozen=True)
class Margins:
    """The three time-history margins (limit / demand, > 1 passes) of a candidate."""

    travel: float
    acceleration: float
    bearing: float

    @property
    def balance(self) -> float:
        """The smaller of the acceleration and bearing margins, and of the travel margin when
        that is below 1 (CRITERION)."""
        return min(self.acceleration, self.bearing, self.travel if self.travel < 1 - TOL else math.inf)

    @property
    def passed(self) -> bool:
        return min(self.travel, self.acceleration, self.bearing) >= 1.0 - TOL

    def to_dict(self) -> dict:
        return {"travel": _fin(self.travel), "acceleration": _fin(self.acceleration), "bearing": _fin(self.bearing)}


@dataclass(frozen=True)
class Verified:
    """One candidate (design.Candidate) with its time-history margins and checks (the spectral
    ones with REPLACED advisory, then the two time-history checks); ``device_ok``: every
    spectral required check outside REPLACED passes."""

    candidate: object
    margins: Margins
    checks: tuple
    device_ok: bool
    need: float                 # time-history travel need, m

    @property
    def passed(self) -> bool:
        return self.device_ok and self.margins.passed


def _fin(x: float) -> float | None:
    return float(f"{x:.6g}") if math.isfinite(x) else None


def _th_checks(c, dem: PlateDemand, a_lim: float, why_lim: str, mu_low: float, mu_high: float, margin: float,
               n_rec: int) -> tuple[tuple, Margins, float]:
    need = margin * dem.travel + mu_high * c.R_hat
    cap = c.capacity
    stat = f"the {dem.statistic} over {n_rec} record{'s' if n_rec != 1 else ''}"
    bound = "mu_low" if dem._stat(dem.travel_low) >= dem._stat(dem.travel_high) else "mu_high"
    fbound = "mu_high" if dem._stat(dem.felt_high) >= dem._stat(dem.felt_low) else "mu_low"
    mu_t, mu_a = (mu_low if bound == "mu_low" else mu_high), (mu_high if fbound == "mu_high" else mu_low)
    travel = Check("time-history travel within the capacity", need <= cap * (1 + TOL), need, cap,
                   f"{margin:g} x peak travel {dem.travel:.4f} m ({stat}, {bound} {mu_t:g}) "
                   f"+ mu_high R_hat {mu_high * c.R_hat:.4f} m = {need:.4f} m vs capacity {cap:.4f} m",
                   unit="m", key="th_travel")
    acc = Check("time-history felt acceleration below the uplift limit", dem.felt <= a_lim, dem.felt, a_lim,
                f"peak absolute plate acceleration {dem.felt:.4f} m/s^2 ({stat}, {fbound} {mu_a:g}) vs {why_lim}",
                unit="m/s^2", key="th_acceleration")
    load = c.check("ball_load")
    m = Margins(travel=cap / need if need > 0 else math.inf,
                acceleration=a_lim / dem.felt if dem.felt > 0 else math.inf,
                bearing=load.limit / load.value if load.value > 0 else math.inf)
    return (travel, acc), m, need


def _verified(c, dem, a_lim, why_lim, mu_low, mu_high, margin, n_rec) -> Verified:
    th, m, need = _th_checks(c, dem, a_lim, why_lim, mu_low, mu_high, margin, n_rec)
    spectral = tuple(replace(ck, required=False, why=ck.why + " (advisory: the time histories decide)")
                     if ck.key == "acceleration" else ck for ck in c.checks)
    return Verified(c, m, spectral + th, c.passes(ignore=REPLACED), need)


def rank(entries) -> list:
    """``entries`` (Verified) in the order of CRITERION: the passing ones first (within
    BALANCE_TOLERANCE of the best balance the lightest top plate, then the rest by balance),
    then the failing ones nearest first (device checks passed, then the largest balance)."""
    passing = [v for v in entries if v.passed]
    failing = [v for v in entries if not v.passed]

    def tie(v):
        c = v.candidate
        return (round(c.side, 3), c.thickness, c.n_grooves, -c.r)

    ranked = []
    if passing:
        best = max(v.margins.balance for v in passing)
        near = [v for v in passing if v.margins.balance >= (1 - BALANCE_TOLERANCE) * best]
        rest = [v for v in passing if v.margins.balance < (1 - BALANCE_TOLERANCE) * best]
        ranked = (sorted(near, key=lambda v: (round(v.candidate.m_o, 3), -v.margins.balance) + tie(v))
                  + sorted(rest, key=lambda v: (-v.margins.balance, round(v.candidate.m_o, 3)) + tie(v)))
    return ranked + sorted(failing, key=lambda v: (not v.device_ok, -v.margins.balance,
                                                   round(v.candidate.m_o, 3)) + tie(v))


def _check_inputs(records, mu, mu_low, mu_high, margin):
    if not records or not all(isinstance(m, GroundMotion) for m in records):
        raise InputError("the verification needs at least one design record (GroundMotion)")
    if any(m.kind == "none" or not m.pga > 0 for m in records):
        raise InputError("every design record must be a ground motion (not zero)")
    for name, v in (("mu_low", mu_low), ("mu_high", mu_high)):
        if not (isinstance(v, (int, float)) and math.isfinite(v) and 0 <= v < 0.5):
            raise InputError(f"friction bound {name} must be in [0, 0.5), got {v!r}")
    if not mu_low <= mu <= mu_high:
        raise InputError(f"friction bounds must hold the nominal mu: mu_low {mu_low:g} <= mu {mu:g} <= mu_high "
                         f"{mu_high:g}")
    if not (math.isfinite(margin) and margin >= 1):
        raise InputError(f"displacement margin must be >= 1, got {margin}")


def verify(statue, *, records, mu: float, mu_low: float | None = None, mu_high: float | None = None,
           a_lim: float | None = None, a_lim_why: str | None = None, records_info: dict | None = None,
           balls=BALLS, R_grid=R_GRID, margin: float = DISPLACEMENT_MARGIN, g: float = G, executor=None,
           **kwargs):
    """The isolator for ``statue`` (RockingParams) chosen by CRITERION among the candidates of
    :func:`~statue2model.isolator.design.design` (``mu``, ``balls``, ``R_grid``, ``margin``, ``g``
    and ``kwargs``: spectrum or motion, alpha, target, n_grooves, thickness, fuse_release,
    ball_capacity, ...) verified on ``records`` (GroundMotion, the design set) at the friction
    bounds ``mu_low`` and ``mu_high`` (None: :func:`friction_bounds`), against the uplift limit
    ``a_lim`` (m/s^2, described by ``a_lim_why``; None: min(alpha_L a_L, alpha_R a_R)).
    ``records_info``: what the records are ({"source", "rules_met", ...}, kept in design.json);
    ``executor``: where the plate runs go (:func:`plate_demands`).
    Returns a :class:`~statue2model.isolator.design.Design` whose ``verification`` holds the
    margins and the candidates, and ``what_would_pass`` what would pass when none does."""
    lo, hi = friction_bounds(mu)
    mu_low = lo if mu_low is None else mu_low
    mu_high = hi if mu_high is None else mu_high
    records = list(records)
    _check_inputs(records, mu, mu_low, mu_high, margin)
    kw = dict(kwargs, mu=mu, balls=balls, R_grid=R_grid, margin=margin, g=g, a_lim=a_lim, a_lim_why=a_lim_why)
    spec = design(statue, **kw)
    cands = spec.evaluated
    ok_pairs = {(c.R, c.r) for c in cands if c.passes(ignore=REPLACED)}
    longest = (max(R_grid), min(balls))
    pairs = set(ok_pairs) | ({longest} if longest[0] > 2 * longest[1] else set())
    if not ok_pairs:
        pairs.add((spec.R, spec.r))                      # the spectral search's nearest
    demands = plate_demands(sorted(pairs), records, mu_low, mu_high, g, executor)
    floor = {p: margin * dem.travel + mu_high * 2 * (p[0] - p[1]) for p, dem in demands.items()}
    sized = design(statue, travel_floor=floor, **kw)
    cx = sized.evaluated[0].cx
    a_lim_used, why_lim = cx.a_lim, cx.why_lim
    n_rec = len(records)
    entries = [_verified(c, demands[c.R, c.r], a_lim_used, why_lim, mu_low, mu_high, margin, n_rec)
               for c in sized.evaluated if (c.R, c.r) in demands]
    ranked = rank(entries)
    best = ranked[0]
    passed = best.passed
    ranges = sized.candidates.get("ranges", "")
    n_pass = sum(v.passed for v in entries)
    failure = None if passed else (failure_text(best.checks, shown=None)
                                   + f" [nearest of {len(entries)} candidates verified; {ranges}]")
    wwp = None if passed else what_would_pass(best, demands, a_lim_used, cx.ball_capacity, cx.side_max)
    info = dict(records_info or {})
    verification = {
        "margins": best.margins.to_dict(), "balance": _fin(best.margins.balance), "passed": passed,
        "definitions": DEFINITIONS, "criterion": CRITERION,
        "records": {"count": n_rec, "source": info.pop("source", "given"), "rules_met": info.pop("rules_met", None),
                    "labels": [m.label for m in records], **info},
        "statistic": demands[best.candidate.R, best.candidate.r].statistic,
        "statistic_rule": f"the mean over the records with at least {N_MIN} (NTC 2018 §7.3.5, EN 1998-1 "
                          "§4.3.3.4.3), else the most unfavourable record",
        "mu": mu, "mu_low": mu_low, "mu_high": mu_high,
        "mu_rule": "every record at both friction bounds (EN 15129 / ASCE 7-16 §17.2.8.4 bound analyses); each "
                   "demand takes the bound that governs it",
        "a_lim": a_lim_used, "a_lim_why": why_lim, "model": "top plate alone, Coulomb (exact while the statue "
                                                             "stays in full contact)",
        "demand": {**demands[best.candidate.R, best.candidate.r].to_dict(), "travel_need": best.need,
                   "spectral_need": best.candidate.check("travel").value, "capacity": best.candidate.capacity,
                   "capacity_sized_on": ("time histories" if best.need > best.candidate.check("travel").value
                                         else "spectrum")},
        "capacity_rule": "the opening is cut to cover the larger of the spectral and the time-history travel need",
        "pairs_run": len(demands), "runs": 2 * n_rec * len(demands), "candidates_verified": len(entries),
        "candidates_passing": n_pass,
        "pruned": "only the (R, r) whose candidates pass the device checks are run, with the longest period in "
                  "range (and the spectral nearest when none passes them)",
    }
    shown = ranked[:SHOWN_PASSING]
    unverified = [c for c in sized.evaluated if (c.R, c.r) not in demands][:SHOWN_FAILING]
    head = best.checks
    table = {"criterion": CRITERION, "tried": len(sized.evaluated), "verified": len(entries), "passing": n_pass,
             "shown": len(shown) + len(unverified), "ranges": ranges,
             "order": "verified candidates by the criterion (chosen first, then the failing ones nearest first), "
                      "then candidates not run (a device check fails), nearest first",
             "checks": [{"key": c.key, "name": c.name, "unit": c.unit, "required": c.required} for c in head],
             "check_columns": ["value", "limit", "ratio", "passed"],
             "margin_definitions": DEFINITIONS,
             "rows": [_row(v) for v in shown] + [_unverified_row(c) for c in unverified]}
    notes = [f"verified on {n_rec} design record{'s' if n_rec != 1 else ''} at mu {mu_low:.4g} and {mu_high:.4g}: "
             f"{n_pass} of {len(entries)} candidates pass; margins travel {best.margins.travel:.2f}, acceleration "
             f"{best.margins.acceleration:.2f}, bearing {best.margins.bearing:.2f}"]
    if wwp:
        notes.append("what would pass: " + wwp["text"])
    d = best.candidate.as_design(statue, spectrum=kwargs.get("spectrum"), motion=kwargs.get("motion"),
                                 target=kwargs.get("target"), alpha=kwargs.get("alpha", (1.0, 1.0)),
                                 tried=len(sized.evaluated), candidates=table, failure=failure, notes=notes)
    return replace(d, checks=best.checks, criterion=CRITERION, verification=verification, what_would_pass=wwp,
                   evaluated=sized.evaluated)


def _row(v: Verified) -> dict:
    row = v.candidate.row()
    row["checks"] = [[_fin(c.value), _fin(c.limit), _fin(c.ratio), c.passed] for c in v.checks]
    row.update(passed=v.passed, device_ok=v.device_ok, margins=v.margins.to_dict(), balance=_fin(v.margins.balance),
               th_need=_fin(v.need), worst_ratio=_fin(max(c.ratio for c in v.checks if c.required)))
    return row


def _unverified_row(c) -> dict:
    row = c.row()
    row["checks"] = row["checks"] + [[None, None, None, False], [None, None, None, False]]
    row.update(passed=False, device_ok=False, margins=None, balance=None, th_need=None)
    return row


def what_would_pass(best: Verified, demands: dict, a_lim: float, ball_capacity: float, side_max: float) -> dict:
    """What the nearest candidate ``best`` lacks and what would give it (module docstring):
    a dict of numbers and ``text``, one sentence per fix; ``restrain`` True when no (R, r) run
    keeps the statue in full contact (``text`` then says that alone)."""
    c, m = best.candidate, best.margins
    out, text = {"candidate": {"R": c.R, "r": c.r, "n_grooves": c.n_grooves, "side": c.side, "T": c.T,
                               "thickness": c.thickness}, "restrain": False}, []
    acc = {p: (a_lim / dem.felt if dem.felt > 0 else math.inf, dem) for p, dem in demands.items()}
    top_p, (top_m, top_d) = max(acc.items(), key=lambda kv: (kv[1][0], kv[0][0]))
    if top_m < 1.0 - TOL:
        longest = max(demands, key=lambda p: demands[p].T)
        out.update(restrain=True, best_acceleration_margin=_fin(top_m), best_pair={"R": top_p[0], "r": top_p[1]})
        text.append(f"restrain the statue: no device in range keeps it in full contact, the largest "
                    f"acceleration margin is {top_m:.2f} < 1 (R {top_p[0]:g} m, r {top_p[1] * 1000:g} mm, T "
                    f"{top_d.T:.2f} s: felt {top_d.felt:.3f} m/s^2 vs uplift {a_lim:.3f} m/s^2; the longest "
                    f"period in range is {demands[longest].T:.2f} s)")
    elif m.acceleration < 1.0 - TOL:
        fits = sorted((p for p, (am, _) in acc.items() if am >= 1.0 and p[1] == c.r), key=lambda p: p[0]) or \
            sorted((p for p, (am, _) in acc.items() if am >= 1.0), key=lambda p: p[0])
        if fits:
            p = fits[0]
            out["R_needed"] = p[0]
            text.append(f"a longer period: R {p[0]:g} m with {p[1] * 1000:g} mm balls (T {demands[p].T:.2f} s) keeps "
                        f"the felt acceleration within the uplift limit (margin {acc[p][0]:.2f})")
    if m.bearing < 1.0 - TOL:
        P = c.W / c.n_grooves
        scale = (c.r / BALL_TESTED) ** 2
        P_allow = ball_capacity * scale
        n_need = math.ceil(c.W / P_allow)
        r_need = BALL_TESTED * math.sqrt(P / ball_capacity)
        out.update(load_per_ball=_fin(P), ball_capacity_needed=_fin(P / scale), ball_capacity_given=ball_capacity,
                   ball_radius_needed=_fin(r_need), balls_needed=n_need)
        text.append(f"grooves that carry {P:.0f} N per {c.r * 1000:g} mm ball, i.e. {P / scale:.0f} N on a "
                    f"{BALL_TESTED * 1000:g} mm ball (the [isolator] ball_capacity convention; {ball_capacity:.0f} N "
                    f"given): load-test a harder surface, an insert or a rubber layer against it")
        text.append(f"or, at {ball_capacity:.0f} N on a {BALL_TESTED * 1000:g} mm ball, balls of "
                    f"{r_need * 1000:.0f} mm radius ({c.n_grooves} of them, the same plate) or {n_need} balls of "
                    f"{c.r * 1000:g} mm (this layout has {c.n_grooves} grooves: more balls need more grooves or a "
                    "ball cage)")
    if m.travel < 1.0 - TOL or not best.device_ok:
        out.update(capacity_needed=_fin(best.need), capacity=_fin(c.capacity))
        if c.side_needed > side_max + 1e-9:
            out["side_needed"] = _fin(c.side_needed)
            text.append(f"a plate of side {c.side_needed:.3f} m (largest allowed {side_max:g} m) for a travel capacity "
                        f"of {best.need:.3f} m (now {c.capacity:.3f} m)")
        elif m.travel < 1.0 - TOL:
            text.append(f"a travel capacity of {best.need:.3f} m (now {c.capacity:.3f} m): wider grooves or a "
                        "plate that does not tip (groove spacing)")
    for ck in best.checks:
        if ck.required and not ck.passed and ck.key not in ("th_travel", "th_acceleration", "ball_load", "travel",
                                                              "plate_size"):
            text.append(f"also {ck.name} (now: {ck.why})")
    if out["restrain"]:        # no device would do: the fixes of this one are beside the point
        text = text[:1]
    out["text"] = "; ".join(text) if text else "nothing in range: see the failing checks"
    return out
