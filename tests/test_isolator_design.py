"""The isolator design: capacity, the thesis' devices, one device per statue and hazard,
and a clear answer when nothing in range works (isolator/design.py, device.groove_capacity)."""
from __future__ import annotations

import json
import math

import numpy as np
import pytest
from scipy.optimize import brentq

from statue2model.geometry.rocking_params import RockingParams
from statue2model.isolator.design import (
    DISPLACEMENT_MARGIN,
    PLATE_TOLERANCE,
    SHOWN_FAILING,
    SHOWN_PASSING,
    assess,
    design,
    tipping_capacity,
)
from statue2model.hazard.code_spectra import G as G0
from statue2model.hazard.code_spectra import ec8
from statue2model.isolator.device import groove_capacity
from statue2model.errors import InputError

G = 9.81
MU = 0.0073                                             # Table 25, the four-groove device
HAZARD = ec8(0.25 * G0, "C")                            # the pipeline's default spectrum
FUSE = 0.075 * G                                        # the pipeline's default fuse

# Venere Landolina, scaled prototype (thesis Table 24) and its alpha (Table 22)
VENERE = RockingParams.from_dict({"m": 12.074, "h": 0.3523, "b_L": 0.1995, "b_R": 0.0805, "I_G": 0.7994})
VENERE_ALPHA = (0.159, 0.175)


def _venere_spectrum():
    """The spectrum the thesis' 1:2 prototype feels (ch. 6.3.2), built from the thesis' inputs, not
    from its answer (tests/test_venere_reproduction.py, docs/venere.md): the SLA at the Paolo Orsi
    museum, Syracuse, from the NTC hazard grid, T_R = 75 years (the damage level of a class III
    building: the thesis prints its T_R only in Fig. 117a), soil C, T1; the floor spectrum at
    z = 8.0 m of 11.5 m, 3 storeys, T1 = 0.32 s (Circolare general formulation); times / sqrt(2)
    for the prototype. At T = 1.55 s it gives 0.4334 m/s^2 (the thesis: 0.3917)."""
    from statue2model.hazard.floor import floor_spectrum
    from statue2model.hazard.froude_spectrum import FroudeSpectrum
    from statue2model.hazard.ntc_grid import PAOLO_ORSI, PAOLO_ORSI_CELL, return_period, site_spectrum

    ground = site_spectrum(PAOLO_ORSI_CELL, *PAOLO_ORSI, return_period(50, 1.5, 0.63), soil="C",
                           topography="T1", limit_state="SLA")
    floor = floor_spectrum(ground, z=8.0, H=11.5, T1=0.32, code="ntc2018", n=3, structure="masonry")
    return FroudeSpectrum(floor, 2.0)


# --- capacity --------------------------------------------------------------------------------------
@pytest.mark.parametrize("R, r, a", [(0.30, 0.0095, 0.05), (0.32, 0.02, 0.08), (2.0, 0.025, 0.3), (0.2, 0.1, 0.19)])
def test_groove_capacity_is_where_the_contact_point_reaches_the_rim(R, r, a):
    """Independent geometry: the ball's two contact forces are collinear, so the bottom
    groove's centre C_b, the ball's centre B and the top groove's centre C_t lie on one
    line, B at R - r from both. Sweep the line's angle phi, take the bottom contact point
    P_b = C_b + R (sin, -cos) phi and the plates' relative shift u = x(C_t) - x(C_b); the
    capacity is u where |x(P_b)| = a."""
    phi = np.linspace(0.0, math.asin(min(a / R, 1.0)) * 1.2, 200001)
    phi = phi[phi < math.pi / 2]
    B = (R - r) * np.sin(phi)                            # C_b at x = 0
    C_t = 2 * B                                          # C_t = C_b + 2 (B - C_b)
    P_b = R * np.sin(phi)
    u = np.interp(a, P_b, C_t)
    assert groove_capacity(R, r, a) == pytest.approx(u, rel=1e-6)
    # the top groove's contact point is as far out from its own axis
    P_t = C_t - (C_t - B) * R / (R - r)
    assert np.allclose(np.abs(P_t - C_t), P_b)
    # the old rule "ball centre travel d / 2 + r within the opening" gave away r + a r / R
    assert 2 * (a - r) < groove_capacity(R, r, a) <= 2 * a


