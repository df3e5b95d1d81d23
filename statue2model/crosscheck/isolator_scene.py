"""Scene (b): the rolling-ball isolator in PyBullet, with or without the statue on it.

The real device: the bottom plate (grooves carved in its upper face) is the
ground, so it is a static concave triangle mesh (PyBullet's
GEOM_FORCE_CONCAVE_TRIMESH) and the ground motion is the gravity tilt of
world.py; one ball (a sphere of radius r) per groove; the top plate, the
mirror image of the bottom one, is a moving body whose collision shape is its
own triangle mesh (a concave mesh on a moving body: Bullet collides it with
convex shapes - the balls and the statue's hull - through the same
convex-concave algorithm; only concave-concave pairs are skipped, and the two
plates never touch); its mass and inertia are set from our numbers, not from the
mesh. The statue (scene (a)'s hull, inertia from our mass properties) stands on
the top plate's upper face. Plates come from statue2model.isolator.plates
(the same solids the CNC files are made of), tessellated with ``segments``
vertices per groove ring, or (default) the grooves as a 4 mm triangular lattice on the
sphere (grooves.grid_cap, :data:`GRID`: the measured choice, see there and the benchmark).
The statue rides on the plate free-standing (``mount='contact'``: the rocking check) or
as one rigid body with it (``mount='rigid'``: the 2D plate model's assumption, the plate
response); see :func:`simulate_isolator`.

Frames: bottom plate's lower face z = 0, carved face z = t; groove sphere
centres at z = t - depth + R; top plate's lower face at z = t + 2 (r - depth).
u (top plate displacement) is measured relative to the bottom plate (the ground).

Rolling friction: the balls get rollingFriction = mu r / f (contact.rolling_for_mu)
so the plate feels a resistance mu W; see contact.py and the calibration in isolator_cases.py.

Capacity: the run watches the 3D plate displacement |u| against the isolator's capacity
(``capacity``: the design's, or its ``d_max``, with :meth:`IsolatorScene.from_design`; none
otherwise) at every engine step; where it is passed the outcome is "isolator capacity
exceeded", with the step's time and u, and (``stop_at_capacity``, default) the run stops
there, as the 2D analyses do. The grooves are of finite size in 3D as well: a ball that
rolls over a rim (its centre beyond the opening radius a) is reported apart, "ball left its
groove" (the capacity, where the balls' contact points reach the rims, comes before that).

Example
-------
>>> from statue2model.crosscheck.isolator_scene import IsolatorScene
>>> sc = IsolatorScene.simple(R=0.9, r=0.0095, mu=0.0, m_o=50.0, segments=64)
>>> round(sc.R_hat, 3)
1.781
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass, field, replace

import numpy as np

from ..errors import InputError
from .contact import ContactSettings, rolling_for_mu
from .grooves import grid_plate_mesh, tile_boxes, tile_plate
from .statue_scene import StatueScene, add_statue, inertia_frame
from .world import SimSettings, World, matrix_from_quat, quat_from_matrix, real_time_factor, step_mean_acc

STEEL = 7850.0  # kg/m^3, the balls
MOUNTS = ("contact", "fixed", "rigid")
GRID = 0.004
"""Default groove tessellation: a triangular lattice of 4 mm (m) on the sphere (see grooves.grid_cap). Measured
(R 0.3 m, r 9.5 mm, mu = 0, from 60 mm): 0.29 mm lost per cycle at dt 0.5 ms, -0.14 / -0.03 mm at
0.25 / 0.125 ms (converges to 0); the revolved CNC mesh loses 0.28 / 7.3 / 4.7 mm at 32 / 64 / 128
segments and does not converge with dt (64: 3.3 mm at 0.25 ms). At rest under the 407 kg statue the
plate's 20 Hz acceleration is 0.04 m/s^2 rms against 0.72 with the 128-segment mesh (a fan of
``segments`` slivers at the groove's deepest point: the ball touches dozens of triangles, Bullet keeps 4
contact points per pair and the set changes every step)."""

GROOVES = ("tiles", "lattice", "cnc")
GROOVE = "lattice"
"""Default groove model: the lattice (:data:`GRID`). 'tiles' (grooves.tile_cap, a compound of boxes on
the rigid-body solver) is 6-8 x faster with the plate acceleration at 2D's, but its flat tiles make the
restoring force a staircase: the free-vibration period of the crosscheck case is 2.9 % long at 0.7 r
tiles against 1.5 % for the lattice (measured, docs/crosscheck.md "Speed"): selectable, not the default."""
TILE_PER_R = 1.0
"""Default tile side / ball radius (groove 'tiles')."""


def _groove(groove: str | None, grid: float | None) -> str:
    if groove is not None:
        return groove
    return "cnc" if grid is None else GROOVE


@dataclass(frozen=True, eq=False)
class IsolatorScene:
    """An isolator (PlateGeometry ``geom``), its friction ``mu``, top-plate mass ``m_o`` (kg),
    ball density (kg/m^3), optional statue; groove tessellation: a lattice of ``grid`` m on the sphere
    (default, grooves.grid_cap) or, with ``grid=None``, the CNC solid with ``segments`` per ring.
    ``groove``: 'lattice' (default), 'cnc', or 'tiles' - convex tangent tiles of ``tile`` m (default
    TILE_PER_R x r, grooves.tile_cap), a compound of convex pieces (run it with
    SimSettings(maximal_coordinates=True): the rigid-body solver)."""

    geom: object
    mu: float
    m_o: float
    segments: int = 256
    ball_density: float = STEEL
    statue: StatueScene | None = None
    grid: float | None = GRID
    capacity: float | None = None
    groove: str = GROOVE
    tile: float | None = None

    def __post_init__(self):
        if self.groove not in GROOVES:
            raise InputError(f"groove must be one of {', '.join(GROOVES)}, got {self.groove!r}")
        if self.groove == "lattice" and self.grid is None:     # grid=None: the CNC mesh (as before 'groove')
            object.__setattr__(self, "groove", "cnc")
        if self.tile is not None and not (math.isfinite(self.tile) and 1e-3 <= self.tile <= 0.2):
            raise InputError(f"groove tile size must be in [1, 200] mm, got {self.tile!r} m")
        if self.capacity is not None and not (self.capacity > 0):
            raise InputError(f"isolator capacity must be a positive length in m, got {self.capacity!r}")
        if not (math.isfinite(self.mu) and 0 <= self.mu < 1):
            raise InputError(f"rolling friction mu must be in [0, 1), got {self.mu!r}")
        if not (math.isfinite(self.m_o) and self.m_o > 0):
            raise InputError(f"top plate mass must be positive, got {self.m_o!r}")
        if not (isinstance(self.segments, int) and 16 <= self.segments <= 4096):
            raise InputError(f"segments must be an integer in 16..4096, got {self.segments!r}")
        if self.grid is not None and not (math.isfinite(self.grid) and 1e-4 <= self.grid <= 0.1):
            raise InputError(f"groove grid spacing must be in [0.1, 100] mm, got {self.grid!r} m")

    @property
    def R(self) -> float:
        return self.geom.R

    @property
    def r(self) -> float:
        return self.geom.ball_radius

    @property
    def R_hat(self) -> float:
        return 2.0 * (self.geom.R - self.geom.ball_radius)

    @property
    def travel_capacity(self) -> float:
        """Largest plate displacement |u| checked (m): ``capacity`` (the design's), inf if none."""
        return math.inf if self.capacity is None else float(self.capacity)

    @property
    def ball_mass(self) -> float:
        return self.ball_density * 4.0 / 3.0 * math.pi * self.r**3

    @property
    def M(self) -> float:
        """Supported mass: top plate + statue (kg); the balls are not in the 2D model."""
        return self.m_o + (self.statue.mass if self.statue is not None else 0.0)

    @classmethod
    def from_design(cls, design: dict, statue: StatueScene | None = None, segments: int = 256,
                    mu: float | None = None, grid: float | None = GRID, groove: str | None = None
                    ) -> IsolatorScene:
        """From the JSON of ``statue2model isolator design`` (a dict). ``groove``: 'tiles' | 'lattice' |
        'cnc'; None: the default (GROOVE), or 'cnc' if ``grid`` is None (the CLI's --grid 0)."""
        from ..isolator.plates import PlateGeometry

        try:
            geom = PlateGeometry(side=float(design["side"]), thickness=float(design["thickness"]),
                                 R=float(design["R"]), depth=float(design["depth"]),
                                 groove_centres=tuple(tuple(c) for c in design["groove_centres"]),
                                 ball_radius=float(design["r"]))
            m_o = float(design["m_o"])
            mu = float(design["mu"]) if mu is None else mu
            cap = design.get("capacity")
            cap = design.get("d_max") if cap is None else cap
            cap = None if cap is None else float(cap)
        except (KeyError, TypeError, ValueError) as exc:
            raise InputError(f"not an isolator design ({exc})") from None
        return cls(geom=geom, mu=mu, m_o=m_o, segments=segments, statue=statue, grid=grid, capacity=cap,
                   groove=_groove(groove, grid))

    @classmethod
    def simple(cls, R: float, r: float, mu: float, m_o: float, side: float | None = None, spacing: float = 0.4,
               thickness: float = 0.03, travel: float = 0.1, segments: int = 256, grid: float | None = GRID,
               groove: str | None = None) -> IsolatorScene:
        """Four grooves ``spacing`` apart, deep enough for a ball travel of ``travel`` (m) each way."""
        from ..isolator.plates import PlateGeometry, depth_for_opening

        depth = depth_for_opening(R, travel + r)
        side = spacing + 2 * (travel + r) + 0.04 if side is None else side
        h = spacing / 2
        geom = PlateGeometry(side=side, thickness=thickness, R=R, depth=depth,
                             groove_centres=((-h, -h), (h, -h), (h, h), (-h, h)), ball_radius=r)
        return cls(geom=geom, mu=mu, m_o=m_o, segments=segments, grid=grid, groove=_groove(groove, grid))

    @property
    def tile_size(self) -> float:
        """Side of the groove tiles (m, groove 'tiles'): ``tile``, or TILE_PER_R x the ball radius."""
        return TILE_PER_R * self.r if self.tile is None else float(self.tile)

    def plate_mesh(self, which: str) -> tuple[np.ndarray, np.ndarray]:
        """Collision geometry of a plate in its own frame: groove 'tiles' - grooves.tile_plate (every
        8 vertices / 12 faces one convex tile); 'lattice' - grooves.grid_plate_mesh (``grid``);
        'cnc' - the CNC solid of ``isolator plates`` (``segments`` per ring)."""
        if self.groove == "tiles":
            return tile_plate(self.geom, which, self.tile_size)
        if self.groove == "lattice":
            return grid_plate_mesh(self.geom, which, self.grid)
        from ..isolator.plates import plate_solid, to_trimesh

        m = to_trimesh(plate_solid(self.geom, which, segments=self.segments))
        return np.asarray(m.vertices), np.asarray(m.faces)


def _tiles_body(world, v: np.ndarray, *, mass: float, inertia: list[float], inertial_pos, inertial_rot,
                base_pos, fixed: bool) -> int:
    """One body whose collision shape is the boxes of ``v`` (grooves.tile_boxes), loaded from a
    temporary URDF (one link, one <collision> box per tile: Bullet builds a compound of boxes with a
    bounding-volume tree, any number of children; PyBullet's createCollisionShapeArray keeps 16 and
    convex hulls cost a GJK each). Mass (kg), principal inertia (kg m^2) about the inertial frame
    (``inertial_pos`` m, ``inertial_rot`` 3x3) in the link frame, placed at ``base_pos``."""
    import os
    import tempfile

    from scipy.spatial.transform import Rotation

    ctr, rot, dims = tile_boxes(v)
    rpy = Rotation.from_matrix(rot).as_euler("xyz")        # URDF rpy: fixed axes x, y, z
    irpy = Rotation.from_matrix(np.asarray(inertial_rot, dtype=float)).as_euler("xyz")
    f = "{:.15g}".format
    ip = " ".join(map(f, inertial_pos))
    lines = ['<robot name="plate"><link name="plate">',
             f'<inertial><origin xyz="{ip}" rpy="{" ".join(map(f, irpy))}"/><mass value="{f(mass)}"/>'
             f'<inertia ixx="{f(inertia[0])}" iyy="{f(inertia[1])}" izz="{f(inertia[2])}" ixy="0" ixz="0" iyz="0"/>'
             '</inertial>']
    lines.extend(f'<collision><origin xyz="{" ".join(map(f, c))}" rpy="{" ".join(map(f, a))}"/>'
                 f'<geometry><box size="{" ".join(map(f, d))}"/></geometry></collision>'
                 for c, a, d in zip(ctr, rpy, dims))
    lines.append("</link></robot>")
    fd, path = tempfile.mkstemp(suffix=".urdf", prefix="s2m_tiles_")
    try:
        with os.fdopen(fd, "w") as fh:
            fh.write("\n".join(lines) + "\n")
        return world.call("loadURDF", path, basePosition=list(map(float, base_pos)), useFixedBase=int(fixed),
                          useMaximalCoordinates=int(world.settings.maximal_coordinates),
                          flags=world.p.URDF_USE_INERTIA_FROM_FILE)
    finally:
        os.unlink(path)


class PlateRun:
    """What a 3D isolator run (:class:`Isolator3DResult`, pendulum_scene.PendulumResult) answers from
    its fields (finite, ball_left_groove, t_capacity, statue_overturned, the peaks, the capacity ...):
    whether the capacity was passed, the outcome and the keys both write to JSON (:meth:`_plate_dict`).
    ``efficiency`` and ``real_time_factor`` are each class's own."""

    @property
    def capacity_exceeded(self) -> bool:
        return self.t_capacity is not None

    @property
    def outcome(self) -> str:
        """The first that holds of: "non-finite state", "ball left its groove", "isolator capacity
        exceeded", "statue overturned", "ok"."""
        if not self.finite:
            return "non-finite state"
        if self.ball_left_groove:
            return "ball left its groove"
        if self.t_capacity is not None:
            return "isolator capacity exceeded"
        if self.statue_overturned:
            return "statue overturned"
        return "ok"

    def _plate_dict(self) -> dict:
        """The JSON keys common to both runs (the capacity as None when there is none)."""
        d = {"outcome": self.outcome, "u_max": self.u_max, "acc_abs_max": self.acc_abs_max, "pga": self.pga,
             "efficiency": self.efficiency, "peaks_t": self.peaks_t.tolist(), "peaks_u": self.peaks_u.tolist(),
             "statue_overturned": self.statue_overturned, "finite": self.finite, "wall_time_s": self.wall_time,
             "steps": self.steps, "real_time_factor": self.real_time_factor,
             "capacity": self.capacity if math.isfinite(self.capacity) else None,
             "capacity_exceeded": self.capacity_exceeded, "t_capacity": self.t_capacity,
             "u_at_capacity": self.u_at_capacity, "t_overturn": self.t_overturn,
             "settings": self.settings.to_dict(), "notes": list(self.notes)}
        if self.theta is not None:
            d["theta_max"] = float(np.nanmax(np.abs(self.theta))) if self.theta.size else 0.0
        return d


@dataclass(frozen=True, eq=False)
class Isolator3DResult(PlateRun):
    """A 3D run of the isolator (SI units).

    t, u, acc_abs   : top plate displacement relative to the ground (x) and its absolute
                      acceleration (x), every dt_out
    ball_r_max      : largest distance of a ball from its groove's axis, m (rim at opening - r)
    peaks_t, peaks_u: extrema of u (one per half cycle)
    theta           : the statue's rotation (rad), if a statue rides on the plate
    acc_step        : the absolute plate acceleration of every engine step (m/s^2; velocity change
                      over the step / dt + the step's ground acceleration), for filtering
    capacity        : the |u| checked (m, scene.travel_capacity); t_capacity, u_at_capacity: the first
                      engine step at which |u| passed it (None if never)
    t_overturn      : the engine step's time, s, at which the statue overturned (None if it did not)
    """

    scene: IsolatorScene
    settings: SimSettings
    t: np.ndarray
    u: np.ndarray
    acc_abs: np.ndarray
    theta: np.ndarray | None
    peaks_t: np.ndarray
    peaks_u: np.ndarray
    ball_r_max: float
    u_max: float
    acc_abs_max: float
    pga: float
    statue_overturned: bool
    ball_left_groove: bool
    finite: bool
    wall_time: float
    steps: int
    notes: tuple = field(default=())
    acc_step: np.ndarray | None = None
    capacity: float = math.inf
    t_capacity: float | None = None
    u_at_capacity: float | None = None
    t_overturn: float | None = None

    @property
    def efficiency(self) -> float:
        return self.acc_abs_max / self.pga if self.pga > 0 else float("nan")

    @property
    def real_time_factor(self) -> float:
        return real_time_factor(self.steps, self.settings.dt, self.wall_time)

    def to_dict(self) -> dict:
        return self._plate_dict() | {"ball_r_max": self.ball_r_max, "ball_left_groove": self.ball_left_groove,
                                     "segments": self.scene.segments, "grid": self.scene.grid,
                                     "groove": self.scene.groove}


def _box_inertia(m: float, a: float, b: float, c: float) -> list[float]:
    return [m * (b * b + c * c) / 12, m * (a * a + c * c) / 12, m * (a * a + b * b) / 12]


def simulate_isolator(scene: IsolatorScene, motion, *, u0: float = 0.0, t_end: float | None = None,
                      settings: SimSettings | None = None, contact: ContactSettings | None = None,
                      dt_out: float = 0.005, free_time: float = 10.0, meshes: dict | None = None,
                      mount: str = "contact", ball_contact: tuple | None = None, internal_edges: bool = True,
                      settle: float = 0.25, stop_at_capacity: bool = True) -> Isolator3DResult:
    """Run scene (b) under ``motion`` (GroundMotion along +x), the top plate released from
    rest displaced by u0 (m; the balls halfway, on their grooves). Stops early if a ball
    leaves its groove, the statue overturns or the state stops being finite.
    ``meshes``: {'bottom': (v, f), 'top': (v, f)} to reuse tessellated plates.

    ``mount`` (how the statue rides on the top plate): 'contact' - its hull stands free on the
    plate (it can rock and slide: the rocking check); 'fixed' - held to the plate by a fixed
    constraint (JOINT_FIXED, at the statue's centre of mass); 'rigid' - plate and statue are one
    rigid body (mass m_o + m, the combined centre of mass and inertia tensor; collision: the
    plate's mesh only). 'fixed' and 'rigid' are the 2D plate model's own assumption (the statue
    moves with the plate: it does not uplift) and give the plate response.
    ``ball_contact``: (contactStiffness N/m, contactDamping N s/m) of the balls, or None (rigid).
    ``settle``: with u0 = 0, seconds run with gravity alone before t = 0 (the balls seat on the
    facets under the load: a start-up transient of up to 1.8 m/s^2 in the first 0.1 s otherwise);
    u stays measured from the geometric centre.
    ``stop_at_capacity``: end the run where |u| passes scene.travel_capacity (outcome
    "isolator capacity exceeded"); False: report it and go on."""
    if mount not in MOUNTS:
        raise InputError(f"mount must be one of {', '.join(MOUNTS)}, got {mount!r}")
    contact = ContactSettings() if contact is None else contact
    settings = SimSettings() if settings is None else settings
    if scene.groove == "tiles" and not settings.maximal_coordinates:     # a compound of boxes on a
        settings = replace(settings, maximal_coordinates=True)            # moving body: rigid-body solver
    geom = scene.geom
    R, r, t_pl, depth = geom.R, geom.ball_radius, geom.thickness, geom.depth
    a_open = geom.opening_radius
    if not math.isfinite(u0) or abs(u0) / 2 >= a_open - r:
        raise InputError(f"u0 = {u0} m puts the balls beyond the groove rims (|u0|/2 < {a_open - r:.4f} m)")
    if t_end is None:
        t_end = motion.end + free_time
    if not (math.isfinite(t_end) and t_end > 0):
        raise InputError(f"t_end must be positive, got {t_end}")
    meshes = meshes or {w: scene.plate_mesh(w) for w in ("bottom", "top")}
    dt = settings.dt
    n = math.ceil(t_end / dt - 1e-9)
    every = max(1, round(dt_out / dt))
    acc_g = step_mean_acc(motion, 0.0, dt, n + 1)
    f = contact.friction
    phi = math.asin(u0 / (2 * (R - r)))
    notes = []
    t0 = time.perf_counter()
    with World(settings) as world:
        p = world.p
        mesh_flags = p.GEOM_FORCE_CONCAVE_TRIMESH | (p.GEOM_CONCAVE_INTERNAL_EDGE if internal_edges else 0)
        tiles = scene.groove == "tiles"

        def plate_body(which, mass=0.0, inertia=(0.0, 0.0, 0.0), inertial_pos=(0.0, 0.0, 0.0),
                       inertial_rot=np.eye(3), base_pos=(0.0, 0.0, 0.0)):
            v, fc = meshes[which]
            if tiles:
                return _tiles_body(world, v, mass=mass, inertia=list(inertia), inertial_pos=inertial_pos,
                                   inertial_rot=inertial_rot, base_pos=base_pos, fixed=which == "bottom")
            shape = world.call("createCollisionShape", p.GEOM_MESH, vertices=v.tolist(),
                               indices=fc.ravel().tolist(), flags=mesh_flags)
            if which == "bottom":
                return world.call("createMultiBody", 0.0, shape)
            return world.call("createMultiBody", mass, shape, basePosition=list(base_pos),
                              baseInertialFramePosition=list(inertial_pos),
                              baseInertialFrameOrientation=quat_from_matrix(inertial_rot),
                              useMaximalCoordinates=int(settings.maximal_coordinates))

        bottom = plate_body("bottom")
        world.call("changeDynamics", bottom, -1, lateralFriction=f, restitution=0.0, collisionMargin=0.0)
        # balls
        balls = []
        centres = []
        zc = t_pl - depth + R                               # bottom groove sphere centres
        ss = world.call("createCollisionShape", p.GEOM_SPHERE, radius=r)
        for (cx, cy) in geom.groove_centres:
            pos = [cx + (R - r) * math.sin(phi), cy, zc - (R - r) * math.cos(phi)]
            b = world.call("createMultiBody", scene.ball_mass, ss, basePosition=pos,
                           useMaximalCoordinates=int(settings.maximal_coordinates))
            world.call("changeDynamics", b, -1, lateralFriction=f, restitution=0.0, linearDamping=0.0,
                       angularDamping=0.0, rollingFriction=rolling_for_mu(scene.mu, r, f), spinningFriction=0.0)
            if ball_contact is not None:
                world.call("changeDynamics", b, -1, contactStiffness=float(ball_contact[0]),
                           contactDamping=float(ball_contact[1]))
            balls.append(b)
            centres.append((cx, cy))
        # top plate (mirror of the bottom one), displaced by 2 (R - r) sin(phi), raised by 2 (R - r)(1 - cos phi)
        gap = 2 * (r - depth)
        ux, uz = 2 * (R - r) * math.sin(phi), 2 * (R - r) * (1 - math.cos(phi))
        top_z = t_pl + gap
        rigid = scene.statue is not None and mount == "rigid"
        if rigid:        # one body: plate (box inertia about its centre) + statue (our tensor), parallel axes
            st_sc = scene.statue
            m_tot = scene.m_o + st_sc.mass
            c_pl = np.array([0.0, 0.0, 0.5 * t_pl])
            c_st = np.asarray(st_sc.com, dtype=float) + [0.0, 0.0, t_pl]     # statue base on the upper face
            c = (scene.m_o * c_pl + st_sc.mass * c_st) / m_tot

            def shift(m, d):
                return m * (float(d @ d) * np.eye(3) - np.outer(d, d))

            inert = (np.diag(_box_inertia(scene.m_o, geom.side, geom.side, t_pl)) + shift(scene.m_o, c_pl - c)
                     + np.asarray(st_sc.inertia, dtype=float) + shift(st_sc.mass, c_st - c))
            w_in, V_in = inertia_frame(inert)
            m_top, i_top, c_top, V_top = m_tot, w_in.tolist(), c.tolist(), V_in
        else:
            m_top, i_top = scene.m_o, _box_inertia(scene.m_o, geom.side, geom.side, t_pl)
            c_top, V_top = [0.0, 0.0, 0.5 * t_pl], np.eye(3)
        top = plate_body("top", m_top, i_top, c_top, V_top, (ux, 0.0, top_z + uz))
        world.call("changeDynamics", top, -1, mass=m_top,    # mass again: without it a maximal-coordinate
                   localInertiaDiagonal=list(i_top),          # body gets 0
                   lateralFriction=f, restitution=0.0, linearDamping=0.0, angularDamping=0.0, collisionMargin=0.0)
        # the plates never touch (the balls keep them 2 (r - depth) apart): skip their concave-concave
        # pair, which Bullet would otherwise visit every step (measured: 0.4 ms of a 1.4 ms step)
        world.call("setCollisionFilterPair", bottom, top, -1, -1, 0)
        statue = None
        V = None
        if scene.statue is not None and not rigid:
            statue = add_statue(world, scene.statue, contact, z0=2 * t_pl + gap + uz)
            world.call("resetBasePositionAndOrientation", statue,
                       (np.array(world.call("getBasePositionAndOrientation", statue)[0]) + [ux, 0, 0]).tolist(),
                       world.call("getBasePositionAndOrientation", statue)[1])
            _, V = inertia_frame(scene.statue.inertia)
            if mount == "fixed":      # joint frame at the statue's centre of mass, both frames in place
                pt, qt = world.call("getBasePositionAndOrientation", top)
                ps, qs = world.call("getBasePositionAndOrientation", statue)
                inv_p, inv_q = world.call("invertTransform", pt, qt)
                rel_p, rel_q = world.call("multiplyTransforms", inv_p, inv_q, ps, qs)
                cid = world.call("createConstraint", top, -1, statue, -1, p.JOINT_FIXED, [0, 0, 0], rel_p,
                                 [0, 0, 0], rel_q, [0, 0, 0, 1])
                world.call("changeConstraint", cid, maxForce=1e3 * scene.statue.mass * settings.g)
        # the plate's own centre (0, 0, t/2 in the plate frame) as seen from the body's inertial frame:
        # u and the plate acceleration are those of this point (= the centre of mass unless 'rigid')
        d_loc = np.zeros(3)
        if rigid:
            q0 = world.call("getBasePositionAndOrientation", top)
            d_loc = matrix_from_quat(q0[1]).T @ (np.array([ux, 0.0, top_z + uz + 0.5 * t_pl]) - np.array(q0[0]))

        def plate_point():
            pc, qc = world.call("getBasePositionAndOrientation", top)
            vc, wc = world.call("getBaseVelocity", top)
            if not rigid:
                return pc[0], vc[0]
            rr = matrix_from_quat(qc) @ d_loc
            return pc[0] + rr[0], vc[0] + (wc[1] * rr[2] - wc[2] * rr[1])

        x_top0 = plate_point()[0] - ux   # top plate's x at u = 0
        if u0 == 0.0 and settle > 0:
            world.set_ground_acc(0.0)
            for _ in range(math.ceil(settle / dt - 1e-9)):
                world.step()
        ts, us, aa, th = [], [], [], []
        v_prev = plate_point()[1]
        ball_r = 0.0
        left = overturned = False
        finite = True
        steps = 0
        a_abs_max = 0.0
        u_max = 0.0
        af = []
        cap = scene.travel_capacity
        t_cap = u_cap = t_ot = None
        for k in range(n + 1):
            xp, vx = plate_point()
            u = xp - x_top0
            if not (math.isfinite(u) and math.isfinite(vx)):
                finite = False
                break
            a_rel = (vx - v_prev) / dt if k > 0 else 0.0
            v_prev = vx
            a_abs = acc_g[k - 1] + a_rel if k > 0 else 0.0
            a_abs_max = max(a_abs_max, abs(a_abs))
            af.append(a_abs)
            u_max = max(u_max, abs(u))
            hit = t_cap is None and abs(u) > cap
            if hit:
                t_cap, u_cap = k * dt, u
                notes.append(f"the plate passed the capacity {cap * 1000:.1f} mm at t = {k * dt:.4f} s "
                             f"(u = {u * 1000:.1f} mm)")
            theta = None
            if statue is not None:
                _, orn = world.call("getBasePositionAndOrientation", statue)
                Rm = matrix_from_quat(orn) @ V.T
                theta = math.atan2(Rm[0, 2], Rm[2, 2])
                d = scene.statue.params.delta_R if theta > 0 else scene.statue.params.delta_L
                if abs(theta) >= d:
                    overturned = True
                    t_ot = k * dt
            if k % every == 0 or (hit and stop_at_capacity):
                for b, (cx, cy) in zip(balls, centres):
                    bp = world.call("getBasePositionAndOrientation", b)[0]
                    rho = math.hypot(bp[0] - cx, bp[1] - cy)
                    ball_r = max(ball_r, rho)
                    if rho > a_open or bp[2] < t_pl - depth:     # over the rim, or fell out
                        left = True
                ts.append(k * dt)
                us.append(u)
                aa.append(a_abs)
                th.append(np.nan if theta is None else theta)
            if left or overturned or k == n or (hit and stop_at_capacity):
                if left:
                    notes.append(f"a ball left its groove at t = {k * dt:.3f} s")
                if overturned:
                    notes.append(f"the statue overturned at t = {k * dt:.3f} s")
                break
            world.set_ground_acc(acc_g[k])
            world.step()
            steps += 1
    wall = time.perf_counter() - t0
    t_arr, u_arr = np.asarray(ts), np.asarray(us)
    pk_t, pk_u = _peaks(t_arr, u_arr)
    return Isolator3DResult(
        scene=scene, settings=settings, t=t_arr, u=u_arr, acc_abs=np.asarray(aa),
        theta=np.asarray(th) if statue is not None else None, peaks_t=pk_t, peaks_u=pk_u,
        ball_r_max=ball_r, u_max=u_max, acc_abs_max=a_abs_max, pga=motion.pga, statue_overturned=overturned,
        ball_left_groove=left, finite=finite, wall_time=wall, steps=steps, notes=tuple(notes),
        acc_step=np.asarray(af), capacity=cap, t_capacity=t_cap, u_at_capacity=u_cap, t_overturn=t_ot)


def _peaks(t: np.ndarray, u: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Extrema of u (sign changes of the sampled velocity), parabola-refined."""
    if u.size < 3:
        return np.array([]), np.array([])
    du = np.diff(u)
    idx = [i for i in range(1, u.size - 1) if du[i - 1] * du[i] < 0 or (du[i - 1] != 0 and du[i] == 0)]
    pt, pu = [], []
    for i in idx:
        y0, y1, y2 = u[i - 1], u[i], u[i + 1]
        den = y0 - 2 * y1 + y2
        x = 0.5 * (y0 - y2) / den if den != 0 else 0.0
        x = max(-1.0, min(1.0, x))
        pt.append(t[i] + x * (t[i + 1] - t[i]))
        pu.append(y1 - 0.25 * (y0 - y2) * x)
    return np.asarray(pt), np.asarray(pu)
