"""The comparison cases: the 2D model and the 3D scenes on the same statue and motions.

Each case gives one :class:`Case` (name, quantity, value_2d, value_3d, rel_error, target, met,
status) and the two time histories for the overlay plots. ``status`` is what counts:

* ``met`` / ``missed``: a check - the 2D model *as the user runs it* (restitution from eq. 15, or
  the e_L / e_R the configuration gives from a prototype test) against the 3D scene;
* ``diagnostic``: shown, never counted - the 2D model given the restitution the 3D scene has
  (:func:`calibrate_restitution`), i.e. "2D given 3D's e": it tells how much of a miss is e;
* ``not applicable``: the validity screen (:func:`screen`) found that the 3D body slides or twists,
  or that the 2D trajectory needs more friction than the scene has or a negative normal force:
  the 2D rocking model does not describe that run ("slides / twists: 2D not applicable"), the
  numbers are in the case's ``screen``.

Statue cases (:func:`compare`):

* restitution: every calibrated e (e_L and e_R, per release 0.1-0.7 delta, i.e. per impact speed)
  against eq. 15 (target 5 %);
* free rocking from theta0 = 0.5 delta_R: quarter period (1 %), first rebound peak (5 %);
* one-sine pulses at 0.8 x and 1.25 x the 2D minimum overturning amplitude: overturn (same),
  lift-off from the contacts (the non-pivot base edge above statue_scene.LIFT_HEIGHT; the 2D side
  at the same height, (b_L + b_R) sin|theta|; target 5 ms), peak rotation before the first impact
  (both read before their own first impact; 5 %), peak rotation (5 %);
* the overturning boundary of one-sine pulses at each frequency of a small grid, every band edge
  found by a fine 2D amplitude scan and bisection, the 3D edge bisected near it: ratio 3D / 2D
  within 10 % (:func:`boundary_cases`);
* the user's motion (--motion): overturn, lift-off, peak rotation (with both models' spread).

Isolator cases: statue2model.crosscheck.isolator_cases.

Example
-------
>>> from statue2model.crosscheck.compare import Case
>>> c = Case.relative("quarter period", "s", 0.4373, 0.4371, 0.01)
>>> c.met, c.status, c.as_diagnostic().status
(True, 'met', 'diagnostic')
"""
from __future__ import annotations

import math
from dataclasses import asdict, dataclass, field, replace

import numpy as np

from ..hazard import motions
from ..rocking.engine import simulate as simulate_2d
from ..rocking.model import RockingModel
from .contact import ContactSettings, effective_e
from .statue_scene import LIFT_HEIGHT, STATUE_SETTINGS, StatueScene, simulate_statue
from .world import SimSettings

DT_OUT_2D = 0.005
"""Output step of the 2D histories, s."""
LIFT_TARGET = 0.005
"""Target of the lift-off time, s (|3D - 2D|, both read at statue_scene.LIFT_HEIGHT)."""
E_TARGET = 0.05
"""Target of each calibrated 3D restitution against eq. 15 (relative)."""
BOUNDARY_TARGET = 0.10
"""Target of each overturning-boundary ratio 3D / 2D (|ratio - 1|)."""
SLIP_LIMIT = 2e-3
"""Validity screen: largest horizontal slip, m, of the 3D base points on the floor (the pivot)."""
YAW_LIMIT = math.radians(2.0)
"""Validity screen: largest 3D yaw, rad (rotation about the vertical; the 2D model has none)."""
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
        """The case with the validity screen ``scr`` (:func:`screen`) attached; 'not applicable'
        (with the numbers in ``why``) if the screen says the 2D model does not apply."""
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
    """Cases plus the time histories behind them: histories[name] = {'t2', 'y2', 't3', 'y3', 'label'}."""

    cases: tuple
    histories: dict = field(default_factory=dict)
    runs: dict = field(default_factory=dict)


