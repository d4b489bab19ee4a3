"""Exact vertex welding and edge tables, without rounding and without loops.

Two points are the same vertex only when their coordinates are bit-for-bit
equal (``-0.0`` and ``0.0`` count as equal). Rows are hashed to 64 bits, sorted
once, and the hash groups are verified against the full rows, so a hash
collision can never merge two different vertices.
"""
from __future__ import annotations

import numpy as np

__all__ = ["exact_ids", "weld", "edge_table"]

# Odd 64-bit multipliers (from splitmix64 / xxhash) for mixing columns.
_MULT = np.array(
    [0x9E3779B97F4A7C15, 0xC2B2AE3D27D4EB4F, 0x165667B19E3779F9, 0x27D4EB2F165667C5,
     0x85EBCA77C2B2AE63, 0xFF51AFD7ED558CCD, 0xC4CEB9FE1A85EC53, 0x94D049BB133111EB],
    dtype=np.uint64,
)


def _row_hash(rows: np.ndarray) -> np.ndarray:
    bits = rows.view(np.uint64)
    h = np.zeros(len(rows), dtype=np.uint64)
    with np.errstate(over="ignore"):
        for j in range(rows.shape[1]):  # a handful of columns, not rows
            c = bits[:, j] * _MULT[j % len(_MULT)]
            h ^= c ^ (c >> np.uint64(29))
            h *= _MULT[(j + 3) % len(_MULT)]
        h ^= h >> np.uint64(32)
    return h


def exact_ids(rows: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Number identical rows of a float or integer table.

    Parameters
    ----------
    rows : (m, k) ndarray of float64 or int64

    Returns
    -------
    ids : (m,) int64 ndarray
        Equal rows get equal ids, numbered 0 .. u-1.
    first : (u,) int64 ndarray
        Index of one representative row per id.

    Examples
    --------
    >>> ids, first = exact_ids(np.array([[0.0, 1.0], [2.0, 3.0], [-0.0, 1.0]]))
    >>> ids.tolist(), first.tolist()
    ([0, 1, 0], [0, 1])
    """
    rows = np.ascontiguousarray(rows)
    if rows.dtype.kind == "f":
        rows = np.ascontiguousarray(rows.astype(np.float64, copy=False) + 0.0)  # folds -0.0 into 0.0
    else:
        rows = np.ascontiguousarray(rows.astype(np.int64, copy=False))
    m = len(rows)
    if m == 0:
        return np.zeros(0, np.int64), np.zeros(0, np.int64)
    h = _row_hash(rows)
    order = np.argsort(h, kind="stable")
    hs = h[order]
    new = np.empty(m, dtype=bool)
    new[0] = True
    np.not_equal(hs[1:], hs[:-1], out=new[1:])
    group = np.cumsum(new) - 1
    starts = order[new]
    # Verify every row against its group's first row: exactness despite hashing.
    rep = starts[group]
    same = np.all(rows[order] == rows[rep], axis=1)
    if not same.all():
        _, first, inverse = np.unique(rows, axis=0, return_index=True, return_inverse=True)
        return inverse.reshape(-1).astype(np.int64), first.astype(np.int64)
    # Number groups by first appearance so ids are stable and reproducible.
    first_pos = starts
    rank = np.empty(len(first_pos), dtype=np.int64)
    by_pos = np.argsort(first_pos, kind="stable")
    rank[by_pos] = np.arange(len(first_pos))
    ids = np.empty(m, dtype=np.int64)
    ids[order] = rank[group]
    return ids, np.sort(first_pos)


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
    >>> len(v), f.tolist()
    (4, [[0, 1, 2], [1, 3, 2]])
    """
    flat = np.asarray(triangles, dtype=np.float64).reshape(-1, 3)
    ids, first = exact_ids(flat)
    return flat[first], ids.reshape(-1, 3)


def edge_table(faces: np.ndarray) -> dict[str, np.ndarray]:
    """Directed and undirected edge bookkeeping of a welded mesh.

    Parameters
    ----------
    faces : (n, 3) int ndarray

    Returns
    -------
    dict
        ``key`` (3n,) undirected edge key per facet edge (edge i of facet f is
        ``3 f + i``, from corner i to corner i+1); ``order`` sorts the keys;
        ``unique`` the distinct keys, ``inverse`` and ``counts`` per distinct
        edge; ``forward`` (3n,) True when the edge runs from lower to higher
        vertex id.

    Examples
    --------
    >>> t = edge_table(np.array([[0, 1, 2], [0, 2, 3]]))
    >>> t["counts"].tolist()
    [1, 2, 1, 1, 1]
    """
    f = np.asarray(faces, dtype=np.int64)
    a = f.reshape(-1)
    b = np.roll(f, -1, axis=1).reshape(-1)
    lo = np.minimum(a, b)
    hi = np.maximum(a, b)
    nv = int(f.max()) + 1 if f.size else 1
    key = lo * nv + hi
    order = np.argsort(key, kind="stable")
    ks = key[order]
    new = np.empty(len(ks), dtype=bool)
    if len(ks):
        new[0] = True
        np.not_equal(ks[1:], ks[:-1], out=new[1:])
    group = np.cumsum(new) - 1
    inverse = np.empty(len(ks), dtype=np.int64)
    inverse[order] = group
    starts = np.flatnonzero(new)
    counts = np.diff(np.append(starts, len(ks)))
    return {"key": key, "order": order, "unique": ks[new], "inverse": inverse,
            "counts": counts, "forward": a < b}
