"""Per-layer SVG drawings of a print plan, written by a pool of processes when there are many.

Each layer is one SVG file at true scale (mm), every path drawn at its width
and coloured by its role (`slicelab.toolpath.roles.STYLES`, the colours of
PrusaSlicer's G-code viewer), in print order. Every layer is drawn on the
same page, so the files can be flipped through as a stack. A layer takes
about half a millisecond to draw; a plan of more than some 200 layers has
its runs of layers drawn by forked processes, which write their files
themselves (`slicelab.toolpath.pool.forked_pool`).

See Also
--------
slicelab.export.gcode.write_gcode : the same paths as G-code.
slicelab.viz.layers.preview_png : a few layers in one PNG.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

from ..toolpath.roles import STYLES
from .svg import SvgDrawing

__all__ = ["write_svgs"]

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


def write_svgs(plan, directory, *, workers: int | None = None) -> list:
    """One SVG per layer (true scale, paths drawn at their widths, coloured by role).

    Every layer is drawn on the same page: the box of all the paths (part
    coordinates, mm) widened by 2 mm.

    Parameters
    ----------
    plan : PrintPlan
    directory : str or Path
        Created if missing.
    workers : int, optional
        Processes drawing the layers (default: all cores when the plan has more
        than five runs of `_SVG_RUN` layers, else 1: below some 200 layers, starting
        a pool and sending it the layers costs more than it saves); the files are
        the same for any number.

    Returns
    -------
    list of Path
        The files written, bottom layer first.

    See Also
    --------
    slicelab.export.gcode.write_gcode : the same paths as G-code.
    slicelab.export.svg.SvgDrawing : the SVG writer.

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
    pts = [q for lp in plan.layers for _, q, _ in lp.ordered()]
    if not pts:
        return []
    allp = np.concatenate(pts)
    lo, hi = allp.min(axis=0) - 2, allp.max(axis=0) + 2
    page = (lo[0], lo[1], hi[0], hi[1])
    n = len(plan.layers)
    width = max(4, len(str(n)))
    paths = [d / f"layer_{k:0{width}d}_z{lp.z:.3f}.svg" for k, lp in enumerate(plan.layers)]
    runs = [range(a, min(n, a + _SVG_RUN)) for a in range(0, n, _SVG_RUN)]
    if workers is None:
        workers = (os.cpu_count() or 1) if len(runs) > 5 else 1
    if workers <= 1 or len(runs) < 2:
        _write_run(plan.layers, paths, page)
        return paths
    from ..toolpath.pool import forked_pool
    with forked_pool(min(int(workers), len(runs))) as pool:
        futures = [pool.submit(_write_run, [plan.layers[k] for k in run], [paths[k] for k in run], page)
                   for run in runs]
        for fut in futures:
            fut.result()
    return paths
