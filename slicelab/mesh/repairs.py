"""Repairs that are safe: CAD float noise welded, collapsed and duplicate facets removed, windings made consistent.

CAD programs write coordinates such as ``3.4e-17`` where 0 is meant (a cosine
of 90 degrees) on one facet and an exact 0 on its neighbour, and an STL file's
single-precision numbers put one vertex a unit in the last place (2e-6 mm at
25 mm) from its copy on the next facet. Exact welding
(`slicelab.geometry.weld`) then sees two vertices and an open seam. `repair`
snaps vertices that lie within a tolerance far below any modelled feature
(by default 8 single-precision units in the last place of the largest
coordinate: 0.06 micrometre on a part 100 mm from the origin; at least 1e-9 of
the bounding-box diagonal), which closes such seams without moving any real geometry. It
does not remove self-intersections or guess at anything larger; it fills holes only when
asked (``fill_holes=True``, `slicelab.mesh.holes`).

See Also
--------
slicelab.check : counts the defects; ``MeshReport.n_near_vertices`` says when
    `repair` can close open edges.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..geometry.graphs import graph_components
from ..geometry.topology import edge_table, shells, weld
from .core import Mesh

__all__ = ["RepairReport", "Repaired", "repair", "near_vertex_pairs", "default_tolerance"]

#: Least snapping tolerance, as a share of the bounding-box diagonal.
RELATIVE_TOLERANCE = 1e-9
#: Snapping tolerance in single-precision units in the last place of the largest coordinate: an
#: STL file stores float32, and CAD exports leave copies of a vertex a unit or two apart.
FLOAT32_ULPS = 8


def default_tolerance(mesh: Mesh) -> float:
    """The snapping tolerance for `mesh` (mm): `FLOAT32_ULPS` single-precision units in the last
    place of its largest coordinate, at least `RELATIVE_TOLERANCE` of its bounding-box diagonal.

    Examples
    --------
    >>> from slicelab.samples import box
    >>> default_tolerance(box((0, 0, 0), (30, 40, 0)))    # 8 x 2**-18 mm: 40 lies in [32, 64)
    3.0517578125e-05
    """
    if len(mesh) == 0:
        return 0.0
    lo, hi = mesh.bounds
    largest = float(np.abs(np.concatenate([lo, hi])).max())
    ulp = float(np.spacing(np.float32(largest))) if np.isfinite(largest) else 0.0
    return max(FLOAT32_ULPS * ulp, float(RELATIVE_TOLERANCE * np.linalg.norm(hi - lo)))


def near_vertex_pairs(vertices: np.ndarray, tolerance: float) -> np.ndarray:
    """Pairs (i, j), i < j, of distinct vertices at most `tolerance` apart, (p, 2), sorted.

    The points are binned in cubes twice the tolerance wide, on eight grids
    shifted by 0 or the tolerance along each axis: two points within the
    tolerance differ by at most it along each axis, so along each axis one of
    the two shifts puts no cube face between them, and one of the eight grids
    holds both in one cube. Each grid's cubes are found by sorting a hash of
    their indices; points sharing a hash are then measured. No k-d tree: SciPy's
    import would cost `slicelab slice --repair` a fifth of a second.

    Examples
    --------
    >>> v = np.array([[0, 0, 0], [3.4e-17, 0, 0], [1, 0, 0]])
    >>> near_vertex_pairs(v, 1e-9).tolist()
    [[0, 1]]
    """
    v = np.asarray(vertices, dtype=np.float64)
    if len(v) < 2 or not tolerance > 0:
        return np.zeros((0, 2), np.int64)
    tol = float(tolerance)
    scaled = v / (2 * tol)
    found = []
    for shift in np.ndindex(2, 2, 2):  # over the eight grids
        cube = np.floor(scaled + 0.5 * np.array(shift)).astype(np.int64)
        # Products wrap around in 64 bits: a hash, whose collisions only add candidates.
        key = cube[:, 0] * np.int64(73856093) ^ cube[:, 1] * np.int64(19349663) ^ cube[:, 2] * np.int64(83492791)
        order = np.argsort(key)
        same = key[order][1:] == key[order][:-1]  # a point and the next in hash order
        run, k = same, 1
        while run.any():  # pairs k apart in hash order, all between sharing the hash (few)
            i = np.flatnonzero(run)
            found.append(np.stack([order[i], order[i + k]], axis=1))
            run, k = run[:-1] & same[k:], k + 1
    if not found:
        return np.zeros((0, 2), np.int64)
    pairs = np.sort(np.concatenate(found), axis=1)
    d = v[pairs[:, 0]] - v[pairs[:, 1]]
    pairs = pairs[np.einsum("ij,ij->i", d, d) <= tol * tol]
    pairs = pairs[np.lexsort((pairs[:, 1], pairs[:, 0]))]
    keep = np.ones(len(pairs), bool)
    keep[1:] = np.any(pairs[1:] != pairs[:-1], axis=1)  # found on several grids once
    return pairs[keep]


# The sentence `RepairReport.changes` gives for each count that is not 0, in this order: for one,
# and for more.
_SENTENCES = (
    ("n_snapped_vertices", "snapped 1 near-coincident vertex (within {tolerance:.2g} mm)",
     "snapped {n} near-coincident vertices (within {tolerance:.2g} mm)"),
    ("n_collapsed_removed", "removed 1 collapsed facet", "removed {n} collapsed facets"),
    ("n_duplicates_removed", "removed 1 duplicate facet", "removed {n} duplicate facets"),
    ("n_flipped", "reversed 1 facet to agree with its neighbours", "reversed {n} facets to agree with their neighbours"),
    ("n_shells_turned_outward", "turned 1 inside-out shell outward", "turned {n} inside-out shells outward"),
    ("n_non_orientable_shells", "1 shell cannot be oriented (left as it is)",
     "{n} shells cannot be oriented (left as they are)"),
    ("n_holes_filled", "filled 1 hole ({largest_hole:.3g} mm across)",
     "filled {n} holes (the largest {largest_hole:.3g} mm across)"),
)


@dataclass(frozen=True)
class RepairReport:
    """What `repair` changed.

    Attributes
    ----------
    tolerance : float
        Snapping distance used (mm).
    n_snapped_vertices : int
        Vertices moved onto a neighbour closer than `tolerance`.
    n_collapsed_removed : int
        Facets with two corners on one vertex (after snapping) removed.
    n_duplicates_removed : int
        Facets on the same three vertices as another removed: copies with the
        same winding, and pairs of opposite winding (a wall of no thickness).
    n_flipped : int
        Facets whose winding was reversed to agree with their shell.
    n_shells_turned_outward : int
        Shells whose every facet was reversed so the shell encloses positive volume.
    n_non_orientable_shells : int
        Shells whose windings cannot all agree (a Moebius-like surface); left as they are.
    n_holes_filled : int
        Loops of open edges closed by a fan of facets (``fill_holes=True``).
    largest_hole : float
        The largest filled hole's bounding-box diagonal (mm).
    """

    tolerance: float
    n_snapped_vertices: int = 0
    n_collapsed_removed: int = 0
    n_duplicates_removed: int = 0
    n_flipped: int = 0
    n_shells_turned_outward: int = 0
    n_non_orientable_shells: int = 0
    n_holes_filled: int = 0
    largest_hole: float = 0.0

    @property
    def changed(self) -> bool:
        """True when anything was changed."""
        return any((self.n_snapped_vertices, self.n_collapsed_removed, self.n_duplicates_removed,
                    self.n_flipped, self.n_shells_turned_outward, self.n_holes_filled))

    def changes(self) -> list[str]:
        """One sentence for each kind of change made."""
        return [(one if getattr(self, name) == 1 else more).format(n=getattr(self, name), tolerance=self.tolerance,
                                                                   largest_hole=self.largest_hole)
                for name, one, more in _SENTENCES if getattr(self, name)]

    def to_dict(self) -> dict:
        """Plain-Python dictionary, ready for JSON."""
        d = {k: getattr(self, k) for k in self.__dataclass_fields__}
        d["changes"] = self.changes()
        return d


@dataclass(frozen=True)
class Repaired:
    """A repaired mesh and the report of what was changed."""

    mesh: Mesh
    report: RepairReport = field(repr=False)


def _snap(vertices: np.ndarray, faces: np.ndarray, tolerance: float) -> tuple[np.ndarray, np.ndarray, int]:
    """Merge clusters of vertices closer than `tolerance`; each takes its lowest member's position."""
    pairs = near_vertex_pairs(vertices, tolerance)
    if len(pairs) == 0:
        return vertices, faces, 0
    n = len(vertices)
    _, label = graph_components(n, pairs[:, 0], pairs[:, 1])
    # The representative of each cluster is its lowest vertex id.
    rep = np.full(label.max() + 1, n, dtype=np.int64)
    np.minimum.at(rep, label, np.arange(n))
    target = rep[label]
    return vertices, target[faces], int(np.count_nonzero(target != np.arange(n)))


