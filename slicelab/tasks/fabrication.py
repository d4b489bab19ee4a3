"""Jobs that make printable things: a watertight cut, a partition into pieces, a print's G-code.

Each job calls its library function and writes the outputs; the work itself
lives in `slicelab.slicing.cut`, `slicelab.slicing.partition` and
`slicelab.printing.planner`.

See Also
--------
slicelab.tasks.jobs : the registry, `run_job`, and the jobs that analyse a file.
"""
from __future__ import annotations


import json

import numpy as np

from ..files.atomic import atomic_open
from .spec import (
    Job,
    ParameterError,
    choice,
    drawn_meanwhile,
    number,
    reason,
    resolve_plane,
    vector,
    whole,
)
from .spec import plane as plane_value

__all__ = ["CUT", "PARTITION", "SLICE", "slice_settings"]


# ------------------------------------------------------------------------- cut
def _cut_parameters(*, plane=None, preview: bool = True, repair: bool = False, fill_holes: bool = False) -> dict:
    """plane: ``(origin, normal)`` or None (horizontal, at mid-height); preview: draw exploded.png;
    repair: snap CAD float noise, drop collapsed facets and fix windings first (`slicelab.repair`);
    fill_holes: repair, and close the holes too (``fill_holes=True``)."""
    return {"plane": plane_value(plane), "preview": bool(preview), "repair": bool(repair),
            "fill_holes": bool(fill_holes)}


def _cut_compute(inp, p):
    import warnings

    from ..slicing.cut import CutWarning, cut
    origin, normal = resolve_plane(inp.mesh, p["plane"])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", CutWarning)  # reported as a reason
        return origin, normal, cut(inp.mesh, origin, normal)


def _write_parts(named, out) -> tuple[dict, list]:
    """Write meshes through `write_mesh`; the results are the checks of the files as written."""
    from ..mesh.written import write_mesh
    results, reasons = {}, []
    for role, name, mesh in named:
        if len(mesh) == 0:  # an STL with no facets could not be read back
            continue
        w = write_mesh(mesh, out.path(role, name) if name else out.path(role))
        r = w.report
        results[role if name is None else name] = {
            "facets": r.n_facets, "volume": r.volume, "watertight": bool(r.watertight and r.winding_consistent),
            "collapsed_in_float32": w.n_collapsed, "moved_in_float32": w.n_moved}
        if not (r.watertight and r.winding_consistent):
            reasons.append(reason("not_watertight", f"{w.path.name} as written has {r.n_open_edges} open, "
                                                    f"{r.n_nonmanifold_edges} non-manifold and "
                                                    f"{r.n_misoriented_edges} misoriented edges"))
    return results, reasons


def _open_input(inp, p=None) -> list:
    """Why the input has no inside, with the flag that would mend it (none left after --fill-holes)."""
    r = inp.check
    if r.watertight and r.winding_consistent:
        return []
    filled = bool(p and p.get("fill_holes"))
    hint = "" if filled else " (near-coincident vertices: try --repair)" if r.n_near_vertices else \
        " (1 hole: --fill-holes closes it)" if r.n_holes == 1 else \
        f" ({r.n_holes} holes: --fill-holes closes them)" if r.n_holes else ""
    if not hint and (r.n_nonmanifold_edges or r.n_open_edges) and (p or {}).get("repair", True):
        # Edges of three or more facets (a fin, a sheet inside) or open edges that bound no hole have
        # no safe repair (with --no-repair, the repair may yet mend them: that is said instead).
        hint = (" (edges of three or more facets, or open edges around no hole, have no safe repair: delete "
                "or mend those facets in a mesh editor, such as Blender's Select > Select All by Trait > "
                "Non Manifold, and try again)")
    return [reason("open_input", f"the input is not watertight{' even after --fill-holes' if filled else ''}: "
                                 f"{r.n_open_edges} open, {r.n_nonmanifold_edges} non-manifold, "
                                 f"{r.n_misoriented_edges} misoriented edges{hint}")]


