"""Ctrl-C from the program's first line, and Ctrl-C that a library swallows (issue #24, items 4 and 5).

Item 4: a Ctrl-C in the first second of any command, while it still imports, printed a
traceback ending in KeyboardInterrupt and the process died of the signal (status -2): the
package's ``__init__`` and the command line's module imported numpy, scipy and the geometry
before ``main`` installed its guard. The entry (``statue2model.__main__:main``, and
``statue2model.cli:main`` of older installs) now imports only the standard library first.

Item 5: trimesh catches ``BaseException`` around each of its optional imports (networkx,
scipy, PIL, rtree...) and in its loaders: a Ctrl-C landing there, while the scan loads, was
dropped; the guard counted it, but the command computed on (props wrote all its files, slice
ran to its end or to the guard's forced stop 20 s later, which left its lock behind). The scan
reader now raises it again (compute.interrupts.interrupt_checkpoint), and the forced stop
releases the process's locks.
"""
from __future__ import annotations

import contextlib
import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

ENV = {**os.environ, "PYTHONUNBUFFERED": "1", "OPENBLAS_NUM_THREADS": "1"}
ENV.pop("STATUE2MODEL_DEBUG", None)
ROOT = Path(__file__).resolve().parents[1]


@pytest.fixture(scope="module")
def box(tmp_path_factory) -> Path:
    import trimesh

    path = tmp_path_factory.mktemp("mesh") / "box.stl"
    trimesh.creation.box(extents=(0.12, 0.10, 0.20)).export(path)
    return path


def _entry_point() -> str:
    """The console script's ``module:function`` (pyproject.toml [project.scripts])."""
    try:
        import tomllib
    except ModuleNotFoundError:  # pragma: no cover - Python 3.10
        import tomli as tomllib
    return tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))["project"]["scripts"]["statue2model"]


# The console script pip writes (bin/statue2model) and `python -m statue2model` (runpy, as -m does). Each
# prints "go" where the program's own code begins: the interpreter's startup, and the import machinery
# finding the entry module, are before any line of the package. The console script: once it has imported
# the entry module (the import is the entry's first line; pip's script runs a line of its own before it
# calls the function); for older installs (statue2model.cli:main) as it calls the function; python -m:
# as runpy starts running __main__.py (an audit hook on its exec).
CONSOLE_SCRIPT = """import re
import sys
from {module} import {function}
print("go", flush=True)
if __name__ == '__main__':
    sys.argv[0] = re.sub(r'(-script\\.pyw|\\.exe)?$', '', sys.argv[0])
    sys.exit({function}())
"""
OLDER_CONSOLE_SCRIPT = """import re
import sys
from statue2model.cli import main
if __name__ == '__main__':
    sys.argv[0] = re.sub(r'(-script\\.pyw|\\.exe)?$', '', sys.argv[0])
    print("go", flush=True)
    sys.exit(main())
"""
PYTHON_M = """import runpy, sys

def first_line(event, args):     # runpy is about to run __main__.py: its first line comes next
    if event == "exec" and getattr(args[0], "co_filename", "").endswith("__main__.py"):
        print("go", flush=True)

sys.addaudithook(first_line)
sys.argv = ["statue2model", *sys.argv[1:]]
runpy.run_module("statue2model", run_name="__main__", alter_sys=True)
"""


def _ctrl_c_after_go(script: Path, args: list[str], delay: float) -> tuple[int, str, bytes]:
    p = subprocess.Popen([sys.executable, str(script), *args], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                         env=ENV, start_new_session=True)
    try:
        assert p.stdout.readline().strip() == b"go"
        time.sleep(delay)
        os.killpg(p.pid, signal.SIGINT)          # a terminal's Ctrl-C: the whole process group
        out, err = p.communicate(timeout=60)
    finally:
        if p.poll() is None:
            os.killpg(p.pid, signal.SIGKILL)
            p.wait()
    return p.returncode, err.decode(errors="replace"), out


@pytest.mark.parametrize("entry", ["console script", "console script of older installs", "python -m"])
def test_ctrl_c_while_the_command_imports_is_one_line_and_130(tmp_path, box, entry):
    if entry == "python -m":
        text = PYTHON_M
    elif entry == "console script":
        module, function = _entry_point().split(":")
        text = CONSOLE_SCRIPT.format(module=module, function=function)
    else:
        text = OLDER_CONSOLE_SCRIPT
    script = tmp_path / "statue2model_entry.py"
    script.write_text(text)
    failures = []
    # from the entry's first line through the imports of the command line and of props (about 0.6 s)
    for delay in (0.0, 0.002, 0.005, 0.01, 0.02, 0.04, 0.07, 0.1, 0.15, 0.2, 0.3, 0.4, 0.55):
        out = tmp_path / f"d{delay}"
        code, err, _ = _ctrl_c_after_go(script, ["props", str(box), "--json", str(out / "p.json")], delay)
        lines = [s for s in err.splitlines() if s.strip()]
        if code != 130 or lines != ["statue2model: interrupted"]:
            failures.append(f"{delay} s: status {code}, stderr {err[-300:]!r}")
        elif out.exists() and any(out.iterdir()):
            failures.append(f"{delay} s: left {sorted(p.name for p in out.iterdir())}")
    assert not failures, "\n".join(failures)