def _duplicates(faces: np.ndarray) -> np.ndarray:
    """Mask of facets to keep once copies and opposite pairs on the same three vertices are removed."""
    key = np.sort(faces, axis=1)
    # Orientation: the winding read from the lowest vertex is (lo, mid, hi) or (lo, hi, mid).
    r = np.argmin(faces, axis=1)
    nxt = faces[np.arange(len(faces)), (r + 1) % 3]
    forward = nxt == key[:, 1]
    # Facets grouped by their sorted corners, groups in lexicographic order (as np.unique(axis=0)
    # would number them, without loading numpy.ma: 10 ms of a command).
    by = np.lexsort((key[:, 2], key[:, 1], key[:, 0]))
    sk = key[by]
    starts = np.r_[True, np.any(sk[1:] != sk[:-1], axis=1)]
    group = np.empty(len(faces), np.int64)
    group[by] = np.cumsum(starts) - 1
    counts = np.bincount(group)
    if counts.max(initial=0) < 2:
        return np.ones(len(faces), bool)
    n_fwd = np.bincount(group, weights=forward, minlength=len(counts)).astype(np.int64)
    n_rev = counts - n_fwd
    # Keep |fwd - rev| facets of the majority winding: copies collapse to one, opposite pairs cancel.
    keep_n = np.minimum(np.abs(n_fwd - n_rev), 1)
    keep_fwd = n_fwd > n_rev
    order = np.lexsort((np.arange(len(faces)), ~forward, group))
    rank = np.empty(len(faces), np.int64)
    sorted_group = group[order]
    sorted_fwd = forward[order]
    # Rank of each facet among the facets of its group with its winding.
    run_start = np.r_[True, (sorted_group[1:] != sorted_group[:-1]) | (sorted_fwd[1:] != sorted_fwd[:-1])]
    start_idx = np.maximum.accumulate(np.where(run_start, np.arange(len(order)), 0))
    rank[order] = np.arange(len(order)) - start_idx
    return (forward == keep_fwd[group]) & (rank < keep_n[group])


