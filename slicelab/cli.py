"""The ``slicelab`` command line.

Every command is a pair of functions: ``_add_<name>`` declares its arguments
and ``_run_<name>`` does the work. Bad input ends with one line on stderr and
exit status 2, never a traceback.
"""
from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

import numpy as np

from . import __version__
from .io import MeshFileError, atomic_open

__all__ = ["main"]


class UsageError(ValueError):
    """A command-line argument that makes no sense (exit status 2)."""


def _vector(text: str) -> np.ndarray:
    try:
        values = [float(v) for v in text.split(",")]
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected three numbers like 1,0,0, got {text!r}") from None
    if len(values) != 3 or not np.all(np.isfinite(values)):
        raise argparse.ArgumentTypeError(f"expected three finite numbers like 1,0,0, got {text!r}")
    return np.array(values)


def _positive(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number, got {text!r}") from None
    if not (value > 0 and np.isfinite(value)):
        raise argparse.ArgumentTypeError(f"expected a positive number, got {text!r}")
    return value


def _add_plane_arguments(p: argparse.ArgumentParser) -> None:
    g = p.add_argument_group("plane (give --z, or --origin and --normal)")
    g.add_argument("--z", type=float, help="horizontal plane at this height (mm)")
    g.add_argument("--origin", type=_vector, metavar="X,Y,Z", help="a point of the plane (mm)")
    g.add_argument("--normal", type=_vector, metavar="A,B,C", help="the plane's normal")


def _plane(args) -> tuple[np.ndarray, np.ndarray]:
    if args.z is not None:
        if args.origin is not None or args.normal is not None:
            raise UsageError("give either --z or --origin/--normal, not both")
        return np.array([0.0, 0.0, args.z]), np.array([0.0, 0.0, 1.0])
    if args.origin is None or args.normal is None:
        raise UsageError("give a plane: --z Z, or --origin X,Y,Z and --normal A,B,C")
    if not np.any(args.normal):
        raise UsageError("--normal must not be the zero vector")
    return args.origin, args.normal


# --------------------------------------------------------------------- inspect
def _add_inspect(sub) -> None:
    p = sub.add_parser("inspect", help="load STL files and report their defects",
                       description="Load each STL file and print its mesh report.")
    p.add_argument("files", nargs="+", type=Path, metavar="FILE")
    p.add_argument("--json", action="store_true", help="print one JSON object per file")


def _run_inspect(args) -> int:
    from .check import check
    from .io import load
    status = 0
    for path in args.files:
        try:
            t0 = time.perf_counter()
            mesh = load(path)
            report = check(mesh)
            elapsed = time.perf_counter() - t0
        except MeshFileError as exc:
            print(f"slicelab: error: {exc}", file=sys.stderr)
            status = 2
            continue
        if args.json:
            print(json.dumps({"file": str(path), **report.to_dict(), "seconds": round(elapsed, 4)}))
        else:
            print(f"== {path}  ({elapsed:.2f} s)")
            print(report)
    return status


COMMANDS = ["inspect"]


def build_parser() -> argparse.ArgumentParser:
    """The argument parser with every subcommand."""
    parser = argparse.ArgumentParser(
        prog="slicelab",
        description="Exact slicing of STL meshes: checks, sections, splits, cuts and toolpaths.")
    parser.add_argument("--version", action="version", version=f"slicelab {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    sub.required = True
    for name in COMMANDS:
        globals()[f"_add_{name}"](sub)
    return parser


def main(argv=None) -> int:
    """Run the command line; return the exit status.

    Examples
    --------
    >>> main(["--version"])  # doctest: +SKIP
    slicelab 0.1.0
    """
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        return int(globals()[f"_run_{args.command.replace('-', '_')}"](args) or 0)
    except (MeshFileError, UsageError) as exc:
        print(f"slicelab: error: {exc}", file=sys.stderr)
        return 2
    except (ValueError, OSError) as exc:
        msg = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
        print(f"slicelab: error: {msg}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("slicelab: interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":  # pragma: no cover
    raise SystemExit(main())
