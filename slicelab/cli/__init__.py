"""The ``slicelab`` command line.

Every command is a pair of functions, one that declares its arguments and
one that runs the job of the same name (`slicelab.tasks.jobs`, which checks
the parameters and writes the outputs, atomically) and prints what it did.
Bad input ends with one line on stderr and exit status 2, never a traceback.

==========================  =====================================================
``cli.arguments``           argument types, the plane, job options, messages
``cli.analysis``            inspect, section, layers, split, profile, batch
``cli.fabrication``         cut, partition, arrange, slice
==========================  =====================================================
"""
from __future__ import annotations

import argparse
import sys

from .. import __version__
from ..mesh.formats import UNITS
from ..mesh.io import MeshFileError
from ..tasks.spec import ParameterError
from . import analysis, fabrication
from .arguments import UsageError, flag_message, negative_values, positive

__all__ = ["main", "run", "build_parser", "COMMANDS"]

_TABLE = {**analysis.COMMANDS, **fabrication.COMMANDS}
COMMANDS = ["inspect", "section", "layers", "split", "profile", "batch", "cut", "partition", "arrange", "slice"]


class _Version(argparse.Action):
    """``--version``: the version, and which compiled kernels a command runs: the module built at
    install, or numba's and where they are cached (`slicelab.geometry.compiled.describe`), which a
    slow start or a bug report needs to know."""

    def __call__(self, parser, namespace, values, option_string=None):
        from ..geometry.compiled import describe
        print(f"slicelab {__version__} (compiled kernels: {describe()})")
        parser.exit()


class _Parser(argparse.ArgumentParser):
    """argparse's parser, whose usage errors are one line naming the problem and where help is
    (argparse prints the whole usage first: up to 25 lines for ``slice``)."""

    def error(self, message):
        self.exit(2, f"{self.prog}: error: {message} (see {self.prog} --help)\n")


def build_parser() -> argparse.ArgumentParser:
    """The argument parser with every subcommand.

    Examples
    --------
    >>> import contextlib, io
    >>> err = io.StringIO()
    >>> with contextlib.redirect_stderr(err):
    ...     try:
    ...         build_parser().parse_args(["slice", "part.stl", "--layer-height", "thin"])
    ...     except SystemExit as exc:
    ...         print(exc.code)
    2
    >>> print(err.getvalue(), end="")
    slicelab slice: error: argument --layer-height: expected a number, got 'thin' (see slicelab slice --help)
    """
    parser = _Parser(
        prog="slicelab",
        description="Exact slicing of STL meshes: checks, sections, splits, cuts and toolpaths.")
    parser.add_argument("--version", action=_Version, nargs=0,
                        help="show the version and how the compiled kernels load, and exit")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    sub.required = True
    for name in COMMANDS:
        _TABLE[name][0](sub)
    for p in sub.choices.values():  # every command reads mesh files: their units
        g = p.add_argument_group("units of the input")
        g.add_argument("--units", choices=tuple(UNITS), default=None,
                       help="the unit the file is written in (default mm); coordinates are scaled to mm")
        g.add_argument("--scale", type=positive, default=None, metavar="F",
                       help="a further factor for the coordinates")
    return parser


def main(argv=None) -> int:
    """Run the command line; return the exit status.

    Examples
    --------
    >>> main(["--version"])  # doctest: +SKIP
    slicelab 0.1.0
    """
    parser = build_parser()
    args = parser.parse_args(negative_values(list(sys.argv[1:] if argv is None else argv)))
    try:
        return int(_TABLE[args.command][1](args) or 0)
    except ParameterError as exc:
        print(f"slicelab: error: {flag_message(exc)}", file=sys.stderr)
        return 2
    except (MeshFileError, UsageError) as exc:
        print(f"slicelab: error: {exc}", file=sys.stderr)
        return 2
    except BrokenPipeError:  # the reader left (`slicelab inspect ... | head`): nothing is wrong here
        return _reader_gone()
    except (ValueError, OSError) as exc:
        msg = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
        print(f"slicelab: error: {msg}", file=sys.stderr)
        return 2
    except MemoryError:
        print("slicelab: error: out of memory: the parameters ask for more than this machine has "
              "(a coarser --pixel-size or --layer-height needs less)", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("slicelab: interrupted", file=sys.stderr)
        return 130
    except (ArithmeticError, RecursionError, Exception) as exc:  # noqa: BLE001 - a bug, said in one line
        import os
        if os.environ.get("SLICELAB_DEBUG"):
            raise
        msg = str(exc).splitlines()[0] if str(exc) else ""
        print(f"slicelab: internal error: {type(exc).__name__}: {msg} (a bug: please report it with the "
              f"command; SLICELAB_DEBUG=1 shows the traceback)", file=sys.stderr)
        return 1


#: The status of a command whose reader closed the pipe: a process ended by SIGPIPE, as the shell shows it.
SIGPIPE_STATUS = 141


def _reader_gone() -> int:
    """Point stdout at the null device, so that nothing more fails on it, and return `SIGPIPE_STATUS`."""
    import os
    try:
        null = os.open(os.devnull, os.O_WRONLY)
        os.dup2(null, sys.stdout.fileno())
        os.close(null)
    except (OSError, ValueError):  # a stdout without a file descriptor (a notebook's)
        pass
    return SIGPIPE_STATUS


def run() -> int:
    """The console command: `main`, then a quick end of the process.

    Once `main` has returned, everything the command writes is written and
    closed, and the process ends. The exit handlers run as at any exit (the
    process pools', Dask's, temporary directories'), the standard streams are
    flushed, and the process ends there, without the interpreter's teardown
    of every module and object, which would add to every command's wall time.
    While a thread that is not a daemon still runs, the process ends the
    usual way, which waits for it. The garbage collector's objects are
    frozen first: its last collection would walk every object the compiled
    kernels left. An exception `main` does not turn into a status ends the
    process the usual way, with its traceback.
    """
    import atexit
    import gc
    import os
    import threading
    status = main()
    gc.freeze()
    main_thread = threading.main_thread()
    if any(t.is_alive() and not t.daemon and t is not main_thread for t in threading.enumerate()):
        return status
    atexit._run_exitfuncs()
    for stream in (sys.stdout, sys.stderr):
        try:
            stream.flush()
        except (OSError, ValueError):  # a closed pipe (`slicelab ... | head`): nothing more to say
            pass
    os._exit(status)


if __name__ == "__main__":  # pragma: no cover
    raise SystemExit(run())
