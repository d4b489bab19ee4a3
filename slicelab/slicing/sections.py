"""Exact plane sections of a mesh: one plane, or every layer at once.

One rule decides every degenerate case: a vertex whose signed distance to the
plane is >= 0 counts as *above*. A facet is cut only when it has a vertex
strictly below and one above, so a facet owns its top edge, facets lying in
the plane add nothing, and the section at a plane is the limit of sections
taken just below it. The point where an edge meets the plane is computed from
its (below, above) endpoints in that canonical order, so the two facets
sharing the edge get the bit-identical point. Segments run with the material
on their left: from the edge that goes above -> below (in the facet's winding)
to the edge that goes below -> above, which is the direction n x N.
"""
from __future__ import annotations

import json
from dataclasses import dataclass, field
from functools import cached_property

import numpy as np

from ..geometry.chains import chain_segments, join_open_chains
from ..geometry.planes import (
    NEXT_CORNER,
    Frame,
    crossing_edges,
    edge_points,
    plane_distances,
)
from ..geometry.slice_kernels import cut_planes
from ..geometry.polygons import Polygon, build_polygons, loop_hierarchy, signed_area
from ..geometry.topology import exact_ids
from ..mesh.core import Mesh

__all__ = ["Section", "section", "slice_layers", "layer_heights", "section_from_distances"]


@dataclass(frozen=True, eq=False)
class Section:
    """The cut of a mesh by one plane, in the plane's 2-D frame (mm).

    Attributes
    ----------
    frame : Frame
    segments : (m, 2, 2) ndarray
        Every cut segment, material on its left.
    loops : list of (k, 2) ndarray
        Closed rings (implicitly closed): outer counter-clockwise, holes clockwise.
    open_chains : list of (k, 2) ndarray
        Chains that could not be closed (open scans).
    joined_gaps : (j,) ndarray
        Gaps (mm) bridged to close open chains.
    hierarchy : (depth, parent) of (L,) int ndarray, optional
        The loops' nesting when already known; otherwise found on first use
        (`loop_depth`, `loop_parent`): a print plan's hundreds of layers never ask.

    Properties ``loop_depth`` and ``loop_parent`` give the nesting depth of each loop and
    its smallest enclosing loop (-1 if none).
    """

    frame: Frame
    segments: np.ndarray
    loops: list = field(default_factory=list)
    open_chains: list = field(default_factory=list)
    joined_gaps: np.ndarray = field(default_factory=lambda: np.zeros(0))
    hierarchy: tuple | None = field(default=None, repr=False)

    @cached_property
    def _nesting(self) -> tuple:
        return self.hierarchy if self.hierarchy is not None else loop_hierarchy(self.loops)

    @property
    def loop_depth(self) -> np.ndarray:
        """Nesting depth of each loop (0 for outermost)."""
        return self._nesting[0]

    @property
    def loop_parent(self) -> np.ndarray:
        """Smallest enclosing loop of each loop, or -1."""
        return self._nesting[1]

    def __repr__(self) -> str:
        return (f"Section({len(self.segments)} segments, {len(self.loops)} loops, "
                f"{len(self.open_chains)} open, area={self.area:.6g} mm2)")

    @cached_property
    def polygons(self) -> list[Polygon]:
        """Each outer loop with its holes; islands inside holes are polygons of their own."""
        return build_polygons(self.loops, self.loop_depth, self.loop_parent)

    @property
    def area(self) -> float:
        """Material area (mm^2): the signed areas of all closed loops added up."""
        return float(sum(signed_area(p) for p in self.loops))

    @property
    def z(self) -> float:
        """Height of a horizontal section (NaN for any other plane)."""
        return float(self.frame.origin[2]) if self.frame.horizontal else float("nan")

    def to_3d(self, points) -> np.ndarray:
        """World coordinates of points given in this section's plane."""
        return self.frame.to_3d(points)

    def bounds(self) -> np.ndarray:
        """(2, 2) array: min and max plane coordinates of the segments."""
        if len(self.segments) == 0:
            return np.zeros((2, 2))
        flat = self.segments.reshape(-1, 2)
        return np.stack([flat.min(axis=0), flat.max(axis=0)])

    def to_shapely(self):
        """The material as a shapely MultiPolygon (shapely is imported here, lazily).

        Examples
        --------
        >>> import slicelab
        >>> from slicelab.samples import box
        >>> round(slicelab.section(box((0, 0, 0), (2, 3, 1)), (0, 0, 0.5), (0, 0, 1)).to_shapely().area, 9)
        6.0
        """
        import shapely
        return shapely.MultiPolygon([shapely.Polygon(p.exterior, list(p.holes)) for p in self.polygons])

    def svg(self, *, margin: float = 2.0, stroke: float = 0.1, fill: str = "#4a6fa5") -> str:
        """The section as SVG text at true scale (1 user unit = 1 mm).

        See Also
        --------
        slicelab.files.SvgDrawing : the writer.
        """
        from ..files.svg import SvgDrawing
        lo, hi = self.bounds() if len(self.segments) else (np.zeros(2), np.ones(2))
        svg = SvgDrawing((*(lo - margin), *(hi + margin)), digits=6,
                         desc=f"slicelab section; plane {json.dumps(self.frame.to_dict())}; "
                              f"area {self.area:.9g} mm2")
        with svg.group("material", fill=fill, fill_rule="evenodd", stroke="black", stroke_width=stroke):
            for p in self.polygons:
                svg.path([p.exterior, *p.holes], closed=True)
        if self.open_chains:
            with svg.group("open", fill="none", stroke="red", stroke_width=2 * stroke):
                for c in self.open_chains:
                    svg.path([c])
        return svg.to_string()

    def to_svg(self, path, **kwargs) -> None:
        """Write `svg` to a file, atomically.

        Examples
        --------
        >>> import slicelab, tempfile, os
        >>> from slicelab.samples import box
        >>> s = slicelab.section(box(), (0, 0, 0.5), (0, 0, 1))
        >>> s.to_svg(os.path.join(tempfile.mkdtemp(), "s.svg"))
        """
        from ..files.atomic import atomic_open
        with atomic_open(path, "w", encoding="utf-8") as fh:
            fh.write(self.svg(**kwargs))

    def to_dict(self) -> dict:
        """Loops, open chains and hierarchy as plain lists (for JSON)."""
        return {
            "frame": self.frame.to_dict(),
            "area": self.area,
            "loops": [p.tolist() for p in self.loops],
            "loop_depth": self.loop_depth.tolist(),
            "loop_parent": self.loop_parent.tolist(),
            "open_chains": [c.tolist() for c in self.open_chains],
            "joined_gaps": self.joined_gaps.tolist(),
        }


