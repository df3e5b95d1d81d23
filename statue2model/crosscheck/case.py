"""One compared quantity (:class:`Case`) and a set of them with the runs behind it (:class:`Comparison`).

A :class:`Case` holds name, quantity, value_2d, value_3d, rel_error, target, met and status.
``status`` is what counts:

* ``met`` / ``missed``: a check - the 2D model *as the user runs it* (restitution from eq. 15, or
  the e_L / e_R the configuration gives from a prototype test) against the 3D scene;
* ``diagnostic``: shown, never counted - the 2D model given the restitution the 3D scene has
  (:func:`~statue2model.crosscheck.restitution.calibrate_restitution`), i.e. "2D given 3D's e":
  it tells how much of a miss is e;
* ``not applicable``: the validity screen (:mod:`statue2model.crosscheck.screen`) found that the 3D
  body slides or twists, or that the 2D trajectory needs more friction than the scene has or a
  negative normal force: the 2D rocking model does not describe that run ("slides / twists: 2D not
  applicable"), the numbers are in the case's ``screen``.

A :class:`Comparison` is what every case family returns (its cases, the time histories for the
overlay plots, the 3D run details; the isolator's free vibration and the record ensemble return a
record that holds one, with their calibration or statistics beside it) and what
:func:`statue2model.crosscheck.compare.compare` returns: :meth:`Comparison.join` puts the families'
parts together.

Example
-------
>>> c = Case.relative("quarter period", "s", 0.4373, 0.4371, 0.01)
>>> c.met, c.status, c.as_diagnostic().status
(True, 'met', 'diagnostic')
>>> part = Comparison((c,), runs={"free rocking": {}})
>>> both = Comparison.join([part, Comparison((c.as_diagnostic(),))])
>>> len(both.cases), list(both.runs)
(2, ['free rocking'])
"""
from __future__ import annotations

import math
from dataclasses import asdict, dataclass, field, replace

STATUSES = ("met", "missed", "not applicable", "diagnostic")
NOT_APPLICABLE = "slides / twists: 2D not applicable"


@dataclass(frozen=True)
class Case:
    """One compared quantity. ``kind``: 'relative' (|3D - 2D| / |2D| <= target),
    'absolute' (|3D - 2D| <= target, in the quantity's unit) or 'equal' (same value).
    ``met``: the values are within the target; ``status`` (one of STATUSES): 'met' / 'missed' for a
    check, 'diagnostic' or 'not applicable' for a case that is shown but not counted
    (``screen``: the validity screen's numbers)."""

    name: str
    quantity: str
    value_2d: float
    value_3d: float
    rel_error: float
    target: float
    met: bool
    kind: str = "relative"
    unit: str = ""
    note: str = ""
    why: str = ""
    spread: dict | None = None
    status: str = ""
    screen: dict | None = None

    def __post_init__(self):
        if not self.status:
            object.__setattr__(self, "status", "met" if self.met else "missed")
        if self.status not in STATUSES:
            raise ValueError(f"case status must be one of {STATUSES}, got {self.status!r}")

    @property
    def counted(self) -> bool:
        """A check (met or missed), not a diagnostic or a not-applicable case."""
        return self.status in ("met", "missed")

    def as_diagnostic(self, why: str = "") -> Case:
        """The same comparison, labelled diagnostic (shown, never counted)."""
        return replace(self, status="diagnostic", why=why or self.why)

    def screened(self, scr: dict | None) -> Case:
        """The case with the validity screen ``scr`` (:func:`~statue2model.crosscheck.screen.screen`)
        attached; 'not applicable' (with the numbers in ``why``) if the screen says the 2D model does
        not apply."""
        if scr is None:
            return self
        if scr["applicable"] or self.status == "diagnostic":
            return replace(self, screen=scr)
        return replace(self, status="not applicable", screen=scr,
                       why=f"{NOT_APPLICABLE}: " + "; ".join(scr["reasons"]))

    @classmethod
    def relative(cls, name, unit, v2, v3, target, note="", quantity=None) -> Case:
        err = abs(v3 - v2) / abs(v2) if v2 not in (0, None) and v3 is not None and math.isfinite(v3) else math.inf
        return cls(name, quantity or name, _f(v2), _f(v3), err, target, bool(err <= target), "relative", unit, note)

    @classmethod
    def absolute(cls, name, unit, v2, v3, target, note="", quantity=None) -> Case:
        ok = v2 is not None and v3 is not None
        diff = abs(v3 - v2) if ok else math.inf
        err = diff / abs(v2) if ok and v2 != 0 else (0.0 if diff == 0 else math.inf)
        return cls(name, quantity or name, _f(v2), _f(v3), err, target, bool(diff <= target), "absolute", unit,
                   note)

    @classmethod
    def equal(cls, name, v2, v3, note="", quantity=None) -> Case:
        same = bool(v2) == bool(v3)
        return cls(name, quantity or name, float(bool(v2)), float(bool(v3)), 0.0 if same else 1.0, 0.0, same,
                   "equal", "", note)

    def to_dict(self) -> dict:
        d = asdict(self)
        if not math.isfinite(d["rel_error"]):
            # one side has no value (e.g. a squat body lifts in 3D but not in 2D): JSON has no inf
            d["rel_error"] = None
        return d


def _f(x):
    return None if x is None else float(x)


@dataclass(frozen=True, eq=False)
class Comparison:
    """Cases plus the time histories behind them: histories[name] = {'t2', 'y2', 't3', 'y3', 'label'}
    (arrays, s and the plotted quantity), and the 3D run details ``runs`` (for crosscheck.json).
    A case family returns one (or a record holding one)."""

    cases: tuple
    histories: dict = field(default_factory=dict)
    runs: dict = field(default_factory=dict)

    @classmethod
    def join(cls, parts) -> Comparison:
        """The parts one after the other: their cases in order, their histories and runs merged in
        order (a later part's key replaces an earlier one's value, in the earlier one's place)."""
        cases, histories, runs = [], {}, {}
        for part in parts:
            cases += part.cases
            histories.update(part.histories)
            runs.update(part.runs)
        return cls(cases=tuple(cases), histories=histories, runs=runs)
