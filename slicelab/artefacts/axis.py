"""Vessel axis: find the axis of revolution of a scan and move it onto +z, rim up, base at z = 0.

A scan comes in whatever pose the scanner left it, and a section through an
unaligned vessel says nothing about its shape. `align` finds the axis of
revolution and moves the vessel so that the axis is +z through the origin,
rim up, base at z = 0; `slicelab.artefacts.profile` then cuts it through the axis.

How the axis is found
---------------------
Up to four starts, in order of trust: the line the facets' normal lines meet
(a linear line complex [1]_ [2]_), then the principal axes of the surface;
each is refined by fitting concentric circles to horizontal sections
(`slicelab.artefacts.axis_fit`). The start whose circles fit best wins. The
rim goes up: the end where surface crosses the axis (the base) goes down;
failing that, the open boundary marks the rim; failing that, the centre of
mass goes down.

References
----------
.. [1] H. Pottmann and J. Wallner, *Computational Line Geometry*, Springer, 2001.
.. [2] H. Pottmann, M. Peternell and B. Ravani, "An introduction to line geometry
   with applications", *Computer-Aided Design* 31(1), 3-16, 1999.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..mesh.core import Mesh
from .axis_fit import normal_lines_axis, principal_axis, refine_axis, rotation_to_z, surface_moments

__all__ = ["Alignment", "align"]

_FIT_FACETS = 300_000     # facets sampled for fitting the axis; enough for a 0.01 degree fit
_NOT_REVOLUTION = 0.03    # relative circle residual above which a shape is not of revolution


@dataclass(frozen=True, eq=False)
class Alignment:
    """A mesh moved so that its axis of revolution is +z through the origin, rim up, base at z = 0.

    Attributes
    ----------
    mesh : Mesh
        The moved mesh (``input.transformed(matrix)``).
    matrix : (4, 4) ndarray
        Homogeneous rigid motion from input to aligned coordinates.
    axis : (3,) ndarray
        Unit axis direction in input coordinates, pointing from base to rim.
    origin : (3,) ndarray
        Where the axis meets the base plane, in input coordinates.
    residual : float
        RMS distance (mm) of horizontal sections from circles about the axis:
        how far the shape is from a surface of revolution.
    relative_residual : float
        `residual` divided by the mean radius of those circles.
    up_from : str
        The cue that decided which end is the rim: ``"base"``,
        ``"open boundary"`` or ``"centre of mass"``.
    method : str
        Which start won: ``"normals"`` (line complex) or ``"principal axes"``.

    See Also
    --------
    align : makes one.
    """

    mesh: Mesh
    matrix: np.ndarray
    axis: np.ndarray
    origin: np.ndarray
    residual: float
    relative_residual: float
    up_from: str
    method: str

    @property
    def is_revolution(self) -> bool:
        """True when horizontal sections stay within 3 % (RMS, of the radius) of circles about the axis."""
        return bool(self.relative_residual <= _NOT_REVOLUTION)

    def __repr__(self) -> str:
        return (f"Alignment(axis={np.round(self.axis, 6).tolist()}, residual={self.residual:.4g} mm "
                f"({100 * self.relative_residual:.3g} %), up from {self.up_from}, {self.method})")

    def to_dict(self) -> dict:
        """Plain numbers for JSON (the mesh left out)."""
        return {"matrix": self.matrix.tolist(), "axis": self.axis.tolist(), "origin": self.origin.tolist(),
                "residual": self.residual, "relative_residual": self.relative_residual,
                "up_from": self.up_from, "method": self.method}


def _fit_sample(triangles: np.ndarray) -> np.ndarray:
    """A deterministic random subset of facets; area statistics of a sample are unbiased."""
    n = len(triangles)
    if n <= _FIT_FACETS:
        return triangles
    keep = np.random.default_rng(0).random(n) < _FIT_FACETS / n
    return triangles[keep]


def _up_sign(t: np.ndarray, area: np.ndarray, point: np.ndarray, direction: np.ndarray, mesh: Mesh):
    """+1 if the rim lies towards +direction, -1 if not; and the cue that decided."""
    c = t.sum(axis=1) / 3.0 - point
    h = c @ direction
    corners = t - point
    hc = corners @ direction
    rc = np.linalg.norm(corners - hc[..., None] * direction, axis=2)
    lo, hi = float(hc.min()), float(hc.max())
    mid, length = (lo + hi) / 2, hi - lo
    near = rc.min(axis=1) < 0.15 * float(rc.max())  # facets reaching close to the axis
    if area[near].sum() > 0.002 * area.sum():
        # Surface crossing the axis is the base (a rim is a ring, away from the axis).
        m = float((area[near] * h[near]).sum() / area[near].sum())
        if abs(m - mid) > 0.1 * length:
            return (1 if m < mid else -1), "base"
    from ..geometry.topology import edge_table, weld
    _, faces = weld(mesh.triangles)
    et = edge_table(faces)
    open_edges = np.flatnonzero(et["counts"] == 1)
    if len(open_edges):
        f = et["first"][open_edges]
        tri, k = f // 3, f % 3
        a = mesh.triangles[tri, k]
        b = mesh.triangles[tri, (k + 1) % 3]
        w = np.linalg.norm(b - a, axis=1)
        m = float((w * (((a + b) / 2 - point) @ direction)).sum() / w.sum())
        if abs(m - mid) > 0.1 * length:
            return (1 if m > mid else -1), "open boundary"
    # The centre of mass of the enclosed volume (or of the surface, if open) sits low.
    from ..mesh.validation import signed_volume
    vol = signed_volume(mesh.triangles)
    if vol > 0:
        tt = mesh.triangles - point
        v6 = np.einsum("ij,ij->i", tt[:, 0], np.cross(tt[:, 1], tt[:, 2]))
        com_h = float((v6 * ((tt.sum(axis=1) / 4.0) @ direction)).sum() / v6.sum())
    else:
        com_h = float((area * h).sum() / area.sum())
    return (1 if com_h <= mid else -1), "centre of mass"


def align(mesh: Mesh) -> Alignment:
    """Move a scanned vessel so its axis of revolution is +z through the origin, rim up, base at z = 0.

    Up to four starts, in order of trust: the line the normal lines meet
    (`normal_lines_axis`, a linear line complex), then the principal axes
    (`principal_axis`). Each is refined by fitting concentric circles to
    horizontal sections in its frame (`refine_axis`: Kåsa's algebraic fit,
    one radius per wall, reweighted with Tukey's biweight so that a handle
    or a spout loses its say); the start whose circles fit best wins
    (`normal_lines_axis` and `refine_axis` cite the papers). The base (surface
    crossing the axis), else the open boundary (the rim), else the centre of
    mass decides which way is up.

    Parameters
    ----------
    mesh : Mesh
        A vessel (or any body of revolution) in any position; open scans,
        noise and missing sherds are fine.

    Returns
    -------
    Alignment

    Raises
    ------
    ValueError
        The mesh has too few facets or no area.

    See Also
    --------
    slicelab.artefacts.profile : cuts the aligned vessel through its axis.
    slicelab.artefacts.normal_lines_axis, slicelab.artefacts.principal_axis : starts.
    slicelab.artefacts.refine_axis : the concentric-circle refinement.

    Examples
    --------
    >>> import numpy as np
    >>> from slicelab.samples import pot
    >>> m = pot(20, 24)
    >>> tilt = np.eye(4); tilt[:3, :3] = rotation_to_z([1, 2, 2]).T; tilt[:3, 3] = [5, -7, 3]
    >>> a = align(m.transformed(tilt))
    >>> np.round(a.axis * 3, 3).tolist(), np.round(a.mesh.bounds[:, 2], 1).tolist()
    ([1.0, 2.0, 2.0], [0.0, 120.0])
    """
    if len(mesh) < 4:
        raise ValueError(f"cannot align a mesh of {len(mesh)} facets")
    t = _fit_sample(mesh.triangles)
    area, centroid, cov = surface_moments(t)
    scale = math.sqrt(float(np.trace(cov))) or 1.0
    # Starts in order of trust; the next is tried only while the best fit is poor (over 1 %), and
    # never twice in one basin. The other two principal axes come last: a jug's handle can make
    # the wrong eigenvalue stand apart.
    _, eig = np.linalg.eigh(cov)
    apart = principal_axis(cov)
    starts = [("normals", normal_lines_axis(t, area, centroid, scale)), ("principal axes", (centroid, apart))]
    starts += [("principal axes", (centroid, v)) for v in eig.T if abs(float(v @ apart)) < 0.5]
    results, tried = [], []
    for name, (p, d) in starts:  # at most four starts, a few passes each
        fits = [r[3][2] for r in results if r[3] is not None]
        if fits and min(fits) <= 0.01:
            break
        if any(abs(float(d @ e)) > math.cos(math.radians(3)) for e in tried):
            continue
        tried.append(d)
        results.append((name, *refine_axis(t, p, d)))
        tried.append(results[-1][2])
    fitted = [r for r in results if r[3] is not None]
    if fitted:
        method, point, direction, (rms, rel, _) = min(fitted, key=lambda r: r[3][2])
    else:
        method, point, direction, _ = results[0]
        rms = rel = math.inf
    direction = direction / np.linalg.norm(direction)
    sign, cue = _up_sign(t, area, point, direction, mesh)
    direction = sign * direction
    R = rotation_to_z(direction)
    # Rotated by einsum, not matmul: numpy hands (n, 3) x (3, 3) to a threaded BLAS, which on a
    # busy machine ran 10-20x slower (15 M points: 5-8 s against 0.5 s).
    moved = np.einsum("...j,ij->...i", mesh.triangles, R) - R @ point
    z0 = float(moved[..., 2].min())
    moved[..., 2] -= z0  # the lowest corner lands exactly on z = 0
    origin = point + z0 * direction
    matrix = np.eye(4)
    matrix[:3, :3] = R
    matrix[:3, 3] = -R @ origin
    # A proper rotation keeps the winding and moves normals as it moves points.
    normals = np.einsum("...j,ij->...i", mesh.file_normals, R)
    return Alignment(Mesh(moved, normals), matrix, direction, origin, float(rms), float(rel), cue, method)


