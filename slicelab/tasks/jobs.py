"""The jobs on a mesh file, each defined once: the command line and `run_batch` both run them.

==============  ==============================================  ==========================================
job             parameters (defaults)                           outputs
==============  ==============================================  ==========================================
``inspect``     none                                            none (the report is the mesh check)
``section``     plane (mid-height), max_gap (1)                 ``section.svg``
``layers``      layer_height, max_gap (1), svg (True)           ``layers.json``, ``layer_NNNN_zZ.svg``
``split``       plane, max_gap, visible_from, preview (True)    ``front.stl``, ``rear.stl``,
                                                                ``section.svg``, ``preview.png``
``profile``     planes (12), side, spread, align, max_gap,      ``profile.svg``, ``profile.png``,
                png, json, dxf, csv (True)                      ``profile.json``, ``profile.dxf``,
                                                                ``profile.csv``
``cut``         plane, preview (True)                           ``rear.stl``, ``front.stl``, ``exploded.png``
``partition``   volume, joint, clearance, step, flight,         ``part_NNN.stl``, ``parts.json``,
                rotate, preview                                 ``exploded.png``
``slice``       print settings, workers, preview (False)        ``print.gcode``; ``layer_*.svg``,
                                                                ``preview.png``
==============  ==============================================  ==========================================

`run_job` checks the parameters, refuses an output folder that is a file
before any work, loads the file (unless given the mesh), computes, writes
and reports. The cut, partition and slice jobs live in
`slicelab.tasks.fabrication`.
"""
from __future__ import annotations

import json
import time
from pathlib import Path

import numpy as np

from ..files.atomic import StagedFolder, atomic_open, same_file
from .fabrication import CUT, PARTITION, SLICE
from .limits import check_layers, check_planes, likely_units
from .spec import (
    Job,
    JobInput,
    JobResult,
    Outputs,
    ParameterError,
    choice,
    drawn_meanwhile,
    number,
    plain,
    reason,
    resolve_plane,
    vector,
    whole,
)
from .spec import plane as plane_value
from .threads import pinned

__all__ = ["JOBS", "TASKS", "SUFFIXES", "job_parameters", "run_job", "check_output_dir", "check_outputs"]


def check_output_dir(path) -> None:
    """Refuse an output folder that exists as a file (before any work, so nothing is left half done).

    Examples
    --------
    >>> import tempfile, pathlib
    >>> f = pathlib.Path(tempfile.mkdtemp()) / "f"; _ = f.write_text("")
    >>> check_output_dir(f)
    Traceback (most recent call last):
    ...
    ValueError: ... exists and is not a directory
    """
    path = Path(path)
    if path.exists() and not path.is_dir():
        raise ValueError(f"{path} exists and is not a directory")


def _gap(value) -> float:
    return number("max_gap", value, low=0)


def _plane_result(origin, normal) -> dict:
    return {"origin": origin.tolist(), "normal": normal.tolist()}


# --------------------------------------------------------------------- inspect
def _inspect_parameters() -> dict:
    return {}


INSPECT = Job(
    "inspect", "load the file and check the mesh (normals, open edges, shells, volume)",
    _inspect_parameters, {},
    compute=lambda inp, p: inp.check,
    write=lambda value, inp, p, out: None,
    report=lambda value, inp, p: (value.to_dict(), []),
)


# --------------------------------------------------------------------- section
def _section_parameters(*, plane=None, max_gap: float = 1.0) -> dict:
    """plane: ``(origin, normal)`` or None (horizontal, at mid-height); max_gap: mm."""
    return {"plane": plane_value(plane), "max_gap": _gap(max_gap)}


def _section_compute(inp, p):
    from ..slicing import section
    origin, normal = resolve_plane(inp.mesh, p["plane"])
    return origin, normal, section(inp.mesh, origin, normal, max_gap=p["max_gap"])


def _section_write(value, inp, p, out):
    value[2].to_svg(out.path("svg"))


def _section_report(value, inp, p):
    origin, normal, s = value
    holes = int(np.count_nonzero(s.loop_depth % 2 == 1)) if len(s.loops) else 0
    results = {"plane": _plane_result(origin, normal), "area": s.area, "segments": len(s.segments),
               "loops": len(s.loops), "holes": holes, "open_chains": len(s.open_chains),
               "joined_gaps": len(s.joined_gaps)}
    reasons = []
    if s.open_chains:
        reasons.append(reason("open_section", f"the section has {len(s.open_chains)} open chains"))
    return results, reasons