def overturn_amplitude_2d(model: RockingModel, freq: float, kind: str = "sine", lo: float | None = None,
                          hi: float | None = None, tol: float = 1e-3, sign: float = 1.0,
                          free_time: float | None = None) -> float:
    """Smallest amplitude (m/s^2) of a one-sine (or one-cosine) pulse ``sign`` x amp of ``freq`` Hz
    that overturns the 2D model, by bisection (relative tolerance ``tol``) between ``lo`` (default the
    smaller uplift acceleration) and ``hi`` (20 x the larger); assumes one band. ``free_time``: s
    simulated after the pulse (default: the engine's). inf if ``hi`` does not overturn."""
    make = motions.sine_pulse if kind == "sine" else motions.cosine_pulse
    p = model.params
    lo = min(p.a_L, p.a_R) if lo is None else lo
    hi = 20 * max(p.a_L, p.a_R) if hi is None else hi

    def overturns(a: float) -> bool:
        m = make(sign * a, freq)
        return simulate_2d(model, m, **({} if free_time is None else {"t_end": m.end + free_time})).overturned

    if not overturns(hi):
        return math.inf
    while hi - lo > tol * hi:
        mid = 0.5 * (lo + hi)
        if overturns(mid):
            hi = mid
        else:
            lo = mid
    return hi


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


def lift_angle(params, height: float = LIFT_HEIGHT) -> float:
    """|theta| (rad) at which the non-pivot base edge of the 2D body is ``height`` m above the
    floor: (b_L + b_R) sin|theta| = height."""
    return math.asin(min(1.0, height / (params.b_L + params.b_R)))


def liftoff_time_2d(model: RockingModel, motion, t_end: float, height: float = LIFT_HEIGHT) -> float | None:
    """Lift-off of the 2D model read at the 3D criterion (statue_scene.LIFT_HEIGHT): the first time
    its non-pivot base edge is ``height`` m above the floor (None if never before ``t_end``)."""
    return threshold_time_2d(model, motion, lift_angle(model.params, height), t_end)


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


def overturn_grid(scene: StatueScene, model: RockingModel, freqs, factors, settings: SimSettings,
                  contact: ContactSettings, free_time: float = 3.0, progress=None) -> dict:
    """Overturn / no-overturn of the 2D ``model`` and the 3D scene on a one-cosine grid: for each
    frequency (Hz) the amplitudes ``factors`` x the 2D minimum overturning amplitude (frequencies
    without 2D overturning below 20 a_uplift are skipped). Every point also gets the 2D model's
    contact demand (:func:`contact_demand_2d`): it is *valid* (its rocking-only assumption holds
    for the 3D contact) if the friction it needs stays below the 3D friction coefficient
    (contact.friction squared: PyBullet multiplies the two bodies') and the normal force stays
    positive. Returns {'rows': [...], 'agree', 'total', 'agree_valid', 'total_valid', 'skipped'}."""
    mu_3d = contact.friction**2
    rows, skipped = [], []
    for f in freqs:
        f = float(f)
        a_ot = overturn_amplitude_2d(model, f, "cosine")
        if not math.isfinite(a_ot):
            skipped.append(f)
            continue
        for fac in factors:
            m = motions.cosine_pulse(float(fac) * a_ot, f)
            r2 = simulate_2d(model, m, t_end=m.end + free_time)
            d = contact_demand_2d(model, m, m.end + free_time)
            r3 = simulate_statue(scene, m, settings=settings, contact=contact, free_time=free_time, dt_out=0.01)
            valid = d["mu_required"] <= mu_3d and d["n_min"] > 0
            rows.append({"freq": f, "factor": float(fac), "amp_g": float(fac) * a_ot / model.params.g,
                         "overturn_2d": bool(r2.overturned), "overturn_3d": bool(r3.overturned),
                         "agree": bool(r2.overturned) == bool(r3.overturned), "valid_2d": bool(valid),
                         "mu_required": d["mu_required"], "n_min": d["n_min"],
                         "max_pivot_slip": r3.max_pivot_slip, "max_yaw": float(np.abs(r3.yaw).max(initial=0.0)),
                         "max_flight": r3.max_flight, "finite": r3.finite})
        if progress:
            progress(f)
    val = [r for r in rows if r["valid_2d"]]
    return {"rows": rows, "agree": sum(r["agree"] for r in rows), "total": len(rows),
            "agree_valid": sum(r["agree"] for r in val), "total_valid": len(val), "skipped": skipped,
            "mu_3d": mu_3d}


