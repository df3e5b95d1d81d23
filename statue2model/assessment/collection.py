"""A museum's collection in one assessment: one row per object, ranked by risk.

Built from what each scan of a collection run returns (the pipeline's scan task): for an
assessed object ``{"scan", "folder", "out", "report", "status": {stage: status}, "warnings": [{stage,
text}], "data": {stage: manifest data}, "verdict": run.json's verdict}``, for a refused scan
``{"scan", "folder", "error"}`` (``folder``: the object's folder name, optional). Plain functions on dicts:

    object_row(result, folder)  one object's row (see :func:`object_row` for every key)
    rank(rows)                  the rows most urgent first, by :data:`RANKING_RULE`, with "rank" 1..n
    summary(rows)               the counts at the top of the collection page
    csv_rows(rows)              collection.csv: :data:`CSV_COLUMNS` (units in the headers), cells as text

The ranking rule (:data:`RANKING_RULE`, printed on the page) orders by the risk of the object
as it stands today, on a fixed base, never by what a device would do:

    1. objects not assessed (a refused scan, or a params stage that did not complete): their risk
       is unknown, and fixing the scan is the first thing to do;
    2. then by the fixed-base state reached at the design level (:data:`TIERS`): overturns (any
       design record overturns it, or its rocking reaches its limit), lifts (the mean of the design
       records exceeds its uplift), may slide before it rocks (sliding is not assessed: its risk is
       unknown and said so; after the objects known to overturn or lift, never above them without a
       measure), lifts in some records only (the mean holds), full contact.
       Without the dynamics stage's limit states, the quasi-static checks of the verdict decide
       (overturning in the variability sweep, uplift acceleration against the design PGA);
    3. within a state, by P(overturning at the design PGA, fixed base), largest first, then by
       P(uplift at the design PGA, fixed base), then by the largest demand / capacity on the fixed
       base, then by name. An unknown probability or ratio sorts as the largest (conservative).

The probabilities are the fragility study's ``p_design`` per limit state (the verdict's
``fragility.limit_states``). Their band, ``(lo, hi)``, carries the uncertainty of the fitted
median only: with the lognormal curve P(a) = Phi(ln(a / median) / beta), lo = P at the design PGA
with the median at the upper end of its confidence interval (``median_ci[1]``), hi = the same with
the lower end (``median_ci[0]``), beta as fitted; widened to hold ``p_design`` itself. No band
when the interval or beta is missing (the row then shows ``p_design`` alone). An empirical curve
(the fixed-base uplift where the lognormal is not kept: assessment/fragility_fit.py UPLIFT_RULE) has
no beta: its band is the 95 % Wilson interval of the count of thresholds (``p_design_ci``).

Example
-------
>>> ls = {"n_records": 7, "rows": [
...     {"name": "full_contact", "title": "full contact (no uplift)", "base": "fixed", "demand": 3.12,
...      "capacity": 2.72, "ratio": 1.147, "exceeded": True, "n_exceeding": 5, "unit": "m/s^2"},
...     {"name": "overturning", "title": "overturning", "base": "fixed", "demand": 0.0, "capacity": 0.143,
...      "ratio": 0.0, "exceeded": False, "n_exceeding": 0, "unit": "-"}]}
>>> girl = {"scan": "girl.ply", "out": "/c/girl", "report": "/c/girl/report.html",
...         "status": {"params": "done"}, "warnings": [], "data": {"params": {"a_min": 2.717, "weakest_deg": 90.0}},
...         "verdict": {"recommendation": "the statue lifts ...", "code": "RUN_ISOLATOR_STAGE", "fixed": {"lifts": True},
...                     "limit_states": ls, "hazard": {"pga": 2.8194}}}
>>> rows = rank([object_row(girl, "/c"), object_row({"scan": "bad<1>.stl", "error": "scan not found"}, "/c")])
>>> [(r["rank"], r["object"], r["state"]) for r in rows]
[(1, 'bad<1>', 'not assessed'), (2, 'girl', 'lifts')]
>>> rows[1]["governing_fixed"], round(rows[1]["governing_fixed_ratio"], 3), rows[1]["link"]
('full contact (no uplift)', 1.147, 'girl/report.html')
>>> summary(rows)["needing_protection"], summary(rows)["not_assessed"]
(1, 1)
"""
from __future__ import annotations

