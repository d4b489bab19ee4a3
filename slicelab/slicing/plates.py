"""Build plates: the pieces of a partition laid out on as few printer beds as they fit.

Each piece stands on its largest flat face that fits the build volume
(`place_for_printing`). Its footprint is the outline of everything it covers
on the bed (its facets projected, filled on a fine raster and traced, so an
L-shaped piece leaves its corner free), widened by half the spacing. Pieces
go largest first onto the first plate where they fit, at the lowest, then
leftmost, free position among the corners the pieces already placed offer,
each tried at a few turns about z (bottom-left fill).

See Also
--------
slicelab.partition : makes the pieces.
slicelab.slicing.placement.place_for_printing : how each piece is laid down.

References
----------
.. [1] B. S. Baker, E. G. Coffman, R. L. Rivest, "Orthogonal packings in
   two dimensions", SIAM Journal on Computing 9(4), 1980 (bottom-left).
.. [2] E. K. Burke, R. S. R. Hellier, G. Kendall, G. Whitwell, "Complete and
   robust no-fit polygon generation for the irregular stock cutting problem",
   European Journal of Operational Research 179(1), 2007 (irregular shapes).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..mesh.core import Mesh
from .placement import place_for_printing

__all__ = ["Plate", "Plates", "arrange", "footprint"]


def footprint(mesh: Mesh, resolution: float = 0.25):
    """The region a mesh covers on the xy plane, as a shapely (Multi)Polygon (mm).

    The facets are filled on a raster of `resolution` mm (OpenCV) and the
    outline traced, so holes in the footprint and concave outlines are kept.

    Examples
    --------
    >>> from slicelab.samples import box
    >>> footprint(box((0, 0, 0), (10, 20, 5))).area
    200.0
    """
    import cv2
    import shapely
    t = mesh.triangles[:, :, :2]
    lo = t.reshape(-1, 2).min(axis=0) - 2 * resolution
    hi = t.reshape(-1, 2).max(axis=0) + 2 * resolution
    shape = np.ceil((hi - lo) / resolution).astype(int)[::-1] + 1
    img = np.zeros(shape, np.uint8)
    q = (t - lo) / resolution
    a, b = q[:, 1] - q[:, 0], q[:, 2] - q[:, 0]
    area2 = np.abs(a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0])
    # Facets smaller than a pixel (a scan's) mark the pixels of their corners and centroid; the
    # larger ones (few: a CAD part's) are filled one by one.
    small = area2 <= 2.0
    # Every corner is marked (a thin facet can cover no pixel centre), and small facets' centroids.
    dots = np.concatenate([q.reshape(-1, 2), q[small].mean(axis=1)])
    ij = np.clip(np.rint(dots).astype(np.int64), 0, np.array(shape[::-1]) - 1)
    img[ij[:, 1], ij[:, 0]] = 1
    big = np.round(q[~small & (area2 > 0)] * 16).astype(np.int32)  # 4 fractional bits
    for tri in big:  # over facets larger than a pixel: the fill is OpenCV's, per convex polygon
        cv2.fillConvexPoly(img, tri, 1, lineType=cv2.LINE_8, shift=4)
    contours, hierarchy = cv2.findContours(img, cv2.RETR_CCOMP, cv2.CHAIN_APPROX_SIMPLE)
    if hierarchy is None:
        return shapely.Polygon()
    polys = []
    for k, c in enumerate(contours):  # over outlines, few
        if hierarchy[0][k][3] >= 0 or len(c) < 3:
            continue
        holes = [contours[j] for j in range(len(contours)) if hierarchy[0][j][3] == k and len(contours[j]) >= 3]
        ring = lo + (c.reshape(-1, 2) + 0.5) * resolution
        polys.append(shapely.Polygon(ring, [lo + (h.reshape(-1, 2) + 0.5) * resolution for h in holes]))
    # The traced outline runs through pixel centres: a pixel out covers the facets' edges and the
    # simplification that removes the raster's staircase.
    grown = shapely.buffer(shapely.union_all(polys), resolution, join_style="mitre")
    # Clipped by the exact convex hull of the corners: a straight outside edge stays exact.
    hull = shapely.convex_hull(shapely.MultiPoint(t.reshape(-1, 2)))
    # Simplifying may cut up to its tolerance inside: grown back by as much, within the hull.
    thin = shapely.simplify(shapely.intersection(grown, hull), resolution / 4)
    return shapely.intersection(shapely.buffer(thin, resolution / 4, join_style="mitre"), hull)


@dataclass(frozen=True)
class Plate:
    """One build plate.

    Attributes
    ----------
    pieces : tuple of int
        Indices of the pieces on it.
    matrices : tuple of (4, 4) ndarray
        Each piece's rigid motion from its own coordinates onto the plate.
    footprint_area : float
        Area the pieces cover (mm^2), without the spacing.
    """

    pieces: tuple
    matrices: tuple
    footprint_area: float


@dataclass(frozen=True)
class Plates:
    """The plates `arrange` filled.

    Attributes
    ----------
    plates : tuple of Plate
    build_volume : tuple of float
    spacing : float
    lower_bound : int
        Plates that the pieces' total footprint needs at least (total area / plate area, rounded up).
    """

    plates: tuple
    build_volume: tuple
    spacing: float
    lower_bound: int

    def __len__(self) -> int:
        return len(self.plates)

    def plate_mesh(self, k: int, pieces) -> Mesh:
        """The pieces of plate `k` in place, as one mesh (several bodies)."""
        plate = self.plates[k]
        return Mesh(np.concatenate([pieces[i].transformed(m).triangles for i, m in zip(plate.pieces,
                                                                                        plate.matrices)]))

    @property
    def fill(self) -> list[float]:
        """Share of each plate's area the pieces cover."""
        X, Y, _ = self.build_volume
        return [p.footprint_area / (X * Y) for p in self.plates]

    def to_dict(self) -> dict:
        """Plain-Python dictionary, ready for JSON."""
        return {"build_volume": list(self.build_volume), "spacing": self.spacing, "lower_bound": self.lower_bound,
                "plates": [{"pieces": list(p.pieces), "matrices": [m.tolist() for m in p.matrices],
                            "footprint_area": p.footprint_area, "fill": f}
                           for p, f in zip(self.plates, self.fill)]}


