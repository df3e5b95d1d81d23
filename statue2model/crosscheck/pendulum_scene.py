"""Scene (b'): the rolling-ball isolator by its exact kinematics - a translating spherical pendulum.

With rolling without slip (MODEL.md sec. 4, "Exact kinematics") the top plate does not rotate:
it translates on a sphere of radius R_hat = 2 (R - r) about a pivot R_hat above its rest
position, u = R_hat sin(phi) horizontally and z = R_hat (1 - cos phi) up. The balls and the
grooves are not modelled; the plate is one PyBullet multibody link (a box ``side`` x ``side`` x
``thickness``, upper face at z = thickness at rest, mass m_o) on three prismatic joints x, y, z
from a fixed base (two massless-ish carriages of EPS_MASS x m_o each between them):

* level and translating EXACTLY: prismatic joints cannot rotate the plate;
* the rise z(u) = R_hat - sqrt(R_hat^2 - |u|^2) (= R_hat (1 - cos phi)): a velocity motor on the
  z joint whose target is (z(u + v dt) - z) / dt, solved by the engine together with the statue's
  contacts (no force limit in practice: 1e3 x the total weight); the position follows z(u) to
  O(a dt^2) per step, corrected the next step;
* N, the ACTUAL vertical load on the balls, is the force of that z motor (the constraint force:
  the statue's contact forces on the plate + m_o (g + z'')), read after every step;
* the sphere's horizontal reaction -N u / sqrt(R_hat^2 - |u|^2) (the normal force's horizontal
  part for a vertical part N), an external force on the plate with the previous step's N;
* the rolling resistance mu N opposing the horizontal velocity: velocity motors (target 0) on
  the x and y joints, limited to mu N |v_x| / |v| and mu N |v_y| / |v| (the direction of the
  step's start; at rest that of the restoring force, along x at the centre), so sticking is exact
  along that direction (no sign chatter); a force across it at rest meets no resistance (the
  ground motion is along x: only the statue's small y reactions act across it);
* the capacity: the run ends where |u| passes ``capacity`` (outcome "isolator capacity exceeded").

The statue (scene (a)'s hull, statue_scene.add_statue) stands on the plate's upper face with real
contacts, solved in the same solve as the plate's joints (no added-mass lag: an explicit split with
a kinematically driven plate would be unstable for a statue heavier than the plate, m / m_o ~ 25).
The one lag: the horizontal reaction and the friction limit use N of the previous step (relative
error |N_k - N_{k-1}| / N a step: ~1e-5 in free vibration; at a statue impact up to the impact's
jump in N for one step). The ground motion is world.py's gravity tilt; u is relative to the ground.

Units: SI (m, s, kg, N).

Example
-------
>>> from statue2model.crosscheck.pendulum_scene import PendulumIsolator
>>> iso = PendulumIsolator(R_hat=0.581, mu=0.0, m_o=50.0)
>>> round(iso.period, 3)
1.529
"""
from __future__ import annotations

import math
import time
from dataclasses import asdict, dataclass, field, replace

import numpy as np

from ..errors import InputError
from .contact import ContactSettings
from .isolator_scene import PlateRun, _box_inertia, _peaks
from .statue_scene import STATUE_SETTINGS, StatueScene, add_statue, inertia_frame
from .world import run_clock, SimSettings, World, step_mean_acc

EPS_MASS = 1e-6
"""Mass of each of the two carriages (x, y joints) per kg of plate: adds 2e-6 to the horizontal inertia."""
Z_MOTOR_FORCE = 1e3
"""Force limit of the z motor per N of total weight (never reached: the rise is a hard constraint)."""