SECTION = Job(
    "section", "cut the mesh with one plane; draw the section as SVG (mm)",
    _section_parameters, {"svg": "section.svg"},
    _section_compute, _section_write, _section_report,
    columns=("area", "loops", "holes", "open_chains"),
)


# ---------------------------------------------------------------------- layers
def _layers_parameters(*, layer_height=None, max_gap: float = 1.0, svg: bool = True) -> dict:
    """layer_height: mm (required); svg: also draw one SVG per layer."""
    if layer_height is None:
        raise ParameterError("layer_height", "is required (a positive number, mm)")
    return {"layer_height": number("layer_height", layer_height, positive=True), "max_gap": _gap(max_gap),
            "svg": bool(svg)}


def _layers_compute(inp, p):
    from ..slicing import slice_layers
    return slice_layers(inp.mesh, p["layer_height"], max_gap=p["max_gap"])


def _layers_write(layers, inp, p, out):
    if p["svg"]:
        width = max(4, len(str(len(layers))))
        for k, s in enumerate(layers):
            s.to_svg(out.path("svg", f"layer_{k:0{width}d}_z{s.z:.3f}.svg"))
    with atomic_open(out.path("json"), "w", encoding="utf-8") as fh:
        json.dump({"file": str(inp.path), "layer_height": p["layer_height"],
                   "layers": [{"index": k, "z": s.z, **s.to_dict()} for k, s in enumerate(layers)]}, fh)


def _layers_report(layers, inp, p):
    n_open = sum(len(s.open_chains) for s in layers)
    results = {"layers": len(layers), "loops": sum(len(s.loops) for s in layers), "open_chains": n_open}
    return results, [reason("open_section", f"{n_open} open chains over the layers")] if n_open else []


LAYERS = Job(
    "layers", "slice the mesh at mid-layer heights; every loop as JSON, one SVG per layer",
    _layers_parameters, {"json": "layers.json", "svg": "layer_NNNN_zZ.svg"},
    _layers_compute, _layers_write, _layers_report,
    columns=("layers", "loops", "open_chains"),
    feasible=lambda inp, p: check_layers(inp.mesh, p["layer_height"]),
)


# ----------------------------------------------------------------------- split
def _split_parameters(*, plane=None, max_gap: float = 1.0, visible_from=None, preview: bool = True) -> dict:
    """visible_from: keep only the facets facing a viewer in this direction; preview: draw a PNG."""
    seen = None if visible_from is None else vector("visible_from", visible_from, nonzero=True)
    return {"plane": plane_value(plane), "max_gap": _gap(max_gap), "visible_from": seen,
            "preview": bool(preview)}


def _split_compute(inp, p):
    from ..slicing.split import split
    origin, normal = resolve_plane(inp.mesh, p["plane"])
    seen = None if p["visible_from"] is None else np.array(p["visible_from"])
    return origin, normal, split(inp.mesh, origin, normal, visible_from=seen, max_gap=p["max_gap"])


def _split_write(value, inp, p, out):
    from ..mesh.written import write_mesh
    sp = value[2]
    written = {}
    draw = None
    if p["preview"]:
        from ..viz import save_split_preview as draw
    with drawn_meanwhile(draw, sp, out.path("preview") if p["preview"] else None):
        for side in ("front", "rear"):
            piece = getattr(sp, side)
            if len(piece):  # an STL without facets could not be read back
                w = write_mesh(piece, out.path(side), checked=False)  # open by design: no check
                written[f"{side}_collapsed_in_float32"] = w.n_collapsed
        sp.section.to_svg(out.path("svg"))
    return {"results": written}


def _split_report(value, inp, p):
    origin, normal, sp = value
    sec = sp.section
    return {"plane": _plane_result(origin, normal), "front_facets": len(sp.front), "rear_facets": len(sp.rear),
            "cut_facets": sp.n_cut, "n_front": sp.n_front, "n_rear": sp.n_rear,
            "section_area": sec.area, "section_segments": len(sec.segments), "section_loops": len(sec.loops),
            "section_open_chains": len(sec.open_chains)}, []


SPLIT = Job(
    "split", "split the mesh by a plane into front, section and rear",
    _split_parameters,
    {"front": "front.stl", "rear": "rear.stl", "svg": "section.svg", "preview": "preview.png"},
    _split_compute, _split_write, _split_report,
    columns=("front_facets", "rear_facets", "cut_facets", "section_area"),
)


