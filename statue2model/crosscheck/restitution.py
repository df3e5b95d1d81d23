"""Restitution in the cross-check: the 3D scene's own e, and the two 2D models that differ by their e.

* :func:`calibrate_restitution`: the 3D scene's effective restitution, measured on free rocking
  (eq. 43) for releases at RELEASES x delta on each pivot, i.e. per impact speed;
* :func:`restitution_cases`: each calibrated e (e_L and e_R, every release) against eq. 15
  (target E_TARGET, 5 %), screened;
* :func:`user_model`: the 2D model *as the user runs it* (eq. 15's e, or a prototype test's) - the
  checks use it;
* :func:`model_2d`: the 2D model given the e the 3D scene has (its table e(|theta'-|)) - the
  diagnostics ("2D given 3D's e", DIAG_WHY) use it.

Example
-------
>>> from statue2model.crosscheck.statue_scene import StatueScene
>>> sc = StatueScene.block(b=0.1, h=0.5, m=100.0)
>>> round(impact_speed(sc.params, "R", sc.params.delta_R), 3)   # |theta'-| after a release at delta_R, rad/s
0.749
"""
from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from ..hazard import motions
from ..rocking.model import Restitution, RockingModel
from .case import Case
from .contact import ContactSettings, effective_e
from .screen import contact_demand_2d, slip_of, validity_screen
from .statue_scene import StatueScene, simulate_statue
from .world import SimSettings

E_TARGET = 0.05
"""Target of each calibrated 3D restitution against eq. 15 (relative)."""
RELEASES = (0.1, 0.3, 0.5, 0.7)
"""Release angles (fractions of delta) of the restitution calibration."""
DIAG_WHY = "2D given 3D's e (the restitution calibrated on the 3D scene): a diagnostic, not a check"


def impact_speed(params, side: str, peak: float) -> float:
    """|theta'| (rad/s) with which a body that peaked at |theta| = ``peak`` on pivot ``side`` comes
    back to theta = 0 (free rocking energy, MODEL.md section 2)."""
    d, inertia, de = (params.d_R, params.I_R, params.delta_R) if side == "R" else (params.d_L, params.I_L,
                                                                                    params.delta_L)
    return math.sqrt(max(0.0, 2 * params.m * params.g * d * (math.cos(de - abs(peak)) - math.cos(de)) / inertia))


def calibrate_restitution(scene: StatueScene, settings: SimSettings, contact: ContactSettings,
                          releases=RELEASES, t_end: float = 1.5) -> dict:
    """The 3D scene's effective restitution, measured on free rocking (eq. 43), not assumed.

    The body is released from rest at f delta_R on the right pivot (its first two peaks give e_L,
    the landing on the left edge) and at f delta_L on the left pivot (e_R), for f in ``releases``.
    Each release gives one (impact speed |theta'-|, e) pair; the 3D e depends on the speed, so the
    diagnostic 2D model ("2D given 3D's e") gets the table e(|theta'-|) (MODEL.md section 2).
    ``e_L`` / ``e_R``: the values at f = 0.5. ``points``: every release with its raw e, the 3D pivot
    slip (m) and yaw (rad), for :func:`restitution_cases`."""
    p = scene.params
    out = {"releases": list(releases), "e_L_theory": p.e_L, "e_R_theory": p.e_R, "points": []}
    for side in ("R", "L"):
        land = "L" if side == "R" else "R"
        pts = []
        for f in releases:
            th0 = f * p.delta_R if side == "R" else -f * p.delta_L
            r = simulate_statue(scene, motions.free(), theta0=th0, t_end=t_end, settings=settings,
                                contact=contact, dt_out=settings.dt)
            pk = r.peak_theta
            if not r.finite:
                raise RuntimeError(f"the 3D free rocking from {f:g} delta on the {side} pivot did not stay finite")
            # no second peak above the peak floor (1e-4 rad): the rebound is below what the run resolves,
            # e taken as 0 (a squat body's plastic impact), flagged
            no_rebound = pk.size < 2
            e = 0.0 if no_rebound else effective_e(p, pk[0], pk[1], side)
            first = pk[0] if pk.size else th0
            pts.append((impact_speed(p, side, first), e, f))
            out["points"].append({"side": land, "release_frac": f, "theta0": th0, "speed": pts[-1][0], "e": e,
                                  "no_rebound": no_rebound,
                                  "e_theory": getattr(p, f"e_{land}"), "slip": slip_of(r),
                                  "yaw": float(np.abs(r.yaw).max(initial=0.0)),
                                  "tilt_out": float(np.abs(r.tilt_out).max(initial=0.0))})
        pts.sort()
        out[f"e_{land}_table"] = {"speeds": [x[0] for x in pts], "values": [min(1.0, x[1]) for x in pts],
                                  "release_frac": [x[2] for x in pts]}
        mid = min(pts, key=lambda x: abs(x[2] - 0.5))
        out[f"e_{land}"] = mid[1]
    return out


