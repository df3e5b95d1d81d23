"""Floor spectra: EC8 4.3.5.2 eq. 4.25 and the NTC 2018 (Circolare 2019 C7.2.3) formula, by hand."""
import numpy as np
import pytest

from statue2model.hazard.floor import floor_spectrum, ntc_floor_coefficients, parse_floor
from statue2model.errors import InputError
from statue2model.hazard.code_spectra import G, ec8, ntc2018

GROUND = ec8(0.2 * G, ground="B")          # a_g S = 0.24 g


def test_ec8_formula_by_hand():
    fl = floor_spectrum(GROUND, z=2, H=3, T1=0.5, code="ec8")
    aS = 0.24 * G
    # Ta = 0: 3 (5/3) / 2 - 0.5 = 2; Ta = T1: 3 (5/3) - 0.5 = 4.5; Ta = 2 T1: again 2; long periods: >= a_g S
    assert np.allclose(fl.Se([0.0, 0.5, 1.0, 10.0]), [2.0 * aS, 4.5 * aS, 2.0 * aS, aS])
    top = floor_spectrum(GROUND, z=3, H=3, T1=0.5, code="ec8")
    assert np.isclose(top.Se(0.5), 5.5 * aS)
    ground_level = floor_spectrum(GROUND, z=0, H=3, T1=0.5, code="ec8")
    assert np.isclose(ground_level.Se(0.0), aS)                       # the floor at z = 0 is the ground


@pytest.mark.parametrize("T1, abap", [(0.3, (0.8, 1.4, 5.0)), (0.5, (0.8, 1.4, 5.0)), (0.7, (0.3, 1.2, 4.0)),
                                      (2.0, (0.3, 1.0, 2.5))])
def test_ntc_formula_by_hand(T1, abap):
    a, b, ap = abap
    assert ntc_floor_coefficients(T1) == abap
    site = ntc2018(0.15 * G, 2.4, 0.3, soil="B")
    aS = site.a_g * site.S
    fl = floor_spectrum(site, z=1, H=2, T1=T1)                          # code from the site: NTC
    assert fl.code == "ntc2018"
    top = aS * 1.5 * ap
    assert np.isclose(fl.Se(0.0), aS * 1.5)                             # the floor acceleration
    assert np.allclose(fl.Se([a * T1, 0.5 * (a + b) * T1]), top)        # plateau
    Ta = 2 * b * T1
    assert np.isclose(fl.Se(Ta), top / (1 + (ap - 1) * (1 - 2) ** 2))
    Ta = 0.5 * a * T1
    assert np.isclose(fl.Se(Ta), top / (1 + (ap - 1) * 0.25))


def test_parse_and_refusals():
    fl = parse_floor("z=2, H=3, t1=0.4, code=EC8", GROUND)
    assert (fl.code, fl.z, fl.H, fl.T1) == ("ec8", 2.0, 3.0, 0.4) and fl.to_dict()["z_over_H"] == 2 / 3
    for bad in ["z=2,H=3", "z=4,H=3,T1=0.4", "z=2,H=3,T1=0", "z=2,H=3,T1=0.4,code=asce", "z=2,H=3,T1=x",
                "z=2,H=3,T1=0.4,z=1", "z2,H=3,T1=0.4", "z=2,H=3,T1=0.4,q=2"]:
        with pytest.raises(InputError):
            parse_floor(bad, GROUND)
