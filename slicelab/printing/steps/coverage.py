"""How a layer's extrusions cover it: pixels within half a width of each path, counted.

See Also
--------
slicelab.printing.pipeline.layer_paths : the paths measured.
"""
from __future__ import annotations

import numpy as np

from ...geometry.spatial import SegmentIndex
from ..grid.raster import GridMask, draw_polylines
from ..table import LayerPaths

__all__ = ["covered_pixels", "coverage_map"]


def covered_pixels(shape, row0: int, col0: int, pixel_size: float, path: np.ndarray, width) -> np.ndarray:
    """Pixels of a window whose centre lies within width/2 of a polyline (an extrusion, round ends).

    Exact: OpenCV draws candidates (`slicelab.printing.grid.raster.draw_polylines`,
    a little wider than the extrusion) and each candidate's distance to the
    polyline is measured.

    Parameters
    ----------
    shape, row0, col0, pixel_size
        The window of the world grid, as for `slicelab.printing.grid.raster.draw_polylines`.
    path : (k, 2) ndarray
        The polyline (mm).
    width : float or (k,) ndarray
        Extrusion width, or its width at each vertex (linear along each segment).

    Returns
    -------
    (h, w) bool ndarray

    See Also
    --------
    coverage_map : every extrusion of a layer counted.

    Examples
    --------
    >>> cov = covered_pixels((5, 9), 0, 0, 1.0, np.array([[1.0, 2.0], [7.0, 2.0]]), 2.0)
    >>> cov.astype(int)[1:4].tolist()
    [[0, 1, 1, 1, 1, 1, 1, 1, 0], [1, 1, 1, 1, 1, 1, 1, 1, 1], [0, 1, 1, 1, 1, 1, 1, 1, 0]]
    """
    p = pixel_size
    # OpenCV's thick lines are up to two pixels wider than asked: good candidates, not the answer.
    cand = draw_polylines(shape, row0, col0, p, [path], float(np.max(width)) + 3 * p) > 0
    rows, cols = np.nonzero(cand)
    out = np.zeros(shape, bool)
    if len(path) < 2 or len(rows) == 0:
        return out
    seg = np.stack([path[:-1], path[1:]], axis=1)
    d, s, t = SegmentIndex(seg, 4 * p).nearest(np.stack([(col0 + cols) * p, (row0 + rows) * p], 1))
    w = np.asarray(width, np.float64)
    half = 0.5 * (w if w.ndim == 0 else w[s] + t * (w[s + 1] - w[s]))
    inside = d <= half
    out[rows[inside], cols[inside]] = True
    return out


def coverage_map(paths: LayerPaths, pixel_size: float = 0.1, *, margin: int = 4) -> tuple[np.ndarray, GridMask]:
    """How many extrusions cover each pixel centre, each extrusion w wide (round ends).

    Returns
    -------
    counts : (h, w) uint8 ndarray
        0 is a gap, 2 or more double coverage.
    grid : GridMask
        The window (``counts > 0``) on the world grid.

    See Also
    --------
    covered_pixels : the coverage of one extrusion.

    Examples
    --------
    >>> import slicelab
    >>> from slicelab.samples import box
    >>> s = slicelab.section(box((0.03, 0.03, 0), (10.03, 10.03, 1)), (0, 0, .5), (0, 0, 1))
    >>> counts, grid = coverage_map(slicelab.layer_paths(s, slicelab.PrintSettings(infill_density=1.0, pixel_size=0.1)), 0.1)
    >>> round(float((counts >= 1).sum() * 0.01 / 100), 2)  # covered area / square's area
    0.99
    """
    p = float(pixel_size)
    items = list(paths.ordered())
    if not items:
        return np.zeros((1, 1), np.uint8), GridMask(np.zeros((1, 1), bool), 0, 0, p)
    allpts = np.concatenate([q for _, q, _ in items])
    pad = margin + paths.line_width / p
    c0, r0 = np.floor(allpts.min(axis=0) / p - pad).astype(int)
    c1, r1 = np.ceil(allpts.max(axis=0) / p + pad).astype(int)
    counts = np.zeros((r1 - r0 + 1, c1 - c0 + 1), np.uint8)
    for _, q, w in items:  # over paths
        wmax = float(np.max(w))
        lo = np.floor(q.min(axis=0) / p - wmax / p - 3).astype(int)
        hi = np.ceil(q.max(axis=0) / p + wmax / p + 3).astype(int)
        cov = covered_pixels((hi[1] - lo[1] + 1, hi[0] - lo[0] + 1), int(lo[1]), int(lo[0]), p, q, w)
        counts[lo[1] - r0:hi[1] - r0 + 1, lo[0] - c0:hi[0] - c0 + 1] += cov
    return counts, GridMask(counts > 0, int(r0), int(c0), p)
