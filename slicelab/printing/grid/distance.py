"""The distance to a layer's boundary on its pixels, exact, and its level sets.

Every material pixel held along the boundary gets the exact distance from
its centre to the section's boundary segments (those that bound material
under the fill rule), up to the depth the perimeters and their filling
need, so the contours that marching squares interpolates between pixels lie
near the true offsets. The distance is found among the segments' pieces in
the pixel's bucket, in one compiled loop. The contours' vertices are then
moved onto the exact offsets (along the line from their nearest boundary
point), with the offsets' arcs round boundary vertices followed and their
creases and sharp corners (which linear interpolation cuts off) put back
where two features' offsets meet exactly at the level: the perimeters' accuracy
does not depend on the pixel size.

The field lives on the blocks of the layer's mask (`slicelab.printing.grid.masks.BlockMask`):
only the blocks near the boundary hold pixels, so its cost follows the
boundary. Blocks deep inside take one value, the depth below which the
field is computed.

See Also
--------
slicelab.printing.steps.perimeters : the perimeters drawn along these level sets.
slicelab.geometry.contours : marching squares and ring simplification.
slicelab.geometry.spatial : `SegmentIndex`, the exact distances to the boundary.
slicelab.geometry.blocks : the blocks and their halos.
"""
from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np

from ...geometry.contours import march_blocks
from ...geometry.polygons import signed_area
from ...geometry.spatial import SegmentIndex
from .masks import BlockMask
from ..steps.simplify import simplify_rings

__all__ = ["DistanceField", "signed_mask_distance", "distance_field", "level_rings"]


@dataclass(frozen=True, eq=False)
class DistanceField:
    """Signed distance to a tile's boundary (mm; positive in material), on the pixels of its blocks.

    Attributes
    ----------
    blocks : (n, B, B) float32 ndarray
        The field on the active blocks of ``grid.blocks``. Pixels outside the
        material hold -p/2; the field stops at `deep`.
    grid : BlockMask
        The tile (material and its blocks).
    deep : float
        The field's value in full blocks, and its largest value: distances
        beyond it are not computed.
    refined : int
        How many pixels hold the exact distance to the boundary segments.
    """

    blocks: np.ndarray
    grid: BlockMask
    deep: float
    refined: int = 0

    @property
    def outside(self) -> float:
        """The value of pixels outside the material (-p/2)."""
        return -0.5 * self.grid.pixel_size

    @cached_property
    def values(self) -> np.ndarray:
        """The field on the tile's whole window, (h, w) float32 (made on first use, for plots)."""
        g = self.grid
        return g.blocks.assemble(self.blocks, np.float32(self.outside), np.float32(self.deep), g.row0, g.col0,
                                 g.shape)

    def mosaic(self, halo: int, values: np.ndarray | None = None) -> np.ndarray:
        """The field (or `values` on the same blocks) with a halo, as one image (`BlockGrid.mosaic`)."""
        v = self.blocks if values is None else values
        return self.grid.blocks.mosaic(v, halo, v.dtype.type(self.outside), v.dtype.type(self.deep))

    def wide_mosaic(self, halo: int) -> tuple[np.ndarray, int]:
        """The field's mosaic with a halo of at least `halo` pixels, and that halo: made once and
        shared by the filters that read no further (a filter reading r pixels needs a halo >= r)."""
        for h, image in self._wide.items():
            if h >= halo:
                return image, h
        self._wide[halo] = self.mosaic(halo)
        return self._wide[halo], halo

    @cached_property
    def _wide(self) -> dict:
        return {}


def signed_mask_distance(mask: np.ndarray, pixel_size: float, *, outside: bool = True,
                         precise: bool = True) -> np.ndarray:
    """Approximate signed distance (mm) to a mask's boundary: positive inside, from OpenCV.

    The boundary is taken half a pixel beyond the last pixel centre. With
    ``outside=False`` every pixel outside gets -p/2 (one transform instead of two),
    and the result is float32 (micrometre-exact for any layer under 100 m).
    ``precise=False`` takes OpenCV's 5 x 5 chamfer distance instead of the exact
    distance between pixel centres: within about 2 % of it, and three times
    faster on one thread (`distance_field` refines what the contours need).

    See Also
    --------
    distance_field : this distance, made exact near the levels to draw.

    Examples
    --------
    >>> m = np.zeros((1, 7), bool); m[0, 2:5] = True
    >>> signed_mask_distance(m, 1.0).tolist()
    [[-1.5, -0.5, 0.5, 1.5, 0.5, -0.5, -1.5]]
    """
    import cv2
    m8 = np.ascontiguousarray(mask, dtype=np.uint8)
    din = cv2.distanceTransform(m8, cv2.DIST_L2, cv2.DIST_MASK_PRECISE if precise else cv2.DIST_MASK_5)
    if not outside:  # float32, in place: these arrays are the biggest of a layer
        din -= 0.5  # pixels outside are at 0 from the background: they become -1/2 too
        din *= pixel_size
        return din
    dout = cv2.distanceTransform(1 - m8, cv2.DIST_L2, cv2.DIST_MASK_PRECISE)
    return np.where(mask, din.astype(np.float64) - 0.5, 0.5 - dout.astype(np.float64)) * pixel_size


