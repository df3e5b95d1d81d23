"""The free-standing statue's cases: free rocking, one-sine pulses and the user's motion, 2D against 3D.

* free rocking from theta0 = 0.5 delta_R: quarter period (1 %), first rebound peak (5 %)
  (:func:`free_rocking_cases`);
* one-sine pulses at 0.8 x and 1.25 x the 2D minimum overturning amplitude: overturn (same),
  lift-off from the contacts (the non-pivot base edge above statue_scene.LIFT_HEIGHT; the 2D side
  at the same height, (b_L + b_R) sin|theta|; target LIFT_TARGET, 5 ms), peak rotation before the
  first impact (both read before their own first impact; 5 %), peak rotation (5 %)
  (:func:`pulse_cases`);
* the user's motion (--motion): overturn, lift-off, peak rotation (with both models' spread)
  (:func:`motion_cases`).

Each family returns a :class:`~statue2model.crosscheck.case.Comparison` (its cases, the time
histories for the overlay plots, the 3D run details); every case carries its run's validity
screen (:mod:`statue2model.crosscheck.screen`). The lift-off readers (:func:`first_crossing`,
:func:`threshold_time_2d`, :func:`lift_angle`, :func:`liftoff_time_2d`) serve the imperfect-base
cases too.
"""
from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from ..hazard import motions
from ..quantities import G
from ..rocking.engine import simulate as simulate_2d
from ..rocking.model import RockingModel
from .boundary import overturn_amplitude_2d
from .case import Case, Comparison
from .contact import ContactSettings
from .restitution import DIAG_WHY, model_2d, user_model
from .screen import screen
from .statue_scene import LIFT_HEIGHT, StatueScene, simulate_statue
from .world import SimSettings

DT_OUT_2D = 0.005
"""Output step of the 2D histories, s."""
LIFT_TARGET = 0.005
"""Target of the lift-off time, s (|3D - 2D|, both read at statue_scene.LIFT_HEIGHT)."""


def first_crossing(t: np.ndarray, q: np.ndarray, level: float) -> float | None:
    """First time (s) the samples ``q`` (shape (n,), at times ``t``) exceed ``level``, linearly
    interpolated between the two samples around it; None if never.

    >>> first_crossing(np.array([0.0, 1.0, 2.0]), np.array([0.0, 0.5, 1.5]), 1.0)
    1.5
    """
    i = np.flatnonzero(q > level)
    if i.size == 0:
        return None
    i = int(i[0])
    if i == 0:
        return float(t[0])
    return float(t[i - 1] + (t[i] - t[i - 1]) * (level - q[i - 1]) / (q[i] - q[i - 1]))


def threshold_time_2d(model: RockingModel, motion, angle: float, t_end: float, dt: float = 1e-4) -> float | None:
    """First time |theta| > ``angle`` (rad) in the 2D model, linearly interpolated on a
    ``dt`` grid (see :func:`liftoff_time_2d`)."""
    r = simulate_2d(model, motion, t_end=t_end, dt_out=dt)
    return first_crossing(r.history["t"], np.abs(r.history["theta"]), angle)


def no_lift_case(tag: str, r2, r3) -> Case:
    """The peak rotation where neither model lifts off (the non-pivot base edge stays below
    LIFT_HEIGHT in both): not compared ('not applicable'), with the reason. The 3D rotation of a body
    in full contact is the contact's compliance (a fraction of a milliradian), not rocking; the 2D
    one is zero, or a hair past the exact uplift instant, of the same order as that compliance."""
    q2 = max(abs(r2.theta_max_L), abs(r2.theta_max_R))
    q3 = max(abs(r3.theta_max_L), abs(r3.theta_max_R))
    return Case(f"{tag}: peak rotation", "peak rotation", q2, q3, math.inf, 0.05, False, kind="relative", unit="rad",
                status="not applicable",
                why=f"not applicable: neither model lifts off (the non-pivot base edge stays below "
                    f"{LIFT_HEIGHT * 1000:g} mm in both: 2D {q2:.2e} rad, 3D {q3:.2e} rad, the order of the "
                    "contact's compliance, not rocking)")


def lift_angle(params, height: float = LIFT_HEIGHT) -> float:
    """|theta| (rad) at which the non-pivot base edge of the 2D body is ``height`` m above the
    floor: (b_L + b_R) sin|theta| = height."""
    return math.asin(min(1.0, height / (params.b_L + params.b_R)))


