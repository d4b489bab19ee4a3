"""Exact vertex welding, edge tables and edge-manifold counts, without rounding and without loops.

Two points are the same vertex only when their coordinates are bit-for-bit
equal (``-0.0`` and ``0.0`` count as equal). Rows are hashed into an
open-addressing table and compared bit for bit with the row already in their
slot, so a hash collision can never merge two different vertices.
"""
from __future__ import annotations

import os
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass

import numpy as np

__all__ = ["exact_ids", "weld", "edge_table", "shells", "EdgeCounts", "edge_counts", "manifold_summary"]

# Odd 64-bit multipliers (from splitmix64 / xxhash) for mixing columns.
_MULT = np.array(
    [0x9E3779B97F4A7C15, 0xC2B2AE3D27D4EB4F, 0x165667B19E3779F9, 0x27D4EB2F165667C5,
     0x85EBCA77C2B2AE63, 0xFF51AFD7ED558CCD, 0xC4CEB9FE1A85EC53, 0x94D049BB133111EB],
    dtype=np.uint64,
)
_NEG_ZERO = np.float64(-0.0).view(np.uint64)


def _fmix(h: np.ndarray, tmp: np.ndarray) -> np.ndarray:
    # splitmix64 finaliser, in place (tmp is scratch): a bijection that spreads every bit over the word.
    np.right_shift(h, np.uint64(31), out=tmp)
    h ^= tmp
    h *= _MULT[5]
    np.right_shift(h, np.uint64(29), out=tmp)
    h ^= tmp
    h *= _MULT[7]
    np.right_shift(h, np.uint64(32), out=tmp)
    h ^= tmp
    return h


def _row_hash(bits: np.ndarray, out: np.ndarray | None = None) -> np.ndarray:
    """64-bit hash of each row of a (m, k) uint64 table (into `out` when given)."""
    # Each column is folded (xorshift: its high half, where a float's sign and exponent sit,
    # reaches the low half) and multiplied before the sum is mixed. A plain sum of products
    # loses the sign bit, and float32-exact doubles have 29 zero low bits: half the
    # vertices of a symmetric part would share a hash.
    with np.errstate(over="ignore"):
        h = np.empty(len(bits), np.uint64) if out is None else out
        h.fill(0)
        tmp = np.empty_like(h)
        for j in range(bits.shape[1]):  # a handful of columns, not rows
            np.right_shift(bits[:, j], np.uint64(32), out=tmp)
            tmp ^= bits[:, j]
            tmp *= _MULT[j % len(_MULT)]
            h += tmp
        return _fmix(h, tmp)


# Tables with more rows than this are hashed and verified by two threads: numpy lets go of
# the GIL in those loops, so both cores share the weld of a big mesh.
_THREADED_ROWS = 1 << 21


def _in_halves(fn, m: int) -> None:
    """Run ``fn(lo, hi)`` over range(m): two halves on two threads when m is big."""
    if m < _THREADED_ROWS or (os.cpu_count() or 1) < 2:
        fn(0, m)
        return
    half = m // 2
    with ThreadPoolExecutor(max_workers=1) as pool:
        other = pool.submit(fn, half, m)
        fn(0, half)
        other.result()


