"""Typed records of what one room hands the next: the isolator design as the verdict reads it.

The isolator stage writes design.json (isolator/design.py ``Design.to_dict``, schema
``statue2model.isolator_design/4``); the verdict and the collection read it back through
:class:`DesignRecord`, not as a dict: a field is named once, typed, and a file that does not hold
what the record needs is an InputError naming the field (a file is input: it may hold anything).
The limit states' record is assessment/limit_states.py ``LimitStates.from_dict``.

>>> rec = DesignRecord.from_dict({"passed": True, "capacity": 0.58, "travel_need": 0.48, "T": 4.0,
...                               "n_grooves": 4, "cost": 9011.0, "th_margins": {"travel": 1.2}})
>>> rec.passed, rec.travel_margin, rec.th_margins["travel"]
(True, 1.2083333333333333, 1.2)
>>> DesignRecord.from_dict(rec.to_dict()) == rec
True
"""
from __future__ import annotations

import math
from dataclasses import asdict, dataclass, field

from ..errors import InputError


def field_number(d: dict, key: str, where: str = "design.json") -> float | None:
    """d[key] as a finite float, None when missing, null or not finite; a non-number is an InputError
    naming ``where`` and the key (a record read back from a file is input). Every typed record of the
    assessment reads its numbers with it (this module, limit_states.py)."""
    x = d.get(key)
    if x is None:
        return None
    if isinstance(x, bool) or not isinstance(x, (int, float)):
        raise InputError(f"{where}: {key} must be a number, got {x!r:.40}")
    x = float(x)
    return x if math.isfinite(x) else None


def _text(d: dict, key: str) -> str | None:
    x = d.get(key)
    return None if x is None else str(x)


@dataclass(frozen=True)
class CheckRecord:
    """One check of the design: ``name``, ``value`` and ``limit`` (in ``unit``; None when not
    finite), ``required``, ``passed``."""

    name: str
    value: float | None
    limit: float | None
    unit: str
    required: bool
    passed: bool

    @classmethod
    def from_dict(cls, d: dict) -> CheckRecord:
        if not isinstance(d, dict):
            raise InputError(f"design.json: a check must be a table, got {type(d).__name__}")
        w = f"design.json check {d.get('name')!r:.40}"
        return cls(str(d.get("name") or ""), field_number(d, "value", w), field_number(d, "limit", w), str(d.get("unit") or ""),
                   bool(d.get("required", True)), bool(d.get("passed")))


