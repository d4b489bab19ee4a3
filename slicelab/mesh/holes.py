"""Holes: the loops of open edges of a mesh, and facets that close them.

A scan seldom sees all of its object (the underside of a bust, a pit the
light did not reach): its mesh has holes, loops of edges that only one facet
uses. A slicer needs closed solids, so PrusaSlicer closes such holes unasked
(admesh). `fill_holes` closes each loop with a fan of facets from the mean of
its vertices, wound against the loop so that every new edge pairs with the
open edge it closes: the mesh becomes watertight and its windings stay
consistent. A fan over a loop that is not star-shaped seen from its mean
folds over itself, but covers the loop's inside once in the sense of the
winding number, which is what the sections' fill rule reads. It is a guess at
surface nobody measured, so it is asked for (``--fill-holes``), and the
report gives the number of holes and the size of the largest.

See Also
--------
slicelab.mesh.repairs.repair : calls it with ``fill_holes=True``.
slicelab.geometry.chain_segments : chains the open edges into loops.
"""
from __future__ import annotations

import numpy as np

from ..geometry.chains import chain_segments
from ..geometry.topology import edge_table

__all__ = ["hole_loops", "fill_holes"]


def hole_loops(faces: np.ndarray, edges: dict | None = None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The closed loops of open edges, each in the direction its facets run along it.

    Parameters
    ----------
    faces : (n, 3) int ndarray
        A welded mesh's facets, windings consistent.
    edges : dict, optional
        `slicelab.geometry.edge_table` of `faces`, when at hand.

    Returns
    -------
    start, end : (m,) int ndarray
        Vertex ids of the open edges that close into loops, loop after loop, in walking order.
    bounds : (h + 1,) int ndarray
        Loop k is edges ``bounds[k]:bounds[k + 1]``. Open edges that do not close into a loop
        (windings that disagree along them) are left out.

    Examples
    --------
    >>> from slicelab.samples import box
    >>> from slicelab.geometry import weld
    >>> _, f = weld(box().triangles[2:])      # a cube without its first two facets: a square hole
    >>> start, end, bounds = hole_loops(f)
    >>> bounds.tolist(), bool(np.array_equal(np.roll(start, -1), end))
    ([0, 4], True)
    """
    f = np.asarray(faces, dtype=np.int64)
    et = edge_table(f) if edges is None else edges
    fe = et["first"][et["counts"] == 1]  # the facet edge of each open edge
    a = f.reshape(-1)[fe]
    b = f[:, [1, 2, 0]].reshape(-1)[fe]
    ch = chain_segments(a, b)
    keep = np.flatnonzero(ch.closed)
    if not len(keep):
        return np.zeros(0, np.int64), np.zeros(0, np.int64), np.zeros(1, np.int64)
    lengths = (ch.bounds[1:] - ch.bounds[:-1])[keep]
    order = np.concatenate([ch.order[ch.bounds[k]:ch.bounds[k + 1]] for k in keep])  # over loops (few)
    return a[order], b[order], np.concatenate([[0], np.cumsum(lengths)])


def fill_holes(vertices: np.ndarray, faces: np.ndarray) -> tuple[np.ndarray, np.ndarray, int, float]:
    """Close every loop of open edges with a fan of facets from the mean of its vertices.

    Parameters
    ----------
    vertices : (v, 3) float ndarray
    faces : (n, 3) int ndarray
        Windings consistent (`slicelab.mesh.repair` makes them so first).

    Returns
    -------
    vertices, faces : ndarray
        With one vertex per hole added, and the fans' facets after the others.
    n_holes : int
        Loops closed.
    largest : float
        The largest hole's size: its bounding box's diagonal (mm).

    Examples
    --------
    >>> from slicelab import check
    >>> from slicelab.samples import box
    >>> from slicelab.geometry import weld
    >>> v, f = weld(box((0, 0, 0), (2, 2, 2)).triangles[2:])
    >>> v2, f2, n, size = fill_holes(v, f)
    >>> n, round(size, 6), len(f2) - len(f)
    (1, 2.828427, 4)
    >>> from slicelab import Mesh
    >>> r = check(Mesh(v2[f2]))
    >>> r.watertight, r.winding_consistent, round(r.volume, 9)
    (True, True, 8.0)
    """
    v = np.asarray(vertices, dtype=np.float64)
    f = np.asarray(faces, dtype=np.int64)
    start, end, bounds = hole_loops(f)
    n_holes = len(bounds) - 1
    if n_holes == 0:
        return v, f, 0, 0.0
    loop = np.repeat(np.arange(n_holes), np.diff(bounds))
    # Each hole's centre: the mean of its vertices (each loop edge starts at one of them).
    centre = np.zeros((n_holes, 3))
    np.add.at(centre, loop, v[start])
    centre /= np.diff(bounds)[:, None]
    lo = np.full((n_holes, 3), np.inf)
    hi = np.full((n_holes, 3), -np.inf)
    np.minimum.at(lo, loop, v[start])
    np.maximum.at(hi, loop, v[start])
    largest = float(np.linalg.norm(hi - lo, axis=1).max())
    # The fan's facet on open edge a -> b runs b -> a -> centre: its edge b -> a pairs with a -> b.
    fan = np.stack([end, start, len(v) + loop], axis=1)
    return np.concatenate([v, centre]), np.concatenate([f, fan]), n_holes, largest
