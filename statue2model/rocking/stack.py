"""A statue on a pedestal: the 2D two-block rocking model (MODEL.md sections 2 and 10).

Two rigid bodies in the plane of the excitation, on a rigid floor that moves horizontally
(u_g'' in m/s^2, > 0 toward +x); no sliding at either interface (friction large enough), no
bouncing. Sources: Psycharis, "Dynamic behaviour of rocking two-block assemblies", EESD 19
(1990) 555-575; Spanos, Roussis & Politis, "Dynamic analysis of stacked rigid blocks", Soil
Dyn. Earthq. Eng. 21 (2001) 559-578 (the four response patterns and the impacts at both
interfaces). The equations below are derived here (Lagrange) in the project's notation.

Bodies (SI units, angles in rad)
--------------------------------
* Block 1, the pedestal (:class:`Pedestal`): a homogeneous rectangle, half-width b1,
  half-height h1, mass m1, I1 = m1 (b1^2 + h1^2) / 3 about its centre.
* Block 2, the statue: a :class:`~statue2model.geometry.rocking_params.RockingParams`
  (m2, h2 = h, b_L, b_R, I_G2 = I_G) standing on the pedestal's top with its centre of mass G2
  at the horizontal offset x2 from the pedestal's centre line.

Coordinates and sign convention (that of MODEL.md section 2 for each contact)
-----------------------------------------------------------------------------
* theta1 - the pedestal's rotation on the floor: > 0 about its right (+x) floor corner,
  < 0 about its left one.
* theta2 - the statue's rotation RELATIVE TO THE PEDESTAL on the pedestal's top: > 0 about
  its right pivot (at x2 + b_R from the pedestal's centre line), < 0 about its left pivot
  (at x2 - b_L). The statue's absolute rotation is theta1 + theta2.
* s1 = sign of theta1, s2 = sign of theta2 (the active pivots); s = 0: the contact is closed.

A body rotation by phi (> 0 clockwise, i.e. toward +x) maps a vector (x, y) of the body
to R(phi)(x, y) = (x cos phi + y sin phi, -x sin phi + y cos phi); the derivative of
w = R(phi) v is perp(w) = (w_y, -w_x). With P1 the floor pivot:

    a1 = (-s1 b1, h1)                  P1 -> G1 in the pedestal's frame
    c  = (x2 + s2 b2 - s1 b1, 2 h1)    P1 -> P2 (the statue's pivot); b2 = b_R (s2 > 0), b_L (s2 < 0)
    a2 = (-s2 b2, h2)                  P2 -> G2 in the statue's frame
    w1 = R(theta1) a1,  u = R(theta1) c,  w2 = R(theta1 + theta2) a2
    r_G1 = P1 + w1,  r_G2 = P1 + u + w2

Equations of motion (Lagrange; floor frame, the inertia force -m u_g'' on each body)
-----------------------------------------------------------------------------------
    k   = u . w2,          k' = dk/dtheta2 = u . perp(w2) = u_x w2_y - u_y w2_x
    I1P = I1 + m1 |a1|^2   (pedestal about its floor pivot)
    I2P = I_G2 + m2 |a2|^2 (statue about its pivot)
    M11 = I1P + m2 |c|^2 + I2P + 2 m2 k,   M12 = I2P + m2 k,   M22 = I2P
    V1  = m1 (u_g'' w1_y - g w1_x) + m2 [u_g'' (u_y + w2_y) - g (u_x + w2_x)]     (dV/dtheta1)
    V2  = m2 (u_g'' w2_y - g w2_x)                                                (dV/dtheta2)

    both rock:     M11 theta1'' + M12 theta2'' = -V1 - m2 k' (2 theta1' theta2' + theta2'^2)
                   M12 theta1'' + M22 theta2'' = -V2 + m2 k' theta1'^2
    pedestal rocks, statue stuck (theta2 = 0):   M11 theta1'' = -V1   (the composite body)
    statue rocks, pedestal at rest (theta1 = 0): M22 theta2'' = -V2   (exactly MODEL.md's eq. 35)
    rest:          theta1 = theta2 = 0

for each of the four pivot combinations (s1, s2). With theta1 = 0 the last line is
I_side theta2'' = -m2 g d [sin(delta - s2 theta2) + s2 (u_g''/g) cos(delta - s2 theta2)] s2, the
single body; with theta2 = 0 the pedestal carries the statue as one rigid body (the
*composite*: mass m1 + m2, centre of mass at x_c = m2 x2 / (m1 + m2) from the centre line
and h_c = [m1 h1 + m2 (2 h1 + h2)] / (m1 + m2) above the floor, b_L,c = b1 + x_c,
b_R,c = b1 - x_c, :attr:`StackModel.composite`).

Transitions
-----------
* A closed contact opens when its contact moment would change sign. For a closed contact j
  and a pivot side s, let theta_j''(s) be the acceleration of theta_j computed with contact j
  free on pivot s (the other contact as it is). The contact moment about that pivot that keeps
  theta_j'' = 0 is lambda_j(s) = -theta_j''(s) / (M^-1)_jj, and (M^-1)_jj > 0: it changes sign
  exactly where s theta_j''(s) does. So contact j stays closed while theta_j''(+1) <= 0 <=
  theta_j''(-1) and opens on pivot s when s theta_j''(s) > 0 (an event of the integration).
* From rest the two bodies are static, so the thresholds are closed forms: the statue lifts
  when u_g'' > g b_L / h2 (on its left pivot) or u_g'' < -g b_R / h2; the pedestal (with the
  statue stuck) when u_g'' > g b_L,c / h_c or u_g'' < -g b_R,c / h_c. Whichever limit is smaller
  in the direction of the ground's acceleration is reached first.
* Where several patterns are possible at an instant, the one chosen opens the fewest contacts
  that satisfy the conditions above (the contact whose event fired first).

Impacts (per-contact restitution, momentum of the other block; Spanos et al. 2001)
------------------------------------------------------------------------------------
When theta_i returns to 0 with theta_i' != 0, contact i changes pivot and

    theta_i'+ = e_i theta_i'-           (e_i: e_floor or e_top of the landing edge)

and the other coordinate's velocity follows from conservation of its generalised momentum
p_j = dT/dtheta_j' across the impact, whose impulses do no work in a virtual theta_j:

    impact of the statue (i = 2): p_1 = the angular momentum of the whole stack about the
      pedestal's floor pivot, conserved (the impulse between the blocks is internal);
    impact of the pedestal (i = 1): p_2 = the statue's angular momentum about its pivot on
      the pedestal's top, conserved (the floor's impulse does not act on the statue).

A closed contact j (theta_j = theta_j' = 0) stays closed unless that conservation, solved with
contact j free on a pivot s, gives s theta_j'+ > 0 (the impulse would pull it): then it opens
with that velocity (if its kinetic energy exceeds 1e-10 of its overturning barrier). If the
rule would raise the kinetic energy (a large e with strong coupling), the impact falls back to
Housner's plastic law for the assembly, the generalised-momentum projection q'+ = M_new^-1 B_new^T
D B_old q'- (angular momentum conserved about the new pivot for each subsystem, Psycharis 1990),
which never adds energy. Defaults: e_top = the statue's eq. 15 values (RockingParams.e_L,
e_R), e_floor = those of the composite (pedestal + statue as one body): each block's own
angular-momentum value; a float or an (e_L, e_R) pair overrides them (e_L: landing on the left
edge, after rocking on the right pivot).

With the pedestal at rest a statue impact is the single-body law theta2'+ = e theta2'- (the
pedestal stays down unless the impulse lifts it), and a pedestal impact with the statue stuck
is the composite's theta1'+ = e theta1'-: the model reduces to the single-body one in both limits.

Zeno: after an impact whose next excursion would peak below rest_tol * delta (the engine's rule,
theta'^2 / (2 |theta''|) < rest_tol delta) the contact closes.

Overturning
-----------
* The statue: |theta2| reaches its delta_side (relative to the pedestal; the project's
  criterion for a body on a fixed base, exact when the pedestal is at rest).
* The pedestal (with the statue): the centre of mass of the whole stack passes over the
  pedestal's floor pivot (with the statue stuck: |theta1| = the composite's delta_side).
The run stops at the first overturning; the result names the body.

Outputs: peak |theta| / delta of each body (the statue's over its own delta_side, the
pedestal's over the composite's), uplift times, impacts, the time spent in each pattern and a
history (t, theta1, theta2, pattern, and the horizontal absolute acceleration of the pedestal's
top under the statue's centre of mass, ``top_acc``: the input of the sliding of the statue,
:meth:`StackResult.top_motion`; impulses at impacts are not in it).

Two implementations
-------------------
:func:`simulate_stack` runs the compiled kernel (:mod:`statue2model.rocking.stack_kernel`, numba
DOP853 with the events on its dense output; ``method="compiled"``, the default) or the scipy one below
(``method="scipy"``: solve_ivp restarted at every event and record sample, the reference, 100-200 times
slower). Both give the whole StackResult (history, ``top_acc`` and impacts included) and agree to the
integration tolerance where the response is not chaotic (tests/test_stack_kernel.py). The scipy path
checks the events' signs at the ends of its steps only; the kernel at 1/8 of each step, so it also sees
a contact that crosses theta = 0 and comes back within one step (a pedestal rocking by microradians).
:func:`simulate_stack_batch` runs many (model, motion scale) rows at once in numba's threads.

Example
-------
>>> from statue2model.geometry.rocking_params import RockingParams
>>> from statue2model.hazard import motions
>>> statue = RockingParams.rectangular_block(b=0.1, h=0.5, m=200.0)
>>> model = StackModel(statue, Pedestal.box(width=0.6, depth=0.6, height=1.0, mass=300.0))
>>> model.first_to_lift                  # toward +x, toward -x: 0.2 g lifts the statue, 0.333 g the stack
('statue', 'statue')
>>> r = simulate_stack(model, motions.sine_pulse(0.25 * 9.81, 2.0))
>>> r.statue.uplift, r.pedestal.uplift, r.outcome
(True, False, 'statue rocks')
>>> round(r.statue.theta_max_over_delta, 3)
0.228
>>> simulate_stack(model, motions.sine_pulse(0.3 * 9.81, 2.0)).outcome
'statue overturns'
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

from ..errors import InputError
from ..geometry.rocking_params import RockingParams
from ..hazard.motions import GroundMotion, record
from .engine import FREE_TIME

PATTERNS = ("rest", "pedestal", "statue", "both")
"""The response patterns: rest; the pedestal rocks carrying the statue stuck to it; the statue
rocks on the pedestal at rest; both rock."""
OPEN_EPS = 1e-10   # a contact opened by an impulse carries at least this fraction of its barrier
MAX_EVENTS = 20_000
IMPACT_EPS = 1e-12
"""An impact is found where s theta = -IMPACT_EPS delta (not 0, where a contact that has just
opened starts): a root-finder would take the start itself for the impact."""


def _positive(name: str, value) -> float:
    if isinstance(value, bool):
        raise InputError(f"{name} must be a positive finite number, got {value!r}")
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise InputError(f"{name} must be a positive finite number, got {value!r}") from None
    if not (math.isfinite(v) and v > 0):
        raise InputError(f"{name} must be a positive finite number, got {value!r}")
    return v


@dataclass(frozen=True)
class Pedestal:
    """A homogeneous rectangular pedestal: half-width ``b`` and half-height ``h`` (m) along the
    excitation, mass ``m`` (kg); I_G = m (b^2 + h^2) / 3 (kg m^2) about its centre.

    >>> Pedestal.box(width=0.6, depth=0.5, height=1.0, mass=300.0)
    Pedestal(b=0.3, h=0.5, m=300.0)
    """

    b: float
    h: float
    m: float

    def __post_init__(self):
        for name in ("b", "h", "m"):
            object.__setattr__(self, name, _positive(f"pedestal {name}", getattr(self, name)))

    @classmethod
    def box(cls, width: float, depth: float, height: float, mass: float) -> "Pedestal":
        """From full sizes (m) and the mass (kg); ``width`` is along the excitation, ``depth``
        (across it) is not used in 2D but must be positive."""
        _positive("pedestal depth", depth)
        return cls(_positive("pedestal width", width) / 2, _positive("pedestal height", height) / 2,
                   _positive("pedestal mass", mass))

    @property
    def I_G(self) -> float:
        return self.m * (self.b**2 + self.h**2) / 3.0


def _e_pair(name: str, value, default: tuple[float, float]) -> tuple[float, float]:
    if value is None:
        return default
    pair = tuple(value) if isinstance(value, (tuple, list)) else (value, value)
    if len(pair) != 2:
        raise InputError(f"{name} must be a number or an (e_L, e_R) pair, got {value!r}")
    out = []
    for v in pair:
        try:
            v = float(v)
        except (TypeError, ValueError):
            raise InputError(f"{name} must be a number or an (e_L, e_R) pair, got {value!r}") from None
        if not (math.isfinite(v) and 0.0 <= v <= 1.0):
            raise InputError(f"coefficient of restitution {name} must lie in [0, 1], got {v}")
        out.append(v)
    return out[0], out[1]


@dataclass(frozen=True)
class StackModel:
    """A statue (``statue``, RockingParams) on a pedestal (``pedestal``) whose centre of mass is
    ``x2`` (m) to the right of the pedestal's centre line; ``e_floor`` and ``e_top`` the coefficients
    of restitution of the pedestal on the floor and of the statue on the pedestal: None (the default:
    eq. 15 of the composite and of the statue), a float, or an (e_L, e_R) pair (module docstring).
    Both statue pivots must lie on the pedestal's top."""

    statue: RockingParams
    pedestal: Pedestal
    x2: float = 0.0
    e_floor: object = None
    e_top: object = None

    def __post_init__(self):
        if not isinstance(self.statue, RockingParams):
            raise InputError("statue must be a RockingParams")
        if not isinstance(self.pedestal, Pedestal):
            raise InputError("pedestal must be a Pedestal")
        try:
            x2 = float(self.x2)
        except (TypeError, ValueError):
            raise InputError(f"statue offset x2 must be a number of m, got {self.x2!r}") from None
        if not math.isfinite(x2):
            raise InputError(f"statue offset x2 must be finite, got {self.x2!r}")
        object.__setattr__(self, "x2", x2)
        b1, s = self.pedestal.b, self.statue
        if abs(x2 - s.b_L) > b1 * (1 + 1e-12):
            raise InputError(f"the statue's left pivot (x2 - b_L = {x2 - s.b_L:.4g} m) is off the pedestal's top "
                             f"(half-width {b1:.4g} m)")
        if x2 + s.b_R > b1 * (1 + 1e-12):
            raise InputError(f"the statue's right pivot (x2 + b_R = {x2 + s.b_R:.4g} m) is off the pedestal's top "
                             f"(half-width {b1:.4g} m)")
        c = self.composite
        object.__setattr__(self, "e_floor", _e_pair("e_floor", self.e_floor, (c.e_L, c.e_R)))
        object.__setattr__(self, "e_top", _e_pair("e_top", self.e_top, (s.e_L, s.e_R)))

    def kernel_vector(self, rest_tol: float = 1e-9) -> np.ndarray:
        """The model vector of the compiled kernel (:mod:`statue2model.rocking.stack_kernel`, indices
        ``B1`` ... ``ACC_TOL``), the numbers of the scipy path's mechanics (``_Mech``)."""
        from . import stack_kernel as SK

        me = _Mech(self)
        c, s = self.composite, self.statue
        P = np.zeros(SK.N_P)
        P[SK.B1], P[SK.H1], P[SK.M1], P[SK.I1] = me.b1, me.h1, me.m1, me.I1
        P[SK.M2], P[SK.I2], P[SK.H2], P[SK.BL2], P[SK.BR2] = me.m2, me.I2, me.h2, me.bL2, me.bR2
        P[SK.X2], P[SK.GR] = me.x2, me.g
        P[SK.D1P], P[SK.D1N], P[SK.D2P], P[SK.D2N] = me.delta1[1], me.delta1[-1], me.delta2[1], me.delta2[-1]
        P[SK.P1], P[SK.P2] = me.p1, me.p2
        P[SK.E1P], P[SK.E1N], P[SK.E2P], P[SK.E2N] = me.e1[1], me.e1[-1], me.e2[1], me.e2[-1]
        P[SK.BAR1], P[SK.BAR2] = me.barrier[1], me.barrier[2]
        P[SK.LS_UP], P[SK.LS_DN], P[SK.LP_UP], P[SK.LP_DN] = s.a_L, s.a_R, c.a_L, c.a_R
        P[SK.REST_TOL] = float(rest_tol)
        P[SK.ACC_TOL] = 1e-9 * me.g / min(me.h1, me.h2)
        return P

    @property
    def composite(self) -> RockingParams:
        """The pedestal and the statue as one rigid body rocking on the pedestal's floor corners."""
        p, s = self.pedestal, self.statue
        m = p.m + s.m
        xc = s.m * self.x2 / m
        y1, y2 = p.h, 2 * p.h + s.h
        hc = (p.m * y1 + s.m * y2) / m
        ic = p.I_G + p.m * (xc**2 + (y1 - hc) ** 2) + s.I_G + s.m * ((self.x2 - xc) ** 2 + (y2 - hc) ** 2)
        return RockingParams(m=m, h=hc, b_L=p.b + xc, b_R=p.b - xc, I_G=ic, g=s.g)

    @property
    def uplift_limits(self) -> dict:
        """Ground accelerations (m/s^2) that lift each body from rest: {"statue": (a_L, a_R),
        "pedestal": (a_L, a_R)}; a_L toward +x lifts on the left pivot, -a_R on the right."""
        c, s = self.composite, self.statue
        return {"statue": (s.a_L, s.a_R), "pedestal": (c.a_L, c.a_R)}

    @property
    def first_to_lift(self) -> tuple[str, str]:
        """(toward +x, toward -x): which body lifts first under a ground acceleration growing from
        rest in each direction ('statue', 'pedestal' or 'both' at a tie)."""
        lim = self.uplift_limits
        out = []
        for k in (0, 1):
            a, b = lim["statue"][k], lim["pedestal"][k]
            out.append("both" if math.isclose(a, b, rel_tol=1e-12) else "statue" if a < b else "pedestal")
        return out[0], out[1]


