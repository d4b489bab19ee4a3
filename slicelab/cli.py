"""The ``slicelab`` command line.

Every command is a pair of functions: ``_add_<name>`` declares its arguments
and ``_run_<name>`` runs the job of the same name (`slicelab.tasks.jobs`,
which checks the parameters and writes the outputs, atomically) and prints
what it did. Job options left out on the command line are left out of the
job's parameters too, so their defaults live in one place, the job. Bad input
ends with one line on stderr and exit status 2, never a traceback.
"""
from __future__ import annotations

import argparse
import json
import re
import sys
from pathlib import Path

import numpy as np

from . import __version__
from .mesh.formats import UNITS
from .mesh.io import MeshFileError
from .tasks.batch import TASKS
from .tasks.jobs import JOBS, run_job
from .tasks.spec import ParameterError

__all__ = ["main"]

_GIVEN = argparse.SUPPRESS  # the default of a job option: absent unless given
# Parameters whose flag is not simply --name-with-dashes.
_FLAGS = {"n_perimeters": "--perimeters", "plane": "a plane (--z, or --origin and --normal)"}


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


def _density(text: str) -> float:
    """A density as a fraction: ``20`` and ``20%`` are percentages, a bare number up to 1 a fraction."""
    percent = text.strip().endswith("%")
    try:
        value = float(text.strip().rstrip("%"))
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a percentage like 20 or 20% or a fraction like 0.2, "
                                         f"got {text!r}") from None
    return value / 100 if percent or value > 1 else value


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


def _default(job: str, name: str):
    return JOBS[job].defaults[name]


def _options(args, job: str, **more) -> dict:
    """The job's parameters given on the command line, how to read the file, and `more`."""
    reading = {n: getattr(args, n) for n in ("units", "scale") if getattr(args, n, None) is not None}
    return {**{n: getattr(args, n) for n in JOBS[job].defaults if hasattr(args, n)}, **reading, **more}


def _add_plane_arguments(p: argparse.ArgumentParser) -> None:
    g = p.add_argument_group("plane (give --z, or --origin and --normal)")
    g.add_argument("--z", type=float, help="horizontal plane at this height (mm)")
    g.add_argument("--origin", type=_vector, metavar="X,Y,Z", help="a point of the plane (mm)")
    g.add_argument("--normal", type=_vector, metavar="A,B,C", help="the plane's normal")


def _plane(args, required: bool = True):
    """(origin, normal) from --z or --origin/--normal; None when none is given and none is required."""
    if args.z is not None:
        if args.origin is not None or args.normal is not None:
            raise UsageError("give either --z or --origin/--normal, not both")
        return np.array([0.0, 0.0, args.z]), np.array([0.0, 0.0, 1.0])
    if args.origin is None and args.normal is None and not required:
        return None
    if args.origin is None or args.normal is None:
        raise UsageError("give a plane: --z Z, or --origin X,Y,Z and --normal A,B,C")
    return args.origin, args.normal


def _max_gap(p, job: str, what: str = "chains") -> None:
    p.add_argument("--max-gap", type=float, default=_GIVEN, metavar="MM",
                   help=f"join open {what} whose ends are this close "
                        f"(default {_default(job, 'max_gap'):g} mm; 0 disables)")


def _no_preview(p, name: str = "preview.png") -> None:
    p.add_argument("--no-preview", dest="preview", action="store_false", default=_GIVEN,
                   help=f"do not draw {name}")


def _repair_flag(p) -> None:
    p.add_argument("--repair", action="store_true", default=_GIVEN,
                   help="first snap CAD float noise (near-coincident vertices), drop collapsed and duplicate "
                        "facets and make windings agree (slicelab.repair); the changes are reported")


def _negative_values(argv: list[str]) -> list[str]:
    """``--origin -3,2,1`` as ``--origin=-3,2,1``: argparse takes a value that starts with a minus
    sign for an option unless it is a plain number."""
    out, k = [], 0
    while k < len(argv):
        tok = argv[k]
        if (tok.startswith("--") and "=" not in tok and k + 1 < len(argv)
                and re.fullmatch(r"-[\d.][\d.eE+\-]*(,[-+]?[\d.][\d.eE+\-]*)*", argv[k + 1])):
            out.append(f"{tok}={argv[k + 1]}")
            k += 2
            continue
        out.append(tok)
        k += 1
    return out