def restitution_cases(scene: StatueScene, calib: dict, contact: ContactSettings, t_end: float = 1.5) -> list:
    """Each calibrated 3D restitution (both sides, every release) against eq. 15: a check (E_TARGET),
    screened (the 2D free rocking's friction demand - no normal-force check; the 3D run's slip and
    yaw)."""
    p = scene.params
    model = RockingModel.housner(p)
    cases = []
    for pt in calib["points"]:
        land, side = pt["side"], "R" if pt["side"] == "L" else "L"
        d = contact_demand_2d(model, motions.free(), t_end, theta0=pt["theta0"])
        scr = validity_screen(d["mu_required"], d["n_min"], pt["slip"], pt["yaw"], contact.friction**2,
                              normal_force=False, scene_words="")
        c = Case.relative(f"restitution e_{land}: release {pt['release_frac']:g} delta_{side} "
                          f"(|theta'-| = {pt['speed']:.2f} rad/s)", "-", pt["e_theory"], pt["e"], E_TARGET,
                          note="3D effective e (eq. 43, first two peaks of free rocking; contact restitution 0) "
                               "against eq. 15 (angular momentum)", quantity=f"restitution e_{land}")
        if not c.met and scr["applicable"]:
            off = (f"{100 * (pt['e'] / pt['e_theory'] - 1):+.1f} %" if pt["e_theory"] > 0 else
                   f"{pt['e'] - pt['e_theory']:+.3f}")
            c = replace(c, why=f"3D e_{land} is {off} from eq. 15 at "
                               f"{pt['speed']:.2f} rad/s (3D yaw {scr['yaw_deg']:.2f} deg, out-of-plane tilt "
                               f"{math.degrees(pt['tilt_out']):.2f} deg, pivot slip {scr['slip_mm']:.2f} mm)")
        cases.append(c.screened(scr))
    return cases


def user_model(scene: StatueScene, e_L: float | None = None, e_R: float | None = None, scale: float = 1.0
               ) -> RockingModel:
    """The 2D model as the user runs it: the scene's parameters, the restitution of eq. 15, or the
    e_L / e_R of a prototype test (the configuration's [model] e_L, e_R) where given; ``scale``
    multiplies e (the sensitivity study)."""
    p = scene.params
    eL = p.e_L if e_L is None else e_L
    eR = p.e_R if e_R is None else e_R
    return RockingModel.housner(p, e_L=min(1.0, scale * eL), e_R=min(1.0, scale * eR))


def model_2d(scene: StatueScene, calib: dict | None = None, table: bool = True, scale: float = 1.0
             ) -> RockingModel:
    """The diagnostic 2D model "given 3D's e": the scene's parameters and the restitution the 3D
    scene has (``calib`` from :func:`calibrate_restitution`: its table e(|theta'-|), or its
    constants if ``table`` is False); without ``calib``, eq. 15's (= :func:`user_model`). ``scale``
    multiplies e (the sensitivity study)."""
    p = scene.params
    if calib is None:
        return user_model(scene, scale=scale)
    es = {}
    for side in ("L", "R"):
        tab = calib.get(f"e_{side}_table")
        if table and tab and len(tab["speeds"]) > 1:
            es[side] = Restitution.table(tab["speeds"], [min(1.0, scale * v) for v in tab["values"]], f"e_{side}")
        else:
            es[side] = min(1.0, scale * calib[f"e_{side}"])
    return RockingModel.housner(p, e_L=es["L"], e_R=es["R"])
