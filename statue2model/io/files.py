"""Writing output files so that nothing half-written ever looks complete, and
nothing the program did not write is ever removed or overwritten.

Every file is written to a temporary sibling and renamed into place only once it
is complete (``os.replace`` is atomic on one file system); on any error the
temporary file is removed. An ``OSError`` while writing (disk full, quota,
permission, read-only file system, name too long) becomes an
:class:`~statue2model.errors.OutputError` naming the file: one line, exit status 3.

Output folders (``run --out``, ``slice --out``, the folder of ``props --json``)
are opened with :func:`open_output`: the folder must be new, empty, or marked as
statue2model's own by its manifest ``DIR/.statue2model.json``, which names every
file and folder the program wrote there (``entries``: name -> kind of output).
Only listed names are ever replaced or removed; anything else stays untouched.
The manifest is a *claim*, written before the files it names (so an interrupted
run never leaves files the next run would take for the user's); whether a stage
or a slice is complete is told by its own manifest (``stage.json``,
``slice.json``), written last. ``--reuse`` lets a folder with other files be
used: the program writes beside them and refuses a name that collides with one.
A listed name that is no longer there is dropped from the manifest when the folder is
opened again (a file the user puts there later is the user's, not ours).

The files one command writes (``rock --json OUT``: OUT, OUT_history.csv, OUT.png;
``fragility --out DIR``: fragility.json, .csv, .png) appear together or not at all
(:class:`OutputGroup`): each is written into a hidden staging folder beside them
(``.statue2model.staging-PID-*``), and only when every one is complete are they listed
in the manifest and renamed into place; on any error (disk full, Ctrl-C) the staging
folder is removed and nothing of the command appears, nor is listed.
One writer per folder: ``DIR/.statue2model.lock`` (PID, host, start time; created
with ``O_CREAT | O_EXCL``) refuses a second writer at once; a lock whose process
is gone (same host: its PID no longer runs; any host: not refreshed for LOCK_STALE_AFTER s,
whatever process has its PID now) is reported and replaced. A symlinked folder is followed:
the files go into its target, the link stays.

Example
-------
>>> import tempfile
>>> d = Path(tempfile.mkdtemp())
>>> _ = (d / "notes.txt").write_text("mine")
>>> try:
...     open_output(d, "run")
... except InputError as exc:
...     print(str(exc).split(":")[0])
--out ... holds files statue2model did not write (notes.txt)
>>> with open_output(d, "run", reuse=True) as od:
...     _ = od.claim(["run.json"])
...     _ = write_json(d / "run.json", {"ok": True})
>>> sorted(p.name for p in d.iterdir()), (d / "notes.txt").read_text()
(['.statue2model.json', 'notes.txt', 'run.json'], 'mine')
"""
from __future__ import annotations

import errno
import json
import os
import re
import shutil
import signal
import socket
import sys
import tempfile
import time
from collections.abc import Callable, Iterable
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import InputError, OutputError

MANIFEST_NAME = ".statue2model.json"
LOCK_NAME = ".statue2model.lock"
LOCK_HEARTBEAT = 30.0
"""s: the process holding a lock refreshes the lock file's modification time this often."""
LOCK_STALE_AFTER = 600.0
"""s: a lock not refreshed for this long is stale, whatever its PID and host: its process is gone (20
missed heartbeats, wide for clock skew). On another host the PID cannot be checked from here (a lost
cluster worker); on this host a PID still running may be another process's since a reboot or a
wrap-around of the PIDs (a live holder refreshes its lock every LOCK_HEARTBEAT s)."""
MANIFEST_SCHEMA = "statue2model.output/1"
STAGING_PREFIX = ".statue2model.staging-"
"""Hidden folder (``.statue2model.staging-PID-XXXX``) where an :class:`OutputGroup` writes its files."""

#: errno -> the words of the one-line message
_REASONS = {
    errno.ENOSPC: "no space left on device",
    errno.EDQUOT: "disk quota exceeded",
    errno.EACCES: "permission denied",
    errno.EPERM: "operation not permitted",
    errno.EROFS: "read-only file system",
    errno.ENAMETOOLONG: "file name too long",
    errno.EFBIG: "file too large",
    errno.EIO: "input/output error",
    errno.EMFILE: "too many open files",
    errno.ENFILE: "too many open files in the system",
}


