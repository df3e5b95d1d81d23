"""Elastic response spectra for isolator design: EN 1998-1:2004 §3.2.2.2 and NTC 2018 §3.2.3.2.1.

References are written out here, not taken from the module: the recommended values of
EC8 Tables 3.2 / 3.3, the NTC Tab. 3.2.IV formulas for S_S and C_C, Tab. 3.2.V for S_T,
and a hand-computed NTC spectrum.
"""
import json
import math

import numpy as np
import pytest

from statue2model.errors import InputError
from statue2model.hazard import code_spectra as D

G = 9.80665

# (S, T_B, T_C, T_D), EN 1998-1:2004 Table 3.2 (Type 1) and Table 3.3 (Type 2)
EC8_TYPE1 = {"A": (1.00, 0.15, 0.4, 2.0), "B": (1.20, 0.15, 0.5, 2.0), "C": (1.15, 0.20, 0.6, 2.0),
             "D": (1.35, 0.20, 0.8, 2.0), "E": (1.40, 0.15, 0.5, 2.0)}
EC8_TYPE2 = {"A": (1.00, 0.05, 0.25, 1.2), "B": (1.35, 0.05, 0.25, 1.2), "C": (1.50, 0.10, 0.25, 1.2),
             "D": (1.80, 0.10, 0.30, 1.2), "E": (1.60, 0.05, 0.25, 1.2)}


def all_spectra():
    out = [D.ec8(0.25 * G, g, t, xi) for g in "ABCDE" for t in (1, 2) for xi in (2.0, 5.0, 20.0)]
    out += [D.ntc2018(ag * G, 2.5, tc, s, topo, xi) for ag in (0.05, 0.3) for tc in (0.25, 0.45)
            for s in "ABCDE" for topo in ("T1", "T4") for xi in (5.0, 15.0)]
    return out


# --- EC8 tables ------------------------------------------------------------------------
@pytest.mark.parametrize("kind,table", [(1, EC8_TYPE1), (2, EC8_TYPE2)])
@pytest.mark.parametrize("ground", list("ABCDE"))
def test_ec8_table_values(kind, table, ground):
    sp = D.ec8(0.2 * G, ground, kind)
    assert (sp.S, sp.T_B, sp.T_C, sp.T_D) == table[ground]
    assert sp.code == f"EC8-{kind}" and sp.F0 == 2.5 and sp.eta == 1.0 and sp.xi == 5.0
    assert sp.a_g == pytest.approx(0.2 * G)


def test_ec8_ground_is_case_insensitive():
    assert D.ec8(2.0, "c") == D.ec8(2.0, "C")


# --- eta ------------------------------------------------------------------------------
def test_eta():
    assert D.damping_correction(5.0) == 1.0
    assert D.damping_correction(10.0) == pytest.approx(math.sqrt(10 / 15))
    assert D.damping_correction(0.0) == pytest.approx(math.sqrt(2.0))
    # floor 0.55 from xi = 10 / 0.55^2 - 5 = 28.06 %
    xi_floor = 10 / 0.55 ** 2 - 5
    assert D.damping_correction(xi_floor - 0.1) > 0.55
    assert D.damping_correction(xi_floor + 0.1) == 0.55
    assert D.damping_correction(100.0) == 0.55
    assert D.ec8(2.0, "A", 1, 40.0).eta == 0.55
    assert D.ntc2018(2.0, 2.5, 0.3, xi=40.0).eta == 0.55
    with pytest.raises(InputError, match="xi"):
        D.damping_correction(-1.0)


