"""Meshes written as they are reported: the file's own check, after its float32 rounding.

STL stores single-precision coordinates. Rounding can make two distinct
vertices one float32 point: a cut's sliver facet collapses (two of its
corners meet), or two sheets of surface that pass within a float32 step of
each other come to share an edge that four facets use. `write_mesh` rounds
first and leaves out the facets that collapsed (the surface around them
closes up, as after an edge collapse). When the file would then not be
watertight with consistent windings, it writes instead the mesh's own
topology: every vertex of the float64 mesh keeps a float32 point of its own,
vertices that rounding merged being moved to the neighbouring float32 values
(one float32 step, in the direction that keeps their order), so the file is
watertight whenever the mesh in memory is. It writes the file atomically and
checks what it wrote, so a report that says "watertight" speaks of the file.

See Also
--------
slicelab.mesh.save : the plain writer.
slicelab.mesh.repair : the fuller mending (near vertices, duplicates, windings).
"""
from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..geometry.topology import exact_ids
from ..geometry.triangles import winding_normals
from .core import Mesh
from .io import save, write_binary_stl
from .validation import MeshReport, check

__all__ = ["WrittenMesh", "write_mesh", "as_float32", "distinct_float32"]

#: Rounds of moving merged vertices apart before `distinct_float32` gives up (a moved vertex
#: can land on a third one; each round resolves what the previous one made).
_MAX_ROUNDS = 8
#: Weights of y and z in the key that screens corners for equality (irrational-looking: points of a
#: regular grid rarely share a key).
_KEY = (1.6180339887, 2.7182818285)


@dataclass(frozen=True)
class WrittenMesh:
    """A mesh file and the check of its contents.

    Attributes
    ----------
    path : Path
    report : MeshReport or None
        `check` of the mesh as stored in the file (float32 coordinates);
        None when not asked for.
    n_collapsed : int
        Facets left out because float32 rounding gave them no area.
    n_moved : int
        Vertices moved one or a few float32 steps off a point that rounding
        gave them in common with another vertex (see `distinct_float32`);
        0 unless leaving out the collapsed facets did not keep the file
        watertight.
    """

    path: Path
    report: MeshReport
    n_collapsed: int = 0
    n_moved: int = 0

    def to_dict(self) -> dict:
        """Plain-Python dictionary, ready for JSON."""
        return {"path": str(self.path), "n_collapsed": self.n_collapsed, "n_moved": self.n_moved,
                **(self.report.to_dict() if self.report is not None else {})}


def as_float32(mesh: Mesh) -> tuple[Mesh, int]:
    """The mesh an STL file will hold: coordinates rounded to float32, collapsed facets left out.

    Returns the rounded mesh and the number of facets left out.

    Examples
    --------
    >>> from slicelab.samples import box
    >>> t = box().triangles.copy()
    >>> sliver = np.array([[[10, 0, 0], [10 + 1e-7, 0, 0], [10.5, 1, 0]]])  # two corners one float32 point
    >>> m, n = as_float32(Mesh(np.concatenate([t, sliver])))
    >>> len(m), n
    (12, 1)
    """
    t32, n_out = _rounded(mesh.triangles)
    return Mesh(t32.astype(np.float64)), n_out


def _rounded(triangles: np.ndarray) -> tuple[np.ndarray, int]:
    """Triangles rounded to float32 without the facets that collapsed, and how many those were.

    A facet collapses when two of its corners round to one point. Dropping it
    needs no weld: its two merged corners already close the surface around it
    (an edge collapse), so the cost stays one pass over the facets.
    """
    t32 = triangles.astype(np.float32)
    # Corners that coincide have equal keys (one float32 sum per corner, the same operations on
    # the same values): the full comparison is made only where two keys agree.
    key = [t32[:, j, 0] + t32[:, j, 1] * np.float32(_KEY[0]) + t32[:, j, 2] * np.float32(_KEY[1])
           for j in range(3)]
    cand = np.flatnonzero((key[0] == key[1]) | (key[1] == key[2]) | (key[2] == key[0]))
    c = t32[cand]
    a, b, d = c[:, 0], c[:, 1], c[:, 2]
    hit = cand[(a == b).all(axis=1) | (b == d).all(axis=1) | (d == a).all(axis=1)]
    if len(hit) == 0:
        return t32, 0
    keep = np.ones(len(t32), bool)
    keep[hit] = False
    return t32[keep], len(hit)


def _packed(v32: np.ndarray) -> np.ndarray:
    """Float32 points (m, 3) as (m, 2) int64 rows of their bits, ``-0.0`` folded into ``0.0``."""
    bits = (v32 + np.float32(0)).view(np.uint32).astype(np.uint64)
    rows = np.empty((len(v32), 2), np.uint64)
    np.left_shift(bits[:, 0], np.uint64(32), out=rows[:, 0])
    rows[:, 0] |= bits[:, 1]
    rows[:, 1] = bits[:, 2]
    return rows.view(np.int64)


def _step(x: np.ndarray, direction: np.ndarray, k: np.ndarray) -> np.ndarray:
    """`x` (float32) moved `k` float32 steps towards ``direction * inf`` (k small)."""
    x = x.copy()
    target = np.where(direction > 0, np.float32(np.inf), np.float32(-np.inf))
    for i in range(1, int(k.max(initial=0)) + 1):  # a few steps, not rows
        move = k >= i
        x[move] = np.nextafter(x[move], target[move])
    return x


