"""The isolator cases of the cross-check: free vibration of the top plate, the isolated statue
(plate acceleration, efficiency, displacement, capacity) and the plate's noise floor at rest.

* isolator free vibration: period vs 2 pi sqrt(R_hat / g) (2 %), per-cycle decay
  vs 4 mu R_hat (10 %), with the rolling friction mapped (c = mu r) and then
  calibrated (the faceted grooves and inelastic ball contacts dissipate by
  themselves: measured at mu = 0 and taken off): a :class:`FreeVibration`, the Comparison and the
  calibration (the 3D rolling friction ``mu_3d`` the isolated statue then runs with);
* the isolated statue under the user's motion: peak absolute plate acceleration
  3D vs the 2D plate (isolator/time_history.py), and the efficiency; and whether the plate
  passes the isolator's capacity (the design's) in 2D and in 3D (must agree).

Example
-------
>>> import numpy as np
>>> from statue2model.crosscheck.isolator_cases import lowpass, window_mean
>>> a = np.r_[np.zeros(50), np.ones(50)]
>>> float(window_mean(a, 0.001, 0.004)[75])
1.0
>>> bool(abs(lowpass(np.ones(100), 0.001).mean() - 1.0) < 1e-9)
True
"""
from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from ..hazard import motions
from ..isolator.coupled import simulate_coupled
from ..isolator.device import Isolator
from ..isolator.time_history import simulate as plate_2d
from .case import Case, Comparison
from .contact import ContactSettings
from .isolator_scene import simulate_isolator
from .world import SimSettings


@dataclass(frozen=True, eq=False)
class FreeVibration:
    """What :func:`isolator_free_cases` returns: ``comparison`` (its cases, the plate's time history,
    the 3D runs) and ``calibration`` ({'mu', 'rolling_mapped', 'decay_mapped', ...; 'mu_3d': the
    3D rolling friction the isolated statue runs with, with ``calibrate`` and mu > 0}, mu
    dimensionless, decays in m)."""

    comparison: Comparison
    calibration: dict


