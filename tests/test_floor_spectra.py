"""Floor spectra against values computed by hand from the published formulas: EC8 4.3.5.2 eq. 4.25,
the Circolare 2019 eq. C7.2.11 with Tab. C7.2.II (framed buildings) and its general formulation
C7.2.5-C7.2.10 (first mode, linear with height). Accelerations in g unless said otherwise.

The two sites (the ground spectra's arithmetic):

NTC: ntc2018(0.2g, F0 = 2.4, Tc* = 0.3 s, soil C): S = S_S = 1.70 - 0.60 * 2.4 * 0.2 = 1.412 (within 1.0-1.5);
  C_C = 1.05 * 0.3^-0.33 = 1.05 * 1.487819 = 1.562210, T_C = 1.562210 * 0.3 = 0.468663 s, T_B = T_C / 3 = 0.156221 s,
  T_D = 4 * 0.2 + 1.6 = 2.4 s; a_g S = 0.2 * 1.412 = 0.2824 g; plateau P = 0.2824 * 2.4 = 0.67776 g.
  Ground S_e(T, 5 %): T = 0: 0.2824; 0.5: P T_C / 0.5 = 0.635282; 1: 0.317641; 2: 0.158820;
  4 (> T_D): P T_C T_D / 16 = 0.047646.
EC8: ec8(0.25g, ground C, type 1): S = 1.15, T_B 0.2, T_C 0.6, T_D 2.0; a_g S = 0.2875 g; plateau 0.71875 g.
  Ground: T = 0: 0.2875; 0.5: 0.71875; 1: 0.71875 * 0.6 = 0.43125; 2: 0.215625; 4: 0.71875 * 0.6 * 2 / 16 = 0.053906.

The building: masonry, n = 3 storeys, H = 12 m, object on floor 2: z = 2 * 12 / 3 = 8 m, z/H = 2/3.
General formulation: gamma_1 = 3n / (2n + 1) = 9/7, gamma_1 psi_1 = 9/7 * 2/3 = 6/7 = 0.857143;
sqrt(1 + 0.0004 * 5^2) = sqrt(1.01) = 1.004988; A = 1.1 / sqrt(0.05) = 4.919350 (A - 1 = 3.919350);
a = 0.8, b = 1.1.
"""
import json
import math

import numpy as np
import pytest

from statue2model.errors import InputError
from statue2model.hazard.building import Building, estimated_period
from statue2model.hazard.code_spectra import G, ec8, ntc2018
from statue2model.hazard.floor import (FloorSpectrum, floor_spectrum, floor_spectrum_for, general_amplification,
                                       ntc_framed_coefficients, parse_floor)

NTC = ntc2018(0.2 * G, 2.4, 0.3, soil="C")
EC8 = ec8(0.25 * G, ground="C")
PERIODS = [0.0, 0.5, 1.0, 2.0, 4.0]
NTC_GROUND = [0.2824, 0.635282, 0.317641, 0.158820, 0.047646]
EC8_GROUND = [0.2875, 0.71875, 0.43125, 0.215625, 0.053906]

MASONRY_03 = Building(n=3, H=12.0, T1=0.3)
MASONRY_06 = Building(n=3, H=12.0, T1=0.6)
FRAME_05 = Building(n=3, H=12.0, T1=0.5, structure="concrete-frame")


def g(values):
    return np.asarray(values) * G


def test_the_sites_by_hand():
    assert np.allclose(NTC.Se(PERIODS), g(NTC_GROUND), rtol=2e-5)
    assert np.allclose(EC8.Se(PERIODS), g(EC8_GROUND), rtol=2e-5)


