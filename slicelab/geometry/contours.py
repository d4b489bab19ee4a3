"""Contours of images: marching squares, ring simplification, skeleton tracing.

Images are 2-D arrays indexed (row, col); contours come out in the same
fractional (row, col) indices, so callers map them to the world with their
own grid. OpenCV does the pixel-wide passes (compare, morphology,
Douglas-Peucker), numpy the rest; no Python loop runs over pixels.

See Also
--------
slicelab.geometry.chains : chaining the marching-squares segments into rings.
slicelab.printing.grid.distance : the distance fields whose level sets these are.
"""
from __future__ import annotations

import numpy as np

from .blocks import BlockGrid
from .chains import chain_segments

__all__ = ["crossed_cells", "march", "march_blocks", "simplify_ring", "skeleton_neighbours", "trace_skeleton"]

_BOX = np.ones((2, 2), np.uint8)


def crossed_cells(values: np.ndarray, level: float) -> np.ndarray:
    """255/0 mask of the marching-squares cells the level crosses, indexed by their first corner.

    Cell (i, j) has corners (i..i+1, j..j+1): it is crossed where their 2 x 2
    maximum and minimum (of ``values >= level``) differ. OpenCV's compare and
    morphology do it in a few fast passes. The last row and column hold no cell.

    Parameters
    ----------
    values : (h, w) float32 or float64 ndarray
    level : float

    Returns
    -------
    (h, w) uint8 ndarray

    See Also
    --------
    march : the contours through these cells.

    Examples
    --------
    >>> v = np.zeros((4, 4)); v[1:3, 1:3] = 1
    >>> (crossed_cells(v, 0.5) > 0).astype(int).tolist()
    [[1, 1, 1, 0], [1, 0, 1, 0], [1, 1, 1, 0], [0, 0, 0, 0]]
    """
    import cv2
    hi = cv2.compare(values, float(level), cv2.CMP_GE)
    cells = cv2.compare(cv2.dilate(hi, _BOX, anchor=(0, 0)), cv2.erode(hi, _BOX, anchor=(0, 0)), cv2.CMP_NE)
    cells[-1, :] = 0
    cells[:, -1] = 0
    return cells


def march(values: np.ndarray, level: float) -> list[np.ndarray]:
    """Closed contours of `values` at `level`, as (row, col) rings with the high side on the left.

    Marching squares with linear interpolation along pixel edges, saddles
    resolved by joining the high corners: the same contours as
    ``skimage.measure.find_contours(values, level, fully_connected="high",
    positive_orientation="low")`` (tests compare the two), but vectorised:
    every crossing edge gets an integer key and the segments are chained by
    `slicelab.geometry.chain_segments`, so no Python loop runs over pixels. It is
    the per-layer hot path of whole-part planning. Contours that reach the
    array's border are not closed and are dropped. Each ring starts at its
    lowest point (smallest row, then column).

    Parameters
    ----------
    values : (h, w) ndarray
    level : float

    Returns
    -------
    list of (k, 2) ndarray
        Fractional (row, col) indices, implicitly closed.

    See Also
    --------
    crossed_cells : the cells the contours pass through.
    simplify_ring : Douglas-Peucker simplification of the rings.

    References
    ----------
    W. E. Lorensen, H. E. Cline, "Marching cubes: a high resolution 3D surface
    construction algorithm", SIGGRAPH 1987 (its 2-D case, marching squares).

    Examples
    --------
    >>> v = np.zeros((5, 5)); v[1:4, 1:4] = 1; v[2, 2] = 2
    >>> [np.round(r, 3).tolist() for r in march(v, 0.5)]
    [[[0.5, 1.0], [0.5, 2.0], [0.5, 3.0], [1.0, 3.5], [2.0, 3.5], [3.0, 3.5], [3.5, 3.0], [3.5, 2.0], [3.5, 1.0], [3.0, 0.5], [2.0, 0.5], [1.0, 0.5]]]
    """
    import cv2
    v = np.asarray(values)
    if v.dtype not in (np.float32, np.float64):  # what cv2.compare takes
        v = v.astype(np.float64)
    h, w = v.shape
    if h < 2 or w < 2:
        return []
    found = cv2.findNonZero(crossed_cells(v, level))
    if found is None:
        return []
    c, r = found.reshape(-1, 2).T.astype(np.int64)  # (x, y) = (col, row), in row-major order
    corners = (v[r, c], v[r, c + 1], v[r + 1, c], v[r + 1, c + 1])
    # Edge keys: horizontal edge (i, j)-(i, j+1) is 2 (i w + j); vertical (i, j)-(i+1, j) is that + 1.
    return _rings(*_cell_segments(corners, level, r, c, lambda dr, dc, vert: 2 * ((r + dr) * w + c + dc) + vert))


