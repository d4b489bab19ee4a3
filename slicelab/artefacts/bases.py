"""A base sherd's base: found at one end of the sherd, and its footprint measured.

A base is a broad plane face square to the axis at one extreme of the
sherd, the wall rising from its outer edge (`base_side`). Its footprint's
edge (the base corner, `slicelab.samples.vessel_truth`'s base diameter) is
measured as a whole vessel's is (`slicelab.artefacts.outlines`): in each
meridian section the exterior face, fitted unsmoothed just above the corner,
is continued down to the base's plane; those points get a least-squares
circle in the plane normal to the axis (`slicelab.artefacts.lips.fit_circle`)
whose radius carries its standard uncertainty. The base fraction is the
angle the footprint's edge covers about that circle's centre, over 360
degrees.
"""
from __future__ import annotations

import math

import numpy as np

__all__ = ["base_side", "plane_fit", "base_corners", "base_points", "base_measure"]


def plane_fit(pts: np.ndarray, rounds: int = 3):
    """The best plane through points (centroid, unit normal with z >= 0), three rounds of dropping
    those over three robust sigmas off it; None for fewer than 20 points.

    Examples
    --------
    >>> g = np.random.default_rng(0).uniform(-5, 5, (200, 2))
    >>> c, n = plane_fit(np.column_stack([g, 0.01 * g[:, 0]]))
    >>> (np.round(n, 4) + 0.0).tolist()
    [-0.01, 0.0, 1.0]
    """
    out = None
    for _ in range(rounds):  # robust rounds
        if len(pts) < 20:
            return out
        c = pts.mean(axis=0)
        _, _, vt = np.linalg.svd(pts - c, full_matrices=False)
        nrm = vt[2] if vt[2][2] >= 0 else -vt[2]
        out = (c, nrm)
        dist = (pts - c) @ nrm
        pts = pts[np.abs(dist) <= max(3 * 1.4826 * float(np.median(np.abs(dist))), 1e-12)]
    return out


def base_side(verts: np.ndarray, t_wall: float, tol: float) -> int:
    """+1 if a base lies at the low end of the sherd (in the frame of its axis), -1 at the high end,
    0 if none.

    A base: the plane fitted to the 5 % of vertices nearest that end, then twice more to those
    within `tol` of it (a slightly tilted axis sees the face aslant), holds within `tol` a face of
    at least 3 % of the vertices, square to the axis within 5 degrees, at least max(1.3 walls, 8 mm)
    across radially; and the wall rises from its outer edge (what lies over three walls from the face
    is, in the median, no nearer the axis than the face).

    Examples
    --------
    >>> from slicelab.samples import sherd_mesh
    >>> v, f = sherd_mesh("pot", "base", 60.0, spacing=1.0)
    >>> base_side(v, 4.0, 0.3), base_side(v * [1, 1, -1], 4.0, 0.3)
    (1, -1)
    """
    z = verts[:, 2]
    r = np.hypot(verts[:, 0], verts[:, 1])
    m = max(20, int(0.05 * len(z)))
    for s_ in (1.0, -1.0):
        near = np.argsort(s_ * z)[:m]
        fit = plane_fit(verts[near])
        on = np.zeros(len(z), bool)
        for _ in range(2):  # the face seen whole
            if fit is None:
                break
            on = np.abs((verts - fit[0]) @ fit[1]) <= tol
            fit = plane_fit(verts[on]) if on.sum() >= 20 else None
        if fit is None:
            continue
        c, nrm = fit
        if on.sum() < max(20, 0.03 * len(z)) or nrm[2] < math.cos(math.radians(5)):
            continue
        broad = float(np.ptp(r[on]))
        if broad < max(1.3 * t_wall, 8.0) and not (broad >= max(0.8 * t_wall, 6.0) and _floor(verts, c, nrm, s_, r, on, tol)):
            continue
        h = s_ * ((verts - c) @ nrm)
        far = h > min(3 * t_wall, 0.5 * float(h.max()))  # a plate's wall rises a few millimetres only
        if far.any() and float(np.median(r[far])) >= float(np.median(r[on])):
            return int(s_)
    return 0


