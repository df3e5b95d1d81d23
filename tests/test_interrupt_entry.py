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


# Where the Ctrl-C lands is chosen exactly, not by a delay (a delay lands elsewhere on a loaded machine): the
# program runs under an audit hook that sends SIGINT to its own process at one point of the command and
# nowhere else. Points: the N-th import after the entry's first line ("import=N"); the import of a named
# module ("import=networkx": inside trimesh's `try: import networkx except BaseException`); the first
# call of a function while a named module is imported ("call=MODULE/FUNCTION": inside a C extension's
# init: scipy's Cython module `_ccallback_c` calls abc's `register` and clears an error it gets there,
# rtree's finder prints one it catches); the first write of a file whose name holds a text ("open=.part").
# "count" only counts the imports. The hook is armed at the entry's first line: before it, the
# interpreter's own start (site, runpy) answers a Ctrl-C with its traceback, out of the package's reach.
CTRL_C_AT = """import os, signal, sys

kind, _, what = sys.argv[1].partition("=")
state = {"armed": False, "imports": 0, "fired": False}


def ctrl_c():
    state["fired"] = True
    sys.setprofile(None)
    os.kill(os.getpid(), signal.SIGINT)


def first_call_of(name):
    def profile(frame, event, arg):
        if event == "call" and frame.f_code.co_name == name and not state["fired"]:
            ctrl_c()
    return profile


def hook(event, args):
    if not state["armed"] or state["fired"]:
        return
    if event == "import":
        state["imports"] += 1
        if kind == "import" and what in (str(state["imports"]), args[0]):
            ctrl_c()
        elif kind == "call" and args[0] == what.partition("/")[0]:
            sys.setprofile(first_call_of(what.partition("/")[2]))
    elif (kind == "open" and event == "open" and isinstance(args[0], str) and what in os.path.basename(args[0])
          and args[1] not in ("r", "rb")):
        ctrl_c()


def arm():
    state["armed"] = True
    if kind == "count":
        import atexit
        atexit.register(lambda: print(f"imports {state['imports']}", file=sys.stderr))


sys.addaudithook(hook)
sys.argv = ["statue2model", *sys.argv[2:]]
"""
# the console script pip writes (bin/statue2model), armed once it has imported the entry module (its
# first line); that of older installs (statue2model.cli:main), armed as it calls the function;
# `python -m statue2model`, armed as runpy starts running __main__.py (an audit hook on its exec)
ENTRIES = {
    "console script": CTRL_C_AT + "from {module} import {function}\narm()\nsys.exit({function}())\n",
    "console script of older installs": CTRL_C_AT + "from statue2model.cli import main\narm()\nsys.exit(main())\n",
    "python -m": CTRL_C_AT + """import runpy

def first_line(event, args):
    if event == "exec" and getattr(args[0], "co_filename", "").endswith("__main__.py") and not state["armed"]:
        arm()

sys.addaudithook(first_line)
runpy.run_module("statue2model", run_name="__main__", alter_sys=True)
""",
}
NAMED = ["import=networkx", "call=scipy._lib._ccallback_c/register", "call=rtree.finder/LoadLibrary",
         "call=trimesh.exchange.ply/_ply_binary", "open=.part"]


def _entry_script(tmp_path: Path, entry: str) -> Path:
    module, function = _entry_point().split(":")
    script = tmp_path / "statue2model_entry.py"
    script.write_text(ENTRIES[entry].replace("{module}", module).replace("{function}", function))
    return script


def _props_interrupted_at(script: Path, point: str, out: Path, mesh: Path) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, str(script), point, "props", str(mesh), "--json", str(out / "p.json")],
                          capture_output=True, text=True, env=ENV, timeout=300)


def _imports_of_props(script: Path, tmp_path: Path, mesh: Path) -> int:
    r = _props_interrupted_at(script, "count", tmp_path / "count", mesh)
    assert r.returncode == 0, r.stderr[-2000:]
    return int(r.stderr.strip().splitlines()[-1].split()[1])


SCAN = ROOT / "meshes" / "dancing_girl.ply"     # the reproducer (trimesh's PLY reader)