# --- shape --------------------------------------------------------------------------------
def test_plateau_values():
    sp = D.ec8(0.3 * G, "B")
    T = np.linspace(sp.T_B, sp.T_C, 11)
    np.testing.assert_allclose(sp.Se(T), 0.3 * G * 1.2 * 2.5, rtol=1e-14)
    sp = D.ec8(0.3 * G, "D", 2, 10.0)
    np.testing.assert_allclose(sp.Se([0.1, 0.2, 0.3]), 0.3 * G * 1.8 * 2.5 * math.sqrt(10 / 15), rtol=1e-14)
    sp = D.ntc2018(0.2 * G, 2.6, 0.35, "C", "T2")
    assert sp.plateau == pytest.approx(0.2 * G * sp.S * 2.6)
    np.testing.assert_allclose(sp.Se([sp.T_B, sp.T_C]), sp.plateau, rtol=1e-14)


def test_zero_period_is_a_g_S():
    for sp in all_spectra():
        assert float(sp.Se(0.0)) == pytest.approx(sp.a_g * sp.S, rel=1e-14)


@pytest.mark.parametrize("corner", ["T_B", "T_C", "T_D"])
def test_continuity_at_corners(corner):
    for sp in all_spectra():
        Tc = getattr(sp, corner)
        lo, at, hi = sp.Se([Tc * (1 - 1e-12), Tc, Tc * (1 + 1e-12)])
        assert lo == pytest.approx(at, rel=1e-9) and hi == pytest.approx(at, rel=1e-9)


def test_branches_ec8_written_out():
    ag, S, eta, TB, TC, TD = 0.25 * G, 1.15, math.sqrt(10 / 13), 0.2, 0.6, 2.0
    sp = D.ec8(ag, "C", 1, 8.0)
    T = np.array([0.0, 0.1, 0.4, 1.0, 3.0, 4.0, 6.0])
    ref = np.empty_like(T)
    ref[0] = ag * S
    ref[1] = ag * S * (1 + 0.1 / TB * (2.5 * eta - 1))
    ref[2] = ag * S * eta * 2.5
    ref[3] = ag * S * eta * 2.5 * TC / 1.0
    ref[4:] = ag * S * eta * 2.5 * TC * TD / T[4:] ** 2
    np.testing.assert_allclose(sp.Se(T), ref, rtol=1e-13)


def test_se_is_vectorised_and_keeps_shape():
    sp = D.ec8(2.0, "B")
    T = np.linspace(0, 5, 12).reshape(3, 4)
    out = sp.Se(T)
    assert out.shape == (3, 4)
    np.testing.assert_array_equal(out.ravel(), [float(sp.Se(t)) for t in T.ravel()])
    assert np.shape(sp.Se(1.0)) == ()


def test_sde():
    for sp in all_spectra()[::7]:
        T = np.array([0.0, 0.1, 0.5, 1.5, 2.5, 4.0, 6.0])
        np.testing.assert_allclose(sp.SDe(T), sp.Se(T) * T ** 2 / (4 * math.pi ** 2), rtol=1e-14)
    # beyond T_D the displacement spectrum is constant: a_g S eta F0 T_C T_D / (4 pi^2)
    sp = D.ec8(0.3 * G, "B")
    np.testing.assert_allclose(sp.SDe([2.0, 3.0, 4.0]), 0.3 * G * 1.2 * 2.5 * 0.5 * 2.0 / (4 * math.pi ** 2))


@pytest.mark.parametrize("T", [-0.1, float("nan"), float("inf")])
def test_bad_periods(T):
    with pytest.raises(InputError, match="periods"):
        D.ec8(2.0).Se([0.5, T])


# --- NTC 2018 -------------------------------------------------------------------------------
# Tab. 3.2.IV: lo <= c0 - c1 F0 ag/g <= hi ; C_C = k (Tc*)^e
NTC_REF = {"A": (1.00, 1.00, 0.00, 1.00, 1.00, 0.00), "B": (1.00, 1.40, 0.40, 1.20, 1.10, -0.20),
           "C": (1.00, 1.70, 0.60, 1.50, 1.05, -0.33), "D": (0.90, 2.40, 1.50, 1.80, 1.25, -0.50),
           "E": (1.00, 2.00, 1.10, 1.60, 1.15, -0.40)}


