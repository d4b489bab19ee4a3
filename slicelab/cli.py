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
from .export.files import atomic_open
from .mesh.io import MeshFileError

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


def _check_output_dir(path: Path) -> None:
    # Refuse before any work is done, so a bad -o never leaves half the outputs behind.
    if path.exists() and not path.is_dir():
        raise UsageError(f"{path} exists and is not a directory")


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
    from .mesh.io import load
    from .mesh.validation import check
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
    from .mesh.io import load
    from .slicing.sections import section
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
    from .mesh.io import load
    from .slicing.sections import slice_layers
    _check_output_dir(args.output)
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
    from .mesh.io import load, save
    from .slicing.split import split
    origin, normal = _plane(args)
    if args.visible_from is not None and not np.any(args.visible_from):
        raise UsageError("--visible-from must not be the zero vector")
    _check_output_dir(args.output)
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
        from .viz.preview import save_split_preview
        save_split_preview(s, args.output / "preview.png")
    t4 = time.perf_counter()
    sec = s.section
    print(f"{args.file}: {len(mesh)} facets: front {s.n_front} / cut {s.n_cut} / rear {s.n_rear} facets; "
          f"front.stl {len(s.front)} facets, rear.stl {len(s.rear)} facets"
          + (" (facing the viewer)" if args.visible_from is not None else ""))
    print(f"section: {len(sec.segments)} segments, {len(sec.loops)} loops, "
          f"{len(sec.open_chains)} open chains, area {sec.area:.6g} mm2")
    print(f"load {t1 - t0:.2f} s, split {t2 - t1:.2f} s, write {t3 - t2:.2f} s"
          + ("" if args.no_preview else f", preview {t4 - t3:.2f} s")
          + f"; total {t4 - t0:.2f} s; wrote {args.output}/")
    return 0


# --------------------------------------------------------------------- profile
def _add_profile(sub) -> None:
    p = sub.add_parser("profile", help="align a scanned vessel and draw its profile with measurements",
                       description="Align FILE on its axis of revolution, cut it through the axis at "
                                   "--planes angles, write the archaeological profile drawing (SVG, 1:1 in "
                                   "mm) and print the measurements.")
    p.add_argument("file", type=Path, metavar="FILE")
    p.add_argument("-o", "--output", type=Path, required=True, metavar="OUT.svg")
    p.add_argument("--png", type=Path, metavar="OUT.png", help="also write the drawing as a PNG")
    p.add_argument("--json", type=Path, metavar="OUT.json", help="also write measurements and outlines as JSON")
    p.add_argument("--planes", type=int, default=12, metavar="N", help="planes through the axis (default 12)")
    p.add_argument("--side", choices=("left", "right"), default="left",
                   help="side of the axis for the section (default left; the exterior goes opposite)")
    p.add_argument("--spread", action="store_true", help="draw every other half-section in grey")
    p.add_argument("--no-align", action="store_true", help="the mesh is already aligned (axis +z, base z=0)")
    p.add_argument("--max-gap", type=float, default=1.0, metavar="MM",
                   help="join open section chains whose ends are this close (default 1 mm)")


def _run_profile(args) -> int:
    from .artefacts.profiles import profile
    from .mesh.io import load
    if args.planes < 1:
        raise UsageError("--planes must be at least 1")
    t0 = time.perf_counter()
    mesh = load(args.file)
    t1 = time.perf_counter()
    p = profile(mesh, planes=args.planes, align=not args.no_align, max_gap=args.max_gap, name=args.file.name)
    t2 = time.perf_counter()
    p.to_svg(args.output, side=args.side, spread=args.spread)
    if args.png:
        p.to_png(args.png, side=args.side, spread=args.spread)
    if args.json:
        with atomic_open(args.json, "w", encoding="utf-8") as fh:
            json.dump(p.to_dict(), fh)
    t3 = time.perf_counter()
    if p.alignment is not None:
        print(f"{args.file}: {len(mesh)} facets; {p.alignment!r}")
    print(p.measurements)
    if not p.is_revolution:
        print("warning: not a solid of revolution; the drawn half is not typical of the others")
    print(f"load {t1 - t0:.2f} s, align + profile {t2 - t1:.2f} s, drawing {t3 - t2:.2f} s; wrote {args.output}")
    return 0


