"""The commands that make printable things: cut, partition, arrange, slice."""
from __future__ import annotations

import argparse
import sys
from pathlib import Path

from ..tasks.jobs import run_job
from .arguments import (
    command,
    GIVEN, UsageError, add_plane_arguments, density, no_preview, options, pair, plane, point, positive,
    repair_flag, say_plates, say_repair, timings, volume, warn,
)

__all__ = ["COMMANDS", "DOCS"]

#: Each command's one-line help and description (``slicelab COMMAND --help``).
DOCS = {
    "cut": {
        "help": 'cut a solid by a plane into two closed, capped parts',
        "description": 'Cut FILE with a plane into two watertight parts, each capped on the plane with a '
                       'constrained Delaunay triangulation; write DIR/rear.stl (the side against the normal), '
                       'DIR/front.stl and DIR/exploded.png. An input that is not a closed solid, or parts that '
                       'would not be watertight, are refused before anything is written.',
    },
    "partition": {
        "help": "cut a solid into pieces that fit a printer's build volume",
        "description": 'Cut FILE recursively until every piece fits the build volume; write DIR/part_NNN.stl, '
                       'DIR/parts.json (sizes, turns, glue areas) and DIR/exploded.png.',
    },
    "arrange": {
        "help": 'pack pieces onto as few build plates as they fit',
        "description": 'Lay each piece (one per file) on its largest flat face that fits, turn it about z and pack '
                       'the pieces onto build plates; write DIR/plate_NN.stl (the pieces in place: slice it as one '
                       'print), DIR/plates.json (placements) and a top view DIR/plate_NN.png of each plate.',
    },
    "slice": {
        "help": 'slice a part into printer G-code (perimeters, skins, infill)',
        "description": 'Plan every layer of FILE (perimeters, solid top and bottom skins, bridges, sparse infill, '
                       'supports with --support) on all cores and write Marlin G-code; overhangs left unheld and '
                       "islands starting in mid-air are named in a warning. Settings left out take the printer "
                       "profile's, the settings file's, then slicelab.printing.PrintSettings' defaults.",
    },
}


def _add_cut(sub) -> None:
    p = command(sub, "cut", DOCS)
    add_plane_arguments(p)
    p.add_argument("-o", "--output", type=Path, required=True, metavar="DIR")
    no_preview(p, "exploded.png")
    repair_flag(p)


def _run_cut(args) -> int:
    r = run_job("cut", args.file, options(args, "cut", plane=plane(args)), args.output)
    say_repair(r)
    print(f"{args.file}: {r.n_facets} facets; {r.value[2].report.describe()}")
    for name in ("rear", "front"):
        part = r.results.get(name)
        if part is None:
            print(f"{name}.stl: not written (the plane leaves nothing on that side)")
            continue
        print(f"{name}.stl: {part['facets']} facets, volume {part['volume']:.6g} mm3, "
              f"{'watertight' if part['watertight'] else 'NOT watertight'} as written")
    print(f"{timings(r, 'cut')}; wrote {args.output}/")
    warn(r)
    return 0


def _add_partition(sub) -> None:
    p = command(sub, "partition", DOCS)
    p.add_argument("--volume", type=volume, required=True, metavar="XxYxZ",
                   help="build volume in mm, e.g. 200x200x200")
    p.add_argument("--joint", choices=("flat", "stair"), default=GIVEN,
                   help="flat cuts (default), or interlocking stair joints with at least twice the glue area")
    p.add_argument("--clearance", type=float, default=GIVEN, metavar="MM", help="glue gap (default 0)")
    p.add_argument("--step", type=pair, default=GIVEN, metavar="H,D",
                   help="stair step height and depth in mm (default 10,20)")
    p.add_argument("--flight", type=int, default=GIVEN, metavar="N",
                   help="stair steps up before stepping down (default 1: castellated)")
    p.add_argument("--no-rotate", dest="rotate", action="store_false", default=GIVEN,
                   help="do not turn pieces about z to fit")
    p.add_argument("-o", "--output", type=Path, required=True, metavar="DIR")
    p.add_argument("--plates", action="store_true", default=GIVEN,
                   help="also pack the pieces onto as few build plates as they fit: DIR/plate_NN.stl, "
                        "DIR/plates.json, DIR/plate_NN.png")
    p.add_argument("--spacing", type=float, default=GIVEN, metavar="MM",
                   help="gap between pieces on a plate (default 5 mm)")
    no_preview(p, "exploded.png")
    repair_flag(p)


def _run_partition(args) -> int:
    r = run_job("partition", args.file, options(args, "partition"), args.output)
    say_repair(r)
    print(f"{args.file}: {r.n_facets} facets")
    written = [w["watertight"] for w in r.results["written"].values()]
    if "plates" in r.results:
        say_plates(r.results["plates"])
    print(r.value.report.describe(watertight=written))
    print(f"{timings(r, 'partition')}; wrote {args.output}/ (pieces placed for printing; "
          f"watertight as read back from the files)")
    warn(r)
    return 0


