"""Boolean masks on the world-anchored pixel grid: whole windows, or blocks along a boundary.

Pixel (r, c) of the world grid has its centre at ``(x, y) = (c * p, r * p)``
for pixel size p: rows run along +y and nothing is flipped. A mask covers a
window of that grid (``row0``, ``col0`` and its shape), so masks of
different layers line up by integer offsets, whatever their windows.

A `GridMask` holds every pixel of its window. A `BlockMask` holds pixels
only in the blocks near its boundary (`slicelab.geometry.blocks.BlockGrid`);
the others are uniformly empty or full, so its cost follows the boundary,
and set operations between block masks work block by block. Both offer the
same window methods; a block mask's whole array (`BlockMask.mask`) is made
on first use, for plots and callers that want pixels everywhere.

See Also
--------
slicelab.printing.grid.raster.rasterize : a layer's material as block masks.
"""
from __future__ import annotations

import functools
from dataclasses import dataclass
from functools import cached_property

import numpy as np

from ...geometry.blocks import EMPTY, FULL, BlockGrid

__all__ = ["GridMask", "BlockMask", "bits_in_blocks", "dilate_mask", "erode_mask", "near_mask", "open_mask", "pixels_in_boxes",
           "reach_disc"]


class _Window:
    """Millimetre coordinates of a window of the world grid (needs row0, col0, shape, pixel_size)."""

    @property
    def transform(self) -> np.ndarray:
        """3x3 affine matrix taking (col, row, 1) array indices to (x, y, 1) in mm.

        Examples
        --------
        >>> GridMask(np.ones((1, 1), bool), 2, 3, 0.1).transform @ [0, 0, 1]
        array([0.3, 0.2, 1. ])
        """
        p = self.pixel_size
        return np.array([[p, 0.0, self.col0 * p], [0.0, p, self.row0 * p], [0.0, 0.0, 1.0]])

    @property
    def extent(self) -> list[float]:
        """matplotlib ``imshow(..., origin="lower", extent=...)`` of the window (pixel edges, mm)."""
        p = self.pixel_size
        h, w = self.shape
        return [(self.col0 - 0.5) * p, (self.col0 + w - 0.5) * p,
                (self.row0 - 0.5) * p, (self.row0 + h - 0.5) * p]

    def xy(self, rows, cols) -> np.ndarray:
        """Millimetre coordinates of (fractional) array indices."""
        rows, cols = np.asarray(rows, np.float64), np.asarray(cols, np.float64)
        return np.stack([(self.col0 + cols) * self.pixel_size, (self.row0 + rows) * self.pixel_size], -1)

    def indices(self, xy) -> np.ndarray:
        """Fractional (row, col) array indices of points in mm (inverse of `xy`)."""
        q = np.asarray(xy, np.float64) / self.pixel_size
        return np.stack([q[..., 1] - self.row0, q[..., 0] - self.col0], -1)

    def contains(self, xy) -> np.ndarray:
        """The mask at points (mm): the pixel each lies in (its nearest pixel centre).

        Examples
        --------
        >>> GridMask(np.array([[True, False]]), 0, 0, 1.0).contains([[0.2, 0.1], [1.4, 0.0], [5.0, 5.0]]).tolist()
        [True, False, False]
        """
        q = np.rint(np.asarray(xy, np.float64).reshape(-1, 2) / self.pixel_size).astype(np.int64)
        return self.at(q[:, 1], q[:, 0])

    def _check(self, other) -> None:
        if other.pixel_size != self.pixel_size:
            raise ValueError("masks on different pixel grids cannot be combined")


