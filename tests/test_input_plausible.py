"""Numbers that cannot be physical are refused where they are read, with the unit they were
probably typed in (issue 24, item 10): a ground-motion sample above 100 g or not finite, an
absurd record time step, a 1.8 km statue (--height 1800), a 300 m groove (--R 300); the
unusual-but-possible ones are taken with a warning. One table holds every range
(statue2model.geometry.units.PLAUSIBLE)."""
from __future__ import annotations

import json
import math

import numpy as np
import pytest
import trimesh

from statue2model.cli import main
from statue2model.hazard import motions
from statue2model.errors import InputError
from statue2model.quantities import G_STANDARD
from statue2model.geometry.body import body_from_mesh
from statue2model.geometry.rocking_params import RockingParams
from statue2model.geometry.units import PLAUSIBLE, POSSIBLE_SIZE, PLAUSIBLE_SIZE, check_plausible
from statue2model.io.files import write_json
from statue2model.isolator.device import Isolator, isolator_from_design
from statue2model.pipeline.config import load_config_text

G = 9.81
A1 = RockingParams.rectangular_block(0.0384, 0.2000, 1.286)


def run(argv, capsys):
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


@pytest.fixture
def params(tmp_path):
    path = tmp_path / "props.json"
    write_json(path, A1.to_dict())
    return path


# ------------------------------------------------------------------ the table
def test_one_table_of_ranges_is_consistent():
    for key, r in PLAUSIBLE.items():
        assert r.hard_low <= r.low < r.high <= r.hard_high, key
        assert r.unit in ("m", "kg", "kg/m^3", "m/s^2", "s", "N", "-", "%", "Hz", "rad", "m/s"), key
        assert all(k > 0 for _, k in r.typed), key
    # the scan's unit detection reads the same numbers (one place)
    assert PLAUSIBLE_SIZE == (PLAUSIBLE["height"].low, PLAUSIBLE["height"].high)
    assert POSSIBLE_SIZE == (PLAUSIBLE["height"].hard_low, PLAUSIBLE["height"].hard_high)
    assert PLAUSIBLE["acceleration"].hard_high == pytest.approx(100 * G)
    assert PLAUSIBLE["height"].hard_high <= 30 and PLAUSIBLE["groove_radius"].hard_high <= 20


@pytest.mark.parametrize("quantity, value, meant", [
    ("height", 1800.0, "did you mean 1800 mm (1.8 m)?"),
    ("groove_radius", 300.0, "300 mm (0.3 m)"),
    ("ball_radius", 9.5, "9.5 mm (0.0095 m)"),
    ("supported_mass", 5e6, "5e+06 g (5000 kg)"),
    ("time_step", 5.0, "5 ms (0.005 s)"),
    ("acceleration", 2000.0, "2000 cm/s^2 (gal) (20 m/s^2)"),
])
def test_impossible_values_are_refused_with_the_unit_meant(quantity, value, meant):
    r = PLAUSIBLE[quantity]
    assert not r.hard_low <= value <= r.hard_high
    with pytest.raises(InputError, match="is implausible for") as exc:
        check_plausible(quantity, value, "X")
    msg = str(exc.value)
    assert msg.startswith(f"X = {value:.4g} {r.unit} is implausible") and meant in msg, msg
    # the value named as meant is the value times the unit's size, and is plausible
    shown = meant.removeprefix("did you mean ")
    name, k = next((n, k) for n, k in r.typed if shown.startswith(f"{value:.4g} {n} ("))
    assert r.low <= value * k <= r.high and f"({value * k:.4g} {r.unit})" in shown


def test_grey_zone_warns_and_plausible_is_silent():
    assert check_plausible("height", 1.8) is None and check_plausible("groove_radius", 0.3) is None
    note = check_plausible("height", 6.0, "--height")
    assert note.startswith("--height = 6 m is unusual for a statue height (0.1 to 4 m)")
    assert check_plausible("height", 20.0) is not None                  # at the possible edge: a warning
    with pytest.raises(InputError):
        check_plausible("height", 20.01)
    with pytest.raises(InputError, match="not a finite number"):
        check_plausible("height", math.nan)


# ------------------------------------------------------------------ ground motions
def _csv(path, rows):
    path.write_text("time_s,acc_m_s2\n" + "".join(f"{t},{a}\n" for t, a in rows))
    return path


def test_record_sample_of_1e300_is_refused_naming_file_line_value(tmp_path):
    path = _csv(tmp_path / "big.csv", [(0, 0), (0.01, 0.5), (0.02, "1e300"), (0.03, 0)])
    with pytest.raises(InputError) as exc:
        motions.read_record(path)
    msg = str(exc.value)
    assert str(path) in msg and "line 4" in msg and "1e+300 m/s^2" in msg and "implausible" in msg, msg


