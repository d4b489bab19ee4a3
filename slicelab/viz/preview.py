"""Preview of a split: front and rear projected onto the plane, the section drawn over them.

Millions of facets are drawn without a Python loop over them: each facet is
projected onto the plane, tested against the pixel centres of its bounding
box, and a depth buffer keeps, in each pixel, the facet nearest to a viewer
on the front side (the side the plane's normal points to). Both panels are seen
from that viewer and drawn in the plane's 2-D frame, so the section lies
exactly over both: the front part from outside, and the rear part as it is
seen once the front part is lifted away.
"""
from __future__ import annotations

import numpy as np

from ..geometry.ragged import within_group

__all__ = ["render_depth", "draw_split", "save_split_preview"]

_FACING = np.array([0.80, 0.80, 0.82])           # facets seen from outside: light grey
_BACK = np.array([0.78, 0.52, 0.33])             # facets seen from inside: terracotta


def render_depth(triangles, normals, frame, extent, shape, *, block: int = 4_000_000):
    """Shade of the facet nearest the viewer in each pixel (orthographic, along -normal).

    Every pixel centre inside a facet's projection is a candidate (facets are
    expanded over the pixels of their bounding box and tested with edge
    functions, in blocks of about `block` candidates); a depth buffer keeps
    the nearest.

    Parameters
    ----------
    triangles : (n, 3, 3) ndarray
    normals : (n, 3) ndarray
        Unit facet normals (for shading and to tell outside from inside).
    frame : Frame
        The plane; the viewer looks along ``-frame.normal``.
    extent : (4,) sequence
        ``(s_min, s_max, t_min, t_max)`` of the image in plane coordinates (mm).
    shape : (rows, cols)
    block : int
        Candidates (facet, pixel) handled at once; bounds the memory used.

    Returns
    -------
    (rows, cols, 4) float ndarray
        RGBA, row 0 at ``t_max`` (as `imshow` draws it with ``origin="upper"``);
        transparent where no facet projects.

    Examples
    --------
    >>> from slicelab.samples import box
    >>> from slicelab.geometry import Frame
    >>> m = box((0, 0, 0), (1, 1, 1))
    >>> img = render_depth(m.triangles, m.normals, Frame.from_plane((0, 0, 0), (0, 0, 1)),
    ...                    (-1, 2, -1, 2), (30, 30))
    >>> img.shape, float(img[..., 3].sum())  # the unit square: 10 x 10 pixels of 0.1 mm
    ((30, 30, 4), 100.0)
    """
    rows, cols = shape
    out = np.zeros((rows, cols, 4))
    t = np.asarray(triangles, dtype=np.float64)
    if len(t) == 0:
        return out
    n = np.asarray(normals, dtype=np.float64)
    s0, s1, t0, t1 = map(float, extent)
    ps, pt = (s1 - s0) / cols, (t1 - t0) / rows
    # Plane coordinates and depth of every corner in one product with the frame's axes.
    axes = np.stack([frame.u, frame.v, frame.normal], axis=1)
    q = np.einsum("ij,jk->ik", t.reshape(-1, 3), axes) - frame.origin @ axes  # faster than @ here
    # Pixel coordinates with pixel centres on integers: x to the right, y downwards.
    x = ((q[:, 0] - s0) / ps - 0.5).reshape(-1, 3)
    y = ((t1 - q[:, 1]) / pt - 0.5).reshape(-1, 3)
    depth = q[:, 2].reshape(-1, 3)  # larger is nearer the viewer
    del q

    def lo(a):  # per-facet minimum and maximum, without a slow reduction over an axis of 3
        return np.minimum(np.minimum(a[:, 0], a[:, 1]), a[:, 2])

    def hi(a):
        return np.maximum(np.maximum(a[:, 0], a[:, 1]), a[:, 2])

    c_lo = np.clip(np.ceil(lo(x)), 0, cols).astype(np.int64)
    c_hi = np.clip(np.floor(hi(x)), -1, cols - 1).astype(np.int64)
    r_lo = np.clip(np.ceil(lo(y)), 0, rows).astype(np.int64)
    r_hi = np.clip(np.floor(hi(y)), -1, rows - 1).astype(np.int64)
    w = np.maximum(c_hi - c_lo + 1, 0)
    count = w * np.maximum(r_hi - r_lo + 1, 0)
    live = np.flatnonzero(count > 0)  # facets that hold at least one pixel centre in their box

    best = np.full(rows * cols, -np.inf)
    owner = np.full(rows * cols, -1, dtype=np.int64)
    ends = np.searchsorted(np.cumsum(count[live]), np.arange(block, int(count[live].sum()) + block, block))
    start = 0
    for stop in np.unique(np.minimum(ends + 1, len(live))):  # over blocks of facets, not facets
        f = live[start:stop]
        start = stop
        if len(f) == 0:
            continue
        k = count[f]
        fid = np.repeat(f, k)
        j = within_group(k)
        px = c_lo[fid] + j % w[fid]
        py = r_lo[fid] + j // w[fid]
        # Edge functions: the pixel centre is inside when all three have the facet's orientation.
        xa, ya = x[fid], y[fid]
        e0 = (xa[:, 1] - xa[:, 0]) * (py - ya[:, 0]) - (ya[:, 1] - ya[:, 0]) * (px - xa[:, 0])
        e1 = (xa[:, 2] - xa[:, 1]) * (py - ya[:, 1]) - (ya[:, 2] - ya[:, 1]) * (px - xa[:, 1])
        e2 = (xa[:, 0] - xa[:, 2]) * (py - ya[:, 2]) - (ya[:, 0] - ya[:, 2]) * (px - xa[:, 2])
        total = e0 + e1 + e2
        inside = (((e0 >= 0) & (e1 >= 0) & (e2 >= 0)) | ((e0 <= 0) & (e1 <= 0) & (e2 <= 0))) & (total != 0)
        fid, pix = fid[inside], (py * cols + px)[inside]
        # Depth at the pixel centre from the barycentric weights (e1 weighs corner 0, e2 corner 1).
        dz = depth[fid]
        z = (e1[inside] * dz[:, 0] + e2[inside] * dz[:, 1] + e0[inside] * dz[:, 2]) / total[inside]
        cand = np.full(rows * cols, -np.inf)
        np.maximum.at(cand, pix, z)
        win = (z == cand[pix]) & (z > best[pix])
        best[pix[win]] = z[win]
        owner[pix[win]] = fid[win]

    hit = np.flatnonzero(owner >= 0)
    cos = n[owner[hit]] @ frame.normal
    light = (0.35 + 0.65 * np.abs(cos))[:, None]
    flat = out.reshape(-1, 4)
    flat[hit, :3] = np.where((cos >= 0)[:, None], _FACING, _BACK) * light
    flat[hit, 3] = 1.0
    return out