def _hist2d(r) -> tuple[np.ndarray, np.ndarray]:
    h = r.history
    return h["t"], h["theta"]


def _jf(x: float) -> float | None:
    """A float for JSON (None if not finite: e.g. the infinite friction a take-off needs)."""
    return float(x) if math.isfinite(x) else None


def slip_of(r3) -> float:
    """The 3D run's slip, m: the pivot's (from touch-down) or the standing base's (from rest)."""
    sl = np.abs(r3.slide[np.isfinite(r3.slide)]) if r3.slide.size else np.zeros(0)
    return max(r3.max_pivot_slip, float(sl.max(initial=0.0)))


def screen(model: RockingModel, motion, r3, contact: ContactSettings, t_end: float, theta0: float = 0.0
           ) -> dict:
    """The validity screen of one run: does the 2D rocking model apply to it?

    2D side: the friction |F| / N its trajectory needs at the pivot and its smallest normal force
    N / (m g) (:func:`contact_demand_2d`) against the scene's friction (contact.friction squared:
    PyBullet multiplies the two bodies' coefficients). 3D side: the slip of the base points on the
    floor (Statue3DResult.max_pivot_slip, or the standing base's slide if larger) against SLIP_LIMIT and the yaw against YAW_LIMIT (``r3``
    may be a Statue3DResult or a list of them: the worst counts). Returns {'applicable', 'reasons',
    'mu_required', 'mu_scene', 'n_min', 'slip_mm', 'yaw_deg', 'slip_limit_mm', 'yaw_limit_deg'}."""
    rs = r3 if isinstance(r3, (list, tuple)) else [r3]
    slip = max(slip_of(r) for r in rs)
    yaw = max(float(np.abs(r.yaw).max(initial=0.0)) for r in rs)
    return screen_values(model, motion, slip, yaw, contact, t_end, theta0)


def screen_values(model: RockingModel, motion, slip: float, yaw: float, contact: ContactSettings, t_end: float,
                  theta0: float = 0.0) -> dict:
    """:func:`screen` from the 3D run's numbers alone: its largest slip (m, :func:`slip_of`) and yaw
    (rad); for runs made elsewhere (the record ensemble's worker processes)."""
    d = contact_demand_2d(model, motion, t_end, theta0=theta0)
    mu = contact.friction**2
    reasons = []
    if d["mu_required"] > mu:
        reasons.append(f"the 2D rocking needs friction {d['mu_required']:.3g} > the scene's {mu:.3g}")
    if d["n_min"] <= 0:
        reasons.append(f"the 2D rocking needs a negative normal force (N / mg = {d['n_min']:.3g}: it takes off)")
    if slip > SLIP_LIMIT:
        reasons.append(f"3D pivot slips {slip * 1000:.1f} mm > {SLIP_LIMIT * 1000:g} mm")
    if yaw > YAW_LIMIT:
        reasons.append(f"3D body yaws {math.degrees(yaw):.2f} deg > {math.degrees(YAW_LIMIT):g} deg")
    return {"applicable": not reasons, "reasons": reasons, "mu_required": _jf(d["mu_required"]), "mu_scene": mu,
            "n_min": d["n_min"], "slip_mm": slip * 1000, "yaw_deg": math.degrees(yaw),
            "slip_limit_mm": SLIP_LIMIT * 1000, "yaw_limit_deg": math.degrees(YAW_LIMIT)}


