"""Whole-part print planning: layers, top and bottom skins, parallel toolpaths.

A part is cut once, in one vectorised pass (`slice_layers`), at the middle of
every layer: the first layer is `first_layer_height` thick, the others
`layer_height`. Layers are then independent except for one thing, the first
and last layers: a region of a layer that the `top_layers` layers above (or
the `bottom_layers` layers below) do not all cover is top (or bottom) skin,
and must be filled solid. Masks share one world-anchored pixel grid, so a
skin is a plain mask difference. Workers take runs of consecutive layers and
rasterise the few neighbours they need themselves, so nothing but sections
goes in and toolpaths come out. The first layer starts with its skirt and
brim (`slicelab.printing.steps.skirt`); a part that does not fit the printer is
refused before anything is sliced (`slicelab.printing.config.bed`).

See Also
--------
slicelab.gcode.writer.write_gcode : the plan as printer G-code.
"""
from __future__ import annotations

import gc
import math
import os
import sys
from dataclasses import astuple, dataclass, field
from functools import cached_property, partial

import numpy as np

from ..mesh.core import Mesh
from .config.bed import check_bed, footprint_extent
from .fill import PATTERNS
from ._reuse import RunStart, same_point
from .runs import RUN_LAYERS, START_LAYERS, RunJob, run_layers
from .config.settings import PrintSettings
from .pipeline import AREA_FIELDS, OVERHANG_FIELDS, records

__all__ = ["PrintPlan", "plan", "layer_bounds"]


def layer_bounds(height: float, layer_height: float, first_layer_height: float) -> np.ndarray:
    """(n, 2) bottom and top of every layer of a part `height` tall, from 0.

    The first layer is `first_layer_height` thick, the others `layer_height`;
    a layer is printed when its middle lies inside the part.

    Examples
    --------
    >>> layer_bounds(1.0, 0.3, 0.2).round(6).tolist()
    [[0.0, 0.2], [0.2, 0.5], [0.5, 0.8], [0.8, 1.1]]
    """
    if height <= 0:
        return np.zeros((0, 2))
    n = int(math.ceil(max(0.0, height - first_layer_height) / layer_height)) + 1
    tops = first_layer_height + layer_height * np.arange(n)
    bottoms = np.concatenate([[0.0], tops[:-1]])
    keep = (bottoms + tops) / 2 < height
    return np.stack([bottoms[keep], tops[keep]], axis=1)


