"""Scene (a): the statue free-standing on a rigid floor, in PyBullet.

Frame: the scene is turned about z by -direction so that the excitation
direction is +x; the right pivot (theta > 0, MODEL.md) is then the footprint
hull's extreme point along +x. Rotation theta is read as the angle of the
body's (initially vertical) z axis in the x-z plane, theta > 0 toward +x, i.e.
exactly the 2D model's theta; the out-of-plane tilt (about x) and the yaw are
recorded too, to show how two-dimensional the 3D motion stays.

Collision geometry: a body resting on a plane touches it only through its
convex hull, so the statue's collision shape is the convex hull of its mesh
(``collision="hull"``). Its base is flattened first: hull vertices within the
footprint tolerance of z = 0 are put on z = 0 (the footprint the 2D model
pivots on is the set of those vertices; without this the 3D body would stand on
its three lowest scan points, millimetres apart in height, and pivot elsewhere).
``collision="mesh"`` (for the cost benchmark) uses the full triangle mesh as a
concave shape on a thin static box floor (PyBullet cannot collide a concave
mesh with a plane).

Inertia: mass, centre of mass and the full inertia tensor come from our mass
properties (statue2model.geometry.massprops), not from PyBullet's estimate:
the inertial frame sits at the centre of mass, turned to the principal axes of
our tensor, with our principal moments (checked by :func:`inertia_check`).

Example
-------
>>> from statue2model.crosscheck.statue_scene import StatueScene
>>> from statue2model.dynamics import motions
>>> from statue2model.geometry.rocking_params import RockingParams
>>> sc = StatueScene.block(b=0.1, h=0.5, m=100.0)
>>> r = simulate_statue(sc, motions.free(), theta0=0.5 * sc.params.delta_R, t_end=0.6)
>>> r.overturned, r.impact_times.size >= 1
(False, True)
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass, field, replace

import numpy as np

from ..errors import InputError
from ..geometry.rocking_params import RockingParams
from .contact import ContactSettings
from .world import SimSettings, World, matrix_from_quat, quat_from_matrix, real_time_factor, step_mean_acc

UPLIFT_ANGLE = 1e-5
FLIGHT_HEIGHT = 1e-4
"""Height, m, of the statue's lowest point above which it counts as airborne (contact penetration ~1e-5 m)."""
"""|theta| (rad) above which the 3D body counts as lifted (engine noise is ~1e-8 rad at rest)."""


