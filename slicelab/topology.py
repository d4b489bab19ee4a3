"""Exact vertex welding and edge tables, without rounding and without loops.

Two points are the same vertex only when their coordinates are bit-for-bit
equal (``-0.0`` and ``0.0`` count as equal). Rows are hashed to 64 bits, sorted
once, and the hash groups are verified against the full rows, so a hash
collision can never merge two different vertices.
"""
from __future__ import annotations

import numpy as np

__all__ = ["exact_ids", "weld", "edge_table", "shells"]

# Odd 64-bit multipliers (from splitmix64 / xxhash) for mixing columns.
_MULT = np.array(
    [0x9E3779B97F4A7C15, 0xC2B2AE3D27D4EB4F, 0x165667B19E3779F9, 0x27D4EB2F165667C5,
     0x85EBCA77C2B2AE63, 0xFF51AFD7ED558CCD, 0xC4CEB9FE1A85EC53, 0x94D049BB133111EB],
    dtype=np.uint64,
)


def _fmix(h: np.ndarray) -> np.ndarray:
    # splitmix64 finaliser, in place: a bijection that spreads every bit over the word.
    h ^= h >> np.uint64(31)
    h *= _MULT[5]
    h ^= h >> np.uint64(29)
    h *= _MULT[7]
    h ^= h >> np.uint64(32)
    return h


def _row_hash(rows: np.ndarray) -> np.ndarray:
    bits = rows if rows.dtype == np.uint64 else rows.view(np.uint64)
    with np.errstate(over="ignore"):
        h = _fmix(bits[:, 0].copy())
        for j in range(1, rows.shape[1]):  # a handful of columns, not rows
            h *= _MULT[j % len(_MULT)]
            h += bits[:, j]
            _fmix(h)
    return h


def _row_hash32(rows: np.ndarray) -> np.ndarray:
    # float32 columns two by two fill 64-bit words exactly; the words are hashed as usual.
    bits = rows.view(np.uint32)
    if bits.shape[1] % 2:
        bits = np.hstack([bits, np.zeros((len(bits), 1), np.uint32)])
    words = np.ascontiguousarray(bits).view(np.uint64)
    return _row_hash(words)