# --- general formulation (C7.2.5-C7.2.10) --------------------------------------------------------------
# T1 = 0.3 s (aT1 = 0.24 s, bT1 = 0.33 s). NTC: S_e(0.3) = P (plateau) -> a_Z = 0.67776 * 0.857143 * 1.004988
# = 0.583835, A a_Z = 2.872086. T >= bT1: x = T/0.33 - 1, S_eZ = A a_Z / (1 + 3.919350 x^1.2):
#   T 0.5: x 0.515152, x^1.2 0.451151, den 2.768219 -> 1.037522 (ground 0.635282)
#   T 1:   x 2.030303, x^1.2 2.339231, den 10.168262 -> 0.282456 < ground 0.317641: the ground governs
#   T 2:   x 5.060606, x^1.2 6.999114, den 28.431972 -> 0.101016 < 0.158820
#   T 4:   x 11.121212, x^1.2 18.004562, den 71.566170 -> 0.040132 < 0.047646
# T1 = 0.6 s (aT1 = 0.48, bT1 = 0.66): S_e(0.6) = P T_C / 0.6 = 0.529402 -> a_Z = 0.529402 * 0.861418 = 0.456036,
# A a_Z = 2.243400; T = 0.5 on the plateau; T 1: x = 1/0.66 - 1 = 0.515152 (den 2.768219) -> 0.810413;
# T 2: x 2.030303 (den 10.168262) -> 0.220628; T 4: x 5.060606 (den 28.431972) -> 0.078904 (all above the ground).
# EC8 site: S_e(0.3) = S_e(0.6) = 0.71875 (plateau 0.2-0.6 s) -> a_Z = 0.71875 * 0.861418 = 0.619144 for both,
# A a_Z = 3.045786; T1 = 0.3: T 0.5 -> 3.045786 / 2.768219 = 1.100269; T 1 -> 0.299539 < 0.43125 (ground);
# T 2 -> 0.107125 < 0.215625; T 4 -> 0.042559 < 0.053906. T1 = 0.6: T 0.5 plateau 3.045786; T 1 -> 1.100269;
# T 2 -> 0.299539; T 4 -> 0.107125.
@pytest.mark.parametrize("ground, building, expected", [
    (NTC, MASONRY_03, [0.583835, 1.037522, 0.317641, 0.158820, 0.047646]),
    (NTC, MASONRY_06, [0.456036, 2.243400, 0.810413, 0.220628, 0.078904]),
    (EC8, MASONRY_03, [0.619144, 1.100269, 0.43125, 0.215625, 0.053906]),
    (EC8, MASONRY_06, [0.619144, 3.045786, 1.100269, 0.299539, 0.107125]),
])
def test_general_formulation_by_hand(ground, building, expected):
    fl = floor_spectrum_for(ground, building, floor=2, method="ntc2018")
    assert isinstance(fl, FloorSpectrum) and fl.method == "ntc2018" and fl.z == 8.0
    assert np.allclose(fl.Se(PERIODS), g(expected), rtol=2e-5)
    assert math.isclose(fl.pfa, expected[0] * G, rel_tol=2e-5) and fl.pga == fl.pfa
    assert math.isclose(fl.gamma_1, 9 / 7) and math.isclose(fl.A, 4.919350, rel_tol=1e-6)


def test_general_formulation_below_a_T1_by_hand():
    # T1 = 0.3 s, T = 0.1 s < aT1 = 0.24 s: 1 - 0.1/0.24 = 0.583333, ^1.6 = 0.422150, den = 1 + 3.919350 * 0.422150
    # = 2.654554; NTC: 2.872086 / 2.654554 = 1.081947 (ground: 0.2824 (1 + 0.1/0.156221 * 1.4) = 0.535477);
    # EC8: 3.045786 / 2.654554 = 1.147382
    for ground, expected in ((NTC, 1.081947), (EC8, 1.147382)):
        fl = floor_spectrum_for(ground, MASONRY_03, 2, method="ntc2018")
        assert math.isclose(float(fl.Se(0.1)), expected * G, rel_tol=2e-5)


def test_general_is_the_default_on_an_ntc_site_and_ec8_on_an_ec8_site():
    assert floor_spectrum_for(NTC, MASONRY_03, 2).method == "ntc2018"
    fl = floor_spectrum_for(EC8, MASONRY_03, 2)
    assert fl.method == "ec8"
    # eq. 4.25, T1 0.3, z/H 2/3: T 0: 3 (5/3) / (1 + 1) - 0.5 = 2.0 -> 0.575; T 0.5: (1 - 0.5/0.3)^2 = 0.444444,
    # 5 / 1.444444 - 0.5 = 2.961538 -> 0.851442; T 1: (1 - 3.3333)^2 = 5.444444, 5/6.444444 - 0.5 = 0.275862 < 1:
    # the floor a_g S = 0.2875 governs, as at 2 and 4 s (the expression is negative there)
    assert np.allclose(fl.Se(PERIODS), g([0.575, 0.851442, 0.2875, 0.2875, 0.2875]), rtol=2e-5)