def _shrunk_union(outlines):
    """The placed outlines as one prepared geometry, a micrometre inside their edges."""
    import shapely
    union = shapely.buffer(shapely.union_all(outlines), -1e-3)
    shapely.prepare(union)
    return union


def _turns(poly, rotate: bool, fit: float = 0.0) -> list[float]:
    """Turns (degrees) worth trying: the four right angles, those that square the outline's
    smallest enclosing rectangle with the bed, and `fit` (the turn that makes the piece fit the
    bed at all, a diagonal one for a long piece) with its right angles."""
    if not rotate:
        return [0.0]
    import shapely
    rect = shapely.minimum_rotated_rectangle(poly)
    xy = np.asarray(rect.exterior.coords)
    edge = xy[1] - xy[0]
    a = math.degrees(math.atan2(edge[1], edge[0])) % 90.0
    out = [0.0, 90.0, 180.0, 270.0]
    if 1.0 < a < 89.0:  # (an outline squared with the axes up to its raster's noise needs no more)
        out += [(-a) % 360, (90 - a) % 360]
    if fit % 90.0:
        out += [(fit + q) % 360 for q in (0.0, 90.0, 180.0, 270.0)]
    return out


_MAX_TESTS = 400  # exact outline tests per turn and plate: enough for the corners a plate offers


