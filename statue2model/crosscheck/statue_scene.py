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
``collision="patch"`` (the exact isolator's and the stack's statue) keeps of that hull only
the base's contact patch: the base vertices and the hull vertices that can reach the floor at a
tilt below PATCH_TILT x the larger delta (:func:`contact_patch`), with the hull's extreme vertices;
below that tilt the floor touches the patch exactly where it touches the hull, and the engine's
convex-box contact tests fewer vertices (issue [23]). ``collision="mesh"`` (for the cost benchmark) uses the full triangle mesh as a
concave shape on a thin static box floor (PyBullet cannot collide a concave
mesh with a plane).

Inertia: mass, centre of mass and the full inertia tensor come from our mass
properties (statue2model.geometry.massprops), not from PyBullet's estimate:
the inertial frame sits at the centre of mass, turned to the principal axes of
our tensor, with our principal moments (checked by :func:`inertia_check`).

Example
-------
>>> from statue2model.crosscheck.statue_scene import StatueScene
>>> from statue2model.hazard import motions
>>> from statue2model.geometry.rocking_params import RockingParams
>>> sc = StatueScene.block(b=0.1, h=0.5, m=100.0)
>>> r = simulate_statue(sc, motions.free(), theta0=0.5 * sc.params.delta_R, t_end=0.6)
>>> r.overturned, r.impact_times.size >= 1
(False, True)
"""
from __future__ import annotations

import functools
import math
import time
from dataclasses import dataclass, field, replace

import numpy as np

from ..quantities import G
from ..errors import InputError
from ..geometry.rocking_params import RockingParams
from .contact import ContactSettings
from .world import (
    run_clock,
    SimSettings,
    World,
    matrices_from_quats,
    matrix_from_quat,
    quat_from_matrix,
    real_time_factor,
    step_grid,
    step_mean_acc,
)

UPLIFT_ANGLE = 1e-5
"""|theta| (rad) above which the 3D body used to count as lifted (engine noise is ~1e-8 rad at rest).
Kept for reference only: 1e-5 rad lies inside the contact solver's compliance (a block that never
lifts in 2D "lifts" in 3D after 1.5 ms); lift-off is now read from the contacts (LIFT_HEIGHT, unloading)."""
FLIGHT_HEIGHT = 1e-4
"""Height, m, of the statue's lowest point above which it counts as airborne (contact penetration ~1e-5 m)."""
LIFT_HEIGHT = 2e-4
"""Lift-off (geometric): the highest base point - on the non-pivot side - rises above this height, m,
for LIFT_STEPS steps. 20 x the contact solver's penetration at rest (1e-5 m, measured), so compliance
never reads as lift-off; the 2D side is read at the same height, (b_L + b_R) sin|theta|
(statue_cases.liftoff_time_2d)."""
LIFT_STEPS = 4
"""Consecutive engine steps a lift-off (or unloading) criterion must hold (2 ms at dt = 0.5 ms)."""
LAND_HEIGHT = LIFT_HEIGHT / 4
"""Landing (impact, geometric): the raised side's lowest base point, once lifted (above LIFT_HEIGHT for
LIFT_STEPS steps), comes back down below this height, m; the impact time is its crossing of the floor (height 0, the
2D model's theta = 0), interpolated between steps. The 2D side: its exact impact events."""
UNLOAD_FRACTION = 1e-3
"""Lift-off (force): the floor's normal force on the base points farther than UNLOAD_BAND x (b_L + b_R)
from the pivot falls below this fraction of m g (for LIFT_STEPS steps) while the body is on the floor:
the non-pivot side is unloaded. 2D counterpart: the exact uplift instant (|u_g''| reaches g b / h)."""
UNLOAD_BAND = 0.02
UNLOAD_GATE = 0.5
"""The unloading is read (the floor's contacts, every step) only from this fraction of the least
uplift acceleration g b_min / h_G on: below it no side of a body at rest on its base can unload."""
OVERTURN_CHECK = 128
"""Steps between two overturning (and finiteness) checks of a run: the poses are stored each step and
checked in blocks; the steps run past an overturn are not reported (cost: <= OVERTURN_CHECK steps)."""
STATUE_SETTINGS = SimSettings(dt=2e-3, solver_iterations=50)
"""Engine settings of the statue scene when none are given (its accuracy setting; the isolator scene
keeps SimSettings(), dt 0.5 ms). From benchmarks/bench_crosscheck_speed.py against dt 0.125 ms /
200 iterations: default scan, peak rotation 0.3-1.2 %, lift-off 1.3-2.4 ms early, first rebound 1.2 %
(dt 1 ms: 0.2-0.9 %, 1.0-1.7 ms, 0.8 %); slender block, rebound 2.1 %, lift-off 1.3 ms early. The
engine step alone runs ~50-100 x real time at 2 ms on the scan (CPU time, 2 shared cores), ~25-55 x
at 1 ms: 2 ms is the finest step that meets the 50 x target (issue 16, item 8)."""


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
    def from_body(cls, body, direction_deg: float | None = None, name: str | None = None,
                  tol: float | None = None) -> StatueScene:
        """Turn ``body`` (statue2model.geometry.body.Body) so that ``direction_deg``
        (default: the weakest) is +x; stand it on its contact: the scan's points within ``tol`` (m,
        default the footprint's contact tolerance; the contact band's tol / 2 and 2 tol,
        geometry/base.py, give the scenes of its other ends) of the lowest are put on z = 0, the
        rest of the convex hull kept as scanned."""
        from ..compute.interrupts import checked_import

        trimesh = checked_import("trimesh")   # trimesh drops a Ctrl-C during its import

        params = body.rocking(direction_deg)
        psi = math.radians(params.direction_deg)
        c, s = math.cos(-psi), math.sin(-psi)
        Rz = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
        v = body.vertices @ Rz.T
        com = Rz @ body.mass.com
        inertia = Rz @ body.mass.inertia @ Rz.T
        tol = float(body.footprint.tol) if tol is None else float(tol)
        if not (math.isfinite(tol) and tol >= 0):
            raise InputError(f"contact tolerance must be a length >= 0, got {tol}")
        # the scan's points within tol on the floor, then the convex hull: its base is the footprint's
        # contact hull at tol (geometry/base.py contact_case), not only the hull vertices near the floor
        pts = trimesh.Trimesh(v, body.faces, process=False).convex_hull.vertices
        low = v[v[:, 2] <= tol]
        pts = np.vstack([pts[pts[:, 2] > tol], np.column_stack([low[:, :2], np.zeros(len(low))])])
        # a plain ndarray: trimesh's TrackedArray makes every per-step numpy operation on it slow
        hull = np.array(trimesh.convex.convex_hull(pts).vertices, dtype=float)
        # the 2D parameters of the body PyBullet actually holds, as props takes them from the scan's
        # footprint: b_R, b_L where the rays from G' along +-x leave the flattened hull's base polygon
        # (rocking_params.ray_exit; equal to the footprint's to 1e-9 m: the same contact hull). x_R, x_L:
        # the base's extreme points along x, the 3D release pivot and the base points read for slip;
        # they differ from the rays' where the tipping edge is oblique (30 deg on the default scan:
        # b_L 0.352 m by the ray, 0.405 m to the extreme point)
        base = hull[hull[:, 2] == 0.0]
        x_R, x_L = float(base[:, 0].max()), float(base[:, 0].min())
        b_R, b_L = base_rays(base[:, :2], com[:2]) if len(base) >= 3 else (0.0, 0.0)
        if not (b_R > 0 and b_L > 0):
            raise InputError(f"the body cannot stand on its contact within {tol * 1000:.3g} mm of the floor "
                             "(its centre of mass is not above it)")
        params = replace(params, b_R=b_R, b_L=b_L)
        return cls(hull=hull, mass=float(body.mass.mass), com=com, inertia=inertia, params=params,
                   x_R=x_R, x_L=x_L, mesh=(v, np.asarray(body.faces)), name=name or "statue")

    @classmethod
    def block(cls, b: float, h: float, m: float, depth: float | None = None, g: float = G) -> StatueScene:
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
    if collision in ("hull", "patch"):
        verts = scene.hull if collision == "hull" else contact_patch(scene)
        shape = world.call("createCollisionShape", p.GEOM_MESH, vertices=verts.tolist())
    elif collision == "mesh":
        if scene.mesh is None:
            raise InputError("this scene has no full mesh (a block): use collision='hull'")
        v, f = scene.mesh
        shape = world.call("createCollisionShape", p.GEOM_MESH, vertices=v.tolist(), indices=f.ravel().tolist(),
                           flags=p.GEOM_FORCE_CONCAVE_TRIMESH)
    else:
        raise InputError(f"collision must be 'hull', 'patch' or 'mesh', got {collision!r}")
    w, V = inertia_frame(scene.inertia)
    pivot = np.array([scene.x_R if theta0 > 0 else scene.x_L, 0.0, 0.0])
    Ry = _rot_y(theta0)
    pos = pivot - Ry @ pivot + np.array([0.0, 0.0, z0 + contact.margin])
    body = world.call("createMultiBody", scene.mass, shape, basePosition=pos.tolist(),
                      baseOrientation=quat_from_matrix(Ry), baseInertialFramePosition=scene.com.tolist(),
                      baseInertialFrameOrientation=quat_from_matrix(V),
                      useMaximalCoordinates=int(world.settings.maximal_coordinates))
    # mass again: a maximal-coordinate body given localInertiaDiagonal alone gets mass 0 (NaN at the first step)
    world.call("changeDynamics", body, -1, mass=scene.mass, localInertiaDiagonal=w.tolist(), linearDamping=0.0,
               angularDamping=0.0,
               lateralFriction=contact.friction, restitution=contact.restitution, rollingFriction=0.0,
               spinningFriction=0.0, collisionMargin=contact.margin)
    return body


