"""Exploded views: pieces of a cut or a partition pushed apart, shaded.

`plot_exploded` draws into matplotlib Axes (facets as polygons); `save_exploded_png` writes
the same view drawn by the depth buffer of `slicelab.viz.depth`, decimated, as a pixel array.

See Also
--------
slicelab.slicing.partition.partition : the pieces these figures show.
slicelab.slicing.cut.cut : two parts, drawn the same way.
"""
from __future__ import annotations

import numpy as np

from ..geometry.triangles import triangle_areas

__all__ = ["plot_exploded", "exploded_image", "save_exploded_png"]


def plot_exploded(pieces, ax=None, *, spread: float = 0.25, max_facets: int = 200_000, elev: float = 25.0,
                  azim: float = -60.0):
    """Draw pieces pushed apart from their common centre, shaded, in an orthographic view.

    A painter's algorithm over a 2-D PolyCollection: fast enough for a few
    hundred thousand facets (beyond `max_facets` the smallest facets are left out).

    Parameters
    ----------
    pieces : iterable of Mesh
        Such as ``partition(...).pieces`` or ``(cut.rear, cut.front)``.
    ax : matplotlib Axes, optional
        Drawn into; a new figure's when not given.
    spread : float, default 0.25
        Each piece moves away from the common centre by ``2 * spread`` times
        the distance of its box's centre from it.
    max_facets : int, default 200000
        Facets drawn at most.
    elev, azim : float
        View direction (degrees), as matplotlib's 3-D axes take them.

    Returns
    -------
    matplotlib Axes

    See Also
    --------
    save_exploded_png : the same picture written to a file.

    Examples
    --------
    >>> import matplotlib; matplotlib.use("Agg")
    >>> from slicelab.samples import box
    >>> from slicelab.slicing.cut import cut
    >>> c = cut(box(), (0, 0, 0.5), (0, 0, 1))
    >>> len(plot_exploded([c.rear, c.front]).collections)
    1
    >>> import matplotlib.pyplot as plt; plt.close("all")
    """
    import matplotlib.pyplot as plt
    from matplotlib.collections import PolyCollection
    if ax is None:
        _, ax = plt.subplots(figsize=(7, 6))
    pieces = [p for p in pieces if len(p)]
    if not pieces:
        return ax
    allb = np.array([p.bounds for p in pieces])
    centre = (allb[:, 0].min(axis=0) + allb[:, 1].max(axis=0)) / 2
    size = float(np.max(allb[:, 1].max(axis=0) - allb[:, 0].min(axis=0)))
    el, az = np.radians(elev), np.radians(azim)
    view = np.array([np.cos(el) * np.cos(az), np.cos(el) * np.sin(az), np.sin(el)])  # towards the viewer
    right = np.array([-np.sin(az), np.cos(az), 0.0])
    up = np.cross(view, right)
    light = view + np.array([0.3, 0.2, 0.6])
    light /= np.linalg.norm(light)
    total = sum(len(p) for p in pieces)
    cmap = plt.get_cmap("tab10" if len(pieces) <= 10 else "tab20")
    polys, colours, depth = [], [], []
    for k, p in enumerate(pieces):  # over pieces
        c = p.bounds.mean(axis=0)
        shift = (c - centre) * spread * 2
        t = p.triangles
        keep = np.arange(len(t))
        if total > max_facets:  # the largest facets cover the most: drop slivers first
            area = triangle_areas(t)
            keep = np.argsort(-area)[:max(1, int(len(t) * max_facets / total))]
        t = t[keep] + shift
        n = p.normals[keep]
        facing = n @ view > 0
        t, n = t[facing], n[facing]
        shade = 0.35 + 0.65 * np.clip(n @ light, 0, 1)
        base = np.array(cmap(k % cmap.N)[:3])
        colours.append(np.clip(base[None, :] * shade[:, None], 0, 1))
        polys.append(np.stack([t @ right, t @ up], axis=-1))
        depth.append((t @ view).mean(axis=1))
    polys = np.concatenate(polys)
    colours = np.concatenate(colours)
    order = np.argsort(np.concatenate(depth))
    # Edges in the face colour close the hairline seams anti-aliasing leaves between facets.
    ax.add_collection(PolyCollection(polys[order], facecolors=colours[order], edgecolors=colours[order],
                                     linewidths=0.3))
    flat = polys.reshape(-1, 2)
    ax.set_xlim(flat[:, 0].min() - 0.02 * size, flat[:, 0].max() + 0.02 * size)
    ax.set_ylim(flat[:, 1].min() - 0.02 * size, flat[:, 1].max() + 0.02 * size)
    ax.set_aspect("equal")
    ax.set_axis_off()
    return ax


#: matplotlib's "tab10" colours (RGB in [0, 1]), one a piece.
_PALETTE = np.array([(0.12, 0.47, 0.71), (1.0, 0.5, 0.05), (0.17, 0.63, 0.17), (0.84, 0.15, 0.16),
                     (0.58, 0.4, 0.74), (0.55, 0.34, 0.29), (0.89, 0.47, 0.76), (0.5, 0.5, 0.5),
                     (0.74, 0.74, 0.13), (0.09, 0.75, 0.81)])