def _closed_solid(inp, p) -> None:
    """Refuse, before any work, an input that does not bound a solid: its parts could not be closed."""
    why = _open_input(inp, p)
    if why:
        raise ValueError(f"{inp.path}: {why[0]['message']}; {'a cut' if 'plane' in p else 'a partition'} "
                         f"needs a closed solid")


def _all_closed(results: dict, reasons: list) -> None:
    """Refuse parts that are not watertight as written (they were written to a staging folder, which
    is then discarded: no open part is left under its final name)."""
    if reasons:
        raise ValueError(f"{reasons[0]['message']}: nothing was written (the parts would not be closed)")


def _cut_write(value, inp, p, out):
    parts = value[2]
    if not parts.report.closed:
        raise ValueError(f"{inp.path}: the section did not close everywhere (a self-intersecting mesh?): the "
                         f"parts would not be watertight; nothing was written")
    with drawn_meanwhile(_exploded(p), (parts.rear, parts.front), out.path("preview") if p["preview"] else None,
                         spread=0.35, title=f"{inp.path.name}: cut"):
        results, reasons = _write_parts([("rear", None, parts.rear), ("front", None, parts.front)], out)
    _all_closed(results, reasons)
    return {"results": results, "reasons": reasons}


def _exploded(p):
    """The exploded view's writer when the job draws a preview, else None."""
    if not p["preview"]:
        return None
    from ..viz import save_exploded_png
    return save_exploded_png





def _cut_report(value, inp, p):
    origin, normal, parts = value
    rep = parts.report
    results = {"plane": {"origin": origin.tolist(), "normal": normal.tolist()}, "closed": rep.closed,
               "notes": [n for cap in (rep.rear_cap, rep.front_cap) for n in cap.notes]}
    reasons = _open_input(inp, p)
    if not rep.closed:
        reasons.append(reason("open_section", "the section did not close everywhere; the parts are not watertight"))
    if results["notes"]:
        reasons.append(reason("self_intersecting", rep.rear_cap.notes[0] if rep.rear_cap.notes else
                              rep.front_cap.notes[0]))
    return results, reasons


CUT = Job(
    "cut", "cut a solid by a plane into two closed parts, capped on the plane",
    _cut_parameters, {"rear": "rear.stl", "front": "front.stl", "preview": "exploded.png"},
    _cut_compute, _cut_write, _cut_report, feasible=_closed_solid,
)


# ------------------------------------------------------------------- partition
def _partition_parameters(*, volume=None, joint: str = "flat", clearance: float = 0.0, step=(10.0, 20.0),
                          flight: int = 1, rotate: bool = True, preview: bool = True, repair: bool = False,
                          plates: bool = False, spacing: float = 5.0, fill_holes: bool = False) -> dict:
    """volume: the build volume (3 sizes, mm; required); joint: flat or stair; clearance: glue gap (mm);
    step: stair step height and depth (mm); flight: steps up before stepping down; rotate: turn
    pieces about z to fit; preview: draw exploded.png; repair: `slicelab.repair` the mesh first;
    fill_holes: repair, and close the holes too; plates: also pack the pieces onto build plates
    (``plate_NN.stl``, ``plates.json``), `spacing` mm apart."""
    if volume is None:
        raise ParameterError("volume", "is required (three sizes in mm, such as 200x200x200)")
    return {"volume": vector("volume", volume, positive=True), "joint": choice("joint", joint, ("flat", "stair")),
            "clearance": number("clearance", clearance, low=0), "step": vector("step", step, size=2, positive=True),
            "flight": whole("flight", flight, low=1), "rotate": bool(rotate), "preview": bool(preview),
            "repair": bool(repair), "plates": bool(plates), "spacing": number("spacing", spacing, low=0),
            "fill_holes": bool(fill_holes)}