PATCH_TILT = 2.0
"""The contact patch (:func:`contact_patch`) keeps every hull vertex that can touch the floor at a tilt
below PATCH_TILT x max(delta_L, delta_R): a run stops at |theta| = delta (its steps past an
overturn, at most OVERTURN_CHECK, are not reported), so the factor 2 covers the out-of-plane tilt."""


def landing_angles(hull: np.ndarray) -> np.ndarray:
    """Per hull vertex (k, 3; base on z = 0), the smallest tilt (rad) of the body at which it comes as
    low as the base: atan2(z, d) with d its horizontal distance outside the base polygon (pi/2 for a
    vertex above the polygon, 0 for a base vertex on its boundary). Tilted by phi about any horizontal
    axis, a vertex is lower than every base point only when tan(phi) > z / d."""
    from scipy.spatial import ConvexHull, QhullError

    base = hull[hull[:, 2] == 0.0][:, :2]
    try:
        eq = ConvexHull(base).equations                   # n . x + c <= 0 inside, n a unit vector
    except (QhullError, ValueError):
        return np.zeros(len(hull))
    d = (hull[:, :2] @ eq[:, :2].T + eq[:, 2]).max(axis=1)
    return np.where(d > 0, np.arctan2(hull[:, 2], np.maximum(d, 1e-300)), 0.5 * math.pi)


