"""Squat and sliding bodies: plastic impacts where eq. 15 gives e < 0, and the
'slides before it rocks' check (static friction mu_s against the uplift acceleration)."""
import json
import math

import numpy as np
import pytest
from scipy.integrate import quad

from statue2model.cli import main
from statue2model.hazard import motions
from statue2model.rocking import RockingModel, simulate
from statue2model.rocking.batch import NOT_APPLICABLE_CODE
from statue2model.rocking.engine import NOT_APPLICABLE
from statue2model.rocking.model import MU_STATIC, Restitution
from statue2model.rocking.spectrum import stability_spectrum
from statue2model.rocking.sweeps import variability
from statue2model.errors import InputError
from statue2model.io.files import write_json
from statue2model.geometry.rocking_params import RockingParams

G = 9.81
SQUAT = RockingParams.rectangular_block(b=0.5, h=0.3, m=500)       # delta = 59 deg > 54.7 deg


def run(argv, capsys):
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


def params_file(tmp_path, p, name="p.json"):
    path = tmp_path / name
    write_json(path, p.to_dict())
    return path


# --- plastic impact ------------------------------------------------------------------------
def test_squat_block_restitution_is_clipped_to_plastic():
    d = SQUAT.delta_L
    assert d > math.asin(math.sqrt(2 / 3))
    raw = 1 - 1.5 * math.sin(d) ** 2                                  # eq. 14, symmetric rectangle
    assert raw == pytest.approx(-0.10294117647, rel=1e-9)
    assert SQUAT.e_L_raw == pytest.approx(raw, rel=1e-12) and SQUAT.e_R_raw == pytest.approx(raw, rel=1e-12)
    assert SQUAT.e_L == 0.0 and SQUAT.e_R == 0.0
    assert SQUAT.to_dict()["e_L"] == 0.0 and SQUAT.to_dict()["e_L_raw"] == pytest.approx(raw)
    model = RockingModel.housner(SQUAT)
    assert model.e_L.values == (0.0,) and model.e_R.values == (0.0,)
    assert any("plastic impact (eq. 15 gives e = -0.103 < 0)" in n for n in model.notes)
    # a slender block is untouched
    a1 = RockingParams.rectangular_block(0.0384, 0.2, 1.286)
    assert a1.e_L == a1.e_L_raw == pytest.approx(1 - 1.5 * math.sin(a1.delta_L) ** 2)
    assert RockingModel.housner(a1).notes == []
    # an explicit negative e is still refused
    with pytest.raises(InputError):
        Restitution.constant(-0.1, "e_L")


def test_plastic_impact_ends_free_rocking_at_the_first_impact():
    model = RockingModel.housner(SQUAT)
    p = SQUAT
    th0 = 0.5 * p.delta_R
    r = simulate(model, motions.free(), theta0=th0)
    assert r.n_impacts == 1 and not r.overturned
    assert r.t_rest == pytest.approx(r.impact_times[0], abs=0.0)       # at rest at the impact itself
    assert r.theta_max_L == 0.0 and r.theta_max_R == pytest.approx(th0)
    assert r.outcome == "rocking" and r.stats["n_steps"] < 500
    # the impact time is the quarter period from the energy integral (MODEL.md section 3):
    # theta = th0 - u^2 removes the square-root singularity at th0
    p2 = p.p_R**2

    def f(u):
        th = th0 - u * u
        return 2 * u / math.sqrt(2 * p2 * (math.cos(p.delta_R - th0) - math.cos(p.delta_R - th))) if u > 0 else \
            2 / math.sqrt(2 * p2 * math.sin(p.delta_R - th0))
    quarter, _ = quad(f, 0.0, math.sqrt(th0), epsabs=1e-13, epsrel=1e-12)
    assert r.impact_times[0] == pytest.approx(quarter, rel=1e-6)


def test_plastic_impacts_under_a_long_excitation_do_not_chatter():
    model = RockingModel.housner(SQUAT)
    # 10 cycles at 2.5 g, 1 Hz: every excursion ends at its impact, the ground lifts it again
    r = simulate(model.with_(mu_static=5.0), motions.parse_spec("sines:amp=2.5g,freq=1,cycles=10")[0])
    assert r.applicable
    assert 2 <= r.n_impacts <= 40 and r.stats["n_steps"] < 20_000
    assert r.t_rest is not None and not r.overturned


def test_the_coupled_isolator_model_takes_the_plastic_impact_from_the_model():
    from statue2model.isolator.coupled import simulate_coupled
    from statue2model.isolator.device import Isolator

    small = RockingParams.rectangular_block(b=0.5, h=0.3, m=50)
    iso = Isolator(R=0.30, r=0.0183, M=80.0, mu=0.01)
    r = simulate_coupled(iso, RockingModel.housner(small), motions.free(), theta0=0.3)
    assert r.n_impacts == 1 and r.impacts[0, 3] == 0.0                 # theta'+ = 0 at the plastic impact
    r = simulate_coupled(iso, RockingModel.housner(small, e_L=0.5, e_R=0.5), motions.free(), theta0=0.3)
    assert r.n_impacts > 5


