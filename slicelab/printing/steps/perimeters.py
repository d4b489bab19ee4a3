"""Perimeters by erosion: level sets of the exact distance field, filling limits, gap fill.

The perimeters of a layer are level sets of the distance to its boundary:
the k-th one (k = 0, 1, ...) runs at ``(k + 1/2) w`` for line width w, so
each extrusion covers the band ``[k w, (k + 1) w]``. The distance field is
exact wherever those contours pass (`slicelab.printing.grid.distance`), so the
perimeters lie on the true offsets, sharp corners included.

Every level gets its own hierarchy (erosion splits islands and merges
holes). The filling's region is one more level set, where the region opened
by a disc of w/2 keeps it (slivers too thin to fill are left out). Material
that no perimeter covers and that is wide enough to print (thin walls, gaps
between perimeters) is filled along its medial axis (`slicelab.printing.steps.gapfill`).

All of it reads the distance field no deeper than `perimeter_depth`, so only
the blocks of the layer within that distance of the boundary hold pixels:
the work follows the boundary, and pixels deep inside are never touched.

See Also
--------
slicelab.printing.grid.distance : the distance field and its level sets.
slicelab.printing.pipeline : the perimeters, gap fill and filling in print order.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from types import SimpleNamespace

import numpy as np

from ...geometry.contours import march, march_blocks
from ...geometry.polygons import Polygon, build_polygons, loop_hierarchy, points_in_ring, signed_area
from ...geometry.regions import overlay, valid_region
from ...geometry.spatial import SegmentIndex
from ..grid.distance import distance_field, level_rings
from .gapfill import disc, medial_fill, medial_fill_blocks, uncovered_blocks
from ..grid.masks import BlockMask, GridMask, bits_in_blocks
from ..grid.raster import BAND, LayerRaster, rasterize
from .simplify import simplify_rings

__all__ = ["level_polygons", "Perimeters", "layer_perimeters", "medial_fill", "mask_rings", "perimeter_depth",
           "perimeter_band", "split_by_mask"]


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
    areas = np.array([signed_area(r) for r in rings])  # once, for the nesting and the kinds
    return build_polygons(rings, *loop_hierarchy(rings, areas), areas)


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


def mask_rings(grid: GridMask, mask: np.ndarray, tolerance: float = 0.5) -> list[np.ndarray]:
    """Rings (material on the left, mm) through the boundary pixel centres of a mask, from OpenCV.

    Holes are traced through the material pixels around them (8-connected),
    so they come out up to a pixel too large: fine for limits of filling.

    See Also
    --------
    slicelab.printing.grid.distance.level_rings : sub-pixel rings of a distance field.

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


def perimeter_depth(line_width: float, n_perimeters: int, overlap: float = 0.15) -> float:
    """How far from the boundary (mm) the perimeters, gap fill and filling limit read the distance field.

    The filling's limit lies at ``n w + w/2 - overlap w``; slivers of its region
    thinner than w are opened away, which reads the field w/2 deeper.

    Examples
    --------
    >>> round(perimeter_depth(0.4, 2), 6)
    1.14
    """
    w = float(line_width)
    return n_perimeters * w + 0.5 * w - overlap * w + 0.5 * w


def perimeter_band(line_width: float, n_perimeters: int, overlap: float, pixel_size: float) -> float:
    """The band of pixels (mm) a layer's raster must hold along its boundary for its perimeters.

    `perimeter_depth` and three pixels beyond it (the contours' cells and the
    filters' halos), and at least `slicelab.printing.grid.raster.BAND`: a raster
    made with this band is used as it is, one with a narrower band is made again.

    Examples
    --------
    >>> round(perimeter_band(0.4, 2, 0.15, 0.2), 6)
    1.74
    """
    return max(BAND, perimeter_depth(line_width, n_perimeters, overlap) + 3 * float(pixel_size))


