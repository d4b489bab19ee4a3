"""Compiled loops over segments and points: nearest segments, exact distances, cuts, windings, simplification.

Each is one plain loop over its input, compiled by numba and cached on disk
beside this file, in place of dozens of small numpy calls; the modules that
call them (`slicelab.geometry.spatial`, `slicelab.printing.grid.distance`,
`slicelab.printing.grid.raster`, `slicelab.printing.steps.simplify`) keep the interfaces
and say what the results mean. `slicelab.geometry.kernels.warm` loads them
with the pixel kernels.

See Also
--------
slicelab.geometry.kernels : the compiled loops over pixels and blocks.
slicelab.geometry.spatial.SegmentIndex : the buckets `band_distances` and `nearest_in_buckets` read.

References
----------
.. [1] S. K. Lam, A. Pitrou, S. Seibert, "Numba: a LLVM-based Python JIT
   compiler", LLVM-HPC 2015.
.. [2] D. H. Douglas, T. K. Peucker, "Algorithms for the reduction of the number of
   points required to represent a digitized line or its caricature",
   The Canadian Cartographer 10(2), 1973.
"""
from __future__ import annotations

import numpy as np

from .compiled import njit

__all__ = ["nearest_in_buckets", "band_distances", "loops_touch", "cut_at_crossings", "winding_at", "douglas_peucker",
           "mark_blocks_near", "row_crossings", "bucket_boxes", "link_zigzags"]


@njit(cache=True, nogil=True)
def nearest_in_buckets(q, first, count, owner, segments):
    """Nearest of each point's candidate segments: distance, segment and parameter along it.

    Point i's candidates are ``owner[first[i]:first[i] + count[i]]``; the
    first candidate reaching the smallest distance wins. A point with no
    candidate gets inf.
    """
    n = len(q)
    dist = np.full(n, np.inf)
    best = np.zeros(n, np.int64)
    tt = np.zeros(n)
    for i in range(n):
        low = np.inf
        px, py = q[i, 0], q[i, 1]
        for u in range(first[i], first[i] + count[i]):
            s = owner[u]
            ax, ay = segments[s, 0, 0], segments[s, 0, 1]
            dx, dy = segments[s, 1, 0] - ax, segments[s, 1, 1] - ay
            wx, wy = px - ax, py - ay
            t = (wx * dx + wy * dy) / max(dx * dx + dy * dy, 1e-300)
            t = min(max(t, 0.0), 1.0)
            ex, ey = wx - t * dx, wy - t * dy
            e2 = ex * ex + ey * ey
            if e2 < low:
                low = e2
                best[i] = s
                tt[i] = t
        if count[i] > 0:
            dist[i] = np.sqrt(low)
    return dist, best, tt


