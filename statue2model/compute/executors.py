"""Where many independent runs execute: one interface for every sweep.

An :class:`Executor` maps a module-level function over a list of items and
returns the results in the order of the items, whatever order they finish in:

* :class:`SerialExecutor` - one after the other in this process (1 worker).
* :class:`ProcessExecutor` - a pool of local worker processes (``spawn``), one
  core each.
* :class:`DaskExecutor` - the workers of a Dask distributed cluster, reached
  through its scheduler address (``tcp://host:8786``).

Every executor runs each task on one numba thread and one BLAS thread
(parallelism comes from the workers, not from threads inside a task), so
``workers`` is the number of cores used. The sweeps (:func:`~statue2model.rocking.spectrum.stability_spectrum`,
:func:`~statue2model.rocking.sweeps.variability`,
:func:`~statue2model.rocking.sweeps.parameter_sweep`, and the batch below them,
:func:`~statue2model.rocking.batch.run_batch`) take ``executor=``; without one
they run in this process on numba's threads, as before. Each run is
deterministic and independent of the others, so the results are bit-identical
whichever executor runs them.

``fn`` must be picklable: a function defined at module level (or a builtin),
not a lambda or a closure; the items and results must be picklable too.

Example
-------
>>> import math
>>> with SerialExecutor() as ex:
...     ex.map(math.factorial, [5, 3, 1])
[120, 6, 1]
>>> with make_executor(workers=2) as ex:          # 2 local processes
...     print(ex.describe())
...     ex.map(math.factorial, range(6))
processes, 2 workers
[1, 1, 2, 6, 24, 120]
>>> [c.tolist() for c in chunks(10, 2, per_worker=2, min_chunk=1)]   # contiguous row blocks
[[0, 1, 2], [3, 4, 5], [6, 7], [8, 9]]

A Dask cluster on this machine, every port on the loopback interface (docs/run.md):
``dask scheduler --host 127.0.0.1 --port 8786 --dashboard-address 127.0.0.1:8787``
and ``dask worker tcp://127.0.0.1:8786 --host 127.0.0.1 --dashboard-address 127.0.0.1:0``, then
``make_executor("tcp://127.0.0.1:8786")``, or ``statue2model spectrum ... --scheduler
tcp://127.0.0.1:8786`` on the command line. Across machines: TLS and authentication
(Dask's security settings), statue2model installed on every machine.
"""
from __future__ import annotations

import math
import os
import re
import signal
import sys
from collections.abc import Callable, Iterable

import numpy as np

from ..errors import InputError, missing_extra
from .interrupts import InterruptGuard, _check_signals, _current_guard, interrupts_deferred  # noqa: F401 (re-exported)


def _single_numba_thread() -> int:
    """Limit numba's parallel loops in the calling thread to 1 thread; returns the
    previous count. Chooses the OpenMP layer unless the user chose one (as
    :func:`statue2model.rocking.batch.run_batch` does)."""
    import numba
    from numba import config

    if config.THREADING_LAYER == "default":
        config.THREADING_LAYER = "omp"
    previous = numba.get_num_threads()
    numba.set_num_threads(1)
    return previous


def _single_blas_thread():
    """Limit the BLAS (OpenBLAS, MKL) and OpenMP pools of this process to 1 thread:
    a threaded BLAS sums in an order that depends on its thread count, which would
    change the last bits of the geometry (mass properties) from one executor to
    another. Returns the threadpoolctl limiter (``restore_original_limits()``)."""
    from threadpoolctl import threadpool_limits

    return threadpool_limits(limits=1)


class _one_thread:
    """Context manager: numba's parallel loops in the calling thread and this process's BLAS and
    OpenMP pools on one thread (:func:`_single_numba_thread`, :func:`_single_blas_thread`), the
    previous counts restored afterwards: the items a map runs in this process."""

    def __enter__(self):
        self.previous = _single_numba_thread()
        self.blas = _single_blas_thread()
        return self

    def __exit__(self, *exc):
        import numba

        numba.set_num_threads(self.previous)
        self.blas.restore_original_limits()
        return False


def _one_line(exc: BaseException) -> str:
    text = str(exc).strip()
    return text.splitlines()[0] if text else type(exc).__name__


