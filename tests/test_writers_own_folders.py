"""Every writer refuses a folder (or a file) it did not write; a command's outputs appear
together or not at all; a run's stage cache is recognised only from what the run wrote
(statue2model.io.files.open_output / OutputGroup, statue2model.pipeline.cache)."""
from __future__ import annotations

import errno
import hashlib
import json
from pathlib import Path

import pytest
import trimesh

from statue2model.cli import main
from statue2model.errors import InputError
from statue2model.io import files
from statue2model.io.files import MANIFEST_NAME, STAGING_PREFIX
from statue2model.pipeline import cache
from folder_snapshots import PARAMS, only_line, snapshot


def leftovers(folder: Path) -> list[str]:
    return [str(p) for p in folder.rglob("*") if p.name.endswith(".part") or ".partial-" in p.name
            or p.name.startswith(STAGING_PREFIX) or p.name == files.LOCK_NAME]


@pytest.fixture(scope="module")
def box(tmp_path_factory) -> Path:
    path = tmp_path_factory.mktemp("mesh") / "box.stl"
    trimesh.creation.box(extents=(0.12, 0.10, 0.20)).export(path)
    return path


@pytest.fixture
def params(tmp_path) -> Path:
    p = tmp_path / "in" / "p.json"
    p.parent.mkdir()
    p.write_text(json.dumps(PARAMS))
    return p


@pytest.fixture
def csv_record(tmp_path) -> Path:
    p = tmp_path / "in" / "rec.csv"
    p.parent.mkdir(exist_ok=True)
    p.write_text("t,x\n" + "".join(f"{i * 0.01:.2f},{0.01 * (-1) ** (i // 50):.4f}\n" for i in range(400)))
    return p


# --- every command that writes: a user's file of an output's name is refused, never touched -------
# (argv, the name the user's file takes in the output folder OUT); {p}: PARAMS.json, {r}: a CSV
CASES = {
    "props": (["props", "{box}", "--json", "{OUT}/props.json"], "props.png"),
    "rock": (["rock", "{p}", "--motion", "sine:amp=0.3g,freq=2", "--json", "{OUT}/rock.json"], "rock_history.csv"),
    "spectrum": (["spectrum", "{p}", "--freq", "1:2:2", "--amp", "0.1g:0.2g:2", "--json", "{OUT}/s.json"], "s.csv"),
    "variability": (["variability", "{p}", "--motion", "sine:amp=0.3g,freq=2", "--pga", "0.1g:0.2g:2",
                     "--json", "{OUT}/v.json"], "v.png"),
    "sweep": (["sweep", "{p}", "--motion", "sine:amp=0.3g,freq=2", "--param", "e", "--values", "0.8:0.9:2",
               "--json", "{OUT}/w.json"], "w.json"),
    "identify": (["identify", "{p}", "{r}", "--json", "{OUT}/i.json"], "i.csv"),
    "motion": (["motion", "sine:amp=0.3g,freq=2", "--csv", "{OUT}/table.csv"], "table.png"),
    "records": (["records", "--spectrum", "ec8:ag=0.2g", "--n", "1", "--duration", "5", "--band", "0.1:1",
                 "--out", "{OUT}"], "notes.txt"),
    "isolator design": (["isolator", "design", "{p}", "--spectrum", "ec8:ag=0.05g,ground=A", "--mu", "0.0073",
                         "--json", "{OUT}/d.json"], "d.txt"),
    "isolator plates": (["isolator", "plates", "{design}", "--out", "{OUT}"], "notes.txt"),
    "isolator simulate": (["isolator", "simulate", "--R", "0.3", "--r", "0.0183", "--mass", "21", "--mu", "0.0114",
                           "--motion", "free:u0=0.05", "--t-end", "2", "--json", "{OUT}/sim.json"], "sim.csv"),
    "isolator identify": (["isolator", "identify", "{r}", "--json", "{OUT}/f.json"], "f.json"),
    "crosscheck": (["crosscheck", "{p}", "--motion", "free:theta0=0.1", "--out", "{OUT}"], "notes.txt"),
    "fragility": (["fragility", "{p}", "--records", "synthetic:1,duration=2", "--levels", "0.1g:0.2g:2",
                   "--boot", "0", "--out", "{OUT}"], "fragility.json"),
    "config": (["config", "--out", "{OUT}/project.toml"], "project.toml"),
    "slice": (["slice", "{box}", "--scale", "1:1", "--no-previews", "--out", "{OUT}"], "notes.txt"),
    "run": (["run", "{box}", "--stages", "params", "--out", "{OUT}"], "notes.txt"),
}