def _add_arrange(sub) -> None:
    p = command(sub, "arrange", DOCS, file=False)
    p.add_argument("files", type=Path, nargs="+", metavar="PART")
    p.add_argument("--volume", type=volume, required=True, metavar="XxYxZ", help="build volume in mm")
    p.add_argument("--spacing", type=float, default=5.0, metavar="MM", help="gap between pieces (default 5 mm)")
    p.add_argument("--no-rotate", dest="rotate", action="store_false", help="do not turn pieces about z")
    p.add_argument("-o", "--output", type=Path, required=True, metavar="DIR")
    p.add_argument("--no-preview", dest="preview", action="store_false", help="do not draw plate_NN.png")


def _run_arrange(args) -> int:
    from ..tasks.jobs import check_output_dir
    from ..tasks.plates import arrange_files
    check_output_dir(args.output)
    if not (args.spacing >= 0):
        raise UsageError("--spacing must be >= 0")
    res, why = arrange_files(args.files, args.volume, args.output, spacing=args.spacing, rotate=args.rotate,
                             preview=args.preview, units=args.units, scale=args.scale)
    say_plates(res)
    print(f"wrote {args.output}/")
    for w in why:
        print(f"slicelab: warning: {w['message']}", file=sys.stderr)
    return 0


class _Default:
    """A print setting's default, said in its flag's help (``%(setting_default)s``): read from
    `slicelab.printing.PrintSettings` (the prusa-mk3 profile's values) only when help is shown,
    so that building the parser, as every command does, imports no settings."""

    def __init__(self, name: str):
        self.name = name

    def __str__(self) -> str:
        from ..printing.config.settings import PrintSettings
        value = getattr(PrintSettings(), self.name)
        if isinstance(value, tuple):
            return "x".join(f"{v:g}" for v in value)
        return value if isinstance(value, str) else f"{value:g}"


def _add_slice(sub) -> None:
    p = command(sub, "slice", DOCS, file=False)
    p.add_argument("files", type=Path, nargs="*", metavar="FILE",
                   help="the part; several are put side by side on the bed, upright as given, and print together")
    p.add_argument("-o", "--output", type=Path, metavar="OUT.gcode", help="the G-code file (required unless "
                                                                          "--print-config)")
    p.add_argument("--layer-height", type=positive, default=GIVEN, metavar="H", help="(default 0.2 mm)")
    p.add_argument("--first-layer-height", type=positive, default=GIVEN, metavar="H",
                   help="default: the layer height")
    p.add_argument("--perimeters", dest="n_perimeters", type=int, default=GIVEN, metavar="N",
                   help="perimeters around every island (default 2)")
    p.add_argument("--infill-density", type=density, default=GIVEN, metavar="D",
                   help="sparse infill density: 20 or 20%% is a percentage, a bare number up to 1 a "
                        "fraction (0.2); default 20%%")
    pattern = p.add_argument("--infill-pattern", choices=("rectilinear", "concentric", "gyroid"), default=GIVEN,
                             help="sparse infill pattern (default %(setting_default)s)")
    pattern.setting_default = _Default("infill_pattern")
    for flag, kind, meta, what in (
            ("--line-width", positive, "W", "extrusion width of every line, mm"),
            ("--infill-angle", float, "DEG", "direction of the infill lines, turned 90 degrees every layer"),
            ("--top-layers", int, "N", "solid layers under every top surface"),
            ("--bottom-layers", int, "N", "solid layers over every bottom surface"),
            ("--pixel-size", positive, "MM", "pixel grid of the layers (skins, gaps, overhangs; the perimeters "
                                            "lie on the exact offsets whatever its size)"),
            ("--gcode-resolution", float, "MM", "every path simplified to this tolerance"),
            ("--nozzle-temperature", float, "C", "degrees Celsius"),
            ("--bed-temperature", float, "C", "degrees Celsius"),
            ("--fan-speed", float, "PCT", "part-cooling fan, percent, after the first layers"),
            ("--fan-off-layers", int, "N", "first layers printed with the fan off"),
            ("--skirt-loops", int, "N", "loops around the first layer; 0: no skirt"),
            ("--skirt-distance", float, "MM", "gap between the skirt and the part"),
            ("--brim-width", float, "MM", "brim around the first layer; 0: none"),
            ("--bed-size", str, "XxY", "the bed, mm; a part that does not fit is refused"),
            ("--max-height", float, "MM", "the printer's build height; a taller part is refused"),
            ("--acceleration", float, "MM/S2", "for the print-time estimate"),
            ("--jerk", float, "MM/S", "for the print-time estimate"),
            ("--overhang-threshold", float, "DEG", "steepest wall, from the vertical, that holds itself"),
            ("--bridge-speed", positive, "MM/S", "speed of bridge lines"),
            ("--bridge-flow-ratio", positive, "R", "flow of bridge lines, against other lines'"),
            ("--min-layer-time", float, "S", "a quicker layer is slowed to last this long"),
            ("--fan-below-layer-time", float, "S", "a layer quicker than this gets more fan"),
            ("--min-print-speed", positive, "MM/S", "the slowest a layer is slowed to"),
            ("--nozzle-diameter", positive, "MM", "the nozzle's bore")):
        action = p.add_argument(flag, type=kind, default=GIVEN, metavar=meta,
                                help=f"{what} (default %(setting_default)s)")
        action.setting_default = _Default(flag[2:].replace("-", "_"))
    p.add_argument("--center", dest="bed_center", type=point, default=GIVEN, metavar="X,Y",
                   help="where the part's footprint is centred on the bed (default: the bed's middle)")
    p.add_argument("--support", choices=("off", "auto", "bed"), default=GIVEN,
                   help="support material under overhangs and mid-air islands: off (default; they are "
                        "reported), auto (standing on the bed or the part), bed (only where they reach the bed)")
    p.add_argument("--dont-support-bridges", action=argparse.BooleanOptionalAction, default=GIVEN,
                   help="bridge what the layer below holds on one side only, supporting only a band along its "
                        "outline, as PrusaSlicer does (default); --no-dont-support-bridges supports it whole")
    p.add_argument("--support-sheath", action=argparse.BooleanOptionalAction, default=GIVEN,
                   help="a loop around each region of sparse support (default), as PrusaSlicer does")
    p.add_argument("--seam-position", choices=("aligned", "rear", "nearest"), default=GIVEN,
                   help="where perimeter loops start: aligned with the layer below (default), at the rear, or "
                        "nearest the nozzle")
    p.add_argument("--external-perimeters-first", action="store_const", const=True, default=GIVEN,
                   help="print each island's outer perimeter before the inner ones (default: last)")
    g = p.add_argument_group("printer and settings files")
    g.add_argument("--printer", default=GIVEN, metavar="NAME",
                   help="a bundled printer profile: prusa-mk3 (default values), generic-marlin-220, "
                        "generic-klipper-300")
    g.add_argument("--config", type=Path, default=GIVEN, metavar="FILE.toml",
                   help="settings file: printer = NAME and a table per group ([extrusion], [infill], ..., as "
                        "--print-config writes them) or one [settings] table; the flags given here override it")
    g.add_argument("--print-config", action="store_true",
                   help="print the settings in force (as a settings file) and stop")
    p.add_argument("--workers", type=int, default=GIVEN, metavar="N", help="processes (default: all cores)")
    p.add_argument("--preview", dest="preview_dir", type=Path, default=None, metavar="DIR",
                   help="also write DIR/layer_*.svg and DIR/preview.png")
    repair_flag(p, default=True)