def isolator_free_cases(iso_scene, settings: SimSettings, contact: ContactSettings, u0: float | None = None,
                        cycles: float = 2.2, calibrate: bool = True) -> FreeVibration:
    """Free vibration of the top plate (no statue) from u0 (default: 60 % of the balls'
    travel, at most 90 % of the isolator's capacity): period, and per-cycle decay with the
    mapped and with the calibrated rolling friction. Returns its :class:`FreeVibration`."""
    sc = replace(iso_scene, statue=None)
    g = settings.g
    T = 2 * math.pi * math.sqrt(sc.R_hat / g)
    if u0 is None:
        u0 = min(1.2 * (sc.geom.opening_radius - sc.r), 0.9 * sc.travel_capacity)
    t_end = cycles * T
    meshes = {w: sc.plate_mesh(w) for w in ("bottom", "top")}
    iso2 = Isolator(R=sc.R, r=sc.r, M=sc.M, mu=sc.mu, g=g, capacity=sc.travel_capacity)
    r2 = plate_2d(iso2, motions.free(), u0=u0, t_end=t_end, dt_out=0.005)
    runs, hist = {}, {}

    def run(mu, tag):
        r = simulate_isolator(replace(sc, mu=mu), motions.free(), u0=u0, t_end=t_end, settings=settings,
                              contact=contact, meshes=meshes, dt_out=0.002)
        runs[tag] = r.to_dict()
        return r

    def decay(r):
        pk = np.abs(r.peaks_u)
        pk = np.concatenate([[abs(u0)], pk])
        return float(pk[0] - pk[2]) if pk.size >= 3 else math.nan

    def period(r):
        pt = r.peaks_t
        return float(2 * pt[0]) if pt.size == 1 else float(pt[1] - pt[0]) * 2 if pt.size >= 2 else math.nan

    r_nom = run(sc.mu, "isolator free vibration (mu mapped)")
    target_decay = 4 * sc.mu * sc.R_hat
    cases = [Case.relative("isolator free vibration: period", "s", T, _first_period(r_nom, u0), 0.02,
                           note="2 pi sqrt(R_hat / g); 3D: twice the time between the first two extrema",
                           quantity="isolator period")]
    cases.append(Case.relative("isolator free vibration: decay per cycle (c = mu r)", "m", target_decay,
                               decay(r_nom), 0.10, note="rollingFriction mapped, not calibrated",
                               quantity="friction decay per cycle"))
    calib = {"mu": sc.mu, "rolling_mapped": sc.mu * sc.r / contact.friction, "decay_mapped": decay(r_nom)}
    hist["isolator free vibration"] = {"t2": r2.t, "y2": r2.u, "t3": r_nom.t, "y3": r_nom.u, "label": "u (m)"}
    if calibrate and sc.mu > 0:
        r0 = run(0.0, "isolator free vibration (mu = 0)")
        d0, d1 = decay(r0), decay(r_nom)
        calib["decay_at_mu0"] = d0
        calib["mu0_equivalent"] = d0 / (4 * sc.R_hat)
        calib["period_mu0"] = _first_period(r0, u0)
        if cases[1].met:          # the mapping c = mu r already gives 4 mu R_hat: keep it
            calib["mu_3d"] = sc.mu
            return FreeVibration(Comparison(tuple(cases), hist, runs), calib)
        mu_cal = sc.mu * (target_decay - d0) / (d1 - d0) if d1 > d0 else sc.mu
        mu_cal = max(mu_cal, 0.0)
        r_cal = run(mu_cal, "isolator free vibration (mu calibrated)")
        calib.update(mu_3d=mu_cal, decay_calibrated=decay(r_cal))
        cases.append(Case.relative("isolator free vibration: decay per cycle (calibrated)", "m", target_decay,
                                   decay(r_cal), 0.10, quantity="friction decay per cycle",
                                   note=f"mu_3d = {mu_cal:.5f} (the grooves alone dissipate as mu = "
                                        f"{calib['mu0_equivalent']:.5f})"))
        hist["isolator free vibration"]["t3"], hist["isolator free vibration"]["y3"] = r_cal.t, r_cal.u
        cases[0] = Case.relative("isolator free vibration: period", "s", T, _first_period(r_cal, u0), 0.02,
                                 note=cases[0].note, quantity="isolator period")
    return FreeVibration(Comparison(tuple(cases), hist, runs), calib)


def _first_period(r, u0) -> float:
    """Period from the zero crossings of u (friction shifts the extrema, not the crossings)."""
    t, u = r.t, r.u
    s = np.sign(u)
    idx = np.flatnonzero(s[1:] * s[:-1] < 0)
    cross = [t[i] + (t[i + 1] - t[i]) * u[i] / (u[i] - u[i + 1]) for i in idx]
    if len(cross) >= 3:
        return float(cross[2] - cross[0])
    if len(cross) == 2:
        return float(2 * (cross[1] - cross[0]))
    return math.nan


TRACE = ("Traced (benchmarks/bench_crosscheck_speed.py, designed isolator of the default scan: R 2 m, r 25 mm, "
         "4 s record 0.2 g, statue fixed): the 3D excess is the contact solver's, not the friction mapping; "
         "3D / 2D 20 Hz peak 1.59 at dt 0.5 ms, 50 iterations, 4 mm lattice; 2.12 / 1.22 at 10 / 200 iterations; "
         "1.78 / 1.16 at dt 1 / 0.25 ms; 1.27 / 1.11 / 0.96 with 8 / 16 / 25 mm facets; 1.71 with mu = 0 in "
         "both (friction off); same free-standing. Converged (25 mm facets, dt 0.25 ms, 200 iterations): "
         "0.265 vs 2D 0.269 m/s^2 (1.5 %), displacement 73.0 vs 75.6 mm (3.4 %). Flat tangent tiles "
         "(--groove tiles: convex contacts, no facet edges) at dt 0.5 ms, 50 iterations: 0.94-0.98.")