# ----------------------------------------------------------------------- batch
def _add_batch(sub) -> None:
    p = sub.add_parser("batch", help="run one task over every STL file under a folder (resumable)",
                       description="Run --task on every *.stl under DIR: one JSON report per file "
                                   "(input SHA-256, parameters, outputs, timings, status ok/warn/fail and "
                                   "reasons) beside its outputs in OUT, and OUT/summary.csv. Files whose "
                                   "report is up to date are skipped. Runs on local processes, or on a Dask "
                                   "cluster given --scheduler (pip install 'slicelab[cluster]').")
    p.add_argument("folder", type=Path, metavar="DIR")
    p.add_argument("-o", "--output", type=Path, required=True, metavar="OUT")
    p.add_argument("--task", choices=("inspect", "section", "split", "profile", "layers"), required=True)
    _add_plane_arguments(p)
    t = p.add_argument_group("task options")
    t.add_argument("--layer-height", type=_positive, metavar="H", help="layers: layer height (mm)")
    t.add_argument("--planes", type=int, default=12, metavar="N", help="profile: planes through the axis")
    t.add_argument("--side", choices=("left", "right"), default="left", help="profile: side of the section")
    t.add_argument("--no-png", action="store_true", help="profile: SVG only")
    t.add_argument("--max-gap", type=float, default=1.0, metavar="MM", help="join open chains this close")
    t.add_argument("--min-size", type=float, default=2.0, metavar="MM",
                   help="flag parts smaller than this as implausible (default 2 mm)")
    t.add_argument("--max-size", type=float, default=5000.0, metavar="MM",
                   help="flag parts larger than this as implausible (default 5000 mm)")
    r = p.add_argument_group("running")
    r.add_argument("--workers", type=int, metavar="N",
                   help="local processes (default: CPU count; 1: in this process)")
    r.add_argument("--scheduler", metavar="ADDRESS", help="Dask scheduler, e.g. tcp://host:8786")
    r.add_argument("--force", action="store_true", help="rerun files whose report is up to date")
    r.add_argument("--retry-failed", action="store_true", help="rerun files whose report says fail")
    r.add_argument("--no-progress", action="store_true", help="no progress bar")
    r.add_argument("--exclude", action="append", default=[], metavar="GLOB",
                   help="leave out paths under DIR matching this pattern (repeatable), e.g. 'large/*'")


def _run_batch(args) -> int:
    from .tasks.batch import run_batch, task_parameters
    if not args.folder.is_dir():
        raise UsageError(f"{args.folder}: not a folder")
    if args.workers is not None and args.workers < 1:
        raise UsageError("--workers must be at least 1")
    options = {}
    if args.task in ("section", "split"):
        if args.z is not None or args.origin is not None or args.normal is not None:
            options["origin"], options["normal"] = _plane(args)
    elif args.z is not None or args.origin is not None or args.normal is not None:
        raise UsageError(f"the {args.task} task takes no plane")
    if args.task == "layers":
        if args.layer_height is None:
            raise UsageError("the layers task needs --layer-height")
        options["layer_height"] = args.layer_height
    if args.task == "profile":
        options.update(planes=args.planes, side=args.side, png=not args.no_png)
    try:
        params = task_parameters(args.task, max_gap=args.max_gap, min_size=args.min_size,
                                 max_size=args.max_size, **options)
    except ValueError as exc:
        raise UsageError(str(exc)) from None
    result = run_batch(args.folder, args.output, args.task, params, workers=args.workers,
                       scheduler=args.scheduler, force=args.force, retry_failed=args.retry_failed,
                       progress=False if args.no_progress else None, exclude=args.exclude)
    print(result)
    for rep in result.reports:
        if rep["status"] != "ok":
            print(f"  {rep['status']:<4} {rep['file']}: {'; '.join(r['message'] for r in rep['reasons'])}")
    print(f"wrote {result.summary}")
    return 1 if result.count("fail") else 0

# ------------------------------------------------------------------------- cut
def _add_cut(sub) -> None:
    p = sub.add_parser("cut", help="cut a solid by a plane into two closed, capped parts",
                       description="Cut FILE with a plane into two watertight parts, each capped on the "
                                   "plane with a constrained Delaunay triangulation; write DIR/rear.stl "
                                   "(the side against the normal), DIR/front.stl and DIR/exploded.png. "
                                   "Exit status 1 when the section did not close (open input).")
    p.add_argument("file", type=Path, metavar="FILE")
    _add_plane_arguments(p)
    p.add_argument("-o", "--output", type=Path, required=True, metavar="DIR")
    p.add_argument("--no-preview", action="store_true", help="do not draw exploded.png")