def _argv(case, box, params, record, out, design=None):
    argv, _ = CASES[case]
    return [a.replace("{box}", str(box)).replace("{p}", str(params)).replace("{r}", str(record))
            .replace("{OUT}", str(out)).replace("{design}", str(design)) for a in argv]


@pytest.mark.parametrize("case", sorted(CASES))
def test_every_writer_refuses_a_users_file_and_touches_nothing(tmp_path, box, params, csv_record, capsys, case):
    out = tmp_path / "mine"
    out.mkdir()
    _, name = CASES[case]
    (out / name).write_text("the user's own file\n")
    design = tmp_path / "in" / "design.json"
    design.write_text(json.dumps({"R": 0.3, "r": 0.0183, "M": 21.0, "mu": 0.0114, "side": 0.4, "thickness": 0.03,
                                  "depth": 0.01, "groove_centres": [[0.1, 0.1], [-0.1, 0.1], [0.0, -0.1]],
                                  "passed": True}))
    before = snapshot(out)
    assert main(_argv(case, box, params, csv_record, out, design)) == 2
    line = only_line(capsys)
    assert line.startswith("statue2model: error:") and name in line, line
    assert snapshot(out) == before


def test_fragility_refuses_a_folder_holding_a_users_study_before_any_work(tmp_path, params, capsys):
    """The issue's case: `fragility --out DIR` overwrote a user's own fragility.json."""
    out = tmp_path / "study"
    out.mkdir()
    (out / "fragility.json").write_text('{"mine": true}\n')
    before = snapshot(out)
    argv = ["fragility", str(params), "--records", "synthetic:1,duration=2", "--levels", "0.1g:1g:2",
            "--boot", "0", "--out", str(out)]
    assert main(argv) == 2
    line = only_line(capsys)
    assert "holds files statue2model did not write (fragility.json): choose another --out, or move them" in line
    assert "records x" not in capsys.readouterr().out          # refused before the study ran
    assert snapshot(out) == before
    # a new folder: written, listed, and a second study replaces its own files
    new = tmp_path / "new"
    assert main(argv[:-1] + [str(new)]) == 0
    entries = json.loads((new / MANIFEST_NAME).read_text())["entries"]
    assert set(entries) == {"fragility.json", "fragility.csv", "fragility.png"}
    assert main(argv[:-1] + [str(new)]) == 0
    assert not leftovers(new)


def test_a_stage_folder_of_a_run_is_refused_as_an_output(tmp_path, box, capsys):
    run = tmp_path / "run"
    assert main(["run", str(box), "--stages", "params", "--out", str(run)]) == 0
    capsys.readouterr()
    before = snapshot(run)
    props = run / "params" / "props.json"
    for argv in (["fragility", str(props), "--records", "synthetic:1,duration=2", "--levels", "0.1g:0.2g:2",
                  "--boot", "0", "--out", str(run / "params")],
                 ["rock", str(props), "--motion", "sine:amp=0.3g,freq=2"],            # default: beside props.json
                 ["records", "--spectrum", "ec8:ag=0.2g", "--n", "1", "--duration", "5", "--band", "0.1:1",
                  "--out", str(run / "params")],
                 ["motion", "sine:amp=0.3g,freq=2", "--csv", str(run / "params" / "sub" / "t.csv")],
                 ["records", "--spectrum", "ec8:ag=0.2g", "--n", "1", "--duration", "5", "--band", "0.1:1",
                  "--out", str(run / "params" / "new" / "set")]):             # a new folder inside one too
        assert main(argv) == 2
        line = only_line(capsys)
        assert " the params stage folder of a statue2model run" in line, line
    assert snapshot(run) == before


