"""The archaeological profile drawing of a vessel as a PNG (matplotlib, no pyplot).

The layout is `slicelab.artefacts.layout`, the same one the SVG is drawn
from, so the two cannot disagree. It lives beside the layout, in the
artefacts floor, so that `Profile.to_png` needs nothing from the floors
above (`slicelab.viz.profile_png` is this function).
"""
from __future__ import annotations

import numpy as np

from .drawing import LINE, THIN, layout

__all__ = ["profile_png"]


def profile_png(profile, path, *, dpi: float = 150.0, side: str = "left", spread: bool = False,
                label: str | None = None) -> None:
    """Render the drawing with matplotlib (no pyplot: safe in worker threads) and write a PNG atomically.

    Parameters
    ----------
    profile : Profile
    path : str or os.PathLike
    dpi : float, default 150
        Pixels per inch: the drawing is 1:1 when printed at this resolution.
    side, spread, label
        As in `slicelab.artefacts.layout`.

    See Also
    --------
    slicelab.artefacts.Profile.to_png : calls it.
    slicelab.artefacts.profile_svg : the same layout as SVG.

    Examples
    --------
    >>> import os, tempfile
    >>> from slicelab.artefacts import profile
    >>> from slicelab.samples import pot
    >>> profile_png(profile(pot(20, 24), planes=2), os.path.join(tempfile.mkdtemp(), "p.png"), dpi=40)
    """
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure
    from matplotlib.patches import PathPatch, Rectangle
    from matplotlib.path import Path as MplPath

    from ..files.atomic import atomic_path
    lay = layout(profile, side=side, spread=spread, label=label)
    x0, y0, x1, y1 = lay["page"]
    pt = 72.0 / 25.4  # points per mm
    fig = Figure(figsize=((x1 - x0) / 25.4, (y1 - y0) / 25.4), dpi=dpi)
    FigureCanvasAgg(fig)
    ax = fig.add_axes((0, 0, 1, 1))
    ax.set_xlim(x0, x1)
    ax.set_ylim(y0, y1)
    ax.set_axis_off()
    for name, items in lay["layers"]:  # a few layers of a few items
        for it in items:
            kind = it[0]
            if kind == "polygon":
                verts, codes = [], []
                for r in it[1]:
                    verts += [*r, r[0]]
                    codes += [MplPath.MOVETO] + [MplPath.LINETO] * (len(r) - 1) + [MplPath.CLOSEPOLY]
                ax.add_patch(PathPatch(MplPath(np.array(verts), codes), facecolor="black", edgecolor="black",
                                       linewidth=LINE * pt))
            elif kind == "line":
                style = {"linestyle": (0, tuple(float(v) / it[2] for v in it[3].split()))} if it[3] else {}
                ax.plot(it[1][:, 0], it[1][:, 1], color="#999999" if name == "spread" else "black",
                        linewidth=it[2] * pt, solid_joinstyle="round", **style)
            elif kind == "rect":
                _, x, y, rw, rh, fill = it
                ax.add_patch(Rectangle((x, y), rw, rh, facecolor=fill, edgecolor="black", linewidth=THIN * pt))
            elif kind == "text":
                _, x, y, text, size, anchor = it
                ax.text(x, y, text, fontsize=size * pt, ha="center" if anchor == "middle" else "left",
                        va="baseline", family="sans-serif")
    with atomic_path(path) as tmp:
        fig.savefig(tmp, format="png", dpi=dpi)