def _partition_feasible(inp, p):
    from .limits import check_partition
    _closed_solid(inp, p)
    check_partition(inp.mesh, p["volume"], joint=p["joint"], step=p["step"])


def _partition_compute(inp, p):
    from ..slicing.partition import partition
    return partition(inp.mesh, tuple(p["volume"]), joint=p["joint"], clearance=p["clearance"],
                     step=tuple(p["step"]), flight=p["flight"], rotate=p["rotate"])


def _partition_write(parts, inp, p, out):
    # Each piece is written as it will be printed: laid on its cut face, turned, centred on the bed.
    pieces = parts.pieces
    width = max(3, len(str(len(pieces))))
    names = [f"part_{k:0{width}d}.stl" for k in range(len(pieces))]
    placed = [piece.transformed(info.placement.matrix) for piece, info in zip(pieces, parts.report.pieces)]
    with drawn_meanwhile(_exploded(p), pieces, out.path("preview") if p["preview"] else None,
                         title=f"{inp.path.name}: {len(pieces)} pieces, {p['joint']} joints"):
        results, reasons = _write_parts([("pieces", n, m) for n, m in zip(names, placed)], out)
    _all_closed(results, reasons)
    report = parts.report.to_dict()
    for name, piece in zip(names, report["pieces"]):
        piece["file"] = name
        piece["written"] = results[name]
        piece["watertight"] = results[name]["watertight"]  # what the file holds, not the memory
    with atomic_open(out.path("json"), "w", encoding="utf-8") as fh:
        json.dump({"file": str(inp.path), **report}, fh, indent=1)
    extra = {}
    if p["plates"]:
        from .plates import write_plates
        extra, why = write_plates(pieces, names, p["volume"], out.folder, spacing=p["spacing"],
                                  rotate=p["rotate"], preview=p["preview"])
        out.record("plates", sorted(out.folder.glob("plate_*")) + [out.folder / "plates.json"])
        reasons += why
    return {"results": {"written": results, "watertight": all(r["watertight"] for r in results.values()),
                        **({"plates": extra} if extra else {})},
            "reasons": reasons}


def _partition_report(parts, inp, p):
    rep = parts.report
    results = {"pieces": len(parts.pieces), "glue_area": rep.glue_area, "flat_area": rep.flat_area}
    return results, []


PARTITION = Job(
    "partition", "cut a solid into pieces that fit a printer's build volume",
    _partition_parameters, {"pieces": "part_NNN.stl", "json": "parts.json", "preview": "exploded.png"},
    _partition_compute, _partition_write, _partition_report, feasible=_partition_feasible,
)


# ----------------------------------------------------------------------- slice
def _setting_names() -> set:
    from ..printing import setting_names
    return set(setting_names())


def _size(name: str, value) -> list:
    """Two sizes given as ``"250x210"``, ``"250,210"`` or a pair of numbers."""
    if isinstance(value, str):
        value = value.lower().replace(",", "x").split("x")
    return vector(name, value, size=2, positive=True)


