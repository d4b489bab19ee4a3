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


# --------------------------------------------------------------------- section
def _add_section(sub) -> None:
    p = sub.add_parser("section", help="cut a mesh with one plane and draw the section as SVG",
                       description="Cut FILE with a plane; write the section as a true-scale SVG (mm).")
    p.add_argument("file", type=Path, metavar="FILE")
    _add_plane_arguments(p)
    p.add_argument("-o", "--output", type=Path, required=True, metavar="OUT.svg")
    p.add_argument("--max-gap", type=float, default=1.0, metavar="MM",
                   help="join open chains whose ends are this close (default 1 mm; 0 disables)")


def _run_section(args) -> int:
    from .io import load
    from .sections import section
    origin, normal = _plane(args)
    t0 = time.perf_counter()
    mesh = load(args.file)
    t1 = time.perf_counter()
    s = section(mesh, origin, normal, max_gap=args.max_gap)
    t2 = time.perf_counter()
    s.to_svg(args.output)
    holes = int(np.count_nonzero(s.loop_depth % 2 == 1)) if len(s.loops) else 0
    print(f"{args.file}: {len(mesh)} facets; section: {len(s.segments)} segments, {len(s.loops)} loops "
          f"({holes} holes), {len(s.open_chains)} open chains, {len(s.joined_gaps)} gaps joined, "
          f"area {s.area:.6g} mm2")
    print(f"load {t1 - t0:.2f} s, section {t2 - t1:.2f} s; wrote {args.output}")
    return 0


# ---------------------------------------------------------------------- layers
def _add_layers(sub) -> None:
    p = sub.add_parser("layers", help="slice a mesh into horizontal layers (SVG per layer + JSON)",
                       description="Slice FILE at mid-layer heights; write one SVG per layer and "
                                   "layers.json with every loop.")
    p.add_argument("file", type=Path, metavar="FILE")
    p.add_argument("--layer-height", type=_positive, required=True, metavar="H")
    p.add_argument("-o", "--output", type=Path, required=True, metavar="DIR")
    p.add_argument("--max-gap", type=float, default=1.0, metavar="MM",
                   help="join open chains whose ends are this close (default 1 mm; 0 disables)")


def _run_layers(args) -> int:
    from .io import load
    from .sections import slice_layers
    if args.output.exists() and not args.output.is_dir():
        raise UsageError(f"{args.output} exists and is not a directory")
    t0 = time.perf_counter()
    mesh = load(args.file)
    t1 = time.perf_counter()
    layers = slice_layers(mesh, args.layer_height, max_gap=args.max_gap)
    t2 = time.perf_counter()
    args.output.mkdir(parents=True, exist_ok=True)
    width = max(4, len(str(len(layers))))
    for k, s in enumerate(layers):
        s.to_svg(args.output / f"layer_{k:0{width}d}_z{s.z:.3f}.svg")
    with atomic_open(args.output / "layers.json", "w", encoding="utf-8") as fh:
        json.dump({"file": str(args.file), "layer_height": args.layer_height,
                   "layers": [{"index": k, "z": s.z, **s.to_dict()} for k, s in enumerate(layers)]}, fh)
    n_open = sum(len(s.open_chains) for s in layers)
    print(f"{args.file}: {len(mesh)} facets; {len(layers)} layers, "
          f"{sum(len(s.loops) for s in layers)} loops, {n_open} open chains")
    print(f"load {t1 - t0:.2f} s, slice {t2 - t1:.2f} s; wrote {args.output}/")
    return 0


# ----------------------------------------------------------------------- split
def _add_split(sub) -> None:
    p = sub.add_parser("split", help="split a mesh by a plane into front, section and rear",
                       description="Cut FILE with a plane into the part in front (the side the normal "
                                   "points to) and the part behind; write DIR/front.stl, DIR/rear.stl, "
                                   "DIR/section.svg and DIR/preview.png.")
    p.add_argument("file", type=Path, metavar="FILE")
    _add_plane_arguments(p)
    p.add_argument("-o", "--output", type=Path, required=True, metavar="DIR")
    p.add_argument("--visible-from", type=_vector, metavar="X,Y,Z",
                   help="keep only the facets facing a viewer in this direction (as for a drawing)")
    p.add_argument("--max-gap", type=float, default=1.0, metavar="MM",
                   help="join open section chains whose ends are this close (default 1 mm; 0 disables)")
    p.add_argument("--no-preview", action="store_true", help="do not draw preview.png")


def _run_split(args) -> int:
    from .io import load, save
    from .split import split
    origin, normal = _plane(args)
    if args.visible_from is not None and not np.any(args.visible_from):
        raise UsageError("--visible-from must not be the zero vector")
    if args.output.exists() and not args.output.is_dir():
        raise UsageError(f"{args.output} exists and is not a directory")
    t0 = time.perf_counter()
    mesh = load(args.file)
    t1 = time.perf_counter()
    s = split(mesh, origin, normal, visible_from=args.visible_from, max_gap=args.max_gap)
    t2 = time.perf_counter()
    args.output.mkdir(parents=True, exist_ok=True)
    save(s.front, args.output / "front.stl")
    save(s.rear, args.output / "rear.stl")
    s.section.to_svg(args.output / "section.svg")
    t3 = time.perf_counter()
    if not args.no_preview:
        from .preview import save_split_preview
        save_split_preview(s, args.output / "preview.png")
    t4 = time.perf_counter()
    sec = s.section
    print(f"{args.file}: {len(mesh)} facets: front {s.n_front} / cut {s.n_cut} / rear {s.n_rear} facets; "
          f"front.stl {len(s.front)} facets, rear.stl {len(s.rear)} facets"
          + (" (facing the viewer)" if args.visible_from is not None else ""))
    print(f"section: {len(sec.segments)} segments, {len(sec.loops)} loops, {len(sec.open_chains)} open chains, "
          f"area {sec.area:.6g} mm2")
    print(f"load {t1 - t0:.2f} s, split {t2 - t1:.2f} s, write {t3 - t2:.2f} s"
          + ("" if args.no_preview else f", preview {t4 - t3:.2f} s")
          + f"; total {t4 - t0:.2f} s; wrote {args.output}/")
    return 0


COMMANDS = ["inspect", "section", "layers", "split"]


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
