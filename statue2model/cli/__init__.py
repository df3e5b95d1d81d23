"""Command line: argument parsing only; each subcommand calls one stage.

    statue2model props [MESH] [--units m|mm|cm|in|auto] [--up x|y|z|-x|-y|-z|auto]
                       [--height H] [--density RHO | --mass M] [--direction DEG]
                       [--base-tol M] [--json OUT]
    statue2model rock PARAMS.json --motion SPEC [model options] [--t-end S] [--json OUT]
    statue2model spectrum | variability | sweep | identify | motion | records ...   (see --help of each)
    statue2model slice [MESH] --scale 1:2 [--board 9mm] ... --out DIR
    statue2model isolator design|plates|simulate|identify ...
    statue2model crosscheck MESH_OR_PARAMS --motion SPEC [--isolator DESIGN.json] --out DIR
    statue2model fragility PARAMS_OR_MESH --records synthetic:N | DIR --levels LO:HI:N [--isolator D.json] --out DIR
    statue2model run [MESH|FOLDER] [--config project.toml] [--out DIR] [--stages LIST] [--force]
                     [--workers N | --scheduler ADDRESS]      every stage, cached, with an HTML report
    statue2model config [--out project.toml]                  the project file with every default
    statue2model validate CAMPAIGN.toml --out DIR [--models 2d,3d] [--identify OTHER.toml]   a shake-table campaign

Errors in the input are printed as one line (``statue2model: error: ...``) with
exit status 2 (also a refused output folder: one holding the user's files, or in use
by another statue2model command). An output that cannot be written (disk full,
quota, permission, read-only file system, name too long) is one line naming the
file, exit status 3, and leaves no file that looks complete. Ctrl-C: status 130.
Set STATUE2MODEL_DEBUG=1 to see tracebacks of internal errors (status 1).

This module holds only ``main``, the top-level parser and the error-to-exit-status
handling. It imports nothing heavy (no numpy): ``main`` puts its Ctrl-C handling in place
before any command is imported (the console script's entry is ``statue2model.__main__:main``,
that of older installs ``statue2model.cli:main``; tests/test_interrupt_entry.py). Each
command's parser and handler live beside it by topic: geometry (props), dynamics (rock,
spectrum, variability, sweep, identify, motion), fabrication (slice), isolator, crosscheck,
run (run, config); argtypes holds the argument types they share.
"""
from __future__ import annotations

import argparse
import errno
import os
import sys

from ..version import __version__
from ..errors import InputError, OutputError
from .argtypes import join_dash_values


def _output_reasons() -> dict:
    """errno -> words of an output error (ENOSPC, EDQUOT, EACCES, EROFS, ENAMETOOLONG, ...)."""
    from ..io.files import _REASONS

    return _REASONS


