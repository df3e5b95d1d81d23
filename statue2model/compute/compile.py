"""The numba kernels: compiled once, announced while they compile, cached for later runs.

What is compiled
----------------
The entry points of the four kernel modules that Python calls (:data:`KERNELS`),
each for the one argument-type signature its module declares in ``SIGNATURES``
(float64 scalars, int64 integers, C-contiguous float64 arrays, read-only motion
samples: see :func:`statue2model.rocking.kernel.as_samples`). The helpers they
call are compiled into them. From scratch this takes about 65 s of one core
(:data:`COLD_SECONDS`); :func:`warm_up` runs the four modules in up to three
processes at once (about 35 s on 2 cores). Loading them from the cache takes
well under a second.

* :func:`ensure_compiled` is called by the Python functions in front of the
  kernels (the rocking engine and batch, the plate and coupled simulations, the
  ground acceleration): once per process it checks the cache and, only if a kernel
  is missing, prints one line on stderr before compiling everything
  (``compiling the rocking and isolator kernels once (numba, about 25 s; cached in
  ...)``) and one after (``compiled in 24.1 s``). Worker processes (the ``spawn``
  pool of :mod:`statue2model.compute.executors`) then load the kernels from the
  cache: nothing is compiled twice.
* :func:`warm_up` compiles (or loads) every kernel now, with a line per kernel.
* :func:`cache_state` tells, kernel by kernel, whether the cache holds it;
  :func:`kernel_stats` what this process compiled and loaded.
* ``python3 -m statue2model.compute.compile`` fills the cache (``.ci/install``
  runs it, so the first ``statue2model run`` compiles nothing); ``--check`` only
  reports (exit status 1 when a kernel is missing).

>>> [name.rsplit(".", 2)[-2:] for name in names()][:2]
[['kernel', 'simulate_kernel'], ['kernel', 'simulate_batch']]

Where the cache is (numba's rules, the first that applies)
---------------------------------------------------------
1. ``$NUMBA_CACHE_DIR/<folder>_<sha1 of the folder's path>/`` when that variable is set;
2. the ``__pycache__`` folder beside each kernel module when it is writable:
   ``statue2model/rocking/__pycache__``, ``statue2model/hazard/__pycache__`` and
   ``statue2model/isolator/__pycache__``.
   That is the checkout for an editable install (``pip install -e``, what
   ``.ci/install`` does) and ``<venv>/lib/python3.X/site-packages/statue2model/...``
   for a normal install into a virtual environment the user owns;
3. otherwise (a system-wide install used by another user) the user's cache,
   ``~/.cache/numba/<folder>_<sha1>/`` (``$XDG_CACHE_HOME``): each user compiles once.

Files: ``<module>.<function>-<line>.py3X.nbi`` (index) and ``.1.nbc`` (the machine
code of the one signature). An entry is used only with the same numba and Python
versions, the same CPU and the same bytecode, modification time and size of the
module's file; otherwise the kernel is compiled again (and announced). Numba
checks only the function's own file, but the kernels contain code of other modules:
every kernel that of ``hazard/motion_kernel.py`` (the compiled ground motion), the
rocking, stack and coupled kernels that of ``rocking/dop853.py`` (the shared DOP853
machinery), the isolator and stack kernels that of ``rocking/kernel.py`` (and the coupled
kernel that of ``isolator/kernel.py``): :func:`ensure_compiled` therefore keeps the
hash of those sources beside each such module's cache (``<module>.depends.json``)
and empties that cache when they changed (:data:`DEPENDS`).
"""
from __future__ import annotations

import contextlib
import functools
import hashlib
import importlib
import json
import os
import subprocess
import sys
import threading
import time
from collections.abc import Callable
from pathlib import Path

KERNELS = (
    ("statue2model.rocking.kernel", "simulate_kernel"),
    ("statue2model.rocking.kernel", "simulate_batch"),
    ("statue2model.rocking.kernel", "ground_acc"),
    ("statue2model.isolator.kernel", "coulomb"),
    ("statue2model.isolator.kernel", "boucwen"),
    ("statue2model.isolator.coupled_kernel", "simulate_kernel"),
    ("statue2model.rocking.stack_kernel", "simulate_stack_kernel"),
    ("statue2model.rocking.stack_kernel", "simulate_stack_batch"),
)
"""(module, function) of every kernel entry point called from Python."""