# -- the mechanics ------------------------------------------------------------------------
class _Mech:
    """The model's numbers and the equations (module docstring); no state."""

    def __init__(self, model: StackModel):
        p, s = model.pedestal, model.statue
        self.b1, self.h1, self.m1, self.I1 = p.b, p.h, p.m, p.I_G
        self.m2, self.I2, self.h2, self.bL2, self.bR2 = s.m, s.I_G, s.h, s.b_L, s.b_R
        self.x2, self.g = model.x2, s.g
        c = model.composite
        self.delta1 = {1: c.delta_R, -1: c.delta_L}
        self.delta2 = {1: s.delta_R, -1: s.delta_L}
        self.p1, self.p2 = max(c.p_L, c.p_R), max(s.p_L, s.p_R)
        self.e1 = {1: model.e_floor[0], -1: model.e_floor[1]}     # by the side rocked on before
        self.e2 = {1: model.e_top[0], -1: model.e_top[1]}
        self.barrier = {1: min(c.m * c.g * (c.d_L - c.h), c.m * c.g * (c.d_R - c.h)),
                        2: min(s.m * s.g * (s.d_L - s.h), s.m * s.g * (s.d_R - s.h))}

    def vectors(self, th1, th2, s1, s2):
        s1 = s1 or 1
        s2 = s2 or 1
        b2 = self.bR2 if s2 > 0 else self.bL2
        a1x, a1y = -s1 * self.b1, self.h1
        cx, cy = self.x2 + s2 * b2 - s1 * self.b1, 2 * self.h1
        a2x, a2y = -s2 * b2, self.h2
        c1, n1 = math.cos(th1), math.sin(th1)
        c12, n12 = math.cos(th1 + th2), math.sin(th1 + th2)
        w1 = (a1x * c1 + a1y * n1, -a1x * n1 + a1y * c1)
        u = (cx * c1 + cy * n1, -cx * n1 + cy * c1)
        w2 = (a2x * c12 + a2y * n12, -a2x * n12 + a2y * c12)
        return w1, u, w2, (a1x * a1x + a1y * a1y), (cx * cx + cy * cy), (a2x * a2x + a2y * a2y)

    def system(self, th1, th2, w1d, w2d, s1, s2, a):
        """(M11, M12, M22, F1, F2): M q'' = F."""
        w1, u, w2, A1, C, A2 = self.vectors(th1, th2, s1, s2)
        m1, m2, g = self.m1, self.m2, self.g
        k = u[0] * w2[0] + u[1] * w2[1]
        kp = u[0] * w2[1] - u[1] * w2[0]
        I1P, I2P = self.I1 + m1 * A1, self.I2 + m2 * A2
        M11 = I1P + m2 * C + I2P + 2 * m2 * k
        M12 = I2P + m2 * k
        V1 = m1 * (a * w1[1] - g * w1[0]) + m2 * (a * (u[1] + w2[1]) - g * (u[0] + w2[0]))
        V2 = m2 * (a * w2[1] - g * w2[0])
        F1 = -V1 - m2 * kp * (2 * w1d * w2d + w2d * w2d)
        F2 = -V2 + m2 * kp * w1d * w1d
        return M11, M12, I2P, F1, F2

    def acc(self, y, s1, s2, a):
        """(theta1'', theta2'') of the pattern (s1, s2) (0: that contact closed)."""
        if s1 == 0 and s2 == 0:
            return 0.0, 0.0
        M11, M12, M22, F1, F2 = self.system(y[0], y[1], y[2], y[3], s1, s2, a)
        if s2 == 0:
            return F1 / M11, 0.0
        if s1 == 0:
            return 0.0, F2 / M22
        det = M11 * M22 - M12 * M12
        return (M22 * F1 - M12 * F2) / det, (M11 * F2 - M12 * F1) / det

    def mass(self, th1, th2, s1, s2):
        M11, M12, M22, _, _ = self.system(th1, th2, 0.0, 0.0, s1, s2, 0.0)
        return np.array([[M11, M12], [M12, M22]])

    def body_velocity_map(self, th1, th2, s1, s2):
        """B (6 x 2): (vG1x, vG1y, w1, vG2x, vG2y, w2) per unit (theta1', theta2')."""
        w1, u, w2, *_ = self.vectors(th1, th2, s1, s2)
        return np.array([[w1[1], 0.0], [-w1[0], 0.0], [1.0, 0.0],
                         [u[1] + w2[1], w2[1]], [-u[0] - w2[0], -w2[0]], [1.0, 1.0]])

    @property
    def D(self):
        return np.array([self.m1, self.m1, self.I1, self.m2, self.m2, self.I2])

    def com_x(self, th1, th2, s1, s2):
        """Horizontal position of the stack's centre of mass from the floor pivot, times s1."""
        w1, u, w2, *_ = self.vectors(th1, th2, s1, s2)
        return (s1 or 1) * (self.m1 * w1[0] + self.m2 * (u[0] + w2[0])) / (self.m1 + self.m2)

    def top_point_acc(self, th1, w1d, a1, s1):
        """Horizontal acceleration, relative to the floor, of the pedestal's top under G2."""
        s1 = s1 or 1
        cx, cy = self.x2 - s1 * self.b1, 2 * self.h1
        c1, n1 = math.cos(th1), math.sin(th1)
        rx, ry = cx * c1 + cy * n1, -cx * n1 + cy * c1
        return a1 * ry - w1d * w1d * rx

    def energy(self, y, s1, s2):
        """Kinetic + potential energy (J) above the stack at rest, no ground motion."""
        w1, u, w2, *_ = self.vectors(y[0], y[1], s1, s2)
        M = self.mass(y[0], y[1], s1, s2)
        q = np.array([y[2], y[3]])
        pot = self.g * (self.m1 * (w1[1] - self.h1) + self.m2 * (u[1] + w2[1] - 2 * self.h1 - self.h2))
        return 0.5 * float(q @ M @ q) + pot


