"""The limit states of a free-standing artefact at the design level, on a fixed base and on the
isolator (MODEL.md section 8): each one's demand over the design record set, its capacity and
their ratio, with the definition of each in one sentence.

The codes' rule for a set of time histories (NTC 2018 par. 7.3.5, EN 1998-1 4.3.3.4.3): with at
least 7 records (:data:`statue2model.hazard.matching.N_MIN`) the design effect is the MEAN of the
records' effects, with fewer the most unfavourable one (the MAX; the codes ask for at least 3).
:func:`evaluate` runs every record of the set, already matched to the design target (no scaling
here), once on a fixed base (:func:`statue2model.rocking.engine.simulate`) and, with an
isolator, on it (:func:`statue2model.isolator.coupled.simulate_coupled`: the statue rocks on
the moving top plate, full contact checked, not assumed) at the design's two friction bounds
mu_low and mu_high when it was verified at them (each quantity at the bound that makes it worse,
EN 15129 / ASCE 7-16 17.2.8.4 practice; the rows' details say ``mu_bounds``), else once at its mu,
and keeps per record the numbers below
(:class:`FixedRecord`, :class:`IsolatedRecord`). The rows (:class:`LimitState`), in the order the
damage grows; each reads ``ratio = demand / capacity`` unless its definition says otherwise:

    full contact  fixed: the peak ground acceleration toward each side (u_g'' > 0 toward +x lifts
                  the statue on its LEFT pivot, against alpha_L a_L; u_g'' < 0 on its right, against
                  alpha_R a_R; MODEL.md section 2), the statistic over the records per side; the row
                  is the side with the larger ratio. With an uncertain base contact
                  (``uplift_band``, the weakest uplift acceleration a_min at half and at double the
                  contact tolerance, geometry only, :class:`statue2model.geometry.base.BaseContact`)
                  each side's capacity is alpha_side min(a_side, the band's LOW end): the
                  conservative reading; the time histories keep the model's own limits.
                  isolated: the peak absolute acceleration of the top plate (what the statue feels)
                  against the weaker side's uplift acceleration (the peak's sign is not kept:
                  conservative). Exceeded when ratio >= 1.
    rocking       the peak |theta| / delta (an overturned record counts as 1, and on the isolator a
                  record that reached the isolator's capacity too), capacity 1 (theta = delta tips
                  the statue over statically); the number of impacts beside it. Exceeded when
                  ratio >= 1.
    overturning   the fraction of records that overturn. The mean of an effect with a collapse in it
                  is not defined, so ANY overturning record exceeds the limit state (the
                  conservative reading): capacity 1 / n (one record of n), ratio = the number of
                  records that overturn, exceeded when >= 1. On the isolator a record that reached
                  the isolator's capacity counts as overturned (the run stops there: the balls
                  leave their grooves or the top plate tips).
    capacity      (isolated) the travel the design's check asks for, with the records' peak plate
                  travel relative to the ground in place of the spectral displacement:
                  DISPLACEMENT_MARGIN (1.5, :mod:`statue2model.isolator.checks`) x the statistic of
                  max |u_o| + mu R_hat (where friction may have left the plate resting off centre),
                  against the design's travel capacity min(groove rim, top-plate tipping). Exceeded
                  when ratio > 1 or any record passed the capacity outright.
    bearing       (isolated) the static load per ball W / n (the design's required check, isolator/checks.py),
                  against the long-term capacity of a ball on the design's groove surface (design.json
                  ``ball_capacity.per_ball``, isolator/bearing.py). Exceeded when ratio > 1.

``governing`` is each base's row with the largest ratio, ``first_exceeded`` each base's first
exceeded row in the order above. Every number of :meth:`LimitStates.to_dict` is finite or None
with its reason beside it.

Example
-------
>>> from statue2model.geometry.rocking_params import RockingParams
>>> from statue2model.hazard import motions
>>> from statue2model.isolator.device import Isolator
>>> from statue2model.rocking.model import RockingModel
>>> block = RockingParams.rectangular_block(b=0.05, h=0.25, m=10.0)      # lifts at g b / h = 1.962 m/s^2
>>> records = [motions.sine_pulse(1.0 + 0.1 * k, 2.0) for k in range(7)]  # peaks 1.0 .. 1.6 m/s^2
>>> ls = evaluate(RockingModel.housner(block), records, iso=Isolator(R=0.30, r=0.0183, M=15.0, mu=0.01))
>>> fc = ls.row("full_contact", "fixed")
>>> ls.statistic, round(fc.demand, 3), round(fc.capacity, 3), round(fc.ratio, 4), fc.exceeded
('mean', 1.3, 1.962, 0.6626, False)
>>> ls.first_exceeded, ls.governing["fixed"].name
({'fixed': None, 'isolated': None}, 'full_contact')
"""
from __future__ import annotations

import math
from dataclasses import asdict, dataclass, field, replace

import numpy as np

from ..errors import InputError
from . import states
from .records import field_number

LIMIT_STATES = states.IDS
"""The rows of a base, in the order the damage grows (``first_exceeded`` follows it): the registry's
(assessment/states.py)."""
TITLES = {s.id: s.title for s in states.REGISTRY}
BASES = states.BASES
RULE = ("NTC 2018 par. 7.3.5, EN 1998-1 4.3.3.4.3: with at least 7 records the mean of the effects, "
        "with fewer the most unfavourable one (the codes ask for at least 3)")
