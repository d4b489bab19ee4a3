"""Figures of layers and print plans (matplotlib, imported lazily by the functions).

Each plotting helper draws on a given Axes (or a new one) and returns the
Axes; `preview_png` draws a few layers of a plan into a PNG file with OpenCV
(`slicelab.viz.canvas`), without matplotlib. Paths are coloured by role from
`slicelab.printing.roles.STYLES`.
"""
from __future__ import annotations

import math

import numpy as np

from ..printing.roles import STYLES

__all__ = ["plot_raster", "plot_distance", "plot_toolpath", "plot_coverage", "plan_3d", "preview_png"]


def _axes(ax):
    if ax is None:
        import matplotlib.pyplot as plt
        _, ax = plt.subplots(figsize=(6, 6))
    ax.set_aspect("equal")
    return ax


def _legend(ax):
    """A legend with one entry per label, upper right (none when nothing is labelled)."""
    handles, labels = ax.get_legend_handles_labels()
    uniq = dict(zip(labels, handles))
    if uniq:
        ax.legend(uniq.values(), uniq.keys(), loc="upper right", fontsize=8)


def _plot_rings(ax, polygons, **style):
    """Every ring (exterior and holes) of `polygons`, closed, in one style."""
    for p in polygons:
        for r in (p.exterior, *p.holes):
            q = np.vstack([r, r[:1]])
            ax.plot(q[:, 0], q[:, 1], **style)


# ------------------------------------------------------------- layer rasters and paths
def plot_raster(raster, hierarchy=None, ax=None, *, cmap="tab10"):
    """The material mask with its contour tree, each contour coloured by depth.

    Examples
    --------
    >>> import matplotlib; matplotlib.use("Agg")
    >>> import slicelab
    >>> from slicelab.samples import nested_shells
    >>> r = slicelab.rasterize(slicelab.section(nested_shells(), (0, 0, 20), (0, 0, 1)), 0.5)
    >>> ax = plot_raster(r)
    >>> len(ax.lines)
    3
    """
    import matplotlib.pyplot as plt

    from ..printing.grid.hierarchy import raster_hierarchy
    ax = _axes(ax)
    from ..printing.grid.masks import GridMask
    for tile in raster.tiles:  # each island in its own box (far-apart islands share a tile)
        boxes = raster.island_boxes.tolist() or [(tile.row0, tile.col0, tile.row0 + tile.shape[0] - 1,
                                                  tile.col0 + tile.shape[1] - 1)]
        for r0, c0, r1, c1 in boxes:
            win = GridMask(tile.window(r0, c0, (r1 - r0 + 1, c1 - c0 + 1)), r0, c0, raster.pixel_size)
            ax.imshow(win.mask, origin="lower", extent=win.extent, cmap="Greys", vmin=0, vmax=2,
                      interpolation="nearest")
    h = raster_hierarchy(raster) if hierarchy is None else hierarchy
    colours = plt.get_cmap(cmap)
    for c, d in zip(h.contours, h.depth):
        ring = np.vstack([c, c[:1]])
        ax.plot(ring[:, 0], ring[:, 1], color=colours(int(d) % 10), lw=1.2, label=f"depth {d}")
    _legend(ax)
    ax.set_xlabel("x (mm)")
    ax.set_ylabel("y (mm)")
    return ax


def plot_distance(perimeters, ax=None, *, tile: int = 0, cmap="magma"):
    """The distance field of one tile with the perimeter levels and the filling's limit.

    Examples
    --------
    >>> import matplotlib; matplotlib.use("Agg")
    >>> from slicelab import layer_perimeters, section
    >>> from slicelab.samples import box
    >>> per = layer_perimeters(section(box((0, 0, 0), (4, 3, 1)), (0, 0, .5), (0, 0, 1)), pixel_size=0.1)
    >>> ax = plot_distance(per)
    >>> len(ax.images)
    1
    """
    ax = _axes(ax)
    f = per_field = perimeters.fields[tile]
    vals = np.where(per_field.grid.mask, f.values, np.nan)
    im = ax.imshow(vals, origin="lower", extent=f.grid.extent, cmap=cmap, interpolation="nearest")
    ax.figure.colorbar(im, ax=ax, shrink=0.7, label="distance to the boundary (mm)")
    for k, polys in enumerate(perimeters.rings):
        _plot_rings(ax, polys, color="cyan", lw=0.8,
                    label=f"perimeters ({len(perimeters.levels)})" if k == 0 else None)
    _plot_rings(ax, perimeters.fill, color="lime", lw=0.8, ls="--", label="filling limit")
    _plot_rings(ax, perimeters.solid, color="white", lw=0.8, ls="--", label="solid filling limit")
    for g in perimeters.gap_fill:
        ax.plot(g[:, 0], g[:, 1], color="deepskyblue", lw=1.5, label="gap fill")
    _legend(ax)
    return ax