class Executor:
    """Base class: ``map(fn, items, desc=None) -> list`` in the order of ``items``.

    Attributes: ``name`` ("serial", "processes" or "dask") and ``workers`` (the
    number of tasks that run at once, = cores used). Use as a context manager
    (or call :meth:`close`) to release the workers."""

    name: str = "executor"
    workers: int = 1

    def map(self, fn: Callable, items: Iterable, *, desc: str | None = None) -> list:
        """``[fn(x) for x in items]``, run by the workers; ``desc`` shows a progress
        bar (tqdm, on stderr) counting finished items."""
        raise NotImplementedError

    def describe(self) -> str:
        """One line, e.g. ``processes, 2 workers``."""
        return f"{self.name}, {self.workers} worker{'s' if self.workers != 1 else ''}"

    def close(self) -> None:
        """Release the workers (idempotent)."""

    def __enter__(self):
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def __repr__(self) -> str:
        return f"<{type(self).__name__}: {self.describe()}>"


def _bar(desc: str | None, total: int):
    if not desc:
        return None
    from tqdm import tqdm

    return tqdm(total=total, desc=desc, unit="task", leave=False)


PROGRESS_DELAY = 1.0
"""Seconds of work before :func:`progress_bar` shows its bar (short work prints nothing)."""


class _NoBar:
    def update(self, n=1):
        pass

    def close(self):
        pass


def progress_bar(desc: str, total: int, unit: str = "step", delay: float = PROGRESS_DELAY):
    """A progress bar on stderr (tqdm: done / total, rate, time left) for long work done
    in this process, shown once the work has run ``delay`` s and removed when closed;
    ``update(k)`` after each k steps, ``close()`` at the end (use try/finally). Where tqdm
    is missing, a bar that shows nothing."""
    try:
        from tqdm import tqdm
    except ImportError:  # pragma: no cover - tqdm is a dependency
        return _NoBar()
    return tqdm(total=total, desc=desc, unit=unit, leave=False, delay=delay)


class SerialExecutor(Executor):
    """Runs the items one after the other in this process, on one numba thread
    (the count of the calling thread is restored afterwards)."""

    name = "serial"

    def __init__(self):
        self.workers = 1

    def map(self, fn: Callable, items: Iterable, *, desc: str | None = None) -> list:
        items = list(items)
        bar = _bar(desc, len(items))
        out = []
        try:
            with _one_thread():
                for x in items:
                    out.append(fn(x))
                    if bar is not None:
                        bar.update(1)
        finally:
            if bar is not None:
                bar.close()
        return out

    def describe(self) -> str:
        return "serial, 1 worker (this process)"


def available_cores() -> int:
    """The cores this process may run on (its CPU affinity where the system tells it,
    else ``os.cpu_count()``)."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except (AttributeError, OSError):  # pragma: no cover - macOS, Windows
        return max(1, os.cpu_count() or 1)


_PR_SET_PDEATHSIG = 1      # linux/prctl.h


def _die_with_parent(parent_pid: int, use_pdeathsig: bool) -> None:
    """End this worker when its parent ends, even on SIGKILL of the parent (nothing runs
    in a killed process, so the parent cannot stop its workers itself).

    * Linux: ``prctl(PR_SET_PDEATHSIG, SIGKILL)``, the kernel kills this process when
      the thread that started it ends (``use_pdeathsig``: the pool was made by the
      main thread, whose end is the end of the parent).
    * Everywhere: a daemon thread that ends the process once ``os.getppid()`` is no
      longer the parent (checked every 0.5 s, between the GIL-holding steps of a task).
    """
    import threading

    if use_pdeathsig and sys.platform.startswith("linux"):
        try:
            import ctypes

            libc = ctypes.CDLL(None, use_errno=True)
            libc.prctl(_PR_SET_PDEATHSIG, signal.SIGKILL, 0, 0, 0)
        except (OSError, AttributeError):  # pragma: no cover - no prctl: the watchdog remains
            pass
    if os.getppid() != parent_pid:         # the parent ended before the line above ran
        os._exit(1)

    def watch() -> None:
        import time

        while True:
            time.sleep(0.5)
            if os.getppid() != parent_pid:
                os._exit(1)

    threading.Thread(target=watch, name="statue2model-parent-watchdog", daemon=True).start()


def _thread_lock_for_bars() -> None:
    """tqdm bars of this process lock with a thread lock only (no named semaphore)."""
    try:
        import threading

        from tqdm import tqdm
    except ImportError:  # pragma: no cover - tqdm is a dependency
        return
    tqdm.set_lock(threading.RLock())


def _init_process_worker(parent_pid: int | None = None, use_pdeathsig: bool = False) -> None:
    """Initializer of each worker process: one numba and one BLAS thread per process;
    Ctrl-C is the parent's to handle (it cancels the pool), not the workers'; the
    worker ends with its parent (:func:`_die_with_parent`). Progress bars drawn inside a
    task lock with a thread lock: tqdm's default also makes a named multiprocessing lock,
    which a worker killed or terminated (a broken pool, Ctrl-C) never unlinks (the resource
    tracker then warns "leaked semaphore objects" when the command ends)."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    if parent_pid is not None:
        _die_with_parent(parent_pid, use_pdeathsig)
    _thread_lock_for_bars()
    _single_numba_thread()
    _single_blas_thread()