BEARING_OPTIONS = (
    "a harder groove surface (a hardwood, resin or metal insert or liner in each groove)",
    "a rubber layer on the grooves (the thesis' device, ch. 5.2.3: it spreads the contact and adds damping)",
    "more balls (the load per ball is W / n)",
    "larger balls (on wood the capacity grows as r^2 up to 40 mm balls, more slowly above)",
    "fuse balls that carry the plate at rest (SDI-BPS, ch. 2.4; the design's fuse), so the rolling balls "
    "are loaded only while the plate moves",
)
SCHEMA = "statue2model.limit_states/1"


def _num(x) -> float | None:
    """A finite float or None (JSON has no nan or inf)."""
    if x is None:
        return None
    x = float(x)
    return x if math.isfinite(x) else None


def _nan(x: float | None) -> float:
    """A stored None of a float field back as nan (it was non-finite: JSON has none)."""
    return math.nan if x is None else x


def _mapping(d, where: str) -> dict:
    if not isinstance(d, dict):
        raise InputError(f"{where}: expected a table, got {type(d).__name__}")
    return d


# --- per record ---------------------------------------------------------------------------------
@dataclass(frozen=True)
class FixedRecord:
    """One record on a fixed base (SI units). ``pga_pos``: the largest u_g'' toward +x (m/s^2; it
    lifts the statue on its left pivot), ``pga_neg``: the largest -u_g'' (toward -x, right pivot);
    ``uplift``: the time history left full contact (``t_uplift`` s, None if never);
    ``theta_max_over_delta``: peak |theta| / delta_side over both sides; ``n_impacts``;
    ``overturned``; ``outcome`` (the engine's words); ``applicable``: False if the body slides
    before it rocks under this record (the rocking numbers are then those of a base that cannot
    slide). With a support (assessment/support.py): ``slide_pos`` / ``slide_neg`` the statue's peak
    sliding on it toward +x / -x (m), and with a pedestal ``ped_slide_pos`` / ``ped_slide_neg`` the
    pedestal's on the floor (m), ``ped_uplift``, ``ped_overturned``, ``ped_theta_max_over_delta``
    its rocking with the statue, ``from_stack`` True when the rocking numbers above are the two-block
    run's (the pedestal lifted); nan (None in the file) where not computed."""

    label: str
    pga_pos: float
    pga_neg: float
    uplift: bool
    t_uplift: float | None
    theta_max_over_delta: float
    n_impacts: int
    overturned: bool
    outcome: str
    applicable: bool
    slide_pos: float = math.nan
    slide_neg: float = math.nan
    ped_slide_pos: float = math.nan
    ped_slide_neg: float = math.nan
    ped_uplift: bool = False
    ped_overturned: bool = False
    ped_theta_max_over_delta: float = math.nan
    from_stack: bool = False

    def to_dict(self) -> dict:
        """Every field, in order; a non-finite number as None."""
        return _clean(asdict(self))

    @classmethod
    def from_dict(cls, d: dict) -> FixedRecord:
        """The record of :meth:`to_dict` (a None number back as nan; ``FixedRecord.from_dict(r.to_dict())
        .to_dict() == r.to_dict()``)."""
        d = _mapping(d, "fixed-base record")
        w = f"fixed-base record {d.get('label')!r:.40}"
        return cls(str(d.get("label", "")), _nan(field_number(d, "pga_pos", w)), _nan(field_number(d, "pga_neg", w)),
                   bool(d.get("uplift")), field_number(d, "t_uplift", w), _nan(field_number(d, "theta_max_over_delta", w)),
                   int(d.get("n_impacts") or 0), bool(d.get("overturned")), str(d.get("outcome", "")),
                   bool(d.get("applicable", True)), *(_nan(field_number(d, k, w)) for k in _SLIDES),
                   bool(d.get("ped_uplift")), bool(d.get("ped_overturned")),
                   _nan(field_number(d, "ped_theta_max_over_delta", w)), bool(d.get("from_stack")))


_SLIDES = ("slide_pos", "slide_neg", "ped_slide_pos", "ped_slide_neg")


@dataclass(frozen=True)
class IsolatedRecord:
    """One record with the statue on the isolator (SI units). ``pga``: the ground's peak |u_g''|
    (m/s^2); ``u_max``: the peak |u_o| of the top plate relative to the ground (m);
    ``capacity_exceeded``: |u_o| passed the isolator's capacity (the run stopped there, at
    ``t_capacity`` s); ``acc_felt``: the peak |absolute acceleration| of the top plate, what the
    statue feels (m/s^2); ``uplift``, ``t_uplift``: the statue left full contact on the plate;
    ``theta_max_over_delta``, ``n_impacts``, ``overturned``, ``outcome`` as on the fixed base."""

    label: str
    pga: float
    u_max: float
    capacity_exceeded: bool
    t_capacity: float | None
    acc_felt: float
    uplift: bool
    t_uplift: float | None
    theta_max_over_delta: float
    n_impacts: int
    overturned: bool
    outcome: str

    def to_dict(self) -> dict:
        """Every field, in order; a non-finite number as None."""
        return _clean(asdict(self))

    @classmethod
    def from_dict(cls, d: dict) -> IsolatedRecord:
        """The record of :meth:`to_dict` (a None number back as nan)."""
        d = _mapping(d, "isolated record")
        w = f"isolated record {d.get('label')!r:.40}"
        return cls(str(d.get("label", "")), _nan(field_number(d, "pga", w)), _nan(field_number(d, "u_max", w)),
                   bool(d.get("capacity_exceeded")), field_number(d, "t_capacity", w), _nan(field_number(d, "acc_felt", w)),
                   bool(d.get("uplift")), field_number(d, "t_uplift", w), _nan(field_number(d, "theta_max_over_delta", w)),
                   int(d.get("n_impacts") or 0), bool(d.get("overturned")), str(d.get("outcome", "")))


