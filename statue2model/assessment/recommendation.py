"""The recommendation code: what the verdict tells a conservator to do, as one identifier.

The verdict (assessment/verdict.py) decides one :class:`Code` by its rule (verdict.RULE) and writes it
to run.json beside a headline, a few bullets and the full reasoning. Everything that depends on the
decision reads the code, never the wording: the report's colour (:attr:`CodeInfo.status`), the
collection's counts and columns (:attr:`CodeInfo.needs_protection`, :attr:`CodeInfo.to_consider`),
the headline. Rewording a sentence changes nothing else.

=============================  ======  =====================================================================
code                           status  what it tells a conservator
=============================  ======  =====================================================================
NO_ISOLATOR                    ok      leave it as it stands: it stays in full contact under the design
                                       earthquake, in every design record
NO_ISOLATOR_BUT_RECORDS_LIFT   warn    the code's check holds (the mean of the records), but single design
                                       records lift it: consider isolating it
ISOLATE                        ok      build the designed device: on it the statue stays in full contact
                                       and the device keeps its travel, at the design level and beyond
DEVICE_DOES_NOT_PROTECT        fail    do not build the designed device: on it a limit state is exceeded
NO_DEVICE_IN_RANGE             fail    no rolling-ball isolator in the tool's range protects it: a
                                       restraint or a specialist's device is needed
RUN_ISOLATOR_STAGE             warn    it lifts; this run designed no isolator: run the isolator stage
RUN_ISOLATED_DYNAMICS          warn    the device was designed but not analysed over the design records
SLIDES                         warn    it stays in full contact but slides beyond its allowance (or would
                                       slide before it lifts, not yet measured): restrain it
PEDESTAL_OVERTURNS             fail    its pedestal overturns with it: anchor or widen the pedestal
NO_VERDICT                     warn    the scan's rocking parameters were not computed: no verdict
=============================  ======  =====================================================================

Example
-------
>>> info(Code.ISOLATE).status, info(Code.NO_ISOLATOR_BUT_RECORDS_LIFT).to_consider
('ok', True)
>>> Code("NO_DEVICE_IN_RANGE") is Code.NO_DEVICE_IN_RANGE
True
"""
from __future__ import annotations

import enum
import math
from dataclasses import dataclass

from ..hazard.matching import N_MIN
from ..quantities import G


class Code(str, enum.Enum):
    """The recommendation's identifier (its value is what run.json and collection.csv hold)."""

    NO_ISOLATOR = "NO_ISOLATOR"
    NO_ISOLATOR_BUT_RECORDS_LIFT = "NO_ISOLATOR_BUT_RECORDS_LIFT"
    ISOLATE = "ISOLATE"
    DEVICE_DOES_NOT_PROTECT = "DEVICE_DOES_NOT_PROTECT"
    NO_DEVICE_IN_RANGE = "NO_DEVICE_IN_RANGE"
    RUN_ISOLATOR_STAGE = "RUN_ISOLATOR_STAGE"
    RUN_ISOLATED_DYNAMICS = "RUN_ISOLATED_DYNAMICS"
    SLIDES = "SLIDES"
    PEDESTAL_OVERTURNS = "PEDESTAL_OVERTURNS"
    NO_VERDICT = "NO_VERDICT"

    def __str__(self) -> str:
        return self.value


DEVICE_ROLES = {
    "build": "the designed isolator is the protection: build it",
    "analyse": "the designed isolator is the protection once analysed over the design records",
    "design": "an isolator is the protection, none was designed yet",
    "optional": "no isolator needed by the code's check; the designed one is an option to consider",
    "rejected": "the designed isolator does not protect: do not build it",
    "none in range": "no isolator in the tool's range protects it",
    "not needed": "no isolator needed",
    "not applicable": "an isolator is not the remedy (it slides, or its pedestal overturns): restrain or anchor it",
}
"""What the designed isolator is to an object of each code (:attr:`CodeInfo.device`): the collection shows a
device as passing, and counts its plates and price, only for the roles of :data:`DEVICE_COUNTED`."""
DEVICE_COUNTED = ("build", "analyse")


