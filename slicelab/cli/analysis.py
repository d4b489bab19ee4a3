"""The commands that analyse a mesh: inspect, section, layers, split, profile, batch."""
from __future__ import annotations

import json
import sys
from pathlib import Path

from ..mesh.io import MeshFileError
from ..tasks.jobs import JOBS, TASKS, run_job
from .arguments import (
    finish,
    command,
    GIVEN, UsageError, add_plane_arguments, default, max_gap, no_preview, options, plane, positive,
    say_repair, vector, warn,
)

__all__ = ["COMMANDS", "DOCS"]

#: Each command's one-line help and description (``slicelab COMMAND --help``).
DOCS = {
    "inspect": {
        "help": 'load STL files and report their defects',
        "description": 'Load each STL file and print its mesh report.',
    },
    "section": {
        "help": 'cut a mesh with one plane and draw the section as SVG',
        "description": 'Cut FILE with a plane; write the section as a true-scale SVG (mm).',
    },
    "layers": {
        "help": 'slice a mesh into horizontal layers (SVG per layer + JSON)',
        "description": 'Slice FILE at mid-layer heights; write one SVG per layer and layers.json with every loop.',
    },
    "split": {
        "help": 'split a mesh by a plane into front, section and rear',
        "description": 'Cut FILE with a plane into the part in front (the side the normal points to) and the part '
                       'behind; write DIR/front.stl, DIR/rear.stl (each when not empty), DIR/section.svg and '
                       'DIR/preview.png.',
    },
    "profile": {
        "help": 'align a scanned vessel and draw its profile with measurements',
        "description": 'Align FILE on its axis of revolution, cut it through the axis at --planes angles, write '
                       'the archaeological profile drawing (SVG, 1:1 in mm; also PNG, and DXF for CAD with a layer '
                       'per surface, breaks and the axis) and the outline points (CSV), and print the '
                       'measurements.',
    },
    "batch": {
        "help": 'run one task over every mesh file (STL, PLY, OBJ, 3MF) under a folder (resumable)',
        "description": 'Run --task on every .stl, .ply, .obj and .3mf file under DIR (any case): one JSON report '
                       'per file (input SHA-256, parameters, outputs, timings, status ok/warn/fail and reasons) in '
                       'OUT, the outputs in a folder named after the file, extension kept (OUT/pot.stl/ beside '
                       'OUT/pot.stl.json; the same file names as the command of the same name writes; names that '
                       'would clash, even by case only, get a suffix ~2), and OUT/summary.csv. A file that is not '
                       'a regular file (a named pipe, a device) is reported, never read. Files whose report is up '
                       'to date are skipped. Every number in summary.csv has its unit in its column name; for '
                       '--task profile it is an EVE table (kind, span, rim EVE, rim diameter and its uncertainty, '
                       'axis trusted, up from) with a rim-diameter chart weighted by rim EVE beside it '
                       '(rim_diameters.png, its numbers in rim_diameters.csv). Runs on local processes, or on a '
                       "Dask cluster given --scheduler (pip install 'slicelab[cluster]'); the numbers are the same "
                       'on either, whatever the thread count.',
    },
}


def _add_inspect(sub) -> None:
    p = command(sub, "inspect", DOCS, file=False)
    p.add_argument("files", nargs="+", type=Path, metavar="FILE")
    p.add_argument("--json", action="store_true", help="print one JSON object per file")


def _run_inspect(args) -> int:
    status = 0
    for path in args.files:
        try:
            r = run_job("inspect", path, options(args, "inspect"))
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
            warn(r)
    return status


def _add_section(sub) -> None:
    p = command(sub, "section", DOCS)
    add_plane_arguments(p)
    p.add_argument("-o", "--output", type=Path, required=True, metavar="OUT.svg")
    max_gap(p, "section")


def _run_section(args) -> int:
    r = run_job("section", args.file, options(args, "section", plane=plane(args)), paths={"svg": args.output})
    s = r.results
    print(f"{args.file}: {r.n_facets} facets; section: {s['segments']} segments, {s['loops']} loops "
          f"({s['holes']} holes), {s['open_chains']} open chains, {s['joined_gaps']} gaps joined, "
          f"area {s['area']:.6g} mm2")
    return finish(r, 'section', f"; wrote {args.output}")