def _mask_rings(mask) -> list[np.ndarray]:
    """Rings (mm, material on the left) half way between a mask's pixels and the pixels beside them."""
    p = mask.pixel_size
    if isinstance(mask, BlockMask):
        # Full blocks beside empty ones are held too: the contour may run along their seam.
        g, bits = mask.blocks.seamed(mask.bits, False, True)
        r0 = c0 = 0
        rings = march_blocks(bits.astype(np.float32), 0.5, g, 0.0, 1.0)
    else:
        r0, c0 = mask.row0 - 1, mask.col0 - 1
        rings = march(np.pad(mask.mask, 1).astype(np.float32), 0.5)
    rings = [c for c in rings if len(c)]
    if not rings:
        return []
    # Every ring simplified in one compiled pass: a quarter pixel keeps the corners of the staircases.
    rings = simplify_rings(rings, 0.25)
    sizes = np.array([len(c) for c in rings])
    rc = np.concatenate(rings)
    xy = np.stack([(c0 + rc[:, 1]) * p, (r0 + rc[:, 0]) * p], 1)
    out = []
    ends = np.cumsum(sizes).tolist()
    for ring in (xy[b - k:b] for b, k in zip(ends, sizes.tolist())):  # over rings: the smallest are dropped
        if len(ring) >= 3 and abs(signed_area(ring)) >= 4 * p * p:
            out.append(ring)
    return out


def _mask_polygons(rings: list[np.ndarray]) -> list:
    """Shapely polygons of a mask's rings (`_mask_rings`): the counter-clockwise rings with the
    clockwise ones inside them as holes, in the order of their exteriors.

    The same polygons as `level_polygons`: rings traced round a mask's pixels never cross, so a
    hole lies in the smallest outer ring that holds its first vertex, and where only one outer
    ring's box holds it, that ring is the one (no point-in-ring test).
    """
    import shapely
    areas = np.array([signed_area(r) for r in rings])
    outer = np.flatnonzero(areas >= 0)
    lo = np.array([r.min(axis=0) for r in rings]).reshape(-1, 2)
    hi = np.array([r.max(axis=0) for r in rings]).reshape(-1, 2)
    holes = {int(k): [] for k in outer}
    extra = {}
    for k in np.flatnonzero(areas < 0):  # over holes
        v = rings[k][0]
        cand = outer[np.all((v >= lo[outer]) & (v <= hi[outer]), axis=1) & (np.abs(areas[outer]) >= -areas[k])]
        if len(cand) > 1:  # islands in holes: the smallest outer ring that holds the vertex
            cand = cand[[bool(points_in_ring(v[None], rings[j])[0]) for j in cand]]
            cand = cand[np.argsort(areas[cand], kind="stable")[:1]]
        if len(cand):
            holes[int(cand[0])].append(rings[k])
        else:  # no outer ring round it: an inside-out ring, taken reversed
            extra[int(k)] = rings[k][::-1]
    polys = {k: shapely.Polygon(rings[k], holes[k]) for k in holes}
    polys.update({k: shapely.Polygon(r) for k, r in extra.items()})
    return [polys[k] for k in sorted(polys)]


def _rings_of(geometry) -> list[np.ndarray]:
    """Exterior (counter-clockwise) and hole (clockwise) rings of a shapely geometry's polygons."""
    import shapely
    rings = []
    for poly in shapely.get_parts(shapely.orient_polygons(geometry)):  # over polygons
        if poly.geom_type != "Polygon" or poly.is_empty:
            continue
        rings += [np.asarray(r.coords)[:-1] for r in (poly.exterior, *poly.interiors)]
    return rings