@dataclass(frozen=True, eq=False)
class StatueScene:
    """A rigid statue ready for PyBullet, in the excitation frame (excitation along +x).

    hull        : (k, 3) vertices of the collision hull (base flattened), m
    mesh        : (vertices, faces) of the full mesh in this frame (for collision="mesh"), or None
    mass        : kg; com : (3,) m; inertia : (3, 3) kg m^2 about the com, this frame
    params      : the 2D RockingParams along +x (of the same mass properties and footprint)
    x_R, x_L    : x of the right and left pivots, m
    """

    hull: np.ndarray
    mass: float
    com: np.ndarray
    inertia: np.ndarray
    params: RockingParams
    x_R: float
    x_L: float
    mesh: tuple | None = None
    name: str = "statue"

    @classmethod
    def from_body(cls, body, direction_deg: float | None = None, name: str | None = None) -> StatueScene:
        """Turn ``body`` (statue2model.geometry.body.Body) so that ``direction_deg``
        (default: the weakest) is +x; flatten the base of its convex hull."""
        import trimesh

        params = body.rocking(direction_deg)
        psi = math.radians(params.direction_deg)
        c, s = math.cos(-psi), math.sin(-psi)
        Rz = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
        v = body.vertices @ Rz.T
        com = Rz @ body.mass.com
        inertia = Rz @ body.mass.inertia @ Rz.T
        tol = float(body.footprint.tol)
        hull = trimesh.Trimesh(v, body.faces, process=False).convex_hull.vertices.copy()
        hull[hull[:, 2] <= tol, 2] = 0.0
        hull = trimesh.convex.convex_hull(hull).vertices.copy()
        # the 2D parameters of the body PyBullet actually holds: pivots = extreme points along x of
        # the flattened hull's base (they differ from the scan footprint's by up to 0.14 mm on the
        # default scan: hull vertices within the tolerance, not the footprint polygon)
        base = hull[hull[:, 2] == 0.0]
        x_R, x_L = float(base[:, 0].max()), float(base[:, 0].min())
        params = replace(params, b_R=x_R - float(com[0]), b_L=float(com[0]) - x_L)
        return cls(hull=hull, mass=float(body.mass.mass), com=com, inertia=inertia, params=params,
                   x_R=x_R, x_L=x_L, mesh=(v, np.asarray(body.faces)), name=name or "statue")

    @classmethod
    def block(cls, b: float, h: float, m: float, depth: float | None = None, g: float = 9.81) -> StatueScene:
        """Homogeneous rectangular block, half-width b, half-height h (m), mass m (kg),
        thickness ``depth`` across the excitation (default 2 b)."""
        depth = 2 * b if depth is None else depth
        x, y, z = np.meshgrid([-b, b], [-depth / 2, depth / 2], [0.0, 2 * h], indexing="ij")
        hull = np.column_stack([x.ravel(), y.ravel(), z.ravel()])
        Ixx = m * (depth**2 + 4 * h * h) / 12
        Iyy = m * (4 * b * b + 4 * h * h) / 12
        Izz = m * (4 * b * b + depth**2) / 12
        params = RockingParams(m=m, h=h, b_L=b, b_R=b, I_G=Iyy, g=g)
        return cls(hull=hull, mass=m, com=np.array([0.0, 0.0, h]), inertia=np.diag([Ixx, Iyy, Izz]),
                   params=params, x_R=b, x_L=-b, name=f"block b={b:g} h={h:g}")

    @classmethod
    def from_params(cls, params: RockingParams, depth: float | None = None) -> StatueScene:
        """A prism standing on [-b_L, b_R] x [-depth/2, depth/2] (default depth b_L + b_R),
        2 h tall, with the mass, centre of mass (0, 0, h) and I_G of ``params``; the other two
        moments are those of a homogeneous box (they do not enter planar rocking)."""
        depth = params.b_L + params.b_R if depth is None else depth
        x, y, z = np.meshgrid([-params.b_L, params.b_R], [-depth / 2, depth / 2], [0.0, 2 * params.h],
                              indexing="ij")
        hull = np.column_stack([x.ravel(), y.ravel(), z.ravel()])
        w = params.b_L + params.b_R
        m, h = params.m, params.h
        inertia = np.diag([m * (depth**2 + 4 * h * h) / 12, params.I_G, m * (w * w + depth**2) / 12])
        return cls(hull=hull, mass=m, com=np.array([0.0, 0.0, h]), inertia=inertia, params=params,
                   x_R=params.b_R, x_L=-params.b_L, name="prism from rocking parameters")