COLD_SECONDS = {
    "statue2model.rocking.kernel.simulate_kernel": 13.0,
    "statue2model.rocking.kernel.simulate_batch": 3.0,
    "statue2model.rocking.kernel.ground_acc": 0.2,
    "statue2model.isolator.kernel.coulomb": 6.0,
    "statue2model.isolator.kernel.boucwen": 3.0,
    "statue2model.isolator.coupled_kernel.simulate_kernel": 12.0,
    "statue2model.rocking.stack_kernel.simulate_stack_kernel": 19.0,
    "statue2model.rocking.stack_kernel.simulate_stack_batch": 6.0,
}
"""Seconds of one core to compile each entry point from scratch, the helpers it
brings included (benchmarks/bench_compile.py on the 2-core test machine); the
announcement's estimate."""

START_SECONDS = 2.0
"""Seconds to start a compiling process (Python, numpy, numba)."""

DEPENDS = {
    "statue2model.rocking.kernel": ("statue2model.rocking.dop853", "statue2model.rocking.sincos",
                                    "statue2model.hazard.motion_kernel"),
    "statue2model.isolator.kernel": ("statue2model.rocking.kernel", "statue2model.rocking.sincos",
                                     "statue2model.hazard.motion_kernel"),
    "statue2model.isolator.coupled_kernel": ("statue2model.rocking.kernel", "statue2model.isolator.kernel",
                                             "statue2model.rocking.dop853", "statue2model.rocking.sincos",
                                             "statue2model.hazard.motion_kernel"),
    "statue2model.rocking.stack_kernel": ("statue2model.rocking.kernel", "statue2model.rocking.dop853",
                                          "statue2model.rocking.sincos", "statue2model.hazard.motion_kernel"),
}
"""Kernel modules whose compiled code also holds code of these modules (numba does
not see that: see the module docstring)."""

_LOCK = threading.Lock()


def _stderr(line: str) -> None:
    print(line, file=sys.stderr, flush=True)


def names() -> list[str]:
    """Qualified names (``module.function``) of :data:`KERNELS`."""
    return [f"{mod}.{fn}" for mod, fn in KERNELS]


def kernels() -> list[tuple[str, object, tuple]]:
    """[(qualified name, numba dispatcher, argument types)] of :data:`KERNELS`."""
    out = []
    for mod, name in KERNELS:
        m = importlib.import_module(mod)
        out.append((f"{mod}.{name}", getattr(m, name), tuple(m.SIGNATURES[name])))
    return out


def _is_dispatcher(fn) -> bool:
    return hasattr(fn, "compile") and hasattr(fn, "signatures")       # not under NUMBA_DISABLE_JIT


def _cached(fn, sig: tuple) -> bool | None:
    """Does numba's cache hold ``fn`` for ``sig``? (numba's own test: the index holds the
    key of the signature, CPU and bytecode, and the source file is unchanged). None when
    that cannot be told (caching off, or another numba's internals)."""
    try:
        cache = fn._cache
        key = cache._index_key(sig, fn.targetctx.codegen())
        return key in cache._cache_file._load_index()
    except Exception:                                  # pragma: no cover - another numba
        return None


def cache_state() -> dict[str, bool | None]:
    """{qualified kernel name: True if this process has it or the cache holds it, False
    if the next call would compile it, None if that cannot be told}."""
    state = {}
    for name, fn, sig in kernels():
        if not _is_dispatcher(fn) or sig in fn.overloads:
            state[name] = True                         # loaded (or NUMBA_DISABLE_JIT: nothing to compile)
        else:
            state[name] = _cached(fn, sig)
    return state


def kernel_stats(_=None) -> dict[str, dict]:
    """{qualified kernel name: {"signatures": [str], "cache_hits": n, "cache_misses": n}}
    in this process (a miss is a compilation here). Module level with one ignored
    argument, so that an executor can map it over its workers."""
    out = {}
    for name, fn, _sig in kernels():
        if _is_dispatcher(fn):
            out[name] = {"signatures": [str(s) for s in fn.signatures],
                         "cache_hits": int(sum(fn.stats.cache_hits.values())),
                         "cache_misses": int(sum(fn.stats.cache_misses.values()))}
    return out


def cache_dirs() -> list[str]:
    """The folders numba caches the kernels in (see the module docstring)."""
    dirs = []
    for _, fn, _ in kernels():
        path = getattr(getattr(fn, "_cache", None), "cache_path", None)
        if path and path not in dirs:
            dirs.append(path)
    return dirs


def _groups(todo: list[str], workers: int) -> list[list[str]]:
    """``todo`` in at most ``workers`` groups, whole modules together (an entry point
    compiles its module's helpers), the largest first into the lightest group."""
    by_mod: dict[str, list[str]] = {}
    for name in todo:
        by_mod.setdefault(name.rsplit(".", 1)[0], []).append(name)
    mods = sorted(by_mod.values(), key=lambda g: -sum(COLD_SECONDS.get(n, 5.0) for n in g))
    groups: list[list[str]] = [[] for _ in range(max(1, min(workers, len(mods))))]
    for g in mods:
        min(groups, key=lambda x: sum(COLD_SECONDS.get(n, 5.0) for n in x)).extend(g)
    return [g for g in groups if g]


