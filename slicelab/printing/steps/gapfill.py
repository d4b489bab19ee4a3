"""Gap fill: extrusions along the medial axis of the material that perimeters and filling miss.

A pixel of the perimeters' zone (distance F < n w from the boundary) is
covered when the perimeter of its own level passes within w/2 of it; beyond
the perimeters only the filling covers. What is left (thin walls, gaps
between perimeters, pinches the filling cannot enter) is thinned to its
skeleton (Guo and Hall's thinning), and the skeleton's chains become polylines whose
width is the local width of the gap.

Everything runs on the blocks of the layer (`slicelab.geometry.blocks`):
each step reads a bounded neighbourhood, so the blocks go through OpenCV and
the thinning as one stack with halos wide enough for it, and connected parts
are joined across block seams.

See Also
--------
slicelab.printing.steps.perimeters : the perimeters and the filling region.
slicelab.geometry.contours.trace_skeleton : the skeleton's chains.
"""
from __future__ import annotations

import numpy as np

from ...geometry.blocks import BlockGrid
from ...geometry.contours import trace_skeleton
from ...geometry.graphs import thin
from ..grid.masks import GridMask
from ..grid.raster import BLOCK

__all__ = ["disc", "medial_fill", "uncovered_blocks", "medial_fill_blocks"]


def disc(radius_px: float) -> np.ndarray:
    """OpenCV's elliptic structuring element of radius ``ceil(radius_px)`` (at least 1).

    Examples
    --------
    >>> disc(1.2).shape
    (5, 5)
    """
    import cv2
    r = max(1, int(np.ceil(radius_px)))
    return cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (2 * r + 1, 2 * r + 1))


def _threshold(min_width: float, p: float) -> float:
    # A strip n px wide reaches n/2 (even n), (n+1)/2 (odd n) in the pixel distance transform.
    # Fine pixels need three across (slivers one or two pixels wide are rounding); from pixels
    # three quarters of the narrowest gap (0.15 mm for 0.4 mm lines), that gap is one or two
    # pixels across, and must be kept.
    return max(min_width / (2 * p) + 0.25, 1.0 if p >= 0.75 * min_width else 1.5)


def _polylines(paths, width_of, p: float, w: float, min_width: float, row0: int = 0, col0: int = 0):
    """Skeleton chains (pixel rows and columns) as simplified polylines (mm) with their widths."""
    import cv2
    polylines, widths = [], []
    for path in paths:  # over gap-fill chains
        width_px = width_of(path)
        # Douglas-Peucker by OpenCV (skimage's approximate_polygon is the same algorithm, but
        # importing it loads scipy.signal: half a second in every worker of a print plan).
        simple = cv2.approxPolyDP(path.astype(np.int32).reshape(-1, 1, 2), 0.5, False).reshape(-1, 2)
        # Widths follow the simplified vertices (nearest skeleton pixel of each).
        near = np.argmin(np.abs(path[:, None, :] - simple[None]).sum(-1), axis=0)
        xy = np.stack([(col0 + simple[:, 1]) * p, (row0 + simple[:, 0]) * p], -1).astype(np.float64)
        if np.hypot(*np.diff(xy, axis=0).T).sum() < 0.5 * w:
            continue
        polylines.append(xy)
        widths.append(np.clip((2 * width_px[near] - 0.5) * p, min_width, 1.5 * w))
    return polylines, widths


def _labelled(labels: np.ndarray, chosen: np.ndarray) -> np.ndarray:
    """Where `labels` (non-negative) is one of `chosen`: ``np.isin(labels, chosen)``, by a table
    (`np.isin` and `np.unique` load numpy.ma, an import in every worker of a print plan)."""
    table = np.zeros(int(labels.max(initial=0)) + 1, bool)
    table[chosen] = True
    return table[labels]


