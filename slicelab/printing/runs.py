"""A worker's share of a print: runs of consecutive layers, planned one after the other.

The planner (`slicelab.printing.planner`) cuts a part's layers into runs of
`RUN_LAYERS` and hands them to its workers a few at a time, each as a
`RunJob`: the sections of those layers and of the neighbours their skins read,
and everything else the steps need. A pool's worker needs no state from the
parent. Within a run the nozzle is carried from one layer to the next (seams);
each run starts afresh, so the paths do not depend on how runs are grouped into
calls or on the number of workers.

Each layer runs the steps of `slicelab.printing.pipeline` (`layer_inputs`,
`plan_layer`, `finish_layer`). Around them, a memo
(`slicelab.printing._reuse.Repeats`): a layer of a prismatic stretch takes
what the layer two below made when all it depends on is the same; a run that
starts as an earlier one did takes its first `START_LAYERS` layers from a
`slicelab.printing._reuse.RunStart` made once.

See Also
--------
slicelab.printing.planner.plan : the whole part, its runs spread over a pool.
slicelab.printing.pipeline.layer_paths : one layer's toolpaths, without the memo.
"""
from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import Callable

import numpy as np

from .config.settings import PrintSettings
from .fill import PATTERNS

__all__ = ["RUN_LAYERS", "START_LAYERS", "RunJob", "run_layers"]

#: Layers over which the nozzle is carried (seams): the paths' unit of work.
RUN_LAYERS = 20
#: First layers of a run made once for the runs that start alike (their toolpaths settle by then).
START_LAYERS = 6


@dataclass(frozen=True, eq=False)
class RunJob:
    """Layers ``first`` .. ``stop - 1`` of a part of ``n`` layers, and all their planning reads.

    Attributes
    ----------
    first, stop, n : int
    window : dict
        Layer index -> its section (`slicelab.slicing.sections.Section`), for these layers and
        the `bottom_layers` below and `top_layers` above them (their skins read them).
    z_tops : (stop - first,) ndarray
        The top of each of these layers (the nozzle's height).
    settings : PrintSettings
    tolerance : float
        Outlines within this many mm are the same (the memo's test, `Repeats`).
    starts : dict
        Run start -> `RunStart`, for the runs of these layers that start as an earlier one did.
    seams : list, optional
        The seam point of each of these layers (`slicelab.printing.seams.seam_targets`; None
        where loops start nearest the nozzle).
    heights : (stop - first,) ndarray, optional
        Each layer's thickness, for `layer_text`.
    extent : tuple, optional
        The plan's extent, for `layer_drawing`.
    layer_text, layer_drawing : callable, optional
        Called on the layers once planned (see `slicelab.printing.planner.plan`): their G-code
        and their drawings, made on the worker.
    """

    first: int
    stop: int
    n: int
    window: dict
    z_tops: np.ndarray
    settings: PrintSettings
    tolerance: float = 1e-9
    starts: dict = field(default_factory=dict)
    seams: list | None = None
    heights: np.ndarray | None = None
    extent: tuple | None = None
    layer_text: Callable | None = None
    layer_drawing: Callable | None = None


def run_layers(job: RunJob, state: dict | None = None) -> list:
    """The `slicelab.printing.pipeline.LayerResult` of each layer of `job`, bottom to top.

    `state`, if given, receives the nozzle's position, what the memo keeps and the solid skin
    after the last layer (what a `RunStart` holds).

    Examples
    --------
    >>> from slicelab.samples import box
    >>> from slicelab.slicing import slice_layers
    >>> s = PrintSettings(pixel_size=0.1)
    >>> sections = slice_layers(box((0, 0, 0), (6, 6, 1)), heights=[0.1, 0.3, 0.5])
    >>> job = RunJob(0, 3, 3, dict(enumerate(sections)), np.array([0.2, 0.4, 0.6]), s)
    >>> [r.index for r in run_layers(job)], [r.paths.z for r in run_layers(job)]
    ([0, 1, 2], [0.2, 0.4, 0.6])
    """
    from ._reuse import Repeats
    from .pipeline import (LayerResult, LayerWindow, OverhangSummary, at_height, finish_layer, layer_inputs, plan_layer,
                           skins_step)
    s, first, window = job.settings, job.first, job.window
    # Layers whose toolpaths the layer two above may take (not when the infill changes with height).
    repeats = Repeats(window, job.n, (s.bottom_layers + 1, s.top_layers), job.tolerance,
                      enabled=not PATTERNS[s.infill_pattern].varies_with_z or s.infill_density == 0)
    grid = LayerWindow(window, job.n, s)
    out = []
    grid.reach(first)  # (the skins of layer first - 1 read no further)
    below_solid = skins_step(first - 1, grid, s)[0] if first > 0 else None
    resume = first
    pos = None
    for k in range(first, job.stop):  # over layers
        if k < resume:
            continue
        seam = job.seams[k - first] if job.seams is not None else None
        z = job.z_tops[k - first]
        if k == first or k % RUN_LAYERS == 0:  # a run starts: the nozzle afresh
            pos = None
            repeats.clear()
            alike = job.starts.get(k)
            if alike is not None:  # a run that starts as an earlier one: what it made, at these heights
                for i, r in enumerate(alike.layers):
                    out.append(replace(r, index=k + i, paths=at_height(r.paths, job.z_tops[k + i - first])))
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
            out.append(LayerResult(k, at_height(lp, z), areas, held))
            continue
        at = pos
        grid.reach(k)  # (a layer that took the toolpaths below needs no raster, only its mask if a neighbour reads it)
        inputs, ov, below_solid = layer_inputs(k, grid, s, below_solid)
        skirt, brim, pos = _first_layer_loops(window[0], s, pos) if k == 0 else ((), (), pos)
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
            repeats.keep(k, at, seam, (inputs.solid, inputs.top), (lp, unmarked, areas, held))
        out.append(LayerResult(k, at_height(lp, z), areas, held, ov.unheld if ov is not None else ()))
    if state is not None:
        state.update(pos=pos, kept=dict(repeats.kept), below_solid=below_solid)
    return _with_outputs(out, job)


def _first_layer_loops(section, s: PrintSettings, pos):
    """The first layer's skirt and brim loops, and where the nozzle ends after them."""
    from .steps.simplify import simplify_paths
    from .steps.skirt import skirt_loops
    skirt, brim = skirt_loops(section, s.line_width, loops=s.skirt_loops, distance=s.skirt_distance,
                              brim_width=s.brim_width)
    skirt, brim = (simplify_paths(q, s.gcode_resolution) for q in (skirt, brim))
    if skirt or brim:
        pos = (list(skirt) + list(brim))[-1][-1]
    return skirt, brim, pos


def _with_outputs(out: list, job: RunJob) -> list:
    """The layers with their text and drawing, when the job asks for them."""
    layers = [r.paths for r in out]
    texts = [None] * len(out) if job.layer_text is None else job.layer_text(job.first, layers, job.heights)
    drawings = [None] * len(out) if job.layer_drawing is None else job.layer_drawing(layers, job.extent)
    return [replace(r, text=t, drawing=d) for r, t, d in zip(out, texts, drawings)]