def estimate(todo: list[str] | None = None, workers: int | None = None) -> float:
    """Seconds :func:`warm_up` takes to compile ``todo`` (default: every kernel) on
    ``workers`` processes (default: the cores this process may use, at most 3)."""
    todo = names() if todo is None else todo
    groups = _groups(todo, _workers(workers))
    longest = max((sum(COLD_SECONDS.get(n, 5.0) for n in g) for g in groups), default=0.0)
    return longest + (START_SECONDS if len(groups) > 1 else 0.0)


def _workers(workers: int | None) -> int:
    if workers is not None:
        return max(1, int(workers))
    from .executors import available_cores

    return min(3, available_cores())


_CHILD = ("import sys; sys.path.insert(0, sys.argv[1]); "
          "from statue2model.compute.compile import _compile_here; _compile_here(sys.argv[2:])")


def _compile_here(todo: list[str]) -> None:
    """In a compiling process: compile ``todo`` into the cache; one JSON line of
    seconds per kernel on stdout."""
    times = {}
    for name, fn, sig in kernels():
        if name in todo and _is_dispatcher(fn):
            t0 = time.perf_counter()
            fn.compile(sig)
            times[name] = time.perf_counter() - t0
    print(json.dumps(times), flush=True)


def _compile_elsewhere(todo: list[str], workers: int) -> dict[str, float]:
    """Compile ``todo`` in separate processes at once, one group of modules each
    (:func:`_groups`); returns their seconds by kernel ({} if a process failed: the
    caller then compiles here, where an error shows in full)."""
    root = str(Path(__file__).resolve().parents[2])      # the folder holding the statue2model package
    procs = []
    try:
        for g in _groups(todo, workers):
            procs.append(subprocess.Popen([sys.executable, "-c", _CHILD, root, *g], stdout=subprocess.PIPE,
                                          stderr=subprocess.PIPE, text=True))
    except (OSError, ValueError):                      # no interpreter to start: compile here
        for p in procs:
            p.kill()
            p.wait()
        return {}
    times: dict[str, float] = {}
    ok = True
    for p in procs:
        out, _err = p.communicate()
        try:
            times.update(json.loads(out.strip().splitlines()[-1]))
        except (ValueError, IndexError):
            ok = False
        ok = ok and p.returncode == 0
    return times if ok else {}


def warm_up(progress: Callable[[str], None] | None = print, workers: int | None = None) -> dict:
    """Compile (or load from the cache) every kernel entry point for its signature.

    Kernels missing from the cache are compiled in up to ``workers`` processes at once
    (default: the cores this process may use, at most 3; 1: here, one after the
    other), then loaded here. ``progress``: called with one line per kernel (None:
    silent). Returns ``{"seconds": total, "kernels": {name: {"seconds": s,
    "compiled": bool}}}`` (``compiled`` False: it was in the cache or already loaded)."""
    t_all = time.perf_counter()
    _refresh_dependents()
    todo = [k for k, v in cache_state().items() if v is not True]
    workers = _workers(workers)
    elsewhere = _compile_elsewhere(todo, workers) if len(_groups(todo, workers)) > 1 else {}
    report = {}
    for name, fn, sig in kernels():
        if not _is_dispatcher(fn):
            continue
        misses = sum(fn.stats.cache_misses.values())
        t0 = time.perf_counter()
        fn.compile(sig)
        dt = time.perf_counter() - t0
        if sum(fn.stats.cache_misses.values()) > misses:
            report[name], how = {"seconds": dt, "compiled": True}, "compiled"
        elif name in elsewhere:
            report[name], how = {"seconds": elsewhere[name], "compiled": True}, "compiled in a separate process"
        else:
            report[name], how = {"seconds": dt, "compiled": False}, "loaded"
        if progress is not None:
            progress(f"  {name}: {how} in {report[name]['seconds']:.1f} s")
    return {"seconds": time.perf_counter() - t_all, "kernels": report}