def free_energy(model: StackModel, state) -> float:
    """Kinetic + potential energy (J) of the stack in ``state`` = (theta1, theta2, theta1', theta2')
    (rad, rad/s), measured from the stack at rest; the pivots follow the signs of theta (of theta'
    where theta = 0).

    >>> from statue2model.geometry.rocking_params import RockingParams
    >>> m = StackModel(RockingParams.rectangular_block(0.1, 0.5, 200.0), Pedestal(0.3, 0.5, 300.0))
    >>> free_energy(m, (0.0, 0.0, 0.0, 0.0))
    0.0
    """
    y = [float(v) for v in state]
    if len(y) != 4 or not all(math.isfinite(v) for v in y):
        raise InputError(f"state must be 4 finite numbers (theta1, theta2, theta1', theta2'), got {state!r}")
    s1 = _side(y[0], y[2])
    s2 = _side(y[1], y[3])
    return _Mech(model).energy(y, s1, s2)


def _side(th, om) -> int:
    if th != 0.0:
        return 1 if th > 0 else -1
    if om != 0.0:
        return 1 if om > 0 else -1
    return 0


# -- the ground motion, plainly -------------------------------------------------------------
class _Ground:
    def __init__(self, motion: GroundMotion):
        self.m = motion
        self.t0, self.t1 = motion.start, motion.end
        self.kind = motion.kind
        if motion.kind == "record":
            self.ts = motion.start + motion.dt * np.arange(motion.samples.size)
            self.s = np.asarray(motion.samples, dtype=float)
        if motion.kind == "harmonic":
            self.w = 2 * math.pi * motion.freq

    def __call__(self, t: float) -> float:
        if self.kind == "none" or not (self.t0 <= t < self.t1):
            return 0.0
        m = self.m
        if self.kind == "harmonic":
            return m.amp * math.sin(self.w * (t - self.t0) + m.phase)
        if self.kind == "rect":
            return m.amp
        return float(np.interp(t, self.ts, self.s))

    def max_step(self) -> float:
        if self.kind == "harmonic":
            return 1.0 / (50 * self.m.freq)
        return np.inf

    def piece(self, t: float):
        """(end, u_g'') of the smooth piece of the motion that starts at t: a record's sample
        interval (u_g'' linear in it), else up to the motion's next start or end."""
        if self.kind == "record" and self.t0 <= t < self.t1:
            k = min(int(np.searchsorted(self.ts, t, side="right")) - 1, self.ts.size - 2)
            ta, tb = float(self.ts[k]), float(self.ts[k + 1])
            a0, slope = float(self.s[k]), float(self.s[k + 1] - self.s[k]) / (tb - ta)
            return tb, lambda x: a0 + slope * (x - ta)
        end = self.t0 if t < self.t0 else self.t1 if t < self.t1 else math.inf
        return end, self

    def next_exceedance(self, ta: float, tb: float, up: float, dn: float):
        """First t in [ta, tb] where u_g'' > up or u_g'' < -dn (None if none)."""
        lo, hi = max(ta, self.t0), min(tb, self.t1)
        if self.kind == "none" or lo >= hi:
            return None

        def over(x):
            return np.maximum(x - up, -dn - x)

        if self.kind == "rect":
            return lo if over(self.m.amp) > 0 else None
        if self.kind == "record":
            inner = self.ts[(self.ts > lo) & (self.ts < hi)]
            tt = np.concatenate([[lo], inner])
            aa = np.interp(tt, self.ts, self.s)
        else:
            n = max(int(math.ceil((hi - lo) * self.m.freq * 4000)), 2)
            tt = np.linspace(lo, hi, n + 1)[:-1]
            aa = self.m.amp * np.sin(self.w * (tt - self.t0) + self.m.phase)
        f = over(aa)
        k = int(np.argmax(f > 0)) if np.any(f > 0) else -1
        if k < 0:
            if self.kind == "record":       # the last piece up to hi
                tl, al = tt[-1], aa[-1]
                ah = float(np.interp(hi, self.ts, self.s))
                if max(ah - up, -dn - ah) > 0:
                    fa, fb = float(over(al)), float(max(ah - up, -dn - ah))
                    return float(tl + (hi - tl) * (-fa) / (fb - fa)) if fa < 0 else float(tl)
            return None
        if k == 0:
            return float(tt[0])
        ta_, tb_ = float(tt[k - 1]), float(tt[k])
        if self.kind == "record":
            level = up if aa[k] > up else -dn
            return ta_ + (tb_ - ta_) * (level - aa[k - 1]) / (aa[k] - aa[k - 1])
        level = up if aa[k] > up else -dn
        return brentq(lambda x: self(x) - level, ta_, tb_, xtol=1e-14, rtol=1e-15)