@pytest.mark.parametrize("soil", list("ABCDE"))
def test_ntc_ss_formula_and_bounds(soil):
    lo, c0, c1, hi, _, _ = NTC_REF[soil]
    F0 = 2.5
    for ag_g in np.linspace(0.01, 0.6, 60):
        S_S, _ = D.ntc_soil(soil, ag_g * G, F0, 0.3)
        assert S_S == pytest.approx(min(hi, max(lo, c0 - c1 * F0 * ag_g)), abs=1e-12)
        assert lo <= S_S <= hi


def test_ntc_ss_bounds_reached():
    # B: 1.40 - 0.40 x ; x = F0 ag/g = 0.25 -> 1.30 capped at 1.20 ; x = 1.2 -> 0.92 floored at 1.00
    assert D.ntc_soil("B", 0.1 * G, 2.5, 0.3)[0] == 1.20
    assert D.ntc_soil("B", 0.48 * G, 2.5, 0.3)[0] == 1.00
    assert D.ntc_soil("B", 0.5 * G, 1.0, 0.3)[0] == pytest.approx(1.20)
    assert D.ntc_soil("B", 0.25 * G, 2.4, 0.3)[0] == pytest.approx(1.16)  # in between
    # C: 1.70 - 0.60 x in [1.00, 1.50]
    assert D.ntc_soil("C", 0.1 * G, 2.5, 0.3)[0] == 1.50
    assert D.ntc_soil("C", 0.3 * G, 2.5, 0.3)[0] == pytest.approx(1.25)
    # D: 2.40 - 1.50 x in [0.90, 1.80]
    assert D.ntc_soil("D", 0.05 * G, 2.5, 0.3)[0] == 1.80
    assert D.ntc_soil("D", 0.5 * G, 2.5, 0.3)[0] == 0.90
    assert D.ntc_soil("D", 0.3 * G, 2.5, 0.3)[0] == pytest.approx(1.275)
    # E: 2.00 - 1.10 x in [1.00, 1.60]
    assert D.ntc_soil("E", 0.1 * G, 2.5, 0.3)[0] == 1.60
    assert D.ntc_soil("E", 0.3 * G, 2.5, 0.3)[0] == pytest.approx(1.175)


@pytest.mark.parametrize("soil", list("ABCDE"))
def test_ntc_cc(soil):
    *_, k, e = NTC_REF[soil]
    for tc in (0.2, 0.3, 0.45, 0.6):
        assert D.ntc_soil(soil, 0.2 * G, 2.5, tc)[1] == pytest.approx(k * tc ** e, rel=1e-14)
        sp = D.ntc2018(0.2 * G, 2.5, tc, soil)
        assert sp.T_C == pytest.approx(k * tc ** e * tc, rel=1e-14)
        assert sp.T_B == pytest.approx(sp.T_C / 3, rel=1e-14)


def test_ntc_topography():
    base = D.ntc2018(0.2 * G, 2.5, 0.3, "C", "T1")
    for topo, st in {"T1": 1.0, "T2": 1.2, "T3": 1.2, "T4": 1.4}.items():
        sp = D.ntc2018(0.2 * G, 2.5, 0.3, "C", topo)
        assert sp.S == pytest.approx(base.S * st)
        assert (sp.T_B, sp.T_C, sp.T_D) == (base.T_B, base.T_C, base.T_D)


