"""Planes: a plane's 2-D frame, exact signed distances, and where facet edges cross it.

One rule decides every degenerate case: a vertex whose signed distance to the
plane is >= 0 counts as *above*. A facet crosses the plane only when it has a
corner strictly below and one above. The point where an edge meets the plane
is computed from its (below, above) endpoints in that canonical order, so the
two facets sharing the edge get the bit-identical point.

See Also
--------
slicelab.slicing.section : the section of a mesh built from these kernels.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["Frame", "NEXT_CORNER", "crossing_edges", "edge_points", "plane_distances"]


@dataclass(frozen=True, eq=False)
class Frame:
    """A plane with a right-handed 2-D frame (u, v, normal).

    Plane coordinates (s, t) of a point p are ``((p - origin) . u, (p - origin) . v)``.
    For a horizontal plane facing +z, u = x and v = y and the origin is
    (0, 0, z), so plane coordinates are plain world (x, y); facing -z, v = -y.
    For a vertical or steep plane v points up (z projected onto the plane)
    and u = v x normal, so drawings stand upright; for a nearly horizontal
    one u follows x.

    Examples
    --------
    >>> f = Frame.from_plane((5, 5, 2), (0, 0, 1))
    >>> f.origin.tolist(), f.u.tolist(), f.v.tolist()
    ([0.0, 0.0, 2.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0])
    """

    origin: np.ndarray
    u: np.ndarray
    v: np.ndarray
    normal: np.ndarray

    @classmethod
    def from_plane(cls, origin, normal) -> "Frame":
        """Frame of the plane through `origin` with normal `normal` (any length).

        Examples
        --------
        >>> f = Frame.from_plane((0, 0, 0), (0, -1, 0))
        >>> f.u.tolist(), f.v.tolist()
        ([1.0, 0.0, 0.0], [0.0, 0.0, 1.0])
        """
        o = np.asarray(origin, dtype=np.float64).reshape(3)
        n = np.asarray(normal, dtype=np.float64).reshape(3)
        length = np.linalg.norm(n)
        if not (np.isfinite(length) and length > 0) or not np.isfinite(o).all():
            raise ValueError("the plane needs a finite origin and a non-zero normal")
        n = n / length
        if n[0] == 0 and n[1] == 0:  # horizontal: plain (x, y), or (x, -y) facing down
            s = 1.0 if n[2] > 0 else -1.0
            return cls(np.array([0.0, 0.0, o[2]]), np.array([1.0, 0.0, 0.0]),
                       np.array([0.0, s, 0.0]), np.array([0.0, 0.0, s]))
        if abs(n[2]) > 0.9:
            # Nearly horizontal: u follows x, as for the horizontal frame.
            u = np.array([1.0, 0.0, 0.0]) - n[0] * n
            u /= np.linalg.norm(u)
            return cls(o, u, np.cross(n, u), n)
        # Vertical or steep: v points up (z projected onto the plane), so drawings stand upright.
        v = np.array([0.0, 0.0, 1.0]) - n[2] * n
        v /= np.linalg.norm(v)
        return cls(o, np.cross(v, n) + 0.0, v + 0.0, n)

    @property
    def horizontal(self) -> bool:
        """True for a plane z = const."""
        return self.normal[0] == 0 and self.normal[1] == 0

    def to_2d(self, points) -> np.ndarray:
        """Plane coordinates of 3-D points (projected onto the plane)."""
        d = np.asarray(points, dtype=np.float64) - self.origin
        return np.stack([d @ self.u, d @ self.v], axis=-1)

    def to_3d(self, points) -> np.ndarray:
        """World coordinates of plane coordinates.

        Examples
        --------
        >>> Frame.from_plane((0, 0, 3), (0, 0, 1)).to_3d([[1, 2]]).tolist()
        [[1.0, 2.0, 3.0]]
        """
        p = np.asarray(points, dtype=np.float64)
        return self.origin + p[..., :1] * self.u + p[..., 1:2] * self.v

    def distances(self, points) -> np.ndarray:
        """Signed distances of 3-D points to the plane."""
        d = np.asarray(points, dtype=np.float64) - self.origin
        return d[..., 0] * self.normal[0] + d[..., 1] * self.normal[1] + d[..., 2] * self.normal[2]

    def to_dict(self) -> dict:
        return {k: getattr(self, k).tolist() for k in ("origin", "u", "v", "normal")}


#: The next corner of a triangle in winding order: edge ``i`` runs from corner i to ``NEXT_CORNER[i]``.
NEXT_CORNER = np.array([1, 2, 0])


def crossing_edges(dist: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The two edges where each straddling facet crosses the plane.

    Parameters
    ----------
    dist : (p, 3) ndarray
        Signed distances of the corners of facets that each have a corner
        below (< 0) and one above (>= 0).

    Returns
    -------
    down, up : (p,) int ndarrays
        Edge ``i`` runs from corner i to corner i+1 (winding order); `down`
        goes above -> below, `up` below -> above. The below/above corners of
        `down` are ``(down + 1) % 3, down`` and of `up` ``up, (up + 1) % 3``.

    Examples
    --------
    >>> crossing_edges(np.array([[-1.0, 1.0, 2.0]]))
    (array([2]), array([0]))
    """
    above = dist >= 0
    a_next = above[:, NEXT_CORNER]
    return np.argmax(above & ~a_next, axis=1), np.argmax(~above & a_next, axis=1)