class _Parser(argparse.ArgumentParser):
    """argparse with errors on one line (no usage block): ``PROG: error: MESSAGE (see PROG --help)``,
    exit status 2, as every other bad input. Sub-commands' parsers are of this class too."""

    def error(self, message: str):
        self.exit(2, f"{self.prog}: error: {message} (see {self.prog} --help)\n")


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(
        prog="statue2model",
        description="From a 3D scan of a statue to its rocking model, prototype and isolator.",
    )
    parser.add_argument("--version", action="version", version=f"statue2model {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    sub.required = True

    from . import crosscheck, dynamics, fabrication, fragility, geometry, isolator, run, validate

    geometry.add_parsers(sub)
    dynamics.add_parsers(sub)
    fabrication.add_parsers(sub)
    isolator.add_parsers(sub)
    crosscheck.add_parsers(sub)
    fragility.add_parsers(sub)
    run.add_parsers(sub)
    validate.add_parsers(sub)
    return parser


def main(argv: list[str] | None = None) -> int:
    """Run one command; returns its exit status. A Ctrl-C at any moment of the command
    (even one Python could only report as "Exception ignored", see
    :class:`~statue2model.compute.interrupts.InterruptGuard`) ends it with the one line
    ``statue2model: interrupted`` and status 130: also while the program is still
    importing (the guard is installed first, from a module that imports only the standard
    library; every command is imported under it), and in the instant before the guard is in
    place or after it is gone (the KeyboardInterrupt of Python's own handler, caught here)."""
    try:
        return _main(argv)
    except KeyboardInterrupt:
        print("statue2model: interrupted", file=sys.stderr)
        if argv is None:
            _end_now(130)
        return 130


def _main(argv: list[str] | None) -> int:
    from ..compute.interrupts import InterruptGuard

    with InterruptGuard() as guard:
        try:
            try:
                parser = build_parser()
                args = parser.parse_args(join_dash_values(sys.argv[1:] if argv is None else list(argv)))
                code = _dispatch(args, guard)
            finally:
                guard.stop()        # from here on a Ctrl-C is only counted
        except KeyboardInterrupt:   # also one that lands in the finally, before stop()
            code = 130
        except Exception:           # a Ctrl-C turned into another error while a command was imported
            if not guard.interrupted:   # (numpy's C import: "ImportError ... could not import module")
                raise
            code = 130
        if code == 130 or guard.interrupted:
            print("statue2model: interrupted", file=sys.stderr)
            code = 130
            if argv is None:
                _end_now(code)
    return code


def _end_now(code: int) -> None:
    """End the program at once after a Ctrl-C, past the interpreter's own shutdown: every
    file is already written whole or not at all and the workers are stopped, but at exit
    CPython would (1) join a broken process pool's threads, which can wait forever on a
    pipe its terminated workers no longer read (seen on Debian's 3.11.2), and (2) under
    ``python -m`` end by killing itself with SIGINT (status -2) when the KeyboardInterrupt
    passed through code built by ``exec`` (dataclasses). Only when ``main`` is the program
    (``argv`` None: the console script, ``python -m statue2model``), never from Python."""
    try:
        if "multiprocessing" in sys.modules:   # the pool's semaphores: unlinked, as at a normal exit
            from multiprocessing import util   # (exit priority >= 0: not the joins that can hang)

            util._run_finalizers(0)
        sys.stdout.flush()
        sys.stderr.flush()
    finally:
        os._exit(code)


def _dispatch(args, guard=None) -> int:
    """The command's handler; its errors as exit statuses (KeyboardInterrupt goes to main). An
    exception raised after a Ctrl-C arrived (``guard.interrupted``: a library that turned the
    KeyboardInterrupt into its own error, e.g. a figure half drawn, or trimesh's PLY reader that
    dropped it and then failed on its file: "cannot read ...: Bad file descriptor") is the
    interrupt's, not the input's nor a bug: status 130, nothing printed here (main says
    "interrupted")."""
    try:
        return args.func(args)
    except Exception:
        if guard is not None and guard.interrupted:
            return 130
        return _error_status()


def _error_status() -> int:
    """The exit status of the exception being handled (printed as one line)."""
    try:
        raise
    except OutputError as exc:
        print(f"statue2model: error: {exc}", file=sys.stderr)
        return 3
    except InputError as exc:
        print(f"statue2model: error: {exc}", file=sys.stderr)
        return 2
    except OSError as exc:
        if exc.errno not in _output_reasons() or os.environ.get("STATUE2MODEL_DEBUG"):
            return _internal(exc)
        print(f"statue2model: error: {_os_error_line(exc)}", file=sys.stderr)
        return 3
    except MemoryError:  # a request no budget check caught
        print("statue2model: error: the request does not fit in this machine's memory: use smaller grids, "
              "a coarser --dt-out or a shorter --t-end", file=sys.stderr)
        return 2
    except Exception as exc:  # a bug: still one line unless debugging
        return _internal(exc)


def _os_error_line(exc: OSError) -> str:
    """One line for an OSError no output helper translated (e.g. a library writing directly)."""
    from ..io.files import output_error

    if exc.errno in (errno.ENOSPC, errno.EDQUOT, errno.EFBIG):
        return str(output_error(exc, exc.filename if exc.filename is not None else "an output file"))
    return f"{_output_reasons()[exc.errno]}" + (f": {exc.filename}" if exc.filename is not None else "")


def _internal(exc: BaseException) -> int:
    if os.environ.get("STATUE2MODEL_DEBUG"):
        raise exc
    print(f"statue2model: internal error: {type(exc).__name__}: {exc} "
          "(set STATUE2MODEL_DEBUG=1 for the traceback)", file=sys.stderr)
    return 1


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