@pytest.mark.slow
@pytest.mark.parametrize("entry", list(ENTRIES))
def test_ctrl_c_anywhere_in_the_imports_is_one_line_130_and_writes_nothing(tmp_path, entry):
    """Issue [24] items 4 and 5: a Ctrl-C at any point from the entry's first line through the imports
    and the scan's reading ends the command: status 130, the one line "statue2model: interrupted", no
    traceback, no file written (none of these points is past the command's last write). It failed at
    "call=scipy._lib._ccallback_c/register" (the interrupt dropped: props wrote its files, then said
    "interrupted"), "call=rtree.finder/LoadLibrary" (a second line "rtree.finder ... unexpected error")
    and "call=trimesh.exchange.ply/_ply_binary" (a second line "cannot read ...: Bad file descriptor"
    on some runs)."""
    script = _entry_script(tmp_path, entry)
    if entry == "console script":
        n = _imports_of_props(script, tmp_path, SCAN)
        assert n > 500, n             # numpy, scipy, trimesh, matplotlib... are imported after the first line
        points = [f"import={k}" for k in [1, 3, 8, 21, 55, 144, 377, n // 2, 3 * n // 4, n]] + NAMED
    else:                             # the entries differ only before the command line's guard is in place
        points = ["import=1", "import=2", "import=4", "import=8", *NAMED[:2]]
    failures = []
    for i, point in enumerate(points):
        out = tmp_path / f"out{i}"
        r = _props_interrupted_at(script, point, out, SCAN)
        lines = [s for s in r.stderr.splitlines() if s.strip()]
        left = sorted(p.name for p in out.iterdir()) if out.exists() else []
        if r.returncode != 130 or lines != ["statue2model: interrupted"] or left:
            failures.append(f"{point}: status {r.returncode}, left {left}, stderr {r.stderr[-300:]!r}")
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


@pytest.mark.slow
@pytest.mark.parametrize("command", ["props", "slice"])
def test_a_ctrl_c_that_trimesh_swallows_still_stops_the_command(tmp_path, box, command):
    script = tmp_path / "swallowed.py"
    script.write_text(SWALLOWED)
    out = tmp_path / "out"
    args = ["props", str(box), "--json", str(out / "p.json")] if command == "props" else \
        ["slice", str(box), "--out", str(out), "--scale", "1:2", "--no-previews"]
    r = subprocess.run([sys.executable, str(script), *args], capture_output=True, text=True, env=ENV, timeout=120)
    assert r.returncode == 130, (r.returncode, r.stderr[-2000:])
    assert r.stderr.strip() == "statue2model: interrupted", r.stderr[-2000:]   # not the forced stop's line
    assert "wrote" not in r.stdout and "Rocking parameters" not in r.stdout, r.stdout[-2000:]
    assert not out.exists() or not any(out.iterdir()), sorted(p.name for p in out.rglob("*"))   # no lock, nothing


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


def test_a_ctrl_c_inside_an_import_is_held_until_the_import_ends(tmp_path, monkeypatch):
    """The guard never raises KeyboardInterrupt inside an import (where a library would drop it, print
    it as its own error, or be left half imported): the module is imported whole, and the interrupt
    comes as soon as the import is over (the guard's watcher sends it again)."""
    from statue2model.compute.interrupts import InterruptGuard

    (tmp_path / "ctrl_c_mid_import.py").write_text(
        "import signal\nsignal.raise_signal(signal.SIGINT)\nfor i in range(100000):\n    pass\nwhole = True\n")
    monkeypatch.syspath_prepend(str(tmp_path))
    with InterruptGuard() as guard:
        with pytest.raises(KeyboardInterrupt):
            try:
                import ctrl_c_mid_import
            except KeyboardInterrupt:
                pytest.fail("KeyboardInterrupt raised inside the import")
            assert ctrl_c_mid_import.whole
            for _ in range(6000):          # the watcher looks every 0.05 s: delivered on one of its looks
                time.sleep(0.01)
        guard.stop()
    assert guard.count == 2                # the Ctrl-C, and its delivery once the import was over


def test_nothing_is_written_after_a_ctrl_c_that_a_library_dropped(tmp_path):
    from statue2model.compute.interrupts import InterruptGuard
    from statue2model.io.files import OutputGroup, atomic_write, write_json

    with InterruptGuard():
        try:                               # a library that drops the Ctrl-C
            signal.raise_signal(signal.SIGINT)
        except BaseException:
            pass
        with pytest.raises(KeyboardInterrupt):
            write_json(tmp_path / "a.json", {"x": 1})
        with pytest.raises(KeyboardInterrupt):
            with OutputGroup(tmp_path / "g", "demo", names=["b.csv"]) as g:
                atomic_write(g / "b.csv", lambda p: p.write_text("x\n"))
    assert sorted(p.name for p in tmp_path.iterdir()) == []
    write_json(tmp_path / "a.json", {"x": 1})    # no guard (the package used from Python): written
    assert (tmp_path / "a.json").exists()
