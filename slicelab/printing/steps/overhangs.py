"""Overhangs and bridges: what a layer lays over nothing.

A layer's material not over the layer below is a mask difference on the shared
pixel grid. A wall leaning by less than the overhang threshold steps out by
less than ``layer_height * tan(threshold)`` per layer, and the extrusion below
holds it; what lies farther than that from the material below hangs in the
air. Each connected part of it is then either a **bridge**, when material
below holds it on two sides (its lines are laid straight across, from one
anchor towards the other), or an **overhang**, which needs support. Held on
one side only, a part may also be bridged out from that side, all but a band
along the layer's outline, which stays an overhang (``edge_band``, as
PrusaSlicer's ``dont_support_bridges``). An island with no material at all
under it starts in mid-air.

Every layer pays a mask difference and a dilation of the layer below by the
reach, read on the difference's blocks only, which leave exactly the pixels
that hang; only layers where some do pay more, over the bounding box of those
pixels.

See Also
--------
slicelab.printing.planner.plan : runs it on every layer and reports what is not held.
slicelab.printing.pipeline.layer_paths : lays bridge lines across each bridge.

References
----------
.. [1] PrusaSlicer's "bridge detection" (BridgeDetector) takes the direction of
   a bridge from its anchors in the same spirit: lines that span from one
   supported edge to another.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from ...geometry.blocks import FULL
from ...geometry.polygons import loop_edges, signed_area
from ...geometry.spatial import SegmentIndex
from ..grid.masks import BlockMask, GridMask, dilate_mask, near_mask, reach_disc

__all__ = ["Bridge", "EDGE_MARGIN", "LayerOverhangs", "layer_overhangs", "mark_overhangs", "shortest_span",
           "PERIMETER_KINDS"]

#: The kinds of rows whose stretches over nothing are overhang perimeters.
PERIMETER_KINDS = ("external", "hole", "internal")
#: Width (mm) beyond the perimeters of the band along a one-sided bridge's outline that stays
#: unheld (`layer_overhangs`' `edge_band`): with two 0.4 mm perimeters, 2.8 mm, about the band
#: PrusaSlicer supports under a mushroom's cap (its support lines under ``data/mushroom.stl``'s cap
#: lie within some 3 mm of the rim, read by hand from the G-code ``scripts/bench_slice.py`` has it write).
EDGE_MARGIN = 2.0
#: Offsets (row, column) of the pixels around a pixel (`mark_overhangs`): a point lies within 0.71
#: pixel of its pixel's centre, so material on its side of a boundary holds one of them.
_AROUND = np.array([(dr, dc) for dr in (-1, 0, 1) for dc in (-1, 0, 1) if dr or dc])


@dataclass(frozen=True, eq=False)
class Bridge:
    """A region held by material below on two sides (or on one, see `layer_overhangs`).

    Attributes
    ----------
    mask : GridMask
        The region over nothing (world grid).
    angle : float
        Direction of its lines (degrees): from one anchor to the other.
    span : float
        Distance between the two anchors' centres (mm); held on one side, how far the region
        reaches from it.
    """

    mask: GridMask
    angle: float
    span: float


@dataclass(frozen=True, eq=False)
class LayerOverhangs:
    """What a layer lays over nothing.

    Attributes
    ----------
    bridges : tuple of Bridge
    overhang_area : float
        Area over nothing, beyond the threshold and not bridged (mm^2): what supports would hold.
    mid_air : int
        Islands with no material under them at all.
    where : (2,) ndarray or None
        A point of the largest unheld part (mm), to name it in a warning.
    unheld : tuple of (k, 2) ndarray
        The outlines of the unheld parts (mm, polygons through their edge pixels' centres), outer
        rings counter-clockwise and holes clockwise: where supports go. A part unheld whole is
        outlined with all of its step over nothing (what the wall below reaches too): on a
        leaning wall, what hangs beyond the reach is a strip narrower than a pixel that moves
        along the wall from layer to layer, and supports under it alone would not join up.
    angle : float
        The steepest overhang measured (degrees from the vertical): how far the layer reaches
        beyond the one below, over the layer height; 0 when it stays within the threshold.
    """

    bridges: tuple = ()
    overhang_area: float = 0.0
    mid_air: int = 0
    where: np.ndarray | None = None
    unheld: tuple = ()
    angle: float = 0.0


def _crop(mask) -> tuple[int, int, tuple] | None:
    """The window (row0, col0, shape) of a mask's set pixels, or None if it has none."""
    m = mask.mask
    rows, cols = np.flatnonzero(m.any(axis=1)), np.flatnonzero(m.any(axis=0))
    if len(rows) == 0:
        return None
    return (mask.row0 + int(rows[0]), mask.col0 + int(cols[0]),
            (int(rows[-1] - rows[0]) + 1, int(cols[-1] - cols[0]) + 1))


def _hanging_window(below, diff, kernel: np.ndarray, hangs=None):
    """The window (row0, col0, shape) of the pixels of `diff` with no pixel of `below` within
    the offsets of `kernel` (`slicelab.printing.grid.masks.reach_disc`), or None if there are none;
    and the (rows, cols) of those `hangs` says do not hang after all (or None).

    On block masks the test runs on the blocks of `diff` alone (`near_mask`): its cost follows
    the few blocks where the layers differ, not the layer. `hangs(xy)` (optional) tells from
    the pixels' centres (mm) which hang: an exact test, or None when it cannot say.
    """
    if not (isinstance(diff, BlockMask) and isinstance(below, BlockMask) and diff.blocks.size == below.blocks.size):
        return _crop(GridMask(diff.mask & ~dilate_mask(below, kernel).window(diff.row0, diff.col0, diff.shape),
                              diff.row0, diff.col0, diff.pixel_size)), None
    g = diff.blocks
    bsz = g.size
    free = diff.bits & ~near_mask(below, g.rows, g.cols, kernel)
    full = g.n_full > 0  # a whole block over nothing: its pixels may all hang
    if not (full or free.any()):  # (most layers)
        return None, None
    kk, rr, cc = np.nonzero(free)
    rows, cols = g.rows[kk] * bsz + rr, g.cols[kk] * bsz + cc
    refuted = None
    keep = hangs(np.stack([cols, rows], 1) * diff.pixel_size) if hangs is not None and len(rows) else None
    if keep is not None and not keep.all():
        refuted = rows[~keep], cols[~keep]
        rows, cols = rows[keep], cols[keep]
    if full:
        fr, fc = np.nonzero(g.table == FULL)
        fr, fc = (fr + g.row0) * bsz, (fc + g.col0) * bsz
        rows = np.concatenate((rows, fr, fr + bsz - 1))
        cols = np.concatenate((cols, fc, fc + bsz - 1))
    if len(rows) == 0:
        return None, None
    r0, c0 = int(rows.min()), int(cols.min())
    return (r0, c0, (int(rows.max()) - r0 + 1, int(cols.max()) - c0 + 1)), refuted


def layer_overhangs(mine, below, layer_height: float, *, threshold: float = 50.0, islands=None,
                    min_anchor: float | None = None, edge_band: float | None = None,
                    angle: float = 0.0, below_section=None, anchor: float = 0.0) -> LayerOverhangs:
    """Bridges, unheld overhang and mid-air islands of a layer.

    Parameters
    ----------
    mine : GridMask or BlockMask
        The layer's material.
    below : GridMask or BlockMask or None
        The material of the layer under it (None: nothing).
    layer_height : float
        How far below the layer below lies (mm).
    threshold : float, default 50
        Overhang angle from the vertical (degrees) up to which a wall holds itself.
    islands : LayerRaster, optional
        The layer's raster (`mine` is its material): its islands with nothing under them are
        counted in `LayerOverhangs.mid_air` (without it, the layer counts as one island).
    min_anchor : float, optional
        Smallest anchor (mm^2) that holds a bridge; default four pixels.
    edge_band : float, optional
        Given, a part held on one side only is bridged from that side too, all but a band this
        wide (mm) along the layer's outline, which stays unheld: supports then hold the
        perimeters and the bridge's free edges, as PrusaSlicer's ``dont_support_bridges`` does.
        None (default): such a part is unheld whole.
    angle : float, default 0
        Direction (degrees) of such a one-sided bridge's lines when it surrounds its anchor (a
        mushroom's cap around its stem); otherwise they run from the anchor towards the part.
    below_section : Section, optional
        The layer below's section: a pixel the masks find hanging is then checked against it, its
        centre's exact distance to the section's boundary against the reach (the masks put that
        boundary half a pixel beyond the last pixel below, give or take half a pixel).
    anchor : float, default 0
        How far (mm) each bridge reaches onto the material below it, within the layer: its lines
        are anchored there (PrusaSlicer's bridges run some 3 mm onto their supports).

    Returns
    -------
    LayerOverhangs

    Examples
    --------
    >>> import numpy as np
    >>> from slicelab.printing.grid.masks import GridMask
    >>> pillars = np.zeros((40, 100), bool); pillars[:, :20] = pillars[:, 80:] = True
    >>> deck = np.ones((40, 100), bool)
    >>> ov = layer_overhangs(GridMask(deck, 0, 0, 0.1), GridMask(pillars, 0, 0, 0.1), 0.2)
    >>> len(ov.bridges), round(ov.bridges[0].angle % 180, 1), round(ov.bridges[0].span, 1), ov.overhang_area
    (1, 0.0, 6.2, 0.0)
    >>> ov = layer_overhangs(GridMask(deck, 0, 0, 0.1), GridMask(pillars & (np.arange(100) < 50), 0, 0, 0.1), 0.2)
    >>> len(ov.bridges), round(ov.overhang_area, 1)     # a cantilever: held on one side only
    (0, 31.2)
    >>> ov = layer_overhangs(GridMask(deck, 0, 0, 0.1), GridMask(pillars & (np.arange(100) < 50), 0, 0, 0.1), 0.2,
    ...                      edge_band=1.0)            # bridged out from the pillar, but for its edges
    >>> len(ov.bridges), round(ov.bridges[0].angle % 180, 1), round(ov.overhang_area, 1)
    (1, 0.0, 17.6)
    """
    import cv2
    p = mine.pixel_size
    mid_air = 0
    n_islands = len(islands.island_boxes) if islands is not None else 0
    if below is None:
        diff = mine
        mid_air = n_islands or 1
    else:
        diff = mine - below
        if n_islands > 1:  # the islands' pixels over the layer below, in their boxes
            over = islands.island_pixels(mine & below)
            if not over.all():  # some island has none: has it pixels at all?
                mid_air = int(np.count_nonzero((islands.island_pixels(mine) > 0) & (over == 0)))
        elif n_islands == 1 and mine.area > 0 and (mine & below).area == 0:
            mid_air = 1
    if diff.area == 0:
        return LayerOverhangs(mid_air=mid_air)
    reach = layer_height * math.tan(math.radians(threshold))
    # A first, cheap pass, block by block: a pixel hangs when no pixel of the layer below lies
    # within the reach and half a pixel of it (the test the distances below make), so the layer
    # below dilated by that disc leaves exactly the hanging pixels: most layers end here.
    hangs = None
    if below_section is not None and below is not None:  # near the threshold, the section's exact distances decide

        def exact(xy):  # (called only on layers with pixels found hanging: the index is made then)
            loops = [lp for lp in below_section.loops if len(lp) >= 3]
            d = SegmentIndex(loop_edges(loops), 4 * p).within(xy, reach + 2 * p) if loops else None
            return None if d is None else d > reach
        hangs = exact

    window, refuted = (_crop(diff), None) if below is None else _hanging_window(below, diff, reach_disc(reach, p, 0.5 * p), hangs)
    if window is None:
        return LayerOverhangs(mid_air=mid_air)
    hold = int(math.ceil(anchor / p))
    margin = int(math.ceil(reach / p)) + 3 + hold
    row0, col0 = window[0] - margin, window[1] - margin
    shape = (window[2][0] + 2 * margin, window[2][1] + 2 * margin)
    free = diff.window(row0, col0, shape)
    held = below.window(row0, col0, shape) if below is not None else np.zeros(shape, bool)
    # What lies farther than `reach` from the material below hangs in the air. Distances run
    # between pixel centres: the edge of the material below lies half a pixel before its last one.
    dist = cv2.distanceTransform((~held).astype(np.uint8), cv2.DIST_L2, cv2.DIST_MASK_PRECISE) * p
    hanging = free & (dist - 0.5 * p > reach)
    if refuted is not None:  # farther than the reach from the pixels below, not from their section
        inside = (refuted[0] >= row0) & (refuted[0] < row0 + shape[0]) & (refuted[1] >= col0) & \
            (refuted[1] < col0 + shape[1])
        hanging[refuted[0][inside] - row0, refuted[1][inside] - col0] = False
    steepest = math.degrees(math.atan2(max(float(dist[free].max()) - 0.5 * p, 0.0), layer_height)) \
        if free.any() else 0.0
    count, labels, stats, _ = cv2.connectedComponentsWithStats(hanging.astype(np.uint8), connectivity=8)
    min_px = 4 if min_anchor is None else max(1, int(min_anchor / (p * p)))
    grow = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (2 * (margin - hold) + 1, 2 * (margin - hold) + 1))
    win = _Hanging(mine, free, held, mine.window(row0, col0, shape), dist, row0=row0, col0=col0, p=p, hold=hold,
                   edge_band=edge_band)
    bridges, area, worst, where, outlines = [], 0.0, 0, None, []
    h, w = shape
    for k in range(1, count):  # over the hanging parts, few
        if stats[k, cv2.CC_STAT_AREA] < min_px:
            continue
        # The part's box, widened by what the two dilations reach: the work follows the part.
        x, y = stats[k, cv2.CC_STAT_LEFT], stats[k, cv2.CC_STAT_TOP]
        ya, yb = max(0, y - margin - 3), min(h, y + stats[k, cv2.CC_STAT_HEIGHT] + margin + 3)
        xa, xb = max(0, x - margin - 3), min(w, x + stats[k, cv2.CC_STAT_WIDTH] + margin + 3)
        part = labels[ya:yb, xa:xb] == k
        region = cv2.dilate(part.astype(np.uint8), grow).astype(bool) & free[ya:yb, xa:xb]
        bridge, part, footprint = win.judge(part, region, (ya, yb, xa, xb), min_px, angle)
        if bridge is not None:
            bridges.append(bridge)
        if footprint is None:
            continue
        px = int(np.count_nonzero(part))
        area += px * p * p
        # Its outline and holes (an edge band is a ring), turned as `LayerOverhangs.unheld` says.
        contours, tree = cv2.findContours(footprint.astype(np.uint8), cv2.RETR_CCOMP, cv2.CHAIN_APPROX_SIMPLE)
        for c, (_, _, _, parent) in zip(contours, tree[0] if tree is not None else ()):  # over rings, few
            if len(c) >= 3:
                r = (c.reshape(-1, 2) + (col0 + xa, row0 + ya)) * p
                outlines.append(r if (signed_area(r) > 0) == (parent < 0) else r[::-1])
        if px > worst:
            rr, cc = np.nonzero(part)
            i = len(rr) // 2
            worst, where = px, np.array([(col0 + xa + cc[i]) * p, (row0 + ya + rr[i]) * p])
    return LayerOverhangs(tuple(bridges), area, mid_air, where, tuple(outlines), steepest)