"""The measured trace of the plate-acceleration discrepancy, quoted in the acceleration cases' note."""

ACC_CUTOFF = 20.0
"""Low-pass cutoff, Hz, of the plate accelerations compared (see isolated_statue_cases)."""


def lowpass(a: np.ndarray, dt: float, fc: float = ACC_CUTOFF) -> np.ndarray:
    """Zero-phase 4th-order Butterworth low-pass of a signal sampled every ``dt`` s at ``fc`` Hz."""
    from scipy import signal

    a = np.asarray(a, dtype=float)
    if a.size < 30 or fc >= 0.5 / dt:
        return a
    sos = signal.butter(4, fc, fs=1.0 / dt, output="sos")
    return signal.sosfiltfilt(sos, a)


def window_mean(a: np.ndarray, dt: float, window: float) -> np.ndarray:
    """Moving average over ``window`` s (the velocity change over the window / window)."""
    n = max(1, round(window / dt))
    return np.convolve(np.asarray(a, dtype=float), np.ones(n) / n, mode="same")


def groove_label(sc) -> str:
    """How an IsolatorScene's grooves are modelled, in words."""
    if sc.groove == "tiles":
        return f"flat tangent tiles of {sc.tile_size * 1e3:g} mm"
    return "the CNC mesh" if sc.groove == "cnc" else f"a {sc.grid * 1e3:g} mm lattice"