def _extent(split, margin: float = 0.04):
    frame = split.section.frame
    boxes = [split.section.bounds()] if len(split.section.segments) else []
    for m in (split.front, split.rear):
        if len(m):
            flat = m.triangles.reshape(-1, 3)
            lo, hi = flat.min(axis=0), flat.max(axis=0)
            corners = np.array([[x, y, z] for x in (lo[0], hi[0]) for y in (lo[1], hi[1])
                                for z in (lo[2], hi[2])])
            uv = frame.to_2d(corners)  # the bounding box's corners bound the projection
            boxes.append(np.stack([uv.min(axis=0), uv.max(axis=0)]))
    if not boxes:
        return -1.0, 1.0, -1.0, 1.0
    lo = np.min([b[0] for b in boxes], axis=0)
    hi = np.max([b[1] for b in boxes], axis=0)
    pad = margin * max(float((hi - lo).max()), 1e-9)
    return lo[0] - pad, hi[0] + pad, lo[1] - pad, hi[1] + pad


def _draw_section(ax, section, colour="#c0392b"):
    from matplotlib.patches import PathPatch
    from matplotlib.path import Path as MplPath
    for poly in section.polygons:
        rings = [poly.exterior, *poly.holes]
        verts = np.concatenate([np.vstack([r, r[:1]]) for r in rings])
        codes = np.concatenate([[MplPath.MOVETO] + [MplPath.LINETO] * (len(r) - 1) + [MplPath.CLOSEPOLY]
                                for r in rings])
        # Light fill, firm outline: for a solid part the section covers most of the picture.
        ax.add_patch(PathPatch(MplPath(verts, codes), facecolor=colour, alpha=0.25, edgecolor="none"))
        ax.add_patch(PathPatch(MplPath(verts, codes), facecolor="none", edgecolor=colour, lw=1.3))
    for chain in section.open_chains:
        ax.plot(chain[:, 0], chain[:, 1], color=colour, lw=1.2, ls="--")