def split_by_mask(polygons: list[Polygon], mask, min_area: float = 0.0) -> tuple[list, list]:
    """Rings of the parts of polygons inside and outside a mask (mm, material on the left).

    The mask's boundary is taken half way between its pixels and the pixels
    beside them; the polygons are cut along it by shapely.

    Parameters
    ----------
    polygons : list of Polygon
    mask : GridMask or BlockMask
    min_area : float
        Rings enclosing less are dropped.

    Returns
    -------
    inside, outside : list of (k, 2) ndarray

    Examples
    --------
    >>> from slicelab.printing.grid.masks import GridMask
    >>> sq = np.array([[0, 0], [4, 0], [4, 4], [0, 4]], float)
    >>> m = GridMask(np.ones((10, 2), bool), 0, 0, 1.0)   # x in [-0.5, 1.5]
    >>> inside, outside = split_by_mask(level_polygons([sq]), m)
    >>> [round(abs(signed_area(r)), 6) for r in inside + outside]
    [6.0, 10.0]
    """
    import shapely
    if not polygons:
        return [], []
    # The polygons of one level are disjoint, and so are a mask's: each side is one valid shape,
    # unless simplification made two of them touch or a ring pinch (`valid_region` mends that).
    walls = valid_region([shapely.Polygon(q.exterior, q.holes) for q in polygons])
    rings = _mask_rings(mask)
    cut = valid_region(_mask_polygons(rings)) if rings else shapely.MultiPolygon()

    def keep(geometry):
        return [r for r in _rings_of(geometry) if abs(signed_area(r)) >= min_area]

    return keep(overlay(shapely.intersection, walls, cut)), keep(overlay(shapely.difference, walls, cut))


