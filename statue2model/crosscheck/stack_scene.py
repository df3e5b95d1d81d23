"""Scene (c): a statue standing on a free pedestal, the pedestal on a rigid floor, in PyBullet.

Frame and conventions are those of :mod:`statue2model.crosscheck.statue_scene`: the scene is
turned so that the excitation is +x, theta > 0 is a rotation of a body's (initially vertical) z axis
toward +x in the x-z plane. The pedestal's own frame has its base at z = 0 and its top at
z = ``height``; the statue's hull frame (StatueScene) has its base at z = 0.

Ground motion: as in every scene here (world.py), the floor is static and the ground acceleration
u_g''(t) is applied to both bodies as a gravity tilt (-u_g'', 0, -g), exact for the motion relative
to the floor.

Friction: PyBullet multiplies the two bodies' lateral coefficients. The floor gets ``mu_floor``,
the pedestal 1 and the statue ``mu_top``: the pedestal-floor pair then has mu_floor, the
statue-pedestal pair mu_top (the statue-floor pair, mu_top mu_floor, only acts once the statue has
fallen off). Restitution is 0 everywhere (contact.py: Housner's impact is the plastic one of a
rigid body).

What is read (every engine step, from the stored poses):

* theta1, the pedestal's rotation relative to the floor; theta2, the statue's rotation relative to
  the pedestal (R_rel = R_pedestal^T R_statue, theta2 = atan2(R_rel[0, 2], R_rel[2, 2])).
* Lift-off (statue_scene.LIFT_HEIGHT for LIFT_STEPS steps): the statue's highest base point above
  the pedestal's top, measured in the pedestal's frame; the pedestal's highest base point above the
  floor.
* Overturning: the statue when |theta2| reaches its own delta of that side (or when its centre of
  mass falls below the pedestal's top: it fell off); the pedestal when |theta1| reaches the
  stack's composite delta (the pedestal and the statue as one rigid body, the statue where it was
  placed: :meth:`StackScene.composite_params`).
* Sliding: the horizontal displacement of a body's *pivot point* relative to its support, from its
  position at rest. The pivot point is the middle of the base's pivot edge on the side the body
  leans to: (x_R, y_G, 0) of its own frame when its theta >= 0, (x_L, y_G, 0) when theta < 0
  (y_G: the centre of mass's y). A rigid rotation about that edge leaves it in place, so rocking
  without slip reads 0; an upright body's two pivot points move together. The statue's is
  expressed in the pedestal's top frame (relative to the pedestal: it rotates and slides with it),
  the pedestal's in the floor's. ``slide_x`` is its signed x component, the peak the largest
  horizontal magnitude.

Example
-------
>>> from statue2model.crosscheck.statue_scene import StatueScene
>>> from statue2model.hazard import motions
>>> st = StatueScene.block(b=0.25, h=0.2, m=100.0)
>>> sc = StackScene.box(st, width=3.0, depth=3.0, height=0.2, mass=1e4, mu_top=0.2)
>>> r = simulate_stack_3d(sc, motions.rect_pulse(0.4 * 9.81, 0.3))
>>> round(r.statue.peak_slide, 2), r.statue.lifted, r.pedestal.peak_slide < 1e-4, r.stopped
(0.18, False, True, 'rest')
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ..geometry.rocking_params import RockingParams
from .contact import ContactSettings
from .statue_scene import (
    STATUE_SETTINGS,
    StatueScene,
    _lift_off_time,
    add_statue,
    inertia_frame,
)
from .world import run_clock, SimSettings, World, matrices_from_quats, quat_from_matrix, real_time_factor, step_grid, step_mean_acc

STACK_SETTINGS = STATUE_SETTINGS
"""Engine settings of the stack scene when none are given: the statue scene's (dt 2 ms, 50 solver
iterations), so that a stack and :func:`simulate_statue` compare at the same settings. Measured
(tests/test_stack_scene.py): the statue's peak rotation within 1-2 % of the statue on the floor, the
sliding peaks within 0.2 % of the exact Coulomb block, ~50-90 x real time (CPU time, 2 shared
cores); dt 1 ms gives the same to ~1 % at about half the speed."""
BLOCK = 128
"""Steps between two overturning / finiteness checks of the stored poses (steps run past an
overturn are not reported)."""
REST_SPEED = 2e-3
"""A body is at rest (early stop, after the motion) when its centre of mass moves slower than this,
m/s, relative to the floor ..."""
REST_RATE = 1e-2
"""... and turns slower than this, rad/s ..."""
REST_TIME = 0.25
"""... for this long, s, both bodies (longer than a rocking peak's instant of zero velocity)."""
REST_EVERY = 5
"""Steps between two rest checks."""
TOL = 1e-9
"""Geometric tolerance, m, of the 'statue on the top' check."""


def _finite(v: float, what: str, positive: bool = True) -> float:
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v) or (positive and v <= 0):
        raise InputError(f"{what} must be a {'positive ' if positive else ''}finite number, got {v!r}")
    return float(v)