import math
import os
from pathlib import Path, PurePosixPath

from ..quantities import G  # m/s^2
from . import states
from .recommendation import DEVICE_COUNTED, Code, info, status_of
from .verdict import finite_number as _finite

NOT_ASSESSED = "not assessed"
TIERS = (NOT_ASSESSED, "overturns", "lifts", "slides", "lifts in some records", "full contact")
"""The fixed-base state at the design level, most urgent first (the ranking's first key)."""
TIER_TEXT = {NOT_ASSESSED: "not assessed: risk unknown, fix the scan first",
             "slides": "stays in full contact but slides beyond its allowance (on the floor or its pedestal) at the "
                       "design level, or would slide before it lifts where the dynamics stage did not run",
             "overturns": "overturns (a design record overturns it)",
             "lifts": "lifts and rocks (mean of the design records)",
             "lifts in some records": "lifts in some design records (the mean holds)",
             "full contact": "stays in full contact"}

RANKING_RULE = (
    "Most urgent first, by the risk of each object as it stands today on a fixed base: "
    "(1) objects not assessed (a refused scan or a failed params stage): their risk is unknown and fixing "
    "the scan comes first; (2) then by the state the object reaches at the design level on a fixed base: "
    "overturns (any design record overturns it), lifts (the mean over the design records exceeds its uplift), "
    "may slide before it rocks (sliding is not assessed: its risk is unknown, shown as such, after the objects "
    "known to overturn or lift), lifts in some records only, stays in full contact; without the design-record analyses the verdict's quasi-static checks decide; "
    "(3) within a state, by the probability of overturning at the design PGA (fixed base), then the "
    "probability of uplift at the design PGA, then the largest demand/capacity ratio on the fixed base, "
    "largest first, then by name. An unknown probability or ratio counts as the largest.")

FRAGILITY_KEYS = tuple((states.curve(k, base), k, base) for base in states.BASES
                       for k in (states.FULL_CONTACT, states.OVERTURNING))
"""(row key: the fragility curve's, the limit state, base): the probabilities a row carries
(``p_<curve>``). On the isolator, overturning counts the device's capacity exceeded
(assessment/states.py)."""


def _phi(x: float) -> float:
    return 0.5 * math.erfc(-x / math.sqrt(2.0))


def p_band(curve: dict | None, pga: float | None) -> tuple[float | None, float | None, float | None]:
    """(p, lo, hi): the probability at the design PGA ``pga`` (m/s^2) of one fragility curve (a
    study's ``fragility_limit_states[state][base]``: p_design, median, median_ci, beta) and its band
    from the median's confidence interval (module docstring); None where it is not known.

    >>> c = {"p_design": 0.4726, "median": 2.8368, "median_ci": [2.7286, 3.0487], "beta": 0.0897}
    >>> [round(v, 3) for v in p_band(c, 2.8194)]
    [0.473, 0.192, 0.642]
    >>> p_band({"p_design": None, "median": None}, 2.8)
    (None, None, None)
    """
    if not isinstance(curve, dict):
        return None, None, None
    p = _finite(curve.get("p_design"))
    pci = [_finite(x) for x in (list(curve.get("p_design_ci") or []) + [None, None])[:2]]
    if p is not None and None not in pci:
        return p, min(pci[0], p), max(pci[1], p)
    ci = list(curve.get("median_ci") or []) + [None, None]
    m_lo, m_hi, beta = _finite(ci[0]), _finite(ci[1]), _finite(curve.get("beta"))
    pga = _finite(pga)
    if p is None or pga is None or pga <= 0 or m_lo is None or m_hi is None or m_lo <= 0 or m_hi <= 0 \
            or beta is None or beta < 0:
        return p, None, None

    def at(m):
        if beta == 0:
            return 1.0 if pga >= m else 0.0
        return _phi(math.log(pga / m) / beta)

    lo, hi = sorted((at(m_hi), at(m_lo)))
    return p, min(lo, p), max(hi, p)


