"""The rolling-ball isolator as a frozen set of parameters (MODEL.md section 4).

Two plates carved with spherical grooves of radius R; balls of radius r roll
between facing grooves; the top plate (mass m_o) carries the statue (mass m).

    M      = m_o + m          supported mass, kg;   W = M g
    R_hat  = 2 (R - r)        equivalent radius of the top plate's path, m
    k      = W / R_hat        horizontal stiffness of the grooves, N/m
    T      = 2 pi sqrt(R_hat / g)   period, independent of the mass
    mu                        rolling friction coefficient (friction force mu W)

Restoring force models:

    'coulomb'  F = k u_o + mu W sgn(u_o')                          (eq. 21)
    'boucwen'  F = a k_i u_o + (1 - a) F_y z, k_i = q k, a = 1/q,  (eqs. 22-24)
               F_y = mu W, u_y = F_y / k_i = mu R_hat / q,
               z' = [1 - |z|^n (beta + gamma sgn(u_o' z))] u_o' / u_y, beta = gamma = 1/2
               q = 30 without rubber, q = 5 with the rubber layer (ch. 5.2.3)

Example
-------
>>> iso = Isolator(R=0.30, r=0.0095, M=11.664, mu=0.0131)
>>> round(iso.R_hat, 3), round(iso.T, 2)          # thesis: 0.581 m, 1.53 s
(0.581, 1.53)
>>> round(Isolator(R=0.30, r=0.0183, M=10.0, mu=0.01).T, 2)
1.51
"""
from __future__ import annotations

import math
from dataclasses import asdict, dataclass

from ..errors import InputError

G = 9.81
MODELS = ("coulomb", "boucwen")


@dataclass(frozen=True)
class Isolator:
    R: float
    r: float
    M: float
    mu: float
    model: str = "coulomb"
    q: float = 30.0
    n: int = 1
    g: float = G

    def __post_init__(self):
        for name in ("R", "r", "M", "g"):
            value = getattr(self, name)
            if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0):
                raise InputError(f"isolator {name} must be a positive number, got {value!r}")
        if self.r >= self.R:
            raise InputError(f"ball radius r = {self.r:g} m must be smaller than the groove radius R = {self.R:g} m")
        if not (math.isfinite(self.mu) and 0 <= self.mu < 1):
            raise InputError(f"rolling friction mu must be in [0, 1), got {self.mu!r}")
        if self.model not in MODELS:
            raise InputError(f"isolator model {self.model!r} is not one of {', '.join(MODELS)}")
        if self.model == "boucwen":
            if not (math.isfinite(self.q) and self.q > 1):
                raise InputError(f"Bouc-Wen q (initial / groove stiffness) must be > 1, got {self.q!r}")
            if self.n not in (1, 2):
                raise InputError(f"Bouc-Wen exponent n must be 1 or 2 (exact z update), got {self.n!r}")
            if self.mu == 0:
                raise InputError("the Bouc-Wen model needs mu > 0 (its yield force is mu W)")

    @property
    def R_hat(self) -> float:
        return 2.0 * (self.R - self.r)

    @property
    def W(self) -> float:
        return self.M * self.g

    @property
    def k(self) -> float:
        return self.W / self.R_hat

    @property
    def omega(self) -> float:
        return math.sqrt(self.g / self.R_hat)

    @property
    def T(self) -> float:
        return 2.0 * math.pi / self.omega

    @property
    def u_y(self) -> float:
        """Bouc-Wen yield displacement mu R_hat / q, m."""
        return self.mu * self.R_hat / self.q

    def to_dict(self) -> dict:
        out = asdict(self)
        out.update(R_hat=self.R_hat, W=self.W, k=self.k, T=self.T)
        if self.model == "boucwen":
            out["u_y"] = self.u_y
        return out


def fuse_release_acceleration(r: float, z: float, g: float = G) -> float:
    """Ground-plate acceleration (m/s^2) that lifts a fuse ball of radius r out of a
    seat of depth z (eq. 52): g sqrt(2 r z - z^2) / (2 (r - z))."""
    if not (0 < z < r):
        raise InputError(f"fuse seat depth must be in (0, r = {r:g} m), got {z!r}")
    return g * math.sqrt(2 * r * z - z * z) / (2 * (r - z))


def fuse_seat_depth(r: float, release: float, g: float = G) -> float:
    """Seat depth z (m) for a fuse ball of radius r that releases at ``release`` m/s^2:
    eq. 52 solved for z, z = r (1 - 1 / sqrt(1 + 4 s^2)) with s = release / g."""
    if not (r > 0 and release > 0):
        raise InputError("fuse ball radius and release acceleration must be positive")
    s = release / g
    return r * (1.0 - 1.0 / math.sqrt(1.0 + 4.0 * s * s))


def lever_arm(m: float, h: float, m_o: float, h_o: float) -> float:
    """Height l (m) of the resultant of the statue (mass m, centre h above the top
    plate) and the top plate (m_o, thickness h_o), eq. 47."""
    return (m * (h + h_o) + m_o * h_o / 2.0) / (m + m_o)


def safety_length(acc: float, l: float, g: float = G) -> float:
    """a = (u''/g) l (eq. 48): shift of the vertical resultant under acceleration acc."""
    return acc / g * l


def allowable_displacement(L_cr: float, a: float) -> float:
    """d_max = L_cr - a (eq. 49)."""
    return L_cr - a