def _size_text(size: int) -> str:
    for unit, k in (("GB", 1e9), ("MB", 1e6), ("kB", 1e3)):
        if size >= k:
            return f"{size / k:.1f} {unit}"
    return f"{size} bytes"


def output_error(exc: OSError, path: str | os.PathLike, size: int | None = None) -> OutputError:
    """The one-line :class:`OutputError` for ``exc`` raised while writing ``path``
    (``size``: bytes to be written, when known).

    >>> str(output_error(OSError(errno.ENOSPC, "No space left on device"), "out/a.json", 2048))
    'no space left on device while writing out/a.json (2.0 kB)'
    """
    reason = _REASONS.get(exc.errno) or (exc.strerror or str(exc)).lower()
    extra = f" ({_size_text(size)})" if size else ""
    return OutputError(f"{reason} while writing {path}{extra}")


def _default(obj: Any) -> Any:
    if isinstance(obj, np.ndarray):
        return obj.tolist()
    if isinstance(obj, (np.floating, np.integer)):
        return obj.item()
    if isinstance(obj, np.bool_):
        return bool(obj)
    if isinstance(obj, Path):
        return str(obj)
    raise TypeError(f"cannot write {type(obj).__name__} to JSON")


def prepare_dir(path: str | os.PathLike) -> Path:
    """Create the folder ``path`` (and parents); a clear error if that is impossible
    (:class:`InputError` when the path is taken by a file, else :class:`OutputError`)."""
    path = Path(path)
    try:
        path.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        if exc.errno in _REASONS:
            raise OutputError(f"cannot create output folder {path}: {_REASONS[exc.errno]}") from None
        raise InputError(f"cannot create output folder {path}: {exc.strerror or exc}") from None
    if not os.access(path, os.W_OK):
        raise InputError(f"output folder {path} is not writable")
    return path


def _read_umask() -> int:
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


_UMASK = _read_umask()   # read once: os.umask can only be read by setting it


def stop_if_interrupted() -> None:
    """Before a write: a Ctrl-C that arrived while the command ran stops it here, even one a
    library dropped on its way (``except BaseException``): the SIGINT handler of the command
    line (compute.interrupts.InterruptGuard, found through the signal module: io imports
    nothing above it) counts every Ctrl-C and its ``check`` raises KeyboardInterrupt. Without
    that handler (the package used from Python) nothing happens."""
    check = getattr(signal.getsignal(signal.SIGINT), "check", None)
    if check is not None:
        check()


def _write_file(tmp: Path, write: Callable[[Path], None]) -> None:
    """The one place every output's bytes are written (tests make it fail)."""
    stop_if_interrupted()
    write(tmp)


def atomic_write(path: str | os.PathLike, write: Callable[[Path], None], size: int | None = None) -> Path:
    """Call ``write(tmp_path)`` and move the result to ``path`` only if it succeeds;
    on any error the temporary file is removed, and an ``OSError`` becomes an
    :class:`OutputError` naming ``path`` (``size``: bytes to write, when known)."""
    path = Path(path)
    parent = path.parent if str(path.parent) else Path(".")
    prepare_dir(parent)
    try:
        fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".part", dir=parent)
    except OSError as exc:
        raise output_error(exc, path, size) from None
    os.close(fd)
    tmp_path = Path(tmp)
    try:
        _write_file(tmp_path, write)
        os.chmod(tmp_path, 0o666 & ~_UMASK)  # mkstemp makes 0600; give the usual file mode
        os.replace(tmp_path, path)
    except BaseException as exc:
        try:
            tmp_path.unlink(missing_ok=True)
        except OSError:
            pass
        if isinstance(exc, OSError) and not isinstance(exc, (FileNotFoundError, IsADirectoryError)):
            raise output_error(exc, path, size) from None
        raise
    return path


