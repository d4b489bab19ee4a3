"""Measurements of a vessel from its half-sections: diameters, heights, wall and base thickness, volumes.

A half-section is one side of a section through the axis, in (r, z)
(`slicelab.artefacts.HalfProfile`: a counter-clockwise ring with its exterior
and interior outlines). Volumes come from Pappus' theorem (`pappus_volume`),
the cavity is clipped at the fill level with `clip_ring`, wall thickness is
the perpendicular distance between resampled outlines (`resample`).
`measure_halves` gathers them into `Measurements`.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from .profiles import HalfProfile

__all__ = ["Measurements", "measure_halves", "pappus_volume", "clip_ring", "resample", "UP_COSINE"]

UP_COSINE = math.cos(math.radians(35))  # an edge faces up (down) when its outward normal is within 35 degrees of +z (-z)


def clip_ring(ring: np.ndarray, axis: int = 0, keep_below: bool = False, at: float = 0.0) -> np.ndarray:
    """Clip a closed ring to the half-plane ``x[axis] >= at`` (or ``<=``), keeping its orientation.

    Sutherland-Hodgman against one line [1]_: a concave ring stays one ring
    (pieces joined by zero-width bridges along the line, which add no area).

    Parameters
    ----------
    ring : (k, 2) ndarray
        A closed ring (the last point joins the first).
    axis : {0, 1}
        The coordinate tested.
    keep_below : bool, default False
        Keep ``x[axis] <= at`` instead.
    at : float, default 0
        Where the line is.

    Returns
    -------
    (m, 2) ndarray
        The clipped ring; points made on the line lie exactly on it.

    See Also
    --------
    slicelab.artefacts.half_profiles : clips sections at the axis.
    pappus_volume

    References
    ----------
    .. [1] I. E. Sutherland and G. W. Hodgman, "Reentrant polygon clipping",
       *Communications of the ACM* 17(1), 32-42, 1974.

    Examples
    --------
    >>> sq = np.array([[-1, 0], [1, 0], [1, 1], [-1, 1]], float)
    >>> clip_ring(sq).tolist()
    [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]
    """
    p = np.asarray(ring, dtype=np.float64)
    if len(p) == 0:
        return p.reshape(0, 2)
    q = np.roll(p, -1, axis=0)
    sp, sq = p[:, axis] - at, q[:, axis] - at
    if keep_below:
        sp, sq = -sp, -sq
    inside_p, inside_q = sp >= 0, sq >= 0
    cross = inside_p != inside_q
    s = np.divide(sp, sp - sq, out=np.zeros(len(p)), where=cross)
    x = p + s[:, None] * (q - p)
    x[:, axis] = at  # exactly on the line
    pts = np.stack([p, x], axis=1)
    out = pts[np.stack([inside_p, cross], axis=1)]
    if len(out) > 1:  # drop repeated points (a vertex on the line gives one twice)
        keep = np.any(out != np.roll(out, 1, axis=0), axis=1)
        out = out[keep] if keep.any() else out[:1]
    return out


def pappus_volume(ring: np.ndarray) -> float:
    """Volume swept by a closed (r, z) ring turned once about the z axis (Pappus).

    ``2 pi`` times the ring's first moment about the axis, exact for a polygon;
    positive for a counter-clockwise ring.

    See Also
    --------
    clip_ring : cuts a cavity at its fill level before it is turned.
    measure_halves : capacity and clay volume from it.

    Examples
    --------
    >>> round(pappus_volume(np.array([[0, 0], [1, 0], [1, 1], [0, 1]], float)) / np.pi, 12)
    1.0
    """
    p = np.asarray(ring, dtype=np.float64)
    if len(p) < 3:
        return 0.0
    r, z = p[:, 0], p[:, 1] - p[:, 1].mean()
    r1, z1 = np.roll(r, -1), np.roll(z, -1)
    return float(2 * np.pi * ((r + r1) * (r * z1 - r1 * z)).sum() / 6.0)


def resample(chain: np.ndarray, step: float):
    """Points about every `step` along a polyline, their arc-length weights and source edges.

    Parameters
    ----------
    chain : (k, 2) ndarray
        An open polyline.
    step : float
        Largest spacing of the samples along it.

    Returns
    -------
    points : (n, 2) ndarray
        Evenly spaced along the polyline, both ends included.
    weights : (n,) ndarray
        Arc length each point stands for (trapezoidal: half at the ends); they sum to its length.
    edges : (n,) int ndarray
        Index of the polyline edge each point lies on.

    Examples
    --------
    >>> pts, w, edge = resample(np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 2.0]]), 1.0)
    >>> pts.tolist(), w.tolist(), edge.tolist()
    ([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [1.0, 2.0]], [0.5, 1.0, 1.0, 0.5], [0, 1, 1, 1])
    """
    d = np.diff(chain, axis=0)
    seg = np.hypot(d[:, 0], d[:, 1])
    total = float(seg.sum())
    if total == 0:
        return chain[:1], np.ones(1), np.zeros(1, np.int64)
    cum = np.concatenate([[0.0], np.cumsum(seg)])
    n = max(2, int(math.ceil(total / step)) + 1)
    s = np.linspace(0.0, total, n)
    pts = np.column_stack([np.interp(s, cum, chain[:, 0]), np.interp(s, cum, chain[:, 1])])
    w = np.full(n, total / (n - 1))
    w[[0, -1]] /= 2
    edge = np.clip(np.searchsorted(cum, s, side="right") - 1, 0, len(seg) - 1)
    return pts, w, edge


def _edge_facing(chain: np.ndarray, reverse: bool) -> np.ndarray:
    """Outward normal z-component of each edge of a chain cut from a CCW ring."""
    d = np.diff(chain, axis=0)
    if reverse:  # the chain walks the ring backwards
        d = -d
    length = np.hypot(d[:, 0], d[:, 1])
    return np.divide(-d[:, 0], length, out=np.zeros(len(d)), where=length > 0)


def _wall_thickness(half: HalfProfile, step: float):
    """Perpendicular wall thickness along the interior outline (floor and rim excluded).

    Each interior sample's distance to the nearest of the exterior's samples,
    taken `step` apart: off the true distance d by at most step^2 / 8d.
    """
    from scipy.spatial import cKDTree
    inner, outer = half.inner, half.outer
    if len(inner) < 2 or len(outer) < 2:
        return np.zeros(0), np.zeros(0)
    o_pts, _, o_edge = resample(outer, step)
    # The underside of the base is not wall: leave out interior points nearest to it.
    underside = _edge_facing(outer, reverse=True)[o_edge] <= -UP_COSINE
    pts, wts, i_edge = resample(inner, step)
    wall = _edge_facing(inner, reverse=False)[i_edge] < UP_COSINE  # the floor faces up
    pts, wts = pts[wall], wts[wall]
    if len(pts) == 0:
        return np.zeros(0), np.zeros(0)
    dist, idx = cKDTree(o_pts).query(pts)
    keep = ~underside[idx]
    return dist[keep], wts[keep]


@dataclass(frozen=True)
class Measurements:
    """A vessel's measurements from its half-sections (mm, mm^3).

    Diameters, heights and thicknesses are medians over the half-sections (a
    handle in one half does not move them); volumes are means (uniform angles:
    the mean is a quadrature of the volume integral in cylindrical
    coordinates, handle included). Wall thickness is perpendicular (what calipers give), pooled
    over every half, floor and rim excluded. Capacity is the cavity filled to
    the lowest rim top, by Pappus' theorem.

    See Also
    --------
    measure_halves : makes one.
    slicelab.artefacts.Profile : holds one, with the half-sections it comes from.
    """

    height: float
    rim_diameter: float
    max_diameter: float
    max_diameter_height: float
    base_diameter: float
    wall_thickness_min: float
    wall_thickness_mean: float
    wall_thickness_max: float
    base_thickness: float
    capacity: float
    clay_volume: float
    halves: int
    spread: float
    residual: float

    def to_dict(self) -> dict:
        """Plain floats (NaN where a measurement does not apply)."""
        return {k: getattr(self, k) for k in self.__dataclass_fields__}

    def __str__(self) -> str:
        rows = [("height", self.height, "mm"), ("rim diameter", self.rim_diameter, "mm"),
                ("max diameter", self.max_diameter, "mm"),
                ("  at height", self.max_diameter_height, "mm"),
                ("base diameter", self.base_diameter, "mm"),
                ("wall min/mean/max", None, "mm"), ("base thickness", self.base_thickness, "mm"),
                ("capacity", self.capacity / 1e6, "l"), ("clay volume", self.clay_volume / 1e3, "cm3"),
                ("half-sections", self.halves, ""), ("spread", self.spread, "mm"),
                ("axis residual", self.residual, "mm")]
        out = []
        for name, v, unit in rows:
            if v is None:
                text = (f"{self.wall_thickness_min:.3f} / {self.wall_thickness_mean:.3f} / "
                        f"{self.wall_thickness_max:.3f}")
            else:
                text = f"{v:.6g}" if isinstance(v, float) else str(v)
            out.append(f"{name:<18}{text} {unit}".rstrip())
        return "\n".join(out)


def _base_thickness(half: HalfProfile, underside: np.ndarray) -> float:
    """Floor height minus underside height, averaged over the inner half of the base's radius.

    Averaged rather than read at the axis alone, where one noisy vertex on
    each side would decide it.
    """
    inner = half.inner
    up = _edge_facing(inner, reverse=False)[::-1] >= UP_COSINE
    run = int(np.argmin(up)) if not up.all() else len(up)
    floor = inner[::-1][: run + 1]  # from the axis outwards, while the interior faces up
    r_lim = 0.5 * min(float(floor[:, 0].max()), float(underside[:, 0].max()))
    if len(floor) < 2 or len(underside) < 2 or not r_lim > 0:
        on_axis = half.polygon[half.polygon[:, 0] == 0, 1]
        return float(on_axis.max() - on_axis.min())
    r = np.linspace(0.0, r_lim, 65)

    def height(chain):
        o = np.argsort(chain[:, 0], kind="stable")
        return np.interp(r, chain[o, 0], chain[o, 1])

    return float(np.mean(height(floor) - height(underside)))


def measure_halves(halves: list[HalfProfile], height: float, spread: float, residual: float) -> Measurements:
    """Measure a vessel from its half-sections (see `Measurements` for what each number is).

    Parameters
    ----------
    halves : list of HalfProfile
        The half-sections of an aligned vessel (at least one).
    height : float
        The vessel's height (mm); it also sets the sampling step of the
        outlines (1/2000 of it).
    spread : float
        Largest distance (mm) of a half from the drawn one, passed through.
    residual : float
        The alignment's circle residual (mm), passed through.

    Returns
    -------
    Measurements

    See Also
    --------
    slicelab.artefacts.half_profiles : the half-sections.
    slicelab.artefacts.profile : aligns, cuts and measures in one call.

    Examples
    --------
    >>> from slicelab.artefacts import half_profiles
    >>> from slicelab.samples import revolve
    >>> cup = revolve([[0, 0], [40, 0], [40, 80], [37, 80], [37, 5], [0, 5]], 256)
    >>> m = measure_halves(half_profiles(cup, 0.0), 80.0, 0.0, 0.0)
    >>> round(m.rim_diameter, 6), round(m.base_thickness, 6), round(m.capacity / (np.pi * 37 ** 2 * 75), 3)
    (80.0, 5.0, 1.0)
    """
    nan = float("nan")
    rim, rmax, zmax, base, base_t, clay = [], [], [], [], [], []
    thick, thick_w = [], []
    step = max(height, 1e-9) / 2000
    for h in halves:  # over half-sections (tens)
        ring = h.polygon
        rim.append(h.outer[0, 0] if len(h.outer) else nan)
        k = int(np.argmax(ring[:, 0]))
        rmax.append(ring[k, 0])
        zmax.append(ring[k, 1])
        # Footprint: the exterior's downward-facing run at its bottom end.
        face = _edge_facing(h.outer, reverse=True)
        down = face[::-1] <= -UP_COSINE
        run = int(np.argmin(down)) if not down.all() else len(down)
        base.append(h.outer[::-1][run, 0] if len(h.outer) else nan)
        if (ring[:, 0] == 0).sum() >= 2:
            base_t.append(_base_thickness(h, h.outer[::-1][: run + 1]))
        clay.append(pappus_volume(ring) + sum(pappus_volume(x) for x in h.holes))
        t, w = _wall_thickness(h, step)
        thick.append(t)
        thick_w.append(w)
    # Capacity: fill to the lowest rim top, i.e. the level where it would spill.
    level = min(float(h.polygon[:, 1].max()) for h in halves)
    cap = []
    for h in halves:  # over half-sections
        ring = h.polygon
        on_axis = ring[:, 0] == 0
        if not on_axis.any():
            continue
        k = len(ring)
        fwd = (h.top + np.arange(k)) % k
        stop = int(np.argmax(on_axis[fwd]))
        cavity = np.vstack([ring[fwd[:stop + 1]], [[0.0, ring[h.top, 1]]]])
        cavity = clip_ring(cavity, 1, keep_below=True, at=level)
        cap.append(abs(pappus_volume(cavity)))
    t = np.concatenate(thick) if thick else np.zeros(0)
    w = np.concatenate(thick_w) if thick_w else np.zeros(0)

    def mean(x):
        x = np.asarray(x, dtype=float)
        return float(np.mean(x)) if len(x) else nan

    def median(x):  # lengths read off single halves: a handle or a spout in one half must not move them
        x = np.asarray(x, dtype=float)
        return float(np.median(x)) if len(x) else nan

    return Measurements(
        height=float(height), rim_diameter=2 * median(rim), max_diameter=2 * median(rmax),
        max_diameter_height=median(zmax), base_diameter=2 * median(base),
        wall_thickness_min=float(t.min()) if len(t) else nan,
        wall_thickness_mean=float((t * w).sum() / w.sum()) if len(t) else nan,
        wall_thickness_max=float(t.max()) if len(t) else nan,
        base_thickness=median(base_t), capacity=mean(cap), clay_volume=mean(clay),
        halves=len(halves), spread=float(spread), residual=float(residual))