def _chamfer_blocks(tile: BlockMask, halo: int) -> np.ndarray:
    """OpenCV's chamfer distance (pixels) of the tile's active blocks, right up to `halo` pixels.

    Each block is taken with `halo` pixels of its neighbours: a distance up to
    the halo is then the distance on the whole grid. A small window goes
    through OpenCV whole, when that is fewer pixels than the blocks and their halos.
    """
    import cv2
    g, b = tile.blocks, tile.blocks.size
    n = len(g)
    h, w = tile.shape
    if h * w <= n * (b + 2 * halo) ** 2:
        nr, nc = g.table.shape
        r0, c0 = g.row0 * b, g.col0 * b
        whole = tile.window(r0, c0, (nr * b, nc * b)).view(np.uint8)
        d = cv2.distanceTransform(whole, cv2.DIST_L2, cv2.DIST_MASK_5)
        d = d.reshape(nr, b, nc, b).transpose(0, 2, 1, 3)
        return d[g.rows - g.row0, g.cols - g.col0]
    image = g.mosaic(tile.bits.view(np.uint8), halo, np.uint8(0), np.uint8(1))
    return g.cores(cv2.distanceTransform(image, cv2.DIST_L2, cv2.DIST_MASK_5), halo)


def distance_field(tile: BlockMask, index: SegmentIndex | None, levels, *, depth: float | None = None) -> DistanceField:
    """The distance field of a tile: the exact distance to its boundary on every material pixel, up to a depth.

    Each material pixel of the tile's active blocks gets the distance from its
    centre to the nearest boundary segment, found among the segments' pieces
    listed in its bucket (`SegmentIndex.piece_buckets`) by one compiled loop
    (`slicelab.geometry.segment_kernels.band_distances`); pixels farther than the
    depth take `DistanceField.deep`. The contours that marching squares
    interpolates between pixels then lie on the true offsets. Without an
    index, OpenCV's chamfer distance between pixel centres stands in
    (`signed_mask_distance`, ``precise=False``): within half a pixel and about
    2 % of the distance to the pixels' edge.

    Parameters
    ----------
    tile : BlockMask
        Its blocks must hold every pixel within `depth` (plus a pixel) of the boundary.
    index : SegmentIndex or None
        The tile's boundary segments (those that bound material under the fill
        rule); None keeps the pixel-exact field.
    levels : sequence of float
        Distances (mm) whose level sets will be drawn: the default depth is the deepest.
    depth : float, optional
        The field is computed up to this distance (mm) and a pixel or two
        beyond (`DistanceField.deep`); default the deepest level.

    Returns
    -------
    DistanceField

    See Also
    --------
    signed_mask_distance : the pixel distance used without an index.
    level_rings : the level sets of the field, as simplified rings.

    Examples
    --------
    >>> import slicelab
    >>> from slicelab.samples import box
    >>> r = slicelab.rasterize(slicelab.section(box((0, 0, 0), (3, 2, 1)), (0, 0, .5), (0, 0, 1)), 0.1)
    >>> t = r.tiles[0]
    >>> f = distance_field(t, SegmentIndex(r.segments[0], 0.4), [0.25])
    >>> i, j = np.rint(t.indices([1.5, 0.3])).astype(int)
    >>> round(float(f.values[i, j]), 6), f.refined > 0
    (0.3, True)
    """
    from ...geometry.segment_kernels import band_distances
    p = tile.pixel_size
    levels = [float(v) for v in levels]
    depth = max(levels, default=0.0) if depth is None else float(depth)
    halo = int(np.ceil(depth / p)) + 2
    deep = (halo - 0.5) * p
    g = tile.blocks
    if index is None or not len(index) or not len(g):
        # Only levels inside the material are ever drawn: the outside needs no distances.
        values = _chamfer_blocks(tile, halo)
        values -= 0.5
        values *= p
        np.minimum(values, np.float32(deep), out=values)
        return DistanceField(values, tile, deep, 0)
    rows0, cols0 = g.origins()
    origin, width, height, start, owner, pieces = index.piece_buckets(deep)
    values, exact = band_distances(np.ascontiguousarray(tile.bits), rows0.astype(np.int64), cols0.astype(np.int64),
                                   float(p), float(deep), float(deep), int(origin[0]), int(origin[1]), width,
                                   height, start, owner, pieces)
    return DistanceField(values, tile, deep, int(exact))


