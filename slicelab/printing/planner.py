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
from dataclasses import astuple, dataclass, field, replace
from functools import cached_property, partial

import numpy as np

from ..mesh.core import Mesh
from .config.bed import check_bed, footprint_extent
from .fill import PATTERNS
from ._reuse import RunStart, same_point
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
        """Volume of all extrusions, width x layer height x length (mm^3); summed once (the plan's
        layers do not change)."""
        return float(sum(lp.extruded_area() * h for lp, h in zip(self.layers, self.heights)))

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


# ------------------------------------------------------------------ workers
_RUN = 20  # layers over which the nozzle is carried (seams), the paths' unit of work
_START = 6  # first layers of a run made once for the runs that start alike (their toolpaths settle by then)
_GROUP = 5  # runs per call at most: a worker's call holds the rasters of its layers' neighbours


def _run_chunk(first: int, stop: int, n: int, window: dict, z_tops: np.ndarray, s: PrintSettings,
               layer_text=None, heights=None, layer_drawing=None, extent=None, repeat_tolerance: float = 1e-9,
               starts: dict | None = None, seams=None, state: dict | None = None) -> list:
    """The `LayerResult` of layers first..stop-1 of n (with, given `layer_text` and `layer_drawing`,
    their text and drawings: see `plan`).

    `window` maps a layer's index to its section for these layers and the
    `bottom_layers` below and `top_layers` above them (their skins need them);
    `z_tops` are the tops of these layers. The nozzle is carried from one layer to the
    next within each run of `_RUN` layers (and from `first`) and starts afresh at each run,
    so the paths do not depend on how runs are grouped into calls. Each layer runs the steps of
    `slicelab.printing.pipeline` (`layer_inputs`, `plan_layer`, `finish_layer`). Around them, a
    memo (`slicelab.printing._reuse.Repeats`): a layer of a prismatic stretch takes what the
    layer two below made when all it depends on is the same (outlines within `repeat_tolerance`
    mm), within a run of layers; a run that starts as an earlier one did takes its first layers
    from `starts` (run start -> `RunStart`). `seams` are the seam points of these layers
    (`slicelab.printing.seams.seam_targets`, None where loops start nearest the nozzle or at the
    rear). Everything comes as arguments: a pool's worker needs no state from the parent.
    `state`, if given, receives the nozzle's position, what the memo keeps and the solid skin
    after the last layer.
    """
    from ._reuse import Repeats
    from .pipeline import LayerResult, LayerWindow, OverhangSummary, at_height, finish_layer, layer_inputs, plan_layer
    from .steps.simplify import simplify_paths
    from .steps.skins import layer_skins
    from .steps.skirt import skirt_loops
    # Layers whose toolpaths the layer two above may take (not when the infill changes with height).
    repeats = Repeats(window, n, (s.bottom_layers + 1, s.top_layers), repeat_tolerance,
                      enabled=not PATTERNS[s.infill_pattern].varies_with_z or s.infill_density == 0)
    grid = LayerWindow(window, n, s)
    out = []
    grid.reach(first)  # (the skins of layer first - 1 read no further)
    below_solid = layer_skins(first - 1, grid.masks, s.skins, s.line_width)[0] if first > 0 else None
    resume = first
    for k in range(first, stop):  # over layers
        if k < resume:
            continue
        seam = seams[k - first] if seams is not None else None
        if k == first or k % _RUN == 0:  # a run starts: the nozzle afresh
            pos = None
            repeats.clear()
            alike = starts.get(k) if starts else None
            if alike is not None:  # a run that starts as an earlier one: what it made, at these heights
                for i, r in enumerate(alike.layers):
                    out.append(replace(r, index=k + i, paths=at_height(r.paths, z_tops[k + i - first])))
                pos, below_solid = alike.pos, alike.below_solid
                repeats.kept.update(alike.kept)
                resume = k + len(alike.layers)
                continue
        taken = repeats.take(k, pos, seam)  # (a steady layer: before its raster and skins)
        if taken is not None:  # the layer two below again: the same toolpaths, at this height
            lp, _, areas, held = taken
            items = list(lp.ordered())
            pos = items[-1][1][-1] if items else pos
            below_solid = None
            out.append(LayerResult(k, at_height(lp, z_tops[k - first]), areas, held))
            continue
        at, below = pos, seam
        grid.reach(k)  # (a layer that took the toolpaths below needs no raster, only its mask if a neighbour reads it)
        inputs, ov, solid = layer_inputs(k, grid, s, below_solid)
        below_solid = solid
        skirt = brim = ()
        if k == 0:
            skirt, brim = skirt_loops(window[0], s.line_width, loops=s.skirt_loops, distance=s.skirt_distance,
                                      brim_width=s.brim_width)
            skirt, brim = (simplify_paths(q, s.gcode_resolution) for q in (skirt, brim))
            if skirt or brim:
                pos = (list(skirt) + list(brim))[-1][-1]
        # With no bridge and nothing unheld, a layer with the outline, skins, start and seam of the
        # layer two below makes what it made (a step within the skins' reach above or below).
        plain = k > 0 and not inputs.bridges and not (ov is not None and len(ov.unheld))
        made = repeats.take(k, pos, seam, (inputs.solid, inputs.top)) if plain else None
        if made is not None:
            _, lp, areas, _ = made  # (its toolpaths before the layer below marked them)
        else:
            planned = plan_layer(window[k], s, inputs, start=pos, seam=seam)
            lp, areas = planned.paths, planned.areas
        unmarked = lp
        lp = finish_layer(k, grid, s, lp, skirt, brim)
        items = list(lp.ordered())
        if items:
            pos = items[-1][1][-1]
        held = OverhangSummary.of(ov)
        if plain:  # for the layer two above: the toolpaths as marked here and before marking
            repeats.keep(k, at, below, (inputs.solid, inputs.top), (lp, unmarked, areas, held))
        out.append(LayerResult(k, at_height(lp, z_tops[k - first]), areas, held,
                               ov.unheld if ov is not None else ()))
    if state is not None:
        state.update(pos=pos, kept=dict(repeats.kept), below_solid=below_solid)
    layers = [r.paths for r in out]
    texts = [None] * len(out) if layer_text is None else layer_text(first, layers, heights)
    drawings = [None] * len(out) if layer_drawing is None else layer_drawing(layers, extent)
    return [replace(r, text=t, drawing=d) for r, t, d in zip(out, texts, drawings)]


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

    from ..slicing.sections import slice_layers
    t0 = time.perf_counter()
    if len(mesh) == 0:
        raise ValueError("the mesh has no facets: nothing to print")
    lo, hi = mesh.bounds
    check_bed(mesh, s)
    lo = lo + np.array([0.0, 0.0, sunk])  # (the part lowered into the bed: below it, nothing prints)
    bounds = layer_bounds(float(hi[2] - lo[2]), s.layer_height, s.first_layer_height)
    if len(bounds) == 0:
        raise ValueError("the part is flat: nothing to print")
    # The modules the layers need load on a thread while the part is sliced (numpy lets go of
    # the GIL): forked workers then inherit them instead of importing each.
    # Loading them creates some 100,000 long-lived objects, and the garbage collector would walk
    # them all a few times over (0.2 s): it pauses meanwhile.
    import threading
    collecting = gc.isenabled()
    gc.disable()
    try:
        warm = threading.Thread(target=_warm_imports, daemon=True)
        warm.start()
        sections = slice_layers(mesh, heights=lo[2] + bounds.mean(axis=1))
        warm.join()
    finally:
        if collecting:
            gc.enable()
    check_bed(mesh, s, first_layer=sections[0])
    t1 = time.perf_counter()
    n = len(sections)
    workers = (os.cpu_count() or 1) if workers is None else max(1, int(workers))
    z_tops = bounds[:, 1]

    heights = bounds[:, 1] - bounds[:, 0]
    offset = np.array([s.centre[0] - (lo[0] + hi[0]) / 2, s.centre[1] - (lo[1] + hi[1]) / 2, -lo[2]])
    text = None if layer_text is None or s.support != "off" else partial(layer_text, settings=s, offset=offset)
    drawing = None if s.support != "off" else layer_drawing
    extent = footprint_extent(lo[:2], hi[:2], sections[0], s)
    # Seams: one pass up the whole part before any layer is planned (`slicelab.printing.seams`).
    from .seams import seam_targets
    seams = seam_targets(sections) if s.seam_position == "aligned" else [None] * n
    # Layers of a prism differ by the float32 rounding of the file's coordinates (walls lean by it).
    from ..mesh.repairs import default_tolerance
    tol = default_tolerance(mesh)

    # Runs that start as an earlier one did (steady layers, the same outline): their first layers
    # are made once, here, for all of them (`make_starts`).
    from ._reuse import outline_size, run_starts, start_candidates
    size = [outline_size(sec) for sec in sections]  # over layers: their areas and boundaries, once
    reach = (s.bottom_layers + 1, s.top_layers)
    repeating = not PATTERNS[s.infill_pattern].varies_with_z or s.infill_density == 0
    maybe = set(start_candidates(dict(enumerate(sections)), n, reach, tol, _RUN, _START, size)) if repeating \
        else set()
    alike, made = {}, {}

    def job(a, b, text=text, drawing=drawing):
        """The arguments of run a..b-1: its layers, the neighbours its skins look at and the first
        layers of its runs that start as an earlier one."""
        lo, hi = max(0, a - s.bottom_layers - 1), min(n, b + s.top_layers)  # (the skins of a - 1 too)
        starts = {k: made[alike[k]] for k in range(a, b) if k in alike and alike[k] in made}
        return (a, b, n, {j: sections[j] for j in range(lo, hi)}, z_tops[a:b], s, text, heights[a:b], drawing,
                extent, tol, starts, seams[a:b])

    def make_starts():
        if maybe:
            found = run_starts(dict(enumerate(sections)), n, reach, tol, _RUN, _START, sorted(maybe))
            # (and the same seams: the pass up the part found them at the same places)
            alike.update({k: k0 for k, k0 in found.items()
                          if all(same_point(seams[k + i], seams[k0 + i], tol) for i in range(_START))})
        for k0 in sorted(set(alike.values())):  # over the outlines of the steady stretches, few
            state = {}
            rows = _run_chunk(*job(k0, k0 + _START, None, None), state=state)
            made[k0] = RunStart(tuple(rows), state["pos"], state["kept"], state["below_solid"])

    def may_need_starts(chunk):
        return any(k in maybe for k in range(chunk[0], chunk[1], _RUN))

    results = []
    # Fixed runs of layers, whatever the number of workers: a run carries the nozzle from
    # one layer to the next (seams), so the same runs give the same G-code in series. Runs go
    # to the workers a few at a time (each rasterises its neighbours once), in enough calls
    # for the workers to share them evenly.
    runs = -(-n // _RUN)
    group = max(1, min(_GROUP, runs // (3 * workers))) if workers > 1 else _GROUP
    chunks = [(a, min(n, a + group * _RUN)) for a in range(0, n, group * _RUN)]
    if workers == 1 or len(chunks) == 1:
        bar = _bar(n, progress)
        make_starts()
        for a, b in chunks:
            results += _run_chunk(*job(a, b))
            bar.update(b - a)
        bar.close()
    else:
        from concurrent.futures import as_completed

        from .._pools import process_pool
        from ._schedule import costliest_first
        bar = _bar(n, progress)
        order = costliest_first(chunks, sections, s, tol, size)
        with process_pool(workers) as pool:
            # The runs that cannot start alike go first: the workers plan them while the others'
            # first layers are made here.
            futures = {pool.submit(_run_chunk, *job(a, b)): (a, b) for a, b in order if not may_need_starts((a, b))}
            make_starts()
            futures.update({pool.submit(_run_chunk, *job(a, b)): (a, b) for a, b in order if may_need_starts((a, b))})
            for fut in as_completed(futures):
                results += fut.result()
                a, b = futures[fut]
                bar.update(b - a)
        bar.close()
    results.sort(key=lambda r: r.index)
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
