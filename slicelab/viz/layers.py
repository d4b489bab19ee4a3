"""Figures of layers and print plans (matplotlib, imported lazily by the functions).

Each plotting helper draws on a given Axes (or a new one) and returns the
Axes; `preview_png` draws a few layers of a plan into a PNG file with OpenCV
(`slicelab.viz.canvas`), without matplotlib, with a legend of the roles drawn
(`slicelab.viz.legend`) and an oblique view of every layer (`oblique_view`).
Paths are coloured by role from `slicelab.printing.roles.STYLES`.

Which layers a preview shows is said as `preview_layers` reads it (the
``--preview-layers`` of ``slicelab slice``): layer numbers, heights and words,
``0,57,z=12.5,last``; by default the first, middle and last layers and the
one with the most bridge and overhang area (`default_preview_layers`).
"""
from __future__ import annotations

import math

import numpy as np

from ..printing.roles import STYLES
from .layer_choice import (LAYER_WORDS, PREVIEW_LAYERS_FORM, default_preview_layers,  # noqa: F401
                           pick_preview_layers, preview_layers)
from .legend import rgb

__all__ = ["plot_raster", "plot_distance", "plot_toolpath", "plot_coverage", "plan_3d", "preview_png",
           "oblique_view", "oblique_size", "preview_layers", "pick_preview_layers", "default_preview_layers", "LAYER_WORDS",
           "PREVIEW_LAYERS_FORM"]


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


# ------------------------------------------------------------- the whole part, seen obliquely
_WALLS = ("external", "hole", "overhang")
_SHADES = 5


def _oblique_frame(plan, size: int, azim: float, elev: float):
    """The oblique view's size in pixels ``(w, h)``, its turn (cosines and sines of `azim` and
    `elev`) and the pixels of a point ``(scale, x0, y0)``: x = x0 + across * scale, y = y0 - up * scale."""
    a, e = math.radians(azim), math.radians(elev)
    ca, sa, ce, se = math.cos(a), math.sin(a), math.cos(e), math.sin(e)
    x0, y0, x1, y1 = plan.extent
    top = plan.layers[-1].z if plan.layers else 0.0
    cx, cy = np.array([x0, x1, x1, x0] * 2), np.array([y0, y0, y1, y1] * 2)
    cz = np.repeat([0.0, top], 4)
    sx, sy = cx * ca - cy * sa, cz * ce + (cx * sa + cy * ca) * se  # across, and up the picture
    scale = (size - 4) / max(float(np.ptp(sx)), float(np.ptp(sy)), 1e-9)
    w, h = int(np.ptp(sx) * scale) + 4, int(np.ptp(sy) * scale) + 4
    return (w, h), (ca, sa, ce, se), (scale, 2 - sx.min() * scale, 2 + sy.max() * scale)


def oblique_view(plan, canvas, x: int, y: int, size: int, *, azim: float = -35.0, elev: float = 30.0) -> dict:
    """Every layer's toolpaths seen from above at an angle, drawn into `canvas` with the top-left
    corner at (x, y) and the longer side `size` pixels (`oblique_size`): each path in its role's
    colour, the outer walls shaded by how they face the light (a wall facing it bright, one seen
    edge-on dark).

    Seen from `elev` degrees above the bed and turned `azim` degrees about z (-35: from the front
    and the right), a point higher up lies nearer the viewer than any point lower down that it
    covers: drawn bottom to top with OpenCV, each layer over the ones below, the picture is
    right without a depth buffer, in time that follows the number of points drawn.

    Returns
    -------
    dict
        ``"kinds"``: the kinds drawn; ``"box"``: the drawing's ``(x, y, w, h)`` in pixels.
    """
    import cv2
    (w, h), (ca, sa, ce, se), (scale, ox, oy) = _oblique_frame(plan, size, azim, elev)
    ox, oy = ox + x, oy + y
    shift = 1 << 4  # fractional bits of the points handed to OpenCV
    flat = {k: rgb(s.plot_colour) for k, s in STYLES.items()}
    shades = {k: [tuple(int(min(255, v * (0.5 + 0.6 * i / (_SHADES - 1)))) for v in flat[k])
                  for i in range(_SHADES)] for k in _WALLS}
    light = (math.cos(math.radians(azim - 85)), math.sin(math.radians(azim - 85)))  # from the viewer's left
    drawn = set()
    for lp in plan.layers:  # bottom to top: each layer over those below
        groups: dict = {}
        for kind, q, _ in lp.pieces():  # over the layer's paths
            if len(q) > 1:
                groups.setdefault(kind, []).append(q)
        for kind, chains in groups.items():  # over the kinds in the layer, a dozen at most
            drawn.add(kind)
            counts = np.array([len(q) for q in chains])
            xy = np.concatenate(chains)
            px = ox + (xy[:, 0] * ca - xy[:, 1] * sa) * scale
            py = oy - (lp.z * ce + (xy[:, 0] * sa + xy[:, 1] * ca) * se) * scale
            pts = np.rint(np.column_stack([px, py]) * shift).astype(np.int32)
            ends = np.cumsum(counts)
            if kind not in _WALLS:
                cv2.polylines(canvas.rgb, [c.reshape(-1, 1, 2) for c in np.split(pts, ends[:-1])], False,
                              flat[kind], 1, cv2.LINE_AA, 4)
                continue
            # A wall's stretches, each in the shade of how its segments face the light.
            d = np.diff(xy, axis=0)
            facing = np.abs(d[:, 1] * light[0] - d[:, 0] * light[1]) / (np.hypot(d[:, 0], d[:, 1]) + 1e-12)
            shade = np.minimum((facing * _SHADES).astype(np.int64), _SHADES - 1)
            joins = ends[:-1] - 1  # segments from one path's end to the next path's start
            cut = np.zeros(len(shade), bool)
            cut[0] = True
            cut[1:] = shade[1:] != shade[:-1]
            cut[joins] = True
            cut[joins[joins + 1 < len(cut)] + 1] = True
            keep = np.ones(len(shade), bool)
            keep[joins] = False
            runs: dict = {}
            starts = np.flatnonzero(cut)
            for s0, s1 in zip(starts.tolist(), np.r_[starts[1:], len(shade)].tolist()):  # over stretches
                if keep[s0]:
                    runs.setdefault(int(shade[s0]), []).append(pts[s0:s1 + 1].reshape(-1, 1, 2))
            for i, stretch in runs.items():  # over the shades, five
                cv2.polylines(canvas.rgb, stretch, False, shades[kind][i], 1, cv2.LINE_AA, 4)
    return {"kinds": drawn, "box": (x, y, w, h)}


