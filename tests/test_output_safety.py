"""Never lose a user's files: foreign output folders, one writer per folder, disk
full, symlinked --out (statue2model.io.files.open_output, atomic_write)."""
from __future__ import annotations

import errno
import hashlib
import json
import os
import socket
import subprocess
import sys
from pathlib import Path

import pytest
import trimesh

from statue2model.cli import main
from statue2model.io import files
from statue2model.io.files import LOCK_NAME, MANIFEST_NAME


@pytest.fixture(scope="module")
def box(tmp_path_factory) -> Path:
    path = tmp_path_factory.mktemp("mesh") / "box.stl"
    trimesh.creation.box(extents=(0.12, 0.10, 0.20)).export(path)
    return path


def snapshot(folder: Path) -> dict[str, str]:
    """relative path -> sha256 of every file and "dir" of every folder, hidden ones too."""
    out = {}
    for p in sorted(folder.rglob("*")):
        rel = str(p.relative_to(folder))
        out[rel] = "dir" if p.is_dir() else hashlib.sha256(p.read_bytes()).hexdigest()
    return out


def foreign_folder(path: Path, look_alikes: bool = True) -> Path:
    """A user's folder: hidden files, and names that look like statue2model's."""
    path.mkdir(parents=True)
    (path / "notes.txt").write_text("my notes\n")
    (path / ".backup.old-2024").mkdir()
    (path / ".backup.old-2024" / "thesis.docx").write_bytes(os.urandom(300))
    (path / ".hidden").write_text("secret")
    (path / ".data.partial-12").mkdir()                       # looks like a partial folder of ours
    (path / ".data.partial-12" / "keep.bin").write_bytes(b"\x00\x01")
    if look_alikes:
        (path / "slice.json").write_text('{"n_layers": 3, "pitch": 0.01}')
        (path / "config.toml").write_text("[mine]\nx = 1\n")
        (path / "report.html").write_text("<html>my report</html>")
        (path / "params").mkdir()
        (path / "params" / "measurements.csv").write_text("a,b\n1,2\n")
        (path / "layers").mkdir()
        (path / "layers" / "sketch.dxf").write_text("0\nEOF\n")
    return path


def only_line(capsys) -> str:
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1, err
    return err[0]


COMMANDS = {
    "params": lambda box, out, *extra: ["run", str(box), "--stages", "params", "--out", str(out), *extra],
    "isolator": lambda box, out, *extra: ["run", str(box), "--stages", "isolator", "--out", str(out), *extra],
    "slice": lambda box, out, *extra: ["slice", str(box), "--scale", "1:1", "--no-previews", "--out", str(out),
                                       *extra],
}


@pytest.mark.parametrize("command", sorted(COMMANDS))
@pytest.mark.parametrize("reuse", [False, True])
def test_a_foreign_folder_is_refused_and_never_touched(tmp_path, box, capsys, command, reuse):
    out = foreign_folder(tmp_path / "mine")
    before = snapshot(out)
    code = main(COMMANDS[command](box, out, *(["--reuse"] if reuse else [])))
    line = only_line(capsys)
    assert code == 2, line
    assert line.startswith("statue2model: error: --out ")
    if reuse:       # beside them: but a name it would have to replace collides (config.toml, layers, ...)
        assert "which statue2model did not write and would have to replace" in line
    else:
        assert "holds files statue2model did not write (.backup.old-2024, .data.partial-12, .hidden" in line
        assert "choose another --out, or pass --reuse" in line
    assert snapshot(out) == before