@functools.lru_cache(maxsize=32)
def contact_patch(scene: StatueScene, tilt: float | None = None) -> np.ndarray:
    """The vertices (m, 3) of the statue's collision shape reduced to its base's contact patch: the base
    vertices (z = 0), every hull vertex that can reach the floor at a tilt below ``tilt`` (rad; default
    PATCH_TILT x the larger delta, :func:`landing_angles`) and the hull's extreme vertices along x, y
    and z (a solid of the hull's bounding box, not a flat polygon). Their convex hull lies inside the statue's and, tilted less than ``tilt``, touches a plane
    below it where the full hull does. The hull itself when the patch would not be smaller than half.

    >>> sc = StatueScene.block(b=0.1, h=0.5, m=100.0)
    >>> len(contact_patch(sc)) == len(sc.hull)
    True
    """
    hull = scene.hull
    p = scene.params
    tilt = PATCH_TILT * max(p.delta_L, p.delta_R) if tilt is None else float(tilt)
    keep = (hull[:, 2] == 0.0) | (landing_angles(hull) < tilt)
    # the hull's extreme vertices along x, y, z: the same bounding box, so the engine's contact-breaking
    # threshold (its bounding sphere x 0.02) and the contacts it keeps are the hull's
    keep[np.argmax(hull, axis=0)] = True
    keep[np.argmin(hull, axis=0)] = True
    out = hull if 2 * int(keep.sum()) > len(hull) else hull[keep]
    out = np.array(out)
    out.flags.writeable = False                           # kept per scene (lru_cache): read-only
    return out


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
    uplift_time       : lift-off read from the contacts, geometrically: the first time (interpolated
                        between steps) the highest base point - the non-pivot side - rises above
                        LIFT_HEIGHT and stays there LIFT_STEPS steps (None if never; 0 for a release
                        from theta0 != 0). The 2D side is read at the same height (statue_cases.py)
    unload_time       : lift-off read from the contact forces: the first step at which the floor's
                        normal force on the base points away from one pivot (farther than UNLOAD_BAND
                        x (b_L + b_R)) falls below UNLOAD_FRACTION m g and stays there LIFT_STEPS
                        steps while the body stands on the floor (None if never); 2D: its uplift time
    max_lift          : largest height, m, of the highest base point (the lifted edge)
    overturned, overturn_time, overturn_side : |theta| reached delta_side
    theta_max_L / _R  : largest rotation on each pivot
    impact_times      : landings read from the contacts (geometric): a side's lowest base point (the
                        base vertices at x_L or x_R), lifted above LIFT_HEIGHT for LIFT_STEPS steps,
                        comes back below LAND_HEIGHT; the time is its crossing of the floor (height 0),
                        interpolated between engine steps (:func:`_landing_times`)
    sign_change_times : sign changes of theta (the impacts as read before issue [11]), a diagnostic
    peak_t, peak_theta : one extremum of theta per half cycle
    finite            : no NaN or infinity in the state
    wall_time, steps  : cost of the run (s of wall clock, engine steps)
    cpu_time          : process CPU time of the whole call, s (real_time_factor: simulated s per CPU s)
    max_pivot_slip    : largest horizontal displacement, m, of a pivot vertex (the base vertices at
                        x_R and x_L) while on the floor (below LIFT_HEIGHT), from where it touched
                        down (or stood at rest): sliding at the pivot, the body standing or rocking
                        (the 2D model has none). A yaw while the vertex is in the air (about the other
                        pivot) is not slip: it is the screen's yaw. The validity screen's slip (screen.slip_of)
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
    unload_time: float | None = None
    max_lift: float = 0.0
    sign_change_times: np.ndarray = field(default_factory=lambda: np.array([]))
    cpu_time: float = 0.0

    @property
    def theta_max_over_delta(self) -> float:
        p = self.scene.params
        return max(self.theta_max_L / p.delta_L, self.theta_max_R / p.delta_R)

    @property
    def real_time_factor(self) -> float:
        """Simulated seconds per process CPU second of the whole run (the wall clock's when no CPU time
        was measured): robust on a shared machine."""
        return real_time_factor(self.steps, self.settings.dt, self.cpu_time or self.wall_time)

    @property
    def outcome(self) -> str:
        if not self.finite:
            return "non-finite state"
        if self.overturned:
            return f"overturn ({self.overturn_side})"
        return "rocking" if self.uplift_time is not None else "no motion"

    def to_dict(self) -> dict:
        return {"outcome": self.outcome, "uplift_time": self.uplift_time, "unload_time": self.unload_time,
                "lift_height": LIFT_HEIGHT, "max_lift": self.max_lift, "overturned": self.overturned,
                "overturn_time": self.overturn_time, "overturn_side": self.overturn_side,
                "theta_max_L": self.theta_max_L, "theta_max_R": self.theta_max_R,
                "theta_max_over_delta": self.theta_max_over_delta,
                "impact_times": self.impact_times.tolist(),
                "sign_change_times": self.sign_change_times.tolist(), "peaks": {"t": self.peak_t.tolist(),
                                                                      "theta": self.peak_theta.tolist()},
                "max_tilt_out": float(np.abs(self.tilt_out).max(initial=0.0)),
                "max_yaw": float(np.abs(self.yaw).max(initial=0.0)),
                "max_slide": float(np.nanmax(np.abs(self.slide), initial=0.0)),
                "max_pivot_slip": self.max_pivot_slip, "max_flight": self.max_flight,
                "flight_time": self.flight_time,
                "finite": self.finite, "wall_time_s": self.wall_time, "cpu_time_s": self.cpu_time,
                "steps": self.steps,
                "real_time_factor": self.real_time_factor, "settings": self.settings.to_dict(),
                "contact": self.contact.to_dict(), "inertia_check": self.inertia}