def _cut(vertex: np.ndarray, corners2: np.ndarray, dist: np.ndarray, plane: np.ndarray):
    """Cut facet/plane pairs whose corners straddle the plane.

    Parameters: the exact vertex id of each corner (p, 3) (its identity), plane-frame
    corners (p, 3, 2), signed distances (p, 3), plane index per pair (p,). Every pair
    must have a corner below (< 0) and one above (>= 0).

    Returns segments (s, 2, 2), start and end topological keys (s,), plane (s,).
    """
    down, up = crossing_edges(dist)
    rows = np.arange(len(dist))
    b_start, a_start = NEXT_CORNER[down], down
    b_end, a_end = up, NEXT_CORNER[up]
    # A facet whose only upper corner lies in the plane touches it at a point: no segment.
    keep = ~((a_start == a_end) & (dist[rows, a_start] == 0))
    if not keep.all():
        rows, b_start, a_start, b_end, a_end = (x[keep] for x in (rows, b_start, a_start, b_end, a_end))
    p0 = edge_points(corners2, dist, rows, b_start, a_start)
    p1 = edge_points(corners2, dist, rows, b_end, a_end)

    # Each end's (above vertex, below vertex); a point on an above corner in the plane is keyed by
    # that vertex twice, which no edge (two distinct vertices) can match.
    flat = vertex.reshape(-1)

    def end(b, a):
        return flat[3 * rows + a], flat[3 * rows + np.where(dist[rows, a] == 0, a, b)]

    ends = np.stack([*end(b_start, a_start), *end(b_end, a_end)], axis=1)
    start_id, end_id = _end_ids(ends, plane[rows], int(flat.max()) + 1 if len(flat) else 1,
                                int(plane.max()) + 1 if len(plane) else 1)
    # Segments that round to zero length (a corner a hair off the plane, two crossing edges
    # whose points round to that corner) are kept: chaining needs their keys. `_assemble`
    # drops them once the loops are known.
    return np.stack([p0, p1], axis=1), start_id, end_id, plane[rows]


