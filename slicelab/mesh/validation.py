"""Mesh checks a lab needs before slicing: normals, open edges, shells, volume.

Vertices are welded exactly (see `slicelab.geometry.topology`), so the counts describe
the mesh as stored, with no tolerance that could hide or invent a defect.
"""
from __future__ import annotations

from concurrent.futures import ThreadPoolExecutor
from dataclasses import asdict, dataclass

import numpy as np

from ..geometry.topology import edge_counts, edge_table, shells
from ..geometry.triangles import edge_cross
from .core import Mesh
from .repairs import default_tolerance, near_vertex_pairs

__all__ = ["MeshReport", "check", "signed_volume"]


@dataclass(frozen=True)
class MeshReport:
    """What `check` found in a mesh.

    Attributes
    ----------
    n_facets, n_vertices : int
        Facets, and distinct (welded) vertices.
    n_degenerate : int
        Facets of zero area.
    n_flipped_normals : int
        Stored normals more than 90 degrees from the winding normal.
    n_zero_normals : int
        Stored normals that are zero (many exporters write them so; not a defect).
    n_open_edges : int
        Edges used by one facet only (holes in the surface).
    n_nonmanifold_edges : int
        Edges used by three facets or more.
    n_misoriented_edges : int
        Edges of two facets that run the same way (inconsistent winding).
    n_shells : int
        Edge-connected pieces of surface.
    volume : float
        Signed volume in mm^3 (positive for outward normals).
    area : float
        Surface area in mm^2.
    watertight : bool
        No open and no non-manifold edge.
    bounds : tuple
        ((xmin, ymin, zmin), (xmax, ymax, zmax)).
    n_near_vertices : int
        Vertices on open edges that lie within `slicelab.mesh.default_tolerance`
        (8 single-precision units in the last place of the largest coordinate) of
        another such vertex: CAD float noise (a coordinate of 3.4e-17 where 0 is
        meant, or a copy of a vertex a unit in the last place away) rather than a
        real hole. `slicelab.repair` snaps them.
    n_holes : int
        Loops that the open edges close into, each walked one way round by its
        facets: holes that ``slicelab.repair(mesh, fill_holes=True)`` (``--fill-holes``)
        closes.
    n_unbalanced_edges : int
        Edges that facets walk more often one way than the other (open and
        misoriented edges among them). With none, the surface bounds a solid in
        the sense of the winding number even where it is not manifold (two shells
        that touch along an edge): every plane cuts it into closed loops, and
        `slicelab slice` reads its layers by their winding numbers.
    """

    n_facets: int
    n_vertices: int
    n_degenerate: int
    n_flipped_normals: int
    n_zero_normals: int
    n_open_edges: int
    n_nonmanifold_edges: int
    n_misoriented_edges: int
    n_shells: int
    volume: float
    area: float
    watertight: bool
    bounds: tuple
    n_near_vertices: int = 0
    n_unbalanced_edges: int = 0
    n_holes: int = 0

    @property
    def winding_consistent(self) -> bool:
        """True when every two-facet edge is walked once each way."""
        return self.n_misoriented_edges == 0

    @property
    def closed_by_winding(self) -> bool:
        """True when every edge is walked as often one way as the other (`n_unbalanced_edges`)."""
        return self.n_facets > 0 and self.n_unbalanced_edges == 0

    @property
    def needs_repair(self) -> bool:
        """True when `slicelab.repair` may change something: degenerate facets, open, non-manifold
        or misoriented edges, near-coincident vertices, a negative volume (inside out), or several
        shells (one of which may be wound against its nesting)."""
        return bool(self.n_degenerate or self.n_open_edges or self.n_nonmanifold_edges
                    or self.n_misoriented_edges or self.n_near_vertices or self.volume < 0 or self.n_shells > 1)

    def to_dict(self) -> dict:
        """Plain-Python dictionary, ready for JSON."""
        d = asdict(self)
        d["winding_consistent"] = self.winding_consistent
        d["closed_by_winding"] = self.closed_by_winding
        return d

    def __str__(self) -> str:
        (x0, y0, z0), (x1, y1, z1) = self.bounds
        lines = [
            f"facets            {self.n_facets}",
            f"vertices          {self.n_vertices}",
            f"size (mm)         {x1 - x0:.4g} x {y1 - y0:.4g} x {z1 - z0:.4g}",
            f"volume (mm3)      {self.volume:.6g}",
            f"area (mm2)        {self.area:.6g}",
            f"shells            {self.n_shells}",
            f"degenerate        {self.n_degenerate}",
            f"flipped normals   {self.n_flipped_normals}",
            f"zero normals      {self.n_zero_normals}",
            f"open edges        {self.n_open_edges}"
            + (f" ({self.n_near_vertices} near-coincident {'vertex' if self.n_near_vertices == 1 else 'vertices'}:"
               " slicelab.repair closes them)" if self.n_near_vertices
               else " (1 hole: --fill-holes closes it)" if self.n_holes == 1
               else f" ({self.n_holes} holes: --fill-holes closes them)" if self.n_holes else ""),
            f"non-manifold      {self.n_nonmanifold_edges}"
            + (" (each walked as often both ways: closed by winding number, slice reads it)"
               if self.n_nonmanifold_edges and self.closed_by_winding else ""),
            f"misoriented edges {self.n_misoriented_edges}",
            f"watertight        {'yes' if self.watertight else 'no'}",
        ]
        return "\n".join(lines)