def liftoff_time_2d(model: RockingModel, motion, t_end: float, height: float = LIFT_HEIGHT) -> float | None:
    """Lift-off of the 2D model read at the 3D criterion (statue_scene.LIFT_HEIGHT): the first time
    its non-pivot base edge is ``height`` m above the floor (None if never before ``t_end``)."""
    return threshold_time_2d(model, motion, lift_angle(model.params, height), t_end)


def _hist2d(r) -> tuple[np.ndarray, np.ndarray]:
    h = r.history
    return h["t"], h["theta"]


def free_rocking_cases(scene: StatueScene, settings: SimSettings, contact: ContactSettings,
                       theta0_frac: float = 0.5, t_end: float = 3.0, model: RockingModel | None = None
                       ) -> Comparison:
    """Free rocking on the right pivot from theta0 = theta0_frac delta_R (``model``: the user's)."""
    p = scene.params
    model = user_model(scene) if model is None else model
    th0 = theta0_frac * p.delta_R
    r2 = simulate_2d(model, motions.free(), theta0=th0, t_end=t_end, dt_out=min(DT_OUT_2D, settings.dt * 4))
    r3 = simulate_statue(scene, motions.free(), theta0=th0, t_end=t_end, settings=settings, contact=contact,
                         dt_out=settings.dt)
    scr = screen(model, motions.free(), r3, contact, t_end, theta0=th0)
    cases = []
    q2 = r2.impact_times[0] if r2.n_impacts else None
    q3 = r3.impact_times[0] if r3.impact_times.size else None
    cases.append(Case.relative("free rocking: quarter period", "s", q2, q3, 0.01,
                               note=f"release at theta0 = {theta0_frac:g} delta_R on the right pivot",
                               quantity="quarter period").screened(scr))
    if r3.peak_theta.size >= 2 and r2.peak_values.size >= 2:
        cases.append(Case.relative("free rocking: first rebound peak", "rad", r2.peak_values[1],
                                   abs(r3.peak_theta[1]), 0.05, quantity="peak rotation",
                                   note="2D with the user's e (eq. 15 unless a prototype test gives it)"
                                   ).screened(scr))
    t2, y2 = _hist2d(r2)
    hist = {"free rocking": {"t2": t2, "y2": y2, "t3": r3.t, "y3": r3.theta, "label": "theta (rad)"}}
    return Comparison(tuple(cases), hist, {"free rocking": r3.to_dict() | {"screen": scr}})


def peak_before_first_impact_2d(r2) -> float | None:
    """Largest |theta| of a 2D run before its first impact (None if it overturns first)."""
    t, q = r2.history["t"], np.abs(r2.history["theta"])
    if r2.n_impacts:
        q = q[t <= r2.impact_times[0]]
    elif r2.overturned:
        return None
    return float(q.max(initial=0.0))


def peak_before_first_impact_3d(r3) -> float | None:
    """Largest |theta| of a 3D run before its first impact (a sign change of theta), None if it
    overturns first."""
    q = np.abs(r3.theta)
    if r3.impact_times.size:
        q = q[r3.t <= r3.impact_times[0]]
    elif r3.overturned:
        return None
    return float(q.max(initial=0.0))


def _liftoff_cases(tag: str, model: RockingModel, motion, r2, r3, t_end: float) -> tuple[list, bool]:
    """Lift-off from the contacts: does it lift at all (same in both), when (LIFT_TARGET), and the
    force-based lift-off as a diagnostic. Returns the cases and whether either model lifted off by the
    geometric criterion (the non-pivot base edge above LIFT_HEIGHT in both): the one criterion that
    decides whether the peak rotation is compared, so a 2D rotation of a few 1e-5 rad (a hair past the
    exact uplift instant) is never compared with the 3D contact's compliance."""
    tl2 = liftoff_time_2d(model, motion, t_end)
    cases = [Case.equal(f"{tag}: lifts off", tl2 is not None, r3.uplift_time is not None, quantity="lift-off",
                        note=f"non-pivot base edge above {LIFT_HEIGHT * 1000:g} mm (3D: contacts; 2D: "
                             f"(b_L + b_R) sin|theta|)")]
    if tl2 is not None:
        cases.append(Case.absolute(f"{tag}: lift-off time", "s", tl2, r3.uplift_time, LIFT_TARGET,
                                   quantity="lift-off time",
                                   note=f"non-pivot base edge above {LIFT_HEIGHT * 1000:g} mm in both "
                                        f"(2D exact uplift, |u_g''| = g b / h, at "
                                        f"{r2.uplift_time if r2.uplift_time is not None else float('nan'):.4f} s)"))
    if r2.uplift_time is not None or r3.unload_time is not None:
        cases.append(Case.absolute(f"{tag}: non-pivot side unloaded", "s", r2.uplift_time, r3.unload_time,
                                   LIFT_TARGET, quantity="unload time",
                                   note="3D: normal force of the base points away from the pivot < 0.1 % m g; "
                                        "2D: the exact uplift instant").as_diagnostic(
            why="the contact solver's forces oscillate by 10-30 % of the load before uplift (micro-rocking in "
                "the contact compliance), so the force criterion leads the rigid-body instant by up to ~7 ms: "
                "shown, the geometric lift-off is the check"))
    return cases, tl2 is not None or r3.uplift_time is not None


