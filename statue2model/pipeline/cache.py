"""Content-hash caching of pipeline stages, and folders that are complete or absent.

A stage's *key* is the SHA-256 of everything its result depends on: the stage's
name, the package's source code, the scan file's bytes, the configuration
sections it reads and the keys of the stages it reads from. A stage folder is
complete when its manifest ``stage.json`` exists, holds the same key, and every
file and folder it lists under ``files`` (the SHA-256 of each file the stage wrote,
recorded when it wrote them) is there with those bytes; then the stage is not
recomputed (``--force`` recomputes it anyway). A stage is recognised only from what
the run itself wrote: a file changed, replaced or removed since (a hand study written
into ``dynamics/``) makes the stage run again. Files in a stage folder that the stage
did not write (not listed) are left alone while the stage is taken from the cache; a
stage that must be computed again replaces its whole folder, so then such files, and
listed files whose bytes changed, are refused with one line naming them (nothing is
changed: move them out), as files.open_output refuses a user's files.

A stage is computed in a hidden sibling folder (``.NAME.partial-PID``) and swapped
into place only once its manifest is written, so an interrupted run (Ctrl-C, a
crash, a killed worker) leaves either the previous complete folder or nothing:
never a folder that looks complete. The next run removes stale partial folders
and resumes with the first stage that is not complete.

Example
-------
>>> import tempfile, pathlib
>>> out = pathlib.Path(tempfile.mkdtemp())
>>> key = stage_key("demo", {"x": 1})
>>> def work(d):
...     (d / "result.txt").write_text("42")
...     return {"summary": {"answer": 42}}
>>> m = run_stage(out / "demo", key, work)
>>> m["summary"], m["cached"]
({'answer': 42}, False)
>>> run_stage(out / "demo", key, work)["cached"]            # same inputs: not recomputed
True
>>> run_stage(out / "demo", stage_key("demo", {"x": 2}), work)["cached"]
False
"""
from __future__ import annotations

import hashlib
import json
import os
import shutil
import time
from collections.abc import Callable
from functools import lru_cache
from pathlib import Path

from ..errors import InputError, OutputError
from ..io.files import file_sha256, read_json, swap_in, write_json

MANIFEST = "stage.json"
PACKAGE_DIR = Path(__file__).resolve().parent.parent


def file_hash(path: str | os.PathLike, chunk: int = 1 << 20) -> str:
    """SHA-256 of a file's bytes (hex)."""
    return file_sha256(path, chunk)


@lru_cache(maxsize=1)
def code_hash() -> str:
    """SHA-256 over the package's Python sources: a code change invalidates every stage."""
    h = hashlib.sha256()
    for path in sorted(PACKAGE_DIR.rglob("*.py")):
        h.update(str(path.relative_to(PACKAGE_DIR)).encode())
        h.update(path.read_bytes())
    return h.hexdigest()


def stage_key(name: str, inputs: dict) -> str:
    """Key of stage ``name`` with ``inputs`` (JSON-able: config sections, file
    hashes, upstream keys) and the package's code."""
    blob = json.dumps({"stage": name, "code": code_hash(), "inputs": inputs}, sort_keys=True, default=str)
    return hashlib.sha256(blob.encode()).hexdigest()


DIR = "dir"
"""The value of a folder in a stage manifest's ``files``."""


def stage_files(folder: str | os.PathLike) -> dict[str, str]:
    """Everything in the stage folder ``folder`` but its manifest: relative path (``/``)
    -> SHA-256 of a file's bytes, or ``"dir"`` for a folder; a symlink is not followed
    (it is recorded as ``"link:TARGET"``: a stage writes none)."""
    folder = Path(folder)
    out = {}
    for p in sorted(folder.rglob("*")):
        rel = p.relative_to(folder).as_posix()
        if rel == MANIFEST:
            continue
        if p.is_symlink():
            out[rel] = f"link:{os.readlink(p)}"
        elif p.is_dir():
            out[rel] = DIR
        else:
            out[rel] = file_hash(p)
    return out


def _read_manifest(stage_dir: Path) -> dict | None:
    manifest = Path(stage_dir) / MANIFEST
    if not manifest.is_file():
        return None
    try:
        data = read_json(manifest)
    except (InputError, OSError):  # an unreadable manifest is no manifest
        return None
    return data if isinstance(data, dict) else None


OS_METADATA = (".DS_Store", "Thumbs.db", "desktop.ini")
"""Files a file browser drops into any folder it shows (with macOS's ``._*``): never the
user's work, so a stage folder holding them may be replaced."""