@dataclass(frozen=True, eq=False)
class StackScene:
    """A statue on a pedestal on the floor, in the excitation frame (excitation along +x).

    statue             : the statue (StatueScene; its hull base at z = 0 of its frame)
    pedestal           : the pedestal as a rigid body (a StatueScene: hull with base at z = 0, mass
                         kg, centre of mass m, inertia kg m^2); :meth:`box` makes the box one
    offset_x, offset_y : the statue's centre of mass from the pedestal's centre of mass, in plan, m
    mu_top             : friction coefficient statue / pedestal top
    mu_floor           : friction coefficient pedestal / floor
    """

    statue: StatueScene
    pedestal: StatueScene
    offset_x: float = 0.0
    offset_y: float = 0.0
    mu_top: float = 1.0
    mu_floor: float = 1.0

    def __post_init__(self):
        for name in ("offset_x", "offset_y"):
            _finite(getattr(self, name), f"statue offset {name}", positive=False)
        for name in ("mu_top", "mu_floor"):
            v = getattr(self, name)
            _finite(v, f"friction {name}", positive=False)
            if not 0 <= v <= 5:
                raise InputError(f"friction {name} must be in 0..5, got {v!r}")
        top = self.pedestal.hull[:, 2].max()
        face = self.pedestal.hull[self.pedestal.hull[:, 2] >= top - TOL][:, :2]
        if len(face) < 3:
            raise InputError("the pedestal has no flat top to stand the statue on")
        from scipy.spatial import ConvexHull, QhullError

        try:
            eq = ConvexHull(face).equations                   # a x + b y + c <= 0 inside
        except (QhullError, ValueError):
            raise InputError("the pedestal's top has no area to stand the statue on") from None
        base = self.statue.hull[self.statue.hull[:, 2] == 0.0][:, :2] + self._shift()[:2]
        out = (base @ eq[:, :2].T + eq[:, 2]).max()
        if out > TOL:
            raise InputError(f"the statue's base is not on the pedestal's top: it overhangs by {out * 1000:.3g} mm "
                             f"(offset {self.offset_x:g}, {self.offset_y:g} m)")

    @classmethod
    def box(cls, statue: StatueScene, width: float, depth: float, height: float, mass: float,
            offset_x: float = 0.0, offset_y: float = 0.0, mu_top: float = 1.0, mu_floor: float = 1.0) -> StackScene:
        """The statue on a homogeneous box pedestal, ``width`` along x (the excitation), ``depth``
        along y, ``height`` (m), ``mass`` (kg, inertia the box's), centred on the floor's origin."""
        for v, what in ((width, "pedestal width"), (depth, "pedestal depth"), (height, "pedestal height"),
                        (mass, "pedestal mass")):
            _finite(v, what)
        ped = StatueScene.block(b=0.5 * width, h=0.5 * height, m=mass, depth=depth, g=statue.params.g)
        ped = StatueScene(hull=ped.hull, mass=ped.mass, com=ped.com, inertia=ped.inertia, params=ped.params,
                          x_R=ped.x_R, x_L=ped.x_L, name=f"pedestal {width:g} x {depth:g} x {height:g} m")
        return cls(statue=statue, pedestal=ped, offset_x=offset_x, offset_y=offset_y, mu_top=mu_top,
                   mu_floor=mu_floor)

    @property
    def height(self) -> float:
        """Height of the pedestal's top, m."""
        return float(self.pedestal.hull[:, 2].max())

    def _shift(self) -> np.ndarray:
        """Translation (3,) from the statue's frame to the pedestal's (the statue on the top, its
        centre of mass at the pedestal's plus the offset), m."""
        return np.array([self.pedestal.com[0] + self.offset_x - self.statue.com[0],
                         self.pedestal.com[1] + self.offset_y - self.statue.com[1], self.height])

    def composite_params(self) -> RockingParams:
        """The stack as one rigid body rocking on the pedestal's base (the statue fixed where it
        stands): total mass, its centre of mass's height h and distances b_R, b_L to the pedestal's
        pivots x_R, x_L (m), I_G about it (kg m^2). Its a_R, a_L (m/s^2) are the ground
        accelerations that lift the pedestal, its delta the pedestal's overturning angle."""
        ms, mp = self.statue.mass, self.pedestal.mass
        cs, cp = self.statue.com + self._shift(), np.asarray(self.pedestal.com, dtype=float)
        m = ms + mp
        c = (ms * cs + mp * cp) / m

        def iyy(mass, inertia, at):
            d = at - c
            return float(inertia[1, 1]) + mass * (d[0] ** 2 + d[2] ** 2)

        return RockingParams(m=m, h=float(c[2]), b_L=float(c[0] - self.pedestal.x_L),
                             b_R=float(self.pedestal.x_R - c[0]),
                             I_G=float(iyy(ms, self.statue.inertia, cs) + iyy(mp, self.pedestal.inertia, cp)),
                             g=self.statue.params.g)

    def to_dict(self) -> dict:
        ped = self.pedestal
        return {"statue": self.statue.name, "statue_mass": self.statue.mass, "pedestal": ped.name,
                "pedestal_mass": ped.mass, "pedestal_width": ped.x_R - ped.x_L, "pedestal_height": self.height,
                "offset_x": self.offset_x, "offset_y": self.offset_y, "mu_top": self.mu_top,
                "mu_floor": self.mu_floor}


