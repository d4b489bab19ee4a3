"""Square blocks of a world-anchored pixel grid: pixels held only where they matter.

A pixel grid anchored to the world is cut into blocks of ``size x size``
pixels: block (i, j) holds pixel rows ``i size .. i size + size - 1`` and the
same columns. A `BlockGrid` keeps pixels only for its *active* blocks,
stacked as an ``(n, size, size)`` array in row-major order of the blocks;
every other block is uniform, `EMPTY` or `FULL`, as its table says. Work on a
layer then follows its active blocks (a band along the boundary), not the
area of its bounding box.

`BlockGrid.pack` surrounds every active block with a halo copied from its
neighbours (or their uniform value). Reshaped to one tall image, the stack
goes through OpenCV in one call, and a filter that reads at most `halo`
pixels away gives on each block's own pixels what it gives on the whole grid.

See Also
--------
slicelab.printing.grid.masks.BlockMask : a layer's material held by blocks.
slicelab.geometry.contours.march_blocks : marching squares over the stack, chained across blocks.
"""
from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np

__all__ = ["EMPTY", "FULL", "BlockGrid", "blocks_near"]

EMPTY = -1
FULL = -2


def blocks_near(segments: np.ndarray, pixel_size: float, size: int, reach: int, rows: tuple[int, int],
                cols: tuple[int, int]) -> np.ndarray:
    """Which blocks of a range hold a pixel within `reach` pixels of a segment (a bool table).

    Segments are cut into pieces no longer than a block; each piece marks the
    blocks its pixel box, widened by `reach`, overlaps.

    Parameters
    ----------
    segments : (m, 2, 2) ndarray
        In mm.
    pixel_size : float
    size : int
        Block size (pixels).
    reach : int
        Pixels.
    rows, cols : (int, int)
        First and last block row (column) of the range, inclusive.

    Returns
    -------
    (nr, nc) bool ndarray

    Examples
    --------
    >>> seg = np.array([[[0.0, 0.0], [10.0, 0.0]]])
    >>> blocks_near(seg, 1.0, 4, 1, (-1, 1), (0, 3)).astype(int).tolist()
    [[1, 1, 1, 0], [1, 1, 1, 0], [0, 0, 0, 0]]
    """
    from .segment_kernels import mark_blocks_near
    nr, nc = rows[1] - rows[0] + 1, cols[1] - cols[0] + 1
    table = np.zeros((nr, nc), bool)
    if len(segments) == 0:
        return table
    # One compiled pass over the segments and their pieces: as array operations, some twenty
    # numpy calls a tile cost more than the marking itself.
    mark_blocks_near(np.ascontiguousarray(segments, np.float64).reshape(-1, 2, 2), float(pixel_size), int(size),
                     int(reach), int(rows[0]), int(cols[0]), table)
    return table


def _padded(table: np.ndarray, reach: int) -> np.ndarray:
    """A block table with `reach` rings of empty blocks around it (`np.pad`'s result, without
    its per-call cost: the grids of every layer are padded several times)."""
    h, w = table.shape
    out = np.full((h + 2 * reach, w + 2 * reach), EMPTY, table.dtype)
    out[reach:reach + h, reach:reach + w] = table
    return out


#: Row and column offsets of a block's eight neighbours and itself, (3, 3) each.
_DR, _DC = np.mgrid[-1:2, -1:2]