class ProcessExecutor(Executor):
    """A pool of ``workers`` local processes (default: ``os.cpu_count()``), started
    with ``spawn`` (fork after numba's threads have started is unsafe), each
    limited to one numba thread. The pool starts on the first :meth:`map` (each
    worker then imports statue2model and loads numba's on-disk cache, about a
    second) and is reused by later maps until :meth:`close`.

    ``workers=1`` is still one separate process (not this one), so timings
    compare like with like; use :class:`SerialExecutor` to stay in-process.

    ``cap=True`` limits ``workers`` to :func:`available_cores` (more processes than
    cores only slow the runs down); ``asked`` keeps the number asked for and
    :meth:`describe` says when it was capped. The workers end with this process,
    even when it is killed (:func:`_die_with_parent`).

    A worker process that dies during a map (killed: ``kill -9``, the system's
    out-of-memory killer; or a crash) breaks the whole pool: Python fails every
    task not yet finished. Those tasks are run again once (:attr:`retries`) on a
    fresh pool, with identical inputs, hence identical numbers; the results
    already received are kept. The retry starts only once every process of the
    broken pool has ended (a task's output folder is then free: its lock names a
    process that is gone). What was run again is said in one line on stderr
    (``say``) and kept in :attr:`notes` and :attr:`retried` (cleared by each map).
    A pool that breaks on every attempt raises ``BrokenProcessPool`` with one line
    naming the worker that died and the tasks left unfinished."""

    name = "processes"

    inline_first = 0.0
    """CPU seconds (class default 0: off). While the pool has not started, a map runs its items
    in this process (one numba and one BLAS thread, as :class:`SerialExecutor`), one after
    the other, as long as its projected CPU time stays under this (the first item's time,
    which includes loading the compiled kernels the map needs, plus the mean of the others
    times the items after the first); the items left then go to the pool, started then. Each
    worker's start costs about 1.5 s of CPU (it imports statue2model and loads numba's
    cache): a map of short items (the sweeps of one default run: a few seconds in all) is
    cheaper here. The results are the same wherever an item runs (each is deterministic on
    one thread). Set by :func:`make_executor` ``inline_first=``."""

    retries = 1
    """Times the unfinished tasks of a broken pool (a worker process died) are run again on a fresh pool."""

    def __init__(self, workers: int | None = None, cap: bool = False, say: Callable[[str], None] | None = None,
                 inline_first: float = 0.0):
        self.asked = _check_workers(workers if workers is not None else available_cores())
        self.inline_first = float(inline_first)
        self.workers = min(self.asked, available_cores()) if cap else self.asked
        self._pool = None
        self._say = say
        self.notes: list[str] = []
        """One line per broken pool of the last :meth:`map` (which worker died, which tasks were run again)."""
        self.retried: tuple[int, ...] = ()
        """Positions (in the items of the last :meth:`map`) of the tasks that were run again."""

    def describe(self) -> str:
        line = super().describe()
        if self.workers < self.asked:
            line += f" ({self.asked} asked: capped to the {self.workers} cores of this machine)"
        return line

    def _get_pool(self):
        if self._pool is None:
            import multiprocessing
            import threading
            from concurrent.futures import ProcessPoolExecutor

            main = threading.current_thread() is threading.main_thread()
            self._pool = ProcessPoolExecutor(max_workers=self.workers, mp_context=multiprocessing.get_context("spawn"),
                                             initializer=_init_process_worker, initargs=(os.getpid(), main))
        return self._pool

    def map(self, fn: Callable, items: Iterable, *, desc: str | None = None) -> list:
        items = list(items)
        self.notes, self.retried = [], ()
        if not items:
            return []
        results: list = [None] * len(items)
        retried: set[int] = set()
        bar = None
        try:
            bar = _bar(desc, len(items))
            todo = list(range(self._run_here(fn, items, results, bar), len(items)))
            if not todo:
                return results
            for attempt in range(self.retries + 1):
                todo, why = self._attempt(fn, items, todo, results, bar)
                if not todo:
                    return results
                if attempt == self.retries:
                    from concurrent.futures.process import BrokenProcessPool

                    again = f" (after {self.retries} run{'s' if self.retries != 1 else ''} again on a fresh pool)" \
                        if self.retries else ""
                    raise BrokenProcessPool(f"{why}{again}: {_tasks(todo)} of {len(items)} not finished")
                retried.update(todo)
                self.retried = tuple(sorted(retried))
                note = f"{why}: {_tasks(todo)} of {len(items)} unfinished, run again on a fresh pool of " \
                       f"{self.workers} process{'es' if self.workers != 1 else ''} (same inputs, same numbers)"
                self.notes.append(note)
                (self._say or _say_note)(f"statue2model: note: {note}")
            return results      # pragma: no cover - the loop returns or raises
        except BaseException:
            self._abandon()
            raise
        finally:
            if bar is not None:
                bar.close()

    def _run_here(self, fn: Callable, items: list, results: list, bar) -> int:
        """Run the first items of a map in this process while the pool has not started and the
        map's projected CPU time stays under :attr:`inline_first` (filling ``results``); returns
        how many ran here."""
        if self._pool is not None or not self.inline_first > 0:
            return 0
        import time

        t0 = time.process_time()
        done, first = 0, 0.0
        with _one_thread():
            for x in items:
                spent = time.process_time() - t0
                if done == 1:
                    first = spent        # the first item also loads what the map needs (compiled kernels)
                if done and first + (spent - first) / max(done - 1, 1) * (len(items) - 1) > self.inline_first:
                    break
                results[done] = fn(x)
                done += 1
                if bar is not None:
                    bar.update(1)
        return done

    def _attempt(self, fn: Callable, items: list, todo: list[int], results: list, bar) -> tuple[list[int], str]:
        """Run the tasks ``todo`` (positions in ``items``) on the pool, filling ``results``;
        the first task's own exception is raised at once. Returns the positions left
        unfinished because the pool broke (a worker process died; the pool is then
        stopped and its processes have ended) and one line saying which worker died."""
        from concurrent.futures import as_completed
        from concurrent.futures.process import BrokenProcessPool

        if self._pool is None and os.name == "posix":
            from multiprocessing import resource_tracker

            resource_tracker.ensure_running()   # started first: it unblocks SIGINT after starting
        futures = {}
        broken: list[int] = []
        with interrupts_deferred():     # the pool starts (or takes) all its tasks whole, then Ctrl-C
            pool = self._get_pool()
            for k, i in enumerate(todo):
                try:
                    futures[pool.submit(fn, items[i])] = i
                except BrokenProcessPool:       # a worker died while the tasks were being handed out
                    broken.extend(todo[k:])
                    break
        for f in as_completed(futures):
            exc = f.exception()
            if isinstance(exc, BrokenProcessPool):
                broken.append(futures[f])
                continue
            if exc is not None:
                raise exc       # the first task failure at once
            results[futures[f]] = f.result()
            if bar is not None:
                bar.update(1)
        if not broken:
            return [], ""
        procs = list((getattr(pool, "_processes", None) or {}).values())
        self._abandon()
        for p in procs:         # ended and reaped: their PIDs no longer hold any output folder's lock
            p.join(timeout=10.0)
        return sorted(broken), _who_died(procs)

    def _abandon(self) -> None:
        """On an error or Ctrl-C: stop the workers now, without waiting for their tasks. The
        pending futures are not cancelled here: the terminated workers break the pool and its
        manager thread fails them all (cancelling them first races with it: CPython < 3.12,
        gh-107219, printed an InvalidStateError traceback from that thread on Ctrl-C)."""
        pool, self._pool = self._pool, None
        if pool is None:
            return
        with interrupts_deferred(raise_held=False):     # a second Ctrl-C does not leave workers running
            procs = list((getattr(pool, "_processes", None) or {}).values())
            manager = getattr(pool, "_executor_manager_thread", None)
            pool.shutdown(wait=False, cancel_futures=False)
            for p in procs:
                if p.is_alive():
                    p.terminate()
            # the manager thread now fails the pending futures and closes its pipes; wait for it
            # (bounded): at exit, CPython 3.11 wakes it through a pipe it may be closing at that
            # moment ("Exception ignored ... OSError: Bad file descriptor" from threading._shutdown)
            if manager is not None and manager.is_alive():
                manager.join(timeout=3.0)

    def close(self) -> None:
        if self._pool is not None:
            self._pool.shutdown(wait=True, cancel_futures=True)
            self._pool = None