def signed_volume(triangles: np.ndarray, cross: np.ndarray | None = None) -> float:
    """Signed volume enclosed by triangles (divergence theorem).

    Corners are taken relative to the bounding-box centre, which keeps the
    sum accurate for parts far from the origin. `cross`, the facets'
    ``(v1 - v0) x (v2 - v0)``, may be passed when already computed.

    Examples
    --------
    >>> from slicelab import Mesh
    >>> v = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]]
    >>> f = [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]]
    >>> round(signed_volume(Mesh.from_vertices_faces(v, f).triangles), 12)
    0.166666666667
    """
    t = np.asarray(triangles, dtype=np.float64)
    if len(t) == 0:
        return 0.0
    first = t[:, 0]
    c = np.array([first[:, k].min() / 2 + first[:, k].max() / 2 for k in range(3)])  # columns: fast
    if cross is None:
        cross = edge_cross(t)
    # det[v0 - c, v1 - c, v2 - c] = (v0 - c) . ((v1 - v0) x (v2 - v0))
    return float(np.einsum("ij,ij->", t[:, 0] - c, cross) / 6.0)


def _longest2_bound(t: np.ndarray) -> np.ndarray:
    # A cheap upper bound of each facet's squared longest edge: the squared bounding-box diagonal.
    span = np.zeros(len(t))
    for k in range(3):
        # Corner by corner: numpy reduces the 3-long rows of (n, 3) far slower than it compares columns.
        a, b, c = t[:, 0, k], t[:, 1, k], t[:, 2, k]
        span += (np.maximum(np.maximum(a, b), c) - np.minimum(np.minimum(a, b), c)) ** 2
    return span