def _opened(field, level: float, radius: float) -> np.ndarray:
    """The region {field >= level} opened by a disc of `radius` mm, on the field's blocks (bool).

    Parts of the region thinner than 2 radius (slivers where fill lines would run nearly
    parallel and cover nothing) are removed; elsewhere its edge is the level set, since the
    dilated core reaches 1.5 px past it.
    """
    import cv2
    p = field.grid.pixel_size
    kernel = disc(radius / p + 1.5)
    image, h = field.wide_mosaic(kernel.shape[0] // 2)
    core = cv2.compare(image, float(level + radius), cv2.CMP_GE)
    region = field.grid.blocks.cores(cv2.dilate(core, kernel), h).view(bool)
    return region & (field.blocks >= level)


#: The boundary is simplified to this fraction of a pixel before distances are measured to it:
#: a dense scan's section then has a few times fewer segments, and the offsets move by at most
#: this (a micrometre at the default pixel), far inside their accuracy.
_DISTANCE_TOLERANCE = 0.01


def _solid_share(field, fill: np.ndarray, solid) -> tuple[int, int]:
    """Pixels of a tile's filling region (`fill` on the field's blocks, and its full blocks), and
    how many of them the `solid` mask holds: all of them or none spare cutting the region."""
    from ...geometry.blocks import FULL
    g = field.grid.blocks
    whole = g.size * g.size
    fr, fc = np.nonzero(g.table == FULL)
    total = int(np.count_nonzero(fill)) + len(fr) * whole
    held = int(np.count_nonzero(fill & bits_in_blocks(solid, g.rows, g.cols, g.size)))
    held += int(np.count_nonzero(bits_in_blocks(solid, fr + g.row0, fc + g.col0, g.size)))
    return total, held


def _one_island(loops: list) -> bool:
    """Whether the loops are one outer loop (material on its left) and holes inside it."""
    areas = np.array([signed_area(lp) for lp in loops])
    if np.count_nonzero(areas > 0) != 1 or np.count_nonzero(areas == 0):
        return False
    outer = loops[int(np.argmax(areas))]
    holes = [lp[0] for lp, a in zip(loops, areas) if a < 0]
    return not holes or bool(points_in_ring(np.array(holes), outer).all())


def _islands_unreached(raster, t: int, rings: list, field, level: float) -> int:
    """Islands of tile t that the first perimeter level does not reach (too thin for a perimeter).

    An island that is one outer loop with holes in it is reached if a ring of the level lies in
    its box (`LayerRaster.island_boxes`); if every island of the tile is such an island, none is
    missed. Otherwise the tile's missed islands are counted on its pixels (`_islands_missed`).
    """
    members = np.flatnonzero(raster.loop_tile == t)
    islands = raster.loop_island[members] if len(raster.loop_island) else np.zeros(len(members), np.int64)
    ids = np.flatnonzero(np.bincount(islands))  # the islands present (np.unique would load numpy.ma)
    if len(raster.island_boxes):
        r0, c0, r1, c1 = raster.island_boxes[ids].T
    else:  # a raster made without islands: its tile is one box
        r0 = c0 = np.array([np.iinfo(np.int64).min])
        r1 = c1 = np.array([np.iinfo(np.int64).max])
    at = np.array([ring[0] for ring in rings], np.float64).reshape(-1, 2) / raster.pixel_size
    x, y = at[:, :1], at[:, 1:]
    reached = ((x >= c0) & (x <= c1) & (y >= r0) & (y <= r1)).any(axis=0)
    for island, ok in zip(ids, reached):  # over islands, few
        if not (ok and _one_island([raster.loops[i] for i in members[islands == island]])):
            return _islands_missed(field, level)
    return 0


def _islands_missed(field, level: float) -> int:
    """Islands of a tile the level does not reach (too thin for a perimeter).

    An island the level reaches has pixels just above it: the field climbs from below the level
    at the boundary by at most ~1.5 px a step, so it cannot step over a band 3 px wide. Islands
    missed lie wholly in the blocks near the boundary, each one connected part of them.
    """
    labels, count = field.grid.blocks.components(field.grid.bits)
    p = field.grid.pixel_size
    v = field.blocks
    reached = np.zeros(count + 1, bool)
    reached[labels[(v >= level) & (v <= level + 3 * p)]] = True
    return count - int(np.count_nonzero(reached[1:]))


def layer_perimeters(layer, line_width: float = 0.4, n_perimeters: int = 2, *, pixel_size: float | None = None,
                     rule: str = "nonzero", overlap: float = 0.15, tolerance: float | None = None,
                     solid: GridMask | BlockMask | None = None, min_gap_width: float | None = None) -> Perimeters:
    """Perimeters of a layer by erosion, with the regions left for filling.

    Parameters
    ----------
    layer : Section or LayerRaster
    line_width : float, default 0.4
        Extrusion width w (mm).
    n_perimeters : int, default 2
        Number of perimeters, at offsets w/2, 3w/2, ...
    pixel_size : float, optional
        Used when `layer` is a Section; default half the line width.
    rule : {"nonzero", "evenodd"}
        Used when `layer` is a Section.
    overlap : float, default 0.15
        How far (in line widths) the filling's extrusion overlaps the last
        perimeter: its centre lines stop at ``n_perimeters w + w/2 - overlap w``.
    tolerance : float, optional
        Simplification tolerance (mm); default a tenth of a pixel, at most 0.01 mm.
    solid : GridMask or BlockMask, optional
        Where the filling must be solid; the fill region is split into
        `Perimeters.solid` (inside the mask) and `Perimeters.fill`
        (`split_by_mask`).
    min_gap_width : float, optional
        Narrowest gap or thin wall that gets gap fill (default w/2).

    Returns
    -------
    Perimeters

    See Also
    --------
    slicelab.printing.grid.distance.distance_field, slicelab.printing.grid.distance.level_rings : the levels' rings.
    perimeter_depth : how deep the distance field is computed.
    slicelab.printing.steps.gapfill.medial_fill_blocks : the gap fill.
    slicelab.printing.pipeline.layer_paths : the perimeters with filling, in print order.

    Examples
    --------
    >>> import slicelab
    >>> from slicelab.samples import box
    >>> s = slicelab.section(box((0, 0, 0), (10, 6, 1)), (0, 0, .5), (0, 0, 1))
    >>> per = layer_perimeters(s, 0.4, 2, pixel_size=0.1)
    >>> [round(abs(p.area), 6) for level in per.rings for p in level]
    [53.76, 42.24]
    """
    w = float(line_width)
    if not (w > 0 and np.isfinite(w)):
        raise ValueError(f"line width must be a positive number, got {line_width!r}")
    if n_perimeters < 0:
        raise ValueError(f"perimeter count must be >= 0, got {n_perimeters!r}")
    depth = perimeter_depth(w, n_perimeters, overlap)
    if not isinstance(layer, LayerRaster):
        pixel_size = 0.5 * w if pixel_size is None else float(pixel_size)
        layer = rasterize(layer, pixel_size, rule=rule, band=perimeter_band(w, n_perimeters, overlap, pixel_size))
    raster = layer
    p = raster.pixel_size
    if raster.band < depth + 3 * p:  # too few pixels held along the boundary: hold more
        block = raster.tiles[0].blocks.size if raster.tiles else None
        raster = rasterize(SimpleNamespace(loops=raster.loops), p, rule=raster.rule, band=depth + 3 * p,
                           **({"block": block} if block else {}))
    tol = min(0.1 * p, 0.01) if tolerance is None else float(tolerance)
    levels = (np.arange(n_perimeters) + 0.5) * w
    fill_level = n_perimeters * w + 0.5 * w - overlap * w
    min_gap = 0.5 * w if min_gap_width is None else float(min_gap_width)
    rings_by_level = [[] for _ in range(n_perimeters)]
    fill_rings, gaps, gap_w, fields = [], [], [], []
    thin = 0
    fill_px = solid_px = 0  # pixels of the filling's region, and of its solid part
    for t, (tile, segs) in enumerate(zip(raster.tiles, raster.segments)):  # over tiles
        # Short pieces: fewer second rounds in the k-d tree; runs of pieces joined: fewer
        # candidates near each pixel.
        index = SegmentIndex(segs, 2 * p, join=True, tolerance=_DISTANCE_TOLERANCE * p)
        # Only perimeter levels are refined: the filling limit needs no sub-pixel accuracy.
        fld = distance_field(tile, index, levels, depth=depth)
        fields.append(fld)
        first, mine = [], []
        for k, level in enumerate(levels):  # over levels
            found = level_rings(fld, level, tolerance=tol, index=index)
            rings_by_level[k] += found
            mine += found
            first = found if k == 0 else first
        # The filling's region: its level set where the opening keeps it, the opening's edge
        # elsewhere (the field lowered below the level there), simplified to half a pixel (at
        # most 0.05 mm). Its mask is taken half a pixel lower, as its pixels' centres lie inside
        # the level set.
        fill_mask = _opened(fld, fill_level - 0.5 * p, 0.5 * w)
        lowered = np.where(fill_mask, fld.blocks, np.minimum(fld.blocks, np.float32(fill_level - 0.6 * p)))
        fill_rings += level_rings(fld, fill_level, tolerance=min(0.5 * p, 0.05), values=lowered, index=index)
        if solid is not None:
            total, held = _solid_share(fld, fill_mask, solid)
            fill_px, solid_px = fill_px + total, solid_px + held
        unc = uncovered_blocks(fld, fill_mask, levels, w, mine)
        g, gw = medial_fill_blocks(tile.blocks, unc, p, w, min_gap)
        gaps += g
        gap_w += gw
        if n_perimeters:
            thin += _islands_unreached(raster, t, first, fld, float(levels[0]))
    solid_rings = []
    if solid is not None and fill_rings and 0 < solid_px == fill_px:  # all of the filling is solid
        solid_rings, fill_rings = fill_rings, []
    elif solid is not None and fill_rings and (solid_px or not fill_px):  # a part: cut along the mask
        solid_rings, fill_rings = split_by_mask(level_polygons(fill_rings), solid, 4 * p * p)
    return Perimeters(w, levels, [level_polygons(r) for r in rings_by_level], fill_level,
                      level_polygons(fill_rings), level_polygons(solid_rings), gaps, gap_w, thin, fields)