@dataclass(frozen=True)
class CodeInfo:
    """What a code means: ``status`` (ok, warn, fail: the report's colour), ``needs_protection``
    (the collection counts it among the objects to protect), ``to_consider`` (a warning to consider
    protection while the code's check holds), ``action`` (the first words of the headline), ``device``
    (what the designed isolator is to the object: a key of :data:`DEVICE_ROLES`)."""

    status: str
    needs_protection: bool
    to_consider: bool
    action: str
    device: str

    @property
    def device_counts(self) -> bool:
        """The designed isolator is the object's protection: shown as passing, its plates and price counted."""
        return self.device in DEVICE_COUNTED


CODES: dict[Code, CodeInfo] = {
    Code.NO_ISOLATOR: CodeInfo("ok", False, False, "No isolator needed", "not needed"),
    Code.NO_ISOLATOR_BUT_RECORDS_LIFT: CodeInfo("warn", False, True, "Consider isolating it", "optional"),
    Code.ISOLATE: CodeInfo("ok", True, False, "Isolate it", "build"),
    Code.DEVICE_DOES_NOT_PROTECT: CodeInfo("fail", True, False, "Do not build the designed isolator", "rejected"),
    Code.NO_DEVICE_IN_RANGE: CodeInfo("fail", True, False, "No isolator of this kind protects it", "none in range"),
    Code.RUN_ISOLATOR_STAGE: CodeInfo("warn", True, False, "Design an isolator", "design"),
    Code.RUN_ISOLATED_DYNAMICS: CodeInfo("warn", True, False, "Analyse the designed isolator", "analyse"),
    Code.SLIDES: CodeInfo("warn", True, False, "Restrain it against sliding", "not applicable"),
    Code.PEDESTAL_OVERTURNS: CodeInfo("fail", True, False, "Anchor or widen its pedestal", "not applicable"),
    Code.NO_VERDICT: CodeInfo("warn", False, False, "No verdict", "not needed"),
}
STATUSES = ("ok", "warn", "fail")


def info(code) -> CodeInfo:
    """The :class:`CodeInfo` of ``code`` (a Code or its value); an unknown value is NO_VERDICT's."""
    try:
        return CODES[Code(code)]
    except ValueError:
        return CODES[Code.NO_VERDICT]


def status_of(code, doubt: bool = False) -> str:
    """The report's colour of ``code``; ``doubt`` (e.g. the 3D cross-check does not confirm the 2D
    answer) turns an 'ok' into 'warn'."""
    st = info(code).status
    return "warn" if doubt and st == "ok" else st


@dataclass(frozen=True)
class Facts:
    """The numbers a headline and its bullets are made of (SI; None when not known).

    pga            design PGA at the object (m/s^2)        hazard   the design target in words
    uplift         weakest uplift acceleration (m/s^2)      n        design records (None: quasi-static)
    k_lift         records lifting it on a fixed base        k_over   records overturning it on a fixed base
    device         one line on the device, or ""
    cost           the device's price (EUR)                 travel_margin  capacity / travel need - 1
    iso_governing  title of the exceeded state on the device (DEVICE_DOES_NOT_PROTECT)
    iso_k          records exceeding it                     iso_felt_ratio  felt / uplift on the device
    p_over_fixed / p_fail_isolated  P at the design PGA of the fragility curves
    reason         why no device works (plain words), or ""
    slide / slide_cap / k_slide  the governing sliding row: demand and capacity (m), records exceeding
    slide_what     what slides, in words ("it slides on the pedestal's top"); k_ped_over  records overturning
                   the pedestal
    """

    pga: float | None = None
    hazard: str = ""
    uplift: float | None = None
    n: int | None = None
    k_lift: int | None = None
    k_over: int | None = None
    device: str = ""
    cost: float | None = None
    travel_margin: float | None = None
    iso_governing: str = ""
    iso_k: int | None = None
    iso_felt_ratio: float | None = None
    p_over_fixed: float | None = None
    p_fail_isolated: float | None = None
    reason: str = ""
    slide: float | None = None
    slide_cap: float | None = None
    k_slide: int | None = None
    slide_what: str = ""
    k_ped_over: int | None = None