@dataclass(frozen=True)
class PendulumIsolator:
    """The isolator as a translating spherical pendulum (SI units).

    R_hat     : pendulum length 2 (R - r), m
    mu        : rolling resistance coefficient (force mu N against the plate's velocity)
    m_o       : top plate mass, kg
    capacity  : largest |u| (m); None: unlimited
    side, thickness : the top plate's square side and thickness, m (the statue stands on its upper face)
    r         : ball radius, m (names the device: R = R_hat / 2 + r; the kinematics depend on R_hat alone)
    statue    : the StatueScene standing on the plate, or None (the plate alone)
    """

    R_hat: float
    mu: float
    m_o: float
    capacity: float | None = None
    side: float = 1.0
    thickness: float = 0.03
    r: float = 0.0095
    statue: StatueScene | None = field(default=None, compare=False, repr=False)

    def __post_init__(self):
        if not (math.isfinite(self.R_hat) and 0.01 <= self.R_hat <= 100):
            raise InputError(f"R_hat must be in 0.01..100 m, got {self.R_hat!r}")
        if not (math.isfinite(self.mu) and 0 <= self.mu < 1):
            raise InputError(f"rolling friction mu must be in [0, 1), got {self.mu!r}")
        if not (math.isfinite(self.m_o) and self.m_o > 0):
            raise InputError(f"top plate mass must be positive, got {self.m_o!r}")
        if self.capacity is not None and not (math.isfinite(self.capacity) and 0 < self.capacity < self.R_hat):
            raise InputError(f"isolator capacity must be in (0, R_hat) m, got {self.capacity!r}")
        for name in ("side", "thickness"):
            v = getattr(self, name)
            if not (math.isfinite(v) and 1e-3 <= v <= 20):
                raise InputError(f"plate {name} must be in 1 mm..20 m, got {v!r}")
        if not (math.isfinite(self.r) and 0 < self.r < 1):
            raise InputError(f"ball radius r must be in (0, 1) m, got {self.r!r}")

    @property
    def R(self) -> float:
        """Groove radius R = R_hat / 2 + r, m."""
        return self.R_hat / 2 + self.r

    @property
    def M(self) -> float:
        """Supported mass: top plate + statue (kg)."""
        return self.m_o + (self.statue.mass if self.statue is not None else 0.0)

    @property
    def period(self) -> float:
        """Small-amplitude period 2 pi sqrt(R_hat / g), s."""
        from ..quantities import G

        return 2 * math.pi * math.sqrt(self.R_hat / G)

    @property
    def travel_capacity(self) -> float:
        return math.inf if self.capacity is None else float(self.capacity)

    def rise(self, u) -> np.ndarray:
        """Rise of the plate at horizontal displacement |u| (m): R_hat - sqrt(R_hat^2 - u^2) = R_hat (1 - cos phi)."""
        u = np.asarray(u, dtype=float)
        return self.R_hat - np.sqrt(np.maximum(self.R_hat**2 - u * u, 0.0))

    @classmethod
    def from_design(cls, design: dict, statue: StatueScene | None = None) -> PendulumIsolator:
        """From the JSON of ``statue2model isolator design`` (a dict): R, r, mu, m_o (or M), capacity
        (or d_max), side, thickness; ``statue`` stands on it."""
        try:
            R, r = float(design["R"]), float(design["r"])
            if "m_o" in design:
                m_o = float(design["m_o"])
            else:           # M is the supported mass: the plate is what the statue does not weigh
                m_o = float(design["M"]) - (statue.mass if statue is not None else 0.0)
                if not m_o > 0:
                    raise ValueError(f"M = {design['M']} kg leaves no plate mass under the {statue.mass:.1f} kg statue")
            cap = design.get("capacity")
            cap = design.get("d_max") if cap is None else cap
            return cls(R_hat=2.0 * (R - r), mu=float(design["mu"]), m_o=m_o,
                       capacity=None if cap is None else float(cap),
                       side=float(design.get("side", 1.0)), thickness=float(design.get("thickness", 0.03)),
                       r=r, statue=statue)
        except (KeyError, TypeError, ValueError) as exc:
            raise InputError(f"not an isolator design ({exc})") from None

    def to_dict(self) -> dict:
        """The parameters (the statue by its mass)."""
        d = {k: v for k, v in asdict(replace(self, statue=None)).items() if k != "statue"}
        return d | {"model": "pendulum", "R": self.R, "statue_mass": None if self.statue is None else self.statue.mass}