def test_general_formulation_at_another_damping():
    # xi_1 = 10 %: eta(10) = sqrt(10/15) = 0.816497, S_e(0.3, 10 %) = 0.67776 * 0.816497 = 0.553389;
    # a_Z = 0.553389 * 6/7 * sqrt(1 + 0.0004 * 100) = 0.553389 * 0.857143 * 1.019804 = 0.483727;
    # A = 1.1 / sqrt(0.10) = 3.478505; the plateau A a_Z = 1.682646
    fl = floor_spectrum_for(NTC, Building(n=3, H=12.0, T1=0.3, xi=10.0), 2)
    assert math.isclose(fl.A, 3.478505, rel_tol=1e-6) and math.isclose(fl.a_Z, 0.483727 * G, rel_tol=2e-5)
    assert math.isclose(float(fl.Se(0.3)), 1.682646 * G, rel_tol=2e-5)
    assert fl.xi == 5.0                                           # the object's damping: the spectrum is 5 %


def test_A_above_one_and_the_literal_reading_reported():
    assert general_amplification(5.0) == pytest.approx(1.1 / math.sqrt(0.05))      # 4.92, a_p = 5 of C7.2.11
    for xi in (0.5, 2.0, 5.0, 10.0, 20.0, 50.0, 99.0):
        assert general_amplification(xi) > 1.0
    d = floor_spectrum_for(NTC, MASONRY_03, 2).to_dict()
    assert d["A"] == pytest.approx(4.919350, rel=1e-6)
    assert d["A_if_xi_read_in_percent"] == pytest.approx(1.1 / math.sqrt(5.0))   # 0.492 < 1: not used


def test_the_ground_spectrum_bounds_the_general_formulation():
    fl = floor_spectrum_for(NTC, MASONRY_03, 2)
    T = np.linspace(0.0, 4.0, 801)
    assert np.all(fl.Se(T) >= NTC.Se(T))
    # where it governs, by hand: at 1 s the formula gives 0.282456 < 0.317641 (above), at 0.5 s 1.037522 > 0.635282
    assert fl.bound_governs([0.5, 1.0]).tolist() == [False, True]
    # a floor near the ground: floor 1 of 10, H 35 m, T1 0.6 s: gamma_1 psi_1 = 30/21 * 0.1 = 0.142857,
    # a_Z = 0.529402 * 0.142857 * 1.004988 = 0.076006 < a_g S = 0.2824: below T1 only our bound (beyond the
    # Circolare's, for T > T1) keeps the floor from moving less than the ground
    low = floor_spectrum_for(NTC, Building(n=10, H=35.0, T1=0.6), 1)
    assert math.isclose(float(low.formula(0.0)), 0.076006 * G, rel_tol=2e-5)
    assert math.isclose(low.pfa, 0.2824 * G, rel_tol=1e-9) and bool(low.bound_governs(0.0))
    assert low.bound_intervals()[0][0] == 0.0


# --- C7.2.11, framed buildings ------------------------------------------------------------------------
# Concrete frame, T1 = 0.5 s: Tab. C7.2.II's middle row (0.5 <= T1 <= 1.0): a 0.3, b 1.2, a_p 4; aT1 0.15, bT1 0.6;
# (1 + z/H) a_p = 5/3 * 4 = 6.666667 a_g S. T 0: 6.666667 / (1 + 3 * 1) = 1.666667; T 0.5: plateau 6.666667;
# T 1: (1 - 1/0.6)^2 = 0.444444, 6.666667 / 2.333333 = 2.857143; T 2: (1 - 2/0.6)^2 = 5.444444,
# 6.666667 / 17.333333 = 0.384615 < 1; T 4: (1 - 4/0.6)^2 = 32.111111, 6.666667 / 97.333333 = 0.068493 < 1:
# alpha S governs at 2 and 4 s (the old code gave 0.0685 a_g S at 4 s with no bound).
@pytest.mark.parametrize("ground, aS", [(NTC, 0.2824), (EC8, 0.2875)])
def test_framed_formula_by_hand(ground, aS):
    fl = floor_spectrum_for(ground, FRAME_05, 2, method="ntc2018-framed")
    assert fl.coefficients == (0.3, 1.2, 4.0)
    assert np.allclose(fl.Se(PERIODS), g(np.array([1.666667, 6.666667, 2.857143, 1.0, 1.0]) * aS), rtol=1e-6)
    assert np.allclose(fl.formula([2.0, 4.0]), g(np.array([0.384615, 0.068493]) * aS), rtol=1e-5)
    assert fl.bound_governs(PERIODS).tolist() == [False, False, False, True, True]
    # T 0.1 < aT1 = 0.15: (1 - 0.1/0.15)^2 = 0.111111, 6.666667 / (1 + 3 * 0.111111) = 5.0
    assert math.isclose(float(fl.Se(0.1)), 5.0 * aS * G, rel_tol=1e-9)


