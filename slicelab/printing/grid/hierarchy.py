"""The raster hole hierarchy: outer boundaries, holes and islands in holes of a layer raster.

OpenCV's contour tree (``RETR_TREE``) of each island's mask gives every
contour's depth and parent; each contour is then matched to the section loop
it traces, so the raster's hierarchy and the vector loops' agree (or say where
they do not: the union of overlapping shells traces no single loop).

See Also
--------
slicelab.printing.grid.raster.rasterize : the layer rasters.
slicelab.geometry.polygons.loop_hierarchy : the same hierarchy from the vector loops.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ...geometry.polygons import signed_area
from .masks import GridMask
from .raster import LayerRaster, rasterize  # noqa: F401  (rasterize: the examples)

__all__ = ["RasterContours", "raster_hierarchy"]


@dataclass(frozen=True, eq=False)
class RasterContours:
    """The contour tree of a layer raster (OpenCV ``RETR_TREE``), matched to the vector loops.

    Attributes
    ----------
    contours : list of (k, 2) ndarray
        Boundary pixel centres of each contour, in mm.
    tile : (n,) int ndarray
        Tile of each contour.
    depth : (n,) int ndarray
        0 for an outer boundary, 1 for a hole, 2 for an island in a hole...
    parent : (n,) int ndarray
        Enclosing contour, or -1.
    loop : (n,) int ndarray
        The section loop each contour traces (index into ``raster.loops``),
        or -1 when none does (e.g. the union of overlapping shells).
    """

    contours: list
    tile: np.ndarray
    depth: np.ndarray
    parent: np.ndarray
    loop: np.ndarray


def raster_hierarchy(raster: LayerRaster) -> RasterContours:
    """Outer boundaries, holes and islands in holes of a raster, to any depth.

    A contour is matched to the vector loop of the same kind (outer or hole)
    whose bounding box is nearest, if within 1.5 pixels on every side.

    Examples
    --------
    >>> import slicelab
    >>> from slicelab.samples import nested_shells
    >>> s = slicelab.section(nested_shells(), (0, 0, 20), (0, 0, 1))
    >>> h = raster_hierarchy(rasterize(s, 0.5))
    >>> h.depth.tolist(), (s.loop_depth[h.loop]).tolist()
    ([0, 1, 2], [0, 1, 2])
    """
    import cv2
    p = raster.pixel_size
    contours, tiles, depths, parents, matched = [], [], [], [], []
    loop_lo = np.array([lp.min(axis=0) for lp in raster.loops]).reshape(-1, 2)
    loop_hi = np.array([lp.max(axis=0) for lp in raster.loops]).reshape(-1, 2)
    loop_ccw = np.array([signed_area(lp) > 0 for lp in raster.loops], bool)
    # Island by island, each in its own box: far-apart islands share a tile, not a window.
    if len(raster.island_boxes):
        parts = [(t, GridMask(tile.window(r0, c0, (r1 - r0 + 1, c1 - c0 + 1)), r0, c0, p),
                  np.flatnonzero((raster.loop_tile == t) & (raster.loop_island == g)))
                 for t, tile in enumerate(raster.tiles)
                 for g, (r0, c0, r1, c1) in enumerate(raster.island_boxes.tolist())]
    else:  # a raster made without islands: each tile whole
        parts = [(t, tile, np.flatnonzero(raster.loop_tile == t)) for t, tile in enumerate(raster.tiles)]
    for t, tile, cand in parts:  # over islands
        cs, hier = cv2.findContours(tile.mask.astype(np.uint8), cv2.RETR_TREE, cv2.CHAIN_APPROX_SIMPLE)
        if hier is None:
            continue
        par = hier[0][:, 3].astype(np.int64)
        dep = np.zeros(len(cs), np.int64)
        for k in range(len(cs)):  # over contours: follow parent links
            j = par[k]
            while j >= 0:
                dep[k] += 1
                j = par[j]
        base = len(contours)
        used = set()
        order = np.argsort([-cv2.contourArea(c) for c in cs], kind="stable")
        match = np.full(len(cs), -1, np.int64)
        for k in order:  # over contours
            pts = tile.xy(cs[k][:, 0, 1], cs[k][:, 0, 0])
            lo, hi = pts.min(axis=0), pts.max(axis=0)
            kind = dep[k] % 2 == 0
            ok = cand[(loop_ccw[cand] == kind) & ~np.isin(cand, list(used))]
            if len(ok):
                cost = np.maximum(np.abs(loop_lo[ok] - lo).max(axis=1), np.abs(loop_hi[ok] - hi).max(axis=1))
                best = int(np.argmin(cost))
                if cost[best] <= 1.5 * p:
                    match[k] = ok[best]
                    used.add(int(ok[best]))
        for k in range(len(cs)):
            contours.append(tile.xy(cs[k][:, 0, 1], cs[k][:, 0, 0]))
        tiles += [t] * len(cs)
        depths.append(dep)
        parents.append(np.where(par >= 0, par + base, -1))
        matched.append(match)
    cat = (lambda xs: np.concatenate(xs) if xs else np.zeros(0, np.int64))
    return RasterContours(contours, np.array(tiles, np.int64), cat(depths), cat(parents), cat(matched))