def _clean(obj: Any) -> Any:
    """numpy -> Python, and every non-finite float (NaN, +-inf; Python or numpy, at any depth of
    dicts, lists, tuples and arrays) -> None: JSON has no spelling for them, and a file must never
    hold one (``null`` is "undefined"; the writer of the value states why beside it)."""
    if isinstance(obj, dict):
        return {k: _clean(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_clean(v) for v in obj]
    if isinstance(obj, np.ndarray):
        return _clean(obj.tolist())
    if isinstance(obj, (float, np.floating)):
        return float(obj) if np.isfinite(obj) else None
    return obj


def write_json(path: str | os.PathLike, data: Any) -> Path:
    """Write ``data`` as indented JSON, atomically: numpy arrays become lists, and every
    non-finite number (NaN, inf; nested too) becomes null (:func:`_clean`), so the file
    always parses as strict JSON.

    >>> import tempfile
    >>> p = write_json(Path(tempfile.mkdtemp()) / "a.json", {"m": [1.5, float("inf")], "b": np.float64("nan")})
    >>> json.loads(p.read_text())
    {'m': [1.5, None], 'b': None}
    """
    text = json.dumps(_clean(data), indent=2, default=_default, allow_nan=False) + "\n"
    blob = text.encode("utf-8")
    return atomic_write(path, lambda p: p.write_bytes(blob), size=len(blob))


def file_sha256(path: str | os.PathLike, chunk: int = 1 << 20) -> str:
    """SHA-256 of a file's bytes (hex)."""
    import hashlib

    h = hashlib.sha256()
    with open(path, "rb") as f:
        while block := f.read(chunk):
            h.update(block)
    return h.hexdigest()


def read_json(path: str | os.PathLike) -> Any:
    """Read a JSON file; a clear error when it is missing or malformed."""
    path = Path(path)
    if not path.is_file():
        raise InputError(f"file not found: {path}")
    try:
        return json.loads(path.read_text(encoding="utf-8"))
    except (UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise InputError(f"{path} is not valid JSON: {exc}") from None


def swap_in(tmp: str | os.PathLike, out: str | os.PathLike) -> Path:
    """Replace folder ``out`` by the complete folder ``tmp`` (two renames on one file
    system; the old folder is removed afterwards), so ``out`` is never half-written.
    A symlinked ``out`` is followed: its target is replaced, the link stays. If the
    second rename fails, the old folder is put back."""
    stop_if_interrupted()
    tmp, out = Path(tmp), Path(out)
    if out.is_symlink():
        out = out.resolve()
    old = None
    try:
        if out.exists():
            old = out.with_name(f".{out.name}.old-{os.getpid()}")
            if old.exists():
                shutil.rmtree(old)
            os.replace(out, old)
        try:
            os.replace(tmp, out)
        except BaseException:
            if old is not None and not out.exists():
                os.replace(old, out)
                old = None
            raise
    except OSError as exc:
        raise output_error(exc, out) from None
    if old is not None:
        shutil.rmtree(old, ignore_errors=True)
        if old.exists():                         # e.g. a file in it held open: say so, do not hide it
            print(f"statue2model: warning: could not remove the replaced folder {old}", file=sys.stderr)
    return out


# --- output folders: a manifest of what the program wrote, and one writer at a time ---------------
_LEFTOVER = re.compile(r"^\.(?P<name>.+?)\.(?:partial-\d+|old-\d+|[^.]+\.part)$")


def read_manifest(folder: str | os.PathLike) -> dict | None:
    """The output manifest of ``folder`` ({"schema", "kind", "entries": {name: kind}}),
    or None when there is none (or it is unreadable: then nothing counts as ours)."""
    path = Path(folder) / MANIFEST_NAME
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, json.JSONDecodeError):
        return None
    if not isinstance(data, dict) or data.get("schema") != MANIFEST_SCHEMA or not isinstance(data.get("entries"), dict):
        return None
    return data


def _ours(name: str, entries: dict) -> bool:
    """Whether the name in a folder with manifest ``entries`` was written by statue2model:
    listed, or a leftover (partial, replaced, temporary) of a listed name."""
    if name in (MANIFEST_NAME, LOCK_NAME) or name in entries or name.startswith(STAGING_PREFIX):
        return True
    m = _LEFTOVER.match(name)
    return bool(m and m.group("name") in entries)


def foreign_entries(folder: str | os.PathLike, entries: dict | None = None) -> list[str]:
    """The names in ``folder`` that statue2model did not write (hidden ones too), sorted;
    ``entries``: the manifest's (default: read from the folder)."""
    folder = Path(folder)
    if entries is None:
        entries = (read_manifest(folder) or {}).get("entries", {})
    if not folder.is_dir():
        return []
    return sorted(p.name for p in folder.iterdir() if not (_ours(p.name, entries) or _own_folder(p)))


def run_stage_of(folder: str | os.PathLike) -> str | None:
    """The stage name when ``folder`` is a stage folder of a ``statue2model run`` (its
    ``stage.json`` names the stage and its cache key), else None. A stage folder is the
    run's: a command writing there would change what the run's cache and report read."""
    try:
        data = json.loads((Path(folder) / "stage.json").read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, json.JSONDecodeError):
        return None
    if isinstance(data, dict) and isinstance(data.get("stage"), str) and isinstance(data.get("key"), str):
        return data["stage"]
    return None


def _refuse_stage_folder(folder: Path, what: str) -> None:
    """Refuse ``folder`` when it is, or lies inside, a stage folder of a run."""
    try:
        real = Path(os.path.realpath(folder))
    except (OSError, ValueError):
        real = Path(folder)
    for f in (real, *real.parents):
        stage = run_stage_of(f)
        if stage is not None:
            inside = "" if f == real else f" inside {f},"
            raise InputError(f"{what} {folder} is{inside} the {stage} stage folder of a statue2model run: the run "
                             "replaces it and reads only what it wrote there; choose another place (nothing was "
                             "written)")


def _own_folder(p: Path) -> bool:
    """A subfolder with its own output manifest (e.g. outputs/girl/slice): statue2model's."""
    return p.is_dir() and not p.is_symlink() and read_manifest(p) is not None


def _pid_alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:             # alive, someone else's
        return True
    except (OverflowError, ValueError, OSError):
        return False
    return True


def _clock(stamp: str) -> str:
    return stamp[11:19] if isinstance(stamp, str) and len(stamp) >= 19 else str(stamp)


def acquire_lock(folder: Path, command: str, say=None, heartbeat: float = LOCK_HEARTBEAT) -> Path:
    """Create ``folder/.statue2model.lock`` (O_CREAT | O_EXCL) holding this PID, host,
    start time and command; refuse at once when a live process holds it; a lock of a
    process that is gone is reported with ``say`` and replaced: on this host a PID no longer
    running, on another host a lock not refreshed for LOCK_STALE_AFTER s (the holder refreshes
    its lock's modification time every ``heartbeat`` s from a daemon thread, :func:`_keep_fresh`,
    which ends when the lock is released). A lock not refreshed for LOCK_STALE_AFTER s is stale
    on this host too, even when its PID is running: after a reboot (or a wrap-around) the PID
    may be an unrelated process's."""
    say = say or (lambda m: print(m, file=sys.stderr))
    lock = Path(folder) / LOCK_NAME
    info = {"pid": os.getpid(), "host": socket.gethostname(), "started": time.strftime("%Y-%m-%dT%H:%M:%S"),
            "command": command}
    for _ in range(3):
        try:
            fd = os.open(lock, os.O_CREAT | os.O_EXCL | os.O_WRONLY, 0o666)   # the umask decides
        except FileExistsError:
            try:
                held = json.loads(lock.read_text(encoding="utf-8"))
                age = time.time() - lock.stat().st_mtime
            except FileNotFoundError:
                continue                            # released meanwhile: try again
            except (OSError, UnicodeDecodeError, json.JSONDecodeError):
                held, age = {}, time.time() - lock.stat().st_mtime if lock.exists() else 0.0
            pid = held.get("pid") if isinstance(held, dict) else None
            host = held.get("host") if isinstance(held, dict) else None
            where = "" if host == socket.gethostname() else f" on {host}"
            if not isinstance(pid, int):
                if age < 10:                        # being written this instant
                    raise InputError(f"{folder} is in use by another statue2model command; wait for it or "
                                     "choose another --out")
                stale = "an unreadable lock"
            elif age > LOCK_STALE_AFTER:            # no heartbeat: whatever runs under that PID now is not its holder
                stale = (f"a lock of PID {pid}{where} (started {_clock(held.get('started'))}) not refreshed for "
                         f"{age:.0f} s (over {LOCK_STALE_AFTER:.0f} s): its process is gone")
            elif where or _pid_alive(pid):
                raise InputError(f"{folder} is in use by statue2model {held.get('command') or 'command'} "
                                 f"(PID {pid}{where}, started {_clock(held.get('started'))}); wait for it or "
                                 "choose another --out")
            else:
                stale = f"a stale lock of PID {pid} (started {_clock(held.get('started'))}, no longer running)"
            say(f"statue2model: note: {folder}: replaced {stale}")
            try:
                lock.unlink()
            except FileNotFoundError:
                pass
            except OSError as exc:
                raise output_error(exc, lock) from None
            continue
        except OSError as exc:
            raise output_error(exc, lock) from None
        try:
            with os.fdopen(fd, "w", encoding="utf-8") as f:
                json.dump(info, f)
        except OSError as exc:
            lock.unlink(missing_ok=True)
            raise output_error(exc, lock) from None
        _HELD_LOCKS.add(lock)
        if heartbeat and heartbeat > 0:
            import threading

            threading.Thread(target=_keep_fresh, args=(lock, heartbeat), name="statue2model-lock-heartbeat",
                             daemon=True).start()
        return lock
    raise InputError(f"{folder} is in use by another statue2model command; wait for it or choose another --out")


def _keep_fresh(lock: Path, every: float) -> None:
    """Refresh ``lock``'s modification time every ``every`` s while it is this process's (ends once it
    is released or taken over: no state outside the file)."""
    while True:
        time.sleep(every)
        try:
            held = json.loads(lock.read_text(encoding="utf-8"))
            if not (isinstance(held, dict) and held.get("pid") == os.getpid()):
                return
            os.utime(lock)
        except (OSError, ValueError):
            return


_HELD_LOCKS: set[Path] = set()
"""The locks this process took and has not released (:func:`release_held_locks`)."""


def release_held_locks() -> None:
    """Release every lock this process holds: called by the CLI's interrupt guard just before it
    ends the process at once (a stop that took too long after Ctrl-C), which runs no ``finally``."""
    for lock in list(_HELD_LOCKS):
        release_lock(lock)


def release_lock(lock: Path) -> None:
    """Remove ``lock`` if it is still this process's."""
    _HELD_LOCKS.discard(Path(lock))
    try:
        held = json.loads(Path(lock).read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return
    if isinstance(held, dict) and held.get("pid") == os.getpid():
        try:
            Path(lock).unlink()
        except OSError:
            pass


def remove_path(p: Path) -> None:
    """Remove a file or a folder (a link is removed, not followed); a missing one is fine."""
    try:
        if p.is_dir() and not p.is_symlink():
            shutil.rmtree(p)
        else:
            p.unlink(missing_ok=True)
    except OSError as exc:
        raise output_error(exc, p) from None


def remove_if_empty(folder: Path) -> None:
    """Remove a folder this command created when it holds nothing but (at most) its manifest."""
    try:
        left = {p.name for p in folder.iterdir()}
        if left <= {MANIFEST_NAME}:
            (folder / MANIFEST_NAME).unlink(missing_ok=True)
            folder.rmdir()
    except OSError:
        pass


class OutputDir:
    """An output folder opened by :func:`open_output` (a context manager: the lock is
    released on exit, also on Ctrl-C and errors). ``path``: the real folder (symlinks
    followed); ``entries``: name -> kind of everything statue2model wrote there."""

    def __init__(self, path: Path, kind: str, entries: dict, lock: Path | None, reuse: bool,
                 adoptable: Iterable[str] = (), created: bool = False):
        self.path, self.kind, self.entries, self.lock, self.reuse = path, kind, dict(entries), lock, reuse
        self.adoptable, self.created = set(adoptable), created

    def __enter__(self) -> OutputDir:
        return self

    def __exit__(self, *exc) -> bool:
        self.close()
        return False

    def close(self) -> None:
        """Release the lock; a folder this command created and wrote nothing into is removed."""
        if self.lock is not None:
            release_lock(self.lock)
            self.lock = None
        if self.created:
            remove_if_empty(self.path)
            self.created = False

    def owns(self, name: str) -> bool:
        """Whether ``name`` (in this folder) is listed as written by statue2model."""
        return name in self.entries

    def check(self, names: Iterable[str]) -> list[str]:
        """Refuse if one of ``names`` exists and statue2model did not write it (before any
        work: nothing is listed or written)."""
        names = [str(n) for n in names]
        clash = [n for n in names if n not in self.entries and os.path.lexists(self.path / n)
                 and n not in self.adoptable]
        if clash:
            them = "them" if len(clash) > 1 else "it"
            raise InputError(f"--out {self.path} holds {', '.join(clash)}, which statue2model did not write and "
                             f"would have to replace: move {them} away or choose another --out (nothing was changed)")
        return names

    def group(self, names: Iterable[str] = ()) -> OutputGroup:
        """An :class:`OutputGroup` writing into this folder; ``names``: the files it will
        write, checked now (a clash with a user's file refuses before any work)."""
        return OutputGroup(self.path, self.kind, od=self, names=self.check(names))

    def claim(self, names: Iterable[str], kind: str | None = None) -> list[str]:
        """List ``names`` in the manifest before writing them; refuse if one exists and
        statue2model did not write it (it is never touched)."""
        names = self.check(names)
        new = [n for n in names if n not in self.entries]
        if new:
            for n in new:
                self.entries[n] = kind or self.kind
            self._save()
        return names

    def forget(self, names: Iterable[str]) -> None:
        """Drop ``names`` from the manifest (after removing them)."""
        gone = [n for n in names if n in self.entries]
        for n in gone:
            del self.entries[n]
        if gone:
            self._save()

    def remove(self, name: str) -> None:
        """Remove the listed ``name`` (file or folder) if it exists; never an unlisted one."""
        if name not in self.entries:
            raise InputError(f"statue2model did not write {self.path / name}; not removing it")
        remove_path(self.path / name)

    def clean(self) -> list[Path]:
        """Remove the leftovers of interrupted writes of listed names (hidden partial,
        replaced and temporary files); anything else is kept, a listed name too (an object's
        folder named like a leftover, from its scan's name)."""
        removed = []
        for p in self.path.iterdir():
            if p.name in self.entries:        # a listed name is never a leftover, whatever it looks like
                continue
            if p.name.startswith(STAGING_PREFIX) and p.is_dir() and not p.is_symlink() and _stale_staging(p.name):
                shutil.rmtree(p, ignore_errors=True)
                removed.append(p)
                continue
            m = _LEFTOVER.match(p.name)
            if m and m.group("name") in self.entries:
                if p.is_dir() and not p.is_symlink():
                    shutil.rmtree(p, ignore_errors=True)
                else:
                    p.unlink(missing_ok=True)
                removed.append(p)
        return removed

    def _save(self) -> None:
        from ..version import __version__

        kind = (read_manifest(self.path) or {}).get("kind", self.kind)
        write_json(self.path / MANIFEST_NAME, {"schema": MANIFEST_SCHEMA, "kind": kind, "version": __version__,
                                               "entries": dict(sorted(self.entries.items()))})


def open_output(path: str | os.PathLike, kind: str, *, reuse: bool = False, command: str | None = None,
                adopt: Callable[[Path], list[str]] | None = None, lock: bool = True, say=None,
                can_reuse: bool = True) -> OutputDir:
    """Open output folder ``path`` for a ``kind`` of output (run, slice, props, ...):
    created when new; refused when it holds anything statue2model did not write
    (unless ``reuse``: then the program writes beside it, never touching it), or when
    it is a stage folder of a run; locked against a second writer (``lock``).
    ``adopt(folder)``: names of an older statue2model output without a manifest, taken
    over with ``reuse``. ``can_reuse``: whether the command has --reuse (its refusal
    mentions it only then)."""
    stop_if_interrupted()
    path = Path(path)
    if path.is_symlink():
        path = Path(os.path.realpath(path))      # follow the link: write into its target
    if path.exists() and not path.is_dir():
        raise InputError(f"--out {path} is a file; give a folder")
    created = not path.exists()
    _refuse_stage_folder(path, "--out")           # a new folder inside a stage folder too
    prepare_dir(path)
    if not os.access(path, os.W_OK):
        raise InputError(f"output folder {path} is not writable")
    held = acquire_lock(path, command or kind, say) if lock else None
    try:
        data = read_manifest(path)
        entries = dict(data["entries"]) if data else {}
        left_over = {m.group("name") for m in map(_LEFTOVER.match, os.listdir(path)) if m}
        gone = [n for n in entries if not os.path.lexists(path / n) and n not in left_over]
        if gone:                                  # listed but not there: a name the user may take later
            entries = {n: k for n, k in entries.items() if n not in gone}
            OutputDir(path, data.get("kind", kind), entries, None, True)._save()
        foreign = foreign_entries(path, entries)
        older = adopt(path) if (adopt is not None and data is None and foreign) else []
        if foreign and not reuse:
            shown = ", ".join(foreign[:6]) + (", ..." if len(foreign) > 6 else "")
            hint = (f"; it looks like the output of an older statue2model {kind}: pass --reuse to go on with it"
                    if older else ": choose another --out, or pass --reuse to write beside them" if can_reuse
                    else ": choose another --out, or move them away (nothing was changed)")
            raise InputError(f"--out {path} holds files statue2model did not write ({shown}){hint}")
        od = OutputDir(path, kind, entries, held, reuse, adoptable=older if reuse else (), created=created)
        if older and reuse:
            od.claim(older)                       # --reuse on an older output: take over its names
        return od
    except BaseException:
        if held is not None:
            release_lock(held)
        if created:
            try:
                path.rmdir()
            except OSError:
                pass
        raise


def _by_folder(paths: Iterable[str | os.PathLike]) -> dict[Path, list[str]]:
    by_folder: dict[Path, list[str]] = {}
    for p in map(Path, paths):
        by_folder.setdefault(p.parent if str(p.parent) else Path("."), []).append(p.name)
    return by_folder


def check_files(paths: Iterable[str | os.PathLike]) -> None:
    """Refuse (before any work; nothing is written) if one of the files ``paths`` exists
    and statue2model did not write it (not listed in its folder's manifest), or is a folder."""
    for folder, names in _by_folder(paths).items():
        _refuse_stage_folder(folder, f"{folder / names[0]}: the folder")
        data = read_manifest(folder) if folder.is_dir() else None
        entries = dict(data["entries"]) if data else {}
        for n in names:
            if (folder / n).is_dir() and not (folder / n).is_symlink() and n not in entries:
                raise InputError(f"{folder / n} is a folder; give a file name")
        clash = [n for n in names if n not in entries and os.path.lexists(folder / n)]
        if clash:
            raise InputError(f"{', '.join(str(folder / n) for n in clash)} exists and statue2model did not write "
                             "it: give another file name (nothing was overwritten)")


def claim_files(paths: Iterable[str | os.PathLike], kind: str) -> None:
    """Refuse as :func:`check_files`, then list the files ``paths`` in their folder's
    manifest (just before they are renamed into place). The folder may hold anything
    else: only these names are touched."""
    check_files(paths)
    for folder, names in _by_folder(paths).items():
        prepare_dir(folder)
        data = read_manifest(folder)
        entries = dict(data["entries"]) if data else {}
        OutputDir(folder, kind, entries, None, True).claim(names)


def _stale_staging(name: str) -> bool:
    """Whether the staging folder ``name`` (STAGING_PREFIX + PID-...) belongs to a process that is gone."""
    pid = name[len(STAGING_PREFIX):].split("-", 1)[0]
    return not (pid.isdigit() and _pid_alive(int(pid)))


class OutputGroup:
    """The files one command writes into ``folder``: they appear together or not at all.

    ``group.path(name)`` (or ``group / name``) is where a file is written: in a hidden
    staging folder ``folder/.statue2model.staging-PID-XXXX`` (made on ``__enter__``).
    Leaving the ``with`` block without an error lists every staged name in the folder's
    manifest (refused if one now collides with a file statue2model did not write) and
    renames them into place; names of ``names`` (the files announced) that were not
    written this time and are statue2model's are removed (no stale plot beside a new
    JSON). On any error (disk full, Ctrl-C, a bug) the staging folder is removed: nothing
    of the group appears or is listed, an older complete output stays, and an
    :class:`OutputError` names the final file, not the staging one. A folder the group
    created and left empty is removed.

    ``od``: the :class:`OutputDir` it writes into (``od.group(names)``); without one, the
    folder's manifest is updated as by :func:`claim_files` (files named by ``--json OUT``).

    >>> import tempfile
    >>> d = Path(tempfile.mkdtemp())
    >>> try:
    ...     with OutputGroup(d, "demo", names=["a.json", "a.csv"]) as g:
    ...         _ = write_json(g / "a.json", {"x": 1})
    ...         raise OSError(errno.ENOSPC, "No space left on device")
    ... except OSError:
    ...     pass
    >>> sorted(p.name for p in d.iterdir())
    []
    >>> with OutputGroup(d, "demo", names=["a.json", "a.csv"]) as g:
    ...     _ = write_json(g / "a.json", {"x": 1})
    ...     _ = atomic_write(g / "a.csv", lambda p: p.write_text("x\\n1\\n"))
    >>> sorted(p.name for p in d.iterdir())
    ['.statue2model.json', 'a.csv', 'a.json']
    """

    def __init__(self, folder: str | os.PathLike, kind: str, od: OutputDir | None = None,
                 names: Iterable[str] = ()):
        self.folder, self.kind, self.od = Path(folder), kind, od
        self.names = [str(n) for n in names]
        if od is None:
            check_files([self.folder / n for n in self.names])
        self.tmp: Path | None = None
        self.created = False
        self.written: list[Path] = []

    @classmethod
    def files(cls, paths: Iterable[str | os.PathLike], kind: str) -> OutputGroup:
        """The group of the files ``paths`` (all in one folder: a command's ``--json OUT``
        and the files beside it), checked now, before any work (see :func:`check_files`)."""
        paths = [Path(p) for p in paths]
        folders = {p.parent for p in paths}
        if len(folders) != 1:
            raise ValueError("an output group's files are in one folder")
        return cls(folders.pop(), kind, names=[p.name for p in paths])

    def path(self, name: str | os.PathLike) -> Path:
        """Where to write the file ``name`` (a name, or its final path in the folder)."""
        if self.tmp is None:
            raise RuntimeError("OutputGroup.path outside its with block")
        name = Path(name)
        if name.parent != Path(".") and name.parent != self.folder:
            raise ValueError(f"{name} is not in the group's folder {self.folder}")
        return self.tmp / name.name

    __truediv__ = path

    def __enter__(self) -> OutputGroup:
        stop_if_interrupted()
        self.created = not self.folder.exists()
        prepare_dir(self.folder)
        try:
            self.tmp = Path(tempfile.mkdtemp(prefix=f"{STAGING_PREFIX}{os.getpid()}-", dir=self.folder))
        except OSError as exc:
            raise output_error(exc, self.folder) from None
        return self

    def __exit__(self, et, exc, tb) -> bool:
        if et is None:
            try:
                self.commit()
            except BaseException:
                self._discard()
                raise
            return False
        self._discard()
        if isinstance(exc, OutputError) and self.tmp is not None and str(self.tmp) in str(exc):
            raise OutputError(str(exc).replace(str(self.tmp), str(self.folder))) from None
        return False

    def _discard(self) -> None:
        if self.tmp is not None:
            shutil.rmtree(self.tmp, ignore_errors=True)
        if self.created:
            remove_if_empty(self.folder)

    def _entries(self) -> dict:
        if self.od is not None:
            return self.od.entries
        return dict((read_manifest(self.folder) or {}).get("entries", {}))

    def _forget(self, names: list[str]) -> None:
        if not names:
            return
        if self.od is not None:
            self.od.forget(names)
        else:
            OutputDir(self.folder, self.kind, self._entries(), None, True).forget(names)

    def commit(self) -> list[Path]:
        """List the staged files and rename them into place (see the class docstring)."""
        stop_if_interrupted()           # a Ctrl-C that arrived meanwhile: nothing appears
        staged = sorted(p.name for p in self.tmp.iterdir())
        listed_before = set(self._entries())
        if self.od is not None:
            self.od.claim(staged)
        elif staged:
            claim_files([self.folder / n for n in staged], self.kind)
        # the earlier files of these names step aside (.NAME.old-PID) until every new one is in
        # place; if a rename fails, the new ones go and the earlier ones come back
        moved: list[tuple[Path, Path | None]] = []           # (final path, its earlier file's backup)
        try:
            for n in staged:
                src, dst = self.tmp / n, self.folder / n
                backup = None
                if os.path.lexists(dst):
                    backup = self.folder / f".{n}.old-{os.getpid()}"
                    if backup.is_dir() and not backup.is_symlink():
                        shutil.rmtree(backup)
                    os.replace(dst, backup)
                moved.append((dst, backup))
                os.replace(src, dst)
                self.written.append(dst)
        except BaseException as exc:
            for dst, backup in reversed(moved):
                try:
                    if dst in self.written:
                        if dst.is_dir() and not dst.is_symlink():
                            shutil.rmtree(dst)
                        else:
                            dst.unlink(missing_ok=True)
                    if backup is not None:
                        os.replace(backup, dst)
                except OSError:
                    pass
            self.written = []
            try:                                    # only what is there stays listed
                self._forget([n for n in staged if n not in listed_before and not os.path.lexists(self.folder / n)])
            except (OSError, OutputError):
                pass
            if isinstance(exc, OSError):
                raise output_error(exc, self.folder / n) from None
            raise
        for _, backup in moved:
            if backup is not None:
                try:
                    if backup.is_dir() and not backup.is_symlink():
                        shutil.rmtree(backup)
                    else:
                        backup.unlink()
                except OSError:
                    pass
        entries = self._entries()
        stale = [n for n in self.names if n not in staged and n in entries]
        for n in stale:
            remove_path(self.folder / n)
        self._forget(stale)
        self.tmp.rmdir()
        self.tmp = None
        self.created = False
        return self.written