# --- outputs appear together or not at all ------------------------------------------------------
def _fail_at(monkeypatch, n: int, err=errno.ENOSPC) -> list:
    """The n-th file written through files.atomic_write fails half-written (ENOSPC)."""
    real, seen = files._write_file, []

    def write(tmp, fn):
        seen.append(Path(tmp))
        real(tmp, fn)
        if len(seen) == n:
            data = Path(tmp).read_bytes()
            Path(tmp).write_bytes(data[: len(data) // 2])
            raise OSError(err, "No space left on device")

    monkeypatch.setattr(files, "_write_file", write)
    return seen


@pytest.mark.parametrize("n", [1, 2, 3, "rename"])
def test_disk_full_leaves_an_earlier_rock_output_whole_and_lists_nothing_new(tmp_path, params, capsys,
                                                                             monkeypatch, n):
    """rock writes rock.json, rock_history.csv and rock.png (staged), then renames them into place:
    a failure at any of them leaves the earlier complete output byte for byte, never a new JSON
    beside an old CSV; "rename": the third rename fails after two new files were in place."""
    out = tmp_path / "o"
    argv = ["rock", str(params), "--motion", "sine:amp=0.3g,freq=2", "--t-end", "2", "--json", str(out / "rock.json")]
    assert main(argv) == 0
    (out / "mine.txt").write_text("user")
    before = snapshot(out)
    capsys.readouterr()
    argv[3] = "sine:amp=0.4g,freq=2"                                      # another result
    if n == "rename":
        real_replace = files.os.replace

        def replace(a, b):
            if Path(a).parent.name.startswith(STAGING_PREFIX) and Path(b).name == "rock_history.csv":
                raise OSError(errno.EIO, "Input/output error")
            return real_replace(a, b)

        monkeypatch.setattr(files.os, "replace", replace)
    else:
        seen = _fail_at(monkeypatch, n)
    code = main(argv)
    line = only_line(capsys)
    assert code == 3, line
    name = "rock_history.csv" if n == "rename" else seen[-1].name.split(".part")[0].rsplit(".", 1)[0][1:]
    assert f"while writing {out / name}" in line                          # the final name, not the staged one
    monkeypatch.undo()
    assert snapshot(out) == before                                        # all or nothing
    assert not leftovers(out) and not list(out.glob(".*.old-*"))
    entries = json.loads((out / MANIFEST_NAME).read_text())["entries"]
    assert set(entries) == {"rock.json", "rock_history.csv", "rock.png"}


def test_a_failed_props_lists_nothing_it_did_not_write(tmp_path, box, capsys, monkeypatch):
    """Minor of the issue: a failed `props --json` left a manifest listing files it never wrote."""
    out = tmp_path / "mine"
    out.mkdir()
    (out / "notes.txt").write_text("mine")
    _fail_at(monkeypatch, 3)                                              # the PNG, the last of the three
    assert main(["props", str(box), "--json", str(out / "props.json")]) == 3
    assert "while writing " + str(out / "props.png") in only_line(capsys)
    assert sorted(p.name for p in out.iterdir()) == ["notes.txt"]         # no manifest, no JSON, no CSV
    monkeypatch.undo()
    assert main(["props", str(box), "--json", str(out / "props.json")]) == 0
    assert set(json.loads((out / MANIFEST_NAME).read_text())["entries"]) == {"props.json", "props_rose.csv",
                                                                             "props.png"}


def test_ctrl_c_while_writing_leaves_no_part_of_the_group(tmp_path, params, monkeypatch, capsys):
    real, seen = files._write_file, []

    def write(tmp, fn):
        seen.append(tmp)
        real(tmp, fn)
        if len(seen) == 2:
            raise KeyboardInterrupt

    monkeypatch.setattr(files, "_write_file", write)
    out = tmp_path / "o" / "rock.json"
    assert main(["rock", str(params), "--motion", "sine:amp=0.3g,freq=2", "--t-end", "2", "--json", str(out)]) == 130
    assert not out.parent.exists()                         # the folder it made for them goes too


def test_a_listed_name_that_is_gone_is_dropped_when_the_folder_is_opened(tmp_path):
    d = tmp_path / "o"
    with files.open_output(d, "demo") as od, od.group(["a.json", "b.json"]) as g:
        files.write_json(g / "a.json", {})
        files.write_json(g / "b.json", {})
    (d / "b.json").unlink()
    with files.open_output(d, "demo") as od:
        assert set(od.entries) == {"a.json"}
    (d / "b.json").write_text("the user's, made later")
    with pytest.raises(InputError, match=r"holds files statue2model did not write \(b.json\)"):
        files.open_output(d, "demo")


def test_a_killed_stage_leaves_a_leftover_that_the_next_open_cleans(tmp_path):
    """A run killed (SIGKILL, or ended at once after Ctrl-C) while a stage was first being
    computed leaves the listed name missing and its hidden partial folder: the folder is
    still ours on the next open, and the leftover is cleaned."""
    d = tmp_path / "run"
    with files.open_output(d, "run") as od, od.group(["run.json"]) as g:
        files.write_json(g / "run.json", {})
        od.claim(["dynamics"])
    partial = d / ".dynamics.partial-999999"
    partial.mkdir()
    (partial / "half.json").write_text("{")
    with files.open_output(d, "run") as od:
        assert "dynamics" in od.entries
        od.clean()
    assert not partial.exists()


def test_a_group_removes_its_own_stale_names_only(tmp_path):
    d = tmp_path / "o"
    with files.open_output(d, "demo") as od, od.group(["a.json", "a.png"]) as g:
        files.write_json(g / "a.json", {"v": 1})
        files.atomic_write(g / "a.png", lambda p: p.write_bytes(b"png"))
    with files.open_output(d, "demo") as od, od.group(["a.json", "a.png"]) as g:   # no plot this time
        files.write_json(g / "a.json", {"v": 2})
    assert sorted(p.name for p in d.iterdir()) == [MANIFEST_NAME, "a.json"]
    assert json.loads((d / MANIFEST_NAME).read_text())["entries"] == {"a.json": "demo"}


# --- the cache: only what the run wrote ---------------------------------------------------------
def _stage(tmp_path):
    key = cache.stage_key("s", {"a": 1})
    calls = []

    def work(d):
        calls.append(1)
        (d / "sub").mkdir()
        (d / "result.json").write_text('{"answer": 42}')
        (d / "sub" / "plot.png").write_bytes(b"png")
        return {"summary": {"answer": 42}}

    return tmp_path / "s", key, work, calls


def test_a_stage_records_the_hashes_of_what_it_wrote(tmp_path):
    d, key, work, calls = _stage(tmp_path)
    m = cache.run_stage(d, key, work)
    assert m["files"] == {"result.json": hashlib.sha256(b'{"answer": 42}').hexdigest(), "sub": "dir",
                          "sub/plot.png": hashlib.sha256(b"png").hexdigest()}
    assert cache.run_stage(d, key, work)["cached"] and len(calls) == 1


@pytest.mark.parametrize("change", ["modified", "replaced", "removed", "added folder removed"])
def test_a_changed_stage_file_means_the_stage_runs_again(tmp_path, change):
    d, key, work, calls = _stage(tmp_path)
    cache.run_stage(d, key, work)
    if change == "modified":                       # a hand study written over the stage's file
        (d / "result.json").write_text('{"answer": 41}')
    elif change == "replaced":                     # same length, other bytes
        (d / "sub" / "plot.png").write_bytes(b"PNG")
    elif change == "removed":
        (d / "sub" / "plot.png").unlink()
    else:
        (d / "sub" / "plot.png").unlink()
        (d / "sub").rmdir()
    assert cache.completed(d, key) is None
    if change in ("modified", "replaced"):         # not silently overwritten: refused, named, untouched
        before = snapshot(d)
        with pytest.raises(InputError, match="changed since the run wrote it") as exc:
            cache.run_stage(d, key, work)
        assert "\n" not in str(exc.value) and snapshot(d) == before and len(calls) == 1
        (d / ("result.json" if change == "modified" else "sub/plot.png")).unlink()   # the user moves it away
    m = cache.run_stage(d, key, work)
    assert not m["cached"] and len(calls) == 2 and cache.completed(d, key) is not None


def test_a_foreign_file_in_a_stage_folder_is_kept_and_refused_when_the_stage_must_run(tmp_path):
    d, key, work, calls = _stage(tmp_path)
    cache.run_stage(d, key, work)
    (d / "my_study.json").write_text("{}")
    assert cache.run_stage(d, key, work)["cached"]                   # the stage's own files are intact
    before = snapshot(d)
    for k, force in ((cache.stage_key("s", {"a": 2}), False), (key, True)):
        with pytest.raises(InputError, match=r"my_study.json \(not written by the run\)"):
            cache.run_stage(d, k, work, force=force)
        assert snapshot(d) == before and len(calls) == 1


def test_a_stage_folder_without_its_manifest_is_foreign(tmp_path):
    d, key, work, calls = _stage(tmp_path)
    d.mkdir()
    (d / "result.json").write_text("mine")
    with pytest.raises(InputError, match="not written by the run"):
        cache.run_stage(d, key, work)
    assert (d / "result.json").read_text() == "mine"


def test_a_run_does_not_serve_a_hand_written_stage_file_as_cached(tmp_path, box, capsys):
    out = tmp_path / "run"
    argv = ["run", str(box), "--stages", "params", "--out", str(out)]
    assert main(argv) == 0
    assert main(argv) == 0
    assert "params     cached" in capsys.readouterr().out
    png = out / "params" / "props.png"
    png.write_bytes(b"a hand-made plot")
    assert main(argv) == 2                        # changed since: the stage must run and would replace it
    line = only_line(capsys)
    assert "props.png (changed since the run wrote it)" in line and png.read_bytes() == b"a hand-made plot"
    png.unlink()                                  # moved away: the stage runs again, not 'cached'
    assert main(argv) == 0
    assert "params     done" in capsys.readouterr().out
    run = json.loads((out / "run.json").read_text())
    assert "files" not in run["stages"]["params"]                     # the hashes stay in stage.json
    assert cache.completed(out / "params", json.loads((out / "params" / "stage.json").read_text())["key"])


def test_os_metadata_in_a_stage_folder_never_blocks_a_recompute(tmp_path):
    """A file browser's .DS_Store / Thumbs.db / ._* is not the user's work: the stage is
    still served from the cache, and recomputed (its folder replaced) when it must be."""
    d, key, work, calls = _stage(tmp_path)
    cache.run_stage(d, key, work)
    for name in (".DS_Store", "Thumbs.db", "._result.json"):
        (d / name).write_bytes(b"\0metadata")
    assert cache.run_stage(d, key, work)["cached"]
    m = cache.run_stage(d, key + "-changed", work)
    assert not m["cached"] and len(calls) == 2
    (d / "notes.txt").write_text("mine")                     # the user's own file still blocks it
    with pytest.raises(InputError, match=r"notes.txt \(not written by the run\)"):
        cache.run_stage(d, key + "-again", work)