# --------------------------------------------------------------------- profile
def _profile_parameters(*, planes: int = 12, side: str = "left", spread: bool = False, align: bool = True,
                        max_gap: float = 1.0, png: bool = True, json: bool = True, dxf: bool = True,
                        csv: bool = True) -> dict:
    """planes through the axis; side of the drawn section; spread: other halves in grey;
    align: turn the vessel onto its axis first; png, json, dxf, csv: also write these."""
    return {"planes": whole("planes", planes, low=1), "side": choice("side", side, ("left", "right")),
            "spread": bool(spread), "align": bool(align), "max_gap": _gap(max_gap), "png": bool(png),
            "json": bool(json), "dxf": bool(dxf), "csv": bool(csv)}


# The profile's sums run on one BLAS thread whatever the environment says (`slicelab.tasks.threads`):
# its numbers are then the same in a terminal, a local pool and on Dask. Its drawing and report
# compute too (the handles, the ovality), so they are pinned as well.
@pinned
def _profile_compute(inp, p):
    from ..artefacts import profile
    return profile(inp.mesh, planes=p["planes"], align=p["align"], max_gap=p["max_gap"], name=inp.path.name)


@pinned
def _profile_write(pr, inp, p, out):
    pr.to_svg(out.path("svg"), side=p["side"], spread=p["spread"])
    if p["png"]:
        pr.to_png(out.path("png"), side=p["side"], spread=p["spread"])
    if p["json"]:
        with atomic_open(out.path("json"), "w", encoding="utf-8") as fh:
            json.dump(pr.to_dict(), fh)
    if p["dxf"] or p["csv"]:
        from ..artefacts.profile_files import profile_csv, profile_dxf
        if p["dxf"]:
            profile_dxf(pr, out.path("dxf"))
        if p["csv"]:
            profile_csv(pr, out.path("csv"))


def _eve(pr) -> dict:
    """What an EVE table needs of a profile: the piece's kind, its rim and base as shares of a whole
    vessel's (estimated vessel equivalents: a whole vessel is 1), the rim diameter's uncertainty, and
    how far its axis and its stance can be trusted. The sherd's report may hold more than older
    versions of it did (`rim_diameter_sd`, `base_fraction`, `up_confidence`, `kind_confidence`,
    `axis_confidence`), and
    the profile whether it is `fragmentary`: each is read where it is, None where not."""
    import math

    from ..artefacts.drawing import orientation_uncertain
    sherd, m = pr.sherd, pr.measurements

    def got(x, name):
        v = getattr(x, name, None)
        return None if v is None or (isinstance(v, float) and not math.isfinite(v)) else v
    if sherd is None:
        # A whole vessel: the full turn (the alignment's span is counted in bins, a little under).
        eve = {"kind": "whole", "span": 360.0, "rim_eve": 1.0 if math.isfinite(m.rim_diameter) else None,
               "base_eve": 1.0, "rim_diameter_sd": None, "axis_trusted": pr.is_revolution, "axis_spread": None}
    else:
        base = got(sherd, "base_fraction")
        # A piece whose kind is uncertain adds nothing to a lab's EVE totals (a body or base sherd
        # taken for a rim would): its rim EVE stays in its report and drawing, with the warning.
        sure = "kind_uncertain" not in getattr(sherd, "warnings", ())
        eve = {"kind": sherd.kind, "rim_eve": got(sherd, "rim_fraction") if sherd.kind == "rim" and sure else None,
               "base_eve": base if sherd.kind == "base" and sure else None, "rim_diameter_sd": got(sherd, "rim_diameter_sd"),
               "axis_trusted": bool(sherd.axis_trusted), "axis_spread": got(sherd, "axis_spread")}
    cue = sherd if sherd is not None else pr.alignment
    eve.update(up_confidence=got(cue, "up_confidence"), kind_confidence=got(cue, "kind_confidence"),
               axis_confidence=got(cue, "axis_confidence"), orientation_uncertain=orientation_uncertain(pr),
               fragmentary=got(pr, "fragmentary"))
    return eve


