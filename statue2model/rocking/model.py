"""The 2D rocking model: immutable parameters (MODEL.md section 2).

Symbols, once (SI units):

* ``params`` - :class:`~statue2model.geometry.rocking_params.RockingParams`:
  m, h, b_L, b_R, I_G and what follows from them (d_i, delta_i, I_i, p_i, a_i).
* ``alpha_L``, ``alpha_R`` in (0, 1] - reduction of the uplift acceleration of
  an imperfect base: the body lifts on the left pivot when u_g'' > alpha_L a_L and
  on the right pivot when u_g'' < -alpha_R a_R.
* ``theta_L``, ``theta_R`` > 0 (rad) - rotation over which the contact rolls from
  the whole base to the pivot (rolling transition, eq. 37); alpha grows linearly
  from alpha_side at theta = 0 to 1 at |theta| = theta_side.
* ``e_L``, ``e_R`` - restitution theta'+ = e theta'- at impacts that land on the
  left edge (after rocking on the right pivot) and on the right edge. Each is a
  constant or a table e(|theta'-|) (:class:`Restitution`).
* ``linearised`` - sin(delta - |theta|) -> delta - |theta|, cos -> 1 (Housner's
  slender-block approximation, used by the closed forms).
* ``mu_static`` - static friction coefficient between the base and its support
  (default :data:`MU_STATIC`). The model is pure rocking: it applies only where the
  body lifts before it slides. Sliding from rest needs a ground acceleration
  mu_s g, uplift needs alpha_side a_side = alpha_side g b_side / h, so a body whose
  easier uplift (the side that lifts first) needs more than mu_s g *slides before
  it rocks*, and under a ground acceleration above mu_s g its rocking outcome is
  not applicable (:meth:`RockingModel.applicability`). The friction the pivot
  needs once the body rocks (it can exceed mu_s during impacts) is not checked.

Restitution: the default is eq. 15's angular-momentum value, clipped at 0: a
squat body (eq. 15 < 0) has a plastic impact, e = 0, and stops rocking at its
first impact (:meth:`RockingParams.restitution_notes`).

alpha_L = alpha_R = 1 and theta_L = theta_R = 0 is the classical (Housner) model.

Example
-------
>>> from statue2model.geometry.rocking_params import RockingParams
>>> block = RockingParams.rectangular_block(b=0.0384, h=0.2, m=1.286)
>>> model = RockingModel.imperfect(block, alpha_L=0.65, alpha_R=0.65,
...                                theta_L=0.13 * block.delta_L, theta_R=0.13 * block.delta_R)
>>> round(model.uplift_limits[0] / 9.81, 4)    # alpha_L a_L / g
0.1248
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np

from ..errors import InputError
from ..geometry.rocking_params import RockingParams
from . import kernel as K

THETA_FLOOR = 1e-9  # shortest rolling transition integrated, as a fraction of delta

MU_STATIC = 0.7
"""Default static friction coefficient of the body's base on its support: a typical
value for dry stone on stone (handbook figures run from about 0.6 to 0.8), not a
measured one and not from the thesis; set the real one with ``--mu-static`` or
``[model] mu_static``. With mu_s > b/h a rigid block starts to rock rather than slide
(the thesis, ch. 2.2.2, citing its ref. [6], Aslam et al.; Shenton, J. Eng. Mech. 122(7),
1996, gives the full slide / rock / slide-rock criteria)."""


def _finite(name: str, value) -> float:
    try:
        value = float(value)
    except (TypeError, ValueError):
        raise InputError(f"{name} must be a number, got {value!r}") from None
    if not math.isfinite(value):
        raise InputError(f"{name} must be finite, got {value}")
    return value


@dataclass(frozen=True)
class Restitution:
    """Coefficient of restitution of one side: a constant, or a table e(|theta'|)
    interpolated linearly in the impact speed |theta'-| (rad/s) and held constant
    beyond its ends.

    >>> Restitution.table([0.2, 0.8], [0.95, 0.98])(0.5)
    0.965
    """

    speeds: tuple[float, ...] = (0.0,)
    values: tuple[float, ...] = (1.0,)
    name: str = "e"

    def __post_init__(self):
        if len(self.speeds) != len(self.values) or not self.values:
            raise InputError(f"{self.name}: speeds and values must have the same, non-zero length")
        for v in self.values:
            v = _finite(self.name, v)
            if not 0.0 <= v <= 1.0:
                raise InputError(f"coefficient of restitution {self.name} must lie in [0, 1], got {v}")
        sp = [_finite(f"{self.name} speed", w) for w in self.speeds]
        if any(w < 0 for w in sp) or any(b <= a for a, b in zip(sp, sp[1:])):
            raise InputError(f"{self.name}: impact speeds must be >= 0 and strictly increasing")

    @classmethod
    def constant(cls, e: float, name: str = "e") -> "Restitution":
        return cls((0.0,), (_finite(name, e),), name)

    @classmethod
    def table(cls, speeds, values, name: str = "e") -> "Restitution":
        return cls(tuple(float(w) for w in speeds), tuple(float(v) for v in values), name)

    @property
    def is_constant(self) -> bool:
        return len(self.values) == 1

    def __call__(self, speed):
        """e at impact speed(s) |theta'-| in rad/s."""
        speed = np.asarray(speed, dtype=float)
        out = np.full_like(speed, self.values[0]) if self.is_constant else \
            np.interp(np.abs(speed), self.speeds, self.values)
        return float(out) if out.ndim == 0 else out

    def arrays(self) -> tuple[np.ndarray, np.ndarray]:
        return np.asarray(self.speeds, dtype=float), np.asarray(self.values, dtype=float)

    def to_dict(self):
        if self.is_constant:
            return self.values[0]
        return {"speeds_rad_s": list(self.speeds), "values": list(self.values)}

    @classmethod
    def from_value(cls, value, name: str) -> "Restitution":
        """A number, a Restitution, or {"speeds_rad_s": [...], "values": [...]}."""
        if isinstance(value, Restitution):
            return replace(value, name=name)
        if isinstance(value, dict):
            try:
                return cls.table(value["speeds_rad_s"], value["values"], name)
            except KeyError as exc:
                raise InputError(f"{name}: a table needs 'speeds_rad_s' and 'values' ({exc} missing)") from None
        return cls.constant(value, name)


@dataclass(frozen=True)
class RockingModel:
    """Parameters of one 2D rocking model (immutable; see the module docstring)."""

    params: RockingParams
    alpha_L: float = 1.0
    alpha_R: float = 1.0
    theta_L: float = 0.0
    theta_R: float = 0.0
    e_L: Restitution = field(default_factory=lambda: Restitution.constant(1.0, "e_L"))
    e_R: Restitution = field(default_factory=lambda: Restitution.constant(1.0, "e_R"))
    linearised: bool = False
    mu_static: float = MU_STATIC

    def __post_init__(self):
        mu = _finite("mu_static", self.mu_static)
        if not mu > 0.0:
            raise InputError(f"static friction coefficient mu_static must be > 0, got {mu}")
        for name in ("alpha_L", "alpha_R"):
            a = _finite(name, getattr(self, name))
            if not 0.0 < a <= 1.0:
                raise InputError(f"{name} must lie in (0, 1], got {a}")
        for name, alpha in (("theta_L", self.alpha_L), ("theta_R", self.alpha_R)):
            th = _finite(name, getattr(self, name))
            if th < 0.0:
                raise InputError(f"{name} must be > 0 (rad), got {th}")
            if alpha < 1.0 and th <= 0.0:
                raise InputError(f"{name} must be > 0 (rad) when alpha < 1 (the rolling transition needs a length)")
        if not isinstance(self.e_L, Restitution) or not isinstance(self.e_R, Restitution):
            raise InputError("e_L and e_R must be Restitution objects")

    # -- constructors -------------------------------------------------------
    @classmethod
    def housner(cls, params: RockingParams, e_L=None, e_R=None, linearised: bool = False,
                mu_static: float | None = None) -> "RockingModel":
        """Classical model; e defaults to the angular-momentum values of eq. 15 (clipped
        at 0: plastic impact); mu_static to MU_STATIC."""
        return cls(params, 1.0, 1.0, 0.0, 0.0,
                   Restitution.from_value(params.e_L if e_L is None else e_L, "e_L"),
                   Restitution.from_value(params.e_R if e_R is None else e_R, "e_R"), bool(linearised),
                   MU_STATIC if mu_static is None else mu_static)

    @classmethod
    def imperfect(cls, params: RockingParams, alpha_L: float, alpha_R: float, theta_L=None, theta_R=None,
                  e_L=None, e_R=None, linearised: bool = False, mu_static: float | None = None) -> "RockingModel":
        """Imperfect asymmetric model (eqs. 33-38); theta_side defaults to 0.07 delta_side,
        the thesis' rough estimate of the full-uplift rotation (ch. 4.2)."""
        return cls(params, alpha_L, alpha_R,
                   0.07 * params.delta_L if theta_L is None else theta_L,
                   0.07 * params.delta_R if theta_R is None else theta_R,
                   Restitution.from_value(params.e_L if e_L is None else e_L, "e_L"),
                   Restitution.from_value(params.e_R if e_R is None else e_R, "e_R"), bool(linearised),
                   MU_STATIC if mu_static is None else mu_static)

    def with_(self, **changes) -> "RockingModel":
        """A copy with some fields changed (e.g. ``theta_R=...``, ``e_L=0.9``)."""
        for key in ("e_L", "e_R"):
            if key in changes:
                changes[key] = Restitution.from_value(changes[key], key)
        return replace(self, **changes)

    # -- derived ------------------------------------------------------------
    @property
    def kind(self) -> str:
        classical = self.alpha_L == 1.0 and self.alpha_R == 1.0 and self.theta_L == 0.0 and self.theta_R == 0.0
        return "housner" if classical else "imperfect"

    @property
    def uplift_limits(self) -> tuple[float, float]:
        """(alpha_L a_L, alpha_R a_R) in m/s^2: stick while -alpha_R a_R <= u_g'' <= alpha_L a_L."""
        p = self.params
        aL, aR = self.effective_alpha
        if self.linearised:
            return aL * p.g * p.delta_L, aR * p.g * p.delta_R
        return aL * p.a_L, aR * p.a_R

    @property
    def effective_alpha(self) -> tuple[float, float]:
        """(alpha_L, alpha_R) as integrated. A rolling transition shorter than
        THETA_FLOOR * delta_side (1e-9 of the overturning angle) is taken as none: the
        body could only roll by less than that before rocking needs the full uplift
        acceleration a_side, so alpha_side acts as 1 (it would only make the run stiff)."""
        p = self.params
        aL = self.alpha_L if self.theta_L >= THETA_FLOOR * p.delta_L else 1.0
        aR = self.alpha_R if self.theta_R >= THETA_FLOOR * p.delta_R else 1.0
        return aL, aR

    @property
    def lift_accelerations(self) -> tuple[float, float]:
        """(alpha_L a_L, alpha_R a_R) in m/s^2 with the exact a_side = g b_side / h (also for a
        linearised model): the ground acceleration toward +x (-x) that lifts the body on its
        left (right) pivot, what friction must hold for the body to rock rather than slide."""
        p = self.params
        aL, aR = self.effective_alpha
        return aL * p.a_L, aR * p.a_R

    @property
    def slides_first(self) -> bool:
        """True if the body slides before it rocks: even its easier uplift (the side that
        lifts first) needs more than the friction can hold, min(alpha_i a_i) > mu_static g."""
        return min(self.lift_accelerations) > self.mu_static * self.params.g

    def sliding_note(self) -> str:
        """'' if the body lifts before it slides in both directions; else one line: 'slides
        before it rocks: ...' (no rocking above mu_s g), or a warning when only the harder
        side needs more friction than mu_s."""
        g, mu = self.params.g, self.mu_static
        up, dn = self.lift_accelerations
        sides = {"L": (up, "+x", self.effective_alpha[0], self.params.b_L),
                 "R": (dn, "-x", self.effective_alpha[1], self.params.b_R)}
        first = "L" if up <= dn else "R"
        a1, _, al1, b1 = sides[first]
        if a1 > mu * g:
            al = f"alpha_{first} " if al1 < 1 else ""
            return (f"slides before it rocks: lifting it needs a ground acceleration of {a1 / g:.3f} g "
                    f"({al}g b_{first}/h on the pivot that lifts first, b_{first}/h = {b1 / self.params.h:.3f}) but "
                    f"friction holds only mu_s g = {mu:.3f} g (static friction mu_s = {mu:g}): above {mu:.3f} g the "
                    f"body slides and the rocking outcome is not applicable")
        other = "R" if first == "L" else "L"
        a2, dir2, _, _ = sides[other]
        if a2 > mu * g:
            return (f"warning: uplift on the {other} pivot needs {a2 / g:.3f} g > mu_s g = {mu:.3f} g: a ground "
                    f"acceleration above {mu:.3f} g toward {dir2} while the body is at rest slides it before it "
                    f"lifts on that side; the rocking model assumes it does not slide")
        return ""

    def applicability(self, peak_pos: float, peak_neg: float) -> tuple[bool, str]:
        """(applicable, why) of a run whose ground acceleration reaches ``peak_pos`` toward
        +x and ``peak_neg`` toward -x (both >= 0, m/s^2): not applicable if the body slides
        before it rocks (:attr:`slides_first`) and the ground exceeds mu_s g. Below mu_s g
        such a body neither slides nor lifts (the outcome 'no motion' holds)."""
        peak = max(float(peak_pos), float(peak_neg))
        if self.slides_first and peak > self.mu_static * self.params.g:
            return False, (f"{self.sliding_note()}; peak ground acceleration {peak / self.params.g:.3f} g")
        return True, ""

    @property
    def notes(self) -> list[str]:
        """What a reader must know about this model's assumptions: plastic impacts where
        eq. 15 is negative (and the model uses e = 0) and the sliding check."""
        plastic = {side for side, e in (("L", self.e_L), ("R", self.e_R)) if e.is_constant and e.values[0] == 0.0}
        out = [n for n in self.params.restitution_notes() if n[2] in plastic]     # 'e_L: ...'
        s = self.sliding_note()
        if s:
            out.append(s)
        return out

    @property
    def energy_gain_possible(self) -> bool:
        """True if e_side^2 I_new / I_old > 1 at some impact (the impact would add energy)."""
        p = self.params
        return max(self.e_L.values) ** 2 * p.I_L / p.I_R > 1 + 1e-12 or \
            max(self.e_R.values) ** 2 * p.I_R / p.I_L > 1 + 1e-12

    def kernel_vector(self, rest_tol: float = 1e-9, early_exit: bool | str = False) -> np.ndarray:
        """The flat parameter vector P of :mod:`statue2model.rocking.kernel` (indices
        ``kernel.P2L`` ... ``kernel.EARLY``): the one packing of the model for the compiled
        kernels, the fixed-base engine's and the coupled plate + statue kernel's, whose
        vector starts with it (:func:`statue2model.isolator.coupled.parameter_vector`). ``early_exit``:
        True - stop once the ground is still, a peak has been seen on each side and no impact
        can add energy (the maxima and the outcome are then final; for sweeps); "outcome" -
        also stop a record's run as soon as its energy plus all the energy the rest of the
        record could pump in stays below the overturning barrier (the outcome is final, the
        maxima are not; for fragility studies)."""
        if early_exit not in (True, False, "outcome"):
            raise InputError(f"early_exit must be True, False or 'outcome', got {early_exit!r}")
        p = self.params
        P = np.zeros(K.N_P)
        P[K.P2L], P[K.P2R] = p.p_L**2, p.p_R**2
        P[K.DL], P[K.DR] = p.delta_L, p.delta_R
        aL, aR = self.effective_alpha
        P[K.AL], P[K.AR] = aL, aR
        P[K.TL] = self.theta_L if aL < 1.0 else 0.0
        P[K.TR] = self.theta_R if aR < 1.0 else 0.0
        P[K.GRAV] = p.g
        P[K.LIN] = 1.0 if self.linearised else 0.0
        P[K.LIM_UP], P[K.LIM_DN] = self.uplift_limits
        P[K.REST_TOL] = rest_tol
        P[K.EARLY] = 0.0 if not early_exit or self.energy_gain_possible else 2.0 if early_exit == "outcome" else 1.0
        return P

    def to_dict(self) -> dict:
        return {"model": self.kind, "linearised": self.linearised,
                "alpha_L": self.alpha_L, "alpha_R": self.alpha_R,
                "theta_L": self.theta_L, "theta_R": self.theta_R,
                "e_L": self.e_L.to_dict(), "e_R": self.e_R.to_dict(),
                "mu_static": self.mu_static, "slides_first": self.slides_first, "notes": self.notes,
                "params": self.params.to_dict()}
