"""One vocabulary for the limit states: the registry every room reads (issue [21]).

A limit state has one identifier everywhere: in limit_states.json's rows (``name``), in
fragility.json's ``limit_states`` and as the prefix of every fragility curve key, in the 3D
classification, in the verdict, the collection and the report. Its row here gives the rest: the
title the tables print, the bases it is checked on, the fragility curve of each base, the
classification's outcome, and the words a sentence uses. Adding a limit state is one row here
(and its demand in assessment/limit_states.py); tests/test_states.py fails when a module lists
identifiers of its own.

==============  ===========================  ===============  ==========================================
identifier      title                        bases            fragility curve (fragility.json ``curves``)
==============  ===========================  ===============  ==========================================
full_contact    full contact (no uplift)     fixed, isolated  full_contact_fixed, full_contact_isolated
sliding         sliding on its support       fixed            sliding_fixed
rocking         rocking without overturning  fixed, isolated  -
overturning     overturning                  fixed, isolated  overturning_fixed, overturning_isolated
pedestal_...    the pedestal sliding, and    fixed            pedestal_sliding_fixed,
                the pedestal (with the                        pedestal_overturning_fixed
                statue) overturning
capacity        isolator travel capacity     isolated         capacity_isolated
bearing         ball load on the grooves     isolated         -
==============  ===========================  ===============  ==========================================

``sliding`` is the statue's on its support (the floor, or the pedestal's top with a pedestal);
``pedestal_sliding`` and ``pedestal_overturning`` (the pedestal, carrying the statue) are rows only when
the project has a [pedestal]. The fixed base is then the statue on its pedestal on the floor.

On the isolator, overturning counts a run that reached the device's capacity as overturned (the
balls leave their grooves: as bad as overturning); the curve of overturning alone there is
``overturning_alone_isolated``, a component shown beside it.

>>> title("capacity"), curve("overturning", "isolated"), STATE_OF_CURVE["full_contact_fixed"]
('isolator travel capacity', 'overturning_isolated', ('full_contact', 'fixed'))
>>> [s.id for s in on_base("fixed")]
['full_contact', 'sliding', 'rocking', 'overturning', 'pedestal_sliding', 'pedestal_overturning']
"""
from __future__ import annotations

from dataclasses import dataclass, field

BASES = ("fixed", "isolated")
"""The two bases: the statue on its own base (fixed) and on the isolator."""


@dataclass(frozen=True)
class LimitState:
    """One limit state (module docstring): ``id``, ``title`` (limit_states.json, the tables),
    ``bases``, ``curves`` (base -> fragility curve key), ``fragility_title`` (the fragility section's
    and the verdict's words for the curve), ``classified`` (the 3D classification checks it),
    ``exceeded_words`` (what the object does when it is exceeded, for sentences), ``noun`` (its
    exceedance in a word or two: "uplift", "capacity exceeded"), ``rule`` (how the design level judges
    it over the design records, one of :data:`RULES`)."""

    id: str
    title: str
    bases: tuple[str, ...]
    curves: dict = field(default_factory=dict)
    fragility_title: str = ""
    classified: bool = False
    exceeded_words: str = ""
    noun: str = ""
    rule: str = "mean"


REGISTRY: tuple[LimitState, ...] = (
    LimitState("full_contact", "full contact (no uplift)", BASES,
               {"fixed": "full_contact_fixed", "isolated": "full_contact_isolated"},
               "full contact lost (uplift)", True, "lifts off", "uplift"),
    LimitState("sliding", "sliding on its support", ("fixed",), {"fixed": "sliding_fixed"},
               "sliding beyond its allowance", exceeded_words="slides beyond its allowance", noun="sliding"),
    LimitState("rocking", "rocking without overturning", BASES, exceeded_words="rocks to its limit",
               noun="rocking to its limit"),
    LimitState("overturning", "overturning", BASES,
               {"fixed": "overturning_fixed", "isolated": "overturning_isolated"},
               "overturning", True, "overturns", "overturning", rule="any"),
    LimitState("pedestal_sliding", "the pedestal sliding on the floor", ("fixed",),
               {"fixed": "pedestal_sliding_fixed"}, "the pedestal sliding beyond its allowance",
               exceeded_words="slides on its pedestal's base beyond the allowance", noun="pedestal sliding"),
    LimitState("pedestal_overturning", "the pedestal overturning (with the statue)", ("fixed",),
               {"fixed": "pedestal_overturning_fixed"}, "the pedestal overturning",
               exceeded_words="overturns with its pedestal", noun="pedestal overturning", rule="any"),
    LimitState("capacity", "isolator travel capacity", ("isolated",), {"isolated": "capacity_isolated"},
               "isolator capacity exceeded", True, "reaches the capacity", "capacity exceeded"),
    LimitState("bearing", "ball load on the grooves", ("isolated",), exceeded_words="overloads the grooves",
               noun="ball load exceeded", rule="static"),
)
"""Every limit state, in the order the damage grows (limit_states.json's ``first_exceeded`` follows it)."""