def oblique_size(plan, size: int, *, azim: float = -35.0, elev: float = 30.0) -> tuple[int, int]:
    """Width and height (pixels) of `oblique_view` with the longer side `size`."""
    return _oblique_frame(plan, size, azim, elev)[0]


def preview_png(plan, path, layers=None, *, pixels: int = 400, legend: bool = False, whole: bool = False) -> dict:
    """Draw some layers' toolpaths side by side into a PNG (roles coloured, travel in grey), with a
    legend of the roles drawn and an oblique view of the whole part if asked.

    Composed as a pixel array with OpenCV (`slicelab.viz.canvas`), not a
    matplotlib figure, whose import and layout would weigh on every
    `slicelab slice --preview`: each panel is framed, with millimetre ticks, and titled with
    its layer and height (and why it was chosen); paths are drawn in their roles' colours
    (`slicelab.printing.roles.STYLES`), a colour at a time, over the travel
    between them. All panels show the same box of the bed, at one scale.

    Parameters
    ----------
    plan : PrintPlan
    path : str or Path
        Written atomically.
    layers : sequence or str, optional
        What `preview_layers` reads: layer numbers, ``"z=12.5"`` heights, `LAYER_WORDS`, or text
        such as ``"0,57,z=12.5,last"``. Default: `default_preview_layers` (the first, middle and
        last layers and the one with the most bridges and overhangs).
    pixels : int, default 400
        Size of the longer side of each panel.
    legend : bool, default False
        A legend of the roles drawn, at the right (`slicelab.viz.legend`).
    whole : bool, default False
        First, every layer seen from above at an angle (`oblique_view`).

    Returns
    -------
    dict
        ``"panels"``: each layer's panel ``(x, y, width, height)`` in pixels (top-left corner
        first); ``"extent"``: the ``(x_min, x_max, y_min, y_max)`` (mm, part coordinates) each shows;
        ``"layers"``: per panel, ``{"layer", "z", "why"}``; ``"legend"``: its entries
        (``{"label", "colour", "kinds"}``) and ``"legend_box"``, their strokes ``"legend_swatches"``;
        ``"whole"``: the oblique view's box (None without).

    Raises
    ------
    ValueError
        When `layers` names a layer the plan does not have.

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
    >>> shown = preview_png(p, out, "first,last", pixels=100, legend=True, whole=True)
    >>> [(d["layer"], d["why"]) for d in shown["layers"]]
    [(0, 'first'), (4, 'last')]
    >>> [e["label"] for e in shown["legend"]]
    ['Skirt/Brim', 'External perimeter', 'Perimeter', 'Solid infill', 'Top solid infill', 'Travel']
    """
    from ..files.atomic import atomic_path
    from .canvas import Canvas
    from .legend import TRAVEL_RGB, draw_legend, legend_entries, legend_size
    n = len(plan.layers)
    if n == 0:
        raise ValueError("no layer to draw")
    if layers is None:
        picked = default_preview_layers(plan)
    else:
        picked = pick_preview_layers(preview_layers(layers), [lp.z for lp in plan.layers], plan)
    cols = min(4, len(picked))
    rows = math.ceil(len(picked) / cols)
    subtitles = any(why for _, why in picked) or whole
    left, gap, top, bottom, right = 70, 55, 56 if subtitles else 40, 40, 15
    size = int(pixels)
    ww, wh = oblique_size(plan, size) if whole else (0, 0)
    first_x = 15 + max(ww, 200) + left if whole else left  # the oblique view goes first, without ticks
    # One box of the bed for every panel: the union of the layers' paths, a millimetre around.
    tables = [list(plan.layers[k].pieces()) for k, _ in picked]
    boxes = [(np.concatenate([q for _, q, _ in t]).min(axis=0), np.concatenate([q for _, q, _ in t]).max(axis=0))
             for t in tables if t]
    if boxes:
        (x0, y0), (x1, y1) = np.min([b[0] for b in boxes], axis=0) - 1, np.max([b[1] for b in boxes], axis=0) + 1
    else:
        x0, y0, x1, y1 = -1.0, -1.0, 1.0, 1.0
    scale = size / max(x1 - x0, y1 - y0)
    w, h = max(int(round((x1 - x0) * scale)), 1), max(int(round((y1 - y0) * scale)), 1)
    kinds = {kind for t in tables for kind, _, _ in t}
    travel = any(len(t) > 1 for t in tables)
    entries = legend_entries(kinds | set(plan_kinds(plan)) if whole else kinds, travel=travel) if legend else []
    lw, lh = legend_size(entries) if legend else (0, 0)
    panels_right = first_x + cols * size + (cols - 1) * gap
    row = max(h, wh)  # each row as tall as its panels (and the first the oblique view)
    canvas = Canvas(panels_right + (30 + lw if legend else 0) + right,
                    max(top + rows * (row + top + bottom) - top, top + lh + bottom))
    panels, extents, shown = [], [], []
    for i, ((k, why), pieces) in enumerate(zip(picked, tables)):  # over panels, a few
        lp = plan.layers[k]
        px = first_x + (i % cols) * (size + gap) + (size - w) // 2
        py = top + (i // cols) * (row + top + bottom) + (row - h) // 2

        def at(q):  # mm -> pixels of the canvas (y up)
            return np.column_stack([px + (q[:, 0] - x0) * scale, py + (y1 - q[:, 1]) * scale])

        moves = [np.stack([a[-1], b[0]]) for (_, a, _), (_, b, _) in zip(pieces, pieces[1:])]
        canvas.lines([at(t) for t in moves], colour=TRAVEL_RGB)
        by_colour: dict = {}
        for kind, q, _ in pieces:  # over paths: grouped by colour, one drawing call each
            by_colour.setdefault(STYLES[kind].plot_colour, []).append(at(q))
        for colour, chains in by_colour.items():
            canvas.lines(chains, colour=rgb(colour))
        title = f"layer {k}, z = {lp.z:.2f} mm"
        canvas.axes(px, py, w, h, (x0, x1, y0, y1), title="" if why else title)
        if why:
            canvas.text(title, px + w / 2, py - 26, scale=1.2, anchor="centre")
            canvas.text(why, px + w / 2, py - 8, anchor="centre", colour=(90, 90, 90))
        panels.append((px, py, w, h))
        extents.append(tuple(float(v) for v in (x0, x1, y0, y1)))
        shown.append({"layer": int(k), "z": round(float(lp.z), 6), "why": why})
    whole_box = None
    if whole:
        mid = 15 + max(ww, 200) / 2
        whole_box = oblique_view(plan, canvas, int(mid - ww / 2), top + (row - wh) // 2, size)["box"]
        canvas.text(f"all {n} layers", mid, top - 26, scale=1.2, anchor="centre")
        canvas.text("from the front right, 30 deg up", mid, top - 8, anchor="centre", colour=(90, 90, 90))
    swatches, legend_box = [], None
    if legend:
        legend_box = (panels_right + 30, top, lw, lh)
        swatches = draw_legend(canvas, entries, panels_right + 30, top)
    data = canvas.png()
    with atomic_path(path) as tmp:
        tmp.write_bytes(data)
    return {"panels": panels, "extent": extents, "layers": shown,
            "legend": [{"label": e.label, "colour": "#%02x%02x%02x" % e.rgb, "kinds": list(e.kinds)} for e in entries],
            "legend_box": legend_box, "legend_swatches": swatches, "whole": whole_box}


def plan_kinds(plan) -> set:
    """The kinds of extrusion in any layer of `plan` (overhang pieces of walls included)."""
    kinds = set()
    for lp in plan.layers:  # over the layers
        kinds.update(lp.kind)
        if lp.hang and any(hg is not None and np.any(hg) for hg in lp.hang):
            kinds.add("overhang")
    return kinds
