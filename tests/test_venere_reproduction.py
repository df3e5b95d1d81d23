"""The thesis' Venere Landolina case (ch. 6.3.2 and 6.4) reproduced from the thesis' INPUTS, step
by step, each step checked against a value computed here by plain math; then set beside the
thesis' own numbers. Nothing is solved from the thesis' answer (docs/venere.md tells the story).

Inputs and their sources (thesis: /work/shared/seed/000_de54c32822c7e0fc.txt, ch. 6.3.2 at
line 2013, ch. 6.4 at lines 2075-2077, Tables 22, 24-26):

* site: the Paolo Orsi museum, Viale Teocrito 66, Syracuse, about 37.0756 N, 15.2866 E
  (thesis: "Syracuse, Italy"); subsoil C, topography T1; limit state SLA (thesis, line 2013);
* hazard: NTC 2008 Allegato B, Tabella 1 (the grid NTC 2018 par. 3.2 keeps), the four points
  around the site, IDs 49645, 49646, 49867, 49868 (typed below from the table), combined as
  Allegato A asks: inverse-distance weights (eq. 2), logarithmic interpolation in T_R (eq. 1);
* return period: NOT in the thesis' text (V_N, c_u, n, T_R, a_g, F0, T_C* are printed only in
  its Fig. 117a). Assumed: the SLA at the damage level (Direttiva P.C.M. 9/2/2011 par. 2.3:
  "in genere quello preso in considerazione per lo stato limite di danno"), NTC 2018 SLD
  P_VR = 63 % in V_R = V_N c_u = 50 x 1.5 (a museum: class III) -> T_R = 75.4 years;
* floor: the second of three storeys, interstoreys 4.0 m -> z = 8.0 m, H = 11.5 m, building
  period T1 = 0.32 s as the thesis states (C H^(3/4) with C = 0.05 gives 0.312 s); a masonry
  museum: the Circolare 2019 general formulation C7.2.5-C7.2.10 (statue2model.hazard.floor);
* Froude: the 1:2 prototype's records are the full-scale ones with times / sqrt(2), so a device
  period T on the prototype reads the full-scale spectrum at sqrt(2) T;
* the device: R_hat ~ 0.60 m -> T = 1.55 s, four grooves, mu = 0.0073 (Table 25), stroke 0.15 m;
  the statue: Table 24 (m, h, b_L, b_R, I_G), alpha_L = 0.159, alpha_R = 0.175 (Table 22).

Tolerances: code against hand values rel 1e-4 (the hand weights below use a flat-earth
distance, the code the great circle: over 7 km the weights differ by less than 1e-5) or exact
where the same formula is evaluated. The thesis' numbers are compared, not fitted: the
design acceleration ours/thesis is asserted as it comes out (+10.6 %), with the interval our
inputs imply around it.
"""
from __future__ import annotations

import math

import pytest

from statue2model.geometry.rocking_params import RockingParams
from statue2model.hazard.code_spectra import G as G0
from statue2model.hazard.floor import floor_spectrum
from statue2model.hazard.froude_spectrum import FroudeSpectrum
from statue2model.hazard.ntc_grid import (
    PAOLO_ORSI,
    PAOLO_ORSI_CELL,
    RETURN_PERIODS,
    return_period,
    site_parameters,
    site_spectrum,
)
from statue2model.isolator.design import assess

SITE = (15.2866, 37.0756)                     # lon E, lat N of the museum
# Tabella 1 rows, the columns of T_R = 72 and 101 years: ID, LON, LAT, (a_g in g/10, F0, T_C*) x 2
TABELLA_1 = {49867: (15.23836, 37.07074, (0.6912, 2.5161, 0.28241), (0.87773, 2.3933, 0.30627)),
             49868: (15.30073, 37.06970, (0.6259, 2.5211, 0.28337), (0.76696, 2.4963, 0.29606)),
             49645: (15.23965, 37.12073, (0.7053, 2.5149, 0.28360), (0.89395, 2.3932, 0.30807)),
             49646: (15.30205, 37.11969, (0.6398, 2.5178, 0.28474), (0.77856, 2.4754, 0.31259))}
