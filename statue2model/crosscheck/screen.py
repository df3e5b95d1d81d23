"""The validity screen: does the 2D rocking model apply to a 3D run?

2D side: the friction |F| / N the 2D trajectory needs at the pivot and its smallest normal force
N / (m g) (:func:`contact_demand_2d`) against the scene's friction (contact.friction squared:
PyBullet multiplies the two bodies' coefficients). 3D side: the slip of the base points on the
floor (:func:`slip_of`) against SLIP_LIMIT and the yaw against YAW_LIMIT. One function builds the
screen (:func:`validity_screen`); :func:`screen` and :func:`screen_values` feed it one run, the
restitution cases and the overturning boundary their own numbers. A case the screen rejects is
'not applicable' (:meth:`statue2model.crosscheck.case.Case.screened`).

What counts as slip (:func:`slip_of`). The 2D model's assumption is a pivot that does not slide while
it carries the body: the slip is the pivot vertices' horizontal travel on the floor from where they
last touched down (Statue3DResult.max_pivot_slip: each contact phase on its own; from rest it covers
a standing base that slides) and, before the body first lifts off, the base centre's slide from its
start (sliding instead of rocking). After the first lift-off the base centre's displacement is not
slip: it sums the pivot slips of every contact phase (each already checked) and the base's turn about
a pivot vertex (a yaw of psi moves the centre by up to (b_L + b_R) / 2 x psi with no slip at all;
the yaw has its own limit), and a rigid drift of the whole body along a uniform floor leaves the
rocking unchanged. Measured on the default scan's design set (7 records x 10 PGA levels around the
2D medians; issue 28): the old reading (base centre over the whole run) dropped 17 of
70 runs as 'slips > 2 mm', 14 of them with every contact phase's pivot slip < 2 mm (drifts of 2-131 mm
grown over 2-56 upright phases, 4-19 s into the records); before lift-off no run slid more than 0.04 mm.

Slip and the outcome's decision. An overturning 3D run stops at |theta| = delta (statue_scene:
stop_on_overturn), the instant the 2D model calls overturning and where its contact demand
(:func:`contact_demand_2d`) stops too: slip during the fall past delta is never counted. Slip before
it is, however close to delta (during the excitation a body may pass a large theta and be pulled
back, MODEL.md section 3). Measured on the
same set: the three runs whose pivot slipped > 2 mm did so at theta / delta 0.04-0.28, 1.3-11 s before
overturning, and every yaw > 2 deg came at theta / delta < 0.48, >= 0.13 s before it; no earlier cut
(a fraction of delta) would keep any of them, so none is made.

Example
-------
>>> s = validity_screen(0.4, 0.8, 1e-3, 0.0, 1.0)
>>> s["applicable"], s["slip_mm"]
(True, 1.0)
>>> validity_screen(1.5, -0.1, 0.0, 0.0, 1.0)["reasons"][0]
"the 2D rocking needs friction 1.5 > the scene's 1"
"""
from __future__ import annotations

import math

import numpy as np

from ..rocking.engine import simulate as simulate_2d
from ..rocking.model import RockingModel
from .contact import ContactSettings

SLIP_LIMIT = 2e-3
"""Validity screen: largest horizontal slip, m, of the 3D base points on the floor (the pivot)."""
YAW_LIMIT = math.radians(2.0)
"""Validity screen: largest 3D yaw, rad (rotation about the vertical; the 2D model has none)."""


def contact_demand_2d(model: RockingModel, motion, t_end: float, dt: float = 2e-4, theta0: float = 0.0) -> dict:
    """What the 2D model's rocking-only assumption asks of the contact along its own trajectory:
    the friction coefficient |F| / N the pivot needs not to slide and the smallest normal force
    N / (m g) (< 0: the body would have to be pulled down, i.e. it takes off). F and N are the
    pivot's reaction from the motion of the centre of mass (ground frame, inertial force -m u_g''):
    F = m (x_G'' + u_g''), N = m (z_G'' + g); at rest F = m u_g'', N = m g.
    Returns {'mu_required', 'n_min', 't_mu', 't_n'} (up to overturning or t_end)."""
    p = model.params
    r = simulate_2d(model, motion, theta0=theta0, t_end=t_end, dt_out=dt)
    t, q, w = r.history["t"], r.history["theta"], r.history["theta_dot"]
    a = motion.acc(t) if motion.kind != "none" else np.zeros_like(t)
    g = p.g
    fx = a.copy()
    fz = np.full_like(t, g)
    pos, neg = q > 0, q < 0
    ph = p.delta_R - q[pos]
    qdd = -p.p_R**2 * (np.sin(ph) + a[pos] / g * np.cos(ph))
    fx[pos] = p.d_R * (np.cos(ph) * qdd + np.sin(ph) * w[pos] ** 2) + a[pos]
    fz[pos] = p.d_R * (np.sin(ph) * qdd - np.cos(ph) * w[pos] ** 2) + g
    ps = p.delta_L + q[neg]
    qdd = p.p_L**2 * (np.sin(ps) - a[neg] / g * np.cos(ps))
    fx[neg] = p.d_L * (np.cos(ps) * qdd - np.sin(ps) * w[neg] ** 2) + a[neg]
    fz[neg] = p.d_L * (-np.sin(ps) * qdd - np.cos(ps) * w[neg] ** 2) + g
    if r.overturned and r.overturn_time is not None:
        keep = t <= r.overturn_time
        t, fx, fz = t[keep], fx[keep], fz[keep]
    mu = np.where(fz > 0, np.abs(fx) / np.maximum(fz, 1e-12), np.inf)
    i, j = int(np.argmax(mu)), int(np.argmin(fz))
    return {"mu_required": float(mu[i]), "t_mu": float(t[i]), "n_min": float(fz[j] / g), "t_n": float(t[j])}


