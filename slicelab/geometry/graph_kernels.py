"""Compiled loops over graphs and pixel sets: connected components by union-find, and thinning.

Small algorithms that every print plan and mesh check runs, compiled here so
that a command never imports SciPy or scikit-image for them (their imports
would add to every command's start-up: `scripts/bench_slice.py` prints by how
much).

- `label_components` labels the connected components of an undirected
  graph given by its edge list, as ``scipy.sparse.csgraph.connected_components``
  does (the same labels: components numbered in the order of their lowest node).
- `chain_keys` chains segments whose end key is another's start key into
  paths and cycles, walking each from its head: the list ranking of
  `slicelab.geometry.chain_segments` as one pass over the segments, the keys
  matched in a hash table instead of by sorting.
- `thin_pixels` thins a binary image to a one-pixel skeleton by a
  two-subiteration parallel algorithm driven by a table of the 256
  neighbourhoods (`slicelab.geometry.graphs.GUO_HALL` is Guo and Hall's [2]_).
- `skeleton_chains` walks a skeleton's pixel links into chains that meet at
  junctions (`slicelab.geometry.contours.trace_skeleton`): a gap along a wall
  200 mm long is a skeleton of thousands of pixels on every layer.

See Also
--------
slicelab.geometry.graphs : the functions that call them and say what the results mean.

References
----------
.. [1] R. E. Tarjan, "Efficiency of a good but not linear set union
   algorithm", Journal of the ACM 22(2), 1975.
.. [2] Z. Guo, R. W. Hall, "Parallel thinning with two-subiteration
   algorithms", Communications of the ACM 32(3), 1989.
"""
from __future__ import annotations

import numpy as np

from .compiled import njit

__all__ = ["label_components", "chain_keys", "thin_pixels", "skeleton_chains", "warm"]


@njit(cache=True, nogil=True)
def _root(parent, x):
    """The root of x's tree, halving the path on the way (each node then points to its grandparent)."""
    while parent[x] != x:
        parent[x] = parent[parent[x]]
        x = parent[x]
    return x


@njit(cache=True, nogil=True)
def label_components(n, a, b):
    """Connected components of the undirected graph on nodes 0..n-1 with edges (a[k], b[k]).

    Union-find [1]_, each tree rooted at its lowest node, so that one pass in
    node order numbers the components in the order of their lowest node.
    Every a[k], b[k] must lie in [0, n) (the caller checks).

    Returns
    -------
    count : int
    labels : (n,) int64 ndarray
    """
    parent = np.arange(n)
    for k in range(len(a)):  # over edges
        x = _root(parent, a[k])
        y = _root(parent, b[k])
        if x < y:
            parent[y] = x
        elif y < x:
            parent[x] = y
    labels = np.empty(n, np.int64)
    count = 0
    for v in range(n):  # a root comes before every other node of its tree
        r = _root(parent, v)
        if r == v:
            labels[v] = count
            count += 1
        else:
            labels[v] = labels[r]
    return count, labels