@dataclass(frozen=True)
class DesignRecord:
    """The isolator design as the verdict and the collection read it (SI units; None: not in the
    file or not finite).

    passed          every required check passes          capacity / travel_need   m
    a_design, mu    plate acceleration (m/s^2), friction T, R, r                  s, m, m
    n_grooves       balls                                layout, surface, ball_material  words
    side, cost      plate side (m), price (EUR)          th_margins   time-history margins by name
    felt            the largest felt acceleration over the verification's record sets (m/s^2)
    n_sets          record sets verified                 slc_rule     the collapse level's rule
    reserve_pga     the reserve check's PGA (m/s^2)      tail         the reserve's lower tail (as written)
    wwp_text        what would pass, one sentence        wwp_reason   its kind (design.what_would_pass)
    failure         the failing checks in words          checks       the checks (:class:`CheckRecord`)
    """

    passed: bool = False
    capacity: float | None = None
    travel_need: float | None = None
    a_design: float | None = None
    mu: float | None = None
    T: float | None = None
    R: float | None = None
    r: float | None = None
    n_grooves: int | None = None
    layout: str | None = None
    surface: str | None = None
    ball_material: str | None = None
    side: float | None = None
    cost: float | None = None
    th_margins: dict = field(default_factory=dict)
    felt: float | None = None
    n_sets: int = 0
    slc_rule: str | None = None
    reserve_pga: float | None = None
    tail: dict | None = None
    wwp_text: str | None = None
    wwp_reason: str | None = None
    failure: str | None = None
    checks: tuple = ()

    @property
    def travel_margin(self) -> float | None:
        """capacity / travel need (> 1: the device keeps its travel), None when either is unknown."""
        if self.capacity is None or not self.travel_need:
            return None
        return self.capacity / self.travel_need

    @property
    def felt_or_spectral(self) -> float:
        """What the statue feels on the plate (m/s^2): the time histories' largest, else the spectral
        a_design + mu g."""
        if self.felt is not None:
            return self.felt
        from ..quantities import G

        return (self.a_design or 0.0) + (self.mu or 0.0) * G

    @classmethod
    def from_dict(cls, d: dict) -> DesignRecord:
        """The record of design.json's dict (or of :meth:`to_dict`); older designs' d_max and d_design
        stand for capacity and travel_need."""
        if not isinstance(d, dict):
            raise InputError(f"design.json: expected a table, got {type(d).__name__}")
        v = d.get("verification") or {}
        if not isinstance(v, dict):
            raise InputError("design.json: verification must be a table")
        sets = [s for s in v.get("sets") or () if isinstance(s, dict)]
        felts = [f for f in (field_number(s, "felt", "design.json verification set") for s in sets) if f is not None]
        wwp = d.get("what_would_pass") if isinstance(d.get("what_would_pass"), dict) else {}
        margins = d.get("th_margins") if isinstance(d.get("th_margins"), dict) else {}
        n = d.get("n_grooves")
        reserve = v.get("reserve") if isinstance(v.get("reserve"), dict) else {}
        slc = v.get("slc") if isinstance(v.get("slc"), dict) else {}
        felt = max(felts) if felts else field_number(d, "felt")
        return cls(
            passed=bool(d.get("passed")),
            capacity=field_number(d, "capacity") if d.get("capacity") is not None else field_number(d, "d_max"),
            travel_need=field_number(d, "travel_need") if d.get("travel_need") is not None else field_number(d, "d_design"),
            a_design=field_number(d, "a_design"), mu=field_number(d, "mu"), T=field_number(d, "T"), R=field_number(d, "R"), r=field_number(d, "r"),
            n_grooves=n if isinstance(n, int) and not isinstance(n, bool) else None,
            layout=_text(d, "layout"), surface=_text(d, "surface_name") or _text(d, "surface"),
            ball_material=_text(d, "ball_material"), side=field_number(d, "side"), cost=field_number(d, "cost"),
            th_margins={str(k): field_number(margins, k, "design.json th_margins") for k in margins},
            felt=felt, n_sets=len(sets) if sets else int(d.get("n_sets") or 0),
            slc_rule=_text(slc, "rule") or _text(d, "slc_rule"),
            reserve_pga=field_number(reserve, "pga") if reserve else field_number(d, "reserve_pga"),
            tail=(reserve.get("tail") if reserve else d.get("tail")) or None,
            wwp_text=_text(wwp, "text") or _text(d, "wwp_text"), wwp_reason=_text(wwp, "reason") or _text(d, "wwp_reason"),
            failure=_text(d, "failure"),
            checks=tuple(CheckRecord.from_dict(c) for c in d.get("checks") or ()))

    def to_dict(self) -> dict:
        """The record's own fields (JSON-ready): ``DesignRecord.from_dict(r.to_dict()) == r``."""
        out = asdict(self)
        out["checks"] = [asdict(c) for c in self.checks]
        return out

    def failing_checks(self, n: int = 3) -> str:
        """The first ``n`` failing required checks with value and limit, in words."""
        bad = [c for c in self.checks if c.required and not c.passed]
        if not bad:
            return "see design.json"

        def q(x):
            return "-" if x is None else format(x, ".4g")
        return "; ".join(f"{c.name}: {q(c.value)} vs {q(c.limit)}" + (f" {c.unit}" if c.unit else "") for c in bad[:n])
