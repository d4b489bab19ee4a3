"""Compiled loops over pixels and blocks: halos, block lookups, set operations and winding numbers.

A layer's toolpaths take a few dozen passes over the pixels held along its
boundary. Written with numpy, each pass is several array calls whose fixed
cost (tens of microseconds each) adds up to most of a layer's time; these
loops do each pass in one compiled call instead (numba, compiled on first use
and cached on disk beside this file). Each kernel is a plain loop over its
input, linear in it; the modules that call them (`slicelab.geometry.blocks`,
`slicelab.printing.grid.masks`,
`slicelab.printing.grid.raster`) keep the interfaces and say what the results mean.

See Also
--------
slicelab.geometry.march_kernels : marching squares over the blocks, and chaining.
slicelab.geometry.blocks.BlockGrid.mosaic : the blocks and halos `fill_blocks` copies.
slicelab.geometry.segment_kernels : the compiled loops over segments and points.

References
----------
.. [1] S. K. Lam, A. Pitrou, S. Seibert, "Numba: a LLVM-based Python JIT
   compiler", LLVM-HPC 2015.
"""
from __future__ import annotations

import numpy as np

from .compiled import njit

__all__ = ["fill_blocks", "sample_blocks", "combine_blocks", "winding_rows", "warm"]

# Block table values of uniform blocks (`slicelab.geometry.blocks`: EMPTY, FULL).
_EMPTY = -1
_FULL = -2


@njit(cache=True, nogil=True)
def _span(h, d, b, q):
    """Rows (or columns) of a block's q-pixel window that its neighbour d blocks away fills."""
    return max(h + d * b, 0), min(h + (d + 1) * b, q)


@njit(cache=True, nogil=True)
def fill_blocks(out, data, h, empty, full, table, brow0, bcol0, rows, cols):
    """Write each active block with a halo of `h` pixels of its neighbours into a (R, q, m, q) canvas.

    Block k goes to ``out[k // m, :, k % m, :]`` (q = B + 2 h); a halo pixel
    takes its neighbour's value, or `empty` / `full` for uniform blocks and
    blocks outside `table` (empty). `table` holds stack indices or -1 / -2, its
    ``[0, 0]`` at world block (brow0, bcol0); `rows`, `cols` are the world block
    indices of the blocks to write: the table's active blocks (stack order), or
    any others, whose pixels then come from the table too.
    """
    n, b = rows.shape[0], data.shape[1]
    q = b + 2 * h
    m = out.shape[2]
    nr, nc = table.shape
    reach = (h + b - 1) // b
    for k in range(n):
        ro, mo = k // m, k % m
        for dr in range(-reach, reach + 1):
            i_lo, i_hi = _span(h, dr, b, q)
            if i_hi <= i_lo:
                continue
            tr = rows[k] + dr - brow0
            for dc in range(-reach, reach + 1):
                j_lo, j_hi = _span(h, dc, b, q)
                if j_hi <= j_lo:
                    continue
                tc = cols[k] + dc - bcol0
                src = _EMPTY
                if 0 <= tr < nr and 0 <= tc < nc:
                    src = table[tr, tc]
                if src >= 0:
                    for i in range(i_lo, i_hi):
                        si = i - h - dr * b
                        for j in range(j_lo, j_hi):
                            out[ro, i, mo, j] = data[src, si, j - h - dc * b]
                else:
                    v = full if src == _FULL else empty
                    for i in range(i_lo, i_hi):
                        for j in range(j_lo, j_hi):
                            out[ro, i, mo, j] = v


@njit(cache=True, nogil=True)
def _block_at(table, brow0, bcol0, i, j):
    """Stack index, or -1 / -2 (empty / full), of world block (i, j) of a table (empty outside it)."""
    ti, tj = i - brow0, j - bcol0
    if 0 <= ti < table.shape[0] and 0 <= tj < table.shape[1]:
        return table[ti, tj]
    return _EMPTY


