"""Segments in the plane: equal pieces, and exact nearest distances through a k-d tree.

See Also
--------
slicelab.printing.grid.distance : exact distance fields measured with `SegmentIndex`.
"""
from __future__ import annotations

from functools import cached_property

import numpy as np

from .ragged import within_group

__all__ = ["split_segments", "join_collinear", "simplify_chains", "SegmentIndex"]


def split_segments(segments: np.ndarray, piece: float) -> tuple[np.ndarray, np.ndarray]:
    """Cut segments into equal pieces no longer than `piece`.

    A segment of length L becomes ``max(1, ceil(L / piece))`` pieces, laid
    end to end in order; each segment's first and last piece end exactly at
    its own endpoints.

    Parameters
    ----------
    segments : (m, 2, 2) ndarray
    piece : float
        Longest piece.

    Returns
    -------
    pieces : (n, 2, 2) ndarray
        `segments` itself when no segment is longer than `piece`.
    owner : (n,) int ndarray
        The segment each piece comes from (non-decreasing).

    See Also
    --------
    SegmentIndex : nearest distances to segments, over such pieces.

    Examples
    --------
    >>> pieces, owner = split_segments(np.array([[[0, 0], [3, 0]], [[3, 0], [3, 1]]], float), 1.5)
    >>> pieces[:, :, 0].tolist(), owner.tolist()
    ([[0.0, 1.5], [1.5, 3.0], [3.0, 3.0]], [0, 0, 1])
    """
    edges = np.asarray(segments, np.float64).reshape(-1, 2, 2)
    d = edges[:, 1] - edges[:, 0]
    k = np.maximum(1, np.ceil(np.hypot(d[:, 0], d[:, 1]) / piece)).astype(np.int64)
    if (k == 1).all():
        return edges, np.arange(len(edges), dtype=np.int64)
    idx = np.repeat(np.arange(len(edges)), k)
    j = within_group(k)[:, None]
    a = edges[idx, 0] + d[idx] * (j / k[idx, None])
    b = np.where(j + 1 == k[idx, None], edges[idx, 1], edges[idx, 0] + d[idx] * ((j + 1) / k[idx, None]))
    return np.stack([a, b], axis=1), idx


def join_collinear(segments: np.ndarray) -> np.ndarray:
    """Join runs of consecutive segments that continue each other in a straight line.

    Segment i + 1 continues segment i when it starts exactly where i ends and
    points the same way (the pieces of one segment, `split_segments`): the
    run becomes one segment, the same set of points.

    Examples
    --------
    >>> pieces, _ = split_segments(np.array([[[0, 0], [3, 0]], [[3, 0], [3, 1]]], float), 1.0)
    >>> join_collinear(pieces).tolist()
    [[[0.0, 0.0], [3.0, 0.0]], [[3.0, 0.0], [3.0, 1.0]]]
    """
    seg = np.asarray(segments, np.float64).reshape(-1, 2, 2)
    if len(seg) < 2:
        return seg
    d = seg[:, 1] - seg[:, 0]
    a, b = d[:-1], d[1:]
    cross = a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]
    dot = np.einsum("ij,ij->i", a, b)
    same = np.all(seg[:-1, 1] == seg[1:, 0], axis=1) & (dot > 0) & \
        (np.abs(cross) <= 1e-9 * np.hypot(a[:, 0], a[:, 1]) * np.hypot(b[:, 0], b[:, 1]))
    first = np.flatnonzero(np.concatenate([[True], ~same]))
    last = np.concatenate([first[1:], [len(seg)]]) - 1
    return np.stack([seg[first, 0], seg[last, 1]], axis=1)