@dataclass(frozen=True, eq=False)
class PendulumResult(PlateRun):
    """A run of the pendulum scene; the fields of isolator_scene.Isolator3DResult where they apply.

    t, u, acc_abs : top plate displacement relative to the ground (x, m) and absolute acceleration
                    (x, m/s^2), every dt_out
    uy, z, N      : the plate's y displacement and rise (m) and the vertical load N (N), every dt_out
    theta         : the statue's rotation (rad) every dt_out, if a statue rides on the plate
    acc_step      : absolute plate acceleration (x) of every engine step, for filtering
    tilt_max      : largest rotation of the plate seen (rad; 0 by construction)
    uplift_time, max_lift, max_pivot_slip, yaw_max, theta_max_L, theta_max_R : the statue on the plate,
                    read as the fixed-base scene reads them (statue_scene.Statue3DResult), relative to
                    the plate (s or None, m, m, rad, rad, rad)
    wall_time, cpu_time : s; real_time_factor is simulated s per CPU s
    """

    scene: PendulumIsolator
    settings: SimSettings
    t: np.ndarray
    u: np.ndarray
    uy: np.ndarray
    z: np.ndarray
    N: np.ndarray
    acc_abs: np.ndarray
    theta: np.ndarray | None
    peaks_t: np.ndarray
    peaks_u: np.ndarray
    u_max: float
    acc_abs_max: float
    pga: float
    statue_overturned: bool
    finite: bool
    wall_time: float
    cpu_time: float
    steps: int
    tilt_max: float = 0.0
    notes: tuple = field(default=())
    acc_step: np.ndarray | None = None
    capacity: float = math.inf
    t_capacity: float | None = None
    u_at_capacity: float | None = None
    t_overturn: float | None = None
    ball_left_groove: bool = False
    uplift_time: float | None = None
    max_lift: float = 0.0
    max_pivot_slip: float = 0.0
    yaw_max: float = 0.0
    theta_max_L: float = 0.0
    theta_max_R: float = 0.0

    @property
    def efficiency(self) -> float:
        return self.acc_abs_max / self.pga if self.pga > 0 else 0.0

    @property
    def real_time_factor(self) -> float:
        """Simulated seconds per CPU second."""
        return self.steps * self.settings.dt / self.cpu_time if self.cpu_time > 0 else 0.0

    def to_dict(self) -> dict:
        d = self._plate_dict() | {"model": "pendulum", "cpu_time_s": self.cpu_time, "tilt_max": self.tilt_max,
                                  "isolator": self.scene.to_dict()}
        if self.theta is not None:
            d |= {"uplift_time": self.uplift_time, "max_lift": self.max_lift, "max_pivot_slip": self.max_pivot_slip,
                  "yaw_max": self.yaw_max, "theta_max_L": self.theta_max_L, "theta_max_R": self.theta_max_R}
        return d


TILT_EVERY = 50
"""Steps between two reads of the plate's tilt (PendulumResult.tilt_max; and at the last step): on its
three prismatic joints the plate cannot rotate, the read is a check (0.0 in every run measured)."""