class _Hanging:
    """A window of a layer around what it lays over nothing: the arrays each hanging part is
    judged on (`_Hanging.judge`), with world offset (`row0`, `col0`).

    `free`: the layer's pixels not over the layer below; `held`: the layer below's; `mine`: the
    layer's; `dist`: the distance (mm) to the layer below; `hold`: a bridge's anchor (pixels);
    `edge_band`: see `layer_overhangs`.
    """

    def __init__(self, layer, free, held, mine, dist, *, row0: int, col0: int, p: float, hold: int, edge_band):
        self.layer, self.free, self.held, self.mine, self.dist = layer, free, held, mine, dist
        self.row0, self.col0, self.p, self.hold, self.edge_band = row0, col0, p, hold, edge_band
        self._edge = None

    def near_edge(self) -> np.ndarray:
        """The window's pixels within the edge band of the layer's outline, made on first need."""
        import cv2
        if self._edge is None:  # (distances to the outline, from a window wide enough to see it)
            p, (h, w) = self.p, self.free.shape
            b = int(math.ceil(self.edge_band / p)) + 1
            inside = self.layer.window(self.row0 - b, self.col0 - b, (h + 2 * b, w + 2 * b)).astype(np.uint8)
            self._edge = cv2.distanceTransform(inside, cv2.DIST_L2, cv2.DIST_MASK_PRECISE)[b:b + h, b:b + w] * p \
                <= self.edge_band + 0.5 * p
        return self._edge

    def bridge(self, region: np.ndarray, box, angle: float, span: float) -> Bridge:
        """A bridge over `region` (at `box` in the window), its lines running `hold` pixels onto
        the material below, within the layer."""
        import cv2
        ya, yb, xa, xb = box
        if self.hold:
            disc = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (2 * self.hold + 1, 2 * self.hold + 1))
            onto = cv2.dilate(region.astype(np.uint8), disc).astype(bool) & self.held[ya:yb, xa:xb] \
                & self.mine[ya:yb, xa:xb]
            region = region | onto
        return Bridge(GridMask(region, self.row0 + ya, self.col0 + xa, self.p), float(angle), float(span))

    def judge(self, part: np.ndarray, region: np.ndarray, box, min_px: int, angle: float):
        """What a hanging part is: ``(bridge or None, the part left unheld, its footprint or None)``.

        Held on two sides, a bridge from one anchor towards the other; held all round (a roof over
        a hollow), a bridge across its shortest span; held on one side and given an edge band,
        bridged out from it but for the band, which stays unheld; else unheld whole, with all of
        its step over nothing (what supports hold).
        """
        import cv2
        ya, yb, xa, xb = box
        ring = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (5, 5))
        anchors = cv2.dilate(region.astype(np.uint8), ring).astype(bool) & self.held[ya:yb, xa:xb]
        n_a, _, a_stats, a_centres = cv2.connectedComponentsWithStats(anchors.astype(np.uint8), connectivity=8)
        big = sorted((j for j in range(1, n_a) if a_stats[j, cv2.CC_STAT_AREA] >= min_px),
                     key=lambda j: -a_stats[j, cv2.CC_STAT_AREA])
        if len(big) >= 2:
            (x0, y0), (x1, y1) = a_centres[big[0]], a_centres[big[1]]
            return self.bridge(region, box, math.degrees(math.atan2(y1 - y0, x1 - x0)),
                               math.hypot(x1 - x0, y1 - y0) * self.p), part, None
        if big and not (cv2.dilate(region.astype(np.uint8), ring).astype(bool) & ~self.mine[ya:yb, xa:xb]).any():
            across, span = shortest_span(region)  # (held all round)
            return self.bridge(region, box, across, span * self.p), part, None
        band = self.near_edge()[ya:yb, xa:xb] & part if big and self.edge_band is not None else None
        # Held on one side: bridged out from it, all but the edge band (a part within the band,
        # a sliver along a leaning wall, has nothing to bridge and stays unheld whole).
        if band is not None and np.count_nonzero(part) - np.count_nonzero(band) >= min_px:
            rr, cc = np.nonzero(part)
            (xa0, ya0), (xp, yp) = a_centres[big[0]], (cc.mean(), rr.mean())
            out = math.degrees(math.atan2(yp - ya0, xp - xa0)) if math.hypot(xp - xa0, yp - ya0) > 2 else angle
            bridge = self.bridge(region, box, out, float(self.dist[ya:yb, xa:xb][part].max()))
            return bridge, band, (band if band.any() else None)
        return None, part, region  # held nowhere: supports hold all of its step over nothing