def _floor(verts, c, nrm, s_, r, on, tol) -> bool:
    """Over the face, within its radii, a second level face (a floor) turned the other way: a quarter
    of the vertices there lie within `tol` of one height, a fifth of the face's breadth or more above
    it. A base has one; a rim's land, which a thick wall makes as broad, has the wall under it."""
    h = s_ * ((verts - c) @ nrm)
    lo, hi = float(r[on].min()), float(r[on].max())
    over = (r >= lo) & (r <= hi) & (h > 0.2 * (hi - lo))
    if over.sum() < 10:
        return False
    hv = np.sort(h[over])
    k = np.searchsorted(hv, hv + 2 * tol) - np.arange(len(hv))  # how many lie within 2 tol above each
    return bool(k.max() >= 0.25 * len(hv))


def base_corners(strips, z_base: float, tol: float):
    """Per strip: its angle and the radius where its exterior face, fitted (unsmoothed) from half a
    wall to three walls above the footprint's outer edge, reaches the base's plane `z_base`.

    Examples
    --------
    >>> from slicelab.artefacts.strips import strip
    >>> ring = np.array([[10, 0], [30, 0], [40, 20], [36, 20], [27, 5], [10, 5]], float)
    >>> a, r = base_corners([strip(ring, 0.0, 0.0)], 0.0, 0.1)
    >>> round(float(r[0]), 3)
    30.0
    """
    from .lips import edge_radius
    out = []
    for s in strips:  # a dozen strips
        raw = s.raw if s.raw is not None else s.points
        foot = (s.end < 0) & (np.abs(s.points[:, 1] - z_base) <= max(tol, 0.02 * s.thickness)) & \
            (s.normals[:, 1] <= -math.cos(math.radians(30)))
        if foot.sum() < 3:
            continue
        k = int(np.flatnonzero(foot)[np.argmax(s.points[foot, 0])])
        n = len(s.points)
        q, m = int(round(0.5 * s.thickness / s.step)), max(int(round(2.5 * s.thickness / s.step)), 3)
        idx = (k + q + np.arange(m)) % n  # counter-clockwise from the underside: up the exterior
        stop = int(np.argmax(s.end[idx] >= 0)) if (s.end[idx] >= 0).any() else m  # not past the face
        if stop >= 3:
            out.append((s.angle, edge_radius(raw[idx[:stop]], z_base)))
    if not out:
        return np.zeros(0), np.zeros(0)
    a, r = (np.array(x) for x in zip(*out))
    return a, r


def base_points(verts: np.ndarray, strips, tol: float):
    """The base's plane height (the median of the vertices within 2 `tol` of the lowest) and, per
    strip, its angle and footprint edge radius (`base_corners`)."""
    z = verts[:, 2]
    under = z <= z.min() + 2 * tol
    z_base = float(np.median(z[under])) if under.any() else float(z.min())
    a, r = base_corners(strips, z_base, tol)
    return z_base, a, r


def base_measure(verts: np.ndarray, strips, noise: float, tol: float, axis_sd: float = 0.0):
    """A base sherd's footprint: its edge's diameter (mm), the diameter's standard uncertainty and the
    share of its circle kept; NaN where the sections do not show it.

    The base's plane is the median height of the vertices within `tol` of the lowest; its edge,
    `base_corners` through `slicelab.artefacts.lips.circle_radius` (`axis_sd` the axis position's
    uncertainty, mm); the share, the angle the vertices within a wall of that edge (and of the plane)
    cover about the axis.
    """
    from .lips import circle_radius
    from .strips import sherd_interval
    z = verts[:, 2]
    z_base, a, r = base_points(verts, strips, tol)
    if len(r) < 3:
        return math.nan, math.nan, math.nan
    radius, sd_r = circle_radius(a, r, axis_sd)
    cx = cy = 0.0
    t = float(np.median([s.thickness for s in strips]))
    q = verts - [cx, cy, 0.0]
    rr = np.hypot(q[:, 0], q[:, 1])
    edge = (np.abs(rr - radius) <= max(0.5 * t, 3 * noise)) & (z <= z_base + t)
    frac = sherd_interval(q[edge], bins=1440)[1] / (2 * math.pi) if edge.sum() >= 3 else math.nan
    return 2 * radius, 2 * sd_r, frac