def test_table_rows_and_their_edges():
    assert ntc_framed_coefficients(0.4999) == (0.8, 1.4, 5.0)
    assert ntc_framed_coefficients(0.5) == (0.3, 1.2, 4.0)        # T1 = 0.5 s: the middle row
    assert ntc_framed_coefficients(1.0) == (0.3, 1.2, 4.0)
    assert ntc_framed_coefficients(1.0001) == (0.3, 1.0, 2.5)
    # first row, T1 0.4 s, z/H 1/2: aT1 0.32, bT1 0.56; at 4 s (1 - 4/0.56)^2 = 37.73, 1 + 4 * 37.73 = 151.9:
    # 1.5 * 5 / 151.9 = 0.0494 a_g S without the bound, a_g S with it
    fl = floor_spectrum(NTC, z=1, H=2, T1=0.4, code="ntc2018-framed")
    assert math.isclose(float(fl.Se(4.0)), 0.2824 * G) and math.isclose(float(fl.Se(0.4)), 7.5 * 0.2824 * G)


def test_framed_formula_refused_for_masonry():
    for structure in ("masonry", "other"):
        b = Building(n=3, H=12.0, T1=0.3, structure=structure)
        with pytest.raises(InputError, match="framed buildings only.*general formulation"):
            floor_spectrum_for(NTC, b, 2, method="ntc2018-framed")
    with pytest.raises(InputError, match="general formulation"):
        parse_floor("z=2,H=3,T1=0.4,n=3,structure=masonry,code=ntc2018-framed", NTC)
    assert parse_floor("z=2,H=3,T1=0.4,structure=steel-frame,code=ntc2018-framed", NTC).coefficients == (0.8, 1.4, 5.0)


# --- continuity, shape, units ------------------------------------------------------------------------
@pytest.mark.parametrize("method, building", [("ntc2018", MASONRY_03), ("ntc2018", MASONRY_06),
                                              ("ntc2018-framed", FRAME_05), ("ec8", MASONRY_03)])
def test_continuity_at_the_branch_joints(method, building):
    fl = floor_spectrum_for(NTC, building, 2, method=method)
    a, b = {"ntc2018": (0.8, 1.1), "ntc2018-framed": (0.3, 1.2), "ec8": (0.5, 1.0)}[method]
    for joint in (a * building.period, b * building.period, NTC.T_B, NTC.T_C, NTC.T_D):
        left, right = fl.formula([joint * (1 - 1e-9), joint * (1 + 1e-9)])
        assert math.isclose(left, right, rel_tol=1e-6)
        left, right = fl.Se([joint * (1 - 1e-9), joint * (1 + 1e-9)])
        assert math.isclose(left, right, rel_tol=1e-6)


def test_shape_displacement_and_refusals_of_periods():
    fl = floor_spectrum_for(NTC, MASONRY_03, 2)
    T = np.array([[0.0, 0.5], [1.0, 4.0]])
    assert fl.Se(T).shape == (2, 2) and np.all(np.isfinite(fl.Se(np.linspace(0, 10, 1001))))
    assert math.isclose(float(fl.SDe(1.0)), 0.317641 * G / (4 * math.pi ** 2), rel_tol=2e-5)
    with pytest.raises(InputError):
        fl.Se(-0.1)


def test_floor_zero_and_isolated_buildings():
    assert floor_spectrum_for(NTC, MASONRY_03, 0) is NTC                  # on the ground: the ground spectrum
    iso = Building(n=3, H=12.0, T1=2.5, structure="concrete-frame", isolated=True)
    fl = floor_spectrum_for(NTC, iso, 2, method="ntc2018-framed")
    # z = 0 (Circolare): T1 2.5 > 1: a 0.3, b 1.0, a_p 2.5; T 0: a_g S; on [0.75, 2.5): 2.5 a_g S
    assert fl.z_over_H == 0.0 and np.allclose(fl.Se([0.0, 1.0]), g([0.2824, 2.5 * 0.2824]))
    with pytest.raises(InputError, match="isolated"):
        floor_spectrum_for(NTC, iso, 2)                                  # the general formulation


