"""Compiled loops over closed rings: which rings hold which (the nesting of a layer's loops).

A layer's loops are nested (outer rings, holes, islands in holes) a few
times for every layer: its section, each perimeter level, the filling.
`ring_hierarchy` finds every ring's depth and smallest enclosing ring in one
compiled call, where a loop over the rings made several numpy calls each.

See Also
--------
slicelab.geometry.polygons.loop_hierarchy : the function that calls it and says what it means.

References
----------
.. [1] S. K. Lam, A. Pitrou, S. Seibert, "Numba: a LLVM-based Python JIT
   compiler", LLVM-HPC 2015.
"""
from __future__ import annotations

import numpy as np

from .compiled import njit

__all__ = ["ring_hierarchy", "warm"]


@njit(cache=True, nogil=True)
def _holds(points, s, e, x, y):
    """Whether ring ``points[s:e]`` (implicitly closed) holds point (x, y): the even-odd rule,
    crossings to the right of the point counted edge by edge."""
    inside = False
    for i in range(s, e):  # over the ring's edges
        j = i + 1 if i + 1 < e else s
        x0, y0, x1, y1 = points[i, 0], points[i, 1], points[j, 0], points[j, 1]
        if (y0 > y) != (y1 > y) and x < x0 + (y - y0) * (x1 - x0) / (y1 - y0):
            inside = not inside
    return inside


@njit(cache=True, nogil=True)
def ring_hierarchy(points, bounds, areas, order):
    """Nesting depth and smallest enclosing ring of each of the rings ``points[bounds[k]:bounds[k + 1]]``.

    A ring's first vertex stands for it. Each ring, in `order` (largest
    first), counts for every other ring no larger whose first vertex lies in
    its box and in it (even-odd rule); the smallest such ring is the parent.

    Parameters
    ----------
    points : (n, 2) float ndarray
    bounds : (L + 1,) int ndarray
    areas : (L,) float ndarray
        The rings' areas (absolute).
    order : (L,) int ndarray
        The rings by decreasing area.

    Returns
    -------
    depth, parent : (L,) int64 ndarrays
        Parent -1 where no ring holds one.
    """
    n = len(bounds) - 1
    depth = np.zeros(n, np.int64)
    parent = np.full(n, -1, np.int64)
    best = np.full(n, np.inf)
    lo = np.empty((n, 2))
    hi = np.empty((n, 2))
    for k in range(n):  # over rings: their boxes
        lo[k, 0], lo[k, 1] = points[bounds[k], 0], points[bounds[k], 1]
        hi[k, 0], hi[k, 1] = lo[k, 0], lo[k, 1]
        for i in range(bounds[k] + 1, bounds[k + 1]):
            lo[k, 0], lo[k, 1] = min(lo[k, 0], points[i, 0]), min(lo[k, 1], points[i, 1])
            hi[k, 0], hi[k, 1] = max(hi[k, 0], points[i, 0]), max(hi[k, 1], points[i, 1])
    for a in order:  # over rings, largest first
        for c in range(n):  # over the rings it may hold
            if c == a or areas[c] > areas[a]:
                continue
            x, y = points[bounds[c], 0], points[bounds[c], 1]
            if not (lo[a, 0] <= x <= hi[a, 0] and lo[a, 1] <= y <= hi[a, 1]):
                continue
            if _holds(points, bounds[a], bounds[a + 1], x, y):
                depth[c] += 1
                if areas[a] < best[c]:
                    parent[c] = a
                    best[c] = areas[a]
    return depth, parent


def warm() -> None:
    """Call every kernel once with the types its callers pass (see `slicelab.geometry.kernels.warm`).

    Examples
    --------
    >>> warm()
    """
    ring_hierarchy(np.zeros((3, 2)), np.array([0, 3], np.int64), np.zeros(1), np.zeros(1, np.int64))