def simulate_statue(scene: StatueScene, motion, *, theta0: float = 0.0, t_end: float | None = None,
                    settings: SimSettings | None = None, contact: ContactSettings | None = None,
                    dt_out: float = 0.002, collision: str = "hull", stop_on_overturn: bool = True,
                    free_time: float = 5.0, motion_y=None) -> Statue3DResult:
    """Run scene (a): the statue on a rigid floor under ``motion`` (a GroundMotion along +x, the
    scene's excitation direction) and, if given, ``motion_y`` (the horizontal component across it,
    along +y: a record's second component, :func:`statue2model.hazard.motions.along`), released
    from rest at theta0 (rad, about the right pivot if > 0). t_end defaults to the end of the
    motion + ``free_time``; ``settings`` default to :data:`STATUE_SETTINGS`. The run stops at
    overturning (|theta| >= delta; theta is the rotation in the x-z plane, the out-of-plane tilt
    is ``tilt_out``).

    Cost: the step loop only steps the engine and reads the base pose (and, for a run from rest
    until the non-pivot side has unloaded, the contact forces); rotation, base-point heights,
    lift-off, pivot slip, flight and the overturning check are computed from the stored poses
    with numpy (the overturning check every OVERTURN_CHECK steps; steps run past it are not
    reported). ``collision``: default "hull" ("patch", :func:`contact_patch`, is ~25 % faster in the
    engine but not bit-identical: the chaotic record and restitution runs of the tests move)."""
    from .contact import ContactSettings as _CS

    c0 = run_clock()
    contact = _CS() if contact is None else contact
    settings = STATUE_SETTINGS if settings is None else settings
    p2 = scene.params
    if theta0 >= p2.delta_R or -theta0 >= p2.delta_L or not math.isfinite(theta0):
        raise InputError(f"theta0 = {theta0} rad is not between -delta_L and delta_R")
    if t_end is None:
        t_end = max(motion.end, 0.0 if motion_y is None else motion_y.end) + free_time
    dt = settings.dt
    n, every = step_grid(t_end, dt_out, dt)
    acc = step_mean_acc(motion, 0.0, dt, n).tolist()
    acc_y = [0.0] * n if motion_y is None else step_mean_acc(motion_y, 0.0, dt, n).tolist()
    _, V = inertia_frame(scene.inertia)
    hull_c = scene.hull - scene.com                   # hull about the com, link frame
    base_v, piv = base_vertices(scene)
    watch = theta0 == 0.0                                # lift-off is read only for runs from rest
    t0 = time.perf_counter()
    with World(settings) as world:
        _floor(world, contact, collision)
        body = add_statue(world, scene, contact, theta0=theta0, collision=collision)
        check = inertia_check(world, body, scene)
        unload = _UnloadWatch(world, body, scene, V, piv, dt) if watch else None
        pb, cid, g = world.p, world.client, settings.g
        step, gravity, get_pose = pb.stepSimulation, pb.setGravity, pb.getBasePositionAndOrientation
        pos, orn = get_pose(body, physicsClientId=cid)
        P, Q = [pos], [orn]
        last, stop_k, ot_k, bad_k = n, None, None, None    # last step kept; overturn / non-finite step
        checked, a_set = 0, None
        for k in range(1, n + 1):
            a = (acc[k - 1], acc_y[k - 1])
            if a != a_set:                               # gravity (-a, -a_y, -g): World.set_ground_acc
                gravity(-a[0], -a[1], -g, physicsClientId=cid)
                a_set = a
            step(physicsClientId=cid)
            pos, orn = get_pose(body, physicsClientId=cid)
            P.append(pos)
            Q.append(orn)
            if unload is not None and unload.pending and (a[0] * a[0] + a[1] * a[1] >= unload.a2_min or unload.run):
                unload.update(k, pos, orn)
            if k - checked >= OVERTURN_CHECK or k == n:
                ot, bad = _first_events(np.asarray(P[checked:k + 1]), np.asarray(Q[checked:k + 1]), V, p2)
                if ot is not None and ot_k is None:      # (an overturn comes before a non-finite pose)
                    ot_k = checked + ot
                    if stop_on_overturn:
                        break
                if bad is not None:
                    bad_k = checked + bad
                    break
                checked = k + 1
        steps = len(P) - 1
    wall = time.perf_counter() - t0
    if bad_k is not None:                                 # the first non-finite pose is not kept
        last = bad_k - 1
        if ot_k is not None and ot_k > last:
            ot_k = None
    if ot_k is not None and stop_on_overturn:
        last = stop_k = ot_k
    h = _histories(np.asarray(P[:last + 1], dtype=float), np.asarray(Q[:last + 1], dtype=float), scene, V,
                   hull_c, base_v, piv, dt)
    th_all = h["theta"]
    q_R = float(np.abs(th_all[th_all > 0]).max(initial=0.0))
    q_L = float(np.abs(th_all[th_all <= 0]).max(initial=0.0))
    # samples every ``every`` steps and the last step (as the step loop used to record them)
    ks = np.arange(0, last + 1, every)
    if n <= last and ks[-1] != n:
        ks = np.append(ks, n)
    ts, th = (ks * dt).tolist(), th_all[ks].tolist()
    tx, yw, sl = h["tilt"][ks].tolist(), h["yaw"][ks].tolist(), h["slide"][ks].tolist()
    if stop_k is not None:                                # the overturning step, once more
        ts.append(stop_k * dt)
        th.append(float(th_all[stop_k]))
        tx.append(tx[-1] if tx else 0.0)
        yw.append(yw[-1] if yw else 0.0)
        sl.append(np.nan)
    up_t = 0.0 if theta0 != 0.0 else (_lift_off_time(h["lift"], dt) if watch else None)
    unload_t = None
    if unload is not None and unload.time is not None and unload.step <= last:
        unload_t = unload.time
    ot_t = ot_k * dt if ot_k is not None else None
    ot_side = None if ot_k is None else ("R" if th_all[ot_k] > 0 else "L")
    t_arr, th_arr = np.asarray(ts, dtype=float), np.asarray(th, dtype=float)
    sign_t, pk_t, pk_th = _impacts_and_peaks(t_arr, th_arr)
    imp = _landing_times(h["edge"], dt, last)
    return Statue3DResult(
        scene=scene, settings=settings, contact=contact, t=t_arr, theta=th_arr, tilt_out=np.asarray(tx),
        yaw=np.asarray(yw), slide=np.asarray(sl), uplift_time=up_t, overturned=ot_t is not None,
        overturn_time=ot_t, overturn_side=ot_side, theta_max_L=q_L, theta_max_R=q_R,
        impact_times=imp, sign_change_times=sign_t, peak_t=pk_t, peak_theta=pk_th, finite=bad_k is None,
        wall_time=wall, steps=steps, cpu_time=time.process_time() - c0,
        inertia=check, max_pivot_slip=h["slip"], max_flight=max(0.0, h["flight"]),
        flight_time=h["n_flight"] * dt, unload_time=unload_t, max_lift=max(0.0, h["lift_max"]))