# -- results ------------------------------------------------------------------------------
@dataclass(frozen=True)
class BodyResult:
    """One body's response: ``theta_max`` peak |theta| (rad; the statue's relative to the pedestal),
    ``theta_max_over_delta`` its peak over its delta_side (the statue's own, the pedestal's the
    composite's), ``uplift``/``uplift_time`` (s, first), ``n_impacts``, ``overturned`` and
    ``overturn_time`` (s)."""

    theta_max: float
    theta_max_over_delta: float
    uplift_time: float | None
    n_impacts: int
    overturned: bool
    overturn_time: float | None

    @property
    def uplift(self) -> bool:
        return self.uplift_time is not None

    def to_dict(self) -> dict:
        return {"theta_max": self.theta_max, "theta_max_over_delta": self.theta_max_over_delta,
                "uplift": self.uplift, "uplift_time": self.uplift_time, "n_impacts": self.n_impacts,
                "overturned": self.overturned, "overturn_time": self.overturn_time}


@dataclass(frozen=True)
class Impact:
    """One impact: time (s), contact (1 the pedestal on the floor, 2 the statue on the pedestal),
    ``side`` the edge it lands on ("L"/"R"), ``speed`` |theta_i'| before (rad/s), the stack's
    energy before and after (J, no ground motion term: exact for the free motion)."""

    t: float
    contact: int
    side: str
    speed: float
    energy_before: float
    energy_after: float