@dataclass(frozen=True, eq=False)
class BlockGrid:
    """Active blocks of a world-anchored pixel grid, and the uniform value of the others.

    Attributes
    ----------
    size : int
        Block size B (pixels).
    row0, col0 : int
        World block indices of ``table[0, 0]``.
    table : (nr, nc) int64 ndarray
        Index of the block in the stack, or `EMPTY` / `FULL`. Blocks outside
        the table are empty.

    Examples
    --------
    >>> t = np.array([[EMPTY, 0, FULL], [1, 2, EMPTY]])
    >>> g = BlockGrid(2, 5, -1, t)
    >>> len(g), g.rows.tolist(), g.cols.tolist(), g.origins()[0].tolist()
    (3, [5, 6, 6], [0, -1, 0], [10, 12, 12])
    >>> data = np.arange(12).reshape(3, 2, 2)
    >>> g.pack(data, 1, -1, 9)[0].tolist()
    [[-1, -1, -1, -1], [-1, 0, 1, 9], [-1, 2, 3, 9], [5, 8, 9, -1]]
    """

    size: int
    row0: int
    col0: int
    table: np.ndarray

    @classmethod
    def from_status(cls, size: int, row0: int, col0: int, active: np.ndarray, full: np.ndarray) -> BlockGrid:
        """A grid from a table of active blocks and one of full blocks (the rest empty)."""
        table = np.where(full, FULL, EMPTY).astype(np.int64)
        table[active] = np.arange(int(np.count_nonzero(active)))
        return cls(int(size), int(row0), int(col0), table)

    def __len__(self) -> int:
        return len(self.rows)

    @cached_property
    def _active(self) -> tuple[np.ndarray, np.ndarray]:
        r, c = np.nonzero(self.table >= 0)  # row-major: the stack's order
        return r + self.row0, c + self.col0

    @property
    def rows(self) -> np.ndarray:
        """World block row of each active block."""
        return self._active[0]

    @property
    def cols(self) -> np.ndarray:
        """World block column of each active block."""
        return self._active[1]

    @property
    def n_full(self) -> int:
        """How many blocks are full."""
        return int(np.count_nonzero(self.table == FULL))

    def widen(self, data: np.ndarray, empty, full, reach: int = 1) -> tuple[BlockGrid, np.ndarray]:
        """The grid with every uniform block that has a block of another kind within `reach` blocks
        made active (holding its uniform value), and the stack to match.

        Filters that read up to ``reach * B`` pixels away, and contours along
        the edge of a uniform block, then see only active blocks change.

        Examples
        --------
        >>> g = BlockGrid(1, 0, 0, np.array([[FULL, EMPTY]]))
        >>> h, data = g.widen(np.zeros((0, 1, 1), bool), False, True)
        >>> h.table.tolist(), data[:, 0, 0].astype(int).tolist()
        ([[0, 1, 2, -1], [3, 4, 5, -1], [6, 7, 8, -1]], [0, 0, 0, 0, 1, 0, 0, 0, 0])
        """
        import cv2
        t = _padded(self.table, reach)
        kind = np.where(t >= 0, 2, np.where(t == FULL, 1, 0)).astype(np.uint8)
        box = np.ones((2 * reach + 1, 2 * reach + 1), np.uint8)
        hi = cv2.dilate(kind, box, borderType=cv2.BORDER_REPLICATE)
        lo = cv2.erode(kind, box, borderType=cv2.BORDER_REPLICATE)
        return self._activated(data, empty, full, reach, t, kind, (kind == 2) | (hi != kind) | (lo != kind))

    def seamed(self, data: np.ndarray, empty, full) -> tuple[BlockGrid, np.ndarray]:
        """The grid with every full block beside an empty one (or at a corner with it) made active,
        and the stack to match: every cell that a contour between the empty and the full value
        crosses then has a corner in an active block, as `slicelab.geometry.contours.march_blocks`
        needs (a few blocks, where `widen` would make every neighbour of an active block active too).

        Examples
        --------
        The full block is held (outside the table is empty), beside the active block; the empty
        blocks are not (`widen` would hold them, and the active block's neighbours):

        >>> g = BlockGrid(1, 0, 0, np.array([[FULL, EMPTY, EMPTY, 0]]))
        >>> h, data = g.seamed(np.zeros((1, 1, 1), bool), False, True)
        >>> h.table.tolist(), data[:, 0, 0].tolist()
        ([[-1, -1, -1, -1, -1, -1], [-1, 0, -1, -1, 1, -1], [-1, -1, -1, -1, -1, -1]], [True, False])
        """
        import cv2
        t = _padded(self.table, 1)
        kind = np.where(t >= 0, 2, np.where(t == FULL, 1, 0)).astype(np.uint8)
        near_empty = cv2.dilate((kind == 0).view(np.uint8), np.ones((3, 3), np.uint8),
                                borderType=cv2.BORDER_REPLICATE).view(bool)
        return self._activated(data, empty, full, 1, t, kind, (kind == 2) | ((kind == 1) & near_empty))

    def _activated(self, data, empty, full, reach: int, t, kind, active) -> tuple[BlockGrid, np.ndarray]:
        """The grid of the table `t` (this grid's, padded by `reach` blocks) with the blocks `active`
        held, and their stack (uniform blocks made active hold their value)."""
        grid = BlockGrid.from_status(self.size, self.row0 - reach, self.col0 - reach, active, (kind == 1) & ~active)
        n = len(self)
        ext = np.empty((n + 2,) + data.shape[1:], data.dtype)
        ext[:n] = data
        ext[n], ext[n + 1] = empty, full
        src = t[active]
        return grid, ext[np.where(src >= 0, src, np.where(src == FULL, n + 1, n))]

    def origins(self) -> tuple[np.ndarray, np.ndarray]:
        """World pixel row and column of each active block's first pixel."""
        return self.rows * self.size, self.cols * self.size

    def status(self, brow, bcol) -> np.ndarray:
        """Stack index, `EMPTY` or `FULL` of world blocks (empty outside the table)."""
        i = np.asarray(brow, np.int64) - self.row0
        j = np.asarray(bcol, np.int64) - self.col0
        nr, nc = self.table.shape
        ok = (i >= 0) & (i < nr) & (j >= 0) & (j < nc)
        out = np.full(np.shape(i), EMPTY, np.int64)
        out[ok] = self.table[i[ok], j[ok]]
        return out

    def locate(self, rows, cols) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Block (stack index, `EMPTY` or `FULL`) and position in it of world pixels."""
        rows, cols = np.asarray(rows, np.int64), np.asarray(cols, np.int64)
        b = self.size
        return self.status(rows // b, cols // b), rows % b, cols % b

    def sample(self, data: np.ndarray, empty, full, rows, cols) -> np.ndarray:
        """Values of world pixels: from the stack, or the uniform value of their block.

        Examples
        --------
        >>> g = BlockGrid(2, 0, 0, np.array([[0, FULL]]))
        >>> g.sample(np.array([[[1, 2], [3, 4]]]), 0, 9, [1, 0, 5], [0, 3, 0]).tolist()
        [3, 9, 0]
        """
        from .kernels import sample_blocks
        rows, cols = np.asarray(rows, np.int64), np.asarray(cols, np.int64)
        if rows.shape == cols.shape:  # (most calls: no broadcasting to do)
            shape = rows.shape
            rows, cols = np.ascontiguousarray(rows).reshape(-1), np.ascontiguousarray(cols).reshape(-1)
        else:
            shape = np.broadcast_shapes(rows.shape, cols.shape)
            rows, cols = (np.ascontiguousarray(np.broadcast_to(a, shape)).reshape(-1) for a in (rows, cols))
        dtype = data.dtype.type
        out = sample_blocks(self.table, self.row0, self.col0, self.size, np.ascontiguousarray(data), dtype(empty),
                            dtype(full), rows, cols)
        return out.reshape(shape)

    def neighbour(self, dr: int, dc: int) -> np.ndarray:
        """Stack index of each active block's neighbour (dr, dc) blocks away; n if empty, n + 1 if full."""
        n = len(self)
        k = self.status(self.rows + dr, self.cols + dc)
        return np.where(k >= 0, k, np.where(k == FULL, n + 1, n))

    @cached_property
    def neighbours(self) -> np.ndarray:
        """(3, 3, n) stack index of each active block's eight neighbours and itself (see `neighbour`).

        Examples
        --------
        >>> g = BlockGrid(1, 0, 0, np.array([[0, FULL], [EMPTY, 1]]))
        >>> g.neighbours[:, :, 0].tolist()   # n = 2 (empty), 3 (full)
        [[2, 2, 2], [2, 0, 3], [2, 2, 1]]
        """
        n = len(self)
        # The table padded with an empty ring, as stack indices (n empty, n + 1 full): each
        # neighbour is then one gather.
        t = _padded(self.table, 1)
        t = np.where(t >= 0, t, np.where(t == FULL, n + 1, n))
        r, c = self.rows - self.row0 + 1, self.cols - self.col0 + 1
        return t[r[None, None, :] + _DR[..., None], c[None, None, :] + _DC[..., None]]

    def pack(self, data: np.ndarray, halo: int, empty, full) -> np.ndarray:
        """The stack with a halo of `halo` pixels copied from each block's neighbours.

        Parameters
        ----------
        data : (n, B, B) ndarray
        halo : int
        empty, full
            Values of the pixels of empty and full blocks.

        Returns
        -------
        (n, B + 2 halo, B + 2 halo) ndarray

        See Also
        --------
        mosaic : the same blocks side by side in one image.
        """
        q = self.size + 2 * int(halo)
        out = np.empty((len(self), q, 1, q), data.dtype)
        self._fill(out, data, int(halo), empty, full, self.rows, self.cols)
        return out.reshape(len(self), q, q)

    def mosaic(self, data: np.ndarray, halo: int, empty, full, *, gap: int = 0, at=None) -> np.ndarray:
        """The blocks with their halos (`pack`) side by side in one wide image, rows of blocks.

        OpenCV's filters run several times faster on a wide image than on a
        tall column of small blocks. `gap` rows and columns of zeros part the
        blocks; slots past the last block are zeros. `cores` takes the blocks'
        own pixels back. `at` (world block rows, cols) lays out those blocks
        instead of the active ones, their pixels and halos read from this grid
        all the same (another mask's blocks, say).

        Returns
        -------
        (R (B + 2 halo + gap), m (B + 2 halo + gap)) ndarray
        """
        h = int(halo)
        q = self.size + 2 * h + gap
        rows, cols = (self.rows, self.cols) if at is None else \
            (np.asarray(at[0], np.int64), np.asarray(at[1], np.int64))
        m, n_rows = self._layout(q, len(rows))
        img = np.zeros((n_rows, q, m, q), data.dtype)
        self._fill(img, data, h, empty, full, rows, cols)
        return img.reshape(n_rows * q, m * q)

    def cores(self, image: np.ndarray, halo: int, *, gap: int = 0, n: int | None = None) -> np.ndarray:
        """The blocks' own pixels, (n, B, B), from an image laid out by `mosaic` (of `n` blocks when
        laid out `at` others)."""
        b, h = self.size, int(halo)
        q = b + 2 * h + gap
        n = len(self) if n is None else int(n)
        m, rows = self._layout(q, n)
        v = image.reshape(rows, q, m, q)[:, h:h + b, :, h:h + b].transpose(0, 2, 1, 3)
        return v.reshape(rows * m, b, b)[:n]

    @staticmethod
    def _layout(q: int, n: int) -> tuple[int, int]:
        """Blocks per row of a mosaic of n cells q pixels wide (about 2000 pixels), and its rows."""
        m = max(1, min(n, 2048 // q))
        return m, max(1, -(-n // m))

    def _fill(self, out: np.ndarray, data: np.ndarray, h: int, empty, full, rows, cols) -> None:
        """Write block k (world block rows[k], cols[k]) and its halo into ``out[k // m, :, k % m, :]``
        of a (rows, q, m, q) canvas."""
        from .kernels import fill_blocks
        if h < 0:
            raise ValueError(f"a halo must be >= 0 pixels, got {h}")
        if len(rows) == 0:
            return
        data = np.ascontiguousarray(data)
        # One compiled loop over the blocks and the neighbours their halos reach.
        fill_blocks(out, data, h, data.dtype.type(empty), data.dtype.type(full), self.table, self.row0, self.col0,
                    rows, cols)

    def assemble(self, data: np.ndarray, empty, full, row0: int, col0: int, shape) -> np.ndarray:
        """The values of a window of world pixels as one array (`sample` over the window)."""
        h, w = shape
        b = self.size
        out = np.full((h, w), empty, data.dtype)
        nr, nc = self.table.shape
        i0, j0 = max(row0 // b - self.row0, 0), max(col0 // b - self.col0, 0)
        i1, j1 = min((row0 + h - 1) // b - self.row0 + 1, nr), min((col0 + w - 1) // b - self.col0 + 1, nc)
        if i1 <= i0 or j1 <= j0:
            return out
        t = self.table[i0:i1, j0:j1]
        big = np.full(t.shape + (b, b), empty, data.dtype)
        big[t == FULL] = full
        big[t >= 0] = data[t[t >= 0]]
        big = big.transpose(0, 2, 1, 3).reshape(t.shape[0] * b, t.shape[1] * b)
        r0, c0 = (self.row0 + i0) * b, (self.col0 + j0) * b  # world pixel of big[0, 0]
        ra, rb = max(row0, r0), min(row0 + h, r0 + big.shape[0])
        ca, cb = max(col0, c0), min(col0 + w, c0 + big.shape[1])
        if rb > ra and cb > ca:
            out[ra - row0:rb - row0, ca - col0:cb - col0] = big[ra - r0:rb - r0, ca - c0:cb - c0]
        return out

    def components(self, bits: np.ndarray) -> tuple[np.ndarray, int]:
        """8-connected components of the set pixels of the active blocks, across their seams.

        Full blocks do not join components: two parts of the active blocks that
        meet only through a full block keep their own labels.

        Returns
        -------
        labels : (n, B, B) int ndarray
            0 for unset pixels, else 1 .. count.
        count : int

        Examples
        --------
        >>> g = BlockGrid(2, 0, 0, np.array([[0, 1]]))
        >>> bits = np.array([[[0, 1], [0, 0]], [[1, 0], [0, 1]]], bool)
        >>> labels, count = g.components(bits)
        >>> count, labels[:, 0].tolist()
        (1, [[0, 1], [1, 0]])
        """
        import cv2

        from .graphs import graph_components
        n, b = len(self), self.size
        if n == 0:
            return np.zeros((0, b, b), np.int32), 0
        # An empty row and column part the blocks.
        img = self.mosaic(bits.view(np.uint8), 0, np.uint8(0), np.uint8(0), gap=1)
        count, lab = cv2.connectedComponents(img, connectivity=8, ltype=cv2.CV_32S)
        lab = self.cores(lab, 0, gap=1)
        if count <= 1:
            return lab, 0
        nb = self.neighbours
        pairs = []
        # Each seam once: the right, lower, lower-right and lower-left neighbours. A pixel joins the
        # pixel facing it across the seam, or one diagonally beside that when that one is unset
        # (otherwise the two are already one part of the other block).
        for dr, dc in ((0, 1), (1, 0), (1, 1), (1, -1)):
            k = nb[dr + 1, dc + 1]
            a = np.flatnonzero(k < n)
            if len(a) == 0:
                continue
            if dr == 0:
                la, lb = lab[a, :, b - 1], lab[k[a], :, 0]
            elif dc == 0:
                la, lb = lab[a, b - 1, :], lab[k[a], 0, :]
            else:
                c = b - 1 if dc == 1 else 0
                la, lb = lab[a, b - 1, c], lab[k[a], 0, b - 1 - c]
            pairs.append(np.stack([la, lb]).reshape(2, -1))
            if dr == 0 or dc == 0:
                for d in (-1, 1):  # the diagonal pixels across the seam
                    side = np.zeros_like(lb)
                    if d < 0:
                        side[:, 1:] = lb[:, :-1]
                    else:
                        side[:, :-1] = lb[:, 1:]
                    pairs.append(np.stack([np.where(lb == 0, la, 0), side]).reshape(2, -1))
        e = np.concatenate(pairs, axis=1).astype(np.int64) if pairs else np.zeros((2, 0), np.int64)
        e = e[:, (e[0] > 0) & (e[1] > 0)]
        e = np.sort(e[0] * count + e[1])  # each pair of labels once (sorted, as np.unique gives them)
        e = e[np.r_[True, e[1:] != e[:-1]]] if len(e) else e
        e = np.stack([e // count, e % count])
        k, glob = graph_components(count, e[0], e[1])
        # Label 0 (background) is a component of its own: renumber so that it stays 0.
        order = np.full(k, -1, np.int64)
        order[glob[0]] = 0
        rest = np.arange(k)
        rest = rest[rest != glob[0]]
        order[rest] = np.arange(1, len(rest) + 1)
        return order[glob].astype(np.int32 if k < 2 ** 31 else np.int64)[lab], len(rest)