def _onto_offset(rings: list, level: float, index: SegmentIndex, p: float, tolerance: float,
                 cell: float) -> list:
    """Contour rings moved onto the exact offset, its arcs and creases followed (all rings at once).

    Marching squares interpolates the field linearly between pixel centres:
    on an offset line the field is linear and the vertex exact, but round a
    corner of the boundary (an arc of the offset) or at a crease (where two
    boundary features are equally near) it is not. One compiled pass
    (`slicelab.geometry.offset_kernels.onto_offset`) moves each vertex within
    half a pixel of the level onto the offset, along the line from its
    nearest boundary point, adds points where a chord strays from the offset
    by more than half the tolerance, and puts back the sharp corners
    interpolation cut off.
    """
    from ...geometry.offset_kernels import onto_offset
    sizes = np.array([len(r) for r in rings])
    bounds = np.concatenate([[0], np.cumsum(sizes)])
    origin, width, height, start, owner, pieces = index.piece_buckets(cell)
    # Vertices within half a pixel of the level are moved; a corner's tip may lie 6 pixels out.
    out, ob = onto_offset(np.concatenate(rings), bounds, float(level), float(tolerance), 0.5 * p, 6 * p,
                          float(cell), int(origin[0]), int(origin[1]), width, height, start, owner, pieces)
    return [out[a:b] for a, b in zip(ob[:-1].tolist(), ob[1:].tolist())]


def level_rings(field: DistanceField, level: float, *, tolerance: float, index: SegmentIndex | None = None,
                values: np.ndarray | None = None, min_area: float | None = None) -> list[np.ndarray]:
    """Closed rings (material on the left) where the field crosses `level`, on the exact offset, simplified.

    Parameters
    ----------
    field : DistanceField
    level : float
    tolerance : float
        Simplification tolerance (mm), Douglas-Peucker (`slicelab.printing.steps.simplify.simplify_rings`).
    index : SegmentIndex, optional
        Boundary segments; given (and `values` not), the rings are moved onto the
        exact offset at `level`, its arcs, creases and sharp corners included.
    values : (n, B, B) ndarray, optional
        Another field on the same blocks to contour at `level` instead (e.g.
        the field lowered below the level where a mask excludes it); its
        empty and full blocks are the field's.
    min_area : float, optional
        Rings enclosing less (mm^2) are dropped; default 4 pixels.

    Returns
    -------
    list of (k, 2) ndarray
        Rings in mm, implicitly closed.

    See Also
    --------
    distance_field : the field contoured.
    slicelab.geometry.march_blocks, slicelab.printing.steps.simplify.simplify_rings : the contours and their simplification.

    Examples
    --------
    >>> import slicelab
    >>> from slicelab.samples import box
    >>> r = slicelab.rasterize(slicelab.section(box((0, 0, 0), (3, 2, 1)), (0, 0, .5), (0, 0, 1)), 0.1)
    >>> idx = SegmentIndex(r.segments[0], 0.4)
    >>> rings = level_rings(distance_field(r.tiles[0], idx, [0.5]), 0.5, tolerance=0.005, index=idx)
    >>> np.round(rings[0], 9).tolist()
    [[0.5, 0.5], [2.5, 0.5], [2.5, 1.5], [0.5, 1.5]]
    """
    g = field.grid.blocks
    p = field.grid.pixel_size
    min_area = 4 * p * p if min_area is None else min_area
    if not len(g):
        return []
    stack = field.blocks if values is None else values
    rings = []
    found = [c[:, ::-1] * p for c in march_blocks(stack, level, g, field.outside, field.deep) if len(c) >= 3]
    if values is None and index is not None and len(index) and found:
        found = _onto_offset(found, level, index, p, tolerance, field.deep)
    # Every ring of the level simplified in one compiled pass.
    for xy in simplify_rings(found, tolerance):
        if len(xy) >= 3 and abs(signed_area(xy)) >= min_area:
            rings.append(xy)
    return rings