@dataclass(frozen=True, eq=False)
class StackResult:
    """What one run of :func:`simulate_stack` gives (SI units, rad).

    ``statue``, ``pedestal``: :class:`BodyResult`; ``outcome``: 'no motion', 'statue rocks',
    'pedestal rocks', 'both rock', 'statue overturns' or 'stack overturns' (the pedestal with the
    statue), with ' (stopped: too many events)' if the event guard ended the run;
    ``pattern_times``: s spent in each of :data:`PATTERNS`; ``t_rest``: when the stack came to rest
    for good after moving (None: never moved, overturned or moving at the end); ``impacts``: tuple of
    :class:`Impact`; history ``t``, ``theta1``, ``theta2``, ``omega1``, ``omega2``, ``pattern`` (index
    into PATTERNS) and ``top_acc`` (m/s^2, absolute horizontal acceleration of the pedestal's top under
    the statue's centre of mass) every ``dt_out`` s from 0; ``stats``: solver counters."""

    model: StackModel
    motion: GroundMotion
    statue: BodyResult
    pedestal: BodyResult
    outcome: str
    pattern_times: dict
    t_end: float
    t_rest: float | None
    impacts: tuple
    dt_out: float
    t: np.ndarray = field(repr=False)
    theta1: np.ndarray = field(repr=False)
    theta2: np.ndarray = field(repr=False)
    omega1: np.ndarray = field(repr=False)
    omega2: np.ndarray = field(repr=False)
    pattern: np.ndarray = field(repr=False)
    top_acc: np.ndarray = field(repr=False)
    stats: dict = field(default_factory=dict)

    # -- the response every consumer reads (rocking/bodies.py Response): the statue's, which falls with
    # its pedestal
    @property
    def overturned(self) -> bool:
        return bool(self.statue.overturned or self.pedestal.overturned)

    @property
    def theta_max_over_delta(self) -> float:
        return 1.0 if self.overturned else float(self.statue.theta_max_over_delta)

    @property
    def uplift_time(self) -> float | None:
        times = [t for t in (self.statue.uplift_time, self.pedestal.uplift_time) if t is not None]
        return min(times) if times else None

    @property
    def n_impacts(self) -> int:
        return int(self.statue.n_impacts)

    def top_motion(self) -> GroundMotion:
        """The pedestal top's horizontal acceleration as a record GroundMotion (the input of
        :func:`statue2model.rocking.sliding.simulate_sliding` for the statue on the pedestal)."""
        return record(self.top_acc, self.dt_out, label=f"pedestal top under {self.motion.label}")

    def to_dict(self) -> dict:
        return {"statue": self.statue.to_dict(), "pedestal": self.pedestal.to_dict(), "outcome": self.outcome,
                "pattern_times": dict(self.pattern_times), "t_end": self.t_end, "t_rest": self.t_rest,
                "n_impacts": len(self.impacts), "stats": dict(self.stats)}


def _pattern_index(s1, s2) -> int:
    return (1 if s1 else 0) + (2 if s2 else 0)


