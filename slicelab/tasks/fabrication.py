"""Jobs that make printable things: a watertight cut, a partition into pieces, a print's G-code.

Each job calls its library function and writes the outputs; the work itself
lives in `slicelab.slicing.cut`, `slicelab.slicing.partition` and
`slicelab.toolpath.planner`.

See Also
--------
slicelab.tasks.jobs : the registry, `run_job`, and the jobs that analyse a file.
"""
from __future__ import annotations

import json

from ..export.files import atomic_open
from .spec import (
    Job,
    ParameterError,
    choice,
    number,
    reason,
    resolve_plane,
    vector,
    whole,
)
from .spec import plane as plane_value

__all__ = ["CUT", "PARTITION", "SLICE"]


# ------------------------------------------------------------------------- cut
def _cut_parameters(plane=None, preview: bool = True) -> dict:
    """plane: ``(origin, normal)`` or None (horizontal, at mid-height); preview: draw exploded.png."""
    return {"plane": plane_value(plane), "preview": bool(preview)}


def _cut_compute(inp, p):
    import warnings

    from ..slicing.cut import CutWarning, cut
    origin, normal = resolve_plane(inp.mesh, p["plane"])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", CutWarning)  # reported as a reason
        return origin, normal, cut(inp.mesh, origin, normal)


def _cut_write(value, inp, p, out):
    from ..mesh import save
    parts = value[2]
    for name in ("rear", "front"):
        save(getattr(parts, name), out.path(name))
    if p["preview"]:
        from ..viz import save_exploded_png
        save_exploded_png((parts.rear, parts.front), out.path("preview"), spread=0.35,
                          title=f"{inp.path.name}: cut")


def _cut_report(value, inp, p):
    from ..mesh import check
    origin, normal, parts = value
    results = {"plane": {"origin": origin.tolist(), "normal": normal.tolist()}, "closed": parts.report.closed}
    for name in ("rear", "front"):
        r = check(getattr(parts, name))
        results[name] = {"facets": r.n_facets, "volume": r.volume,
                         "watertight": bool(r.watertight and r.winding_consistent)}
    reasons = [] if parts.report.closed else [
        reason("open_section", "the section did not close everywhere (open input); the parts are not watertight")]
    return results, reasons


CUT = Job(
    "cut", "cut a solid by a plane into two closed parts, capped on the plane",
    _cut_parameters, {"rear": "rear.stl", "front": "front.stl", "preview": "exploded.png"},
    _cut_compute, _cut_write, _cut_report,
)


# ------------------------------------------------------------------- partition
def _partition_parameters(volume=None, joint: str = "flat", clearance: float = 0.0, step=(10.0, 20.0),
                          flight: int = 1, rotate: bool = True, preview: bool = True) -> dict:
    """volume: the build volume (3 sizes, mm; required); joint: flat or stair; clearance: glue gap (mm);
    step: stair step height and depth (mm); flight: steps up before stepping down; rotate: turn
    pieces about z to fit; preview: draw exploded.png."""
    if volume is None:
        raise ParameterError("volume", "is required (three sizes in mm, such as 200x200x200)")
    return {"volume": vector("volume", volume, positive=True), "joint": choice("joint", joint, ("flat", "stair")),
            "clearance": number("clearance", clearance, low=0), "step": vector("step", step, size=2, positive=True),
            "flight": whole("flight", flight, low=1), "rotate": bool(rotate), "preview": bool(preview)}


def _partition_compute(inp, p):
    from ..slicing.partition import partition
    return partition(inp.mesh, tuple(p["volume"]), joint=p["joint"], clearance=p["clearance"],
                     step=tuple(p["step"]), flight=p["flight"], rotate=p["rotate"])


def _partition_write(parts, inp, p, out):
    from ..mesh import save
    pieces = parts.pieces
    width = max(3, len(str(len(pieces))))
    for k, piece in enumerate(pieces):
        save(piece, out.path("pieces", f"part_{k:0{width}d}.stl"))
    with atomic_open(out.path("json"), "w", encoding="utf-8") as fh:
        json.dump({"file": str(inp.path), **parts.report.to_dict()}, fh, indent=1)
    if p["preview"]:
        from ..viz import save_exploded_png
        save_exploded_png(pieces, out.path("preview"),
                          title=f"{inp.path.name}: {len(pieces)} pieces, {p['joint']} joints")


def _partition_report(parts, inp, p):
    rep = parts.report
    results = {"pieces": len(parts.pieces), "watertight": rep.watertight, "glue_area": rep.glue_area,
               "flat_area": rep.flat_area}
    reasons = [] if rep.watertight else [reason("not_watertight", "some pieces are not watertight")]
    return results, reasons


PARTITION = Job(
    "partition", "cut a solid into pieces that fit a printer's build volume",
    _partition_parameters, {"pieces": "part_NNN.stl", "json": "parts.json", "preview": "exploded.png"},
    _partition_compute, _partition_write, _partition_report,
)


# ----------------------------------------------------------------------- slice
_SETTINGS = ("layer_height", "first_layer_height", "line_width", "n_perimeters", "infill_density",
             "infill_angle", "top_layers", "bottom_layers", "pixel_size", "nozzle_temperature",
             "bed_temperature")


def _slice_parameters(layer_height=None, first_layer_height=None, line_width=None, n_perimeters=None,
                      infill_density=None, infill_angle=None, top_layers=None, bottom_layers=None,
                      pixel_size=None, nozzle_temperature=None, bed_temperature=None, workers=None,
                      preview: bool = False) -> dict:
    """`slicelab.toolpath.PrintSettings` fields (None: its default; the first layer as thick as
    the others unless given); workers: processes (None: all cores); preview: layer SVGs and a PNG."""
    from ..toolpath import PrintSettings
    given = {k: v for k, v in locals().items() if k in _SETTINGS and v is not None}
    if first_layer_height is None and layer_height is not None:
        given["first_layer_height"] = layer_height
    if infill_density is not None and not 0 <= number("infill_density", infill_density) <= 1:
        raise ParameterError("infill_density", f"must be a fraction from 0 to 1 (0 % to 100 %), "
                                               f"got {infill_density!r}")
    try:
        PrintSettings(**given)
    except ValueError as exc:  # PrintSettings' messages begin with the field's name
        name, _, problem = str(exc).partition(" ")
        raise (ParameterError(name, problem) if name in _SETTINGS else exc) from None
    return {**given, "workers": None if workers is None else whole("workers", workers, low=1),
            "preview": bool(preview)}


def _slice_compute(inp, p):
    from ..toolpath import PrintSettings, plan
    settings = PrintSettings(**{k: v for k, v in p.items() if k in _SETTINGS})
    return plan(inp.mesh, settings, workers=p["workers"])


def _slice_write(pp, inp, p, out):
    from ..export import write_gcode
    write_gcode(pp, out.path("gcode"))
    if p["preview"]:
        from ..export import write_svgs
        from ..viz import preview_png
        if out.folder is None:
            raise ValueError("a preview needs a folder")
        out.record("svg", write_svgs(pp, out.folder))
        preview_png(pp, out.path("preview"))


def _slice_report(pp, inp, p):
    return {"layers": len(pp.layers), "print_length": pp.print_length, "filament_length": pp.filament_length,
            "extruded_volume": pp.extruded_volume}, []


SLICE = Job(
    "slice", "plan every layer (perimeters, skins, infill) and write Marlin G-code",
    _slice_parameters, {"gcode": "print.gcode", "svg": "layer_*.svg", "preview": "preview.png"},
    _slice_compute, _slice_write, _slice_report,
)