def _view(elev: float, azim: float):
    """(towards the viewer, right, up) unit vectors of an orthographic view, as matplotlib's 3-D axes."""
    el, az = np.radians(elev), np.radians(azim)
    view = np.array([np.cos(el) * np.cos(az), np.cos(el) * np.sin(az), np.sin(el)])
    right = np.array([-np.sin(az), np.cos(az), 0.0])
    return view, right, np.cross(view, right)


def exploded_image(pieces, *, pixels: int = 640, spread: float = 0.25, elev: float = 25.0,
                   azim: float = -60.0) -> np.ndarray:
    """The exploded view of `plot_exploded` as an RGBA image, drawn by the depth buffer.

    Each piece, pushed away from the common centre, is drawn by
    `slicelab.viz.depth.render_depth` in its colour, decimated as one mesh
    would be (its share of a sample as many as the pixels, every facet wider
    than two pixels kept); the nearest piece wins each pixel.

    Parameters
    ----------
    pieces : iterable of Mesh
    pixels : int, default 640
        The image's longer side.
    spread, elev, azim : float
        As for `plot_exploded`.

    Returns
    -------
    (rows, cols, 4) float ndarray
        RGBA in [0, 1], transparent where no piece is seen.

    Examples
    --------
    >>> from slicelab.samples import box
    >>> from slicelab.slicing.cut import cut
    >>> img = exploded_image(cut(box(), (0, 0, 0.5), (0, 0, 1)), pixels=100)
    >>> max(img.shape[:2]), bool(img[..., 3].any())
    (100, True)
    """
    from ..geometry import Frame
    from .depth import render_depth
    pieces = [p for p in pieces if len(p)]
    if not pieces:
        return np.zeros((1, 1, 4))
    view, right, up = _view(elev, azim)
    allb = np.array([p.bounds for p in pieces])
    centre = (allb[:, 0].min(axis=0) + allb[:, 1].max(axis=0)) / 2
    shifts = [(b.mean(axis=0) - centre) * spread * 2 for b in allb]
    # The extent from the pieces' boxes, moved and projected (8 corners each).
    corners = np.array([[[x, y, z] for x in b[:, 0] for y in b[:, 1] for z in b[:, 2]] for b in allb])
    corners = corners + np.array(shifts)[:, None, :] - centre
    s, t = corners @ right, corners @ up
    pad = 0.02 * max(float(np.ptp(s)), float(np.ptp(t)), 1e-9)
    extent = (s.min() - pad, s.max() + pad, t.min() - pad, t.max() + pad)
    scale = pixels / max(extent[1] - extent[0], extent[3] - extent[2])
    shape = (max(int(round((extent[3] - extent[2]) * scale)), 1), max(int(round((extent[1] - extent[0]) * scale)), 1))
    total = sum(len(p) for p in pieces)
    img = np.zeros(shape + (4,))
    nearest = np.full(shape, -np.inf, np.float32)
    for k, (p, shift) in enumerate(zip(pieces, shifts)):  # over pieces
        frame = Frame(centre - shift, right, up, view)
        budget = max(int(np.ceil(shape[0] * shape[1] * len(p) / total)), 1)
        rgba, depth = render_depth(p.triangles, p.normals, frame, extent, shape, decimate=budget,
                                   colour=_PALETTE[k % len(_PALETTE)], with_depth=True)
        nearer = depth > nearest
        nearest[nearer] = depth[nearer]
        img[nearer] = rgba[nearer]
    return img


def save_exploded_png(pieces, path, *, title: str | None = None, pixels: int = 640, **kwargs) -> None:
    """Write the exploded view of the pieces to a PNG file, atomically.

    The view is `exploded_image`'s, composed with a title as a pixel array
    (`slicelab.viz.canvas`): no matplotlib figure.

    Parameters
    ----------
    pieces : iterable of Mesh
    path : str or Path
    title : str, optional
    pixels : int, default 640
        The view's longer side.
    **kwargs
        ``spread``, ``elev``, ``azim``: passed to `exploded_image`.

    See Also
    --------
    plot_exploded : the picture, into matplotlib Axes.

    Examples
    --------
    >>> import tempfile, os
    >>> from slicelab.samples import box
    >>> from slicelab.slicing.partition import partition
    >>> parts = partition(box((0, 0, 0), (300, 120, 80)), (200, 200, 200))
    >>> save_exploded_png(parts.pieces, os.path.join(tempfile.mkdtemp(), "p.png"))
    """
    from ..files.atomic import atomic_path
    from .canvas import Canvas
    img = exploded_image(pieces, pixels=pixels, **kwargs)
    rows, cols = img.shape[:2]
    top = 36 if title else 10
    canvas = Canvas(cols + 20, rows + top + 10)
    canvas.paste(img, 10, top)
    if title:
        canvas.text(title, canvas.rgb.shape[1] / 2, 24, scale=1.1, anchor="centre")
    data = canvas.png()
    with atomic_path(path) as tmp:
        tmp.write_bytes(data)