def _rows_of(ls: dict | None, base: str) -> list[dict]:
    return [r for r in (ls or {}).get("rows") or () if r.get("base") == base]


def _governing(ls: dict | None, base: str) -> dict | None:
    """The limit-state row of ``base`` with the largest demand / capacity (None without rows)."""
    best = None
    for r in _rows_of(ls, base):
        v = _finite(r.get("ratio"))
        if v is not None and (best is None or v > _finite(best.get("ratio"))):
            best = r
    return best


def _row(ls: dict | None, name: str, base: str) -> dict | None:
    for r in _rows_of(ls, base):
        if r.get("name") == name:
            return r
    return None


def _quantity(x, unit) -> str:
    x = _finite(x)
    if x is None:
        return "-"
    return (f"{x / G:.3f} g" if unit == "m/s^2" else f"{x * 1000:.0f} mm" if unit == "m" else
            f"{x:.0f} N" if unit == "N" else f"{x:.3g}")


def fixed_state(verdict: dict) -> str:
    """The fixed-base state at the design level (one of :data:`TIERS` after the first) of an
    assessed object's verdict: from its limit states on the design records when present, else
    from its quasi-static checks.

    >>> fixed_state({"fixed": {"lifts": True, "overturns": False}})
    'lifts'
    >>> fixed_state({"fixed": {"lifts": True}, "limit_states": {"rows": [{"name": "full_contact",
    ...     "base": "fixed", "exceeded": False, "n_exceeding": 2}]}})
    'lifts in some records'
    """
    fixed = verdict.get("fixed") or {}
    ls = verdict.get("limit_states")
    if ls and _rows_of(ls, "fixed"):
        ot, rk, fc, pot = (_row(ls, n, "fixed") for n in (states.OVERTURNING, states.ROCKING, states.FULL_CONTACT,
                                                          states.PEDESTAL_OVERTURNING))
        if any((r or {}).get("exceeded") for r in (ot, rk, pot)):
            return "overturns"
        if (fc or {}).get("exceeded"):
            return "lifts"
        if any((_row(ls, n, "fixed") or {}).get("exceeded") for n in (states.SLIDING, states.PEDESTAL_SLIDING)) \
                or fixed.get("slides"):
            return "slides"
        if int(_finite((fc or {}).get("n_exceeding")) or 0) > 0:
            return "lifts in some records"
        return "full contact"
    if fixed.get("overturns"):
        return "overturns"
    if fixed.get("lifts"):
        return "lifts"
    if fixed.get("slides"):
        return "slides"
    return "full contact"


NO_DEVICE = {"friction": "it lifts below the balls' own rolling resistance (restrain it)",
             "pit": "it lifts below the balls' own rolling resistance (restrain it)",
             "acceleration": "no device in range keeps it in full contact (restrain it)",
             "ball_load": "too heavy for the groove surfaces in range",
             "plate_size": "the device it needs exceeds the largest plate",
             "reserve": "no device in range keeps a reserve to where it would overturn"}
"""The device column's words for the kind of reason no design passes (isolator.design.what_would_pass)."""


DEVICE_TEXT = {"optional": "optional: no isolator needed by the code's check, single design records lift it",
               "rejected": "does not protect at the design level: do not build it",
               "none in range": "none: no isolator in range protects it",
               "not needed": "not needed: it stays in full contact",
               "not applicable": "not applicable: an isolator is not the remedy (restrain or anchor it)",
               "design": "not designed: run the isolator stage"}
"""The device column's words for the roles (recommendation.DEVICE_ROLES) where the designed device does not count."""
NOT_APPLICABLE_WHY = {Code.SLIDES.value: "not applicable: it slides, it does not lift (restrain it)",
                      Code.PEDESTAL_OVERTURNS.value: "not applicable: its pedestal overturns (anchor or widen the "
                                                     "pedestal; an isolator under the statue does not hold it)"}