def g_text(x) -> str:
    """An acceleration (m/s^2) in g for a sentence, '-' when undefined: the verdict's every 'g'."""
    return "-" if x is None or not math.isfinite(x) else f"{x / G:.3f} g"


def _pct(x) -> str:
    return f"{x * 100:.0f} %"


def _records(k, n) -> str:
    return f"{k} of {n} design records"


def _s(k) -> str:
    """The verb's -s after a count: '1 of 7 design records lifts it', '2 of 7 ... lift it'."""
    return "s" if k == 1 else ""


MAX_WORDS = 40
"""A headline's longest: the optional details (the price, the margin, the overturn count, the reason)
are dropped, in that order, until it fits."""


def headline(code, f: Facts) -> str:
    """One plain sentence (at most :data:`MAX_WORDS` words, no formula, no config key): what to do and
    why, in the terms of the governing limit state. The bullets carry every number it drops."""
    code = Code(code)
    for detail in range(4, -1, -1):          # 4: every detail, 0: none
        text = _headline(code, f, detail)
        if words(text) <= MAX_WORDS:
            return text
    return text


def _headline(code: Code, f: Facts, detail: int) -> str:
    """The headline with ``detail`` optional parts kept (4: all; module docstring of MAX_WORDS)."""
    act = CODES[code].action
    lifts = (f"without it, {_records(f.k_lift, f.n)} lift{_s(f.k_lift)} it" if f.n and f.k_lift is not None
             else "without it, the design earthquake lifts it")
    over = f" and {f.k_over} overturn{_s(f.k_over)} it" if f.n and f.k_over and detail >= 2 else ""
    if code is Code.NO_ISOLATOR:
        where = f"in all {f.n} design records" if f.n else "under the design earthquake's peak ground acceleration"
        return f"{act}: on its own base it stays in full contact under the design earthquake, {where}."
    if code is Code.NO_ISOLATOR_BUT_RECORDS_LIFT:
        return (f"{act}: the code's check holds on average, but {_records(f.k_lift, f.n)} lift{_s(f.k_lift)} it "
                f"on {'its' if f.k_lift == 1 else 'their'} own" + (f" and {f.k_over} overturn{_s(f.k_over)} it"
                                                                   if f.k_over and detail >= 2 else "") + ".")
    if code is Code.ISOLATE:
        cost = f" (about {f.cost:.0f} EUR)" if f.cost and detail >= 4 else ""
        margin = (f", with {_pct(f.travel_margin)} travel to spare" if f.travel_margin is not None
                  and f.travel_margin >= 0 and detail >= 3 else "")
        return (f"{act}: on the designed device{cost} it stays in full contact under the design earthquake"
                f"{margin}; {lifts}{over}.")
    if code is Code.DEVICE_DOES_NOT_PROTECT:
        what = f.iso_governing or "a limit state"
        recs = f" in {_records(f.iso_k, f.n)}" if f.n and f.iso_k and detail >= 1 else ""
        return f"{act}: on it, {what} is exceeded{recs}; {lifts}{over}."
    if code is Code.NO_DEVICE_IN_RANGE:
        why = f" ({f.reason})" if f.reason and detail >= 1 else ""
        return f"{act}{why}; {lifts}{over}: restrain it, or have a specialist's device made."
    if code is Code.RUN_ISOLATOR_STAGE:
        return f"{act}: {lifts[len('without it, '):]}{over}, and this run designed no isolator."
    if code is Code.RUN_ISOLATED_DYNAMICS:
        return f"{act} over the design records: it was designed but not analysed; {lifts}{over}."
    if code is Code.SLIDES:
        if f.slide is None:
            return (f"{act}: it would slide before it lifts, and the design earthquake reaches its friction; "
                    "run the dynamics stage to measure how far.")
        recs = f" ({_records(f.k_slide, f.n)})" if f.n and f.k_slide is not None and detail >= 1 else ""
        return (f"{act}: {f.slide_what or 'it slides'} {mm_text(f.slide)} mm under the design earthquake, more than "
                f"the {mm_text(f.slide_cap)} mm it may{recs}; it stays in full contact.")
    if code is Code.PEDESTAL_OVERTURNS:
        k = f" in {_records(f.k_ped_over, f.n)}" if f.n and f.k_ped_over else ""
        return f"{act}: the pedestal overturns with the statue{k}; an isolator under the statue does not hold it."
    return f"{act}: the scan's rocking parameters were not computed."