def base_rays(base_xy: np.ndarray, com_xy: np.ndarray) -> tuple[float, float]:
    """(b_R, b_L), m: the lengths of the rays from ``com_xy`` (2,) along +x and -x to where they leave
    the convex hull of the base points ``base_xy`` (n, 2) - the rocking geometry of the x direction
    (geometry.rocking_params.ray_exit)."""
    from scipy.spatial import ConvexHull

    from ..geometry.rocking_params import ray_exit

    from scipy.spatial import QhullError

    try:
        poly = base_xy[ConvexHull(base_xy).vertices]      # counter-clockwise
    except (QhullError, ValueError):                      # a point or a line: no area to stand on
        return 0.0, 0.0
    return (ray_exit(poly, com_xy, np.array([1.0, 0.0]))[0], ray_exit(poly, com_xy, np.array([-1.0, 0.0]))[0])


def base_vertices(scene: StatueScene) -> tuple[np.ndarray, dict]:
    """The hull's base vertices (bool mask, z = 0) and the pivot vertices of each side ({"R", "L"}:
    indices of the base vertices at x_R, x_L), as :func:`_histories` reads them."""
    base_v = scene.hull[:, 2] == 0.0
    return base_v, {"R": np.flatnonzero(base_v & (scene.hull[:, 0] == scene.x_R)),
                    "L": np.flatnonzero(base_v & (scene.hull[:, 0] == scene.x_L))}


