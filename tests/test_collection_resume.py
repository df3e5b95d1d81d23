"""A collection that is interrupted resumes from its cache, and a worker process that dies
does not sink the run: its unfinished tasks are run again on a fresh pool, with the same
numbers (issue #29 item 3).

The scans are two small regular 24-gon prisms (tests/scan_fixtures.column), so the numbers
have closed forms: mass = density x area x height, h = height / 2, b = R cos(pi / 24), and the
weakest uplift acceleration b / h (in g) along an edge normal. Only the params stage runs
(about a second a scan)."""
from __future__ import annotations

import json
import math
import os
import signal
from concurrent.futures.process import BrokenProcessPool
from pathlib import Path

import pytest

from scan_fixtures import column
from statue2model.compute.executors import ProcessExecutor, SerialExecutor
from statue2model.io.files import LOCK_NAME
from statue2model.pipeline import cache
from statue2model.pipeline.config import load_config_text
from statue2model.pipeline.run import run_collection

SIDES = 24
PRISMS = {"column_a": (0.15, 0.6), "column_b": (0.10, 0.5)}      # radius, height in m
DENSITY = 2650.0                                                   # kg/m^3, the default stone
CFG = load_config_text("[prototype]\nenabled = false\n[crosscheck]\nenabled = false\n", "resume.toml")


def quiet(msg):
    pass


def expected(radius: float, height: float) -> dict:
    """Closed-form numbers of a regular SIDES-gon prism standing on its base."""
    area = 0.5 * SIDES * radius ** 2 * math.sin(2 * math.pi / SIDES)
    b = radius * math.cos(math.pi / SIDES)
    return {"mass [kg]": DENSITY * area * height, "h [m]": height / 2, "b_L [m]": b, "b_R [m]": b,
            "weakest uplift [g]": b / (height / 2)}


@pytest.fixture(scope="module")
def scans(tmp_path_factory):
    import trimesh

    folder = tmp_path_factory.mktemp("prisms")
    for name, (r, h) in PRISMS.items():
        v, f = column(radius=r, height=h, rings=4, sectors=SIDES)
        trimesh.Trimesh(v, f, process=False).export(folder / f"{name}.stl")
    return folder


def check_numbers(data: dict) -> None:
    assert [row["scan"] for row in data["table"]] == ["column_a.stl", "column_b.stl"]
    for row in data["table"]:
        ref = expected(*PRISMS[row["scan"][:-4]])
        for key, value in ref.items():
            assert row[key] == pytest.approx(value, rel=1e-5), (row["scan"], key)


class StopAfterFirst(SerialExecutor):
    """Runs the first task, then Ctrl-C (KeyboardInterrupt from the map, as the CLI's guard raises it)."""

    def map(self, fn, items, *, desc=None):
        items = list(items)
        fn(items[0])
        raise KeyboardInterrupt


def test_an_interrupted_collection_resumes_from_the_cache(scans, tmp_path):
    out = tmp_path / "out"
    with pytest.raises(KeyboardInterrupt):
        run_collection(scans, out, CFG, stages=["params"], executor=StopAfterFirst(), say=quiet)
    # nothing locked, nothing half-written that looks complete; the first scan's stage is complete
    assert not list(out.rglob(LOCK_NAME))
    first = out / "column_a" / "params"
    assert cache.completed(first, json.loads((first / "stage.json").read_text())["key"]) is not None
    assert not (out / "column_b" / "params").exists()
    assert not (out / "collection.json").exists()

    again = run_collection(scans, out, CFG, stages=["params"], executor=SerialExecutor(), say=quiet)
    assert [s["status"]["params"] for s in again["scans"]] == ["cached", "done"]
    check_numbers(again)
    assert not list(out.rglob(LOCK_NAME))


def _square_die_once(task):
    """x^2, but the worker running x == 2 is killed (SIGKILL, as ``kill -9``) the first time."""
    marker, x = task
    if x == 2 and not os.path.exists(marker):
        Path(marker).write_text("died once")
        os.kill(os.getpid(), signal.SIGKILL)
    return x * x


def _always_die(x):
    os._exit(3)


@pytest.mark.slow
def test_a_killed_worker_is_replaced_and_its_tasks_run_again(tmp_path):
    marker = str(tmp_path / "died")
    notes = []
    with ProcessExecutor(2, say=notes.append) as ex:
        assert ex.map(_square_die_once, [(marker, x) for x in range(6)]) == [0, 1, 4, 9, 16, 25]
        assert 2 in ex.retried and os.path.exists(marker)
        assert len(ex.notes) == 1 and "SIGKILL" in ex.notes[0] and "run again on a fresh pool" in ex.notes[0]
        assert notes == [f"statue2model: note: {ex.notes[0]}"]
        assert ex.map(_square_die_once, [(marker, x) for x in range(3)]) == [0, 1, 4]   # the fresh pool stays
        assert ex.retried == () and ex.notes == []