def _warn(r, skip=()) -> None:
    """Each warning the job found, as a sentence on stderr (its code is in the JSON reports)."""
    for why in r.reasons:
        if why["code"] not in skip:
            print(f"slicelab: warning: {why['message']}", file=sys.stderr)


def _say_repair(r) -> None:
    rep = r.results.get("repair")
    if rep is not None:
        print("repair: " + ("; ".join(rep["changes"]) if rep["changes"] else "nothing to repair"))


def _timings(r, verb: str) -> str:
    t = r.timings
    return f"load {t['load']:.2f} s, {verb} {t['compute']:.2f} s, write {t['write']:.2f} s"


# --------------------------------------------------------------------- inspect
def _add_inspect(sub) -> None:
    p = sub.add_parser("inspect", help="load STL files and report their defects",
                       description="Load each STL file and print its mesh report.")
    p.add_argument("files", nargs="+", type=Path, metavar="FILE")
    p.add_argument("--json", action="store_true", help="print one JSON object per file")


def _run_inspect(args) -> int:
    status = 0
    for path in args.files:
        try:
            r = run_job("inspect", path, _options(args, "inspect"))
        except MeshFileError as exc:
            print(f"slicelab: error: {exc}", file=sys.stderr)
            status = 2
            continue
        elapsed = r.timings["load"] + r.timings["compute"]
        if args.json:
            print(json.dumps({"file": str(path), **r.results, "seconds": round(elapsed, 4)}))
        else:
            print(f"== {path}  ({elapsed:.2f} s)")
            print(r.value)
            _warn(r)
    return status


# --------------------------------------------------------------------- section
def _add_section(sub) -> None:
    p = sub.add_parser("section", help="cut a mesh with one plane and draw the section as SVG",
                       description="Cut FILE with a plane; write the section as a true-scale SVG (mm).")
    p.add_argument("file", type=Path, metavar="FILE")
    _add_plane_arguments(p)
    p.add_argument("-o", "--output", type=Path, required=True, metavar="OUT.svg")
    _max_gap(p, "section")


def _run_section(args) -> int:
    r = run_job("section", args.file, _options(args, "section", plane=_plane(args)), paths={"svg": args.output})
    s = r.results
    print(f"{args.file}: {r.n_facets} facets; section: {s['segments']} segments, {s['loops']} loops "
          f"({s['holes']} holes), {s['open_chains']} open chains, {s['joined_gaps']} gaps joined, "
          f"area {s['area']:.6g} mm2")
    print(f"{_timings(r, 'section')}; wrote {args.output}")
    _warn(r)
    return 0


# ---------------------------------------------------------------------- layers
def _add_layers(sub) -> None:
    p = sub.add_parser("layers", help="slice a mesh into horizontal layers (SVG per layer + JSON)",
                       description="Slice FILE at mid-layer heights; write one SVG per layer and "
                                   "layers.json with every loop.")
    p.add_argument("file", type=Path, metavar="FILE")
    p.add_argument("--layer-height", type=_positive, required=True, metavar="H")
    p.add_argument("-o", "--output", type=Path, required=True, metavar="DIR")
    _max_gap(p, "layers")
    p.add_argument("--no-svg", dest="svg", action="store_false", default=_GIVEN, help="layers.json only")


def _run_layers(args) -> int:
    r = run_job("layers", args.file, _options(args, "layers"), args.output)
    s = r.results
    _say_repair(r)
    print(f"{args.file}: {r.n_facets} facets; {s['layers']} layers, {s['loops']} loops, "
          f"{s['open_chains']} open chains")
    print(f"{_timings(r, 'slice')}; wrote {args.output}/")
    _warn(r)
    return 0


# ----------------------------------------------------------------------- split
def _add_split(sub) -> None:
    p = sub.add_parser("split", help="split a mesh by a plane into front, section and rear",
                       description="Cut FILE with a plane into the part in front (the side the normal "
                                   "points to) and the part behind; write DIR/front.stl, DIR/rear.stl "
                                   "(each when not empty), DIR/section.svg and DIR/preview.png.")
    p.add_argument("file", type=Path, metavar="FILE")
    _add_plane_arguments(p)
    p.add_argument("-o", "--output", type=Path, required=True, metavar="DIR")
    p.add_argument("--visible-from", type=_vector, default=_GIVEN, metavar="X,Y,Z",
                   help="keep only the facets facing a viewer in this direction (as for a drawing)")
    _max_gap(p, "split", "section chains")
    _no_preview(p)