def _device(verdict: dict, data: dict, code: str = "") -> dict:
    """The row's device columns (:func:`object_row`) of the verdict's isolator and the recommendation
    ``code``: what the designed device is to the object is the code's (recommendation.CodeInfo.device):
    only a device the code counts (DEVICE_COUNTED: build it, or analyse it first) shows as passing and
    has its ``cost`` (EUR) and plates counted; for the others (not needed, optional, rejected, not
    applicable: it slides, its pedestal overturns) the column says so and ``cost`` is None. Without a code
    (an old run.json) the design's own state decides."""
    iso = verdict.get("isolated") or {}
    role = info(code).device if code else None
    if not iso:
        why = "the isolator stage did not run" if not data.get("isolator") else "no design"
        return {"device_state": "not designed", "device": f"none: {why}", "R": None, "r": None,
                "n_grooves": None, "T": None, "cost": None, "device_note": ""}
    R, r, T = _finite(iso.get("R")), _finite(iso.get("r")), _finite(iso.get("T"))
    n = iso.get("n_grooves") if isinstance(iso.get("n_grooves"), int) else None
    geo = (f"R {R:.2f} m" if R is not None else "R -") + (f", r {r * 1000:.1f} mm" if r is not None else "") \
        + (f", {n} grooves" if n is not None else "") + (f", T {T:.2f} s" if T is not None else "")
    cost = _finite(iso.get("cost"))
    out = {"R": R, "r": r, "n_grooves": n, "T": T, "cost": None, "device_note": str(iso.get("what_would_pass") or "")}
    # a device rejected for the ball load alone stays "conditional" (what its grooves must carry), and where no
    # device is in range the design's reason is said
    keep = (role == "none in range" and not iso.get("passed")) or (role == "rejected" and iso.get("conditional"))
    if role is not None and role not in DEVICE_COUNTED and not keep:
        text = NOT_APPLICABLE_WHY.get(code) or DEVICE_TEXT[role]
        if role in ("optional", "rejected"):
            text = f"{geo}: {text}" + (f" (about {cost:.0f} EUR if built)" if cost and role == "optional" else "")
        return {**out, "device_state": "none" if role == "none in range" else role, "device": text}
    if iso.get("passed"):
        state = "passed"
        text = f"{geo}: passes" + (f", about {cost:.0f} EUR" if cost else "")
        if role == "analyse":
            text += " (not yet analysed over the design records)"
        out["cost"] = cost
    elif iso.get("conditional"):
        state = "conditional"
        b = _row(verdict.get("limit_states"), "bearing", "isolated") or {}
        need, given = _finite(b.get("demand")), _finite(b.get("capacity"))
        text = f"{geo}: conditional on the ball load" + (
            f" (grooves must carry {need:.0f} N per ball, {given:.0f} N given)" if None not in (need, given) else "")
    else:
        state = "none"
        text = "none: " + NO_DEVICE.get(iso.get("reason_key"), "no design in range passes")
        out["device_note"] = str(iso.get("reason") or "no design in range passes")
    return {**out, "device_state": state, "device": text}


def _doubts(verdict: dict, data: dict) -> list[str]:
    """The row's doubts, from the stages' facts (never from the warnings' words): an uncertain base
    contact with its uplift band, guessed units, the 3D cross-check's unconfirmed limit states, the
    isolator's advisory checks not met."""
    out = []
    params, iso = data.get("params") or {}, data.get("isolator") or {}
    band = ((verdict.get("limit_states") or {}).get("uplift_band") or [None, None])
    lo, hi = (_finite(x) for x in (list(band) + [None, None])[:2])
    if lo is None or hi is None:
        lo, hi = (_finite(x) for x in (list(params.get("contact_band") or []) + [None, None])[:2])
    if lo is not None and hi is not None:
        out.append(f"base contact uncertain: uplift {lo / G:.3f}-{hi / G:.3f} g")
    elif params.get("contact_uncertain") is True:
        out.append("base contact uncertain")
    if params.get("units_sure") is False:
        out.append(f"units guessed: assumed {params.get('units') or '?'}")
    missed = (verdict.get("crosscheck") or {}).get("missed") or []
    if missed:
        out.append("3D cross-check does not confirm: " + ", ".join(str(m) for m in missed))
    for name in iso.get("advisory_not_met") or ():
        out.append(f"advisory: {name}")
    seen = []
    for d in out:
        if d not in seen:
            seen.append(d)
    return seen


