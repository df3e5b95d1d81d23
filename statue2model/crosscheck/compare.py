"""The cross-check: the 2D models and the 3D scenes on the same statue and motions (:func:`compare`).

Each case (:class:`~statue2model.crosscheck.case.Case`: name, quantity, value_2d, value_3d,
rel_error, target, met, status) compares one quantity; the case families below each return a
:class:`~statue2model.crosscheck.case.Comparison` (cases, time histories for the overlay plots,
3D run details; the isolator's free vibration and the record ensemble a record holding one, beside
the calibration or the statistics) and :func:`compare` joins them, in this order:

* restitution (:mod:`~statue2model.crosscheck.restitution`): every calibrated e (e_L and e_R, per
  release 0.1-0.7 delta, i.e. per impact speed) against eq. 15 (target 5 %);
* free rocking, one-sine pulses and the user's motion (:mod:`~statue2model.crosscheck.statue_cases`);
* the overturning boundary of one-sine pulses at each frequency of a small grid, ratio 3D / 2D
  within 10 % (:mod:`~statue2model.crosscheck.boundary`);
* with an isolator scene: its free vibration and the isolated statue
  (:mod:`~statue2model.crosscheck.isolator_cases`); the exact-kinematics scene
  (:class:`~statue2model.crosscheck.pendulum_scene.PendulumIsolator`, the default) runs with the statue
  scenes' engine settings and always includes the free-standing statue; the ball scene (the detailed
  mode) with the isolator settings, and the free-standing statue only without ``quick``;
* asked for (``imperfect``, ``records``): the imperfect base (:mod:`~statue2model.crosscheck.imperfect`)
  and the record ensemble (:mod:`~statue2model.crosscheck.ensemble`); the command line reaches them
  with ``statue2model crosscheck ... --imperfect --records N``.

A case is a check (met / missed: the 2D model as the user runs it), a diagnostic (2D given 3D's e)
or not applicable (the validity screen, :mod:`~statue2model.crosscheck.screen`). crosscheck.json is
written by :mod:`statue2model.crosscheck.output`, the overlay plots by
statue2model.report.crosscheck_plots.
"""
from __future__ import annotations

from ..errors import InputError
from .boundary import BOUNDARY_FREQS, boundary_cases
from .case import Comparison
from .contact import ContactSettings
from .ensemble import LEVELS, ensemble_cases, json_safe
from .imperfect import imperfect_cases
from .isolator_cases import is_exact, isolated_statue_cases, isolator_free_cases
from .restitution import calibrate_restitution, model_2d, restitution_cases, user_model
from .statue_cases import free_rocking_cases, motion_cases, pulse_cases
from .statue_scene import STATUE_SETTINGS, StatueScene
from .world import SimSettings


def compare(scene: StatueScene, motion=None, *, iso_scene=None, settings: SimSettings | None = None,
            contact: ContactSettings | None = None, pulse_freq: float = 1.5, quick: bool = False,
            progress=None, e_L: float | None = None, e_R: float | None = None,
            boundary_freqs=None, statue_settings: SimSettings | None = None, imperfect: bool = False,
            records: int = 0, levels=None, workers: int = 2, only_motion: bool = False,
            motion_y=None) -> Comparison:
    """All cases of the module docstring for one statue (and isolator, if given). ``e_L``, ``e_R``:
    the user's restitution (a prototype test; default eq. 15); ``boundary_freqs``: the frequencies of
    the overturning-boundary cases (default BOUNDARY_FREQS[quick]). Engine settings: ``statue_settings``
    for the statue scenes and the exact isolator scene (default :data:`~.statue_scene.STATUE_SETTINGS`,
    dt 2 ms), ``settings`` for the ball isolator scene, the imperfect base and the record ensemble
    (default ``SimSettings()``, dt 0.5 ms). ``imperfect``: also the imperfect-base cases; ``records``: also the ensemble of that many
    records (0: none) at ``levels`` (default ensemble.LEVELS) on ``workers`` processes; their run
    details (``runs['imperfect base: ...']``, ``runs['records']``) with non-finite numbers as null.

    ``only_motion``: the user's motion alone (no restitution calibration, free rocking, pulses or
    boundaries; with an isolator scene the isolated statue under the component along the direction,
    without its free vibration), as :func:`only_motion_cases`; ``motion_y``: the motion's horizontal
    component across the direction (a record with two, :func:`statue2model.hazard.motions.along`)."""
    say = progress or (lambda msg: None)
    if only_motion:
        return only_motion_cases(scene, motion, motion_y=motion_y, iso_scene=iso_scene,
                                 settings=STATUE_SETTINGS if statue_settings is None else statue_settings,
                                 contact=ContactSettings() if contact is None else contact, quick=quick,
                                 e_L=e_L, e_R=e_R, say=say)
    iso_settings = SimSettings() if settings is None else settings
    settings = STATUE_SETTINGS if statue_settings is None else statue_settings
    contact = ContactSettings() if contact is None else contact
    user = user_model(scene, e_L, e_R)
    say("restitution calibration")
    rest = calibrate_restitution(scene, settings, contact)
    parts = [Comparison(tuple(restitution_cases(scene, rest, contact)), runs={"restitution calibration": rest})]
    diag = model_2d(scene, rest)
    say("free rocking")
    parts.append(free_rocking_cases(scene, settings, contact, t_end=2.0 if quick else 3.0, model=user))
    say("pulses")
    parts.append(pulse_cases(scene, settings, contact, pulse_freq, free_time=1.5 if quick else 3.0, model=user,
                             diag_model=diag))
    say("overturning boundaries")
    freqs = BOUNDARY_FREQS[bool(quick)] if boundary_freqs is None else boundary_freqs
    parts.append(boundary_cases(scene, user, freqs, settings, contact, n3=5 if quick else 10,
                                free_time=1.5 if quick else 2.0, max_edges=2 if quick else 4,
                                progress=lambda f: say(f"  boundary at {f:g} Hz done")))
    if motion is not None and motion.kind != "none":
        say(f"motion {motion.label}")
        parts.append(motion_cases(scene, motion, settings, contact, free_time=1.0 if quick else 3.0, model=user,
                                  calib=rest, spread=not quick, e_user=(e_L, e_R)))
        if motion_y is not None:
            say(f"motion {motion.label}, both components")
            parts.append(motion_cases(scene, motion, settings, contact, free_time=1.0 if quick else 3.0, model=user,
                                      e_user=(e_L, e_R), motion_y=motion_y, label=both_label(motion)))
    if iso_scene is not None:
        parts += _isolator_parts(iso_scene, motion, settings if is_exact(iso_scene) else iso_settings, contact,
                                 quick, user, say)
    if imperfect:
        imp = imperfect_cases(scene, iso_settings, contact, bool(quick), pulse_freq=pulse_freq,
                              progress=progress)
        parts.append(Comparison(imp.cases, imp.histories, json_safe(imp.runs)))
    if records:
        parts.append(ensemble_cases(scene, iso_settings, contact, n_records=records,
                                    levels=LEVELS if levels is None else levels, quick=bool(quick),
                                    workers=workers, progress=progress).comparison)
    return Comparison.join(parts)