@pytest.mark.slow
def test_a_worker_that_dies_on_every_attempt_fails_in_one_line(tmp_path):
    with ProcessExecutor(1, say=quiet) as ex, pytest.raises(BrokenProcessPool) as err:
        ex.map(_always_die, [1])
    text = str(err.value)
    assert "\n" not in text and "exit status 3" in text and "task #1 of 1 not finished" in text


@pytest.mark.slow
def test_a_collection_gives_the_same_numbers_serially_and_on_two_processes(scans, tmp_path):
    serial = run_collection(scans, tmp_path / "serial", CFG, stages=["params"], executor=SerialExecutor(), say=quiet)
    with ProcessExecutor(2) as ex:
        procs = run_collection(scans, tmp_path / "procs", CFG, stages=["params"], executor=ex, say=quiet)
    check_numbers(serial)
    assert procs["table"] == serial["table"]
    assert [s["data"] for s in procs["scans"]] == [s["data"] for s in serial["scans"]]


@pytest.mark.slow
def test_a_lost_dask_worker_s_tasks_run_again_elsewhere(tmp_path):
    """A Dask worker killed while it runs a task (the nanny's process gone, as kill -9 or the
    out-of-memory killer): the scheduler runs the task again on a worker that is left."""
    distributed = pytest.importorskip("distributed")
    from statue2model.compute.executors import DaskExecutor

    marker = str(tmp_path / "died")
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None,
                                  host="127.0.0.1") as cluster, DaskExecutor(cluster.scheduler_address) as ex:
        assert ex.map(_square_die_once, [(marker, x) for x in range(6)]) == [0, 1, 4, 9, 16, 25]
    assert os.path.exists(marker)


def test_a_refused_scan_is_a_ranked_row_with_its_reason(scans, tmp_path):
    """A broken scan beside two good ones (params stage only): all three are rows of collection.json,
    .csv and .html; the broken one first (not assessed: unknown risk) with the scan's own one-line reason;
    the good ones keep their numbers; the page links only the assessed objects' reports."""
    import csv
    import io
    import shutil

    folder = tmp_path / "mixed"
    shutil.copytree(scans, folder)
    (folder / "cracked.stl").write_bytes(b"solid nothing\nendsolid\n")
    data = run_collection(folder, tmp_path / "out", CFG, stages=["params"], executor=SerialExecutor(), say=quiet)
    rows = data["rows"]
    assert [r["object"] for r in rows][0] == "cracked" and rows[0]["rank"] == 1 and not rows[0]["assessed"]
    err = next(s["error"] for s in data["scans"] if s["scan"] == "cracked.stl")
    assert rows[0]["reason"] == err and "\n" not in err and err
    assert {r["object"] for r in rows[1:]} == {"column_a", "column_b"} and all(r["assessed"] for r in rows[1:])
    assert data["summary"]["objects"] == 3 and data["summary"]["not_assessed"] == 1
    body = list(csv.reader(io.StringIO((tmp_path / "out" / "collection.csv").read_text(encoding="utf-8"))))
    assert len(body) == 4 and body[1][body[0].index("object")] == "cracked"
    page = (tmp_path / "out" / "collection.html").read_text(encoding="utf-8")
    assert "not assessed" in page and 'href="column_a/report.html"' in page and 'href="cracked/' not in page
    json.dumps(data, allow_nan=False)


def test_a_lock_of_another_host_is_stale_only_once_its_heartbeat_stops(tmp_path):
    """A collection retried on another cluster host finds the lost worker's lock: refused while that
    lock is refreshed (its process may be alive), replaced with a note once it has not been refreshed
    for LOCK_STALE_AFTER s; the holder's own heartbeat keeps its lock fresh."""
    import time

    from statue2model.errors import InputError
    from statue2model.io import files

    lock = tmp_path / LOCK_NAME
    lock.write_text(json.dumps({"pid": 4242, "host": "other-node", "started": "2026-11-26T08:00:00",
                                "command": "run"}), encoding="utf-8")
    with pytest.raises(InputError, match="in use by statue2model run .PID 4242 on other-node"):
        files.acquire_lock(tmp_path, "run", say=quiet, heartbeat=0)
    old = time.time() - files.LOCK_STALE_AFTER - 5
    os.utime(lock, (old, old))
    notes = []
    mine = files.acquire_lock(tmp_path, "run", say=notes.append, heartbeat=0.05)
    assert "PID 4242 on other-node" in notes[0] and "not refreshed for" in notes[0] and "its process is gone" in notes[0]
    assert json.loads(mine.read_text())["pid"] == os.getpid()
    os.utime(mine, (old, old))                              # the heartbeat refreshes it
    time.sleep(0.3)
    assert time.time() - mine.stat().st_mtime < 5
    files.release_lock(mine)
    assert not mine.exists()