def test_groove_capacity_refuses_impossible_grooves():
    with pytest.raises(InputError, match="smaller than the groove radius"):
        groove_capacity(0.01, 0.02, 0.005)
    with pytest.raises(InputError, match="cannot open wider"):
        groove_capacity(0.3, 0.01, 0.31)
    with pytest.raises(InputError, match="positive"):
        groove_capacity(0.3, 0.01, -0.1)


@pytest.mark.parametrize("L_cr, l, R, r, mu", [(0.2, 0.3, 0.32, 0.02, 0.0), (0.135, 0.285, 0.32, 0.02, 0.0073),
                                               (0.4, 1.2, 2.0, 0.025, 0.01)])
def test_tipping_capacity_balances_the_moment_about_the_tipping_line(L_cr, l, R, r, mu):
    """Moment about the outer balls' contact line, in the top plate's frame, at plate
    displacement u: the supports have moved back u R / R_hat, the resultant of weight and
    inertia (acceleration g (u / R_hat + mu)) has moved out (u / R_hat + mu) l."""
    R_hat = 2 * (R - r)

    def moment(u):                                      # > 0: stable
        return (L_cr - u * R / R_hat) - (u / R_hat + mu) * l

    u_tip = brentq(moment, 0.0, 10.0)
    assert tipping_capacity(L_cr, l, R, r, mu) == pytest.approx(u_tip, rel=1e-12)


# --- the thesis' devices -----------------------------------------------------------------------------
def test_the_design_procedure_reproduces_the_three_groove_device():
    """Ch. 5.1: R = 0.30 m with r = 0.0095 m (steel) -> T = 1.53 s; r = 0.0183 m -> 1.51 s."""
    for r, T in ((0.0095, 1.53), (0.0183, 1.51)):
        d = design(VENERE, spectrum=ec8(0.05 * G0, "A"), mu=0.0131, R_grid=(0.30,), balls=(r,), n_grooves=3,
                   thickness=0.03)
        # every check but the ball load (required): on 9.5 mm balls the r^2 scaling of the one tested point
        # (73.6 N on 20 mm) allows 16.6 N, the Venere puts 53 N on each of three
        assert all(c.passed for c in d.checks if c.required and c.key != "ball_load")
        assert (d.R, d.r, d.n_grooves) == (0.30, r, 3)
        assert round(d.T, 2) == T
    assert round(d.R_hat, 3) == 0.563


