"""The commands that make printable things: cut, partition, arrange, slice."""
from __future__ import annotations

import argparse
import sys
from pathlib import Path

from ..tasks.jobs import run_job
from .arguments import (
    command,
    GIVEN, LazyChoices, UsageError, add_plane_arguments, density, no_preview, number, options, pair, plane, point,
    whole_number,
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


#: A setting's flag where it is not ``--name-with-dashes``.
FLAG_NAMES = {"n_perimeters": "--perimeters", "bed_center": "--center"}
#: How the command line reads settings that are not plain numbers or words.
_PARSERS = {"infill_density": density, "bed_center": point}
_NOTES = {"infill_density": ": 20 or 20% is a percentage, a bare number up to 1 a fraction (0.2)"}
_METAVARS = {"mm": "MM", "mm/s": "MM/S", "mm/s2": "MM/S2", "C": "C", "degrees": "DEG", "layers": "N", "s": "S",
             "%": "PCT"}


def _setting_flags(p) -> None:
    """A flag for every print setting, group by group, from its declaration
    (`slicelab.printing.config.fields.setting`): its help, unit and choices; booleans as
    ``--name`` / ``--no-name``; the default said in the help when help is shown."""
    from dataclasses import fields

    from ..printing.config.settings import GROUPS
    for group, cls in GROUPS.items():
        g = p.add_argument_group(f"{group} settings ([{group}] in a settings file)")
        for f in fields(cls):  # over the group's settings
            m = f.metadata
            flag = FLAG_NAMES.get(f.name, "--" + f.name.replace("_", "-"))
            kw = {"dest": f.name, "default": GIVEN}
            unit = f" ({m['unit']})" if m["unit"] and m["unit"] not in ("layers",) else ""
            if f.name in _PARSERS:
                kw.update(type=_PARSERS[f.name], metavar="X,Y" if m["size"] else "D")
            elif m["kind"] is bool:
                kw["action"] = argparse.BooleanOptionalAction
            elif m["choices"] is not None:
                kw["choices"] = LazyChoices(m["choices"])
            elif m["size"]:
                kw.update(type=str, metavar="AxB")
            else:
                kw["type"] = {int: whole_number, float: number, str: str}[m["kind"]]
                kw["metavar"] = _METAVARS.get(m["unit"], "N" if m["kind"] is int else "TEXT" if m["kind"] is str
                                              else "X")
            text = (m["help"] + unit + _NOTES.get(f.name, "")).replace("%", "%%")
            action = g.add_argument(flag, help=f"{text}; default %(setting_default)s", **kw)
            action.setting_default = _Default(f.name)


class _Default:
    """A print setting's default, said in its flag's help (``%(setting_default)s``): read from
    `slicelab.printing.PrintSettings` (the prusa-mk3 profile's values) only when help is shown,
    so that building the parser, as every command does, imports no settings."""

    def __init__(self, name: str):
        self.name = name

    def __str__(self) -> str:
        from ..printing.config.settings import PrintSettings
        value = getattr(PrintSettings(), self.name)  # (derived where the group leaves it out: pixel_size)
        if value is None:
            return "the flavour's" if self.name in ("start_gcode", "end_gcode") else \
                "the bed's middle" if self.name == "bed_center" else "the infill's, turned every layer"
        if isinstance(value, bool):
            return "on" if value else "off"
        if isinstance(value, tuple):
            return "x".join(f"{v:g}" for v in value)
        return value if isinstance(value, str) else f"{value:g}"


def _add_slice(sub) -> None:
    p = command(sub, "slice", DOCS, file=False)
    p.add_argument("files", type=Path, nargs="*", metavar="FILE",
                   help="the part; several are put side by side on the bed, upright as given, and print together")
    p.add_argument("-o", "--output", type=Path, metavar="OUT.gcode", help="the G-code file (required unless "
                                                                          "--print-config)")
    _setting_flags(p)
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
                   help="also write DIR/layer_*.svg, DIR/preview.png (a few layers, every layer seen "
                        "obliquely, a legend of the roles) and DIR/preview.json (the layers it shows)")
    p.add_argument("--preview-layers", default=GIVEN, metavar="LIST",
                   help="the layers preview.png draws: layer numbers (0 is the first, as in layer_NNNN.svg), "
                        "z=HEIGHT (the layer printed at that height above the bed, mm), first, middle, last, "
                        "overhang (the most bridge and overhang area) or largest (the most material), "
                        "separated by commas, e.g. 0,57,z=12.5,last (default: first, middle, last and overhang)")
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
    if s.get("preview_layers"):
        print("preview: layers " + ", ".join(f"{d['layer']}" + (f" ({d['why']})" if d["why"] else "")
                                             for d in s["preview_layers"]) + f", and all {s['layers']} seen obliquely")
    return 0



def _on_one_bed(args, params):
    """The parts of several files side by side on the printer's bed, upright as given: one mesh."""
    from ..mesh import load
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
