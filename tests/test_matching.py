"""Response spectra (exact for piecewise-linear input) and spectrum-compatible record sets."""
import json
import math

import numpy as np
import pytest

from statue2model.cli import main
from statue2model.hazard.floor import parse_floor
from statue2model.hazard.matching import band_for_period, baseline_correct, envelope, match_set
from statue2model.hazard.motions import read_record
from statue2model.hazard.response_spectra import displacement, psa
from statue2model.errors import InputError
from statue2model.hazard.code_spectra import parse_spectrum

NTC_C = "ntc2018:ag=0.1g,F0=2.5,Tc=0.3,soil=C"


def test_ramp_response_is_exact():
    """u'' + 2 xi w u' + w^2 u = -t from rest: closed form, to round-off."""
    dt, T, xi = 0.01, 0.5, 0.05
    t = np.arange(301) * dt
    w = 2 * math.pi / T
    wd = w * math.sqrt(1 - xi ** 2)
    c1 = -2 * xi / w ** 3
    c2 = (1 / w ** 2 + xi * w * c1) / wd
    exact = -(t / w ** 2 - 2 * xi / w ** 3) + np.exp(-xi * w * t) * (c1 * np.cos(wd * t) + c2 * np.sin(wd * t))
    assert np.max(np.abs(displacement(t, dt, T, xi) - exact)) < 1e-12


@pytest.mark.parametrize("xi", [0.0, 0.05, 0.2])
def test_step_spectrum_closed_form(xi):
    """A step a0 gives PSA = a0 (1 + exp(-pi xi / sqrt(1 - xi^2))) at every period (peak read to 1.2 %)."""
    a0 = 1.5
    T = np.array([0.05, 0.1, 0.3, 1.0, 2.0])
    exact = a0 * (1 + math.exp(-math.pi * xi / math.sqrt(1 - xi ** 2)))
    sa = psa(np.full(2001, a0), 0.01, T, xi)
    assert np.all(sa <= exact * (1 + 1e-9)) and np.all(sa >= exact * 0.988), sa / exact


def test_resonant_sine_builds_up_as_closed_form():
    """Undamped oscillator under a resonant sine -a sin(w t) ... u = a/(2 w^2) (w t cos w t - sin w t)."""
    T, a, dt = 1.0, 0.5, 0.001
    w = 2 * math.pi / T
    t = np.arange(10001) * dt
    u = displacement(a * np.sin(w * t), dt, T, 0.0)
    exact = a / (2 * w ** 2) * (w * t * np.cos(w * t) - np.sin(w * t))
    # a sine is not piecewise linear: the error is its interpolation error, (w dt)^2 / 8 = 5e-6
    assert np.max(np.abs(u - exact)) < 1e-5 * np.max(np.abs(exact))


def test_psa_shapes_and_bad_input():
    acc = np.random.default_rng(0).standard_normal((3, 500))
    assert psa(acc, 0.01, [0.1, 0.5]).shape == (3, 2) and psa(acc[0], 0.01, [0.1, 0.5]).shape == (2,)
    assert np.allclose(psa(acc, 0.01, [0.2])[:, 0], [psa(a, 0.01, [0.2])[0] for a in acc])
    for bad in [dict(acc=[1.0, np.nan]), dict(periods=[0.0]), dict(dt=-1.0), dict(xi=1.0)]:
        kw = dict(acc=acc[0], dt=0.01, periods=[0.5], xi=0.05) | bad
        with pytest.raises(InputError):
            psa(kw["acc"], kw["dt"], kw["periods"], kw["xi"])


def test_baseline_ends_at_rest():
    dt, D = 0.01, 10.0
    t = np.arange(1001) * dt
    env = envelope(t, D)
    a = baseline_correct(np.random.default_rng(3).standard_normal((2, t.size)) * env + 0.3 * env, dt, env)
    v = np.concatenate([np.zeros((2, 1)), np.cumsum(0.5 * dt * (a[:, 1:] + a[:, :-1]), axis=1)], axis=1)
    u_end = np.sum(0.5 * dt * (v[:, 1:] + v[:, :-1]), axis=1)
    assert np.allclose(v[:, -1], 0, atol=1e-12) and np.allclose(u_end, 0, atol=1e-12) and a[0, 0] == 0