@pinned
def _profile_report(pr, inp, p):
    """Results (NaN left as None by `plain`) and the warnings, each naming its cause."""
    import math
    a, m = pr.alignment, pr.measurements
    results = {**m.to_dict(), "relative_residual": None if a is None else a.relative_residual,
               "up_from": None if a is None else a.up_from, "axis": None if a is None else a.axis.tolist(),
               "origin": None if a is None else a.origin.tolist(),
               "shape_residual": None if a is None else a.shape_residual,
               "span": None if a is None else a.span, "ovality": pr.ovality, "rim_drop": pr.rim_drop,
               "appendage_angle": pr.appendage_angle, "appendages": [x.to_dict() for x in pr.appendages],
               "sealed": pr.sealed, "closed_gap": pr.closed_gap,
               "sherd": None if pr.sherd is None else pr.sherd.to_dict(), **_eve(pr)}
    reasons = []
    sherd = pr.sherd
    if sherd is not None:
        reasons.append(reason("sherd", sherd.sentence() + (
            "; no capacity, height or base diameter" if sherd.kind != "base" else "; no capacity or height")))
        if sherd.up_from == "unknown":
            reasons.append(reason("upside_down_risk", "no rim and no base on the sherd: which way is up is "
                                                      "a guess, and the drawing may stand on its head"))
        # The sherd's own doubts (its kind, which end is the lip, its axis, its rim diameter), each with
        # its code, where its report says them; a stance already said to be a guess is not said twice.
        for code, sentence in getattr(sherd, "cautions", list)():
            if not (code == "up_uncertain" and sherd.up_from == "unknown"):
                reasons.append(reason(code, sentence))
    elif a is not None and a.up_from == "centre of mass":
        reasons.append(reason("upside_down_risk", "neither a base crossing the axis nor an open rim was found: "
                                                  "up was taken from the centre of mass"))
    elif a is not None and a.up_from == "open boundary":
        # No base crossing the axis: the opening taken for the rim may as well be a break below (a ring
        # of wall broken off under a whole lip), and the drawing would stand on its head.
        reasons.append(reason("upside_down_risk", "no base crossing the axis was found: up was taken from the "
                                                  "open boundary, which may be a break rather than the rim"))
    angle, parts = pr.appendage_angle, pr.appendages
    if angle is not None or parts:
        where = f"at {angle:.0f} degrees about the axis " if angle is not None else ""
        said = "; ".join(f"handle, spout or lug {x.sentence()}" for x in parts)
        reasons.append(reason("handle_or_spout", f"a handle, spout or lug {where}(in the aligned frame): the "
                                                 f"half-sections through it are left out of the diameters and "
                                                 f"the wall" + (f"; {said}" if said else "")))
    if pr.sealed:
        reasons.append(reason("sealed", f"the vessel is sealed (no mouth): the capacity, "
                                        f"{m.capacity / 1e6:.4g} l, is the volume of its inner cavity shell"))
    if sherd is None and len(pr.halves) < 2 * pr.planes:
        missing = 2 * pr.planes - len(pr.halves)
        reasons.append(reason("hole_in_wall", f"{missing // 2} of {pr.planes} planes through the axis cross a "
                                              f"hole in the scan and were left out"))
    if pr.closed_gap > 0:
        reasons.append(reason("open_rim", f"the scan is open at the rim (its top was not captured): every "
                                          f"section through the axis was open and was closed across gaps up "
                                          f"to {pr.closed_gap:g} mm, as --max-gap {pr.closed_gap:g} would; "
                                          f"the rim top is the chord across the gap"))
    drop = pr.rim_drop
    if math.isfinite(drop) and drop > max(1.0, 5 * m.noise):
        reasons.append(reason("open_rim", f"the rim is broken or uneven: its top drops {drop:.1f} mm under the "
                                          f"median; the capacity is filled to its lowest point"))
    oval = pr.ovality
    if math.isfinite(oval) and oval > _OVAL_PERCENT:
        reasons.append(reason("asymmetric", f"the body is {oval:.1f} % oval (widest minus narrowest diameter "
                                            f"over the mean): diameters are medians over the angles"))
    if a is not None and a.noise > _NOISY_MM:
        reasons.append(reason("noisy", f"the scan is noisy: about {a.noise:.2f} mm on every vertex; outlines "
                                       f"were smoothed over {8 * a.noise:.1f} mm, and the wall's extremes widen"))
    if not pr.is_revolution:
        fit = ""
        if a is not None and math.isfinite(a.residual):
            fit = (f"horizontal sections stray {a.residual:.3g} mm RMS "
                   f"({100 * a.relative_residual:.3g} % of the radius) from circles about the best axis; ")
        reasons.append(reason("not_revolution", f"not a solid of revolution: {fit}half-sections differ by "
                                                f"up to {m.spread:.3g} mm"))
    return results, reasons


