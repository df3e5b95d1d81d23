"""The bundled El Centro 1940 N-S record: its numbers, its provenance note, its SPEC."""
import hashlib
import math

import numpy as np
import pytest

from statue2model.hazard.motions import parse_spec, read_record
from statue2model.quantities import G_STANDARD as G_STD
from statue2model.hazard.response_spectra import psa
from statue2model.errors import InputError
from statue2model.io.paths import RECORDS_DIR, bundled_record, bundled_records

SHA256 = "e096f0458ae7565ac8e9fac80eda018e4715a357ea4c14504ce1cfa6556c53a6"   # as stated in its README


def test_el_centro_as_documented():
    path = bundled_record("elcentro_1940_ns")
    assert hashlib.sha256(path.read_bytes()).hexdigest() == SHA256       # copied unchanged
    m = read_record(path)
    assert len(m.samples) == 1559 and m.dt == 0.02
    assert abs(m.pga / G_STD - 0.3188) < 5e-5
    readme = (RECORDS_DIR / "README.md").read_text(encoding="utf-8")
    assert "elcentro_1940_ns.AT2" in readme and "public domain" in readme and SHA256 in readme
    assert bundled_records() == ["elcentro_1940_ns"]


def test_spec_forms():
    m, theta0 = parse_spec("bundled:name=elcentro_1940_ns")
    assert theta0 == 0.0 and len(m.samples) == 1559
    half, _ = parse_spec("bundled:name=elcentro_1940_ns.AT2,pga=0.2g,scale=1:2")
    assert abs(half.pga - 0.2 * 9.81) < 1e-9 and abs(half.dt - 0.02 / math.sqrt(2)) < 1e-15
    for bad in ["bundled:name=nope", "bundled:name=../records/elcentro_1940_ns", "bundled", "bundled:name=x,dt=1"]:
        with pytest.raises(InputError):
            parse_spec(bad)


def test_el_centro_spectrum_peaks_near_half_a_second():
    """Its 5 % spectrum: the well-known twin peaks of about 0.9 g near 0.2 and 0.5 s."""
    m = read_record(bundled_record("elcentro_1940_ns"))
    T = np.geomspace(0.05, 4, 80)
    sa = psa(m.samples, m.dt, T) / G_STD
    assert 0.15 < T[np.argmax(sa)] < 0.6 and 0.8 < sa.max() < 1.1
