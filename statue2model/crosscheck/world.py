"""A PyBullet world in DIRECT mode, and the ground motion applied as a gravity tilt.

Ground motion (why a gravity tilt is exact). Every scene here has a rigid ground
(the floor, or the isolator's bottom plate) that translates with the prescribed
acceleration u_g''(t) along +x. Written in the ground's own frame, which
translates without rotating, Newton's law of every body gains the inertial
force -m u_g''(t) x, i.e. gravity becomes (-u_g''(t), 0, -g). Contacts,
friction and restitution depend only on relative velocities, which are the same
in both frames. So the motion *relative to the ground* is identical, with no
table body, no kinematic driving and no integration of u_g'' into a displacement
(which would add drift). The engine advances velocities with the force of the
step, so the step's gravity uses the mean of u_g'' over the step (Simpson's rule
on t, t + dt/2, t + dt): the ground-velocity change per step is then exact for a
motion polynomial of degree <= 3 between steps. ``tests/test_crosscheck.py``
checks this against a driven heavy table.

Units: SI (m, s, kg, m/s^2).

Example
-------
>>> from statue2model.crosscheck.world import SimSettings, World
>>> with World(SimSettings(dt=1e-3)) as w:
...     w.set_ground_acc(0.0, 0.0)
...     w.client >= 0
True
"""
from __future__ import annotations

import math
import os
import sys
import threading
import time
from dataclasses import asdict, dataclass
from typing import TYPE_CHECKING

import numpy as np

from ..errors import InputError, missing_extra

if TYPE_CHECKING:
    from typing_extensions import Self

from ..quantities import G  # m/s^2


def check_user_dt(name: str, dt: float) -> float:
    """``dt`` (s) if it is a time step a user may ask of a cross-check scene (1e-5..5e-3 s: --dt,
    --statue-dt, [crosscheck] dt and statue_dt), else an InputError naming ``name``.

    >>> check_user_dt("--dt", 0.01)
    Traceback (most recent call last):
    ...
    statue2model.errors.InputError: --dt must be in 1e-5..5e-3 s, got 0.01
    """
    if not 1e-5 <= dt <= 5e-3:
        raise InputError(f"{name} must be in 1e-5..5e-3 s, got {dt}")
    return dt


def import_pybullet():
    """The ``pybullet`` module, imported without its build banner ("pybullet build time: ...").

    The C extension prints the banner at import, below Python (printf/fprintf: to fd 1 in
    some builds, fd 2 in others), so ``contextlib.redirect_stdout`` cannot catch it: fds 1
    and 2 point at /dev/null around the first import (C's buffers flushed before they are
    restored). A command's stdout then holds its results only and its stderr the one error
    line. Every import of pybullet in statue2model goes through here.
    """
    if "pybullet" in sys.modules:
        return sys.modules["pybullet"]
    for stream in (sys.stdout, sys.stderr):
        try:
            stream.flush()
        except (AttributeError, OSError, ValueError):
            pass
    try:
        saved = [os.dup(1), os.dup(2)]
    except OSError:                    # no fd 1 or 2 to guard: nothing to keep clean
        return _import()
    try:
        null = os.open(os.devnull, os.O_WRONLY)
        try:
            os.dup2(null, 1)
            os.dup2(null, 2)
            pybullet = _import()
        finally:
            _flush_c_stdio()
            os.close(null)
    finally:
        os.dup2(saved[0], 1)
        os.dup2(saved[1], 2)
        os.close(saved[0])
        os.close(saved[1])
    return pybullet


def _import():
    try:
        import pybullet
    except ImportError as exc:
        raise missing_extra("physics", "the 3D cross-check", exc) from None
    return pybullet


def _flush_c_stdio() -> None:
    """fflush(NULL): C's stdout is fully buffered on a pipe; flushed now, the banner goes to /dev/null."""
    try:
        import ctypes

        ctypes.CDLL(None).fflush(None)
    except (OSError, AttributeError):
        pass


def run_clock() -> float:
    """The process CPU time, s, at the start of a scene's run, once the process's one-time costs are paid
    (importing PyBullet, loading the compiled ground motion: a run's real-time factor counts its own
    work - set-up, steps, histories - not the first run's imports)."""
    import_pybullet()
    from ..compute.compile import ensure_compiled

    ensure_compiled()
    return time.process_time()


def real_time_factor(steps: int, dt: float, wall_time: float) -> float:
    """Simulated seconds per wall-clock second of a run of ``steps`` steps of ``dt`` s."""
    return steps * dt / wall_time if wall_time > 0 else float("inf")


