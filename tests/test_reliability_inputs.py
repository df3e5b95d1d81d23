"""Inputs that once ended in an internal error, a hang, a silent omission or a 50 MB error
line (issue #24): each is now one clear line, or a row of the collection with its reason.

The scans are small boxes; a collection runs the params stage only (about a second a scan)."""
from __future__ import annotations

import json
import os
import threading
from pathlib import Path

import pytest
import trimesh

from statue2model.cli import main
from statue2model.compute.executors import SerialExecutor
from statue2model.errors import InputError, quoted
from statue2model.geometry.scan import read_scan
from statue2model.pipeline.config import load_config_text
from statue2model.pipeline.run import object_folders, run_collection

CFG = load_config_text("[prototype]\nenabled = false\n[crosscheck]\nenabled = false\n", "reliability.toml")


def quiet(msg):
    pass


def box(path: Path, height: float = 0.5) -> Path:
    trimesh.creation.box(extents=(0.3, 0.3, height)).export(path)
    return path


def cli(argv, capsys):
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


# --- 1. an object's folder never takes the name of the collection's own files, nor another's ---
def test_object_folders_are_distinct_and_never_the_collection_s_files():
    scans = ["collection.html.stl", "config.toml.stl", "run.json.ply", ".statue2model.json.stl", "a.stl", "a.ply",
             "a.stl.stl", "A.obj", "girl.ply", "report.html.off"]
    folders = object_folders(scans)
    assert folders == ["collection.html.stl", "config.toml.stl", "run.json.ply", ".statue2model.json.stl", "a.stl",
                       "a.ply", "a.stl.stl", "A.obj", "girl", "report.html.off"]
    assert len({f.casefold() for f in folders}) == len(folders)
    with pytest.raises(InputError, match="differ only in case"):
        object_folders(["Venus.stl", "venus.stl", "venus.ply"])


def test_a_scan_named_like_the_collection_s_files_is_assessed_and_resumed(tmp_path):
    """collection.html.stl once got the folder collection.html, which the page then could not
    replace (IsADirectoryError); a.stl beside a.ply was refused. Every object is now assessed in
    its own folder, the page is written, and a second run finds each object's cache."""
    folder = tmp_path / "scans"
    folder.mkdir()
    for name in ("collection.html.stl", "config.toml.stl", "a.stl", "a.ply"):
        box(folder / name)
    out = tmp_path / "out"
    data = run_collection(folder, out, CFG, stages=["params"], executor=SerialExecutor(), say=quiet)
    assert all("error" not in s for s in data["scans"]), data["scans"]
    assert sorted(r["object"] for r in data["rows"]) == ["a.ply", "a.stl", "collection.html.stl", "config.toml.stl"]
    for name in ("collection.html", "collection.json", "collection.csv", "config.toml"):
        assert (out / name).is_file()
    for name in ("collection.html.stl", "config.toml.stl", "a.stl", "a.ply"):
        assert (out / name / "run.json").is_file()
    page = (out / "collection.html").read_text(encoding="utf-8")
    assert 'href="collection.html.stl/report.html"' in page and 'href="a.ply/report.html"' in page
    again = run_collection(folder, out, CFG, stages=["params"], executor=SerialExecutor(), say=quiet)
    assert [s["status"]["params"] for s in again["scans"]] == ["cached"] * 4


# --- 2. a project file nested 100 000 deep -------------------------------------------------------
def test_a_deeply_nested_project_file_is_one_line_and_status_2(tmp_path, capsys):
    project = tmp_path / "deep.toml"
    project.write_text("x = " + "[" * 100_000 + "]" * 100_000, encoding="utf-8")
    code, _, err = cli(["run", "--config", project, "--out", tmp_path / "o"], capsys)
    assert code == 2 and err.count("\n") == 1, err
    assert err.startswith("statue2model: error: ") and "nested too deeply" in err and "internal" not in err
    assert not (tmp_path / "o").exists()