RELEASES = (0.1, 0.3, 0.5, 0.7)
"""Release angles (fractions of delta) of the restitution calibration."""


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
    screened (the 2D free rocking's contact demand; the 3D run's slip and yaw)."""
    p = scene.params
    model = RockingModel.housner(p)
    cases = []
    for pt in calib["points"]:
        land, side = pt["side"], "R" if pt["side"] == "L" else "L"
        d = contact_demand_2d(model, motions.free(), t_end, theta0=pt["theta0"])
        reasons = []
        if d["mu_required"] > contact.friction**2:
            reasons.append(f"the 2D rocking needs friction {d['mu_required']:.3g} > {contact.friction**2:.3g}")
        if pt["slip"] > SLIP_LIMIT:
            reasons.append(f"3D pivot slips {pt['slip'] * 1000:.1f} mm > {SLIP_LIMIT * 1000:g} mm")
        if pt["yaw"] > YAW_LIMIT:
            reasons.append(f"3D body yaws {math.degrees(pt['yaw']):.2f} deg > {math.degrees(YAW_LIMIT):g} deg")
        scr = {"applicable": not reasons, "reasons": reasons, "mu_required": _jf(d["mu_required"]),
               "mu_scene": contact.friction**2, "n_min": d["n_min"], "slip_mm": pt["slip"] * 1000,
               "yaw_deg": math.degrees(pt["yaw"]), "slip_limit_mm": SLIP_LIMIT * 1000,
               "yaw_limit_deg": math.degrees(YAW_LIMIT)}
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
    from ..rocking.model import Restitution

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


DIAG_WHY = "2D given 3D's e (the restitution calibrated on the 3D scene): a diagnostic, not a check"


def free_rocking_cases(scene: StatueScene, settings: SimSettings, contact: ContactSettings,
                       theta0_frac: float = 0.5, t_end: float = 3.0, model: RockingModel | None = None
                       ) -> tuple[list, dict, dict]:
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
    return cases, hist, {"free rocking": r3.to_dict() | {"screen": scr}}


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


def _liftoff_cases(tag: str, model: RockingModel, motion, r2, r3, t_end: float) -> list:
    """Lift-off from the contacts: does it lift at all (same in both), when (LIFT_TARGET), and the
    force-based lift-off as a diagnostic."""
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
    return cases


def pulse_cases(scene: StatueScene, settings: SimSettings, contact: ContactSettings, freq: float = 1.5,
                factors=(0.8, 1.25), free_time: float = 3.0, model: RockingModel | None = None,
                diag_model: RockingModel | None = None) -> tuple[list, dict, dict]:
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
        cs += _liftoff_cases(tag, model, m, r2, r3, m.end)
        p2, p3 = peak_before_first_impact_2d(r2), peak_before_first_impact_3d(r3)
        if p2 is not None or p3 is not None:
            cs.append(Case.relative(f"{tag}: peak rotation before the first impact", "rad", p2, p3, 0.05,
                                    quantity="peak rotation",
                                    note="each read before its own first impact (theta changes sign)"))
        if not r2.overturned and not r3.overturned:
            cs.append(Case.relative(f"{tag}: peak rotation", "rad", max(r2.theta_max_L, r2.theta_max_R),
                                    max(r3.theta_max_L, r3.theta_max_R), 0.05, quantity="peak rotation"))
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
    return cases, hist, runs


def motion_cases(scene: StatueScene, motion, settings: SimSettings, contact: ContactSettings,
                 free_time: float = 3.0, label: str | None = None, model: RockingModel | None = None,
                 calib: dict | None = None, spread: bool = False, e_user: tuple = (None, None)
                 ) -> tuple[list, dict, dict]:
    """The user's motion on the free-standing statue. Checks: ``model`` (the user's 2D model,
    default eq. 15's e, or ``e_user``); with ``calib`` (:func:`calibrate_restitution`) the peak
    rotation of 2D given 3D's e is added as a diagnostic.

    ``spread``: also run the models' own sensitivity (2D with e x 0.99 and x 1.01, 2D with rtol 1e-6
    and 1e-10, 3D with dt / 2) and store the range of the peak rotation in the case's ``spread``
    field, so the reader sees whether the 2D-3D difference lies inside it."""
    model = user_model(scene, *e_user) if model is None else model
    tag = label or motion.label
    t_end = motion.end + free_time
    r2 = simulate_2d(model, motion, t_end=t_end, dt_out=DT_OUT_2D)
    r3 = simulate_statue(scene, motion, settings=settings, contact=contact, free_time=free_time)
    scr = screen(model, motion, r3, contact, t_end)
    cases = [Case.equal(f"{tag}: overturn", r2.overturned, r3.overturned, quantity="overturn")]
    cases += _liftoff_cases(tag, model, motion, r2, r3, t_end)
    runs = {tag: r3.to_dict() | {"screen": scr}}
    if not r2.overturned and not r3.overturned and r2.uplift_time is not None:
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
                                  free_time=free_time)
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
    cases = [c.screened(scr) for c in cases]
    t2, y2 = _hist2d(r2)
    return cases, {tag: {"t2": t2, "y2": y2, "t3": r3.t, "y3": r3.theta, "label": "theta (rad)"}}, runs


# ----------------------------------------------------------------------------- overturning boundary

def _edges(amps, outs) -> list[tuple[float, float, str]]:
    """Brackets (a_lo, a_hi, 'up' | 'down') where the outcome changes along the amplitude scan
    ('up': no overturn below, overturn above)."""
    return [(float(amps[i]), float(amps[i + 1]), "up" if outs[i + 1] else "down")
            for i in range(len(amps) - 1) if outs[i] != outs[i + 1]]


def _bisect(run, lo: float, hi: float, rtol: float) -> float:
    """The amplitude where run() changes between lo and hi (relative tolerance rtol)."""
    o_lo = run(lo)
    while hi - lo > rtol * hi:
        mid = 0.5 * (lo + hi)
        if run(mid) == o_lo:
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


def overturn_edges_2d(model: RockingModel, freq: float, lo: float, hi: float, n: int = 120,
                      free_time: float = 2.0, rtol: float = 1e-3) -> list[tuple[float, str]]:
    """Every overturning band edge of one-sine pulses of ``freq`` Hz between amplitudes ``lo`` and
    ``hi`` (m/s^2) for the 2D model: a scan of ``n`` amplitudes, then bisection of each change.
    Returns [(amplitude, 'up' | 'down'), ...] ('up': overturns just above)."""
    def run(a):
        m = motions.sine_pulse(a, freq)
        return bool(simulate_2d(model, m, t_end=m.end + free_time).overturned)

    amps = np.linspace(lo, hi, n)
    outs = [run(a) for a in amps]
    return [(_bisect(run, a, b, rtol), d) for a, b, d in _edges(amps, outs)]


def boundary_cases(scene: StatueScene, model: RockingModel, freqs, settings: SimSettings,
                   contact: ContactSettings, *, n3: int = 6, n2: int = 120, span=(0.6, 1.8), max_edges: int = 4,
                   free_time: float = 2.0, rtol: float = 0.01, progress=None) -> tuple[list, dict]:
    """The overturning boundary of one-sine pulses in 2D and 3D at each frequency of ``freqs`` (Hz).

    2D: the lowest overturning amplitude a1 (geometric scan from the uplift acceleration to 20 x it),
    then every band edge in ``span`` x a1 from a fine scan (``n2`` amplitudes) and bisection. 3D: a
    coarse scan (``n3`` amplitudes over the same range) for its own edges, and for each of the first
    ``max_edges`` 2D edges a bracket at (1 -+ BOUNDARY_TARGET) x the edge, bisected (``rtol``) when the
    3D outcome changes the same way inside it; else the nearest 3D edge of the coarse scan, if any.
    One case per 2D edge: the ratio 3D / 2D (target BOUNDARY_TARGET), screened with the 2D demand just
    below and above the edge and the 3D runs of the bracket. Returns (cases, runs)."""
    p = model.params
    cases, out = [], {}
    a_up = min(p.a_L, p.a_R)
    for f in freqs:
        f = float(f)
        cache = {}

        def run3(a, f=f, cache=cache):
            if a not in cache:
                m = motions.sine_pulse(a, f)
                cache[a] = simulate_statue(scene, m, settings=settings, contact=contact, free_time=free_time,
                                           dt_out=0.01)
            return bool(cache[a].overturned)

        def ot2(a, f=f):
            m = motions.sine_pulse(a, f)
            return bool(simulate_2d(model, m, t_end=m.end + free_time).overturned)

        scan = np.geomspace(a_up, 20 * a_up, 160)
        first = next((a for a in scan if ot2(a)), None)
        if first is None:
            out[f"{f:g} Hz"] = {"skipped": "no 2D overturning below 20 x the uplift acceleration"}
            continue
        lo, hi = span[0] * first, span[1] * first
        e2 = overturn_edges_2d(model, f, lo, hi, n=n2, free_time=free_time)
        amps3 = np.linspace(lo, hi, n3)
        e3_coarse = _edges(amps3, [run3(a) for a in amps3])
        rows = []
        for k, (a2, d) in enumerate(e2[:max_edges]):
            b_lo, b_hi = a2 * (1 - BOUNDARY_TARGET), a2 * (1 + BOUNDARY_TARGET)
            o_lo, o_hi = run3(b_lo), run3(b_hi)
            if o_lo != o_hi and (o_hi if d == "up" else o_lo):
                a3, how = _bisect(run3, b_lo, b_hi, rtol), "bisected inside +-10 % of the 2D edge"
            else:
                same = [0.5 * (x + y) for x, y, dd in e3_coarse if dd == d]
                a3 = min(same, key=lambda x: abs(x - a2)) if same else None
                how = ("nearest 3D edge of the coarse scan (none inside +-10 %)" if same else
                       f"no 3D '{d}' edge in {lo / p.g:.3f}-{hi / p.g:.3f} g")
            d_lo = contact_demand_2d(model, motions.sine_pulse(0.99 * a2, f), 1 / f + free_time)
            d_hi = contact_demand_2d(model, motions.sine_pulse(1.01 * a2, f), 1 / f + free_time)
            worst = d_lo if (d_lo["mu_required"] > d_hi["mu_required"]) else d_hi
            rs = [cache[b_lo], cache[b_hi]]
            slip = max(slip_of(r) for r in rs)
            yaw = max(float(np.abs(r.yaw).max(initial=0.0)) for r in rs)
            reasons = []
            mu = contact.friction**2
            if worst["mu_required"] > mu:
                reasons.append(f"the 2D rocking needs friction {worst['mu_required']:.3g} > the scene's {mu:.3g}")
            if min(d_lo["n_min"], d_hi["n_min"]) <= 0:
                reasons.append(f"the 2D rocking needs a negative normal force (N / mg = "
                               f"{min(d_lo['n_min'], d_hi['n_min']):.3g}: it takes off)")
            if slip > SLIP_LIMIT:
                reasons.append(f"3D pivot slips {slip * 1000:.1f} mm > {SLIP_LIMIT * 1000:g} mm")
            if yaw > YAW_LIMIT:
                reasons.append(f"3D body yaws {math.degrees(yaw):.2f} deg > {math.degrees(YAW_LIMIT):g} deg")
            scr = {"applicable": not reasons, "reasons": reasons, "mu_required": _jf(worst["mu_required"]),
                   "mu_scene": mu, "n_min": min(d_lo["n_min"], d_hi["n_min"]), "slip_mm": slip * 1000,
                   "yaw_deg": math.degrees(yaw), "slip_limit_mm": SLIP_LIMIT * 1000,
                   "yaw_limit_deg": math.degrees(YAW_LIMIT)}
            name = (f"overturning boundary {f:g} Hz" if k == 0 else
                    f"overturning band edge {k + 1} ({d}) {f:g} Hz")
            ratio = a3 / a2 if a3 is not None else None
            c = Case(name, "overturning amplitude", a2 / p.g, None if a3 is None else a3 / p.g,
                     abs(ratio - 1) if ratio is not None else math.inf, BOUNDARY_TARGET,
                     ratio is not None and abs(ratio - 1) <= BOUNDARY_TARGET, "relative", "g",
                     note=f"one-sine pulse, 2D: fine scan + bisection; 3D: {how}; ratio 3D / 2D = "
                          + ("-" if ratio is None else f"{ratio:.3f}"))
            cases.append(c.screened(scr))
            rows.append({"edge": d, "a_2d_g": a2 / p.g, "a_3d_g": None if a3 is None else a3 / p.g,
                         "ratio": ratio, "screen": scr})
        out[f"{f:g} Hz"] = {"edges_2d_g": [(a / p.g, d) for a, d in e2],
                            "edges_3d_coarse_g": [(0.5 * (x + y) / p.g, d) for x, y, d in e3_coarse],
                            "scan_g": [lo / p.g, hi / p.g], "n3": n3, "runs_3d": len(cache), "cases": rows,
                            "wall_time_3d_s": sum(r.wall_time for r in cache.values())}
        if progress:
            progress(f)
    return cases, out


BOUNDARY_FREQS = {True: (1.0, 2.0), False: (0.75, 1.0, 1.5, 2.0, 3.0)}
"""Frequencies (Hz) of the overturning-boundary cases: quick and full."""


def compare(scene: StatueScene, motion=None, *, iso_scene=None, settings: SimSettings | None = None,
            contact: ContactSettings | None = None, pulse_freq: float = 1.5, quick: bool = False,
            progress=None, e_L: float | None = None, e_R: float | None = None,
            boundary_freqs=None, statue_settings: SimSettings | None = None) -> Comparison:
    """All cases of the module docstring for one statue (and isolator, if given). ``e_L``, ``e_R``:
    the user's restitution (a prototype test; default eq. 15); ``boundary_freqs``: the frequencies of
    the overturning-boundary cases (default BOUNDARY_FREQS[quick]). Engine settings: ``statue_settings``
    for the statue scenes (default :data:`~.statue_scene.STATUE_SETTINGS`, dt 2 ms), ``settings`` for
    the isolator scenes (default ``SimSettings()``, dt 0.5 ms)."""
    say = progress or (lambda msg: None)
    iso_settings = SimSettings() if settings is None else settings
    settings = STATUE_SETTINGS if statue_settings is None else statue_settings
    contact = ContactSettings() if contact is None else contact
    user = user_model(scene, e_L, e_R)
    cases, hist, runs = [], {}, {}
    say("restitution calibration")
    rest = calibrate_restitution(scene, settings, contact)
    runs["restitution calibration"] = rest
    cases += restitution_cases(scene, rest, contact)
    diag = model_2d(scene, rest)
    say("free rocking")
    c, h, r = free_rocking_cases(scene, settings, contact, t_end=2.0 if quick else 3.0, model=user)
    cases += c; hist.update(h); runs.update(r)
    say("pulses")
    c, h, r = pulse_cases(scene, settings, contact, pulse_freq, free_time=1.5 if quick else 3.0, model=user,
                          diag_model=diag)
    cases += c; hist.update(h); runs.update(r)
    say("overturning boundaries")
    freqs = BOUNDARY_FREQS[bool(quick)] if boundary_freqs is None else boundary_freqs
    c, r = boundary_cases(scene, user, freqs, settings, contact, n3=5 if quick else 10,
                          free_time=1.5 if quick else 2.0, max_edges=2 if quick else 4,
                          progress=lambda f: say(f"  boundary at {f:g} Hz done"))
    cases += c; runs["overturning boundaries"] = r
    if motion is not None and motion.kind != "none":
        say(f"motion {motion.label}")
        c, h, r = motion_cases(scene, motion, settings, contact, free_time=1.0 if quick else 3.0, model=user,
                               calib=rest, spread=not quick, e_user=(e_L, e_R))
        cases += c; hist.update(h); runs.update(r)
    calib = None
    if iso_scene is not None:
        from .isolator_cases import isolated_statue_cases, isolator_free_cases

        say("isolator free vibration")
        c, h, r, calib = isolator_free_cases(iso_scene, iso_settings, contact, cycles=1.2 if quick else 2.2)
        cases += c; hist.update(h); runs.update(r)
        if motion is not None and motion.kind != "none":
            say("isolated statue")
            c, h, r = isolated_statue_cases(iso_scene, motion, iso_settings, contact, mu_3d=calib.get("mu_3d"),
                                            free_time=1.0 if quick else 2.0, mount="rigid",
                                            label="isolated statue (fixed to the plate)")
            cases += c; hist.update(h); runs.update(r)
            if not quick:
                say("isolated statue, free-standing")
                c, h, r = isolated_statue_cases(iso_scene, motion, iso_settings, contact, mu_3d=calib.get("mu_3d"),
                                                free_time=2.0, mount="contact",
                                                label="isolated statue (free-standing)", model=user)
                cases += c; hist.update(h); runs.update(r)
    if calib is not None:
        runs["calibration"] = calib
    return Comparison(cases=tuple(cases), histories=hist, runs=runs)