@dataclass(frozen=True, eq=False)
class PrintPlan:
    """Every layer's toolpaths, bottom to top, with what the print will use.

    Attributes
    ----------
    settings : PrintSettings
    layers : list of LayerPaths
        ``layers[k].z`` is the top of layer k above the bed (the nozzle height).
    heights : (n,) ndarray
        Thickness of each layer.
    offset : (3,) ndarray
        Translation from the part's coordinates to the bed's (added in G-code).
    areas : (n,) record array
        Per layer (`slicelab.printing.pipeline.LayerAreas`): ``material``, the area
        inside the last perimeter ``inner`` and its ``solid`` (skin) part (mm^2), from
        the rasters, and the length of the sparse filling region's boundary
        ``fill_edge`` (mm, from its level set).
    part_volume : float
        Sum of material area x layer height (mm^3).
    overhangs : (n,) record array
        Per layer (`slicelab.printing.pipeline.OverhangSummary`): the ``area`` over nothing
        beyond the overhang threshold and not bridged (mm^2), the islands that start in
        ``mid_air``, the ``bridges``, a point (``x``, ``y``; part coordinates, NaN if none) of
        the largest unheld part, and the steepest overhang measured (``angle``, degrees from
        the vertical, 0 within the threshold).
    seconds : dict
        Time spent slicing and making the paths.
    texts : dict
        Layers whose G-code the workers formatted as they planned them (``layer_text``):
        index -> (the nozzle's start, the layer's block), taken by the G-code writer.
    extent : (4,) tuple
        ``(x0, y0, x1, y1)``, part coordinates (mm): the box of the part's footprint and of
        its skirt and brim's outer edges, which holds every path.
    drawings : dict
        Layers the workers drew as they planned them (``layer_drawing``): index -> the
        layer's SVG document, taken by `slicelab.gcode.layer_svgs.write_svgs`.
    sunk : float
        How far the part was lowered into the bed (mm) because its lowest layers held no line
        (`plan`); what lies below the bed is not printed.

    See Also
    --------
    slicelab.gcode.writer.write_gcode, slicelab.gcode.layer_svgs.write_svgs : the plan written out.
    slicelab.viz.layers.preview_png, slicelab.viz.layers.plan_3d : pictures of its layers.
    """

    settings: PrintSettings
    layers: list
    heights: np.ndarray
    offset: np.ndarray
    areas: np.ndarray
    part_volume: float = 0.0
    seconds: dict = field(default_factory=dict)
    overhangs: np.ndarray = field(default_factory=lambda: records([], OVERHANG_FIELDS))
    texts: dict = field(default_factory=dict, repr=False)
    extent: tuple = (0.0, 0.0, 0.0, 0.0)
    drawings: dict = field(default_factory=dict, repr=False)
    sunk: float = 0.0

    def warnings(self) -> list[dict]:
        """What will not print as planned, each a dict with a ``code`` and a ``message``.

        ``lowered``: the part was lowered into the bed so that its first layer prints
        (`sunk`); ``unsupported_overhang``: material over nothing beyond the overhang threshold
        that no bridge holds (no supports are made); ``mid_air``: islands that start with
        nothing under them.
        """
        ov = self.overhangs
        out = []
        if self.sunk:
            out.append({"code": "lowered", "sunk_mm": self.sunk,
                        "message": f"the part's lowest {self.sunk:.3g} mm hold no line (it touches the bed "
                                   f"at a point or an edge): it was lowered {self.sunk:.3g} mm into the bed so "
                                   f"that its first layer prints, and that much of its bottom is left out"})
        if len(ov) == 0 or self.settings.support == "auto":  # supports hold all of it
            return out
        held = " (supports stand only on the bed: those over the part are not held)" \
            if self.settings.support == "bed" else "; slicelab makes no supports unless asked (--support auto)"
        z = self.z
        hang = np.flatnonzero(ov["area"] > 0)
        if len(hang):
            k = hang[np.argmax(ov["area"][hang])]
            steepest = float(ov["angle"][hang].max())
            out.append({"code": "unsupported_overhang", "area_mm2": float(ov["area"][hang].sum()),
                        "layers": int(len(hang)), "first_z": float(z[hang[0]]), "steepest_deg": steepest,
                        "message": f"{ov['area'][hang].sum():.1f} mm2 over nothing on {len(hang)} layers "
                                   f"(from z = {z[hang[0]]:.2f} mm) overhang more than "
                                   f"{self.settings.overhang_threshold:g} degrees (up to {steepest:.0f}) "
                                   f"and no bridge holds them "
                                   f"(largest at x = {ov['x'][k]:.1f}, y = {ov['y'][k]:.1f} mm in the part's "
                                   f"coordinates){held}"})
        air = np.flatnonzero(ov["mid_air"] > 0)
        if len(air):
            out.append({"code": "mid_air", "islands": int(ov["mid_air"][air].sum()), "first_z": float(z[air[0]]),
                        "message": f"{int(ov['mid_air'][air].sum())} island(s) start in mid-air (first at z = "
                                   f"{z[air[0]]:.2f} mm) and would print onto nothing{held}"})
        return out

    def __repr__(self) -> str:
        return (f"PrintPlan({len(self.layers)} layers, print {self.print_length / 1000:.1f} m, "
                f"extruded {self.extruded_volume / 1000:.2f} cm3, filament {self.filament_length / 1000:.2f} m)")

    @property
    def z(self) -> np.ndarray:
        return np.array([lp.z for lp in self.layers])

    @cached_property
    def extruded_volume(self) -> float:
        """Volume of all extrusions (mm^3): width x layer height x length, but a bridge's round
        strand (`PrintSettings.bridge_strand`) x length; summed once (the plan's layers do not change)."""
        strand = self.settings.bridge_strand
        total = 0.0
        for lp, h in zip(self.layers, self.heights):  # over layers
            total += lp.extruded_area() * h
            for _, q, w in lp.rows(("bridge",)):  # bridges, a few rows: their strand, not w x h
                seg = np.hypot(*np.diff(q, axis=0).T)
                wm = w if np.ndim(w) == 0 else 0.5 * (np.asarray(w)[:-1] + np.asarray(w)[1:])
                total += float(np.sum(seg * (strand - wm * h)))
        return float(total)

    @cached_property
    def print_length(self) -> float:
        """Total length of the extrusion paths (mm), summed once."""
        return float(sum(lp.extrusion_length for lp in self.layers))

    @property
    def filament_length(self) -> float:
        """Filament the extrusions consume (mm)."""
        return self.extruded_volume * self.settings.extrusion_multiplier / self.settings.filament_area

    def predicted_volume(self) -> float:
        """Volume the part calls for: solid shells (perimeters, skins) plus sparse fill at its density.

        From the part's rasters and distance fields, not from the toolpaths:
        per layer, (material - inner region) + solid part of the inner region +
        density x the rest, times the layer height. Sparse lines linked into
        zigzags also run along about half of their region's boundary (every
        other gap between two lines, on each side), so half that boundary
        at one line width is added.
        """
        a = self.areas
        total, inner, solid, edge = a["material"], a["inner"], a["solid"], a["fill_edge"]
        s = self.settings
        d = s.infill_density
        links = 0.5 * edge * s.line_width if d > 0 else 0.0
        return float(np.sum(self.heights * ((total - inner) + solid + d * (inner - solid) + links)))


