"""Watertight cuts: split a solid by a plane and cap both parts.

A solid too big for a printer is cut so that the parts can be built apart:
split the facets along the plane, find the edges in the plane that really
bound the cut, and fill the cut face with a constrained Delaunay
triangulation that respects holes and concave outlines, for any plane. Here:

* The facets are split by `slicelab.slicing.split_facets`, so the rear part
  keeps everything behind the plane and the front part everything at or in
  front of it.
* The cap of each part is the section of the material *just on its side* of
  the plane (the limit of sections taken towards the plane from that side).
  This settles the edge-neighbourhood analysis of in-plane edges in one
  rule: an edge lying in the plane bounds the rear cap when a facet behind
  the plane uses it, the front cap when a facet in front does; facets lying
  in the plane ("on+" and "on-") are dropped, because the caps cover them
  (on+: the cap of the side the facet faces away from covers it, on-: the
  other cap does).
* The caps are made by `slicelab.slicing.cap` from the split's own pieces,
  so every cap vertex is, bit for bit, a 3-D cut point of the split and the
  parts close with no crack and no T-junction, for tilted planes too.

See Also
--------
slicelab.slicing.split.split : the split alone (two open shells and the section).
slicelab.slicing.stair.stair_cut : a cut with an interlocking stair-shaped joint.
slicelab.slicing.partition.partition : cuts until every piece fits a build volume.

References
----------
.. [1] H.-C. Chae, H.-Y. Kang, S.-H. Yoo, S.-H. Lee, H.-Y. Moon, "Development of
   slicing algorithm for rapid prototyping building about big sized objects"
   (re-splitting of facets, the on+/on- edge neighbourhood, constrained
   Delaunay caps for any plane).
"""
from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np

from ..geometry.planes import Frame, plane_distances
from ..mesh.core import Mesh
from .cap import Cap, cap_segments, plane_edges
from .split import split_facets

__all__ = ["CutWarning", "CutReport", "Cut", "cut"]


class CutWarning(UserWarning):
    """A cut whose section did not close everywhere (the input was not watertight)."""


@dataclass(frozen=True)
class CutReport:
    """What `cut` did.

    Attributes
    ----------
    frame : Frame
        The cutting plane, with the 2-D frame the caps are triangulated in.
    rear_cap, front_cap : Cap
        The faces that close the rear and the front part.
    n_cut : int
        Input facets divided by the plane.
    n_in_plane : int
        Input facets lying in the plane (dropped: the caps cover them).
    """

    frame: Frame
    rear_cap: Cap
    front_cap: Cap
    n_cut: int
    n_in_plane: int

    @property
    def closed(self) -> bool:
        """Both caps closed: the parts are watertight when the input was."""
        return self.rear_cap.closed and self.front_cap.closed

    def describe(self) -> str:
        """One line for people."""
        parts = [f"cut {self.n_cut} facets", f"{self.n_in_plane} in the plane",
                 f"rear cap {len(self.rear_cap.triangles)} triangles {self.rear_cap.area:.6g} mm2",
                 f"front cap {len(self.front_cap.triangles)} triangles {self.front_cap.area:.6g} mm2"]
        for name, cap in (("rear", self.rear_cap), ("front", self.front_cap)):
            if cap.open_chains:
                parts.append(f"{name}: {len(cap.open_chains)} open chains not capped")
            if cap.n_failed:
                parts.append(f"{name}: {cap.n_failed} polygons not triangulated")
            parts += [f"{name}: {note}" for note in cap.notes]
        return "; ".join(parts)


@dataclass(frozen=True, eq=False)
class Cut:
    """The two closed parts of a cut, and the `report` of how it went.

    Attributes
    ----------
    rear : Mesh
        The part on the side against the plane's normal.
    front : Mesh
        The part on the side the normal points to.
    report : CutReport
        The plane, both caps, and what did not close.

    Iterating gives ``(rear, front)``, so ``rear, front = cut(...)`` unpacks
    the parts.
    """

    rear: Mesh
    front: Mesh
    report: CutReport

    def __iter__(self):
        return iter((self.rear, self.front))

    def __repr__(self) -> str:
        return f"Cut(rear={self.rear!r}, front={self.front!r}; {self.report.describe()})"


# ------------------------------------------------------------------ the cut
def _to_2d(frame: Frame, mirror: bool):
    sign = -1.0 if mirror else 1.0

    def f(points):
        if frame.horizontal:  # exact: plain (x, y), with y negated facing down
            return points[:, :2] * np.array([1.0, frame.v[1] * sign])
        q = frame.to_2d(points)
        q[:, 1] *= sign
        return q
    return f