@functools.cache
def ensure_compiled(say: Callable[[str], None] = _stderr) -> bool:
    """Once per process: if a kernel is not in the cache, say so on one line (what is
    compiled, about how long, where it is cached), compile every kernel
    (:func:`warm_up`) and say how long it took. Returns True when it compiled. Cheap
    when the cache is warm (a few small index files read); each kernel then loads at
    its first call. Processes of one machine that find the cache cold at once (the
    workers of a collection run) compile one at a time: the others wait, then load."""
    with _LOCK:
        _refresh_dependents()
        if all(v is True for v in cache_state().values()):
            return False
        with _machine_lock():
            state = cache_state()
            todo = [k for k, v in state.items() if v is False]
            if not todo and None not in state.values():     # another process compiled them meanwhile
                return False
            where = ", ".join(cache_dirs()) or "numba's cache"
            if todo:
                say(f"compiling the rocking and isolator kernels once (numba, about {estimate(todo):.0f} s; "
                    f"cached in {where} for later runs)")
            t0 = time.perf_counter()
            res = warm_up(progress=None)
            compiled = any(r["compiled"] for r in res["kernels"].values())
            if todo or compiled:                       # (unknown cache state: said afterwards only)
                say(f"compiled in {time.perf_counter() - t0:.1f} s" if todo else
                    f"compiled the rocking and isolator kernels in {time.perf_counter() - t0:.1f} s (numba; "
                    f"cached in {where} for later runs)")
            return compiled


@contextlib.contextmanager
def _machine_lock():
    """An exclusive lock on ``statue2model-compile.lock`` in the cache folder (no lock
    where that cannot be had: no fcntl, a read-only folder)."""
    f = None
    try:
        import fcntl

        f = open(Path(cache_dirs()[0]) / "statue2model-compile.lock", "a")
        fcntl.flock(f, fcntl.LOCK_EX)
    except (ImportError, OSError, IndexError):
        pass
    try:
        yield
    finally:
        if f is not None:
            f.close()                                  # releases the lock


def _dispatchers(module) -> list:
    """The cached numba functions defined in ``module`` (not those it imports)."""
    return [v for v in vars(module).values() if _is_dispatcher(v) and getattr(v, "_cache", None) is not None
            and getattr(getattr(v, "py_func", None), "__module__", None) == module.__name__]


def _refresh_dependents() -> None:
    """Empty the caches of a kernel module whose dependencies (:data:`DEPENDS`) changed
    since it was compiled; keeps the dependencies' hash beside its cache."""
    for mod, deps in DEPENDS.items():
        disp = _dispatchers(importlib.import_module(mod))
        path = getattr(disp[0]._cache, "cache_path", None) if disp else None
        if not path:
            continue
        h = hashlib.sha256()
        for dep in deps:
            h.update(Path(importlib.import_module(dep).__file__).read_bytes())
        stamp = Path(path) / f"{mod.rsplit('.', 1)[-1]}.depends.json"
        want = {"depends": list(deps), "sha256": h.hexdigest()}
        try:
            if json.loads(stamp.read_text()) == want:
                continue
        except (OSError, ValueError):
            pass
        try:
            for fn in disp:
                fn._cache.flush()                      # an empty index: compiled again at the next call
            tmp = stamp.with_name(f"{stamp.name}.{os.getpid()}.tmp")
            tmp.write_text(json.dumps(want))
            os.replace(tmp, stamp)
        except (OSError, AttributeError):              # pragma: no cover - a read-only cache
            pass


def main(argv: list[str] | None = None) -> int:
    """``python3 -m statue2model.compute.compile [--check] [--workers N]``."""
    import argparse

    ap = argparse.ArgumentParser(prog="python3 -m statue2model.compute.compile",
                                 description="Compile the numba kernels of statue2model into numba's cache "
                                             "(or load them from it), one line per kernel.")
    ap.add_argument("--check", action="store_true",
                    help="only tell which kernels the cache holds (exit status 1 if one is missing)")
    ap.add_argument("--workers", type=int, metavar="N",
                    help="compiling processes at once (default: the cores, at most 3)")
    args = ap.parse_args(argv)
    _refresh_dependents()
    state = cache_state()
    dirs = ", ".join(cache_dirs()) or "numba's cache"
    if args.check:
        for k, v in state.items():
            print(f"  {k}: {'cached' if v else 'not cached' if v is False else 'unknown'}")
        print(f"cache: {dirs}")
        return 0 if all(v is True for v in state.values()) else 1
    todo = [k for k, v in state.items() if v is not True]
    if todo:
        print(f"compiling {len(todo)} of {len(state)} numba kernels (about {estimate(todo, args.workers):.0f} s), "
              f"cached in {dirs}", flush=True)
    with _machine_lock():
        res = warm_up(progress=lambda line: print(line, flush=True), workers=args.workers)
    n = sum(r["compiled"] for r in res["kernels"].values())
    print(f"numba kernels ready in {res['seconds']:.1f} s ({n} compiled, {len(res['kernels']) - n} from the cache)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
