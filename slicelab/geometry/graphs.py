"""Connected components of graphs, and thinning of pixel sets to one-pixel skeletons.

Both run as compiled loops (`slicelab.geometry.graph_kernels`), so that
slicing, checking a mesh and planning a print import neither SciPy nor
scikit-image, whose imports would add to every command's start-up
(`scripts/bench_slice.py` prints what each would add).
"""
from __future__ import annotations

import numpy as np

__all__ = ["graph_components", "thin", "thinning_table", "GUO_HALL"]


def graph_components(n: int, a, b) -> tuple[int, np.ndarray]:
    """Connected components of the undirected graph on nodes 0..n-1 with edges (a[k], b[k]).

    The same count and labels as ``scipy.sparse.csgraph.connected_components``
    of the graph (``directed=False``): components are numbered in the order of
    their lowest node.

    Parameters
    ----------
    n : int
        Number of nodes.
    a, b : (m,) int array_like
        The ends of each edge; repeated edges and loops are allowed.

    Returns
    -------
    count : int
    labels : (n,) int64 ndarray

    Raises
    ------
    ValueError
        If an edge names a node outside 0..n-1, or the ends differ in number.

    References
    ----------
    R. E. Tarjan, "Efficiency of a good but not linear set union algorithm",
    Journal of the ACM 22(2), 1975 (union-find).

    Examples
    --------
    >>> count, labels = graph_components(6, [4, 1], [5, 2])
    >>> count, labels.tolist()
    (4, [0, 1, 1, 2, 3, 3])
    """
    from .graph_kernels import label_components
    n = int(n)
    a = np.ascontiguousarray(a, dtype=np.int64).reshape(-1)
    b = np.ascontiguousarray(b, dtype=np.int64).reshape(-1)
    if len(a) != len(b):
        raise ValueError(f"edges need two ends each: got {len(a)} and {len(b)} ends")
    if len(a) and (min(a.min(), b.min()) < 0 or max(a.max(), b.max()) >= n):
        raise ValueError(f"an edge names a node outside 0..{n - 1}")
    count, labels = label_components(n, a, b)
    return int(count), labels


def thinning_table(rule) -> np.ndarray:
    """The table of a two-subiteration thinning: for each of the 256 neighbourhoods, the
    subiterations (bit 0: first, bit 1: second) that remove a set pixel with it.

    Parameters
    ----------
    rule : callable
        ``rule(p, first)`` -> bool array: whether the first (`first` True)
        or second subiteration removes the pixel. ``p`` holds the eight
        neighbours ``p2, ..., p9`` of the thinning papers, each an array over
        the 256 codes (0 or 1), clockwise from the north: N, NE, E, SE, S, SW, W, NW.

    Returns
    -------
    (256,) uint8 ndarray
    """
    codes = np.arange(256)
    p = [(codes >> i) & 1 for i in range(8)]
    return (np.asarray(rule(p, True), bool) * 1 + np.asarray(rule(p, False), bool) * 2).astype(np.uint8)


def _guo_hall(p, first):
    p2, p3, p4, p5, p6, p7, p8, p9 = p
    # C: the number of 8-connected groups of set neighbours that a removal would part;
    # N: how many neighbours (paired) the pixel has, from 2 (not an end) to 3 (on the border).
    c = ((p2 == 0) & ((p3 | p4) == 1)) * 1 + ((p4 == 0) & ((p5 | p6) == 1)) + ((p6 == 0) & ((p7 | p8) == 1)) \
        + ((p8 == 0) & ((p9 | p2) == 1))
    n1 = (p9 | p2) + (p3 | p4) + (p5 | p6) + (p7 | p8)
    n2 = (p2 | p3) + (p4 | p5) + (p6 | p7) + (p8 | p9)
    n = np.minimum(n1, n2)
    # The first subiteration peels the west and south sides (and corners), the second the east and
    # north sides, so that a strip is thinned from both sides to its middle.
    keep = ((p6 | p7 | (1 - p9)) & p8) if first else ((p2 | p3 | (1 - p5)) & p4)
    return (c == 1) & (n >= 2) & (n <= 3) & (keep == 0)


#: Guo and Hall's first algorithm (A1): a one-pixel skeleton that keeps every component.
GUO_HALL = thinning_table(_guo_hall)


def thin(mask, table: np.ndarray | None = None) -> np.ndarray:
    """The skeleton of a binary image: each 8-connected component thinned to one-pixel-wide lines.

    Guo and Hall's two-subiteration parallel thinning by default: pixels are
    peeled off the borders, alternately from the north-west and the
    south-east, until none can go without parting a component or shortening a
    line. A strip of even width keeps one pixel across (the medial axis of a
    distance transform does not). Only set pixels are visited, so the cost
    follows their number and the strips' widths, not the image's size.

    Parameters
    ----------
    mask : (h, w) array_like of bool
    table : (256,) uint8 ndarray, optional
        Another two-subiteration rule (`thinning_table`).

    Returns
    -------
    (h, w) bool ndarray

    See Also
    --------
    slicelab.geometry.contours.trace_skeleton : the skeleton as polylines.

    References
    ----------
    Z. Guo, R. W. Hall, "Parallel thinning with two-subiteration algorithms",
    Communications of the ACM 32(3), 1989.

    Examples
    --------
    >>> m = np.zeros((7, 9), bool); m[2:5, 1:8] = True   # a strip 3 pixels wide
    >>> thin(m).astype(int)[1:6].tolist()
    [[0, 0, 0, 0, 0, 0, 0, 0, 0], [0, 0, 0, 0, 0, 0, 0, 0, 0], [0, 0, 1, 1, 1, 1, 1, 0, 0], [0, 0, 0, 0, 0, 0, 0, 0, 0], [0, 0, 0, 0, 0, 0, 0, 0, 0]]
    """
    from .graph_kernels import thin_pixels
    image = np.array(mask, dtype=bool, copy=True, order="C").view(np.uint8)
    if image.ndim != 2:
        raise ValueError(f"thin takes a 2-D image, got {image.ndim} dimensions")
    thin_pixels(image, GUO_HALL if table is None else np.ascontiguousarray(table, np.uint8))
    return image.view(bool)