# -- the run ------------------------------------------------------------------------------
class _Run:
    """The state of one run (local to :func:`simulate_stack`)."""

    def __init__(self, model, motion, t_end, rtol, rest_tol, max_events, grid):
        self.mech = _Mech(model)
        self.ground = _Ground(motion)
        self.t_end, self.rtol, self.rest_tol, self.max_events = t_end, rtol, rest_tol, max_events
        me = self.mech
        self.acc_tol = 1e-9 * me.g / min(me.h1, me.h2)
        self.atol = np.array([rtol * min(me.delta1.values()), rtol * min(me.delta2.values()),
                              rtol * min(me.delta1.values()) * me.p1, rtol * min(me.delta2.values()) * me.p2])
        self.grid = grid
        self.k_out = 0
        n = grid.size
        self.out = {k: np.zeros(n) for k in ("theta1", "theta2", "omega1", "omega2", "top_acc")}
        self.out["pattern"] = np.zeros(n, dtype=int)
        self.qmax = {1: {1: 0.0, -1: 0.0}, 2: {1: 0.0, -1: 0.0}}
        self.uplift = {1: None, 2: None}
        self.n_imp = {1: 0, 2: 0}
        self.overturn = {1: None, 2: None}
        self.impacts = []
        self.ptimes = dict.fromkeys(PATTERNS, 0.0)
        self.n_events = 0
        self.stats = {"n_rhs": 0, "n_segments": 0}

    # bookkeeping
    def note_peak(self, y, s1, s2):
        for i, s, th in ((1, s1, y[0]), (2, s2, y[1])):
            if s:
                self.qmax[i][s] = max(self.qmax[i][s], abs(th))

    def note_uplift(self, t, s1, s2):
        for i, s in ((1, s1), (2, s2)):
            if s and self.uplift[i] is None:
                self.uplift[i] = t

    def fill(self, t_until, y, pat, inclusive=False):
        """History samples in [current, t_until) (or ]) of a still state: the ground's acceleration on top."""
        g = self.grid
        k = self.k_out
        while k < g.size and (g[k] < t_until or (inclusive and g[k] <= t_until)):
            self._write(k, g[k], y, pat)
            k += 1
        self.k_out = k

    def _write(self, k, t, y, pat):
        me, o = self.mech, self.out
        a = self.ground(t)
        o["theta1"][k], o["theta2"][k], o["omega1"][k], o["omega2"][k] = y
        o["pattern"][k] = _pattern_index(*pat)
        if pat[0]:
            a1, _ = me.acc(y, pat[0], pat[1], a)
            o["top_acc"][k] = a + me.top_point_acc(y[0], y[2], a1, pat[0])
        else:
            o["top_acc"][k] = a

    # pattern choice
    def choose(self, t, y, pat, prefer=None):
        """The pattern at (t, y) for the open contacts of ``pat`` and the closed ones decided by their
        contact moments (module docstring); ``prefer`` = (contact, side) whose opening fired."""
        me = self.mech
        a = self.ground(t)
        opts = [[pat[0]] if pat[0] else [0, 1, -1], [pat[1]] if pat[1] else [0, 1, -1]]
        cands = [(c1, c2) for c1 in opts[0] for c2 in opts[1]]
        accs = {c: me.acc(y, c[0], c[1], a) for c in cands}
        tol = self.acc_tol

        def consistent(c):
            for i in (0, 1):
                if pat[i]:
                    continue
                if c[i]:
                    slack = tol if prefer is not None and prefer == (i + 1, c[i]) else -tol
                    if c[i] * accs[c][i] <= -slack:
                        return False
                else:
                    for s in (1, -1):
                        cc = list(c)
                        cc[i] = s
                        if s * accs[tuple(cc)][i] > tol:
                            return False
            return True

        def rank(c):
            pref = 0 if prefer is not None and c[prefer[0] - 1] == prefer[1] else 1
            return pref, sum(1 for i in (0, 1) if c[i] and not pat[i])

        for c in sorted(cands, key=rank):
            if consistent(c):
                return c
        if prefer is not None:
            c = list(pat)
            c[prefer[0] - 1] = prefer[1]
            return tuple(c)
        return pat

    # impacts
    def impact(self, t, y, pat, i, depth: int = 0):
        me = self.mech
        y = list(y)
        y[i - 1] = 0.0
        s_old = pat[i - 1]
        w_old = np.array([y[2], y[3]])
        e = (me.e1 if i == 1 else me.e2)[s_old]
        new = list(pat)
        new[i - 1] = -s_old
        j = 2 if i == 1 else 1
        B_old = me.body_velocity_map(y[0], y[1], *pat)
        v_old = B_old @ w_old
        D = me.D
        E_old = me.energy(y, *pat)
        q = np.zeros(2)
        q[i - 1] = e * w_old[i - 1]
        if pat[j - 1]:
            M = me.mass(y[0], y[1], *new)
            p_j = (me.body_velocity_map(y[0], y[1], *new)[:, j - 1] * D) @ v_old
            q[j - 1] = (p_j - M[j - 1, i - 1] * q[i - 1]) / M[j - 1, j - 1]
        else:
            for s in (1, -1):
                trial = list(new)
                trial[j - 1] = s
                M = me.mass(y[0], y[1], *trial)
                p_j = (me.body_velocity_map(y[0], y[1], *trial)[:, j - 1] * D) @ v_old
                wj = (p_j - M[j - 1, i - 1] * q[i - 1]) / M[j - 1, j - 1]
                if s * wj > 0 and 0.5 * M[j - 1, j - 1] * wj * wj > OPEN_EPS * me.barrier[j]:
                    q[j - 1] = wj
                    new = trial
                    break
        y_new = [y[0], y[1], q[0], q[1]]
        E_new = me.energy(y_new, *new)
        if E_new > E_old * (1 + 1e-12) + 1e-300:
            # Housner's plastic law for the assembly: the generalised-momentum projection
            open_ = [k for k in (0, 1) if new[k]]
            B = me.body_velocity_map(y[0], y[1], *new)[:, open_]
            M = B.T @ (D[:, None] * B)
            q = np.zeros(2)
            q[open_] = np.linalg.solve(M, B.T @ (D * v_old))
            y_new = [y[0], y[1], q[0], q[1]]
            E_new = me.energy(y_new, *new)
        self.n_imp[i] += 1
        self.impacts.append(Impact(t, i, "L" if s_old > 0 else "R", abs(float(w_old[i - 1])), E_old, E_new))
        # Zeno: close contact i when its next excursion would be negligible
        acc = me.acc(y_new, *new, self.ground(t))
        c = -new[i - 1] * acc[i - 1]
        wp = abs(y_new[1 + i])
        delta = (me.delta1 if i == 1 else me.delta2)[new[i - 1]]
        if wp == 0.0 or (c > 0.0 and wp * wp / (2.0 * c) < self.rest_tol * delta):
            y_new[1 + i] = 0.0
            new[i - 1] = 0
        # the other contact, open but at its pivot's closing point (|theta_j| within the impact event's offset),
        # now driven into it by this impact: it impacts at once (its event would start on the wrong side and
        # never fire: the body would then rock about a pivot it has passed)
        j = 2 if i == 1 else 1
        sj = new[j - 1]
        if sj and depth == 0 and sj * y_new[j - 1] <= IMPACT_EPS * (me.delta1 if j == 1 else me.delta2)[sj] \
                and sj * y_new[j + 1] < 0.0:
            return self.impact(t, y_new, tuple(new), j, depth=1)
        return y_new, tuple(new)

    # one integrated segment
    def segment(self, t0, t1, y0, pat, ground):
        me = self.mech
        s1, s2 = pat
        stats = self.stats

        def rhs(t, y):
            stats["n_rhs"] += 1
            a1, a2 = me.acc(y, s1, s2, ground(t))
            return [y[2], y[3], a1, a2]

        events, tags = [], []
        tol = self.acc_tol

        def add(fn, tag, terminal, direction):
            fn.terminal, fn.direction = terminal, direction
            events.append(fn)
            tags.append(tag)

        if s1:
            e1 = IMPACT_EPS * me.delta1[s1]
            add(lambda t, y: s1 * y[0] + e1, ("impact", 1), True, -1)
            add(lambda t, y: me.com_x(y[0], y[1], s1, s2), ("overturn", 1), True, 1)
            add(lambda t, y: y[2], ("peak", 1), False, 0)
        if s2:
            d2 = me.delta2[s2]
            e2 = IMPACT_EPS * d2
            add(lambda t, y: s2 * y[1] + e2, ("impact", 2), True, -1)
            add(lambda t, y: s2 * y[1] - d2, ("overturn", 2), True, 1)
            add(lambda t, y: y[3], ("peak", 2), False, 0)
        for i in (1, 2):
            if pat[i - 1]:
                continue
            for s in (1, -1):
                c = list(pat)
                c[i - 1] = s
                c = tuple(c)
                add(lambda t, y, c=c, i=i, s=s: s * me.acc(y, c[0], c[1], ground(t))[i - 1] - tol,
                    ("open", i, s), True, 1)
        g = self.grid
        k0 = self.k_out
        k1 = k0
        while k1 < g.size and g[k1] < t1:
            k1 += 1
        t_eval = np.concatenate([g[k0:k1], [t1]])
        sol = solve_ivp(rhs, (t0, t1), y0, method="DOP853", rtol=self.rtol, atol=self.atol, events=events,
                        t_eval=t_eval, max_step=self.ground.max_step(), first_step=min(t1 - t0, 0.01 / self.mech.p2))
        stats["n_segments"] += 1
        if sol.status < 0:
            raise RuntimeError(f"stack solver failed after t = {t0:.6g} s: {sol.message}")
        tt = np.asarray(sol.t, dtype=float)
        yy = np.asarray(sol.y, dtype=float).reshape(4, tt.size)
        n_out = min(tt.size, k1 - k0)
        for n in range(n_out):
            self._write(k0 + n, tt[n], yy[:, n], pat)
            self.note_peak(yy[:, n], s1, s2)
        self.k_out = k0 + n_out
        for tag, ye in zip(tags, sol.y_events):
            if tag[0] == "peak":
                for ype in ye:
                    self.note_peak(ype, s1, s2)
        if sol.status == 1:
            t_hit, hit, y_hit = math.inf, None, None
            for tag, te, ye in zip(tags, sol.t_events, sol.y_events):
                if tag[0] != "peak" and te.size and te[0] < t_hit:
                    t_hit, hit, y_hit = float(te[0]), tag, ye[0]
            return t_hit, list(y_hit), hit
        return t1, list(yy[:, -1]), None