def _say_note(line: str) -> None:
    print(line, file=sys.stderr, flush=True)


def _tasks(positions: list[int]) -> str:
    """``task 3`` / ``3 tasks (#1, 3, 4)``: positions counted from 1, at most 8 shown."""
    shown = ", ".join(str(i + 1) for i in positions[:8]) + (", ..." if len(positions) > 8 else "")
    return f"task #{shown}" if len(positions) == 1 else f"{len(positions)} tasks (#{shown})"


def _who_died(procs: list) -> str:
    """One line naming the worker process(es) of a broken pool that ended on their own (the
    pool terminates the others itself, with SIGTERM)."""
    dead = []
    for p in procs:
        code = p.exitcode
        if code is None or code == 0 or code == -signal.SIGTERM:
            continue
        if code < 0:
            try:
                how = f"signal {signal.Signals(-code).name}"
            except ValueError:
                how = f"signal {-code}"
            if -code == signal.SIGKILL:
                how += ": killed, e.g. kill -9 or out of memory"
        else:
            how = f"exit status {code}"
        dead.append(f"PID {p.pid} ({how})")
    if not dead:
        return "a worker process ended abruptly"
    return f"worker process{'es' if len(dead) > 1 else ''} {', '.join(dead)} ended abruptly"


def _dask_call(item, fn):
    """Run one task on a Dask worker: one numba thread (numba's count is per
    thread, and Dask runs tasks in a thread pool) and one BLAS thread, then ``fn(item)``."""
    _single_numba_thread()
    _single_blas_thread()
    return fn(item)


