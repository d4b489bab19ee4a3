"""A half-section's outlines smoothed against the scan's noise, and the measurements read off them.

A half-section of a scan (`slicelab.artefacts.HalfProfile`) carries the
scanner's noise: at 0.1 mm, its lowest point is 0.4 mm under the base, its
edges point every which way, and a rim top 4 mm wide is a zigzag. Here the
ring is split at the rim top into its exterior and interior outlines, each
is resampled evenly and smoothed with a Gaussian along its arc length, as
wide as the noise calls for (`smooth_chain`; ends kept by odd reflection, so
a straight outline stays straight up to its end on the axis), and the
vessel's planes and corners are found on the smoothed outlines by geometry,
with tolerances tied to the noise:

* the base plane is the median height of what lies within the tolerance of
  the lowest smoothed point (the footprint), the rim plane likewise at the
  top;
* the base corner (the footprint's edge) and the rim's outer edge are where
  straight lines fitted to the wall, just beyond the rounding the smoothing
  leaves, meet those planes (`Outline`);
* the wall thickness is the distance from the smoothed interior to the
  smoothed exterior, the floor over the footprint (interior facing up) and
  a band one wall thickness deep below the rim top left out.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .curves import resample

__all__ = ["SMOOTH_PER_NOISE", "FLOOR_COSINE", "smooth_chain", "split_ring", "ring_noise", "Outline",
           "outline"]

#: Smoothing width (Gaussian sigma along the outline) per standard deviation of the noise.
SMOOTH_PER_NOISE = 8.0
#: The floor faces up: its outward normal is within 45 degrees of +z.
FLOOR_COSINE = math.cos(math.radians(45))


def smooth_chain(chain: np.ndarray, width: float, step: float) -> np.ndarray:
    """An open polyline resampled every `step` and smoothed by a Gaussian of sigma `width` (arc length).

    The ends stay where they are and a straight end stays straight: the
    chain is extended past each end by its point reflection there.

    Examples
    --------
    >>> c = np.array([[0.0, 0.0], [10.0, 0.0], [10.0, 10.0]])
    >>> s = smooth_chain(c, 1.0, 0.1)
    >>> s[[0, -1]].tolist(), bool(np.hypot(*(s - [10, 0]).T).min() > 0.3)
    ([[0.0, 0.0], [10.0, 10.0]], True)
    """
    from scipy.ndimage import gaussian_filter1d
    pts = resample(chain, step)[0]
    if not width > 0 or len(pts) < 3:
        return pts
    k = width / step
    pad = min(int(4 * k) + 1, len(pts) - 1)
    head = 2 * pts[0] - pts[1:pad + 1][::-1]
    tail = 2 * pts[-1] - pts[-pad - 1:-1][::-1]
    out = gaussian_filter1d(np.vstack([head, pts, tail]), k, axis=0, mode="nearest")[pad:len(pts) + pad]
    out[0], out[-1] = pts[0], pts[-1]
    return out


def split_ring(ring: np.ndarray, top: int):
    """A counter-clockwise (r, z) ring split at index `top` into its exterior and interior outlines.

    Both run from the top down: the exterior backwards along the ring, the
    interior forwards, each to the first point on the axis (r = 0), or to
    the lowest point when the ring does not reach the axis.

    Examples
    --------
    >>> cup = np.array([[0, 0], [4, 0], [4, 8], [3, 8], [3, 1], [0, 1]], float)
    >>> outer, inner = split_ring(cup, 2)
    >>> outer.tolist(), inner.tolist()
    ([[4.0, 8.0], [4.0, 0.0], [0.0, 0.0]], [[4.0, 8.0], [3.0, 8.0], [3.0, 1.0], [0.0, 1.0]])
    """
    k = len(ring)
    fwd = (top + np.arange(k)) % k
    bwd = (top - np.arange(k)) % k
    on_axis = ring[:, 0] <= 0.0
    if on_axis.any():
        stop_in = int(np.argmax(on_axis[fwd]))
        stop_out = int(np.argmax(on_axis[bwd]))
    else:
        low = int(np.argmin(ring[:, 1]))
        stop_in, stop_out = int((low - top) % k), int((top - low) % k)
    return ring[bwd[:max(stop_out, 1) + 1]], ring[fwd[:max(stop_in, 1) + 1]]


def ring_noise(ring: np.ndarray) -> float:
    """Noise sigma of a closed outline from its points alone: the robust spread of the second
    difference across the outline, minus its neighbours' mean (curvature cancels), over 2.09.

    Examples
    --------
    >>> t = np.linspace(0, 2 * np.pi, 2000, endpoint=False)
    >>> circle = 50 * np.column_stack([np.cos(t), np.sin(t)])
    >>> ring_noise(circle) < 1e-6
    True
    >>> noisy = circle * (1 + np.random.default_rng(0).normal(0, 0.002, 2000))[:, None]
    >>> round(ring_noise(noisy), 1)
    0.1
    """
    p = np.asarray(ring, dtype=np.float64)
    if len(p) < 7:
        return 0.0
    prev, nxt = np.roll(p, 1, axis=0), np.roll(p, -1, axis=0)
    d = nxt - prev
    n = np.column_stack([d[:, 1], -d[:, 0]])
    length = np.hypot(n[:, 0], n[:, 1])
    n = np.divide(n, length[:, None], out=np.zeros_like(n), where=length[:, None] > 0)
    lap = np.einsum("ij,ij->i", p - (prev + nxt) / 2, n)
    dd = lap - (np.roll(lap, 1) + np.roll(lap, -1)) / 2
    return float(1.4826 * np.median(np.abs(dd - np.median(dd))) / 2.09)


def _arc(chain: np.ndarray) -> np.ndarray:
    step = np.diff(chain, axis=0)
    return np.concatenate([[0.0], np.cumsum(np.hypot(step[:, 0], step[:, 1]))])


def _corner(chain: np.ndarray, k: int, level: float, skip: float, length: float) -> float:
    """Radius where a straight line fitted to `chain` just past index `k` (from `skip` to `skip +
    length` along it) meets the height `level`; the radius at `k` when the line runs level."""
    s = _arc(chain)
    win = (s >= s[k] + skip) & (s <= s[k] + skip + length)
    if win.sum() < 2:
        return float(chain[k, 0])
    pts = chain[win]
    c = pts.mean(axis=0)
    _, _, vt = np.linalg.svd(pts - c, full_matrices=False)
    d = vt[0]
    if abs(d[1]) < 0.05:  # the wall runs nearly level: no crossing to trust
        return float(chain[k, 0])
    r = float(c[0] + (level - c[1]) * d[0] / d[1])
    reach = abs(s[k] + skip + length - s[k]) + abs(float(chain[k, 1]) - level)
    return float(np.clip(r, chain[k, 0] - reach, chain[k, 0] + reach))


@dataclass(frozen=True, eq=False)
class Outline:
    """A half-section's smoothed outlines and what is read off them (mm, in the half's (r, z)).

    Attributes
    ----------
    outer : (n, 2) ndarray
        Smoothed exterior, from the rim top down to the axis (or the lowest point).
    inner : (m, 2) ndarray
        Smoothed interior, from the rim top down to the axis (or the lowest point).
    noise : float
        Noise sigma (mm) the smoothing was sized for.
    width : float
        Smoothing sigma (mm, along the outline).
    tolerance : float
        Height band (mm) of the base and rim planes: four sigmas of the smoothed noise.
    z_top, z_base : float
        Heights of the rim plane and of the base plane (the footprint's).
    rim_r : float
        Radius of the rim's outer edge.
    base_r : float
        Radius of the footprint's edge (the base corner).
    max_r, max_z : float
        The widest point of the exterior and its height.
    thickness, weight : ndarray
        Wall thickness along the interior (rim band and floor left out) and the arc length of each sample.
    base_thickness : float
        Floor minus underside over the inner half of the base (NaN when the half does not reach the axis).
    """

    outer: np.ndarray
    inner: np.ndarray
    noise: float
    width: float
    tolerance: float
    z_top: float
    z_base: float
    rim_r: float
    base_r: float
    max_r: float
    max_z: float
    thickness: np.ndarray
    weight: np.ndarray
    base_thickness: float

    @property
    def height(self) -> float:
        """Rim plane minus base plane."""
        return self.z_top - self.z_base

    def cavity(self) -> np.ndarray:
        """The cavity's ring: the interior from the rim top to the axis, closed up the axis."""
        return np.vstack([self.inner, [[0.0, self.inner[0, 1]]]])


def _facing_up(chain: np.ndarray) -> np.ndarray:
    """Per point of a chain running down the interior (material on its left): does it face up?"""
    dr, dz = np.gradient(chain[:, 0]), np.gradient(chain[:, 1])
    return -dr >= FLOOR_COSINE * np.hypot(dr, dz)


def outline(ring: np.ndarray, noise: float, step: float) -> Outline:
    """Smooth a half-section's ring (counter-clockwise, (r, z)) and measure it.

    Parameters
    ----------
    ring : (k, 2) ndarray
        `HalfProfile.polygon`.
    noise : float
        Noise sigma of the scan (mm); the smoothing is `SMOOTH_PER_NOISE` times as wide.
    step : float
        Resampling step along the outlines (mm).

    Returns
    -------
    Outline

    Examples
    --------
    >>> cup = np.array([[0, 0], [40, 0], [40, 80], [37, 80], [37, 5], [0, 5]], float)
    >>> o = outline(cup, 0.0, 0.05)
    >>> o.height, o.rim_r, o.base_r, round(float(np.median(o.thickness)), 6), o.base_thickness
    (80.0, 40.0, 40.0, 3.0, 5.0)
    """
    from scipy.spatial import cKDTree
    ring = np.asarray(ring, dtype=np.float64)
    seg = np.hypot(*np.diff(np.vstack([ring, ring[:1]]), axis=0).T)
    spacing = max(float(np.median(seg[seg > 0])) if (seg > 0).any() else step, step)
    width = SMOOTH_PER_NOISE * noise
    if width < 0.5 * step:  # a clean scan: nothing to smooth
        width, noise = 0.0, 0.0
    # Noise left after smoothing: raw points `spacing` apart averaged over about 2 sqrt(pi) width.
    smoothed_noise = noise * math.sqrt(min(1.0, spacing / (2 * math.sqrt(math.pi) * width))) if width > 0 else 0.0
    scale = float(np.abs(ring).max()) or 1.0
    tol = max(4 * smoothed_noise, 5e-4 * scale)  # the floor allows for a slightly tilted axis
    # The split: the middle of the rim top, where the ring smoothed round is highest.
    zs = ring[:, 1]
    if width > 0:
        from scipy.ndimage import gaussian_filter1d
        zs = gaussian_filter1d(zs, width / spacing, mode="wrap")
    outer_raw, inner_raw = split_ring(ring, int(np.argmax(zs)))
    outer = smooth_chain(outer_raw, width, step)
    inner = smooth_chain(inner_raw, width, step)
    both = np.vstack([outer, inner])
    z_hi, z_lo = float(both[:, 1].max()), float(outer[:, 1].min())
    z_top = float(np.median(both[both[:, 1] >= z_hi - tol, 1]))
    up = outer[::-1]  # from the axis up to the rim
    band = up[:, 1] <= z_lo + tol
    z_base = float(np.median(up[band, 1]))
    skip, length = 3 * width + 2 * step, max(2 * width, 0.01 * scale, 4 * step)  # past the rounding
    k_base = int(np.flatnonzero(band)[np.argmax(up[band, 0])])
    base_r = _corner(up, k_base, z_base, skip, length)
    land = outer[:, 1] >= z_top - tol
    k_rim = int(np.argmin(land)) - 1 if not land.all() else len(outer) - 1
    rim_r = _corner(outer, max(k_rim, 0), z_top, skip, length)
    i = int(np.argmax(outer[:, 0]))
    max_r, max_z = float(outer[i, 0]), float(outer[i, 1])
    if rim_r > max_r:
        max_r, max_z = rim_r, z_top
    if base_r > max_r:
        max_r, max_z = base_r, z_base
    # Wall thickness along the interior: the floor over the footprint and the rim band left out.
    dense = resample(outer, step)[0]
    dist = cKDTree(dense).query(inner)[0]
    floor = _facing_up(inner) & (inner[:, 0] <= base_r)
    t_ref = float(np.median(dist[~floor])) if (~floor).any() else 0.0
    wall = ~floor & (inner[:, 1] <= z_top - t_ref)
    arc = np.gradient(_arc(inner)) if len(inner) > 1 else np.ones(len(inner))
    # Base thickness: floor minus underside over the inner half of the base.
    base_t = math.nan
    if ring[:, 0].min() <= 0.0 and inner[-1, 0] <= 0.0 and up[0, 0] <= 0.0:
        run = int(np.argmin(_facing_up(inner)[::-1])) if not _facing_up(inner).all() else len(inner)
        floor_chain = inner[::-1][: max(run, 2)]
        under = up[band]
        r_lim = 0.5 * min(float(floor_chain[:, 0].max()), float(under[:, 0].max()))
        if r_lim > 0 and len(under) >= 2:
            r = np.linspace(0.0, r_lim, 65)

            def height(chain):
                o = np.argsort(chain[:, 0], kind="stable")
                return np.interp(r, chain[o, 0], chain[o, 1])

            base_t = float(np.mean(height(floor_chain) - height(under)))
    return Outline(outer, inner, float(noise), float(width), float(tol), z_top, z_base, float(rim_r), float(base_r),
                   max_r, max_z, dist[wall], arc[wall], base_t)