def simulate_stack(model: StackModel, motion: GroundMotion, t_end: float | None = None, rtol: float = 1e-9, *,
                   theta0=(0.0, 0.0), omega0=(0.0, 0.0), dt_out: float | None = None, rest_tol: float = 1e-9,
                   max_events: int = MAX_EVENTS, method: str = "compiled") -> StackResult:
    """Integrate the two-block model under ``motion`` from (theta0, omega0) = ((theta1, theta2),
    (theta1', theta2')) at t = 0 (rad, rad/s; theta2 relative to the pedestal).

    ``t_end`` (s) defaults to the end of the motion + engine.FREE_TIME; the run stops earlier at
    the first overturning, or once the stack is at rest after the motion. ``rtol``: the
    integrator's relative tolerance (DOP853). ``dt_out``: the history's step (default the record's
    dt, 5 ms for other motions). ``max_events`` ends a run that chatters (the outcome says so).

    ``method``: "compiled" (the default: the numba kernel of :mod:`statue2model.rocking.stack_kernel`,
    about 100 times faster) or "scipy" (solve_ivp's DOP853 with events, restarted at every event and
    record sample: the reference). Both give the whole StackResult, history and impacts included;
    they agree to the integration tolerance where the motion is not chaotic (tests/test_stack_kernel.py).
    ``stats`` differ: the compiled path counts steps ("n_steps", "n_rejected", "n_rhs"), the scipy
    path right-hand sides and segments."""
    if method not in ("compiled", "scipy"):
        raise InputError(f"method must be 'compiled' or 'scipy', got {method!r}")
    if not isinstance(model, StackModel):
        raise InputError("model must be a StackModel")
    if not isinstance(motion, GroundMotion):
        raise InputError("motion must be a GroundMotion")
    if not (1e-13 <= rtol <= 1e-3):
        raise InputError(f"rtol must lie in [1e-13, 1e-3], got {rtol}")
    try:
        th = [float(v) for v in theta0]
        om = [float(v) for v in omega0]
    except (TypeError, ValueError):
        raise InputError("theta0 and omega0 must be pairs of numbers (pedestal, statue)") from None
    if len(th) != 2 or len(om) != 2 or not all(math.isfinite(v) for v in th + om):
        raise InputError("theta0 and omega0 must be pairs of finite numbers (pedestal, statue)")
    if t_end is None:
        t_end = motion.end + FREE_TIME
    t_end = float(t_end)
    if not (math.isfinite(t_end) and t_end > 0):
        raise InputError(f"t_end must be a positive time in s, got {t_end}")
    if dt_out is None:
        dt_out = motion.dt if motion.kind == "record" else 5e-3
    if not (math.isfinite(dt_out) and dt_out > 0):
        raise InputError(f"dt_out must be a positive time step, got {dt_out}")
    grid = np.arange(int(math.floor(t_end / dt_out + 1e-9)) + 1) * dt_out
    if not (math.isfinite(rest_tol) and rest_tol >= 0):
        raise InputError(f"rest_tol must be a non-negative number, got {rest_tol}")
    me = _Mech(model)
    s1, s2 = _side(th[0], om[0]), _side(th[1], om[1])
    for i, s, v in ((1, s1, th[0]), (2, s2, th[1])):
        d = (me.delta1 if i == 1 else me.delta2)[s] if s else 1.0
        if s and s * v >= d:
            raise InputError(f"initial rotation theta{i} = {v} rad is at or beyond the overturning angle {d:.4g} rad")
    if method == "compiled":
        return _simulate_compiled(model, motion, t_end, rtol, th, om, grid, rest_tol, int(max_events))
    run = _Run(model, motion, t_end, rtol, rest_tol, max_events, grid)
    y = [th[0], th[1], om[0], om[1]]
    t = 0.0
    pat = run.choose(t, y, (s1, s2))
    run.note_uplift(0.0, *pat)
    run.note_peak(y, *pat)
    breaks = sorted({b for b in (motion.start, motion.end) if 0.0 < b < t_end})
    t_rest = None
    truncated = False
    moved = pat != (0, 0)
    last_t, same_t = -1.0, 0
    while t < t_end:
        if run.n_events >= max_events:
            truncated = True
            break
        if t == last_t:
            same_t += 1
            if same_t > 50:
                raise RuntimeError(f"stack model stalled at t = {t:.9g} s (pattern {PATTERNS[_pattern_index(*pat)]})")
        else:
            last_t, same_t = t, 0
        if pat == (0, 0):
            if moved and t_rest is None:
                t_rest = t
            lim = model.uplift_limits
            up = min(lim["statue"][0], lim["pedestal"][0])
            dn = min(lim["statue"][1], lim["pedestal"][1])
            t_up = run.ground.next_exceedance(t, t_end, up, dn)
            if t_up is None:
                run.ptimes["rest"] += t_end - t
                run.fill(t_end, y, pat, inclusive=True)
                t = t_end
                break
            run.ptimes["rest"] += t_up - t
            run.fill(t_up, y, pat)
            t = t_up
            a = run.ground(t)
            if a > 0:
                side, which = -1, (1 if lim["pedestal"][0] <= lim["statue"][0] else 2)
            else:
                side, which = 1, (1 if lim["pedestal"][1] <= lim["statue"][1] else 2)
            pat = run.choose(t, y, pat, prefer=(which, side))
            if pat == (0, 0):       # touched the limit without passing it: look a little later
                t_next = next((b for b in breaks if b > t), None)
                t = min(t + max(1e-9, 1e-12 * t), t_end if t_next is None else t_next)
                continue
            run.n_events += 1
            run.note_uplift(t, *pat)
            moved = True
            t_rest = None
            continue
        t_piece, ground = run.ground.piece(t)
        t_stop = min(next((b for b in breaks if b > t), t_end), t_piece)
        name = PATTERNS[_pattern_index(*pat)]
        t_new, y_new, hit = run.segment(t, t_stop, y, pat, ground)
        run.ptimes[name] += t_new - t
        t, y = t_new, y_new
        run.note_peak(y, *pat)
        if hit is None:
            if t >= t_end:
                break
            pat = run.choose(t, y, pat)      # the ground may have jumped (a pulse's end)
            run.note_uplift(t, *pat)
            continue
        run.n_events += 1
        if hit[0] == "overturn":
            run.overturn[hit[1]] = t
            break
        if hit[0] == "impact":
            y, pat = run.impact(t, y, pat, hit[1])
            pat = run.choose(t, y, pat)
        else:                                   # a closed contact opens
            pat = run.choose(t, y, pat, prefer=(hit[1], hit[2]))
        run.note_uplift(t, *pat)
        if pat == (0, 0) and t >= motion.end:
            t_rest = t
            run.fill(t_end, y, pat, inclusive=True)
            run.ptimes["rest"] += t_end - t
            t = t_end
            break
    return _result(model, motion, run, t, t_rest if pat == (0, 0) else None, truncated)


def _result(model, motion, run, t_final, t_rest, truncated) -> StackResult:
    me = run.mech
    n = run.k_out

    def body(i, delta):
        q = run.qmax[i]
        def opt(x):
            return None if x is None else float(x)

        return BodyResult(theta_max=float(max(q.values())),
                          theta_max_over_delta=float(max(q[1] / delta[1], q[-1] / delta[-1])),
                          uplift_time=opt(run.uplift[i]), n_impacts=run.n_imp[i],
                          overturned=run.overturn[i] is not None, overturn_time=opt(run.overturn[i]))

    statue, pedestal = body(2, me.delta2), body(1, me.delta1)
    if statue.overturned:
        outcome = "statue overturns"
    elif pedestal.overturned:
        outcome = "stack overturns"
    elif statue.uplift and pedestal.uplift:
        outcome = "both rock"
    elif statue.uplift:
        outcome = "statue rocks"
    elif pedestal.uplift:
        outcome = "pedestal rocks"
    else:
        outcome = "no motion"
    if truncated:
        outcome += " (stopped: too many events)"
    o = run.out
    stats = dict(run.stats, n_events=run.n_events, t_final=t_final, truncated=truncated)
    return StackResult(model=model, motion=motion, statue=statue, pedestal=pedestal, outcome=outcome,
                       pattern_times={k: float(v) for k, v in run.ptimes.items()}, t_end=run.t_end,
                       t_rest=None if statue.overturned or pedestal.overturned or not (statue.uplift or pedestal.uplift)
                       else (None if t_rest is None else float(t_rest)), impacts=tuple(run.impacts), dt_out=float(run.grid[1] - run.grid[0])
                       if run.grid.size > 1 else run.t_end,
                       t=run.grid[:n].copy(), theta1=o["theta1"][:n].copy(), theta2=o["theta2"][:n].copy(),
                       omega1=o["omega1"][:n].copy(), omega2=o["omega2"][:n].copy(), pattern=o["pattern"][:n].copy(),
                       top_acc=o["top_acc"][:n].copy(), stats=stats)


# -- the compiled path ----------------------------------------------------------------------
MAX_STEPS = 20_000_000
"""The compiled kernel's guard on steps (accepted + rejected) of one run."""
_IMPACT_CAP = 4096


def _outcome(S, SK, truncated: bool) -> str:
    out = SK.OUTCOMES[int(S[SK.S_OUTCOME])]
    return out + " (stopped: too many events)" if truncated else out