def slip_of(r3) -> float:
    """The 3D run's slip, m (module docstring): the pivot's (each contact phase from its touch-down,
    Statue3DResult.max_pivot_slip) or the standing base's slide from rest before the first lift-off
    (``uplift_time``; the whole run when it never lifts).

    >>> import numpy as np
    >>> from types import SimpleNamespace as R
    >>> r = R(t=np.array([0.0, 1.0, 2.0, 3.0]), slide=np.array([0.0, 5e-4, np.nan, 9e-3]),
    ...       uplift_time=1.5, max_pivot_slip=3e-3)
    >>> slip_of(r), slip_of(R(t=r.t, slide=r.slide, uplift_time=None, max_pivot_slip=1e-3))
    (0.003, 0.009)
    """
    t = np.asarray(r3.t, dtype=float)
    sl = np.asarray(r3.slide, dtype=float)
    if sl.size != t.size:
        raise ValueError(f"slip_of: slide has {sl.size} samples for {t.size} times")
    up = getattr(r3, "uplift_time", None)
    before = np.isfinite(sl) & (t < (math.inf if up is None else up))
    return max(float(r3.max_pivot_slip), float(np.abs(sl[before]).max(initial=0.0)))


def _jf(x: float) -> float | None:
    """A float for JSON (None if not finite: e.g. the infinite friction a take-off needs)."""
    return float(x) if math.isfinite(x) else None


def validity_screen(mu_required: float, n_min: float, slip: float, yaw: float, mu_scene: float, *,
                    normal_force: bool = True, scene_words: str = "the scene's ") -> dict:
    """The screen from its numbers: the friction the 2D trajectory needs (``mu_required``) against
    the scene's (``mu_scene``), the smallest 2D normal force ``n_min`` (N / (m g); checked > 0 if
    ``normal_force``), the 3D slip (m) against SLIP_LIMIT and yaw (rad) against YAW_LIMIT.
    ``scene_words``: how the friction reason names the scene's coefficient ('' in the restitution
    cases, which give the bare number). Returns {'applicable', 'reasons', 'mu_required', 'mu_scene',
    'n_min', 'slip_mm', 'yaw_deg', 'slip_limit_mm', 'yaw_limit_deg'}."""
    reasons = []
    if mu_required > mu_scene:
        reasons.append(f"the 2D rocking needs friction {mu_required:.3g} > {scene_words}{mu_scene:.3g}")
    if normal_force and n_min <= 0:
        reasons.append(f"the 2D rocking needs a negative normal force (N / mg = {n_min:.3g}: it takes off)")
    if slip > SLIP_LIMIT:
        reasons.append(f"3D pivot slips {slip * 1000:.1f} mm > {SLIP_LIMIT * 1000:g} mm")
    if yaw > YAW_LIMIT:
        reasons.append(f"3D body yaws {math.degrees(yaw):.2f} deg > {math.degrees(YAW_LIMIT):g} deg")
    return {"applicable": not reasons, "reasons": reasons, "mu_required": _jf(mu_required), "mu_scene": mu_scene,
            "n_min": n_min, "slip_mm": slip * 1000, "yaw_deg": math.degrees(yaw),
            "slip_limit_mm": SLIP_LIMIT * 1000, "yaw_limit_deg": math.degrees(YAW_LIMIT)}


def screen(model: RockingModel, motion, r3, contact: ContactSettings, t_end: float, theta0: float = 0.0
           ) -> dict:
    """The validity screen of one run of ``model`` under ``motion`` (from ``theta0`` rad, up to
    ``t_end`` s) and its 3D counterpart ``r3`` (a Statue3DResult or a list of them: the worst
    counts): :func:`validity_screen` of the 2D contact demand and the 3D slip (:func:`slip_of`)
    and yaw."""
    rs = r3 if isinstance(r3, (list, tuple)) else [r3]
    slip = max(slip_of(r) for r in rs)
    yaw = max(float(np.abs(r.yaw).max(initial=0.0)) for r in rs)
    return screen_values(model, motion, slip, yaw, contact, t_end, theta0)


def screen_values(model: RockingModel, motion, slip: float, yaw: float, contact: ContactSettings, t_end: float,
                  theta0: float = 0.0) -> dict:
    """:func:`screen` from the 3D run's numbers alone: its largest slip (m, :func:`slip_of`) and yaw
    (rad); for runs made elsewhere (the record ensemble's worker processes)."""
    d = contact_demand_2d(model, motion, t_end, theta0=theta0)
    return validity_screen(d["mu_required"], d["n_min"], slip, yaw, contact.friction**2)