def medial_fill(grid: GridMask, uncovered: np.ndarray, w: float, min_width: float):
    """Polylines along the medial axis of the parts of `uncovered` at least `min_width` wide.

    Returns the polylines (mm) and the extrusion width at each vertex (the
    local width of the uncovered part, between `min_width` and 1.5 w). The
    pixels are worked on in the world-anchored blocks of the layers' size
    (`slicelab.printing.grid.raster.BLOCK`) that hold some (`medial_fill_blocks`), so
    the cost follows the gaps, not their box.

    See Also
    --------
    medial_fill_blocks : the same on the blocks of a layer.
    slicelab.geometry.trace_skeleton : the skeleton's chains.

    References
    ----------
    Z. Guo, R. W. Hall, "Parallel thinning with two-subiteration algorithms",
    Communications of the ACM 32(3), 1989 (`slicelab.geometry.graphs.thin`).

    Examples
    --------
    >>> g = GridMask(np.zeros((20, 60), bool), 0, 0, 0.05)
    >>> strip = np.zeros((20, 60), bool); strip[7:13, 5:55] = True   # 0.3 mm x 2.5 mm
    >>> lines, widths = medial_fill(g, strip, 0.4, 0.2)   # its medial axis: 2.5 - 0.3 mm long
    >>> len(lines), round(float(np.hypot(*np.diff(lines[0], axis=0).T).sum()), 1), round(float(widths[0].max()), 3)
    (1, 2.2, 0.275)
    """
    rows, cols = np.nonzero(uncovered)
    if len(rows) == 0:
        return [], []
    # Only the blocks that hold uncovered pixels are worked on (`medial_fill_blocks`, the same
    # polylines): a few slivers along a wide ring have a box of millions of pixels.
    b = BLOCK  # (the layers' block size)
    rows, cols = rows + grid.row0, cols + grid.col0
    br, bc = rows // b, cols // b
    b0r, b0c = int(br.min()), int(bc.min())
    held = np.zeros((int(br.max()) - b0r + 1, int(bc.max()) - b0c + 1), bool)
    held[br - b0r, bc - b0c] = True
    blocks = BlockGrid.from_status(b, b0r, b0c, held, np.zeros_like(held))
    bits = np.zeros((len(blocks), b, b), bool)
    bits[blocks.table[br - b0r, bc - b0c], rows - br * b, cols - bc * b] = True
    return medial_fill_blocks(blocks, bits, grid.pixel_size, w, min_width)


