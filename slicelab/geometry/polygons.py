"""Polygons in the plane: signed area, point in ring, hole hierarchy, grouping loops into polygons.

See Also
--------
slicelab.geometry.chains : the closed loops these functions take.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["signed_area", "loop_edges", "points_in_ring", "loop_hierarchy", "Polygon", "build_polygons"]


def signed_area(points: np.ndarray) -> float:
    """Shoelace area of a closed ring (positive when counter-clockwise).

    Examples
    --------
    >>> signed_area(np.array([[0, 0], [1, 0], [1, 1], [0, 1]], float))
    1.0
    """
    p = np.asarray(points, dtype=np.float64)
    if len(p) < 3:
        return 0.0
    q = p - p[0]  # from a vertex: keeps the sum accurate far from the origin, and its term is 0
    x, y = q[:, 0], q[:, 1]
    return float(0.5 * (np.dot(x[:-1], y[1:]) - np.dot(x[1:], y[:-1])))


def loop_edges(loops) -> np.ndarray:
    """Every loop's edges, (m, 2, 2): each point to the next, the last back to the first.

    Examples
    --------
    >>> loop_edges([np.array([[0, 0], [1, 0], [0, 1]], float)]).tolist()
    [[[0.0, 0.0], [1.0, 0.0]], [[1.0, 0.0], [0.0, 1.0]], [[0.0, 1.0], [0.0, 0.0]]]
    """
    loops = [lp for lp in loops if len(lp)]
    if not loops:
        return np.zeros((0, 2, 2))
    pts = np.concatenate(loops)
    stops = np.cumsum([len(lp) for lp in loops])
    nxt = np.arange(1, len(pts) + 1)
    nxt[stops - 1] = np.concatenate([[0], stops[:-1]])  # (one gather for all loops)
    return np.stack([pts, pts[nxt]], axis=1)


def loop_hierarchy(loops: list[np.ndarray], areas: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Nesting depth and parent of each closed loop.

    Parameters
    ----------
    loops : list of (k, 2) ndarray
        Non-crossing closed rings.
    areas : (L,) ndarray, optional
        Their signed areas (`signed_area`), when already known.

    Returns
    -------
    depth : (L,) int ndarray
        How many other loops enclose each loop (0 for outermost).
    parent : (L,) int ndarray
        The smallest enclosing loop, or -1.

    Examples
    --------
    >>> sq = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], float)
    >>> loop_hierarchy([sq * 4, sq + 1, sq * 10 - 3])[0].tolist()
    [1, 2, 0]
    """
    L = len(loops)
    depth = np.zeros(L, dtype=np.int64)
    parent = np.full(L, -1, dtype=np.int64)
    if L < 2:
        return depth, parent
    from .polygon_kernels import ring_hierarchy
    areas = np.abs(np.array([signed_area(p) for p in loops]) if areas is None else np.asarray(areas, np.float64))
    bounds = np.concatenate([[0], np.cumsum([len(p) for p in loops])]).astype(np.int64)
    # One compiled pass: each loop, largest first, counts for the smaller loops whose first vertex
    # (which stands for its loop: the midpoint of its first edge would tie with a touching
    # neighbour as often) lies in its box and in it.
    return ring_hierarchy(np.ascontiguousarray(np.concatenate(loops), np.float64), bounds,
                          np.ascontiguousarray(areas), np.argsort(-areas))


def points_in_ring(points: np.ndarray, ring: np.ndarray) -> np.ndarray:
    """Which points lie inside a closed ring (even-odd crossing test, vectorised).

    Examples
    --------
    >>> sq = np.array([[0, 0], [2, 0], [2, 2], [0, 2]], float)
    >>> points_in_ring(np.array([[1.0, 1.0], [3.0, 1.0], [1.0, -0.5]]), sq).tolist()
    [True, False, False]
    """
    p = np.asarray(points, dtype=np.float64).reshape(-1, 2)
    r = np.asarray(ring, dtype=np.float64)
    x0, y0 = r[:, 0], r[:, 1]
    nxt = np.concatenate((r[1:], r[:1]))  # each vertex's successor (np.roll costs 6x more)
    x1, y1 = nxt[:, 0], nxt[:, 1]
    out = np.zeros(len(p), dtype=bool)
    step = max(1, 4_000_000 // max(len(r), 1))  # points per block: bounded temporaries
    for s in range(0, len(p), step):  # over blocks of points
        x, y = p[s:s + step, :1], p[s:s + step, 1:]
        straddle = (y0 > y) != (y1 > y)
        with np.errstate(divide="ignore", invalid="ignore"):
            xcross = x0 + (y - y0) * (x1 - x0) / (y1 - y0)
        out[s:s + step] = np.count_nonzero(straddle & (x < xcross), axis=1) % 2 == 1
    return out


@dataclass(frozen=True, eq=False)
class Polygon:
    """One region of material: an outer ring and its holes.

    Attributes
    ----------
    exterior : (k, 2) ndarray
        Counter-clockwise ring (implicitly closed).
    holes : tuple of (k, 2) ndarray
        Clockwise rings.
    depth : int
        Nesting depth of the exterior (0 outermost, 2 for an island in a hole...).
    """

    exterior: np.ndarray
    holes: tuple
    depth: int

    @property
    def area(self) -> float:
        """Area of the exterior minus its holes (mm^2)."""
        return signed_area(self.exterior) + sum(signed_area(h) for h in self.holes)


def build_polygons(loops: list[np.ndarray], depth: np.ndarray, parent: np.ndarray,
                   areas: np.ndarray | None = None) -> list[Polygon]:
    """Group loops into polygons: counter-clockwise loops are exteriors, clockwise ones holes.

    A clockwise loop with no counter-clockwise parent (an inside-out shell) is
    reported as an exterior of its own, reversed. `areas`, the loops' signed
    areas, are measured here unless given.

    Examples
    --------
    >>> sq = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], float)
    >>> loops = [sq * 4, (sq + 1)[::-1]]
    >>> polys = build_polygons(loops, *loop_hierarchy(loops))
    >>> len(polys), len(polys[0].holes), polys[0].area
    (1, 1, 15.0)
    """
    areas = np.array([signed_area(p) for p in loops]) if areas is None else np.asarray(areas)
    polys: dict[int, list] = {}
    for k in np.flatnonzero(areas >= 0):
        polys[int(k)] = [loops[k], [], int(depth[k])]
    for k in np.flatnonzero(areas < 0):
        p = int(parent[k])
        if p >= 0 and p in polys:
            polys[p][1].append(loops[k])
        else:
            polys[int(k)] = [loops[k][::-1], [], int(depth[k])]
    return [Polygon(ext, tuple(holes), d) for _, (ext, holes, d) in sorted(polys.items())]