def test_rock_with_a_1e300_sample_is_one_input_error_not_an_internal_error(params, tmp_path, capsys):
    path = _csv(tmp_path / "big.csv", [(0, 0), (0.01, "1e300"), (0.02, 0), (0.03, 0)])
    code, out, err = run(["rock", params, "--motion", f"file:path={path}", "--json", tmp_path / "r.json"], capsys)
    assert code == 2 and "internal error" not in err and "line 3" in err and "1e+300" in err, err
    assert len(err.strip().splitlines()) == 1 and not (tmp_path / "r.json").exists()


def test_non_finite_samples_name_their_line(tmp_path):
    one = tmp_path / "one.csv"
    one.write_text("# acc\n0\n0.1\ninf\n")
    with pytest.raises(InputError, match=r"one.csv: line 4: the acceleration is not a finite number \(inf\)"):
        motions.read_record(one, dt=0.01)
    at2 = tmp_path / "rec.AT2"
    at2.write_text("PEER\nx\ny\nNPTS=  4, DT=   .0050 SEC\n0.0 0.1\nnan 0.0\n")
    with pytest.raises(InputError, match=r"rec.AT2: line 6: the acceleration is not a finite number"):
        motions.read_record(at2)


def test_at2_sample_above_100g_is_refused_and_100g_itself_is_not(tmp_path):
    at2 = tmp_path / "rec.AT2"
    at2.write_text("PEER\nx\ny\nNPTS=  4, DT=   .0050 SEC\n0.0 0.1\n101.0 0.0\n")
    with pytest.raises(InputError, match=r"rec.AT2: line 6: acceleration = 990.5 m/s\^2 is implausible"):
        motions.read_record(at2)
    at2.write_text("PEER\nx\ny\nNPTS=  4, DT=   .0050 SEC\n0.0 0.1\n100.0 0.0\n")   # 100 g in the file's g
    assert motions.read_record(at2).pga == pytest.approx(100 * G_STANDARD)


def test_absurd_time_steps_are_refused(tmp_path):
    slow = _csv(tmp_path / "slow.csv", [(0, 0), (5, 0.1), (10, 0)])               # one sample every 5 s
    with pytest.raises(InputError, match=r"slow.csv: time step \(the time column\) = 5 s .*did you mean 5 ms"):
        motions.read_record(slow)
    one = tmp_path / "one.csv"
    one.write_text("0\n0.1\n0\n")
    with pytest.raises(InputError, match="did you mean 5 ms"):
        motions.parse_spec(f"file:path={one},dt=5")
    with pytest.raises(InputError, match="time step"):
        motions.record([0.0, 1.0, 0.0], 1e-9)
    assert motions.read_record(one, dt=0.005).dt == 0.005                         # a usual one


def test_accelerations_above_100g_are_refused_everywhere():
    with pytest.raises(InputError, match=r"amp=150g is 150 g: no ground motion reaches 100 g"):
        motions.parse_spec("cosine:amp=150g,freq=2")
    with pytest.raises(InputError, match="pga=2000m/s2"):
        motions.parse_spec("synthetic:duration=5,pga=2000m/s2")
    assert motions.parse_accel("100g") == pytest.approx(981.0)                   # the limit itself is allowed
    for make in (lambda: motions.cosine_pulse(1e300, 1.0), lambda: motions.rect_pulse(-2000.0, 0.1),
                 lambda: motions.synthetic_record(5.0, 0.01, pga=1e4),
                 lambda: motions.record(np.array([0.0, 1e300, 0.0]), 0.01),
                 lambda: motions.cosine_pulse(1.0, 1.0).scaled_to_pga(1e5)):
        with pytest.raises(InputError, match="implausible for a ground acceleration"):
            make()
    assert motions.cosine_pulse(5 * G, 2.0).pga == pytest.approx(5 * G)          # a strong but real pulse
    with pytest.raises(InputError, match=r"sample 1"):
        motions.record(np.array([0.0, 1e300, 0.0]), 0.01)


def test_fragility_levels_and_design_accelerations_above_100g_are_refused(params, tmp_path, capsys):
    code, _, err = run(["fragility", params, "--records", "synthetic:2,duration=5", "--levels", "0.1g:200g:3",
                        "--out", tmp_path / "f"], capsys)
    assert code == 2 and "no ground motion reaches 100 g" in err, err
    with pytest.raises(InputError, match="100 g"):
        load_config_text('[isolator]\nfuse_release = "500g"\n')


# ------------------------------------------------------------------ the statue's height, mass, density
def _box(tmp_path):
    path = tmp_path / "box.stl"
    trimesh.creation.box(extents=(0.3, 0.2, 1.0)).export(path)
    return path


def test_height_1800_is_refused_before_any_work(tmp_path, capsys):
    box = trimesh.creation.box(extents=(0.3, 0.2, 1.0))
    with pytest.raises(InputError, match=r"height = 1800 m is implausible for a statue height; did you mean "
                                         r"1800 mm \(1.8 m\)\?"):
        body_from_mesh(box.vertices, box.faces, height=1800.0)
    code, out, err = run(["props", _box(tmp_path), "--height", "1800", "--json", tmp_path / "p" / "props.json"],
                         capsys)
    assert code == 2 and "did you mean 1800 mm (1.8 m)?" in err and not (tmp_path / "p").exists(), err


