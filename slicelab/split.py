"""Depth segmentation: split a mesh by a plane into front, section and rear (seed 000).

Every facet goes whole to one side or is cut along the plane, with the same
rule as the sections (a corner on the plane counts as in front). A facet with
two corners strictly on one side and one strictly on the other gives three
facets (pattern e), one with a corner on the plane and the others on either
side gives two (pattern c); facets touching the plane at a corner or an edge
stay whole. Cut points are computed exactly as the section computes them, so
front and rear meet edge to edge along the section.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .mesh import Mesh
from .sections import (_NEXT, Frame, Section, crossing_edges, edge_points, plane_distances,
                       section_from_distances)

__all__ = ["Split", "split", "split_facets"]


@dataclass(frozen=True, eq=False)
class Split:
    """A mesh split by a plane.

    Attributes
    ----------
    front : Mesh
        Facets on the side the plane's normal points to (and facets in the plane).
    rear : Mesh
        Facets behind the plane.
    section : Section
        The cut, in the plane's frame.
    n_front, n_cut, n_rear : int
        Input facets kept whole in front, cut by the plane, kept whole behind.
    """

    front: Mesh
    rear: Mesh
    section: Section
    n_front: int
    n_cut: int
    n_rear: int

    def __repr__(self) -> str:
        return (f"Split(front={len(self.front)} facets, rear={len(self.rear)} facets, "
                f"{self.n_cut} cut, {self.section!r})")


def split_facets(triangles: np.ndarray, dist: np.ndarray, frame: Frame | None = None):
    """Split facets by the plane whose corner distances are `dist`.

    Parameters
    ----------
    triangles : (n, 3, 3) ndarray
    dist : (n, 3) ndarray
        Signed corner distances (>= 0 counts as in front).
    frame : Frame, optional
        For a horizontal plane, cut points are put exactly at its height.

    Returns
    -------
    front, rear : (k, 3, 3) ndarrays
        Triangles on each side, each with its source facet's winding.
    front_src, rear_src : (k,) int ndarrays
        Index of the source facet of each triangle.
    n_cut : int
        Facets actually divided.

    Examples
    --------
    >>> t = np.array([[[0, 0, -1], [2, 0, -1], [0, 0, 1]]], float)
    >>> f, r, fs, rs, n = split_facets(t, t[..., 2])
    >>> len(f), len(r), n
    (1, 2, 1)
    """
    below = dist < 0
    nb = below.sum(axis=1)
    straddle = (nb > 0) & (nb < 3)
    whole_front = np.flatnonzero(nb == 0)
    whole_rear = np.flatnonzero(nb == 3)
    rows = np.flatnonzero(straddle)
    d = dist[rows]
    c = triangles[rows]
    down, up = crossing_edges(d)
    r = np.arange(len(rows))
    p_down = edge_points(c, d, r, _NEXT[down], down)
    p_up = edge_points(c, d, r, up, _NEXT[up])
    if frame is not None and frame.horizontal:
        # Put cut points exactly in the plane (corners on the plane already are).
        p_down[:, 2] = np.where(d[r, down] == 0, p_down[:, 2], frame.origin[2])
        p_up[:, 2] = np.where(d[r, _NEXT[up]] == 0, p_up[:, 2], frame.origin[2])

    # Walk each side's polygon in winding order: front is p_up, corners up+1 .. down, p_down;
    # rear is p_down, corners down+1 .. up, p_up. Each has 3 or 4 points; fan from the first.
    def corner(k):
        return c[r, k % 3]

    n_front_corners = (down - up) % 3  # 1 or 2
    two = n_front_corners == 2
    front_poly = np.stack([p_up, corner(up + 1), np.where(two[:, None], corner(up + 2), p_down),
                           p_down], axis=1)
    rear_two = ~two
    rear_poly = np.stack([p_down, corner(down + 1), np.where(rear_two[:, None], corner(down + 2), p_up),
                          p_up], axis=1)

    def fan(poly, quad):
        tris = np.concatenate([poly[:, [0, 1, 2]], poly[quad][:, [0, 2, 3]]])
        src = np.concatenate([rows, rows[quad]])
        a, b, cc = tris[:, 0], tris[:, 1], tris[:, 2]
        # A cut point that coincides with a corner on the plane leaves a degenerate piece: drop it.
        ok = np.any(a != b, axis=1) & np.any(b != cc, axis=1) & np.any(a != cc, axis=1)
        return tris[ok], src[ok]

    f_tris, f_src = fan(front_poly, two)
    r_tris, r_src = fan(rear_poly, rear_two)
    # Count a facet as cut only when it left pieces on both sides.
    n_cut = len(np.intersect1d(f_src, r_src))
    front = np.concatenate([triangles[whole_front], f_tris])
    rear = np.concatenate([triangles[whole_rear], r_tris])
    return front, rear, np.concatenate([whole_front, f_src]), np.concatenate([whole_rear, r_src]), n_cut


def split(mesh: Mesh, origin, normal, *, visible_from=None, max_gap: float = 1.0) -> Split:
    """Split a mesh by a plane into front, section and rear.

    Parameters
    ----------
    mesh : Mesh
    origin, normal : (3,) array_like
        The plane; `front` is the side `normal` points to.
    visible_from : (3,) array_like, optional
        A direction towards the viewer: only facets facing it (winding normal
        with a positive component along it) are kept in `front` and `rear`,
        as the diary did for drawing. The section is always complete.
    max_gap : float, default 1.0
        Passed to the section (joining of open chains, mm).

    Returns
    -------
    Split

    Examples
    --------
    >>> from slicelab.samples import box
    >>> s = split(box((0, 0, 0), (1, 1, 1)), (0, 0, 0.5), (0, 0, 1))
    >>> len(s.front), len(s.rear), s.n_cut, s.section.area
    (14, 14, 8, 1.0)
    """
    frame = Frame.from_plane(origin, normal)
    t = mesh.triangles
    dist = plane_distances(frame, t)
    front, rear, fs, rs, n_cut = split_facets(t, dist, frame)
    fn, rn = mesh.file_normals[fs], mesh.file_normals[rs]
    if visible_from is not None:
        view = np.asarray(visible_from, dtype=np.float64).reshape(3)
        if not np.any(view) or not np.isfinite(view).all():
            raise ValueError("visible_from must be a finite, non-zero direction")
        fk = mesh.normals[fs] @ view > 0
        rk = mesh.normals[rs] @ view > 0
        front, fn, rear, rn = front[fk], fn[fk], rear[rk], rn[rk]
    below = dist < 0
    nb = below.sum(axis=1)
    straddle = (nb > 0) & (nb < 3)
    n_front = int(np.count_nonzero(nb == 0))
    n_rear = int(np.count_nonzero(nb == 3))
    # Straddling facets that only touch the plane stay whole on one side.
    n_front += int(np.count_nonzero(straddle)) - n_cut - _touching_rear(dist[straddle])
    n_rear += _touching_rear(dist[straddle])
    sec = section_from_distances(frame, t, dist, max_gap)
    return Split(Mesh(front, fn), Mesh(rear, rn), sec, n_front, n_cut, n_rear)


def _touching_rear(d: np.ndarray) -> int:
    # Facets with no corner strictly in front (only corners on the plane) stay whole behind.
    return int(np.count_nonzero(~(d > 0).any(axis=1)))