def _os_metadata(name: str) -> bool:
    return name in OS_METADATA or name.startswith("._")


def differences(stage_dir: Path, manifest: dict | None = None) -> dict[str, list[str]]:
    """How the stage folder differs from what its stage wrote: {"changed": listed files
    whose bytes (or kind) differ, "missing": listed names not there, "foreign": names
    not listed (sorted relative paths; a foreign folder is named, not its content)}.
    A folder without a readable manifest: everything in it is foreign. A manifest
    without ``files`` (a run made before they were recorded, taken over with --reuse):
    nothing can be checked, nothing counts as foreign; :func:`completed` never takes
    such a stage from the cache, and it may be replaced."""
    stage_dir = Path(stage_dir)
    manifest = _read_manifest(stage_dir) if manifest is None else manifest
    found = {"changed": [], "missing": [], "foreign": []}
    if not stage_dir.is_dir():
        return found
    if manifest is None:
        found["foreign"] = sorted(p.name for p in stage_dir.iterdir() if not _os_metadata(p.name))
        return found
    listed = manifest.get("files")
    if not isinstance(listed, dict):
        return found
    seen = set()
    for p in sorted(stage_dir.rglob("*")):
        rel = p.relative_to(stage_dir).as_posix()
        if rel == MANIFEST or _os_metadata(p.name) or any(rel.startswith(f + "/") for f in found["foreign"]):
            continue
        seen.add(rel)
        if rel not in listed:
            found["foreign"].append(rel)
            continue
        want = listed[rel]
        if p.is_symlink():
            ok = want == f"link:{os.readlink(p)}"
        elif p.is_dir():
            ok = want == DIR
        else:
            ok = isinstance(want, str) and want != DIR and not want.startswith("link:") and file_hash(p) == want
        if not ok:
            found["changed"].append(rel)
    found["missing"] = sorted(n for n in listed if n not in seen)
    return found


def completed(stage_dir: Path, key: str) -> dict | None:
    """The manifest of a complete stage folder with this key, else None: complete means
    every file the stage listed is there with the bytes it wrote (files it did not list
    are not its output: they do not count)."""
    data = _read_manifest(stage_dir)
    if data is None or data.get("key") != key or not isinstance(data.get("files"), dict):
        return None
    diff = differences(stage_dir, data)
    return None if diff["changed"] or diff["missing"] else data


def check_replaceable(stage_dir: Path) -> None:
    """Refuse (one line; nothing is changed) to replace a stage folder that holds files
    the stage did not write, or listed files changed since it wrote them."""
    diff = differences(stage_dir)
    bad = [f"{n} (not written by the run)" for n in diff["foreign"]] + \
          [f"{n} (changed since the run wrote it)" for n in diff["changed"]]
    if bad:
        shown = ", ".join(bad[:6]) + (f", ... ({len(bad)} in all)" if len(bad) > 6 else "")
        raise InputError(f"{stage_dir} holds {shown}: the {Path(stage_dir).name} stage must be computed again "
                         "and replaces its folder; move them out of it (nothing was changed)")


def run_stage(stage_dir: Path, key: str, work: Callable[[Path], dict], force: bool = False) -> dict:
    """Run ``work(tmp_dir) -> manifest dict`` unless ``stage_dir`` is complete with
    ``key``; returns the manifest, with ``cached`` (bool) and ``seconds`` (of the
    computation, or of the cached one)."""
    stage_dir = Path(stage_dir)
    if not force:
        done = completed(stage_dir, key)
        if done is not None:
            return {**done, "cached": True}
    check_replaceable(stage_dir)
    stage_dir.parent.mkdir(parents=True, exist_ok=True)
    tmp = stage_dir.with_name(f".{stage_dir.name}.partial-{os.getpid()}")
    shutil.rmtree(tmp, ignore_errors=True)
    tmp.mkdir()
    t0 = time.perf_counter()
    try:
        manifest = dict(work(tmp) or {})
        manifest.update(key=key, stage=stage_dir.name, seconds=time.perf_counter() - t0,
                        finished=time.strftime("%Y-%m-%dT%H:%M:%S"), files=stage_files(tmp))
        write_json(tmp / MANIFEST, manifest)
        swap_in(tmp, stage_dir)
    except OutputError as exc:           # name the stage's file, not its hidden partial folder
        shutil.rmtree(tmp, ignore_errors=True)
        if str(tmp) not in str(exc):
            raise
        raise OutputError(str(exc).replace(str(tmp), str(stage_dir))) from None
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        raise
    return {**manifest, "cached": False}