def pulse_cases(scene: StatueScene, settings: SimSettings, contact: ContactSettings, freq: float = 1.5,
                factors=(0.8, 1.25), free_time: float = 3.0, model: RockingModel | None = None,
                diag_model: RockingModel | None = None) -> Comparison:
    """One-sine pulses (toward +x first: the body lifts on its left pivot) at ``factors`` x the
    minimum overturning amplitude of ``model`` (the user's 2D model, default eq. 15's e); the
    checks use ``model``, ``diag_model`` (2D given 3D's e) adds diagnostics."""
    model = user_model(scene) if model is None else model
    a_ot = overturn_amplitude_2d(model, freq, "sine")
    cases, hist, runs = [], {}, {}
    for fac in factors:
        m = motions.sine_pulse(fac * a_ot, freq)
        tag = f"one-sine {freq:g} Hz x{fac:g}"
        t_end = m.end + free_time
        r2 = simulate_2d(model, m, t_end=t_end, dt_out=1e-3)
        r3 = simulate_statue(scene, m, settings=settings, contact=contact, free_time=free_time)
        scr = screen(model, m, r3, contact, t_end)
        cs = [Case.equal(f"{tag}: overturn", r2.overturned, r3.overturned, quantity="overturn")]
        lift_cs, lifts = _liftoff_cases(tag, model, m, r2, r3, m.end)
        cs += lift_cs
        p2, p3 = peak_before_first_impact_2d(r2), peak_before_first_impact_3d(r3)
        if lifts and (p2 is not None or p3 is not None):
            cs.append(Case.relative(f"{tag}: peak rotation before the first impact", "rad", p2, p3, 0.05,
                                    quantity="peak rotation",
                                    note="each read before its own first impact (theta changes sign)"))
        if lifts and not r2.overturned and not r3.overturned:
            cs.append(Case.relative(f"{tag}: peak rotation", "rad", max(r2.theta_max_L, r2.theta_max_R),
                                    max(r3.theta_max_L, r3.theta_max_R), 0.05, quantity="peak rotation"))
        if not lifts:
            cs.append(no_lift_case(tag, r2, r3))
        if diag_model is not None:
            rd = simulate_2d(diag_model, m, t_end=t_end)
            cs.append(Case.equal(f"{tag}: overturn (2D given 3D's e)", rd.overturned, r3.overturned,
                                 quantity="overturn").as_diagnostic(DIAG_WHY))
            if not rd.overturned and not r3.overturned:
                cs.append(Case.relative(f"{tag}: peak rotation (2D given 3D's e)", "rad",
                                        max(rd.theta_max_L, rd.theta_max_R), max(r3.theta_max_L, r3.theta_max_R),
                                        0.05, quantity="peak rotation").as_diagnostic(DIAG_WHY))
        cases += [c.screened(scr) for c in cs]
        t2, y2 = _hist2d(r2)
        hist[tag] = {"t2": t2, "y2": y2, "t3": r3.t, "y3": r3.theta, "label": "theta (rad)"}
        runs[tag] = r3.to_dict() | {"amp_m_s2": fac * a_ot, "a_overturn_2d": a_ot, "screen": scr}
    return Comparison(tuple(cases), hist, runs)


