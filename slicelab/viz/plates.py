"""Top views of build plates: each piece's footprint, numbered, on the bed."""
from __future__ import annotations

import numpy as np

__all__ = ["save_plate_png"]


def save_plate_png(plates, k: int, pieces, path, *, names=None, dpi: int = 100) -> None:
    """Draw plate `k` from above (the bed, each piece's footprint and its number) into a PNG, atomically.

    Examples
    --------
    >>> import os, tempfile
    >>> from slicelab.samples import box
    >>> from slicelab.slicing import arrange
    >>> parts = [box((0, 0, 0), (50, 30, 10))] * 3
    >>> out = os.path.join(tempfile.mkdtemp(), "plate.png")
    >>> save_plate_png(arrange(parts, (200, 200, 100)), 0, parts, out)
    >>> open(out, "rb").read(4)
    b'\\x89PNG'
    """
    import shapely
    from matplotlib.figure import Figure
    from matplotlib.patches import PathPatch, Rectangle
    from matplotlib.path import Path as MplPath

    from ..files.atomic import atomic_path
    from ..slicing.plates import footprint
    X, Y, _ = plates.build_volume
    plate = plates.plates[k]
    fig = Figure(figsize=(6, 6 * Y / X + 0.4), layout="constrained")
    ax = fig.subplots()
    ax.add_patch(Rectangle((0, 0), X, Y, facecolor="#f1f3f5", edgecolor="#495057", lw=1.2))
    colours = ["#4a6fa5", "#e8590c", "#2b8a3e", "#862e9c", "#c92a2a", "#0b7285", "#5c940d", "#d9480f"]
    for n, (i, m) in enumerate(zip(plate.pieces, plate.matrices)):  # over the pieces on the plate
        fp = footprint(pieces[i].transformed(m))
        for poly in getattr(fp, "geoms", [fp]):
            rings = [np.asarray(poly.exterior.coords)] + [np.asarray(r.coords) for r in poly.interiors]
            codes = np.concatenate([[MplPath.MOVETO] + [MplPath.LINETO] * (len(r) - 2) + [MplPath.CLOSEPOLY]
                                    for r in rings])
            ax.add_patch(PathPatch(MplPath(np.concatenate(rings), codes), facecolor=colours[n % len(colours)],
                                   alpha=0.6, edgecolor="black", lw=0.8))
        c = shapely.centroid(fp)
        label = str(i) if names is None else names[i]
        ax.text(c.x, c.y, label, ha="center", va="center", fontsize=9, weight="bold")
    ax.set_xlim(-0.02 * X, 1.02 * X)
    ax.set_ylim(-0.02 * Y, 1.02 * Y)
    ax.set_aspect("equal")
    ax.set_xlabel("x (mm)")
    ax.set_ylabel("y (mm)")
    ax.set_title(f"plate {k + 1} of {len(plates)}: {len(plate.pieces)} pieces, "
                 f"{100 * plates.fill[k]:.0f} % of the bed covered")
    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=dpi, format="png")
