"""Layer rasters: a section's material as pixel masks on a world-anchored grid.

Pixel (r, c) of the world grid has its centre at ``(x, y) = (c * p, r * p)``
for pixel size p: rows run along +y and nothing is flipped. A mask keeps only
a window of that grid (``row0``, ``col0`` and its shape), so masks of
different layers line up by integer offsets, whatever their windows.

The material comes from the section's oriented loops by a scanline over
pixel-centre rows: every edge adds its direction (+1 up, -1 down) at the
first pixel centre right of its crossing, and a running sum along the row
gives each pixel centre's winding number. Overlapping shells (CAD exports)
then fill as one region under the nonzero rule, and an overlap becomes a
hole under the even-odd rule. OpenCV gives the contour tree of the mask.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..geometry.polygons import signed_area
from ..geometry.ragged import expand_ranges
from ..geometry.spatial import split_segments

__all__ = ["GridMask", "LayerRaster", "RasterContours", "rasterize", "winding_numbers",
           "raster_hierarchy", "draw_polylines", "RULES"]

RULES = ("nonzero", "evenodd")


@dataclass(frozen=True, eq=False)
class GridMask:
    """A boolean mask on the world-anchored pixel grid.

    Attributes
    ----------
    mask : (h, w) bool ndarray
        ``mask[r, c]`` is the pixel centred at ``((col0 + c) p, (row0 + r) p)``.
    row0, col0 : int
        World grid indices of the window's first row and column.
    pixel_size : float
        p, in mm.

    Examples
    --------
    >>> g = GridMask(np.ones((2, 3), bool), row0=10, col0=-1, pixel_size=0.5)
    >>> g.xy([0, 1], [0, 2]).tolist(), g.area
    ([[-0.5, 5.0], [0.5, 5.5]], 1.5)
    """

    mask: np.ndarray
    row0: int
    col0: int
    pixel_size: float

    @property
    def shape(self) -> tuple[int, int]:
        return self.mask.shape

    @property
    def area(self) -> float:
        """Material area counted in pixels (mm^2)."""
        return float(np.count_nonzero(self.mask)) * self.pixel_size ** 2

    @property
    def transform(self) -> np.ndarray:
        """3x3 affine matrix taking (col, row, 1) array indices to (x, y, 1) in mm.

        Examples
        --------
        >>> GridMask(np.ones((1, 1), bool), 2, 3, 0.1).transform @ [0, 0, 1]
        array([0.3, 0.2, 1. ])
        """
        p = self.pixel_size
        return np.array([[p, 0.0, self.col0 * p], [0.0, p, self.row0 * p], [0.0, 0.0, 1.0]])

    @property
    def extent(self) -> list[float]:
        """matplotlib ``imshow(..., origin="lower", extent=...)`` of the window (pixel edges, mm)."""
        p = self.pixel_size
        h, w = self.shape
        return [(self.col0 - 0.5) * p, (self.col0 + w - 0.5) * p,
                (self.row0 - 0.5) * p, (self.row0 + h - 0.5) * p]

    def xy(self, rows, cols) -> np.ndarray:
        """Millimetre coordinates of (fractional) array indices."""
        rows, cols = np.asarray(rows, np.float64), np.asarray(cols, np.float64)
        return np.stack([(self.col0 + cols) * self.pixel_size, (self.row0 + rows) * self.pixel_size], -1)

    def indices(self, xy) -> np.ndarray:
        """Fractional (row, col) array indices of points in mm (inverse of `xy`)."""
        q = np.asarray(xy, np.float64) / self.pixel_size
        return np.stack([q[..., 1] - self.row0, q[..., 0] - self.col0], -1)

    def window(self, row0: int, col0: int, shape) -> np.ndarray:
        """This mask copied into another window of the same grid (False outside it).

        Examples
        --------
        >>> g = GridMask(np.ones((2, 2), bool), 0, 0, 1.0)
        >>> g.window(1, -1, (2, 2)).astype(int).tolist()
        [[0, 1], [0, 0]]
        """
        h, w = shape
        out = np.zeros((h, w), bool)
        r0, c0 = max(row0, self.row0), max(col0, self.col0)
        r1 = min(row0 + h, self.row0 + self.shape[0])
        c1 = min(col0 + w, self.col0 + self.shape[1])
        if r1 > r0 and c1 > c0:
            out[r0 - row0:r1 - row0, c0 - col0:c1 - col0] = \
                self.mask[r0 - self.row0:r1 - self.row0, c0 - self.col0:c1 - self.col0]
        return out

    def _check(self, other: "GridMask") -> None:
        if other.pixel_size != self.pixel_size:
            raise ValueError("masks on different pixel grids cannot be combined")

    def __and__(self, other: "GridMask") -> "GridMask":
        self._check(other)
        return GridMask(self.mask & other.window(self.row0, self.col0, self.shape), self.row0, self.col0,
                        self.pixel_size)

    def __sub__(self, other: "GridMask") -> "GridMask":
        """Pixels of self that are not in other (e.g. skin: a layer minus the layer above)."""
        self._check(other)
        return GridMask(self.mask & ~other.window(self.row0, self.col0, self.shape), self.row0, self.col0,
                        self.pixel_size)

    def __or__(self, other: "GridMask") -> "GridMask":
        self._check(other)
        r0, c0 = min(self.row0, other.row0), min(self.col0, other.col0)
        r1 = max(self.row0 + self.shape[0], other.row0 + other.shape[0])
        c1 = max(self.col0 + self.shape[1], other.col0 + other.shape[1])
        shape = (r1 - r0, c1 - c0)
        return GridMask(self.window(r0, c0, shape) | other.window(r0, c0, shape), r0, c0, self.pixel_size)

    @staticmethod
    def union(masks, pixel_size: float) -> "GridMask":
        """Union of several masks on one grid (an empty 1x1 mask for none)."""
        masks = list(masks)
        if not masks:
            return GridMask(np.zeros((1, 1), bool), 0, 0, pixel_size)
        out = masks[0]
        for m in masks[1:]:  # over tiles, few
            out = out | m
        return out


@dataclass(frozen=True, eq=False)
class LayerRaster:
    """A section rasterised: one mask per group of islands whose boxes overlap.

    `rasterize` makes one; `raster_hierarchy` gives the contour tree of its masks.

    Attributes
    ----------
    tiles : tuple of GridMask
        Each tile is cropped to the bounding box of its islands plus a margin;
        tiles never overlap in material.
    pixel_size : float
    rule : str
        ``"nonzero"`` or ``"evenodd"``.
    loops : list of (k, 2) ndarray
        The section's closed loops (mm) and ``loop_tile``, the tile of each.
    loop_tile : (L,) int ndarray
    segments : list of (m, 2, 2) ndarray
        Per tile, the pieces (at most 4 px long) of loop edges that bound
        material under the rule (material on one side only); pieces buried
        inside overlapping shells are left out. Exact distances are measured
        to these.
    """

    tiles: tuple
    pixel_size: float
    rule: str
    loops: list
    loop_tile: np.ndarray
    segments: list

    @property
    def area(self) -> float:
        """Material area counted in pixels (mm^2)."""
        return sum(t.area for t in self.tiles)

    def combined(self) -> GridMask:
        """All tiles in one mask (window: the union of the tile windows)."""
        return GridMask.union(self.tiles, self.pixel_size)

    def __repr__(self) -> str:
        return (f"LayerRaster({len(self.tiles)} tiles, {sum(t.mask.size for t in self.tiles)} px, "
                f"p={self.pixel_size:g} mm, rule={self.rule}, area={self.area:.6g} mm2)")


def _edges(loops) -> np.ndarray:
    if not loops:
        return np.zeros((0, 2, 2))
    return np.concatenate([np.stack([lp, np.roll(lp, -1, axis=0)], axis=1) for lp in loops])


def winding_numbers(edges: np.ndarray, row0: int, col0: int, shape, pixel_size: float) -> np.ndarray:
    """Winding number of every pixel centre of a window, by a signed-crossing scanline.

    Parameters
    ----------
    edges : (m, 2, 2) ndarray
        Oriented edges (material on their left) of closed loops, in mm.
    row0, col0, shape
        The window on the world grid.
    pixel_size : float

    Returns
    -------
    (h, w) int32 ndarray
        +1 inside a counter-clockwise loop, -1 inside a clockwise one, summed.

    Notes
    -----
    Row r is crossed by an edge when ``ceil(ymin / p) <= r < ceil(ymax / p)``:
    a vertex shared by two edges gives both the same verdict, so a row through
    a vertex is counted once. Every crossing is one ``bincount`` entry; no
    Python loop runs over edges.

    Examples
    --------
    >>> sq = np.array([[0, 0], [2, 0], [2, 2], [0, 2]], float)
    >>> w = winding_numbers(_edges([sq, sq + 1]), 0, 0, (4, 4), 1.0)
    >>> w[::-1].tolist()
    [[0, 0, 0, 0], [0, 1, 1, 0], [1, 2, 1, 0], [1, 1, 0, 0]]
    """
    h, w = shape
    p = float(pixel_size)
    if len(edges) == 0:
        return np.zeros((h, w), np.int32)
    x0, y0 = edges[:, 0, 0], edges[:, 0, 1]
    x1, y1 = edges[:, 1, 0], edges[:, 1, 1]
    r_lo = np.clip(np.ceil(np.minimum(y0, y1) / p).astype(np.int64), row0, row0 + h)
    r_hi = np.clip(np.ceil(np.maximum(y0, y1) / p).astype(np.int64), row0, row0 + h)
    idx, rows = expand_ranges(r_lo, r_hi - r_lo)
    yr = rows * p
    t = (yr - y0[idx]) / (y1[idx] - y0[idx])
    x = x0[idx] + t * (x1[idx] - x0[idx])
    cols = np.clip(np.ceil(x / p).astype(np.int64) - col0, 0, w)
    # An upward edge has the material on its left: pixels right of it leave a winding.
    step = np.where(y1[idx] > y0[idx], np.int32(-1), np.int32(1))
    # The crossings are few (about two per boundary row) against the window's pixels: added
    # into an int32 table in place, not counted into a float table the size of the window.
    acc = np.zeros((h, w + 1), np.int32)
    np.add.at(acc.reshape(-1), (rows - row0) * (w + 1) + cols, step)
    return np.cumsum(acc, axis=1, dtype=np.int32)[:, :w]


def _apply_rule(winding: np.ndarray, rule: str) -> np.ndarray:
    return winding != 0 if rule == "nonzero" else (winding & 1).astype(bool)


def _groups(lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
    """Connected groups of boxes that overlap (transitively)."""
    n = len(lo)
    if n <= 1:
        return np.zeros(n, np.int64)
    if n > 3000:  # pairwise test too big: one tile
        return np.zeros(n, np.int64)
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components
    overlap = np.all((lo[:, None] <= hi[None]) & (lo[None] <= hi[:, None]), axis=2)
    i, j = np.nonzero(overlap)
    return connected_components(coo_matrix((np.ones(len(i)), (i, j)), shape=(n, n)), directed=False)[1]


def rasterize(section, pixel_size: float = 0.05, *, rule: str = "nonzero", margin: int = 3) -> LayerRaster:
    """Rasterise a section's material on the world-anchored pixel grid.

    Parameters
    ----------
    section : Section
        Its closed loops are used (open chains are left out).
    pixel_size : float, default 0.05
        Pixel size p (mm); pixel centres sit at integer multiples of p.
    rule : {"nonzero", "evenodd"}
        Fill rule for overlapping or inside-out loops.
    margin : int, default 3
        Empty pixels kept around each tile.

    Returns
    -------
    LayerRaster

    Examples
    --------
    >>> import slicelab
    >>> from slicelab.samples import box
    >>> s = slicelab.section(box((0, 0, 0), (2, 1, 1)), (0, 0, 0.5), (0, 0, 1))
    >>> r = rasterize(s, 0.1)
    >>> len(r.tiles), round(r.area, 9), r.tiles[0].row0, r.tiles[0].col0
    (1, 2.0, -3, -3)
    """
    if rule not in RULES:
        raise ValueError(f"rule must be one of {RULES}, got {rule!r}")
    p = float(pixel_size)
    if not (p > 0 and np.isfinite(p)):
        raise ValueError(f"pixel size must be a positive number, got {pixel_size!r}")
    loops = [np.asarray(lp, np.float64) for lp in section.loops if len(lp) >= 3]
    if not loops:
        return LayerRaster((), p, rule, [], np.zeros(0, np.int64), [])
    lo = np.array([lp.min(axis=0) for lp in loops])
    hi = np.array([lp.max(axis=0) for lp in loops])
    # Pixel-index boxes, widened by the margin so tiles that would touch are merged.
    plo = np.floor(lo / p).astype(np.int64) - margin
    phi = np.ceil(hi / p).astype(np.int64) + margin
    group = _groups(plo, phi)
    tiles, seg_lists = [], []
    for g in range(group.max() + 1):  # over tiles, few
        members = np.flatnonzero(group == g)
        c0, r0 = plo[members].min(axis=0)
        c1, r1 = phi[members].max(axis=0)
        shape = (int(r1 - r0 + 1), int(c1 - c0 + 1))
        edges = _edges([loops[k] for k in members])
        winding = winding_numbers(edges, int(r0), int(c0), shape, p)
        mask = _apply_rule(winding, rule)
        tiles.append(GridMask(mask, int(r0), int(c0), p))
        # Pieces of at most 4 px, so an edge that is partly buried by another shell keeps its
        # exposed part (to within one piece).
        pieces, _ = split_segments(edges, 4 * p)
        seg_lists.append(_exposed(pieces, edges, winding, rule, int(r0), int(c0), p))
    return LayerRaster(tuple(tiles), p, rule, loops, group.astype(np.int64), seg_lists)


def _exposed(pieces, edges, winding, rule, row0, col0, p) -> np.ndarray:
    """The pieces of loop edges that bound material; a piece that another shell's edge crosses
    (points near its ends and middle disagree) is cut at the crossings and each part judged on
    its own."""
    votes = [_bounding(pieces, winding, rule, row0, col0, p, at=t) for t in (0.05, 0.5, 0.95)]
    mixed = np.flatnonzero((votes[0] != votes[1]) | (votes[1] != votes[2]))
    out = [pieces[votes[0] & votes[1] & votes[2]]]
    if len(mixed):
        a, d = pieces[mixed, 0], pieces[mixed, 1] - pieces[mixed, 0]
        c, e = edges[:, 0], edges[:, 1] - edges[:, 0]
        den = d[:, None, 0] * e[None, :, 1] - d[:, None, 1] * e[None, :, 0]
        w = c[None] - a[:, None]
        with np.errstate(divide="ignore", invalid="ignore"):
            t = (w[..., 0] * e[None, :, 1] - w[..., 1] * e[None, :, 0]) / den
            u = (w[..., 0] * d[:, None, 1] - w[..., 1] * d[:, None, 0]) / den
        hit = (den != 0) & (t > 0) & (t < 1) & (u >= 0) & (u <= 1)
        for i in range(len(mixed)):  # over crossed pieces: few
            ts = np.concatenate([[0.0], np.sort(t[i][hit[i]]), [1.0]])
            parts = np.stack([a[i] + ts[:-1, None] * d[i], a[i] + ts[1:, None] * d[i]], axis=1)
            out.append(parts[_bounding(parts, winding, rule, row0, col0, p)])
    return np.concatenate(out)


def _bounding(edges, winding, rule, row0, col0, p, at: float = 0.5) -> np.ndarray:
    """Which edges have material on exactly one side (sampled 1.5 px either side of the point
    at fraction `at` along them)."""
    d = edges[:, 1] - edges[:, 0]
    length = np.hypot(d[:, 0], d[:, 1])
    n = np.stack([-d[:, 1], d[:, 0]], 1) / np.where(length > 0, length, 1.0)[:, None]
    mid = edges[:, 0] + at * d
    h, w = winding.shape

    def material(pts):
        r = np.rint(pts[:, 1] / p).astype(np.int64) - row0
        c = np.rint(pts[:, 0] / p).astype(np.int64) - col0
        inside = (r >= 0) & (r < h) & (c >= 0) & (c < w)
        out = np.zeros(len(pts), bool)
        out[inside] = _apply_rule(winding[r[inside], c[inside]], rule)
        return out

    # 1.5 px: the nearest pixel centre of the sample point is then surely on its side.
    left, right = material(mid + 1.5 * p * n), material(mid - 1.5 * p * n)
    return (left != right) & (length > 0)


@dataclass(frozen=True, eq=False)
class RasterContours:
    """The contour tree of a layer raster (OpenCV ``RETR_TREE``), matched to the vector loops.

    Attributes
    ----------
    contours : list of (k, 2) ndarray
        Boundary pixel centres of each contour, in mm.
    tile : (n,) int ndarray
        Tile of each contour.
    depth : (n,) int ndarray
        0 for an outer boundary, 1 for a hole, 2 for an island in a hole...
    parent : (n,) int ndarray
        Enclosing contour, or -1.
    loop : (n,) int ndarray
        The section loop each contour traces (index into ``raster.loops``),
        or -1 when none does (e.g. the union of overlapping shells).
    """

    contours: list
    tile: np.ndarray
    depth: np.ndarray
    parent: np.ndarray
    loop: np.ndarray


def raster_hierarchy(raster: LayerRaster) -> RasterContours:
    """Outer boundaries, holes and islands in holes of a raster, to any depth.

    A contour is matched to the vector loop of the same kind (outer or hole)
    whose bounding box is nearest, if within 1.5 pixels on every side.

    Examples
    --------
    >>> import slicelab
    >>> from slicelab.samples import nested_shells
    >>> s = slicelab.section(nested_shells(), (0, 0, 20), (0, 0, 1))
    >>> h = raster_hierarchy(rasterize(s, 0.5))
    >>> h.depth.tolist(), (s.loop_depth[h.loop]).tolist()
    ([0, 1, 2], [0, 1, 2])
    """
    import cv2
    p = raster.pixel_size
    contours, tiles, depths, parents, matched = [], [], [], [], []
    loop_lo = np.array([lp.min(axis=0) for lp in raster.loops]).reshape(-1, 2)
    loop_hi = np.array([lp.max(axis=0) for lp in raster.loops]).reshape(-1, 2)
    loop_ccw = np.array([signed_area(lp) > 0 for lp in raster.loops], bool)
    for t, tile in enumerate(raster.tiles):  # over tiles
        cs, hier = cv2.findContours(tile.mask.astype(np.uint8), cv2.RETR_TREE, cv2.CHAIN_APPROX_SIMPLE)
        if hier is None:
            continue
        par = hier[0][:, 3].astype(np.int64)
        dep = np.zeros(len(cs), np.int64)
        for k in range(len(cs)):  # over contours: follow parent links
            j = par[k]
            while j >= 0:
                dep[k] += 1
                j = par[j]
        base = len(contours)
        cand = np.flatnonzero(raster.loop_tile == t)
        used = set()
        order = np.argsort([-cv2.contourArea(c) for c in cs], kind="stable")
        match = np.full(len(cs), -1, np.int64)
        for k in order:  # over contours
            pts = tile.xy(cs[k][:, 0, 1], cs[k][:, 0, 0])
            lo, hi = pts.min(axis=0), pts.max(axis=0)
            kind = dep[k] % 2 == 0
            ok = cand[(loop_ccw[cand] == kind) & ~np.isin(cand, list(used))]
            if len(ok):
                cost = np.maximum(np.abs(loop_lo[ok] - lo).max(axis=1), np.abs(loop_hi[ok] - hi).max(axis=1))
                best = int(np.argmin(cost))
                if cost[best] <= 1.5 * p:
                    match[k] = ok[best]
                    used.add(int(ok[best]))
        for k in range(len(cs)):
            contours.append(tile.xy(cs[k][:, 0, 1], cs[k][:, 0, 0]))
        tiles += [t] * len(cs)
        depths.append(dep)
        parents.append(np.where(par >= 0, par + base, -1))
        matched.append(match)
    cat = (lambda xs: np.concatenate(xs) if xs else np.zeros(0, np.int64))
    return RasterContours(contours, np.array(tiles, np.int64), cat(depths), cat(parents), cat(matched))


def draw_polylines(shape, row0: int, col0: int, pixel_size: float, polylines, width: float, *,
                   closed: bool = False, shift: int = 4) -> np.ndarray:
    """Draw polylines `width` mm wide into a window of the world grid (uint8, 255 = covered).

    OpenCV draws them anti-aliased, with sub-pixel vertices (`shift`
    fractional bits); its thick lines come out up to two pixels wider than
    asked, so the result marks candidates rather than exact coverage.

    Parameters
    ----------
    shape : (h, w)
        The window's shape; its first pixel is (`row0`, `col0`) of the world grid.
    row0, col0 : int
    pixel_size : float
    polylines : list of (k, 2) ndarray
        Points in mm.
    width : float
        Line width (mm).
    closed : bool, default False
        Join each polyline's last point to its first.
    shift : int, default 4

    Returns
    -------
    (h, w) uint8 ndarray

    See Also
    --------
    slicelab.toolpath.paths.covered_pixels : the exact coverage of one polyline.

    Examples
    --------
    >>> img = draw_polylines((5, 9), 0, 0, 1.0, [np.array([[1.0, 2.0], [7.0, 2.0]])], 1.0)
    >>> bool((img[2, 1:8] > 0).all()), int(img[0].max()), int(img[4].max())
    (True, 0, 0)
    """
    import cv2
    img = np.zeros(shape, np.uint8)
    if not polylines:
        return img
    p = pixel_size
    scale = float(1 << shift)
    pts = [np.round((np.asarray(q) / p - (col0, row0)) * scale).astype(np.int32).reshape(-1, 1, 2)
           for q in polylines]
    cv2.polylines(img, pts, closed, 255, thickness=max(1, int(round(width / p))), lineType=cv2.LINE_AA,
                  shift=shift)
    return img