@pytest.fixture(scope="module")
def ground_set():
    return match_set(parse_spectrum(NTC_C), n=7, seed=1, duration=20, dt=0.01)


def test_matched_set_meets_its_tolerance(ground_set):
    """The default set: the mean spectrum, recomputed independently here, is within -10 %/+30 % of the
    target over 0.1-4 s, and the check says so."""
    s = ground_set
    target = parse_spectrum(NTC_C)
    T = np.geomspace(0.1, 4.0, 37)
    mean = psa(np.stack([m.samples for m in s.records]), 0.01, T).mean(axis=0)
    ratio = mean / target.Se(T)
    assert 0.9 <= ratio.min() and ratio.max() <= 1.3, ratio
    c = s.check()
    assert c["met"] and s.met and c["band_s"] == [0.1, 4.0] and 0.9 <= c["worst_ratio"] <= 1.3
    assert abs(c["min_ratio"] - ratio.min()) < 0.03                  # the two grids agree
    assert c["mean_pga_over_target_pga"] >= 1.0                       # EC8 3.2.3.1.2 (4)b
    assert len(s.records) == 7 and s.seeds == tuple(range(1, 8))
    assert all(m.dt == 0.01 and len(m.samples) == 2001 for m in s.records)


def test_check_fails_when_it_should(ground_set):
    """The same set against a target 20 % higher misses the -10 % bound, and says where."""
    s = ground_set
    from dataclasses import replace

    c = replace(s, target=s.target * 1.2).check()
    assert not c["met"] and c["worst_ratio"] < 0.9 and c["worst_ratio"] == c["min_ratio"]


def test_a_set_is_reproducible_from_its_seeds(ground_set):
    again = match_set(parse_spectrum(NTC_C), n=2, seed=2, duration=20, dt=0.01)
    assert np.array_equal(again.records[0].samples, ground_set.records[1].samples)


def test_floor_set_and_ec8_band():
    target = parse_floor("z=2,H=3,T1=0.4", parse_spectrum(NTC_C))
    s = match_set(target, n=7, seed=5, duration=20, dt=0.01, band=band_for_period(0.4))
    assert s.met and s.band == pytest.approx((0.08, 0.8)) and s.to_dict()["target"]["kind"] == "floor"


def test_refusals():
    sp = parse_spectrum(NTC_C)
    for kw in [dict(n=0), dict(seed=-1), dict(band=(0.02, 4.0)), dict(band=(0.1, 8.0)), dict(band=(2.0, 1.0)),
               dict(tolerance=(0.1, 0.3)), dict(dt=0.0)]:
        with pytest.raises(InputError):
            match_set(sp, **kw)
    with pytest.raises(InputError, match="Se"):
        match_set(object())


def test_records_command(tmp_path, capsys):
    out = tmp_path / "set"
    code = main(["records", "--spectrum", NTC_C, "--floor", "z=2,H=3,T1=0.4", "--n", "3", "--duration", "10",
                 "--band", "0.1:1.5", "--scale", "1:2", "--out", str(out)])
    stdout, err = capsys.readouterr()
    assert code == 0, err
    data = json.loads((out / "set.json").read_text())
    assert data["check"]["met"] is True and data["seeds"] == [1, 2, 3] and data["froude_scale"] == "1:2"
    assert (out / "spectra.png").stat().st_size > 1000
    m = read_record(out / "record_01.csv")
    assert abs(m.dt - 0.01 / math.sqrt(2)) < 1e-9 and len(m.samples) == 1001
    assert "mean/target over 0.1-1.5 s" in stdout


def test_records_command_refuses_an_unmet_set(tmp_path, capsys):
    out = tmp_path / "set"
    argv = ["records", "--spectrum", "ec8:ag=0.2g", "--n", "1", "--duration", "10", "--band", "0.1:1",
            "--tolerance", "1:1", "--out", str(out)]
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "misses its tolerance" in err and not out.exists()
    assert main(argv + ["--keep-unmet"]) == 0
    assert "WARNING" in capsys.readouterr().out
    assert json.loads((out / "set.json").read_text())["check"]["met"] is False
