"""Ctrl-C for a whole command, from the first line of the program: stdlib only (the command
line's ``main`` installs :class:`InterruptGuard` before it imports numpy or any command).

* :class:`InterruptGuard` - the SIGINT handler of a command: counts every Ctrl-C, raises
  it as KeyboardInterrupt (never inside an import: there it is held until the import is
  over), re-delivers one that Python lost, ends a stop that hangs; its :meth:`~InterruptGuard.check`
  stops the command before a write once a Ctrl-C arrived, wherever it went.
* :class:`interrupts_deferred` - a block a Ctrl-C must not cut in half (raised at its end).
* :class:`interrupt_checkpoint` - a block of third-party code that may swallow the
  KeyboardInterrupt (``except BaseException``, as trimesh does around its optional imports
  and in its loaders): a Ctrl-C that arrived inside it is raised again when it ends normally.
* :func:`checked_import` - ``importlib.import_module`` inside such a block.

:mod:`statue2model.compute.executors` re-exports the first two (their historic home).
"""
from __future__ import annotations

import os
import signal
import sys


class InterruptGuard:
    """Ctrl-C for a whole command: installed by the CLI's ``main`` around its work (a
    context manager, main thread only; elsewhere it does nothing and ``interrupted``
    stays False).

    Python raises KeyboardInterrupt wherever the main thread is when SIGINT arrives. In a
    weakref callback or a ``__del__`` run by the garbage collector (numba's and
    multiprocessing's caches hold such callbacks) the exception cannot propagate: Python
    prints "Exception ignored ... KeyboardInterrupt" and goes on, and the Ctrl-C is lost.
    This guard

    * counts every SIGINT (``interrupted``: at least one arrived), so the command's exit
      status is 130 whatever happened to the exception;
    * takes such a lost KeyboardInterrupt (``sys.unraisablehook``, a C-level append: no
      Python code runs where the interrupt was lost), prints nothing, and a watcher thread
      delivers the interrupt again within 0.05 s (a SIGINT sent to the main thread, which
      also wakes a blocking wait; ``_thread.interrupt_main`` where threads cannot be
      signalled): it is then raised in ordinary code (one re-delivery at a time: none is
      sent again before the handler has run; other unraisable exceptions go to the previous
      hook, as before);
    * holds a Ctrl-C back inside :class:`interrupts_deferred` blocks (starting or
      stopping a pool's processes), raised when the block ends;
    * holds a Ctrl-C back while the main thread imports a module (importlib's frames on its
      stack), and the watcher delivers it again within 0.05 s of the import's end. A
      KeyboardInterrupt raised inside an import is the cause of three faults: libraries that
      catch ``BaseException`` around their imports drop it (trimesh), or print it as their
      own error (rtree: "rtree.finder ... unexpected error"); C extensions turn it into an
      ImportError that a fallback ``except ImportError`` drops; and a module interrupted
      half-way (a C extension's init) is imported again by the next ``import`` of it. The
      imports of a command take about a second, so the Ctrl-C waits at most that long;
    * :meth:`check`, called before every write (statue2model.io.files), raises a Ctrl-C that
      arrived but was dropped on its way (by a library): nothing is written after it;
    * after :meth:`stop` (the command is already ending) only counts.

    On leaving, the previous SIGINT handler and unraisable hook are restored.
    """

    poll = 0.05
    """Seconds between the watcher's looks at lost interrupts."""

    def __init__(self):
        self.count = 0
        """SIGINTs received while installed."""
        self.stopping = False
        self._defer = 0
        self._held = False
        self._installed = False
        self._previous = None
        self._previous_hook = None
        self._lost: list = []
        self._done = None
        self._watcher = None
        self._deadline = None
        self._resent = False
        self._import_held = False

    @property
    def interrupted(self) -> bool:
        """Whether a Ctrl-C (SIGINT) arrived while the guard was installed."""
        return self.count > 0

    def stop(self) -> None:
        """The command is ending: later SIGINTs are counted, never raised."""
        self.stopping = True

    grace = 20.0
    """Seconds a command may take to stop after its first Ctrl-C; past them the process
    ends at once with status 130 (files are written whole or not at all, and a stage left
    half-computed is a hidden partial folder the next run removes)."""

    def __call__(self, signum, frame) -> None:       # the SIGINT handler
        self.count += 1
        self._resent = False
        if self.count == 1 and self._installed:
            self._start_deadline()
        if self.stopping:
            return
        if self._defer:
            self._held = True
            return
        if _in_import(frame):
            self._import_held = True        # the watcher delivers it again once the import is over
            return
        self._import_held = False
        raise KeyboardInterrupt

    def check(self) -> None:
        """Before a write: KeyboardInterrupt if a Ctrl-C arrived while the command ran (whether it
        was raised and then dropped by a library, or is still held back), so that nothing is
        written after it. Not in a deferred block (raised at its end), not once the command is
        ending (:meth:`stop`), not while an exception is being handled (the clean-up of a
        stop that is already on its way writes, e.g. a manifest put back), main thread only."""
        if not self.count or self.stopping or self._defer or not self._installed:
            return
        import threading

        if threading.current_thread() is not threading.main_thread() or sys.exc_info()[0] is not None:
            return
        self._import_held = False
        raise KeyboardInterrupt

    def _start_deadline(self) -> None:
        import threading

        self._deadline = threading.Timer(self.grace, self._give_up)
        self._deadline.daemon = True
        self._deadline.start()

    def _give_up(self) -> None:
        """The stop took longer than :attr:`grace` (a wait Python cannot interrupt): end now."""
        if not self._installed:
            return
        try:
            files = sys.modules.get("statue2model.io.files")     # loaded if a folder was locked: no import here
            if files is not None:
                files.release_held_locks()      # no stale lock: the next command need not wait or replace it
        except Exception:  # pragma: no cover - ending anyway
            pass
        try:
            sys.stderr.write(f"statue2model: interrupted (stopping took over {self.grace:.0f} s: ended at once)\n")
            sys.stderr.flush()
            sys.stdout.flush()
        finally:
            os._exit(130)

    def _take_lost(self) -> bool:
        """Pass the unraisable exceptions collected so far on; whether one was a KeyboardInterrupt."""
        interrupt = False
        while self._lost:
            u = self._lost.pop(0)
            if isinstance(u.exc_type, type) and issubclass(u.exc_type, KeyboardInterrupt):
                interrupt = True
            else:
                (self._previous_hook or sys.__unraisablehook__)(u)
            del u
        return interrupt

    def _watch(self) -> None:
        import threading

        main = threading.main_thread().ident
        while not self._done.wait(self.poll):
            lost = self._take_lost()
            if self._import_held and not self._resent and not _in_import(sys._current_frames().get(main)):
                lost = True                     # the import that held it back is over
            if lost and not self.stopping and not self._resent:
                self._resent = True            # cleared by the handler: never more than one in flight
                self._interrupt_main()         # this guard's handler runs again, in the main thread

    @staticmethod
    def _interrupt_main() -> None:
        """SIGINT to the main thread: unlike ``_thread.interrupt_main`` (a flag only, looked at
        when the main thread next runs Python code), it also ends a blocking wait there
        (``as_completed``, a lock, a sleep). Where there is no ``pthread_kill``, the flag."""
        import threading

        if hasattr(signal, "pthread_kill"):
            try:
                signal.pthread_kill(threading.main_thread().ident, signal.SIGINT)
                return
            except (OSError, ValueError):   # pragma: no cover - the main thread is ending
                pass
        import _thread

        _thread.interrupt_main()

    def __enter__(self) -> InterruptGuard:
        import threading

        if threading.current_thread() is threading.main_thread():
            self._previous = signal.signal(signal.SIGINT, self)
            self._previous_hook, sys.unraisablehook = sys.unraisablehook, self._lost.append
            self._done = threading.Event()
            self._watcher = threading.Thread(target=self._watch, name="statue2model-interrupts", daemon=True)
            self._watcher.start()
            self._installed = True
        return self

    def __exit__(self, *exc) -> None:
        self.stopping = True
        if not self._installed:
            return
        self._done.set()
        self._watcher.join()
        if self._deadline is not None:
            self._deadline.cancel()
        _check_signals()         # an interrupt delivered again but not yet handled is counted here, not raised
        if sys.unraisablehook == self._lost.append:
            sys.unraisablehook = self._previous_hook
        self._take_lost()
        if signal.getsignal(signal.SIGINT) is self:
            signal.signal(signal.SIGINT, self._previous if self._previous is not None else signal.default_int_handler)
        self._installed = False