_OVAL_PERCENT = 1.5   # ovality (%) above which a vessel is reported asymmetric
_NOISY_MM = 0.075     # vertex noise (mm) above which a scan is reported noisy


PROFILE = Job(
    "profile", "align a vessel on its axis; draw its profile (SVG, PNG, DXF), measure it (JSON) and list its "
               "outline (CSV)",
    _profile_parameters, {"svg": "profile.svg", "png": "profile.png", "json": "profile.json",
                          "dxf": "profile.dxf", "csv": "profile.csv"},
    _profile_compute, _profile_write, _profile_report, feasible=lambda inp, p: check_planes(p["planes"]),
    # An EVE table: what the piece is, how much of a vessel it stands for and how far it can be
    # trusted, then the measurements (`slicelab.tasks.summary` gives each its unit).
    columns=("kind", "span", "rim_eve", "rim_diameter", "rim_diameter_sd", "base_eve", "axis_trusted",
             "axis_spread", "axis_confidence", "up_from", "up_confidence", "kind_confidence",
             "orientation_uncertain",
             "fragmentary", "height", "max_diameter", "base_diameter", "wall_thickness_min",
             "wall_thickness_mean", "wall_thickness_max", "base_thickness", "capacity", "clay_volume",
             "residual", "relative_residual", "spread", "ovality", "noise", "appendages", "sealed"),
)

JOBS = {job.name: job for job in (INSPECT, SECTION, LAYERS, SPLIT, PROFILE, CUT, PARTITION, SLICE)}
#: The jobs `slicelab.tasks.run_batch` runs over a folder of scans.
TASKS = ("inspect", "section", "split", "profile", "layers")


def job_parameters(name: str, **options) -> dict:
    """Check and normalise the parameters of job `name` into plain JSON values.

    Every caller (command line, `run_batch`, a script) goes through here, so
    defaults and checks live in one place. A bad value raises
    `ParameterError`, a ValueError whose message begins with the parameter.

    Examples
    --------
    >>> job_parameters("section", plane=((0, 0, 5), (0, 0, 2)))
    {'plane': {'origin': [0.0, 0.0, 5.0], 'normal': [0.0, 0.0, 2.0]}, 'max_gap': 1.0}
    >>> job_parameters("profile", planes=0)
    Traceback (most recent call last):
    ...
    slicelab.tasks.spec.ParameterError: planes must be a whole number >= 1, got 0
    """
    job = JOBS.get(name)
    if job is None:
        raise ValueError(f"unknown job {name!r}; choose one of {', '.join(JOBS)}")
    return job.check_parameters(**options)