def uncovered_blocks(field, fill: np.ndarray, levels, w: float, rings=None) -> np.ndarray:
    """Pixels of a layer's blocks that neither the perimeters nor the filling reach (n, B, B bool).

    Within the perimeters' zone F < n w, a pixel is within w/2 of level
    j = floor(F / w): covered from above if F >= level j, from below only if
    level j exists within w/2, i.e. if a pixel within w/2 reaches it: one
    dilation by a disc of {F >= level j} per level. Given the `rings` found,
    only pixels past the level that a ring passes by count: in a wall a
    little wider than a line (a thin tube's), the level's region is narrower
    than a pixel, and its ring breaks up or is missing although some pixels
    pass the level; the wall is then left to gap fill. Beyond the perimeters
    only the filling covers: where its region was too thin to keep (a wall a
    little wider than the perimeters), the middle is left to gap fill too.

    Parameters
    ----------
    field : DistanceField
    fill : (n, B, B) bool ndarray
        Where the filling's centre lines may go (its extrusions reach w/2 further).
    levels : sequence of float
        The perimeters' levels.
    w : float
        Line width.
    rings : list of (k, 2) ndarray, optional
        The perimeters' rings found on this tile (mm).
    """
    import cv2
    values, inside = field.blocks, field.grid.bits
    g = field.grid.blocks
    n_lv = len(levels)
    if n_lv == 0 or not len(values):
        return np.zeros(values.shape, bool)
    p = field.grid.pixel_size
    kernel = disc(0.5 * w / p + 1)  # +1 px: rounding
    image, r = field.wide_mosaic(kernel.shape[0] // 2)  # its halo r reaches at least the disc's radius

    def grown(image):  # dilated by the disc, the blocks' own pixels
        return g.cores(cv2.dilate(image, kernel), r)

    top = np.float32(n_lv * w)
    zone = inside & (values >= 0) & (values < top)
    level = np.minimum(np.floor(values / w), n_lv - 1)  # float32, as the thresholds below
    uncovered = (values >= top) & inside
    found = None
    if rings is not None:  # the pixels a ring found passes through (and those beside them)
        from ..grid.masks import GridMask, bits_in_blocks
        from ..grid.raster import draw_polylines
        b = g.size
        r0, c0 = g.row0 * b, g.col0 * b
        drawn = draw_polylines((g.table.shape[0] * b, g.table.shape[1] * b), r0, c0, p, rings, p, closed=True)
        near = bits_in_blocks(GridMask(drawn > 0, r0, c0, p), g.rows, g.cols, b)
        found = g.mosaic(near.view(np.uint8), r, np.uint8(0), np.uint8(0)) * np.uint8(255)
    for j in range(n_lv):  # over levels: is level j within w/2 of its zone's pixels?
        need = np.float32(j + 0.5) * np.float32(w) - np.float32(1e-6)
        held = cv2.compare(image, float(need), cv2.CMP_GE)
        if found is not None:
            held &= found
        uncovered |= zone & (level == j) & ~grown(held).view(bool)
    if uncovered.any():
        uncovered &= ~grown(g.mosaic(fill.view(np.uint8), r, np.uint8(0), np.uint8(1))).view(bool)
    return uncovered


def medial_fill_blocks(grid: BlockGrid, uncovered: np.ndarray, pixel_size: float, w: float, min_width: float):
    """`medial_fill` over the blocks of a layer: the same polylines, with work only where gaps are.

    Only blocks holding uncovered pixels take part, each with a halo of about
    1.5 w (the widest gap and the reach of its thinning): the distance
    transforms and the thinning run over their stack, parted by a background
    row, and the parts of gaps are joined across block seams
    (`BlockGrid.components`) before the chains are traced on the whole grid.

    Parameters
    ----------
    grid : BlockGrid
    uncovered : (n, B, B) bool ndarray
        On the active blocks of `grid`.
    pixel_size, w, min_width : float

    Returns
    -------
    polylines : list of (k, 2) ndarray
    widths : list of (k,) ndarray

    Examples
    --------
    >>> from slicelab.geometry.blocks import BlockGrid
    >>> strip = np.zeros((32, 64), bool); strip[7:13, 5:55] = True   # 0.3 mm x 2.5 mm
    >>> g = BlockGrid(32, 0, 0, np.array([[0, 1]]))
    >>> lines, widths = medial_fill_blocks(g, np.stack([strip[:, :32], strip[:, 32:]]), 0.05, 0.4, 0.2)  # 2.5 - 0.3 mm
    >>> len(lines), round(float(np.hypot(*np.diff(lines[0], axis=0).T).sum()), 1), round(float(widths[0].max()), 3)
    (1, 2.2, 0.275)
    """
    import cv2
    p = float(pixel_size)
    has = uncovered.any(axis=(1, 2))
    if not has.any():
        return [], []
    held = np.zeros(grid.table.shape, bool)
    held[grid.rows[has] - grid.row0, grid.cols[has] - grid.col0] = True
    sub = BlockGrid.from_status(grid.size, grid.row0, grid.col0, held, np.zeros_like(held))
    bits = uncovered[has]
    b = grid.size
    halo = int(np.ceil(1.5 * w / p)) + 4

    def stacked(x):  # the blocks with their halos, parted by background
        return sub.mosaic(x.view(np.uint8), halo, np.uint8(0), np.uint8(0), gap=1)

    def own(img):
        return sub.cores(img, halo, gap=1)

    threshold = _threshold(min_width, p)
    img, d = stacked(bits), None
    if threshold > 1.0:  # (else every set pixel is a pixel from the background: every part is wide enough)
        d = cv2.distanceTransform(img, cv2.DIST_L2, cv2.DIST_MASK_PRECISE)
        seeds = own(d) >= threshold
        if not seeds.any():
            return [], []
        labels, _ = sub.components(bits)
        keep = _labelled(labels, labels[seeds]) & bits
        if np.count_nonzero(keep) < np.count_nonzero(bits):  # parts too thin left out: distances again
            img, d = stacked(keep), None
    if d is None:
        d = cv2.distanceTransform(img, cv2.DIST_L2, cv2.DIST_MASK_PRECISE)
    skel = own(thin(img.view(bool)) & (d >= threshold - 1))
    d = own(d)
    k, r, c = np.nonzero(skel)
    rows0, cols0 = sub.origins()
    r0, c0 = int(grid.row0 * b), int(grid.col0 * b)  # small coordinates for OpenCV's int32
    rows, cols = rows0[k] + r - r0, cols0[k] + c - c0
    width = int(cols.max()) + 2 if len(cols) else 1
    key = rows * width + cols
    order = np.argsort(key)
    key, dval = key[order], d[k, r, c][order].astype(np.float64)

    def width_of(path):
        return dval[np.searchsorted(key, path[:, 0] * width + path[:, 1])]

    paths = trace_skeleton(np.stack([rows, cols], 1))
    return _polylines(paths, width_of, p, w, min_width, r0, c0)