@dataclass(frozen=True, eq=False)
class GridMask(_Window):
    """A boolean mask on the world-anchored pixel grid.

    Attributes
    ----------
    mask : (h, w) bool ndarray
        ``mask[r, c]`` is the pixel centred at ``((col0 + c) p, (row0 + r) p)``.
    row0, col0 : int
        World grid indices of the window's first row and column.
    pixel_size : float
        p, in mm.

    Examples
    --------
    >>> g = GridMask(np.ones((2, 3), bool), row0=10, col0=-1, pixel_size=0.5)
    >>> g.xy([0, 1], [0, 2]).tolist(), g.area
    ([[-0.5, 5.0], [0.5, 5.5]], 1.5)
    """

    mask: np.ndarray
    row0: int
    col0: int
    pixel_size: float

    @property
    def shape(self) -> tuple[int, int]:
        return self.mask.shape

    @property
    def area(self) -> float:
        """Material area counted in pixels (mm^2)."""
        return float(np.count_nonzero(self.mask)) * self.pixel_size ** 2

    def at(self, rows, cols) -> np.ndarray:
        """The mask at world pixels (row, col); False outside the window."""
        r = np.asarray(rows, np.int64) - self.row0
        c = np.asarray(cols, np.int64) - self.col0
        h, w = self.shape
        inside = (r >= 0) & (r < h) & (c >= 0) & (c < w)
        out = np.zeros(r.shape, bool)
        out[inside] = self.mask[r[inside], c[inside]]
        return out

    def window(self, row0: int, col0: int, shape) -> np.ndarray:
        """This mask copied into another window of the same grid (False outside it).

        Examples
        --------
        >>> g = GridMask(np.ones((2, 2), bool), 0, 0, 1.0)
        >>> g.window(1, -1, (2, 2)).astype(int).tolist()
        [[0, 1], [0, 0]]
        """
        h, w = shape
        out = np.zeros((h, w), bool)
        r0, c0 = max(row0, self.row0), max(col0, self.col0)
        r1 = min(row0 + h, self.row0 + self.shape[0])
        c1 = min(col0 + w, self.col0 + self.shape[1])
        if r1 > r0 and c1 > c0:
            out[r0 - row0:r1 - row0, c0 - col0:c1 - col0] = \
                self.mask[r0 - self.row0:r1 - self.row0, c0 - self.col0:c1 - self.col0]
        return out

    def __and__(self, other) -> "GridMask":
        self._check(other)
        return GridMask(self.mask & other.window(self.row0, self.col0, self.shape), self.row0, self.col0,
                        self.pixel_size)

    def __sub__(self, other) -> "GridMask":
        """Pixels of self that are not in other (e.g. skin: a layer minus the layer above)."""
        self._check(other)
        return GridMask(self.mask & ~other.window(self.row0, self.col0, self.shape), self.row0, self.col0,
                        self.pixel_size)

    def __or__(self, other) -> "GridMask":
        self._check(other)
        r0, c0 = min(self.row0, other.row0), min(self.col0, other.col0)
        r1 = max(self.row0 + self.shape[0], other.row0 + other.shape[0])
        c1 = max(self.col0 + self.shape[1], other.col0 + other.shape[1])
        shape = (r1 - r0, c1 - c0)
        return GridMask(self.window(r0, c0, shape) | other.window(r0, c0, shape), r0, c0, self.pixel_size)

    @staticmethod
    def union(masks, pixel_size: float):
        """Union of several masks on one grid (an empty 1x1 mask for none)."""
        masks = list(masks)
        if not masks:
            return GridMask(np.zeros((1, 1), bool), 0, 0, pixel_size)
        out = masks[0]
        for m in masks[1:]:  # over tiles, few
            out = out | m
        return out


_OPS = {"and": 0, "sub": 1, "or": 2}  # operation codes of `slicelab.geometry.kernels.combine_blocks`


def _flat(bits: np.ndarray) -> np.ndarray:
    """A stack of block pixels as one flat uint8 array (0 or 1), without a copy when it can."""
    return np.ascontiguousarray(bits).view(np.uint8).reshape(-1)