def test_rock_cli_on_a_squat_block_says_plastic(tmp_path, capsys):
    path = params_file(tmp_path, SQUAT)
    out = tmp_path / "rock.json"
    code, stdout, err = run(["rock", path, "--motion", "free:theta0=0.3", "--json", out], capsys)
    assert code == 0, err
    assert "plastic impact (eq. 15 gives e = -0.103 < 0)" in stdout
    data = json.loads(out.read_text())
    assert data["n_impacts"] == 1 and data["model"]["e_L"] == 0.0
    assert data["model"]["params"]["e_L_raw"] == pytest.approx(SQUAT.e_L_raw)
    assert any("plastic impact" in n for n in data["notes"])


# --- sliding before rocking -----------------------------------------------------------------
def test_slides_first_criterion():
    assert MU_STATIC == 0.7
    wide = RockingParams.rectangular_block(b=0.9, h=1.0, m=100)       # b/h = 0.9
    slim = RockingParams.rectangular_block(b=0.5, h=1.0, m=100)       # b/h = 0.5
    assert RockingModel.housner(wide).slides_first
    assert not RockingModel.housner(slim).slides_first
    assert not RockingModel.housner(wide, mu_static=0.9 + 1e-9).slides_first   # mu_s > b/h: rocks
    assert RockingModel.housner(wide, mu_static=0.9 - 1e-9).slides_first
    # the imperfect model lifts at alpha a: 0.5 x 0.9 g = 0.45 g < 0.7 g, it rocks first
    assert not RockingModel.imperfect(wide, 0.5, 0.5).slides_first
    # asymmetric: the side that lifts first decides (0.3 g), the other side gets a warning
    asym = RockingModel.housner(RockingParams(m=1.0, h=1.0, b_L=0.9, b_R=0.3, I_G=0.3))
    assert not asym.slides_first
    assert asym.notes and asym.notes[0].startswith("warning") and "0.900 g" in asym.notes[0]
    assert asym.applicability(2 * G, 2 * G) == (True, "")
    m = RockingModel.housner(wide)
    assert m.applicability(0.69 * G, 0.69 * G)[0]                       # below mu_s g: neither slides nor rocks
    ok, why = m.applicability(0.0, 0.71 * G)
    assert not ok and "slides before it rocks" in why
    with pytest.raises(InputError):
        RockingModel.housner(wide, mu_static=0.0)
    assert RockingModel.housner(slim).with_(mu_static=0.4).slides_first


def test_rock_cli_sliding_block_is_not_applicable(tmp_path, capsys):
    wide = params_file(tmp_path, RockingParams.rectangular_block(b=0.9, h=1.0, m=100), "wide.json")
    out = tmp_path / "wide_rock.json"
    code, stdout, err = run(["rock", wide, "--motion", "cosine:amp=1.2g,freq=2", "--json", out], capsys)
    assert code == 0, err
    assert "slides before it rocks" in stdout and NOT_APPLICABLE in stdout
    data = json.loads(out.read_text())
    assert data["applicable"] is False and data["outcome"] == NOT_APPLICABLE
    assert "slides before it rocks" in data["why"] and data["model"]["mu_static"] == 0.7
    # more friction: it rocks
    code, stdout, err = run(["rock", wide, "--motion", "cosine:amp=1.2g,freq=2", "--mu-static", "1.0",
                             "--json", out], capsys)
    data = json.loads(out.read_text())
    assert code == 0 and data["applicable"] is True and data["outcome"] != NOT_APPLICABLE and data["n_impacts"] > 0
    assert "slides before it rocks" not in stdout
    # b/h = 0.5: applicable with the default friction
    slim = params_file(tmp_path, RockingParams.rectangular_block(b=0.5, h=1.0, m=100), "slim.json")
    code, stdout, err = run(["rock", slim, "--motion", "cosine:amp=1.2g,freq=2", "--json", out], capsys)
    data = json.loads(out.read_text())
    assert code == 0 and data["applicable"] is True and data["why"] == "" and data["n_impacts"] > 0
    assert data["outcome"] in ("rocking", "overturn mode 1", "overturn mode 2", "overturn mode 3")


