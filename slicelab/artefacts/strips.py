"""A sherd's meridian section as a strip of wall: its two faces, its thickness and its two ends.

A section of a sherd through its axis is a strip: the outer and the inner
face of the wall run side by side, a wall thickness apart, and two ends
cross from one face to the other (the lip, a break, or the base's inner
break). The ends are found as the boundary's points without a partner
across the wall: a ray from a point of a face into the material meets the other face,
turned the other way, within a couple of wall thicknesses; a ray from a
point of an end runs along the strip (the opposite end is a strip's length
away) or meets a face turned aside. That holds for a flat land, a rounded or bevelled lip,
an oblique or rough break alike, where the farthest pair of points (which
jumps between the corners of a flat lip) does not.

`strip` smooths the ring by the scan's noise (a Gaussian along it, 8 noise sigmas, as the
outlines of `slicelab.artefacts.outlines` are), casts the rays and returns a `Strip`.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

__all__ = ["Strip", "strip", "turning", "sherd_interval", "covered_span", "core_interval", "meridian_rings",
           "end_spread"]

_PARTNER_REACH = 2.0    # wall thicknesses within which a face point finds its partner
_OPPOSITE = -0.85       # cosine between partners' normals at most
_MIN_END = 0.3          # an end is at least this many wall thicknesses along the boundary
_TAPER = 0.5            # a partner nearer than this many wall thicknesses: the wall ends in a wedge


@dataclass(frozen=True, eq=False)
class Strip:
    """A meridian section of a sherd, smoothed, with its faces and ends told apart.

    Attributes
    ----------
    angle : float
        The section's angle about the axis (radians).
    points : (n, 2) ndarray
        The smoothed ring in (r, z), counter-clockwise, about `step` apart.
    normals : (n, 2) ndarray
        Outward unit normals.
    end : (n,) int ndarray
        -1 on the faces, else the end (0 or 1) the point belongs to.
    thickness : float
        Median distance to the partner across the wall (mm).
    step : float
        Spacing of `points` (mm).
    raw : (n, 2) ndarray
        The ring resampled alike, unsmoothed (for least-squares fits, which average the noise
        without the smoothing's rounding of corners).

    See Also
    --------
    strip : makes one.
    """

    angle: float
    points: np.ndarray
    normals: np.ndarray
    end: np.ndarray
    thickness: float
    step: float
    raw: np.ndarray | None = None

    def end_points(self, k: int) -> np.ndarray:
        """The points of end `k`, in order along the ring."""
        return self.points[self.end == k]

    def centre(self, k: int) -> np.ndarray:
        """Mean point of end `k`."""
        return self.end_points(k).mean(axis=0)

    def outward(self, k: int) -> np.ndarray:
        """Unit mean outward normal of end `k` (which way the strip ends there)."""
        n = self.normals[self.end == k].sum(axis=0)
        return n / max(float(np.hypot(*n)), 1e-12)


def sherd_interval(points: np.ndarray, bins: int = 720):
    """The angle interval (start, width; radians) that points about the z axis cover: the full
    turn minus the largest empty run of bins.

    Examples
    --------
    >>> phi = np.radians(np.linspace(170, 230, 200))
    >>> start, width = sherd_interval(np.column_stack([np.cos(phi), np.sin(phi), 0 * phi]))
    >>> round(np.degrees(start) % 360), round(np.degrees(width))
    (170, 60)
    """
    phi = np.arctan2(points[:, 1], points[:, 0])
    k = np.floor((phi + np.pi) / (2 * np.pi) * bins).astype(np.int64) % bins
    full = np.bincount(k, minlength=bins) > 0
    if full.all():
        return -np.pi, 2 * np.pi
    empty = np.concatenate([~full, ~full])
    edges = np.diff(np.concatenate([[0], empty.astype(np.int8), [0]]))
    starts, ends = np.flatnonzero(edges == 1), np.flatnonzero(edges == -1)
    lengths = np.minimum(ends - starts, bins)
    i = int(np.argmax(lengths))
    first = (starts[i] + lengths[i]) % bins  # the first covered bin after the gap
    return float(first / bins * 2 * np.pi - np.pi), float((bins - lengths[i]) / bins * 2 * np.pi)


def core_interval(points: np.ndarray, start: float, width: float, bands: int = 24):
    """The angles (from `start`, radians) every height of the wall covers: a meridian section there
    crosses no side break.

    The points (in the axis frame) are banded by their position along the
    section's principal direction (its middle 80 %); the interval is the
    largest 1st percentile of the bands' angles to the smallest 99th.
    Side breaks that waver by degrees and cross the wall obliquely make it
    narrower than the sherd; a section outside it ends where it meets a side
    break, across the wall, like a break.

    Returns
    -------
    lo, hi : float
        Radians from `start`; (0.1, 0.9) of `width` when the bands say nothing.

    Examples
    --------
    >>> phi = np.radians(np.linspace(0, 60, 61))[:, None] + np.radians(np.linspace(0, 5, 30))[None, :]
    >>> z = np.broadcast_to(np.linspace(0, 30, 30), phi.shape)
    >>> pts = np.column_stack([(40 * np.cos(phi)).ravel(), (40 * np.sin(phi)).ravel(), z.ravel()])
    >>> lo, hi = core_interval(pts, 0.0, np.radians(65))
    >>> round(float(np.degrees(lo)), 1), round(float(np.degrees(hi)), 1)  # the band-wise core [5, 60], less 1 %
    (4.5, 60.5)
    """
    phi = (np.arctan2(points[:, 1], points[:, 0]) - start) % (2 * np.pi)
    phi = np.where(phi > width + (2 * np.pi - width) / 2, phi - 2 * np.pi, phi)
    rz = np.column_stack([np.hypot(points[:, 0], points[:, 1]), points[:, 2]])
    c = rz - rz.mean(axis=0)
    _, _, vt = np.linalg.svd(c, full_matrices=False)
    u = c @ vt[0]
    lo_u, hi_u = np.percentile(u, [10, 90])
    k = np.floor((u - lo_u) / max(hi_u - lo_u, 1e-12) * bands).astype(np.int64)
    inside = (k >= 0) & (k < bands)
    counts = np.bincount(k[inside], minlength=bands)
    lo, hi = -np.inf, np.inf
    order = np.lexsort((phi[inside], k[inside]))
    sp, sk = phi[inside][order], k[inside][order]
    starts = np.concatenate([[0], np.cumsum(counts)])
    for b in range(bands):  # two dozen bands
        if counts[b] >= 10:
            seg = sp[starts[b]:starts[b + 1]]
            lo = max(lo, float(seg[int(0.01 * (len(seg) - 1))]))
            hi = min(hi, float(seg[int(math.ceil(0.99 * (len(seg) - 1)))]))
    del sk
    if not (np.isfinite(lo) and np.isfinite(hi)) or hi - lo < 0.2 * width:
        return 0.1 * width, 0.9 * width
    return lo, hi


def covered_span(triangles: np.ndarray, point, direction, bins: int = 720, total: bool = False) -> float:
    """Degrees about an axis that a mesh's facets cover: each facet covers the angles between its
    corners (all of them, if it holds the axis); the full turn less the largest uncovered run (or,
    with ``total``, the sum of the covered angles: pieces with gaps between them).

    Examples
    --------
    >>> from slicelab.samples import box, sherd_mesh
    >>> covered_span(box((-1, -1, 0), (1, 1, 2)).triangles, [0, 0, 0], [0, 0, 1])
    360.0
    >>> v, f = sherd_mesh("pot", "rim", 60.0, spacing=4.0, breaks="straight")
    >>> round(covered_span(v[f], [0, 0, 0], [0, 0, 1]))
    60
    """
    from .axis_fit import rotation_to_z
    R = rotation_to_z(direction)
    q = np.einsum("...j,ij->...i", np.asarray(triangles, dtype=np.float64) - np.asarray(point, float), R)
    phi = np.arctan2(q[..., 1], q[..., 0])                     # (n, 3)
    ref = phi[:, :1]
    d = (phi - ref + np.pi) % (2 * np.pi) - np.pi             # corners relative to the first, (-pi, pi]
    lo, hi = ref[:, 0] + d.min(axis=1), ref[:, 0] + d.max(axis=1)
    # A facet whose corners go round its axis (the base's centre) covers everything.
    x, y = q[..., 0], q[..., 1]
    cross = [x[:, k] * y[:, (k + 1) % 3] - y[:, k] * x[:, (k + 1) % 3] for k in range(3)]
    around = ((cross[0] > 0) & (cross[1] > 0) & (cross[2] > 0)) | ((cross[0] < 0) & (cross[1] < 0) & (cross[2] < 0))
    if around.any():
        return 360.0
    if total:
        # The exact union of the facets' intervals (bins would round each piece's two ends outward).
        lo_w = (lo + np.pi) % (2 * np.pi)
        hi_w = lo_w + (hi - lo)
        iv = np.concatenate([np.column_stack([lo_w, np.minimum(hi_w, 2 * np.pi)]),
                             np.column_stack([np.zeros(int((hi_w > 2 * np.pi).sum())), hi_w[hi_w > 2 * np.pi] - 2 * np.pi])])
        iv = iv[np.argsort(iv[:, 0])]
        reach = np.maximum.accumulate(iv[:, 1])
        starts = np.concatenate([[True], iv[1:, 0] > reach[:-1]])
        first = np.flatnonzero(starts)
        ends = np.concatenate([reach[first[1:] - 1], reach[-1:]])
        return float(np.degrees((ends - iv[first, 0]).sum()))
    a = np.floor((lo + np.pi) / (2 * np.pi) * bins).astype(np.int64)
    b = np.floor((hi + np.pi) / (2 * np.pi) * bins).astype(np.int64) + 1
    diff = np.zeros(2 * bins + 2)
    np.add.at(diff, a % bins, 1)
    np.add.at(diff, (a % bins) + (b - a), -1)
    run = np.cumsum(diff)[:2 * bins]
    covered = (run[:bins] + run[bins:]) > 0
    if covered.all():
        return 360.0
    empty = np.concatenate([~covered, ~covered])
    edges = np.diff(np.concatenate([[0], empty.astype(np.int8), [0]]))
    gaps = np.flatnonzero(edges == -1) - np.flatnonzero(edges == 1)
    return 360.0 * (bins - min(int(gaps.max()), bins)) / bins


def meridian_rings(mesh, angles) -> list:
    """The largest section polygon on the side ``(cos a, sin a)`` of each meridian plane, as an
    (r, z) ring, counter-clockwise (None where the plane misses the mesh or its section stays open).

    `mesh` is in the axis frame (the axis is z through the origin).

    Examples
    --------
    >>> from slicelab import Mesh
    >>> from slicelab.samples import sherd_mesh
    >>> v, f = sherd_mesh("beaker", "rim", 60.0, spacing=2.0)
    >>> ring = meridian_rings(Mesh.from_vertices_faces(v, f), [np.radians(30)])[0]
    >>> round(float(ring[:, 1].max()), 6), bool(ring[:, 0].min() > 30)
    (100.0, True)
    """
    from ..geometry.polygons import signed_area
    from ..slicing.sections import section
    from .curves import clip_ring
    out = []
    for a in angles:  # a few planes
        c, s = math.cos(a), math.sin(a)
        sec = section(mesh, (0.0, 0.0, 0.0), (s, -c, 0.0), max_gap=1.0)
        best, area = None, 0.0
        for poly in sec.polygons:  # the section's few polygons
            ring = clip_ring(poly.exterior, 0)
            if len(ring) >= 3 and signed_area(ring) > area:
                best, area = ring, signed_area(ring)
        out.append(best)
    return out


def _closed_smooth(ring: np.ndarray, width: float, step: float) -> np.ndarray:
    """A closed ring resampled every `step` and smoothed by a Gaussian of sigma `width` (wrapping)."""
    from scipy.ndimage import gaussian_filter1d

    from .curves import resample
    pts = resample(np.vstack([ring, ring[:1]]), step)[0][:-1]
    if width > 0.5 * step and len(pts) > 8:
        pts = gaussian_filter1d(pts, width / step, axis=0, mode="wrap")
    return pts


def turning(points: np.ndarray) -> np.ndarray:
    """Signed turn (radians) at each point of a closed ring, counter-clockwise positive.

    Examples
    --------
    >>> sq = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], float)
    >>> np.round(np.degrees(turning(sq)), 6).tolist()
    [90.0, 90.0, 90.0, 90.0]
    """
    d_in = points - np.roll(points, 1, axis=0)
    d_out = np.roll(points, -1, axis=0) - points
    a = np.arctan2(d_out[:, 1], d_out[:, 0]) - np.arctan2(d_in[:, 1], d_in[:, 0])
    return (a + np.pi) % (2 * np.pi) - np.pi


def strip(ring: np.ndarray, angle: float, noise: float, step: float | None = None) -> Strip | None:
    """A section's ring (counter-clockwise, (r, z)) as a `Strip`, or None when it has no two ends.

    Parameters
    ----------
    ring : (k, 2) ndarray
    angle : float
        The section's angle (radians), kept in the result.
    noise : float
        The scan's noise sigma (mm): the ring is smoothed over 8 sigmas (as outlines are).
    step : float, optional
        Resampling step (mm); default a 20th of the strip's rough thickness (twice its area
        over its perimeter), at least 0.02 mm.

    Examples
    --------
    >>> ring = np.array([[40, 0], [44, 0], [44, 30], [40, 30]], float)
    >>> s = strip(ring, 0.0, 0.0)
    >>> round(s.thickness, 3), sorted(np.round(s.centre(k)).tolist() for k in (0, 1))
    (4.0, [[42.0, 0.0], [42.0, 30.0]])
    """
    from ..geometry.polygons import signed_area
    ring = np.asarray(ring, dtype=np.float64)
    pre = _closed_smooth(ring, 8 * noise, max(noise, 0.02))
    perimeter = float(np.hypot(*np.diff(np.vstack([pre, pre[:1]]), axis=0).T).sum())
    rough_t = 2 * abs(signed_area(pre)) / max(perimeter, 1e-12)
    if step is None:
        step = max(rough_t / 20, 0.02)
    pts = _closed_smooth(ring, 8 * noise, step)
    n = len(pts)
    if n < 16:
        return None
    d = np.roll(pts, -1, axis=0) - np.roll(pts, 1, axis=0)
    nrm = np.column_stack([d[:, 1], -d[:, 0]])
    nrm /= np.maximum(np.hypot(nrm[:, 0], nrm[:, 1]), 1e-12)[:, None]
    dist, hit = _across(pts, nrm, step)
    t = float(np.median(dist[np.isfinite(dist)])) if np.isfinite(dist).any() else rough_t
    # An end: no partner across, or one much nearer than the wall is thick (a wedge's tip, as a
    # flat land over a steeply sloping wall makes).
    lone = ~(dist <= _PARTNER_REACH * t) | (dist < _TAPER * t)
    if not lone.any() or lone.all():
        return None
    # Runs of partnerless points round the ring; gaps shorter than a third of the wall are closed,
    # runs shorter than `_MIN_END` walls dropped; the two longest are the ends.
    runs = _runs(lone)
    if len(runs) > 1:
        merged = [list(runs[0])]
        for a, b in runs[1:]:
            if (a - merged[-1][1]) * step < t / 3:
                merged[-1][1] = b
            else:
                merged.append([a, b])
        if len(merged) > 1 and (merged[0][0] + n - merged[-1][1]) * step < t / 3:
            merged[0][0] = merged[-1][0] - n
            merged.pop()
        runs = [tuple(x) for x in merged]
    runs = [r for r in runs if (r[1] - r[0]) * step >= _MIN_END * t and _crosses(r, dist, hit, n, t, step)]
    if len(runs) < 2:
        return None
    runs = sorted(runs, key=lambda r: r[1] - r[0], reverse=True)[:2]
    end = np.full(n, -1, np.int64)
    for k, (a, b) in enumerate(runs):
        end[np.arange(a, b) % n] = k
    return Strip(float(angle), pts, nrm, end, t, float(step), _closed_smooth(ring, 0.0, step))


def _across(pts: np.ndarray, nrm: np.ndarray, step: float) -> np.ndarray:
    """Per point of a closed ring: how far a ray into the material (along minus its normal) runs to
    the boundary, when the boundary it meets faces the other way (a partner across the wall); inf
    when it meets the boundary at a face turned less than that (an end's far side); and the index of
    the edge it meets."""
    a = pts
    e = np.roll(pts, -1, axis=0) - pts
    en = np.column_stack([e[:, 1], -e[:, 0]])
    en /= np.maximum(np.hypot(en[:, 0], en[:, 1]), 1e-12)[:, None]
    out = np.full(len(pts), np.inf)
    hit_at = np.zeros(len(pts), np.int64)
    for lo in range(0, len(pts), 256):  # rays in blocks: (256, edges) arrays
        p, dr = pts[lo:lo + 256, None], -nrm[lo:lo + 256, None]
        ap = a[None] - p
        denom = dr[..., 0] * e[None, :, 1] - dr[..., 1] * e[None, :, 0]
        ok = np.abs(denom) > 1e-12
        den = np.where(ok, denom, 1.0)
        s = (ap[..., 0] * e[None, :, 1] - ap[..., 1] * e[None, :, 0]) / den
        u = (ap[..., 0] * dr[..., 1] - ap[..., 1] * dr[..., 0]) / den
        hit = ok & (s > 1.5 * step) & (u >= 0) & (u <= 1)
        s = np.where(hit, s, np.inf)
        k = np.argmin(s, axis=1)
        first = s[np.arange(len(k)), k]
        facing = np.einsum("ij,ij->i", en[k], nrm[lo:lo + 256]) <= _OPPOSITE
        out[lo:lo + 256] = np.where(facing, first, np.inf)
        hit_at[lo:lo + 256] = k
    return out, hit_at


def _crosses(run, dist, hit, n: int, t: float, step: float) -> bool:
    """Does a run of partnerless points cross the wall (an end), rather than turn a convex corner of
    one face (a base's edge, a carination)? Across an end, the partner of the face point just before
    it lies just past it (within three wall thicknesses, going through the run), or the other way
    round; past a corner it lies on the other face, a strip's length round."""
    a, b = run
    reach = (b - a) + 3.0 * t / step
    for k in range(1, int(t / step) + 2):  # the first partnered points on either side
        before, after = (a - k) % n, (b - 1 + k) % n
        if np.isfinite(dist[before]) and (hit[before] - before) % n <= reach:
            return True
        if np.isfinite(dist[after]) and (after - hit[after]) % n <= reach:
            return True
        if np.isfinite(dist[before]) and np.isfinite(dist[after]):
            return False
    return False


def _runs(mask: np.ndarray):
    """(start, stop) index pairs of the runs of True in a circular mask (stop may exceed len - 1 by
    wrapping: the run covers start..stop-1 modulo the length)."""
    n = len(mask)
    if mask.all():
        return [(0, n)]
    shift = int(np.argmin(mask))  # a False to start from
    m = np.roll(mask, -shift)
    edges = np.diff(np.concatenate([[0], m.astype(np.int8), [0]]))
    starts, stops = np.flatnonzero(edges == 1), np.flatnonzero(edges == -1)
    return [(int(a + shift), int(b + shift)) for a, b in zip(starts, stops)]


def end_spread(curves, k_ref: int | None = None) -> float:
    """How far the same end of different sections lies apart (mm): for each pair of curves, the
    median distance from the points of one to the polyline of the other; the median over pairs.
    About the noise for a surface of revolution (a lip), the break's wavering for a break.

    Examples
    --------
    >>> land = strip(np.array([[40, 0], [44, 0], [44, 30], [40, 30]], float), 0.0, 0.0)
    >>> top = int(np.argmax([land.centre(k)[1] for k in (0, 1)]))
    >>> round(end_spread([land.end_points(top), land.end_points(top) + [0.0, 0.1]]), 6)
    0.1
    """
    from scipy.spatial import cKDTree
    curves = [c for c in curves if len(c) >= 2]
    if len(curves) < 2:
        return math.nan
    trees = [cKDTree(c) for c in curves]
    out = []
    for i in range(len(curves)):  # a dozen sections: a few dozen small queries
        for j in range(len(curves)):
            if i != j:
                out.append(float(np.median(trees[j].query(curves[i])[0])))
    return float(np.median(out))
