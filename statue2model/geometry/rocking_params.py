"""Rocking parameters of a body on its base, for any excitation direction.

Symbols (MODEL.md section 1; SI units). The excitation acts along the horizontal
unit vector x at angle ``direction_deg`` (psi) in plan, measured from the body's
+x axis toward +y. The body lifts when the resultant of gravity and inertia leaves the
footprint's convex hull along the x ray through G's projection G' (MODEL.md section 1):
b_R is the length of the ray from G' along +x to the hull's boundary, b_L along -x, and the
body tips about the hull edge the ray leaves through (its tipping edge). Where that edge is
oblique to x the ray is shorter than the extreme vertex's projection on x (which overstates
the uplift); over all directions the minimum is the same (at an edge's normal).

=========  ============================================================
m          mass, kg
h          height of the centre of mass G above the base, m
b_R, b_L   horizontal distance along x from G's projection to the right
           (+x) and left (-x) pivot, m
I_G        moment of inertia about the horizontal axis through G
           perpendicular to x, kg m^2
d_i        sqrt(b_i^2 + h^2), pivot i to G, m            (i = L, R)
delta_i    atan(b_i / h), critical (overturning) angle, rad
I_i        I_G + m d_i^2, inertia about pivot i, kg m^2
p_i        sqrt(m g d_i / I_i), frequency parameter, rad/s
obliquity_i  the angle (deg) between x (or -x) and the normal of the tipping edge: 0 where the
           ray meets the edge square
a_i        g b_i / h, uplift acceleration (West), m/s^2: a ground acceleration
           of -a_R (toward -x) lifts the body onto its right pivot
           (theta > 0), one of +a_L onto its left pivot (theta < 0)
e_L, e_R   theoretical restitution, max(0, [I_G + m (h^2 - b_L b_R)] / I_i)
           (eq. 15): e_L for landing on the left edge (after rocking on the
           right pivot). Eq. 15 turns negative for a squat body (a rectangle
           with delta > asin(sqrt(2/3)) = 54.7 deg): the impact is then
           plastic, e = 0 (thesis ch. 2.2.3); ``e_L_raw``, ``e_R_raw`` keep
           eq. 15's own value
=========  ============================================================

Example
-------
>>> from statue2model.geometry.rocking_params import RockingParams
>>> A1 = RockingParams(m=1.286, h=0.2, b_L=0.0384, b_R=0.0384, I_G=1.286 * (0.0384**2 + 0.2**2) / 3)
>>> round(A1.delta_R, 4), round(A1.p_R, 3), round(A1.e_L, 3)
(0.1897, 6.011, 0.947)
"""
from __future__ import annotations

import math
import numbers
from dataclasses import dataclass, fields

import numpy as np

from ..errors import InputError
from .footprint import hull_edge_distances
from .massprops import MassProperties

from ..quantities import G  # m/s^2
"""Gravity, m/s^2 (MODEL.md)."""

PARAM_KEYS = (
    "m", "h", "b_L", "b_R", "I_G", "d_L", "d_R", "delta_L", "delta_R", "I_L", "I_R",
    "p_L", "p_R", "a_L", "a_R", "e_L", "e_R",
)