def test_spectrum_and_variability_of_a_sliding_block(tmp_path, capsys):
    wide = RockingModel.housner(RockingParams.rectangular_block(b=0.9, h=1.0, m=100))
    sp = stability_spectrum(wide, [1.0, 3.0], np.array([0.5, 0.75, 1.0, 1.5]) * G)
    assert sp.codes[:, 0].tolist() == [0, 0]                            # 0.5 g: neither slides nor lifts
    assert np.all(sp.codes[:, 1:] == NOT_APPLICABLE_CODE)               # above 0.7 g: slides first
    assert sp.outcome(1.0, 1.5 * G) == NOT_APPLICABLE and np.all(np.isnan(sp.theta_max_over_delta[:, 1:]))
    assert sp.counts()[NOT_APPLICABLE] == 6 and "slides before it rocks" in sp.why
    assert np.all(np.isnan(sp.min_overturning_amp()))                  # never an overturning point
    # the same spectrum without sliding rocks and overturns at 1.5 g
    sp2 = stability_spectrum(wide.with_(mu_static=2.0), [1.0, 3.0], np.array([0.5, 0.75, 1.0, 1.5]) * G)
    assert sp2.applicable.all() and np.any(sp2.codes >= 2)

    sw = variability(wide, motions.cosine_pulse(1.0, 2.0), np.array([0.3, 0.6, 0.8, 1.2]) * G)
    assert sw.applicable.tolist() == [True, True, False, False]
    assert sw.summary()["n"] == 2 and sw.summary()["n_not_applicable"] == 2
    assert np.isnan(sw.theta_max_over_delta[2:]).all()

    path = params_file(tmp_path, wide.params)
    out = tmp_path / "sp.json"
    code, stdout, err = run(["spectrum", path, "--freq", "1:2:2", "--amp", "0.8g:1.5g:3", "--json", out], capsys)
    assert code == 0, err
    data = json.loads(out.read_text())
    assert data["applicable"] is False and data["n_not_applicable"] == 6
    assert np.all(np.array(data["codes"]) == NOT_APPLICABLE_CODE)     # every point: none is 'no motion'
    assert "slides before it rocks" in stdout and "not applicable" in out.with_suffix(".csv").read_text()
    out = tmp_path / "var.json"
    code, stdout, err = run(["variability", path, "--motion", "cosine:amp=1g,freq=2", "--pga", "0.8g:1.2g:3",
                             "--json", out], capsys)
    assert code == 0, err
    data = json.loads(out.read_text())
    assert data["applicable"] == [False] * 3 and data["outcome"] == [NOT_APPLICABLE] * 3
    assert "slides before it rocks" in stdout and data["summary"]["n"] == 0


def test_config_sliding_friction():
    """The statue's friction is [sliding] mu_statue (issue [22]); [model] mu_static, where it was before,
    is refused with where it went."""
    from statue2model.pipeline.config import load_config, load_config_text

    assert load_config(None).sliding.mu_statue == 0.4
    assert load_config_text("[sliding]\nmu_statue = 0.45\n", "t.toml").sliding.mu_statue == 0.45
    with pytest.raises(InputError, match=r"\[model\] mu_static has moved: write it as \[sliding\] mu_statue"):
        load_config_text("[model]\nmu_static = 0.45\n", "t.toml")
    for bad in ("mu_statue = 0", "mu_pedestal = 3", "kinetic_ratio = 1.5", "allowance = -1"):
        with pytest.raises(InputError, match=bad.split()[0]):
            load_config_text(f"[sliding]\n{bad}\n", "t.toml")
    with pytest.raises(InputError, match="both size"):
        load_config_text("[pedestal]\nsize = [0.6, 0.6, 1.0]\n", "t.toml")
    with pytest.raises(InputError, match="off the pedestal"):
        load_config_text("[pedestal]\nsize = [0.6, 0.6, 1.0]\nmass = 250\nposition = [0.4, 0]\n", "t.toml")
    cfg = load_config_text("[pedestal]\nsize = [0.6, 0.6, 1.0]\nmass = 250\n", "t.toml")
    assert cfg.pedestal.size == (0.6, 0.6, 1.0) and cfg.pedestal.position == (0.0, 0.0)
    assert load_config_text(cfg.to_toml(), "again").pedestal == cfg.pedestal


# --- crosscheck --------------------------------------------------------------------------------
@pytest.mark.slow
def test_crosscheck_on_a_squat_block_does_not_abort(tmp_path, capsys):
    pytest.importorskip("pybullet")
    path = params_file(tmp_path, SQUAT)
    out = tmp_path / "cc"
    code, stdout, err = run(["crosscheck", path, "--motion", "cosine:amp=0.5g,freq=2", "--out", out, "--quick",
                             "--dt", "1e-3"], capsys)
    assert code == 0, err
    data = json.loads((out / "crosscheck.json").read_text())
    assert data["cases"] and data["scene"]["params"]["e_L"] == 0.0
    assert any("plastic impact" in n for n in data["notes"])
    assert any("slides before it rocks" in n for n in data["notes"])      # b/h = 1.67 > the 3D friction 1