class _DropConnectionLogs:
    """A logging filter dropping distributed's records about a lost connection to the
    scheduler ('Failed to reconnect to scheduler', and the tracebacks of its connection
    and reconnection tasks: CommClosedError, OSError, CancelledError, TimeoutError): the
    executor's own one line says it (:meth:`DaskExecutor._lost`)."""

    def filter(self, record) -> bool:
        if "reconnect to scheduler" in str(getattr(record, "msg", "")):
            return False
        exc = record.exc_info[1] if record.exc_info else None
        if exc is None:
            return True
        import asyncio
        import concurrent.futures

        try:
            from distributed.comm.core import CommClosedError
        except ImportError:  # pragma: no cover - filter installed only with distributed
            CommClosedError = OSError
        return not isinstance(exc, (CommClosedError, OSError, asyncio.CancelledError,
                                    concurrent.futures.CancelledError, TimeoutError))


def _remove_filter(targets: list, quiet: _DropConnectionLogs) -> None:
    for t in targets:
        t.removeFilter(quiet)


WORKER_TIMEOUT = 60.0
"""Seconds a Dask sweep waits while the cluster has no worker before it stops with one line
(default of ``DaskExecutor(worker_timeout=)``, else the environment variable
``STATUE2MODEL_WORKER_TIMEOUT``)."""