def run_record(item: tuple) -> tuple[FixedRecord | None, IsolatedRecord | None]:
    """The per-record numbers of one record: ``item`` = (model, iso or None, motion, rtol[, fixed[,
    support[, iso_model]]]); the fixed-base run (unless ``fixed`` is False: the record's run at another friction
    bound of the same isolator, whose fixed base is already run; then None), with its sliding and
    pedestal numbers when ``support`` (assessment/support.py) is given, and, with an isolator, the
    coupled statue-on-isolator run (module level: an executor can map it). With a pedestal that
    lifts, the statue's rocking numbers are the two-block run's; while it stays in full contact the
    statue rocks as on the ground (the single-body model, imperfect or not)."""
    from ..isolator.coupled import simulate_coupled
    from ..rocking.bodies import simulate

    model, iso, motion, rtol = item[:4]
    support = item[5] if len(item) > 5 else None
    iso_model = item[6] if len(item) > 6 and item[6] is not None else model
    fixed = None
    if len(item) < 5 or item[4]:
        hi, lo = motion.extremes()
        r = simulate(model, motion, rtol=rtol)
        fixed = FixedRecord(motion.label, float(hi), float(-lo), r.uplift_time is not None, r.uplift_time,
                            float(r.theta_max_over_delta), r.n_impacts, bool(r.overturned), r.outcome,
                            bool(getattr(r, "applicable", True)))
        if support is not None:
            sr = support.run(motion)
            st = sr.statue or {}
            fixed = replace(fixed, slide_pos=sr.slide_pos, slide_neg=sr.slide_neg, ped_slide_pos=sr.ped_slide_pos,
                            ped_slide_neg=sr.ped_slide_neg, ped_uplift=sr.ped_uplift,
                            ped_overturned=sr.ped_overturned, ped_theta_max_over_delta=sr.ped_theta_max_over_delta,
                            from_stack=sr.statue is not None, **{k: st[k] for k in (
                                "uplift", "t_uplift", "theta_max_over_delta", "n_impacts", "overturned", "outcome")
                                if k in st})
    if iso is None:
        return fixed, None
    c = simulate_coupled(iso, iso_model, motion, rtol=rtol, dt_out=0.05)
    isolated = IsolatedRecord(motion.label, float(motion.pga), float(c.u_max), bool(c.capacity_exceeded),
                              c.t_capacity, float(c.acc_abs_max), bool(c.uplift), c.t_uplift,
                              float(c.theta_max_over_delta), int(c.n_impacts), bool(c.overturned), c.outcome)
    return fixed, isolated


# --- rows ----------------------------------------------------------------------------------------
@dataclass(frozen=True)
class LimitState:
    """One limit state on one base: ``demand`` (the statistic over the records, in ``unit``),
    ``capacity`` (same unit), ``ratio`` (as ``definition`` says; usually demand / capacity),
    ``exceeded``, ``n_exceeding`` (records that exceed it by themselves), ``per_record`` (each
    record's value of the quantity whose statistic is the demand, in the records' order; empty
    for a static check), ``details`` (the numbers behind the row, JSON-ready) and ``reason``
    (why a number is None; '' when all are defined)."""

    name: str
    base: str
    demand: float | None
    capacity: float | None
    ratio: float | None
    unit: str
    definition: str
    exceeded: bool
    n_exceeding: int
    per_record: tuple = ()
    details: dict = field(default_factory=dict)
    reason: str = ""

    @property
    def title(self) -> str:
        return TITLES[self.name]

    @classmethod
    def from_dict(cls, d: dict) -> LimitState:
        """The row of :meth:`to_dict`; a name outside the registry (assessment/states.py) or a base
        other than fixed / isolated is an InputError naming it (its title is the registry's)."""
        d = _mapping(d, "limit-state row")
        name, base = d.get("name"), d.get("base")
        if name not in states.BY_ID:
            raise InputError(f"limit-state row: unknown limit state {name!r:.40} (one of {', '.join(states.IDS)})")
        if base not in BASES:
            raise InputError(f"limit-state row {name}: unknown base {base!r:.40} (fixed or isolated)")
        w = f"limit-state row {name} ({base})"
        k = d.get("n_exceeding") or 0
        if isinstance(k, bool) or not isinstance(k, (int, float)) or k < 0:
            raise InputError(f"{w}: n_exceeding must be a count, got {k!r:.40}")
        return cls(name, base, field_number(d, "demand", w), field_number(d, "capacity", w), field_number(d, "ratio", w), str(d.get("unit") or ""),
                   str(d.get("definition") or ""), bool(d.get("exceeded")), int(k),
                   tuple(_num(v) if isinstance(v, (int, float)) and not isinstance(v, bool) else None
                         for v in d.get("per_record") or ()),
                   dict(d.get("details") or {}), str(d.get("reason") or ""))

    def to_dict(self) -> dict:
        return {"name": self.name, "title": self.title, "base": self.base, "rule": states.get(self.name).rule,
                "demand": _num(self.demand),
                "capacity": _num(self.capacity), "ratio": _num(self.ratio), "unit": self.unit,
                "exceeded": bool(self.exceeded), "n_exceeding": int(self.n_exceeding),
                "per_record": [_num(v) for v in self.per_record], "definition": self.definition,
                "details": _clean(self.details), "reason": self.reason or None}


def _clean(x):
    """A JSON-ready copy: non-finite floats -> None, tuples and arrays -> lists."""
    if isinstance(x, dict):
        return {k: _clean(v) for k, v in x.items()}
    if isinstance(x, (list, tuple, np.ndarray)):
        return [_clean(v) for v in x]
    if isinstance(x, (bool, np.bool_)):
        return bool(x)
    if isinstance(x, (int, np.integer)):
        return int(x)
    if isinstance(x, (float, np.floating)):
        return _num(x)
    return x