def _orient(faces: np.ndarray) -> tuple[np.ndarray, int]:
    """Flip mask making every shell's windings agree across its two-facet edges, and the count of
    shells that cannot agree.

    Each facet is two nodes of a graph, as wound (f) and reversed (f + n); a two-facet edge walked
    the same way by both facets links f to g + n, one walked both ways links f to g. A component
    holding both nodes of a facet is a non-orientable shell; otherwise each shell makes two mirror
    components, and the one holding its lowest facet as wound says which facets to reverse.
    """
    n = len(faces)
    et = edge_table(faces)
    two = np.flatnonzero(et["counts"] == 2)
    ea, eb = et["first"][two], et["last"][two]
    fa, fb = ea // 3, eb // 3
    same = et["forward"][ea] == et["forward"][eb]  # walked the same way: the two disagree
    a = np.r_[fa, fa + n]
    b = np.r_[np.where(same, fb + n, fb), np.where(same, fb, fb + n)]
    _, comp = graph_components(2 * n, a, b)
    bad = comp[:n] == comp[n:]
    _, shell = shells(faces, et)
    # The reference component of each shell: the one its lowest facet has as wound.
    first_facet = np.full(shell.max() + 1, n, np.int64)
    np.minimum.at(first_facet, shell, np.arange(n))
    ref = comp[first_facet[shell]]
    flip = (comp[n:] == ref) & ~bad
    # (bincount rather than np.unique and np.isin, which load numpy.ma: 10 ms of a command)
    bad_shell = np.bincount(shell[bad], minlength=len(first_facet)) > 0
    flip[bad_shell[shell]] = False
    return flip, int(np.count_nonzero(bad_shell))


def repair(mesh: Mesh, *, tolerance: float | None = None, orient: bool = True,
           fill_holes: bool = False) -> Repaired:
    """Snap near-coincident vertices, drop collapsed and duplicate facets, make windings agree;
    optionally close holes.

    Parameters
    ----------
    mesh : Mesh
    tolerance : float, optional
        Vertices at most this far apart (mm) are merged; default 8 single-precision
        units in the last place of the largest coordinate (`default_tolerance`). 0 merges
        only identical ones.
    orient : bool, default True
        Make windings agree and turn shells outward; False only removes
        collapsed and duplicate facets (after snapping).
    fill_holes : bool, default False
        Close each loop of open edges left after snapping with a fan of facets
        (`slicelab.mesh.holes.fill_holes`), before shells are turned outward.

    Returns
    -------
    Repaired
        ``.mesh`` and ``.report`` (a `RepairReport`).

    Notes
    -----
    Windings are made to agree across every edge shared by two facets, shell by
    shell, and each closed shell is then turned so that its normals point away
    from the material: out of a solid, into a cavity (a shell inside an odd
    number of others). Open or non-manifold shells keep the winding of their
    lowest facet's side. Holes are filled only when asked.

    Examples
    --------
    >>> import numpy as np
    >>> from slicelab import check
    >>> from slicelab.samples import box
    >>> t = box().triangles.copy()
    >>> t[t == 0] = np.where(np.arange((t == 0).sum()) % 2, 0.0, 3.4e-17)  # CAD float noise
    >>> check(Mesh(t)).watertight
    False
    >>> fixed = repair(Mesh(t))
    >>> check(fixed.mesh).watertight, fixed.report.n_snapped_vertices > 0
    (True, True)
    """
    tol = default_tolerance(mesh) if tolerance is None else float(tolerance)
    if not (np.isfinite(tol) and tol >= 0):
        raise ValueError(f"tolerance must be a finite number >= 0, got {tolerance!r}")
    if len(mesh) == 0:
        return Repaired(mesh, RepairReport(tol))
    vertices, faces = weld(mesh.triangles)
    vertices, faces, n_snapped = _snap(vertices, faces, tol)
    collapsed = (faces[:, 0] == faces[:, 1]) | (faces[:, 1] == faces[:, 2]) | (faces[:, 2] == faces[:, 0])
    faces = faces[~collapsed]
    keep = _duplicates(faces)
    n_dup = int(np.count_nonzero(~keep))
    faces = faces[keep]
    n_flipped = n_outward = n_bad = n_holes = 0
    largest = 0.0
    if len(faces) and orient:
        flip, n_bad = _orient(faces)
        n_flipped = int(np.count_nonzero(flip))
        faces = np.where(flip[:, None], faces[:, ::-1], faces)
    if len(faces) and fill_holes:  # (windings agree now: each hole's edges run one way round)
        from .holes import fill_holes as close
        vertices, faces, n_holes, largest = close(vertices, faces)
    if len(faces) and orient:
        faces, n_outward = _turn_outward(vertices, faces)
    report = RepairReport(tol, n_snapped, int(np.count_nonzero(collapsed)), n_dup, n_flipped, n_outward, n_bad,
                          n_holes, largest)
    if not report.changed:
        return Repaired(mesh, report)
    return Repaired(Mesh(vertices[faces]), report)