def distinct_float32(mesh: Mesh) -> tuple[Mesh, int]:
    """The mesh rounded to float32 with its topology kept: distinct vertices stay distinct.

    Vertices are welded exactly in float64 and rounded. Where several round
    to one float32 point, the one nearest to it keeps it and each other is
    moved along the axis on which it differs most from that one, by as many
    float32 steps as its rank in the group (1, 2, ...), towards its own side
    of the point; rounds repeat while a moved vertex lands on another one.
    No facet collapses, so the rounded mesh has the same vertices, edges and
    facets as `mesh`: watertight and consistently wound when `mesh` is. Each
    moved coordinate is at most a few float32 steps (about 1e-7 of its
    magnitude) from its float64 value.

    Returns the rounded mesh and the number of vertices moved.

    Examples
    --------
    Two solids that share a corner and pass 1e-9 mm apart along an edge:
    float32 rounding alone would make that edge one that four facets use.

    >>> from slicelab import check
    >>> tet = np.array([[0, 0, 0], [10, 3, 1], [0, 10, 0], [0, 0, 10]], float)
    >>> other = np.array([[0, 0, 0], [10 + 1e-9, 3, 1], [0, -10, 0], [0, 0, -10]])
    >>> f = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])
    >>> m = Mesh(np.concatenate([tet[f], other[f]]))
    >>> check(Mesh(m.triangles.astype(np.float32))).n_nonmanifold_edges
    1
    >>> r, n = distinct_float32(m)
    >>> n, check(r).watertight, r.triangles.dtype == np.float64
    (1, True, True)
    """
    flat = mesh.triangles.reshape(-1, 3)
    ids, first = exact_ids(flat)
    v64 = flat[first]
    v32 = v64.astype(np.float32)
    axis = np.full(len(v64), -1)  # the axis and direction a moved vertex keeps going
    sign = np.zeros(len(v64))
    for _ in range(_MAX_ROUNDS):  # rounds, each vectorised over the vertices
        group, keeper = exact_ids(_packed(v32))
        size = np.bincount(group, minlength=len(keeper))
        crowded = np.flatnonzero(size[group] > 1)
        if len(crowded) == 0:
            break
        # Rank each crowded group's members: vertices not moved yet first, then by distance to the
        # point. The first stays; the others move off, a moved one further along its own way.
        g = group[crowded]
        d = np.linalg.norm(v64[crowded] - v32[crowded].astype(np.float64), axis=1)
        order = np.lexsort((crowded, d, axis[crowded] >= 0, g))
        crowded, g = crowded[order], g[order]
        start = np.flatnonzero(np.r_[True, g[1:] != g[:-1]])
        counts = np.diff(np.r_[start, len(g)])
        rank = np.arange(len(g)) - np.repeat(start, counts)
        stay = np.repeat(crowded[start], counts)
        go = rank > 0
        who, ref, k = crowded[go], stay[go], rank[go]
        new = axis[who] < 0
        diff = v64[who[new]] - v64[ref[new]]
        axis[who[new]] = np.argmax(np.abs(diff), axis=1)
        sign[who[new]] = np.sign(diff[np.arange(len(diff)), axis[who[new]]])
        v32[who, axis[who]] = _step(v32[who, axis[who]], sign[who], k)
    else:
        raise RuntimeError("distinct_float32: vertices still share float32 points after "
                           f"{_MAX_ROUNDS} rounds")
    return Mesh(v32.astype(np.float64)[ids].reshape(-1, 3, 3)), int(np.count_nonzero(axis >= 0))


def _defects(r: MeshReport) -> int:
    return r.n_open_edges + r.n_nonmanifold_edges + r.n_misoriented_edges


def write_mesh(mesh: Mesh, path, *, ascii: bool = False, checked: bool = True) -> WrittenMesh:
    """Write `mesh` as STL (atomically) and return the check of what the file holds.

    The corners are rounded to float32 once and those values are written as
    they are (binary: a record array straight to disk), with the winding
    normals of the rounded corners.

    Parameters
    ----------
    mesh : Mesh
    path : str or os.PathLike
    ascii : bool, default False
    checked : bool, default True
        Check the written mesh (welding it: about as long as `check`); when
        leaving out the collapsed facets does not keep it watertight with
        consistent windings, write `distinct_float32` of `mesh` instead (its
        topology, and so its watertightness, are those of `mesh`). False for
        pieces that are open by design (a split's halves): the collapsed
        facets are still left out, and the result's report is None.

    Returns
    -------
    WrittenMesh

    Examples
    --------
    >>> import os, tempfile
    >>> from slicelab import load
    >>> from slicelab.samples import torus
    >>> out = write_mesh(torus(n_major=24, n_minor=12), os.path.join(tempfile.mkdtemp(), "t.stl"))
    >>> out.report.watertight, check(load(out.path)) == out.report
    (True, True)
    """
    t32, n_out = _rounded(mesh.triangles)
    report, n_moved = None, 0
    if checked:
        written = Mesh(t32.astype(np.float64))
        report = check(written)
        if _defects(report) and len(written):
            # Rounding changed the topology more than an edge collapse can mend: keep the mesh's own.
            kept, n = distinct_float32(mesh)
            kept_report = check(kept)
            if _defects(kept_report) <= _defects(report):
                written, report, n_out, n_moved = kept, kept_report, 0, n
                t32 = kept.triangles.astype(np.float32)  # float32 values: exact
        normals = written.normals
    else:
        normals = winding_normals(t32)
    if ascii:
        save(Mesh(t32.astype(np.float64)), path, ascii=True)
    else:
        write_binary_stl(t32, normals, path)
    return WrittenMesh(Path(path), report, n_out, n_moved)