def simulate_pendulum(scene: PendulumIsolator, motion, statue: StatueScene | None = None,
                      settings: SimSettings | None = None, *, u0: float = 0.0, t_end: float | None = None,
                      contact: ContactSettings | None = None, dt_out: float = 0.005, free_time: float = 10.0,
                      stop_at_capacity: bool = True, mount: str = "contact") -> PendulumResult:
    """Run the pendulum scene under ``motion`` (GroundMotion along +x): the plate released from rest
    at u = u0 (m, along x, on its sphere), with ``statue`` (StatueScene) standing free on it or None.
    ``mount='rigid'``: the statue is fixed to the plate (its mass joins the plate link's: what the 2D
    plate model assumes; no rotation is then followed).
    Stops where |u| passes the capacity (``stop_at_capacity``), the statue overturns or the state
    stops being finite. ``t_end`` (s): default motion.end + free_time. ``settings``: default
    statue_scene.STATUE_SETTINGS (dt 2 ms: ~40 x real time with the default scan's statue, 140 x alone).

    >>> from statue2model.hazard.motions import free
    >>> r = simulate_pendulum(PendulumIsolator(R_hat=0.6, mu=0.0, m_o=50.0), free(), u0=0.05, t_end=0.2)
    >>> r.outcome, bool(abs(r.u[-1] - 0.05 * math.cos(0.2 * math.sqrt(9.80665 / 0.6))) < 3e-4)  # dt 2 ms
    ('ok', True)
    """
    c0 = run_clock()
    contact = ContactSettings() if contact is None else contact
    settings = STATUE_SETTINGS if settings is None else settings
    if mount not in ("contact", "rigid"):
        raise InputError(f"mount must be 'contact' or 'rigid', got {mount!r}")
    m_plate = scene.m_o
    if mount == "rigid" and statue is not None:
        m_plate, statue = scene.m_o + statue.mass, None
    Rh, t_pl = scene.R_hat, scene.thickness
    cap = scene.travel_capacity
    if not (math.isfinite(u0) and abs(u0) < min(cap, 0.99 * Rh)):
        raise InputError(f"u0 = {u0} m must be finite and within the capacity {cap} m")
    if t_end is None:
        t_end = motion.end + free_time
    if not (math.isfinite(t_end) and t_end > 0):
        raise InputError(f"t_end must be positive, got {t_end}")
    dt = settings.dt
    n = math.ceil(t_end / dt - 1e-9)
    every = max(1, round(dt_out / dt))
    acc_g = step_mean_acc(motion, 0.0, dt, n + 1)
    g = settings.g
    m_tot = m_plate + (statue.mass if statue is not None else 0.0)
    notes = []
    acc_l = acc_g.tolist()                  # Python floats: the step loop's arithmetic
    t0 = time.perf_counter()
    with World(settings) as world:
        p = world.p
        box = world.call("createCollisionShape", p.GEOM_BOX,
                         halfExtents=[scene.side / 2, scene.side / 2, t_pl / 2])
        eps = EPS_MASS * m_plate
        zero, ident = [0.0, 0.0, 0.0], [0.0, 0.0, 0.0, 1.0]
        plate = world.call(
            "createMultiBody", 0.0, -1, -1, [0.0, 0.0, 0.0], ident,
            linkMasses=[eps, eps, m_plate], linkCollisionShapeIndices=[-1, -1, box],
            linkVisualShapeIndices=[-1, -1, -1], linkPositions=[zero, zero, [0.0, 0.0, t_pl / 2]],
            linkOrientations=[ident] * 3, linkInertialFramePositions=[zero] * 3,
            linkInertialFrameOrientations=[ident] * 3, linkParentIndices=[0, 1, 2],
            linkJointTypes=[p.JOINT_PRISMATIC] * 3, linkJointAxis=[[1.0, 0, 0], [0, 1.0, 0], [0, 0, 1.0]],
            useMaximalCoordinates=0)
        for j in range(3):
            world.call("changeDynamics", plate, j, linearDamping=0.0, angularDamping=0.0, jointDamping=0.0,
                       lateralFriction=contact.friction, restitution=0.0, rollingFriction=0.0,
                       spinningFriction=0.0)
        world.call("changeDynamics", plate, 2, mass=m_plate,
                   localInertiaDiagonal=_box_inertia(m_plate, scene.side, scene.side, t_pl))
        world.call("changeDynamics", plate, -1, linearDamping=0.0, angularDamping=0.0)
        z_0 = float(scene.rise(u0))
        world.call("resetJointState", plate, 0, u0, 0.0)
        world.call("resetJointState", plate, 2, z_0, 0.0)
        body = theta = None
        V = None
        if statue is not None:
            body = add_statue(world, statue, contact, z0=t_pl + z_0, collision="patch")
            pos, orn = world.call("getBasePositionAndOrientation", body)
            world.call("resetBasePositionAndOrientation", body, [pos[0] + u0, pos[1], pos[2]], orn)
            _, V = inertia_frame(statue.inertia)
            v_up = tuple(float(c) for c in V[2, :])
        f_z = Z_MOTOR_FORCE * m_tot * g
        joints = [0, 1, 2]
        ctrl = p.VELOCITY_CONTROL
        N = m_tot * g                      # vertical load of the previous step (first: the weight)
        ts, us, uys, zs, Ns, aa, th = [], [], [], [], [], [], []
        af, P, Q = [], [], []
        finite = True
        overturned = False
        steps = 0
        a_abs_max = u_max = tilt_max = 0.0
        t_cap = u_cap = t_ot = None
        v_prev = 0.0
        get_states, set_motors, apply_force = p.getJointStates, p.setJointMotorControlArray, p.applyExternalForce
        get_pose, get_link = p.getBasePositionAndOrientation, p.getLinkState
        d_R, d_L = (statue.params.delta_R, statue.params.delta_L) if statue is not None else (0.0, 0.0)
        step, gravity, world_frame = p.stepSimulation, p.setGravity, p.WORLD_FRAME
        cid = world.client
        a_set = None
        for k in range(n + 1):
            (x, vx, _, _), (y, vy, _, _), (z, vz, _, fz) = get_states(plate, joints, physicsClientId=cid)
            if k > 0:
                N = fz
            if not (math.isfinite(x) and math.isfinite(vx) and math.isfinite(y) and math.isfinite(N)):
                finite = False
                break
            a_abs = acc_l[k - 1] + (vx - v_prev) / dt if k > 0 else 0.0
            v_prev = vx
            if abs(a_abs) > a_abs_max:
                a_abs_max = abs(a_abs)
            af.append(a_abs)
            uh = math.hypot(x, y)
            if uh > u_max:
                u_max = uh
            hit = t_cap is None and uh > cap
            if hit:
                t_cap, u_cap = k * dt, x
                notes.append(f"the plate passed the capacity {cap * 1000:.1f} mm at t = {k * dt:.4f} s "
                             f"(|u| = {uh * 1000:.1f} mm)")
            if body is not None:
                pos, orn = get_pose(body, physicsClientId=cid)
                P.append((pos[0] - x, pos[1] - y, pos[2] - t_pl - z))   # relative to the plate's upper face
                Q.append(orn)
                theta = _theta_of(orn, v_up)
                if not (math.isfinite(theta) and math.isfinite(pos[0]) and math.isfinite(pos[2])):
                    finite = False
                    break
                if (theta >= d_R) if theta > 0 else (-theta >= d_L):
                    overturned = True
                    t_ot = k * dt
            if k % every == 0 or hit or overturned or k == n:
                if k % TILT_EVERY == 0 or hit or overturned or k == n:
                    q = get_link(plate, 2, physicsClientId=cid)[1]
                    tilt_max = max(tilt_max, 2.0 * math.asin(min(1.0, math.sqrt(q[0] ** 2 + q[1] ** 2 + q[2] ** 2))))
                ts.append(k * dt)
                us.append(x)
                uys.append(y)
                zs.append(z)
                Ns.append(N)
                aa.append(a_abs)
                th.append(0.0 if theta is None else theta)
            if overturned or k == n or (hit and stop_at_capacity):
                if overturned:
                    notes.append(f"the statue overturned at t = {k * dt:.3f} s")
                break
            # the sphere's horizontal reaction, with this step's N from the previous step
            s = math.sqrt(max(Rh * Rh - uh * uh, 1e-12 * Rh * Rh))
            fx, fy = -N * x / s, -N * y / s
            apply_force(plate, 2, [fx, fy, 0.0], [x, y, t_pl / 2 + z], world_frame, physicsClientId=cid)
            # rolling resistance: bounded velocity motors, isotropic along the step's direction of motion
            vh = math.hypot(vx, vy)
            if vh > 1e-9:
                cx, cy = abs(vx) / vh, abs(vy) / vh
            else:
                fh = math.hypot(fx, fy)
                cx, cy = (abs(fx) / fh, abs(fy) / fh) if fh > 0 else (1.0, 0.0)   # at the centre: along x
            fr = scene.mu * max(N, 0.0)
            xn, yn = x + vx * dt, y + vy * dt
            zt = Rh - math.sqrt(max(Rh * Rh - xn * xn - yn * yn, 0.0))
            set_motors(plate, joints, ctrl, targetVelocities=[0.0, 0.0, (zt - z) / dt],
                       forces=[fr * cx, fr * cy, f_z], physicsClientId=cid)
            if acc_l[k] != a_set:                # gravity (-a, 0, -g): World.set_ground_acc
                a_set = acc_l[k]
                gravity(-a_set, 0.0, -g, physicsClientId=cid)
            step(physicsClientId=cid)
            steps += 1
    wall = time.perf_counter() - t0
    t_arr, u_arr = np.asarray(ts), np.asarray(us)
    pk_t, pk_u = _peaks(t_arr, u_arr)
    rocking = {}
    if body is not None and P:
        rocking = _statue_on_plate(statue, V, np.asarray(P, dtype=float), np.asarray(Q, dtype=float), dt)
    cpu = time.process_time() - c0             # the whole call: set-up, steps and the statue's histories
    return PendulumResult(
        scene=scene, settings=settings, t=t_arr, u=u_arr, uy=np.asarray(uys), z=np.asarray(zs), N=np.asarray(Ns),
        acc_abs=np.asarray(aa), theta=np.asarray(th) if statue is not None else None, peaks_t=pk_t, peaks_u=pk_u,
        u_max=u_max, acc_abs_max=a_abs_max, pga=motion.pga, statue_overturned=overturned, finite=finite,
        wall_time=wall, cpu_time=cpu, steps=steps, tilt_max=tilt_max, notes=tuple(notes), acc_step=np.asarray(af),
        capacity=cap, t_capacity=t_cap, u_at_capacity=u_cap, t_overturn=t_ot, **rocking)