def _link(result: dict, folder) -> str | None:
    rep = result.get("report")
    if not rep:
        return None
    rep = Path(rep)
    if folder is not None:
        try:
            return PurePosixPath(*Path(os.path.relpath(rep, folder)).parts).as_posix()
        except ValueError:                 # another drive (Windows): keep the out folder's name
            pass
    out = Path(result["out"]).name if result.get("out") else rep.parent.name
    return f"{out}/{rep.name}"


def object_row(result: dict, folder: str | os.PathLike | None = None) -> dict:
    """One object's row from its scan task's ``result`` (module docstring); ``folder``: the
    collection's output folder, which ``link`` is relative to (default: ``<out name>/report.html``).

    Keys: ``object`` (the object's folder in the collection, ``folder``: the scan's name without
    suffix, or its whole name where that would clash, see pipeline.run.object_folders), ``scan``; ``assessed`` (bool) and ``reason``
    (why not: the refused scan's error, or the params stage's status; "" when assessed);
    ``recommendation`` (run.json's verdict["recommendation"], the reasoning, verbatim; "" for a refused
    scan), ``code`` and ``headline`` (the verdict's recommendation code and headline; "" without) and
    ``status`` (ok, warn, fail from the code, recommendation.status_of, with the 3D cross-check's doubt;
    "not assessed"); ``state`` (one of :data:`TIERS`) and ``basis``
    ("design records" or "quasi-static"); ``governing_fixed`` / ``governing_isolated`` (the
    limit state with the largest demand / capacity at the design level on that base, its title),
    ``governing_*_ratio`` and ``governing_*_text`` ("demand vs capacity" in its unit);
    ``p_<key>``, ``p_<key>_lo``, ``p_<key>_hi`` for each key of :data:`FRAGILITY_KEYS` (the
    probability at the design PGA and its band, :func:`p_band`); ``design_pga`` (m/s^2: the PGA
    the probabilities are read at); ``uplift_g`` (the weakest uplift acceleration, g) and
    ``weakest_deg`` (its direction, deg); ``m`` (kg), ``h``, ``b_L``, ``b_R`` (m); ``device_state``
    (passed, conditional, none, not designed, or the code's device role where the designed device is not
    the object's protection: optional, rejected, not needed, not applicable, design; :func:`_device`),
    ``device`` (one line: R, r, grooves, T and the state, or none with the reason), ``device_note`` (the
    isolator's "what would pass", else ""), ``R``, ``r`` (m), ``n_grooves``, ``T`` (s), ``cost`` (EUR, the
    device's price where it is counted: device_state passed, else None); ``sheets`` (the prototype's sheet count); ``doubts`` (short
    texts: uncertain base contact, guessed units, the 3D cross-check's unconfirmed limit states,
    advisory checks not met); ``warnings`` (their count); ``link`` (report.html relative to
    ``folder``, posix; None without a report). Every number is a
    finite float, an int or None.
    """
    if not isinstance(result, dict):
        raise TypeError(f"a scan result is a dict, not {type(result).__name__}")
    scan = str(result.get("scan") or "?")
    name = scan.rsplit(".", 1)[0] if "." in scan.lstrip(".") else scan     # as Path.stem, "/" kept as text
    name = str(result.get("folder") or name)      # its output folder's: the whole file name where stems clash
    row = {"object": name, "scan": scan, "assessed": False, "reason": "", "recommendation": "", "code": "",
           "headline": "",
           "status": NOT_ASSESSED, "state": NOT_ASSESSED, "basis": "", "link": _link(result, folder),
           "governing_fixed": None, "governing_fixed_ratio": None, "governing_fixed_text": "",
           "governing_isolated": None, "governing_isolated_ratio": None, "governing_isolated_text": "",
           "design_pga": None, "uplift_g": None, "weakest_deg": None, "m": None, "h": None, "b_L": None,
           "b_R": None, "device_state": "not designed", "device": "", "device_note": "", "R": None, "r": None,
           "n_grooves": None, "T": None, "cost": None, "sheets": None, "doubts": [], "warnings": len(result.get("warnings") or ())}
    for key, _, _ in FRAGILITY_KEYS:
        row.update({f"p_{key}": None, f"p_{key}_lo": None, f"p_{key}_hi": None})
    if "error" in result:
        row["reason"] = " ".join(str(result["error"]).split()) or "refused"
        return row
    verdict = result.get("verdict") or {}
    data = result.get("data") or {}
    params = data.get("params") or {}
    st = (result.get("status") or {}).get("params")
    row["recommendation"] = str(verdict.get("recommendation") or "")
    row["code"], row["headline"] = _code(verdict), str(verdict.get("headline") or "")
    if st not in ("done", "cached") or not params:
        row["reason"] = f"the params stage did not complete (status: {st or 'not run'})"
        return row
    row["assessed"] = True
    # the colour from the code (a reworded sentence changes nothing); the 3D cross-check's doubt carried
    doubt = bool((verdict.get("crosscheck") or {}).get("missed"))
    row["status"] = status_of(row["code"], doubt) if row["code"] else "warn"
    row["state"] = fixed_state(verdict)
    ls = verdict.get("limit_states")
    row["basis"] = "design records" if ls and _rows_of(ls, "fixed") else "quasi-static"
    for base in ("fixed", "isolated"):
        g = _governing(ls, base)
        if g is not None:
            row[f"governing_{base}"] = str(g.get("title") or g.get("name"))
            row[f"governing_{base}_ratio"] = _finite(g.get("ratio"))
            if g.get("name") == "overturning":
                row[f"governing_{base}_text"] = (f"{g.get('n_exceeding', '-')} of {ls.get('n_records', '-')} "
                                                 "records overturn")
            else:
                row[f"governing_{base}_text"] = (f"{_quantity(g.get('demand'), g.get('unit'))} vs "
                                                 f"{_quantity(g.get('capacity'), g.get('unit'))}")
    dyn = data.get("dynamics") or {}
    pga = _finite(dyn.get("fragility_design_pga")) or _finite((verdict.get("hazard") or {}).get("pga"))
    row["design_pga"] = pga
    fl = (verdict.get("fragility") or {}).get("limit_states") or {}
    for key, state, base in FRAGILITY_KEYS:
        p, lo, hi = p_band((fl.get(state) or {}).get(base), pga)
        row.update({f"p_{key}": p, f"p_{key}_lo": lo, f"p_{key}_hi": hi})
    a_min = _finite(params.get("a_min", params.get("a_R")))
    row["uplift_g"] = None if a_min is None else a_min / G
    row["weakest_deg"] = _finite(params.get("weakest_deg"))
    for k in ("m", "h", "b_L", "b_R"):
        row[k] = _finite(params.get(k))
    row.update(_device(verdict, data, row["code"]))
    sheets = (data.get("prototype") or {}).get("n_sheets")
    row["sheets"] = sheets if isinstance(sheets, int) and not isinstance(sheets, bool) else None
    row["doubts"] = _doubts(verdict, data)
    return row