@dataclass(frozen=True, eq=False)
class BlockMask(_Window):
    """A boolean mask on the world grid whose pixels are held only in the blocks of its boundary.

    Attributes
    ----------
    bits : (n, B, B) bool ndarray
        Pixels of the active blocks of `blocks`, in its stack order.
    blocks : BlockGrid
        Which blocks are active, empty or full.
    row0, col0 : int
        The window on the world grid (the material lies inside it).
    shape : (int, int)
    pixel_size : float

    Examples
    --------
    >>> from slicelab.geometry.blocks import BlockGrid
    >>> g = BlockGrid(2, 0, 0, np.array([[0, -2]]))
    >>> m = BlockMask(np.array([[[1, 0], [1, 1]]], bool), g, 0, 0, (2, 4), 1.0)
    >>> m.mask.astype(int).tolist(), m.area
    ([[1, 0, 1, 1], [1, 1, 1, 1]], 7.0)
    >>> (m - GridMask(np.ones((1, 1), bool), 0, 0, 1.0)).mask.astype(int).tolist()
    [[0, 0, 1, 1], [1, 1, 1, 1]]
    """

    bits: np.ndarray
    blocks: BlockGrid
    row0: int
    col0: int
    shape: tuple
    pixel_size: float

    @cached_property
    def mask(self) -> np.ndarray:
        """The whole window as one (h, w) bool array (made on first use)."""
        return self.window(self.row0, self.col0, self.shape)

    @property
    def area(self) -> float:
        """Material area counted in pixels (mm^2)."""
        return float(np.count_nonzero(self.bits) + self.blocks.n_full * self.blocks.size ** 2) \
            * self.pixel_size ** 2

    @property
    def pixels(self) -> int:
        """How many pixels the mask holds (its active blocks')."""
        return int(self.bits.size)

    def window(self, row0: int, col0: int, shape) -> np.ndarray:
        """This mask copied into a window of the same grid (False outside it)."""
        return self.blocks.assemble(self.bits, False, True, row0, col0, shape)

    def at(self, rows, cols) -> np.ndarray:
        """The mask at world pixels (row, col)."""
        return self.blocks.sample(self.bits, False, True, rows, cols)

    def to_grid(self) -> GridMask:
        """The same mask with every pixel of its window held."""
        return GridMask(self.mask, self.row0, self.col0, self.pixel_size)

    def _op(self, other, op: str):
        self._check(other)
        if not (isinstance(other, BlockMask) and other.blocks.size == self.blocks.size):
            if op == "or":
                return self.to_grid() | other
            return self.to_grid() & other if op == "and" else self.to_grid() - other
        a, b = self.blocks, other.blocks
        if op == "or":
            r0, c0 = min(a.row0, b.row0), min(a.col0, b.col0)
            r1 = max(a.row0 + a.table.shape[0], b.row0 + b.table.shape[0])
            c1 = max(a.col0 + a.table.shape[1], b.col0 + b.table.shape[1])
            row0, col0 = min(self.row0, other.row0), min(self.col0, other.col0)
            shape = (max(self.row0 + self.shape[0], other.row0 + other.shape[0]) - row0,
                     max(self.col0 + self.shape[1], other.col0 + other.shape[1]) - col0)
        else:
            r0, c0 = a.row0, a.col0
            r1, c1 = r0 + a.table.shape[0], c0 + a.table.shape[1]
            row0, col0, shape = self.row0, self.col0, self.shape
        from ...geometry.kernels import combine_blocks
        # One compiled pass over the result's blocks: uniform pairs stay uniform, a held block
        # beside a uniform one is copied (or complemented), two held blocks are combined.
        bb = a.size * a.size
        table, bits = combine_blocks(_OPS[op], bb, a.table, a.row0, a.col0, _flat(self.bits), b.table, b.row0,
                                     b.col0, _flat(other.bits), r0, c0, r1 - r0, c1 - c0)
        bits = bits.view(bool).reshape(-1, a.size, a.size)
        return BlockMask(bits, BlockGrid(a.size, r0, c0, table), row0, col0, tuple(shape), self.pixel_size)

    def __and__(self, other):
        return self._op(other, "and")

    def __sub__(self, other):
        """Pixels of self that are not in other."""
        return self._op(other, "sub")

    def __or__(self, other):
        return self._op(other, "or")

    def __repr__(self) -> str:
        return (f"BlockMask({len(self.blocks)} blocks of {self.blocks.size} px, {self.blocks.n_full} full, "
                f"window {self.shape[0]}x{self.shape[1]} at ({self.row0}, {self.col0}), p={self.pixel_size:g})")


def _stack(bits: np.ndarray, status: np.ndarray) -> np.ndarray:
    """The pixels of blocks given by status (stack index, EMPTY or FULL) as a stack."""
    n = len(bits)
    ext = np.zeros((n + 2,) + bits.shape[1:], bool)
    ext[:n] = bits
    ext[n + 1] = True
    return ext[np.where(status >= 0, status, np.where(status == EMPTY, n, n + 1))]