def _in_import(frame) -> bool:
    """Whether ``frame`` (the main thread's) runs inside an import: a frame of importlib's
    bootstrap on its stack (every ``import`` of a module not yet loaded, Python's or a C
    extension's, runs there; one already loaded does not)."""
    while frame is not None:
        if frame.f_code.co_filename.startswith("<frozen importlib._bootstrap"):
            return True
        frame = frame.f_back
    return False


def _check_signals() -> None:
    """A Python-level call: Python runs pending signal handlers when a function starts."""


def _current_guard() -> InterruptGuard | None:
    handler = signal.getsignal(signal.SIGINT)
    return handler if isinstance(handler, InterruptGuard) else None


class interrupts_deferred:
    """A block that a Ctrl-C must not cut in half (starting a pool's worker processes, or
    stopping them): SIGINT is blocked in this thread meanwhile, so processes started here
    begin with it blocked (a terminal's Ctrl-C goes to the whole process group: a worker
    still importing statue2model would print a KeyboardInterrupt traceback; the workers
    ignore SIGINT anyway, the parent stops them). A SIGINT that arrives meanwhile is
    raised as KeyboardInterrupt when the block ends normally (``raise_held=False``: only
    counted, for a block that runs while an exception is already on its way)."""

    def __init__(self, raise_held: bool = True):
        self.raise_held = raise_held
        self._guard = None
        self._blocked = False

    def __enter__(self) -> interrupts_deferred:
        import threading

        if threading.current_thread() is not threading.main_thread():
            return self
        self._guard = _current_guard()
        if self._guard is not None:
            self._guard._defer += 1
        if hasattr(signal, "pthread_sigmask"):
            self._blocked = signal.SIGINT not in signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT})
        return self

    def __exit__(self, exc_type, exc, tb) -> None:
        guard = self._guard
        if guard is not None:
            guard._defer -= 1
            held = guard._held and guard._defer == 0        # an outer block still defers it
            guard._held = guard._held and guard._defer > 0
        else:
            held = False
        if self._blocked:
            signal.pthread_sigmask(signal.SIG_UNBLOCK, {signal.SIGINT})  # one that is pending runs its handler now
        if held and exc_type is None and self.raise_held and not guard.stopping:
            raise KeyboardInterrupt