def _run_split(args) -> int:
    r = run_job("split", args.file, _options(args, "split", plane=_plane(args)), args.output)
    s = r.results
    pieces = ", ".join(f"{n}.stl {s[n + '_facets']} facets" if s[n + "_facets"] else f"no {n}.stl (empty)"
                       for n in ("front", "rear"))
    print(f"{args.file}: {r.n_facets} facets: front {s['n_front']} / cut {s['cut_facets']} / rear {s['n_rear']} "
          f"facets; {pieces}" + (" (facing the viewer)" if r.parameters["visible_from"] is not None else ""))
    print(f"section: {s['section_segments']} segments, {s['section_loops']} loops, "
          f"{s['section_open_chains']} open chains, area {s['section_area']:.6g} mm2")
    for n in ("front", "rear"):
        if s.get(f"{n}_collapsed_in_float32"):
            print(f"{n}.stl: {s[f'{n}_collapsed_in_float32']} sliver facets that float32 rounding collapsed "
                  f"were left out")
    print(f"{_timings(r, 'split')}; total {sum(r.timings.values()):.2f} s; wrote {args.output}/")
    _warn(r)
    return 0


# --------------------------------------------------------------------- profile
def _add_profile(sub) -> None:
    p = sub.add_parser("profile", help="align a scanned vessel and draw its profile with measurements",
                       description="Align FILE on its axis of revolution, cut it through the axis at "
                                   "--planes angles, write the archaeological profile drawing (SVG, 1:1 in "
                                   "mm) and print the measurements.")
    p.add_argument("file", type=Path, metavar="FILE")
    p.add_argument("-o", "--output", type=Path, required=True, metavar="OUT.svg")
    p.add_argument("--png", dest="png_path", type=Path, metavar="OUT.png", help="also write the drawing as a PNG")
    p.add_argument("--json", dest="json_path", type=Path, metavar="OUT.json",
                   help="also write measurements and outlines as JSON")
    p.add_argument("--planes", type=int, default=_GIVEN, metavar="N",
                   help=f"planes through the axis (default {_default('profile', 'planes')})")
    p.add_argument("--side", choices=("left", "right"), default=_GIVEN,
                   help="side of the axis for the section (default left; the exterior goes opposite)")
    p.add_argument("--spread", action="store_true", default=_GIVEN,
                   help="draw every other half-section in grey")
    p.add_argument("--no-align", dest="align", action="store_false", default=_GIVEN,
                   help="the mesh is already aligned (axis +z, base z=0)")
    _max_gap(p, "profile", "section chains")


def _run_profile(args) -> int:
    params = _options(args, "profile", png=args.png_path is not None, json=args.json_path is not None)
    r = run_job("profile", args.file, params,
                paths={"svg": args.output, "png": args.png_path, "json": args.json_path})
    p = r.value
    if p.alignment is not None:
        print(f"{args.file}: {r.n_facets} facets; {p.alignment!r}")
    print(p.measurements)
    t = r.timings
    print(f"load {t['load']:.2f} s, align + profile {t['compute']:.2f} s, drawing {t['write']:.2f} s; "
          f"wrote {args.output}")
    _warn(r)
    return 0


