"""Profiles of what is not a whole closed vessel: sherds, open or broken scans, reassembled fragments.

* A sherd (`sherd_profile`): sections across its span, the drawn one the
  medoid; what the sherd holds is measured (its rim or base, its wall), the
  rest is NaN.
* An open scan (`closing_gap`): the `max_gap` its sections need to close.
* A vessel reassembled from fragments (`composite_half`): each meridian
  plane crosses a few fragments, with gaps between them; the union of all
  the planes' pieces, in (r, z), is the profile as far as it is preserved.
"""
from __future__ import annotations

import math

import numpy as np

from ..mesh.core import Mesh
from ..slicing.sections import section
from .halves import HalfProfile, half_from_ring, half_profiles, representative
from .measure import Measurements

__all__ = ["closing_gap", "sherd_profile", "composite_half", "shell_count"]


def closing_gap(mesh: Mesh, angles, candidates=None, *, lowest: bool = False):
    """The `max_gap` (mm) that closes the sections of an open scan through the axis at `angles`.

    Per plane, each open chain's end is paired with the nearest chain start
    (the way `slicelab.section` joins them, nearest first); the plane needs the
    largest of those distances. The answer is the median over the planes
    whose sections are open (a hole in the wall opens a few planes only, an
    uncaptured rim all of them); infinite when none is open. With
    ``lowest=True``, also the height of the lowest open end (where the scan
    is open: at the rim, or lower); with ``lowest="median"``, the median over
    the open planes of each one's lowest open end (a hole opens a few planes
    low down, a base cut away all of them).

    Examples
    --------
    >>> from slicelab.samples import scan
    >>> mesh, _ = scan("beaker", spacing=2.0, pose=False, open_rim=True)
    >>> round(closing_gap(mesh, [0.0, 1.0]), 1)  # the rim top, 3 mm wide, was not captured
    3.0
    """
    from scipy.spatial import cKDTree
    need, lows = [], []
    for k, a in enumerate(angles):  # a few planes
        c, s = math.cos(a), math.sin(a)
        sub = mesh if candidates is None else Mesh(mesh.triangles[candidates[k]])
        sec = section(sub, (0.0, 0.0, 0.0), (s, -c, 0.0), max_gap=0.0)
        if not sec.open_chains:
            continue
        ends = np.array([ch[-1] for ch in sec.open_chains])
        starts = np.array([ch[0] for ch in sec.open_chains])
        need.append(float(cKDTree(starts).query(ends)[0].max()))
        lows.append(min(float(ends[:, 1].min()), float(starts[:, 1].min())))
    gap = float(np.median(need)) if need else math.inf
    if lowest == "median":
        return gap, (float(np.median(lows)) if lows else math.inf)
    return (gap, min(lows, default=math.inf)) if lowest else gap


def sherd_profile(mesh: Mesh, alignment, planes: int, max_gap: float):
    """A sherd's profile: `planes` sections across its span, the drawn one the medoid; what the
    sherd holds is measured (its rim or base, its wall), the rest is NaN.

    Returns
    -------
    halves : list of HalfProfile
    representative : int
    spread : ndarray
    measurements : Measurements
    """
    from ..mesh.validation import signed_volume
    from .sherds import sherd_interval, sherd_wall
    start, width = sherd_interval(mesh.triangles.reshape(-1, 3))
    angles = start + width * (np.arange(planes) + 0.5) / planes
    halves = []
    for a in angles:  # over planes
        halves += [h for h in half_profiles(mesh, float(a), max_gap=max_gap)
                   if abs((h.angle - a + math.pi) % (2 * math.pi) - math.pi) < 1e-6]
    if not halves:
        raise ValueError("no plane through the axis gave a closed section of the sherd (is it closed?)")
    z = mesh.triangles[..., 2]
    rep, spread = representative(halves, float(z.max() - z.min()))
    report = alignment.sherd
    walls = [sherd_wall(h.polygon, alignment.noise) for h in halves]
    walls = [w for w in walls if len(w)]
    nan = float("nan")

    def med(x):
        return float(np.median(x)) if len(x) else nan

    m = Measurements(
        height=nan, rim_diameter=report.rim_diameter, max_diameter=nan, max_diameter_height=nan,
        base_diameter=report.base_diameter, wall_thickness_min=med([w.min() for w in walls]),
        wall_thickness_mean=med([w.mean() for w in walls]), wall_thickness_max=med([w.max() for w in walls]),
        base_thickness=nan, capacity=nan, clay_volume=abs(signed_volume(mesh.triangles)), halves=len(halves),
        spread=float(spread.max()), residual=alignment.residual, noise=alignment.noise,
        rim_diameter_sd=report.rim_diameter_sd,
        wall_thickness_p5=med([np.percentile(w, 5) for w in walls]),
        wall_thickness_p95=med([np.percentile(w, 95) for w in walls]))
    return halves, rep, spread, m