@njit(cache=True, nogil=True)
def band_distances(inside, rows0, cols0, p, deep, cell, ox, oy, width, height, start, owner, pieces):
    """Exact distance from each material pixel's centre to the boundary, up to `deep`.

    Parameters
    ----------
    inside : (n, B, B) bool ndarray
        Material pixels of the active blocks.
    rows0, cols0 : (n,) int64 ndarray
        World pixel of each block's first pixel (centre at ``(col p, row p)``).
    p, deep : float
        Pixel size; the largest distance measured (mm), at most `cell`.
    cell, ox, oy, width, height, start, owner, pieces
        Square buckets of side `cell` (bucket (i, j) is ``(oy + i, ox + j)``
        in cells): bucket q lists ``owner[start[q]:start[q + 1]]``, every piece
        within a cell of it (`slicelab.geometry.spatial.SegmentIndex.piece_buckets`).

    Returns
    -------
    values : (n, B, B) float32 ndarray
        The distance (mm) in material, `deep` where it is farther, -p/2 outside.
    exact : int
        How many pixels hold a distance below `deep`.
    """
    n, b = inside.shape[0], inside.shape[1]
    out = np.empty((n, b, b), np.float32)
    outside = np.float32(-0.5 * p)
    top = np.float32(deep)
    exact = 0
    most = 0
    for q in range(len(start) - 1):
        most = max(most, start[q + 1] - start[q])
    # The candidates of the bucket at hand, gathered into contiguous arrays: pixels in the
    # same bucket (a run of a row) share them.
    ax, ay = np.empty(most), np.empty(most)
    dx, dy, inv = np.empty(most), np.empty(most), np.empty(most)
    bcol = np.empty(b, np.int64)
    for k in range(n):
        for c in range(b):
            bcol[c] = int(np.floor((cols0[k] + c) * p / cell)) - ox
        for r in range(b):
            y = (rows0[k] + r) * p
            by = int(np.floor(y / cell)) - oy
            held = -1
            count = 0
            for c in range(b):
                if not inside[k, r, c]:
                    out[k, r, c] = outside
                    continue
                bx = bcol[c]
                if bx < 0 or bx >= width or by < 0 or by >= height:
                    out[k, r, c] = top
                    continue
                key = by * width + bx
                if key != held:
                    held = key
                    count = start[key + 1] - start[key]
                    for u in range(count):
                        sgm = owner[start[key] + u]
                        ax[u], ay[u] = pieces[sgm, 0, 0], pieces[sgm, 0, 1]
                        dx[u], dy[u] = pieces[sgm, 1, 0] - ax[u], pieces[sgm, 1, 1] - ay[u]
                        den = dx[u] * dx[u] + dy[u] * dy[u]
                        inv[u] = 1.0 / den if den > 0 else 0.0
                x = (cols0[k] + c) * p
                low = np.inf
                for u in range(count):
                    wx, wy = x - ax[u], y - ay[u]
                    t = min(max((wx * dx[u] + wy * dy[u]) * inv[u], 0.0), 1.0)
                    ex, ey = wx - t * dx[u], wy - t * dy[u]
                    low = min(low, ex * ex + ey * ey)
                d = np.sqrt(low)
                if d < deep:
                    out[k, r, c] = d
                    exact += 1
                else:
                    out[k, r, c] = top
    return out, exact


@njit(cache=True, nogil=True)
def _orient(ax, ay, bx, by, cx, cy):
    """Sign of the turn a -> b -> c: 1 left, -1 right, 0 in line."""
    v = (bx - ax) * (cy - ay) - (by - ay) * (cx - ax)
    return 1 if v > 0 else (-1 if v < 0 else 0)


@njit(cache=True, nogil=True)
def loops_touch(edges, bounds):
    """Whether any two edges of closed loops meet, other than a loop's consecutive edges at their
    shared vertex: crossings, touching vertices and edges overlapping in line all count.

    A sweep along x over the edges sorted by their left ends; two edges are
    compared only if their boxes meet, with exact orientation tests.

    Parameters
    ----------
    edges : (m, 2, 2) float64 ndarray
        The loops' edges, loop after loop, each loop's edges in order.
    bounds : (r + 1,) int ndarray
        Loop k is ``edges[bounds[k]:bounds[k + 1]]``.
    """
    m = len(edges)
    nxt = np.empty(m, np.int64)  # the next edge of each edge's loop
    for k in range(len(bounds) - 1):
        for i in range(bounds[k], bounds[k + 1]):
            nxt[i] = i + 1 if i + 1 < bounds[k + 1] else bounds[k]
    xlo = np.minimum(edges[:, 0, 0], edges[:, 1, 0])
    order = np.argsort(xlo)
    for a in range(m):
        i = order[a]
        ax, ay, bx, by = edges[i, 0, 0], edges[i, 0, 1], edges[i, 1, 0], edges[i, 1, 1]
        xhi = max(ax, bx)
        ylo, yhi = min(ay, by), max(ay, by)
        for c in range(a + 1, m):
            j = order[c]
            if xlo[j] > xhi:
                break
            cx, cy, dx, dy = edges[j, 0, 0], edges[j, 0, 1], edges[j, 1, 0], edges[j, 1, 1]
            if max(cy, dy) < ylo or min(cy, dy) > yhi:
                continue
            o1, o2 = _orient(ax, ay, bx, by, cx, cy), _orient(ax, ay, bx, by, dx, dy)
            o3, o4 = _orient(cx, cy, dx, dy, ax, ay), _orient(cx, cy, dx, dy, bx, by)
            if nxt[i] == j or nxt[j] == i:
                # Consecutive edges meet at their shared vertex: only folding back in line counts.
                if o1 == 0 and o2 == 0:
                    ux, uy = bx - ax, by - ay
                    vx, vy = dx - cx, dy - cy
                    if ux * vx + uy * vy < 0:
                        return True
                continue
            if o1 * o2 <= 0 and o3 * o4 <= 0:
                if o1 == 0 and o2 == 0:  # in line: they meet only if their extents overlap
                    if max(min(ax, bx), min(cx, dx)) > min(max(ax, bx), max(cx, dx)) or \
                            max(ylo, min(cy, dy)) > min(yhi, max(cy, dy)):
                        continue
                return True
    return False