def _worker_timeout(value) -> float:
    source = "worker_timeout"
    if value is None:
        value = os.environ.get("STATUE2MODEL_WORKER_TIMEOUT")
        source = "STATUE2MODEL_WORKER_TIMEOUT"
        if value is None or not str(value).strip():
            return WORKER_TIMEOUT
    try:
        t = float(value)
    except (TypeError, ValueError):
        raise InputError(f"{source} must be a number of seconds > 0, got {value!r}") from None
    if not (math.isfinite(t) and t > 0):
        raise InputError(f"{source} must be a number of seconds > 0, got {value!r}")
    return t


class DaskExecutor(Executor):
    """The workers of a Dask distributed cluster at ``address`` (e.g.
    ``tcp://10.0.0.5:8786``); connects at once and raises :class:`InputError` if
    the scheduler does not answer within ``timeout`` s. ``workers`` is the
    number of worker threads the scheduler reports when connecting.

    Each task carries its item (inputs are not scattered: scattered data dies with
    the worker that holds it), so the tasks of a lost worker are run again on
    another one (``retries``) with identical inputs, hence identical numbers. One
    line (InputError), never Dask's own tracebacks, when

    * the cluster has no worker for ``worker_timeout`` s (default
      :data:`WORKER_TIMEOUT`, or ``STATUE2MODEL_WORKER_TIMEOUT`` in the environment):
      when connecting to a cluster without workers, or during a map whose workers all
      left (a restarted worker that comes back in time changes nothing);
    * the scheduler is lost during a map.

    Each task runs on one numba thread; workers must be able to import statue2model (the
    same version)."""

    name = "dask"

    retries = 3
    """Times a task is run again when the worker running it is lost."""
    poll = 1.0
    """Seconds between the looks at the cluster while a map waits."""

    def __init__(self, address: str, timeout: float = 10.0, worker_timeout: float | None = None):
        try:
            from distributed import Client
        except ImportError as exc:
            raise missing_extra("cluster", "running on a Dask scheduler", exc) from None
        self.address = str(address)
        self.worker_timeout = _worker_timeout(worker_timeout)
        self._client = None
        self._quiet = _DropConnectionLogs()
        self._quiet_on = []
        self._unhush_at_gc = None
        self._hush()
        try:
            self._client = Client(self.address, timeout=timeout, set_as_default=False)
        except (OSError, ValueError, AssertionError, RuntimeError) as exc:  # timeout/refused, bad address
            self._unhush()
            raise InputError(f"cannot reach the Dask scheduler at {self.address}: {_one_line(exc)}") from None
        try:
            self.workers = self._n_workers()
            if self.workers == 0:
                self.workers = self._wait_for_workers()
        except BaseException:
            self.close()
            raise

    def _hush(self) -> None:
        """Drop distributed's lost-connection records from now until :meth:`close` (or until
        this executor is garbage-collected, for a caller that never closes it)."""
        import logging
        import weakref

        targets = [logging.getLogger("distributed.client"), logging.getLogger("distributed.core")]
        targets += list(logging.getLogger("distributed").handlers)
        for t in targets:
            t.addFilter(self._quiet)
        self._quiet_on = targets
        self._unhush_at_gc = weakref.finalize(self, _remove_filter, targets, self._quiet)

    def _unhush(self) -> None:
        if self._unhush_at_gc is not None:
            self._unhush_at_gc()            # runs once: later calls (and the collection) do nothing
        self._quiet_on = []

    def _n_workers(self) -> int:
        """Worker threads the scheduler has now (asks it)."""
        return int(sum(self._client.nthreads().values()))

    def _no_workers(self, waited: float) -> InputError:
        return InputError(f"no Dask worker at {self.address} for {waited:.0f} s (STATUE2MODEL_WORKER_TIMEOUT="
                          f"{self.worker_timeout:g}: set it to wait longer): the sweep did not run; start workers "
                          f"(dask worker {self.address} --host 127.0.0.1 --dashboard-address 127.0.0.1:0, on "
                          "this machine), or run without --scheduler on local workers")

    def _wait_for_workers(self) -> int:
        import time

        t0 = time.monotonic()
        while True:
            n = self._n_workers()
            if n:
                return n
            if time.monotonic() - t0 >= self.worker_timeout:
                raise self._no_workers(time.monotonic() - t0)
            time.sleep(min(self.poll, self.worker_timeout / 4))

    def map(self, fn: Callable, items: Iterable, *, desc: str | None = None) -> list:
        import time

        items = list(items)
        if not items:
            return []
        client = self._client
        if client is None:
            raise RuntimeError("this DaskExecutor is closed")
        import warnings

        futures = []
        bar = None
        task_error = None                       # a task's own exception: never a lost scheduler
        try:
            with warnings.catch_warnings():      # the items travel inside the graph, on purpose (see the class)
                warnings.filterwarnings("ignore", message=".*[Ll]arge object.*")
                warnings.filterwarnings("ignore", message=".*[Ss]ending large graph.*")
                futures = client.map(_dask_call, items, fn=fn, pure=False, retries=self.retries)
            bar = _bar(desc, len(futures))
            pending = list(futures)
            alone_since = None                  # when the cluster was first seen without a worker
            poll = min(self.poll, self.worker_timeout / 4)
            last_look = time.monotonic()
            while pending:
                done = [f for f in pending if f.done()]     # the client's own state: no message
                for f in done:
                    if f.status == "error":
                        try:
                            f.result()  # raise the worker's exception here
                        except Exception as exc:
                            if self._client_gone():     # no answer from the scheduler: not the task's
                                raise
                            task_error = exc            # e.g. the task's own FileNotFoundError
                            raise
                    elif f.status != "finished":      # cancelled: the scheduler went away
                        futures = []                    # nothing to cancel there
                        raise self._lost(None)
                    if bar is not None:
                        bar.update(1)
                if done:
                    pending = [f for f in pending if not f.done()]
                    continue
                time.sleep(0.05)
                if time.monotonic() - last_look >= poll:    # ask the scheduler for its workers
                    last_look = time.monotonic()
                    if self._n_workers() == 0:
                        alone_since = last_look if alone_since is None else alone_since
                        if last_look - alone_since >= self.worker_timeout:
                            raise self._no_workers(last_look - alone_since)
                    else:
                        alone_since = None
            return client.gather(futures)
        except InputError:
            self._cancel(futures)
            raise
        except Exception as exc:
            if exc is not task_error and self._scheduler_lost(exc):
                raise self._lost(exc) from None
            self._cancel(futures)
            raise
        except BaseException:
            self._cancel(futures)
            raise
        finally:
            if bar is not None:
                bar.close()

    def _cancel(self, futures) -> None:
        """Cancel the map's tasks (when the scheduler still answers)."""
        if not futures or self._client is None:
            return
        try:
            self._client.cancel(futures)
        except Exception:  # the scheduler went away meanwhile: nothing to cancel there
            pass

    def _client_gone(self) -> bool:
        """Whether the client no longer talks with its scheduler."""
        return getattr(self._client, "status", "running") not in ("running", "connecting")

    def _scheduler_lost(self, exc: BaseException) -> bool:
        """Whether ``exc``, raised by the client (never a task's own exception: :meth:`map`
        passes those on as they are), says the client lost its scheduler."""
        import asyncio
        import concurrent.futures

        from distributed.comm.core import CommClosedError

        if isinstance(exc, (CommClosedError, asyncio.CancelledError, concurrent.futures.CancelledError,
                            ConnectionError, TimeoutError, OSError)):
            return True
        return self._client_gone()

    def _lost(self, exc: BaseException | None) -> InputError:
        why = f" ({_one_line(exc)})" if exc is not None else ""
        return InputError(f"lost the Dask scheduler at {self.address} during the run{why}: the sweep did not "
                          "finish; start the scheduler again, or run without --scheduler on local workers")

    def describe(self) -> str:
        return f"dask at {self.address}, {self.workers} worker{'s' if self.workers != 1 else ''}"

    def close(self) -> None:
        client, self._client = self._client, None
        try:
            if client is not None:
                try:
                    client.close(timeout=5)
                except Exception:  # a lost scheduler: the client is closing anyway
                    pass
        finally:
            self._unhush()