@pytest.mark.slow
@pytest.mark.parametrize("command", ["params", "slice"])
def test_with_reuse_the_output_goes_beside_the_users_files(tmp_path, box, capsys, command):
    out = foreign_folder(tmp_path / "mine", look_alikes=False)
    (out / "run.txt").write_text("not ours")                   # near names are no clash
    before = snapshot(out)
    assert main(COMMANDS[command](box, out, "--reuse")) == 0
    after = snapshot(out)
    assert {k: after.get(k) for k in before} == before          # byte for byte
    entries = json.loads((out / MANIFEST_NAME).read_text())["entries"]
    written = {"params": {"params", "run.json", "config.toml", "report.html"},
               "slice": {"layers", "sheets", "bom.csv", "slice.json", "prototype.stl"}}[command]
    assert written <= set(entries) and not set(entries) & {k.split("/")[0] for k in before}
    assert not (out / LOCK_NAME).exists()
    capsys.readouterr()
    assert main(COMMANDS[command](box, out)) == 2               # still the user's files in it: --reuse again
    assert "did not write (.backup.old-2024, .data.partial-12, .hidden, notes.txt, run.txt)" in only_line(capsys)
    assert main(COMMANDS[command](box, out, "--reuse")) == 0    # its own names are replaced, theirs kept
    after = snapshot(out)
    assert {k: after.get(k) for k in before} == before


def test_props_json_never_overwrites_a_users_file(tmp_path, box, capsys):
    out = foreign_folder(tmp_path / "mine")
    (out / "props.png").write_bytes(b"my picture")
    before = snapshot(out)
    assert main(["props", str(box), "--json", str(out / "props.json")]) == 2
    assert "props.png exists and statue2model did not write it" in only_line(capsys)
    assert snapshot(out) == before
    assert main(["props", str(box), "--json", str(out / "p.json")]) == 0      # new names beside them: fine
    after = snapshot(out)
    assert {k: after.get(k) for k in before} == before
    assert {"p.json", "p.png", "p_rose.csv"} <= set(after)
    assert main(["props", str(box), "--json", str(out / "p.json")]) == 0      # its own: rewritten


def test_an_older_run_is_named_and_taken_over_with_reuse(tmp_path, box, capsys):
    out = tmp_path / "run"
    assert main(COMMANDS["params"](box, out)) == 0
    (out / MANIFEST_NAME).unlink()                               # as written before manifests
    (out / "notes.txt").write_text("mine")
    capsys.readouterr()
    assert main(COMMANDS["params"](box, out)) == 2
    line = only_line(capsys)
    assert "looks like the output of an older statue2model run: pass --reuse" in line
    assert main(COMMANDS["params"](box, out, "--reuse")) == 0
    assert "cached" in capsys.readouterr().out
    assert (out / "notes.txt").read_text() == "mine"
    assert "notes.txt" not in json.loads((out / MANIFEST_NAME).read_text())["entries"]


def test_a_folder_in_use_is_refused_at_once(tmp_path, box, capsys):
    out = tmp_path / "run"
    assert main(COMMANDS["params"](box, out)) == 0
    lock = out / LOCK_NAME                       # a live writer: this very process (PID alive)
    lock.write_text(json.dumps({"pid": os.getpid(), "host": socket.gethostname(),
                                "started": "2026-11-23T17:02:11", "command": "run"}))
    before = snapshot(out)
    capsys.readouterr()
    for argv in (COMMANDS["params"](box, out), COMMANDS["params"](box, out, "--reuse", "--force")):
        assert main(argv) == 2
        line = only_line(capsys)
        assert f"is in use by statue2model run (PID {os.getpid()}, started 17:02:11); wait for it" in line
        assert snapshot(out) == before
    lock.unlink()


def test_a_concurrent_run_in_another_process_is_refused(tmp_path, box):
    out = tmp_path / "run"
    code = ("import sys, time\nfrom statue2model.io.files import open_output\n"
            f"with open_output({str(out)!r}, 'run', command='run'):\n"
            "    print('locked', flush=True)\n    sys.stdin.read()\n")
    holder = subprocess.Popen([sys.executable, "-c", code], stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True)
    try:
        assert holder.stdout.readline().strip() == "locked"
        r = subprocess.run([sys.executable, "-m", "statue2model", *COMMANDS["params"](box, out)],
                           capture_output=True, text=True, timeout=120, check=False)
        assert r.returncode == 2, r.stderr
        assert f"in use by statue2model run (PID {holder.pid}, started " in r.stderr
        assert sorted(p.name for p in out.iterdir()) == [LOCK_NAME]
    finally:
        holder.communicate("", timeout=30)
    assert holder.returncode == 0
    assert not (out / LOCK_NAME).exists()                           # released on exit