@dataclass(frozen=True)
class RockingParams:
    """The base quantities of the rocking model; everything else is derived (see module doc)."""

    m: float
    h: float
    b_L: float
    b_R: float
    I_G: float
    direction_deg: float = 0.0
    g: float = G
    obliquity_L: float = 0.0
    obliquity_R: float = 0.0

    def __post_init__(self):
        for name in ("m", "h", "b_L", "b_R", "I_G", "g"):
            value = getattr(self, name)
            if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0):
                raise InputError(f"rocking parameter {name} must be a positive finite number, got {value!r}")

    @property
    def d_L(self) -> float:
        return math.hypot(self.b_L, self.h)

    @property
    def d_R(self) -> float:
        return math.hypot(self.b_R, self.h)

    @property
    def delta_L(self) -> float:
        return math.atan2(self.b_L, self.h)

    @property
    def delta_R(self) -> float:
        return math.atan2(self.b_R, self.h)

    @property
    def I_L(self) -> float:
        return self.I_G + self.m * self.d_L**2

    @property
    def I_R(self) -> float:
        return self.I_G + self.m * self.d_R**2

    @property
    def p_L(self) -> float:
        return math.sqrt(self.m * self.g * self.d_L / self.I_L)

    @property
    def p_R(self) -> float:
        return math.sqrt(self.m * self.g * self.d_R / self.I_R)

    @property
    def a_L(self) -> float:
        return self.g * self.b_L / self.h

    @property
    def a_R(self) -> float:
        return self.g * self.b_R / self.h

    @property
    def e_L_raw(self) -> float:
        """Eq. 15 as it stands (negative for a squat body): [I_G + m (h^2 - b_L b_R)] / I_L."""
        return (self.I_G + self.m * (self.h**2 - self.b_L * self.b_R)) / self.I_L

    @property
    def e_R_raw(self) -> float:
        """Eq. 15 as it stands (negative for a squat body): [I_G + m (h^2 - b_L b_R)] / I_R."""
        return (self.I_G + self.m * (self.h**2 - self.b_L * self.b_R)) / self.I_R

    @property
    def e_L(self) -> float:
        """Theoretical restitution landing on the left edge: max(0, eq. 15); 0 is a plastic
        impact (the body stops rocking at it).

        >>> RockingParams.rectangular_block(b=0.5, h=0.3, m=500).e_L   # squat: eq. 15 gives -0.103
        0.0
        """
        return max(0.0, self.e_L_raw)

    @property
    def e_R(self) -> float:
        """Theoretical restitution landing on the right edge: max(0, eq. 15)."""
        return max(0.0, self.e_R_raw)

    def restitution_notes(self) -> list[str]:
        """One line per side where eq. 15 is negative and the impact is taken as plastic."""
        return [f"e_{side}: plastic impact (eq. 15 gives e = {raw:.3g} < 0): e_{side} = 0, the body stops "
                f"rocking at the first impact on that edge"
                for side, raw in (("L", self.e_L_raw), ("R", self.e_R_raw)) if raw < 0]

    def to_dict(self) -> dict:
        """All base and derived quantities under the names of the module table, and
        eq. 15's unclipped restitution (``e_L_raw``, ``e_R_raw``)."""
        out = {k: getattr(self, k) for k in PARAM_KEYS}
        out["e_L_raw"], out["e_R_raw"] = self.e_L_raw, self.e_R_raw
        out["direction_deg"] = self.direction_deg
        out["g"] = self.g
        out["obliquity_L"], out["obliquity_R"] = self.obliquity_L, self.obliquity_R
        return out

    @classmethod
    def rectangular_block(cls, b: float, h: float, m: float, g: float = G) -> "RockingParams":
        """Homogeneous rectangular block of half-width b and half-height h (m), mass m (kg):
        I_G = m (b^2 + h^2) / 3.

        >>> RockingParams.rectangular_block(0.0384, 0.2, 1.286).p_R  # Table 14, block A1
        6.0106...
        """
        return cls(m=m, h=h, b_L=b, b_R=b, I_G=m * (b * b + h * h) / 3.0, g=g)

    @classmethod
    def from_dict(cls, data: dict) -> "RockingParams":
        """Build from a ``props`` JSON (or any dict holding m, h, b_L, b_R, I_G)."""
        names = {f.name for f in fields(cls)}
        missing = [k for k in ("m", "h", "b_L", "b_R", "I_G") if k not in data]
        if missing:
            raise InputError(f"rocking parameters are missing {', '.join(missing)}")
        values = {}
        for k, v in data.items():
            if k not in names:
                continue
            # bool is an int in Python, and float("1e3") would take a string: only JSON numbers
            if isinstance(v, (bool, np.bool_)) or not isinstance(v, numbers.Real):
                raise InputError(f"rocking parameter {k} must be a number, got {json_text(v)}")
            values[k] = float(v)
        return cls(**values)


def json_text(v) -> str:
    """A value as JSON writes it (true, "1.2", null), for messages."""
    import json

    try:
        return json.dumps(v)
    except (TypeError, ValueError):
        return repr(v)


def unit_vectors(direction_deg: float) -> tuple[np.ndarray, np.ndarray]:
    """Excitation direction x and rocking axis y = z cross x, both horizontal (3,)."""
    psi = math.radians(direction_deg)
    return np.array([math.cos(psi), math.sin(psi), 0.0]), np.array([-math.sin(psi), math.cos(psi), 0.0])


def ray_exit(hull: np.ndarray, point: np.ndarray, x: np.ndarray) -> tuple[float, int, float]:
    """Where the ray from ``point`` (2,) along the unit vector ``x`` (2,) leaves the convex CCW ``hull``
    (k, 2): (length t, index k of the edge hull[k] -> hull[k + 1] it leaves through, cos of the angle
    between x and that edge's outward normal). The ray leaves through the edge whose line it meets first,
    t = min over the edges facing x (n . x > 0) of d_k / (n_k . x), d_k the point's distance to the edge's
    line (positive inside).

    >>> square = np.array([[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]])
    >>> t, k, c = ray_exit(square, np.zeros(2), np.array([1.0, 0.0]))
    >>> round(t, 12), k, round(c, 12)
    (1.0, 1, 1.0)
    >>> round(ray_exit(square, np.zeros(2), np.array([1.0, 1.0]) / 2 ** 0.5)[0], 12)    # the corner
    1.414213562373
    """
    normals, dist = hull_edge_distances(np.asarray(hull, dtype=float), np.asarray(point, dtype=float))
    c = normals @ np.asarray(x, dtype=float)
    facing = c > 1e-12
    if not facing.any():
        raise InputError("the footprint's hull is degenerate: no edge faces the direction")
    t = np.full(len(c), np.inf)
    t[facing] = dist[facing] / c[facing]
    k = int(np.argmin(t))
    return float(t[k]), k, float(c[k])


