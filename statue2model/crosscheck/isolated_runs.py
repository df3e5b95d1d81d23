"""The runs of the isolated classification: the statue on the isolator, 2D and 3D, as yes/no outcomes.

:func:`statue2model.crosscheck.classification.classify_ensemble` scores the 2D model against the 3D
scene per limit state over a record set; on a fixed base it runs the rocking model and the statue
scene. On the isolator it takes the two runners of this module (``base="isolated"``):

* 2D (:class:`Coupled2D`, called as run_2d(model, motion, free_time)): the coupled model, plate +
  rocking statue (statue2model.isolator.coupled.simulate_coupled: the 2D model as the user runs it),
  on the 2D device (isolator.device.Isolator with the design's R, r, M, mu and capacity);
* 3D (:func:`outcome_3d_isolated`, task = (PendulumIsolator with its statue, motion, settings,
  contact, free_time)): the exact-kinematics scene (crosscheck.pendulum_scene: the top plate as a
  translating spherical pendulum, rolling resistance mu N, the statue standing on it with real
  contacts).

Both read the same three outcomes (MODEL.md section 8): **uplift** (3D: the statue's highest base
point LIFT_HEIGHT above the plate for LIFT_STEPS steps, as on the fixed base; 2D: max |theta| at that
height, statue_cases.lift_angle), **overturning** (|theta| reached delta) and **capacity** (|u| passed
the device's capacity). Both runs stop where the plate passes the capacity (the 2D model does not
follow the balls out of their grooves; the 3D scene stops there too, so the two read the same
event); a run stopped there has not overturned in either model, and the capacity row counts it.

The 3D outcome carries the statue's pivot slip (per contact phase: the pendulum scene keeps no slide
history, so a standing slide on the plate is not in it) and yaw relative to the plate; the
classification's validity screen reads only those on the isolator (the 2D contact demand is the
fixed-base model's). Both outcomes carry the plate's peak absolute acceleration ``plate_acc``
(m/s^2; 3D low-passed at 20 Hz like the plate cases): what the statue feels, quoted when a run differs.

Example
-------
>>> from statue2model.crosscheck.isolated_runs import Coupled2D
>>> from statue2model.isolator.device import Isolator
>>> run = Coupled2D(Isolator(R=1.6, r=0.05, M=425.0, mu=0.0073, capacity=0.35))
>>> run.isolator.R_hat
3.1
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..isolator.coupled import simulate_coupled
from ..isolator.device import Isolator
from ..rocking.model import RockingModel
from .classification import governing_side
from .isolator_cases import isolator_2d, lowpass
from .pendulum_scene import simulate_pendulum
from .statue_cases import lift_angle

__all__ = ["Coupled2D", "isolator_2d", "outcome_3d_isolated"]


@dataclass(frozen=True)
class Coupled2D:
    """The 2D runner of the isolated classification (picklable, for the executors):
    ``Coupled2D(isolator)(model, motion, free_time)`` -> outcome dict (module docstring)."""

    isolator: Isolator

    def __call__(self, model: RockingModel, motion, free_time: float) -> dict:
        r = simulate_coupled(self.isolator, model, motion, t_end=motion.end + free_time, dt_out=0.01)
        over = bool(r.overturned)
        lifted = over or max(r.theta_max_L, r.theta_max_R) >= lift_angle(model.params)
        side = governing_side(r.theta_max_L, r.theta_max_R, model.params)
        return {"uplift": bool(lifted), "overturned": over, "capacity": bool(r.capacity_exceeded),
                "peak": math.inf if over else float(r.theta_max_over_delta), "side": side,
                "uplift_time": r.t_uplift, "overturn_side": r.overturn_side, "u_max": float(r.u_max),
                "plate_acc": float(r.acc_abs_max), "t_capacity": r.t_capacity, "finite": True}


def outcome_3d_isolated(task: tuple) -> dict:
    """One isolated 3D run (module level, for the executors): task = (scene: PendulumIsolator with its
    ``statue``, motion, settings, contact, free_time)."""
    scene, motion, settings, contact, free_time = task
    r = simulate_pendulum(scene, motion, scene.statue, settings, contact=contact,
                          t_end=motion.end + free_time, dt_out=0.01)
    p = scene.statue.params
    over = bool(r.statue_overturned)
    side = governing_side(r.theta_max_L, r.theta_max_R, p)
    peak = max(r.theta_max_L / p.delta_L, r.theta_max_R / p.delta_R)
    return {"uplift": over or r.uplift_time is not None, "overturned": over, "capacity": bool(r.capacity_exceeded),
            "peak": math.inf if over else float(peak), "side": side, "uplift_time": r.uplift_time,
            "overturn_side": None if not over else side, "max_lift": float(r.max_lift),
            "slip": float(r.max_pivot_slip), "yaw": float(r.yaw_max), "u_max": float(r.u_max),
            "plate_acc": float(np.abs(lowpass(r.acc_step, r.settings.dt)).max(initial=0.0)),
            "t_capacity": r.t_capacity, "finite": bool(r.finite), "wall_time_s": float(r.wall_time),
            "sim_time_s": float(r.steps * r.settings.dt), "cpu_time_s": float(r.cpu_time)}