def edge_points(corners: np.ndarray, dist: np.ndarray, rows, below, above) -> np.ndarray:
    """Where edges (below corner, above corner) of facets `rows` meet the plane.

    Always evaluated from the endpoints in the order (below, above), so the
    two facets sharing an edge get the bit-identical point; an above corner on
    the plane is returned exactly.

    Examples
    --------
    >>> c = np.array([[[0.0, 0.0], [4.0, 0.0], [0.0, 4.0]]])
    >>> edge_points(c, np.array([[-1.0, 3.0, 0.0]]), [0, 0], [0, 0], [1, 2]).tolist()
    [[1.0, 0.0], [0.0, 4.0]]
    """
    db, da = dist[rows, below], dist[rows, above]
    pb, pa = corners[rows, below], corners[rows, above]
    t = (db / (db - da))[:, None]
    return np.where((da == 0)[:, None], pa, pb + t * (pa - pb))


# Distances below this (mm, about 6e-73) count as zero for every plane: a cut that close to a
# corner makes pieces whose area is about the distance squared, and whose squared area (as any
# norm computes it) would underflow to zero.
_TINY = 2.0 ** -240
_CHUNK = 1 << 15  # facets per block: keeps the temporaries in cache


def _snap(dist: np.ndarray, bound: float) -> np.ndarray:
    for s in range(0, len(dist), _CHUNK):  # over blocks of facets, not facets
        x = dist[s:s + _CHUNK]
        x[np.abs(x) <= bound] = 0.0
    return dist


def plane_distances(frame: Frame, triangles: np.ndarray, *, snap: bool = True,
                    snap_axis_planes: bool = False) -> np.ndarray:
    """Signed distance of every corner to the plane, (n, 3).

    For a plane whose normal has one non-zero component (x, y or z = const)
    the computed sign is exact. For any other plane a corner that lies in the
    plane comes out a few ulps off it, with a sign decided by rounding;
    distances smaller than a bound on that rounding error are set to zero
    (`snap`), so such a corner is in the plane for sections, splits and cuts
    alike. For every plane, distances below 2^-240 mm count as zero too: a
    cut that close to a corner would leave pieces of no representable area.

    `snap_axis_planes` applies the same bound to planes x, y or z = const,
    whose distances are exact but whose corners may be meant to lie in them
    and come out an ulp off (a cavity's corner a fifth of the way across a
    part, the part then turned): `slicelab.cut` asks for it, as a pyramid of no
    representable size cut off such a corner would round away and leave its
    parts open. Sections keep exact distances there, as `slice_layers` does.

    Examples
    --------
    >>> f = Frame.from_plane((0, 0, 1), (0, 0, -1))
    >>> plane_distances(f, np.array([[[0, 0, 0], [0, 0, 1], [0, 0, 3]]], float)).tolist()
    [[1.0, 0.0, -2.0]]
    """
    if not snap:
        if frame.horizontal:
            return (triangles[..., 2] - frame.origin[2]) * frame.normal[2]
        return frame.distances(triangles)
    if frame.horizontal and not snap_axis_planes:  # z - z0: the sign is exact
        return _snap((triangles[..., 2] - frame.origin[2]) * frame.normal[2], _TINY)
    dist = np.empty(triangles.shape[:2])
    o = frame.origin
    n0, n1, n2 = frame.normal
    rounded = snap_axis_planes or np.count_nonzero(frame.normal) > 1
    reach = 0.0  # the largest |p - origin| along any axis
    for s in range(0, len(triangles), _CHUNK):  # over blocks of facets, not facets
        d = triangles[s:s + _CHUNK] - o
        x = d[..., 0] * n0
        x += d[..., 1] * n1  # same operations in the same order as Frame.distances
        x += d[..., 2] * n2
        dist[s:s + _CHUNK] = x
        if rounded and len(d):
            reach = max(reach, float(d.max()), -float(d.min()))
    bound = _TINY
    if rounded:
        # Rounding of p - o, of the products and of the sums is a few ulps of these terms.
        size = (reach + float(np.abs(o).max())) * float(np.abs(frame.normal).sum())
        bound = max(bound, 64 * np.finfo(np.float64).eps * size)
    return _snap(dist, bound)