# Runs per call at most: a worker's call holds the rasters of its layers' neighbours.
_GROUP = 5


def plan(mesh: Mesh, settings: PrintSettings | None = None, *, workers: int | None = None,
         progress: bool | None = None, layer_text=None, layer_drawing=None) -> PrintPlan:
    """Plan a whole print: slice, find skins, make every layer's toolpaths in parallel.

    Parameters
    ----------
    mesh : Mesh
    settings : PrintSettings, optional
    workers : int, optional
        Processes (default: all cores); 1 runs in this process.
    progress : bool, optional
        Show a tqdm bar (default: when stderr is a terminal).
    layer_text : callable, optional
        ``layer_text(first, layers, heights, settings, offset)``, called by the workers on each
        run of layers they plan (a module-level function, as the pool pickles it): what it
        returns per layer, when not None, goes to `PrintPlan.texts`. The G-code writer's
        `slicelab.gcode.writer.layer_texts` formats their G-code there, on all cores. Not
        called with supports, which are added to the layers afterwards.
    layer_drawing : callable, optional
        ``layer_drawing(layers, extent)``, called by the workers likewise (extent: `PrintPlan.extent`):
        what it returns per layer goes to `PrintPlan.drawings`. The layer SVGs' own
        `slicelab.gcode.layer_svgs.layer_drawings` draws them there. Not called with supports.

    Returns
    -------
    PrintPlan

    Raises
    ------
    ValueError
        When there is nothing to print (no facets, a flat part, or a part too thin for any line:
        a plan of its skirt alone), or the part does not fit the printer (`check_bed`).

    See Also
    --------
    slicelab.printing.pipeline.layer_paths : one layer's toolpaths.
    slicelab.gcode.writer.write_gcode, slicelab.gcode.layer_svgs.write_svgs : the plan written out.
    slicelab.viz.layers.preview_png : a picture of some layers.

    Examples
    --------
    >>> from slicelab.samples import box
    >>> p = plan(box((0, 0, 0), (6, 6, 1)), PrintSettings(pixel_size=0.1), workers=1)
    >>> len(p.layers), p.z.round(3).tolist()
    (5, [0.2, 0.4, 0.6, 0.8, 1.0])
    >>> set(p.layers[0].filling_kinds)   # bottom layers are solid
    {'solid'}
    """
    s = settings or PrintSettings()
    given = dict(workers=workers, progress=progress, layer_text=layer_text, layer_drawing=layer_drawing)
    first = _plan(mesh, s, 0.0, **given)
    # A part whose lowest layers hold no line (a scan touching the bed at a point, a part on an
    # edge) would have its first extrusion laid in the air: lowered into the bed until its first
    # layer prints, it loses only layers that print nothing.
    k = next((k for k, lp in enumerate(first.layers) if any(x not in ("skirt", "brim") for x in lp.kind)), 0)
    if k > 0:
        return _plan(mesh, s, float(np.sum(first.heights[:k])), **given)
    return first