def _theta(Q: np.ndarray, V: np.ndarray) -> np.ndarray:
    """theta (m,) of poses with orientations Q (m, 4): the link frame R = Rc V^T, atan2(R_02, R_22)."""
    R = matrices_from_quats(Q) @ V.T
    return np.arctan2(R[:, 0, 2], R[:, 2, 2])


def _first_events(P: np.ndarray, Q: np.ndarray, V: np.ndarray, params) -> tuple[int | None, int | None]:
    """(first row with |theta| >= delta of its side, first row with a non-finite pose) of a block of
    poses P (m, 3), Q (m, 4); None when there is none (the overturn only before the non-finite row)."""
    with np.errstate(invalid="ignore"):
        th = _theta(Q, V)
        bad = ~(np.isfinite(th) & np.isfinite(P).all(axis=1))
        over = np.abs(th) >= np.where(th > 0, params.delta_R, params.delta_L)
    nb = int(np.argmax(bad)) if bad.any() else None
    if nb is not None:
        over[nb:] = False
    return (int(np.argmax(over)) if over.any() else None), nb


def _histories(P: np.ndarray, Q: np.ndarray, scene: StatueScene, V: np.ndarray, hull_c: np.ndarray,
               base_v: np.ndarray, piv: dict, dt: float, chunk: int = 4096) -> dict:
    """Per-step quantities of the kept poses P (m, 3), Q (m, 4), m = steps + 1: theta, tilt_out, yaw,
    slide (NaN while |theta| >= 1e-3), lift (height of the highest base point, m), edge ({"R", "L"}:
    height, m, of the lowest base vertex at x_R / x_L, each (m,)); and the maxima:
    flight (lowest hull point), n_flight (steps with it above FLIGHT_HEIGHT), lift_max, slip (pivot
    slip, Statue3DResult.max_pivot_slip). Hull vertex heights are formed ``chunk`` steps at a time."""
    m = len(P)
    Rc = matrices_from_quats(Q)
    R = Rc @ V.T                                          # link frame: identity when upright
    theta = np.arctan2(R[:, 0, 2], R[:, 2, 2])
    tilt = np.arctan2(-R[:, 1, 2], np.hypot(R[:, 0, 2], R[:, 2, 2]))
    yaw = np.arctan2(R[:, 1, 0], R[:, 0, 0])
    base0 = np.array([0.5 * (scene.x_R + scene.x_L), 0.0, 0.0])
    base_x = P[:, 0] - Rc[:, 0, :] @ (V.T @ scene.com) + R[:, 0, :] @ base0
    slide = np.where(np.abs(theta) < 1e-3, base_x - base0[0], np.nan)
    lift = np.empty(m)
    flight, n_flight = -np.inf, 0
    # contiguous operands: numpy's matmul of a strided (m, 3) by a transposed (3, k) runs 30 x slower
    # (7.7 ms against 0.23 ms for 1000 steps of the default scan's 195 vertices), with the same result
    hull_t = np.ascontiguousarray(hull_c.T)
    for a in range(0, m, chunk):
        b = min(m, a + chunk)
        z = P[a:b, 2, None] + np.ascontiguousarray(R[a:b, 2, :]) @ hull_t     # (steps, vertices) heights, m
        zlow = z.min(axis=1)
        flight = max(flight, float(zlow.max(initial=-np.inf)))
        n_flight += int((zlow > FLIGHT_HEIGHT).sum())
        lift[a:b] = z[:, base_v].max(axis=1)
    slip, edge = 0.0, {}
    for side, idx in piv.items():                         # the pivot vertices on the floor
        if idx.size == 0 or m == 0:
            continue
        w = P[:, None, :] + np.einsum("kij,vj->kvi", R, hull_c[idx])      # (steps, pivot vertices, 3)
        edge[side] = w[:, :, 2].min(axis=1)
        down = w[:, :, 2] < LIFT_HEIGHT
        landed = np.zeros_like(down)
        landed[1:] = down[1:] & ~down[:-1]                # touched down: slip counted from there
        start = np.where(landed, np.arange(m)[:, None], -1)
        start = np.maximum.accumulate(start, axis=0)      # step of the last touch-down (-1: at rest)
        cols = np.arange(idx.size)[None, :]
        anchor = np.where((start >= 0)[:, :, None], w[np.maximum(start, 0), cols, :2],
                          scene.hull[idx, :2][None, :, :])
        d = np.hypot(*(w[:, :, :2] - anchor).transpose(2, 0, 1))
        if down.any():
            slip = max(slip, float(d[down].max()))
    return {"theta": theta, "tilt": tilt, "yaw": yaw, "slide": slide, "lift": lift, "edge": edge,
            "flight": flight, "n_flight": n_flight, "lift_max": float(lift.max(initial=-np.inf)), "slip": slip}