def bullets(code, f: Facts) -> list[str]:
    """The numbers under the headline (3 to 6 short lines), the same as the limit-state rows'."""
    code = Code(code)
    out = []
    if f.pga is not None:
        out.append(f"Design earthquake: peak ground acceleration {g_text(f.pga)} at the object"
                   + (f" ({f.hazard})" if f.hazard else "") + ".")
    if f.uplift is not None:
        line = f"It lifts from {g_text(f.uplift)} of ground acceleration"
        if f.n and f.k_lift is not None:
            line += f"; {_records(f.k_lift, f.n)} lift{_s(f.k_lift)} it on its own base"
            if f.k_over is not None:
                line += ", none overturns it" if f.k_over == 0 else f", {f.k_over} overturn{_s(f.k_over)} it"
            line += (f" (the codes judge full contact on the {'mean' if f.n >= N_MIN else 'worst'} of the {f.n} records, "
                     "overturning on any one)")
        out.append(line + ".")
    if f.slide is not None and code is Code.SLIDES:
        out.append(_slide_bullet(f))
    if f.device:
        out.append(f"Device: {f.device}.")
    if code is Code.ISOLATE and f.travel_margin is not None:
        out.append(f"On the device: travel margin {_pct(f.travel_margin)}"
                   + (f", the statue feels {f.iso_felt_ratio:.2f} of its uplift acceleration" if f.iso_felt_ratio
                      is not None else "") + ".")
    if code is Code.DEVICE_DOES_NOT_PROTECT and f.iso_governing:
        out.append(f"On the device: {f.iso_governing} exceeded"
                   + (f" in {_records(f.iso_k, f.n)}" if f.n and f.iso_k else "") + ".")
    if f.p_over_fixed is not None:
        line = f"Probability of overturning at the design level: {prob_text(f.p_over_fixed)} on its own base"
        if f.p_fail_isolated is not None:
            line += f", {prob_text(f.p_fail_isolated)} of failure on the device"
        out.append(line + ".")
    if f.slide is not None and code is not Code.SLIDES:
        out.append(_slide_bullet(f))
    if f.reason and code is Code.NO_DEVICE_IN_RANGE:
        out.append(f"Why no device: {f.reason}.")
    return out[:6]


def _slide_bullet(f: Facts) -> str:
    """The sliding row in a line: how far (the mean of the records' peaks) against how far it may."""
    if f.slide == 0.0:
        return "Sliding: none; the friction holds in every design record."
    return (f"Sliding: {f.slide_what or 'it slides'} {mm_text(f.slide)} mm, against {mm_text(f.slide_cap)} mm it may"
            + (f"; {_records(f.k_slide, f.n)} pass it" if f.n and f.k_slide is not None else "") + ".")


def prob_text(p: float) -> str:
    """A probability for a sentence: '< 0.01', '> 0.99' or two decimals (the verdict's every P)."""
    return "< 0.01" if p < 0.005 else "> 0.99" if p > 0.995 else f"{p:.2f}"


def mm_text(x, spec: str = ".0f") -> str:
    """A length (m) in millimetres for a sentence, '-' when undefined (the verdict's every mm)."""
    return "-" if x is None or not math.isfinite(x) else format(x * 1000, spec)


def words(text: str) -> int:
    """The number of words of ``text``."""
    return len(text.split())
