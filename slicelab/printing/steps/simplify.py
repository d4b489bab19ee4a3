"""Clean toolpaths: Douglas-Peucker simplification of many polylines at once.

A printer's planner stutters on streams of tiny moves, and a pixel contour or a
marching-squares ring has a vertex every pixel. Before a layer's paths are
written they are simplified to a tolerance (PrusaSlicer's ``gcode_resolution``,
0.0125 mm by default): a vertex is dropped when the simplified path passes
within the tolerance of it, so true corners stay and every original point
lies within the tolerance of the result.

The simplification is Douglas-Peucker's, with the distance to the chord
*segment* (not to its infinite line, as OpenCV's ``approxPolyDP`` measures:
that drops a path doubling back on itself), and it runs on every polyline of a
layer at once, in one compiled loop (`slicelab.geometry.segment_kernels.douglas_peucker`)
that splits each interval at its farthest vertex, with an explicit stack. A
closed polyline (last point equal to the first) keeps its first point, the seam.

References
----------
D. H. Douglas, T. K. Peucker, "Algorithms for the reduction of the number of
points required to represent a digitized line or its caricature",
The Canadian Cartographer 10(2), 1973.

See Also
--------
slicelab.geometry.contours.simplify_ring : the same algorithm on one ring.
"""
from __future__ import annotations

import numpy as np

__all__ = ["simplify_mask", "simplify_path", "simplify_paths", "simplify_rings", "simplify_rows"]


def simplify_mask(points: np.ndarray, keep: np.ndarray, tolerance: float) -> np.ndarray:
    """Douglas-Peucker on concatenated polylines: which vertices to keep.

    Parameters
    ----------
    points : (n, 2) ndarray
        The vertices of every polyline, one after another.
    keep : (n,) bool ndarray
        Vertices that must stay: at least the first and last vertex of every
        polyline (then no chord spans two polylines).
    tolerance : float
        Largest distance of a dropped vertex from the simplified path.

    Returns
    -------
    (n,) bool ndarray
        `keep` with the vertices the simplification needs added.

    See Also
    --------
    simplify_paths : a list of polylines simplified.

    Examples
    --------
    >>> pts = np.array([[0, 0], [1, 0.01], [2, 0], [2, 1], [0, 0], [5, 0], [2, 0]], float)
    >>> ends = np.array([1, 0, 0, 1, 1, 0, 1], bool)   # [0..3] and [4..6]
    >>> simplify_mask(pts, ends, 0.05).astype(int).tolist()   # the point 3 mm back along the line stays
    [1, 0, 1, 1, 1, 1, 1]
    """
    from ...geometry.segment_kernels import douglas_peucker
    pts = np.ascontiguousarray(points, np.float64)
    return douglas_peucker(pts, np.ascontiguousarray(keep, bool), float(tolerance))


def simplify_paths(paths: list, tolerance: float, widths: list | None = None):
    """Simplify polylines (open, or closed with the last point equal to the first) to a tolerance.

    Every polyline keeps its two ends (a closed one its seam) and at least
    two vertices; every dropped vertex lies within `tolerance` of the
    simplified polyline.

    Parameters
    ----------
    paths : list of (k, 2) ndarray
    tolerance : float
        mm; 0 keeps every vertex.
    widths : list of (k,) ndarray, optional
        Per-vertex values to thin in step with the vertices (gap fill widths).

    Returns
    -------
    list of (m, 2) ndarray, or (list, list) when `widths` is given

    See Also
    --------
    simplify_path : one polyline.
    simplify_rings : rings that are implicitly closed.

    Examples
    --------
    >>> t = np.linspace(0, np.pi, 200)
    >>> arc = np.c_[50 * np.cos(t), 50 * np.sin(t)]
    >>> line = np.array([[0, 0], [1, 0], [2, 0], [3, 0]], float)
    >>> [len(p) for p in simplify_paths([arc, line], 0.0125)]
    [72, 2]
    """
    if not paths:
        return ([], []) if widths is not None else []
    sizes = np.array([len(p) for p in paths])
    pts = np.concatenate([np.asarray(p, np.float64).reshape(-1, 2) for p in paths])
    ends = np.zeros(len(pts), bool)
    stops = np.cumsum(sizes)
    ends[stops[sizes > 0] - 1] = True
    ends[(stops - sizes)[sizes > 0]] = True
    keep = simplify_mask(pts, ends, tolerance) if tolerance > 0 else np.ones(len(pts), bool)
    spans = list(zip((stops - sizes).tolist(), stops.tolist()))
    out = [pts[a:b][keep[a:b]] for a, b in spans]
    if widths is None:
        return out
    w = np.concatenate([np.broadcast_to(np.asarray(x, np.float64), (n,)) for x, n in zip(widths, sizes)])
    return out, [w[a:b][keep[a:b]] for a, b in spans]


def simplify_path(path: np.ndarray, tolerance: float) -> np.ndarray:
    """One polyline simplified to a tolerance (see `simplify_paths`).

    Examples
    --------
    >>> simplify_path(np.array([[0, 0], [1, 0.001], [2, 0], [2, 2]]), 0.01).tolist()
    [[0.0, 0.0], [2.0, 0.0], [2.0, 2.0]]
    """
    return simplify_paths([path], tolerance)[0]


def simplify_rings(rings: list, tolerance: float) -> list:
    """Implicitly closed rings (first point not repeated) simplified to a tolerance.

    Each ring keeps its first vertex and at least one other; every dropped
    vertex lies within `tolerance` of the simplified ring.

    See Also
    --------
    simplify_paths : open and explicitly closed polylines.

    Examples
    --------
    >>> sq = np.array([[0, 0], [1, 0], [2, 0], [2, 2], [1, 2.001], [0, 2]], float)
    >>> simplify_rings([sq], 0.01)[0].tolist()
    [[0.0, 0.0], [2.0, 0.0], [2.0, 2.0], [0.0, 2.0]]
    """
    closed = [np.vstack([r, r[:1]]) for r in rings]
    return [q[:-1] for q in simplify_paths(closed, tolerance)]


def simplify_rows(kinds: list, paths: list, widths: list, resolution: float) -> tuple[list, list]:
    """The simplify step: each row of a layer's table simplified to `resolution` (its ends, seam and
    corners kept, so the travel between paths is unchanged; gap fill keeps a width at each vertex).

    Returns
    -------
    paths, widths : list

    Examples
    --------
    >>> line = np.array([[0, 0], [1, 1e-4], [2, 0]], float)
    >>> p, w = simplify_rows(["solid"], [line], [0.4], 0.01)
    >>> p[0].tolist(), w
    ([[0.0, 0.0], [2.0, 0.0]], [0.4])
    """
    gap = np.array([k == "gap_fill" for k in kinds], bool)
    simple, widths = list(paths), list(widths)
    rows = np.flatnonzero(~gap)
    for i, q in zip(rows, simplify_paths([paths[i] for i in rows], resolution)):
        simple[i] = q
    rows = np.flatnonzero(gap)
    got, gw = simplify_paths([paths[i] for i in rows], resolution, [widths[i] for i in rows])
    for i, q, w in zip(rows, got, gw):
        simple[i], widths[i] = q, w
    return simple, widths