def _desc(x) -> float:
    """A sort key for 'largest first' where unknown counts as the largest."""
    x = _finite(x)
    return -math.inf if x is None else -x


def rank_key(row: dict) -> tuple:
    """The sort key of :data:`RANKING_RULE` (smaller = more urgent)."""
    tier = TIERS.index(row["state"]) if row.get("state") in TIERS else 0
    if not row.get("assessed"):
        return (0, 0.0, 0.0, 0.0, str(row.get("object", "")))
    return (tier, _desc(row.get("p_overturning_fixed")), _desc(row.get("p_full_contact_fixed")),
            _desc(row.get("governing_fixed_ratio")), str(row.get("object", "")))


def risk_today(row: dict) -> float:
    """The risk the value weighs (:data:`VALUE_RULE`): P(overturning at the design PGA, fixed base); where
    it is not known, 1 for an object that overturns, lifts or may slide at the design level (conservative),
    else P(uplift) or 0.5 when that is not known either."""
    p = _finite(row.get("p_overturning_fixed"))
    if p is not None:
        return p
    if row.get("state") in ("overturns", "lifts", "slides"):
        return 1.0
    u = _finite(row.get("p_full_contact_fixed"))
    return 0.5 if u is None else u


VALUE_RULE = ("With values ([values] in the project file): the assessed objects are ranked by risk x value, "
              "largest first (risk: the probability of overturning at the design PGA on a fixed base; where it "
              "is not known, 1 for an object that overturns, lifts or may slide, else the probability of uplift); "
              "an object without a value counts at the largest value given; ties by the rule above. Objects not "
              "assessed stay first.")