def _slice_parameters(*, printer=None, config=None, workers=None, preview: bool = False, preview_layers=None,
                      repair: bool = True, fill_holes: bool = False, **settings) -> dict:
    """`slicelab.printing.PrintSettings` fields in `settings` (left out: the printer profile's, then the
    settings file's, then PrintSettings' defaults; the first layer as thick as the others unless given;
    bed_size as ``"250x210"`` or two numbers); printer: a bundled profile's name; config: a TOML
    settings file; workers: processes (None: all cores); preview: layer SVGs and a PNG (a few layers,
    an oblique view of them all, a legend); preview_layers: the layers the PNG draws, as
    ``"0,57,z=12.5,last"`` or a list of such items (`slicelab.viz.layers.preview_layers`; None: the
    first, middle and last and the one with the most bridges and overhangs); repair:
    `slicelab.repair` the mesh first when its check finds something to mend, as PrusaSlicer does
    (False refuses such a mesh instead); fill_holes: repair, and close the holes too."""
    from ..printing import PrintSettings, setting_names
    from ..printing.config.printers import resolve_settings
    known = set(setting_names())
    for name in settings:
        if name not in known:
            raise ParameterError(name, "is not a print setting (see slicelab.printing.PrintSettings)")
    given = {k: v for k, v in settings.items() if v is not None}
    if "first_layer_height" not in given and "layer_height" in given:
        given["first_layer_height"] = given["layer_height"]
    density = given.get("infill_density")
    if density is not None and not 0 <= number("infill_density", density) <= 1:
        raise ParameterError("infill_density", f"must be a fraction from 0 to 1 (0 % to 100 %), got {density!r}")
    from ..printing.config.settings import sized_settings
    for name in sized_settings():  # pairs given as "250x210" or "0.6,2.5"
        if isinstance(given.get(name), str):
            given[name] = tuple(_size(name, given[name]))
    try:
        resolved = resolve_settings(printer=printer, config=config, **given)
        if "first_layer_height" not in resolved and "layer_height" in resolved:
            resolved["first_layer_height"] = resolved["layer_height"]
        PrintSettings(**resolved)
    except (ValueError, TypeError) as exc:  # PrintSettings' messages begin with the field's name
        name, _, problem = str(exc).partition(" ")
        raise (ParameterError(name, problem) if name in known | {"printer"} else ValueError(str(exc))) from None
    return {**resolved, "workers": None if workers is None else whole("workers", workers, low=1),
            "preview": bool(preview), "preview_layers": _preview_layers(preview_layers, preview),
            "repair": bool(repair), "fill_holes": bool(fill_holes)}


def _preview_layers(value, preview) -> list | None:
    """The preview's layers as plain values (numbers, ``"z=H"``, words), checked for their form."""
    if value is None:
        return None
    from ..viz.layer_choice import preview_layers
    try:
        items = preview_layers(value)
    except ValueError as exc:
        raise ParameterError("preview_layers", str(exc)) from None
    if not preview:
        raise ParameterError("preview_layers", "chooses the layers of the preview: ask for one too "
                                               "(--preview DIR)")
    return list(items)


def _picked_layers(p, tops, pp=None) -> list:
    """The preview's layers among layers whose tops are `tops` (with the plan `pp`, all of them; before
    planning, those that numbers and heights name), refused as a parameter where one does not exist."""
    from ..viz.layer_choice import pick_preview_layers
    try:
        return pick_preview_layers(p["preview_layers"], tops, pp)
    except ValueError as exc:
        raise ParameterError("preview_layers", str(exc)) from None


def slice_settings(params: dict):
    """The `PrintSettings` in force for checked slice parameters (`job_parameters("slice", ...)`)."""
    return _settings(params)


def _settings(p):
    """The PrintSettings of checked slice parameters."""
    from ..printing import PrintSettings
    known = _setting_names()
    return PrintSettings(**{k: v for k, v in p.items() if k in known})


def _slice_feasible(inp, p):
    from ..printing.config.bed import check_bed
    from .limits import check_print
    # An open or inside-out mesh has no inside: its layers would print fragments (pins for a plate).
    # A surface whose every edge is walked as often both ways bounds a solid by winding number,
    # manifold or not (shells touching along an edge): its layers are closed loops.
    why = _open_input(inp, p)
    if why and not inp.check.closed_by_winding:
        message = why[0]["message"]
        hint = "" if "--" in message or "mesh editor" in message or p["repair"] else \
            " (leave out --no-repair to repair it)"
        raise ValueError(f"{inp.path}: {message}{hint}; its layers would not be closed regions")
    if inp.check.volume < 0:  # only with --no-repair: a repair turns it outward
        raise ValueError(f"{inp.path}: the mesh is inside out (its volume is {inp.check.volume:.6g} mm3): "
                         f"leave out --no-repair to turn it outward")
    s = _settings(p)
    check_print(inp.mesh, layer_height=min(s.layer_height, s.first_layer_height), pixel_size=s.pixel_size,
                line_width=s.line_width, n_perimeters=s.n_perimeters)
    if p["preview"] and p["preview_layers"] and len(inp.mesh):
        # Refused before any work: the layers the part will have (a part lowered into the bed to
        # print its first layer loses some: checked again once planned, before anything is written).
        from ..printing.planner import layer_bounds
        _picked_layers(p, layer_bounds(float(np.ptp(inp.mesh.bounds[:, 2])), s.layer_height,
                                       s.first_layer_height)[:, 1])
    try:
        check_bed(inp.mesh, s)
    except ValueError as exc:  # its message begins with the setting's name
        name, _, problem = str(exc).partition(" ")
        raise (ParameterError(name, problem) if name in _setting_names() else exc) from None


