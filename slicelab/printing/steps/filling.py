"""The fill step: a layer's region inside its perimeters filled, sparse or solid, bridges and gaps.

The region the walls leave (`slicelab.printing.steps.perimeters.Perimeters`: its
sparse part and the part inside the skins) is filled by the pattern of the
infill settings (`slicelab.printing.fill.PATTERNS`), but for its regions smaller
than `solid_infill_below_area`, which are solid; the skins by solid
rectilinear lines (along each bridge's own angle over a bridge), and what the
solid lines leave uncovered (slivers where they run nearly parallel to the
wall) by gap fill along its medial axis.

The filling's limits are pixel contours, up to half a pixel off the exact
offset in a staircase of pixel steps; they are simplified at a pixel (at most
the filling's overlap with the perimeters) before the pattern fills them, so
the links of the zigzags follow the limit's shape, not its pixels.

See Also
--------
slicelab.printing.pipeline.plan_layer : the steps of a layer in order.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ...geometry.polygons import Polygon
from ..fill import fill_pattern
from ..fill.lines import line_spacing, rectilinear
from ..grid.masks import reach_disc
from ..grid.raster import GridMask, draw_polylines, raster_blocks
from .perimeters import Perimeters, level_polygons, medial_fill, split_by_mask
from .simplify import simplify_rings

__all__ = ["Fills", "fill_step"]


@dataclass(frozen=True, eq=False)
class Fills:
    """A layer's filling: its paths and their kinds (``sparse``, ``solid``, ``top``, ``bridge``), and
    its gap fill with the width at each vertex."""

    paths: list
    kinds: list
    gap_fill: list
    gap_widths: list


def fill_step(per: Perimeters, infill, *, line_width: float, pixel_size: float, resolution: float,
              layer_index: int = 0, z: float = 0.0, top=None, bridges=(), solid_angle: float | None = None) -> Fills:
    """Fill what the walls leave: sparse infill, solid skins (top and bridge lines among them), gaps.

    Parameters
    ----------
    per : Perimeters
        The walls step's result: the sparse region (``fill``), the solid one (``solid``) and gap fill.
    infill : Infill
        The infill settings: density, angle, pattern, overlap.
    line_width, pixel_size, resolution : float
        mm; the filling's limits are simplified to a pixel (at most the overlap), at least the resolution.
    layer_index : int
        Parity turns the filling 90 degrees.
    z : float
        The layer's height, for patterns that vary with it.
    top : mask, optional
        The skin the layer above leaves exposed: filled apart from the rest of the skin, its lines
        of kind ``"top"``.
    bridges : sequence of Bridge
        Regions over nothing: the solid filling inside each is laid along its angle, kind ``"bridge"``.
    solid_angle : float, optional
        Angle of solid filling; default the layer's filling angle.

    Returns
    -------
    Fills

    See Also
    --------
    slicelab.printing.fill.fill_pattern : the sparse patterns.
    slicelab.printing.fill.lines.rectilinear : the solid lines.
    """
    w = float(line_width)
    density = infill.infill_density
    fill_angle = float(infill.infill_angle) + 90.0 * (layer_index % 2)
    limit = max(float(resolution), min(pixel_size, infill.infill_overlap * w))
    fills, kinds = [], []
    # A region of sparse infill too small to hold its pattern (a narrow rib, a boss) is filled
    # solid, as PrusaSlicer's solid_infill_below_area does.
    small = [q for q in per.fill if q.area < infill.solid_infill_below_area] if density < 1 else []
    sparse_polys = [q for q in per.fill if q.area >= infill.solid_infill_below_area] if small else per.fill
    if density > 0 and sparse_polys:
        sparse = fill_pattern(infill.infill_pattern, _simplified(sparse_polys, limit), line_spacing(w, density),
                              infill.infill_angle, layer_index=layer_index, z=z if np.isfinite(z) else 0.0)
        fills += sparse
        kinds += ["sparse"] * len(sparse)
    solid_polys = list(per.solid) + small
    for b in bridges:  # over the layer's bridges, few
        if not solid_polys:
            break
        inside, outside = split_by_mask(solid_polys, b.mask, 4 * pixel_size ** 2)
        if inside:
            lines = rectilinear(_simplified(level_polygons(inside), limit), w, b.angle)
            fills += lines
            kinds += ["bridge"] * len(lines)
            solid_polys = level_polygons(outside)
    angle = fill_angle if solid_angle is None else solid_angle
    if solid_polys and top is not None:  # the top surface: its own region, as PrusaSlicer's top infill
        inside, outside = split_by_mask(solid_polys, top, 4 * pixel_size ** 2)
        if inside:
            lines = rectilinear(_simplified(level_polygons(inside), limit), w, angle)
            fills += lines
            kinds += ["top"] * len(lines)
            solid_polys = level_polygons(outside)
    for group in _apart(solid_polys, small):  # (each set of disjoint regions filled on its own)
        solid_paths = rectilinear(_simplified(group, limit), w, angle)
        fills += solid_paths
        kinds += ["solid"] * len(solid_paths)
    gap_fill, gap_widths = list(per.gap_fill), list(per.gap_widths)
    if per.solid or small or (density >= 1 and per.fill):  # solid filling, bridges included
        solid_region = list(per.solid) + small + (list(per.fill) if density >= 1 else [])
        g, gw = _solid_gaps(per, fills, [] if density >= 1 else sparse_polys, solid_region)
        gap_fill += g
        gap_widths += gw
    return Fills(fills, kinds, gap_fill, gap_widths)


def _apart(solid: list, small: list) -> list:
    """The solid regions in groups whose polygons do not overlap: the small regions filled solid
    apart from the layer's skins (a small region may touch or overlap a skin's polygon where the
    two were traced from different masks, and lines clipped to overlapping rings pair their
    crossings wrongly)."""
    ids = {id(q) for q in small}
    rest = [q for q in solid if id(q) not in ids]
    kept = [q for q in solid if id(q) in ids]
    return [g for g in (rest, kept) if g]


def _simplified(polygons: list, tolerance: float) -> list:
    """Polygons with every ring simplified to a tolerance (the filling's limits)."""
    rings = simplify_rings([r for p in polygons for r in (p.exterior, *p.holes)], tolerance)
    out, k = [], 0
    for p in polygons:  # over polygons
        n = 1 + len(p.holes)
        ext, *holes = rings[k:k + n]
        k += n
        if len(ext) >= 3:
            out.append(Polygon(ext, tuple(h for h in holes if len(h) >= 3), p.depth))
    return out


def _solid_gaps(per: Perimeters, fills: list, sparse: list, region: list):
    """Gap fill for what solid filling misses (slivers where its lines run nearly parallel).

    Only the box of the solid `region` (polygons) is looked at, with a margin of a line and a
    half: the work follows the solid region, not the tile.
    """
    w = per.line_width
    rings = [r for polys in per.rings for p in polys for r in (p.exterior, *p.holes)]
    out, widths = [], []
    if not region:
        return out, widths
    corners = np.concatenate([q.exterior for q in region])
    lo, hi = corners.min(axis=0), corners.max(axis=0)
    for fld in per.fields:  # over tiles
        g = fld.grid
        p = g.pixel_size

        def box(margin):  # world pixel rows and columns of the region's box widened by `margin` px
            return (int(np.floor(lo[1] / p)) - margin, int(np.ceil(hi[1] / p)) + margin + 1,
                    int(np.floor(lo[0] / p)) - margin, int(np.ceil(hi[0] / p)) + margin + 1)

        r0, r1, c0, c1 = box(int(np.ceil(1.5 * w / p)) + 3)
        r0, c0 = max(g.row0, r0), max(g.col0, c0)
        r1, c1 = min(g.row0 + g.shape[0], r1), min(g.col0 + g.shape[1], c1)
        if r1 <= r0 or c1 <= c0:
            continue
        shape = (r1 - r0, c1 - c0)
        cov = draw_polylines(shape, r0, c0, p, rings, w, closed=True)
        cov |= draw_polylines(shape, r0, c0, p, list(fills) + list(per.gap_fill), w)
        uncovered = g.window(r0, c0, shape) & (cov < 128)
        if sparse:  # pixels within half a line and a pixel of the sparse filling are its lines'
            import cv2
            edges = np.concatenate([np.stack([r, np.concatenate((r[1:], r[:1]))], 1)
                                    for q in sparse for r in (q.exterior, *q.holes)])
            # The sparse region drawn on blocks along its boundary (the cost follows it), then
            # dilated by the disc of that reach: the pixels a distance transform would find within it.
            held = raster_blocks(edges, r0, c0, shape, p, band=0.0).window(r0, c0, shape)
            uncovered &= ~cv2.dilate(held.view(np.uint8), reach_disc(0.5 * w + p, p)).view(bool)
        # Only the region's box, widened by what its lines' ends reach: there the distance to the
        # sparse region is exact (the margin holds every sparse pixel that near).
        ir0, ir1, ic0, ic1 = box(int(np.ceil((0.5 * w + p) / p)))
        inner = np.zeros(shape, bool)
        inner[max(0, ir0 - r0):max(0, ir1 - r0), max(0, ic0 - c0):max(0, ic1 - c0)] = True
        uncovered &= inner
        a, b = medial_fill(GridMask(uncovered, r0, c0, p), uncovered, w, 0.5 * w)
        out += a
        widths += b
    return out, widths
