"""Chaining oriented segments into loops, and joining the open chains of broken scans.

Segments are chained by topology: each end point carries an integer key (the
mesh edge or the in-plane vertex it lies on), so chaining is a match of keys
(a hash table), never a comparison of rounded coordinates, and one compiled
walk along the chains (`slicelab.geometry.graph_kernels.chain_keys`). Open
chains, as an open scan leaves them, are joined across small gaps by a k-d
tree of their ends.

See Also
--------
slicelab.geometry.polygons : signed areas and the hole hierarchy of the loops.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["Chains", "chain_segments", "join_open_chains"]


@dataclass(frozen=True)
class Chains:
    """Segments grouped into chains, in walking order.

    Attributes
    ----------
    order : (m,) int ndarray
        Segment indices, chain after chain, each chain in walking order.
    bounds : (c + 1,) int ndarray
        Chain k is ``order[bounds[k]:bounds[k + 1]]``.
    closed : (c,) bool ndarray
        Whether the chain's last segment ends where its first begins.
    """

    order: np.ndarray
    bounds: np.ndarray
    closed: np.ndarray

    def __len__(self) -> int:
        return len(self.closed)


def chain_segments(start_key: np.ndarray, end_key: np.ndarray) -> Chains:
    """Chain segments whose end key equals another's start key.

    Where several segments meet at one key (an in-plane vertex touched twice),
    the k-th segment ending there goes on to the k-th starting there (both in
    index order). Chains come in the order of their lowest segment; a cycle
    starts at its lowest segment.

    Parameters
    ----------
    start_key, end_key : (m,) int ndarray
        Topological key of each segment's start and end point.

    Returns
    -------
    Chains

    See Also
    --------
    slicelab.geometry.graph_kernels.chain_keys : the compiled pass that chains them.

    Examples
    --------
    >>> c = chain_segments(np.array([0, 2, 1, 5]), np.array([1, 0, 2, 6]))
    >>> c.order.tolist(), c.bounds.tolist(), c.closed.tolist()
    ([0, 2, 1, 3], [0, 3, 4], [True, False])
    """
    from .graph_kernels import chain_keys
    start_key = np.ascontiguousarray(start_key, dtype=np.int64).reshape(-1)
    end_key = np.ascontiguousarray(end_key, dtype=np.int64).reshape(-1)
    if len(start_key) != len(end_key):
        raise ValueError("start_key and end_key must have the same length")
    order, bounds, closed = chain_keys(start_key, end_key)
    return Chains(order, bounds, closed)


def join_open_chains(chains: list[np.ndarray], max_gap: float) -> tuple[list, list, np.ndarray]:
    """Join open chains end to start where the gap is at most `max_gap`.

    Nearest ends are joined first; a chain may close on itself.

    Parameters
    ----------
    chains : list of (k, 2) ndarray
        Open polylines, each oriented (material on the left).
    max_gap : float
        Largest gap bridged, in mm.

    Returns
    -------
    loops : list of (k, 2) ndarray
        Chains that closed once joined (implicitly closed).
    still_open : list of (k, 2) ndarray
    gaps : (j,) ndarray
        Length of every gap bridged.

    Examples
    --------
    >>> a = np.array([[0, 0], [1, 0], [1, 1]], float)
    >>> b = np.array([[0.9, 1.05], [0, 1], [0, 0.05]], float)
    >>> loops, still, gaps = join_open_chains([a, b], 0.2)
    >>> len(loops), len(still), np.round(gaps, 3).tolist()
    (1, 0, [0.05, 0.112])
    """
    n = len(chains)
    if n == 0 or max_gap <= 0:
        return [], list(chains), np.zeros(0)
    from scipy.spatial import cKDTree
    ends = np.array([c[-1] for c in chains])
    starts = np.array([c[0] for c in chains])
    pairs = cKDTree(ends).sparse_distance_matrix(cKDTree(starts), max_gap, output_type="ndarray")
    nxt = np.full(n, -1)
    taken = np.zeros(n, dtype=bool)
    gaps = []
    for k in np.argsort(pairs["v"], kind="stable"):  # over candidate joins, few
        i, j = int(pairs["i"][k]), int(pairs["j"][k])
        if nxt[i] < 0 and not taken[j]:
            nxt[i], taken[j] = j, True
            gaps.append(float(pairs["v"][k]))
    loops, still, seen = [], [], np.zeros(n, dtype=bool)
    for head in [i for i in range(n) if not taken[i]] + list(range(n)):
        if seen[head]:
            continue
        walk, k = [], head
        while k >= 0 and not seen[k]:
            seen[k] = True
            walk.append(k)
            k = nxt[k]
        pts = np.concatenate([chains[w] for w in walk])
        if k == head:
            loops.append(pts)
        else:
            still.append(pts)
    return loops, still, np.array(gaps)