def rank(rows: list[dict]) -> list[dict]:
    """The rows most urgent first by :data:`RANKING_RULE` or, when any row has a ``value``, by risk x value
    (:data:`VALUE_RULE`), each a copy with ``rank`` 1..n (and ``risk_x_value`` when values are given)."""
    values = [v for v in (_finite(r.get("value")) for r in rows) if v is not None and v > 0]
    if not values:
        return [{**r, "rank": i} for i, r in enumerate(sorted(rows, key=rank_key), start=1)]
    top = max(values)

    def weighted(r):
        v = _finite(r.get("value"))
        return risk_today(r) * (top if v is None or v <= 0 else v)

    def key(r):
        base = rank_key(r)
        return (0, 0.0, *base) if not r.get("assessed") else (1, -weighted(r), *base)
    out = []
    for i, r in enumerate(sorted(rows, key=key), start=1):
        out.append({**r, "rank": i, "risk_x_value": weighted(r) if r.get("assessed") else None})
    return out


def _code(verdict: dict) -> str:
    """The verdict's recommendation code (assessment/recommendation.py), "" when it has none or an
    unknown one (an old or hand-made run.json)."""
    try:
        return Code(verdict.get("code")).value
    except ValueError:
        return ""


def needs_protection(row: dict) -> bool:
    """An assessed object whose recommendation code asks for protection (recommendation.CODES); an
    assessed object without a code counts as needing it (the conservative reading)."""
    if not row.get("assessed"):
        return False
    return info(row["code"]).needs_protection if row.get("code") else True


def to_consider(row: dict) -> bool:
    """An assessed object the code's check leaves unprotected while single design records lift it."""
    return bool(row.get("assessed")) and bool(row.get("code")) and info(row["code"]).to_consider


def summary(rows: list[dict]) -> dict:
    """The collection's counts: ``objects``, ``assessed``, ``not_assessed``, ``needing_protection``
    (:func:`needs_protection`), ``to_consider`` (no isolator needed by the codes' mean, but single
    design records lift the object: the verdict's warning), ``devices_passed`` and
    ``devices_conditional`` (designs that pass; that pass but for the ball load; only devices the object's
    code counts, recommendation.DEVICE_COUNTED: never one of an object that slides, needs none or whose
    device does not protect), ``no_device`` (needing protection with no device passing or conditional,
    where an isolator is the remedy: not one that slides or whose pedestal overturns), ``prototype_sheets``
    (all prototypes' sheets), ``isolator_plates`` (2 per passing device) and ``devices_cost`` (EUR, the
    passing devices' prices summed; those without a price add nothing).

    >>> summary([{"assessed": True, "code": "ISOLATE", "device_state": "passed", "sheets": 2},
    ...          {"assessed": False}])["isolator_plates"]
    2
    """
    assessed = [r for r in rows if r.get("assessed")]
    need = [r for r in assessed if needs_protection(r)]
    passing = [r for r in assessed if r.get("device_state") == "passed"]
    passed = len(passing)
    return {"objects": len(rows), "assessed": len(assessed), "not_assessed": len(rows) - len(assessed),
            "needing_protection": len(need),
            "to_consider": sum(to_consider(r) for r in assessed),
            "devices_passed": passed,
            "devices_conditional": sum(r.get("device_state") == "conditional" for r in assessed),
            "no_device": sum(r.get("device_state") not in ("passed", "conditional", "not applicable") for r in need),
            "prototype_sheets": sum(r.get("sheets") or 0 for r in assessed),
            "isolator_plates": 2 * passed,
            "devices_cost": float(sum(_finite(r.get("cost")) or 0.0 for r in passing))}


