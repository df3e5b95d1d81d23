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
``workers`` is the number of cores used. The sweeps (:func:`~statue2model.dynamics.spectrum.stability_spectrum`,
:func:`~statue2model.dynamics.sweeps.variability`,
:func:`~statue2model.dynamics.sweeps.parameter_sweep`, and the batch below them,
:func:`~statue2model.dynamics.batch.run_batch`) take ``executor=``; without one
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

A Dask cluster: start ``dask scheduler`` on one machine and ``dask worker
tcp://HOST:8786`` on each machine (statue2model installed on all of them), then
``make_executor("tcp://HOST:8786")``, or ``statue2model spectrum ... --scheduler
tcp://HOST:8786`` on the command line.
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


def _single_numba_thread() -> int:
    """Limit numba's parallel loops in the calling thread to 1 thread; returns the
    previous count. Chooses the OpenMP layer unless the user chose one (as
    :func:`statue2model.dynamics.batch.run_batch` does)."""
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


class SerialExecutor(Executor):
    """Runs the items one after the other in this process, on one numba thread
    (the count of the calling thread is restored afterwards)."""

    name = "serial"

    def __init__(self):
        self.workers = 1

    def map(self, fn: Callable, items: Iterable, *, desc: str | None = None) -> list:
        items = list(items)
        bar = _bar(desc, len(items))
        previous = _single_numba_thread()
        blas = _single_blas_thread()
        out = []
        try:
            for x in items:
                out.append(fn(x))
                if bar is not None:
                    bar.update(1)
        finally:
            import numba

            numba.set_num_threads(previous)
            blas.restore_original_limits()
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


def _init_process_worker(parent_pid: int | None = None, use_pdeathsig: bool = False) -> None:
    """Initializer of each worker process: one numba and one BLAS thread per process;
    Ctrl-C is the parent's to handle (it cancels the pool), not the workers'; the
    worker ends with its parent (:func:`_die_with_parent`)."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    if parent_pid is not None:
        _die_with_parent(parent_pid, use_pdeathsig)
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
    even when it is killed (:func:`_die_with_parent`)."""

    name = "processes"

    def __init__(self, workers: int | None = None, cap: bool = False):
        self.asked = _check_workers(workers if workers is not None else available_cores())
        self.workers = min(self.asked, available_cores()) if cap else self.asked
        self._pool = None

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
        from concurrent.futures import as_completed

        items = list(items)
        if not items:
            return []
        pool = self._get_pool()
        futures = [pool.submit(fn, x) for x in items]
        bar = _bar(desc, len(futures))
        try:
            for f in as_completed(futures):
                f.result()  # raise the first failure at once
                if bar is not None:
                    bar.update(1)
            return [f.result() for f in futures]
        except BaseException:
            self._abandon()
            raise
        finally:
            if bar is not None:
                bar.close()

    def _abandon(self) -> None:
        """On an error or Ctrl-C: stop the workers now, without waiting for their tasks. The
        pending futures are not cancelled here: the terminated workers break the pool and its
        manager thread fails them all (cancelling them first races with it: CPython < 3.12,
        gh-107219, printed an InvalidStateError traceback from that thread on Ctrl-C)."""
        pool, self._pool = self._pool, None
        if pool is None:
            return
        procs = list(getattr(pool, "_processes", {}).values())
        pool.shutdown(wait=False, cancel_futures=False)
        for p in procs:
            if p.is_alive():
                p.terminate()

    def close(self) -> None:
        if self._pool is not None:
            self._pool.shutdown(wait=True, cancel_futures=True)
            self._pool = None


def _dask_call(item, fn):
    """Run one task on a Dask worker: one numba thread (numba's count is per
    thread, and Dask runs tasks in a thread pool) and one BLAS thread, then ``fn(item)``."""
    _single_numba_thread()
    _single_blas_thread()
    return fn(item)


class _DropReconnectLog:
    """A logging filter dropping distributed's 'Failed to reconnect to scheduler' record."""

    def filter(self, record) -> bool:
        return "reconnect to scheduler" not in str(getattr(record, "msg", ""))