def tipping_edges(hull: np.ndarray, com_xy: np.ndarray, direction_deg: float) -> dict:
    """The hull edges the body tips about toward +x and -x of ``direction_deg``: {"R": ((x1, y1), (x2, y2)),
    "L": ...} in the body's plan frame (m), with each ray's length and obliquity (deg)."""
    x, _ = unit_vectors(direction_deg)
    hull = np.asarray(hull, dtype=float)
    out = {}
    for side, sign in (("R", 1.0), ("L", -1.0)):
        t, k, c = ray_exit(hull, com_xy, sign * x[:2])
        a, b = hull[k], hull[(k + 1) % len(hull)]
        out[side] = {"edge": [[float(a[0]), float(a[1])], [float(b[0]), float(b[1])]], "ray": t,
                     "obliquity_deg": math.degrees(math.acos(min(1.0, c)))}
    return out


def rocking_params(mass: MassProperties, hull: np.ndarray, direction_deg: float, g: float = G) -> RockingParams:
    """Rocking parameters along ``direction_deg`` for a body with mass properties ``mass``
    (base on z = 0) whose footprint has convex hull ``hull`` ((k, 2), m): b_R and b_L are the lengths
    of the rays from G's projection along +x and -x to the hull's boundary (:func:`ray_exit`)."""
    x, y = unit_vectors(direction_deg)
    hull = np.asarray(hull, dtype=float)
    com = np.asarray(mass.com[:2], dtype=float)
    if hull_edge_distances(hull, com)[1].min() <= 0:
        raise InputError(
            f"along {direction_deg:g} deg the centre of mass is outside the base: the body would not stand"
        )
    b_R, _, c_R = ray_exit(hull, com, x[:2])
    b_L, _, c_L = ray_exit(hull, com, -x[:2])
    if b_R <= 0 or b_L <= 0:
        raise InputError(
            f"along {direction_deg:g} deg the centre of mass is outside the base: the body would not stand"
        )
    return RockingParams(
        m=mass.mass, h=float(mass.com[2]), b_L=b_L, b_R=b_R,
        I_G=mass.inertia_about_axis(y), direction_deg=float(direction_deg) % 360.0, g=g,
        obliquity_L=math.degrees(math.acos(min(1.0, c_L))), obliquity_R=math.degrees(math.acos(min(1.0, c_R))),
    )


@dataclass(frozen=True)
class Rose:
    """Vulnerability rose: the rocking parameters for every plan direction.

    params        : one RockingParams per sampled direction psi (``step_deg`` apart)
    weakest_deg   : exact direction of the weakest uplift (the outward normal of the
                    footprint hull's edge nearest to G's projection)
    a_min         : the uplift acceleration there, m/s^2

    a_tip = a_R(psi) = g b_R(psi) / h is the ground acceleration (toward psi + 180 deg)
    that lifts the body toward psi; a_L(psi) = a_R(psi + 180 deg).
    """

    params: tuple[RockingParams, ...]
    weakest_deg: float
    a_min: float

    @property
    def direction_deg(self) -> np.ndarray:
        return np.array([p.direction_deg for p in self.params])

    @property
    def a_tip(self) -> np.ndarray:
        return np.array([p.a_R for p in self.params])

    def to_dict(self) -> dict:
        """Weakest direction and, per key of the rocking parameters, a list over directions."""
        rows = [p.to_dict() for p in self.params]
        out = {"weakest_direction_deg": self.weakest_deg, "a_min": self.a_min, "a_tip": self.a_tip.tolist()}
        out.update({k: [r[k] for r in rows] for k in ("direction_deg",) + PARAM_KEYS})
        return out

    def to_csv(self) -> str:
        """One line per direction: direction_deg and every rocking parameter."""
        keys = ("direction_deg",) + PARAM_KEYS
        lines = [",".join(keys)]
        for p in self.params:
            d = p.to_dict()
            lines.append(",".join(f"{d[k]:.10g}" for k in keys))
        return "\n".join(lines) + "\n"


def weakest_direction(mass: MassProperties, hull: np.ndarray, g: float = G) -> tuple[float, float]:
    """Exact weakest direction (deg) and its uplift acceleration (m/s^2).

    The minimum over psi of the distance from G's projection to the hull's supporting
    line is the distance to the nearest hull edge, reached along that edge's outward
    normal; ties go to the smallest angle.
    """
    normals, dist = hull_edge_distances(np.asarray(hull), mass.com[:2])
    near = dist <= dist.min() * (1 + 1e-9)
    angles = np.round(np.degrees(np.arctan2(normals[near, 1], normals[near, 0])) % 360.0, 9) % 360.0
    return float(angles.min()), g * float(dist.min()) / float(mass.com[2])


def vulnerability_rose(mass: MassProperties, hull: np.ndarray, step_deg: float = 1.0, g: float = G) -> Rose:
    """The rose at ``step_deg`` steps plus the exact weakest direction."""
    if not (np.isfinite(step_deg) and 0 < step_deg <= 90):
        raise InputError(f"rose step must be between 0 and 90 degrees, got {step_deg}")
    psi = np.arange(0.0, 360.0, step_deg)
    params = tuple(rocking_params(mass, hull, float(a), g) for a in psi)
    weakest_deg, a_min = weakest_direction(mass, hull, g)
    return Rose(params=params, weakest_deg=weakest_deg, a_min=a_min)