def isolated_statue_cases(iso_scene, motion, settings: SimSettings, contact: ContactSettings,
                          mu_3d: float | None = None, free_time: float = 2.0, cutoff: float = ACC_CUTOFF,
                          mount: str = "rigid", label: str = "isolated statue", model=None
                          ) -> Comparison:
    """The statue on the isolator under ``motion``: peak absolute plate acceleration and the
    efficiency (peak plate / PGA), 3D against the 2D plate (Coulomb) with the same mu.

    Like with like: the 3D plate acceleration of every engine step contains the contact impulses
    of the balls on the groove facets (spikes of a few m/s^2 lasting one step); the 2D plate's is
    smooth but for the friction jump at each velocity reversal. Both are compared raw and after the
    same zero-phase low-pass at ``cutoff`` Hz (default 20 Hz: the band of a strong-motion
    accelerometer on the plate and of engineering accelerograms; the statue's rocking responds to
    far lower frequencies: p ~ 3-5 rad/s, pulses of 1-4 Hz). The target applies to the filtered
    peak; the raw ones are reported.

    ``mount='rigid'`` (default): statue and top plate are one rigid body - what the 2D plate model
    assumes (the statue does not uplift) - so the plate response is compared like with like;
    ``mount='contact'``: the statue stands free on the plate (it may rock: the rocking check);
    with ``model`` (the user's RockingModel) its overturning and the capacity are then checked
    against the coupled 2D model (plate + rocking statue, statue2model.isolator.coupled: the 2D
    model as the user runs it), and a counted case "fails (overturns or capacity exceeded)"
    compares the failure itself. A 2D run stops where the plate passes the capacity (the model
    does not follow the balls out of their grooves): when it stops there before the 3D body's
    own outcome, a separate overturn or capacity case that misses becomes a diagnostic that
    says so.
    Case names start with ``label``; returns their Comparison (cases, histories, runs)."""
    g = settings.g
    dt = settings.dt
    cap = iso_scene.travel_capacity
    iso2 = Isolator(R=iso_scene.R, r=iso_scene.r, M=iso_scene.M, mu=iso_scene.mu, g=g, capacity=cap)
    t_end = motion.end + free_time
    r2 = plate_2d(iso2, motion, t_end=t_end, dt_out=dt)
    sc3 = iso_scene if mu_3d is None else replace(iso_scene, mu=mu_3d)
    r3 = simulate_isolator(sc3, motion, t_end=t_end, settings=settings, contact=contact, dt_out=0.005, mount=mount)
    # both runs stop where the plate passes the capacity: compare up to the earlier stop
    a2_all = r2.acc_abs
    n2 = int(np.argmin(np.isfinite(a2_all))) if not np.all(np.isfinite(a2_all)) else a2_all.size
    n_common = min(n2, r3.acc_step.size)
    a2, a3 = a2_all[:max(n_common, 1)], r3.acc_step[:max(n_common, 1)]
    # (a run stopped at the capacity within a few steps leaves less than a filter window: 0)
    a2f = float(np.abs(lowpass(a2, dt, cutoff)).max(initial=0.0))
    a3f = float(np.abs(lowpass(a3, dt, cutoff)).max(initial=0.0))
    a3w = float(np.abs(window_mean(a3, dt, 0.005)).max(initial=0.0))
    a2w = float(np.abs(window_mean(a2, dt, 0.005)).max(initial=0.0))
    why = (f"raw per-step peaks 2D {r2.acc_abs_max:.3f}, 3D {r3.acc_abs_max:.3f} m/s^2 (ball-facet contact "
           f"impulses); 5 ms window mean 2D {a2w:.3f}, 3D {a3w:.3f}; compared: both low-passed at {cutoff:g} Hz; "
           f"engine dt {dt * 1e3:g} ms, {settings.solver_iterations} solver iterations, grooves: "
           f"{groove_label(sc3)}. {TRACE}")
    cases = [Case.relative(f"{label}: peak plate acceleration", "m/s^2", a2f, a3f, 0.10,
                           note=f"absolute top-plate acceleration, both low-passed at {cutoff:g} Hz "
                                "(4th-order Butterworth, zero phase)", quantity="peak plate acceleration"),
             Case.relative(f"{label}: peak plate acceleration (raw)", "m/s^2", r2.acc_abs_max,
                           r3.acc_abs_max, 0.10, note="every engine step, unfiltered",
                           quantity="peak plate acceleration"),
             Case.relative(f"{label}: efficiency (peak plate / PGA)", "-", a2f / motion.pga,
                           a3f / motion.pga if motion.pga > 0 else math.nan, 0.10, quantity="efficiency",
                           note=f"filtered at {cutoff:g} Hz"),
             Case.relative(f"{label}: peak plate displacement", "m", r2.u_max, r3.u_max, 0.10,
                           quantity="peak plate displacement")]
    cases = [replace(c, note=(c.note + "; " + why) if "acceleration" in c.name else c.note) for c in cases]
    overturn = bool(r3.statue_overturned)
    coupled = None
    if mount == "contact" and model is not None:
        coupled = simulate_coupled(iso2, model, motion, t_end=t_end, dt_out=0.01)
    ot2 = bool(coupled.overturned) if coupled is not None else False
    cap2 = coupled if coupled is not None else r2
    t_ot3 = r3.t_overturn
    side2 = ("the coupled 2D model (plate + rocking statue)" if coupled is not None else
             "the 2D plate model (the statue does not uplift)")
    c_ot = Case.equal(f"{label}: statue overturns", ot2, overturn, quantity="overturn",
                      note=f"2D: {side2}; 3D outcome: {r3.outcome}"
                           + (f" at t = {t_ot3:.3f} s" if t_ot3 is not None else ""))

    def when(r):
        return "not exceeded" if not r.capacity_exceeded else f"at t = {r.t_capacity:.3f} s"

    c_cap = None
    if math.isfinite(cap):
        c_cap = Case.equal(f"{label}: isolator capacity exceeded", cap2.capacity_exceeded,
                           r3.capacity_exceeded, quantity="capacity exceeded",
                           note=f"|u| against the capacity {cap * 1000:.1f} mm: 2D {when(cap2)}, 3D {when(r3)}")
    if coupled is not None:
        t3 = min(x for x in (t_ot3, r3.t_capacity, math.inf) if x is not None)
        if cap2.capacity_exceeded and not ot2 and cap2.t_capacity is not None and cap2.t_capacity < t3:
            stop = (f"the 2D run stops where the plate passes the capacity, t = {cap2.t_capacity:.3f} s (it does "
                    f"not follow the balls out of their grooves); 3D went on: {r3.outcome}"
                    + (f" at t = {t3:.3f} s" if math.isfinite(t3) else "")
                    + "; the failure itself is the counted case (fails)")
            c_ot = c_ot if c_ot.met else c_ot.as_diagnostic(stop)     # a miss the stop explains
            c_cap = c_cap.as_diagnostic(stop) if c_cap is not None and not c_cap.met else c_cap
    cases.append(c_ot)
    if c_cap is not None:
        cases.append(c_cap)
    if coupled is not None:
        cases.append(Case.equal(f"{label}: fails (overturns or capacity exceeded)",
                                ot2 or bool(cap2.capacity_exceeded), overturn or bool(r3.capacity_exceeded),
                                quantity="failure", note=f"2D: {coupled.outcome}; 3D: {r3.outcome} (either "
                                                         "failure counts: the conservative reading)"))
    hist = {f"{label}: plate": {"t2": r2.t, "y2": r2.u, "t3": r3.t, "y3": r3.u, "label": "u (m)"},
            f"{label}: plate acceleration (low-passed)": {
                "t2": r2.t[:a2.size], "y2": lowpass(a2, dt, cutoff), "t3": np.arange(a3.size) * dt,
                "y3": lowpass(a3, dt, cutoff), "label": f"absolute plate acc., {cutoff:g} Hz low-pass (m/s^2)"}}
    return Comparison(tuple(cases), hist, {label: r3.to_dict() | {"acc_abs_max_filtered": a3f,
                                                                  "acc_abs_max_window5ms": a3w,
                                                                  "acc_2d_filtered": a2f, "cutoff_hz": cutoff,
                                                                  "capacity_2d": r2.to_dict()["capacity"],
                                                                  "capacity_exceeded_2d": r2.capacity_exceeded,
                                                                  "t_capacity_2d": r2.t_capacity}})