def _lift_off_time(lift: np.ndarray, dt: float) -> float | None:
    """Geometric lift-off (Statue3DResult.uplift_time) from the per-step height of the highest base
    point: the start of the first run of LIFT_STEPS steps (from step 1) above LIFT_HEIGHT, interpolated
    with the step before."""
    above = lift > LIFT_HEIGHT
    above[0] = False
    if above.sum() < LIFT_STEPS:
        return None
    run = np.convolve(above.astype(int), np.ones(LIFT_STEPS, dtype=int), mode="valid")  # run[i]: i..i+S-1
    full = np.flatnonzero(run == LIFT_STEPS)
    if full.size == 0:
        return None
    s = int(full[0])
    while s > 1 and above[s - 1]:                        # the run that reached LIFT_STEPS started here
        s -= 1
    lk, lp = float(lift[s]), float(lift[s - 1])
    return s * dt - dt * (lk - LIFT_HEIGHT) / (lk - lp) if lk > lp else s * dt


def _landing_times(edge: dict, dt: float, last: int) -> np.ndarray:
    """Impact times, s (Statue3DResult.impact_times), from the per-step heights ``edge`` (side -> (m,),
    m) of each side's lowest base vertex over steps 0..last: each time the raised side - lifted above
    LIFT_HEIGHT and higher than the other side for LIFT_STEPS steps (from step 0 on for a release; a
    pivot edge rolled up by an out-of-plane tilt is not a lift) - comes back below LAND_HEIGHT at step
    j, the time its height crosses 0 (the floor) - interpolated between the last step above 0 and the first at
    or below it, searched while the side stays below LAND_HEIGHT - or, if it stays above 0 there, the
    crossing of LAND_HEIGHT before step j. Sorted, both sides together."""
    out = []
    zs = {s: np.asarray(z[:last + 1], dtype=float) for s, z in edge.items()}
    for s, z in zs.items():
        if z.size <= LIFT_STEPS:
            continue
        other = [v for o, v in zs.items() if o != s]
        raised = (z > LIFT_HEIGHT) & (z > np.maximum.reduce(other)) if other else z > LIFT_HEIGHT
        up = np.convolve(raised.astype(int), np.ones(LIFT_STEPS, dtype=int), mode="valid")
        lifted = np.flatnonzero(up == LIFT_STEPS) + LIFT_STEPS - 1   # step that confirms a lift
        low = z <= LAND_HEIGHT
        downs, ups = np.flatnonzero(low), np.flatnonzero(~low)
        pos = 0
        while True:
            i = np.searchsorted(lifted, pos)
            if i >= lifted.size:
                break
            k = np.searchsorted(downs, lifted[i] + 1)
            if k >= downs.size:
                break
            j = int(downs[k])
            u = np.searchsorted(ups, j)
            e = int(ups[u]) - 1 if u < ups.size else z.size - 1   # end of this run below LAND_HEIGHT
            floor = np.flatnonzero(z[j:e + 1] <= 0.0)
            c, lvl = (j + int(floor[0]), 0.0) if floor.size else (j, LAND_HEIGHT)
            z0, z1 = z[c - 1], z[c]
            out.append((c - (lvl - z1) / (z0 - z1)) * dt if z0 > lvl >= z1 else c * dt)
            pos = e + 1
    return np.sort(np.asarray(out, dtype=float))