def simplify_chains(segments: np.ndarray, tolerance: float) -> np.ndarray:
    """Runs of consecutive segments (each starting where the one before ends) simplified to a
    tolerance: Douglas-Peucker on each run's vertices, its two ends kept.

    Every dropped vertex lies within `tolerance` of the simplified run, so a
    distance measured to the result is within `tolerance` of the distance to
    the segments. A fine polygon of a curved surface (a dense scan's section)
    becomes a few times fewer segments.

    Examples
    --------
    >>> t = np.linspace(0, np.pi / 2, 91)
    >>> arc = np.c_[10 * np.cos(t), 10 * np.sin(t)]
    >>> seg = np.stack([arc[:-1], arc[1:]], 1)
    >>> out = simplify_chains(seg, 0.01)
    >>> len(seg), len(out), out[0, 0].tolist(), out[-1, 1].round(9).tolist()
    (90, 26, [10.0, 0.0], [0.0, 10.0])
    """
    from .segment_kernels import douglas_peucker
    seg = np.asarray(segments, np.float64).reshape(-1, 2, 2)
    if len(seg) < 2 or tolerance <= 0:
        return seg
    cont = np.all(seg[:-1, 1] == seg[1:, 0], axis=1)
    first = np.flatnonzero(np.concatenate([[True], ~cont]))
    last = np.concatenate([first[1:], [len(seg)]]) - 1
    # Each run's vertices: its segments' starts, then its last end.
    pts = np.insert(seg[:, 0], last + 1, seg[last, 1], axis=0)
    size = last - first + 2
    run = np.repeat(np.arange(len(first)), size)
    keep = np.zeros(len(pts), bool)
    ends = np.cumsum(size)
    keep[ends - 1] = True
    keep[ends - size] = True
    kept = np.flatnonzero(douglas_peucker(np.ascontiguousarray(pts), keep, float(tolerance)))
    same = run[kept[:-1]] == run[kept[1:]]
    return np.stack([pts[kept[:-1][same]], pts[kept[1:][same]]], axis=1)


def _bucketed(lo: np.ndarray, hi: np.ndarray, cell: float, limit: int | None = None):
    """Boxes [lo, hi], widened by a cell, listed in each square bucket of side `cell` they meet.

    Returns (origin, width, height, start, owners): bucket (col, row) of the grid is
    ``cell (origin + (col, row))``, numbered ``q = row width + col``, and lists the boxes
    ``owners[start[q]:start[q + 1]]`` (`slicelab.geometry.segment_kernels.bucket_boxes`, one
    compiled counting sort). None if the entries would outnumber `limit`.
    """
    from .segment_kernels import bucket_boxes
    origin, width, height, start, owner, fits = bucket_boxes(
        np.ascontiguousarray(lo, np.float64).reshape(-1, 2), np.ascontiguousarray(hi, np.float64).reshape(-1, 2),
        float(cell), -1 if limit is None else int(limit))
    return (origin, int(width), int(height), start, owner) if fits else None