def _check_workers(workers) -> int:
    try:
        n = int(workers)
    except (TypeError, ValueError):
        raise InputError(f"workers must be a whole number >= 1, got {workers!r}") from None
    if n != workers or n < 1:
        raise InputError(f"workers must be a whole number >= 1, got {workers!r}")
    return n


def make_executor(scheduler: str | None = None, workers: int | None = None, timeout: float = 10.0,
                  cap: bool = False, worker_timeout: float | None = None, inline_first: float = 0.0) -> Executor:
    """``scheduler`` given: a :class:`DaskExecutor` on it (``workers`` must then be
    None: the cluster decides; ``timeout``: s to reach the scheduler; ``worker_timeout``:
    s without any worker before giving up, see :class:`DaskExecutor`); else a
    :class:`ProcessExecutor` of ``workers`` local processes (None: one per CPU).
    ``workers=1`` is one worker process. ``cap``: at most one local worker per core;
    ``inline_first``: s of CPU, short maps run in this process until the pool starts
    (see :class:`ProcessExecutor`)."""
    if scheduler is not None:
        if workers is not None:
            raise InputError("give either a Dask scheduler or a number of local workers, not both")
        check_scheduler_address(scheduler)
        return DaskExecutor(str(scheduler).strip(), timeout=timeout, worker_timeout=worker_timeout)
    return ProcessExecutor(None if workers is None else _check_workers(workers), cap=cap, inline_first=inline_first)