def _end_ids(ends: np.ndarray, plane: np.ndarray, n_vertices: int, n_planes: int):
    """The start and end keys of segments from their ends' (above, other) vertex ids, (s, 4)
    (`_cut`, `slicelab.geometry.slice_kernels.cut_planes`), and their planes: one integer per
    key when it fits (the chaining hashes them), else the three columns numbered by `exact_ids`."""
    if n_vertices * n_vertices * n_planes < 2 ** 62:  # one integer per key (the chaining hashes them)
        keys = (ends[:, 0::2] * n_vertices + ends[:, 1::2]) * n_planes + plane[:, None]
        return keys[:, 0].copy(), keys[:, 1].copy()
    ids, _ = exact_ids(np.concatenate([np.stack([ends[:, 0], ends[:, 1], plane], axis=1),
                                       np.stack([ends[:, 2], ends[:, 3], plane], axis=1)]))
    s = len(ends)
    return ids[:s], ids[s:]


def _assemble(frames: list[Frame], segments, start_id, end_id, seg_plane, max_gap: float) -> list[Section]:
    """Chain the segments of every plane at once (keys never match across planes) and build
    one Section per frame."""
    chains = chain_segments(start_id, end_id)
    nonzero = np.any(segments[:, 0] != segments[:, 1], axis=1)
    starts = segments[:, 0]
    loops = [[] for _ in frames]
    open_chains = [[] for _ in frames]
    n_chains = len(chains)
    walk = chains.order  # every segment, chain after chain, each in walking order
    chain_of = np.repeat(np.arange(n_chains), np.diff(chains.bounds))
    chain_plane = seg_plane[walk[chains.bounds[:-1]]] if n_chains else np.zeros(0, np.int64)
    kept = nonzero[walk]
    size = np.bincount(chain_of[kept], minlength=n_chains)  # segments of each chain that have a length
    # The closed chains with three segments or more, all at once: their segments' starts, split by chain.
    ring = chains.closed & (size >= 3)
    pieces = np.split(starts[walk[kept & ring[chain_of]]], np.cumsum(size[ring])[:-1]) if ring.any() else []
    for plane, pts in zip(chain_plane[ring].tolist(), pieces):  # over loops
        loops[plane].append(pts)
    for k in np.flatnonzero(~chains.closed & (size > 0)).tolist():  # over open chains (open scans only)
        idx = walk[chains.bounds[k]:chains.bounds[k + 1]]
        last = segments[idx[-1], 1]
        open_chains[int(chain_plane[k])].append(np.vstack([starts[idx[nonzero[idx]]], last]))
    # Every plane's segments that have a length, in one gather: each Section takes its slice.
    order = np.argsort(seg_plane, kind="stable")
    order = order[nonzero[order]]
    cuts = np.searchsorted(seg_plane[order], np.arange(len(frames) + 1)).tolist()
    kept_segments = segments[order]
    out = []
    for k, frame in enumerate(frames):  # over planes
        gaps = np.zeros(0)
        if open_chains[k] and max_gap > 0:
            closed, open_chains[k], gaps = join_open_chains(open_chains[k], max_gap)
            loops[k] += closed
        out.append(Section(frame, kept_segments[cuts[k]:cuts[k + 1]], loops[k], open_chains[k], gaps))
    return out


def _frame_coords(frame: Frame, corners: np.ndarray) -> np.ndarray:
    if frame.horizontal:  # exact: plane coordinates are the world x, y (y negated facing down)
        return corners[..., :2] * np.array([1.0, frame.v[1]])
    return frame.to_2d(corners)


def _straddling(dist: np.ndarray) -> np.ndarray:
    below = dist < 0
    return np.flatnonzero(below.any(axis=1) & ~below.all(axis=1))


def section_from_distances(frame: Frame, triangles: np.ndarray, dist: np.ndarray,
                           max_gap: float = 1.0) -> Section:
    """`section` from corner distances already computed (shared with `slicelab.split`)."""
    cross = _straddling(dist)
    c3 = triangles[cross]
    vertex = exact_ids(c3.reshape(-1, 3))[0].reshape(-1, 3)
    seg, s_id, e_id, plane = _cut(vertex, _frame_coords(frame, c3), dist[cross], np.zeros(len(cross), np.int64))
    return _assemble([frame], seg, s_id, e_id, plane, max_gap)[0]


def section(mesh: Mesh, origin, normal, *, max_gap: float = 1.0) -> Section:
    """Cut a mesh with any plane.

    Parameters
    ----------
    mesh : Mesh
    origin : (3,) array_like
        A point of the plane (mm).
    normal : (3,) array_like
        The plane's normal; need not be unit length.
    max_gap : float, default 1.0
        Open chains (from an open scan) whose ends lie within this distance
        (mm) are joined, nearest first; 0 disables joining.

    Returns
    -------
    Section
        The cut segments and their closed loops, in the plane's 2-D frame.

    Examples
    --------
    >>> from slicelab.samples import box
    >>> s = section(box((0, 0, 0), (2, 3, 1)), (0, 0, 0.5), (0, 0, 1))
    >>> len(s.loops), s.area
    (1, 6.0)
    """
    frame = Frame.from_plane(origin, normal)
    return section_from_distances(frame, mesh.triangles, plane_distances(frame, mesh.triangles), max_gap)