def _slice_compute(inp, p):
    from ..gcode import layer_drawings, layer_texts
    from ..printing import plan
    # The workers format each layer's G-code (and draw its preview) as they plan it: the writers
    # then only join the text and write the files.
    return plan(inp.mesh, _settings(p), workers=p["workers"], layer_text=layer_texts,
                layer_drawing=layer_drawings if p["preview"] else None)


def _slice_write(pp, inp, p, out):
    from ..gcode import write_gcode
    notes = [f"repaired: {change}" for change in inp.repair.changes()] if inp.repair is not None else []
    if not p["preview"]:
        totals = write_gcode(pp, out.path("gcode"), workers=p["workers"], notes=notes)
        return {"results": {"print_time": totals["seconds"], "filament_used": totals["filament"]}}
    if out.folder is None:
        raise ValueError("a preview needs a folder")
    if p["preview_layers"]:
        _picked_layers(p, pp.z, pp)  # (before anything is written)
    from ..gcode import write_svgs
    from ..viz import preview_png
    totals = write_gcode(pp, out.path("gcode"), workers=p["workers"], notes=notes)  # (may fork: before any thread)
    svgs = []
    # The layers the planner's workers drew are only files to write: on a thread while the PNG is
    # drawn (file output and OpenCV let go of the GIL). Layers left to draw may need a pool,
    # which is not forked beside a thread.
    ahead = len(pp.drawings) == len(pp.layers)
    with drawn_meanwhile((lambda: svgs.extend(write_svgs(pp, out.folder, workers=1))) if ahead else None):
        if not ahead:
            svgs += write_svgs(pp, out.folder, workers=p["workers"])
        shown = preview_png(pp, out.path("preview"), p["preview_layers"], legend=True, whole=True)
    out.record("svg", svgs)
    with atomic_open(out.path("preview_json"), "w", encoding="utf-8") as fh:
        json.dump({"file": str(inp.path), "part_layers": len(pp.layers), **shown}, fh, indent=1)
    return {"results": {"print_time": totals["seconds"], "filament_used": totals["filament"],
                        "preview_layers": shown["layers"]}}


def _slice_report(pp, inp, p):
    bridges = int(pp.overhangs["bridges"].sum())
    warnings = pp.warnings()
    r = inp.check
    if r.n_nonmanifold_edges:  # (sliced all the same: it is closed by winding number, `_slice_feasible`)
        warnings.append(reason("non_manifold", f"{r.n_nonmanifold_edges} non-manifold edges (shells that touch "
                                               f"along an edge, or walls inside): each is walked as often both "
                                               f"ways, so the layers were read by winding number"))
    return {"layers": len(pp.layers), "print_length": pp.print_length, "filament_length": pp.filament_length,
            "extruded_volume": pp.extruded_volume, "bridges": bridges}, warnings


SLICE = Job(
    "slice", "plan every layer (perimeters, skins, infill) and write Marlin G-code",
    _slice_parameters, {"gcode": "print.gcode", "svg": "layer_*.svg", "preview": "preview.png",
                        "preview_json": "preview.json"},
    _slice_compute, _slice_write, _slice_report, feasible=_slice_feasible,
)