def test_venere_case_study():
    """Ch. 6.4: T = 1.55 s (R_hat ~ 0.60 m), design acceleration 0.3917 m/s^2 below the
    statue's uplift 0.3924 m/s^2 (0.040 g; alpha_R a_R = 0.3923 m/s^2 from Tables 22, 24),
    device travel 0.15 m 'geometrically obtained by drawings' (the groove rim), compatible
    with the spectral displacement. The thesis gives neither the grooves' opening nor the
    plate's size: R = 0.32 m with the 20 mm ivory balls gives its R_hat = 0.60 m, an 80 mm
    opening gives the 0.15 m, and a 0.47 m x 30 mm beech plate weighs the measured
    4.359 kg. On the spectrum rebuilt from the thesis' inputs (_venere_spectrum, docs/venere.md)
    the design acceleration is 0.4334 m/s^2, 10.6 % above the thesis' 0.3917: the thesis'
    0.2 % margin below the uplift does not survive, and the device fails the acceleration check."""
    sp = _venere_spectrum()
    d = assess(VENERE, R=0.32, r=0.020, n_grooves=4, opening_radius=0.080, spacing=0.27, side=0.47,
               thickness=0.03, mu=MU, spectrum=sp, alpha=VENERE_ALPHA)
    assert d.T == pytest.approx(1.55, abs=0.005)
    assert d.a_design == pytest.approx(0.4334, abs=1e-4)
    assert d.a_lim == pytest.approx(0.3924, abs=2e-4) and d.a_design > d.a_lim
    assert d.m_o == pytest.approx(4.359, rel=0.01) and d.M == pytest.approx(16.433, rel=0.01)
    assert d.capacity_groove == pytest.approx(0.150, abs=5e-4)
    assert d.d_design == pytest.approx(0.0265, abs=2e-4)                   # SDe(1.55 s)
    assert not d.passed and d.failure.startswith("plate acceleration below the statue's uplift limit")
    # on that plate the top plate tips first: the thesis' 0.15 m is the grooves alone
    assert d.capacity_limited_by == "top plate tipping" and 0.12 < d.capacity < 0.15
    assert d.capacity >= DISPLACEMENT_MARGIN * d.d_design + MU * d.R_hat
    # a plate large enough for the grooves' full travel: capacity 0.15 m
    big = assess(VENERE, R=0.32, r=0.020, n_grooves=4, opening_radius=0.080, spacing=0.33, side=0.53,
                 thickness=0.03, mu=MU, spectrum=sp, alpha=VENERE_ALPHA)
    assert big.capacity == pytest.approx(0.150, abs=5e-4) and big.capacity_limited_by == "groove rim"
    # the exact R_hat of R = 0.30 m with r = 0.020 m is 0.56 m, T = 1.50 s: 18 % over the uplift
    exact = assess(VENERE, R=0.30, r=0.020, n_grooves=4, opening_radius=0.080, spacing=0.27, side=0.47,
                   thickness=0.03, mu=MU, spectrum=sp, alpha=VENERE_ALPHA)
    assert exact.T == pytest.approx(1.50, abs=0.005) and not exact.passed
    assert exact.failure.startswith("plate acceleration below the statue's uplift limit")
    # and it misses the restoring-force rule (advisory): R_hat 0.60 m > 20 d = 0.53 m
    rec = next(c for c in d.checks if c.key == "recentring")
    assert not rec.required and not rec.passed and rec.ratio == pytest.approx(1.13, abs=0.01)
    # full contact on these inputs needs a longer period: R = 0.36 m, T = 1.65 s
    longer = assess(VENERE, R=0.36, r=0.020, n_grooves=4, opening_radius=0.080, spacing=0.27, side=0.47,
                    thickness=0.03, mu=MU, spectrum=sp, alpha=VENERE_ALPHA)
    assert longer.T == pytest.approx(1.654, abs=0.001)
    assert longer.a_design < longer.a_lim


def test_design_for_the_venere_finds_a_thesis_like_device():
    d = design(VENERE, spectrum=_venere_spectrum(), mu=MU, alpha=VENERE_ALPHA, thickness=0.03)
    assert d.passed and d.a_design <= d.a_lim
    assert d.T >= 1.633                           # where the spectrum falls to the uplift 0.3923 m/s^2
    assert 0.3 <= d.R <= 0.45                     # the restoring-force rule keeps it short
    assert d.capacity >= DISPLACEMENT_MARGIN * d.d_design + MU * d.R_hat - 1e-12
    assert d.side == pytest.approx(2 * 0.1995 + 0.04)   # the statue's base sets the plate


# --- one device per statue ----------------------------------------------------------------------------
@pytest.fixture(scope="module")
def statues():
    from statue2model.geometry.body import load_body
    from statue2model.io.paths import default_scan

    scan = load_body(default_scan()).rocking()
    block = RockingParams.from_dict({"m": 5000.0, "h": 0.5, "b_L": 0.5, "b_R": 0.5, "I_G": 5000 * 2 / 12})
    figure = RockingParams.from_dict({"m": 50.0, "h": 0.6, "b_L": 0.08, "b_R": 0.08, "I_G": 50 * 0.5 * 0.5})
    return {"default scan": scan, "squat 5 t block": block, "slender 50 kg figure": figure}