def check_scheduler_address(address: str) -> str:
    """The host of a Dask scheduler address (``tcp://host:8786``, ``host:8786``,
    ``tcp://[::1]:8786``), or an InputError if it is not one. No connection is made."""
    text = str(address).strip()
    m = re.fullmatch(r"(?:(tcp|tls|ws|wss|ucx|inproc)://)?(\[[0-9A-Fa-f:.]+\]|[^\s/:\[\]]+)(:\d+)?/?", text)
    if not m or (m.group(1) is None and m.group(3) is None):
        raise InputError(f"not a Dask scheduler address: {address!r} (e.g. tcp://127.0.0.1:8786)")
    return m.group(2).strip("[]")


def is_local_address(address: str) -> bool:
    """Whether a scheduler address names this machine: localhost, 127.0.0.0/8 or ::1
    (no name is looked up)."""
    import ipaddress

    host = check_scheduler_address(address).lower()
    if str(address).strip().lower().startswith("inproc://"):
        return True
    if host in ("localhost", "localhost.localdomain", "ip6-localhost"):
        return True
    try:
        return ipaddress.ip_address(host).is_loopback
    except ValueError:
        return False


def config_executor(scheduler: str | None, workers: int | None, source: str | None = None,
                    cap: bool = True, inline_first: float = 0.0) -> Executor:
    """The executor of a project file's ``[run]`` section. A scheduler there is used
    only when it is on this machine (localhost, 127.0.0.0/8, ::1): a project file
    received from someone else must not send the scan's numbers to a machine the
    user did not name; otherwise an InputError (one line, nothing contacted) asks to
    confirm it with ``--scheduler`` on the command line."""
    if scheduler:
        if not is_local_address(scheduler):
            where = f"{source}: " if source else ""
            raise InputError(f"{where}[run] scheduler = {str(scheduler).strip()!r} is not on this machine: not used "
                             f"without confirmation; give --scheduler {str(scheduler).strip()} to run there, or "
                             f"--workers N to run here")
        return make_executor(scheduler=scheduler)
    return make_executor(workers=workers, cap=cap, inline_first=inline_first)


def chunks(n: int, executor: Executor | int, *, per_worker: int = 4, min_chunk: int = 8) -> list[np.ndarray]:
    """Split row indices 0..n-1 into contiguous blocks (int64 arrays, in order):
    about ``per_worker`` blocks per worker so that fast and slow blocks balance,
    but no block shorter than ``min_chunk`` rows (except when n is smaller).
    ``executor``: an :class:`Executor` or a number of workers. Deterministic:
    depends on n and the number of workers only."""
    n = int(n)
    if n <= 0:
        return []
    workers = executor if isinstance(executor, (int, np.integer)) else executor.workers
    k = max(1, min(n, max(1, int(workers)) * max(1, per_worker), math.ceil(n / max(1, min_chunk))))
    return np.array_split(np.arange(n, dtype=np.int64), k)
