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
One writer per folder: ``DIR/.statue2model.lock`` (PID, host, start time; created
with ``O_CREAT | O_EXCL``) refuses a second writer at once; a lock whose process
is gone (same host) is reported and replaced. A symlinked folder is followed:
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
MANIFEST_SCHEMA = "statue2model.output/1"

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


def _write_file(tmp: Path, write: Callable[[Path], None]) -> None:
    """The one place every output's bytes are written (tests make it fail)."""
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
    """numpy -> Python, and NaN -> null (JSON has no NaN); infinities stay an error."""
    if isinstance(obj, dict):
        return {k: _clean(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_clean(v) for v in obj]
    if isinstance(obj, np.ndarray):
        return _clean(obj.tolist())
    if isinstance(obj, (float, np.floating)):
        return None if obj != obj else float(obj)
    return obj


def write_json(path: str | os.PathLike, data: Any) -> Path:
    """Write ``data`` as indented JSON (numpy arrays become lists, NaN becomes null), atomically."""
    text = json.dumps(_clean(data), indent=2, default=_default, allow_nan=False) + "\n"
    blob = text.encode("utf-8")
    return atomic_write(path, lambda p: p.write_bytes(blob), size=len(blob))


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
    if name in (MANIFEST_NAME, LOCK_NAME) or name in entries:
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


def acquire_lock(folder: Path, command: str, say=None) -> Path:
    """Create ``folder/.statue2model.lock`` (O_CREAT | O_EXCL) holding this PID, host,
    start time and command; refuse at once when a live process holds it; a lock of a
    process that is gone (same host) is reported with ``say`` and replaced."""
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
            if not isinstance(pid, int):
                if age < 10:                        # being written this instant
                    raise InputError(f"{folder} is in use by another statue2model command; wait for it or "
                                     "choose another --out")
                stale = "an unreadable lock"
            elif host != socket.gethostname() or _pid_alive(pid):
                where = "" if host == socket.gethostname() else f" on {host}"
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
        return lock
    raise InputError(f"{folder} is in use by another statue2model command; wait for it or choose another --out")


def release_lock(lock: Path) -> None:
    """Remove ``lock`` if it is still this process's."""
    try:
        held = json.loads(Path(lock).read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return
    if isinstance(held, dict) and held.get("pid") == os.getpid():
        try:
            Path(lock).unlink()
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
            try:
                left = {p.name for p in self.path.iterdir()}
                if left <= {MANIFEST_NAME}:
                    (self.path / MANIFEST_NAME).unlink(missing_ok=True)
                    self.path.rmdir()
            except OSError:
                pass
            self.created = False

    def owns(self, name: str) -> bool:
        """Whether ``name`` (in this folder) is listed as written by statue2model."""
        return name in self.entries

    def claim(self, names: Iterable[str], kind: str | None = None) -> list[str]:
        """List ``names`` in the manifest before writing them; refuse if one exists and
        statue2model did not write it (it is never touched)."""
        names = [str(n) for n in names]
        clash = [n for n in names if n not in self.entries and os.path.lexists(self.path / n)
                 and n not in self.adoptable]
        if clash:
            them = "them" if len(clash) > 1 else "it"
            raise InputError(f"--out {self.path} holds {', '.join(clash)}, which statue2model did not write and "
                             f"would have to replace: move {them} away or choose another --out (nothing was changed)")
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
        p = self.path / name
        try:
            if p.is_dir() and not p.is_symlink():
                shutil.rmtree(p)
            else:
                p.unlink(missing_ok=True)
        except OSError as exc:
            raise output_error(exc, p) from None

    def clean(self) -> list[Path]:
        """Remove the leftovers of interrupted writes of listed names (hidden partial,
        replaced and temporary files); anything else is kept."""
        removed = []
        for p in self.path.iterdir():
            m = _LEFTOVER.match(p.name)
            if m and m.group("name") in self.entries:
                if p.is_dir() and not p.is_symlink():
                    shutil.rmtree(p, ignore_errors=True)
                else:
                    p.unlink(missing_ok=True)
                removed.append(p)
        return removed

    def _save(self) -> None:
        from .. import __version__

        kind = (read_manifest(self.path) or {}).get("kind", self.kind)
        write_json(self.path / MANIFEST_NAME, {"schema": MANIFEST_SCHEMA, "kind": kind, "version": __version__,
                                               "entries": dict(sorted(self.entries.items()))})


def open_output(path: str | os.PathLike, kind: str, *, reuse: bool = False, command: str | None = None,
                adopt: Callable[[Path], list[str]] | None = None, lock: bool = True, say=None) -> OutputDir:
    """Open output folder ``path`` for a ``kind`` of output (run, slice, props, ...):
    created when new; refused when it holds anything statue2model did not write
    (unless ``reuse``: then the program writes beside it, never touching it); locked
    against a second writer (``lock``). ``adopt(folder)``: names of an older
    statue2model output without a manifest, taken over with ``reuse``."""
    path = Path(path)
    if path.is_symlink():
        path = Path(os.path.realpath(path))      # follow the link: write into its target
    if path.exists() and not path.is_dir():
        raise InputError(f"--out {path} is a file; give a folder")
    created = not path.exists()
    prepare_dir(path)
    if not os.access(path, os.W_OK):
        raise InputError(f"output folder {path} is not writable")
    held = acquire_lock(path, command or kind, say) if lock else None
    try:
        data = read_manifest(path)
        entries = dict(data["entries"]) if data else {}
        foreign = foreign_entries(path, entries)
        older = adopt(path) if (adopt is not None and data is None and foreign) else []
        if foreign and not reuse:
            shown = ", ".join(foreign[:6]) + (", ..." if len(foreign) > 6 else "")
            hint = (f"; it looks like the output of an older statue2model {kind}: pass --reuse to go on with it"
                    if older else ": choose another --out, or pass --reuse to write beside them")
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


def claim_files(paths: Iterable[str | os.PathLike], kind: str) -> None:
    """Before writing the files ``paths`` (e.g. ``props --json``): refuse any that exists
    and statue2model did not write (not listed in its folder's manifest), then list
    them there. The folder may hold anything else: only these names are touched."""
    by_folder: dict[Path, list[str]] = {}
    for p in map(Path, paths):
        by_folder.setdefault(p.parent if str(p.parent) else Path("."), []).append(p.name)
    for folder, names in by_folder.items():
        prepare_dir(folder)
        data = read_manifest(folder)
        entries = dict(data["entries"]) if data else {}
        clash = [n for n in names if n not in entries and os.path.lexists(folder / n)]
        if clash:
            raise InputError(f"{', '.join(str(folder / n) for n in clash)} exists and statue2model did not write "
                             "it: give another file name (nothing was overwritten)")
        OutputDir(folder, kind, entries, None, True).claim(names)