@dataclass(frozen=True, eq=False)
class BodyResult:
    """One body of a stack run (SI units, angles rad).

    theta          : samples of its rotation relative to its support (statue: the pedestal;
                     pedestal: the floor), theta > 0 toward +x
    slide_x        : samples of its pivot point's x displacement relative to its support, m (module doc)
    theta_max      : peak |theta|; theta_max_over_delta: peak |theta| / delta of the side it leans to
                     (statue: its own RockingParams; pedestal: the stack's composite)
    uplift_time    : lift-off, s (its highest base point above its support by LIFT_HEIGHT for
                     LIFT_STEPS steps), None if never
    max_lift       : largest height, m, of its highest base point above its support
    overturned, overturn_time : |theta| reached delta (statue: or it fell off the top), s
    peak_slide     : largest horizontal displacement of its pivot point relative to its support, m
    """

    theta: np.ndarray
    slide_x: np.ndarray
    theta_max: float
    theta_max_over_delta: float
    uplift_time: float | None
    max_lift: float
    overturned: bool
    overturn_time: float | None
    peak_slide: float

    @property
    def lifted(self) -> bool:
        return self.uplift_time is not None

    def to_dict(self) -> dict:
        return {"theta_max": self.theta_max, "theta_max_over_delta": self.theta_max_over_delta,
                "lift_off": self.lifted, "uplift_time": self.uplift_time, "max_lift": self.max_lift,
                "overturned": self.overturned, "overturn_time": self.overturn_time, "peak_slide": self.peak_slide}


@dataclass(frozen=True, eq=False)
class Stack3DResult:
    """A 3D run of the stack: ``statue`` and ``pedestal`` (:class:`BodyResult`), the sample times
    ``t`` (s), ``finite`` (no NaN in the state; False: the run stopped at the last finite step),
    ``stopped`` ("end", "rest": both bodies at rest after the motion, "overturn"), the cost
    ``wall_time`` (s of wall clock) and ``cpu_time`` (process CPU s of the whole call) over ``steps``
    engine steps of ``settings.dt``."""

    scene: StackScene
    settings: SimSettings
    t: np.ndarray
    statue: BodyResult
    pedestal: BodyResult
    finite: bool
    stopped: str
    wall_time: float
    steps: int
    cpu_time: float = 0.0

    @property
    def simulated_time(self) -> float:
        return self.steps * self.settings.dt

    @property
    def real_time_factor(self) -> float:
        """Simulated seconds per process CPU second (the wall clock's when no CPU time was measured)."""
        return real_time_factor(self.steps, self.settings.dt, self.cpu_time or self.wall_time)

    def to_dict(self) -> dict:
        """Finite numbers only (None where undefined)."""
        rtf = self.real_time_factor
        return {"scene": self.scene.to_dict(), "statue": self.statue.to_dict(), "pedestal": self.pedestal.to_dict(),
                "finite": self.finite, "stopped": self.stopped, "simulated_time_s": self.simulated_time,
                "wall_time_s": self.wall_time, "cpu_time_s": self.cpu_time, "steps": self.steps,
                "real_time_factor": rtf if math.isfinite(rtf) else None, "settings": self.settings.to_dict()}