def _winding_number(tri: np.ndarray, point: np.ndarray) -> float:
    """Generalised winding number of a closed surface about a point: 1 inside, 0 outside.

    References
    ----------
    .. [1] A. Van Oosterom, J. Strackee, "The solid angle of a plane triangle",
       IEEE Trans. Biomed. Eng. 30(2), 125-126, 1983.
    .. [2] A. Jacobson, L. Kavan, O. Sorkine-Hornung, "Robust inside-outside
       segmentation using generalized winding numbers", ACM TOG 32(4), 2013.
    """
    a, b, c = (tri[:, k] - point for k in range(3))
    la, lb, lc = (np.sqrt(np.einsum("ij,ij->i", v, v)) for v in (a, b, c))
    num = np.einsum("ij,ij->i", a, np.cross(b, c))
    den = (la * lb * lc + np.einsum("ij,ij->i", a, b) * lc + np.einsum("ij,ij->i", a, c) * lb
           + np.einsum("ij,ij->i", b, c) * la)
    return float(np.arctan2(num, den).sum() / (2 * np.pi))


def _turn_outward(vertices: np.ndarray, faces: np.ndarray):
    """Reverse closed shells whose volume has the wrong sign for their nesting: the faces, and how
    many shells were reversed.

    A shell inside an even number of other shells bounds material (positive volume, normals out);
    one inside an odd number bounds a cavity (negative volume). Nesting is found with the
    generalised winding number of one vertex of each shell about each other closed shell whose
    bounding box holds it.
    """
    et = edge_table(faces)
    count, shell = shells(faces, et)
    tri = vertices[faces]
    t = tri - vertices.mean(axis=0)
    six_vol = np.einsum("ij,ij->i", t[:, 0], np.cross(t[:, 1], t[:, 2]))
    vol = np.bincount(shell, weights=six_vol, minlength=count)
    # A shell is closed when none of its edges is open or shared by more than two facets.
    bad_edge = et["counts"] != 2
    closed = np.ones(count, bool)
    closed[shell[et["first"][bad_edge] // 3]] = False
    order = np.argsort(shell, kind="stable")
    cuts = np.searchsorted(shell[order], np.arange(count + 1))
    members = [order[cuts[k]:cuts[k + 1]] for k in range(count)]  # over shells, not facets
    lo = np.array([tri[m].reshape(-1, 3).min(axis=0) for m in members])
    hi = np.array([tri[m].reshape(-1, 3).max(axis=0) for m in members])
    depth = np.zeros(count, np.int64)
    for a in np.flatnonzero(closed):  # over shells
        p = tri[members[a][0], 0]
        holders = np.flatnonzero(closed & np.all(lo <= p, axis=1) & np.all(hi >= p, axis=1))
        for b in holders[holders != a]:  # over the shells that may hold it
            depth[a] += abs(_winding_number(tri[members[b]], p)) > 0.5
    want_positive = depth % 2 == 0
    turn = closed & (vol != 0) & ((vol > 0) != want_positive)
    if not turn.any():
        return faces, 0
    rev = turn[shell]
    return np.where(rev[:, None], faces[:, ::-1], faces), int(np.count_nonzero(turn))