def march_blocks(stack: np.ndarray, level: float, grid: BlockGrid, empty: float, full: float) -> list[np.ndarray]:
    """`march` over the blocks of a `BlockGrid`, chained across their seams: the contours of the whole grid.

    A block's cells reach one pixel into its neighbours, read where they lie
    (in the stack, or `empty` / `full` for a uniform block): no copy of the
    blocks with halos is made. A cell is marched
    by one block only: the first active one among the blocks of its corners
    (upper left, upper right, lower left, lower right). A crossing is keyed
    by its pixel edge on the whole grid, so the segments of neighbouring
    blocks chain as if the grid were one array: the same contours as `march`
    on the assembled grid, as long as every cell the level crosses has a
    corner in an active block (true when no two uniform blocks of different
    values touch). The cells are marched and chained by two compiled loops
    (`slicelab.geometry.march_kernels.march_cells`, `closed_cycles`); rings come
    in the order of their lowest points.

    Parameters
    ----------
    stack : (n, B, B) ndarray
        The values of the grid's active blocks.
    level : float
    grid : BlockGrid
    empty, full : float
        The values of the pixels of empty and full blocks.

    Returns
    -------
    list of (k, 2) ndarray
        Fractional (row, col) on the world grid, implicitly closed.

    See Also
    --------
    march : the same on one array.

    Examples
    --------
    >>> v = np.zeros((6, 6)); v[1:5, 1:5] = 1; v[2, 2] = 2   # blocks of 3 x 3 pixels
    >>> g = BlockGrid(3, 0, 0, np.arange(4).reshape(2, 2))
    >>> ours = march_blocks(np.stack([v[i:i + 3, j:j + 3] for i in (0, 3) for j in (0, 3)]), 0.5, g, 0.0, 9.0)
    >>> sorted(map(tuple, ours[0])) == sorted(map(tuple, march(v, 0.5)[0]))
    True
    """
    from .march_kernels import closed_cycles, march_cells
    data = np.ascontiguousarray(stack)
    if data.dtype not in (np.float32, np.float64):
        data = data.astype(np.float64)
    n, b = len(grid), grid.size
    if n == 0:
        return []
    if data.shape != (n, b, b):
        raise ValueError(f"the stack must hold the grid's {n} blocks of {b} x {b} pixels, got {data.shape}")
    rows0, cols0 = grid.origins()
    # Crossings are keyed by their pixel edge on the whole grid (with a pixel to spare around
    # it), so the segments of neighbouring blocks chain as if the grid were one array.
    cap = max(1024, 4 * n * b)  # a contour crosses a block in about B cells: rarely exceeded
    while True:  # once, but for a block crossed many times over
        start, end, points, complete = march_cells(data, float(level), grid.neighbours, rows0, cols0,
                                                   grid.row0 * b - 1, grid.col0 * b - 1, grid.table.shape[1] * b + 3,
                                                   cap, data.dtype.type(empty), data.dtype.type(full))
        if complete:
            break
        cap *= 4
    ring_points, bounds = closed_cycles(start, end, points)
    return [ring_points[bounds[i]:bounds[i + 1]] for i in range(len(bounds) - 1)]