def _link_poses(P: np.ndarray, Q: np.ndarray, V: np.ndarray, com: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Frames of a body's own (hull) coordinates from its base poses P (m, 3), Q (m, 4) (PyBullet's:
    the inertial frame, turned by V to the principal axes): origins O (m, 3) and rotations R (m, 3, 3)."""
    R = matrices_from_quats(Q) @ V.T
    return P - R @ com, R


def _theta(R: np.ndarray) -> np.ndarray:
    return np.arctan2(R[:, 0, 2], R[:, 2, 2])


class _Bodies:
    """The kinematics of both bodies from their stored poses (every quantity per step)."""

    def __init__(self, scene: StackScene):
        self.scene = scene
        self.Vs = inertia_frame(scene.statue.inertia)[1]
        self.Vp = inertia_frame(scene.pedestal.inertia)[1]
        st, pd = scene.statue, scene.pedestal
        self.base_s = st.hull[st.hull[:, 2] == 0.0]
        self.base_p = pd.hull[pd.hull[:, 2] == pd.hull[:, 2].min()]
        self.piv_s = {s: np.array([x, st.com[1], 0.0]) for s, x in (("R", st.x_R), ("L", st.x_L))}
        self.piv_p = {s: np.array([x, pd.com[1], 0.0]) for s, x in (("R", pd.x_R), ("L", pd.x_L))}
        self.delta_s = (st.params.delta_R, st.params.delta_L)
        cp = scene.composite_params()
        self.delta_p = (cp.delta_R, cp.delta_L)
        self.top = scene.height

    def frames(self, Ps, Qs, Pp, Qp):
        Os, Rs = _link_poses(Ps, Qs, self.Vs, self.scene.statue.com)
        Op, Rp = _link_poses(Pp, Qp, self.Vp, self.scene.pedestal.com)
        Rt = Rp.transpose(0, 2, 1)
        Rrel = Rt @ Rs
        Orel = np.einsum("kij,kj->ki", Rt, Os - Op)        # statue origin in the pedestal's frame
        return Orel, Rrel, Op, Rp

    def thetas(self, Ps, Qs, Pp, Qp) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(theta2 of the statue relative to the pedestal, theta1 of the pedestal, height of the statue's
        centre of mass above the pedestal's top, m), each (m,)."""
        Orel, Rrel, _, Rp = self.frames(Ps, Qs, Pp, Qp)
        zc = Orel[:, 2] + Rrel[:, 2, :] @ self.scene.statue.com - self.top
        return _theta(Rrel), _theta(Rp), zc

    def events(self, Ps, Qs, Pp, Qp) -> tuple[int | None, int | None, int | None]:
        """First rows of a block of poses where the statue overturned, the pedestal overturned, and a
        pose is not finite (None: none)."""
        with np.errstate(invalid="ignore"):
            th2, th1, zc = self.thetas(Ps, Qs, Pp, Qp)
            bad = ~(np.isfinite(th1) & np.isfinite(th2) & np.isfinite(zc) & np.isfinite(Ps).all(axis=1)
                    & np.isfinite(Pp).all(axis=1))
            ot_s = (np.abs(th2) >= np.where(th2 > 0, *self.delta_s)) | (zc < 0)
            ot_p = np.abs(th1) >= np.where(th1 > 0, *self.delta_p)
        nb = int(np.argmax(bad)) if bad.any() else None
        if nb is not None:
            ot_s[nb:] = ot_p[nb:] = False

        def first(a):
            return int(np.argmax(a)) if a.any() else None

        return first(ot_s), first(ot_p), nb

    def histories(self, Ps, Qs, Pp, Qp) -> dict:
        """Per-step theta, lift (highest base point above the support, m) and pivot-point
        displacement (m, 2) of each body relative to its support, from step 0."""
        Orel, Rrel, Op, Rp = self.frames(Ps, Qs, Pp, Qp)
        out = {}
        for name, O, R, base, piv in (("statue", Orel, Rrel, self.base_s, self.piv_s),
                                      ("pedestal", Op, Rp, self.base_p, self.piv_p)):
            th = _theta(R)
            z = O[:, 2, None] + np.ascontiguousarray(R[:, 2, :]) @ np.ascontiguousarray(base.T)   # contiguous: fast matmul
            lift = z.max(axis=1) - (self.top if name == "statue" else 0.0)
            pts = {s: O + R @ q for s, q in piv.items()}
            side = np.where(th >= 0, 1.0, 0.0)[:, None]
            pt = side * pts["R"] + (1 - side) * pts["L"]
            ref = side * pts["R"][0] + (1 - side) * pts["L"][0]
            out[name] = {"theta": th, "lift": lift, "slide": (pt - ref)[:, :2]}
        return out