def _run_cut(args) -> int:
    import warnings

    from .mesh.io import load, save
    from .mesh.validation import check
    from .slicing.cut import CutWarning, cut
    origin, normal = _plane(args)
    _check_output_dir(args.output)
    t0 = time.perf_counter()
    mesh = load(args.file)
    t1 = time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", CutWarning)  # reported below
        parts = cut(mesh, origin, normal)
    t2 = time.perf_counter()
    args.output.mkdir(parents=True, exist_ok=True)
    for name, part in (("rear", parts.rear), ("front", parts.front)):
        save(part, args.output / f"{name}.stl")
    if not args.no_preview:
        from .slicing.partition import save_exploded_png
        save_exploded_png(parts, args.output / "exploded.png", spread=0.35,
                          title=f"{args.file.name}: cut")
    t3 = time.perf_counter()
    rep = parts.report
    print(f"{args.file}: {len(mesh)} facets; {rep.describe()}")
    for name, part in (("rear", parts.rear), ("front", parts.front)):
        r = check(part)
        print(f"{name}.stl: {r.n_facets} facets, volume {r.volume:.6g} mm3, "
              f"{'watertight' if r.watertight and r.winding_consistent else 'NOT watertight'}")
    print(f"load {t1 - t0:.2f} s, cut {t2 - t1:.2f} s, write {t3 - t2:.2f} s; wrote {args.output}/")
    if not rep.closed:
        print("slicelab: warning: the section did not close everywhere (open input); "
              "the parts are not watertight", file=sys.stderr)
        return 1
    return 0


# ------------------------------------------------------------------- partition
def _volume(text: str) -> tuple:
    parts = text.lower().replace(",", "x").split("x")
    try:
        values = tuple(float(v) for v in parts)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a build volume like 200x200x200, got {text!r}") from None
    if len(values) != 3 or not all(np.isfinite(v) and v > 0 for v in values):
        raise argparse.ArgumentTypeError(f"expected three positive sizes like 200x200x200, got {text!r}")
    return values


def _pair(text: str) -> tuple:
    try:
        values = tuple(float(v) for v in text.split(","))
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected HEIGHT,DEPTH like 10,15, got {text!r}") from None
    if len(values) != 2 or not all(np.isfinite(v) and v > 0 for v in values):
        raise argparse.ArgumentTypeError(f"expected two positive sizes like 10,15, got {text!r}")
    return values


def _add_partition(sub) -> None:
    p = sub.add_parser("partition", help="cut a solid into pieces that fit a printer's build volume",
                       description="Cut FILE recursively until every piece fits the build volume; write "
                                   "DIR/part_NNN.stl, DIR/parts.json (sizes, turns, glue areas) and "
                                   "DIR/exploded.png.")
    p.add_argument("file", type=Path, metavar="FILE")
    p.add_argument("--volume", type=_volume, required=True, metavar="XxYxZ",
                   help="build volume in mm, e.g. 200x200x200")
    p.add_argument("--joint", choices=("flat", "stair"), default="flat",
                   help="flat cuts, or interlocking stair joints with at least twice the glue area")
    p.add_argument("--clearance", type=float, default=0.0, metavar="MM", help="glue gap (default 0)")
    p.add_argument("--step", type=_pair, default=(10.0, 20.0), metavar="H,D",
                   help="stair step height and depth in mm (default 10,20)")
    p.add_argument("--flight", type=int, default=1, metavar="N",
                   help="stair steps up before stepping down (default 1: castellated)")
    p.add_argument("--no-rotate", action="store_true", help="do not turn pieces about z to fit")
    p.add_argument("-o", "--output", type=Path, required=True, metavar="DIR")
    p.add_argument("--no-preview", action="store_true", help="do not draw exploded.png")


def _run_partition(args) -> int:
    from .mesh.io import load, save
    from .slicing.partition import partition
    _check_output_dir(args.output)
    if not (args.clearance >= 0 and np.isfinite(args.clearance)):
        raise UsageError("--clearance must be a number >= 0")
    if args.flight < 1:
        raise UsageError("--flight must be at least 1")
    t0 = time.perf_counter()
    mesh = load(args.file)
    t1 = time.perf_counter()
    parts = partition(mesh, args.volume, joint=args.joint, clearance=args.clearance, step=args.step,
                      flight=args.flight, rotate=not args.no_rotate)
    t2 = time.perf_counter()
    args.output.mkdir(parents=True, exist_ok=True)
    width = max(3, len(str(len(parts))))
    for k, part in enumerate(parts):
        save(part, args.output / f"part_{k:0{width}d}.stl")
    with atomic_open(args.output / "parts.json", "w", encoding="utf-8") as fh:
        json.dump({"file": str(args.file), **parts.report.to_dict()}, fh, indent=1)
    if not args.no_preview:
        from .slicing.partition import save_exploded_png
        save_exploded_png(parts, args.output / "exploded.png",
                          title=f"{args.file.name}: {len(parts)} pieces, {args.joint} joints")
    t3 = time.perf_counter()
    print(f"{args.file}: {len(mesh)} facets")
    print(parts.report.describe())
    print(f"load {t1 - t0:.2f} s, partition {t2 - t1:.2f} s, write {t3 - t2:.2f} s; wrote {args.output}/")
    return 0 if parts.report.watertight else 1


