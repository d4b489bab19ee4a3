"""Measurements of a vessel from its half-sections: diameters, heights, wall and base thickness, volumes.

A half-section is one side of a section through the axis, in (r, z)
(`slicelab.artefacts.HalfProfile`: a counter-clockwise ring with its exterior
and interior outlines). Volumes come from Pappus' theorem (`pappus_volume`),
the cavity is clipped at the fill level with `clip_ring`, wall thickness is
the perpendicular distance between resampled outlines (`resample`).
`measure_halves` reads each half's smoothed outlines
(`slicelab.artefacts.outlines`) and gathers them into `Measurements`.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from .curves import UP_COSINE, clip_ring, resample  # noqa: F401  (re-exported: the measurements' tools)

if TYPE_CHECKING:
    from .halves import HalfProfile

__all__ = ["Measurements", "half_outlines", "measure_halves", "pappus_volume", "clip_ring", "resample", "UP_COSINE"]

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


def _edge_facing(chain: np.ndarray, reverse: bool) -> np.ndarray:
    """Outward normal z-component of each edge of a chain cut from a CCW ring."""
    d = np.diff(chain, axis=0)
    if reverse:  # the chain walks the ring backwards
        d = -d
    length = np.hypot(d[:, 0], d[:, 1])
    return np.divide(-d[:, 0], length, out=np.zeros(len(d)), where=length > 0)


def _number(v, fmt: str) -> str:
    """`v` formatted, or an en dash where it does not apply (NaN, None)."""
    return format(v, fmt) if v is not None and math.isfinite(v) else "\u2013"


@dataclass(frozen=True)
class Measurements:
    """A vessel's measurements from its half-sections (mm, mm^3).

    Read off each half's outlines smoothed against the noise
    (`slicelab.artefacts.outlines`): the height from the base plane (the
    footprint's) to the rim plane, the base diameter at the footprint's
    edge, the rim diameter at the rim's outer edge. Diameters, heights and
    thicknesses are medians over the half-sections (a handle in one half
    does not move them); volumes are means (uniform angles: the mean is a
    quadrature of the volume integral in cylindrical coordinates, handle
    included). Wall thickness is perpendicular (what calipers give), along
    the interior, the floor over the footprint and a band one wall
    thickness deep under the rim top left out: the mean is the median of the
    halves' means, the min and max the medians of the halves' extremes.
    Capacity is the cavity filled to the lowest rim top, by Pappus' theorem
    (the mean over the halves, those over five robust sigmas from the median,
    through a handle, left out). `rim_diameter_sd` is the rim diameter's
    standard uncertainty (a sherd's from its circle, a vessel's from the
    halves' scatter); `wall_thickness_p5` and `wall_thickness_p95` the 5th
    and 95th percentiles of the wall thickness (the medians over the halves:
    the range a drawing's label shows, where the extremes catch a breaks' or
    a noise's outliers); `fragmentary` marks a vessel reassembled from
    fragments, measured only where preserved.

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
    noise: float = 0.0
    rim_diameter_sd: float = math.nan
    wall_thickness_p5: float = math.nan
    wall_thickness_p95: float = math.nan
    fragmentary: bool = False

    def to_dict(self) -> dict:
        """Plain floats (NaN where a measurement does not apply)."""
        return {k: getattr(self, k) for k in self.__dataclass_fields__}

    def __str__(self) -> str:
        cap = self.capacity / 1e6 if math.isfinite(self.capacity) else math.nan
        rows = [("height", self.height, "mm"), ("rim diameter", self.rim_diameter, "mm"),
                ("max diameter", self.max_diameter, "mm"),
                ("  at height", self.max_diameter_height, "mm"),
                ("base diameter", self.base_diameter, "mm"),
                ("wall min/mean/max", None, "mm"), ("base thickness", self.base_thickness, "mm"),
                ("capacity", cap, "l"), ("clay volume", self.clay_volume / 1e3, "cm3"),
                ("half-sections", self.halves, ""), ("spread", self.spread, "mm"),
                ("axis residual", self.residual, "mm"), ("noise", self.noise, "mm")]
        out = []
        for name, v, unit in rows:
            if v is None:
                text = " / ".join(_number(x, ".3f") for x in (self.wall_thickness_min, self.wall_thickness_mean,
                                                              self.wall_thickness_max))
            else:
                text = _number(v, ".6g") if isinstance(v, float) else str(v)
            out.append(f"{name:<18}{text} {unit}".rstrip())
        return "\n".join(out)


def _typical(x) -> np.ndarray:
    """`x` without values over five robust sigmas from its median (a half through a handle)."""
    x = np.asarray(x, dtype=float)
    if len(x) < 3:
        return x
    dev = np.abs(x - np.median(x))
    return x[dev <= max(5 * 1.4826 * float(np.median(dev)), 1e-9 * float(np.abs(x).max()))]


def half_outlines(halves: list[HalfProfile], height: float, noise: float | None = None):
    """Each half's smoothed outlines (`slicelab.artefacts.outlines.outline`), and the noise they were
    smoothed for (estimated from the halves when not given; `ring_noise`).

    The resampling step is 1/2000 of the larger of `height` and the widest radius.

    Examples
    --------
    >>> from slicelab.artefacts import half_profiles
    >>> from slicelab.samples import revolve
    >>> cup = revolve([[0, 0], [40, 0], [40, 80], [37, 80], [37, 5], [0, 5]], 256)
    >>> outs, noise = half_outlines(half_profiles(cup, 0.0), 80.0)
    >>> [round(o.height, 6) for o in outs], noise
    ([80.0, 80.0], 0.0)
    """
    from .outlines import outline, ring_noise
    if noise is None:
        noise = float(np.median([ring_noise(h.polygon) for h in halves])) if halves else 0.0
        noise = noise if noise > 1e-6 else 0.0
    size = max(height, max((float(h.polygon[:, 0].max()) for h in halves), default=0.0), 1e-9)
    step = size / 2000
    return [outline(h.polygon, noise, step) for h in halves], float(noise)


def measure_halves(halves: list[HalfProfile], height: float, spread: float, residual: float,
                   noise: float | None = None, outlines=None) -> Measurements:
    """Measure a vessel from its half-sections (see `Measurements` for what each number is).

    Parameters
    ----------
    halves : list of HalfProfile
        The half-sections of an aligned vessel (at least one).
    height : float
        The vessel's height range (mm); it sets the resampling step of the
        outlines (1/2000 of the larger of it and the widest radius).
    spread : float
        Largest distance (mm) of a half from the drawn one, passed through.
    residual : float
        The alignment's circle residual (mm), passed through.
    noise : float, optional
        The scan's noise sigma (mm), which sizes the smoothing; estimated from
        the halves' outlines when not given (`slicelab.artefacts.outlines.ring_noise`).
    outlines : list of Outline, optional
        The halves' outlines from `half_outlines` (computed here when not given).

    Returns
    -------
    Measurements

    See Also
    --------
    slicelab.artefacts.half_profiles : the half-sections.
    slicelab.artefacts.profile : aligns, cuts and measures in one call.
    slicelab.artefacts.outlines.outline : what is read off each half.

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
    if outlines is None:
        outlines, noise = half_outlines(halves, height, noise)
    outs = outlines
    clay = [pappus_volume(h.polygon) + sum(pappus_volume(x) for x in h.holes) for h in halves]
    # Capacity: fill to the lowest rim top, the level where it would spill; a dip of the lowest
    # half under the median within three sigmas of the smoothed noise is noise, not a dip.
    closed = [o for h, o in zip(halves, outs) if o.inner[-1, 0] <= 0.0 and (h.polygon[:, 0] <= 0.0).any()]
    tops = np.array([o.z_top for o in (closed or outs)])  # halves through the vessel's axis, if any
    level = float(np.median(tops) - max(0.0, np.median(tops) - tops.min() - 3 * max(o.tolerance / 4 for o in outs)))
    cap = []
    for h, o in zip(halves, outs):  # over half-sections
        if o.inner[-1, 0] > 0.0 or (h.polygon[:, 0] > 0.0).all():
            continue  # the interior does not reach the axis: no cavity to fill
        cavity = clip_ring(o.cavity(), 1, keep_below=True, at=level)
        cap.append(abs(pappus_volume(cavity)))

    def mean(x):
        x = np.asarray(x, dtype=float)
        return float(np.mean(x)) if len(x) else nan

    def median(x):  # lengths read off single halves: a handle or a spout in one half must not move them
        x = np.asarray([v for v in x if math.isfinite(v)], dtype=float)
        return float(np.median(x)) if len(x) else nan

    walls = [o for o in outs if len(o.thickness)]
    rims = np.array([o.rim_r for o in outs if math.isfinite(o.rim_r)])
    rim_sd = 2 * 1.2533 * 1.4826 * float(np.median(np.abs(rims - np.median(rims)))) / math.sqrt(len(rims)) \
        if len(rims) >= 3 else nan
    return Measurements(
        height=median(o.height for o in outs), rim_diameter=2 * median(o.rim_r for o in outs),
        max_diameter=2 * median(o.max_r for o in outs),
        max_diameter_height=median(o.max_z - o.z_base for o in outs),
        base_diameter=2 * median(o.base_r for o in outs),
        wall_thickness_min=median(float(o.thickness.min()) for o in walls),
        wall_thickness_mean=median(float((o.thickness * o.weight).sum() / o.weight.sum()) for o in walls),
        wall_thickness_max=median(float(o.thickness.max()) for o in walls),
        base_thickness=median(o.base_thickness for o in outs), capacity=mean(_typical(cap)), clay_volume=mean(clay),
        halves=len(halves), spread=float(spread), residual=float(residual),
        noise=float(noise if noise is not None else outs[0].noise if outs else 0.0), rim_diameter_sd=rim_sd,
        wall_thickness_p5=median(float(np.percentile(o.thickness, 5)) for o in walls),
        wall_thickness_p95=median(float(np.percentile(o.thickness, 95)) for o in walls))