def plot_toolpath(paths, ax=None, *, cmap="viridis", lw: float = 1.0, travel: bool = True):
    """Every extrusion coloured by print order, travel moves dotted.

    Examples
    --------
    >>> import matplotlib; matplotlib.use("Agg")
    >>> import slicelab
    >>> from slicelab.samples import box
    >>> lp = slicelab.layer_paths(slicelab.section(box((0, 0, 0), (4, 3, 1)), (0, 0, .5), (0, 0, 1)),
    ...                           slicelab.PrintSettings(pixel_size=0.1))
    >>> ax = plot_toolpath(lp)
    """
    import matplotlib.pyplot as plt
    from matplotlib.collections import LineCollection
    ax = _axes(ax)
    items = list(paths.ordered())
    colours = plt.get_cmap(cmap)(np.linspace(0, 1, max(len(items), 1)))
    segs, cols, moves = [], [], []
    prev = None
    for k, (_, q, _) in enumerate(items):
        segs.append(q)
        cols.append(colours[k])
        if prev is not None:
            moves.append(np.stack([prev, q[0]]))
        prev = q[-1]
    ax.add_collection(LineCollection(segs, colors=cols, linewidths=lw))
    if travel and moves:
        ax.add_collection(LineCollection(moves, colors="red", linewidths=0.6, linestyles=":"))
    if items:
        allp = np.concatenate(segs)
        ax.set_xlim(allp[:, 0].min() - 1, allp[:, 0].max() + 1)
        ax.set_ylim(allp[:, 1].min() - 1, allp[:, 1].max() + 1)
    sm = plt.cm.ScalarMappable(cmap=cmap, norm=plt.Normalize(0, max(len(items) - 1, 1)))
    ax.figure.colorbar(sm, ax=ax, shrink=0.7, label="print order")
    ax.set_title(f"extrusion {paths.extrusion_length:.0f} mm, travel {paths.travel_length:.0f} mm (dotted)")
    return ax


def plot_coverage(paths, raster=None, ax=None, *, pixel_size: float | None = None):
    """Coverage of the layer by its extrusions drawn at their widths: gaps and double coverage.

    Pixels of material (from `raster`, whose pixel size is then used) that
    nothing covers show red; once covered, light; twice or more, dark.

    Examples
    --------
    >>> import matplotlib; matplotlib.use("Agg")
    >>> import slicelab
    >>> from slicelab.samples import box
    >>> s = slicelab.section(box((0, 0, 0), (4, 3, 1)), (0, 0, .5), (0, 0, 1))
    >>> ax = plot_coverage(slicelab.layer_paths(s, slicelab.PrintSettings(pixel_size=0.1)), slicelab.rasterize(s, 0.1))
    """
    from matplotlib.colors import ListedColormap

    from ..printing.steps.coverage import coverage_map
    ax = _axes(ax)
    p = raster.pixel_size if raster is not None else (pixel_size or 0.1)
    counts, grid = coverage_map(paths, p)
    img = np.minimum(counts, 3).astype(float)
    if raster is not None:
        material = raster.combined().window(grid.row0, grid.col0, grid.shape)
        img[(counts == 0) & ~material] = np.nan
        img[(counts == 0) & material] = 0
        gaps = float(np.count_nonzero((counts == 0) & material)) * p * p
        double = float(np.count_nonzero(counts >= 2)) * p * p
        ax.set_title(f"gaps {gaps:.3g} mm2 ({100 * gaps / max(raster.area, 1e-12):.2f}%), "
                     f"double {double:.3g} mm2")
    else:
        img[counts == 0] = np.nan
    cmap = ListedColormap(["red", "#cfe3f5", "#3b6ea8", "#0b2545"])
    ax.imshow(img, origin="lower", extent=grid.extent, cmap=cmap, vmin=-0.5, vmax=3.5, interpolation="nearest")
    return ax


# ------------------------------------------------------------- print plans
def plan_3d(plan, layers=None, ax=None, *, lw: float = 0.5, elev: float = 25, azim: float = -60):
    """The extrusion paths of a range of layers in 3-D, coloured by role.

    Examples
    --------
    >>> import matplotlib; matplotlib.use("Agg")
    >>> import slicelab
    >>> from slicelab.samples import box
    >>> p = slicelab.plan(box((0, 0, 0), (4, 4, 1)), slicelab.PrintSettings(pixel_size=0.1), workers=1)
    >>> ax = plan_3d(p, range(0, 5, 2))

    See Also
    --------
    preview_png : layers side by side, in a file.
    """
    import matplotlib.pyplot as plt
    from mpl_toolkits.mplot3d.art3d import Line3DCollection
    if ax is None:
        fig = plt.figure(figsize=(7, 6))
        ax = fig.add_subplot(projection="3d")
    layers = range(len(plan.layers)) if layers is None else layers
    segs, cols = [], []
    for k in layers:
        lp = plan.layers[k]
        for kind, q, _ in lp.pieces():
            segs.append(np.column_stack([q, np.full(len(q), lp.z)]))
            cols.append(STYLES[kind].plot_colour)
    if segs:
        ax.add_collection3d(Line3DCollection(segs, colors=cols, linewidths=lw))
        allp = np.concatenate(segs)
        lo, hi = allp.min(axis=0), allp.max(axis=0)
        span = max(hi[0] - lo[0], hi[1] - lo[1]) / 2
        mid = (lo + hi) / 2
        ax.set_xlim(mid[0] - span, mid[0] + span)
        ax.set_ylim(mid[1] - span, mid[1] + span)
        ax.set_zlim(lo[2] - 0.1, hi[2] + 0.1)
    ax.view_init(elev=elev, azim=azim)
    ax.set_xlabel("x (mm)")
    ax.set_ylabel("y (mm)")
    ax.set_zlabel("z (mm)")
    return ax