def _topology(mesh: Mesh, tolerance: float) -> tuple[int, int, int, int, int, int, int, int]:
    """Welded vertices, open / non-manifold / misoriented edges, shells, near-coincident vertices,
    unbalanced edges and holes."""
    t = mesh.triangles
    faces, corner_of_vertex = mesh.welded  # the weld, without gathering the vertices (kept for the slicer)
    et = edge_table(faces)
    e = edge_counts(faces, et)
    n_shells, _ = shells(faces, et)
    n_near = n_holes = 0
    if e.n_open:
        from .holes import hole_loops
        n_holes = len(hole_loops(faces, et)[2]) - 1
        # Only the ends of open edges can be seams that float noise opened: a few vertices to test.
        fe = et["first"][et["counts"] == 1]
        # (bincount rather than np.unique, which loads numpy.ma: 10 ms of a command)
        ends = np.flatnonzero(np.bincount(np.concatenate([faces.reshape(-1)[fe], faces[fe // 3, (fe % 3 + 1) % 3]]),
                                          minlength=int(faces.max()) + 1))
        pairs = near_vertex_pairs(t.reshape(-1, 3)[corner_of_vertex[ends]], tolerance)
        n_near = int(np.count_nonzero(np.bincount(pairs.reshape(-1), minlength=len(ends)))) if len(pairs) else 0
    # An edge is balanced when as many of its facets walk it forward as backward.
    forward = np.bincount(et["inverse"], weights=et["forward"], minlength=len(et["counts"]))
    n_unbalanced = int(np.count_nonzero(2 * forward != et["counts"]))
    return (len(corner_of_vertex), e.n_open, e.n_nonmanifold, e.n_misoriented, int(n_shells), n_near, n_unbalanced,
            n_holes)


def check(mesh: Mesh) -> MeshReport:
    """Count the defects of a mesh and measure it.

    Parameters
    ----------
    mesh : Mesh

    Returns
    -------
    MeshReport

    Examples
    --------
    >>> from slicelab import Mesh
    >>> v = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]]
    >>> f = [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]]
    >>> r = check(Mesh.from_vertices_faces(v, f))
    >>> r.watertight, r.n_shells, r.n_open_edges
    (True, 1, 0)
    """
    t = mesh.triangles
    n = len(t)
    if n == 0:
        z = (0.0, 0.0, 0.0)
        return MeshReport(0, 0, 0, 0, 0, 0, 0, 0, 0, 0.0, 0.0, False, (z, z))
    # Welding and the edge table (sorting) run in a worker thread while this thread measures
    # the facets: numpy releases the GIL, so the two cores share the work.
    with ThreadPoolExecutor(max_workers=1) as pool:
        topo = pool.submit(_topology, mesh, default_tolerance(mesh))
        cross = edge_cross(t)
        double_area = np.sqrt(np.einsum("ij,ij->i", cross, cross))
        # Zero area up to rounding, relative to the facet's own size (its longest edge), not the
        # part's. Only facets that are small against that edge need the edge lengths at all.
        small = np.flatnonzero(double_area <= 1e-6 * _longest2_bound(t))
        longest2 = np.zeros(len(small))
        for i, j in ((0, 1), (1, 2), (2, 0)):
            e = t[small, j] - t[small, i]
            np.maximum(longest2, np.einsum("ij,ij->i", e, e), out=longest2)
        n_degenerate = int(np.count_nonzero(double_area[small] <= 1e-12 * longest2))
        stored = np.einsum("ij,ij->i", mesh.file_normals, mesh.file_normals)
        n_zero_normals = int(np.count_nonzero(stored == 0))
        n_flipped = int(np.count_nonzero(np.einsum("ij,ij->i", mesh.file_normals, mesh.normals) < 0))
        volume = signed_volume(t, cross)
        n_vertices, n_open, n_nonmanifold, n_misoriented, n_shells, n_near, n_unbalanced, n_holes = topo.result()

    lo, hi = mesh.bounds
    return MeshReport(
        n_facets=n,
        n_vertices=n_vertices,
        n_degenerate=n_degenerate,
        n_flipped_normals=n_flipped,
        n_zero_normals=n_zero_normals,
        n_open_edges=n_open,
        n_nonmanifold_edges=n_nonmanifold,
        n_misoriented_edges=n_misoriented,
        n_shells=n_shells,
        volume=volume,
        area=float(double_area.sum() / 2),
        watertight=bool(n_open == 0 and n_nonmanifold == 0),
        bounds=(tuple(map(float, lo)), tuple(map(float, hi))),
        n_near_vertices=n_near,
        n_unbalanced_edges=n_unbalanced,
        n_holes=n_holes,
    )
