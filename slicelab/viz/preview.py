"""Preview of a split: front and rear projected onto the plane, the section drawn over them.

Both halves are drawn by the depth buffer of `slicelab.viz.depth`
(decimated past the pixels' count), seen from a viewer on the front side
(the side the plane's normal points to) and in the plane's 2-D frame, so
the section lies exactly over both: the front part from outside, and the
rear part as it is seen once the front part is lifted away. `draw_split`
makes a matplotlib figure of them; `save_split_preview` composes the PNG
file as a pixel array (`slicelab.viz.canvas`), at a fraction of a figure's
cost.
"""
from __future__ import annotations

import numpy as np

from .depth import Projected, add_wide, render_projected, sample_facets

__all__ = ["draw_split", "save_split_preview"]


def _extent(boxes, margin: float = 0.04):
    """The picture's extent: the union of plane-coordinate boxes, padded."""
    boxes = [b for b in boxes if b is not None]
    if not boxes:
        return -1.0, 1.0, -1.0, 1.0
    lo = np.min([b[0] for b in boxes], axis=0)
    hi = np.max([b[1] for b in boxes], axis=0)
    pad = margin * max(float((hi - lo).max()), 1e-9)
    return lo[0] - pad, hi[0] + pad, lo[1] - pad, hi[1] + pad


def _draw_section(ax, section, pixel: float, colour="#c0392b"):
    """The section over a panel: rings simplified to a third of a pixel (a scan's section has
    hundreds of thousands of points a picture cannot show), added without autoscaling."""
    import cv2
    from matplotlib.patches import PathPatch
    from matplotlib.path import Path as MplPath

    def thin(r):
        if len(r) < 8:
            return r
        q = cv2.approxPolyDP(np.ascontiguousarray(r, dtype=np.float32).reshape(-1, 1, 2), pixel / 3, True)
        return q.reshape(-1, 2).astype(np.float64) if len(q) >= 3 else r

    for poly in section.polygons:
        rings = [thin(r) for r in (poly.exterior, *poly.holes)]
        verts = np.concatenate([np.vstack([r, r[:1]]) for r in rings])
        codes = np.concatenate([[MplPath.MOVETO] + [MplPath.LINETO] * (len(r) - 1) + [MplPath.CLOSEPOLY]
                                for r in rings])
        # Light fill, firm outline: for a solid part the section covers most of the picture.
        path = MplPath(verts, codes)
        for patch in (PathPatch(path, facecolor=colour, alpha=0.25, edgecolor="none"),
                      PathPatch(path, facecolor="none", edgecolor=colour, lw=1.3)):
            patch.set_transform(ax.transData)
            ax.add_artist(patch)  # the limits are set by the caller: no autoscaling over every point
    for chain in section.open_chains:
        ax.plot(chain[:, 0], chain[:, 1], color=colour, lw=1.2, ls="--", scalex=False, scaley=False)


def _figsize(extent) -> tuple[float, float]:
    s0, s1, t0, t1 = extent
    return 12.0, float(np.clip(6.0 * (t1 - t0) / max(s1 - s0, 1e-12), 2.5, 9.0)) + 1.0


def _panels(split, pixels: int):
    """The two halves projected into the section's plane (decimated past `pixels` squared
    facets), and the picture's extent (from the facets drawn)."""
    frame = split.section.frame
    budget = pixels * pixels
    halves = (split.front.triangles, split.rear.triangles)
    drawn = [Projected(t, frame, sample_facets(len(t), budget)) for t in halves]
    section = [split.section.bounds() if len(split.section.segments) else None]
    extent = _extent(section + [p.bounds() if len(p.q) else None for p in drawn])
    pixel = max(extent[1] - extent[0], extent[3] - extent[2]) / pixels
    for t, proj in zip(halves, drawn):
        add_wide(proj, t, frame, pixel)
    front, rear = drawn
    return front, rear, _extent(section + [p.bounds() if len(p.q) else None for p in drawn])


def draw_split(split, *, pixels: int = 700, axes=None):
    """Draw a `Split`: front and rear panels in the plane's frame with the section over both.

    Parameters
    ----------
    split : Split
    pixels : int
        Rendered size of the longer side of each panel.
    axes : pair of matplotlib Axes, optional
        Where to draw; a new figure with two panels by default.

    Returns
    -------
    matplotlib.figure.Figure

    See Also
    --------
    render_depth : how each panel is drawn.
    save_split_preview : the same figure, written to a PNG file.

    Examples
    --------
    >>> import matplotlib; matplotlib.use("Agg")
    >>> import slicelab
    >>> from slicelab.samples import torus
    >>> fig = draw_split(slicelab.split(torus(n_major=24, n_minor=12), (0, 0, 0), (0, 1, 0)), pixels=80)
    >>> [ax.get_title() for ax in fig.axes]
    ['front', 'rear (front lifted away)']
    """
    panels = _panels(split, pixels)
    if axes is None:
        import matplotlib.pyplot as plt
        _, axes = plt.subplots(1, 2, figsize=_figsize(panels[2]), constrained_layout=True)
    return _draw(split, panels, pixels, axes)