def test_a_stale_lock_is_reported_and_replaced(tmp_path, box, capsys):
    gone = subprocess.Popen([sys.executable, "-c", "pass"])
    gone.wait()
    out = tmp_path / "run"
    out.mkdir()
    (out / LOCK_NAME).write_text(json.dumps({"pid": gone.pid, "host": socket.gethostname(),
                                             "started": "2026-11-23T09:00:00", "command": "run"}))
    assert main(COMMANDS["params"](box, out)) == 0
    err = capsys.readouterr().err
    assert f"replaced a stale lock of PID {gone.pid} (started 09:00:00, no longer running)" in err
    assert not (out / LOCK_NAME).exists()
    assert (out / "run.json").is_file()


def test_the_lock_is_released_on_errors_and_ctrl_c(tmp_path):
    out = tmp_path / "o"
    for exc in (RuntimeError("boom"), KeyboardInterrupt()):
        with pytest.raises(type(exc)), files.open_output(out, "run", command="run") as od:
            assert (out / LOCK_NAME).is_file()
            od.claim(["a.txt"])
            files.atomic_write(out / "a.txt", lambda p: p.write_text("x"))
            raise exc
        assert not (out / LOCK_NAME).exists()


def _fail_at(monkeypatch, n: int) -> list:
    """Make the n-th output file written through files.atomic_write fail half-written
    with ENOSPC; returns the list of paths that were attempted."""
    real = files._write_file
    seen = []

    def write(tmp, fn):
        seen.append(tmp)
        real(tmp, fn)
        if len(seen) == n:
            data = Path(tmp).read_bytes()
            Path(tmp).write_bytes(data[: len(data) // 2])   # half of it reached the disk
            raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(files, "_write_file", write)
    return seen


def _leftovers(folder: Path) -> list[str]:
    return [str(p) for p in folder.rglob("*") if p.name.endswith(".part") or ".partial-" in p.name
            or ".old-" in p.name or p.name == LOCK_NAME]


@pytest.mark.parametrize("n", [1, 2, 3, 4])
def test_disk_full_in_props_is_one_line_and_leaves_nothing_that_looks_complete(tmp_path, box, capsys,
                                                                                monkeypatch, n):
    out = tmp_path / "p" / "props.json"
    seen = _fail_at(monkeypatch, n)      # props.json, props_rose.csv, props.png (staged), then the manifest
    assert main(["props", str(box), "--json", str(out)]) == 3
    line = only_line(capsys)
    assert line.startswith("statue2model: error: no space left on device while writing ")
    tmp = Path(seen[-1])
    folder = tmp.parent.parent if tmp.parent.name.startswith(files.STAGING_PREFIX) else tmp.parent
    failed = folder / tmp.name.split(".part")[0].rsplit(".", 1)[0][1:]     # .NAME.XXXX.part -> NAME
    assert f"while writing {failed}" in line                                 # the final name, not the staged one
    assert not failed.exists()
    assert not out.parent.exists()       # all or nothing: no JSON without its CSV and PNG, nothing listed
    assert not _leftovers(tmp_path)


@pytest.fixture(scope="module")
def run_writes(box, tmp_path_factory) -> list[str]:
    """The files a `run --stages params` writes through atomic_write, in order."""
    seen = []
    real = files._write_file
    files._write_file = lambda tmp, fn: (seen.append(Path(tmp).name), real(tmp, fn))[1]
    try:
        assert main(COMMANDS["params"](box, tmp_path_factory.mktemp("count") / "run")) == 0
    finally:
        files._write_file = real
    return seen


@pytest.mark.slow
@pytest.mark.parametrize("which", ["first", "second", "stage.json", "config.toml", "run.json", "last"])
def test_disk_full_in_a_run_is_one_line_and_leaves_nothing_that_looks_complete(tmp_path, box, capsys,
                                                                              monkeypatch, run_writes, which):
    names = [n.split(".part")[0][1:].rsplit(".", 1)[0] for n in run_writes]     # .NAME.XXXX.part -> NAME
    n = {"first": 1, "second": 2, "last": len(names)}.get(which) or names.index(which) + 1
    out = tmp_path / "run"
    seen = _fail_at(monkeypatch, n)
    assert main(COMMANDS["params"](box, out)) == 3
    line = only_line(capsys)
    assert line.startswith("statue2model: error: no space left on device while writing ")
    assert len(seen) == n and f"/{names[n - 1]}" in line
    stage_done = n > names.index("stage.json") + 1
    assert (out / "params").exists() == stage_done                  # a stage folder is there only complete
    assert (out / "params" / "stage.json").exists() == stage_done
    assert not (out / "report.html").exists()                       # written last: never after a failure
    assert (out / "run.json").exists() == (n > names.index("run.json") + 1)
    assert not _leftovers(out) if out.exists() else True
    monkeypatch.undo()
    capsys.readouterr()
    assert main(COMMANDS["params"](box, out)) == 0                  # and the next run works in it
    assert (out / "params" / "stage.json").is_file() and (out / "report.html").is_file()


def test_output_error_text():
    exc = OSError(errno.EDQUOT, "Disk quota exceeded")
    assert str(files.output_error(exc, "o/run.json", 4_200_000)) == "disk quota exceeded while writing o/run.json (4.2 MB)"
    ro = OSError(errno.EROFS, "Read-only file system")
    assert str(files.output_error(ro, "o/a.csv")) == "read-only file system while writing o/a.csv"


def test_an_unwritable_folder_is_one_line(tmp_path, box, capsys, monkeypatch):
    def deny(*a, **k):
        raise PermissionError(errno.EACCES, "Permission denied", str(tmp_path / "ro" / "x"))

    monkeypatch.setattr(files, "_write_file", deny)
    assert main(["props", str(box), "--json", str(tmp_path / "ro" / "props.json")]) == 3
    assert "permission denied while writing" in only_line(capsys)


@pytest.mark.slow
@pytest.mark.parametrize("command", ["params", "slice"])
def test_a_symlinked_out_is_followed_and_kept(tmp_path, box, command):
    target = tmp_path / "real"
    target.mkdir()
    link = tmp_path / "link"
    link.symlink_to(target, target_is_directory=True)
    for _ in range(2):                                      # the second replaces the first's folders
        assert main(COMMANDS[command](box, link, "--force") if command == "params"
                    else COMMANDS[command](box, link)) == 0
        assert link.is_symlink() and os.readlink(link) == str(target)
        assert (target / ("run.json" if command == "params" else "slice.json")).is_file()
        assert not [p.name for p in tmp_path.iterdir() if p.name not in ("real", "link")]
        assert not _leftovers(target)


def test_swap_in_follows_a_link_and_leaves_no_old_folder(tmp_path):
    real = tmp_path / "real"
    real.mkdir()
    (real / "a").write_text("old")
    link = tmp_path / "out"
    link.symlink_to(real)
    new = tmp_path / ".out.partial-1"
    new.mkdir()
    (new / "a").write_text("new")
    files.swap_in(new, link)
    assert link.is_symlink() and (real / "a").read_text() == "new"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out", "real"]


def test_a_folder_with_a_props_record_and_a_slice_folder_is_a_runs_own(tmp_path, box):
    """The default layout: outputs/<scan>/props.json, outputs/<scan>/slice/, then `run` into outputs/<scan>."""
    out = tmp_path / "girl"
    assert main(["props", str(box), "--json", str(out / "props.json")]) == 0
    with files.open_output(out / "slice", "slice", command="slice") as od:
        od.claim(["slice.json"])
        files.write_json(out / "slice" / "slice.json", {"n_layers": 1})
    before = snapshot(out)
    assert main(COMMANDS["params"](box, out)) == 0
    after = snapshot(out)
    assert {k: after.get(k) for k in before if k != MANIFEST_NAME} == {k: v for k, v in before.items()
                                                                     if k != MANIFEST_NAME}
    entries = json.loads((out / MANIFEST_NAME).read_text())["entries"]
    assert entries["props.json"] == "props" and entries["run.json"] == "run"