def _place(poly, placed, X: float, Y: float, turns, union=None, margin: float = 0.0):
    """The lowest, then leftmost, free position of `poly` (turned by one of `turns`) on a plate.

    Candidate positions put the outline's lower-left corner at the plate's
    origin, against the right or top of a placed outline's box, or at one of
    the corners of its convex hull; the first candidate in (y, x) order that
    lies inside the plate and meets no placed outline wins. Candidates whose
    box meets no placed box are free at once (one vectorised test); only the
    others are tested against the outlines. Returns (turn, dx, dy, moved) or None.
    """
    import shapely
    from shapely import affinity
    if union is None and placed:
        union = _shrunk_union(placed)
    boxes = np.array([q.bounds for q in placed]).reshape(-1, 4)
    xs, ys = [np.zeros(1), boxes[:, 2]], [np.zeros(1), boxes[:, 3]]
    for q in placed:  # over the pieces on the plate
        v = shapely.get_coordinates(shapely.convex_hull(q))
        xs.append(v[:, 0])
        ys.append(v[:, 1])
    xs, ys = np.concatenate(xs), np.concatenate(ys)
    best = None
    for turn in turns:  # a handful of turns
        p = affinity.rotate(poly, turn, origin=(0, 0))
        if margin > 0:
            # Widened after the turn: the round joins' polygons then reach the full margin along x and y.
            p = shapely.buffer(p, margin, quad_segs=4)
        x0, y0, x1, y1 = p.bounds
        w, h = x1 - x0, y1 - y0
        if w > X + 1e-6 or h > Y + 1e-6:  # (a piece as wide as the bed, up to rounding, fits)
            continue
        gx, gy = np.meshgrid(np.unique(np.clip(xs, 0, max(X - w, 0))), np.unique(np.clip(ys, 0, max(Y - h, 0))))
        gx, gy = gx.ravel(), gy.ravel()
        order = np.lexsort((gx, gy))
        gx, gy = gx[order], gy[order]
        if best is not None:  # only positions below (or left of) the best so far can win
            keep = (gy < best[0][0]) | ((gy == best[0][0]) & (gx < best[0][1]))
            gx, gy = gx[keep], gy[keep]
        # Boxes that meet no placed box: the first of those is free without an exact test.
        clear = ~((gx[:, None] < boxes[:, 2] - 1e-9) & (gx[:, None] + w > boxes[:, 0] + 1e-9)
                  & (gy[:, None] < boxes[:, 3] - 1e-9) & (gy[:, None] + h > boxes[:, 1] + 1e-9)).any(axis=1)
        first_clear = int(np.argmax(clear)) if clear.any() else len(gx)
        # The candidates before it need the outlines: the first _MAX_TESTS of them, in order.
        tested = list(range(min(first_clear, _MAX_TESTS))) + ([first_clear] if first_clear < len(gx) else [])
        for k in tested:
            dx, dy = gx[k] - x0, gy[k] - y0
            moved = affinity.translate(p, dx, dy)
            # Outlines may touch (each already carries half the spacing), not overlap: the union
            # is shrunk by a micrometre, so touching is not meeting.
            if k == first_clear or not union.intersects(moved):
                best = ((gy[k], gx[k]), turn, dx, dy, moved)
                break
    return None if best is None else best[1:]


def _upright(piece, volume):
    """The piece as given, for `arrange`'s ``stand=False``: no turn, or None if it cannot fit."""
    from types import SimpleNamespace
    lo, hi = piece.bounds
    size = hi - lo
    if size[2] > volume[2] + 1e-9 or min(size[:2]) > min(volume[:2]) + 1e-9 or \
            max(size[:2]) > max(volume[:2]) + 1e-9:
        return None
    return SimpleNamespace(matrix=np.eye(4), turn=0.0)


