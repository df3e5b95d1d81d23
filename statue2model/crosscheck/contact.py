"""Contact parameters of the 3D scenes, mapped from the 2D parameters.

* Friction: the 2D rocking model assumes no sliding, so the statue and the floor
  get a lateral friction coefficient far above what rocking needs (default 1.0;
  PyBullet combines two bodies' coefficients by their product).
* Restitution: PyBullet's restitution is a per-contact Newton coefficient on the
  normal velocity, not Housner's e. Housner's e (eq. 15) is the outcome of a
  *plastic* impact of a rigid body at the landing edge, conserving angular
  momentum about it; so the contacts get restitution 0 and the effective e of the
  3D body is measured from the free-rocking peak decay (eq. 43,
  :func:`effective_e`) and compared with the 2D theoretical value.
  restitutionVelocityThreshold only matters for restitution > 0.
* Rolling friction (isolator balls): PyBullet's rollingFriction c is a length: a
  contact resists relative rolling with a torque up to c N (c combined as
  c_a f_b + c_b f_a with the lateral coefficients f). A ball of radius r rolling
  between two plates turns at w = V / (2 r) relative to each plate (V the top
  plate's speed relative to the bottom one) and dissipates 2 c N w; summed over
  the balls that is c W V / r, the work of a force mu W on the plate. Hence
  c = mu r (divided by the plates' lateral coefficient), :func:`rolling_for_mu`.

Example
-------
>>> round(rolling_for_mu(0.0073, 0.0095), 8)
6.935e-05
"""
from __future__ import annotations

import math
from dataclasses import asdict, dataclass

from ..errors import InputError


@dataclass(frozen=True)
class ContactSettings:
    """friction: lateral coefficient of each body (product per pair); restitution: PyBullet's;
    margin: collision margin of the statue's hull, m (PyBullet's default 1 mm inflates the hull:
    the body would stand 1 mm high and rock on a rounded edge)."""

    friction: float = 1.0
    restitution: float = 0.0
    margin: float = 0.0

    def __post_init__(self):
        if not (math.isfinite(self.friction) and 0 <= self.friction <= 10):
            raise InputError(f"friction must be in [0, 10], got {self.friction!r}")
        if not (math.isfinite(self.restitution) and 0 <= self.restitution <= 1):
            raise InputError(f"restitution must be in [0, 1], got {self.restitution!r}")
        if not (math.isfinite(self.margin) and 0 <= self.margin <= 0.01):
            raise InputError(f"collision margin must be in [0, 0.01] m, got {self.margin!r}")

    def to_dict(self) -> dict:
        return asdict(self)


def rolling_for_mu(mu: float, r: float, plate_friction: float = 1.0) -> float:
    """PyBullet rollingFriction of the balls (m) that gives the plate a rolling
    resistance mu W: c = mu r / plate_friction (see the module docstring)."""
    if not (math.isfinite(mu) and mu >= 0 and r > 0 and plate_friction > 0):
        raise InputError(f"need mu >= 0, r > 0 and a positive plate friction, got {mu}, {r}, {plate_friction}")
    return mu * r / plate_friction


def effective_e(params, peak_a: float, peak_b: float, side_a: str) -> float:
    """Effective restitution from two successive peaks |theta_i| (on pivot ``side_a``,
    'R' or 'L') and |theta_i+1| (on the other pivot), eq. 43 of MODEL.md."""
    A, B = ("R", "L") if side_a == "R" else ("L", "R")
    dA, dB = getattr(params, f"d_{A}"), getattr(params, f"d_{B}")
    IA, IB = getattr(params, f"I_{A}"), getattr(params, f"I_{B}")
    deA, deB = getattr(params, f"delta_{A}"), getattr(params, f"delta_{B}")
    qa, qb = abs(peak_a), abs(peak_b)
    ea = 2.0 * math.sin(deA - 0.5 * qa) * math.sin(0.5 * qa)
    eb = 2.0 * math.sin(deB - 0.5 * qb) * math.sin(0.5 * qb)
    if ea <= 0:
        raise InputError("the first peak must be a rotation > 0")
    return math.sqrt(dB * IA * eb / (IB * dA * ea))