@dataclass(frozen=True)
class LimitStates:
    """The rows of :func:`evaluate` (fixed base first, each base in the order of LIMIT_STATES),
    the per-record tables (``isolated`` None without an isolator), ``n_records``, the
    ``statistic`` of the demands ('mean' with at least 7 records, else 'max': :data:`RULE`), the
    contact limits used (``uplift_limits``: alpha_L a_L toward +x, alpha_R a_R toward -x, m/s^2,
    with the band applied) and ``warnings``."""

    rows: tuple
    fixed: tuple
    isolated: tuple | None
    n_records: int
    statistic: str
    uplift_limits: tuple
    uplift_band: tuple | None = None
    warnings: tuple = ()

    def row(self, name: str, base: str) -> LimitState:
        for r in self.rows:
            if r.name == name and r.base == base:
                return r
        raise InputError(f"no limit state {name!r} on the {base} base (rows: "
                         f"{', '.join(f'{r.base} {r.name}' for r in self.rows)})")

    def base_rows(self, base: str) -> list[LimitState]:
        return [r for r in self.rows if r.base == base]

    @property
    def governing(self) -> dict:
        """base -> the row with the largest defined ratio (None if no ratio is defined)."""
        out = {}
        for base in self._bases():
            rated = [r for r in self.base_rows(base) if r.ratio is not None]
            out[base] = max(rated, key=lambda r: r.ratio) if rated else None
        return out

    @property
    def first_exceeded(self) -> dict:
        """base -> the name of its first exceeded row in the order of LIMIT_STATES, or None."""
        out = {}
        for base in self._bases():
            hit = [r.name for r in self.base_rows(base) if r.exceeded]
            out[base] = min(hit, key=LIMIT_STATES.index) if hit else None
        return out

    def _bases(self) -> tuple:
        iso = self.isolated is not None or any(r.base == "isolated" for r in self.rows)
        return BASES if iso else BASES[:1]

    def to_dict(self) -> dict:
        gov = self.governing
        return {"schema": SCHEMA, "n_records": self.n_records, "statistic": self.statistic, "rule": RULE,
                "records": [r.label for r in self.fixed],
                "uplift_limits": {"left_pivot_toward_plus_x": _num(self.uplift_limits[0]),
                                  "right_pivot_toward_minus_x": _num(self.uplift_limits[1]), "unit": "m/s^2"},
                "uplift_band": None if self.uplift_band is None else [_num(v) for v in self.uplift_band],
                "rows": [r.to_dict() for r in self.rows],
                "governing": {b: None if r is None else r.name for b, r in gov.items()},
                "first_exceeded": self.first_exceeded,
                "fixed_records": [r.to_dict() for r in self.fixed],
                "isolated_records": None if self.isolated is None else [r.to_dict() for r in self.isolated],
                "warnings": list(self.warnings)}

    @classmethod
    def from_dict(cls, d: dict) -> LimitStates:
        """The table of :meth:`to_dict` (limit_states.json, or run.json's verdict["limit_states"]):
        ``LimitStates.from_dict(ls.to_dict()).to_dict() == ls.to_dict()``; a malformed table is an
        InputError naming what is wrong. The per-record tables are optional (the verdict's copy may
        leave them out)."""
        d = _mapping(d, "limit states")
        n = d.get("n_records")
        if isinstance(n, bool) or not isinstance(n, int) or n < 1:
            raise InputError(f"limit states: n_records must be a count >= 1, got {n!r:.40}")
        rows = tuple(LimitState.from_dict(r) for r in d.get("rows") or ())
        lim = _mapping(d.get("uplift_limits") or {}, "limit states: uplift_limits")
        band = d.get("uplift_band")
        iso = d.get("isolated_records")
        return cls(rows, tuple(FixedRecord.from_dict(r) for r in d.get("fixed_records") or ()),
                   None if iso is None else tuple(IsolatedRecord.from_dict(r) for r in iso), n,
                   str(d.get("statistic") or "mean"),
                   (_nan(field_number(lim, "left_pivot_toward_plus_x", "uplift_limits")),
                    _nan(field_number(lim, "right_pivot_toward_minus_x", "uplift_limits"))),
                   None if band is None else tuple(field_number({"v": v}, "v", "uplift_band") for v in band),
                   tuple(str(w) for w in d.get("warnings") or ()))

    def table(self) -> str:
        """The rows as a plain text table (one line each, '-' for an undefined number)."""
        def f(x, spec=".4g"):
            return "-" if x is None or not math.isfinite(x) else format(x, spec)

        lines = [("base", "limit state", "demand", "capacity", "unit", "ratio", "n exceeding", "exceeded")]
        for r in self.rows:
            lines.append((r.base, r.name, f(r.demand), f(r.capacity), r.unit, f(r.ratio, ".3f"),
                          f"{r.n_exceeding}/{self.n_records}", "YES" if r.exceeded else "no"))
        w = [max(len(line[i]) for line in lines) for i in range(len(lines[0]))]
        return "\n".join("  ".join(s.ljust(w[i]) if i in (0, 1, 4, 7) else s.rjust(w[i])
                                   for i, s in enumerate(line)).rstrip() for line in lines)