def _theta_of(q, v: tuple) -> float:
    """The statue's rotation theta (rad) from its PyBullet quaternion q (x, y, z, w): atan2 of the (0, 2)
    and (2, 2) entries of R(q) V^T, V's third row ``v`` (statue_scene._theta, in plain arithmetic: every step).

    >>> round(_theta_of((0.0, math.sin(0.05), 0.0, math.cos(0.05)), (0.0, 0.0, 1.0)), 12)
    0.1
    """
    x, y, z, w = q
    n = x * x + y * y + z * z + w * w
    s = 2.0 / n if n > 0 else 0.0
    r02 = (1.0 - s * (y * y + z * z)) * v[0] + s * (x * y - z * w) * v[1] + s * (x * z + y * w) * v[2]
    r22 = s * (x * z - y * w) * v[0] + s * (y * z + x * w) * v[1] + (1.0 - s * (x * x + y * y)) * v[2]
    return math.atan2(r02, r22)


def _statue_on_plate(statue: StatueScene, V: np.ndarray, P: np.ndarray, Q: np.ndarray, dt: float) -> dict:
    """The statue's lift-off, slip and yaw relative to the plate, read from its per-step poses P (m, 3)
    (relative to the plate's upper face: the plate translates without rotating) and Q (m, 4) exactly as
    the fixed-base scene reads them (statue_scene: geometric lift-off at LIFT_HEIGHT for LIFT_STEPS
    steps, pivot slip from touch-down)."""
    from .statue_scene import _histories, _lift_off_time, base_vertices

    base_v, piv = base_vertices(statue)
    ok = np.isfinite(P).all(axis=1) & np.isfinite(Q).all(axis=1)
    m = int(np.argmin(ok)) if not ok.all() else len(P)
    h = _histories(P[:m], Q[:m], statue, V, statue.hull - statue.com, base_v, piv, dt)
    th = h["theta"]
    return {"uplift_time": _lift_off_time(h["lift"], dt),
            "max_lift": max(0.0, h["lift_max"]), "max_pivot_slip": float(h["slip"]),
            "yaw_max": float(np.abs(h["yaw"]).max(initial=0.0)),
            "theta_max_L": float(np.abs(th[th <= 0]).max(initial=0.0)),
            "theta_max_R": float(th[th > 0].max(initial=0.0))}
