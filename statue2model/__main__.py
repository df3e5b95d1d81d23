"""The program's entry: ``python -m statue2model`` and the console script ``statue2model``
(pyproject.toml: ``statue2model = "statue2model.__main__:main"``).

Tiny on purpose: it and the package's ``__init__`` import nothing heavy, and importing it puts
the program's first Ctrl-C handling in place (the console script pip writes imports it, then runs
a line of its own before calling :func:`main`). A Ctrl-C that lands before
:func:`statue2model.cli.main` has installed its guard (while the command line is still being
imported) or after the guard is gone (the interpreter ending) ends the program at once with the
one line ``statue2model: interrupted`` and status 130, never a traceback: nothing is being
written then. Meant to be the program, not to be imported by other code (importing it sets the
SIGINT handler of the process, when that is still Python's default).
"""
import os
import sys

try:
    import _signal as signal    # the C module, built in: `signal` imports enum first (milliseconds)
except ImportError:  # pragma: no cover - not CPython
    import signal


def _interrupted(signum, frame) -> None:
    """The SIGINT handler outside the command's guard: end now, status 130."""
    try:
        for stream in (sys.stdout, sys.stderr):
            try:
                stream.flush()
            except Exception:   # e.g. a reentrant call: the main thread was writing to it
                pass
        os.write(2, b"statue2model: interrupted\n")
    finally:
        os._exit(130)


def _after_the_program() -> None:
    """The last of the interpreter's exit handlers (registered first, run last): a Ctrl-C from
    here on is ignored. The command has ended and written everything; without this, one that
    lands in the interpreter's final clean-up (after it has put the default SIGINT action
    back: tens of milliseconds of freeing modules) killed the process by the signal, status
    -2, with nothing said. Before this point :func:`_interrupted` answers it. Then
    :func:`_freeze_the_heap`."""
    try:
        signal.signal(signal.SIGINT, signal.SIG_IGN)
    except ValueError:  # pragma: no cover - not the main thread
        pass
    _freeze_the_heap()


def _freeze_the_heap() -> None:
    """Every object left moved out of the cyclic garbage collector's reach (``gc.freeze``), once the
    command has ended: the interpreter's final collection would otherwise walk the whole heap
    (millions of objects after a run: numba, scipy, matplotlib; about 0.3-0.5 s of CPU) to free
    memory the process hands back to the system anyway as it ends. Registered first (run last) also
    where :func:`_after_the_program` is not (SIGINT ignored: a job started in the background)."""
    import gc           # built in

    gc.freeze()


if signal.getsignal(signal.SIGINT) is signal.SIG_IGN:
    import atexit           # built in

    atexit.register(_freeze_the_heap)
elif signal.getsignal(signal.SIGINT) is signal.default_int_handler:
    try:
        signal.signal(signal.SIGINT, _interrupted)
    except ValueError:          # not the main thread: not the program's entry
        pass
    else:
        import atexit           # built in

        atexit.register(_after_the_program)


def main() -> int:
    """Run the command of ``sys.argv`` (:func:`statue2model.cli.main`); its exit status."""
    try:
        from .cli import main as run

        return run()
    except KeyboardInterrupt:   # a handler other than ours was in place: the same line, the same status
        _interrupted(signal.SIGINT, None)
        raise   # pragma: no cover - _interrupted ends the process


if __name__ == "__main__":
    sys.exit(main())