def preview_png(plan, path, layers=None, *, pixels: int = 400) -> dict:
    """Draw some layers' toolpaths side by side into a PNG (roles coloured, travel in grey).

    Composed as a pixel array with OpenCV (`slicelab.viz.canvas`), not a
    matplotlib figure, whose import and layout cost `slicelab slice --preview`
    some 0.4 s (measured by hand): each panel is framed, with millimetre ticks, and titled with
    its layer and height; paths are drawn in their roles' colours
    (`slicelab.printing.roles.STYLES`), a colour at a time, over the travel
    between them.

    Parameters
    ----------
    plan : PrintPlan
    path : str or Path
        Written atomically.
    layers : sequence of int, optional
        Default: the first layer, a quarter of the way up, the middle and the top.
    pixels : int, default 400
        Size of the longer side of each panel.

    Returns
    -------
    dict
        ``"panels"``: each layer's panel ``(x, y, width, height)`` in pixels (top-left corner
        first); ``"extent"``: the ``(x_min, x_max, y_min, y_max)`` (mm, part coordinates) each shows.

    See Also
    --------
    plan_3d : the layers in 3-D.
    plot_toolpath : one layer on a matplotlib Axes.
    slicelab.gcode.layer_svgs.write_svgs : every layer at true scale.

    Examples
    --------
    >>> import slicelab, tempfile, os
    >>> from slicelab.samples import box
    >>> p = slicelab.plan(box((0, 0, 0), (4, 4, 1)), slicelab.PrintSettings(pixel_size=0.1), workers=1)
    >>> out = os.path.join(tempfile.mkdtemp(), "p.png")
    >>> preview_png(p, out, [0, 4], pixels=100)["panels"]
    [(70, 40, 100, 100), (225, 40, 100, 100)]
    >>> open(out, "rb").read(4)
    b'\\x89PNG'
    """
    from ..files.atomic import atomic_path
    from .canvas import Canvas
    n = len(plan.layers)
    if layers is None:
        layers = sorted({0, n // 4, n // 2, n - 1}) if n else []
    layers = [k for k in layers if 0 <= k < n]
    if not layers:
        raise ValueError("no layer to draw")
    cols = min(4, len(layers))
    rows = math.ceil(len(layers) / cols)
    left, gap, top, bottom, right = 70, 55, 40, 40, 15
    size = int(pixels)
    canvas = Canvas(left + cols * size + (cols - 1) * gap + right, top + rows * (size + top + bottom) - top)
    boxes, extents = [], []
    for i, k in enumerate(layers):  # over panels, a few
        lp = plan.layers[k]
        pieces = list(lp.pieces())
        pts = np.concatenate([q for _, q, _ in pieces]) if pieces else np.zeros((1, 2))
        (x0, y0), (x1, y1) = pts.min(axis=0) - 1, pts.max(axis=0) + 1
        scale = size / max(x1 - x0, y1 - y0)
        w, h = max(int(round((x1 - x0) * scale)), 1), max(int(round((y1 - y0) * scale)), 1)
        px = left + (i % cols) * (size + gap) + (size - w) // 2
        py = top + (i // cols) * (size + top + bottom) + (size - h) // 2

        def at(q):  # mm -> pixels of the canvas (y up)
            return np.column_stack([px + (q[:, 0] - x0) * scale, py + (y1 - q[:, 1]) * scale])

        travel = [np.stack([a[-1], b[0]]) for (_, a, _), (_, b, _) in zip(pieces, pieces[1:])]
        canvas.lines([at(t) for t in travel], colour=(200, 200, 200))
        by_colour: dict = {}
        for kind, q, _ in pieces:  # over paths: grouped by colour, one drawing call each
            by_colour.setdefault(STYLES[kind].plot_colour, []).append(at(q))
        for colour, chains in by_colour.items():
            rgb = tuple(int(colour[j:j + 2], 16) for j in (1, 3, 5))
            canvas.lines(chains, colour=rgb)
        canvas.axes(px, py, w, h, (x0, x1, y0, y1), title=f"layer {k}, z = {lp.z:.2f} mm")
        boxes.append((px, py, w, h))
        extents.append(tuple(float(v) for v in (x0, x1, y0, y1)))
    data = canvas.png()
    with atomic_path(path) as tmp:
        tmp.write_bytes(data)
    return {"panels": boxes, "extent": extents}