# ----------------------------------------------------------------------- batch
def _add_batch(sub) -> None:
    p = sub.add_parser("batch", help="run one task over every STL file under a folder (resumable)",
                       description="Run --task on every *.stl under DIR: one JSON report per file "
                                   "(input SHA-256, parameters, outputs, timings, status ok/warn/fail and "
                                   "reasons) in OUT, the outputs in a folder named after the file (the "
                                   "same names as the command of the same name writes), and "
                                   "OUT/summary.csv. Files whose report is up to date are skipped. Runs "
                                   "on local processes, or on a Dask cluster given --scheduler "
                                   "(pip install 'slicelab[cluster]').")
    p.add_argument("folder", type=Path, metavar="DIR")
    p.add_argument("-o", "--output", type=Path, required=True, metavar="OUT")
    p.add_argument("--task", choices=TASKS, required=True)
    _add_plane_arguments(p)
    t = p.add_argument_group("task options (defaults as for the command of the same name)")
    t.add_argument("--layer-height", type=_positive, default=_GIVEN, metavar="H", help="layers: layer height (mm)")
    t.add_argument("--no-svg", dest="svg", action="store_false", default=_GIVEN, help="layers: layers.json only")
    t.add_argument("--planes", type=int, default=_GIVEN, metavar="N", help="profile: planes through the axis")
    t.add_argument("--side", choices=("left", "right"), default=_GIVEN, help="profile: side of the section")
    t.add_argument("--no-png", dest="png", action="store_false", default=_GIVEN, help="profile: no PNG")
    t.add_argument("--no-preview", dest="preview", action="store_false", default=_GIVEN,
                   help="split: no preview.png")
    t.add_argument("--max-gap", type=float, default=_GIVEN, metavar="MM", help="join open chains this close")
    t.add_argument("--min-size", type=float, default=_GIVEN, metavar="MM",
                   help="flag parts smaller than this as implausible (default 2 mm)")
    t.add_argument("--max-size", type=float, default=_GIVEN, metavar="MM",
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
    options = {n: getattr(args, n) for n in ("min_size", "max_size") if hasattr(args, n)}
    plane = _plane(args, required=False)
    if plane is not None:
        options["origin"], options["normal"] = plane
    # Every task option given goes to the task, which refuses the ones it does not take.
    options.update({n: getattr(args, n) for task in TASKS for n in JOBS[task].defaults if hasattr(args, n)})
    options.update({n: getattr(args, n) for n in ("units", "scale") if getattr(args, n, None) is not None})
    params = task_parameters(args.task, **options)
    from .tasks.executors import NoWorkersLeft
    try:
        result = run_batch(args.folder, args.output, args.task, params, workers=args.workers,
                           scheduler=args.scheduler, force=args.force, retry_failed=args.retry_failed,
                           progress=False if args.no_progress else None, exclude=args.exclude)
    except NoWorkersLeft as exc:
        print(f"slicelab: error: {exc}", file=sys.stderr)
        return 1
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
    _no_preview(p, "exploded.png")
    _repair_flag(p)


def _run_cut(args) -> int:
    r = run_job("cut", args.file, _options(args, "cut", plane=_plane(args)), args.output)
    _say_repair(r)
    print(f"{args.file}: {r.n_facets} facets; {r.value[2].report.describe()}")
    for name in ("rear", "front"):
        part = r.results.get(name)
        if part is None:
            print(f"{name}.stl: not written (the plane leaves nothing on that side)")
            continue
        print(f"{name}.stl: {part['facets']} facets, volume {part['volume']:.6g} mm3, "
              f"{'watertight' if part['watertight'] else 'NOT watertight'} as written")
    print(f"{_timings(r, 'cut')}; wrote {args.output}/")
    _warn(r)
    if not all(r.results[n]["watertight"] for n in ("rear", "front") if n in r.results):
        print("slicelab: error: the parts are not watertight as written", file=sys.stderr)
        return 1
    return 0


# ------------------------------------------------------------------- partition
def _add_partition(sub) -> None:
    p = sub.add_parser("partition", help="cut a solid into pieces that fit a printer's build volume",
                       description="Cut FILE recursively until every piece fits the build volume; write "
                                   "DIR/part_NNN.stl, DIR/parts.json (sizes, turns, glue areas) and "
                                   "DIR/exploded.png.")
    p.add_argument("file", type=Path, metavar="FILE")
    p.add_argument("--volume", type=_volume, required=True, metavar="XxYxZ",
                   help="build volume in mm, e.g. 200x200x200")
    p.add_argument("--joint", choices=("flat", "stair"), default=_GIVEN,
                   help="flat cuts (default), or interlocking stair joints with at least twice the glue area")
    p.add_argument("--clearance", type=float, default=_GIVEN, metavar="MM", help="glue gap (default 0)")
    p.add_argument("--step", type=_pair, default=_GIVEN, metavar="H,D",
                   help="stair step height and depth in mm (default 10,20)")
    p.add_argument("--flight", type=int, default=_GIVEN, metavar="N",
                   help="stair steps up before stepping down (default 1: castellated)")
    p.add_argument("--no-rotate", dest="rotate", action="store_false", default=_GIVEN,
                   help="do not turn pieces about z to fit")
    p.add_argument("-o", "--output", type=Path, required=True, metavar="DIR")
    p.add_argument("--plates", action="store_true", default=_GIVEN,
                   help="also pack the pieces onto as few build plates as they fit: DIR/plate_NN.stl, "
                        "DIR/plates.json, DIR/plate_NN.png")
    p.add_argument("--spacing", type=float, default=_GIVEN, metavar="MM",
                   help="gap between pieces on a plate (default 5 mm)")
    _no_preview(p, "exploded.png")
    _repair_flag(p)


def _say_plates(res: dict) -> None:
    print(f"plates: {res['pieces']} pieces on {res['plates_used']} plates (one per plate: {res['one_per_plate']}; "
          f"at least {res['lower_bound']} by area); "
          + ", ".join(f"plate {k + 1} {100 * f:.0f} % covered" for k, f in enumerate(res["fill"])))


def _add_arrange(sub) -> None:
    p = sub.add_parser("arrange", help="pack pieces onto as few build plates as they fit",
                       description="Lay each piece (one per file) on its largest flat face that fits, turn "
                                   "it about z and pack the pieces onto build plates; write DIR/plate_NN.stl "
                                   "(the pieces in place: slice it as one print), DIR/plates.json (placements) "
                                   "and a top view DIR/plate_NN.png of each plate.")
    p.add_argument("files", type=Path, nargs="+", metavar="PART")
    p.add_argument("--volume", type=_volume, required=True, metavar="XxYxZ", help="build volume in mm")
    p.add_argument("--spacing", type=float, default=5.0, metavar="MM", help="gap between pieces (default 5 mm)")
    p.add_argument("--no-rotate", dest="rotate", action="store_false", help="do not turn pieces about z")
    p.add_argument("-o", "--output", type=Path, required=True, metavar="DIR")
    p.add_argument("--no-preview", dest="preview", action="store_false", help="do not draw plate_NN.png")


def _run_arrange(args) -> int:
    from .tasks.jobs import check_output_dir
    from .tasks.plates import arrange_files
    check_output_dir(args.output)
    if not (args.spacing >= 0):
        raise UsageError("--spacing must be >= 0")
    res, why = arrange_files(args.files, args.volume, args.output, spacing=args.spacing, rotate=args.rotate,
                             preview=args.preview, units=args.units, scale=args.scale)
    _say_plates(res)
    print(f"wrote {args.output}/")
    for w in why:
        print(f"slicelab: warning: {w['message']}", file=sys.stderr)
    return 0


def _run_partition(args) -> int:
    r = run_job("partition", args.file, _options(args, "partition"), args.output)
    _say_repair(r)
    print(f"{args.file}: {r.n_facets} facets")
    written = [w["watertight"] for w in r.results["written"].values()]
    if "plates" in r.results:
        _say_plates(r.results["plates"])
    print(r.value.report.describe(watertight=written))
    print(f"{_timings(r, 'partition')}; wrote {args.output}/ (pieces placed for printing; "
          f"watertight as read back from the files)")
    if not r.results["watertight"]:
        for why in r.reasons:
            print(f"slicelab: warning: {why['message']}", file=sys.stderr)
        print(f"slicelab: error: {written.count(False)} of {len(written)} pieces are not watertight as written",
              file=sys.stderr)
        return 1
    return 0


# ----------------------------------------------------------------------- slice
def _add_slice(sub) -> None:
    p = sub.add_parser("slice", help="slice a part into printer G-code (perimeters, skins, infill)",
                       description="Plan every layer of FILE (perimeters, solid top and bottom skins, "
                                   "sparse infill) on all cores and write Marlin G-code. Settings left "
                                   "out take slicelab.toolpath.PrintSettings' defaults.")
    p.add_argument("file", type=Path, metavar="FILE")
    p.add_argument("-o", "--output", type=Path, required=True, metavar="OUT.gcode")
    p.add_argument("--layer-height", type=_positive, default=_GIVEN, metavar="H", help="(default 0.2 mm)")
    p.add_argument("--first-layer-height", type=_positive, default=_GIVEN, metavar="H",
                   help="default: the layer height")
    p.add_argument("--perimeters", dest="n_perimeters", type=int, default=_GIVEN, metavar="N",
                   help="perimeters around every island (default 2)")
    p.add_argument("--infill-density", type=_density, default=_GIVEN, metavar="D",
                   help="sparse infill density: 20 or 20%% is a percentage, a bare number up to 1 a "
                        "fraction (0.2); default 20%%")
    p.add_argument("--infill-pattern", choices=("rectilinear", "concentric", "gyroid"), default=_GIVEN)
    for flag, kind, meta in (("--line-width", _positive, "W"), ("--infill-angle", float, "DEG"),
                             ("--top-layers", int, "N"), ("--bottom-layers", int, "N"),
                             ("--pixel-size", _positive, "MM"), ("--gcode-resolution", float, "MM"),
                             ("--nozzle-temperature", float, "C"), ("--bed-temperature", float, "C"),
                             ("--fan-speed", float, "PCT"), ("--fan-off-layers", int, "N"), ("--skirt-loops", int, "N"),
                             ("--skirt-distance", float, "MM"), ("--brim-width", float, "MM"),
                             ("--bed-size", str, "XxY"), ("--max-height", float, "MM"),
                             ("--acceleration", float, "MM/S2"), ("--jerk", float, "MM/S")):
        p.add_argument(flag, type=kind, default=_GIVEN, metavar=meta)
    p.add_argument("--workers", type=int, default=_GIVEN, metavar="N", help="processes (default: all cores)")
    p.add_argument("--preview", dest="preview_dir", type=Path, default=None, metavar="DIR",
                   help="also write DIR/layer_*.svg and DIR/preview.png")
    _repair_flag(p)


def _run_slice(args) -> int:
    params = _options(args, "slice", preview=args.preview_dir is not None)
    r = run_job("slice", args.file, params, args.preview_dir, paths={"gcode": args.output})
    s = r.results
    _say_repair(r)
    print(f"{args.file}: {r.n_facets} facets; {s['layers']} layers, print {s['print_length'] / 1000:.1f} m, "
          f"filament {s['filament_length'] / 1000:.2f} m ({s['extruded_volume'] / 1000:.2f} cm3)")
    t = r.timings
    print(f"load {t['load']:.2f} s, plan {t['compute']:.2f} s, write {t['write']:.2f} s; wrote {args.output}"
          + (f" and {args.preview_dir}/" if args.preview_dir is not None else ""))
    return 0


COMMANDS = ["inspect", "section", "layers", "split", "profile", "batch", "cut", "partition", "arrange", "slice"]


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
    for p in sub.choices.values():  # every command reads mesh files: their units
        g = p.add_argument_group("units of the input")
        g.add_argument("--units", choices=tuple(UNITS), default=None,
                       help="the unit the file is written in (default mm); coordinates are scaled to mm")
        g.add_argument("--scale", type=_positive, default=None, metavar="F",
                       help="a further factor for the coordinates")
    return parser


def _flag_message(exc: ParameterError) -> str:
    """A parameter's error in the words of the command line (``--max-gap must be ...``)."""
    return f"{_FLAGS.get(exc.name, '--' + exc.name.replace('_', '-'))} {exc.problem}"


def main(argv=None) -> int:
    """Run the command line; return the exit status.

    Examples
    --------
    >>> main(["--version"])  # doctest: +SKIP
    slicelab 0.1.0
    """
    parser = build_parser()
    args = parser.parse_args(_negative_values(list(sys.argv[1:] if argv is None else argv)))
    try:
        return int(globals()[f"_run_{args.command.replace('-', '_')}"](args) or 0)
    except ParameterError as exc:
        print(f"slicelab: error: {_flag_message(exc)}", file=sys.stderr)
        return 2
    except (MeshFileError, UsageError) as exc:
        print(f"slicelab: error: {exc}", file=sys.stderr)
        return 2
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


if __name__ == "__main__":  # pragma: no cover
    raise SystemExit(main())
