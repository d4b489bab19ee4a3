"""Layer rasters: a section's material as pixel masks on a world-anchored grid.

Pixel (r, c) of the world grid has its centre at ``(x, y) = (c * p, r * p)``
for pixel size p: rows run along +y and nothing is flipped. A mask keeps only
a window of that grid (``row0``, ``col0`` and its shape), so masks of
different layers line up by integer offsets, whatever their windows.

The material comes from the section's oriented loops by a scanline over
pixel-centre rows: every edge adds its direction (+1 up, -1 down) at the
first pixel centre right of its crossing, and a running sum along the row
gives each pixel centre's winding number. Overlapping shells (CAD exports)
then fill as one region under the nonzero rule, and an overlap becomes a
hole under the even-odd rule. OpenCV gives the contour tree of the mask.

A layer's mask is held by blocks (`slicelab.printing.grid.masks.BlockMask`):
pixels only in the blocks within `band` of the boundary, found from the
edges' extents; every other block is inside or outside as a whole, which the
winding number of one pixel of it says. Rasterising then costs in proportion
to the boundary, not to the area of the island's box.

See Also
--------
slicelab.printing.grid.hierarchy : the raster hole hierarchy (OpenCV's contour tree of a layer raster).
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ...geometry.blocks import FULL, BlockGrid, blocks_near
from ...geometry.polygons import loop_edges
from ...geometry.spatial import split_segments
from .masks import BlockMask, GridMask, pixels_in_boxes

__all__ = ["GridMask", "LayerRaster", "rasterize", "layer_mask", "winding_numbers", "winding_blocks",
           "raster_blocks", "draw_polylines", "RULES", "BLOCK", "BAND"]

RULES = ("nonzero", "evenodd")
BLOCK = 32  # block size (pixels) of layer masks
BAND = 1.5  # mm of pixels kept along the boundary by default: two perimeters of 0.4 mm and their filling limit


@dataclass(frozen=True, eq=False)
class LayerRaster:
    """A section rasterised: one mask for the layer, and its islands.

    `rasterize` makes one; `raster_hierarchy` gives the contour tree of its masks.

    Attributes
    ----------
    tiles : tuple of BlockMask
        The layer's mask (one tile; none for an empty layer): its window is the
        bounding box of the loops plus a margin. Pixels are held within `band`
        of the boundary.
    pixel_size : float
    rule : str
        ``"nonzero"`` or ``"evenodd"``.
    loops : list of (k, 2) ndarray
        The section's closed loops (mm) and ``loop_tile``, the tile of each.
    loop_tile : (L,) int ndarray
    segments : list of (m, 2, 2) ndarray
        Per tile, the pieces (at most 4 px long) of loop edges that bound
        material under the rule (material on one side only); pieces buried
        inside overlapping shells are left out. Exact distances are measured
        to these.
    band : float
        Every pixel within this distance (mm) of the boundary is held.
    loop_island : (L,) int ndarray
        The island of each loop: loops whose boxes (plus the margin) overlap, directly or
        through others, make one island.
    island_boxes : (I, 4) int ndarray
        Each island's box of world pixels (first row, first column, last row, last column):
        its loops' boxes plus the margin. No two meet.
    """

    tiles: tuple
    pixel_size: float
    rule: str
    loops: list
    loop_tile: np.ndarray
    segments: list
    band: float = BAND
    loop_island: np.ndarray = field(default_factory=lambda: np.zeros(0, np.int64))
    island_boxes: np.ndarray = field(default_factory=lambda: np.zeros((0, 4), np.int64))

    @property
    def area(self) -> float:
        """Material area counted in pixels (mm^2)."""
        return sum(t.area for t in self.tiles)

    @property
    def pixels(self) -> int:
        """How many pixels the tiles hold (their active blocks')."""
        return sum(t.pixels for t in self.tiles)

    def combined(self):
        """All tiles in one mask (window: the union of the tile windows)."""
        return GridMask.union(self.tiles, self.pixel_size)

    def island_pixels(self, mask=None) -> np.ndarray:
        """Pixels of `mask` (default: the layer's own material) in each island's box, (I,) int.

        Examples
        --------
        >>> from types import SimpleNamespace
        >>> square = lambda x0, x1: np.array([[x0, 0], [x1, 0], [x1, x1 - x0], [x0, x1 - x0]], float)
        >>> r = rasterize(SimpleNamespace(loops=[square(0, 2), square(5, 6)]), 0.1)   # 2 mm and 1 mm squares
        >>> len(r.tiles), r.island_pixels().tolist()
        (1, [400, 100])
        """
        return pixels_in_boxes(self.combined() if mask is None else mask, self.island_boxes)

    def __repr__(self) -> str:
        return (f"LayerRaster({len(self.tiles)} tiles, {self.pixels} px held, "
                f"p={self.pixel_size:g} mm, rule={self.rule}, area={self.area:.6g} mm2)")


def _crossings(edges: np.ndarray, r_first: int, r_stop: int, pixel_size: float):
    """Every crossing of an edge with a pixel-centre row in r_first .. r_stop - 1: its row, the x
    of the crossing, and the winding step (+1 or -1) of the pixels right of it.

    Row r is crossed when ``ceil(ymin / p) <= r < ceil(ymax / p)``: a vertex
    shared by two edges gives both the same verdict, so a row through a vertex
    is counted once.
    """
    from ...geometry.segment_kernels import row_crossings
    # One compiled pass: as array operations, a dozen numpy calls per tile cost more than the work.
    return row_crossings(np.ascontiguousarray(edges, np.float64).reshape(-1, 2, 2), float(pixel_size), int(r_first),
                         int(r_stop))


def winding_numbers(edges: np.ndarray, row0: int, col0: int, shape, pixel_size: float) -> np.ndarray:
    """Winding number of every pixel centre of a window, by a signed-crossing scanline.

    Parameters
    ----------
    edges : (m, 2, 2) ndarray
        Oriented edges (material on their left) of closed loops, in mm.
    row0, col0, shape
        The window on the world grid.
    pixel_size : float

    Returns
    -------
    (h, w) int32 ndarray
        +1 inside a counter-clockwise loop, -1 inside a clockwise one, summed.

    Notes
    -----
    Row r is crossed by an edge when ``ceil(ymin / p) <= r < ceil(ymax / p)``:
    a vertex shared by two edges gives both the same verdict, so a row through
    a vertex is counted once. Every crossing is one ``bincount`` entry; no
    Python loop runs over edges.

    See Also
    --------
    winding_blocks : the same numbers, only in the blocks of a `BlockGrid`.

    Examples
    --------
    >>> sq = np.array([[0, 0], [2, 0], [2, 2], [0, 2]], float)
    >>> w = winding_numbers(loop_edges([sq, sq + 1]), 0, 0, (4, 4), 1.0)
    >>> w[::-1].tolist()
    [[0, 0, 0, 0], [0, 1, 1, 0], [1, 2, 1, 0], [1, 1, 0, 0]]
    """
    h, w = shape
    if len(edges) == 0:
        return np.zeros((h, w), np.int32)
    rows, x, step = _crossings(edges, row0, row0 + h, pixel_size)
    cols = np.clip(np.ceil(x / pixel_size).astype(np.int64) - col0, 0, w)
    # The crossings are few (about two per boundary row) against the window's pixels: added
    # into an int32 table in place, not counted into a float table the size of the window.
    acc = np.zeros((h, w + 1), np.int32)
    np.add.at(acc.reshape(-1), (rows - row0) * (w + 1) + cols, step)
    return np.cumsum(acc, axis=1, dtype=np.int32)[:, :w]


def winding_blocks(edges: np.ndarray, blocks: BlockGrid, pixel_size: float, *, rule: str | None = None):
    """Winding number of every pixel of the active blocks of a `BlockGrid`.

    The same numbers as `winding_numbers`, block by block: a block's row
    starts from the crossings left of the block (a binary search in the
    crossings sorted by row and column), then adds its own as it passes them
    (`slicelab.geometry.kernels.winding_rows`, one compiled pass).

    Parameters
    ----------
    edges : (m, 2, 2) ndarray
    blocks : BlockGrid
    pixel_size : float
    rule : {"nonzero", "evenodd"}, optional
        Given, the material under the rule instead of the numbers.

    Returns
    -------
    (n, B, B) int32 ndarray
        Without a rule.
    bits, some : (n, B, B) bool and (n,) bool ndarray
        With a rule: the material, and which blocks hold some.

    Examples
    --------
    >>> sq = np.array([[0, 0], [2, 0], [2, 2], [0, 2]], float)
    >>> g = BlockGrid(2, 0, 0, np.array([[0, 1]]))
    >>> e = loop_edges([sq, sq + 1])
    >>> np.array_equal(np.concatenate(list(winding_blocks(e, g, 1.0)), 1), winding_numbers(e, 0, 0, (2, 4), 1.0))
    True
    >>> bits, some = winding_blocks(e, g, 1.0, rule="evenodd")
    >>> bits[1].astype(int).tolist(), some.tolist()
    ([[0, 0], [1, 0]], [True, True])
    """
    from ...geometry.kernels import winding_rows
    b, n = blocks.size, len(blocks)
    out = np.empty((n, b, b), np.int32 if rule is None else np.uint8)  # the kernel writes every pixel
    if n == 0 or len(edges) == 0:
        return out if rule is None else (out.view(bool), np.zeros(n, bool))
    nr, nc = blocks.table.shape
    r_first, c_first = blocks.row0 * b, blocks.col0 * b - 1
    rows, x, step = _crossings(edges, r_first, (blocks.row0 + nr) * b, pixel_size)
    cols = np.clip(np.ceil(x / pixel_size).astype(np.int64), c_first, (blocks.col0 + nc) * b)
    stride = nc * b + 2
    key = (rows - r_first) * stride + (cols - c_first)
    order = np.argsort(key, kind="stable")
    key = key[order]
    total = np.concatenate([[0], np.cumsum(step[order], dtype=np.int64)])
    row_start = np.searchsorted(key, np.arange(nr * b + 1) * stride)
    br, bc = blocks.origins()
    mode = -1 if rule is None else (0 if rule == "nonzero" else 1)
    some = winding_rows(key, total, row_start, r_first, c_first, stride, br.astype(np.int64), bc.astype(np.int64),
                        mode, out)
    return out if rule is None else (out.view(bool), some)


def _apply_rule(winding: np.ndarray, rule: str) -> np.ndarray:
    return winding != 0 if rule == "nonzero" else (winding & 1).astype(bool)


def raster_blocks(edges: np.ndarray, row0: int, col0: int, shape, pixel_size: float, *, rule: str = "nonzero",
                  band: float = BAND, size: int = BLOCK) -> BlockMask:
    """The material of closed loops in a window, held by blocks within `band` of the edges.

    A block is active when its pixels come within `band` (plus two pixels)
    of an edge; the others hold no edge, so one pixel's winding number
    (`winding_numbers` on the grid of block corners) says for all of them.

    Parameters
    ----------
    edges : (m, 2, 2) ndarray
        Oriented edges of closed loops (mm).
    row0, col0, shape
        The window (world pixels) the material lies in.
    pixel_size : float
    rule : {"nonzero", "evenodd"}
    band : float
        mm.
    size : int
        Block size (pixels).

    Returns
    -------
    BlockMask

    Examples
    --------
    >>> sq = np.array([[0, 0], [20, 0], [20, 20], [0, 20]], float)
    >>> m = raster_blocks(loop_edges([sq]), -3, -3, (207, 207), 0.1, band=0.5, size=16)
    >>> len(m.blocks), m.blocks.n_full, round(m.area, 6), np.array_equal(m.mask, winding_numbers(
    ...     loop_edges([sq]), -3, -3, (207, 207), 0.1) != 0)
    (48, 121, 400.0, True)
    """
    p = float(pixel_size)
    h, w = shape
    rows = (row0 // size, (row0 + h - 1) // size)
    cols = (col0 // size, (col0 + w - 1) // size)
    active = blocks_near(edges, p, size, int(np.ceil(band / p)) + 2, rows, cols)
    # The first pixel of block (i, j) is the pixel (i, j) of a grid of size * p pixels.
    corner = winding_numbers(edges, rows[0], cols[0], active.shape, size * p)
    grid = BlockGrid.from_status(size, rows[0], cols[0], active, _apply_rule(corner, rule) & ~active)
    bits, some = winding_blocks(edges, grid, p, rule=rule)
    # A block near the boundary but wholly outside the material is an empty block: nothing is
    # lost by holding it as one (it is the band outside the material, about half of it).
    if not some.all():
        active[grid.rows[~some] - rows[0], grid.cols[~some] - cols[0]] = False
        grid = BlockGrid.from_status(size, rows[0], cols[0], active, grid.table == FULL)
        bits = bits[some]
    return BlockMask(bits, grid, int(row0), int(col0), (int(h), int(w)), p)


def _groups(lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
    """Connected groups of boxes that overlap (transitively), numbered in the order of their
    first box.

    The boxes that overlap are found pairwise (a layer has a handful of loops) and grouped by
    `slicelab.geometry.graphs.graph_components`, whose cost does not grow with the length of a
    chain of overlaps.

    Examples
    --------
    >>> lo = np.array([[0, 0], [50, 50], [8, 8], [16, 16]])   # 0 meets 2, 2 meets 3
    >>> _groups(lo, lo + 10).tolist()
    [0, 1, 0, 0]
    >>> chain = np.c_[np.arange(40) * 5, np.zeros(40)][::-1]   # each box meets the next: 39 rounds
    >>> int(_groups(np.r_[chain, [[500, 500]]], np.r_[chain, [[500, 500]]] + 6).max())
    1
    """
    n = len(lo)
    if n <= 1:
        return np.zeros(n, np.int64)
    if n > 3000:  # pairwise test too big: one tile
        return np.zeros(n, np.int64)
    from ...geometry.graphs import graph_components
    overlap = np.all((lo[:, None] <= hi[None]) & (lo[None] <= hi[:, None]), axis=2)
    return graph_components(n, *np.nonzero(overlap))[1]


def _layer_window(loops: list, p: float, margin: int):
    """The loops' boxes in pixels, widened by the margin, and the layer's window: (plo, phi), (row0,
    col0), shape."""
    lo = np.array([lp.min(axis=0) for lp in loops])
    hi = np.array([lp.max(axis=0) for lp in loops])
    plo = np.floor(lo / p).astype(np.int64) - margin
    phi = np.ceil(hi / p).astype(np.int64) + margin
    c0, r0 = plo.min(axis=0)
    c1, r1 = phi.max(axis=0)
    return plo, phi, (int(r0), int(c0)), (int(r1 - r0 + 1), int(c1 - c0 + 1))


def _checked(rule: str, pixel_size) -> float:
    if rule not in RULES:
        raise ValueError(f"rule must be one of {RULES}, got {rule!r}")
    p = float(pixel_size)
    if not (p > 0 and np.isfinite(p)):
        raise ValueError(f"pixel size must be a positive number, got {pixel_size!r}")
    return p


def layer_mask(section, pixel_size: float = 0.2, *, rule: str = "nonzero", margin: int = 3, band: float = BAND,
               block: int = BLOCK) -> BlockMask | None:
    """A section's material alone, as `rasterize` holds it (its tile), or None for an empty layer.

    What the skins and overhangs read of a neighbouring layer: the mask, without the
    islands and the loop edges that bound material, which the layer's own perimeters need.

    Examples
    --------
    >>> import slicelab
    >>> from slicelab.samples import box
    >>> s = slicelab.section(box((0, 0, 0), (2, 1, 1)), (0, 0, 0.5), (0, 0, 1))
    >>> m = layer_mask(s, 0.1)
    >>> round(m.area, 9), np.array_equal(m.mask, rasterize(s, 0.1).tiles[0].mask)
    (2.0, True)
    """
    p = _checked(rule, pixel_size)
    loops = [np.asarray(lp, np.float64) for lp in section.loops if len(lp) >= 3]
    if not loops:
        return None
    _, _, (r0, c0), shape = _layer_window(loops, p, margin)
    return raster_blocks(loop_edges(loops), r0, c0, shape, p, rule=rule, band=band, size=block)


def rasterize(section, pixel_size: float = 0.2, *, rule: str = "nonzero", margin: int = 3,
              band: float = BAND, block: int = BLOCK, tile=None) -> LayerRaster:
    """Rasterise a section's material on the world-anchored pixel grid.

    Parameters
    ----------
    section : Section
        Its closed loops are used (open chains are left out).
    pixel_size : float, default 0.2
        Pixel size p (mm); pixel centres sit at integer multiples of p.
    rule : {"nonzero", "evenodd"}
        Fill rule for overlapping or inside-out loops.
    margin : int, default 3
        Empty pixels kept around each island (loops whose widened boxes meet make one).
    band : float, default `BAND`
        Pixels within this distance (mm) of the boundary are held; blocks
        further inside or outside are held as a whole (`raster_blocks`).
    block : int, default `BLOCK`
        Block size (pixels); one block larger than the island holds it whole.
    tile : BlockMask, optional
        The section's mask as `layer_mask` gives it with these settings, taken
        as it is instead of drawn again (the planner draws every layer's mask
        for its neighbours' skins, and the rest only for the layers it plans).

    Returns
    -------
    LayerRaster

    Examples
    --------
    >>> import slicelab
    >>> from slicelab.samples import box
    >>> s = slicelab.section(box((0, 0, 0), (2, 1, 1)), (0, 0, 0.5), (0, 0, 1))
    >>> r = rasterize(s, 0.1)
    >>> len(r.tiles), round(r.area, 9), r.tiles[0].row0, r.tiles[0].col0
    (1, 2.0, -3, -3)
    """
    p = _checked(rule, pixel_size)
    loops = [np.asarray(lp, np.float64) for lp in section.loops if len(lp) >= 3]
    if not loops:
        return LayerRaster((), p, rule, [], np.zeros(0, np.int64), [], float(band))
    # Pixel-index boxes, widened by the margin: loops whose boxes meet make one island.
    plo, phi, (r0, c0), shape = _layer_window(loops, p, margin)
    group = _groups(plo, phi)
    n_islands = int(group.max()) + 1
    boxes = np.empty((n_islands, 4), np.int64)
    # One tile for the whole layer, however many islands: each stage of a tile (distance field,
    # level sets, openings) has a fixed cost, and blocks far from every boundary cost nothing.
    if tile is None:
        tile = raster_blocks(loop_edges(loops), r0, c0, shape, p, rule=rule, band=band, size=block)
    seg_lists = []
    for g in range(n_islands):  # over islands: their boxes, and which of their edges bound material
        members = np.flatnonzero(group == g)
        boxes[g, 1::-1], boxes[g, 3:1:-1] = plo[members].min(axis=0), phi[members].max(axis=0)
        edges = loop_edges([loops[k] for k in members])
        sizes = np.array([len(loops[k]) for k in members], np.int64)
        from ...geometry.segment_kernels import loops_touch
        bounds = np.concatenate([[0], np.cumsum(sizes)])
        if not loops_touch(np.ascontiguousarray(edges, np.float64), bounds):
            # Loops that nowhere meet: the winding number is the same all along either side of
            # a loop, so a loop bounds material along its whole length, or nowhere (buried in
            # another shell), and one look beside its longest edge decides all of its edges.
            d = edges[:, 1] - edges[:, 0]
            length = np.hypot(d[:, 0], d[:, 1])
            longest = bounds[:-1] + np.array([np.argmax(length[a:b]) for a, b in zip(bounds[:-1], bounds[1:])],
                                             np.int64)
            bounding = np.repeat(_bounding(edges[longest], edges, tile, rule), sizes)
            seg_lists.append(edges[bounding & (length > 0)])
            continue
        # Pieces of at most 4 px, so an edge that is partly buried by another shell keeps its
        # exposed part (to within one piece).
        pieces, _ = split_segments(edges, 4 * p)
        seg_lists.append(_exposed(pieces, edges, tile, rule))
    return LayerRaster((tile,), p, rule, loops, np.zeros(len(loops), np.int64), [np.concatenate(seg_lists)],
                       float(band), group.astype(np.int64), boxes)


def _exposed(pieces, edges, tile, rule: str = "nonzero") -> np.ndarray:
    """The pieces of loop edges that bound material; a piece that another shell's edge crosses
    (points near its ends and middle disagree) is cut at the crossings and each part judged on
    its own."""
    votes = [_bounding(pieces, edges, tile, rule, at=t) for t in (0.05, 0.5, 0.95)]
    mixed = np.flatnonzero((votes[0] != votes[1]) | (votes[1] != votes[2]))
    out = [pieces[votes[0] & votes[1] & votes[2]]]
    if len(mixed):
        from ...geometry.segment_kernels import cut_at_crossings
        # Every crossed piece cut at its crossings in one compiled loop (edges whose boxes miss
        # the piece's are passed over), each part then judged on its own.
        parts = cut_at_crossings(np.ascontiguousarray(pieces[mixed]), np.ascontiguousarray(edges, np.float64))
        out.append(parts[_bounding(parts, edges, tile, rule)])
    return np.concatenate(out)


def _bounding(pieces, edges, tile, rule: str, at: float = 0.5) -> np.ndarray:
    """Which pieces have material on exactly one side, at the point at fraction `at` along them.

    The mask is sampled 1.5 px either side of the point. Where both samples agree (a sliver
    of material or of void thinner than 3 px lies there, or the piece is buried in another
    shell), the loops' winding numbers a hair either side of the point decide exactly.
    """
    from ...geometry.segment_kernels import winding_at
    p = tile.pixel_size
    d = pieces[:, 1] - pieces[:, 0]
    length = np.hypot(d[:, 0], d[:, 1])
    n = np.stack([-d[:, 1], d[:, 0]], 1) / np.where(length > 0, length, 1.0)[:, None]
    mid = pieces[:, 0] + at * d

    def material(pts):
        return tile.at(np.rint(pts[:, 1] / p).astype(np.int64), np.rint(pts[:, 0] / p).astype(np.int64))

    # 1.5 px: the nearest pixel centre of the sample point is then surely on its side.
    left, right = material(mid + 1.5 * p * n), material(mid - 1.5 * p * n)
    unsure = np.flatnonzero((left == right) & (length > 0))
    if len(unsure):
        eps = 1e-6 * np.maximum(length[unsure], p)[:, None] * n[unsure]
        e = np.ascontiguousarray(edges, np.float64)
        wl, wr = (winding_at(np.ascontiguousarray(mid[unsure] + s * eps), e) for s in (1, -1))
        left[unsure], right[unsure] = ((wl != 0), (wr != 0)) if rule == "nonzero" else ((wl % 2 == 1), (wr % 2 == 1))
    return (left != right) & (length > 0)


def draw_polylines(shape, row0: int, col0: int, pixel_size: float, polylines, width: float, *,
                   closed: bool = False, shift: int = 4) -> np.ndarray:
    """Draw polylines `width` mm wide into a window of the world grid (uint8, 255 = covered).

    OpenCV draws them anti-aliased, with sub-pixel vertices (`shift`
    fractional bits); its thick lines come out up to two pixels wider than
    asked, so the result marks candidates rather than exact coverage.

    Parameters
    ----------
    shape : (h, w)
        The window's shape; its first pixel is (`row0`, `col0`) of the world grid.
    row0, col0 : int
    pixel_size : float
    polylines : list of (k, 2) ndarray
        Points in mm.
    width : float
        Line width (mm).
    closed : bool, default False
        Join each polyline's last point to its first.
    shift : int, default 4

    Returns
    -------
    (h, w) uint8 ndarray

    See Also
    --------
    slicelab.printing.steps.coverage.covered_pixels : the exact coverage of one polyline.

    Examples
    --------
    >>> img = draw_polylines((5, 9), 0, 0, 1.0, [np.array([[1.0, 2.0], [7.0, 2.0]])], 1.0)
    >>> bool((img[2, 1:8] > 0).all()), int(img[0].max()), int(img[4].max())
    (True, 0, 0)
    """
    import cv2
    img = np.zeros(shape, np.uint8)
    if not polylines:
        return img
    p = pixel_size
    scale = float(1 << shift)
    pts = [np.round((np.asarray(q) / p - (col0, row0)) * scale).astype(np.int32).reshape(-1, 1, 2)
           for q in polylines]
    cv2.polylines(img, pts, closed, 255, thickness=max(1, int(round(width / p))), lineType=cv2.LINE_AA,
                  shift=shift)
    return img