def _figsize(extent) -> tuple[float, float]:
    s0, s1, t0, t1 = extent
    return 12.0, float(np.clip(6.0 * (t1 - t0) / max(s1 - s0, 1e-12), 2.5, 9.0)) + 1.0


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

    Examples
    --------
    >>> import matplotlib; matplotlib.use("Agg")
    >>> import slicelab
    >>> from slicelab.samples import torus
    >>> fig = draw_split(slicelab.split(torus(n_major=24, n_minor=12), (0, 0, 0), (0, 1, 0)), pixels=80)
    >>> [ax.get_title() for ax in fig.axes]
    ['front', 'rear (front lifted away)']
    """
    s0, s1, t0, t1 = _extent(split)
    scale = pixels / max(s1 - s0, t1 - t0)
    shape = (max(int(round((t1 - t0) * scale)), 1), max(int(round((s1 - s0) * scale)), 1))
    if axes is None:
        import matplotlib.pyplot as plt
        _, axes = plt.subplots(1, 2, figsize=_figsize((s0, s1, t0, t1)), constrained_layout=True)
    fig = axes[0].figure
    frame = split.section.frame
    panels = ((axes[0], split.front, "front"), (axes[1], split.rear, "rear (front lifted away)"))
    for ax, mesh, title in panels:
        img = render_depth(mesh.triangles, mesh.normals, frame, (s0, s1, t0, t1), shape)
        ax.imshow(img, extent=(s0, s1, t0, t1), origin="upper", interpolation="nearest")
        _draw_section(ax, split.section)
        ax.set_xlim(s0, s1)
        ax.set_ylim(t0, t1)
        ax.set_aspect("equal")
        ax.set_title(title)
        ax.set_xlabel("s (mm, plane frame)")
    axes[0].set_ylabel("t (mm, plane frame)")
    fig.suptitle(f"{split.n_front:,} facets in front, {split.n_cut:,} cut, {split.n_rear:,} behind; "
                 f"section {split.section.area:.6g} mm2 (red)", fontsize=10)
    return fig


def save_split_preview(split, path, *, pixels: int = 700, dpi: int = 100) -> None:
    """Write `draw_split` as a PNG, atomically.

    Examples
    --------
    >>> import slicelab, tempfile, os
    >>> from slicelab.samples import box
    >>> out = os.path.join(tempfile.mkdtemp(), "p.png")
    >>> save_split_preview(slicelab.split(box(), (0, 0, 0.5), (1, 1, 1)), out, pixels=60)
    >>> open(out, "rb").read(4)
    b'\\x89PNG'
    """
    from matplotlib.figure import (
        Figure,  # no pyplot: works under any backend, leaves no figure open
    )

    from ..mesh.io import atomic_path
    fig = Figure(figsize=_figsize(_extent(split)), layout="constrained")
    draw_split(split, pixels=pixels, axes=fig.subplots(1, 2))
    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=dpi, format="png")