CSV_COLUMNS = (
    ("rank", "rank"), ("object", "object"), ("scan", "scan"), ("room", "room"), ("floor", "floor"),
    ("value", "value (the user's)"), ("risk_x_value", "risk x value"),
    ("assessed", "assessed"),
    ("reason", "not assessed because"), ("status", "status"), ("code", "recommendation code"),
    ("headline", "recommendation"), ("recommendation", "reasoning"),
    ("state", "fixed base at the design level"), ("basis", "basis"),
    ("governing_fixed", "governing limit state, fixed"),
    ("governing_fixed_ratio", "demand/capacity, fixed [-]"),
    ("governing_fixed_text", "demand vs capacity, fixed"),
    ("governing_isolated", "governing limit state, isolated"),
    ("governing_isolated_ratio", "demand/capacity, isolated [-]"),
    ("governing_isolated_text", "demand vs capacity, isolated"),
    ("design_pga", "design PGA [g]"),
    ("p_full_contact_fixed", "P(uplift) fixed at design PGA [-]"), ("p_full_contact_fixed_lo", "P(uplift) fixed low [-]"),
    ("p_full_contact_fixed_hi", "P(uplift) fixed high [-]"),
    ("p_overturning_fixed", "P(overturning) fixed at design PGA [-]"),
    ("p_overturning_fixed_lo", "P(overturning) fixed low [-]"),
    ("p_overturning_fixed_hi", "P(overturning) fixed high [-]"),
    ("p_full_contact_isolated", "P(uplift) isolated at design PGA [-]"),
    ("p_full_contact_isolated_lo", "P(uplift) isolated low [-]"), ("p_full_contact_isolated_hi", "P(uplift) isolated high [-]"),
    ("p_overturning_isolated", "P(overturning or capacity) isolated at design PGA [-]"),
    ("p_overturning_isolated_lo", "P(overturning or capacity) isolated low [-]"),
    ("p_overturning_isolated_hi", "P(overturning or capacity) isolated high [-]"),
    ("uplift_g", "weakest uplift [g]"), ("weakest_deg", "weakest direction [deg]"),
    ("m", "mass [kg]"), ("h", "h [m]"), ("b_L", "b_L [m]"), ("b_R", "b_R [m]"),
    ("device_state", "isolator"), ("device", "isolator device"), ("R", "isolator R [m]"),
    ("r", "isolator ball r [m]"), ("n_grooves", "isolator grooves"), ("T", "isolator T [s]"),
    ("cost", "isolator cost [EUR]"),
    ("sheets", "prototype sheets"), ("doubts", "doubts"), ("warnings", "warnings"), ("link", "report"),
)
"""(row key, CSV header with its unit) of collection.csv, in order."""


def _cell(key: str, v) -> str:
    if v is None:
        return ""
    if isinstance(v, bool):
        return "yes" if v else "no"
    if isinstance(v, (list, tuple)):
        return "; ".join(str(x) for x in v)
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        if not math.isfinite(v):
            return ""
        if key == "design_pga":
            v = v / G
        return f"{v:.6g}"
    return str(v)


def csv_rows(rows: list[dict]) -> tuple[list[str], list[list[str]]]:
    """(header, rows of text) for collection.csv: :data:`CSV_COLUMNS`, a ``None`` (or a non-finite
    number) as an empty cell, booleans as yes/no, lists joined with "; ". Write it with
    statue2model.io.csvsafe.write_csv (which neutralises cells a spreadsheet would run as a formula).

    >>> head, body = csv_rows([{"rank": 1, "object": "a", "assessed": True, "uplift_g": float("nan")}])
    >>> head[:2], body[0][:4], body[0][head.index("weakest uplift [g]")]
    (['rank', 'object'], ['1', 'a', '', ''], '')
    """
    header = [h for _, h in CSV_COLUMNS]
    return header, [[_cell(k, r.get(k)) for k, _ in CSV_COLUMNS] for r in rows]


__all__ = ["CSV_COLUMNS", "FRAGILITY_KEYS", "NOT_ASSESSED", "RANKING_RULE", "TIERS", "TIER_TEXT", "csv_rows",
           "fixed_state", "needs_protection", "object_row", "p_band", "rank", "rank_key", "summary"]