@njit(cache=True, nogil=True)
def chain_keys(start_key, end_key):
    """Chain segments: segment i goes on to a segment that starts where it ends (keys equal).

    Where several segments start at one key, the k-th segment (in index order) that
    ends there goes on to the k-th that starts there. The chains are numbered in the
    order of their lowest segment; an open chain starts at its segment that nothing
    leads to, a cycle at its lowest segment.

    Parameters
    ----------
    start_key, end_key : (m,) int64 ndarrays

    Returns
    -------
    order : (m,) int64 ndarray
        Segment indices, chain after chain, each chain in walking order.
    bounds : (c + 1,) int64 ndarray
        Chain k is ``order[bounds[k]:bounds[k + 1]]``.
    closed : (c,) bool ndarray
    """
    m = len(start_key)
    size, bits = 4, 2
    while size < 2 * m:  # a table at most half full
        size *= 2
        bits += 1
    shift = np.uint64(64 - bits)
    mult = np.uint64(0x9E3779B97F4A7C15)  # Fibonacci hashing: the key's high bits, well mixed
    mask = size - 1
    slot_key = np.empty(size, np.int64)
    used = np.zeros(size, np.bool_)
    first = np.full(size, -1, np.int64)  # each slot's segments starting there, lowest first
    after = np.full(m, -1, np.int64)
    for i in range(m - 1, -1, -1):  # over segments, highest first: each list comes out ascending
        key = start_key[i]
        h = np.int64((np.uint64(key) * mult) >> shift)
        while used[h] and slot_key[h] != key:
            h = (h + 1) & mask
        used[h] = True
        slot_key[h] = key
        after[i] = first[h]
        first[h] = i
    nxt = np.full(m, -1, np.int64)
    prv = np.full(m, -1, np.int64)
    for i in range(m):  # over segments in order: the k-th arrival takes the k-th departure
        key = end_key[i]
        h = np.int64((np.uint64(key) * mult) >> shift)
        while used[h] and slot_key[h] != key:
            h = (h + 1) & mask
        if used[h] and first[h] >= 0:
            j = first[h]
            first[h] = after[j]
            nxt[i] = j
            prv[j] = i
    order = np.empty(m, np.int64)
    bounds = np.empty(m + 1, np.int64)
    closed = np.empty(m, np.bool_)
    seen = np.zeros(m, np.bool_)
    n = c = 0
    bounds[0] = 0
    for v in range(m):  # the lowest segment of each chain comes first
        if seen[v]:
            continue
        head = v
        while prv[head] >= 0 and prv[head] != v:  # back to the head of an open chain, or round a cycle
            head = prv[head]
        cycle = prv[head] == v
        if cycle:
            head = v
        k = head
        while k >= 0 and not seen[k]:
            seen[k] = True
            order[n] = k
            n += 1
            k = nxt[k]
        closed[c] = cycle
        c += 1
        bounds[c] = n
    return order, bounds[:c + 1], closed[:c]


@njit(cache=True, nogil=True)
def _code(image, r, c, h, w):
    """The 8 neighbours of pixel (r, c) as bits: N, NE, E, SE, S, SW, W, NW from bit 0 (0 off the image)."""
    code = 0
    bit = 0
    for dr, dc in ((-1, 0), (-1, 1), (0, 1), (1, 1), (1, 0), (1, -1), (0, -1), (-1, -1)):
        i, j = r + dr, c + dc
        if 0 <= i < h and 0 <= j < w and image[i, j]:
            code |= 1 << bit
        bit += 1
    return code


@njit(cache=True, nogil=True)
def thin_pixels(image, table):
    """Thin a 0/1 uint8 image in place to a one-pixel skeleton; returns the passes made.

    Each iteration makes two subiterations; a subiteration s (1, 2) removes,
    at once, every set pixel whose neighbourhood code (`_code`) has bit s of
    ``table[code]`` set, judged on the image as it was when the subiteration
    began. Iterations go on until one removes nothing. Only set pixels are
    visited: the cost follows the pixels and the passes, not the image's size.
    """
    h, w = image.shape
    rows, cols = np.nonzero(image)
    alive = len(rows)
    drop = np.empty(alive, np.bool_)
    passes = 0
    removed = True
    while removed:
        removed = False
        for step in (1, 2):  # the two subiterations
            passes += 1
            hit = False
            for k in range(alive):  # over the pixels still set
                drop[k] = (table[_code(image, rows[k], cols[k], h, w)] & step) != 0
                hit |= drop[k]
            if not hit:
                continue
            removed = True
            m = 0
            for k in range(alive):  # remove the marked pixels, keep the rest in order
                if drop[k]:
                    image[rows[k], cols[k]] = 0
                else:
                    rows[m], cols[m] = rows[k], cols[k]
                    m += 1
            alive = m
    return passes