def test_ntc_hand_computed():
    # a_g = 0.25 g, F0 = 2.4, Tc* = 0.30 s, subsoil B, T2, xi = 5 %
    # S_S = 1.40 - 0.40 * 2.4 * 0.25 = 1.16 (within [1.00, 1.20]); S = 1.16 * 1.2 = 1.392
    # C_C = 1.10 * 0.30^-0.20 = 1.10 * 1.2722596 = 1.3994856 ; T_C = 0.4198457 s ; T_B = 0.1399486 s
    # T_D = 4.0 * 0.25 + 1.6 = 2.6 s ; plateau = 0.25 * 1.392 * 2.4 = 0.83520 g
    sp = D.ntc2018(0.25 * G, 2.4, 0.30, "B", "T2")
    assert sp.code == "NTC2018" and sp.F0 == 2.4 and sp.eta == 1.0
    assert sp.S == pytest.approx(1.392, abs=1e-12)
    assert sp.T_C == pytest.approx(0.4198457, abs=1e-7)
    assert sp.T_B == pytest.approx(0.1399486, abs=1e-7)
    assert sp.T_D == pytest.approx(2.6, abs=1e-12)
    g = sp.Se([0.0, 0.07, 0.3, 1.0, 3.0]) / G
    # T = 0.07: 0.25*1.392*2.4*[0.07/0.1399486 + (1 - 0.07/0.1399486)/2.4] = 0.522...
    x = 0.07 / 0.13994856
    np.testing.assert_allclose(g, [0.348, 0.8352 * (x + (1 - x) / 2.4), 0.8352, 0.8352 * 0.41984568 / 1.0,
                                   0.8352 * 0.41984568 * 2.6 / 9.0], rtol=1e-6)
    np.testing.assert_allclose(g[3], 0.350655, rtol=1e-5)


def test_ntc_td_formula():
    for ag_g in (0.05, 0.15, 0.35):
        assert D.ntc2018(ag_g * G, 2.5, 0.3).T_D == pytest.approx(4.0 * ag_g + 1.6)


def test_ntc_first_branch_matches_code_form():
    sp = D.ntc2018(0.2 * G, 2.7, 0.4, "D", "T1", 12.0)
    T = np.linspace(0, sp.T_B, 9)
    code = sp.a_g * sp.S * sp.eta * sp.F0 * (T / sp.T_B + (1 - T / sp.T_B) / (sp.eta * sp.F0))
    np.testing.assert_allclose(sp.Se(T), code, rtol=1e-14)


# --- input errors -------------------------------------------------------------------------
@pytest.mark.parametrize("call,match", [
    (lambda: D.ec8(2.0, "S1"), "'S1'"),
    (lambda: D.ec8(2.0, "F"), "'F'"),
    (lambda: D.ec8(2.0, "A", 3), "type must be 1 or 2, got 3"),
    (lambda: D.ec8(-1.0), "a_g"),
    (lambda: D.ec8(float("nan")), "a_g"),
    (lambda: D.ntc2018(2.0, 2.5, 0.3, "X"), "'X'"),
    (lambda: D.ntc2018(2.0, 2.5, 0.3, "A", "T5"), "'T5'"),
    (lambda: D.ntc2018(2.0, 0.0, 0.3), "F0"),
    (lambda: D.ntc2018(2.0, 2.5, -0.3), "Tc"),
    (lambda: D.ElasticSpectrum("X", 1.0, 1.0, 1.0, 2.5, 0.5, 0.4, 2.0), "T_B < T_C < T_D"),
])
def test_input_errors(call, match):
    with pytest.raises(InputError, match=match) as e:
        call()
    assert "\n" not in str(e.value)


# --- dataclass, dict, command-line form ----------------------------------------------------
def test_frozen_and_to_dict():
    sp = D.ec8(0.25 * G, "C", 1, 5)
    with pytest.raises(AttributeError):
        sp.S = 2.0
    d = sp.to_dict()
    assert d == {"code": "EC8-1", "a_g": pytest.approx(0.25 * G), "S": 1.15, "eta": 1.0, "F0": 2.5,
                 "T_B": 0.2, "T_C": 0.6, "T_D": 2.0, "xi": 5.0, "limit_state": None}
    assert D.ElasticSpectrum(**json.loads(json.dumps(d))) == sp
    n = D.parse_spectrum("ntc2018:ag=0.1g,F0=2.5,Tc=0.3,soil=C,ls=slv")
    assert n.limit_state == "SLV" and D.ElasticSpectrum(**json.loads(json.dumps(n.to_dict()))) == n
    with pytest.raises(InputError, match="limit state"):
        D.parse_spectrum("ntc2018:ag=0.1g,F0=2.5,Tc=0.3,ls=ULS")