# --- evaluation ----------------------------------------------------------------------------------
def _check(model, records, iso, design, uplift_band):
    from ..hazard.motions import GroundMotion
    from ..isolator.device import Isolator, isolator_from_design
    from ..rocking.model import RockingModel

    if not isinstance(model, RockingModel):
        raise InputError("limit states: model must be a RockingModel")
    records = tuple(records) if records is not None else ()
    if not records:
        raise InputError("limit states: no records (give the design record set's records)")
    for i, rec in enumerate(records):
        if not isinstance(rec, GroundMotion):
            raise InputError(f"limit states: record {i} is not a GroundMotion, got {type(rec).__name__}")
    if design is not None and not isinstance(design, dict):
        to_dict = getattr(design, "to_dict", None)
        if not callable(to_dict):
            raise InputError("limit states: design must be the isolator design's dict (design.json)")
        design = to_dict()
    if iso is None and design is not None:
        iso = isolator_from_design(design)
    if iso is not None and not isinstance(iso, Isolator):
        raise InputError("limit states: iso must be an Isolator")
    if iso is not None and design is not None:
        for key in ("R", "r", "M", "mu"):
            v = design.get(key)
            if v is not None and not math.isclose(float(v), getattr(iso, key), rel_tol=1e-9):
                raise InputError(f"limit states: the isolator is not the design's ({key} {getattr(iso, key):g} "
                                 f"vs the design's {float(v):g})")
    band = None
    if uplift_band is not None:
        try:
            lo, hi = (float(v) for v in uplift_band)
        except (TypeError, ValueError):
            raise InputError(f"limit states: uplift_band must be two accelerations (low, high) in m/s^2, "
                             f"got {uplift_band!r}") from None
        if not (math.isfinite(lo) and math.isfinite(hi) and 0 < lo <= hi):
            raise InputError(f"limit states: uplift_band must be two accelerations 0 < low <= high (m/s^2), "
                             f"got {uplift_band!r}")
        band = (lo, hi)
    return records, iso, design, band


def contact_limits(model, uplift_band=None) -> tuple[float, float]:
    """(toward +x, toward -x) ground accelerations (m/s^2) that lift ``model`` on its left and its
    right pivot: the model's alpha_L a_L and alpha_R a_R, and with an uncertain base contact
    ``uplift_band`` = (low, high) (a_min at half and double the contact tolerance, geometry only)
    alpha_side min(a_side, low): the low end, the conservative reading.

    >>> from statue2model.geometry.rocking_params import RockingParams
    >>> from statue2model.rocking.model import RockingModel
    >>> m = RockingModel.imperfect(RockingParams.rectangular_block(0.05, 0.25, 10.0), 0.5, 0.5)
    >>> [round(x, 4) for x in contact_limits(m)], [round(x, 4) for x in contact_limits(m, (1.5, 2.5))]
    ([0.981, 0.981], [0.75, 0.75])
    """
    up, dn = model.uplift_limits
    if uplift_band is None:
        return float(up), float(dn)
    low = float(uplift_band[0])
    aL, aR = model.effective_alpha
    return float(min(up, aL * low)), float(min(dn, aR * low))


def _worse(a: IsolatedRecord, b: IsolatedRecord) -> IsolatedRecord:
    """One record's isolated numbers at the governing friction bound: each quantity the worse of the
    runs at the lower (``a``) and the upper (``b``) bound (the larger travel, felt acceleration,
    rotation and impacts; exceeded, lifted or overturned in either), as EN 15129 / ASCE 7-16
    17.2.8.4 bound analyses take each response from the bound that maximises it."""
    def first(ta, tb):
        return min((t for t in (ta, tb) if t is not None), default=None)
    worst = a if (a.overturned, a.capacity_exceeded, a.theta_max_over_delta) >= (
        b.overturned, b.capacity_exceeded, b.theta_max_over_delta) else b
    return IsolatedRecord(a.label, a.pga, max(a.u_max, b.u_max), a.capacity_exceeded or b.capacity_exceeded,
                          first(a.t_capacity, b.t_capacity), max(a.acc_felt, b.acc_felt), a.uplift or b.uplift,
                          first(a.t_uplift, b.t_uplift), max(a.theta_max_over_delta, b.theta_max_over_delta),
                          max(a.n_impacts, b.n_impacts), a.overturned or b.overturned, worst.outcome)


def friction_bounds_of(design: dict | None) -> tuple[float, float] | None:
    """(mu_low, mu_high) of an isolator design verified at its friction bounds (design.json's
    ``verification``), else None."""
    v = (design or {}).get("verification") or {}
    lo, hi = v.get("mu_low"), v.get("mu_high")
    return (float(lo), float(hi)) if lo is not None and hi is not None else None


