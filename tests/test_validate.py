"""``statue2model validate``: the lab-file reader (rounded times, sign, units, band), the campaign file (paths kept
inside its folder), the scores against hand values, and a campaign replayed end to end."""
from __future__ import annotations

import json
import math

import numpy as np
import pytest

from statue2model.assessment.campaign import load_campaign, scores, wilson
from statue2model.cli import main
from statue2model.errors import InputError
from statue2model.hazard.lab import LabFormat, read_lab_motion
from statue2model.quantities import G


def _write_lab(path, t, a, fmt_t="{:.4g}", sep="\t", header="time [s]\tacc [g]"):
    lines = [header] if header else []
    lines += [f"{fmt_t.format(ti)}{sep}{ai:.6f}" for ti, ai in zip(t, a)]
    path.write_text("\n".join(lines) + "\n")
    return path


# --- the reader ------------------------------------------------------------------------------------------
def test_a_time_column_rounded_to_four_digits_is_taken_on_its_grid(tmp_path):
    t = np.arange(0, 4000) * 0.005                     # 0 .. 19.995 s: 4 digits round 10.005 to 10.01
    a = 0.2 * np.sin(2 * np.pi * 1.5 * t)
    m, notes = read_lab_motion(_write_lab(tmp_path / "r.txt", t, a), LabFormat(columns=(1, 2), units="g"))
    assert m.dt == pytest.approx(0.005, rel=1e-4) and m.samples.size == 4000
    assert notes and "rounded" in notes[0]
    np.testing.assert_allclose(m.samples, a * G, atol=1e-6 * G)


def test_units_sign_columns_and_a_comma_file(tmp_path):
    t = np.arange(0, 200) * 0.01
    a = np.linspace(-1.0, 2.0, 200)
    p = _write_lab(tmp_path / "r.csv", t, a, fmt_t="{:.2f}", sep=",", header="t,acc")
    m, _ = read_lab_motion(p, LabFormat(columns=(1, 2), units="m/s^2", sign=-1))
    np.testing.assert_allclose(m.samples, -a, atol=1e-6)             # the file holds 6 decimals
    m2, notes = read_lab_motion(p, LabFormat(columns=None, dt=0.01, column=2, units="g"))
    np.testing.assert_allclose(m2.samples, a * G, atol=1e-6 * G)
    assert not notes


def test_a_zero_phase_band_pass_keeps_the_band_and_the_timing(tmp_path):
    """A 2 Hz sine with a 0.05 Hz drift and 40 Hz noise: the 0.2-20 Hz band keeps the sine (amplitude and phase)
    and removes the rest."""
    t = np.arange(0, 6000) * 0.002
    sine = 0.3 * np.sin(2 * np.pi * 2.0 * t)
    a = sine + 0.2 * np.sin(2 * np.pi * 0.05 * t) + 0.05 * np.sin(2 * np.pi * 40 * t)
    m, notes = read_lab_motion(_write_lab(tmp_path / "r.txt", t, a, fmt_t="{:.3f}"),
                               LabFormat(columns=(1, 2), units="g", band=(0.2, 20.0)))
    mid = slice(2000, 4000)                          # 4-8 s: away from the ends' transients
    assert np.abs(m.samples[mid] / G - sine[mid]).max() < 0.02
    assert np.abs(m.samples[mid] / G - a[mid]).max() > 0.1      # the drift and the noise were there
    assert any("band-pass" in n for n in notes)


@pytest.mark.parametrize("bad, words", [
    ("0\t0.1\n0.01\t0.2\n0.005\t0.3\n", "goes back"),
    ("".join(f"{k * 0.01 + (0.05 if k >= 20 else 0):.3f}\t0.1\n" for k in range(40)), "leaves the uniform grid"),
    ("0\t0.1\n0.01\tx\n", "line 2 is not numbers"),
    ("0\t0.1\n", "at least 2"),
])
def test_a_malformed_lab_file_is_one_line(tmp_path, bad, words):
    p = tmp_path / "bad.txt"
    p.write_text(bad)
    with pytest.raises(InputError, match=words):
        read_lab_motion(p, LabFormat(columns=(1, 2)))


# --- the scores ------------------------------------------------------------------------------------------
def test_wilson_and_brier_against_hand_values():
    # Wilson 95 %, k 8 of n 10: p 0.8, z^2 / n = 0.38415, centre (0.8 + 0.19207) / 1.38415 = 0.71674, half
    # 1.96 sqrt(0.016 + 0.0096) / 1.38415 = 0.22658
    assert wilson(8, 10) == (0.4902, 0.9433)
    assert wilson(0, 5) == (0.0, 0.4345) and wilson(5, 5) == (0.5655, 1.0) and wilson(0, 0) is None
    s = scores([1, 1, 1, 0, 0], [1, 1, 0, 0, 1], [0.8, 0.6, 0.3, 0.2, 0.7])
    assert (s["tp"], s["fn"], s["fp"], s["tn"]) == (2, 1, 1, 1)
    assert s["precision"]["value"] == pytest.approx(2 / 3) and s["recall"]["value"] == pytest.approx(2 / 3)
    # Brier: (0.2^2 + 0.4^2 + 0.7^2 + 0.2^2 + 0.7^2) / 5 = (0.04 + 0.16 + 0.49 + 0.04 + 0.49) / 5 = 0.244
    assert s["brier"] == pytest.approx(0.244)
    none = scores([0, 0], [0, 0], [0.1, 0.2])
    assert none["precision"]["value"] is None and "predicts the outcome in no test" in none["precision"]["reason"]
    assert none["recall"]["value"] is None and "observed in no test" in none["recall"]["reason"]