@njit(cache=True, nogil=True)
def sample_blocks(table, brow0, bcol0, b, data, empty, full, rows, cols):
    """Values at world pixels (rows, cols): from the held blocks' `data`, or the uniform value of
    their block (`empty` outside the table)."""
    out = np.empty(len(rows), data.dtype)
    for i in range(len(rows)):
        br, bc = rows[i] // b, cols[i] // b
        k = _block_at(table, brow0, bcol0, br, bc)
        if k >= 0:
            out[i] = data[k, rows[i] - br * b, cols[i] - bc * b]
        else:
            out[i] = full if k == _FULL else empty
    return out


@njit(cache=True, nogil=True)
def _combine_words(op, wa, wb, wo, sa, sb, nw, ow):
    """`combine_blocks` for one block whose pixels are bytes 0 or 1, read eight to a 64-bit word:
    the result into words ``ow .. ow + nw - 1`` of `wo`; returns its count of pixels set.

    The bytes' sum of a word is the top byte of the word times 0x0101010101010101 (each byte is
    at most 1, so no byte of the running sums carries).
    """
    ones = np.uint64(0x0101010101010101)
    total = 0
    if sa >= 0 and sb >= 0:
        x, y = sa * nw, sb * nw
        for u in range(nw):
            if op == 0:
                v = wa[x + u] & wb[y + u]
            elif op == 1:
                v = wa[x + u] & (wb[y + u] ^ ones)
            else:
                v = wa[x + u] | wb[y + u]
            wo[ow + u] = v
            total += np.int64((v * ones) >> np.uint64(56))
    else:
        # One side held, the other uniform: the held pixels, or (full minus held) their complement.
        if sa >= 0:
            src, x, flip = wa, sa * nw, np.uint64(0)
        else:
            src, x, flip = wb, sb * nw, ones if op == 1 else np.uint64(0)
        for u in range(nw):
            v = src[x + u] ^ flip
            wo[ow + u] = v
            total += np.int64((v * ones) >> np.uint64(56))
    return total