@dataclass(frozen=True)
class SimSettings:
    """Engine settings of one run (SI units).

    dt                 : fixed time step, s (PyBullet's default 1/240 s is far too coarse for impacts)
    solver_iterations  : sequential-impulse iterations per step (numSolverIterations)
    erp, contact_erp   : error reduction of joints / contacts (penetration recovery per step)
    split_impulse      : separate penetration recovery from the velocity solve (no energy added)
    restitution_threshold : restitutionVelocityThreshold, m/s (restitution is applied only above it)
    maximal_coordinates : rigid bodies (btRigidBody) instead of one-link multibodies
    g                  : gravity, m/s^2
    """

    dt: float = 1.0 / 2000.0
    solver_iterations: int = 50
    erp: float = 0.2
    contact_erp: float = 0.2
    split_impulse: bool = True
    restitution_threshold: float = 0.0
    maximal_coordinates: bool = False
    floor: str = "box"
    sat: bool = False
    g: float = G

    def __post_init__(self):
        if not (isinstance(self.dt, (int, float)) and math.isfinite(self.dt) and 1e-6 <= self.dt <= 0.05):
            raise InputError(f"time step dt must be in [1e-6, 0.05] s, got {self.dt!r}")
        if not (isinstance(self.solver_iterations, int) and 1 <= self.solver_iterations <= 10_000):
            raise InputError(f"solver iterations must be an integer in [1, 10000], got {self.solver_iterations!r}")
        for name in ("erp", "contact_erp"):
            v = getattr(self, name)
            if not (math.isfinite(v) and 0 <= v <= 1):
                raise InputError(f"{name} must be in [0, 1], got {v!r}")
        if not (math.isfinite(self.restitution_threshold) and self.restitution_threshold >= 0):
            raise InputError(f"restitution threshold must be >= 0 m/s, got {self.restitution_threshold!r}")
        if not (math.isfinite(self.g) and self.g > 0):
            raise InputError(f"g must be positive, got {self.g!r}")

    def to_dict(self) -> dict:
        return asdict(self)


class World:
    """One DIRECT PyBullet client (no GUI, no rendering), emptied on exit.

    Connecting a client costs ~13 ms of CPU (a 3 s statue run at 50 x real time has 60 ms): with
    ``reuse`` (default) a closed World's client is emptied (resetSimulation, ~1 ms) and kept, at
    most MAX_IDLE_CLIENTS per process, for the next World of the same process, which sets every
    engine parameter again. Runs are bit-identical to runs on a fresh client
    (tests/test_crosscheck_speed.py); ``reuse=False`` connects and disconnects.

    ``set_ground_acc(a0, a1)`` sets gravity to (-a, 0, -g) with a the ground
    acceleration (m/s^2, along +x) averaged over the coming step; ``step()``
    advances one ``settings.dt``.
    """

    def __init__(self, settings: SimSettings | None = None, reuse: bool = True):
        self.settings = SimSettings() if settings is None else settings
        self.reuse = reuse
        self.client = -1
        self.p = None

    def __enter__(self) -> Self:
        pybullet = import_pybullet()

        self.p = pybullet
        self.client = _idle_client(pybullet) if self.reuse else -1
        if self.client < 0:
            self.client = pybullet.connect(pybullet.DIRECT)
        if self.client < 0:
            raise RuntimeError("could not start a PyBullet DIRECT client")
        s = self.settings
        pybullet.setPhysicsEngineParameter(
            fixedTimeStep=s.dt, numSubSteps=0, numSolverIterations=s.solver_iterations, erp=s.erp,
            contactERP=s.contact_erp, frictionERP=s.erp, useSplitImpulse=int(s.split_impulse),
            restitutionVelocityThreshold=s.restitution_threshold, deterministicOverlappingPairs=1,
            enableSAT=int(s.sat),
            physicsClientId=self.client)
        pybullet.setGravity(0.0, 0.0, -s.g, physicsClientId=self.client)
        return self

    def __exit__(self, *exc) -> None:
        if self.client >= 0:
            if not (self.reuse and _park_client(self.p, self.client)):
                self.p.disconnect(physicsClientId=self.client)
            self.client = -1

    # -- helpers bound to this client -------------------------------------------
    def call(self, name: str, *args, **kw):
        """pybullet.<name>(*args, **kw) on this client."""
        return getattr(self.p, name)(*args, physicsClientId=self.client, **kw)

    def set_ground_acc(self, acc: float, lateral: float = 0.0) -> None:
        """Gravity (-acc, -lateral, -g): the ground accelerates by (acc, lateral) m/s^2."""
        self.p.setGravity(-float(acc), -float(lateral), -self.settings.g, physicsClientId=self.client)

    def step(self) -> None:
        self.p.stepSimulation(physicsClientId=self.client)

    def plane(self, friction: float, restitution: float = 0.0) -> int:
        """The rigid floor z = 0: a static plane, or a large thin box (settings.floor == "box")."""
        if self.settings.floor == "box":
            shape = self.call("createCollisionShape", self.p.GEOM_BOX, halfExtents=[20.0, 20.0, 0.1])
            body = self.call("createMultiBody", 0.0, shape, basePosition=[0.0, 0.0, -0.1])
        else:
            shape = self.call("createCollisionShape", self.p.GEOM_PLANE)
            body = self.call("createMultiBody", 0.0, shape)
        self.call("changeDynamics", body, -1, lateralFriction=friction, restitution=restitution,
                  rollingFriction=0.0, spinningFriction=0.0)
        return body