def evaluate(model, records, iso=None, design=None, rtol: float = 1e-7, uplift_band=None,
             executor=None, mu_bounds=None, support=None, iso_model=None, iso_limits=None) -> LimitStates:
    """The limit states of ``model`` (a RockingModel: its alpha-reduced uplift limits are the ones
    used) under ``records`` (the design record set's GroundMotions, at the design level), on a
    fixed base and, with ``iso`` (an Isolator) or ``design`` (the isolator design's dict,
    design.json; its Isolator when ``iso`` is None), on the isolator; see the module docstring.
    ``rtol``: the solvers' relative tolerance; ``uplift_band``: (low, high) m/s^2 when the base
    contact is uncertain, else None; ``executor``: maps the records over its workers
    (statue2model.compute.executors), else they run here. ``mu_bounds``: (mu_low, mu_high) of the
    isolator's rolling friction (default: the design's verified bounds, :func:`friction_bounds_of`,
    else the isolator's mu alone): every record runs on the isolator at both bounds and each quantity
    is taken at the bound that makes it worse (:func:`_worse`). ``support``: what the statue stands on
    (:class:`statue2model.assessment.support.Support`): adds the sliding row, and with a pedestal the
    pedestal's rows; None: neither. ``iso_model``: the body the isolator carries (None: ``model``; the stack
    as one body when the device carries the pedestal) and ``iso_limits`` (toward +x, toward -x) m/s^2 what
    it may feel (None: the contact limits of ``model``)."""
    records, iso, design, band = _check(model, records, iso, design, uplift_band)
    if mu_bounds is None:
        mu_bounds = friction_bounds_of(design)
    if mu_bounds is not None:
        lo, hi = (float(x) for x in mu_bounds)
        if not (math.isfinite(lo) and math.isfinite(hi) and 0 <= lo <= hi):
            raise InputError(f"limit states: mu_bounds must be 0 <= mu_low <= mu_high, got {mu_bounds!r}")
        mu_bounds = (lo, hi)
    isos = [iso] if iso is None or mu_bounds is None else [replace(iso, mu=mu_bounds[0]), replace(iso, mu=mu_bounds[1])]
    items = [(model, i, rec, float(rtol), k == 0, support if k == 0 else None, iso_model)
             for k, i in enumerate(isos) for rec in records]
    if executor is None:
        runs = [run_record(it) for it in items]
    else:
        runs = executor.map(run_record, items, desc=f"limit states: {len(items)} runs")
    n_rec = len(records)
    fixed = tuple(f for f, _ in runs[:n_rec])
    isolated = None if iso is None else tuple(i for _, i in runs[:n_rec])
    if iso is not None and len(isos) == 2:
        isolated = tuple(_worse(a, b) for a, b in zip(isolated, (i for _, i in runs[n_rec:])))
    n = len(records)
    from ..hazard.matching import N_MIN

    statistic = "mean" if n >= N_MIN else "max"
    warnings = []
    if n < N_MIN:
        warnings.append(f"{n} record{'s' if n != 1 else ''}: fewer than {N_MIN}, so the demand is the most "
                        f"unfavourable record's (the max), not the mean ({RULE})")
    if n < 3:
        warnings.append(f"{n} record{'s' if n != 1 else ''}: the codes ask for at least 3 time histories")
    lim = contact_limits(model, band)
    na = sum(not r.applicable for r in fixed)
    if na:
        warnings.append(f"{na} of {n} records exceed the friction of a body that slides before it rocks: their "
                        "rocking numbers are those of a base that cannot slide")
    rows = _fixed_rows(fixed, lim, band, statistic)
    if support is not None:
        warnings += list(support.notes)
        rows += _support_rows(fixed, support, statistic)
        rows.sort(key=lambda r: LIMIT_STATES.index(r.name))
        n_st = sum(r.from_stack for r in fixed)
        if n_st:
            warnings.append(f"the pedestal lifts in {n_st} of {n} records: there the statue's rocking numbers are the "
                            "two-block model's (Housner's restitution on each contact)")
    if iso is not None:
        if design is not None and design.get("passed") is False:
            warnings.append("the isolator design does not pass its own required checks")
        rows += _isolated_rows(isolated, lim if iso_limits is None else tuple(iso_limits), iso, design, statistic,
                               mu_offset=None if mu_bounds is None else mu_bounds[1])
        if mu_bounds is not None:
            rows = [r if r.base != "isolated" else replace(r, details={**r.details, "mu_bounds": list(mu_bounds)})
                    for r in rows]
    return LimitStates(tuple(rows), fixed, isolated, n, statistic, lim, band, tuple(warnings))


def _stat(values, statistic: str) -> float:
    v = np.asarray(values, dtype=float)
    return float(v.mean() if statistic == "mean" else v.max())


def _over(n_exc: int, n: int) -> str:
    return f"{n_exc} of {n} records"


def _fixed_rows(fixed, lim, band, statistic) -> list[LimitState]:
    n = len(fixed)
    up, dn = lim
    pos = [r.pga_pos for r in fixed]
    neg = [r.pga_neg for r in fixed]
    d_L, d_R = _stat(pos, statistic), _stat(neg, statistic)
    r_L, r_R = d_L / up, d_R / dn
    left = r_L >= r_R
    per_rec_ratio = [max(p / up, q / dn) for p, q in zip(pos, neg)]
    n_fc = sum(x >= 1.0 for x in per_rec_ratio)
    cap_text = ("alpha_side min(a_side, the low end of the uncertain base's uplift band "
                f"{band[0]:.4g}-{band[1]:.4g} m/s^2)" if band is not None else "alpha_side a_side")
    full = LimitState(
        "full_contact", "fixed", d_L if left else d_R, up if left else dn, max(r_L, r_R), "m/s^2",
        f"peak ground acceleration toward each side, the {statistic} over the {n} records (m/s^2), against the "
        f"ground acceleration that lifts the statue on that side ({cap_text}: toward +x on the left pivot, toward "
        "-x on the right); the row shows the side with the larger ratio demand / capacity; exceeded when "
        "ratio >= 1; n_exceeding counts the records whose peak reaches the uplift acceleration on either side",
        max(r_L, r_R) >= 1.0, n_fc, tuple(pos if left else neg),
        {"side": "left pivot (ground toward +x)" if left else "right pivot (ground toward -x)",
         "demand_left": d_L, "capacity_left": up, "ratio_left": r_L,
         "demand_right": d_R, "capacity_right": dn, "ratio_right": r_R,
         "per_record_ratio": per_rec_ratio, "n_uplift_time_history": sum(r.uplift for r in fixed),
         "uplift_band": None if band is None else list(band)})
    return [full, *_motion_rows("fixed", [r.theta_max_over_delta for r in fixed], [r.overturned for r in fixed],
                                [False] * n, [r.n_impacts for r in fixed], [r.uplift for r in fixed], statistic)]


