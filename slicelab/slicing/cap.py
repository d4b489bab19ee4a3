"""Caps: the flat faces that close a part where a plane cut it.

A cap is built from oriented cut edges lying in the plane:

* `plane_edges` reads them off one side's split facets (the in-plane edges
  no other piece of that side walks back), so every cap vertex is, bit for
  bit, a 3-D cut point of the split and the part closes with no crack and no
  T-junction, for tilted planes too.
* `cap_segments` chains them into loops and fills the loops with GEOS's
  constrained Delaunay triangulation (through shapely), polygon by polygon:
  an outer loop with its holes; islands in holes are polygons of their own.
  The 2-D coordinates only serve the triangulation: each triangle vertex
  carries the index of its 3-D point through GEOS (as the Z coordinate), so
  nothing is rounded back to 3-D.

See Also
--------
slicelab.slicing.cut.cut : a plane cut whose two parts are closed by caps.
slicelab.slicing.stair.stair_cut : caps of band and tread planes build the stair joint.

References
----------
.. [1] H.-C. Chae, H.-Y. Kang, S.-H. Yoo, S.-H. Lee, H.-Y. Moon, "Development of
   slicing algorithm for rapid prototyping building about big sized objects"
   (the cut face filled with a constrained Delaunay triangulation that
   respects holes and concave outlines).
.. [2] L. P. Chew, "Constrained Delaunay triangulations", Algorithmica 4,
   pp. 97-108, 1989.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..geometry.chains import chain_segments
from ..geometry.planes import NEXT_CORNER
from ..geometry.polygons import loop_hierarchy, signed_area
from ..geometry.ragged import within_group
from ..geometry.topology import exact_ids
from ..geometry.triangles import triangle_areas

__all__ = ["Cap", "plane_edges", "cap_segments", "triangle_min_angles"]


@dataclass(frozen=True, eq=False)
class Cap:
    """The triangulated face of a part in the cutting plane.

    Attributes
    ----------
    points : (p, 3) ndarray
        The cut points (exact 3-D points of the split's facets).
    triangles : (k, 3) int ndarray
        Cap triangles, indices into `points`, wound so that their normal
        points out of the part.
    edges : (m, 2) int ndarray
        The cut edges bounding the cap, as point indices, oriented like the
        cap's triangles (outer loops counter-clockwise about its normal).
    loops : list of (j,) int ndarrays
        Closed loops of `edges`, as point indices.
    open_chains : list of (j, 3) ndarrays
        Chains of cut edges that did not close (an open or broken input).
    n_failed : int
        Polygons whose triangulation failed the checks (not capped).
    notes : tuple of str
        Loops that are not simple polygons (they cross or touch themselves or
        each other, as sections of self-intersecting surfaces do), where, and
        how they were closed anyway.
    """

    points: np.ndarray
    triangles: np.ndarray
    edges: np.ndarray
    loops: list = field(default_factory=list)
    open_chains: list = field(default_factory=list)
    n_failed: int = 0
    notes: tuple = ()

    @property
    def vertices(self) -> np.ndarray:
        """(k, 3, 3) corners of the cap triangles."""
        return self.points[self.triangles]

    @property
    def area(self) -> float:
        """Area of the cap (mm^2)."""
        return float(triangle_areas(self.vertices).sum())

    @property
    def closed(self) -> bool:
        """Every cut edge closed into a loop and every polygon was triangulated."""
        return not self.open_chains and self.n_failed == 0

    def reversed(self) -> Cap:
        """The same cap facing the other way (for the partner part)."""
        return Cap(self.points, self.triangles[:, ::-1].copy(), self.edges[:, ::-1].copy(),
                   [lp[::-1] for lp in self.loops], [c[::-1] for c in self.open_chains], self.n_failed, self.notes)


# ------------------------------------------------------------------ cut edges
def plane_edges(pieces: np.ndarray, corners: np.ndarray, corner_dist: np.ndarray,
                side: int, tol: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
    """The edges of one side's split facets that a cap must close, run the way the cap runs them.

    `pieces` are the facets of one side that reach the plane (pieces of cut
    facets, facets touching it). Their edges in the plane are those no other
    piece of the set walks back and that do not end at a corner of the input
    lying off the plane (compared bit for bit with the piece's source facet).
    Taking the cap's edges from the split's own pieces makes the cap meet them
    exactly, whatever arithmetic put the cut points where they are; an input
    edge left open near the plane is not mistaken for one.

    Parameters
    ----------
    pieces : (k, 3, 3) ndarray
        Facets of one side, as `split_facets` gives them, that reach the plane.
    corners : (k, 3, 3) ndarray
        The input facet each piece comes from (``triangles[source]``).
    corner_dist : (k, 3) ndarray
        Its corner distances, as given to `split_facets`.
    side : {-1, +1}
        -1 for the rear pieces, +1 for the front pieces.
    tol : float, default 0
        Corners closer to the plane than this may coincide with a cut point
        that rounded onto them: they are not taken as off the plane.

    Returns
    -------
    start, end : (m, 3) ndarrays
        Each edge reversed: material on the left seen from outside that
        side's part, through the plane.

    See Also
    --------
    cap_segments : fills the loops these edges make.
    slicelab.slicing.split_facets : the split whose pieces these are.

    Examples
    --------
    >>> from slicelab.slicing import split_facets
    >>> from slicelab.samples import box
    >>> t = box().triangles
    >>> d = t[..., 2] - 0.5
    >>> f, r, fs, rs, _ = split_facets(t, d)
    >>> s, e = plane_edges(r, t[rs], d[rs], -1)
    >>> len(s), bool(np.all(s[:, 2] == 0.5)), round(float(np.linalg.norm(e - s, axis=1).sum()), 9)
    (8, True, 4.0)
    """
    k = len(pieces)
    if k == 0:
        return np.zeros((0, 3)), np.zeros((0, 3))
    strict = (corner_dist * side) > tol
    same = np.all(pieces[:, :, None, :] == corners[:, None, :, :], axis=-1)  # piece corner i == source corner j
    away = np.any(same & strict[:, None, :], axis=2)  # a corner of the input on this side, off the plane
    vid, _ = exact_ids(pieces.reshape(-1, 3))
    vid = vid.reshape(k, 3)
    a, b = vid.reshape(-1), vid[:, NEXT_CORNER].reshape(-1)
    keep = _cancel_pairs(a, b) & ~(away.reshape(-1) | away[:, NEXT_CORNER].reshape(-1)) & (a != b)
    rows, i = np.divmod(np.flatnonzero(keep), 3)
    return pieces[rows, NEXT_CORNER[i]], pieces[rows, i]


# ------------------------------------------------------------------ loops
def _cancel_pairs(sid: np.ndarray, eid: np.ndarray) -> np.ndarray:
    """Mask of edges kept after cancelling each a->b against a b->a.

    Two facets on the same side sharing an edge in the plane (a ridge lying in
    it) give the edge both ways: they close against each other, not the cap.
    """
    keep = np.ones(len(sid), bool)
    if len(sid) == 0:
        return keep
    und, _ = exact_ids(np.stack([np.minimum(sid, eid), np.maximum(sid, eid)], axis=1))
    fwd = sid < eid
    n_f = np.bincount(und, weights=fwd)
    n_b = np.bincount(und, weights=~fwd)
    cancel = np.minimum(n_f, n_b)
    if not cancel.any():
        return keep
    # Runs of the same edge walked the same way; the first `cancel` of each run go.
    order = np.lexsort((fwd, und))
    u, f = und[order], fwd[order]
    new = np.ones(len(u), bool)
    new[1:] = (u[1:] != u[:-1]) | (f[1:] != f[:-1])
    starts = np.flatnonzero(new)
    keep[order] = within_group(np.diff(np.append(starts, len(u)))) >= cancel[u]
    return keep


def _simple_cycles(loop: np.ndarray) -> list[np.ndarray]:
    """Split a closed walk that visits a point twice into simple cycles."""
    if len(np.unique(loop)) == len(loop):
        return [loop]
    out, stack, where = [], [], {}
    for v in loop.tolist():  # over the points of one pinched loop (rare)
        if v in where:
            k = where[v]
            cyc = stack[k:]
            for w in cyc[1:]:
                del where[w]
            del stack[k + 1:]
            out.append(np.array(cyc))
        else:
            where[v] = len(stack)
            stack.append(v)
    if len(stack) > 1:
        out.append(np.array(stack))
    return [c for c in out if len(c) >= 3]


def _drop_repeats(ring: np.ndarray, p2: np.ndarray, slivers: list) -> np.ndarray:
    """Remove consecutive points with equal 2-D coordinates (distinct in 3-D).

    A tilted plane can project two cut points a hair apart onto the same 2-D
    point. The ring keeps one; a zero-area triangle (a, b, c) along the ring
    restores the edges a-b, b-c the parts need.
    """
    while len(ring) >= 3:
        q = p2[ring]
        same = np.all(q == np.roll(q, -1, axis=0), axis=1)
        if not same.any():
            break
        i = int(np.flatnonzero(same)[0])
        n = len(ring)
        a, b, c = ring[i], ring[(i + 1) % n], ring[(i + 2) % n]
        slivers.append((a, b, c))
        ring = np.delete(ring, (i + 1) % n)
    return ring


# ------------------------------------------------------------------ capping
def cap_segments(start: np.ndarray, end: np.ndarray, to_2d) -> Cap:
    """Chain oriented 3-D cut edges into loops and fill them with a constrained Delaunay triangulation.

    Parameters
    ----------
    start, end : (m, 3) ndarrays
        Oriented edges (material on the left seen from the cap's outside),
        such as `plane_edges` gives.
    to_2d : callable
        Maps (k, 3) points to (k, 2) coordinates in which the material lies
        on the left of the edges (outer loops counter-clockwise).

    Returns
    -------
    Cap
        Triangles wound counter-clockwise in `to_2d` coordinates.

    See Also
    --------
    plane_edges : the edges of a split that a cap closes.
    slicelab.geometry.chain_segments : the chaining of edges into loops.

    References
    ----------
    .. [1] L. P. Chew, "Constrained Delaunay triangulations", Algorithmica 4,
       pp. 97-108, 1989.

    Examples
    --------
    >>> sq = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], float)
    >>> cap = cap_segments(sq, np.roll(sq, -1, axis=0), lambda p: p[:, :2])
    >>> len(cap.triangles), cap.area, cap.closed
    (2, 1.0, True)
    """
    start = np.asarray(start, dtype=np.float64).reshape(-1, 3)
    end = np.asarray(end, dtype=np.float64).reshape(-1, 3)
    m = len(start)
    ids, first = exact_ids(np.concatenate([start, end]))
    points = np.concatenate([start, end])[first]
    sid, eid = ids[:m], ids[m:]
    ok = sid != eid  # edges that round to zero length are points: they bound nothing
    sid, eid = sid[ok], eid[ok]
    keep = _cancel_pairs(sid, eid)
    sid, eid = sid[keep], eid[keep]
    edges = np.stack([sid, eid], axis=1)

    chains = chain_segments(sid, eid)
    loops, open_chains = [], []
    for k in range(len(chains)):  # over chains, not edges
        idx = chains.order[chains.bounds[k]:chains.bounds[k + 1]]
        if chains.closed[k]:
            loops += _simple_cycles(sid[idx])
        else:
            open_chains.append(points[np.append(sid[idx], eid[idx[-1]])])

    p2 = np.asarray(to_2d(points), dtype=np.float64).reshape(-1, 2) if len(points) else np.zeros((0, 2))
    slivers: list = []
    rings = [r for r in (_drop_repeats(lp, p2, slivers) for lp in loops) if len(r) >= 3]
    areas = np.array([signed_area(p2[r]) for r in rings])
    nonzero = areas != 0
    # A loop of zero signed area that is not flat (lobes of opposite winding that cancel) still
    # bounds cut edges: it is closed on its own.
    crossed = [r for r, z in zip(rings, nonzero) if not z and _spread(p2[r]) > 0]
    rings = [r for r, z in zip(rings, nonzero) if z]
    areas = areas[nonzero]
    tris, n_failed, notes = _triangulate(rings, areas, p2)
    if crossed:
        more, why = _close_rings(crossed, p2, together=False)
        tris, notes = np.concatenate([tris, more]), notes + why
    if slivers:
        tris = np.concatenate([tris, np.array(slivers, dtype=np.int64).reshape(-1, 3)])
    return Cap(points, tris, edges, loops, open_chains, n_failed, tuple(notes))


def _triangulate(rings: list, areas: np.ndarray, p2: np.ndarray) -> tuple[np.ndarray, int, list]:
    """Constrained Delaunay triangles of rings grouped into polygons with holes.

    The rings are point indices: the grouping keeps them (each polygon's
    triangles are checked against its own rings' points), and an exterior
    that had to be reversed (a clockwise loop with no outer loop around it)
    has its triangles turned back. A polygon GEOS cannot triangulate (a
    section of a self-intersecting surface) is closed ring by ring
    (`_close_rings`), and the notes say which loop and where.
    """
    if not rings:
        return np.zeros((0, 3), np.int64), 0, []
    import shapely
    _, parent = loop_hierarchy([p2[r] for r in rings])
    groups: dict[int, list] = {}
    for k in np.flatnonzero(areas > 0):
        groups[int(k)] = [rings[k], []]
    for k in np.flatnonzero(areas < 0):
        p = int(parent[k])
        if p >= 0 and p in groups:
            groups[p][1].append(rings[k])
        else:
            # A clockwise loop with no outer loop around it (an inside-out shell): fill it
            # wound as it runs, so that the part still closes.
            groups[int(k)] = [rings[k], []]

    polys, ring_sets, flips, keys = [], [], [], []
    for key, (ext, holes) in groups.items():  # over polygons
        keys.append(key)
        flip = areas[key] < 0
        if flip:
            ext = ext[::-1]

        def ring(r):
            return np.column_stack([p2[r], r.astype(np.float64)])  # Z carries the point index

        polys.append(shapely.Polygon(ring(ext), [ring(h) for h in holes]))
        ring_sets.append(np.concatenate([ext, *holes]))
        flips.append(flip)
    result = _cdt(np.array(polys, dtype=object))
    parts, owner = shapely.get_parts(result, return_index=True)
    coords = shapely.get_coordinates(parts, include_z=True).reshape(-1, 4, 3)[:, :3]
    tri = coords[..., 2].astype(np.int64)
    exact = np.all(tri == coords[..., 2], axis=1)
    q = p2[np.clip(tri, 0, len(p2) - 1)]
    a2 = (q[:, 1, 0] - q[:, 0, 0]) * (q[:, 2, 1] - q[:, 0, 1]) - (q[:, 2, 0] - q[:, 0, 0]) * (q[:, 1, 1] - q[:, 0, 1])
    # GEOS winds its triangles clockwise; a zero-area one keeps the winding of its neighbours.
    ccw = np.where(a2 != 0, a2 > 0, False)
    tri = np.where(ccw[:, None], tri, tri[:, ::-1])

    out, n_failed, notes = [], 0, []
    bounds = np.searchsorted(owner, np.arange(len(polys) + 1))
    for g in range(len(polys)):  # over polygons
        t = tri[bounds[g]:bounds[g + 1]]
        ex = exact[bounds[g]:bounds[g + 1]]
        expected = polys[g].area
        got = float(np.abs(a2[bounds[g]:bounds[g + 1]]).sum()) / 2
        ok = (len(t) > 0 and ex.all() and np.isin(ring_sets[g], t).all() and np.isin(t, ring_sets[g]).all()
              and abs(got - expected) <= 1e-9 * max(expected, 1e-300) + 1e-12 * got)
        if not ok:
            ext, holes = groups[keys[g]]
            t, why = _close_rings([ext[::-1] if flips[g] else ext, *holes], p2)
            notes += why
            out.append(t[:, ::-1] if flips[g] else t)
            continue
        out.append(t[:, ::-1] if flips[g] else t)
    return (np.concatenate(out) if out else np.zeros((0, 3), np.int64)), n_failed, notes


def _cdt_ring(ring: np.ndarray, p2: np.ndarray) -> np.ndarray | None:
    """Constrained Delaunay triangles of one counter-clockwise ring, or None when GEOS fails the checks."""
    import shapely
    poly = shapely.Polygon(np.column_stack([p2[ring], ring.astype(np.float64)]))
    parts = shapely.get_parts(_cdt(np.array([poly], dtype=object))[0])
    if len(parts) == 0:
        return None
    coords = shapely.get_coordinates(parts, include_z=True).reshape(-1, 4, 3)[:, :3]
    tri = coords[..., 2].astype(np.int64)
    if not (np.all(tri == coords[..., 2]) and np.isin(ring, tri).all() and np.isin(tri, ring).all()):
        return None
    q = p2[tri]
    a2 = (q[:, 1, 0] - q[:, 0, 0]) * (q[:, 2, 1] - q[:, 0, 1]) - (q[:, 2, 0] - q[:, 0, 0]) * (q[:, 1, 1] - q[:, 0, 1])
    if abs(float(np.abs(a2).sum()) / 2 - poly.area) > 1e-9 * max(poly.area, 1e-300):
        return None
    return np.where((a2 > 0)[:, None], tri, tri[:, ::-1])


def _spread(q: np.ndarray) -> float:
    """Twice the area a fan over the points sweeps, unsigned: zero only for points on a line."""
    a, b = q[1:-1] - q[0], q[2:] - q[0]
    return float(np.abs(a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]).sum())


def _close_rings(rings: list, p2: np.ndarray, together: bool = True) -> tuple[np.ndarray, list]:
    """Close each ring of a polygon GEOS refused on its own: triangles and notes.

    Each ring is filled as a disk wound as it runs, so that every cut edge is
    covered once and the part closes whatever the rings do: an exterior's
    triangles cover its holes, and each hole's triangles, wound the other way,
    take that area back (the signed areas, and so the part's volume, are
    exact). A ring GEOS accepts is filled by its constrained Delaunay
    triangulation; one that crosses itself by a fan from one of its points.
    """
    import shapely

    def where(reason: str, r: np.ndarray) -> str:
        xy = reason.partition("[")[2].rstrip("]").split()
        x, y = (float(v) for v in xy[:2]) if len(xy) >= 2 else p2[r[0]]
        return f"({x:.6g}, {y:.6g})"

    out, notes = [], []
    if together and len(rings) > 1:
        reason = shapely.is_valid_reason(shapely.Polygon(p2[rings[0]], [p2[h] for h in rings[1:]]))
        notes.append(f"{len(rings)} loops meet near {where(reason, rings[0])} ({reason.partition('[')[0]}): "
                     f"each closed on its own, so the cap overlaps itself there")
    for r in rings:  # the few rings of one polygon
        ccw = signed_area(p2[r]) >= 0
        ring = r if ccw else r[::-1]
        reason = shapely.is_valid_reason(shapely.Polygon(p2[ring]))
        tri = _cdt_ring(ring, p2) if reason == "Valid Geometry" else None
        if tri is None:
            tri = np.stack([np.full(len(ring) - 2, ring[0]), ring[1:-1], ring[2:]], axis=1)
            notes.append(f"a loop of {len(r)} points crosses itself near {where(reason, r)}: "
                         f"closed by a fan of triangles, which overlaps itself there")
        out.append(tri if ccw else tri[:, ::-1])
    return np.concatenate(out), notes


def _cdt(polys: np.ndarray) -> np.ndarray:
    """GEOS's constrained Delaunay triangles of each polygon; an empty result where GEOS gives up.

    A section of a self-intersecting input can make a polygon GEOS cannot
    triangulate ("unable to find a convex corner"): that polygon is left
    uncapped (and reported), the others are not held back.
    """
    import shapely
    from shapely.errors import GEOSException
    with np.errstate(all="ignore"):
        try:
            return shapely.constrained_delaunay_triangles(polys)
        except GEOSException:
            out = np.empty(len(polys), dtype=object)
            for k, p in enumerate(polys):  # over polygons, only when one failed
                try:
                    out[k] = shapely.constrained_delaunay_triangles(p)
                except GEOSException:
                    out[k] = shapely.GeometryCollection()
            return out


# ------------------------------------------------------------------ quality
def triangle_min_angles(points: np.ndarray, triangles: np.ndarray) -> np.ndarray:
    """Smallest interior angle of each triangle, in degrees (2-D or 3-D points).

    The measure a Delaunay triangulation maximises: it tells a cap from one
    made of slivers.

    Examples
    --------
    >>> triangle_min_angles(np.array([[0, 0], [1, 0], [0, 1]], float), np.array([[0, 1, 2]])).round(6).tolist()
    [45.0]
    """
    p = np.asarray(points, dtype=np.float64)[np.asarray(triangles)]
    angles = []
    for k in range(3):  # over the three corners
        a = p[:, (k + 1) % 3] - p[:, k]
        b = p[:, (k + 2) % 3] - p[:, k]
        cosang = np.einsum("ij,ij->i", a, b) / np.maximum(np.linalg.norm(a, axis=1) * np.linalg.norm(b, axis=1),
                                                          1e-300)
        angles.append(np.degrees(np.arccos(np.clip(cosang, -1, 1))))
    return np.min(angles, axis=0)
