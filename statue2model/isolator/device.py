"""The rolling-ball isolator as a frozen set of parameters (MODEL.md section 4).

Two plates carved with spherical grooves of radius R; balls of radius r roll
between facing grooves; the top plate (mass m_o) carries the statue (mass m).

    M      = m_o + m          supported mass, kg;   W = M g
    R_hat  = 2 (R - r)        equivalent radius of the top plate's path, m
    k      = W / R_hat        horizontal stiffness of the grooves, N/m
    T      = 2 pi sqrt(R_hat / g)   period, independent of the mass
    mu                        rolling friction coefficient (friction force mu W)
    capacity                  largest |u_o| (m) before a ball leaves its groove or the top
                              plate tips (inf: not checked); every isolated analysis stops
                              there with the outcome "isolator capacity exceeded"

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
>>> isolator_from_design({"R": 0.3, "r": 0.0095, "M": 11.664, "mu": 0.0131, "d_max": 0.15}).capacity
0.15
"""
from __future__ import annotations

import math
from dataclasses import asdict, dataclass

from ..errors import InputError

from ..quantities import G  # m/s^2
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
    capacity: float = math.inf

    def __post_init__(self):
        if not (isinstance(self.capacity, (int, float)) and self.capacity > 0 and self.capacity == self.capacity):
            raise InputError(f"isolator capacity (largest plate displacement) must be a positive length in m "
                             f"or inf, got {self.capacity!r}")
        for name in ("R", "r", "M", "g"):
            value = getattr(self, name)
            if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0):
                raise InputError(f"isolator {name} must be a positive number, got {value!r}")
        if self.r >= self.R:
            raise InputError(f"ball radius r = {self.r:g} m must be smaller than the groove radius R = {self.R:g} m")
        check_lengths(self.R, self.r, self.capacity)
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
        out["capacity"] = self.capacity if math.isfinite(self.capacity) else None    # None: not checked
        if self.model == "boucwen":
            out["u_y"] = self.u_y
        return out


def check_lengths(R: float, r: float, capacity: float = math.inf) -> None:
    """Refuse a groove radius R, ball radius r or capacity (m) that cannot be physical (a number in
    mm taken as m: R = 300 m), by the ranges of :data:`statue2model.geometry.units.PLAUSIBLE`;
    the value in range is let through (the unusual-but-possible ones are warned of where the
    user types them, through :func:`statue2model.geometry.units.check_plausible`).

    >>> check_lengths(300.0, 0.0095)
    Traceback (most recent call last):
    ...
    statue2model.errors.InputError: groove radius R = 300 m is implausible for a groove radius of curvature; did you mean 300 mm (0.3 m) or 300 cm (3 m)?
    """
    from ..geometry.units import check_plausible

    check_plausible("groove_radius", R, "groove radius R")
    check_plausible("ball_radius", r, "ball radius r")
    if math.isfinite(capacity):
        check_plausible("capacity", capacity, "isolator capacity")


def isolator_from_design(design: dict, model: str = "coulomb") -> Isolator:
    """The Isolator of a design (the dict of design.json, SI units): R, r, M, mu and the
    capacity (m; missing or null -> the design's allowable displacement "d_max" if present,
    else inf: not checked)."""
    try:
        R, r, M, mu = (float(design[k]) for k in ("R", "r", "M", "mu"))
        cap = design.get("capacity")
        if cap is None:
            cap = design.get("d_max")
        cap = math.inf if cap is None else float(cap)
    except (KeyError, TypeError, ValueError, AttributeError) as exc:
        raise InputError(f"not an isolator design (R, r, M, mu, capacity): {exc!r}") from None
    return Isolator(R=R, r=r, M=M, mu=mu, model=model, capacity=cap)


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


def groove_capacity(R: float, r: float, opening_radius: float) -> float:
    """Largest relative displacement u_o (m) of the top plate before a ball's contact
    point reaches the rim of its groove: u_o = 2 a (R - r) / R = a R_hat / R, with a the
    groove's opening radius (m), R its radius of curvature, r the ball's radius.

    Derivation (one ball between two facing spherical grooves of radius R, both plates
    alike). The ball touches a groove on the line from that groove's sphere centre
    through the ball's centre, so the ball's centre is always R - r from both sphere
    centres C_b (bottom groove, above it) and C_t (top groove, below it); at rest they
    are 2 (R - r) = R_hat apart on one vertical. When the top plate moves u_o
    horizontally, C_t moves u_o; the ball's centre, equidistant from C_b and C_t (and
    the top plate rising to keep both distances R - r), sits on the midpoint's
    vertical: u_o / 2 from the bottom groove's axis and u_o / 2 from the top groove's
    axis (rolling on both surfaces, it travels half the plate's displacement). On the
    bottom groove the contact point is R / (R - r) times further out along the same
    ray: at rho = (u_o / 2) R / (R - r) = u_o R / R_hat from the groove's axis; the top
    groove's contact point is the mirror image, u_o R / R_hat from its own axis. Both
    reach their rim (rho = a) together, at u_o = a R_hat / R; beyond it the ball rides
    on the rim's edge and the grooves no longer hold it. (The ball's centre is then
    only a (R - r) / R from the axis, and the old rule "ball travel d / 2 + r within
    the opening" wasted about r + (a r / R) of every groove.)

    >>> round(groove_capacity(0.32, 0.02, 0.08), 6)      # R_hat 0.60 m, 80 mm opening
    0.15
    >>> round(groove_capacity(0.30, 0.0095, 0.05), 5)    # about 2 a for r << R
    0.09683
    """
    for name, value in (("groove radius R", R), ("ball radius r", r), ("opening radius", opening_radius)):
        if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0):
            raise InputError(f"{name} must be a positive length in m, got {value!r}")
    if r >= R:
        raise InputError(f"ball radius r = {r:g} m must be smaller than the groove radius R = {R:g} m")
    if opening_radius > R:
        raise InputError(f"a groove of radius R = {R:g} m cannot open wider than R, got opening radius "
                         f"{opening_radius:g} m")
    return opening_radius * 2.0 * (R - r) / R