def _sliding_row(name, per_pos, per_neg, cap, source, support_words, friction, statistic,
                 edge: bool = False) -> LimitState:
    """A sliding row: the peak sliding toward each side, the statistic over the records per side, against
    the distance that side allows; the row is the side with the larger ratio. ``edge``: the capacity is the
    support's edge: a record that slides past it drops the body off its support (a collapse, as an
    overturning record: it exceeds the row by itself, and counts as the edge distance in the statistic,
    the motion beyond being undefined)."""
    n = len(per_pos)
    n_off = 0
    if edge:
        n_off = sum(p >= cap[0] > 0 or q >= cap[1] > 0 for p, q in zip(per_pos, per_neg))
        per_pos = [min(p, cap[0]) for p in per_pos]
        per_neg = [min(q, cap[1]) for q in per_neg]

    def over(d: float, c: float) -> float:
        """demand / capacity of one side; no capacity: infinite once it slides at all."""
        return d / c if c > 0 else (math.inf if d > 0 else 0.0)

    d_pos, d_neg = _stat(per_pos, statistic), _stat(per_neg, statistic)
    r_pos, r_neg = over(d_pos, cap[0]), over(d_neg, cap[1])
    pos = r_pos >= r_neg
    per_ratio = [max(over(p, cap[0]), over(q, cap[1])) for p, q in zip(per_pos, per_neg)]
    ratio = max(r_pos, r_neg)
    off_text = ("; a record that slides past the edge drops the statue off its support and exceeds the row by "
                "itself (it counts as the edge distance in the statistic)" if edge else "")
    reason = ""
    if not math.isfinite(ratio):
        reason = "no sliding capacity on the side it slides to: its base reaches the support's edge"
    who = "the statue" if name == states.SLIDING else "the pedestal, carrying the statue,"
    return LimitState(
        name, "fixed", d_pos if pos else d_neg, cap[0] if pos else cap[1], ratio, "m",
        f"peak sliding displacement of {who} on {support_words} toward each side (exact rigid-plastic sliding, "
        f"Coulomb friction mu_s {friction.mu_s:g}, mu_k {friction.mu_k:g}), the {statistic} over the {n} records "
        f"(m), against {source} on that side; the row shows the side with the larger ratio; exceeded when "
        f"ratio >= 1{off_text}",
        ratio >= 1.0 or n_off >= 1, sum(x >= 1.0 for x in per_ratio), tuple(per_pos if pos else per_neg),
        {"side": "toward +x" if pos else "toward -x", "demand_pos": d_pos, "capacity_pos": cap[0],
         "demand_neg": d_neg, "capacity_neg": cap[1], "mu_s": friction.mu_s, "mu_k": friction.mu_k,
         "capacity_source": source, "n_sliding": sum(max(p, q) > 0 for p, q in zip(per_pos, per_neg)),
         "n_off_the_edge": n_off if edge else None,
         "per_record_ratio": per_ratio}, reason)


def _support_rows(fixed, support, statistic) -> list[LimitState]:
    """The sliding row, and with a pedestal the pedestal's sliding and overturning rows."""
    rows = [_sliding_row(states.SLIDING, [r.slide_pos for r in fixed], [r.slide_neg for r in fixed],
                         support.capacity, support.capacity_source, support.support_words, support.friction,
                         statistic, edge=support.edge)]
    if support.stack is None:
        return rows
    rows.append(_sliding_row(states.PEDESTAL_SLIDING, [r.ped_slide_pos for r in fixed],
                             [r.ped_slide_neg for r in fixed], support.pedestal_capacity,
                             support.pedestal_capacity_source, "the floor", support.pedestal_friction, statistic))
    n = len(fixed)
    n_ot = sum(r.ped_overturned for r in fixed)
    rows.append(LimitState(
        states.PEDESTAL_OVERTURNING, "fixed", n_ot / n, 1.0 / n, float(n_ot), "-",
        f"fraction of the {n} records in which the pedestal overturns with the statue (the two-block model); as "
        "for the statue's overturning any record exceeds it: capacity 1/n, ratio = the number of records, exceeded "
        "when ratio >= 1",
        n_ot >= 1, n_ot, tuple(1.0 if r.ped_overturned else 0.0 for r in fixed),
        {"n_uplift": sum(r.ped_uplift for r in fixed),
         "theta_max_over_delta": _stat([r.ped_theta_max_over_delta for r in fixed], statistic),
         "theta_max_over_delta_per_record": [r.ped_theta_max_over_delta for r in fixed]}))
    return rows


def _motion_rows(base, tod, overturned, at_capacity, impacts, uplift, statistic) -> list[LimitState]:
    """The rocking and overturning rows of one base."""
    n = len(tod)
    lost = [o or c for o, c in zip(overturned, at_capacity)]
    per = tuple(1.0 if x else float(min(t, 1.0)) for t, x in zip(tod, lost))
    demand = _stat(per, statistic)
    n_rock = sum(v >= 1.0 for v in per)
    iso_text = " or reached the isolator's capacity" if base == "isolated" else ""
    rocking = LimitState(
        "rocking", base, demand, 1.0, demand, "-",
        f"peak |theta| / delta over both pivots, the {statistic} over the {n} records (dimensionless; a record "
        f"that overturned{iso_text} counts as 1), against 1 (|theta| = delta tips the statue over statically); "
        "ratio = demand; exceeded when ratio >= 1",
        demand >= 1.0, n_rock, per,
        {"impacts": _stat(impacts, statistic), "impacts_per_record": list(impacts), "n_uplift": sum(uplift),
         "n_overturned": sum(overturned), "n_capacity_exceeded": sum(at_capacity)})
    n_ot = sum(lost)
    over = LimitState(
        "overturning", base, n_ot / n, 1.0 / n, float(n_ot), "-",
        f"fraction of the {n} records in which the statue overturns{iso_text} (dimensionless); the mean of an "
        "effect with a collapse in it is not defined, so any overturning record exceeds this limit state (the "
        "conservative reading): capacity 1/n (one record), ratio = the number of records that overturn, "
        "exceeded when ratio >= 1",
        n_ot >= 1, n_ot, tuple(1.0 if x else 0.0 for x in lost),
        {"n_overturned": sum(overturned), "n_capacity_exceeded": sum(at_capacity)})
    return [rocking, over]