MAX_IDLE_CLIENTS = 2
"""Emptied PyBullet clients a process keeps for the next World (World.reuse)."""
_IDLE: list[tuple[int, int]] = []      # (process id, client id): clients are not shared across a fork
_IDLE_LOCK = threading.Lock()


def _idle_client(pybullet) -> int:
    """A kept, emptied client of this process (World.reuse), or -1."""
    with _IDLE_LOCK:
        while _IDLE:
            pid, client = _IDLE.pop()
            if pid == os.getpid() and pybullet.isConnected(physicsClientId=client):
                return client
    return -1


def _park_client(pybullet, client: int) -> bool:
    """Empty ``client`` and keep it for the next World; False (not kept) when the pool is full."""
    with _IDLE_LOCK:
        if len(_IDLE) >= MAX_IDLE_CLIENTS:
            return False
        pybullet.resetSimulation(physicsClientId=client)
        _IDLE.append((os.getpid(), client))
    return True


def step_grid(t_end: float, dt_out: float, dt: float) -> tuple[int, int]:
    """(n, every) of a scene run to ``t_end`` s at steps of ``dt`` s, its output every ``dt_out`` s: n steps,
    a sample every ``every`` of them; an InputError for a ``t_end`` or ``dt_out`` that is not a positive
    finite number of seconds."""
    if not (isinstance(t_end, (int, float)) and math.isfinite(t_end) and t_end > 0):
        raise InputError(f"t_end must be positive, got {t_end}")
    if not (math.isfinite(dt_out) and dt_out > 0):
        raise InputError(f"dt_out must be positive, got {dt_out}")
    return math.ceil(t_end / dt - 1e-9), max(1, round(dt_out / dt))


def step_mean_acc(motion, t0: float, dt: float, n: int) -> np.ndarray:
    """Mean ground acceleration over each of the n steps [t0 + k dt, t0 + (k+1) dt]
    (Simpson's rule; m/s^2). Zero once the motion has ended."""
    t = t0 + dt * np.arange(n)
    out = np.zeros(n)
    if motion.kind == "none":
        return out
    # u_g'' is exactly 0 from motion.end on: only the steps that start before it are evaluated
    # (motion.acc costs ~1.5 us a point; a 5 s free tail would dominate a statue run)
    live = t < motion.end
    tl = t[live]
    a0 = motion.acc(tl)
    am = motion.acc(tl + 0.5 * dt)
    inside = tl + dt <= motion.end
    a1 = np.empty_like(tl)
    a1[inside] = motion.acc(np.minimum(tl[inside] + dt, motion.end) - 1e-12 * dt)
    a1[~inside] = motion.acc(tl[~inside] + dt)
    out[live] = (a0 + 4.0 * am + a1) / 6.0
    return out


def quat_from_matrix(R: np.ndarray) -> list[float]:
    """PyBullet quaternion (x, y, z, w) of a proper rotation matrix."""
    from scipy.spatial.transform import Rotation

    return Rotation.from_matrix(np.asarray(R, dtype=float)).as_quat().tolist()


def matrix_from_quat(q) -> np.ndarray:
    """Rotation matrix (3, 3) of a PyBullet quaternion (x, y, z, w), normalised first.

    Plain arithmetic (called every engine step: scipy's Rotation costs ~75 us a call, this ~3 us).

    >>> bool(np.allclose(matrix_from_quat(quat_from_matrix(np.diag([1.0, -1.0, -1.0]))), np.diag([1, -1, -1])))
    True
    """
    x, y, z, w = (float(c) for c in q)
    n = x * x + y * y + z * z + w * w
    s = 2.0 / n if n > 0 else 0.0
    return np.array([[1.0 - s * (y * y + z * z), s * (x * y - z * w), s * (x * z + y * w)],
                     [s * (x * y + z * w), 1.0 - s * (x * x + z * z), s * (y * z - x * w)],
                     [s * (x * z - y * w), s * (y * z + x * w), 1.0 - s * (x * x + y * y)]])


def matrices_from_quats(Q: np.ndarray) -> np.ndarray:
    """Rotation matrices (m, 3, 3) of PyBullet quaternions ``Q`` (m, 4: x, y, z, w), normalised:
    :func:`matrix_from_quat` over many poses at once (the per-step one stays scalar: faster alone).

    >>> Q = np.array([[0.0, 0.0, 0.0, 1.0], [0.1, -0.3, 0.2, 0.9]])
    >>> bool(np.allclose(matrices_from_quats(Q), [matrix_from_quat(q) for q in Q]))
    True
    """
    x, y, z, w = Q.T
    nq = x * x + y * y + z * z + w * w
    with np.errstate(divide="ignore", invalid="ignore"):
        s = np.where(nq > 0, 2.0 / nq, 0.0)
    return np.stack([np.stack([1.0 - s * (y * y + z * z), s * (x * y - z * w), s * (x * z + y * w)], -1),
                     np.stack([s * (x * y + z * w), 1.0 - s * (x * x + z * z), s * (y * z - x * w)], -1),
                     np.stack([s * (x * z - y * w), s * (y * z + x * w), 1.0 - s * (x * x + y * y)], -1)], -2)