def both_label(motion) -> str:
    """The tag of the cases of a record's two horizontal components run together in 3D."""
    return f"{motion.label} + across (both components)"


def only_motion_cases(scene: StatueScene, motion, *, motion_y=None, iso_scene=None, settings: SimSettings,
                      contact: ContactSettings, quick: bool = False, e_L: float | None = None,
                      e_R: float | None = None, say=None) -> Comparison:
    """The user's motion alone: the free-standing statue in 3D (with ``motion_y`` a second run with
    both horizontal components, its cases tagged 'both components') against the user's 2D model
    (``e_L``, ``e_R``: default eq. 15) on the component along the direction; with ``iso_scene`` the
    isolated statue, fixed to the plate and free-standing, on that component (the isolator scenes
    are driven along x). A run of a campaign's test or a floor record without the standard cases."""
    say = say or (lambda msg: None)
    if motion is None or motion.kind == "none":
        raise InputError("--only-motion needs a ground motion (a record or a pulse), not free rocking")
    user = user_model(scene, e_L, e_R)
    free_time = 1.0 if quick else 3.0
    say(f"motion {motion.label}")
    parts = [motion_cases(scene, motion, settings, contact, free_time=free_time, model=user,
                          spread=not quick, e_user=(e_L, e_R))]
    if motion_y is not None:
        say(f"motion {motion.label}, both components")
        parts.append(motion_cases(scene, motion, settings, contact, free_time=free_time, model=user,
                                  e_user=(e_L, e_R), motion_y=motion_y,
                                  label=both_label(motion)))
    if iso_scene is not None:
        say("isolated statue")
        parts.append(isolated_statue_cases(iso_scene, motion, settings, contact, free_time=1.0 if quick else 2.0,
                                           mount="rigid", label="isolated statue (fixed to the plate)"))
        if is_exact(iso_scene):
            say("isolated statue, free-standing")
            parts.append(isolated_statue_cases(iso_scene, motion, settings, contact, free_time=2.0,
                                               mount="contact", label="isolated statue (free-standing)",
                                               model=user))
    return Comparison.join(parts)


def _isolator_parts(iso_scene, motion, settings: SimSettings, contact: ContactSettings, quick: bool, user,
                    say) -> list:
    """The isolator's cases: its free vibration (which calibrates the ball scene's rolling friction), the
    isolated statue fixed to the plate under ``motion`` and free-standing (against the coupled 2D
    model ``user``; on the ball scene only without ``quick``); the calibration last
    (``runs['calibration']``)."""
    say("isolator free vibration")
    free = isolator_free_cases(iso_scene, settings, contact, cycles=1.2 if quick else 2.2)
    calib = free.calibration
    parts = [free.comparison]
    if motion is not None and motion.kind != "none":
        say("isolated statue")
        parts.append(isolated_statue_cases(iso_scene, motion, settings, contact, mu_3d=calib.get("mu_3d"),
                                           free_time=1.0 if quick else 2.0, mount="rigid",
                                           label="isolated statue (fixed to the plate)"))
        if not quick or is_exact(iso_scene):
            say("isolated statue, free-standing")
            parts.append(isolated_statue_cases(iso_scene, motion, settings, contact, mu_3d=calib.get("mu_3d"),
                                               free_time=2.0, mount="contact",
                                               label="isolated statue (free-standing)", model=user))
    return parts + [Comparison((), runs={"calibration": calib})]
