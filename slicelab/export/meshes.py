"""Meshes written as they are reported: the file's own check, after its float32 rounding.

STL stores single-precision coordinates. A cut's sliver facets, exact in
double precision, can lose their area when rounded: two corners land on the
same float32 point, the facet collapses and the edges around it stop being
manifold. `write_mesh` rounds first, leaves out the facets that collapsed
(the surface around them closes up, as after an edge collapse), writes the
file atomically and checks what it wrote, so a report that says "watertight"
speaks of the file.

See Also
--------
slicelab.mesh.save : the plain writer.
slicelab.mesh.repair : the fuller mending (near vertices, duplicates, windings).
"""
from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..mesh import Mesh, MeshReport, check, save

__all__ = ["WrittenMesh", "write_mesh", "as_float32"]


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
        Facets left out because float32 rounding gave them no area (or made
        them copies of another facet).
    """

    path: Path
    report: MeshReport
    n_collapsed: int = 0

    def to_dict(self) -> dict:
        """Plain-Python dictionary, ready for JSON."""
        return {"path": str(self.path), "n_collapsed": self.n_collapsed,
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
    t32 = mesh.triangles.astype(np.float32)
    # A facet collapses when two of its corners round to one point; only then is the surface
    # around it mended (welding the whole mesh is the costly part, so it is done only then).
    a, b, c = t32[:, 0], t32[:, 1], t32[:, 2]
    collapsed = (a == b).all(axis=1) | (b == c).all(axis=1) | (c == a).all(axis=1)
    if not collapsed.any():
        return Mesh(t32.astype(np.float64)), 0
    # Dropping a collapsed facet needs no weld: its two merged corners already close the surface
    # around it (an edge collapse), so the cost stays one pass over the facets.
    return Mesh(t32[~collapsed].astype(np.float64)), int(np.count_nonzero(collapsed))


def write_mesh(mesh: Mesh, path, *, ascii: bool = False, checked: bool = True) -> WrittenMesh:
    """Write `mesh` as STL (atomically) and return the check of what the file holds.

    Parameters
    ----------
    mesh : Mesh
    path : str or os.PathLike
    ascii : bool, default False
    checked : bool, default True
        Check the written mesh (welding it: about as long as `check`). False
        for pieces that are open by design (a split's halves): the collapsed
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
    written, n_out = as_float32(mesh)
    save(written, path, ascii=ascii)
    return WrittenMesh(Path(path), check(written) if checked else None, n_out)