@njit(cache=True, nogil=True)
def combine_blocks(op, bb, ta, ra, ca, bits_a, tb, rb, cb, bits_b, r0, c0, nr, nc):
    """A set operation of two block masks (0: and, 1: and not, 2: or), block by block.

    Each mask is a table of stack indices or -1 / -2 (empty / full), its
    ``[0, 0]`` at world block (r, c), and its blocks' `bb` pixels each (uint8,
    0 or 1, one flat array). The result covers world blocks ``r0 .. r0 + nr -
    1`` by ``c0 .. c0 + nc - 1``: two uniform blocks give a uniform one; a
    uniform and a held block give the held pixels, their complement, or
    nothing; two held blocks their pixel-wise result. A result all set (all
    clear) becomes a full (empty) block.

    Returns
    -------
    table : (nr, nc) int64 ndarray
        Stack index (row-major order), -1 or -2.
    bits : (m bb,) uint8 ndarray
    """
    table = np.empty((nr, nc), np.int64)
    out = np.empty(len(bits_a) + len(bits_b), np.uint8)  # at most every held block of both
    m = 0
    # Blocks of a multiple of 8 pixels are read and written as 64-bit words, 8 pixels at a time.
    words = bb % 8 == 0
    wa = bits_a.view(np.uint64) if words else np.zeros(1, np.uint64)
    wb = bits_b.view(np.uint64) if words else np.zeros(1, np.uint64)
    wo = out.view(np.uint64) if words else np.zeros(1, np.uint64)
    for i in range(nr):
        for j in range(nc):
            sa = _block_at(ta, ra, ca, r0 + i, c0 + j)
            sb = _block_at(tb, rb, cb, r0 + i, c0 + j)
            # Each side: -1 empty, -2 full, else held; the result uniform, a copy, or combined.
            if op == 0:
                if sa == _EMPTY or sb == _EMPTY or (sa == _FULL and sb == _FULL):
                    table[i, j] = _EMPTY if (sa == _EMPTY or sb == _EMPTY) else _FULL
                    continue
            elif op == 1:
                if sa == _EMPTY or sb == _FULL or (sa == _FULL and sb == _EMPTY):
                    table[i, j] = _FULL if (sa == _FULL and sb == _EMPTY) else _EMPTY
                    continue
            else:
                if sa == _FULL or sb == _FULL or (sa == _EMPTY and sb == _EMPTY):
                    table[i, j] = _EMPTY if (sa == _EMPTY and sb == _EMPTY) else _FULL
                    continue
            o = m * bb
            total = 0  # pixels set: none, all, or some
            if words:  # eight pixels a step (each byte 0 or 1)
                total = _combine_words(op, wa, wb, wo, sa, sb, bb // 8, o // 8)
            elif sa >= 0 and sb >= 0:
                x, y = sa * bb, sb * bb
                for u in range(bb):
                    if op == 0:
                        v = bits_a[x + u] & bits_b[y + u]
                    elif op == 1:
                        v = bits_a[x + u] & (bits_b[y + u] ^ np.uint8(1))
                    else:
                        v = bits_a[x + u] | bits_b[y + u]
                    out[o + u] = v
                    total += v
            else:
                # One side held, the other uniform: the held pixels, or (full minus held) their
                # complement.
                if sa >= 0:
                    src, x, flip = bits_a, sa * bb, np.uint8(0)
                else:
                    src, x, flip = bits_b, sb * bb, np.uint8(1 if op == 1 else 0)
                for u in range(bb):
                    v = src[x + u] ^ flip
                    out[o + u] = v
                    total += v
            if total == 0:
                table[i, j] = _EMPTY
            elif total == bb:
                table[i, j] = _FULL
            else:
                table[i, j] = m
                m += 1
    return table, out[:m * bb]


@njit(cache=True, nogil=True)
def winding_rows(key, total, row_start, r_first, c_first, stride, rows0, cols0, mode, out):
    """Winding numbers (or the fill rule's bits) of blocks' pixels, from crossings sorted by pixel.

    A crossing at world pixel (R, C) changes the winding of pixels C and right
    of it in row R; it is keyed ``(R - r_first) stride + C - c_first``, the
    keys sorted and `total` the running sum of their steps (one more, from 0).
    Each block row starts from the crossings left of the block (a few in a
    row) and takes its own as its pixels pass them: one pass that writes each
    run of pixels between two crossings at once.

    Parameters
    ----------
    key : (m,) int64 ndarray, sorted
    total : (m + 1,) int64 ndarray
    row_start : int64 ndarray
        Where each row's keys start (row ``R - r_first``).
    r_first, c_first, stride : int
    rows0, cols0 : (n,) int64 ndarray
        World pixel of each block's first pixel.
    mode : int
        -1: the winding numbers; 0: nonzero (1 where the winding is not 0);
        1: even-odd (1 where it is odd).
    out : (n, B, B) int32 or uint8 ndarray
        Filled.

    Returns
    -------
    some : (n,) bool ndarray
        Blocks with a pixel not 0.
    """
    n, b = out.shape[0], out.shape[1]
    m = len(key)
    some = np.zeros(n, np.bool_)
    for k in range(n):
        for r in range(b):
            row = rows0[k] + r - r_first
            first = row_start[row]
            target = row * stride + cols0[k] - c_first  # the key of the block row's first pixel
            j = first
            while j < m and key[j] < target:  # past the crossings left of the block: a few
                j += 1
            c = 0
            while c < b:  # over the runs of pixels between crossings: a few per row
                stop = b
                if j < m and key[j] - target < b:
                    stop = key[j] - target
                acc = total[j] - total[first]
                v = acc if mode < 0 else ((acc != 0) if mode == 0 else (acc & 1))
                if v != 0 and stop > c:
                    some[k] = True
                for x in range(c, stop):
                    out[k, r, x] = v
                c = stop
                while j < m and key[j] - target == c:  # the crossings at this pixel
                    j += 1
    return some


def warm() -> None:
    """Call every kernel once with the types the layers use.

    Called once before a pool's workers fork, so that they inherit the loaded
    kernels instead of each loading them: the built module
    (`slicelab.geometry.compiled`), or numba's forms (compiled on first use,
    about twenty seconds once per installation; later runs load them from its
    disk cache in a few tenths of a second).

    Examples
    --------
    >>> warm()
    >>> from slicelab.geometry.compiled import status
    >>> status() in ("loaded", "not built", "off") or status().startswith(("stale", "unusable"))
    True
    """
    from .graph_kernels import warm as warm_graphs
    from .march_kernels import warm as warm_march
    from .polygon_kernels import warm as warm_polygons
    from .offset_kernels import onto_offset
    from .segment_kernels import (band_distances, bucket_boxes, cut_at_crossings, douglas_peucker, link_zigzags,
                                  loops_touch, mark_blocks_near, nearest_in_buckets, row_crossings, winding_at)
    i64 = np.zeros(1, np.int64)
    warm_march()
    table = np.zeros((1, 1), np.int64)
    for dtype in (np.uint8, np.float32):
        fill_blocks(np.zeros((1, 3, 1, 3), dtype), np.zeros((1, 1, 1), dtype), 1, dtype(0), dtype(1), table, 0, 0,
                    i64, i64)
    nearest_in_buckets(np.zeros((1, 2)), i64, i64, i64, np.zeros((1, 2, 2)))
    combine_blocks(0, 1, table, 0, 0, np.zeros(1, np.uint8), table, 0, 0, np.zeros(1, np.uint8), 0, 0, 1, 1)
    frozen = i64.copy()
    frozen.flags.writeable = False  # points some callers pass as read-only views
    for where in (i64, frozen):
        sample_blocks(table, 0, 0, 1, np.zeros((1, 1, 1), bool), False, True, where, where)
    band_distances(np.ones((1, 1, 1), bool), i64, i64, 0.1, 1.0, 1.0, 0, 0, 1, 1, np.zeros(2, np.int64), i64,
                   np.zeros((1, 2, 2)))
    douglas_peucker(np.zeros((2, 2)), np.ones(2, bool), 0.1)
    cut_at_crossings(np.zeros((1, 2, 2)), np.zeros((1, 2, 2)))
    winding_at(np.zeros((1, 2)), np.zeros((1, 2, 2)))
    mark_blocks_near(np.zeros((1, 2, 2)), 0.1, 32, 2, 0, 0, np.zeros((1, 1), bool))
    row_crossings(np.zeros((1, 2, 2)), 0.1, 0, 1)
    bucket_boxes(np.zeros((1, 2)), np.ones((1, 2)), 1.0, -1)
    one, f1 = np.zeros(1, np.int64), np.zeros(1)
    link_zigzags(one, np.zeros(1, bool), one, one, one, one, one, one, one, f1, f1, np.ones(1), one, one, f1, f1,
                 np.zeros((1, 2)), np.array([0, 1], np.int64), 1.0)
    loops_touch(np.zeros((1, 2, 2)), np.array([0, 1], np.int64))
    onto_offset(np.zeros((1, 2)), np.array([0, 1], np.int64), 0.2, 0.01, 0.05, 0.6, 1.0, 0, 0, 1, 1,
                np.zeros(2, np.int64), i64, np.zeros((1, 2, 2)))
    warm_graphs()
    warm_polygons()
    for dtype in (np.int32, np.uint8):
        winding_rows(i64, np.zeros(2, np.int64), np.zeros(2, np.int64), 0, 0, 1, i64, i64, 0,
                     np.zeros((1, 1, 1), dtype))