def shortest_span(region: np.ndarray, step: float = 3.0) -> tuple[float, float]:
    """The direction (degrees) of the shortest lines across a region, and their length (pixels).

    Lines laid at an angle cross the region in chords; the longest of them (the mean of the
    longest tenth, so that a stray pixel does not decide) is the span a strand must bridge. The
    angle of the shortest such span, tried every `step` degrees, is the bridge's (PrusaSlicer's
    bridge detector likewise prefers the direction of the shortest anchored lines). Each line
    is a bin, a pixel wide, of the coordinate across it; its pixels measure its chord.

    Examples
    --------
    >>> roof = np.zeros((40, 100), bool); roof[5:35, 10:90] = True    # 80 x 30 pixels
    >>> angle, span = shortest_span(roof)
    >>> angle % 180, round(span)                                     # across the 30 pixels
    (90.0, 30)
    """
    rows, cols = np.nonzero(region)
    if len(rows) == 0:
        return 0.0, 0.0
    angles = np.arange(0.0, 180.0, step)
    t = np.radians(angles)
    across = np.rint(-np.sin(t)[:, None] * cols[None] + np.cos(t)[:, None] * rows[None]).astype(np.int64)
    across -= across.min(axis=1, keepdims=True)
    spans = []
    for a in across:  # over the angles tried, few
        chords = np.bincount(a)
        chords = chords[chords > 0]
        spans.append(chords[chords >= np.percentile(chords, 90)].mean())
    best = int(np.argmin(spans))
    return float(angles[best]), float(spans[best])