@pytest.mark.parametrize("text,ref", [
    ("ec8:ag=0.25g,ground=C,type=1,xi=5", lambda: D.ec8(0.25 * G, "C", 1, 5.0)),
    ("EC8: ag = 2.4516625 m/s2 , ground = c", lambda: D.ec8(2.4516625, "C")),
    ("ec8:ag=0.3g,type=2,ground=D,xi=15", lambda: D.ec8(0.3 * G, "D", 2, 15.0)),
    ("ec8:ag=3m/s2", lambda: D.ec8(3.0)),
    ("ntc2018:ag=0.2g,F0=2.4,Tc=0.3,soil=B,topo=T1", lambda: D.ntc2018(0.2 * G, 2.4, 0.3, "B", "T1")),
    ("ntc2018:ag=1.5m/s^2,f0=2.6,tc=0.45,soil=e,topo=t3,xi=10", lambda: D.ntc2018(1.5, 2.6, 0.45, "E", "T3", 10.0)),
    ("ntc2018:ag=0.1g,F0=2.5,Tc=0.28", lambda: D.ntc2018(0.1 * G, 2.5, 0.28)),
])
def test_parse_spectrum(text, ref):
    assert D.parse_spectrum(text) == ref()


def test_parse_round_trip_through_to_dict():
    sp = D.parse_spectrum("ec8:ag=0.35g,ground=E,type=2,xi=12")
    d = sp.to_dict()
    again = D.parse_spectrum(f"ec8:ag={d['a_g']!r}m/s2,ground=E,type={d['code'][-1]},xi={d['xi']!r}")
    assert again == sp
    sp = D.parse_spectrum("ntc2018:ag=0.22g,F0=2.45,Tc=0.33,soil=D,topo=T2,xi=7")
    again = D.parse_spectrum(f"ntc2018:ag={sp.a_g!r}m/s2,F0={sp.F0!r},Tc=0.33,soil=D,topo=T2,xi={sp.xi!r}")
    assert again == sp


@pytest.mark.parametrize("text,match", [
    ("ec9:ag=0.2g", "'ec9'"),
    ("ec8", "no parameters"),
    ("ec8:", "no parameters"),
    ("ec8:ground=B", "lacks ag"),
    ("ec8:ag=0.2g,soil=B", "unknown key 'soil'"),
    ("ec8:ag=0.2g,ground", "'ground'"),
    ("ec8:ag=0.2g,ground=", "'ground='"),
    ("ec8:ag=0.2g,,ground=B", "''"),
    ("ec8:ag=0.2g,ag=0.3g", "'ag' is given twice"),
    ("ec8:ag=abc", "'abc'"),
    ("ec8:ag=0.2gg", "'0.2gg'"),
    ("ec8:ag=-0.2g", "'-0.2g'"),
    ("ec8:ag=0.2g,type=3", "type must be 1 or 2, got '3'"),
    ("ec8:ag=0.2g,ground=S2", "'S2'"),
    ("ec8:ag=0.2g,xi=lots", "'lots'"),
    ("ntc2018:ag=0.2g,F0=2.4", "lacks tc"),
    ("ntc2018:ag=0.2g,F0=x,Tc=0.3", "'x'"),
    ("ntc2018:ag=0.2g,F0=2.4,Tc=0.3,soil=Z", "'Z'"),
    ("ntc2018:ag=0.2g,F0=2.4,Tc=0.3,topo=T9", "'T9'"),
    ("ntc2018:ag=0.2g,F0=2.4,Tc=0.3,ground=B", "unknown key 'ground'"),
])
def test_parse_spectrum_errors(text, match):
    with pytest.raises(InputError, match=match) as e:
        D.parse_spectrum(text)
    assert "\n" not in str(e.value)
