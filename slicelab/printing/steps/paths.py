"""One layer's toolpaths in print order, and how well they cover the layer.

`layer_paths` turns a section into ``external_contour_segments`` (one
closed polyline per island's outer boundary), ``internal_contour_segments``
(hole boundaries and inner perimeters) and ``filling_segments`` (an infill
pattern of `slicelab.printing.fill.PATTERNS`, rectilinear zigzags by default),
plus gap fill along the medial axis of what perimeters miss. Islands are
printed nearest first: the outer perimeter, then the inner ones level by
level, gap fill, then filling (the outside of the part first, then its
inside). Each loop's seam is put at its vertex nearest to the nozzle, and
open paths are entered from their nearer end, which keeps travel short.

Every path is simplified to a `resolution` (PrusaSlicer's ``gcode_resolution``,
0.0125 mm) before it is returned, keeping its corners
(`slicelab.printing.steps.simplify`). The filling's limits are pixel contours, up to
half a pixel off the exact offset in a staircase of pixel steps; they are
simplified at a pixel (at most the filling's overlap with the perimeters)
before the pattern fills them, so the links of the zigzags follow the
limit's shape, not its pixels.

See Also
--------
slicelab.printing.roles : the roles of the paths and how outputs name them.
"""
from __future__ import annotations

import numpy as np

from ...geometry.polygons import Polygon, points_in_ring, signed_area
from ...geometry.spatial import SegmentIndex
from ..fill.lines import line_spacing, rectilinear
from ..grid.masks import reach_disc
from ..fill import fill_pattern
from .perimeters import Perimeters, layer_perimeters, level_polygons, medial_fill, perimeter_band, split_by_mask
from ..grid.raster import GridMask, LayerRaster, draw_polylines, raster_blocks, rasterize
from ..roles import ISLAND_ROLES
from .simplify import simplify_paths, simplify_rings
from ..table import LayerPaths

__all__ = ["SEAMS", "layer_paths", "coverage_map", "covered_pixels"]


#: Where a loop starts (its seam): the vertex nearest the nozzle, the rearmost (largest y), or
#: the one nearest the seam of the layer below (`layer_paths`' `seam_point`; rearmost without one).
SEAMS = ("nearest", "rear", "aligned")


def _closed_from(ring: np.ndarray, pos: np.ndarray, seam: str = "nearest", seam_point=None) -> np.ndarray:
    """The ring as a closed polyline starting at its seam vertex (`SEAMS`)."""
    if seam == "aligned" and seam_point is not None:
        k = int(np.argmin(np.hypot(*(ring - np.asarray(seam_point)).T)))
    elif seam in ("rear", "aligned"):
        back = np.flatnonzero(ring[:, 1] >= ring[:, 1].max() - 1e-9)
        k = int(back[np.argmin(ring[back, 0])])  # the rearmost, then leftmost
    else:
        k = int(np.argmin(np.hypot(*(ring - pos).T)))
    return np.concatenate((ring[k:], ring[:k + 1]))


def _island_of(points: np.ndarray, exteriors: list, areas: np.ndarray) -> np.ndarray:
    """Index of the smallest exterior containing each point (-1 if none)."""
    out = np.full(len(points), -1, np.int64)
    best = np.full(len(points), np.inf)
    if len(points) == 0:
        return out
    for k, ext in enumerate(exteriors):  # over islands
        inside = points_in_ring(points, ext)
        sel = inside & (areas[k] < best)
        out[sel], best[sel] = k, areas[k]
    return out