def _plan(mesh: Mesh, s: PrintSettings, sunk: float, *, workers, progress, layer_text, layer_drawing) -> PrintPlan:
    """`plan`, the part lowered `sunk` mm into the bed."""
    import time
    t0 = time.perf_counter()
    if len(mesh) == 0:
        raise ValueError("the mesh has no facets: nothing to print")
    lo, hi = mesh.bounds
    check_bed(mesh, s)
    lo = lo + np.array([0.0, 0.0, sunk])  # (the part lowered into the bed: below it, nothing prints)
    bounds = layer_bounds(float(hi[2] - lo[2]), s.layer_height, s.first_layer_height)
    if len(bounds) == 0:
        raise ValueError("the part is flat: nothing to print")
    sections = _sections(mesh, lo[2] + bounds.mean(axis=1))
    check_bed(mesh, s, first_layer=sections[0])
    t1 = time.perf_counter()
    workers = (os.cpu_count() or 1) if workers is None else max(1, int(workers))
    heights = bounds[:, 1] - bounds[:, 0]
    offset = np.array([s.centre[0] - (lo[0] + hi[0]) / 2, s.centre[1] - (lo[1] + hi[1]) / 2, -lo[2]])
    extent = footprint_extent(lo[:2], hi[:2], sections[0], s)
    # Seams: one pass up the whole part before any layer is planned (`slicelab.printing.seams`).
    from .seams import random_targets, seam_targets
    seams = seam_targets(sections) if s.seam_position == "aligned" else random_targets(sections) \
        if s.seam_position == "random" else [None] * len(sections)
    # Layers of a prism differ by the float32 rounding of the file's coordinates (walls lean by it).
    from ..mesh.repairs import default_tolerance
    # Supports are added to the layers afterwards: the workers then neither format nor draw them.
    part = _Part(sections, bounds[:, 1], heights, s, default_tolerance(mesh), seams, extent,
                 None if layer_text is None or s.support != "off" else partial(layer_text, settings=s, offset=offset),
                 None if s.support != "off" else layer_drawing)
    results = _planned(part, workers, progress)
    layers = [r.paths for r in results]
    if not any(k not in ("skirt", "brim") for lp in layers for k in lp.kind):
        size = " x ".join(f"{v:.3g}" for v in hi - lo)
        raise ValueError(f"nothing to print: the part ({size} mm) is too thin for lines {s.line_width:g} mm "
                         f"wide, or it is a surface without volume")
    areas = records([astuple(r.areas) for r in results], AREA_FIELDS)
    overhangs = records([astuple(r.overhang) for r in results], OVERHANG_FIELDS)
    if s.support != "off":
        layers = _with_supports(layers, sections, [r.unheld for r in results], s)
        # Support lines may reach a little past the footprint (drawn after planning: no layer is yet).
        pts = [q for lp in layers for q in lp.paths if len(q)]
        if pts:
            pts = np.concatenate(pts)
            extent = (*np.minimum(extent[:2], pts.min(axis=0)).tolist(), *np.maximum(extent[2:], pts.max(axis=0)).tolist())
    texts = {r.index: r.text for r in results if r.text is not None}
    drawings = {r.index: r.drawing for r in results if r.drawing is not None}
    t2 = time.perf_counter()
    return PrintPlan(s, layers, heights, offset, areas, float(np.sum(areas["material"] * heights)),
                     {"slice": t1 - t0, "paths": t2 - t1}, overhangs, texts, extent, drawings, sunk)


def _sections(mesh: Mesh, heights: np.ndarray) -> list:
    """The part's sections at `heights`, while the modules the layers need load on a thread."""
    import threading

    from ..slicing.sections import slice_layers
    # Numpy lets go of the GIL while it slices: forked workers then inherit the modules instead
    # of importing each. Loading them creates some 100,000 long-lived objects, and the garbage
    # collector would walk them all a few times over (0.2 s): it pauses meanwhile.
    collecting = gc.isenabled()
    gc.disable()
    try:
        warm = threading.Thread(target=_warm_imports, daemon=True)
        warm.start()
        sections = slice_layers(mesh, heights=heights)
        warm.join()
    finally:
        if collecting:
            gc.enable()
    return sections


@dataclass(frozen=True, eq=False)
class _Part:
    """What every run of a part reads: its sections, heights and seams, and the outputs asked for."""

    sections: list
    z_tops: np.ndarray
    heights: np.ndarray
    settings: PrintSettings
    tolerance: float
    seams: list
    extent: tuple
    layer_text: object = None
    layer_drawing: object = None

    def job(self, a: int, b: int, starts: dict, outputs: bool = True) -> RunJob:
        """Run a..b-1: its layers, the neighbours its skins read (those of a - 1 too), and the first
        layers of its runs that start as an earlier one (`starts`)."""
        s, n = self.settings, len(self.sections)
        lo, hi = max(0, a - s.bottom_layers - 1), min(n, b + s.top_layers)
        return RunJob(a, b, n, {j: self.sections[j] for j in range(lo, hi)}, self.z_tops[a:b], s, self.tolerance,
                      {k: starts[k] for k in range(a, b) if k in starts}, self.seams[a:b], self.heights[a:b],
                      self.extent, self.layer_text if outputs else None, self.layer_drawing if outputs else None)


