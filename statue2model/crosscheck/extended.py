"""The comparison with the optional extended checks: the imperfect base and the record ensemble.

:func:`compare_extended` runs :func:`statue2model.crosscheck.compare.compare` (every standard case)
and appends the cases of :mod:`statue2model.crosscheck.imperfect` (``imperfect=True``) and of
:mod:`statue2model.crosscheck.ensemble` (``records=N`` > 0), their histories and their run
details (``runs['imperfect base: ...']``, ``runs['records']``; non-finite numbers as null). The command line reaches it with
``statue2model crosscheck ... --imperfect --records N``.
"""
from __future__ import annotations

from .compare import Comparison, compare


def compare_extended(scene, motion=None, *, imperfect: bool = False, records: int = 0, levels=None,
                     workers: int = 2, progress=None, **kw) -> Comparison:
    """runs.compare(scene, motion, progress=progress, **kw) plus the imperfect-base cases and the
    ensemble of ``records`` records (0: none) at ``levels`` (default ensemble.LEVELS) on ``workers``
    processes."""
    from . import ensemble
    from .contact import ContactSettings
    from .world import SimSettings

    comp = compare(scene, motion, progress=progress, **kw)
    if not imperfect and not records:
        return comp
    settings = kw.get("settings") or SimSettings()
    contact = kw.get("contact") or ContactSettings()
    quick = bool(kw.get("quick", False))
    cases, hist, runs = list(comp.cases), dict(comp.histories), dict(comp.runs)
    if imperfect:
        from .imperfect import imperfect_cases

        c, h, r = imperfect_cases(scene, settings, contact, quick, pulse_freq=kw.get("pulse_freq", 1.5),
                                  progress=progress)
        cases += c; hist.update(h); runs.update(ensemble.json_safe(r))
    if records:
        c, res = ensemble.ensemble_cases(scene, settings, contact, n_records=records,
                                         levels=ensemble.LEVELS if levels is None else levels, quick=quick,
                                         workers=workers, progress=progress)
        cases += c
        runs["records"] = ensemble.json_safe(res)       # an overturned run's peak (inf) -> None
    return Comparison(cases=tuple(cases), histories=hist, runs=runs)