def arrange(pieces, build_volume, *, spacing: float = 5.0, rotate: bool = True, stand: bool = True) -> Plates:
    """Lay each piece on its best face and pack the pieces onto as few plates as they fit.

    Parameters
    ----------
    pieces : sequence of Mesh
    build_volume : (X, Y, Z)
        The printer's build volume (mm); a plate is ``[0, X] x [0, Y]``.
    spacing : float, default 5
        Gap kept between pieces (mm); the plate's edge needs none.
    rotate : bool, default True
        Allow turns about z.
    stand : bool, default True
        Lay each piece on its best face; False keeps each piece upright as given (parts
        put side by side to print together), only turned about z and moved.

    Returns
    -------
    Plates

    Raises
    ------
    ValueError
        A piece that fits the build volume on none of its faces (too tall, or
        too wide), named with its size.

    Examples
    --------
    >>> from slicelab.samples import box
    >>> plates = arrange([box((0, 0, 0), (90, 90, 10))] * 5, (200, 200, 100), spacing=5)
    >>> len(plates), plates.lower_bound, [len(p.pieces) for p in plates.plates]
    (2, 2, [4, 1])
    """
    from shapely import affinity
    X, Y, Z = (float(v) for v in build_volume)
    if not all(v > 0 and math.isfinite(v) for v in (X, Y, Z)):
        raise ValueError(f"build_volume must be three positive sizes, got {build_volume!r}")
    if not (spacing >= 0 and math.isfinite(spacing)):
        raise ValueError(f"spacing must be >= 0, got {spacing!r}")
    laid, outlines, areas, fits = [], [], [], []
    for k, piece in enumerate(pieces):  # over pieces
        place = place_for_printing(piece, (X, Y, Z), rotate=rotate) if stand else _upright(piece, (X, Y, Z))
        if place is None:
            lo, hi = piece.bounds
            raise ValueError(f"piece {k} ({' x '.join(f'{v:.4g}' for v in hi - lo)} mm) does not fit the "
                             f"{X:g} x {Y:g} x {Z:g} mm build volume on any face")
        # Laid down but not yet turned or moved: the packing chooses those.
        down = place.matrix.copy()
        a = math.radians(place.turn)
        unturn = np.array([[math.cos(a), math.sin(a), 0], [-math.sin(a), math.cos(a), 0], [0, 0, 1.0]])
        down[:3, :3] = unturn @ down[:3, :3]
        down[:3, 3] = 0.0
        m = piece.transformed(down)
        lo = m.bounds[0]
        down[:3, 3] = [0.0, 0.0, -lo[2]]
        fp = footprint(piece.transformed(down))
        laid.append(down)
        fits.append(place.turn)
        areas.append(float(fp.area))
        outlines.append(fp)
    bound = math.ceil(sum(areas) / (X * Y) - 1e-9) if pieces else 0
    # Each outline is widened by half the spacing (round joins: a mitre would grow spikes at sharp
    # corners), and the plate by as much on each side: pieces may touch its edge.
    grow = spacing
    W, H = X + grow, Y + grow
    plates: list[dict] = []
    for i in sorted(range(len(laid)), key=lambda i: -areas[i]):  # largest first
        turns = _turns(outlines[i], rotate, fits[i])
        need = outlines[i].area + spacing / 2 * outlines[i].length
        for plate in plates + [None]:
            target = plate if plate is not None else {"pieces": [], "matrices": [], "outlines": [], "area": 0.0,
                                                      "taken": 0.0, "union": None}
            if plate is not None and W * H - target["taken"] < need:  # no room left, whatever the shapes
                continue
            spot = _place(outlines[i], target["outlines"], W, H, turns, target["union"], spacing / 2)
            if spot is None:
                if plate is None:  # pragma: no cover - a piece that fits the volume fits an empty plate
                    raise ValueError(f"piece {i} does not fit an empty plate")
                continue
            turn, dx, dy, moved = spot
            a = math.radians(turn)
            R = np.eye(4)
            R[:2, :2] = [[math.cos(a), -math.sin(a)], [math.sin(a), math.cos(a)]]
            R[:2, 3] = [dx - grow / 2, dy - grow / 2]
            # The round joins' polygons may fall a few hundredths of a millimetre short of the
            # margin: a piece that would overhang the plate by that much is pushed back onto it.
            x0, y0, x1, y1 = affinity.translate(affinity.rotate(outlines[i], turn, origin=(0, 0)),
                                                R[0, 3], R[1, 3]).bounds
            R[0, 3] += max(0.0, -x0) - max(0.0, x1 - X)
            R[1, 3] += max(0.0, -y0) - max(0.0, y1 - Y)
            target["pieces"].append(i)
            target["matrices"].append(R @ laid[i])
            target["outlines"].append(moved)
            target["area"] += areas[i]
            target["taken"] += moved.area
            target["union"] = _shrunk_union(target["outlines"])
            if plate is None:
                plates.append(target)
            break
    out = tuple(Plate(tuple(p["pieces"]), tuple(p["matrices"]), p["area"]) for p in plates)
    return Plates(out, (X, Y, Z), float(spacing), bound)