def _serial_cli(monkeypatch):
    """`statue2model run FOLDER` on a SerialExecutor (this process: monkeypatches reach the work)."""
    from statue2model.cli import main
    from statue2model.cli import run as cli_run

    monkeypatch.setattr(cli_run, "_executor", lambda args, cfg: SerialExecutor())
    return main


def _message_lines(err: str) -> list[str]:
    """stderr without the progress bars (tqdm redraws them with carriage returns)."""
    import re

    pieces = (s.strip() for s in re.split(r"[\r\n]", err))
    return [s for s in pieces if s and not re.search(r"\d+/\d+ \[|task/s|it/s", s)]


@pytest.mark.parametrize("n", [1, 5, 9])
def test_disk_full_in_a_folder_run_is_a_write_failure_not_a_failed_scan(scans, tmp_path, monkeypatch, capsys, n):
    """ENOSPC while a scan's files are written (the n-th file written of the run) ends the run with
    exit 3 and one line naming the file (not its hidden partial folder): not one scan's failure
    (before: exit 2, the object ranked first as "not assessed", the next scans run into the same
    full disk), and no collection.json / .csv / .html that looks complete."""
    import errno

    from statue2model.io import files

    main = _serial_cli(monkeypatch)
    real, seen = files._write_file, []

    def write(tmp, fn):
        seen.append(tmp)
        if len(seen) == n:
            raise OSError(errno.ENOSPC, "No space left on device")
        real(tmp, fn)

    monkeypatch.setattr(files, "_write_file", write)
    out = tmp_path / "out"
    assert main(["run", str(scans), "--out", str(out), "--stages", "params"]) == 3
    lines = _message_lines(capsys.readouterr().err)
    assert len(lines) == 1 and lines[0].startswith("statue2model: error: no space left on device while writing "), lines
    assert ".partial-" not in lines[0] and "not assessed" not in lines[0], lines
    for name in ("collection.json", "collection.csv", "collection.html"):
        assert not (out / name).exists()
    assert not [p for p in out.rglob("*") if p.name == LOCK_NAME or ".partial-" in p.name or p.suffix == ".part"]


def test_a_scan_task_passes_write_failures_on_and_keeps_its_own_errors(monkeypatch, tmp_path):
    """The task of one scan (run in worker processes too: the error must pickle) raises an output
    error; a bad scan or a bug stays that scan's row."""
    import errno
    import pickle

    from statue2model.errors import InputError, OutputError
    from statue2model.pipeline import run as pipeline_run

    task = (tmp_path / "a.stl", tmp_path / "a", CFG, ["params"], False, False)
    for raised, escapes in ((OutputError("no space left on device while writing x"), OutputError),
                            (OSError(errno.ENOSPC, "No space left on device", "x/run.json"), OutputError),
                            (OSError(errno.EROFS, "Read-only file system"), OutputError),
                            (InputError("cannot read a.stl"), None), (RuntimeError("bug"), None)):
        def fail(*a, _exc=raised, **k):
            raise _exc

        monkeypatch.setattr(pipeline_run, "run_project", fail)
        if escapes is None:
            assert "error" in pipeline_run._scan_task(task)
            continue
        with pytest.raises(escapes) as info:
            pipeline_run._scan_task(task)
        again = pickle.loads(pickle.dumps(info.value))
        assert type(again) is OutputError and str(again) == str(info.value)


def test_a_lock_whose_heartbeat_stopped_is_taken_over_whatever_its_pid(scans, tmp_path, monkeypatch, capsys):
    """After a reboot the PID of a lock left behind may be another live process's: the folder was
    refused forever ("wait for it"). A lock not refreshed for LOCK_STALE_AFTER s is taken over with
    a one-line note, whatever its PID; a fresh one of a live PID is still refused."""
    import socket
    import time

    from statue2model.io import files

    main = _serial_cli(monkeypatch)
    out = tmp_path / "out"
    out.mkdir()
    lock = out / LOCK_NAME
    alive = os.getppid()                     # a live process, not a statue2model one
    lock.write_text(json.dumps({"pid": alive, "host": socket.gethostname(), "started": "2026-11-26T08:00:00",
                                "command": "run"}), encoding="utf-8")
    assert main(["run", str(scans), "--out", str(out), "--stages", "params"]) == 2     # fresh: in use
    assert f"in use by statue2model run (PID {alive}, started 08:00:00); wait for it" in capsys.readouterr().err
    old = time.time() - files.LOCK_STALE_AFTER - 3600
    os.utime(lock, (old, old))
    assert main(["run", str(scans), "--out", str(out), "--stages", "params"]) == 0
    notes = [s for s in _message_lines(capsys.readouterr().err) if "note" in s]
    assert len(notes) == 1, notes
    assert notes[0].startswith(f"statue2model: note: {out}: replaced a lock of PID {alive} (started 08:00:00) "
                               "not refreshed for ") and f"(over {files.LOCK_STALE_AFTER:.0f} s)" in notes[0], notes
    assert not lock.exists() and (out / "collection.json").is_file()