def exact_ids(rows: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Number identical rows of a float or integer table.

    Rows are sorted by a hash with the row index packed into the low bits of
    the same 64-bit word, which lets numpy's fast value sort stand in for an
    argsort. Groups are then verified against the full rows; the rare groups
    where different rows share a hash are renumbered exactly.

    Parameters
    ----------
    rows : (m, k) ndarray of float64 or int64

    Returns
    -------
    ids : (m,) int64 ndarray
        Equal rows get equal ids, numbered 0 .. u-1 (in no particular order).
    first : (u,) int64 ndarray
        Index of the first row of each id.

    Examples
    --------
    >>> ids, first = exact_ids(np.array([[0.0, 1.0], [2.0, 3.0], [-0.0, 1.0]]))
    >>> bool(ids[0] == ids[2]), bool(ids[0] != ids[1]), sorted(first.tolist())
    (True, True, [0, 1])
    """
    rows = np.ascontiguousarray(rows)
    if rows.ndim == 1:
        rows = rows[:, None]
    if rows.dtype.kind == "f":
        rows = np.ascontiguousarray(rows.astype(np.float64, copy=False) + 0.0)  # folds -0.0 into 0.0
        narrow = rows.astype(np.float32) if rows.shape[1] > 3 else None
        if narrow is not None and np.array_equal(narrow, rows):
            # Wide key tables of float32 values (read from STL): hash half the words. Not worth the
            # extra pass for three columns.
            rows = narrow
    else:
        rows = np.ascontiguousarray(rows.astype(np.int64, copy=False))
    m = len(rows)
    if m == 0:
        return np.zeros(0, np.int64), np.zeros(0, np.int64)
    shift = np.uint64(max(int(m - 1).bit_length(), 1))
    low = (np.uint64(1) << shift) - np.uint64(1)
    h = _row_hash32(rows) if rows.dtype == np.float32 else _row_hash(rows)
    packed = (h & ~low) | np.arange(m, dtype=np.uint64)
    del h
    packed.sort()
    order = (packed & low).astype(np.int64)
    hs = packed >> shift
    del packed
    srt = np.take(rows, order, axis=0)
    new = np.empty(m, dtype=bool)
    new[0] = True
    np.not_equal(hs[1:], hs[:-1], out=new[1:])
    group = np.cumsum(new) - 1
    # Within a hash group every row must equal its neighbour; a mismatch is a collision.
    diff = srt[1:] != srt[:-1]
    clash = ~new[1:] & (diff.any(axis=1) if diff.ndim == 2 else diff)
    if clash.any():
        # Truncated hashes collide now and then in big tables: split only those groups, exactly.
        # The rows of one colliding group that match its first row keep the group's id; every
        # other distinct row in it gets a new id after the last one (ids stay 0 .. u-1).
        bad_group = np.zeros(int(group[-1]) + 1, dtype=bool)
        bad_group[group[1:][clash]] = True
        pos = np.flatnonzero(bad_group[group])
        _, sub = np.unique(srt[pos], axis=0, return_inverse=True)
        sub = sub.reshape(-1)
        _, sub_first = np.unique(sub, return_index=True)
        sub_group = group[pos][sub_first]
        by_group = np.lexsort((sub_first, sub_group))  # within a group, the sub seen first leads
        lead = np.ones(len(by_group), dtype=bool)
        lead[1:] = sub_group[by_group][1:] != sub_group[by_group][:-1]
        new_id = np.empty(len(by_group), dtype=np.int64)
        new_id[by_group[lead]] = sub_group[by_group[lead]]
        n_groups = int(group[-1]) + 1
        new_id[by_group[~lead]] = n_groups + np.arange(int((~lead).sum()))
        group[pos] = new_id[sub]
    ids = np.empty(m, dtype=np.int64)
    ids[order] = group
    first = np.empty(int(group.max()) + 1, dtype=np.int64)
    # Within every id the sorted positions hold ascending row indices, so writing them in
    # reverse leaves each id's lowest row last, and last writes win.
    first[group[::-1]] = order[::-1]
    return ids, first


def weld(triangles: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Weld identical corners into shared vertices.

    Parameters
    ----------
    triangles : (n, 3, 3) ndarray

    Returns
    -------
    vertices : (v, 3) float64 ndarray
    faces : (n, 3) int64 ndarray

    Examples
    --------
    >>> t = np.array([[[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[1, 0, 0], [1, 1, 0], [0, 1, 0]]], float)
    >>> v, f = weld(t)
    >>> len(v), v[f].tolist() == t.tolist(), bool(f[0, 1] == f[1, 0])
    (4, True, True)
    """
    flat = np.asarray(triangles, dtype=np.float64).reshape(-1, 3)
    ids, first = exact_ids(flat)
    return flat[first], ids.reshape(-1, 3)


def edge_table(faces: np.ndarray) -> dict[str, np.ndarray]:
    """Undirected edges of a welded mesh and how often each is used.

    Parameters
    ----------
    faces : (n, 3) int ndarray

    Returns
    -------
    dict
        ``inverse`` (3n,) edge id of each facet edge (edge i of facet f is
        ``3 f + i``, from corner i to corner i+1); ``first`` and ``last`` (e,)
        the lowest and highest facet edge of each id; ``counts`` (e,) facet
        edges per id;
        ``forward`` (3n,) True when the facet edge runs from the lower to the
        higher vertex id.

    Examples
    --------
    >>> t = edge_table(np.array([[0, 1, 2], [0, 2, 3]]))
    >>> sorted(t["counts"].tolist())
    [1, 1, 1, 1, 2]
    """
    f = np.asarray(faces, dtype=np.int64)
    a = f.reshape(-1)
    b = f[:, [1, 2, 0]].reshape(-1)
    nv = int(f.max()) + 1 if f.size else 1
    if nv < 3_000_000_000:  # (lo, hi) packs into one int64 exactly
        inverse, first = exact_ids(np.minimum(a, b) * nv + np.maximum(a, b))
    else:
        inverse, first = exact_ids(np.stack([np.minimum(a, b), np.maximum(a, b)], axis=1))
    counts = np.bincount(inverse, minlength=len(first))
    last = np.empty(len(first), dtype=np.int64)
    last[inverse] = np.arange(len(inverse))  # in order, so each edge's highest facet edge is written last
    return {"inverse": inverse, "first": first, "last": last, "counts": counts, "forward": a < b}


def shells(faces: np.ndarray, edges: dict | None = None) -> tuple[int, np.ndarray]:
    """Edge-connected shells of a welded mesh: their number and each facet's shell.

    Parameters
    ----------
    faces : (n, 3) int ndarray
    edges : dict, optional
        `edge_table(faces)`, when already computed.

    Returns
    -------
    count : int
    labels : (n,) int ndarray
        Shell of each facet, numbered 0 .. count-1.

    Examples
    --------
    >>> shells(np.array([[0, 1, 2], [0, 2, 3], [4, 5, 6]]))[1].tolist()
    [0, 0, 1]
    """
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components
    f = np.asarray(faces, dtype=np.int64)
    n = len(f)
    if n == 0:
        return 0, np.zeros(0, np.int64)
    et = edge_table(f) if edges is None else edges
    first, last, counts, inverse = et["first"], et["last"], et["counts"], et["inverse"]
    # Each edge links the facets of its lowest and highest facet edge; an edge of three facets
    # or more (rare) also links every facet edge to its lowest one.
    a, b = first // 3, last // 3
    many = np.flatnonzero(counts[inverse] > 2)
    if len(many):
        a = np.concatenate([a, first[inverse[many]] // 3])
        b = np.concatenate([b, many // 3])
    graph = coo_matrix((np.ones(len(a), dtype=np.int8), (a, b)), shape=(n, n))
    count, labels = connected_components(graph, directed=False)
    return int(count), labels.astype(np.int64)
