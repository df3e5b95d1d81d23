"""The imperfect model in 3D (statue2model/crosscheck/imperfect.py): a convex base, alpha and theta
identified from 3D tests, classical vs imperfect 2D against the 3D body."""
from __future__ import annotations

import math

import numpy as np
import pytest

pytest.importorskip("pybullet")

from statue2model.crosscheck import imperfect as imp
from statue2model.crosscheck.statue_scene import StatueScene
from statue2model.crosscheck.world import SimSettings
from statue2model.hazard import motions
from statue2model.rocking import RockingModel, simulate
from statue2model.errors import InputError

BLOCK = StatueScene.block(b=0.1, h=0.5, m=100.0)
TH = 0.07 * BLOCK.params.delta_R          # the thesis' reference transition rotation (Table 13)


def test_convex_base_geometry():
    p = BLOCK.params
    geo = imp.base_geometry(p, 0.5, 0.4, TH, TH)
    assert geo["core_L"] == pytest.approx(0.05) and geo["core_R"] == pytest.approx(0.04)
    assert geo["eps_R"] == pytest.approx(0.5 * 0.06 * math.tan(TH))
    sc = imp.imperfect_scene(BLOCK, 0.5, 0.4, TH, TH)
    base = sc.hull[sc.hull[:, 2] < 1e-3]
    # flat core on z = 0, edges raised by eps, the curve convex (z grows with the distance)
    assert base[:, 2].min() == 0.0
    assert base[base[:, 0] == base[:, 0].max(), 2].max() == pytest.approx(geo["eps_R"], rel=1e-9)
    flat = base[base[:, 2] == 0.0, 0]
    assert flat.min() == pytest.approx(-0.05) and flat.max() == pytest.approx(0.04)
    seated = imp.imperfect_scene(BLOCK, 0.5, 0.4, TH, TH, seat="R")
    on = seated.hull[seated.hull[:, 2] == 0.0]
    assert np.all(on[:, 0] == pytest.approx(0.1)) and seated.com[2] == pytest.approx(0.5 - geo["eps_R"])
    assert sc.mass == BLOCK.mass and np.array_equal(sc.inertia, BLOCK.inertia) and sc.params == BLOCK.params


@pytest.mark.parametrize("kw, msg", [({"alpha_L": 1.0}, "alpha_L"), ({"theta_R": 0.2}, "theta_R"),
                                     ({"seat": "middle"}, "seat")])
def test_bad_base_one_line(kw, msg):
    args = {"alpha_L": 0.5, "alpha_R": 0.5, "theta_L": TH, "theta_R": TH} | kw
    with pytest.raises(InputError, match=msg):
        imp.imperfect_scene(BLOCK, **args)


def test_identification_recovers_a_2d_imperfect_model():
    """The identification procedure itself, on the 2D model with known alpha, theta (no PyBullet)."""
    p = BLOCK.params
    model = RockingModel.imperfect(p, alpha_L=0.6, alpha_R=0.6, theta_L=0.02, theta_R=0.02)

    def peak(a):
        r = simulate(model, motions.rect_pulse(a, imp.PULSE_DURATION), t_end=imp.PULSE_DURATION + 0.1)
        return max(r.theta_max_L, r.theta_max_R)

    up = imp.uplift_acceleration(peak, p.a_L)
    assert up["alpha"] == pytest.approx(0.6, abs=0.01)
    m = imp.ramp_motion(1.05 * p.a_L)
    r = simulate(model, m, t_end=imp.RAMP_TIME, dt_out=2e-3)
    fit = imp.fit_transition(r.history["t"], r.history["theta"], m.acc, p, "L")
    assert fit["alpha"] == pytest.approx(0.6, abs=0.02)
    assert fit["theta"] == pytest.approx(0.02, rel=0.10)      # 0.0213: the ramp is not quite static


def test_flat_block_lifts_at_west_and_convex_block_at_alpha():
    """3D: the flat block lifts at g b / h (alpha ~ 1), the convex one at alpha a with the
    transition rotation of its geometry (measured 0.487 and 0.0128 rad for 0.5 and 0.0138)."""
    s = SimSettings()
    flat = imp.uplift_acceleration(lambda a: imp._lift_peak(BLOCK, a, s, imp.ContactSettings()), BLOCK.params.a_L,
                                   refine=3)
    assert 0.95 <= flat["alpha"] <= 1.02
    sc = imp.imperfect_scene(BLOCK, 0.5, 0.5, TH, TH)
    ident = imp.identify_3d(sc, s, imp.ContactSettings(), sides=("L",))
    assert ident["L"]["alpha"] == pytest.approx(0.5, rel=0.05)
    assert ident["L"]["theta"] == pytest.approx(TH, rel=0.20)
    assert 0 < ident["L"]["theta"] < 0.2 * BLOCK.params.delta_L          # order of magnitude from eps and L


def test_imperfect_2d_beats_classical_on_the_3d_convex_block():
    cases = imp.imperfect_cases(BLOCK, SimSettings(), quick=True).cases
    by = {c.name: c for c in cases}
    assert all(by[n].met for n in by if "identified" in n)
    # the classical model does not lift at 0.9 a (West); the imperfect one lifts within 5 ms of 3D
    tag = "imperfect base: one-sine 1.5 Hz x0.9 a (West)"
    assert by[f"{tag}: lift-off time (classical 2D)"].value_2d is None
    assert by[f"{tag}: lift-off time (imperfect 2D)"].met
    assert by[f"{tag}: lift-off time: imperfect 2D closer to 3D than classical"].met
    assert by[f"{tag}: peak rotation: imperfect 2D closer to 3D than classical"].met
    # above the imperfect model's overturning amplitude the 3D body overturns: imperfect 2D agrees
    up = "imperfect base: one-sine 1.5 Hz x1.25 overturning"
    assert by[f"{up}: overturn (imperfect 2D)"].met and by[f"{up}: overturn (imperfect 2D)"].value_3d == 1.0
    assert not by[f"{up}: overturn (classical 2D)"].met
    # the peak in the rolling range is within 20 % (target 10 %: not met, see docs/crosscheck.md)
    assert by[f"{tag}: peak rotation (imperfect 2D)"].rel_error < 0.20


def test_lift_time_3d_reads_the_core_edge_height_and_persists():
    """3D lift-off: the far core edge LIFT_HEIGHT up (core_lift_angle), held LIFT_STEPS samples; a
    one-sample rattle above the angle is not a lift-off."""
    from statue2model.crosscheck.imperfect import core_lift_angle, lift_time_3d
    from statue2model.crosscheck.statue_scene import LIFT_HEIGHT, StatueScene

    p = StatueScene.block(b=0.1, h=0.5, m=100.0).params
    a = core_lift_angle(p, 0.5, 0.5)
    assert abs(a - math.asin(LIFT_HEIGHT / (0.5 * p.b_L + 0.5 * p.b_R))) < 1e-15
    assert core_lift_angle(p) < a                                    # the whole base: a smaller angle
    t = np.arange(0.0, 0.1, 1e-3)
    th = np.where(t > 0.05, (t - 0.05) * 1.0, 0.0)                  # ramps through a at t = 0.05 + a
    th[10] = 10 * a                                                  # one-sample rattle at t = 0.01
    got = lift_time_3d(t, th, a)
    assert got is not None and abs(got - (0.05 + a)) < 1e-9
    assert lift_time_3d(t, th, a, steps=1) == pytest.approx(0.0091, abs=1e-9)   # without persistence: the rattle
    assert lift_time_3d(t, np.zeros_like(t), a) is None