def _simulate_compiled(model, motion, t_end, rtol, th, om, grid, rest_tol, max_events) -> StackResult:
    from ..compute.compile import ensure_compiled
    from . import stack_kernel as SK

    ensure_compiled()
    P = model.kernel_vector(rest_tol)
    kind, M, smp = motion.kernel_args()
    y0 = np.array([th[0], th[1], om[0], om[1]], dtype=float)
    dt_out = float(grid[1] - grid[0]) if grid.size > 1 else float(t_end)
    out = np.zeros((grid.size, 6))
    S = np.zeros(SK.N_S)
    cap = _IMPACT_CAP
    while True:
        imp = np.zeros((cap, 6))
        n = SK.simulate_stack_kernel(P, int(kind), M, smp, y0, float(t_end), float(rtol), int(max_events),
                                     int(MAX_STEPS), dt_out, out, imp, S)
        n_imp = int(S[SK.S_N_IMP1] + S[SK.S_N_IMP2])
        if n_imp <= cap:
            break
        cap = n_imp                      # more impacts than rows: once more with room for all
    if S[SK.S_STATUS] != SK.STATUS_OK:
        why = "too many steps" if S[SK.S_STATUS] == SK.STATUS_MAX_STEPS else "stalled"
        raise RuntimeError(f"stack solver failed after t = {S[SK.S_T_FINAL]:.6g} s ({why})")
    return _result_from_stats(model, motion, float(t_end), S, SK, dt_out, grid[:n], out[:n], imp[:n_imp])


def _result_from_stats(model, motion, t_end, S, SK, dt_out, t, out, imp) -> StackResult:
    c, s = model.composite, model.statue

    def opt(x):
        return None if not math.isfinite(x) else float(x)

    def body(qr, ql, tmod, up, n_imp, ot, t_ot):
        return BodyResult(theta_max=float(max(S[qr], S[ql])), theta_max_over_delta=float(S[tmod]),
                          uplift_time=opt(S[up]), n_impacts=int(S[n_imp]), overturned=bool(S[ot] > 0),
                          overturn_time=opt(S[t_ot]))

    statue = body(SK.S_QMAX2_R, SK.S_QMAX2_L, SK.S_TMOD2, SK.S_T_UPLIFT2, SK.S_N_IMP2, SK.S_OVERTURNED2,
                  SK.S_T_OVERTURN2)
    pedestal = body(SK.S_QMAX1_R, SK.S_QMAX1_L, SK.S_TMOD1, SK.S_T_UPLIFT1, SK.S_N_IMP1, SK.S_OVERTURNED1,
                    SK.S_T_OVERTURN1)
    del c, s
    truncated = bool(S[SK.S_TRUNCATED] > 0)
    impacts = tuple(Impact(float(r[0]), int(r[1]), "L" if r[2] < 0 else "R", float(r[3]), float(r[4]), float(r[5]))
                    for r in imp)
    stats = {"n_steps": int(S[SK.S_N_STEPS]), "n_rejected": int(S[SK.S_N_REJECT]), "n_rhs": int(S[SK.S_N_RHS]),
             "n_events": int(S[SK.S_N_EVENTS]), "t_final": float(S[SK.S_T_FINAL]), "truncated": truncated,
             "method": "compiled"}
    return StackResult(model=model, motion=motion, statue=statue, pedestal=pedestal,
                       outcome=_outcome(S, SK, truncated),
                       pattern_times={k: float(S[SK.S_PT_REST + i]) for i, k in enumerate(PATTERNS)}, t_end=t_end,
                       t_rest=opt(S[SK.S_T_REST]), impacts=impacts, dt_out=dt_out, t=np.array(t, dtype=float),
                       theta1=out[:, 0].copy(), theta2=out[:, 1].copy(), omega1=out[:, 2].copy(),
                       omega2=out[:, 3].copy(), pattern=out[:, 4].astype(int), top_acc=out[:, 5].copy(), stats=stats)


def simulate_stack_batch(models, motion: GroundMotion, scales=None, t_end: float | None = None, rtol: float = 1e-9,
                         *, rest_tol: float = 1e-9, max_events: int = MAX_EVENTS, theta0=(0.0, 0.0),
                         omega0=(0.0, 0.0)) -> np.ndarray:
    """Many runs of the compiled two-block model in one call (numba threads), statistics only.

    Row i: the model ``models[i]`` (a StackModel, or its :meth:`StackModel.kernel_vector` row: ``models``
    may be a list of models or an (n, N_P) array of vectors) under ``motion`` with its accelerations
    times ``scales[i]`` (default 1; a record's samples are shared by every row, the scale is the gain of
    the kernel's motion vector). Returns the statistics matrix (n, N_S) of
    :mod:`statue2model.rocking.stack_kernel` (indices ``S_*``; outcome codes ``OUTCOMES``). A row is
    the computation of :func:`simulate_stack` (method "compiled") of that model, to the bit, under
    ``motion.scaled(scales[i])`` for a pulse (the same amplitude) and under the record itself for a
    scale of 1; a record with another scale differs from ``simulate_stack`` of the scaled record by the
    rounding of the scaled samples only (here the gain multiplies each sample inside the kernel).

    >>> from statue2model.geometry.rocking_params import RockingParams
    >>> from statue2model.hazard import motions
    >>> from statue2model.rocking import stack_kernel as SK
    >>> model = StackModel(RockingParams.rectangular_block(0.1, 0.5, 200.0), Pedestal(0.3, 0.5, 300.0))
    >>> S = simulate_stack_batch([model, model], motions.sine_pulse(9.81, 2.0), scales=[0.25, 0.3])
    >>> [SK.OUTCOMES[int(k)] for k in S[:, SK.S_OUTCOME]]
    ['statue rocks', 'statue overturns']
    """
    from ..compute.compile import ensure_compiled
    from .batch import _threading_layer
    from . import stack_kernel as SK
    from .kernel import suffix_extremes

    if not isinstance(motion, GroundMotion):
        raise InputError("motion must be a GroundMotion")
    if isinstance(models, np.ndarray) and models.ndim == 2:
        if models.shape[1] != SK.N_P:
            raise InputError(f"model vectors must have {SK.N_P} columns, got {models.shape[1]}")
        Pm = np.array(models, dtype=float)             # a writable C copy: the kernel's one signature
    else:
        models = list(models)
        if not all(isinstance(m, StackModel) for m in models):
            raise InputError("models must be StackModels or an (n, N_P) array of their kernel vectors")
        Pm = np.array([m.kernel_vector(rest_tol) for m in models], dtype=float).reshape(len(models), SK.N_P)
    n = Pm.shape[0]
    scales = np.array(np.broadcast_to(1.0 if scales is None else np.asarray(scales, dtype=float), (n,)))   # writable
    if not np.all(np.isfinite(scales)):
        raise InputError("scales must be finite numbers")
    if not (1e-13 <= rtol <= 1e-3):
        raise InputError(f"rtol must lie in [1e-13, 1e-3], got {rtol}")
    t_end = float(motion.end + FREE_TIME if t_end is None else t_end)
    if not (math.isfinite(t_end) and t_end > 0):
        raise InputError(f"t_end must be a positive time in s, got {t_end}")
    y0 = np.array([*theta0, *omega0], dtype=float)
    if y0.shape != (4,) or not np.all(np.isfinite(y0)):
        raise InputError("theta0 and omega0 must be pairs of finite numbers (pedestal, statue)")
    ensure_compiled()
    _threading_layer()
    kind, M, smp = motion.kernel_args()
    M = np.array(M, dtype=float)
    hi, lo = suffix_extremes(smp)
    S = np.zeros((n, SK.N_S))
    if n:
        SK.simulate_stack_batch(Pm, scales, int(kind), M, smp, hi, lo, y0, t_end, float(rtol), int(max_events),
                                int(MAX_STEPS), S)
    bad = S[:, SK.S_STATUS] != SK.STATUS_OK
    if np.any(bad):
        raise RuntimeError(f"stack solver did not finish {int(bad.sum())} of {n} runs")
    return S