class _UnloadWatch:
    """Force lift-off, read during the run (Statue3DResult.unload_time): step by step, while pending,
    whether the floor's contact points away from one pivot carry less than UNLOAD_FRACTION m g
    (:func:`_unloaded_side`), LIFT_STEPS steps in a row. ``time``: its start, s; ``step``: the step
    that confirmed it."""

    def __init__(self, world: World, body: int, scene: StatueScene, V: np.ndarray, piv: dict, dt: float):
        self.world, self.body, self.dt = world, body, dt
        self.V = V
        hull_c = scene.hull - scene.com
        # pivot x in the world = pos_x + (R hull_c)_x averaged over the pivot's vertices
        self.piv_c = [hull_c[idx].mean(axis=0) for idx in piv.values() if idx.size]
        self.band = UNLOAD_BAND * (scene.x_R - scene.x_L)
        self.mg = scene.mass * world.settings.g
        self.pending, self.run, self.t0 = True, 0, 0.0
        self.time = self.step = None
        # the contacts are read only while the ground's horizontal acceleration could unload a side: at
        # rest on its base the body needs |a| >= g b_min / h_G, b_min the least distance from G to the base
        # polygon's edges; read from UNLOAD_GATE x that on (squared, m^2/s^4)
        self.a2_min = (UNLOAD_GATE * world.settings.g * _base_inradius(scene) / max(scene.com[2], 1e-9)) ** 2

    def update(self, k: int, pos, orn) -> None:
        R = matrix_from_quat(orn) @ self.V.T
        xs = [float(pos[0] + R[0] @ c) for c in self.piv_c]
        if _unloaded_side(self.world, self.body, xs, self.band, self.mg):
            if self.run == 0:
                self.t0 = k * self.dt
            self.run += 1
            if self.run >= LIFT_STEPS:
                self.time, self.step, self.pending = self.t0, k, False
        else:
            self.run = 0


@functools.lru_cache(maxsize=32)
def _base_inradius(scene: StatueScene) -> float:
    """The least horizontal distance, m, from the centre of mass to an edge of the base polygon (0 when
    it is not inside or there is no polygon)."""
    from scipy.spatial import ConvexHull, QhullError

    try:
        eq = ConvexHull(scene.hull[scene.hull[:, 2] == 0.0][:, :2]).equations
    except (QhullError, ValueError):
        return 0.0
    return max(0.0, float(-(eq[:, :2] @ scene.com[:2] + eq[:, 2]).max()))


def _unloaded_side(world: World, body: int, pivots_x, band: float, mg: float) -> bool:
    """True if the body stands on the floor (normal force > 10 UNLOAD_FRACTION m g) and the contact
    points farther than ``band`` (m, along x) from one pivot carry less than UNLOAD_FRACTION m g: all
    the weight sits on that pivot (``pivots_x``: world x of the right / left pivot, m)."""
    cps = world.p.getContactPoints(bodyA=body, physicsClientId=world.client)
    if not cps:
        return False
    xn = [(c[5][0], c[9]) for c in cps]
    if sum(f for _, f in xn) <= 10 * UNLOAD_FRACTION * mg:
        return False
    for xp in pivots_x:
        if sum(f for x, f in xn if abs(x - xp) > band) < UNLOAD_FRACTION * mg:
            return True
    return False


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
