"""Chaining oriented segments into loops, and joining the open chains of broken scans.

Segments are chained by topology: each end point carries an integer key (the
mesh edge or the in-plane vertex it lies on), so chaining is a sort and a
match of keys, never a comparison of rounded coordinates. Ordering the chains
uses list ranking by pointer jumping: about log2(longest loop) vectorised
passes, no Python loop over segments.

See Also
--------
slicelab.geometry.polygons : signed areas and the hole hierarchy of the loops.

References
----------
.. [1] J. C. Wyllie, "The complexity of parallel computations", PhD thesis,
   Cornell University, 1979 (list ranking by pointer jumping).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .graphs import graph_components

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


def _match(start_key: np.ndarray, end_key: np.ndarray) -> np.ndarray:
    """next[i] = a segment starting where segment i ends, or -1.

    Where several segments meet at one key (an in-plane vertex touched twice)
    the k-th arrival is paired with the k-th departure.
    """
    m = len(start_key)
    n_keys = int(max(start_key.max(), end_key.max())) + 1 if m else 0
    if n_keys <= 4 * m + 16:
        count_s = np.bincount(start_key, minlength=n_keys)
        if count_s.max() <= 1 and np.bincount(end_key, minlength=n_keys).max() <= 1:
            # Dense keys met at most once (the common case): a lookup table, no sort.
            seg_of = np.full(n_keys, -1, dtype=np.int64)
            seg_of[start_key] = np.arange(m)
            return seg_of[end_key]
    os_ = np.argsort(start_key, kind="stable")
    oe = np.argsort(end_key, kind="stable")
    ss, se = start_key[os_], end_key[oe]
    first_s = np.searchsorted(ss, se, side="left")
    count_s = np.searchsorted(ss, se, side="right") - first_s
    first_e = np.searchsorted(se, se, side="left")
    rank = np.arange(m) - first_e
    ok = rank < count_s
    nxt = np.full(m, -1, dtype=np.int64)
    nxt[oe[ok]] = os_[first_s[ok] + rank[ok]]
    return nxt


def chain_segments(start_key: np.ndarray, end_key: np.ndarray) -> Chains:
    """Chain segments whose end key equals another's start key.

    Parameters
    ----------
    start_key, end_key : (m,) int ndarray
        Topological key of each segment's start and end point.

    Returns
    -------
    Chains

    Examples
    --------
    >>> c = chain_segments(np.array([0, 2, 1, 5]), np.array([1, 0, 2, 6]))
    >>> c.order.tolist(), c.bounds.tolist(), c.closed.tolist()
    ([0, 2, 1, 3], [0, 3, 4], [True, False])
    """
    m = len(start_key)
    if m == 0:
        return Chains(np.zeros(0, np.int64), np.zeros(1, np.int64), np.zeros(0, bool))
    nxt = _match(np.asarray(start_key), np.asarray(end_key))
    has = nxt >= 0
    prv = np.full(m, -1, dtype=np.int64)
    prv[nxt[has]] = np.flatnonzero(has)
    src = np.flatnonzero(has)
    n_comp, comp = graph_components(m, src, nxt[has])

    # A chain starts at its segment without predecessor; a cycle is cut at its lowest index.
    heads_open = np.flatnonzero(prv < 0)
    is_open = np.zeros(n_comp, dtype=bool)
    is_open[comp[heads_open]] = True
    lowest = np.full(n_comp, m, dtype=np.int64)
    np.minimum.at(lowest, comp, np.arange(m))
    cyc_heads = lowest[~is_open]
    tail = nxt.copy()
    tail[prv[cyc_heads]] = -1  # break each cycle just before its head

    # List ranking: distance of each segment to the end of its chain.
    dist = (tail >= 0).astype(np.int64)
    jump = tail.copy()
    active = np.flatnonzero(jump >= 0)
    while len(active):
        j = jump[active]
        dist[active] += dist[j]
        jump[active] = jump[j]
        active = active[jump[active] >= 0]

    # Chain after chain, each from its head (largest distance to the end) to its tail: a scatter.
    counts = np.bincount(comp, minlength=n_comp)
    bounds = np.concatenate([[0], np.cumsum(counts)])
    order = np.empty(m, dtype=np.int64)
    order[bounds[comp] + counts[comp] - 1 - dist] = np.arange(m)
    return Chains(order.astype(np.int64), bounds.astype(np.int64), ~is_open)


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