def _box_of(hull: np.ndarray) -> tuple[np.ndarray, np.ndarray] | None:
    """(centre (3,), half extents (3,)), m, of a hull that is an axis-aligned box (8 corners), else None."""
    lo, hi = hull.min(axis=0), hull.max(axis=0)
    corners = np.all(np.isclose(hull, lo, rtol=0, atol=TOL) | np.isclose(hull, hi, rtol=0, atol=TOL))
    if len(hull) != 8 or not corners or len({tuple(np.isclose(v, hi, rtol=0, atol=TOL)) for v in hull}) != 8:
        return None
    return 0.5 * (lo + hi), 0.5 * (hi - lo)


def _add_pedestal(world: World, pedestal: StatueScene) -> int:
    """The pedestal at rest on the floor (its frame the world's), lateral friction 1, restitution 0.
    A box pedestal collides as a box (GEOM_BOX: the floor's own shape, whose contacts with the statue's
    hull are those of :func:`simulate_statue`'s floor), any other as its convex hull."""
    box = _box_of(pedestal.hull)
    if box is None:
        return add_statue(world, pedestal, ContactSettings(friction=1.0))
    p = world.p
    centre, half = box
    shape = world.call("createCollisionShape", p.GEOM_BOX, halfExtents=half.tolist(),
                       collisionFramePosition=centre.tolist())
    w, V = inertia_frame(pedestal.inertia)
    body = world.call("createMultiBody", pedestal.mass, shape, basePosition=[0.0, 0.0, 0.0],
                      baseInertialFramePosition=np.asarray(pedestal.com, dtype=float).tolist(),
                      baseInertialFrameOrientation=quat_from_matrix(V),
                      useMaximalCoordinates=int(world.settings.maximal_coordinates))
    world.call("changeDynamics", body, -1, mass=pedestal.mass, localInertiaDiagonal=w.tolist(), linearDamping=0.0,
               angularDamping=0.0, lateralFriction=1.0, restitution=0.0, rollingFriction=0.0, spinningFriction=0.0)
    return body