def layer_paths(section, line_width: float = 0.4, n_perimeters: int = 2, infill_density: float = 0.2,
                angle: float = 45.0, pixel_size: float | None = None, *, layer_index: int = 0,
                rule: str = "nonzero", overlap: float = 0.15, solid: GridMask | None = None,
                solid_angle: float | None = None, top=None, bridges=(), start=None, raster: LayerRaster | None = None,
                tolerance: float | None = None, pattern: str = "rectilinear",
                resolution: float = 0.0125, seam: str = "nearest", seam_point=None,
                external_first: bool = False) -> LayerPaths:
    """The toolpaths of one layer: perimeters, gap fill and filling, in print order.

    Parameters
    ----------
    section : Section
    line_width : float, default 0.4
        Extrusion width w (mm).
    n_perimeters : int, default 2
        Perimeters per island, at w/2, 3w/2, ... from the boundary.
    infill_density : float, default 0.2
        Sparse filling density, a fraction in [0, 1]; lines are ``w / infill_density`` apart.
    angle : float, default 45
        Filling direction (degrees); odd layers (`layer_index`) turn rectilinear filling by 90.
    pixel_size : float, optional
        Raster pixel size (mm); default half the line width.
    layer_index : int, default 0
        Parity decides the filling angle (45 / 135 by default).
    rule : {"nonzero", "evenodd"}
        Fill rule for overlapping shells.
    overlap : float, default 0.15
        Overlap of the filling with the last perimeter, in line widths.
    solid : GridMask, optional
        Region (world grid, same pixel size) to fill solid at 100% with
        `solid_angle`: the print planner passes top and bottom skins here.
    solid_angle : float, optional
        Angle of solid filling; default the layer's filling angle.
    top : GridMask or BlockMask, optional
        The part of `solid` that the layer above leaves exposed (top skin): solid
        lines mostly inside it are of kind ``"top"``.
    bridges : sequence of Bridge, optional
        Regions over nothing held by the layer below (`slicelab.printing.steps.overhangs`): the
        solid filling inside each is laid in lines along its angle, kind ``"bridge"``.
    start : (2,) array_like, optional
        Nozzle position before the layer (default: the layer's lower-left corner).
    raster : LayerRaster, optional
        A raster of `section` already made (same pixel size and rule).
    tolerance : float, optional
        The perimeter stage's contour simplification (mm), default a tenth of a pixel.
    pattern : str, default "rectilinear"
        Sparse filling pattern, a name of `slicelab.printing.fill.PATTERNS`;
        solid filling is rectilinear.
    resolution : float, default 0.0125
        Every path is simplified to this tolerance (mm; 0 keeps every vertex).
    seam : {"nearest", "rear", "aligned"}
        Where each perimeter loop starts (`SEAMS`): nearest the nozzle, at the rear, or
        nearest `seam_point` (the planner passes the seam of the layer below).
    seam_point : (2,) array_like, optional
        For ``seam="aligned"``.
    external_first : bool, default False
        Print each island's outer perimeter (and its holes' walls) before the inner ones;
        by default the perimeters go from the innermost out, the outer one last, so it is laid
        against material already there.

    Returns
    -------
    LayerPaths

    See Also
    --------
    slicelab.printing.steps.perimeters.layer_perimeters : the perimeters, filling regions and gap fill.
    slicelab.printing.fill.lines.rectilinear : the zigzag filling.
    slicelab.printing.fill.fill_pattern : the sparse filling's patterns.
    slicelab.printing.steps.simplify.simplify_paths : the paths' simplification.
    coverage_map : how the paths cover the layer.

    Examples
    --------
    >>> import slicelab
    >>> from slicelab.samples import box
    >>> s = slicelab.section(box((0, 0, 0), (10, 6, 1)), (0, 0, .5), (0, 0, 1))
    >>> lp = layer_paths(s, 0.4, 2, 0.2, pixel_size=0.1)
    >>> len(lp.external_contour_segments), len(lp.internal_contour_segments), len(lp.filling_segments)
    (1, 1, 1)
    >>> lp.sequence[:2]
    (('internal', 0), ('external', 0))
    """
    w = float(line_width)
    if not (0 <= infill_density <= 1):
        raise ValueError(f"infill density must be in [0, 1], got {infill_density!r}")
    if raster is None:
        pixel_size = 0.5 * w if pixel_size is None else float(pixel_size)
        raster = rasterize(section, pixel_size, rule=rule, band=perimeter_band(w, n_perimeters, overlap, pixel_size))
    if solid is not None and solid.pixel_size != raster.pixel_size:
        raise ValueError("the solid mask must be on the layer's pixel grid (same pixel size)")
    per = layer_perimeters(raster, w, n_perimeters, overlap=overlap, solid=solid, tolerance=tolerance)
    fill_angle = float(angle) + 90.0 * (layer_index % 2)
    z = float(section.z) if hasattr(section, "z") else 0.0
    limit = max(float(resolution), min(raster.pixel_size, overlap * w))
    fills, kinds = [], []
    if infill_density > 0 and per.fill:
        sparse = fill_pattern(pattern, _simplified(per.fill, limit), line_spacing(w, infill_density), angle,
                              layer_index=layer_index, z=z if np.isfinite(z) else 0.0)
        fills += sparse
        kinds += ["sparse"] * len(sparse)
    solid_polys = per.solid
    for b in bridges:  # over the layer's bridges, few
        if not solid_polys:
            break
        inside, outside = split_by_mask(solid_polys, b.mask, 4 * raster.pixel_size ** 2)
        if inside:
            lines = rectilinear(_simplified(level_polygons(inside), limit), w, b.angle)
            fills += lines
            kinds += ["bridge"] * len(lines)
            solid_polys = level_polygons(outside)
    if solid_polys:
        solid_paths = rectilinear(_simplified(solid_polys, limit), w,
                                  fill_angle if solid_angle is None else solid_angle)
        fills += solid_paths
        kinds += _skin_kinds(solid_paths, top)

    gap_fill, gap_widths = list(per.gap_fill), list(per.gap_widths)
    if per.solid or (infill_density >= 1 and per.fill):  # solid filling, bridges included
        solid_region = list(per.solid) + (list(per.fill) if infill_density >= 1 else [])
        g, gw = _solid_gaps(per, fills, [] if infill_density >= 1 else per.fill, solid_region)
        gap_fill += g
        gap_widths += gw

    # Islands: the outer rings of the first perimeter (or the section's own polygons).
    level0 = per.rings[0] if per.rings else []
    exteriors = [p.exterior for p in level0] if level0 else [p.exterior for p in section.polygons]
    areas = np.array([abs(signed_area(e)) for e in exteriors])
    if seam not in SEAMS:
        raise ValueError(f"seam must be one of {', '.join(SEAMS)}, got {seam!r}")
    loops_internal = []  # (level, ring, kind): inner perimeters, and the walls of holes at level 0
    for k, polys in enumerate(per.rings):
        for p in polys:
            if k > 0:
                loops_internal.append((k, p.exterior, "internal"))
            loops_internal += [(k, h, "hole" if k == 0 else "internal") for h in p.holes]
    groups: dict[int, dict[str, list]] = {}

    def put(island, role, item):
        groups.setdefault(int(island), {r: [] for r in ISLAND_ROLES})[role].append(item)

    if level0:
        for i in range(len(level0)):
            put(i, "external", i)
    rep = lambda items: np.array([x[0] for x in items]).reshape(-1, 2)  # noqa: E731
    owner = _island_of(rep([r for _, r, _ in loops_internal]), exteriors, areas)
    for j, o in enumerate(owner):
        put(o, "internal", j)
    loose = -1
    owner = _island_of(rep(gap_fill), exteriors, areas)
    for j, o in enumerate(owner):
        if o < 0:  # a thin wall with no perimeter: an island of its own
            o, loose = loose, loose - 1
        put(o, "gap_fill", j)
    owner = _island_of(rep(fills), exteriors, areas)
    for j, o in enumerate(owner):
        if o < 0:
            o, loose = loose, loose - 1
        put(o, "filling", j)

    lo = section.bounds()[0] if len(section.segments) else np.zeros(2)
    pos = np.asarray(lo if start is None else start, np.float64)
    out_kind, out_paths, out_w = [], [], []  # the table's rows, in print order
    travel = 0.0
    first = True

    def go(path):
        nonlocal pos, travel, first
        if not first:
            travel += float(np.hypot(*(path[0] - pos)))
        first = False
        pos = path[-1]

    def entry_points(g):
        pts = []
        for role in ISLAND_ROLES:
            for j in g[role]:
                if role == "external":
                    pts.append(level0[j].exterior)
                elif role == "internal":
                    pts.append(loops_internal[j][1])
                elif role == "gap_fill":
                    pts.append(gap_fill[j][[0, -1]])
                else:
                    pts.append(fills[j][[0, -1]])
            if pts:
                break
        return np.concatenate(pts)

    def open_order(cands, paths_of, loops):
        """Yield the paths in print order, each with how to print it: from its start, from its
        end (reversed), or, for a loop (when `loops`), from its vertex nearest the nozzle. The
        next is the nearest to the nozzle (the first in `cands` on ties, its start before its end)."""
        paths = [paths_of(j) for j in cands]
        ring = np.array([loops and len(q) > 3 and np.array_equal(q[0], q[-1]) for q in paths], bool)
        ends = np.array([[q[0], q[-1]] for q in paths], np.float64).reshape(-1, 2, 2)
        alive = np.ones(len(paths), bool)
        while alive.any():  # over the paths: one vectorised distance per pick
            d = np.hypot(*(ends - pos).transpose(2, 0, 1))
            d[~alive] = np.inf
            for i in np.flatnonzero(ring & alive):  # loops (concentric filling), few
                d[i] = (float(np.min(np.hypot(*(paths[i][:-1] - pos).T))), np.inf)
            i, e = divmod(int(np.argmin(d)), 2)
            alive[i] = False
            yield cands[i], ("loop" if ring[i] else ("end" if e else "start"))

    remaining = dict(groups)
    while remaining:  # over islands, nearest first
        key = min(remaining, key=lambda g: float(np.min(np.hypot(*(entry_points(remaining[g]) - pos).T))))
        g = remaining.pop(key)
        # The island's loops: its outer perimeter, its holes' walls and the inner perimeters,
        # level by level (outer level first, or innermost first with the outer loop last).
        loops = [(0, level0[j].exterior, "external") for j in g["external"]]
        loops += [loops_internal[j] for j in g["internal"]]
        order = sorted(set(lv for lv, _, _ in loops), reverse=not external_first)
        for level in order:  # over perimeter levels, few
            same = [lp for lp in loops if lp[0] == level]
            outer = [lp for lp in same if lp[2] == "external"]
            rest = [lp for lp in same if lp[2] != "external"]
            queue = outer + rest if external_first else rest
            while queue or (not external_first and outer):
                if not queue:
                    queue, outer = outer, []
                i = min(range(len(queue)), key=lambda i: float(np.min(np.hypot(*(queue[i][1] - pos).T))))
                lp = queue.pop(i)
                path = _closed_from(lp[1], pos, seam, seam_point)
                go(path)
                out_kind.append(lp[2]), out_paths.append(path), out_w.append(w)
        for role, source in (("gap_fill", gap_fill), ("filling", fills)):
            for j, how in open_order(list(g[role]), lambda j: source[j], role == "filling"):  # nearest first
                path = {"start": source[j], "end": source[j][::-1]}.get(how)
                path = _closed_from(source[j][:-1], pos) if path is None else path
                go(path)
                if role == "gap_fill":
                    out_kind.append("gap_fill"), out_paths.append(path)
                    out_w.append(gap_widths[j][::-1] if how == "end" else gap_widths[j])
                else:
                    out_kind.append(kinds[j]), out_paths.append(path), out_w.append(w)
    # Clean paths: each simplified to the resolution (ends, seams and corners stay, so the
    # travel between paths is unchanged).
    gap = np.array([k == "gap_fill" for k in out_kind], bool)
    simple = list(out_paths)
    for rows, widths in ((np.flatnonzero(~gap), None), (np.flatnonzero(gap), [out_w[i] for i in np.flatnonzero(gap)])):
        if widths is None:
            got = simplify_paths([out_paths[i] for i in rows], resolution)
        else:
            got, widths = simplify_paths([out_paths[i] for i in rows], resolution, widths)
            for i, gw in zip(rows, widths):
                out_w[i] = gw
        for i, q in zip(rows, got):
            simple[i] = q
    return LayerPaths(tuple(out_kind), tuple(simple), tuple(out_w), travel, w,
                      section.z if hasattr(section, "z") else float("nan"), per.thin_walls, per)


def _skin_kinds(paths: list, top) -> list:
    """``"top"`` for each solid path whose length lies mostly in the `top` mask, else ``"solid"``.

    Each segment is judged at its midpoint (its ends lie on the region's limit).
    """
    if top is None or not paths:
        return ["solid"] * len(paths)
    owner = np.repeat(np.arange(len(paths)), [max(len(q) - 1, 0) for q in paths])
    a = np.concatenate([q[:-1] for q in paths])
    b = np.concatenate([q[1:] for q in paths])
    inside, length = top.contains(0.5 * (a + b)), np.hypot(*(b - a).T)
    on_top = np.bincount(owner, length * inside, len(paths))
    total = np.bincount(owner, length, len(paths))
    return ["top" if t > 0.5 * n else "solid" for t, n in zip(on_top, total)]


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
    >>> counts, grid = coverage_map(layer_paths(s, 0.4, 2, 1.0, pixel_size=0.1), 0.1)
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