def test_the_entry_modules_import_nothing_heavy():
    """What runs before the entry's first line (the package and the entry module) and the command
    line's own module import no numpy: the Ctrl-C handling comes first."""
    module = _entry_point().split(":")[0]
    code = (f"import sys, {module}, statue2model.cli, statue2model.compute.interrupts\n"
            "print(sorted(m for m in sys.modules if m.split('.')[0] in ('numpy', 'scipy', 'trimesh')))")
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=ENV, timeout=60)
    assert r.returncode == 0, r.stderr
    assert r.stdout.strip() == "[]", r.stdout


# a Ctrl-C that trimesh swallows: it lands while trimesh imports networkx, inside its
# `try: import networkx except BaseException` (the finder below sends it, then waits to be interrupted)
SWALLOWED = """import os, signal, sys, time

class CtrlCInNetworkx:
    def find_spec(self, name, path=None, target=None):
        if name == "networkx":
            sys.meta_path.remove(self)
            os.kill(os.getpid(), signal.SIGINT)
            time.sleep(5)
        return None

sys.meta_path.insert(0, CtrlCInNetworkx())
from statue2model.__main__ import main
sys.argv = ["statue2model", *sys.argv[1:]]
sys.exit(main())
"""


@pytest.mark.parametrize("command", ["props", "slice"])
def test_a_ctrl_c_that_trimesh_swallows_still_stops_the_command(tmp_path, box, command):
    script = tmp_path / "swallowed.py"
    script.write_text(SWALLOWED)
    out = tmp_path / "out"
    args = ["props", str(box), "--json", str(out / "p.json")] if command == "props" else \
        ["slice", str(box), "--out", str(out), "--scale", "1:2", "--no-previews"]
    t0 = time.monotonic()
    r = subprocess.run([sys.executable, str(script), *args], capture_output=True, text=True, env=ENV, timeout=120)
    took = time.monotonic() - t0
    assert r.returncode == 130, (r.returncode, r.stderr[-2000:])
    assert r.stderr.strip() == "statue2model: interrupted", r.stderr[-2000:]
    assert "wrote" not in r.stdout and "Rocking parameters" not in r.stdout, r.stdout[-2000:]
    assert not out.exists() or not any(out.iterdir()), sorted(p.name for p in out.rglob("*"))   # no lock, nothing
    assert took < 15, took


def test_checkpoint_raises_a_swallowed_ctrl_c_under_the_guard_and_alone():
    from statue2model.compute.interrupts import InterruptGuard, interrupt_checkpoint, interrupts_deferred

    def swallowing_library():
        try:
            signal.raise_signal(signal.SIGINT)
        except BaseException:
            pass

    for guarded in (True, False):
        with InterruptGuard() if guarded else contextlib.nullcontext() as guard:
            with pytest.raises(KeyboardInterrupt):
                with interrupt_checkpoint():
                    swallowing_library()
            with interrupt_checkpoint():          # nothing arrived: nothing raised
                pass
            if guarded:
                with pytest.raises(KeyboardInterrupt):       # held by the deferred block, raised at its end
                    with interrupts_deferred():
                        with interrupt_checkpoint():
                            signal.raise_signal(signal.SIGINT)
                guard.stop()
                with interrupt_checkpoint():      # the command is ending: only counted
                    swallowing_library()
        assert signal.getsignal(signal.SIGINT) is signal.default_int_handler


HANGS_WITH_A_LOCK = """import json, os, signal, sys, time
from statue2model.compute.interrupts import InterruptGuard
from statue2model.io.files import open_output
g = InterruptGuard(); g.grace = 0.5
with g:
    od = open_output(sys.argv[1], "slice", command="slice")
    print(json.dumps(str(od.lock)), flush=True)
    while True:                     # a stop that never ends (a Ctrl-C swallowed again and again)
        try:
            os.kill(os.getpid(), signal.SIGINT)
            time.sleep(10)
        except KeyboardInterrupt:
            pass
"""


def test_the_forced_stop_after_ctrl_c_leaves_no_lock(tmp_path):
    script = tmp_path / "hang.py"
    script.write_text(HANGS_WITH_A_LOCK)
    out = tmp_path / "o"
    r = subprocess.run([sys.executable, str(script), str(out)], capture_output=True, text=True, env=ENV, timeout=60)
    assert r.returncode == 130, (r.returncode, r.stderr)
    assert "ended at once" in r.stderr and "Traceback" not in r.stderr, r.stderr
    assert json.loads(r.stdout.splitlines()[0]).endswith(".statue2model.lock")
    assert not (out / ".statue2model.lock").exists()