def _cell_segments(corners, level: float, r: np.ndarray, c: np.ndarray, key):
    """The contour segments of crossed cells: start and end keys, and each start point (row, col).

    Cell (r, c) has corners ul = (r, c), ur = (r, c + 1), ll = (r + 1, c), lr
    = (r + 1, c + 1), with values `corners`; ``key(dr, dc, vertical)`` numbers,
    for every cell, the pixel edge from (r + dr, c + dc) to its right (0) or
    lower (1) neighbour.
    """
    vu, vr, vl, vw = (np.asarray(x, np.float64) for x in corners)
    cu, cr, cl, cw = vu >= level, vr >= level, vl >= level, vw >= level
    k_top, k_bottom = key(0, 0, 0), key(1, 0, 0)
    k_left, k_right = key(0, 0, 1), key(0, 1, 1)
    keys = np.stack([k_top, k_right, k_bottom, k_left])
    et, eb, el, er = cu != cr, cl != cw, cu != cl, cr != cw
    saddle = et & eb & el & er
    plain = ~saddle
    # Walk the cell's border counter-clockwise (ul, ur, lr, ll in the (col, row) plane): the
    # segment runs from the edge where the walk leaves the high side to the edge where it comes
    # back, which puts the high side on the segment's left. No geometry, so ties cannot flip it.
    def pick(top_, right_, bottom_, left_):
        return np.where(top_, 0, np.where(right_, 1, np.where(bottom_, 2, 3)))

    s_p = pick(cu & ~cr, cr & ~cw, cw & ~cl, cl & ~cu)[plain]
    e_p = pick(~cu & cr, ~cr & cw, ~cw & cl, ~cl & cu)[plain]
    # Saddles join the high corners: around each low corner, from the edge arriving at it to the
    # edge leaving it (low ul: left -> top, low lr: right -> bottom; low ur: top -> right,
    # low ll: bottom -> left).
    low_ul = ~cu[saddle]
    cells = np.concatenate([np.flatnonzero(plain), np.flatnonzero(saddle), np.flatnonzero(saddle)])
    s_edge = np.concatenate([s_p, np.where(low_ul, 3, 0), np.where(low_ul, 1, 2)])
    e_edge = np.concatenate([e_p, np.where(low_ul, 0, 1), np.where(low_ul, 2, 3)])
    start, end = keys[s_edge, cells], keys[e_edge, cells]
    # Each start point is interpolated along its pixel edge, from its first pixel to its second
    # (left to right, top to bottom), the same way in both cells that share the edge.
    first = np.stack([vu, vr, vl, vu])[s_edge, cells]
    second = np.stack([vr, vw, vw, vl])[s_edge, cells]
    t = (level - first) / (second - first)
    vert = (s_edge == 1) | (s_edge == 3)
    pr = r[cells] + (s_edge == 2) + np.where(vert, t, 0.0)
    pc = c[cells] + (s_edge == 1) + np.where(vert, 0.0, t)
    return start, end, pr, pc


def _rings(start, end, pr, pc) -> list[np.ndarray]:
    """The closed chains of contour segments, as rings of their start points, each from its
    lowest point (smallest row, then column): the same rings whatever the keys."""
    chains = chain_segments(start, end)
    rings = []
    for k in range(len(chains)):  # over contours
        if not chains.closed[k]:
            continue
        idx = chains.order[chains.bounds[k]:chains.bounds[k + 1]]
        r, c = pr[idx], pc[idx]
        low = np.flatnonzero(r == r.min())
        first = low[np.argmin(c[low])]
        rc = np.stack([r, c], 1)
        rings.append(np.concatenate((rc[first:], rc[:first])))
    return rings


def simplify_ring(ring: np.ndarray, tolerance: float) -> np.ndarray:
    """Douglas-Peucker simplification of a closed ring (implicitly closed), keeping original points.

    The ring is closed on its first point, which stays, and simplified by the
    compiled loop `slicelab.geometry.kernels.douglas_peucker`, which measures
    the distance to each chord *segment* (a ring doubling back on itself keeps
    its turning point).

    Parameters
    ----------
    ring : (k, 2) ndarray
    tolerance : float
        Largest distance of a dropped point from the simplified ring (same units).

    Returns
    -------
    (m, 2) ndarray
        A subset of `ring`'s rows, in order, starting with its first.

    See Also
    --------
    march : the rings this simplifies.
    slicelab.printing.steps.simplify.simplify_rings : many rings at once.

    References
    ----------
    D. H. Douglas, T. K. Peucker, "Algorithms for the reduction of the number of
    points required to represent a digitized line or its caricature",
    The Canadian Cartographer 10(2), 1973.

    Examples
    --------
    >>> t = np.linspace(0, 2 * np.pi, 400, endpoint=False)
    >>> ring = np.c_[100 + 30 * np.cos(t), 200 + 30 * np.sin(t)]
    >>> len(simplify_ring(ring, 0.05)) < 100, set(map(tuple, simplify_ring(ring, 0.05))) <= set(map(tuple, ring))
    (True, True)
    """
    from .segment_kernels import douglas_peucker
    ring = np.asarray(ring)
    if len(ring) < 4:
        return ring
    closed = np.ascontiguousarray(np.vstack([ring, ring[:1]]), np.float64)
    keep = np.zeros(len(closed), bool)
    keep[[0, -1]] = True
    return ring[douglas_peucker(closed, keep, float(tolerance))[:-1]]


