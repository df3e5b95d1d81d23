"""Record sets are read from their set.json (the files it names, each checked against the
length and hash recorded there), never by globbing; a rejected isolator design is refused
wherever a design is an input (statue2model.hazard.matching.read_record_set,
statue2model.cli.isolator.read_design)."""
from __future__ import annotations

import hashlib
import json
from pathlib import Path

import numpy as np
import pytest

from statue2model.cli import main
from statue2model.hazard import motions
from statue2model.hazard import matching
from statue2model.hazard.matching import read_record_set, set_files
from statue2model.errors import InputError
from statue2model.io import files
from folder_snapshots import PARAMS, only_line, snapshot

RECORDS = ["records", "--spectrum", "ec8:ag=0.2g", "--duration", "5", "--band", "0.1:1"]


@pytest.fixture
def params(tmp_path) -> Path:
    p = tmp_path / "p.json"
    p.write_text(json.dumps(PARAMS))
    return p


def fragility(params, records, out, *extra) -> list[str]:
    return ["fragility", str(params), "--records", str(records), "--levels", "0.1g:0.3g:2", "--boot", "0",
            "--out", str(out), *extra]


def hand_set(folder: Path, n: int = 3, **set_json) -> list[Path]:
    """n records of one sample each side of a pulse, m/s^2 (known PGA k + 1), and a set.json."""
    folder.mkdir(parents=True, exist_ok=True)
    paths = []
    for k in range(n):
        paths.append(motions.write_record_csv(folder / f"r{k}.csv",
                                              motions.record(np.r_[0.0, k + 1.0, -(k + 1.0), 0.0], 0.01)))
    data = set_files(folder, [p.name for p in paths])
    data.update(set_json)
    (folder / "set.json").write_text(json.dumps(data))
    return paths


# --- the set is what set.json names -------------------------------------------------------------
def test_a_second_smaller_set_in_one_folder_is_the_set_read(tmp_path, params, capsys):
    """The issue's case: `records --n 7` then `--n 3` into one folder, and fragility ran on 7
    (here 4 then 2: the same path, half the time)."""
    d = tmp_path / "set"
    assert main([*RECORDS, "--n", "4", "--out", str(d)]) == 0
    assert main([*RECORDS, "--n", "2", "--out", str(d)]) == 0
    data = json.loads((d / "set.json").read_text())
    assert data["files"] == ["record_01.csv", "record_02.csv"] and data["units"] == "m/s2"
    for n in data["files"]:
        assert data["file_checks"][n] == {"bytes": (d / n).stat().st_size,
                                          "sha256": hashlib.sha256((d / n).read_bytes()).hexdigest()}
    assert sorted(p.name for p in d.glob("record_*.csv")) == data["files"]       # its own 3 and 4 are gone
    assert set(json.loads((d / files.MANIFEST_NAME).read_text())["entries"]) == {*data["files"], "set.json",
                                                                                  "spectra.png"}
    (d / "record_09.csv").write_text("time_s,acc_m_s2\n0,0\n0.01,5\n")             # not named: not used
    capsys.readouterr()
    assert main(fragility(params, d, tmp_path / "f")) == 0
    out = capsys.readouterr().out
    assert "2 records x 2 levels x 1 samples" in out
    assert f"note: 1 record file in {d} not named by its set.json (record_09.csv): not used" in out
    recs, _ = read_record_set(d)
    assert [m.pga for m in recs] == pytest.approx([motions.read_record(d / n).pga for n in data["files"]])


def test_an_interrupted_records_command_leaves_the_earlier_set_whole(tmp_path, params, capsys, monkeypatch):
    """The issue's case: after a Ctrl-C, fragility used a partial set without a word."""
    d = tmp_path / "set"
    assert main([*RECORDS, "--n", "2", "--out", str(d)]) == 0
    before = snapshot(d)
    real, n = motions.write_record_csv, []

    def write(path, m, dt=None):
        n.append(path)
        if len(n) == 3:
            raise KeyboardInterrupt
        return real(path, m, dt)

    monkeypatch.setattr(motions, "write_record_csv", write)
    assert main([*RECORDS, "--n", "5", "--seed", "7", "--out", str(d)]) == 130
    assert snapshot(d) == before                          # no record of the new set, nothing listed
    monkeypatch.undo()
    capsys.readouterr()
    assert main(fragility(params, d, tmp_path / "f")) == 0
    assert "2 records x 2 levels" in capsys.readouterr().out