RULES = {"mean": "the {statistic} of the {n} records' effects (NTC 2018 7.3.5, EN 1998-1 4.3.3.4.3: the mean with at "
                 "least 7 records, else the most unfavourable)",
         "any": "any single record (a collapse has no mean: one record that collapses exceeds it)",
         "static": "a static check (the same for every record)"}
"""How the design level judges a limit state over the design records (LimitState.rule): one documented rule per
state, printed beside its row with the count of single records exceeding it (issue [25])."""

BY_ID = {s.id: s for s in REGISTRY}
IDS = tuple(BY_ID)
FULL_CONTACT, SLIDING, ROCKING, OVERTURNING, PEDESTAL_SLIDING, PEDESTAL_OVERTURNING, CAPACITY, BEARING = IDS
ON_PEDESTAL = (PEDESTAL_SLIDING, PEDESTAL_OVERTURNING)
"""The limit states that exist only with a pedestal."""

OVERTURNING_ALONE_ISOLATED = "overturning_alone_isolated"
"""The fragility curve of overturning alone on the isolator (a component of overturning_isolated)."""
CURVE_LABELS = {
    "full_contact_fixed": "full contact lost (uplift), fixed base",
    "overturning_fixed": "overturning, fixed base",
    "full_contact_isolated": "full contact lost on the isolator (felt acceleration or capacity)",
    OVERTURNING_ALONE_ISOLATED: "overturning alone on the isolator",
    "capacity_isolated": "isolator capacity exceeded",
    "overturning_isolated": "overturning on the isolator (overturned or capacity exceeded)",
    "sliding_fixed": "sliding beyond its allowance (or off the pedestal's top)",
    "pedestal_sliding_fixed": "the pedestal sliding beyond its allowance",
    "pedestal_overturning_fixed": "the pedestal overturning with the statue",
}
"""Every fragility curve key (the limit states' and the component) and its label."""
CURVES_FIXED = ("full_contact_fixed", "overturning_fixed", "sliding_fixed", "pedestal_sliding_fixed",
                "pedestal_overturning_fixed")
CURVES_SUPPORT = CURVES_FIXED[2:]
"""The fixed-base curves of the statue's support (its sliding; the pedestal's sliding and overturning): a study
has them when it is given the support (assessment/support.py; the pedestal's only with a pedestal)."""
CURVES_ISOLATED = ("full_contact_isolated", OVERTURNING_ALONE_ISOLATED, "capacity_isolated", "overturning_isolated")
STATE_OF_CURVE = {c: (s.id, b) for s in REGISTRY for b, c in s.curves.items()}
STATE_OF_CURVE[OVERTURNING_ALONE_ISOLATED] = (OVERTURNING, "isolated")
CLASSIFIED = tuple(s.id for s in REGISTRY if s.classified)
"""The limit states the 3D classification checks yes / no, in order."""
WITH_CURVES = tuple(s.id for s in REGISTRY if s.curves)
"""The limit states with fragility curves, in order."""
ADAPT_ORDER = ("overturning_fixed", "overturning_isolated", "full_contact_isolated", "capacity_isolated",
               OVERTURNING_ALONE_ISOLATED)
"""The order in which a base's fragility curves ask for adaptive levels (assessment/fragility.py)."""
RATIOS = (("overturning_alone", OVERTURNING_ALONE_ISOLATED, "overturning_fixed"),
          ("overturning", "overturning_isolated", "overturning_fixed"),
          ("full_contact", "full_contact_isolated", "full_contact_fixed"))
"""(key, isolated curve, fixed curve) of fragility.json's ratios of medians, named by the limit state."""


def get(state: str) -> LimitState:
    """The registry row of ``state``; KeyError naming the known ones for any other spelling."""
    try:
        return BY_ID[state]
    except KeyError:
        raise KeyError(f"unknown limit state {state!r}: one of {', '.join(IDS)}") from None


def title(state: str) -> str:
    """The title of ``state`` (limit_states.json, the tables)."""
    return get(state).title


def rule_text(state: str, statistic: str = "mean", n: int = 7) -> str:
    """The design level's rule of ``state`` in words, for ``n`` records judged by ``statistic``.

    >>> rule_text("overturning")
    'any single record (a collapse has no mean: one record that collapses exceeds it)'
    """
    return RULES[get(state).rule].format(statistic=statistic, n=n)


def curve(state: str, base: str) -> str | None:
    """The fragility curve key of ``state`` on ``base`` (None: none there)."""
    return get(state).curves.get(base)


def on_base(base: str) -> tuple[LimitState, ...]:
    """The limit states checked on ``base``, in order."""
    return tuple(s for s in REGISTRY if base in s.bases)