def test_description_and_dict():
    fl = floor_spectrum_for(NTC, Building(n=3, H=12.0), 2)
    assert "\n" not in fl.text
    for part in ("general formulation", "C7.2.5", "floor 2 of 3", "masonry", "T1 0.322 s", "0.584 g"):
        assert part in fl.text
    d = json.loads(json.dumps(fl.to_dict(), allow_nan=False))
    assert d["kind"] == "floor" and d["method"] == "ntc2018" and "C7.2.5" in d["clause"]
    assert (d["n"], d["floor"], d["structure"], d["T1_estimated"], d["building_xi_percent"]) == (2 + 1, 2, "masonry",
                                                                                               True, 5.0)
    assert d["gamma_1"] == pytest.approx(9 / 7) and d["ground"]["code"] == "NTC2018"
    assert d["pfa_m_s2"] == pytest.approx(0.583835 * G, rel=2e-5)
    assert "C7.2.11" in floor_spectrum_for(NTC, FRAME_05, 1, "ntc2018-framed").to_dict()["clause"]


# --- the building ----------------------------------------------------------------------------------
def test_building_period_estimate():
    # T1 = C_t H^(3/4), 12^0.75 = 6.447420: masonry 0.05 -> 0.322371, concrete frame 0.075 -> 0.483556,
    # steel frame 0.085 -> 0.548031
    assert Building(n=3, H=12.0).period == pytest.approx(0.322371, rel=1e-6)
    assert Building(n=3, H=12.0, structure="concrete-frame").period == pytest.approx(0.483556, rel=1e-6)
    assert estimated_period(12.0, "steel-frame") == pytest.approx(0.548031, rel=1e-6)
    assert Building(n=3, H=12.0, T1=0.7).period == 0.7
    assert Building(n=12, H=50.0, T1=1.2).period == 1.2                   # too tall for the estimate: give T1
    with pytest.raises(InputError, match="40 m"):
        Building(n=12, H=50.0)


@pytest.mark.parametrize("kw", [dict(n=0), dict(n=2.5), dict(n=True), dict(H=-1.0), dict(H=float("nan")),
                                dict(T1=0.0), dict(T1=float("inf")), dict(structure="timber"), dict(xi=0.0),
                                dict(xi=100.0), dict(isolated="yes")])
def test_building_refusals(kw):
    args = dict(n=3, H=12.0) | kw
    with pytest.raises(InputError):
        Building(**args)


def test_floor_refusals():
    for floor in (-1, 4, 1.5, True, "2"):
        with pytest.raises(InputError, match="floor"):
            floor_spectrum_for(NTC, MASONRY_03, floor)
    with pytest.raises(InputError):
        floor_spectrum_for(NTC, MASONRY_03, 2, method="asce7")


# --- the older forms --------------------------------------------------------------------------------
def test_parse_floor():
    fl = parse_floor("z=2, H=3, t1=0.4, code=EC8", NTC)
    assert (fl.method, fl.z, fl.H, fl.T1) == ("ec8", 2.0, 3.0, 0.4) and fl.to_dict()["z_over_H"] == 2 / 3
    old = parse_floor("z=2,H=3,T1=0.3,n=3,code=ntc2018", NTC)            # the old code: now the general one
    assert old.method == "ntc2018"
    # z/H 2/3 with 3 storeys as in MASONRY_03: the same spectrum (only z/H, n, T1 matter)
    assert np.allclose(old.Se(PERIODS), g([0.583835, 1.037522, 0.317641, 0.158820, 0.047646]), rtol=2e-5)
    with pytest.raises(InputError, match="add n"):
        parse_floor("z=2,H=3,T1=0.4", NTC)                                # the default on NTC needs n
    assert parse_floor("z=2,H=3,T1=0.4", EC8).method == "ec8"             # the default on EC8 does not
    for bad in ["z=2,H=3", "z=4,H=3,T1=0.4,n=3", "z=2,H=3,T1=0,n=3", "z=2,H=3,T1=0.4,code=asce", "z=2,H=3,T1=x,n=3",
                "z=2,H=3,T1=0.4,z=1", "z2,H=3,T1=0.4", "z=2,H=3,T1=0.4,q=2", "z=2,H=3,T1=0.4,n=0",
                "z=2,H=3,T1=0.4,n=2.5", "z=2,H=3,T1=0.4,n=3,xi=0", "z=2,H=3,T1=0.4,n=3,structure=wood"]:
        with pytest.raises(InputError):
            parse_floor(bad, NTC)