@njit(cache=True, nogil=True)
def cut_at_crossings(pieces, edges):
    """Each piece cut where an edge crosses its interior: the parts, in order along each piece.

    A crossing is where the piece's open interior (0 < t < 1) meets an edge,
    ends included; parallel edges never cross. A piece no edge crosses comes
    back whole.

    Parameters
    ----------
    pieces, edges : (m, 2, 2), (e, 2, 2) float64 ndarray

    Returns
    -------
    (k, 2, 2) float64 ndarray
    """
    m, ne = len(pieces), len(edges)
    cap = 2 * m + 16
    out = np.empty((cap, 2, 2))
    o = 0
    ts = np.empty(ne + 2)
    for i in range(m):
        ax, ay = pieces[i, 0, 0], pieces[i, 0, 1]
        dx, dy = pieces[i, 1, 0] - ax, pieces[i, 1, 1] - ay
        xlo, xhi = min(ax, ax + dx), max(ax, ax + dx)
        ylo, yhi = min(ay, ay + dy), max(ay, ay + dy)
        nt = 0
        ts[nt] = 0.0
        nt += 1
        for j in range(ne):
            cx, cy = edges[j, 0, 0], edges[j, 0, 1]
            ex, ey = edges[j, 1, 0] - cx, edges[j, 1, 1] - cy
            if max(cx, cx + ex) < xlo or min(cx, cx + ex) > xhi or max(cy, cy + ey) < ylo \
                    or min(cy, cy + ey) > yhi:
                continue
            den = dx * ey - dy * ex
            if den == 0:
                continue
            wx, wy = cx - ax, cy - ay
            t = (wx * ey - wy * ex) / den
            u = (wx * dy - wy * dx) / den
            if 0 < t < 1 and 0 <= u <= 1:
                ts[nt] = t
                nt += 1
        ts[nt] = 1.0
        nt += 1
        cuts = np.sort(ts[:nt])
        for h in range(nt - 1):
            t0, t1 = cuts[h], cuts[h + 1]
            if not t1 > t0:
                continue
            if o >= cap:  # room for twice as many parts
                cap *= 2
                bigger = np.empty((cap, 2, 2))
                bigger[:o] = out[:o]
                out = bigger
            out[o, 0, 0], out[o, 0, 1] = ax + t0 * dx, ay + t0 * dy
            out[o, 1, 0], out[o, 1, 1] = ax + t1 * dx, ay + t1 * dy
            o += 1
    return out[:o]


@njit(cache=True, nogil=True)
def winding_at(points, edges):
    """Winding number of each point with respect to oriented edges (material on their left).

    A horizontal ray to +x from the point counts +1 for each upward edge it
    crosses with the point on the edge's left, -1 for each downward edge with
    the point on its right; an edge spans ``ymin <= y < ymax``, so a vertex on
    the ray is counted once. A counter-clockwise loop's inside gets +1.
    """
    out = np.zeros(len(points), np.int64)
    for i in range(len(points)):
        px, py = points[i, 0], points[i, 1]
        w = 0
        for j in range(len(edges)):
            x0, y0, x1, y1 = edges[j, 0, 0], edges[j, 0, 1], edges[j, 1, 0], edges[j, 1, 1]
            side = (x1 - x0) * (py - y0) - (px - x0) * (y1 - y0)
            if y0 <= py < y1 and side > 0:
                w += 1
            elif y1 <= py < y0 and side < 0:
                w -= 1
        out[i] = w
    return out