class DaskExecutor(Executor):
    """The workers of a Dask distributed cluster at ``address`` (e.g.
    ``tcp://10.0.0.5:8786``); connects at once and raises :class:`InputError` if
    the scheduler does not answer within ``timeout`` s. ``workers`` is the
    number of worker threads the scheduler reports when connecting.

    Each task carries its item (inputs are not scattered: scattered data dies with
    the worker that holds it), so the tasks of a lost worker are run again on
    another one (``retries``) with identical inputs, hence identical numbers. A lost
    scheduler ends the map with one line (InputError). Each task runs on one numba
    thread; workers must be able to import statue2model (the same version)."""

    name = "dask"

    retries = 3
    """Times a task is run again when the worker running it is lost."""

    def __init__(self, address: str, timeout: float = 10.0):
        try:
            from distributed import Client
        except ImportError as exc:
            raise missing_extra("cluster", "running on a Dask scheduler", exc) from None
        self.address = str(address)
        try:
            self._client = Client(self.address, timeout=timeout, set_as_default=False)
        except (OSError, ValueError, AssertionError, RuntimeError) as exc:  # timeout/refused, bad address
            raise InputError(f"cannot reach the Dask scheduler at {self.address}: {_one_line(exc)}") from None
        self.workers = int(sum(self._client.nthreads().values()))

    def map(self, fn: Callable, items: Iterable, *, desc: str | None = None) -> list:
        from distributed import as_completed

        items = list(items)
        if not items:
            return []
        client = self._client
        if client is None:
            raise RuntimeError("this DaskExecutor is closed")
        import warnings

        with warnings.catch_warnings():      # the items travel inside the graph, on purpose (see the class)
            warnings.filterwarnings("ignore", message=".*[Ll]arge object.*")
            warnings.filterwarnings("ignore", message=".*[Ss]ending large graph.*")
            futures = client.map(_dask_call, items, fn=fn, pure=False, retries=self.retries)
        bar = _bar(desc, len(futures))
        import logging

        quiet = _DropReconnectLog()     # our one line says it: not also distributed's log
        logging.getLogger("distributed.client").addFilter(quiet)
        try:
            for f in as_completed(futures, loop=client.loop):  # not the default client: give its loop
                if f.status == "error":
                    f.result()  # raise the worker's exception here
                elif f.status != "finished":      # cancelled: the scheduler went away
                    raise self._lost(None)
                if bar is not None:
                    bar.update(1)
            return client.gather(futures)
        except InputError:
            raise
        except Exception as exc:
            if self._scheduler_lost(exc):
                raise self._lost(exc) from None
            client.cancel(futures)
            raise
        except BaseException:
            client.cancel(futures)
            raise
        finally:
            logging.getLogger("distributed.client").removeFilter(quiet)
            if bar is not None:
                bar.close()

    def _scheduler_lost(self, exc: BaseException) -> bool:
        """Whether ``exc`` says the client lost its scheduler (not a failure of a task)."""
        import asyncio
        import concurrent.futures

        from distributed.comm.core import CommClosedError

        if isinstance(exc, (CommClosedError, asyncio.CancelledError, concurrent.futures.CancelledError,
                            ConnectionError, TimeoutError)):
            return True
        return getattr(self._client, "status", "running") not in ("running", "connecting")

    def _lost(self, exc: BaseException | None) -> InputError:
        why = f" ({_one_line(exc)})" if exc is not None else ""
        return InputError(f"lost the Dask scheduler at {self.address} during the run{why}: the sweep did not "
                          "finish; start the scheduler again, or run without --scheduler on local workers")

    def describe(self) -> str:
        return f"dask at {self.address}, {self.workers} worker{'s' if self.workers != 1 else ''}"

    def close(self) -> None:
        if self._client is not None:
            self._client.close()
            self._client = None


def _check_workers(workers) -> int:
    try:
        n = int(workers)
    except (TypeError, ValueError):
        raise InputError(f"workers must be a whole number >= 1, got {workers!r}") from None
    if n != workers or n < 1:
        raise InputError(f"workers must be a whole number >= 1, got {workers!r}")
    return n


def make_executor(scheduler: str | None = None, workers: int | None = None, timeout: float = 10.0,
                  cap: bool = False) -> Executor:
    """``scheduler`` given: a :class:`DaskExecutor` on it (``workers`` must then be
    None: the cluster decides); else a :class:`ProcessExecutor` of ``workers``
    local processes (None: one per CPU). ``workers=1`` is one worker process.
    ``cap``: at most one local worker per core (see :class:`ProcessExecutor`)."""
    if scheduler is not None:
        if workers is not None:
            raise InputError("give either a Dask scheduler or a number of local workers, not both")
        check_scheduler_address(scheduler)
        return DaskExecutor(str(scheduler).strip(), timeout=timeout)
    return ProcessExecutor(None if workers is None else _check_workers(workers), cap=cap)


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
                    cap: bool = True) -> Executor:
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
    return make_executor(workers=workers, cap=cap)


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