def _device(d):
    return (d.R, d.r, d.n_grooves, round(d.side, 3), round(d.spacing, 3), d.thickness)


TESTED_INSERT = 2500.0
"""N per 20 mm ball: a load test of a hard insert, assumed here so that the 5 t block's balls pass (the
geometry is what these tests are about; no material is claimed to carry it)."""


@pytest.mark.parametrize("spectrum", [HAZARD, ec8(0.1 * G0, "B")], ids=["ec8 0.25g C", "ec8 0.1g B"])
def test_different_statues_get_different_devices(statues, spectrum):
    devices = {}
    for name, st in statues.items():
        d = design(st, spectrum=spectrum, mu=MU, thickness=0.03, fuse_release=FUSE, ball_capacity=TESTED_INSERT)
        assert d.passed, (name, d.failure)
        need = DISPLACEMENT_MARGIN * d.d_design + MU * d.R_hat
        assert d.travel_need == pytest.approx(need) and d.capacity >= need - 1e-12
        assert d.capacity == pytest.approx(min(d.capacity_groove, d.capacity_tip))
        assert d.capacity_groove == pytest.approx(groove_capacity(d.R, d.r, d.opening_radius))
        assert d.a_design <= d.a_lim and d.d_design <= d.d_max
        assert d.side >= 2 * max(st.b_L, st.b_R) + 0.04 - 1e-12      # the statue's base fits
        devices[name] = _device(d)
    assert len(set(devices.values())) == len(devices), devices
    if spectrum is not HAZARD:   # below T_D's plateau the period follows the statue
        assert len({dev[0] for dev in devices.values()}) > 1, devices


def test_the_heavy_block_gets_the_largest_balls_and_fails_on_the_ball_load(statues):
    d = design(statues["squat 5 t block"], spectrum=HAZARD, mu=MU, thickness=0.03)
    load = next(c for c in d.checks if c.key == "ball_load")
    assert d.r == 0.05 and d.n_grooves == 4 and load.required and not load.passed and not d.passed
    # 73.55 N on a 20 mm ball scaled to 50 mm: 459.7 N, against W / 4 of 5 t and the top plate
    assert load.limit == pytest.approx(30 * 9.81 / 4 * (0.05 / 0.02) ** 2, rel=1e-4)
    assert load.ratio == pytest.approx(d.M * 9.81 / 4 / load.limit, rel=1e-9) and load.ratio > 25
    assert d.failure.startswith("load per ball within what the grooves carry")
    # a load test of a harder surface (N per 20 mm ball) that carries it lets it pass
    strong = design(statues["squat 5 t block"], spectrum=HAZARD, mu=MU, thickness=0.03, ball_capacity=TESTED_INSERT)
    assert strong.passed and strong.to_dict()["ball_capacity"]["tested_load"] == TESTED_INSERT


def test_candidates_are_listed_compactly_and_the_choice_follows_the_criterion():
    d = design(VENERE, spectrum=HAZARD, mu=MU, thickness=0.03, R_grid=(0.6, 0.8, 1.0, 1.5, 2.0), balls=(0.0183, 0.025))
    c = d.to_dict()["candidates"]
    assert c["tried"] == d.candidates_tried == 5 * 2 * 2
    assert len(c["rows"]) == min(c["passing"], SHOWN_PASSING) + min(c["tried"] - c["passing"], SHOWN_FAILING)
    names = [k["name"] for k in c["checks"]]
    assert names == [ck.name for ck in d.checks] and all(k["unit"] in ("m", "m/s^2", "N") for k in c["checks"])
    first = c["rows"][0]
    assert (first["R"], first["r"], first["n_grooves"], first["side"]) == (d.R, d.r, d.n_grooves, round(d.side, 6))
    passing = [row for row in c["rows"] if row["passed"]]
    assert len(passing) == c["passing"] > 1
    for row in c["rows"]:
        required = [ck for ck, k in zip(row["checks"], c["checks"]) if k["required"]]
        assert row["passed"] == all(p for _, _, _, p in required)
        for value, limit, ratio, _ in row["checks"]:
            if limit and limit > 0 and ratio is not None:
                assert ratio == pytest.approx(value / limit, rel=1e-4)
    # the chosen plate is within PLATE_TOLERANCE of the lightest passing one, and among
    # those no other has a larger acceleration margin (to 0.01) without a worse advisory
    lightest = min(row["m_o"] for row in passing)
    assert d.m_o <= (1 + PLATE_TOLERANCE) * lightest + 1e-9
    json.dumps(d.to_dict(), allow_nan=False)