def _isolated_rows(recs, lim, iso, design, statistic, mu_offset=None) -> list[LimitState]:
    from ..isolator.checks import DISPLACEMENT_MARGIN, travel_need

    n = len(recs)
    cap_acc = min(lim)
    felt = tuple(r.acc_felt for r in recs)
    at_cap = [r.capacity_exceeded for r in recs]
    d_acc = _stat(felt, statistic)
    n_fc = sum(a >= cap_acc or c for a, c in zip(felt, at_cap))
    full = LimitState(
        "full_contact", "isolated", d_acc, cap_acc, d_acc / cap_acc, "m/s^2",
        f"peak absolute acceleration of the top plate (what the statue feels), the {statistic} over the {n} "
        "records (m/s^2), against the weaker side's uplift acceleration min(alpha_L a_L, alpha_R a_R) (the "
        "peak's sign is not kept: conservative); exceeded when ratio >= 1 or when any record reached the "
        "isolator's capacity (the run stops at the end stop, whose impact would jolt the statue)",
        d_acc / cap_acc >= 1.0 or any(at_cap), n_fc, felt,
        {"n_uplift_on_plate": sum(r.uplift for r in recs), "n_capacity_exceeded": sum(at_cap),
         "ground_pga": _stat([r.pga for r in recs], statistic),
         "felt_over_ground": [r.acc_felt / r.pga if r.pga > 0 else None for r in recs]})
    rows = [full, *_motion_rows("isolated", [r.theta_max_over_delta for r in recs], [r.overturned for r in recs],
                                at_cap, [r.n_impacts for r in recs], [r.uplift for r in recs], statistic)]
    # capacity: the design's travel check with the records' peak travel for SDe
    margin = float(design.get("margin", DISPLACEMENT_MARGIN)) if design else DISPLACEMENT_MARGIN
    # the friction offset at the upper friction bound when the runs took the bounds (the offset
    # friction can hold grows with mu: conservative), else the design's (or isolator's) mu
    mu = mu_offset if mu_offset is not None else float(design.get("mu", iso.mu)) if design else iso.mu
    R_hat = float(design.get("R_hat", iso.R_hat)) if design else iso.R_hat
    cap = design.get("capacity") if design else None
    cap = float(cap) if cap is not None else iso.capacity
    travel = tuple(r.u_max for r in recs)
    t_stat = _stat(travel, statistic)
    demand = travel_need(t_stat, mu, R_hat, margin)
    det = {"travel": t_stat, "margin": margin, "friction_offset": mu * R_hat, "n_capacity_exceeded": sum(at_cap),
           "capacity_source": "design" if design and design.get("capacity") is not None else "isolator"}
    defn = (f"travel the design's check asks for, {margin:g} x the {statistic} over the {n} records of the top "
            f"plate's peak travel relative to the ground + mu R_hat (where friction may leave the plate resting off "
            f"centre; mu {mu:.4g}, the upper friction bound when the runs took the bounds) (m), against the isolator's travel capacity (the lesser of the groove rim and top-plate "
            "tipping); exceeded when ratio > 1 or when any record passed the capacity outright")
    if math.isfinite(cap):
        n_cap = sum(c or u > cap for c, u in zip(at_cap, travel))
        rows.append(LimitState("capacity", "isolated", demand, cap, demand / cap, "m", defn,
                               demand / cap > 1.0 or n_cap > 0, n_cap, travel, det))
    else:
        rows.append(LimitState("capacity", "isolated", demand, None, None, "m", defn, False, 0, travel, det,
                               "the isolator's travel capacity is not given (inf: not checked)"))
    # bearing: the design's ball-load check (isolator/checks.py), against the surface's long-term capacity per
    # ball (design.json "ball_capacity": isolator/bearing.py)
    bc = (design.get("ball_capacity") if design else None) or {}
    P_allow = bc.get("per_ball")
    source = bc.get("source") or "no design: the surface is not known"
    n_balls = design.get("n_grooves") if design else None
    defn = (f"static load per ball W / n (N; the design's check), against what a ball carries on the grooves' surface "
            f"in the long term ({bc.get('criterion', '-')}; {source}); exceeded when ratio > 1 (a static check: every "
            "record or none)")
    det = {"W": iso.W, "n_balls": n_balls, "ball_radius": iso.r, "capacity_source": source,
           "surface": bc.get("surface"), "criterion": bc.get("criterion"), "options": list(BEARING_OPTIONS)}
    if n_balls and P_allow:
        n_balls, P_allow = int(n_balls), float(P_allow)
        P = iso.W / n_balls
        det.update(n_balls_needed=math.ceil(iso.W / P_allow))
        rows.append(LimitState("bearing", "isolated", P, P_allow, P / P_allow, "N", defn, P / P_allow > 1.0,
                               n if P > P_allow else 0, (), det))
    else:
        rows.append(LimitState("bearing", "isolated", None, None, None, "N", defn, False, 0, (), det,
                               "no isolator design: the number of balls and their surface are not known"))
    return rows
