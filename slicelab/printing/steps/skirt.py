"""The first layer's skirt and brim: loops around the part's outline.

A skirt primes the nozzle before the part starts: `loops` closed loops whose
inner edge lies `distance` from the first layer's outline (PrusaSlicer's
``skirt_distance``: its first loop's centre line is ``distance + w / 2`` out,
the next ones a line width further each). A brim helps the first layer hold:
loops touching the outline, outward to `brim_width`. Both are offsets (GEOS
buffers) of the union of the first layer's islands, holes filled; the skirt
goes around the brim when there is one. Loops print from the outermost in, so
the nozzle ends near the part, each loop's seam at its vertex nearest the
nozzle.

See Also
--------
slicelab.printing.planner.plan : adds them to the first layer.
slicelab.printing.roles : their ``;TYPE:Skirt/Brim`` in G-code.
"""
from __future__ import annotations


import numpy as np

from ...geometry.regions import valid_region

__all__ = ["skirt_loops", "skirt_margin", "with_skirt"]


def skirt_margin(line_width: float, loops: int, distance: float, brim_width: float) -> float:
    """How far past the first layer's outline the skirt and brim reach (mm, outer edge).

    Examples
    --------
    >>> skirt_margin(0.4, 1, 6.0, 0.0), skirt_margin(0.4, 0, 6.0, 3.0), skirt_margin(0.4, 2, 6.0, 3.0)
    (6.4, 3.2, 10.0)
    """
    w = float(line_width)
    brim = _brim_count(w, brim_width) * w
    return brim + (distance + loops * w if loops > 0 else 0.0)


def _brim_count(w: float, brim_width: float) -> int:
    return int(round(brim_width / w)) if brim_width > 0 else 0


def _outer_rings(geom) -> list[np.ndarray]:
    import shapely
    parts = shapely.get_parts(geom)
    return [shapely.get_coordinates(shapely.get_exterior_ring(p))[:-1] for p in parts if not p.is_empty]


def _from(ring: np.ndarray, pos: np.ndarray) -> np.ndarray:
    """A ring as a closed polyline from its vertex nearest `pos`."""
    k = int(np.argmin(np.hypot(*(ring - pos).T)))
    return np.concatenate((ring[k:], ring[:k + 1]))


def skirt_loops(section, line_width: float = 0.4, *, loops: int = 1, distance: float = 6.0,
                brim_width: float = 0.0, start=None) -> tuple[list, list]:
    """The skirt and brim loops around a first layer, in print order.

    Parameters
    ----------
    section : Section
        The first layer.
    line_width : float
    loops : int, default 1
        Skirt loops; 0: no skirt.
    distance : float, default 6
        From the outline (or the brim) to the skirt's inner edge (mm).
    brim_width : float, default 0
        How far the brim reaches from the outline (mm); 0: no brim.
    start : (2,) array_like, optional
        Nozzle position before the skirt (default: the layer's lower-left corner).

    Returns
    -------
    skirt, brim : list of (k, 2) ndarray
        Closed polylines, outermost first (skirt before brim).

    See Also
    --------
    with_skirt : the loops added to a layer's paths.
    skirt_margin : how far they reach.

    Examples
    --------
    >>> import slicelab
    >>> from slicelab.samples import box
    >>> s = slicelab.section(box((0, 0, 0), (10, 10, 1)), (0, 0, .5), (0, 0, 1))
    >>> skirt, brim = skirt_loops(s, 0.4, loops=2, distance=3.0, brim_width=1.2)
    >>> len(skirt), len(brim)
    (2, 3)
    >>> [round(float(q[:, 0].min()), 6) for q in skirt + brim]   # outer edges at 1.2 + 3 + 0.8 and 1.2
    [-4.8, -4.4, -1.0, -0.6, -0.2]
    """
    import shapely
    w = float(line_width)
    polys = np.array([shapely.Polygon(p.exterior) for p in section.polygons if len(p.exterior) >= 3], object)
    if not len(polys) or (loops <= 0 and brim_width <= 0):
        return [], []
    # A self-intersecting mesh has outer loops that cross themselves: GEOS unites only valid shapes.
    outline = valid_region(polys)
    n_brim = _brim_count(w, brim_width)
    offsets = [(0.5 + i) * w for i in range(n_brim)][::-1]
    base = n_brim * w + distance
    skirt_offsets = [base + (0.5 + i) * w for i in range(max(0, int(loops)))][::-1]
    lo = section.bounds()[0] if len(section.segments) else np.zeros(2)
    pos = np.asarray(lo if start is None else start, np.float64)
    out = {"skirt": [], "brim": []}
    for role, offs in (("skirt", skirt_offsets), ("brim", offsets)):
        for d in offs:  # over loops, outermost first
            rings = _outer_rings(shapely.buffer(outline, d, quad_segs=16))
            while rings:  # nearest ring first
                j = min(range(len(rings)), key=lambda j: float(np.min(np.hypot(*(rings[j] - pos).T))))
                path = _from(rings.pop(j), pos)
                out[role].append(path)
                pos = path[-1]
    return out["skirt"], out["brim"]


def with_skirt(paths, skirt: list, brim: list):
    """A layer's paths with the skirt and brim printed first.

    Parameters
    ----------
    paths : LayerPaths
    skirt, brim : list of (k, 2) ndarray
        From `skirt_loops`.

    Returns
    -------
    LayerPaths
        The same islands, with the skirt's and brim's rows first and the
        travel to the islands counted.

    Examples
    --------
    >>> import slicelab
    >>> from slicelab.samples import box
    >>> s = slicelab.section(box((0, 0, 0), (10, 10, 1)), (0, 0, .5), (0, 0, 1))
    >>> lp = with_skirt(slicelab.layer_paths(s, slicelab.PrintSettings(pixel_size=0.1)), *skirt_loops(s, 0.4))
    >>> lp.kinds()[:3]
    ['skirt', 'internal', 'external']
    """
    w = paths.line_width
    return paths.inserted(0, [("skirt", q, w) for q in skirt] + [("brim", q, w) for q in brim])