VENERE = RockingParams.from_dict({"m": 12.074, "h": 0.3523, "b_L": 0.1995, "b_R": 0.0805, "I_G": 0.7994})
ALPHA = (0.159, 0.175)                        # Table 22
MU = 0.0073                                   # Table 25 at 16.433 kg
T_R = -50 * 1.5 / math.log(1 - 0.63)          # 75.434 years
Z, H, N, T1 = 8.0, 11.5, 3, 0.32              # floor 2 of 3 at 2 x 4.0 m; the thesis' T_s
THESIS_A_DESIGN = 0.3917                      # m/s^2, ch. 6.4
THESIS_UPLIFT = 0.3924                        # m/s^2 (0.040 g, Table 22), ch. 6.4
THESIS_STROKE = 0.15                          # m, ch. 6.4
TABLE_26_FIXED = (3.117, 3.111, 3.133, 3.117, 3.075, 3.133, 3.127)   # m/s^2, peak table acceleration


def _hand_site():
    """(a_g in g, F0, T_C*) at the site by Allegato A, by hand: flat-earth distances (km) to the
    four points, weights 1/d normalised, then eq. 1 between 72 and 101 years."""
    c = math.cos(math.radians(SITE[1]))
    d = {k: 6371.0 * math.radians(1.0) * math.hypot((lon - SITE[0]) * c, lat - SITE[1])
         for k, (lon, lat, _, _) in TABELLA_1.items()}
    # d = 4.314 (49867), 1.415 (49868), 6.522 (49645), 5.091 (49646) km
    inv = {k: 1.0 / v for k, v in d.items()}
    w = {k: v / sum(inv.values()) for k, v in inv.items()}
    # w = 0.1799, 0.5486, 0.1190, 0.1525
    f = math.log(T_R / 72) / math.log(101 / 72)                         # 0.13764
    out = []
    for j in range(3):
        p1 = sum(w[k] * TABELLA_1[k][2][j] for k in w)
        p2 = sum(w[k] * TABELLA_1[k][3][j] for k in w)
        out.append(math.exp(math.log(p1) + math.log(p2 / p1) * f))
    # a_g: 0.64922 (72 y), 0.80377 (101 y) -> 0.66858 g/10; F0 2.5190, 2.4623 -> 2.5111;
    # T_C* 0.28343, 0.30185 -> 0.28590 s
    return out[0] / 10.0, out[1], out[2]


@pytest.fixture(scope="module")
def chain():
    """The package's chain from the inputs: ground spectrum, floor spectrum, prototype spectrum."""
    ground = site_spectrum(PAOLO_ORSI_CELL, *PAOLO_ORSI, T_R, soil="C", topography="T1", limit_state="SLA")
    floor = floor_spectrum(ground, z=Z, H=H, T1=T1, code="ntc2018", n=N, structure="masonry")
    return ground, floor, FroudeSpectrum(floor, 2.0)


def test_the_four_grid_points_surround_the_museum():
    ids = sorted(p.id for p in PAOLO_ORSI_CELL)
    assert ids == [49645, 49646, 49867, 49868] and PAOLO_ORSI == SITE
    assert 49868 - 49867 == 1 and 49867 - 49645 == 222           # Tabella 1: east +1, north -222
    lons, lats = [p.lon for p in PAOLO_ORSI_CELL], [p.lat for p in PAOLO_ORSI_CELL]
    assert max(lons[::2]) < SITE[0] < min(lons[1::2]) and max(lats[:2]) < SITE[1] < min(lats[2:])
    for p in PAOLO_ORSI_CELL:                                       # the module's constant is the table
        k72, k101 = RETURN_PERIODS.index(72), RETURN_PERIODS.index(101)
        lon, lat, c72, c101 = TABELLA_1[p.id]
        assert (p.lon, p.lat) == (lon, lat)
        assert (p.ag[k72] * 10, p.F0[k72], p.Tc[k72]) == pytest.approx(c72, rel=1e-12)
        assert (p.ag[k101] * 10, p.F0[k101], p.Tc[k101]) == pytest.approx(c101, rel=1e-12)


