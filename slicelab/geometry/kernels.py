"""Compiled loops over pixels and blocks: marching squares, chaining, halos, block lookups and set operations.

A layer's toolpaths take a few dozen passes over the pixels held along its
boundary. Written with numpy, each pass is several array calls whose fixed
cost (tens of microseconds each) adds up to most of a layer's time; these
loops do each pass in one compiled call instead (numba, compiled on first use
and cached on disk beside this file). Each kernel is a plain loop over its
input, linear in it; the modules that call them (`slicelab.geometry.contours`,
`slicelab.geometry.blocks`, `slicelab.toolpath.masks`,
`slicelab.toolpath.raster`) keep the interfaces and say what the results mean.

See Also
--------
slicelab.geometry.contours.march_blocks : the contours these kernels trace.
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

#: numba's intrinsics the kernels call, imported with numba only when it compiles them: LLVM's
#: count-trailing-zeros finds the next crossed cell of a row of bits in one instruction.
_NUMBA_GLOBALS = {"trailing_zeros": "numba.cpython.unsafe.numbers:trailing_zeros"}

__all__ = ["march_cells", "closed_cycles", "fill_blocks", "sample_blocks", "combine_blocks", "winding_rows",
           "warm"]

# Block table values of uniform blocks (`slicelab.geometry.blocks`: EMPTY, FULL).
_EMPTY = -1
_FULL = -2


@njit(cache=True, nogil=True)
def _owned(r, c, b, nb, k, n):
    """Whether block k marches the cell whose upper-left corner is its pixel (r, c), r, c >= -1.

    A cell belongs to the first active block among those of its corners (upper left, upper
    right, lower left, lower right), so that a cell on a seam is marched once.
    """
    if r >= 0 and c >= 0:
        return True
    if r < 0 and c < 0:
        return nb[0, 0, k] >= n and nb[0, 1, k] >= n and nb[1, 0, k] >= n
    if r < 0:
        if nb[0, 1, k] < n:
            return False
        return not (c == b - 1 and nb[0, 2, k] < n)
    return nb[1, 0, k] >= n


@njit(cache=True, nogil=True)
def march_cells(flat, level, b, m, nb, rows0, cols0, r_origin, c_origin, width, cap):
    """Marching-squares segments of the blocks laid side by side in `flat`, keyed by world pixel edge.

    Parameters
    ----------
    flat : 2-D float ndarray
        The n blocks (B x B) with a one-pixel halo, `m` per row (`BlockGrid.mosaic`).
    level : float
    b, m : int
        Block size and blocks per row of the mosaic.
    nb : (3, 3, n) int ndarray
        Stack index of each block's neighbours, >= n if not active (`BlockGrid.neighbours`).
    rows0, cols0 : (n,) int ndarray
        World pixel of each block's first pixel.
    r_origin, c_origin, width : int
        The world pixel edge from (R, C) to its right (down) neighbour is keyed
        ``2 ((R - r_origin) width + C - c_origin)`` (plus 1).
    cap : int
        Room for this many segments: the buffers never move during the loop
        (several times faster in numba than growing them).

    Returns
    -------
    start, end : (s,) int64 ndarray
        Keys of the pixel edges each segment starts and ends on.
    points : (s, 2) float64 ndarray
        Each segment's start (row, col), interpolated along its pixel edge.
    complete : bool
        False if there were more than `cap` segments (call again with more room).

    Segments keep the high side on their left; saddles join the high corners.
    """
    n = nb.shape[2]
    q = b + 2
    start = np.empty(cap, np.int64)
    end = np.empty(cap, np.int64)
    points = np.empty((cap, 2), np.float64)
    s = 0
    # Which pixels of a row are at or above the level, as the bits of words of 64 columns: each
    # pixel is compared once, and a few word operations find the crossed cells of two rows
    # (a cell is crossed when its four corners disagree; most are not).
    words = (b + 63) // 63  # cells j0 .. j0 + 62 of a row read columns j0 .. j0 + 63
    one = np.uint64(1)
    prev = np.zeros(words, np.uint64)
    for k in range(n):
        y0 = (k // m) * q
        x0 = (k % m) * q
        for w in range(words):
            prev[w] = _row_bits(flat, y0, x0 + 63 * w, min(q - 63 * w, 64), level)
        for i in range(b + 1):
            for w in range(words):
                j0 = 63 * w
                up = prev[w]
                lo = _row_bits(flat, y0 + i + 1, x0 + j0, min(q - j0, 64), level)
                prev[w] = lo
                v = up ^ lo
                crossed = (up ^ (up >> one)) | (lo ^ (lo >> one)) | v | (v >> one)
                crossed &= (one << np.uint64(min(b + 1 - j0, 63))) - one
                while crossed:
                    t = trailing_zeros(crossed)
                    crossed &= crossed - one
                    j = j0 + np.int64(t)
                    r, c = i - 1, j - 1
                    if (r < 0 or c < 0) and not _owned(r, c, b, nb, k, n):
                        continue
                    cu = (up >> t) & one == one
                    cr = (up >> (t + one)) & one == one
                    cl = (lo >> t) & one == one
                    cw = (lo >> (t + one)) & one == one
                    vu = np.float64(flat[y0 + i, x0 + j])
                    vr = np.float64(flat[y0 + i, x0 + j + 1])
                    vl = np.float64(flat[y0 + i + 1, x0 + j])
                    vw = np.float64(flat[y0 + i + 1, x0 + j + 1])
                    if s + 2 > cap:  # out of room: the caller asks again with more
                        return start[:0], end[:0], points[:0], False
                    R, C = rows0[k] + r, cols0[k] + c
                    base = 2 * ((R - r_origin) * width + (C - c_origin))
                    saddle = cu == cw and cr == cl
                    # Straight-line code, no tuples indexed at run time (several times slower in numba).
                    for h in range(2 if saddle else 1):
                        if saddle:  # low upper left: left -> top, right -> bottom; else top -> right, bottom -> left
                            if not cu:
                                e, f = (3, 0) if h == 0 else (1, 2)
                            else:
                                e, f = (0, 1) if h == 0 else (2, 3)
                        else:
                            # Walk the border counter-clockwise (top, right, bottom, left edges): the
                            # segment starts where the walk leaves the high side and ends where it comes back.
                            e = _first(cu and not cr, cr and not cw, cw and not cl)
                            f = _first(cr and not cu, cw and not cr, cl and not cw)
                        start[s] = _edge_key(base, e, width)
                        end[s] = _edge_key(base, f, width)
                        # Along the start edge, from its first pixel to its second.
                        if e == 0:
                            points[s, 0], points[s, 1] = R, C + (level - vu) / (vr - vu)
                        elif e == 1:
                            points[s, 0], points[s, 1] = R + (level - vr) / (vw - vr), C + 1.0
                        elif e == 2:
                            points[s, 0], points[s, 1] = R + 1.0, C + (level - vl) / (vw - vl)
                        else:
                            points[s, 0], points[s, 1] = R + (level - vu) / (vl - vu), C
                        s += 1
    return start[:s], end[:s], points[:s], True


@njit(cache=True, nogil=True)
def _row_bits(flat, y, x, count, level):
    """Bit t set where pixel (y, x + t) of `flat` is at or above the level, t < count <= 64."""
    bits = np.uint64(0)
    for t in range(count):
        if flat[y, x + t] >= level:
            bits |= np.uint64(1) << np.uint64(t)
    return bits


@njit(cache=True, nogil=True)
def _edge_key(base, edge, width):
    """Key of a cell's top (0), right (1), bottom (2) or left (3) pixel edge, from its top edge's key."""
    if edge == 0:
        return base
    if edge == 1:
        return base + 3
    if edge == 2:
        return base + 2 * width
    return base + 1


@njit(cache=True, nogil=True)
def _first(top, right, bottom):
    """The first true edge of top (0), right (1), bottom (2), else left (3)."""
    return 0 if top else (1 if right else (2 if bottom else 3))


@njit(cache=True, nogil=True)
def _slot(key, bits):
    """Fibonacci hashing: the top `bits` bits of key x 2^64 / phi. Keys of neighbouring pixel
    edges (consecutive numbers) land far apart, so linear probing meets no long runs."""
    return np.int64((np.uint64(key) * np.uint64(0x9E3779B97F4A7C15)) >> np.uint64(64 - bits))


@njit(cache=True, nogil=True)
def closed_cycles(start, end, points):
    """The closed chains of segments (one's end key is the next one's start key), as rings.

    Keys must be met at most once as a start and once as an end (marching
    squares' pixel edges). Open chains are dropped. Each ring starts at its
    lowest point (smallest row, then column) and rings come in the order of
    those points.

    Returns
    -------
    ring_points : (k, 2) float64 ndarray
        The rings' start points, ring after ring.
    bounds : (r + 1,) int64 ndarray
        Ring j is ``ring_points[bounds[j]:bounds[j + 1]]``.
    """
    m = len(start)
    # Which segment starts at each key: an open-addressing hash table, linear probing.
    size, bits = 2, 1
    while size < 2 * m + 2:
        size *= 2
        bits += 1
    mask = size - 1
    slot_key = np.full(size, -1, np.int64)
    slot_seg = np.empty(size, np.int64)
    for i in range(m):
        h = _slot(start[i], bits)
        while slot_key[h] != -1:
            h = (h + 1) & mask
        slot_key[h] = start[i]
        slot_seg[h] = i
    nxt = np.full(m, -1, np.int64)
    for i in range(m):
        h = _slot(end[i], bits)
        while slot_key[h] != -1:
            if slot_key[h] == end[i]:
                nxt[i] = slot_seg[h]
                break
            h = (h + 1) & mask
    state = np.zeros(m, np.int8)  # 0 new, 1 on this walk, 2 done
    cycle = np.empty(m, np.int64)
    bounds = [0]
    firsts = []
    taken = 0
    for i in range(m):
        if state[i]:
            continue
        j = i
        length = 0
        closed = False
        while True:
            state[j] = 1
            cycle[taken + length] = j
            length += 1
            j = nxt[j]
            if j < 0:
                break
            if j == i:
                closed = True
                break
            if state[j]:
                break
        for u in range(taken, taken + length):
            state[cycle[u]] = 2
        if not closed:
            continue
        # The ring from its lowest point.
        low = taken
        for u in range(taken + 1, taken + length):  # scalars, not row views: several times faster
            ar, ac = points[cycle[u], 0], points[cycle[u], 1]
            zr, zc = points[cycle[low], 0], points[cycle[low], 1]
            if ar < zr or (ar == zr and ac < zc):
                low = u
        firsts.append(low)
        taken += length
        bounds.append(taken)
    nr = len(bounds) - 1
    key = np.empty((nr, 2), np.float64)
    for r in range(nr):
        key[r] = points[cycle[firsts[r]]]
    rank = np.argsort(key[:, 1], kind="mergesort")
    rank = rank[np.argsort(key[rank, 0], kind="mergesort")]
    out = np.empty((taken, 2), np.float64)
    out_bounds = np.zeros(nr + 1, np.int64)
    o = 0
    for r in rank:
        a, z = bounds[r], bounds[r + 1]
        f = firsts[r]
        for u in range(f, z):
            out[o, 0], out[o, 1] = points[cycle[u], 0], points[cycle[u], 1]
            o += 1
        for u in range(a, f):
            out[o, 0], out[o, 1] = points[cycle[u], 0], points[cycle[u], 1]
            o += 1
    for r in range(nr):
        out_bounds[r + 1] = out_bounds[r] + bounds[rank[r] + 1] - bounds[rank[r]]
    return out, out_bounds


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
    ``[0, 0]`` at world block (brow0, bcol0); `rows`, `cols` are the active
    blocks' world block indices.
    """
    n, b = data.shape[0], data.shape[1]
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
    from .offset_kernels import onto_offset
    from .segment_kernels import (band_distances, bucket_boxes, cut_at_crossings, douglas_peucker, loops_touch,
                                  mark_blocks_near, nearest_in_buckets, row_crossings, winding_at)
    i64 = np.zeros(1, np.int64)
    nb = np.full((3, 3, 1), 1, np.int64)
    for dtype in (np.float32, np.float64):
        march_cells(np.zeros((3, 3), dtype), 0.5, 1, 1, nb, i64, i64, -1, -1, 4, 16)
    closed_cycles(np.zeros(0, np.int64), np.zeros(0, np.int64), np.zeros((0, 2)))
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
    loops_touch(np.zeros((1, 2, 2)), np.array([0, 1], np.int64))
    onto_offset(np.zeros((1, 2)), np.array([0, 1], np.int64), 0.2, 0.01, 0.05, 0.6, 1.0, 0, 0, 1, 1,
                np.zeros(2, np.int64), i64, np.zeros((1, 2, 2)))
    warm_graphs()
    for dtype in (np.int32, np.uint8):
        winding_rows(i64, np.zeros(2, np.int64), np.zeros(2, np.int64), 0, 0, 1, i64, i64, 0,
                     np.zeros((1, 1, 1), dtype))