def _draw(split, panels, pixels: int, axes):
    front, rear, (s0, s1, t0, t1) = panels
    scale = pixels / max(s1 - s0, t1 - t0)
    shape = (max(int(round((t1 - t0) * scale)), 1), max(int(round((s1 - s0) * scale)), 1))
    fig = axes[0].figure
    frame = split.section.frame
    panels = ((axes[0], front, split.front, "front"), (axes[1], rear, split.rear, "rear (front lifted away)"))
    for ax, proj, mesh, title in panels:
        img = render_projected(proj, mesh.normals, frame, (s0, s1, t0, t1), shape, 4_000_000)
        # Bytes, not floats: matplotlib resamples and composes a uint8 image several times faster.
        ax.imshow(np.rint(img * 255).astype(np.uint8), extent=(s0, s1, t0, t1), origin="upper", interpolation="nearest")
        ax.set_xlim(s0, s1)
        ax.set_ylim(t0, t1)
        _draw_section(ax, split.section, 1 / scale)
        ax.set_aspect("equal")
        ax.set_title(title)
        ax.set_xlabel("s (mm, plane frame)")
    axes[0].set_ylabel("t (mm, plane frame)")
    fig.suptitle(f"{split.n_front:,} facets in front, {split.n_cut:,} cut, {split.n_rear:,} behind; "
                 f"section {split.section.area:.6g} mm2 (red)", fontsize=10)
    return fig


def _rings_px(section, extent, shape, x0: int, y0: int):
    """The section's rings and open chains in canvas pixels (pixel centres on integers), each ring
    simplified to a third of a pixel (a scan's section has more points than a picture can show)."""
    import cv2
    s0, s1, t0, t1 = extent
    rows, cols = shape
    sx, sy = cols / (s1 - s0), rows / (t1 - t0)

    def px(r):
        return np.column_stack([x0 + (r[:, 0] - s0) * sx - 0.5, y0 + (t1 - r[:, 1]) * sy - 0.5])

    def thin(r):
        if len(r) < 8:
            return r
        q = cv2.approxPolyDP(np.ascontiguousarray(r, dtype=np.float32).reshape(-1, 1, 2), 1 / 3, True)
        return q.reshape(-1, 2).astype(np.float64) if len(q) >= 3 else r

    rings = [thin(px(np.asarray(r, dtype=np.float64)))
             for poly in section.polygons for r in (poly.exterior, *poly.holes)]
    return rings, [px(np.asarray(c, dtype=np.float64)) for c in section.open_chains]


_SECTION = (192, 57, 43)   # the section's red (RGB)
_OPEN = (230, 126, 34)     # open chains of the section: orange


def save_split_preview(split, path, *, pixels: int = 500) -> dict:
    """Write the split's two panels and its section as a PNG, atomically.

    The picture is `draw_split`'s (front, and rear with the front lifted
    away, in the plane's frame, the section in red over both: a light fill
    and an outline; open chains of the section in orange), composed as a
    pixel array with OpenCV (`slicelab.viz.canvas`) instead of a matplotlib
    figure: each panel is rendered at the size it is shown, framed, with
    millimetre ticks.

    Parameters
    ----------
    split : Split
    path : str or os.PathLike
    pixels : int, default 500
        Size of the longer side of each panel.

    Returns
    -------
    dict
        Where things lie in the picture: ``"panels"``, the front's and the
        rear's ``(x, y, width, height)`` in pixels (top-left corner first),
        and ``"extent"``, the ``(s_min, s_max, t_min, t_max)`` (mm, plane
        frame) each panel shows.

    Examples
    --------
    >>> import slicelab, tempfile, os
    >>> from slicelab.samples import box
    >>> out = os.path.join(tempfile.mkdtemp(), "p.png")
    >>> layout = save_split_preview(slicelab.split(box(), (0, 0, 0.5), (1, 1, 1)), out, pixels=60)
    >>> layout["panels"][1][2:]  # width and height of the rear panel
    (53, 60)
    >>> open(out, "rb").read(4)
    b'\\x89PNG'
    """
    from ..files.atomic import atomic_path
    from .canvas import Canvas
    front, rear, extent = _panels(split, pixels)
    s0, s1, t0, t1 = extent
    scale = pixels / max(s1 - s0, t1 - t0)
    shape = (max(int(round((t1 - t0) * scale)), 1), max(int(round((s1 - s0) * scale)), 1))
    rows, cols = shape
    left, gap, top, bottom, right = 70, 40, 62, 50, 15
    canvas = Canvas(left + 2 * cols + gap + right, top + rows + bottom)
    frame = split.section.frame
    titles = ("front", "rear (front lifted away)")
    boxes = []
    for k, (proj, mesh) in enumerate(((front, split.front), (rear, split.rear))):
        x0 = left + k * (cols + gap)
        boxes.append((x0, top, cols, rows))
        canvas.paste(render_projected(proj, mesh.normals, frame, extent, shape, 4_000_000, dtype=np.uint8), x0, top)
        rings, chains = _rings_px(split.section, extent, shape, x0, top)
        canvas.polygons(rings, colour=_SECTION, alpha=0.25, width=1)
        canvas.lines(chains, colour=_OPEN)
        canvas.axes(x0, top, cols, rows, extent, xlabel="s (mm, plane frame)", title=titles[k],
                    ylabel="t (mm, plane frame)" if k == 0 else "", ticks_left=k == 0)
    canvas.text(f"{split.n_front:,} facets in front, {split.n_cut:,} cut, {split.n_rear:,} behind; "
                f"section {split.section.area:.6g} mm2 (red)", canvas.rgb.shape[1] / 2, 20, anchor="centre")
    data = canvas.png()
    with atomic_path(path) as tmp:
        tmp.write_bytes(data)
    return {"panels": boxes, "extent": tuple(float(v) for v in extent)}
