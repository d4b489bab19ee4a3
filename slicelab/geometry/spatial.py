"""Segments in the plane: equal pieces, and exact nearest distances through a k-d tree.

See Also
--------
slicelab.toolpath.distance : exact distance fields measured with `SegmentIndex`.
"""
from __future__ import annotations

import numpy as np

from .ragged import within_group

__all__ = ["split_segments", "SegmentIndex"]


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

    def __init__(self, segments: np.ndarray, piece: float):
        from scipy.spatial import cKDTree
        seg = np.asarray(segments, np.float64).reshape(-1, 2, 2)
        self.segments = seg
        d = seg[:, 1] - seg[:, 0]
        length = np.hypot(d[:, 0], d[:, 1])
        pieces, owner = split_segments(seg, piece)
        k = np.bincount(owner, minlength=len(seg))
        self.pa, self.pb = pieces[:, 0], pieces[:, 1]
        self.piece_segment = owner
        self.pd = self.pb - self.pa
        self.inv_len2 = 1.0 / np.maximum(np.einsum("ij,ij->i", self.pd, self.pd), 1e-300)
        self.half = float(0.5 * (length / k).max()) if len(seg) else 0.0
        self.tree = cKDTree(0.5 * (self.pa + self.pb)) if len(seg) else None

    def __len__(self) -> int:
        return len(self.segments)

    def nearest(self, points) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Distance to the nearest segment, its index, and the parameter (0..1) of the nearest point.

        Parameters
        ----------
        points : (n, 2) array_like

        Returns
        -------
        dist : (n,) ndarray
            inf for every point when there is no segment.
        segment : (n,) int ndarray
        t : (n,) ndarray
            The nearest point is ``a + t (b - a)`` on segment (a, b).
        """
        q = np.asarray(points, np.float64).reshape(-1, 2)
        n = len(self.pa)
        dist = np.full(len(q), np.inf)
        best = np.zeros(len(q), np.int64)
        if n == 0 or len(q) == 0:
            return dist, best, np.zeros(len(q))
        todo = np.arange(len(q))
        k = min(8, n)
        while len(todo):  # a few rounds: k doubles for the points not yet settled
            dm, im = self.tree.query(q[todo], k=k)
            if k == 1:
                dm, im = dm[:, None], im[:, None]
            qx, qy = q[todo, 0, None], q[todo, 1, None]
            wx, wy = qx - self.pa[im, 0], qy - self.pa[im, 1]
            dx, dy = self.pd[im, 0], self.pd[im, 1]
            tt = np.clip((wx * dx + wy * dy) * self.inv_len2[im], 0.0, 1.0)
            ex, ey = wx - tt * dx, wy - tt * dy
            e2 = ex * ex + ey * ey
            a = np.argmin(e2, axis=1)
            r = np.arange(len(todo))
            eb = np.sqrt(e2[r, a])
            dist[todo], best[todo] = eb, im[r, a]
            done = (eb <= dm[:, -1] - self.half) | (k >= n)
            todo = todo[~done]
            k = min(2 * k, n)
        seg = self.piece_segment[best]
        s = self.segments[seg]
        d = s[:, 1] - s[:, 0]
        t = np.clip(np.einsum("ij,ij->i", q - s[:, 0], d) / np.maximum(np.einsum("ij,ij->i", d, d), 1e-300),
                    0.0, 1.0)
        return dist, seg, t
