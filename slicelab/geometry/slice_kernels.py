"""A compiled loop over facet/plane pairs: the segments where a mesh's facets cross many horizontal planes.

`cut_planes` does, for every facet and every plane between its lowest and
highest corner, what `slicelab.geometry.planes.crossing_edges` and
`slicelab.geometry.planes.edge_points` do for one plane with numpy, with the
same operations in the same order, so its points are bit-identical to
theirs; it also gives each end point's vertex ids, from which
`slicelab.slicing.slice_layers` makes the keys that chain the segments. One
pass and no array per pair of corners, distances or ids: slicing comes before
any layer of a print is planned, on one core (`scripts/bench_sections.py`
times it).

See Also
--------
slicelab.geometry.planes : the rule for degenerate cases (a corner at distance >= 0 is above).
slicelab.slicing.slice_layers : the sections made from these segments.
"""
from __future__ import annotations

import numpy as np

from .compiled import njit

__all__ = ["cut_planes", "warm"]


@njit(cache=True, nogil=True)
def cut_planes(triangles, vertex, planes, lo, hi):
    """The segments where facets cross horizontal planes, facet after facet, planes in order.

    Parameters
    ----------
    triangles : (n, 3, 3) float64 ndarray
    vertex : (n, 3) int64 ndarray
        Each corner's vertex id (equal ids: the same point).
    planes : (m,) float64 ndarray
        Plane heights, increasing.
    lo, hi : (n,) int64 ndarrays
        Facet f meets planes lo[f] .. hi[f] - 1, each with a corner strictly below
        it (z < plane) and one at or above it.

    Returns
    -------
    segments : (s, 2, 2) float64 ndarray
        Start and end (x, y) of each segment, oriented as `slicelab.slicing.section`'s.
    ends : (s, 4) int64 ndarray
        The start's (above, other) and the end's (above, other) vertex ids: a point
        on an edge is (its above corner, its below corner), a corner in the plane is
        (that corner, that corner).
    plane : (s,) int64 ndarray
        Each segment's plane.

    Notes
    -----
    A facet whose only corner at or above the plane lies in it touches the plane at a
    point and gives no segment. Each edge's point is computed from its (below, above)
    corners in that order, ``pb + t (pa - pb)`` with ``t = db / (db - da)``, the above
    corner itself when it lies in the plane: the two facets that share an edge get the
    same point.
    """
    n = len(lo)
    total = 0
    for f in range(n):  # over facets: at most a segment per pair
        total += hi[f] - lo[f]
    segments = np.empty((total, 2, 2))
    ends = np.empty((total, 4), np.int64)
    plane = np.empty(total, np.int64)
    d = np.empty(3)
    s = 0
    for f in range(n):  # over facets
        for k in range(lo[f], hi[f]):  # over the planes the facet meets
            z = planes[k]
            for i in range(3):
                d[i] = triangles[f, i, 2] - z
            # The edge above -> below (down) and the edge below -> above (up): one of each.
            down = up = 0
            for i in range(3):
                j = i + 1 if i < 2 else 0
                if d[i] >= 0 and not d[j] >= 0:
                    down = i
                    break
            for i in range(3):
                j = i + 1 if i < 2 else 0
                if not d[i] >= 0 and d[j] >= 0:
                    up = i
                    break
            a0, b0 = down, (down + 1 if down < 2 else 0)  # the start: edge (below b0, above a0)
            b1, a1 = up, (up + 1 if up < 2 else 0)  # the end: edge (below b1, above a1)
            if a0 == a1 and d[a0] == 0:  # the only upper corner lies in the plane: a point
                continue
            for e in range(2):
                a, b = (a0, b0) if e == 0 else (a1, b1)
                da, db = d[a], d[b]
                if da == 0:
                    segments[s, e, 0] = triangles[f, a, 0]
                    segments[s, e, 1] = triangles[f, a, 1]
                    ends[s, 2 * e] = vertex[f, a]
                    ends[s, 2 * e + 1] = vertex[f, a]
                else:
                    t = db / (db - da)
                    xb, yb = triangles[f, b, 0], triangles[f, b, 1]
                    segments[s, e, 0] = xb + t * (triangles[f, a, 0] - xb)
                    segments[s, e, 1] = yb + t * (triangles[f, a, 1] - yb)
                    ends[s, 2 * e] = vertex[f, a]
                    ends[s, 2 * e + 1] = vertex[f, b]
            plane[s] = k
            s += 1
    return segments[:s], ends[:s], plane[:s]


def warm() -> None:
    """Call the kernel once with the types `slicelab.slicing.slice_layers` passes.

    Examples
    --------
    >>> warm()
    """
    i64 = np.zeros(1, np.int64)
    for writable in (True, False):  # a mesh's own arrays are read-only, a subset's are not
        t, v = np.zeros((1, 3, 3)), np.zeros((1, 3), np.int64)
        t.setflags(write=writable)
        v.setflags(write=writable)
        cut_planes(t, v, np.zeros(1), i64, i64)