# --- a campaign --------------------------------------------------------------------------------------------
def box_campaign(folder, n: int = 8):
    """A campaign in ``folder``: a 0.2 x 0.3 x 0.8 m box and ``n`` one-sine tests of 0.1-0.7 g at 2 Hz
    (lab files in g), toppled above 0.45 g and lifted above 0.25 g; returns its campaign.toml."""
    import trimesh

    box = trimesh.creation.box(extents=(0.2, 0.3, 0.8))
    box.apply_translation((0, 0, 0.4))
    box.export(folder / "rock.stl")
    rows = ["name,file,toppled,lifted"]
    for k, amp in enumerate(np.linspace(0.1, 0.7, n)):
        t = np.arange(0, 3.0, 0.005)
        a = np.where(t < 0.5, amp * np.sin(2 * np.pi * 2.0 * t), 0.0)
        _write_lab(folder / f"t{k}.txt", t, a)
        rows.append(f"t{k},t{k}.txt,{int(amp > 0.45)},{int(amp > 0.25)}")
    (folder / "tests.csv").write_text("\n".join(rows) + "\n")
    (folder / "campaign.toml").write_text('name = "box"\ntests = "tests.csv"\n[specimen]\nscan = "rock.stl"\n'
                                          'units = "m"\nup = "z"\ndirection = 0\n[motion]\ncolumns = [1, 2]\n'
                                          'units = "g"\n')
    return folder / "campaign.toml"


@pytest.fixture
def campaign(tmp_path):
    return box_campaign(tmp_path)


def test_a_campaign_is_replayed_and_scored(campaign, tmp_path):
    out = tmp_path / "out"
    assert main(["validate", str(campaign), "--out", str(out), "--models", "2d"]) == 0
    r = json.loads((out / "validation.json").read_text())
    assert r["tests"] == 8 and len(r["rows"]) == 8 and (out / "validation.html").is_file()
    for row in r["rows"]:
        assert 0.0 <= row["p_topple_2d"] <= 1.0 and row["topple_2d"] == (row["p_topple_2d"] >= 0.5)
        assert math.isfinite(row["pga"]) and row["pgv"] > 0
    s = r["models"]["2d"]["topple"]
    assert s["n"] == 8 and s["tp"] + s["fp"] + s["fn"] + s["tn"] == 8 and 0 <= s["brier"] <= 1
    assert "lift" in r["models"]["2d"]
    # the box's uplift along x is g b / h = 9.81 x 0.1 / 0.4: the rays from G' meet the short sides square
    assert r["specimen"]["b_R"] == pytest.approx(0.1, rel=1e-6) and r["specimen"]["obliquity_R"] == pytest.approx(0)
    # the predicted topple probability grows with the amplitude on this monotonic family
    p = [row["p_topple_2d"] for row in r["rows"]]
    assert p[0] == 0.0 and p[-1] == 1.0


def test_identification_on_another_campaign_is_reported(campaign, tmp_path):
    from statue2model.pipeline.validate import validate

    r = validate(campaign, tmp_path / "o", identify_path=campaign)
    idn = r["identification"]
    assert idn["tests"] == 8 and 0 < idn["alpha"] <= 1 and idn["e_factor"] > 0
    assert r["contact"]["alpha"] == idn["alpha"] and "identified" in r["contact"]["source"]
    assert len(idn["grid"]) >= 10 and idn["balanced_accuracy"] == max(g["balanced_accuracy"] for g in idn["grid"])


@pytest.mark.parametrize("edit, words", [
    (("rock.stl", "/etc/hosts"), "absolute path"),
    (("rock.stl", "../rock.stl"), "leaves the campaign's folder"),
    (("tests.csv", "../tests.csv"), "leaves the campaign's folder"),
    (("units = \"g\"", "units = \"gal\""), "units must be one of"),
    (("direction = 0", "direction = \"east\""), "direction must be a number"),
])
def test_a_campaign_file_is_refused_in_one_line(campaign, edit, words):
    text = campaign.read_text().replace(*edit)
    campaign.write_text(text)
    with pytest.raises(InputError, match=words):
        load_campaign(campaign)


def test_a_tests_file_with_a_bad_row_names_it(campaign):
    tests = campaign.parent / "tests.csv"
    tests.write_text(tests.read_text() + "t9,t0.txt,maybe,0\n")
    with pytest.raises(InputError, match="line 10: toppled must be 0 or 1"):
        load_campaign(campaign)


def test_3d_runs_the_sample_on_the_contact_band(campaign, tmp_path):
    """3D on a sample: each test on the scenes of the band's contacts (tol / 2, tol, 2 tol), P the fraction
    that topple; the box (a flat base: every end of the band the same hull) topples at the top amplitude
    in every scene and stays at the bottom one, as 2D predicts."""
    out = tmp_path / "out3"
    assert main(["validate", str(campaign), "--out", str(out), "--models", "2d,3d", "--sample", "2"]) == 0
    r = json.loads((out / "validation.json").read_text())
    rows3 = [row for row in r["rows"] if "p_topple_3d" in row]
    assert [row["name"] for row in rows3] == ["t0", "t7"]
    assert rows3[0]["p_topple_3d"] == 0.0 and rows3[1]["p_topple_3d"] == 1.0
    assert rows3[1]["topple_3d"] is True and rows3[0]["lift_3d"] is False
    assert "3 contacts of the band" in r["models"]["3d"]["how"] and r["models"]["3d"]["topple"]["n"] == 2