def _add_layers(sub) -> None:
    p = command(sub, "layers", DOCS)
    p.add_argument("--layer-height", type=positive, required=True, metavar="H")
    p.add_argument("-o", "--output", type=Path, required=True, metavar="DIR")
    max_gap(p, "layers")
    p.add_argument("--no-svg", dest="svg", action="store_false", default=GIVEN, help="layers.json only")


def _run_layers(args) -> int:
    r = run_job("layers", args.file, options(args, "layers"), args.output)
    s = r.results
    say_repair(r)
    print(f"{args.file}: {r.n_facets} facets; {s['layers']} layers, {s['loops']} loops, "
          f"{s['open_chains']} open chains")
    return finish(r, 'slice', f"; wrote {args.output}/")


def _add_split(sub) -> None:
    p = command(sub, "split", DOCS)
    add_plane_arguments(p)
    p.add_argument("-o", "--output", type=Path, required=True, metavar="DIR")
    p.add_argument("--visible-from", type=vector, default=GIVEN, metavar="X,Y,Z",
                   help="keep only the facets facing a viewer in this direction (as for a drawing)")
    max_gap(p, "split", "section chains")
    no_preview(p)


def _run_split(args) -> int:
    r = run_job("split", args.file, options(args, "split", plane=plane(args)), args.output)
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
    return finish(r, 'split', f"; total {sum(r.timings.values()):.2f} s; wrote {args.output}/")


def _add_profile(sub) -> None:
    p = command(sub, "profile", DOCS)
    p.add_argument("-o", "--output", type=Path, required=True, metavar="OUT.svg")
    p.add_argument("--png", dest="png_path", type=Path, metavar="OUT.png", help="also write the drawing as a PNG")
    p.add_argument("--json", dest="json_path", type=Path, metavar="OUT.json",
                   help="also write measurements and outlines as JSON")
    p.add_argument("--dxf", dest="dxf_path", type=Path, metavar="OUT.dxf",
                   help="also write the section as DXF (mm, in the (r, z) plane; layers SECTION, EXTERIOR, "
                        "INTERIOR, RIM, BREAKS, AXIS, APPENDAGE...)")
    p.add_argument("--csv", dest="csv_path", type=Path, metavar="OUT.csv",
                   help="also write every half-section's outline points as CSV (r_mm, z_mm, surface)")
    p.add_argument("--planes", type=int, default=GIVEN, metavar="N",
                   help=f"planes through the axis (default {default('profile', 'planes')})")
    p.add_argument("--side", choices=("left", "right"), default=GIVEN,
                   help="side of the axis for the section (default left; the exterior goes opposite)")
    p.add_argument("--spread", action="store_true", default=GIVEN,
                   help="draw every other half-section in grey")
    p.add_argument("--no-align", dest="align", action="store_false", default=GIVEN,
                   help="the mesh is already aligned (axis +z, base z=0)")
    max_gap(p, "profile", "section chains")


def _run_profile(args) -> int:
    params = options(args, "profile", png=args.png_path is not None, json=args.json_path is not None,
                     dxf=args.dxf_path is not None, csv=args.csv_path is not None)
    r = run_job("profile", args.file, params,
                paths={"svg": args.output, "png": args.png_path, "json": args.json_path, "dxf": args.dxf_path,
                       "csv": args.csv_path})
    p = r.value
    if p.alignment is not None:
        print(f"{args.file}: {r.n_facets} facets; {p.alignment!r}")
    if p.sherd is not None:
        print(p.sherd.sentence())
    print(p.measurements)
    t = r.timings
    written = ", ".join(str(x) for x in (args.output, args.png_path, args.json_path, args.dxf_path, args.csv_path)
                        if x is not None)
    print(f"load {t['load']:.2f} s, align + profile {t['compute']:.2f} s, drawing {t['write']:.2f} s; "
          f"wrote {written}")
    warn(r)
    return 0


_TIMEOUT = 900.0  # seconds per file: generous, so that only a stuck file meets it

