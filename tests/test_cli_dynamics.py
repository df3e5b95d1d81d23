"""The dynamics commands: the interface other stages rely on, outputs, and one clear
line (exit 2, nothing written) for every kind of bad input."""
import json

import numpy as np
import pytest

from statue2model.cli import main
from statue2model.hazard import motions
from statue2model.rocking import RockingModel, simulate
from statue2model.io.files import write_json
from statue2model.geometry.rocking_params import RockingParams

A1 = RockingParams.rectangular_block(0.0384, 0.2000, 1.286)
INTERFACE_KEYS = ("theta_max_L", "theta_max_R", "theta_max_over_delta", "uplift_time", "n_impacts", "impact_times",
                  "overturned", "overturn_mode", "t_rest")


@pytest.fixture
def params(tmp_path):
    path = tmp_path / "props.json"
    write_json(path, A1.to_dict())
    return path


def run(argv, capsys):
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


def test_rock_writes_the_interface(params, tmp_path, capsys):
    out = tmp_path / "r" / "rock.json"
    code, stdout, err = run(["rock", params, "--motion", "cosine:amp=0.5g,freq=2", "--e", "0.9", "--json", out],
                            capsys)
    assert code == 0, err
    data = json.loads(out.read_text())
    for key in INTERFACE_KEYS:
        assert key in data, key
    r = simulate(RockingModel.housner(A1, 0.9, 0.9), motions.cosine_pulse(0.5 * 9.81, 2.0))
    assert data["overturned"] is True and data["overturn_mode"] == r.overturn_mode
    assert data["impacts_before_overturn"] == r.impacts_before_overturn == data["n_impacts"]
    assert data["theta_max_R"] == pytest.approx(r.theta_max_R, rel=1e-9)
    assert data["t_rest"] is None and data["uplift_time"] == pytest.approx(0.0)
    hist = (out.parent / "rock_history.csv").read_text().splitlines()
    assert hist[0] == "t_s,theta_rad,theta_dot_rad_s,phase" and len(hist) > 10
    assert (out.parent / "rock.png").stat().st_size > 1000
    assert "overturn" in stdout


def test_rock_free_imperfect_and_linearised(params, tmp_path, capsys):
    out = tmp_path / "free.json"
    code, _, err = run(["rock", params, "--motion", "free:theta0=0.05", "--model", "imperfect", "--alpha-L", "0.6",
                        "--alpha-R", "0.7", "--theta-L", "0.01", "--theta-R", "0.02", "--e-L", "0.9", "--e-R", "0.8",
                        "--linearised", "--t-end", "30", "--json", out], capsys)
    assert code == 0, err
    data = json.loads(out.read_text())
    assert data["theta_max_R"] == pytest.approx(0.05) and data["t_rest"] > 0 and data["overturned"] is False
    assert data["model"]["alpha_L"] == 0.6 and data["model"]["linearised"] is True
    assert data["overturn_mode"] is None


def test_rock_record_file_and_froude(params, tmp_path, capsys):
    rec = motions.synthetic_record(5.0, 0.005, 0.3 * 9.81, seed=2)
    path = tmp_path / "rec.csv"
    motions.write_record_csv(path, rec)
    out = tmp_path / "rec.json"
    code, _, err = run(["rock", params, "--motion", f"file:path={path},pga=0.4g,scale=1:2", "--json", out], capsys)
    assert code == 0, err
    data = json.loads(out.read_text())
    assert data["motion"]["pga_m_s2"] == pytest.approx(0.4 * 9.81)
    assert data["motion"]["dt_s"] == pytest.approx(0.005 / np.sqrt(2))


@pytest.mark.slow
def test_spectrum_variability_sweep_identify_motion(params, tmp_path, capsys):
    code, out, err = run(["spectrum", params, "--freq", "1:4:4", "--amp", "0.1g:1g:5", "--alpha", "0.65",
                          "--json", tmp_path / "sp.json"], capsys)
    assert code == 0, err
    sp = json.loads((tmp_path / "sp.json").read_text())
    assert np.array(sp["codes"]).shape == (4, 5) and sp["n_runs"] == 20
    assert (tmp_path / "sp.csv").read_text().count("\n") == 21
    code, out, err = run(["variability", params, "--motion", "synthetic:duration=5", "--pga", "0.05g:0.5g:6",
                          "--json", tmp_path / "v.json"], capsys)
    assert code == 0, err
    assert len(json.loads((tmp_path / "v.json").read_text())["values"]) == 6
    code, out, err = run(["sweep", params, "--motion", "cosine:amp=0.3g,freq=2", "--alpha", "0.65",
                          "--param", "theta_R", "--values", "0.01:0.13:49", "--over-delta",
                          "--json", tmp_path / "s.json"], capsys)
    assert code == 0, err
    s = json.loads((tmp_path / "s.json").read_text())
    assert len(s["values"]) == 49 and s["values"][0] == pytest.approx(0.01 * A1.delta_R)
    # identify from a simulated free-rocking record, in degrees
    r = simulate(RockingModel.housner(A1, 0.92, 0.92), motions.free(), theta0=0.15, t_end=2.0, dt_out=1e-3)
    rec = tmp_path / "free.csv"
    rec.write_text("time,theta_deg\n" + "".join(f"{t},{np.degrees(x)}\n" for t, x in
                                                  zip(r.history["t"], r.history["theta"])))
    code, out, err = run(["identify", params, rec, "--units", "deg", "--json", tmp_path / "id.json"], capsys)
    assert code == 0, err
    ident = json.loads((tmp_path / "id.json").read_text())
    assert all(abs(row["e"] - 0.92) < 2e-3 for row in ident["impacts"][:6])
    # the identified curves feed back into rock
    code, out, err = run(["rock", params, "--motion", "free:theta0=0.1", "--e-L", tmp_path / "id.json",
                          "--e-R", tmp_path / "id.json", "--json", tmp_path / "again.json"], capsys)
    assert code == 0, err
    code, out, err = run(["motion", "cosine:amp=0.3g,freq=2", "--csv", tmp_path / "table.csv"], capsys)
    assert code == 0, err
    rows = np.loadtxt(tmp_path / "table.csv", delimiter=",", skiprows=1)
    assert abs(rows[-1, 3]) < 1e-12 and abs(rows[-1, 2]) < 1e-12  # the table ends at rest where it started


