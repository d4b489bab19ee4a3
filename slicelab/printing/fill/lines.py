"""Rectilinear filling linked into zigzags along the region's boundary.

Fill lines are the lines ``n . x = k s`` (n the unit normal of the fill
direction, s the spacing, k any integer): the grid is anchored to the world
origin, so lines of different layers at the same angle line up. The lines
are clipped to the region's rings by one vectorised pass (each ring edge
yields the lines it crosses with ``np.repeat``), and consecutive lines are
joined where their ends are neighbours along the same ring: the zigzag then
follows the boundary between them and never crosses another line, so a
convex region is filled by one polyline.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ...geometry.polygons import Polygon
from ...geometry.ragged import expand_ranges, within_group

__all__ = ["FillLines", "fill_lines", "rectilinear", "line_spacing"]


def line_spacing(line_width: float, infill_density: float) -> float:
    """Distance between fill lines for an infill density (a fraction; 1 = solid).

    See Also
    --------
    rectilinear : the lines at that spacing.

    Examples
    --------
    >>> line_spacing(0.4, 0.2)
    2.0
    """
    if not (0 < infill_density <= 1):
        raise ValueError(f"infill density must be in (0, 1], got {infill_density!r}")
    return float(line_width) / float(infill_density)


@dataclass(frozen=True, eq=False)
class FillLines:
    """Fill lines clipped to rings, in the rotated frame where they are horizontal.

    Attributes
    ----------
    rings : list of (k, 2) ndarray
        The rings (rotated frame), material on the left.
    start, end : (n,) int ndarray
        Crossing index at each interval's two ends (left, right).
    line : (n,) int ndarray
        Line number k of each interval.
    xc : (c,) ndarray
        x of each crossing (rotated frame); its y is ``line * spacing``.
    ring, edge, t : (c,) ndarrays
        Ring, edge and parameter along the edge of each crossing.
    rot : (2, 2) ndarray
        Rotation taking world points to the rotated frame (``p @ rot.T``).
    spacing : float
    """

    rings: list
    start: np.ndarray
    end: np.ndarray
    line: np.ndarray
    xc: np.ndarray
    yc: np.ndarray
    ring: np.ndarray
    edge: np.ndarray
    t: np.ndarray
    rot: np.ndarray
    spacing: float


def _rotation(angle_deg: float) -> np.ndarray:
    a = np.radians(angle_deg)
    c, s = np.cos(a), np.sin(a)
    return np.array([[c, s], [-s, c]])  # world -> frame where the fill direction is +x


def fill_lines(polygons: list[Polygon], spacing: float, angle: float = 45.0) -> FillLines:
    """Clip the world-anchored family of fill lines to polygons.

    Parameters
    ----------
    polygons : list of Polygon
        The region (exteriors counter-clockwise, holes clockwise).
    spacing : float
        Distance between lines (mm).
    angle : float
        Direction of the lines, degrees from +x.

    Returns
    -------
    FillLines
        The intervals of the lines inside the region, in the frame where they are horizontal.

    See Also
    --------
    rectilinear : the lines linked into zigzags.

    Examples
    --------
    >>> sq = Polygon(np.array([[0, 0], [4, 0], [4, 4], [0, 4]], float) + 0.5, (), 0)
    >>> f = fill_lines([sq], 1.0, 0.0)
    >>> f.line.tolist(), f.xc[f.start].tolist(), f.xc[f.end].tolist()
    ([1, 2, 3, 4], [0.5, 0.5, 0.5, 0.5], [4.5, 4.5, 4.5, 4.5])
    """
    rot = _rotation(angle)
    rings = [np.asarray(r, np.float64) @ rot.T for p in polygons for r in (p.exterior, *p.holes)]
    empty = np.zeros(0, np.int64)
    if not rings:
        return FillLines([], empty, empty, empty, np.zeros(0), np.zeros(0), empty, empty, np.zeros(0), rot,
                         spacing)
    sizes = np.array([len(r) for r in rings])
    a = np.concatenate(rings)
    b = np.concatenate([q for r in rings for q in (r[1:], r[:1])])  # each vertex's successor
    ring_of = np.repeat(np.arange(len(rings)), sizes)
    edge_of = within_group(sizes)
    # Line k meets an edge when ceil(ymin / s) <= k < ceil(ymax / s): a shared vertex gives both
    # of its edges the same verdict, so a line through a vertex is crossed once (or not at all).
    k_lo = np.ceil(np.minimum(a[:, 1], b[:, 1]) / spacing).astype(np.int64)
    k_hi = np.ceil(np.maximum(a[:, 1], b[:, 1]) / spacing).astype(np.int64)
    idx, k = expand_ranges(k_lo, k_hi - k_lo)
    y = k * spacing
    t = (y - a[idx, 1]) / (b[idx, 1] - a[idx, 1])
    x = a[idx, 0] + t * (b[idx, 0] - a[idx, 0])
    entering = b[idx, 1] < a[idx, 1]  # material on the left of a downward edge lies at larger x
    order = np.lexsort((~entering, x, k))
    k, x, entering = k[order], x[order], entering[order]
    # Along a line crossings alternate enter, leave; pair them.
    starts = np.flatnonzero(entering)
    ok = (starts + 1 < len(k))
    starts = starts[ok]
    ends = starts + 1
    good = (k[ends] == k[starts]) & ~entering[ends] & (x[ends] > x[starts])
    starts, ends = starts[good], ends[good]
    return FillLines(rings, starts, ends, k[starts], x, y[order], ring_of[idx][order], edge_of[idx][order],
                     t[order], rot, float(spacing))


def rectilinear(polygons: list[Polygon], spacing: float, angle: float = 45.0, *,
                max_link: float | None = None, min_length: float | None = None) -> list[np.ndarray]:
    """Fill polygons with parallel lines linked into zigzags.

    Parameters
    ----------
    polygons : list of Polygon
    spacing : float
        Distance between lines (mm).
    angle : float, default 45
        Line direction in degrees.
    max_link : float, optional
        Longest stretch of boundary a link may follow (default 3 spacings,
        at least 3 mm).
    min_length : float, optional
        Line pieces shorter than this are left out (default a quarter of the
        spacing): a line grazing a corner of the region would only lay a stub
        (a move of a few hundredths of a millimetre).

    Returns
    -------
    list of (k, 2) ndarray
        World-coordinate polylines.

    See Also
    --------
    fill_lines : the clipped lines before linking.
    line_spacing : the spacing for an infill density.

    Examples
    --------
    >>> sq = Polygon(np.array([[0, 0], [4, 0], [4, 4], [0, 4]], float) + 0.5, (), 0)
    >>> paths = rectilinear([sq], 1.0, 0.0)
    >>> len(paths), paths[0].round(6).tolist()[:4]
    (1, [[0.5, 1.0], [4.5, 1.0], [4.5, 2.0], [0.5, 2.0]])
    """
    from ...geometry.segment_kernels import link_zigzags
    f = fill_lines(polygons, spacing, angle)
    if len(f.start) == 0:
        return []
    max_link = max(3 * spacing, 3.0) if max_link is None else max_link
    min_length = 0.25 * spacing if min_length is None else min_length
    n_cross = len(f.xc)
    interval_of = np.full(n_cross, -1, np.int64)
    interval_of[f.start] = np.arange(len(f.start))
    interval_of[f.end] = np.arange(len(f.start))
    other = np.full(n_cross, -1, np.int64)
    other[f.start], other[f.end] = f.end, f.start
    # Neighbours of each crossing along its ring.
    arc = np.zeros(n_cross)
    seg_len = [np.hypot(*(np.concatenate((r[1:], r[:1])) - r).T) for r in f.rings]
    cum = [np.concatenate([[0.0], np.cumsum(s)]) for s in seg_len]
    perim = np.array([c[-1] for c in cum])
    for r in range(len(f.rings)):  # over rings
        sel = np.flatnonzero(f.ring == r)
        arc[sel] = cum[r][f.edge[sel]] + f.t[sel] * seg_len[r][f.edge[sel]]
    order = np.lexsort((arc, f.ring))
    prev_c = np.full(n_cross, -1, np.int64)
    next_c = np.full(n_cross, -1, np.int64)
    bounds = np.searchsorted(f.ring[order], np.arange(len(f.rings) + 1))
    for r in range(len(f.rings)):  # over rings
        o = order[bounds[r]:bounds[r + 1]]
        if len(o) > 1:
            next_c[o] = np.concatenate((o[1:], o[:1]))
            prev_c[o] = np.concatenate((o[-1:], o[:-1]))
    # Stubs count as used: no path starts on one and no link goes to one.
    used = np.abs(f.xc[f.end] - f.xc[f.start]) < min_length
    sizes = np.array([len(r) for r in f.rings])
    # The intervals linked into zigzags by one compiled walk, starting at the lowest line.
    pts, bounds = link_zigzags(np.lexsort((f.xc[f.start], f.line)), used, next_c, prev_c, interval_of, other,
                               f.line, f.ring, f.edge, f.t, arc, perim, f.start, f.end, f.xc, f.yc,
                               np.concatenate(f.rings), np.concatenate([[0], np.cumsum(sizes)]), float(max_link))
    inv = f.rot  # rows are the frame axes: frame -> world is p @ rot
    return [pts[a:b] @ inv for a, b in zip(bounds[:-1].tolist(), bounds[1:].tolist())]  # over zigzags