def _over_exactly(points, over, below, section, rule: str) -> np.ndarray:
    """`over` with the points it holds not over the material but with material in a pixel
    around theirs decided again by their winding numbers in the section: near its boundary,
    the nearest pixel centre may lie on the other side of it."""
    from ...geometry.segment_kernels import winding_at
    loops = [np.asarray(lp, np.float64) for lp in section.loops if len(lp) >= 3]
    out = np.flatnonzero(~over)
    if not loops or not len(out):
        return over
    q = np.rint(points[out] / below.pixel_size).astype(np.int64)  # their pixels, as `contains` finds them
    near = out[below.at(q[:, 1, None] + _AROUND[:, 0], q[:, 0, None] + _AROUND[:, 1]).any(axis=1)]
    if len(near):
        edges = np.ascontiguousarray(loop_edges(loops))
        w = winding_at(np.ascontiguousarray(points[near]), edges)
        over = over.copy()
        over[near] = (w != 0) if rule == "nonzero" else (w % 2 == 1)
    return over


def mark_overhangs(paths, below, section=None, *, rule: str = "nonzero"):
    """The layer's paths with the stretches of its perimeters that lie over nothing marked.

    A perimeter segment hangs when its middle (on the extrusion's centre line) is not over
    the material of the layer below: more than half the extrusion's width is in the air.
    Those stretches print as PrusaSlicer's ``Overhang perimeter``, slowly
    (`LayerPaths.pieces`, `slicelab.gcode.writer`).

    Parameters
    ----------
    paths : LayerPaths
    below : GridMask or BlockMask
        The material of the layer below.
    section : Section, optional
        The layer below's section: a middle the mask puts over nothing, with material in a pixel
        around its own, is then decided exactly, by its winding number (`rule`). Without
        it, the mask decides: its pixel centres lie up to 0.7 pixel from the points, so at
        0.2 mm pixels a wall leaning well under the threshold is marked in places.
    rule : {"nonzero", "evenodd"}, default "nonzero"

    Returns
    -------
    LayerPaths
        With `LayerPaths.hang` set (or unchanged when nothing hangs).

    Examples
    --------
    >>> import numpy as np
    >>> from slicelab.printing.grid.masks import GridMask
    >>> from slicelab.printing.table import LayerPaths
    >>> loop = np.array([[1, 1], [5, 1], [5, 3], [1, 3], [1, 1]], float)
    >>> lp = LayerPaths(("external",), (loop,), (0.4,), 0.0, 0.4)
    >>> below = GridMask(np.ones((50, 40), bool), 0, 0, 0.1)          # x up to 3.95 mm
    >>> [(k, q.tolist()) for k, q, _ in mark_overhangs(lp, below).pieces()]
    [('external', [[1.0, 1.0], [5.0, 1.0]]), ('overhang', [[5.0, 1.0], [5.0, 3.0]]), ('external', [[5.0, 3.0], [1.0, 3.0], [1.0, 1.0]])]
    """
    rows = [i for i, k in enumerate(paths.kind) if k in PERIMETER_KINDS]
    if not rows:
        return paths
    qs = [paths.paths[i] for i in rows]
    mids = np.concatenate([0.5 * (q[1:] + q[:-1]) for q in qs])
    over = below.contains(mids)
    if section is not None and not over.all():
        over = _over_exactly(mids, over, below, section, rule)
    if over.all():
        return paths
    hang = list(paths.hang) if paths.hang else [None] * len(paths.kind)
    bounds = np.cumsum([0] + [len(q) - 1 for q in qs])
    for i, a, b in zip(rows, bounds[:-1], bounds[1:]):  # over perimeter rows
        h = ~over[a:b]
        hang[i] = h if h.any() else None
    return replace(paths, hang=tuple(hang))
