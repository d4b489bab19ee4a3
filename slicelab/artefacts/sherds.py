"""Sherds: a fragment of a vessel recognised, set in its stance by its rim, and measured.

Most of a lab's finds are sherds. `slicelab.artefacts.align` finds a
sherd's axis from its own surface (the normal lines of any piece of a
surface of revolution meet the axis; `slicelab.artefacts.axis_lines`) and
calls it a sherd when the surface spans less than the full turn about that
axis. `sherd_stance` then:

1. cuts the sherd by meridian planes across its span (`meridian_rings`);
   each section is a strip of wall with two ends;
2. finds the rim: an end that is a level circle, the same height and
   radius in every section (within 0.25 mm plus the noise, where a break
   wavers by millimetres); a base: a broad plane face perpendicular to the
   axis (within 5 degrees) at one extreme of the sherd;
3. fixes the stance: the rim up (its land is the plane a drawer lays the
   sherd on: the rim's top defines the axis direction) or, without a rim,
   the base down; with neither the stance is a guess;
4. measures the rim (its outer edge's diameter, the angle it spans, its
   share of the circle) and the base (the footprint's diameter), and
   judges whether the axis can be trusted: fits on the two halves of the
   sherd (split by angle) must agree with the whole (`SherdReport`).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..mesh.core import Mesh
from .axis_fit import rotation_to_z
from .axis_lines import SurfaceSample, fit_axis_lines
from .measure import clip_ring

__all__ = ["SherdReport", "sherd_interval", "meridian_rings", "sherd_wall", "sherd_stance", "TRUSTED_AXIS"]

#: Degrees the halves' axes may stray from the whole's before the axis is not trusted.
TRUSTED_AXIS = 5.0
_SECTIONS = 9
_RIM_LEVEL = 0.25     # mm: a rim's ends stray less than this (plus the noise) from one level circle


@dataclass(frozen=True)
class SherdReport:
    """What a sherd is and what can be measured on it.

    Attributes
    ----------
    kind : str
        ``"rim"``, ``"base"`` or ``"body"``.
    span : float
        Degrees the sherd covers about the axis.
    rim_span : float
        Degrees of rim kept (NaN without a rim).
    rim_fraction : float
        `rim_span` / 360 (NaN without a rim).
    rim_diameter : float
        Outer diameter of the rim (mm; NaN without a rim).
    base_diameter : float
        Diameter of the footprint's edge (mm; NaN without a base).
    axis_trusted : bool
        The sherd's two halves (split by angle) agree with the whole: for a rim or a base, their
        level faces' planes within `TRUSTED_AXIS` degrees and their axes' offsets within 3 % of the
        radius; for a body sherd, their axes within half of `TRUSTED_AXIS`, and then (checked by
        `slicelab.artefacts.align`) each half, searched on its own, finds no axis more than
        `TRUSTED_AXIS` away that fits it about as well, and a clean mesh's normals meet the axis
        to rounding.
    axis_spread : float
        The angle (degrees) between the halves' planes, or between their axes and the whole's,
        or to a rival axis.
    up_from : str
        ``"rim"``, ``"base plane"`` or ``"unknown"`` (the stance is a guess).
    """

    kind: str
    span: float
    rim_span: float = math.nan
    rim_fraction: float = math.nan
    rim_diameter: float = math.nan
    base_diameter: float = math.nan
    axis_trusted: bool = False
    axis_spread: float = math.nan
    up_from: str = "unknown"

    def sentence(self) -> str:
        """One line for a report, e.g. ``sherd: rim, 62 degrees, 17 % of the rim``.

        Examples
        --------
        >>> SherdReport("rim", 62.0, 61.0, 61 / 360, 97.6, axis_trusted=True, up_from="rim").sentence()
        'sherd: rim, 62 degrees, 17 % of the rim (rim diameter 97.6 mm)'
        >>> SherdReport("body", 40.0).sentence()
        'body sherd: no axis can be trusted (40 degrees)'
        """
        if not self.axis_trusted:
            return f"{self.kind} sherd: no axis can be trusted ({self.span:.0f} degrees)"
        text = f"sherd: {self.kind}, {self.span:.0f} degrees"
        if self.kind == "rim" and math.isfinite(self.rim_fraction):
            text += f", {100 * self.rim_fraction:.0f} % of the rim"
            if math.isfinite(self.rim_diameter):
                text += f" (rim diameter {self.rim_diameter:.1f} mm)"
        if self.kind == "base" and math.isfinite(self.base_diameter):
            text += f" (base diameter {self.base_diameter:.1f} mm)"
        return text

    def to_dict(self) -> dict:
        """Plain values (NaN where a measurement does not apply)."""
        return {k: getattr(self, k) for k in self.__dataclass_fields__}


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


def meridian_rings(mesh: Mesh, angles) -> list:
    """The largest section polygon on the side ``(cos a, sin a)`` of each meridian plane, as an
    (r, z) ring, counter-clockwise (None where the plane misses the mesh or its section stays open).

    `mesh` is in the axis frame (the axis is z through the origin).

    Examples
    --------
    >>> from slicelab.samples import sherd_mesh
    >>> v, f = sherd_mesh("beaker", "rim", 60.0, spacing=2.0)
    >>> ring = meridian_rings(Mesh.from_vertices_faces(v, f), [np.radians(30)])[0]
    >>> round(float(ring[:, 1].max()), 6), bool(ring[:, 0].min() > 30)
    (100.0, True)
    """
    from ..geometry.polygons import signed_area
    from ..slicing.sections import section
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


def _ends(ring: np.ndarray):
    """The two ends of a strip-shaped ring (its farthest pair of points), each the mean of the ring's
    points within 1.5 thicknesses of it, and the strip's thickness (twice its area over its perimeter)."""
    from ..geometry.polygons import signed_area
    p = ring[:: max(1, len(ring) // 400)]
    d = np.linalg.norm(p[:, None] - p[None], axis=2)
    i, j = np.unravel_index(int(np.argmax(d)), d.shape)
    perimeter = float(np.hypot(*np.diff(np.vstack([ring, ring[:1]]), axis=0).T).sum())
    t = 2 * abs(signed_area(ring)) / max(perimeter, 1e-12)
    ends = []
    for k in (i, j):
        near = np.linalg.norm(ring - p[k], axis=1) <= 1.5 * t
        ends.append(ring[near].mean(axis=0))
    return ends[0], ends[1], t


def sherd_wall(ring: np.ndarray) -> np.ndarray:
    """Wall thickness along a sherd's section: from each point of one long side of the strip to the
    other side, the points within 1.5 thicknesses of the strip's two ends (rim, breaks) left out.

    Examples
    --------
    >>> strip = np.array([[40, 0], [44, 0], [44, 30], [40, 30]], float)
    >>> t = sherd_wall(strip)
    >>> round(float(t.min()), 3), round(float(t.max()), 3)
    (4.0, 4.0)
    """
    from scipy.spatial import cKDTree

    from .measure import resample
    e1, e2, t = _ends(ring)
    closed = np.vstack([ring, ring[:1]])
    step = max(t, 1e-9) / 40
    pts = resample(closed, step)[0][:-1]
    i1 = int(np.argmin(np.linalg.norm(pts - e1, axis=1)))
    i2 = int(np.argmin(np.linalg.norm(pts - e2, axis=1)))
    lo, hi = min(i1, i2), max(i1, i2)
    side_a, side_b = pts[lo:hi + 1], np.vstack([pts[hi:], pts[:lo + 1]])
    if len(side_a) < 2 or len(side_b) < 2:
        return np.zeros(0)
    d = cKDTree(side_b).query(side_a)[0]
    away = (np.linalg.norm(side_a - e1, axis=1) > 1.5 * t) & (np.linalg.norm(side_a - e2, axis=1) > 1.5 * t)
    return d[away]


def _plane_normal(pts: np.ndarray):
    """Unit normal (z >= 0) of the best plane through points, three rounds of dropping those over
    three robust sigmas off it; None for fewer than 20 points."""
    nrm = None
    for _ in range(3):  # robust rounds
        if len(pts) < 20:
            return nrm
        c = pts.mean(axis=0)
        _, _, vt = np.linalg.svd(pts - c, full_matrices=False)
        nrm = vt[2] if vt[2][2] >= 0 else -vt[2]
        dist = (pts - c) @ nrm
        pts = pts[np.abs(dist) <= max(3 * 1.4826 * float(np.median(np.abs(dist))), 1e-12)]
    return nrm


def _level_circle_residual(pts: np.ndarray) -> float:
    """RMS distance of 3-D points from their best plane plus RMS distance, in that plane, from their
    best circle (Kåsa's fit): about zero for points of a rim, millimetres for a break."""
    if len(pts) < 4:
        return math.inf
    c = pts - pts.mean(axis=0)
    _, sv, vt = np.linalg.svd(c, full_matrices=False)
    plane = float(sv[-1] / math.sqrt(len(pts)))
    x, y = c @ vt[0], c @ vt[1]
    A = np.column_stack([2 * x, 2 * y, np.ones_like(x)])
    sol = np.linalg.lstsq(A, x * x + y * y, rcond=None)[0]
    radius = math.sqrt(max(float(sol[2] + sol[0] ** 2 + sol[1] ** 2), 0.0))
    circle = float(np.sqrt(np.mean((np.hypot(x - sol[0], y - sol[1]) - radius) ** 2)))
    return plane + circle


def sherd_stance(mesh: Mesh, sample: SurfaceSample, point, direction, noise: float):
    """The stance of a sherd (rim up, or base down), its axis refined by the rim, and its report.

    Parameters
    ----------
    mesh : Mesh
        The sherd in input coordinates.
    sample : SurfaceSample
        Its smoothed normals (`slicelab.artefacts.axis_lines.smoothed_normals`).
    point, direction : (3,) ndarray
        The axis fitted to the normal lines (either sense).
    noise : float
        The scan's noise sigma (mm).

    Returns
    -------
    point, direction : (3,) ndarray
        The axis, `direction` from base to rim.
    report : SherdReport

    See Also
    --------
    slicelab.artefacts.align : calls it for a fragment.

    Examples
    --------
    >>> from slicelab.samples import scan
    >>> from slicelab.artefacts import smoothed_normals, search_axis
    >>> sherd, truth = scan("beaker", spacing=1.0, sherd="rim", span=90.0)
    >>> s = smoothed_normals(sherd.triangles)
    >>> p, d, _ = search_axis(s)
    >>> p, d, report = sherd_stance(sherd, s, p, d, 0.0)
    >>> report.kind, report.up_from, bool(d @ truth["axis"] > np.cos(np.radians(1)))
    ('rim', 'rim', True)
    """
    point = np.asarray(point, dtype=np.float64)
    direction = np.asarray(direction, dtype=np.float64) / np.linalg.norm(direction)
    tol = max(4 * noise, 0.3)

    def frame(p, d):
        R = rotation_to_z(d)
        return R, Mesh(np.einsum("...j,ij->...i", mesh.triangles - p, R))

    R, local = frame(point, direction)
    verts = local.triangles.reshape(-1, 3)
    start, width = sherd_interval(verts)
    angles = start + width * np.linspace(0.1, 0.9, _SECTIONS)
    rings = [r for r in meridian_rings(local, angles) if r is not None and len(r) >= 8]
    # Ends of each section's strip, matched from section to section by height.
    ends, thick = [], []
    for a, ring in zip(angles, rings):  # nine sections
        e1, e2, t = _ends(ring)
        lo_, hi_ = (e1, e2) if e1[1] <= e2[1] else (e2, e1)
        ends.append((a, lo_, hi_))
        thick.append(t)
    t_wall = float(np.median(thick)) if thick else math.nan
    kind, up_from, sign = "body", "unknown", 1.0
    if len(ends) >= 4:
        # A rim is a level circle: its end of every section on one plane and one circle; a break wavers.
        scores = []
        for which, s_ in ((2, 1.0), (1, -1.0)):  # the upper end, then the lower
            pts = np.array([[e[which][0] * math.cos(e[0]), e[which][0] * math.sin(e[0]), e[which][1]]
                            for e in ends])
            scores.append((_level_circle_residual(pts), s_))
        (best, s_best), (other, _) = sorted(scores)
        if best <= _RIM_LEVEL + noise and other >= 2.5 * best:
            kind, up_from, sign = "rim", "rim", s_best
    if kind != "rim":
        # A base: a broad level face at one end of the sherd's height range.
        z = verts[:, 2]
        r = np.hypot(verts[:, 0], verts[:, 1])
        for s_, z_end in ((1.0, z.min()), (-1.0, z.max())):
            near = np.abs(z - z_end) <= tol
            if near.sum() < max(20, 0.03 * len(z)):
                continue
            nrm = _plane_normal(verts[near])
            level = nrm is not None and nrm[2] >= math.cos(math.radians(5))
            if level and float(np.ptp(r[near])) >= max(2 * t_wall, 8.0):
                kind, up_from, sign = "base", "base plane", s_
                break
    if sign < 0:
        direction = -direction
    # Refine the axis: the rim's land (or the base's underside) is level, so its plane gives the
    # direction; the offsets come from the normal lines with the direction held.
    face_of = None
    ref_r = math.nan
    if kind in ("rim", "base"):
        R, _ = frame(point, direction)
        rim_r = float(np.median([e[2][0] if sign > 0 else e[1][0] for e in ends]))

        def face_of(p, d):  # the level face's vertices in the frame of (p, d), and the frame
            R_, loc = frame(p, d)
            v = np.unique(loc.triangles.reshape(-1, 3), axis=0)
            r_ = np.hypot(v[:, 0], v[:, 1])
            if kind == "rim":  # the top band, about its own median radius (this frame's)
                band = v[:, 2] >= v[:, 2].max() - 2 * tol
                sel = band & (np.abs(r_ - float(np.median(r_[band]))) <= 1.5 * t_wall)
            else:
                sel = v[:, 2] <= v[:, 2].min() + 2 * tol
            return v[sel], R_

        for _ in range(3):  # a tilted start sees part of the face; each round sees more of it
            face, R = face_of(point, direction)
            nrm = _plane_normal(face)
            if nrm is None or nrm[2] <= math.cos(math.radians(10)):
                break
            direction = R.T @ nrm
            point = fit_axis_lines(sample, point, direction, tilt=False).point
            if nrm[2] >= math.cos(math.radians(0.01)):
                break
        ref_r = rim_r
    # Trust: the halves of the sherd (split by angle) fitted on their own must agree with the whole:
    # a rim's or a base's face halves on its plane, the normal lines' axes on their offsets (and on
    # their direction, for a body sherd).
    R, local = frame(point, direction)
    start, width = sherd_interval(local.triangles.reshape(-1, 3))
    q = np.einsum("ij,kj->ik", sample.points - point, R)
    phi = (np.arctan2(q[:, 1], q[:, 0]) - start) % (2 * np.pi)
    spread, offset = 0.0, 0.0
    if face_of is not None:
        face, _ = face_of(point, direction)
        fphi = (np.arctan2(face[:, 1], face[:, 0]) - start) % (2 * np.pi)
        normals = [_plane_normal(face[part]) for part in (fphi < width / 2, fphi >= width / 2)]
        spread = math.inf if any(n is None for n in normals) else \
            math.degrees(math.acos(min(1.0, abs(float(normals[0] @ normals[1])))))
    for part in (phi < width / 2, phi >= width / 2):
        if part.sum() < 50:
            spread = math.inf
            continue
        sub = SurfaceSample(sample.points[part], sample.normals[part], sample.weights[part], sample.spacing,
                            sample.rounds, sample.kept_share, sample.noise)
        f = fit_axis_lines(sub, point, direction, tilt=face_of is None)
        gap = f.point - point
        offset = max(offset, float(np.linalg.norm(gap - (gap @ direction) * direction)))
        if face_of is None:
            spread = max(spread, math.degrees(math.acos(min(1.0, abs(float(f.direction @ direction))))))
    if face_of is None:
        trusted = spread <= TRUSTED_AXIS / 2
    else:
        trusted = spread <= TRUSTED_AXIS and offset <= 0.03 * ref_r
    # Measurements in the final frame.
    R, local = frame(point, direction)
    verts = local.triangles.reshape(-1, 3)
    start, width = sherd_interval(verts)
    rim_span, rim_fraction, rim_d, base_d = _sherd_measures(local, kind, noise=noise, t_wall=t_wall, tol=tol)
    report = SherdReport(kind, math.degrees(width), rim_span, rim_fraction, rim_d, base_d, bool(trusted),
                         float(spread), up_from)
    return point, direction, report


def _sherd_measures(local: Mesh, kind: str, *, noise: float, t_wall: float, tol: float) -> tuple:
    """A sherd's rim span (degrees), rim fraction and rim diameter (rims), or base diameter
    (bases), in its final frame (`local`: the axis on z, up from base to rim); NaN where none."""
    verts = local.triangles.reshape(-1, 3)
    start, width = sherd_interval(verts)
    rim_span = rim_fraction = rim_d = base_d = math.nan
    if kind == "rim":
        from .outlines import outline
        rings = [x for x in meridian_rings(local, start + width * np.linspace(0.1, 0.9, _SECTIONS))
                 if x is not None and len(x) >= 8]
        outs = [outline(x, noise, max(t_wall, 1.0) / 100) for x in rings]
    if kind == "rim" and outs:
        rim_d = 2 * float(np.median([o.rim_r for o in outs]))
        z_top = float(np.median([o.z_top for o in outs]))
        r = np.hypot(verts[:, 0], verts[:, 1])
        land = (verts[:, 2] >= z_top - tol) & (r >= rim_d / 2 - 2 * t_wall)
        if land.sum() >= 8:
            rim_span = math.degrees(sherd_interval(verts[land])[1])
            rim_fraction = rim_span / 360.0
    elif kind == "base":
        # The footprint: what lies within two noise sigmas of the underside's plane.
        z = verts[:, 2]
        under = z <= z.min() + 2 * tol
        z_plane = float(np.median(z[under])) if under.any() else float(z.min())
        foot = np.abs(z - z_plane) <= max(2 * noise, 1e-6 * float(np.abs(verts).max()))
        if foot.sum() >= 20:
            base_d = 2 * float(np.percentile(np.hypot(verts[foot, 0], verts[foot, 1]), 99.5))
    return rim_span, rim_fraction, rim_d, base_d