@njit(cache=True, nogil=True)
def _walk(nbr, seen, start, buf):
    """Walk from `start` along unseen neighbours (each pixel's first, in `nbr`'s order) until
    none is left, marking them seen; the pixels in `buf`, their count returned."""
    buf[0] = start
    seen[start] = True
    prev, cur, k = -1, start, 1
    while True:
        nxt = -1
        for t in range(nbr.shape[1]):
            j = nbr[cur, t]
            if j >= 0 and j != prev and not seen[j]:
                nxt = j
                break
        if nxt < 0:
            return k
        prev, cur = cur, nxt
        seen[cur] = True
        buf[k] = cur
        k += 1


@njit(cache=True, nogil=True)
def _junction_beside(nbr, junction, i):
    """The first neighbour of pixel i that is a junction, or -1."""
    for t in range(nbr.shape[1]):
        j = nbr[i, t]
        if j >= 0 and junction[j]:
            return j
    return -1


@njit(cache=True, nogil=True)
def skeleton_chains(nbr, deg):
    """Chains of a skeleton's pixels, meeting at junctions.

    Parameters
    ----------
    nbr : (n, 8) int64 ndarray
        Each pixel's neighbours (indices, -1 where none), in the order the walks try them.
    deg : (n,) int64 ndarray
        Each pixel's neighbour count.

    Returns
    -------
    pixels, bounds : int64 ndarrays
        Chain c is ``pixels[bounds[c]:bounds[c + 1]]`` (at least two pixels each).

    Chains start at their ends (pixels of one neighbour, in index order), then at the pixels
    not yet walked (inside chains whose ends are junctions, and cycles, walked both ways from
    there; a cycle comes back to its first pixel). Junction pixels (three neighbours or more)
    are never walked through: each chain takes the junction beside each of its ends.
    """
    n = nbr.shape[0]
    junction = np.zeros(n, np.bool_)
    seen = np.zeros(n, np.bool_)
    order = np.empty(n, np.int64)
    k = 0
    for i in range(n):
        junction[i] = deg[i] >= 3
        seen[i] = junction[i]
        if deg[i] == 1:
            order[k] = i
            k += 1
    for i in range(n):
        if deg[i] != 1:
            order[k] = i
            k += 1
    fwd = np.empty(n, np.int64)
    back = np.empty(n, np.int64)
    path = np.empty(n + 1, np.int64)
    out = np.empty(4 * n + 4, np.int64)
    bounds = np.zeros(n + 1, np.int64)
    m = 0
    chains = 0
    for q in range(n):
        s = order[q]
        if seen[s]:
            continue
        lf = _walk(nbr, seen, s, fwd)
        lp = 0
        if deg[s] != 1:  # started inside a chain: the other way too
            lb = _walk(nbr, seen, s, back)
            for t in range(lb - 1, 0, -1):
                path[lp] = back[t]
                lp += 1
        for t in range(lf):
            path[lp] = fwd[t]
            lp += 1
        if deg[s] == 2 and lp > 2:  # a cycle: back to its first pixel
            for t in range(nbr.shape[1]):
                if nbr[path[lp - 1], t] == path[0]:
                    path[lp] = path[0]
                    lp += 1
                    break
        ja = _junction_beside(nbr, junction, path[0])
        jb = _junction_beside(nbr, junction, path[lp - 1])
        if lp + (ja >= 0) + (jb >= 0) < 2:
            continue
        if ja >= 0:
            out[m] = ja
            m += 1
        for t in range(lp):
            out[m] = path[t]
            m += 1
        if jb >= 0:
            out[m] = jb
            m += 1
        chains += 1
        bounds[chains] = m
    return out[:m], bounds[:chains + 1]


def warm() -> None:
    """Call every kernel once with the types its callers pass (see `slicelab.geometry.kernels.warm`).

    Examples
    --------
    >>> warm()
    """
    label_components(1, np.zeros(0, np.int64), np.zeros(0, np.int64))
    chain_keys(np.zeros(0, np.int64), np.zeros(0, np.int64))
    thin_pixels(np.zeros((1, 1), np.uint8), np.zeros(256, np.uint8))
    skeleton_chains(np.full((1, 8), -1, np.int64), np.zeros(1, np.int64))