class SegmentIndex:
    """Exact nearest distances from points to a set of segments.

    Segments are cut into pieces no longer than `piece` (`split_segments`); a
    k-d tree on the pieces' midpoints proposes candidates, and a point's
    answer is final once the best exact distance cannot be beaten by any
    piece further away (a piece's points lie within half its length of its
    midpoint).

    Parameters
    ----------
    segments : (m, 2, 2) ndarray
    piece : float
        Longest piece: shorter pieces settle more points in the first round.
    join : bool, default False
        Join runs of collinear segments first (`join_collinear`): fewer, longer
        segments make `nearest` with a `reach` faster. `segments` and the
        indices `nearest` returns are then the joined segments.
    tolerance : float, default 0
        Runs of segments simplified to this tolerance first (`simplify_chains`):
        distances are then within it of the exact ones.

    Attributes
    ----------
    segments : (m, 2, 2) ndarray

    Examples
    --------
    >>> idx = SegmentIndex(np.array([[[0, 0], [10, 0]], [[10, 0], [10, 5]]], float), 1.0)
    >>> d, s, t = idx.nearest(np.array([[3.0, 2.0], [12.0, 7.0]]))
    >>> d.round(6).tolist(), s.tolist(), t.round(3).tolist()
    ([2.0, 2.828427], [0, 1], [0.3, 1.0])
    """

    def __init__(self, segments: np.ndarray, piece: float, *, join: bool = False, tolerance: float = 0.0):
        seg = np.asarray(segments, np.float64).reshape(-1, 2, 2)
        if join:
            seg = join_collinear(seg)
        if tolerance > 0:
            seg = simplify_chains(seg, tolerance)
        self.segments = seg
        self._piece = float(piece)
        self.lo, self.hi = seg.min(axis=1), seg.max(axis=1)
        self._bucket_cache = None

    @cached_property
    def _pieces(self):
        """The pieces, made on first use (most queries are answered from the buckets): their
        ends a, b, b - a, 1 / |b - a|^2, their segments, half the longest, and a k-d tree of
        their midpoints (None without segments)."""
        from scipy.spatial import cKDTree
        seg = self.segments
        pieces, owner = split_segments(seg, self._piece)
        d = seg[:, 1] - seg[:, 0]
        k = np.bincount(owner, minlength=len(seg))
        pa, pb = pieces[:, 0], pieces[:, 1]
        pd = pb - pa
        inv_len2 = 1.0 / np.maximum(np.einsum("ij,ij->i", pd, pd), 1e-300)
        half = float(0.5 * (np.hypot(d[:, 0], d[:, 1]) / k).max()) if len(seg) else 0.0
        tree = cKDTree(0.5 * (pa + pb)) if len(seg) else None
        return pa, pd, inv_len2, owner, half, tree

    def _buckets(self, reach: float):
        """Square buckets of side `cell` (three times `reach`), each with the segments whose box,
        widened by a cell, meets it: (cell, origin, width, height, start, owners), made
        once for the reaches that share them (between a third of the side and the side), or
        None if candidates would be too many (short segments): the k-d tree does better."""
        cached = self._bucket_cache
        if cached is not None and reach <= cached[0] <= 3 * reach:
            return cached
        # Three times the reach: the deeper levels' queries (the next perimeters, the filling's
        # edge) share them.
        cell = 3.0 * float(reach)
        listed = _bucketed(self.lo, self.hi, cell, limit=64 * len(self.segments) + 4096)
        if listed is None:
            return None
        self._bucket_cache = (cell, *listed)
        return self._bucket_cache

    def piece_buckets(self, cell: float):
        """The segments cut into pieces no longer than `cell`, in square buckets of that side.

        Every piece is listed in each bucket its box, widened by a cell,
        meets (at most 4 x 4 buckets): a point's bucket then lists every piece
        within `cell` of it. Made once per cell size.

        Returns
        -------
        origin : (2,) int ndarray
            Cell (x, y) of bucket (0, 0).
        width, height : int
        start : (width height + 1,) int ndarray
            Bucket ``q = row width + col`` lists ``owner[start[q]:start[q + 1]]``.
        owner : int ndarray
            Indices into `pieces`.
        pieces : (n, 2, 2) ndarray

        Examples
        --------
        >>> idx = SegmentIndex(np.array([[[0, 0], [3, 0]]], float), 1.0)
        >>> origin, w, h, start, owner, pieces = idx.piece_buckets(2.0)
        >>> origin.tolist(), (w, h), len(pieces), int(start[-1])
        ([-1, -1], (4, 3), 2, 21)
        """
        cached = getattr(self, "_piece_cache", None)
        if cached is not None and cached[0] == cell:
            return cached[1]
        cell = float(cell)
        pieces, _ = split_segments(self.segments, cell)
        origin, width, height, start, owner = _bucketed(pieces.min(axis=1), pieces.max(axis=1), cell)
        out = (origin, width, height, start, owner, np.ascontiguousarray(pieces))
        self._piece_cache = (cell, out)
        return out

    def _near(self, q: np.ndarray, reach: float):
        """Exact nearest segments of points within `reach` of one, from the buckets (`_buckets`).
        A point farther than `reach` from every candidate gets inf. None if the buckets would
        hold too many candidates, or the points would get too many."""
        buckets = self._buckets(reach)
        if buckets is None:
            return None
        cell, origin, width, height, listed, owner = buckets
        qb = np.floor(q / cell).astype(np.int64) - origin
        inside = (qb[:, 0] >= 0) & (qb[:, 0] < width) & (qb[:, 1] >= 0) & (qb[:, 1] < height)
        # A point outside the buckets is farther than a cell from every segment: no candidates.
        qk = np.where(inside, qb[:, 1] * width + qb[:, 0], 0)
        start = listed[qk]
        count = np.where(inside, listed[qk + 1] - start, 0)
        if count.sum() > 64 * len(q) + 4096:
            return None
        from .segment_kernels import nearest_in_buckets
        # One compiled loop over each point's candidates: the first reaching the smallest wins.
        dist, best, tt = nearest_in_buckets(q, start, count, owner, self.segments)
        far = dist > reach
        dist[far] = np.inf
        return dist, best, tt

    def __len__(self) -> int:
        return len(self.segments)

    def within(self, points, reach: float) -> np.ndarray | None:
        """Distance from each point to the nearest segment where it is within `reach`, inf beyond;
        from the buckets alone (`nearest` with a `reach`), or None when they would not serve (short
        segments, or many candidates a point): `nearest` then answers, with a k-d tree.

        Examples
        --------
        >>> idx = SegmentIndex(np.array([[[0, 0], [10, 0]]], float), 1.0)
        >>> idx.within(np.array([[3.0, 0.5], [3.0, 2.0]]), 1.0).tolist()
        [0.5, inf]
        """
        q = np.asarray(points, np.float64).reshape(-1, 2)
        if len(self.segments) == 0 or len(q) == 0:
            return np.full(len(q), np.inf)
        near = self._near(q, reach)
        return None if near is None else near[0]

    def nearest(self, points, reach: float | None = None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Distance to the nearest segment, its index, and the parameter (0..1) of the nearest point.

        Parameters
        ----------
        points : (n, 2) array_like
        reach : float, optional
            Points within `reach` of a segment are answered from the segments
            near them (buckets of that size), the others by the k-d tree: faster
            when most points are that near and segments are long. The answers
            are the same.

        Returns
        -------
        dist : (n,) ndarray
            inf for every point when there is no segment.
        segment : (n,) int ndarray
        t : (n,) ndarray
            The nearest point is ``a + t (b - a)`` on segment (a, b).
        """
        q = np.asarray(points, np.float64).reshape(-1, 2)
        n = len(self.segments)
        dist = np.full(len(q), np.inf)
        best = np.zeros(len(q), np.int64)
        if n == 0 or len(q) == 0:
            return dist, best, np.zeros(len(q))
        todo = np.arange(len(q))
        near = self._near(q, reach) if reach is not None and reach > 0 else None
        if near is not None:
            dist, known, t0 = near
            found = np.isfinite(dist)
            if found.all():
                return dist, known, t0
            todo = np.flatnonzero(~found)
        tree = np.zeros(len(q), bool)
        tree[todo] = True
        pa, pd, inv_len2, owner, half, kd = self._pieces
        n = len(pa)
        k = min(8, n)
        while len(todo):  # a few rounds: k doubles for the points not yet settled
            dm, im = kd.query(q[todo], k=k)
            if k == 1:
                dm, im = dm[:, None], im[:, None]
            qx, qy = q[todo, 0, None], q[todo, 1, None]
            wx, wy = qx - pa[im, 0], qy - pa[im, 1]
            dx, dy = pd[im, 0], pd[im, 1]
            tt = np.clip((wx * dx + wy * dy) * inv_len2[im], 0.0, 1.0)
            ex, ey = wx - tt * dx, wy - tt * dy
            e2 = ex * ex + ey * ey
            a = np.argmin(e2, axis=1)
            r = np.arange(len(todo))
            eb = np.sqrt(e2[r, a])
            dist[todo], best[todo] = eb, im[r, a]
            done = (eb <= dm[:, -1] - half) | (k >= n)
            todo = todo[~done]
            k = min(2 * k, n)
        seg = owner[best]
        if near is not None:
            seg = np.where(tree, seg, known)
        s = self.segments[seg]
        d = s[:, 1] - s[:, 0]
        t = np.clip(np.einsum("ij,ij->i", q - s[:, 0], d) / np.maximum(np.einsum("ij,ij->i", d, d), 1e-300),
                    0.0, 1.0)
        return dist, seg, t