class interrupt_checkpoint:
    """A block of third-party code that may swallow a Ctrl-C: when the block ends normally
    although a SIGINT arrived during it, KeyboardInterrupt is raised at its end.

    Python raises the KeyboardInterrupt wherever the main thread is; code that catches
    ``BaseException`` there (trimesh does, around each of its optional imports, e.g.
    ``try: import networkx except BaseException as E: networkx = ExceptionWrapper(E)``, and
    in its PLY loader) drops it, and the command would go on with its work (the guard only
    counts it: a ``slice`` computed to the end, or to the guard's forced stop with its lock
    left behind). Main thread only. Under an :class:`InterruptGuard` the guard's count tells
    (a Ctrl-C it holds back in an :class:`interrupts_deferred` block, or one after
    :meth:`InterruptGuard.stop`, is left to the guard); with Python's default handler (the
    library used from Python), a handler of this block's own notes it and raises as Python
    would; any other handler is left alone.

    >>> with interrupt_checkpoint():
    ...     x = 1
    """

    def __init__(self):
        self._guard = None
        self._count = 0
        self._arrived = False
        self._own = False

    def _handler(self, signum, frame) -> None:
        self._arrived = True
        raise KeyboardInterrupt

    def __enter__(self) -> interrupt_checkpoint:
        import threading

        if threading.current_thread() is not threading.main_thread():
            return self
        self._guard = _current_guard()
        if self._guard is not None:
            self._count = self._guard.count
        elif signal.getsignal(signal.SIGINT) is signal.default_int_handler:
            signal.signal(signal.SIGINT, self._handler)
            self._own = True
        return self

    def __exit__(self, exc_type, exc, tb) -> None:
        if self._own:
            self._own = False
            if signal.getsignal(signal.SIGINT) == self._handler:
                signal.signal(signal.SIGINT, signal.default_int_handler)
            if exc_type is None and self._arrived:
                raise KeyboardInterrupt
            return
        guard = self._guard
        if (exc_type is None and guard is not None and guard.count > self._count and not guard.stopping
                and not guard._defer and guard._installed):
            guard._import_held = False      # delivered here: the watcher need not send it again
            raise KeyboardInterrupt


def checked_import(name: str):
    """``importlib.import_module(name)`` inside an :class:`interrupt_checkpoint`: for a library
    that catches ``BaseException`` around its own imports (trimesh), so that a Ctrl-C during
    its import is not lost. Imported already: returned at once."""
    module = sys.modules.get(name)
    if module is not None:
        return module
    import importlib

    with interrupt_checkpoint():
        return importlib.import_module(name)
