"""Perimeters by erosion: level sets of the exact distance field, filling limits, gap fill.

The perimeters of a layer are level sets of the distance to its boundary:
the k-th one (k = 0, 1, ...) runs at ``(k + 1/2) w`` for line width w, so
each extrusion covers the band ``[k w, (k + 1) w]``. The distance field is
exact wherever those contours pass (`slicelab.toolpath.distance`), so the
perimeters lie on the true offsets, sharp corners included.

Every level gets its own hierarchy (erosion splits islands and merges
holes). Material that no perimeter covers and that is wide enough to print
(thin walls, gaps between perimeters) is filled along its medial axis.

See Also
--------
slicelab.toolpath.distance : the distance field and its level sets.
slicelab.toolpath.paths : the perimeters, gap fill and filling in print order.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..geometry.contours import trace_skeleton
from ..geometry.polygons import Polygon, build_polygons, loop_hierarchy, signed_area
from ..geometry.spatial import SegmentIndex
from .distance import distance_field, level_rings
from .raster import GridMask, LayerRaster, rasterize

__all__ = ["level_polygons", "Perimeters", "layer_perimeters", "medial_fill", "mask_rings"]


def level_polygons(rings: list[np.ndarray]) -> list[Polygon]:
    """Group rings of one level into polygons with holes (their own hierarchy).

    See Also
    --------
    slicelab.geometry.loop_hierarchy, slicelab.geometry.build_polygons : the grouping.

    Examples
    --------
    >>> sq = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], float)
    >>> [len(p.holes) for p in level_polygons([sq * 4, (sq + 1)[::-1]])]
    [1]
    """
    if not rings:
        return []
    return build_polygons(rings, *loop_hierarchy(rings))


@dataclass(frozen=True, eq=False)
class Perimeters:
    """The perimeters of one layer and the regions left for filling.

    Attributes
    ----------
    line_width : float
    levels : (n_perimeters,) ndarray
        Offset (mm) of each perimeter's centre line from the boundary.
    rings : list of list of Polygon
        Per level, its polygons (exterior counter-clockwise, holes clockwise),
        with the level's own hierarchy.
    fill_level : float
        Offset of the line along which the filling's centre lines stop.
    fill : list of Polygon
        Where sparse filling goes (centre lines).
    solid : list of Polygon
        Where solid filling goes (centre lines), from the `solid` mask.
    gap_fill : list of (k, 2) ndarray
        Polylines along the medial axis of material no perimeter covers.
    gap_widths : list of (k,) ndarray
        Extrusion width at each gap-fill vertex.
    thin_walls : int
        Islands too thin for a single perimeter (they get gap fill only).
    fields : list of DistanceField
        One per tile, for plots.
    """

    line_width: float
    levels: np.ndarray
    rings: list
    fill_level: float
    fill: list
    solid: list = field(default_factory=list)
    gap_fill: list = field(default_factory=list)
    gap_widths: list = field(default_factory=list)
    thin_walls: int = 0
    fields: list = field(default_factory=list)


def _disc(radius_px: float) -> np.ndarray:
    import cv2
    r = max(1, int(np.ceil(radius_px)))
    return cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (2 * r + 1, 2 * r + 1))


def _opened(values: np.ndarray, level: float, radius: float, p: float) -> np.ndarray:
    """The region {values >= level} opened by a disc of `radius` (a bool mask).

    Parts of the region thinner than 2 radius (slivers where fill lines would run nearly
    parallel and cover nothing) are removed; elsewhere its edge is the exact level set,
    since the dilated core reaches 1.5 px past it.
    """
    import cv2
    core = values >= level + radius
    if not core.any():
        return np.zeros(values.shape, bool)
    region = cv2.dilate(core.view(np.uint8), _disc(radius / p + 1.5)).view(bool)
    region &= values >= level
    return region


def _gap_fill(tile: GridMask, values: np.ndarray, fill_mask: np.ndarray, levels, w: float, min_width: float):
    """Medial-axis polylines (mm) and widths over material that neither the perimeters nor the
    filling region reach (thin walls, gaps between perimeters, pinches the filling cannot enter)."""
    import cv2
    p = tile.pixel_size
    n = len(levels)
    if n == 0:
        return [], []
    # Within the perimeters' zone F < n w, a pixel is within w/2 of level j = floor(F / w):
    # covered from above if F >= level j, from below only if level j exists within w/2, i.e.
    # if the largest F within w/2 reaches it. One grey dilation answers for every level.
    inside = tile.mask.view(np.uint8)
    fmax = cv2.dilate(values.astype(np.float32, copy=False), _disc(0.5 * w / p + 1))  # +1 px: rounding
    # The zone is a band along the boundary, a small part of the tile: its pixels are taken out
    # and judged one by one. Pixels outside sit at -p/2, below it.
    zone = cv2.inRange(values, 0.0, float(np.nextafter(np.float32(n * w), np.float32(0))))
    found = cv2.findNonZero(cv2.bitwise_and(zone, inside))
    # Beyond the perimeters only the filling covers: where its region was too thin to keep (a
    # wall a little wider than the perimeters), the middle is left to gap fill too.
    uncovered = (values >= n * w) & tile.mask
    if found is not None:
        cols, rows = found.reshape(-1, 2).T
        v = values[rows, cols]
        need = (np.minimum(np.floor(v / w), n - 1) + 0.5) * w
        short = fmax[rows, cols] < need - 1e-6
        uncovered[rows[short], cols[short]] = True
    # The filling's centre lines stay inside fill_mask; its extrusions reach w/2 further.
    if uncovered.any():
        uncovered &= ~cv2.dilate(fill_mask.view(np.uint8), _disc(0.5 * w / p + 1)).view(bool)
    return medial_fill(tile, uncovered, w, min_width)


def mask_rings(grid: GridMask, mask: np.ndarray, tolerance: float = 0.5) -> list[np.ndarray]:
    """Rings (material on the left, mm) through the boundary pixel centres of a mask, from OpenCV.

    Holes are traced through the material pixels around them (8-connected),
    so they come out up to a pixel too large: fine for limits of filling.

    See Also
    --------
    slicelab.toolpath.distance.level_rings : sub-pixel rings of a distance field.

    Examples
    --------
    >>> m = np.zeros((6, 8), bool); m[1:5, 1:7] = True; m[2:4, 3:5] = False
    >>> [np.round(r, 6).tolist() for r in mask_rings(GridMask(m, 0, 0, 1.0), m)]
    [[[6.0, 1.0], [6.0, 4.0], [1.0, 4.0], [1.0, 1.0]], [[3.0, 4.0], [5.0, 3.0], [4.0, 1.0], [2.0, 2.0]]]
    """
    import cv2
    if not mask.any():
        return []
    cs, hier = cv2.findContours(mask.astype(np.uint8), cv2.RETR_CCOMP, cv2.CHAIN_APPROX_SIMPLE)
    rings = []
    for c, h in zip(cs, hier[0]):  # over contours
        c = cv2.approxPolyDP(c, tolerance, True).reshape(-1, 2).astype(np.float64)
        if len(c) < 3:
            continue
        xy = grid.xy(c[:, 1], c[:, 0])
        area = signed_area(xy)
        if abs(area) < 4 * grid.pixel_size ** 2:
            continue
        hole = h[3] >= 0  # RETR_CCOMP: outer boundaries, and holes whose parent is one
        rings.append(xy if (area > 0) != hole else xy[::-1])
    return rings


def medial_fill(grid: GridMask, uncovered: np.ndarray, w: float, min_width: float):
    """Polylines along the medial axis of the parts of `uncovered` at least `min_width` wide.

    Returns the polylines (mm) and the extrusion width at each vertex (the
    local width of the uncovered part, between `min_width` and 1.5 w).

    See Also
    --------
    slicelab.geometry.trace_skeleton : the skeleton's chains.

    References
    ----------
    T. Y. Zhang, C. Y. Suen, "A fast parallel algorithm for thinning digital
    patterns", Communications of the ACM 27(3), 1984 (``skimage.morphology.skeletonize``).

    Examples
    --------
    >>> g = GridMask(np.zeros((20, 60), bool), 0, 0, 0.05)
    >>> strip = np.zeros((20, 60), bool); strip[7:13, 5:55] = True   # 0.3 mm x 2.5 mm
    >>> lines, widths = medial_fill(g, strip, 0.4, 0.2)
    >>> len(lines), round(float(np.hypot(*np.diff(lines[0], axis=0).T).sum()), 1), round(float(widths[0].max()), 3)
    (1, 2.3, 0.275)
    """
    import cv2
    from skimage.morphology import skeletonize
    p = grid.pixel_size
    rows, cols = np.nonzero(uncovered)
    if len(rows) == 0:
        return [], []
    # Work in the box of the uncovered pixels only (usually a small part of the tile).
    r0, c0 = rows.min() - 2, cols.min() - 2
    sub = np.zeros((rows.max() - r0 + 3, cols.max() - c0 + 3), np.uint8)
    sub[rows - r0, cols - c0] = 1
    dist = cv2.distanceTransform(sub, cv2.DIST_L2, cv2.DIST_MASK_PRECISE)
    threshold = max(min_width / (2 * p) + 0.25, 1.5)  # a strip n px wide reaches n/2 (even n), (n+1)/2
    seeds = dist >= threshold
    if not seeds.any():
        return [], []
    _, lab = cv2.connectedComponents(sub, connectivity=8)
    sub = np.isin(lab, np.unique(lab[seeds]))
    # skeletonize gives a one-pixel skeleton even across strips of even width (medial_axis does not).
    d = cv2.distanceTransform(sub.astype(np.uint8), cv2.DIST_L2, cv2.DIST_MASK_PRECISE)
    skel = skeletonize(sub) & (d >= threshold - 1)
    polylines, widths = [], []
    for path in trace_skeleton(skel):  # over gap-fill chains
        width_px = d[path[:, 0], path[:, 1]].astype(np.float64)
        # Douglas-Peucker by OpenCV (skimage's approximate_polygon is the same algorithm, but
        # importing it loads scipy.signal: half a second in every worker of a print plan).
        simple = cv2.approxPolyDP(path.astype(np.int32).reshape(-1, 1, 2), 0.5, False).reshape(-1, 2)
        # Widths follow the simplified vertices (nearest skeleton pixel of each).
        near = np.argmin(np.abs(path[:, None, :] - simple[None]).sum(-1), axis=0)
        xy = grid.xy(simple[:, 0] + r0, simple[:, 1] + c0)
        if np.hypot(*np.diff(xy, axis=0).T).sum() < 0.5 * w:
            continue
        polylines.append(xy)
        widths.append(np.clip((2 * width_px[near] - 0.5) * p, min_width, 1.5 * w))
    return polylines, widths


def layer_perimeters(layer, line_width: float = 0.4, n_perimeters: int = 2, *, pixel_size: float = 0.05,
                     rule: str = "nonzero", overlap: float = 0.15, tolerance: float | None = None,
                     solid: GridMask | None = None, min_gap_width: float | None = None) -> Perimeters:
    """Perimeters of a layer by erosion, with the regions left for filling.

    Parameters
    ----------
    layer : Section or LayerRaster
    line_width : float, default 0.4
        Extrusion width w (mm).
    n_perimeters : int, default 2
        Number of perimeters, at offsets w/2, 3w/2, ...
    pixel_size : float, default 0.05
        Used when `layer` is a Section.
    rule : {"nonzero", "evenodd"}
        Used when `layer` is a Section.
    overlap : float, default 0.15
        How far (in line widths) the filling's extrusion overlaps the last
        perimeter: its centre lines stop at ``n_perimeters w + w/2 - overlap w``.
    tolerance : float, optional
        Simplification tolerance (mm); default a tenth of a pixel.
    solid : GridMask, optional
        Where the filling must be solid; the fill region is split into
        `Perimeters.solid` (inside the mask) and `Perimeters.fill`.
    min_gap_width : float, optional
        Narrowest gap or thin wall that gets gap fill (default w/2).

    Returns
    -------
    Perimeters

    See Also
    --------
    slicelab.toolpath.distance.distance_field, slicelab.toolpath.distance.level_rings : the levels' rings.
    medial_fill : the gap fill.
    slicelab.toolpath.paths.layer_paths : the perimeters with filling, in print order.

    Examples
    --------
    >>> import slicelab
    >>> from slicelab.samples import box
    >>> s = slicelab.section(box((0, 0, 0), (10, 6, 1)), (0, 0, .5), (0, 0, 1))
    >>> per = layer_perimeters(s, 0.4, 2, pixel_size=0.1)
    >>> [round(abs(p.area), 6) for level in per.rings for p in level]
    [53.76, 42.24]
    """
    raster = layer if isinstance(layer, LayerRaster) else rasterize(layer, pixel_size, rule=rule)
    w = float(line_width)
    if not (w > 0 and np.isfinite(w)):
        raise ValueError(f"line width must be a positive number, got {line_width!r}")
    if n_perimeters < 0:
        raise ValueError(f"perimeter count must be >= 0, got {n_perimeters!r}")
    p = raster.pixel_size
    tol = 0.1 * p if tolerance is None else float(tolerance)
    levels = (np.arange(n_perimeters) + 0.5) * w
    fill_level = n_perimeters * w + 0.5 * w - overlap * w
    min_gap = 0.5 * w if min_gap_width is None else float(min_gap_width)
    rings_by_level = [[] for _ in range(n_perimeters)]
    fill_rings, solid_rings, gaps, gap_w, fields = [], [], [], [], []
    thin = 0
    for tile, segs in zip(raster.tiles, raster.segments):  # over tiles
        index = SegmentIndex(segs, 2 * p)  # short pieces: fewer second rounds in `nearest`
        # The filling limit needs no sub-pixel accuracy: only perimeter levels are refined.
        fld = distance_field(tile, index, levels)
        fields.append(fld)
        for k, level in enumerate(levels):  # over levels
            rings_by_level[k] += level_rings(fld, level, tolerance=tol, index=index)
        # The filling limit needs no sub-pixel accuracy (its lines end inside the perimeters'
        # overlap): pixel contours of the mask, from OpenCV, are plenty and ten times cheaper.
        # (Half a pixel lower: mask contours run through the boundary pixels' centres.)
        fill_mask = _opened(fld.values, fill_level - 0.5 * p, 0.5 * w, p)
        if solid is None:
            fill_rings += mask_rings(tile, fill_mask)
        else:
            inside = solid.window(tile.row0, tile.col0, tile.shape)
            fill_rings += mask_rings(tile, fill_mask & ~inside)
            solid_rings += mask_rings(tile, fill_mask & inside)
        g, gw = _gap_fill(tile, fld.values, fill_mask, levels, w, min_gap)
        gaps += g
        gap_w += gw
        if n_perimeters:
            import cv2
            n_lab, lab = cv2.connectedComponents(tile.mask.view(np.uint8), connectivity=8)
            # An island the first level reaches has pixels just above it: the field climbs
            # from below the level at the boundary by at most ~1.5 px a step, so it cannot
            # step over a band 3 px wide. Those few pixels say which islands are reached.
            lv = float(levels[0])
            ring = cv2.findNonZero(cv2.inRange(fld.values, lv, lv + 3 * p))
            reached = np.zeros(n_lab, bool)
            if ring is not None:
                x, y = ring.reshape(-1, 2).T
                reached[lab[y, x]] = True
            thin += int(np.count_nonzero(~reached[1:]))
    return Perimeters(w, levels, [level_polygons(r) for r in rings_by_level], fill_level,
                      level_polygons(fill_rings), level_polygons(solid_rings), gaps, gap_w, thin, fields)
