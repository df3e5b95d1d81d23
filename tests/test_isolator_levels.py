"""The collapse level (SLC) the isolator is checked at (hazard/levels.py, MODEL.md section 9) and the band
a design set covers for an isolator (hazard/matching.py design_band), against hand computations."""
from __future__ import annotations

import math

import numpy as np
import pytest

from statue2model.errors import InputError
from statue2model.hazard.code_spectra import G, parse_spectrum
from statue2model.hazard.levels import collapse_site, collapse_spectrum_text
from statue2model.hazard.matching import design_band
from statue2model.hazard.site import site_hazard

PERIODS = np.array([0.0, 0.05, 0.15, 0.4, 0.6, 1.0, 2.0, 3.0, 4.0])


# --- EC8: the design spectrum x gamma_x 1.2 ----------------------------------------------------------------
def test_ec8_collapse_level_is_the_design_spectrum_times_gamma_x():
    text, why = collapse_spectrum_text("ec8:ag=0.25g,ground=C,type=1")
    assert text == "ec8:ag=0.3g,ground=C,type=1" and "10.3(2)" in why and "1.2" in why
    design, slc = parse_spectrum("ec8:ag=0.25g,ground=C,type=1"), parse_spectrum(text)
    assert slc.a_g == pytest.approx(0.25 * G * 1.2, rel=1e-12)
    # S, T_B, T_C, T_D of ground C do not depend on a_g: every ordinate x 1.2, displacements too
    assert (slc.S, slc.T_B, slc.T_C, slc.T_D) == (design.S, design.T_B, design.T_C, design.T_D)
    assert np.allclose(slc.Se(PERIODS), 1.2 * design.Se(PERIODS), rtol=1e-12, atol=0)
    assert np.allclose(slc.SDe(PERIODS[1:]), 1.2 * design.SDe(PERIODS[1:]), rtol=1e-12, atol=0)
    # by hand on the plateau and past T_D (EN 1998-1 eq. 3.2 and 3.4, ground C type 1: S 1.15, T_C 0.6, T_D 2)
    assert float(slc.Se(0.4)) == pytest.approx(1.2 * 0.25 * G * 1.15 * 2.5, rel=1e-12)
    assert float(slc.Se(3.0)) == pytest.approx(1.2 * 0.25 * G * 1.15 * 2.5 * 0.6 * 2.0 / 9.0, rel=1e-12)
    # other keys are kept as written
    assert collapse_spectrum_text("ec8:ag=0.1g,ground=B,type=2")[0] == "ec8:ag=0.12g,ground=B,type=2"


# --- NTC --------------------------------------------------------------------------------------------------
NTC_SLA = "ntc2018:ag=0.0669g,F0=2.511,Tc=0.286,soil=C,topo=T1,ls=SLA"


def ntc_soil_C_by_hand(ag_g: float, F0: float) -> tuple[float, float]:
    """NTC 2018 3.2.3.2.1 (Tab. 3.2.IV soil C, T1): S_S and T_D = 4 a_g / g + 1.6."""
    return min(1.5, max(1.0, 1.7 - 0.6 * F0 * ag_g)), 4 * ag_g + 1.6


def test_ntc_without_the_sites_slc_parameters_scales_a_g_by_the_return_periods():
    text, why = collapse_spectrum_text(NTC_SLA)
    factor = (math.log(1 - 0.63) / math.log(1 - 0.05)) ** (1 / 1.6)    # SLA (P_VR 63 %) -> SLC (5 %): 6.38
    assert factor == pytest.approx(6.38, abs=0.005)
    slc, design = parse_spectrum(text), parse_spectrum(NTC_SLA)
    assert slc.limit_state == "SLC" and text.endswith(",ls=SLC") and text.count("ls=") == 1
    assert slc.a_g == pytest.approx(0.0669 * G * factor, rel=5e-6)      # the text keeps 6 digits
    ag = slc.a_g / G
    # F0 kept, T_C* scaled by the T_R ratio ^ 0.2 (19.38 ^ 0.2 = 1.81; the text keeps 6 digits); T_C = C_C T_C*
    tc = 0.286 * (math.log(1 - 0.63) / math.log(1 - 0.05)) ** 0.2
    assert tc == pytest.approx(0.5174, abs=1e-4)
    assert slc.F0 == 2.511 and slc.T_C == pytest.approx(1.05 * tc ** -0.33 * tc, rel=5e-6)
    assert slc.T_C > design.T_C
    S_S, T_D = ntc_soil_C_by_hand(ag, 2.511)
    assert S_S == pytest.approx(1.7 - 0.6 * 2.511 * ag) and 1.0 < S_S < 1.5       # 1.057: off both bounds
    assert slc.S == pytest.approx(S_S, rel=1e-12) and slc.T_D == pytest.approx(T_D, rel=1e-12)
    S_S0, T_D0 = ntc_soil_C_by_hand(0.0669, 2.511)
    assert design.S == pytest.approx(S_S0) and S_S0 == 1.5 and design.T_D == pytest.approx(T_D0)
    assert float(slc.Se(0.0)) == pytest.approx(ag * G * S_S, rel=1e-12)
    assert "an approximation" in why and "SLA" in why and "T_C*" in why