def test_unusual_height_is_a_warning_of_the_body(tmp_path, capsys):
    box = trimesh.creation.box(extents=(0.3, 0.2, 1.0))
    body = body_from_mesh(box.vertices, box.faces, height=6.0)
    assert body.height == pytest.approx(6.0)
    assert any(w.startswith("height = 6 m is unusual for a statue height") for w in body.warnings), body.warnings
    assert not any("unusual for a statue height" in w
                   for w in body_from_mesh(box.vertices, box.faces, height=1.5).warnings)


@pytest.mark.parametrize("toml, needle", [
    ("[scan]\nheight = 1800\n", "[scan] height = 1800 m is implausible for a statue height; did you mean 1800 mm"),
    ('[scan]\nheight = "1800m"\n', "[scan] height = 1800 m is implausible"),
    ("[scan]\nmass = 5e9\n", "[scan] mass = 5e+09 kg is implausible"),
    ("[scan]\ndensity = 2.7\n", "did you mean 2.7 g/cm^3 (2700 kg/m^3)?"),
    ("[scan]\nbase_tol = 5.0\n", "[scan] base_tol = 5 m is implausible"),
    ("[isolator]\nthickness = 30\n", "[isolator] thickness = 30 m is implausible for an isolator plate thickness; "
                                     "did you mean 30 mm (0.03 m)?"),
])
def test_project_file_refuses_impossible_lengths_masses_densities(toml, needle):
    with pytest.raises(InputError) as exc:
        load_config_text(toml, "p.toml")
    assert str(exc.value).startswith("p.toml: ") and needle in str(exc.value), str(exc.value)


def test_project_file_takes_the_usual_values():
    cfg = load_config_text('[scan]\nheight = 1.8\nmass = 120.0\n[isolator]\nthickness = "30mm"\n')
    assert (cfg.scan.height, cfg.scan.mass, cfg.isolator.thickness) == (1.8, 120.0, 0.03)


# ------------------------------------------------------------------ the isolator
def test_isolator_simulate_refuses_a_300_m_groove(tmp_path, capsys):
    argv = ["isolator", "simulate", "--R", "300", "--r", "0.0095", "--mass", "20", "--mu", "0.01",
            "--motion", "cosine:amp=0.2g,freq=1", "--json", tmp_path / "iso.json"]
    with pytest.raises(SystemExit) as exc:
        main([str(a) for a in argv])
    err = capsys.readouterr().err
    assert exc.value.code == 2 and "300 m is implausible for a groove radius of curvature; did you mean 300 mm (0.3 m)" \
        in err, err
    assert not (tmp_path / "iso.json").exists()
    ok = ["--R", "0.3", "--r", "0.0095", "--mass", "20", "--mu", "0.01", "--motion", "cosine:amp=0.2g,freq=1",
          "--json", tmp_path / "iso.json"]
    for extra, meant in ((["--r", "9.5"], "9.5 m is implausible for a ball radius; did you mean 9.5 mm (0.0095 m)"),
                         (["--capacity", "150m"], "did you mean 150 mm (0.15 m)"),
                         (["--mass", "5e7"], "5e+07 kg is implausible for a supported mass")):
        with pytest.raises(SystemExit) as exc:
            main(["isolator", "simulate", *map(str, ok), *extra])     # the later option wins
        err = capsys.readouterr().err
        assert exc.value.code == 2 and meant in err, err


def test_isolator_simulate_warns_of_an_unusual_groove_and_runs(tmp_path, capsys):
    code, out, err = run(["isolator", "simulate", "--R", "4", "--r", "0.0095", "--mass", "20", "--mu", "0.01",
                          "--motion", "cosine:amp=0.05g,freq=1", "--t-end", "1", "--json", tmp_path / "iso.json"],
                         capsys)
    assert code == 0 and "warning: --R 4 m is unusual for a groove radius of curvature (0.1 to 3 m)" in err, err
    assert json.loads((tmp_path / "iso.json").read_text())["isolator"]["R"] == 4.0


def test_isolator_device_and_design_json_refuse_impossible_lengths():
    with pytest.raises(InputError, match=r"groove radius R = 300 m is implausible.*300 mm \(0.3 m\)"):
        Isolator(R=300.0, r=0.0095, M=20.0, mu=0.01)
    with pytest.raises(InputError, match=r"ball radius r = 9.5 m is implausible"):
        isolator_from_design({"R": 15.0, "r": 9.5, "M": 20.0, "mu": 0.01})
    with pytest.raises(InputError, match=r"isolator capacity = 150 m is implausible.*150 mm \(0.15 m\)"):
        isolator_from_design({"R": 0.3, "r": 0.0095, "M": 20.0, "mu": 0.01, "d_max": 150.0})
    assert Isolator(R=0.30, r=0.0095, M=1e7, mu=0.0).M == 1e7       # a modelling device (a fixed plate): no mass limit