def layer_heights(mesh: Mesh, layer_height: float) -> np.ndarray:
    """Mid-layer plane heights ``z_min + (k + 1/2) h`` of every layer that meets the part.

    Examples
    --------
    >>> from slicelab.samples import box
    >>> layer_heights(box((0, 0, 0), (1, 1, 1)), 0.25).tolist()
    [0.125, 0.375, 0.625, 0.875]
    """
    if len(mesh) == 0:
        _mid_layers(0.0, 0.0, layer_height)  # still refuses a bad height
        return np.zeros(0)
    z0, z1 = mesh.bounds[:, 2]
    return _mid_layers(z0, z1, layer_height)


def _mid_layers(z0: float, z1: float, layer_height) -> np.ndarray:
    h = float(layer_height)
    if not (h > 0 and np.isfinite(h)):
        raise ValueError(f"layer height must be a positive number, got {layer_height!r}")
    k = np.arange(int(np.ceil((z1 - z0) / h)) + 1)
    z = z0 + (k + 0.5) * h
    return z[z < z1]


def slice_layers(mesh: Mesh, layer_height: float | None = None, *, heights=None,
                 max_gap: float = 1.0) -> list[Section]:
    """Horizontal sections of a mesh at many heights, in one vectorised pass.

    Each facet finds the planes between its lowest and highest corner by
    binary search, and one compiled pass cuts every facet/plane pair
    (`slicelab.geometry.slice_kernels.cut_planes`, the same points as `section`'s),
    so the cost grows with facets + segments, not facets x planes.

    Parameters
    ----------
    mesh : Mesh
    layer_height : float, optional
        Planes at mid-layer, ``z_min + (k + 1/2) * layer_height``.
    heights : array_like, optional
        Absolute plane heights instead (any order; the result follows it).
    max_gap : float, default 1.0
        As in `section`.

    Returns
    -------
    list of Section
        One per height, facing +z, in plain (x, y).

    Examples
    --------
    >>> from slicelab.samples import box
    >>> [round(s.area, 9) for s in slice_layers(box((0, 0, 0), (2, 2, 1)), 0.5)]
    [4.0, 4.0]
    """
    if (layer_height is None) == (heights is None):
        raise ValueError("give either layer_height or heights")
    t = mesh.triangles
    z0, z1, z2 = t[:, 0, 2], t[:, 1, 2], t[:, 2, 2]
    zmin = np.minimum(np.minimum(z0, z1), z2)
    zmax = np.maximum(np.maximum(z0, z1), z2)
    if heights is None:
        z = _mid_layers(float(zmin.min()), float(zmax.max()), layer_height) if len(t) else _mid_layers(0.0, 0.0, layer_height)
    else:
        z = np.asarray(heights, dtype=np.float64).reshape(-1)
    if not np.isfinite(z).all():
        raise ValueError("plane heights must be finite")
    planes, back = np.unique(z, return_inverse=True)
    lo = np.searchsorted(planes, zmin, side="right")  # first plane above each facet's lowest corner
    hi = np.searchsorted(planes, zmax, side="right")  # planes at or below its highest corner
    # The corners' vertex ids: the mesh's weld when it is known already (the mesh check makes it) or
    # cheaper than welding the crossing facets' corners (most facets crossed), else those alone.
    if mesh.has_weld or int((hi - lo).sum()) >= len(t):
        vertex = mesh.welded[0]
    else:
        crossed = np.flatnonzero(hi > lo)
        t, lo, hi = t[crossed], lo[crossed], hi[crossed]
        vertex = exact_ids(t.reshape(-1, 3))[0].reshape(-1, 3)
    # Every (facet, plane) pair cut in one compiled pass, facet after facet, as `_cut` would.
    seg, ends, seg_plane = cut_planes(t, vertex, planes, lo.astype(np.int64), hi.astype(np.int64))
    s_id, e_id = _end_ids(ends, seg_plane, int(vertex.max()) + 1 if vertex.size else 1, len(planes))
    frames = [Frame(np.array([0.0, 0.0, zk]), np.array([1.0, 0.0, 0.0]), np.array([0.0, 1.0, 0.0]),
                    np.array([0.0, 0.0, 1.0])) for zk in planes]
    sections = _assemble(frames, seg, s_id, e_id, seg_plane, max_gap)
    return [sections[i] for i in back]