@njit(cache=True, nogil=True)
def douglas_peucker(points, keep, tolerance):
    """Douglas-Peucker on concatenated polylines: `keep` with the vertices the simplification needs.

    Between two consecutive kept vertices, the vertex farthest from their
    chord *segment* (the first, on ties) is kept when it lies beyond
    `tolerance`, recursively (an explicit stack, no recursion).
    """
    out = keep.copy()
    n = len(points)
    kept = np.flatnonzero(keep)
    stack = np.empty((n + 1, 2), np.int64)
    top = 0
    for u in range(len(kept) - 1):
        if kept[u + 1] - kept[u] > 1:
            stack[top, 0] = kept[u]
            stack[top, 1] = kept[u + 1]
            top += 1
    while top > 0:
        top -= 1
        a, b = stack[top, 0], stack[top, 1]
        ax, ay = points[a, 0], points[a, 1]
        dx, dy = points[b, 0] - ax, points[b, 1] - ay
        den = dx * dx + dy * dy
        far, at = -1.0, -1
        for i in range(a + 1, b):
            wx, wy = points[i, 0] - ax, points[i, 1] - ay
            t = 0.0
            if den > 0:
                t = min(max((wx * dx + wy * dy) / den, 0.0), 1.0)
            ex, ey = wx - t * dx, wy - t * dy
            d = np.sqrt(ex * ex + ey * ey)
            if d > far:
                far, at = d, i
        if far > tolerance:
            out[at] = True
            if at - a > 1:
                stack[top, 0], stack[top, 1] = a, at
                top += 1
            if b - at > 1:
                stack[top, 0], stack[top, 1] = at, b
                top += 1
    return out