def motion_cases(scene: StatueScene, motion, settings: SimSettings, contact: ContactSettings,
                 free_time: float = 3.0, label: str | None = None, model: RockingModel | None = None,
                 calib: dict | None = None, spread: bool = False, e_user: tuple = (None, None),
                 motion_y=None) -> Comparison:
    """The user's motion on the free-standing statue. Checks: ``model`` (the user's 2D model,
    default eq. 15's e, or ``e_user``); with ``calib`` (restitution.calibrate_restitution) the peak
    rotation of 2D given 3D's e is added as a diagnostic. ``motion_y``: the record's horizontal
    component across the direction, run in 3D beside ``motion`` (the 2D model has ``motion`` only:
    the cases say how far the second component takes the 3D body from the 2D prediction; a miss
    names that component's PGA).

    ``spread``: also run the models' own sensitivity (2D with e x 0.99 and x 1.01, 2D with rtol 1e-6
    and 1e-10, 3D with dt / 2) and store the range of the peak rotation in the case's ``spread``
    field, so the reader sees whether the 2D-3D difference lies inside it."""
    model = user_model(scene, *e_user) if model is None else model
    tag = label or motion.label
    t_end = motion.end + free_time
    r2 = simulate_2d(model, motion, t_end=t_end, dt_out=DT_OUT_2D)
    r3 = simulate_statue(scene, motion, settings=settings, contact=contact, free_time=free_time, motion_y=motion_y)
    scr = screen(model, motion, r3, contact, t_end)
    cases = [Case.equal(f"{tag}: overturn", r2.overturned, r3.overturned, quantity="overturn")]
    lift_cs, lifts = _liftoff_cases(tag, model, motion, r2, r3, t_end)
    cases += lift_cs
    runs = {tag: r3.to_dict() | {"screen": scr}}
    if not lifts:
        cases.append(no_lift_case(tag, r2, r3))
    if not r2.overturned and not r3.overturned and lifts:
        q2, q3 = max(r2.theta_max_L, r2.theta_max_R), max(r3.theta_max_L, r3.theta_max_R)
        case = Case.relative(f"{tag}: peak rotation", "rad", q2, q3, 0.05, quantity="peak rotation")
        if spread:
            def peak2(m, **kw):
                r = simulate_2d(m, motion, t_end=t_end, **kw)
                return math.nan if r.overturned else max(r.theta_max_L, r.theta_max_R)

            sp2 = {"2D e x0.99": peak2(user_model(scene, *e_user, scale=0.99)),
                   "2D e x1.01": peak2(user_model(scene, *e_user, scale=1.01)),
                   "2D rtol 1e-6": peak2(model, rtol=1e-6), "2D rtol 1e-10": peak2(model, rtol=1e-10)}
            r3h = simulate_statue(scene, motion, settings=replace(settings, dt=settings.dt / 2), contact=contact,
                                  free_time=free_time, motion_y=motion_y)
            sp3 = {"3D dt / 2": math.nan if r3h.overturned else max(r3h.theta_max_L, r3h.theta_max_R)}
            v2 = [q2] + [v for v in sp2.values() if math.isfinite(v)]
            v3 = [q3] + [v for v in sp3.values() if math.isfinite(v)]
            sp = sp2 | sp3 | {"2D range": [min(v2), max(v2)], "3D range": [min(v3), max(v3)],
                              "2D relative spread": (max(v2) - min(v2)) / q2}
            overlap = min(v2) <= max(v3) and min(v3) <= max(v2)
            why = (f"rocking under a record is sensitive to every impact: the 2D peak ranges over "
                   f"{min(v2):.4f}-{max(v2):.4f} rad ({sp['2D relative spread'] * 100:.0f} % of the nominal) for "
                   f"e +-1 % and rtol 1e-6..1e-10, the 3D peak over {min(v3):.4f}-{max(v3):.4f} rad for dt and "
                   f"dt / 2; the two ranges {'overlap' if overlap else 'do not overlap'}")
            case = replace(case, spread=sp, why=why)
            runs[f"{tag} (3D dt / 2)"] = r3h.to_dict()
        elif not case.met:
            case = replace(case, why=f"3D peak {q3:.4f} rad against 2D {q2:.4f} rad: one record's peak is sensitive "
                                     "to every impact (the models' own spread is computed without --quick; the "
                                     "statistical check over records is --records N)")
        cases.append(case)
        if calib is not None:
            rd = simulate_2d(model_2d(scene, calib), motion, t_end=t_end)
            if not rd.overturned:
                cases.append(Case.relative(f"{tag}: peak rotation (2D given 3D's e)", "rad",
                                           max(rd.theta_max_L, rd.theta_max_R), q3, 0.05,
                                           quantity="peak rotation").as_diagnostic(DIAG_WHY))
    if motion_y is not None:
        why = (f"the 3D body also feels the component across the direction (PGA {motion_y.pga / G:.3f} g, "
               f"along it {motion.pga / G:.3f} g), which the 2D model has not")
        cases = [c if c.met or c.status != "missed" else replace(c, why=(c.why + "; " if c.why else "") + why)
                 for c in cases]
        runs[tag]["motion_y_pga_g"] = motion_y.pga / G
    cases = [c.screened(scr) for c in cases]
    t2, y2 = _hist2d(r2)
    return Comparison(tuple(cases), {tag: {"t2": t2, "y2": y2, "t3": r3.t, "y3": r3.theta, "label": "theta (rad)"}},
                      runs)