def bits_in_blocks(mask, brows, bcols, size: int) -> np.ndarray:
    """A mask's pixels in the given world blocks of `size` pixels, (m, size, size) bool.

    A block mask on blocks of the same size answers block by block; any other
    mask from its window.

    Examples
    --------
    >>> m = GridMask(np.ones((3, 3), bool), 1, 1, 1.0)
    >>> bits_in_blocks(m, [0], [0], 2)[0].astype(int).tolist()
    [[0, 0], [0, 1]]
    """
    brows, bcols = np.asarray(brows, np.int64), np.asarray(bcols, np.int64)
    if isinstance(mask, BlockMask) and mask.blocks.size == size:
        return _stack(mask.bits, mask.blocks.status(brows, bcols))
    if len(brows) == 0:
        return np.zeros((0, size, size), bool)
    r0, c0 = int(brows.min()), int(bcols.min())
    nr, nc = int(brows.max()) - r0 + 1, int(bcols.max()) - c0 + 1
    whole = mask.window(r0 * size, c0 * size, (nr * size, nc * size))
    return whole.reshape(nr, size, nc, size).transpose(0, 2, 1, 3)[brows - r0, bcols - c0]


def open_mask(mask, radius: int):
    """A mask opened by OpenCV's elliptic disc of `radius` pixels (parts thinner than it removed).

    A block mask is opened block by block: blocks near blocks of another kind
    are held (`BlockGrid.widen`), each with a halo of twice the radius, so its
    cost follows its boundary. Returns a mask of the same kind, or None when
    nothing is left.

    Examples
    --------
    >>> m = np.zeros((9, 12), bool); m[1:8, 1:6] = True; m[4, 6:11] = True   # a square with a spike
    >>> open_mask(GridMask(m, 0, 0, 1.0), 1).mask.sum(axis=0).tolist()
    [0, 5, 7, 7, 7, 5, 1, 0, 0, 0, 0, 0]
    """
    import cv2
    kernel = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (2 * radius + 1, 2 * radius + 1))
    if not isinstance(mask, BlockMask):
        opened = cv2.morphologyEx(mask.mask.astype(np.uint8), cv2.MORPH_OPEN, kernel).astype(bool)
        return GridMask(opened, mask.row0, mask.col0, mask.pixel_size) if opened.any() else None
    b = mask.blocks.size
    halo = 2 * radius
    if not mask.blocks.n_full:
        # No full block (a sloped wall's edge, slivers): the mask, and so its opening, lies in the
        # active blocks, which are opened alone, with no neighbour held. With a halo of twice the
        # radius, the erosion is right within a radius of each block and the dilation on the block.
        g = mask.blocks
        eroded = cv2.erode(g.mosaic(mask.bits.view(np.uint8), halo, np.uint8(0), np.uint8(1)), kernel)
        if not g.cores(eroded, halo).any():  # slivers only: nothing survives the erosion
            return None
        opened = _as_blocks(g, g.cores(cv2.dilate(eroded, kernel), halo), mask.row0, mask.col0, mask.shape,
                            mask.pixel_size)
        return opened if len(opened.blocks) or opened.blocks.n_full else None
    grid, bits = mask.blocks.widen(mask.bits, False, True, -(-halo // b))
    image = grid.mosaic(bits.view(np.uint8), halo, np.uint8(0), np.uint8(1))
    eroded = cv2.erode(image, kernel)
    opened = _as_blocks(grid, grid.cores(cv2.dilate(eroded, kernel), halo), mask.row0, mask.col0, mask.shape,
                        mask.pixel_size)
    return opened if len(opened.blocks) or opened.blocks.n_full else None


def _as_blocks(grid, values: np.ndarray, row0: int, col0: int, shape, pixel_size: float) -> BlockMask:
    """A block mask of new values (n, B, B) of `grid`'s active blocks: those now uniform made so."""
    flat = values.reshape(len(values), -1) if len(values) else values.reshape(0, 1)
    some, every = flat.any(axis=1), flat.all(axis=1)
    keep = some & ~every
    table = grid.table.copy()
    on = table >= 0
    table[on] = np.where(keep, 0, np.where(every, FULL, EMPTY))
    out = BlockGrid.from_status(grid.size, grid.row0, grid.col0, table == 0, table == FULL)
    return BlockMask(values[keep].view(bool), out, row0, col0, shape, pixel_size)


@functools.lru_cache(maxsize=16)
def reach_disc(reach: float, pixel_size: float, slack: float = 0.0) -> np.ndarray:
    """The structuring element (uint8) of the pixel offsets a distance transform puts within
    `reach` mm: those whose distance d (pixels, centre to centre, float32 as OpenCV's precise
    transform gives it) has ``d * pixel_size - slack`` not above `reach`, computed as the
    planner computes it from the transform. A mask dilated by it holds exactly the pixels whose
    transform to the mask would not exceed the reach.

    Examples
    --------
    >>> [row[1:6] for row in reach_disc(0.4, 0.2).tolist()[1:6]]   # two pixels: (0, 2) is in, (1, 2) is not
    [[0, 0, 1, 0, 0], [0, 1, 1, 1, 0], [1, 1, 1, 1, 1], [0, 1, 1, 1, 0], [0, 0, 1, 0, 0]]
    """
    k = int(np.ceil((reach + slack) / pixel_size)) + 1
    dy, dx = np.mgrid[-k:k + 1, -k:k + 1]
    d = np.sqrt((dy * dy + dx * dx).astype(np.float32))
    return (~(d * pixel_size - slack > reach)).astype(np.uint8)


def dilate_mask(mask, kernel: np.ndarray):
    """A mask dilated by a structuring element (an odd square uint8 array, centred).

    A block mask is dilated block by block, as `open_mask` opens it: the
    blocks within the kernel's reach of a block of another kind are held,
    each with a halo of the kernel's radius, so its cost follows its
    boundary. The window grows by that radius on each side. Returns a mask
    of the same kind.

    Examples
    --------
    >>> m = np.zeros((5, 5), bool); m[2, 2] = True
    >>> cross = np.array([[0, 1, 0], [1, 1, 1], [0, 1, 0]], np.uint8)
    >>> g = dilate_mask(GridMask(m, 0, 0, 1.0), cross)
    >>> (g.row0, g.shape, int(g.mask.sum()))
    (-1, (7, 7), 5)
    """
    import cv2
    r = kernel.shape[0] // 2
    h, w = mask.shape
    if not isinstance(mask, BlockMask):
        grown = cv2.dilate(np.pad(mask.mask, r).view(np.uint8), kernel).view(bool)
        return GridMask(grown, mask.row0 - r, mask.col0 - r, mask.pixel_size)
    b = mask.blocks.size
    grid, bits = mask.blocks.widen(mask.bits, False, True, -(-r // b))
    image = grid.mosaic(bits.view(np.uint8), r, np.uint8(0), np.uint8(1))
    return _as_blocks(grid, grid.cores(cv2.dilate(image, kernel), r), mask.row0 - r, mask.col0 - r,
                      (h + 2 * r, w + 2 * r), mask.pixel_size)


def erode_mask(mask, kernel: np.ndarray):
    """A mask eroded by a structuring element (an odd square uint8 array, centred), in its window.

    A block mask is eroded block by block, as `dilate_mask` dilates it: the
    blocks within the kernel's reach of a block of another kind are held, so
    its cost follows its boundary. Returns a mask of the same kind.

    Examples
    --------
    >>> m = np.zeros((5, 5), bool); m[1:4, 1:4] = True
    >>> cross = np.array([[0, 1, 0], [1, 1, 1], [0, 1, 0]], np.uint8)
    >>> e = erode_mask(GridMask(m, 0, 0, 1.0), cross)
    >>> (e.row0, e.shape, np.argwhere(e.mask).tolist())
    (0, (5, 5), [[2, 2]])
    """
    import cv2
    r = kernel.shape[0] // 2
    h, w = mask.shape
    if not isinstance(mask, BlockMask):
        eroded = cv2.erode(np.pad(mask.mask, r).view(np.uint8), kernel)[r:r + h, r:r + w].view(bool)
        return GridMask(eroded, mask.row0, mask.col0, mask.pixel_size)
    b = mask.blocks.size
    grid, bits = mask.blocks.widen(mask.bits, False, True, -(-r // b))
    image = grid.mosaic(bits.view(np.uint8), r, np.uint8(0), np.uint8(1))
    return _as_blocks(grid, grid.cores(cv2.erode(image, kernel), r), mask.row0, mask.col0, mask.shape,
                      mask.pixel_size)


def near_mask(mask: BlockMask, brows, bcols, kernel: np.ndarray) -> np.ndarray:
    """The pixels of some blocks within a structuring element of a block mask's material.

    `mask` dilated by `kernel` (an odd square uint8 array, centred), read only on
    the world blocks (`brows`, `bcols`) of its block size: each is laid out with
    a halo of the kernel's radius read from `mask`'s blocks, uniform ones
    included, and dilated there. The cost follows those blocks, not `mask`.

    Returns
    -------
    (n, B, B) bool ndarray

    Examples
    --------
    >>> from slicelab.geometry.blocks import BlockGrid
    >>> g = BlockGrid(2, 0, 0, np.array([[0, -1]]))
    >>> m = BlockMask(np.array([[[0, 1], [0, 0]]], bool), g, 0, 0, (2, 4), 1.0)
    >>> near_mask(m, [0], [1], np.ones((3, 3), np.uint8)).astype(int).tolist()   # the block to its right
    [[[1, 0], [1, 0]]]
    """
    import cv2
    g = mask.blocks
    r = kernel.shape[0] // 2
    at = (np.asarray(brows, np.int64), np.asarray(bcols, np.int64))
    if len(at[0]) == 0:
        return np.zeros((0, g.size, g.size), bool)
    image = g.mosaic(mask.bits.view(np.uint8), r, np.uint8(0), np.uint8(1), at=at)
    return g.cores(cv2.dilate(image, kernel), r, n=len(at[0])).view(bool)


def pixels_in_boxes(mask, boxes) -> np.ndarray:
    """How many pixels of a mask lie in each of some boxes that share none (world pixels).

    Parameters
    ----------
    mask : GridMask or BlockMask
    boxes : (G, 4) int array_like
        First row, first column, last row and last column of each box (inclusive); no two
        boxes meet, and the mask's pixels all lie in one of them (a layer's islands, each
        in the box of its loops).

    Returns
    -------
    (G,) int64 ndarray

    A block mask is counted block by block: a block that meets one box gives it all its
    pixels; only a block that meets several (islands closer than a block) is split.

    Examples
    --------
    >>> m = np.zeros((10, 40), bool); m[2:5, 3:8] = True; m[6:9, 30:33] = True
    >>> boxes = [[0, 0, 9, 10], [0, 20, 9, 39]]
    >>> pixels_in_boxes(GridMask(m, 0, 0, 0.1), boxes).tolist()
    [15, 9]
    >>> held = BlockMask(m.reshape(10, 4, 10).transpose(1, 0, 2), BlockGrid(10, 0, 0, np.arange(4).reshape(1, 4)),
    ...                  0, 0, (10, 40), 0.1)     # four blocks of 10 x 10 pixels
    >>> pixels_in_boxes(held, boxes).tolist()
    [15, 9]
    """
    boxes = np.asarray(boxes, np.int64).reshape(-1, 4)
    out = np.zeros(len(boxes), np.int64)
    if not isinstance(mask, BlockMask):
        m = mask.mask
        for g, (r0, c0, r1, c1) in enumerate(boxes.tolist()):  # over boxes, few
            a, b_ = max(r0 - mask.row0, 0), min(r1 + 1 - mask.row0, m.shape[0])
            c, d = max(c0 - mask.col0, 0), min(c1 + 1 - mask.col0, m.shape[1])
            if a < b_ and c < d:
                out[g] = np.count_nonzero(m[a:b_, c:d])
        return out
    grid = mask.blocks
    b = grid.size
    fr, fc = np.nonzero(grid.table == FULL)
    rows = np.concatenate([grid.rows, fr + grid.row0]) * b  # first pixel of each held, then full block
    cols = np.concatenate([grid.cols, fc + grid.col0]) * b
    n = len(grid)
    r0, c0, r1, c1 = (boxes[:, i][None, :] for i in range(4))
    lo_r, hi_r = np.maximum(rows[:, None], r0), np.minimum(rows[:, None] + b - 1, r1)
    lo_c, hi_c = np.maximum(cols[:, None], c0), np.minimum(cols[:, None] + b - 1, c1)
    meets = (lo_r <= hi_r) & (lo_c <= hi_c)
    # Full blocks: every pixel is material, in the box that holds it.
    out += np.sum(np.where(meets[n:], (hi_r - lo_r + 1)[n:] * (hi_c - lo_c + 1)[n:], 0), axis=0)
    held = meets[:n]
    count = held.sum(axis=1)
    one = np.flatnonzero(count == 1)
    if len(one):
        per = np.count_nonzero(mask.bits[one].reshape(len(one), -1), axis=1)
        np.add.at(out, np.argmax(held[one], axis=1), per)
    for k in np.flatnonzero(count > 1):  # blocks between close islands, rare
        for g in np.flatnonzero(held[k]):
            out[g] += np.count_nonzero(mask.bits[k, lo_r[k, g] - rows[k]:hi_r[k, g] - rows[k] + 1,
                                                 lo_c[k, g] - cols[k]:hi_c[k, g] - cols[k] + 1])
    return out