def shell_count(mesh: Mesh, share: float = 0.005) -> int:
    """How many closed connected shells of the mesh hold at least `share` of its area (a reassembled
    vessel's fragments; a jug's handle is one more; noise's specks, and an open scan's sheets that a
    hole or a broken rim cut apart, are none). A mesh with an inward shell (a sealed cavity) is one
    solid with a cavity, not fragments: it counts its outward shells only when no shell is inward,
    else 1 (its cavity and what the cavity holds are the business of the capacity, not of the
    fragments).

    Examples
    --------
    >>> from slicelab.samples import box, concat, nested_shells
    >>> shell_count(concat(box((0, 0, 0), (1, 1, 1)), box((3, 0, 0), (4, 1, 1))))
    2
    >>> shell_count(nested_shells())  # a box, its sealed cavity, an island in the cavity
    1
    """
    from ..geometry.topology import edge_table, shells, weld
    v, f = weld(mesh.triangles)
    if not len(f):
        return 0
    n, label = shells(f)
    t = v[f]
    area = 0.5 * np.linalg.norm(np.cross(t[:, 1] - t[:, 0], t[:, 2] - t[:, 0]), axis=1)
    per = np.bincount(label, area, n)
    et = edge_table(f)
    open_facets = et["first"][et["counts"] == 1] // 3
    closed = np.ones(n, bool)
    closed[label[open_facets]] = False
    big = (per >= share * per.sum()) & closed
    volume = np.bincount(label, np.einsum("ij,ij->i", t[:, 0], np.cross(t[:, 1], t[:, 2])) / 6.0, n)
    if (volume[big] < 0).any():
        return 1
    return int(big.sum())


def composite_half(mesh: Mesh, angles, candidates=None, max_gap: float = 1.0, bridge: float = 0.0):
    """The profile of a reassembled vessel as far as it is preserved: the union, in (r, z), of every
    piece of every half-section (both sides of each plane; shapely's union), its largest part as a
    `HalfProfile` (angle 0), and the share of the union's area that part holds.

    Each fragment's section is a piece of the wall's profile; where the planes cross gaps or missing
    fragments, other planes cross fragments: the union is the profile wherever some fragment keeps it.
    Gaps up to `bridge` mm between the pieces are closed (a morphological closing of the union).

    Returns
    -------
    HalfProfile or None
        None when no plane crosses a closed piece.
    share : float
        The largest part's share of the union (1 when it is one piece).
    """
    from shapely.geometry import Polygon
    from shapely.ops import unary_union

    from .curves import clip_ring
    pieces = []
    for k, a in enumerate(angles):  # a dozen planes
        c, s_ = math.cos(a), math.sin(a)
        sub = mesh if candidates is None else Mesh(mesh.triangles[candidates[k]])
        sec = section(sub, (0.0, 0.0, 0.0), (s_, -c, 0.0), max_gap=max_gap)
        for poly in sec.polygons:  # the plane's pieces, each side
            for side in (1.0, -1.0):
                ext = clip_ring(poly.exterior, 0, keep_below=side < 0)
                if len(ext) >= 3:
                    g = Polygon(np.column_stack([side * ext[:, 0], ext[:, 1]])).buffer(0)
                    if g.area > 0:
                        pieces.append(g)
    if not pieces:
        return None, 0.0
    union = unary_union(pieces)
    if bridge > 0:
        union = union.buffer(bridge / 2, quad_segs=16).buffer(-bridge / 2, quad_segs=16)
    parts = list(getattr(union, "geoms", [union]))
    best = max(parts, key=lambda g: g.area)
    ring = np.asarray(best.exterior.coords)[:-1]
    if not best.exterior.is_ccw:
        ring = ring[::-1]
    ring = np.where(ring[:, :1] <= 1e-9, np.column_stack([np.zeros(len(ring)), ring[:, 1]]), ring)
    return half_from_ring(ring), float(best.area / union.area)
