"""A sealed vessel's cavity: an inner shell of the mesh, facing inward, inside an outer one.

A scan of a closed vessel (a sealed jar, a bottle stopped in the scan) has
no mouth: no section through the axis opens to the top, so there is nothing
to fill to a rim. Its void is an inner closed shell whose normals point into
the void (inward, negative signed volume), lying inside a shell that faces
outward; `cavity_volume` finds such shells and sums their volumes.
"""
from __future__ import annotations

import numpy as np

from ..geometry.topology import exact_ids, shells

__all__ = ["cavity_volume"]


def cavity_volume(mesh) -> float:
    """Volume (mm^3) of the mesh's cavity shells: inward-facing shells inside an outward-facing one.

    Shells are edge-connected sets of facets after welding identical
    vertices (`slicelab.geometry.topology.shells`); each shell's signed
    volume is the divergence theorem's sum (corners taken about the mesh's
    centre); a negative one lying within the bounding box of a positive,
    larger one is a cavity, less the positive shells within its box (solid
    islands in the void).

    Parameters
    ----------
    mesh : Mesh

    Returns
    -------
    float
        0 when the mesh has no cavity.

    Examples
    --------
    >>> from slicelab.samples import box, concat
    >>> cavity_volume(concat(box((0, 0, 0), (10, 10, 10)), box((2, 2, 2), (8, 8, 7), inward=True)))
    180.0
    >>> cavity_volume(box((0, 0, 0), (10, 10, 10)))
    0.0
    >>> from slicelab.samples import nested_shells
    >>> cavity_volume(nested_shells())  # a 24 mm cube of void round a 10 mm cube of solid
    12824.0
    """
    tri = np.asarray(mesh.triangles, dtype=np.float64)
    if len(tri) == 0:
        return 0.0
    ids, _ = exact_ids(tri.reshape(-1, 3))
    n, label = shells(ids.reshape(-1, 3))
    if n < 2:
        return 0.0
    flat = tri.reshape(-1, 3)
    t = tri - (flat.min(axis=0) + flat.max(axis=0)) / 2
    vol = np.einsum("ij,ij->i", t[:, 0], np.cross(t[:, 1], t[:, 2])) / 6.0
    shell_vol = np.bincount(label, weights=vol, minlength=n)
    lo = np.full((n, 3), np.inf)
    hi = np.full((n, 3), -np.inf)
    corner_shell = np.repeat(label, 3)
    np.minimum.at(lo, corner_shell, flat)
    np.maximum.at(hi, corner_shell, flat)
    outer = np.flatnonzero(shell_vol > 0)
    inner = np.flatnonzero(shell_vol < 0)
    if not len(outer) or not len(inner):
        return 0.0
    # Inner shell i inside outer shell o: its box within o's, and o the larger.
    within = (lo[inner, None] >= lo[None, outer]).all(-1) & (hi[inner, None] <= hi[None, outer]).all(-1)
    within &= -shell_vol[inner, None] < shell_vol[None, outer]
    cavities = inner[within.any(axis=1)]
    if not len(cavities):
        return 0.0
    # Solid islands inside a cavity (outward shells within its box) take their volume from the void.
    island = (lo[outer, None] >= lo[None, cavities]).all(-1) & (hi[outer, None] <= hi[None, cavities]).all(-1)
    return float(-shell_vol[cavities].sum() - shell_vol[outer[island.any(axis=1)]].sum())
