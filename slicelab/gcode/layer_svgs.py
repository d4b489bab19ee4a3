"""Per-layer SVG drawings of a print plan, drawn by the planner's workers or a pool of processes.

Each layer is one SVG file at true scale (mm), every path drawn at its width
and coloured by its role (`slicelab.printing.roles.STYLES`, the colours of
PrusaSlicer's G-code viewer), in print order. Every layer is drawn on the
same page, the plan's extent (`PrintPlan.extent`: the footprint and the
skirt) widened by 2 mm, so the files can be flipped through as a stack and a
layer can be drawn before the others are planned. A layer takes about half a
millisecond to draw: `slicelab slice --preview` has the planner's workers
draw each layer as they plan it (`layer_drawings`, the planner's
``layer_drawing``), and only the files are written afterwards; otherwise a
plan of more than some 200 layers has its runs of layers drawn by forked
processes, which write their files themselves
(`slicelab._pools.process_pool`).

See Also
--------
slicelab.gcode.writer.write_gcode : the same paths as G-code.
slicelab.viz.layers.preview_png : a few layers in one PNG.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

from ..printing.roles import STYLES
from ..files.atomic import atomic_open
from ..files.svg import SvgDrawing

__all__ = ["write_svgs", "layer_drawings", "svg_page"]

#: Layers per task when processes draw the layers.
_SVG_RUN = 40


def _svg_layer(lp, page) -> SvgDrawing:
    """One layer's drawing: every path at its width, coloured by role, in print order."""
    svg = SvgDrawing(page, desc=f"slicelab layer z={lp.z:.3f}", digits=3)
    pieces = list(lp.pieces())
    # (a row's width is one number, or one per segment: np.mean only for the latter)
    svg.paths([path for _, path, _ in pieces],
              [(STYLES[kind].gcode_type, {"fill": "none", "stroke": STYLES[kind].colour,
                                          "stroke_width": float(w) if np.ndim(w) == 0 else float(np.mean(w)),
                                          "stroke_linecap": "round", "stroke_linejoin": "round", "stroke_opacity": 0.85})
               for kind, _, w in pieces])
    return svg


def _write_run(layers: list, paths: list, page: tuple) -> None:
    """Draw some layers into their files (a pool's task: its inputs come as arguments)."""
    for lp, path in zip(layers, paths):  # over layers
        _svg_layer(lp, page).write(path)


def svg_page(extent) -> tuple:
    """The page every layer of a plan is drawn on: its extent (`PrintPlan.extent`) widened by 2 mm.

    Examples
    --------
    >>> svg_page((0, 0, 10, 5))
    (-2.0, -2.0, 12.0, 7.0)
    """
    x0, y0, x1, y1 = (float(v) for v in extent)
    return (x0 - 2, y0 - 2, x1 + 2, y1 + 2)


def layer_drawings(layers: list, extent) -> list[str]:
    """The SVG documents of some layers of a plan whose extent is `extent` (see `write_svgs`).

    The planner's workers call it on each run of layers as they plan them
    (`slicelab.printing.planner.plan`'s ``layer_drawing``); `write_svgs`
    then writes these documents as they are.

    Examples
    --------
    >>> import slicelab
    >>> from slicelab.samples import box
    >>> p = slicelab.plan(box((0, 0, 0), (5, 5, 0.6)), slicelab.PrintSettings(pixel_size=0.1), workers=1,
    ...                   layer_drawing=layer_drawings)
    >>> sorted(p.drawings) == [0, 1, 2], "<title>External perimeter</title>" in p.drawings[1]
    (True, True)
    """
    page = svg_page(extent)
    return [_svg_layer(lp, page).to_string() for lp in layers]


def write_svgs(plan, directory, *, workers: int | None = None) -> list:
    """One SVG per layer (true scale, paths drawn at their widths, coloured by role).

    Every layer is drawn on the same page (`svg_page`): the plan's extent (part
    coordinates, mm: the footprint and the skirt's outer edge) widened by 2 mm.
    Layers the planner's workers drew already (`PrintPlan.drawings`) are written
    as they are.

    Parameters
    ----------
    plan : PrintPlan
    directory : str or Path
        Created if missing.
    workers : int, optional
        Processes drawing the layers not drawn yet (default: all cores when more
        than five runs of `_SVG_RUN` layers are left, else 1: below some 200 layers,
        starting a pool and sending it the layers costs more than it saves); the
        files are the same for any number, and drawn ahead or not.

    Returns
    -------
    list of Path
        The files written, bottom layer first.

    See Also
    --------
    slicelab.gcode.writer.write_gcode : the same paths as G-code.
    slicelab.files.svg.SvgDrawing : the SVG writer.

    Examples
    --------
    >>> import slicelab, tempfile
    >>> from slicelab.samples import box
    >>> p = slicelab.plan(box((0, 0, 0), (5, 5, 0.6)), slicelab.PrintSettings(pixel_size=0.1), workers=1)
    >>> files = write_svgs(p, tempfile.mkdtemp())
    >>> len(files), files[0].name, "<title>External perimeter</title>" in files[0].read_text()
    (3, 'layer_0000_z0.200.svg', True)
    """
    import os
    d = Path(directory)
    d.mkdir(parents=True, exist_ok=True)
    if not any(lp.paths for lp in plan.layers):
        return []
    page = svg_page(plan.extent)
    n = len(plan.layers)
    width = max(4, len(str(n)))
    paths = [d / f"layer_{k:0{width}d}_z{lp.z:.3f}.svg" for k, lp in enumerate(plan.layers)]
    drawn = plan.drawings
    for k in [k for k in range(n) if k in drawn]:  # over layers drawn ahead: only their files are left
        with atomic_open(paths[k], "w", encoding="utf-8") as fh:
            fh.write(drawn[k])
    left = [k for k in range(n) if k not in drawn]
    runs = [left[a:a + _SVG_RUN] for a in range(0, len(left), _SVG_RUN)]
    if workers is None:
        workers = (os.cpu_count() or 1) if len(runs) > 5 else 1
    if workers <= 1 or len(runs) < 2:
        _write_run([plan.layers[k] for k in left], [paths[k] for k in left], page)
        return paths
    from .._pools import process_pool
    with process_pool(min(int(workers), len(runs))) as pool:
        futures = [pool.submit(_write_run, [plan.layers[k] for k in run], [paths[k] for k in run], page)
                   for run in runs]
        for fut in futures:
            fut.result()
    return paths
