"""Exploded views: pieces of a cut or a partition pushed apart, shaded (matplotlib).

See Also
--------
slicelab.slicing.partition.partition : the pieces these figures show.
slicelab.slicing.cut.cut : two parts, drawn the same way.
"""
from __future__ import annotations

import numpy as np

from ..geometry.triangles import triangle_areas

__all__ = ["plot_exploded", "save_exploded_png"]


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


def save_exploded_png(pieces, path, *, title: str | None = None, dpi: int = 120, **kwargs) -> None:
    """Write `plot_exploded` of the pieces to a PNG file, atomically.

    Parameters
    ----------
    pieces : iterable of Mesh
    path : str or Path
    title : str, optional
    dpi : int, default 120
    **kwargs
        Passed to `plot_exploded`.

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
    import matplotlib
    matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt

    from ..export.files import atomic_path
    fig, ax = plt.subplots(figsize=(7, 6))
    plot_exploded(pieces, ax, **kwargs)
    if title:
        ax.set_title(title)
    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=dpi, bbox_inches="tight", format="png")
    plt.close(fig)