def test_return_period_and_site_parameters_by_hand():
    assert return_period(50, 1.5, 0.63) == pytest.approx(75.4336, abs=1e-4)   # -75 / ln 0.37
    ag, F0, Tc = _hand_site()
    assert (ag, F0, Tc) == pytest.approx((0.066858, 2.51109, 0.285900), rel=1e-5)
    got = site_parameters(PAOLO_ORSI_CELL, *SITE, T_R)
    assert got == pytest.approx((ag * G0, F0, Tc), rel=1e-4)


def test_ground_spectrum_by_hand(chain):
    ground, _, _ = chain
    ag, F0, Tc = _hand_site()
    S_S = min(1.5, max(1.0, 1.70 - 0.60 * F0 * ag))                # 1.599 -> 1.5 (Tab. 3.2.IV, soil C)
    T_C = 1.05 * Tc ** -0.33 * Tc                                   # C_C 1.5872 -> 0.45379 s
    T_D = 4.0 * ag + 1.6                                            # 1.86743 s
    assert S_S == 1.5 and ground.S == 1.5 and ground.limit_state == "SLA"
    assert (ground.T_B, ground.T_C, ground.T_D) == pytest.approx((T_C / 3, T_C, T_D), rel=1e-4)
    assert float(ground.Se(0.0)) == pytest.approx(ag * G0 * 1.5, rel=1e-4)         # 0.98349 m/s^2
    assert ground.plateau == pytest.approx(ag * G0 * 1.5 * F0, rel=1e-4)            # 2.46962 m/s^2


def test_floor_spectrum_by_hand(chain):
    """Circolare general formulation, first mode linear with height, at z = 8.0 m of 11.5 m."""
    ground, floor, _ = chain
    agS, F0, T_C, T_D = ground.a_g * ground.S, ground.F0, ground.T_C, ground.T_D
    a_Z = agS * F0 * (9 / 7) * (8.0 / 11.5) * math.sqrt(1 + 0.0004 * 5 ** 2)   # T1 = 0.32 s on the plateau
    A = 1.1 / math.sqrt(0.05)                                                   # 4.9193
    assert floor.a_Z == pytest.approx(a_Z, rel=1e-12) and floor.A == pytest.approx(A, rel=1e-12)
    assert floor.pfa == pytest.approx(2.21987, rel=1e-4)                        # m/s^2 = 0.226 g
    T_f = math.sqrt(2) * 2 * math.pi * math.sqrt(0.60 / 9.81)                   # 2.19754 s
    first_mode = A * a_Z / (1 + (A - 1) * (T_f / (1.1 * T1) - 1) ** 1.2)       # 0.36865 m/s^2
    bound = agS * F0 * T_C * T_D / T_f ** 2                                     # T_f > T_D: 0.43337 m/s^2
    assert float(floor.formula(T_f)) == pytest.approx(first_mode, rel=1e-12)
    assert float(floor.Se(T_f)) == pytest.approx(bound, rel=1e-12) and bound > first_mode
    assert (first_mode, bound) == pytest.approx((0.368647, 0.433367), rel=1e-4)


def test_froude_step(chain):
    _, floor, proto = chain
    T_p = 2 * math.pi * math.sqrt(0.60 / 9.81)                                  # 1.55389 s on the prototype
    assert float(proto.Se(T_p)) == float(floor.Se(math.sqrt(2) * T_p))
    assert float(proto.SDe(T_p)) == pytest.approx(float(floor.SDe(math.sqrt(2) * T_p)) / 2, rel=1e-12)
    assert proto.pga == floor.pfa