def exact_ids(rows: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Number identical rows of a float or integer table.

    Rows go into an open-addressing hash table (twice as many slots as rows,
    linear probing) in vectorised rounds: every row still looking for its
    slot writes its index there if the slot is free, then compares itself,
    bit for bit, with the row the slot holds. Equal rows probe the same slots
    in the same rounds, so they always end in the same one; a hash collision
    only costs a row another round, never a wrong merge. No sort: a few
    gathers and scatters over the rows, about three times faster than
    sorting them for the welds of big meshes.

    Parameters
    ----------
    rows : (m, k) or (m,) ndarray of floats or integers
        Floats are compared as float64 bit patterns, ``-0.0`` folded into
        ``0.0`` (a NaN equals a NaN of the same bits).

    Returns
    -------
    ids : (m,) int64 ndarray
        Equal rows get equal ids, numbered 0 .. u-1 (in no particular order).
    first : (u,) int64 ndarray
        Index of the first (lowest) row of each id.

    Examples
    --------
    >>> ids, first = exact_ids(np.array([[0.0, 1.0], [2.0, 3.0], [-0.0, 1.0]]))
    >>> bool(ids[0] == ids[2]), bool(ids[0] != ids[1]), sorted(first.tolist())
    (True, True, [0, 1])
    """
    rows = np.asarray(rows)
    if rows.ndim == 1:
        rows = rows[:, None]
    if rows.dtype.kind == "f":
        rows = np.ascontiguousarray(rows, dtype=np.float64)
        bits = rows.view(np.uint64)
        if (bits == _NEG_ZERO).any():  # a whole copy only when there is a -0.0 to fold into 0.0
            bits = (rows + 0.0).view(np.uint64)
    else:
        bits = np.ascontiguousarray(rows, dtype=np.int64).view(np.uint64)
    m = len(bits)
    if m == 0:
        return np.zeros(0, np.int64), np.zeros(0, np.int64)
    size = 1 << max(4, (2 * m - 1).bit_length())  # load factor at most 1/2
    itype = np.int32 if m < 2**31 else np.int64
    table = np.full(size, -1, itype)
    slot = np.empty(m, np.int64)
    keys = bits[:, 0] if bits.shape[1] == 1 else bits

    def hash_rows(lo, hi):
        h = _row_hash(bits[lo:hi], slot[lo:hi].view(np.uint64))
        h &= np.uint64(size - 1)

    _in_halves(hash_rows, m)
    # First round, every row at once and the table empty: writing in reverse order leaves the
    # lowest row of each slot there (last writes win), so `first` is each id's lowest row.
    table[slot[::-1]] = np.arange(m - 1, -1, -1, dtype=itype)
    same = np.empty(m, bool)

    def verify(lo, hi):
        eq = keys[table[slot[lo:hi]]] == keys[lo:hi]
        same[lo:hi] = eq.all(axis=1) if eq.ndim == 2 else eq

    _in_halves(verify, m)
    where = slot  # the slot each row is in (rows that miss move on: written over below)
    pending = None  # every row, in the first round
    while True:
        if pending is not None:
            same = keys[held] == keys[pending]
            if same.ndim == 2:
                same = same.all(axis=1)
        miss = np.flatnonzero(~same)
        if len(miss) == 0:
            break
        pending = miss.astype(itype) if pending is None else pending[miss]
        slot = where[pending] + 1
        slot &= size - 1
        held = table[slot]
        free = np.flatnonzero(held < 0)
        if len(free):
            table[slot[free[::-1]]] = pending[free[::-1]]
            held[free] = table[slot[free]]
        where[pending] = slot
    used = np.flatnonzero(table >= 0)
    first = table[used].astype(np.int64)
    table[used] = np.arange(len(used), dtype=itype)  # the table now maps slot -> id
    ids = np.empty(m, np.int64)

    def label(lo, hi):
        ids[lo:hi] = table[where[lo:hi]]

    _in_halves(label, m)
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
        key = np.minimum(a, b)
        key *= nv
        key += np.maximum(a, b)
        inverse, first = exact_ids(key)
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
        Vertex ids of each facet; the winding does not matter.
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
    from .graphs import graph_components
    f = np.asarray(faces, dtype=np.int64)
    n = len(f)
    if n == 0:
        return 0, np.zeros(0, np.int64)
    et = edge_table(f) if edges is None else edges
    first, last, counts, inverse = et["first"], et["last"], et["counts"], et["inverse"]
    # Each edge links the facets of its lowest and highest facet edge; an edge of three facets
    # or more (rare) also links every facet edge to its lowest one.
    a, b = first // 3, last // 3
    if counts.max() > 2:
        many = np.flatnonzero(counts[inverse] > 2)
        a = np.concatenate([a, first[inverse[many]] // 3])
        b = np.concatenate([b, many // 3])
    return graph_components(n, a, b)


@dataclass(frozen=True)
class EdgeCounts:
    """How the edges of a welded mesh are shared by its facets.

    Attributes
    ----------
    n_edges : int
        Distinct undirected edges.
    n_open : int
        Edges used by one facet only (holes in the surface).
    n_nonmanifold : int
        Edges used by three facets or more.
    n_misoriented : int
        Edges of two facets that walk them the same way (inconsistent winding).
    """

    n_edges: int
    n_open: int
    n_nonmanifold: int
    n_misoriented: int

    @property
    def closed(self) -> bool:
        """Edge-manifold with consistent winding: every edge walked once each way by two facets."""
        return self.n_edges > 0 and self.n_open == 0 and self.n_nonmanifold == 0 and self.n_misoriented == 0


def edge_counts(faces: np.ndarray, edges: dict | None = None) -> EdgeCounts:
    """Open, non-manifold and misoriented edges of a welded mesh.

    Parameters
    ----------
    faces : (n, 3) int ndarray
        Vertex ids of each facet, in winding order (it decides which edges are misoriented).
    edges : dict, optional
        `edge_table(faces)`, when already computed.

    Returns
    -------
    EdgeCounts

    See Also
    --------
    manifold_summary : the same counts for a triangle soup.
    shells : the edge-connected pieces of the same edge table.

    Examples
    --------
    >>> edge_counts(np.array([[0, 1, 2], [0, 2, 3]]))
    EdgeCounts(n_edges=5, n_open=4, n_nonmanifold=0, n_misoriented=0)
    >>> edge_counts(np.array([[0, 1, 2], [0, 1, 3]])).n_misoriented  # both walk 0 -> 1
    1
    """
    f = np.asarray(faces, dtype=np.int64)
    et = edge_table(f) if edges is None else edges
    counts, first, last, forward = et["counts"], et["first"], et["last"], et["forward"]
    # A two-facet edge is consistent when one facet walks it forward, the other backward.
    two = counts == 2
    return EdgeCounts(n_edges=len(counts), n_open=int(np.count_nonzero(counts == 1)),
                      n_nonmanifold=int(np.count_nonzero(counts > 2)),
                      n_misoriented=int(np.count_nonzero(forward[first[two]] == forward[last[two]])))


def manifold_summary(triangles: np.ndarray) -> EdgeCounts:
    """Edge-manifold check of a triangle soup, its corners welded exactly.

    Parameters
    ----------
    triangles : (n, 3, 3) array_like

    Returns
    -------
    EdgeCounts
        ``closed`` is False for an empty soup.

    See Also
    --------
    edge_counts : the counts of an already welded mesh.
    slicelab.mesh.check : the full report (the same counts, plus shells, volume, normals).

    Examples
    --------
    >>> from slicelab.samples import box
    >>> manifold_summary(box().triangles).closed
    True
    >>> manifold_summary(box().triangles[1:]).n_open
    3
    """
    t = np.asarray(triangles, dtype=np.float64).reshape(-1, 3, 3)
    if len(t) == 0:
        return EdgeCounts(0, 0, 0, 0)
    ids, _ = exact_ids(t.reshape(-1, 3))  # the weld, without gathering the vertices
    return edge_counts(ids.reshape(-1, 3))