def _planned(part: _Part, workers: int, progress) -> list:
    """Every layer's `LayerResult`, bottom to top: runs of layers on `workers` processes.

    Fixed runs of layers, whatever the number of workers: a run carries the nozzle from one
    layer to the next (seams), so the same runs give the same G-code in series. Runs go to the
    workers a few at a time (each rasterises its neighbours once), in enough calls for the
    workers to share them evenly.
    """
    from ._reuse import outline_size, start_candidates
    s, n = part.settings, len(part.sections)
    size = [outline_size(sec) for sec in part.sections]  # over layers: their areas and boundaries, once
    repeating = not PATTERNS[s.infill_pattern].varies_with_z or s.infill_density == 0
    reach = (s.bottom_layers + 1, s.top_layers)
    maybe = set(start_candidates(dict(enumerate(part.sections)), n, reach, part.tolerance, RUN_LAYERS,
                                 START_LAYERS, size)) if repeating else set()
    runs = -(-n // RUN_LAYERS)
    group = max(1, min(_GROUP, runs // (3 * workers))) if workers > 1 else _GROUP
    chunks = [(a, min(n, a + group * RUN_LAYERS)) for a in range(0, n, group * RUN_LAYERS)]
    bar = _bar(n, progress)
    results = []
    if workers == 1 or len(chunks) == 1:
        starts = _run_starts(part, maybe)
        for a, b in chunks:
            results += run_layers(part.job(a, b, starts))
            bar.update(b - a)
    else:
        from concurrent.futures import as_completed

        from .._pools import process_pool
        from ._schedule import costliest_first
        order = costliest_first(chunks, part.sections, s, part.tolerance, size)
        later = [c for c in order if any(k in maybe for k in range(c[0], c[1], RUN_LAYERS))]
        with process_pool(workers) as pool:
            # The runs that cannot start alike go first: the workers plan them while the others'
            # first layers are made here.
            futures = {pool.submit(run_layers, part.job(a, b, {})): (a, b) for a, b in order if (a, b) not in later}
            starts = _run_starts(part, maybe)
            futures.update({pool.submit(run_layers, part.job(a, b, starts)): (a, b) for a, b in later})
            for fut in as_completed(futures):
                results += fut.result()
                a, b = futures[fut]
                bar.update(b - a)
    bar.close()
    results.sort(key=lambda r: r.index)
    return results


def _run_starts(part: _Part, maybe: set) -> dict:
    """Run start -> `RunStart`, for the runs among `maybe` that start as an earlier one did (steady
    layers, the same outline and seams): their first layers, made once for all of them."""
    if not maybe:
        return {}
    from ._reuse import run_starts
    s, n = part.settings, len(part.sections)
    found = run_starts(dict(enumerate(part.sections)), n, (s.bottom_layers + 1, s.top_layers), part.tolerance,
                       RUN_LAYERS, START_LAYERS, sorted(maybe))
    # (and the same seams: the pass up the part found them at the same places)
    alike = {k: k0 for k, k0 in found.items()
             if all(same_point(part.seams[k + i], part.seams[k0 + i], part.tolerance) for i in range(START_LAYERS))}
    made = {}
    for k0 in sorted(set(alike.values())):  # over the outlines of the steady stretches, few
        state = {}
        rows = run_layers(part.job(k0, k0 + START_LAYERS, {}, outputs=False), state)
        made[k0] = RunStart(tuple(rows), state["pos"], state["kept"], state["below_solid"])
    return {k: made[k0] for k, k0 in alike.items()}


def _with_supports(layers: list, sections: list, unheld: list, s: PrintSettings) -> list:
    """The layers with their support material printed after the skirt and before the islands."""
    from .supports import support_lines
    rows = support_lines(sections, unheld, s)
    return [lp.inserted(sum(k in ("skirt", "brim") for k in lp.kind), [(k, q, lp.line_width) for k, q in extra])
            for lp, extra in zip(layers, rows)]  # over layers


def _warm_imports() -> None:
    import cv2  # noqa: F401
    import shapely  # noqa: F401

    from ..geometry.kernels import warm
    from .fill import lines  # noqa: F401  (the patterns load with the registry)
    from .grid import distance, raster  # noqa: F401
    from . import pipeline  # noqa: F401
    from .steps import filling, order, overhangs, perimeters, simplify, skins, skirt  # noqa: F401
    warm()  # the compiled kernels, loaded (or compiled, once) before the workers fork


def _bar(total: int, progress: bool | None):
    """A tqdm bar over the layers, or, when there is none to show, a stand-in that does nothing
    (so a command whose output is not a terminal does not import tqdm)."""
    disable = (not sys.stderr.isatty()) if progress is None else not progress
    if disable:
        return _NoBar()
    from tqdm import tqdm
    return tqdm(total=total, unit="layer", desc="planning", leave=False)


class _NoBar:
    def update(self, n: int = 1) -> None:
        pass

    def close(self) -> None:
        pass