def test_a_spectrum_without_a_limit_state_is_read_as_slv():
    text, why = collapse_spectrum_text("ntc2018:ag=0.1g,F0=2.5,Tc=0.3,soil=B")
    factor = (math.log(1 - 0.10) / math.log(1 - 0.05)) ** (1 / 1.6)       # 2.05 ^ (1 / 1.6) = 1.57
    assert parse_spectrum(text).a_g == pytest.approx(0.1 * G * factor, rel=5e-6)    # 6 digits
    assert "read as SLV" in why and text.endswith("ls=SLC")
    # an SLC spectrum is already the collapse level
    same = "ntc2018:ag=0.3g,F0=2.5,Tc=0.3,soil=B,ls=SLC"
    assert collapse_spectrum_text(same)[0] == same


def test_the_sites_own_slc_spectrum_is_taken_as_given():
    given = "ntc2018:ag=0.2g,F0=2.6,Tc=0.35,soil=C,topo=T1,ls=SLC"
    text, why = collapse_spectrum_text(NTC_SLA, slc=given)
    assert text == given and "as given" in why
    with pytest.raises(InputError, match="below the design spectrum's"):
        collapse_spectrum_text(NTC_SLA, slc="ntc2018:ag=0.05g,F0=2.6,Tc=0.35,soil=C,ls=SLC")
    with pytest.raises(InputError, match="slc_spectrum is EC8-1 but the design spectrum is NTC2018"):
        collapse_spectrum_text(NTC_SLA, slc="ec8:ag=0.3g,ground=C")
    with pytest.raises(InputError):                                           # malformed: its own line
        collapse_spectrum_text(NTC_SLA, slc="ntc2018:ag=0.3g")


def test_the_slc_of_the_paolo_orsi_site_from_the_hazard_grid():
    """V_R 50 years: SLV 475 years, SLC 975 (T_R = -V_R / ln(1 - P_VR)); both are grid return periods."""
    from statue2model.hazard.ntc_grid import PAOLO_ORSI, PAOLO_ORSI_CELL, return_period, site_parameters, \
        site_spectrum

    assert return_period(50, 1.0, 0.05) == pytest.approx(975, abs=0.5)
    slv = site_spectrum(PAOLO_ORSI_CELL, *PAOLO_ORSI, 475, soil="C", limit_state="SLV")
    slc = site_spectrum(PAOLO_ORSI_CELL, *PAOLO_ORSI, 975, soil="C", limit_state="SLC")
    assert slc.a_g > slv.a_g and np.all(slc.Se(PERIODS) > slv.Se(PERIODS))

    def text(T_R, ls):
        ag, F0, Tc = site_parameters(PAOLO_ORSI_CELL, *PAOLO_ORSI, T_R)
        return f"ntc2018:ag={ag / G:.6g}g,F0={F0:.6g},Tc={Tc:.6g},soil=C,topo=T1,ls={ls}"

    t475, t975 = text(475, "SLV"), text(975, "SLC")
    assert parse_spectrum(t975).a_g == pytest.approx(slc.a_g, rel=1e-5)
    assert collapse_spectrum_text(t475, slc=t975) == (t975, "the site's SLC spectrum as given ([isolator] "
                                                            "slc_spectrum)")
    # without it, the K_HAZARD 1.6 scaling is the conservative reading here (the grid's slope is about 2)
    approx = parse_spectrum(collapse_spectrum_text(t475)[0])
    slope = math.log(975 / 475) / math.log(slc.a_g / slv.a_g)
    assert 1.6 < slope < 2.2 and approx.a_g > slc.a_g


def test_collapse_site_keeps_the_building_and_floor():
    site = site_hazard("ec8:ag=0.25g,ground=C", floor=2, storeys=3, height=11.5, period=0.32)
    hz, why = collapse_site(site)
    assert hz.spectrum == "ec8:ag=0.3g,ground=C" and "gamma_x" in why
    assert hz.floor == site.floor and hz.building == site.building
    assert hz.ground.a_g == pytest.approx(1.2 * site.ground.a_g) and hz.pga > site.pga
    ground, _ = collapse_site(site_hazard(NTC_SLA))
    assert ground.building is None and ground.spectrum == collapse_spectrum_text(NTC_SLA)[0]


# --- the band a design set covers ---------------------------------------------------------------------
@pytest.mark.parametrize("code, k", [("EC8-1", 2.0), ("ec8", 2.0), ("NTC2018", 1.2), (None, 1.2)])
def test_design_band_for_an_isolator(code, k):
    band, why = design_band(T_is=3.0, code=code)
    assert band == (0.15, round(k * 3.0, 6)) and f"{k:g} T_is" in why
    # a short isolator period: the band still reaches 2 s
    assert design_band(T_is=1.0, code=code)[0] == (0.15, max(2.0, k * 1.0))
    # and a building's 2 T1 when larger
    assert design_band(T1=2.0, T_is=1.5, code=code)[0] == (0.15, max(4.0, k * 1.5))