def _pixels(skel) -> np.ndarray:
    """(row, col) of a skeleton's pixels in row-major order, from an image or a list of pixels."""
    skel = np.asarray(skel)
    if skel.dtype == bool:
        return np.argwhere(skel).astype(np.int64)
    pts = skel.reshape(-1, 2).astype(np.int64)
    if len(pts) == 0:
        return pts
    # Each pixel once, sorted row-major (np.unique(axis=0) would load numpy.ma): one integer key each.
    lo = pts.min(axis=0)
    width = int(pts[:, 1].max() - lo[1]) + 1
    key = np.sort((pts[:, 0] - lo[0]) * width + (pts[:, 1] - lo[1]))
    key = key[np.r_[True, key[1:] != key[:-1]]]
    return np.stack([key // width + lo[0], key % width + lo[1]], axis=1)


def skeleton_neighbours(skel: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Skeleton pixels and their neighbours, with mixed adjacency.

    A diagonal step counts only where no orthogonal path joins the two
    pixels, so staircases are simple chains.

    Parameters
    ----------
    skel : (h, w) bool ndarray, or (n, 2) int ndarray
        A one-pixel-wide skeleton, as an image or as its pixels (row, col).

    Returns
    -------
    pts : (n, 2) int ndarray
        (row, col) of each skeleton pixel, in row-major order.
    nbr : (n, 8) int ndarray
        Index (into `pts`) of each neighbour, -1 where none.

    See Also
    --------
    trace_skeleton : the polylines these links make.

    Examples
    --------
    >>> s = np.zeros((3, 4), bool); s[1, 0:2] = True; s[2, 2] = True   # an L: right, then down
    >>> pts, nbr = skeleton_neighbours(s)
    >>> pts.tolist(), sorted(int(j) for j in nbr[1] if j >= 0)
    ([[1, 0], [1, 1], [2, 2]], [0, 2])
    """
    pts = _pixels(skel)
    nbr = np.full((len(pts), 8), -1, np.int64)
    if len(pts) == 0:
        return pts, nbr
    # Pixel keys in row-major order are sorted: a neighbour is found by binary search.
    r, c = pts[:, 0] - pts[:, 0].min() + 1, pts[:, 1] - pts[:, 1].min() + 1
    w = int(c.max()) + 2
    key = r * w + c

    def find(dr, dc):
        q = key + dr * w + dc
        i = np.minimum(np.searchsorted(key, q), len(key) - 1)
        return np.where(key[i] == q, i, -1)

    k = 0
    for dr in (-1, 0, 1):
        for dc in (-1, 0, 1):
            if dr == 0 and dc == 0:
                continue
            n = find(dr, dc)
            if dr and dc:
                n = np.where((find(dr, 0) >= 0) | (find(0, dc) >= 0), -1, n)
            nbr[:, k] = n
            k += 1
    return pts, nbr


def trace_skeleton(skel: np.ndarray) -> list[np.ndarray]:
    """Split a one-pixel skeleton into polylines of (row, col) indices, meeting at junctions.

    Chains start at their ends (then in their middles, for cycles) and stop
    at junction pixels (three neighbours or more), which each chain touching
    them includes, so the polylines meet.

    Parameters
    ----------
    skel : (h, w) bool ndarray, or (n, 2) int ndarray
        A one-pixel-wide skeleton, e.g. from `slicelab.geometry.graphs.thin`
        (Guo and Hall's thinning), or its pixels (row, col).

    Returns
    -------
    list of (k, 2) int ndarray

    See Also
    --------
    skeleton_neighbours : the links followed.

    References
    ----------
    Z. Guo, R. W. Hall, "Parallel thinning with two-subiteration algorithms",
    Communications of the ACM 32(3), 1989 (the skeletons traced).

    Examples
    --------
    >>> s = np.zeros((5, 7), bool); s[2, 1:6] = True; s[0:2, 3] = True
    >>> sorted(len(p) for p in trace_skeleton(s))
    [3, 3, 3]
    """
    from .graph_kernels import skeleton_chains
    pts, nbr = skeleton_neighbours(skel)
    if len(pts) == 0:
        return []
    # The walks, pixel by pixel, in one compiled loop (a gap along a long wall is thousands).
    # Junction pixels joined only to other junctions (small clusters) are left as they are.
    idx, bounds = skeleton_chains(nbr, (nbr >= 0).sum(axis=1).astype(np.int64))
    return [pts[idx[a:b]] for a, b in zip(bounds[:-1].tolist(), bounds[1:].tolist())]