def simulate_stack_3d(scene: StackScene, motion, *, t_end: float | None = None,
                      settings: SimSettings | None = None, dt_out: float = 0.005,
                      free_time: float = 3.0) -> Stack3DResult:
    """Run the stack under ``motion`` (a GroundMotion along +x, the excitation direction), both
    bodies dynamic and at rest at t = 0: the pedestal on the floor, the statue on the pedestal.
    ``t_end`` (s) defaults to the end of the motion + ``free_time``; ``settings`` to
    :data:`STACK_SETTINGS`. The run stops early when a body overturns, or when both bodies are at
    rest (REST_SPEED, REST_RATE for REST_TIME) after the motion has ended. Histories are sampled every
    ``dt_out`` s."""
    c0 = run_clock()
    settings = STACK_SETTINGS if settings is None else settings
    if t_end is None:
        t_end = motion.end + free_time
    dt = settings.dt
    n, every = step_grid(t_end, dt_out, dt)
    acc = step_mean_acc(motion, 0.0, dt, n).tolist()
    k_quiet = math.ceil(motion.end / dt - 1e-9)           # from this step on the ground is still
    rest_need = math.ceil(REST_TIME / dt)
    kin = _Bodies(scene)
    t0 = time.perf_counter()
    with World(settings) as world:
        world.plane(scene.mu_floor, 0.0)
        ped = _add_pedestal(world, scene.pedestal)
        st = add_statue(world, scene.statue, ContactSettings(friction=scene.mu_top), z0=scene.height,
                        collision="patch")
        pos, orn = world.call("getBasePositionAndOrientation", st)
        shift = scene._shift()
        world.call("resetBasePositionAndOrientation", st,
                   (np.asarray(pos) + [shift[0], shift[1], 0.0]).tolist(), orn)
        pb, cid, g = world.p, world.client, settings.g
        step, gravity, get_pose = pb.stepSimulation, pb.setGravity, pb.getBasePositionAndOrientation
        get_vel = pb.getBaseVelocity
        Ps, Qs, Pp, Qp = [], [], [], []

        def keep():
            a, b = get_pose(st, physicsClientId=cid)
            c, d = get_pose(ped, physicsClientId=cid)
            Ps.append(a)
            Qs.append(b)
            Pp.append(c)
            Qp.append(d)

        keep()
        stopped, ot_s, ot_p, bad = "end", None, None, None
        checked, a_set, rest = 0, None, 0
        for k in range(1, n + 1):
            a = acc[k - 1]
            if a != a_set:                               # gravity (-a, 0, -g): World.set_ground_acc
                gravity(-a, 0.0, -g, physicsClientId=cid)
                a_set = a
            step(physicsClientId=cid)
            keep()
            if k - checked >= BLOCK or k == n:
                e_s, e_p, e_b = kin.events(*(np.asarray(x, dtype=float) for x in
                                             (Ps[checked:k + 1], Qs[checked:k + 1], Pp[checked:k + 1],
                                              Qp[checked:k + 1])))
                ot_s = None if e_s is None else checked + e_s
                ot_p = None if e_p is None else checked + e_p
                bad = None if e_b is None else checked + e_b
                if ot_s is not None or ot_p is not None or bad is not None:
                    stopped = "overturn" if bad is None else "non-finite state"
                    break
                checked = k + 1
            if k >= k_quiet and k % REST_EVERY == 0:
                still = all(math.hypot(*v) < REST_SPEED and math.hypot(*w) < REST_RATE
                            for v, w in (get_vel(b, physicsClientId=cid) for b in (st, ped)))
                rest = rest + REST_EVERY if still else 0
                if rest >= rest_need:
                    stopped = "rest"
                    break
    wall = time.perf_counter() - t0
    last = len(Ps) - 1
    if bad is not None:                                  # the first non-finite pose is not kept
        last = bad - 1
        ot_s = ot_s if ot_s is not None and ot_s <= last else None
        ot_p = ot_p if ot_p is not None and ot_p <= last else None
    if bad is None and (ot_s is not None or ot_p is not None):
        last = min(k for k in (ot_s, ot_p) if k is not None)
    arrays = [np.asarray(x[:last + 1], dtype=float) for x in (Ps, Qs, Pp, Qp)]
    h = kin.histories(*arrays)
    ks = np.arange(0, last + 1, every)
    if ks[-1] != last:
        ks = np.append(ks, last)
    results = {}
    for name, deltas, ot in (("statue", kin.delta_s, ot_s), ("pedestal", kin.delta_p, ot_p)):
        hh = h[name]
        th = hh["theta"]
        over = np.where(th > 0, th / deltas[0], -th / deltas[1])
        sl = np.hypot(hh["slide"][:, 0], hh["slide"][:, 1])
        results[name] = BodyResult(
            theta=th[ks], slide_x=hh["slide"][ks, 0], theta_max=float(np.abs(th).max(initial=0.0)),
            theta_max_over_delta=float(over.max(initial=0.0)), uplift_time=_lift_off_time(hh["lift"], dt),
            max_lift=max(0.0, float(hh["lift"].max(initial=0.0))), overturned=ot is not None,
            overturn_time=None if ot is None else ot * dt, peak_slide=float(sl.max(initial=0.0)))
    return Stack3DResult(scene=scene, settings=settings, t=ks * dt, statue=results["statue"],
                         pedestal=results["pedestal"], finite=bad is None, stopped=stopped, wall_time=wall,
                         steps=len(Ps) - 1, cpu_time=time.process_time() - c0)
