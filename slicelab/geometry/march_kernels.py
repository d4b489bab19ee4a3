"""Compiled marching squares over a stack of blocks, and the chaining of its segments into rings.

`march_cells` finds the segments of a level set on the active blocks of a
layer's grid (`slicelab.geometry.blocks.BlockGrid`), each block's cells reading
one pixel into its neighbours where they lie (no copy with halos); segments
are keyed by their world pixel edge, so those of neighbouring blocks chain as
on one array. `closed_cycles` chains them into rings.

See Also
--------
slicelab.geometry.contours.march_blocks : the rings in the grid's coordinates.
slicelab.geometry.kernels : the other loops over a layer's blocks.

References
----------
.. [1] W. E. Lorensen, H. E. Cline, "Marching cubes: a high resolution 3D
   surface construction algorithm", SIGGRAPH 1987 (its two-dimensional case).
.. [2] S. K. Lam, A. Pitrou, S. Seibert, "Numba: a LLVM-based Python JIT
   compiler", LLVM-HPC 2015.
"""
from __future__ import annotations

import numpy as np

from .compiled import njit

#: numba's intrinsics the kernels call, imported with numba only when it compiles them: LLVM's
#: count-trailing-zeros finds the next crossed cell of a row of bits in one instruction.
_NUMBA_GLOBALS = {"trailing_zeros": "numba.cpython.unsafe.numbers:trailing_zeros"}

__all__ = ["march_cells", "closed_cycles", "warm"]


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
def march_cells(data, level, nb, rows0, cols0, r_origin, c_origin, width, cap, empty, full):
    """Marching-squares segments of a stack of blocks, keyed by world pixel edge.

    Each block's cells reach one pixel into its neighbours, which are read where
    they lie: in the stack, or the uniform value of an empty or full block. No
    copy of the blocks with halos is made.

    Parameters
    ----------
    data : (n, B, B) float ndarray
        The active blocks' values.
    level : float
    nb : (3, 3, n) int ndarray
        Stack index of each block's neighbours: n if empty, n + 1 if full (`BlockGrid.neighbours`).
    rows0, cols0 : (n,) int ndarray
        World pixel of each block's first pixel.
    r_origin, c_origin, width : int
        The world pixel edge from (R, C) to its right (down) neighbour is keyed
        ``2 ((R - r_origin) width + C - c_origin)`` (plus 1).
    cap : int
        Room for this many segments: the buffers never move during the loop
        (several times faster in numba than growing them).
    empty, full : float
        The values of empty and full blocks' pixels (of the data's type).

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
    n, b = data.shape[0], data.shape[1]
    q = b + 2  # a block's cells read its pixels and one beyond on each side
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
        for w in range(words):
            prev[w] = _row_bits(data, nb, k, -1, 63 * w, min(q - 63 * w, 64), level, empty, full)
        for i in range(b + 1):
            for w in range(words):
                j0 = 63 * w
                up = prev[w]
                lo = _row_bits(data, nb, k, i, j0, min(q - j0, 64), level, empty, full)
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
                    vu = np.float64(_value(data, nb, k, r, c, empty, full))
                    vr = np.float64(_value(data, nb, k, r, c + 1, empty, full))
                    vl = np.float64(_value(data, nb, k, r + 1, c, empty, full))
                    vw = np.float64(_value(data, nb, k, r + 1, c + 1, empty, full))
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
def _row_bits(data, nb, k, r, x, count, level, empty, full):
    """Bit t set where pixel (r, x - 1 + t) of block k, -1 <= r <= B, is at or above the level, t <
    count <= 64: columns -1 and B, and rows -1 and B, lie in the neighbours (`_value`)."""
    n, b = data.shape[0], data.shape[1]
    dr, rr = (-1, r + b) if r < 0 else ((1, r - b) if r >= b else (0, r))
    one = np.uint64(1)
    bits = np.uint64(0)
    lo, hi = max(0, 1 - x), min(count, b + 1 - x)  # the bits of the block's own columns 0 .. B - 1
    for t in range(0, min(lo, count)):  # column -1: the left neighbour's last
        if _neighbour(data, nb[dr + 1, 0, k], n, rr, b - 1, empty, full) >= level:
            bits |= one << np.uint64(t)
    kk = nb[dr + 1, 1, k]
    if kk < n:
        for t in range(lo, hi):  # one row of a held block, read in place
            if data[kk, rr, x - 1 + t] >= level:
                bits |= one << np.uint64(t)
    elif (full if kk == n + 1 else empty) >= level:
        for t in range(lo, hi):
            bits |= one << np.uint64(t)
    for t in range(max(lo, hi), count):  # column B: the right neighbour's first
        if _neighbour(data, nb[dr + 1, 2, k], n, rr, 0, empty, full) >= level:
            bits |= one << np.uint64(t)
    return bits


@njit(cache=True, nogil=True)
def _neighbour(data, kk, n, r, c, empty, full):
    """Pixel (r, c) of stack block kk, or the uniform value of an empty (n) or full (n + 1) one."""
    if kk < n:
        return data[kk, r, c]
    return full if kk == n + 1 else empty


@njit(cache=True, nogil=True)
def _value(data, nb, k, r, c, empty, full):
    """Pixel (r, c) of block k, -1 <= r, c <= B: in the block, or in the neighbour it falls in."""
    b = data.shape[1]
    dr, rr = (-1, r + b) if r < 0 else ((1, r - b) if r >= b else (0, r))
    dc, cc = (-1, c + b) if c < 0 else ((1, c - b) if c >= b else (0, c))
    return _neighbour(data, nb[dr + 1, dc + 1, k], data.shape[0], rr, cc, empty, full)


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


def warm() -> None:
    """Call every kernel once with the types its callers pass (see `slicelab.geometry.kernels.warm`).

    Examples
    --------
    >>> warm()
    """
    i64 = np.zeros(1, np.int64)
    nb = np.full((3, 3, 1), 1, np.int64)
    for dtype in (np.float32, np.float64):
        march_cells(np.zeros((1, 1, 1), dtype), 0.5, nb, i64, i64, -1, -1, 4, 16, dtype(0), dtype(1))
    closed_cycles(np.zeros(0, np.int64), np.zeros(0, np.int64), np.zeros((0, 2)))