def plate_at_rest(iso_scene, settings: SimSettings, contact: ContactSettings, *, t_end: float = 3.0,
                  skip: float = 0.25, mount: str = "contact", cutoff: float = ACC_CUTOFF, **kw) -> dict:
    """The 3D noise floor of the plate acceleration: the isolator (with its statue, mounted as
    ``mount``) at rest with no ground motion for ``t_end`` s. Returns the rms and the peak of the
    absolute plate acceleration (m/s^2), raw (every step) and low-passed at ``cutoff`` Hz, after the
    first ``skip`` s (the contacts settling), and the statue's largest rotation (rad)."""
    r = simulate_isolator(iso_scene, motions.free(), t_end=t_end, settings=settings, contact=contact,
                          dt_out=0.01, mount=mount, **kw)
    a = r.acc_step
    af = lowpass(a, settings.dt, cutoff)
    i0 = round(skip / settings.dt)
    a, af = a[i0:], af[i0:]
    if a.size == 0:
        a = af = np.array([math.nan])
    th = r.theta
    return {"mount": mount, "rms_filtered": float(np.sqrt(np.mean(af**2))), "peak_filtered": float(np.abs(af).max()),
            "rms_raw": float(np.sqrt(np.mean(a**2))), "peak_raw": float(np.abs(a).max()),
            "theta_max": float(np.nanmax(np.abs(th))) if th is not None and np.isfinite(th).any() else 0.0,
            "u_drift": float(np.abs(r.u).max()), "wall_time_s": r.wall_time, "outcome": r.outcome}