def _run_slice(args) -> int:
    params = options(args, "slice", preview=args.preview_dir is not None)
    if not args.print_config and (not args.files or args.output is None):
        raise UsageError("slice needs a FILE and -o OUT.gcode (see slicelab slice --help)")
    if args.print_config:
        from ..tasks.fabrication import slice_settings
        from ..tasks.jobs import job_parameters
        from ..printing.config.printers import format_config
        print(format_config(slice_settings(job_parameters("slice", **params))), end="")
        return 0
    mesh, name = None, args.files[0]
    if len(args.files) > 1:
        mesh, name = _on_one_bed(args, params), f"{len(args.files)} parts on one bed"
    r = run_job("slice", args.files[0], params, args.preview_dir, paths={"gcode": args.output}, mesh=mesh)
    s = r.results
    say_repair(r)
    warn(r)
    print(f"{name}: {r.n_facets} facets; {s['layers']} layers, print {s['print_length'] / 1000:.1f} m, "
          f"filament {s['filament_length'] / 1000:.2f} m ({s['extruded_volume'] / 1000:.2f} cm3)")
    t = r.timings
    print(f"load {t.get('load', 0.0):.2f} s, plan {t['compute']:.2f} s, write {t['write']:.2f} s; wrote {args.output}"
          + (f" and {args.preview_dir}/" if args.preview_dir is not None else ""))
    return 0



def _on_one_bed(args, params):
    """The parts of several files side by side on the printer's bed, upright as given: one mesh."""
    from .. import load
    from ..slicing.plates import arrange
    from ..tasks.fabrication import slice_settings
    from ..tasks.jobs import job_parameters
    s = slice_settings(job_parameters("slice", **{k: v for k, v in params.items() if k not in ("units", "scale")}))
    reading = {k: params[k] for k in ("units", "scale") if params.get(k) is not None}
    parts = [load(f, **reading) for f in args.files]
    spacing = max(5.0, 2 * s.line_width * max(1, s.n_perimeters))
    try:
        plates = arrange(parts, (*s.bed_size, s.max_height), spacing=spacing, stand=False)
    except ValueError as exc:  # a part larger than the bed
        raise UsageError(f"{exc} (the bed, --bed-size / --max-height)") from None
    if len(plates) > 1:
        raise UsageError(f"the {len(parts)} parts need {len(plates)} beds of {s.bed_size[0]:g} x {s.bed_size[1]:g} mm "
                         f"side by side: slice fewer at a time, or pack them with `slicelab arrange`")
    return plates.plate_mesh(0, parts)


#: Each command's (declare arguments, run) functions.
COMMANDS = {
    "cut": (_add_cut, _run_cut),
    "partition": (_add_partition, _run_partition),
    "arrange": (_add_arrange, _run_arrange),
    "slice": (_add_slice, _run_slice),
}
