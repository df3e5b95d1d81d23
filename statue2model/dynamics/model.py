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

    def __post_init__(self):
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
    def housner(cls, params: RockingParams, e_L=None, e_R=None, linearised: bool = False) -> "RockingModel":
        """Classical model; e defaults to the angular-momentum values of eq. 15."""
        return cls(params, 1.0, 1.0, 0.0, 0.0,
                   Restitution.from_value(params.e_L if e_L is None else e_L, "e_L"),
                   Restitution.from_value(params.e_R if e_R is None else e_R, "e_R"), bool(linearised))

    @classmethod
    def imperfect(cls, params: RockingParams, alpha_L: float, alpha_R: float, theta_L=None, theta_R=None,
                  e_L=None, e_R=None, linearised: bool = False) -> "RockingModel":
        """Imperfect asymmetric model (eqs. 33-38); theta_side defaults to 0.07 delta_side,
        the thesis' rough estimate of the full-uplift rotation (ch. 4.2)."""
        return cls(params, alpha_L, alpha_R,
                   0.07 * params.delta_L if theta_L is None else theta_L,
                   0.07 * params.delta_R if theta_R is None else theta_R,
                   Restitution.from_value(params.e_L if e_L is None else e_L, "e_L"),
                   Restitution.from_value(params.e_R if e_R is None else e_R, "e_R"), bool(linearised))

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
    def energy_gain_possible(self) -> bool:
        """True if e_side^2 I_new / I_old > 1 at some impact (the impact would add energy)."""
        p = self.params
        return max(self.e_L.values) ** 2 * p.I_L / p.I_R > 1 + 1e-12 or \
            max(self.e_R.values) ** 2 * p.I_R / p.I_L > 1 + 1e-12

    def kernel_vector(self, rest_tol: float = 1e-9, early_exit: bool = False) -> np.ndarray:
        """The flat parameter vector of :mod:`statue2model.dynamics.kernel`. ``early_exit``:
        stop once the ground is still, a peak has been seen on each side and no impact
        can add energy (the maxima and the outcome are then final; for sweeps)."""
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
        P[K.EARLY] = 1.0 if early_exit and not self.energy_gain_possible else 0.0
        return P

    def to_dict(self) -> dict:
        return {"model": self.kind, "linearised": self.linearised,
                "alpha_L": self.alpha_L, "alpha_R": self.alpha_R,
                "theta_L": self.theta_L, "theta_R": self.theta_R,
                "e_L": self.e_L.to_dict(), "e_R": self.e_R.to_dict(),
                "params": self.params.to_dict()}