def test_the_thesis_device_on_the_reproduced_spectrum(chain):
    """Ch. 6.4: design acceleration 0.3917 m/s^2 at T = 1.55 s below the uplift 0.3924 m/s^2;
    stroke 0.15 m. The device is the one tests/test_isolator_design.py builds for it
    (R = 0.32 m, r = 0.020 m: R_hat = 0.60 m)."""
    _, floor, proto = chain
    d = assess(VENERE, R=0.32, r=0.020, n_grooves=4, opening_radius=0.080, spacing=0.27, side=0.47,
               thickness=0.03, mu=MU, spectrum=proto, alpha=ALPHA)
    assert d.T == pytest.approx(1.5539, abs=1e-4)
    # design acceleration: the full-scale floor spectrum at sqrt(2) T = 2.1975 s, where the ground
    # spectrum bounds it (test_floor_spectrum_by_hand): 0.43337 m/s^2, 10.6 % above the thesis'
    assert d.a_design == pytest.approx(0.433367, rel=1e-4)
    assert d.a_design / THESIS_A_DESIGN == pytest.approx(1.1064, abs=1e-3)
    # the thesis' value lies in what these inputs give at the full-scale period: between the
    # Circolare's first-mode term (0.3686) and its lower bound, the ground spectrum (0.4334)
    assert float(floor.formula(d.T * math.sqrt(2))) < THESIS_A_DESIGN < d.a_design
    # read at the prototype's own period (no Froude) the same spectrum gives 0.7212 m/s^2: +84 %
    assert float(floor.Se(d.T)) == pytest.approx(0.721209, rel=1e-4)
    # uplift: alpha_R g b_R / h = 0.175 x 9.81 x 0.0805 / 0.3523 = 0.39227 m/s^2 (thesis 0.040 g)
    assert d.a_lim == pytest.approx(0.175 * 9.81 * 0.0805 / 0.3523, rel=1e-9)
    assert abs(d.a_lim / THESIS_UPLIFT - 1) < 5e-4
    # so on these inputs the thesis' device lets the statue feel 10 % more than its uplift
    assert not d.passed and d.failure.startswith("plate acceleration below the statue's uplift limit")
    assert next(c for c in d.checks if c.key == "acceleration").ratio == pytest.approx(1.1048, abs=1e-3)
    # travel: SDe on the prototype = a T^2 / (4 pi^2) = 0.026506 m; with the 1.5 margin and the
    # offset friction may leave at its upper bound, mu_high R_hat (mu x 0.0108 / 0.0073): 0.04624 m,
    # within the thesis' 0.15 m stroke (and the grooves' 0.15 m here)
    assert d.d_design == pytest.approx(0.433367 * 1.5539 ** 2 / (4 * math.pi ** 2), rel=1e-3)
    assert d.travel_need == pytest.approx(1.5 * d.d_design + MU * 0.0108 / 0.0073 * 0.60, rel=1e-9)
    assert d.travel_need < THESIS_STROKE and d.capacity_groove == pytest.approx(THESIS_STROKE, abs=5e-4)


def test_the_floor_acceleration_against_table_26(chain):
    """Table 26: the records drove the fixed-base prototype to 3.075-3.133 m/s^2 (mean 3.116).
    Our SLA floor spectrum peaks at 2.220 m/s^2 (71 %): on the same floor formula the table's
    peak lies between T_R = 101 and 140 years (grid columns), not at 75."""
    _, floor, _ = chain
    assert floor.pfa / (sum(TABLE_26_FIXED) / len(TABLE_26_FIXED)) == pytest.approx(0.7124, abs=1e-3)

    def pfa(years):
        g = site_spectrum(PAOLO_ORSI_CELL, *SITE, years, soil="C")
        return floor_spectrum(g, z=Z, H=H, T1=T1, code="ntc2018", n=N, structure="masonry").pfa

    assert pfa(101) < min(TABLE_26_FIXED) and max(TABLE_26_FIXED) < pfa(140)        # 2.617, 3.179 m/s^2