@njit(cache=True, nogil=True)
def mark_blocks_near(segments, pixel_size, size, reach, row0, col0, table):
    """Set ``table[i, j]`` for each block (world block ``row0 + i``, ``col0 + j``) holding a pixel
    within `reach` pixels of a segment's pixel box.

    Each segment is cut into equal pieces no longer than a block, as
    `slicelab.geometry.spatial.split_segments` cuts it (the same arithmetic, so
    the same pieces); each piece marks the blocks its pixel box, widened by
    `reach`, overlaps. One pass over the segments, with no arrays made per step:
    the compiled form of `slicelab.geometry.blocks.blocks_near`.
    """
    nr, nc = table.shape
    p = pixel_size
    piece = size * p
    for i in range(len(segments)):
        x0, y0, x1, y1 = segments[i, 0, 0], segments[i, 0, 1], segments[i, 1, 0], segments[i, 1, 1]
        dx, dy = x1 - x0, y1 - y0
        k = max(1, int(np.ceil(np.hypot(dx, dy) / piece)))
        for j in range(k):
            ax, ay = x0 + dx * (j / k), y0 + dy * (j / k)
            if j + 1 == k:
                bx, by = x1, y1
            else:
                bx, by = x0 + dx * ((j + 1) / k), y0 + dy * ((j + 1) / k)
            lo_c = int(np.floor(min(ax, bx) / p)) - reach
            hi_c = int(np.ceil(max(ax, bx) / p)) + reach
            lo_r = int(np.floor(min(ay, by) / p)) - reach
            hi_r = int(np.ceil(max(ay, by) / p)) + reach
            r0 = min(max(lo_r // size - row0, 0), nr)
            r1 = min(max(hi_r // size - row0 + 1, 0), nr)
            c0 = min(max(lo_c // size - col0, 0), nc)
            c1 = min(max(hi_c // size - col0 + 1, 0), nc)
            for r in range(r0, r1):
                for c in range(c0, c1):
                    table[r, c] = True


@njit(cache=True, nogil=True)
def row_crossings(edges, p, r_first, r_stop):
    """Every crossing of an edge with a row of pixel centres ``y = r p``, r_first <= r < r_stop:
    its row, the x of the crossing and the winding step of the pixels right of it (-1 where the
    edge goes up, material on its left; +1 where it goes down).

    Row r is crossed when ``ceil(ymin / p) <= r < ceil(ymax / p)``, so a row through a vertex
    shared by two edges is counted once. Edge by edge, rows rising, in one pass that makes no
    arrays but its results (`slicelab.printing.grid.raster.winding_numbers` and `winding_blocks` sum
    the steps along the rows).
    """
    m = len(edges)
    lo = np.empty(m, np.int64)
    hi = np.empty(m, np.int64)
    total = 0
    for i in range(m):
        y0, y1 = edges[i, 0, 1], edges[i, 1, 1]
        lo[i] = min(max(int(np.ceil(min(y0, y1) / p)), r_first), r_stop)
        hi[i] = min(max(int(np.ceil(max(y0, y1) / p)), r_first), r_stop)
        total += hi[i] - lo[i]
    rows = np.empty(total, np.int64)
    x = np.empty(total, np.float64)
    step = np.empty(total, np.int32)
    k = 0
    for i in range(m):
        x0, y0, x1, y1 = edges[i, 0, 0], edges[i, 0, 1], edges[i, 1, 0], edges[i, 1, 1]
        s = -1 if y1 > y0 else 1
        for r in range(lo[i], hi[i]):
            t = (r * p - y0) / (y1 - y0)
            rows[k] = r
            x[k] = x0 + t * (x1 - x0)
            step[k] = s
            k += 1
    return rows, x, step


@njit(cache=True, nogil=True)
def bucket_boxes(lo, hi, cell, limit):
    """Boxes [lo, hi], widened by a cell, listed in each square bucket of side `cell` they meet.

    Bucket (col, row) of the grid is ``cell (origin + (col, row))``, numbered ``row width +
    col``; bucket q lists ``owner[start[q]:start[q + 1]]``, boxes in increasing order. A counting
    sort in two passes over the boxes.

    Returns
    -------
    origin : (2,) int64 ndarray
    width, height : int
    start : (width height + 1,) int64 ndarray
    owner : int64 ndarray
    fits : bool
        False (and nothing listed) if the entries would outnumber `limit` (when >= 0).
    """
    n = len(lo)
    b0 = np.empty((n, 2), np.int64)
    b1 = np.empty((n, 2), np.int64)
    origin = np.zeros(2, np.int64)
    top = np.zeros(2, np.int64)
    total = 0
    for i in range(n):
        for a in range(2):
            b0[i, a] = int(np.floor((lo[i, a] - cell) / cell))
            b1[i, a] = int(np.floor((hi[i, a] + cell) / cell))
            if i == 0 or b0[i, a] < origin[a]:
                origin[a] = b0[i, a]
            if i == 0 or b1[i, a] > top[a]:
                top[a] = b1[i, a]
        total += (b1[i, 0] - b0[i, 0] + 1) * (b1[i, 1] - b0[i, 1] + 1)
    width = int(top[0] - origin[0]) + 1 if n else 1
    height = int(top[1] - origin[1]) + 1 if n else 1
    if 0 <= limit < total:
        return origin, width, height, np.zeros(1, np.int64), np.zeros(0, np.int64), False
    start = np.zeros(width * height + 1, np.int64)
    for i in range(n):
        for r in range(b0[i, 1] - origin[1], b1[i, 1] - origin[1] + 1):
            for c in range(b0[i, 0] - origin[0], b1[i, 0] - origin[0] + 1):
                start[r * width + c + 1] += 1
    for q in range(width * height):
        start[q + 1] += start[q]
    fill = start[:-1].copy()
    owner = np.empty(total, np.int64)
    for i in range(n):
        for r in range(b0[i, 1] - origin[1], b1[i, 1] - origin[1] + 1):
            for c in range(b0[i, 0] - origin[0], b1[i, 0] - origin[0] + 1):
                q = r * width + c
                owner[fill[q]] = i
                fill[q] += 1
    return origin, width, height, start, owner, True


@njit(cache=True, nogil=True)
def _put(out, m, x, y):
    """Point (x, y) written at row m of `out`, grown (doubled) first when full; returns `out`."""
    if m == len(out):
        grown = np.empty((2 * len(out) + 16, 2))
        grown[:m] = out[:m]
        out = grown
    out[m, 0], out[m, 1] = x, y
    return out


@njit(cache=True, nogil=True)
def link_zigzags(order, used, nxt, prv, interval, other, line, ring, edge, t, arc, perimeter, start, end, xc, yc,
                 ring_points, ring_start, max_link):
    """Fill-line intervals linked into zigzags along the region's boundary, in the lines' frame.

    A zigzag starts at the next unused interval of `order`, runs along it, and
    goes on to the unused interval on the next line (the same step of lines as
    the last link, after the first) that the nearer of the crossing's two
    neighbours along its ring belongs to, following that ring's vertices, if
    the stretch of boundary is at most `max_link` long; it stops when none is.

    Parameters
    ----------
    order : (i,) int ndarray
        The intervals in the order zigzags may start at.
    used : (i,) bool ndarray
        Intervals no zigzag may take (stubs); the others are marked as taken.
    nxt, prv : (c,) int ndarray
        Each crossing's next and previous crossing along its ring (-1: none).
    interval, other : (c,) int ndarray
        Each crossing's interval, and the crossing at that interval's other end.
    line : (i,) int ndarray
        Each interval's line.
    ring, edge, t, arc : (c,) ndarrays
        Each crossing's ring, the edge of the ring it lies on, its parameter along
        that edge, and its distance along the ring from the ring's first vertex.
    perimeter : (r,) float ndarray
    start, end : (i,) int ndarray
        Each interval's entering and leaving crossing.
    xc, yc : (c,) float ndarray
        The crossings.
    ring_points, ring_start : float (v, 2), int (r + 1,) ndarrays
        Ring r's vertices are ``ring_points[ring_start[r]:ring_start[r + 1]]``.
    max_link : float

    Returns
    -------
    points : (p, 2) float ndarray
        The zigzags' vertices, one zigzag after another.
    bounds : (z + 1,) int ndarray
        Zigzag j is ``points[bounds[j]:bounds[j + 1]]``.
    """
    out = np.empty((4 * len(start) + 16, 2))
    bounds = [0]
    m = 0
    for i0 in order:  # over intervals: where zigzags start
        if used[i0]:
            continue
        used[i0] = True
        out = _put(out, m, xc[start[i0]], yc[start[i0]])
        out = _put(out, m + 1, xc[end[i0]], yc[end[i0]])
        m += 2
        cur, step = end[i0], 0
        while True:  # over the intervals of this zigzag
            best, found, best_nb, best_forward, best_dk = 0.0, False, -1, True, 0
            for side in range(2):
                forward = side == 0
                nb = nxt[cur] if forward else prv[cur]
                if nb < 0 or used[interval[nb]]:
                    continue
                dk = line[interval[nb]] - line[interval[cur]]
                if abs(dk) != 1 or (step != 0 and dk != step):
                    continue
                r = ring[cur]
                length = (arc[nb] - arc[cur]) % perimeter[r] if forward else (arc[cur] - arc[nb]) % perimeter[r]
                if length <= max_link and (not found or length < best):
                    best, found, best_nb, best_forward, best_dk = length, True, nb, forward, dk
            if not found:
                break
            nb, r = best_nb, ring[cur]
            # The ring's vertices strictly between the two crossings, walking the link's way.
            a, n = ring_start[r], ring_start[r + 1] - ring_start[r]
            e0, e1 = edge[cur], edge[nb]
            if best_forward:
                if not (e1 == e0 and t[nb] >= t[cur]):
                    steps = (e1 - e0) % n
                    for i in range(steps if steps else n):
                        v = a + (e0 + 1 + i) % n
                        out = _put(out, m, ring_points[v, 0], ring_points[v, 1])
                        m += 1
            elif not (e1 == e0 and t[nb] <= t[cur]):
                steps = (e0 - e1) % n
                for i in range(steps if steps else n):
                    v = a + (e0 - i + n) % n
                    out = _put(out, m, ring_points[v, 0], ring_points[v, 1])
                    m += 1
            used[interval[nb]] = True
            far = other[nb]
            out = _put(out, m, xc[nb], yc[nb])
            out = _put(out, m + 1, xc[far], yc[far])
            m += 2
            cur, step = far, best_dk
        bounds.append(m)
    return out[:m].copy(), np.array(bounds, np.int64)