BAD = [
    (["--motion", "cosine:amp=0.3g,freq=2", "--e", "1.2"], "restitution"),
    (["--motion", "cosine:amp=0.3g,freq=2", "--alpha", "1.5"], "alpha"),
    (["--motion", "cosine:amp=0.3g,freq=2", "--alpha", "0"], "alpha"),
    (["--motion", "cosine:amp=0.3g,freq=2", "--alpha", "0.5", "--theta-R", "0"], "theta"),
    (["--motion", "cosine:amp=0.3g,freq=2", "--alpha", "0.5", "--theta-R", "-0.01"], "theta"),
    (["--motion", "cosine:amp=0.3g,freq=2", "--model", "imperfect"], "alpha"),
    (["--motion", "cosine:amp=nan,freq=2"], "amplitude"),
    (["--motion", "cosine:amp=0.3g,freq=-2"], "freq"),
    (["--motion", "cosine:amp=0.3g"], "missing"),
    (["--motion", "wobble:amp=1"], "unknown motion"),
    (["--motion", "free:theta0=0.5"], "overturning angle"),
    (["--motion", "file:path=/nonexistent.csv"], "not found"),
    (["--motion", "cosine:amp=0.3g,freq=2", "--t-end", "-1"], "t-end"),
    (["--motion", "cosine:amp=0.3g,freq=2", "--e-L", "x.json"], "e-L"),
]


@pytest.mark.parametrize("extra,word", BAD)
def test_rock_bad_input_one_line(params, tmp_path, capsys, extra, word):
    out = tmp_path / "bad.json"
    code, stdout, err = run(["rock", params, *extra, "--json", out], capsys)
    assert code == 2
    lines = [x for x in err.strip().splitlines() if x]
    assert len(lines) == 1 and word.lower() in lines[0].lower(), err
    assert "Traceback" not in err and not out.exists()


@pytest.mark.parametrize("content,word", [
    ("time,acc\n0,0\n0.01,1\n0.025,2\n0.03,1\n", "irregular"),
    ("0,0\n0.01,abc\n0.02,1\n", "not a number"),
    ("0,0\n0.01,nan\n0.02,1\n", "finite"),
    ("", "empty"),
    ("0,0,1\n0.01,1,2\n", "columns"),
])
def test_rock_malformed_motion_files(params, tmp_path, capsys, content, word):
    f = tmp_path / "m.csv"
    f.write_text(content)
    code, _, err = run(["rock", params, "--motion", f"file:path={f}", "--json", tmp_path / "o.json"], capsys)
    assert code == 2 and word in err.lower() and len(err.strip().splitlines()) == 1, err


@pytest.mark.parametrize("data,word", [
    ({"m": -1.0, "h": 0.2, "b_L": 0.04, "b_R": 0.04, "I_G": 0.01}, "m must be"),
    ({"m": 1.0, "h": float("nan"), "b_L": 0.04, "b_R": 0.04, "I_G": 0.01}, "h must be"),
    ({"m": 1.0, "h": 0.2, "b_L": 0.04}, "missing"),
])
def test_impossible_parameters(tmp_path, capsys, data, word):
    p = tmp_path / "p.json"
    p.write_text(json.dumps(data).replace("NaN", "NaN"))
    code, _, err = run(["rock", p, "--motion", "cosine:amp=0.3g,freq=2"], capsys)
    assert code == 2 and word in err and len(err.strip().splitlines()) == 1, err


def test_not_a_params_file(tmp_path, capsys):
    mesh = tmp_path / "x.stl"
    mesh.write_text("solid x\nendsolid x\n")
    code, _, err = run(["rock", mesh, "--motion", "cosine:amp=0.3g,freq=2"], capsys)
    assert code == 2 and "props" in err


def test_identify_bad_record(params, tmp_path, capsys):
    f = tmp_path / "r.csv"
    f.write_text("0,0\n0.1,0\n0.2,0\n0.3,0\n0.4,0\n0.5,0\n")
    code, _, err = run(["identify", params, f], capsys)
    assert code == 2 and "no rocking" in err
    f.write_text("0,0.1\n0.1,2\n0.2,-2\n0.3,1\n0.4,-1\n0.5,0.5\n")
    code, _, err = run(["identify", params, f], capsys)
    assert code == 2 and "overturning angle" in err