def cut(mesh: Mesh, origin, normal) -> Cut:
    """Cut a solid by a plane into two closed parts, each capped on the plane.

    Parameters
    ----------
    mesh : Mesh
        Ideally watertight with outward normals; otherwise what closes is
        capped and the rest is reported (`CutWarning`, ``report``).
    origin, normal : (3,) array_like
        The plane; any direction, need not be unit length.

    Returns
    -------
    Cut
        ``rear`` (the side against `normal`) and ``front``, each watertight
        (every edge shared by two facets, walked once each way, normals
        outward) when the input is; ``report`` holds the caps.

    Warns
    -----
    CutWarning
        When a cap did not close everywhere (the input was not watertight).

    See Also
    --------
    slicelab.slicing.split.split : the split alone, without caps.
    slicelab.slicing.stair.stair_cut : a cut with an interlocking stair-shaped joint.
    slicelab.slicing.partition.partition : cuts until every piece fits a build volume.

    References
    ----------
    .. [1] H.-C. Chae, H.-Y. Kang, S.-H. Yoo, S.-H. Lee, H.-Y. Moon, "Development
       of slicing algorithm for rapid prototyping building about big sized
       objects".

    Examples
    --------
    >>> from slicelab.samples import box
    >>> from slicelab import check
    >>> c = cut(box((0, 0, 0), (2, 2, 2)), (0, 0, 0.5), (0, 0, 1))
    >>> [(check(p).watertight, round(check(p).volume, 9)) for p in (c.rear, c.front)]
    [(True, 2.0), (True, 6.0)]
    >>> c.report.rear_cap.area
    4.0
    """
    frame = Frame.from_plane(origin, normal)
    t = mesh.triangles
    # (corners an ulp off a plane x, y or z = const count as in it, as on tilted planes)
    dist = plane_distances(frame, t, snap_axis_planes=True)
    front, rear, front_src, rear_src, n_cut = split_facets(t, dist, frame)
    in_plane = ~np.any(dist != 0, axis=1)
    n_in_plane = int(np.count_nonzero(in_plane))
    if n_in_plane:
        keep = ~in_plane[front_src]
        front, front_src = front[keep], front_src[keep]
    # Only facets reaching the plane can have an edge in it.
    near_r = np.flatnonzero(np.any(dist >= 0, axis=1)[rear_src])
    near_f = np.flatnonzero(np.any(dist <= 0, axis=1)[front_src])
    src_r, src_f = rear_src[near_r], front_src[near_f]
    tol = _rounding(frame, t[np.concatenate([src_r, src_f])])
    rs, re = plane_edges(rear[near_r], t[src_r], dist[src_r], -1, tol)
    fs, fe = plane_edges(front[near_f], t[src_f], dist[src_f], +1, tol)
    rear_cap = cap_segments(rs, re, _to_2d(frame, False))
    if _same_edges(rs, re, fe, fs):
        # The usual case: the section seen from the front is the rear one run backwards.
        front_cap = rear_cap.reversed()
    else:
        # Facets in the plane (or an open input) make the two sides differ: cap each on its own.
        front_cap = cap_segments(fs, fe, _to_2d(frame, True))
    report = CutReport(frame, rear_cap, front_cap, int(n_cut), n_in_plane)
    if not report.closed:
        warnings.warn(f"cut: the section did not close everywhere ({report.describe()})", CutWarning,
                      stacklevel=2)
    return Cut(Mesh(_join(rear, rear_cap)), Mesh(_join(front, front_cap)), report)


def _rounding(frame: Frame, near: np.ndarray) -> float:
    """How far off a tilted plane a corner can be and still meet a cut point rounded onto it."""
    if np.count_nonzero(frame.normal) <= 1 or len(near) == 0:
        return 0.0  # x, y or z = const: the split puts cut points exactly in the plane
    reach = np.abs(near.reshape(-1, 3)).max(axis=0) + np.abs(frame.origin)
    return 64 * np.finfo(np.float64).eps * float(reach @ np.abs(frame.normal))


def _same_edges(a0, a1, b0, b1) -> bool:
    """Whether two sets of 3-D edges are equal as multisets."""
    if len(a0) != len(b0):
        return False
    if len(a0) == 0:
        return True
    a = np.concatenate([a0, a1], axis=1) + 0.0
    b = np.concatenate([b0, b1], axis=1) + 0.0
    a = a[np.lexsort(a.T[::-1])]
    b = b[np.lexsort(b.T[::-1])]
    return bool(np.array_equal(a, b))


def _join(pieces: np.ndarray, cap: Cap) -> np.ndarray:
    out = np.empty((len(pieces) + len(cap.triangles), 3, 3))
    out[:len(pieces)] = pieces
    out[len(pieces):] = cap.vertices
    return out