@pytest.mark.parametrize("case, words", [
    ("no set.json", "the folder has no set.json: a record set is read from the set.json"),
    ("missing", "the set is incomplete: set.json names 3 records, 1 missing (r1.csv)"),
    ("changed", "r2.csv changed after set.json was written (length or SHA-256 differs)"),
    ("same length", "r0.csv changed after set.json was written"),
    ("no check", "set.json records no length and hash of r1.csv: the set is incomplete"),
    ("outside", "set.json names '../r0.csv': a record is a .csv or .AT2 file in the set's folder"),
    ("count", "set.json is inconsistent: n_records 4 but 3 files"),
    ("empty", "set.json names no record files"),
    ("units", "--units g but set.json says the records are in m/s2"),
])
def test_a_set_that_is_not_whole_is_refused_with_one_line(tmp_path, params, capsys, case, words):
    d = tmp_path / "set"
    paths = hand_set(d)
    data = json.loads((d / "set.json").read_text())
    extra = []
    if case == "no set.json":
        (d / "set.json").unlink()
    elif case == "missing":
        paths[1].unlink()
    elif case == "changed":
        paths[2].write_text(paths[2].read_text() + "0.05,1\n")
    elif case == "same length":
        text = paths[0].read_text()
        paths[0].write_text(text.replace("0.01,1\n", "0.01,7\n"))
        assert len(paths[0].read_bytes()) == data["file_checks"]["r0.csv"]["bytes"]
    elif case == "no check":
        del data["file_checks"]["r1.csv"]
    elif case == "outside":
        data["files"][0] = "../r0.csv"
    elif case == "count":
        data["n_records"] = 4
    elif case == "empty":
        data["files"] = []
    elif case == "units":
        extra = ["--units", "g"]
    if case not in ("no set.json", "missing", "changed", "same length"):
        (d / "set.json").write_text(json.dumps(data))
    out = tmp_path / "f"
    assert main(fragility(params, d, out, *extra)) == 2
    line = only_line(capsys)
    assert line.startswith(f"statue2model: error: --records {d}: ") and words in line, line
    assert not out.exists()


def test_a_hand_written_set_names_its_files_and_their_units(tmp_path):
    d = tmp_path / "own"
    paths = hand_set(d)
    (d / "set.json").write_text(json.dumps({"files": ["r2.csv", "r0.csv"], "units": "g"}))   # no checks: by hand
    recs, info = read_record_set(d)
    assert [m.pga for m in recs] == pytest.approx([3 * 9.80665, 1 * 9.80665])     # its order, in g
    assert info["ignored"] == ["r1.csv"]
    paths[0].unlink()
    with pytest.raises(InputError, match=r"1 missing \(r0.csv\)"):
        read_record_set(d)


def test_the_run_s_fragility_set_is_a_readable_set(tmp_path):
    """dynamics/records/ of a run: set.json written as assessment/study.py does (set_files)."""
    from statue2model.hazard.code_spectra import parse_spectrum

    rs = matching.match_set(parse_spectrum("ec8:ag=0.2g"), n=2, duration=5, band=(0.1, 1.0))
    d = tmp_path / "records"
    d.mkdir()
    names = []
    for i, m in enumerate(rs.records):
        names.append(motions.write_record_csv(d / f"record_{i + 1:02d}.csv", m).name)
    files.write_json(d / "set.json", {**rs.to_dict(), **set_files(d, names)})
    recs, _ = read_record_set(d)
    assert [m.pga for m in recs] == pytest.approx([m.pga for m in rs.records], rel=1e-8)