# ----------------------------------------------------------------------- slice
def _add_slice(sub) -> None:
    p = sub.add_parser("slice", help="slice a part into printer G-code (perimeters, skins, infill)",
                       description="Plan every layer of FILE (perimeters, solid top and bottom skins, "
                                   "sparse infill) on all cores and write Marlin G-code.")
    p.add_argument("file", type=Path, metavar="FILE")
    p.add_argument("-o", "--output", type=Path, required=True, metavar="OUT.gcode")
    p.add_argument("--layer-height", type=_positive, default=0.2, metavar="H")
    p.add_argument("--first-layer-height", type=_positive, default=None, metavar="H",
                   help="default: the layer height")
    p.add_argument("--line-width", type=_positive, default=0.4, metavar="W")
    p.add_argument("--perimeters", type=int, default=2, metavar="N")
    p.add_argument("--infill", type=float, default=20.0, metavar="PERCENT", help="sparse infill density (0-100)")
    p.add_argument("--infill-angle", type=float, default=45.0, metavar="DEG")
    p.add_argument("--top-layers", type=int, default=3, metavar="N")
    p.add_argument("--bottom-layers", type=int, default=3, metavar="N")
    p.add_argument("--pixel-size", type=_positive, default=0.05, metavar="MM")
    p.add_argument("--nozzle-temperature", type=float, default=210.0, metavar="C")
    p.add_argument("--bed-temperature", type=float, default=60.0, metavar="C")
    p.add_argument("--workers", type=int, default=None, metavar="N", help="processes (default: all cores)")
    p.add_argument("--preview", type=Path, default=None, metavar="DIR",
                   help="also write DIR/layer_*.svg and DIR/preview.png")


def _run_slice(args) -> int:
    from .mesh.io import load
    from .toolpath.planner import PrintSettings, plan
    if not 0 <= args.infill <= 100:
        raise UsageError("--infill is a percentage between 0 and 100")
    for name in ("perimeters", "top_layers", "bottom_layers"):
        if getattr(args, name) < 0:
            raise UsageError(f"--{name.replace('_', '-')} must be >= 0")
    if args.workers is not None and args.workers < 1:
        raise UsageError("--workers must be at least 1")
    if args.preview is not None:
        _check_output_dir(args.preview)
    settings = PrintSettings(layer_height=args.layer_height,
                             first_layer_height=args.first_layer_height or args.layer_height,
                             line_width=args.line_width, perimeters=args.perimeters,
                             infill_density=args.infill / 100, infill_angle=args.infill_angle,
                             top_layers=args.top_layers, bottom_layers=args.bottom_layers,
                             pixel_size=args.pixel_size, nozzle_temperature=args.nozzle_temperature,
                             bed_temperature=args.bed_temperature)
    t0 = time.perf_counter()
    mesh = load(args.file)
    t1 = time.perf_counter()
    pp = plan(mesh, settings, workers=args.workers)
    t2 = time.perf_counter()
    pp.to_gcode(args.output)
    t3 = time.perf_counter()
    if args.preview is not None:
        pp.to_svg(args.preview)
        pp.preview_png(args.preview / "preview.png")
    print(f"{args.file}: {len(mesh)} facets; {len(pp.layers)} layers, print {pp.print_length / 1000:.1f} m, "
          f"filament {pp.filament_length / 1000:.2f} m ({pp.extruded_volume / 1000:.2f} cm3)")
    print(f"load {t1 - t0:.2f} s, plan {t2 - t1:.2f} s, G-code {t3 - t2:.2f} s; wrote {args.output}"
          + (f" and {args.preview}/" if args.preview is not None else ""))
    return 0


COMMANDS = ["inspect", "section", "layers", "split", "profile", "batch", "cut", "partition", "slice"]


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