def run_job(name: str, source, params: dict | None = None, folder=None, *, paths=None, mesh=None,
            check=None) -> JobResult:
    """Run job `name` on the mesh file `source`; write its outputs; return what it did.

    Parameters
    ----------
    name : str
        A job of `JOBS`.
    source : path
        The mesh file (loaded here unless `mesh` is given).
    params : dict, optional
        Parameters (checked by `job_parameters`; defaults when omitted).
    folder : path, optional
        Where the outputs go, under the job's own file names.
    paths : dict, optional
        Output role -> path, for outputs the caller names itself (``-o pot.svg``).
    mesh : Mesh, optional
        The loaded mesh.
    check : MeshReport, optional
        The mesh's check, if already made.

    Returns
    -------
    JobResult

    Examples
    --------
    >>> import pathlib, tempfile, slicelab
    >>> from slicelab.samples import box
    >>> d = pathlib.Path(tempfile.mkdtemp()); slicelab.save(box((0, 0, 0), (10, 10, 10)), d / "cube.stl")
    >>> r = run_job("section", d / "cube.stl", {"plane": ((0, 0, 5), (0, 0, 1))}, d / "out")
    >>> [p.name for p in r.files()], r.results["area"]
    (['section.svg'], 100.0)
    """
    job = JOBS.get(name)
    if job is None:
        raise ValueError(f"unknown job {name!r}; choose one of {', '.join(JOBS)}")
    params = dict(params or {})
    # The file's units are how it is read, not what the job does: checked here for every job.
    reading = {k: params.pop(k) for k in ("units", "scale") if params.get(k) is not None}
    params = job.check_parameters(**params)
    if reading:
        from ..mesh import UNITS
        if "units" in reading:
            choice("units", reading["units"], tuple(UNITS))
        if "scale" in reading:
            reading["scale"] = number("scale", reading["scale"], positive=True)
        params = {**params, **reading}
    if folder is not None:
        check_output_dir(folder)
    check_outputs(job, source, folder, paths)
    timings = {}
    if mesh is None:
        from ..mesh import load
        t0 = time.perf_counter()
        mesh = load(source, **reading)
        timings["load"] = time.perf_counter() - t0
    elif reading:
        from ..mesh import Mesh, unit_scale
        mesh = Mesh(mesh.triangles * unit_scale(**reading), mesh.file_normals)
    repaired = None
    if params.get("repair") or params.get("fill_holes"):
        # Repaired only when the check finds something to mend: a clean part keeps its facets as read.
        from ..mesh import check as check_mesh
        from ..mesh import repair
        t0 = time.perf_counter()
        check = check if check is not None else check_mesh(mesh)
        if params.get("fill_holes") or check.needs_repair:
            fixed = repair(mesh, fill_holes=bool(params.get("fill_holes")))
            mesh, repaired = fixed.mesh, fixed.report
            check = None if fixed.report.changed else check
        timings["repair"] = time.perf_counter() - t0
    inp = JobInput(Path(source), mesh, check, repaired)
    if job.feasible is not None:
        job.feasible(inp, params)
    t0 = time.perf_counter()
    value = job.compute(inp, params)
    t1 = time.perf_counter()
    staged = None if folder is None else StagedFolder(folder, job.name, keep=[source])
    out = Outputs(job.outputs, None if staged is None else staged.staging, paths)
    try:
        written = job.write(value, inp, params, out) or {}
        if staged is not None:
            out.moved(staged.commit())
    except BaseException:
        if staged is not None:
            staged.discard()
        raise
    t2 = time.perf_counter()
    results, reasons = job.report(value, inp, params)
    results = {**results, **written.get("results", {})}
    reasons = list(reasons) + list(written.get("reasons", []))
    if len(mesh):
        size = likely_units(float(np.ptp(mesh.bounds, axis=0).max()))
        if size is not None and not any(r["code"] == "units?" for r in reasons):
            reasons.append(reason("units?", size))
    if repaired is not None:
        results["repair"] = repaired.to_dict()
    timings.update(compute=t1 - t0, write=t2 - t1)
    return JobResult(name, inp.path, params, dict(out.written), plain(results), reasons, timings,
                     len(mesh), value)


#: The endings an output file given by name may have, by the ending of the job's own name for it.
SUFFIXES = {".gcode": (".gcode", ".gco", ".g", ".nc"), ".svg": (".svg",), ".png": (".png",), ".json": (".json",)}


def check_outputs(job, source, folder=None, paths=None) -> None:
    """Refuse, before any work, an output that would be the input file (through links too) and an
    output file named with an ending other than its kind's (G-code under ``part.3mf``).

    Examples
    --------
    >>> import pathlib, tempfile
    >>> d = pathlib.Path(tempfile.mkdtemp()); (d / "rear.stl").write_text("solid")
    5
    >>> check_outputs(JOBS["slice"], d / "rear.stl", paths={"gcode": d / "rear.3mf"})
    Traceback (most recent call last):
    ...
    ValueError: .../rear.3mf: slice writes G-code here: name it .gcode (or .gco, .g, .nc)
    >>> check_outputs(JOBS["cut"], d / "rear.stl", folder=d)   # the cut's own rear.stl
    Traceback (most recent call last):
    ...
    ValueError: .../rear.stl: is the input file; name the output otherwise
    """
    kinds = {".gcode": "G-code", ".svg": "an SVG drawing", ".png": "a PNG image", ".json": "JSON"}
    targets = []
    for role, path in (paths or {}).items():
        if path is None:
            continue
        path = Path(path)
        ending = Path(job.outputs[role]).suffix.lower()
        allowed = SUFFIXES.get(ending, (ending,))
        if path.suffix.lower() not in allowed:
            others = f" (or {', '.join(allowed[1:])})" if len(allowed) > 1 else ""
            raise ValueError(f"{path}: {job.name} writes {kinds.get(ending, ending)} here: name it "
                             f"{allowed[0]}{others}")
        targets.append(path)
    if folder is not None:  # the job's own names that are not patterns (part_NNN.stl, layer_*.svg)
        targets += [Path(folder) / n for n in job.outputs.values() if "NNN" not in n and "*" not in n]
    for path in targets:
        if same_file(path, source):
            raise ValueError(f"{path}: is the input file; name the output otherwise")