_BATCH_OPTIONS = [
    ("--layer-height", dict(type=positive, metavar="H", help="layers: layer height (mm)")),
    ("--no-svg", dict(dest="svg", action="store_false", help="layers: layers.json only")),
    ("--planes", dict(type=int, metavar="N", help="profile: planes through the axis")),
    ("--side", dict(choices=("left", "right"), help="profile: side of the section")),
    ("--no-png", dict(dest="png", action="store_false", help="profile: no PNG")),
    ("--no-dxf", dict(dest="dxf", action="store_false", help="profile: no DXF")),
    ("--no-csv", dict(dest="csv", action="store_false", help="profile: no CSV of the outline points")),
    ("--no-preview", dict(dest="preview", action="store_false", help="split: no preview.png")),
    ("--max-gap", dict(type=float, metavar="MM", help="join open chains this close")),
    ("--min-size", dict(type=float, metavar="MM", help="flag parts smaller than this as implausible (default 2 mm)")),
    ("--max-size", dict(type=float, metavar="MM",
                        help="flag parts larger than this as implausible (default 5000 mm)")),
]


def _add_batch(sub) -> None:
    p = command(sub, "batch", DOCS, file=False)
    p.add_argument("folder", type=Path, metavar="DIR")
    p.add_argument("-o", "--output", type=Path, required=True, metavar="OUT")
    p.add_argument("--task", choices=TASKS, required=True)
    add_plane_arguments(p)
    t = p.add_argument_group("task options (defaults as for the command of the same name)")
    for flag, kw in _BATCH_OPTIONS:  # a table: every task option, with the task it is for
        t.add_argument(flag, default=GIVEN, **kw)
    r = p.add_argument_group("running")
    r.add_argument("--workers", type=int, metavar="N",
                   help="local processes (default: CPU count; 1: one worker process, or with --timeout 0 this "
                        "process)")
    r.add_argument("--timeout", type=float, default=_TIMEOUT, metavar="SECONDS",
                   help=f"time limit per file (default {_TIMEOUT:g} s; 0: none): a file past it fails with the "
                        f"reason timeout and the batch goes on; its local worker process is killed, a Dask task "
                        f"cancelled (its worker may still finish it)")
    r.add_argument("--scheduler", metavar="ADDRESS", help="Dask scheduler, e.g. tcp://host:8786")
    r.add_argument("--force", action="store_true", help="rerun files whose report is up to date")
    r.add_argument("--retry-failed", action="store_true", help="rerun files whose report says fail")
    r.add_argument("--no-progress", action="store_true", help="no progress bar")
    r.add_argument("--exclude", action="append", default=[], metavar="GLOB",
                   help="leave out paths under DIR matching this pattern (repeatable), e.g. 'large/*'")


def _run_batch(args) -> int:
    from ..tasks.batch import run_batch, task_parameters
    if not args.folder.is_dir():
        raise UsageError(f"{args.folder}: not a folder")
    if args.workers is not None and args.workers < 1:
        raise UsageError("--workers must be at least 1")
    if not args.timeout >= 0:
        raise UsageError(f"--timeout must be a number of seconds, 0 for no limit; got {args.timeout:g}")
    options = {n: getattr(args, n) for n in ("min_size", "max_size") if hasattr(args, n)}
    given = plane(args, required=False)
    if given is not None:
        options["origin"], options["normal"] = given
    # Every task option given goes to the task, which refuses the ones it does not take.
    options.update({n: getattr(args, n) for task in TASKS for n in JOBS[task].defaults if hasattr(args, n)})
    options.update({n: getattr(args, n) for n in ("units", "scale") if getattr(args, n, None) is not None})
    params = task_parameters(args.task, **options)
    from ..tasks.executors import NoWorkersLeft
    try:
        result = run_batch(args.folder, args.output, args.task, params, workers=args.workers,
                           scheduler=args.scheduler, force=args.force, retry_failed=args.retry_failed,
                           progress=False if args.no_progress else None, exclude=args.exclude,
                           timeout=None if args.timeout in (0, float("inf")) else args.timeout)
    except NoWorkersLeft as exc:
        print(f"slicelab: error: {exc}", file=sys.stderr)
        return 1
    print(result)
    for rep in result.reports:
        if rep["status"] != "ok":
            print(f"  {rep['status']:<4} {rep['file']}: {'; '.join(r['message'] for r in rep['reasons'])}")
    print(f"wrote {', '.join(str(x) for x in (result.summary, *result.files.values()))}")
    return 1 if result.count("fail") else 0



#: Each command's (declare arguments, run) functions.
COMMANDS = {
    "inspect": (_add_inspect, _run_inspect),
    "section": (_add_section, _run_section),
    "layers": (_add_layers, _run_layers),
    "split": (_add_split, _run_split),
    "profile": (_add_profile, _run_profile),
    "batch": (_add_batch, _run_batch),
}