# --- a rejected design is refused wherever a design is an input --------------------------------
@pytest.fixture(scope="module")
def designs(tmp_path_factory) -> dict[str, Path]:
    d = tmp_path_factory.mktemp("designs")
    p = d / "p.json"
    p.write_text(json.dumps(PARAMS))
    bad = d / "rejected.json"
    assert main(["isolator", "design", str(p), "--spectrum", "ec8:ag=0.4g,ground=D", "--mu", "0.0073",
                 "--alpha", "0.05", "--json", str(bad)]) == 2
    data = json.loads(bad.read_text())
    assert data["passed"] is False
    tampered = d / "tampered.json"                        # says passed, but a required check failed
    tampered.write_text(json.dumps({**data, "passed": True}))
    return {"params": p, "rejected": bad, "tampered": tampered}


@pytest.mark.parametrize("which", ["rejected", "tampered"])
@pytest.mark.parametrize("command", ["fragility", "crosscheck", "plates", "simulate"])
def test_a_rejected_design_is_refused_where_a_design_is_an_input(tmp_path, designs, capsys, command, which):
    dj, p, out = designs[which], designs["params"], tmp_path / "o"
    argv = {"fragility": fragility(p, "synthetic:1,duration=2", out, "--isolator", str(dj)),
            "crosscheck": ["crosscheck", str(p), "--motion", "free:theta0=0.1", "--isolator", str(dj),
                           "--out", str(out)],
            "plates": ["isolator", "plates", str(dj), "--out", str(out)],
            "simulate": ["isolator", "simulate", "--design", str(dj), "--motion", "free:u0=0.05",
                         "--json", str(out / "s.json")]}[command]
    capsys.readouterr()
    assert main(argv) == 2
    line = only_line(capsys)
    assert f"{dj}: `statue2model isolator design` rejected this design (" in line, line
    assert not out.exists()                                   # refused before anything is written


def test_the_pipeline_takes_no_rejected_design(tmp_path):
    from statue2model.pipeline.config import ProjectConfig
    from statue2model.pipeline.stages import Context

    (tmp_path / "design.json").write_text(json.dumps({"R": 0.3, "passed": False}))
    ctx = Context(mesh=tmp_path / "x.stl", config=ProjectConfig(), dirs={"isolator": tmp_path},
                  manifests={"isolator": {"data": {"passed": True}}})
    assert ctx.design() is None
    (tmp_path / "design.json").write_text(json.dumps({"R": 0.3, "passed": True}))
    assert ctx.design() == {"R": 0.3, "passed": True}
    # the ball load is a required check like any other: a design that fails on it alone is not analysed
    checks = [{"key": "travel", "required": True, "passed": True},
              {"key": "ball_load", "required": True, "passed": False}]
    (tmp_path / "design.json").write_text(json.dumps({"R": 0.3, "passed": False, "checks": checks}))
    assert ctx.design() is None


def test_a_design_failing_on_the_ball_load_is_neither_analysed_nor_cut(tmp_path, capsys):
    """The ball load is a required check: a statue too heavy for the only surface allowed gets no device;
    `isolator plates` and `isolator simulate` refuse the design."""
    dj = tmp_path / "heavy.json"
    heavy = tmp_path / "heavy_params.json"
    heavy.write_text(json.dumps({**PARAMS, "m": 4000.0, "I_G": PARAMS["I_G"] * 4000.0 / PARAMS["m"]}))
    assert main(["isolator", "design", str(heavy), "--spectrum", "ec8:ag=0.25g,ground=C", "--mu", "0.0073",
                 "--surface", "beech", "--json", str(dj)]) == 2
    data = json.loads(dj.read_text())
    assert not data["passed"] and "ball_load" in {c["key"] for c in data["checks"] if c["required"] and not c["passed"]}
    assert data["what_would_pass"]["reason"] == "ball_load"
    capsys.readouterr()
    assert main(["isolator", "plates", str(dj), "--out", str(tmp_path / "plates")]) == 2
    assert "rejected this design" in only_line(capsys) and not (tmp_path / "plates").exists()
    assert main(["isolator", "simulate", "--design", str(dj), "--motion", "free:u0=0.05", "--t-end", "1",
                 "--json", str(tmp_path / "s.json")]) == 2
    assert "rejected this design" in only_line(capsys) and not (tmp_path / "s.json").exists()