# --- nothing in range works ------------------------------------------------------------------------------
def test_uplift_below_friction_fails_naming_the_check_and_its_ratio():
    d = design(VENERE, spectrum=ec8(0.05 * G0, "A"), mu=MU, alpha=(0.02, 0.02), thickness=0.03)
    assert not d.passed
    fric = next(c for c in d.checks if c.key == "friction")
    assert not fric.passed and fric.ratio == pytest.approx(MU * G / (0.02 * VENERE.a_R), rel=1e-9)
    assert f"rolling friction below the statue's uplift limit: mu g = {MU * G:.4f} m/s^2" in d.failure
    assert f"(ratio {fric.ratio:.2f})" in d.failure and "R 0.2 to 2 m" in d.failure
    assert "no isolator in range works: " + d.failure in d.report()
    assert d.to_dict()["passed"] is False and d.to_dict()["failure"] == d.failure
    json.dumps(d.to_dict(), allow_nan=False)


def test_a_huge_hazard_fails_with_the_closest_candidate_and_what_it_lacks():
    d = design(VENERE, spectrum=ec8(1.5 * G0, "D"), mu=MU, thickness=0.03, fuse_release=FUSE)
    assert not d.passed and d.failure
    bad = sorted((c for c in d.checks if c.required and not c.passed), key=lambda c: -c.ratio)
    assert bad and all(c.ratio > 1 for c in bad)
    worst = f"(ratio {bad[0].ratio:.2f})" if math.isfinite(bad[0].ratio) else "(not met)"   # never 'inf'
    assert d.failure.startswith(f"{bad[0].name}: ") and worst in d.failure and "inf" not in d.failure
    assert "plate up to 1.25 m" in d.failure
    rows = d.to_dict()["candidates"]["rows"]
    assert not any(row["passed"] for row in rows)
    req = [k["required"] for k in d.to_dict()["candidates"]["checks"]]
    n_bad = [sum(1 for ck, q in zip(row["checks"], req) if q and not ck[3]) for row in rows]
    assert n_bad[0] == min(n_bad) == len(bad)
    assert d.report().startswith("Rolling-ball isolator: FAIL")
    from statue2model.io.files import _clean

    json.dumps(_clean(d.to_dict()), allow_nan=False)        # as write_json writes design.json


def test_units_are_stated_and_not_mixed():
    d = design(VENERE, spectrum=HAZARD, mu=MU, thickness=0.03, fuse_release=FUSE)
    assert {c.unit for c in d.checks} <= {"m", "m/s^2", "N"}
    table = d.report().split("checks (")[1].split("\nwhy:")[0]
    assert "unit" in table.splitlines()[1] and " mm" not in table
    for c in d.to_dict()["checks"]:
        assert c["unit"] and (c["ratio"] is None or c["ratio"] == pytest.approx(c["value"] / c["limit"]))


def test_bad_design_inputs():
    with pytest.raises(InputError, match="exactly one design input"):
        design(VENERE, mu=MU)
    with pytest.raises(InputError, match="thickness"):
        design(VENERE, spectrum=HAZARD, mu=MU, thickness=0.5)
    with pytest.raises(InputError, match="grooves must be 3 or 4"):
        design(VENERE, spectrum=HAZARD, mu=MU, n_grooves=5)
    with pytest.raises(InputError, match="margin"):
        design(VENERE, spectrum=HAZARD, mu=MU, margin=0.5)