def inertia_frame(inertia: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Principal moments (3,) and axes (3, 3, columns; a proper rotation) of a tensor."""
    w, V = np.linalg.eigh(np.asarray(inertia, dtype=float))
    if np.linalg.det(V) < 0:
        V[:, 0] *= -1
    return w, V


def add_statue(world: World, scene: StatueScene, contact: ContactSettings, theta0: float = 0.0,
               z0: float = 0.0, collision: str = "hull") -> int:
    """Create the statue, rotated by theta0 (rad) about its pivot (right if > 0), its base at z = z0."""
    p = world.p
    if collision == "hull":
        shape = world.call("createCollisionShape", p.GEOM_MESH, vertices=scene.hull.tolist())
    elif collision == "mesh":
        if scene.mesh is None:
            raise InputError("this scene has no full mesh (a block): use collision='hull'")
        v, f = scene.mesh
        shape = world.call("createCollisionShape", p.GEOM_MESH, vertices=v.tolist(), indices=f.ravel().tolist(),
                           flags=p.GEOM_FORCE_CONCAVE_TRIMESH)
    else:
        raise InputError(f"collision must be 'hull' or 'mesh', got {collision!r}")
    w, V = inertia_frame(scene.inertia)
    pivot = np.array([scene.x_R if theta0 > 0 else scene.x_L, 0.0, 0.0])
    Ry = _rot_y(theta0)
    pos = pivot - Ry @ pivot + np.array([0.0, 0.0, z0 + contact.margin])
    body = world.call("createMultiBody", scene.mass, shape, basePosition=pos.tolist(),
                      baseOrientation=quat_from_matrix(Ry), baseInertialFramePosition=scene.com.tolist(),
                      baseInertialFrameOrientation=quat_from_matrix(V),
                      useMaximalCoordinates=int(world.settings.maximal_coordinates))
    world.call("changeDynamics", body, -1, localInertiaDiagonal=w.tolist(), linearDamping=0.0, angularDamping=0.0,
               lateralFriction=contact.friction, restitution=contact.restitution, rollingFriction=0.0,
               spinningFriction=0.0, collisionMargin=contact.margin)
    return body


def inertia_check(world: World, body: int, scene: StatueScene) -> dict:
    """Mass, centre of mass and inertia tensor as PyBullet holds them, against ours
    (largest relative differences)."""
    info = world.call("getDynamicsInfo", body, -1)
    mass, diag, pos, orn = info[0], np.array(info[2]), np.array(info[3]), info[4]
    R = matrix_from_quat(orn)
    tensor = R @ np.diag(diag) @ R.T
    scale = np.abs(scene.inertia).max()
    return {"mass": mass, "mass_rel_error": abs(mass - scene.mass) / scene.mass,
            "com_error_m": float(np.abs(pos - scene.com).max()),
            "inertia_rel_error": float(np.abs(tensor - scene.inertia).max() / scale)}


def _rot_y(a: float) -> np.ndarray:
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])


@dataclass(frozen=True, eq=False)
class Statue3DResult:
    """A 3D run of the statue (SI units, angles in rad).

    t, theta          : samples every ``dt_out`` (theta as in the 2D model)
    tilt_out, yaw     : rotation about x (out of the excitation plane) and about z
    slide             : x displacement of the base centre relative to the ground, m
    uplift_time       : first time |theta| > UPLIFT_ANGLE (None if never); the floor's contact
                        manifold is too sparse (often one point at rest) to locate the centre of
                        pressure, so the 2D side is compared at the same threshold (runs.py)
    overturned, overturn_time, overturn_side : |theta| reached delta_side
    theta_max_L / _R  : largest rotation on each pivot
    impact_times      : sign changes of theta; peak_t, peak_theta : one extremum per half cycle
    finite            : no NaN or infinity in the state
    wall_time, steps  : cost of the run (s of CPU wall clock, engine steps)
    max_pivot_slip    : largest horizontal displacement, m, of the lowest base vertex (the pivot in
                        contact) from where it started, while |theta| > 1e-3 rad: sliding or
                        yawing at the pivot (the 2D model has none)
    max_flight        : largest height, m, of the statue's lowest hull point above the floor (> 0: the
                        body left the floor on both pivots); flight_time: time, s, with it > FLIGHT_HEIGHT
    """

    scene: StatueScene
    settings: SimSettings
    contact: ContactSettings
    t: np.ndarray
    theta: np.ndarray
    tilt_out: np.ndarray
    yaw: np.ndarray
    slide: np.ndarray
    uplift_time: float | None
    overturned: bool
    overturn_time: float | None
    overturn_side: str | None
    theta_max_L: float
    theta_max_R: float
    impact_times: np.ndarray
    peak_t: np.ndarray
    peak_theta: np.ndarray
    finite: bool
    wall_time: float
    steps: int
    inertia: dict = field(default_factory=dict)
    max_pivot_slip: float = 0.0
    max_flight: float = 0.0
    flight_time: float = 0.0

    @property
    def theta_max_over_delta(self) -> float:
        p = self.scene.params
        return max(self.theta_max_L / p.delta_L, self.theta_max_R / p.delta_R)

    @property
    def real_time_factor(self) -> float:
        """Simulated seconds per wall-clock second."""
        return real_time_factor(self.steps, self.settings.dt, self.wall_time)

    @property
    def outcome(self) -> str:
        if not self.finite:
            return "non-finite state"
        if self.overturned:
            return f"overturn ({self.overturn_side})"
        return "rocking" if self.uplift_time is not None else "no motion"

    def to_dict(self) -> dict:
        return {"outcome": self.outcome, "uplift_time": self.uplift_time, "overturned": self.overturned,
                "overturn_time": self.overturn_time, "overturn_side": self.overturn_side,
                "theta_max_L": self.theta_max_L, "theta_max_R": self.theta_max_R,
                "theta_max_over_delta": self.theta_max_over_delta,
                "impact_times": self.impact_times.tolist(), "peaks": {"t": self.peak_t.tolist(),
                                                                      "theta": self.peak_theta.tolist()},
                "max_tilt_out": float(np.abs(self.tilt_out).max(initial=0.0)),
                "max_yaw": float(np.abs(self.yaw).max(initial=0.0)),
                "max_slide": float(np.nanmax(np.abs(self.slide), initial=0.0)),
                "max_pivot_slip": self.max_pivot_slip, "max_flight": self.max_flight,
                "flight_time": self.flight_time,
                "finite": self.finite, "wall_time_s": self.wall_time, "steps": self.steps,
                "real_time_factor": self.real_time_factor, "settings": self.settings.to_dict(),
                "contact": self.contact.to_dict(), "inertia_check": self.inertia}


def simulate_statue(scene: StatueScene, motion, *, theta0: float = 0.0, t_end: float | None = None,
                    settings: SimSettings | None = None, contact: ContactSettings | None = None,
                    dt_out: float = 0.002, collision: str = "hull", stop_on_overturn: bool = True,
                    free_time: float = 5.0) -> Statue3DResult:
    """Run scene (a): the statue on a rigid floor under ``motion`` (a GroundMotion along +x),
    released from rest at theta0 (rad, about the right pivot if > 0). t_end defaults to the
    end of the motion + ``free_time``. The run stops at overturning (|theta| >= delta)."""
    from .contact import ContactSettings as _CS

    contact = _CS() if contact is None else contact
    settings = SimSettings() if settings is None else settings
    p2 = scene.params
    if theta0 >= p2.delta_R or -theta0 >= p2.delta_L or not math.isfinite(theta0):
        raise InputError(f"theta0 = {theta0} rad is not between -delta_L and delta_R")
    if t_end is None:
        t_end = motion.end + free_time
    if not (math.isfinite(t_end) and t_end > 0):
        raise InputError(f"t_end must be positive, got {t_end}")
    if not (math.isfinite(dt_out) and dt_out > 0):
        raise InputError(f"dt_out must be positive, got {dt_out}")
    dt = settings.dt
    n = math.ceil(t_end / dt - 1e-9)
    every = max(1, round(dt_out / dt))
    acc = step_mean_acc(motion, 0.0, dt, n)
    _, V = inertia_frame(scene.inertia)
    t0 = time.perf_counter()
    with World(settings) as world:
        _floor(world, contact, collision)
        body = add_statue(world, scene, contact, theta0=theta0, collision=collision)
        check = inertia_check(world, body, scene)
        ts, th, tx, yw, sl = [], [], [], [], []
        up_t = None
        ot_t = ot_side = None
        qmax = {1: 0.0, -1: 0.0}
        finite = True
        base0 = np.array([0.5 * (scene.x_R + scene.x_L), 0.0, 0.0])
        steps = 0
        hull_c = scene.hull - scene.com                   # hull about the com, link frame
        base_v = scene.hull[:, 2] == 0.0
        slip = flight = 0.0
        n_flight = 0
        for k in range(n + 1):
            pos, orn = world.call("getBasePositionAndOrientation", body)
            Rc = matrix_from_quat(orn)
            R = Rc @ V.T                     # link frame: identity when upright
            theta = math.atan2(R[0, 2], R[2, 2])
            if not (math.isfinite(theta) and all(math.isfinite(x) for x in pos)):
                finite = False
                break
            tk = k * dt
            w = np.asarray(pos) + hull_c @ R.T            # hull vertices, world
            zlow = float(w[:, 2].min())
            flight = max(flight, zlow)
            n_flight += zlow > FLIGHT_HEIGHT
            if abs(theta) > 1e-3:                          # base vertices touching the floor: the pivot
                on = base_v & (w[:, 2] < FLIGHT_HEIGHT)
                if on.any():
                    slip = max(slip, float(np.hypot(w[on, 0] - scene.hull[on, 0], w[on, 1] - scene.hull[on, 1]).max()))
            side = 1 if theta > 0 else -1
            qmax[side] = max(qmax[side], abs(theta))
            if up_t is None and theta0 == 0.0 and k > 0 and abs(theta) > UPLIFT_ANGLE:
                up_t = tk
            if k % every == 0 or k == n:
                ts.append(tk)
                th.append(theta)
                tx.append(math.atan2(-R[1, 2], math.hypot(R[0, 2], R[2, 2])))
                yw.append(math.atan2(R[1, 0], R[0, 0]))
                base = np.asarray(pos) - Rc @ (V.T @ scene.com) + R @ base0     # link origin + R base0
                sl.append(float(base[0] - base0[0]) if abs(theta) < 1e-3 else np.nan)
            delta = p2.delta_R if side > 0 else p2.delta_L
            if abs(theta) >= delta and ot_t is None:
                ot_t, ot_side = tk, ("R" if side > 0 else "L")
                if stop_on_overturn:
                    ts.append(tk)
                    th.append(theta)
                    tx.append(tx[-1] if tx else 0.0)
                    yw.append(yw[-1] if yw else 0.0)
                    sl.append(np.nan)
                    break
            if k == n:
                break
            world.set_ground_acc(acc[k])
            world.step()
            steps += 1
    wall = time.perf_counter() - t0
    if theta0 != 0.0:
        up_t = 0.0
    t_arr, th_arr = np.asarray(ts), np.asarray(th)
    imp, pk_t, pk_th = _impacts_and_peaks(t_arr, th_arr)
    return Statue3DResult(
        scene=scene, settings=settings, contact=contact, t=t_arr, theta=th_arr, tilt_out=np.asarray(tx),
        yaw=np.asarray(yw), slide=np.asarray(sl), uplift_time=up_t, overturned=ot_t is not None,
        overturn_time=ot_t, overturn_side=ot_side, theta_max_L=qmax[-1], theta_max_R=qmax[1],
        impact_times=imp, peak_t=pk_t, peak_theta=pk_th, finite=finite, wall_time=wall, steps=steps,
        inertia=check, max_pivot_slip=slip, max_flight=flight, flight_time=n_flight * dt)


def _floor(world: World, contact: ContactSettings, collision: str) -> int:
    if collision == "mesh":   # a concave mesh does not collide with a plane: a thin static box
        p = world.p
        shape = world.call("createCollisionShape", p.GEOM_BOX, halfExtents=[50.0, 50.0, 0.05])
        body = world.call("createMultiBody", 0.0, shape, basePosition=[0.0, 0.0, -0.05])
        world.call("changeDynamics", body, -1, lateralFriction=contact.friction, restitution=contact.restitution)
        return body
    return world.plane(contact.friction, contact.restitution)


def _impacts_and_peaks(t: np.ndarray, theta: np.ndarray, floor: float = 1e-4):
    """Impact times (sign changes of theta, linearly interpolated, ignoring wiggles
    smaller than ``floor`` rad) and one signed extremum per half cycle."""
    imp, pk_t, pk_th = [], [], []
    if t.size < 3:
        return np.array([]), np.array([]), np.array([])
    side, best_i = 0, -1
    for i in range(t.size):
        q = theta[i]
        if abs(q) < floor:
            continue
        s = 1 if q > 0 else -1
        if s != side:
            if side != 0:
                pk_t.append(t[best_i])
                pk_th.append(theta[best_i])
                j = i
                while j > 0 and np.sign(theta[j - 1]) == s:
                    j -= 1
                t0, t1, y0, y1 = t[j - 1], t[j], theta[j - 1], theta[j]
                imp.append(t0 + (t1 - t0) * y0 / (y0 - y1) if y0 != y1 else t1)
            side, best_i = s, i
        elif abs(q) > abs(theta[best_i]):
            best_i = i
    if side != 0 and best_i < t.size - 1:
        pk_t.append(t[best_i])
        pk_th.append(theta[best_i])
    return np.asarray(imp), np.asarray(pk_t), np.asarray(pk_th)