# --- 3. a scan never opens a file it names (an OBJ's mtllib: a FIFO blocked open() forever) ---
def _read_in_thread(path: Path, fifo: Path, seconds: float = 60.0):
    box_ = {}

    def target():
        try:
            box_["raw"] = read_scan(path)
        except BaseException as exc:        # noqa: BLE001 - handed to the test
            box_["exc"] = exc

    t = threading.Thread(target=target, daemon=True)
    t.start()
    t.join(seconds)
    if t.is_alive():                        # blocked on the FIFO: unblock it (a writer), then fail
        fd = os.open(fifo, os.O_WRONLY | os.O_NONBLOCK)
        os.close(fd)
        t.join(10)
        pytest.fail(f"reading {path.name} blocked on the FIFO {fifo.name}")
    return box_


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="FIFOs are POSIX")
def test_an_obj_whose_mtllib_names_a_fifo_is_read_without_opening_it(tmp_path):
    fifo = tmp_path / "f.mtl"
    os.mkfifo(fifo)
    obj = tmp_path / "x.obj"
    obj.write_text("mtllib f.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 2 4\nf 1 3 4\nf 2 3 4\n")
    got = _read_in_thread(obj, fifo)
    assert "exc" not in got, got.get("exc")
    assert got["raw"].faces.shape == (4, 3)


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="FIFOs are POSIX")
def test_a_fifo_named_as_a_scan_is_refused_at_once(tmp_path):
    fifo = tmp_path / "x.stl"
    os.mkfifo(fifo)
    got = _read_in_thread(fifo, fifo)
    assert isinstance(got.get("exc"), InputError) and "not a regular file (a FIFO)" in str(got["exc"])


# --- 9. a dangling symbolic link or a link loop in a folder is a row with its reason ------------
@pytest.mark.skipif(not hasattr(os, "symlink"), reason="symbolic links")
def test_dangling_links_and_link_loops_are_rows_not_assessed_with_their_reason(tmp_path):
    folder = tmp_path / "scans"
    folder.mkdir()
    box(folder / "good.stl")
    (folder / "x.stl").symlink_to("nowhere.stl")
    (folder / "loop.ply").symlink_to("loop2.ply")
    (folder / "loop2.ply").symlink_to("loop.ply")
    said = []
    data = run_collection(folder, tmp_path / "out", CFG, stages=["params"], executor=SerialExecutor(),
                          say=said.append)
    rows = {r["scan"]: r for r in data["rows"]}
    assert set(rows) == {"good.stl", "x.stl", "loop.ply", "loop2.ply"}
    assert rows["good.stl"]["assessed"]
    assert not rows["x.stl"]["assessed"] and "symbolic link to nowhere.stl, which does not exist" in rows["x.stl"]["reason"]
    assert not rows["loop.ply"]["assessed"] and "symbolic link loop" in rows["loop.ply"]["reason"]
    assert any("x.stl: not assessed" in line for line in said)
    assert data["summary"]["not_assessed"] == 3
    json.dumps(data, allow_nan=False)


# --- 12. a user's value is quoted cut, with its length ---------------------------------------------
BIG = 1_000_000


@pytest.mark.parametrize("text", [
    '[scan]\nunits = "{x}"\n',
    '[scan]\nheight = "{x}"\n',
    '[prototype]\nscale = "{x}"\n',
    '[dynamics]\nmotion = "{x}"\n',
    '[isolator]\nspectrum = "ec8:{x}"\n',
    '[run]\nstages = "{x}"\n',
    '[scan]\n{x} = 1\n',
    '[{x}]\na = 1\n',
    '[rooms.{x}]\nfloor = 1\n',
    '[objects]\n"a.stl" = "{x}"\n',
])
def test_a_huge_value_in_the_project_file_is_quoted_cut_with_its_length(text):
    with pytest.raises(InputError) as err:
        load_config_text(text.replace("{x}", "x" * BIG), "p.toml")
    msg = str(err.value)
    assert len(msg) < 600 and "\n" not in msg, msg[:600]
    assert f"({BIG} characters)" in msg or f"({BIG + 4} characters)" in msg, msg


def test_quoted_cuts_strings_and_containers_and_keeps_short_ones():
    assert quoted("mm") == "'mm'" and quoted("m\nm") == "'m\\nm'" and quoted(1.5) == "1.5"
    assert quoted("x" * 100) == repr("x" * 60) + "... (100 characters)"
    assert quoted("[prototype]", bare=True) == "[prototype]" and quoted("a\nb", bare=True) == "'a\\nb'"
    deep: list = []
    for _ in range(10_000):
        deep = [deep]
    assert len(quoted(deep)) < 100 and len(quoted(list(range(10 ** 6)))) < 100
