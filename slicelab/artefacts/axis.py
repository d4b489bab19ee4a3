"""Vessel axis: find the axis of revolution of a scan and move it onto +z, rim up, base at z = 0.

A scan comes in whatever pose the scanner left it, and a section through an
unaligned vessel says nothing about its shape. `align` finds the axis of
revolution and moves the vessel so that the axis is +z through the origin,
rim up, base at z = 0; `slicelab.artefacts.profile` then cuts it through the axis.

How the axis is found
---------------------
Up to four starts, in order of trust: the line the facets' normal lines meet
(a linear line complex [1]_ [2]_), then the principal axes of the surface;
each is refined by fitting concentric circles to horizontal sections
(`slicelab.artefacts.axis_fit`). The start whose circles fit best wins. The
rim goes up: the end where surface crosses the axis (the base) goes down;
failing that, the open boundary marks the rim; failing that, the centre of
mass goes down.

References
----------
.. [1] H. Pottmann and J. Wallner, *Computational Line Geometry*, Springer, 2001.
.. [2] H. Pottmann, M. Peternell and B. Ravani, "An introduction to line geometry
   with applications", *Computer-Aided Design* 31(1), 3-16, 1999.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from ..mesh.core import Mesh
from .axis_fit import circle_pass, line_complex_axis, rotation_to_z, surface_moments
from .axis_lines import SurfaceSample, angular_span, fit_axis_lines, smoothed_normals
from .axis_search import search_axis
from .sherds import TRUSTED_AXIS, SherdReport, sherd_stance
from .strips import covered_span

__all__ = ["Alignment", "align"]

_FIT_FACETS = 300_000     # facets sampled for the circle fits; enough for a 0.01 degree fit
_NOT_REVOLUTION = 0.03    # relative circle residual (noise averaged out) above which a shape is not of revolution
_WHOLE_SPAN = 330.0       # degrees about the axis a whole vessel's surface covers at least
_MIN_SPAN = 10.0          # degrees: an axis that sees the surface under less is not its axis
_POOR_FIT = 0.01          # trimmed mean square sine above which the normal lines did not find an axis
_RIVAL = 1.5              # another axis fitting within this factor of the score leaves a body sherd's axis open
_SHERD_FACETS = 100       # facets a sherd has at least (an archive's coarsest have 250): a CAD box's gaps say nothing
_CLEAN_FIT = 1e-6         # trimmed mean square sine over which a clean (unsmoothed) mesh's normals miss the axis


@dataclass(frozen=True, eq=False)
class Alignment:
    """A mesh moved so that its axis of revolution is +z through the origin, rim up, base at z = 0.

    Attributes
    ----------
    mesh : Mesh
        The moved mesh (``input.transformed(matrix)``).
    matrix : (4, 4) ndarray
        Homogeneous rigid motion from input to aligned coordinates.
    axis : (3,) ndarray
        Unit axis direction in input coordinates, pointing from base to rim.
    origin : (3,) ndarray
        Where the axis meets the base plane, in input coordinates.
    residual : float
        RMS distance (mm) of horizontal sections from circles about the axis:
        the noise and the shape's departure from a surface of revolution.
    relative_residual : float
        `residual` divided by the mean radius of those circles.
    up_from : str
        The cue that decided which end is the rim: ``"base"``,
        ``"open boundary"``, ``"centre of mass"`` or, for a sherd, ``"rim"``,
        ``"base plane"`` or ``"unknown"``.
    method : str
        Which start won: ``"normals"`` (line complex), ``"principal axes"``
        or ``"search"`` (every direction tried, for sherds).
    shape_residual : float
        The same deviations averaged over sectors of 10 degrees of each wall
        (mm): the shape's own departure from circles, the noise averaged out.
    noise : float
        Standard deviation of the scan's vertex noise (mm), estimated from the
        surface itself (`slicelab.artefacts.axis_lines.smoothed_normals`).
    span : float
        Angle (degrees) the surface covers about the axis: 360 for a whole
        vessel, less for a sherd.
    axis_error : float
        Standard error (degrees) of the axis direction from the normal-line fit.
    mean_radius : float
        Mean radius (mm) of the fitted circles.
    fit_score : float
        Trimmed mean square sine of the normals' angles to their meridian planes
        (`slicelab.artefacts.axis_lines.AxisFit.score`).
    sherd : SherdReport or None
        For a fragment (`is_fragment`): its kind, its rim or base and whether its axis can be
        trusted (`slicelab.artefacts.sherds.sherd_stance`).
    noise_sd : float
        Standard uncertainty (mm) of `noise` (`slicelab.artefacts.noise.NoiseEstimate`).
    noise_samples : int
        Vertices the noise was measured on: 0 when the mesh is too small or coarse to say (its
        facets are then taken as they are, unsmoothed).

    See Also
    --------
    align : makes one.
    """

    mesh: Mesh
    matrix: np.ndarray
    axis: np.ndarray
    origin: np.ndarray
    residual: float
    relative_residual: float
    up_from: str
    method: str
    shape_residual: float = float("nan")
    noise: float = 0.0
    span: float = 360.0
    axis_error: float = 0.0
    mean_radius: float = float("nan")
    sherd: SherdReport | None = None
    fit_score: float = 0.0
    noise_sd: float = 0.0
    noise_samples: int = 0

    @property
    def is_fragment(self) -> bool:
        """True for a sherd: its facets leave a gap of more than 30 degrees about the axis (each
        facet covering the angles between its corners, so a coarse mesh's few large facets count
        for what they span, and a CAD solid's go round), and it has 100 facets or more."""
        return self.sherd is not None

    @property
    def noise_uncertain(self) -> bool:
        """True when the noise estimate is over 30 % uncertain (and over 0.02 mm), so the smoothing
        it sized may be off (`slicelab.artefacts.noise.NoiseEstimate.uncertain`; a mesh too small to
        measure is not: nothing is smoothed on it)."""
        return bool(self.noise_samples > 0 and self.noise > 0.02 and self.noise_sd > 0.3 * self.noise)

    @property
    def shape_relative(self) -> float:
        """`shape_residual` divided by the mean radius (NaN when no section fitted)."""
        r = self.mean_radius
        return float(self.shape_residual / r) if r and math.isfinite(r) and r > 0 else float("nan")

    @property
    def is_revolution(self) -> bool:
        """True when horizontal sections stay within 3 % of the radius of circles about the axis,
        the noise averaged out (`shape_residual`); the noise itself does not count against it.
        For a sherd, whose sections are arcs cut by breaks: when its normal lines meet the axis
        (`fit_score`)."""
        if self.sherd is not None:
            return bool(self.fit_score <= _POOR_FIT)
        rel = self.shape_relative
        if not math.isfinite(rel):
            rel = self.relative_residual
        return bool(rel <= _NOT_REVOLUTION)

    def __repr__(self) -> str:
        return (f"Alignment(axis={np.round(self.axis, 6).tolist()}, residual={self.residual:.4g} mm "
                f"({100 * self.relative_residual:.3g} %), noise {self.noise:.3g} mm, span {self.span:.0f} deg, "
                f"up from {self.up_from}, {self.method})")

    def to_dict(self) -> dict:
        """Plain numbers for JSON (the mesh left out)."""
        return {"matrix": self.matrix.tolist(), "axis": self.axis.tolist(), "origin": self.origin.tolist(),
                "residual": self.residual, "relative_residual": self.relative_residual,
                "shape_residual": self.shape_residual, "noise": self.noise, "span": self.span,
                "axis_error": self.axis_error, "up_from": self.up_from, "method": self.method,
                "noise_sd": self.noise_sd, "noise_samples": self.noise_samples,
                "sherd": None if self.sherd is None else self.sherd.to_dict()}


def _fit_sample(triangles: np.ndarray) -> np.ndarray:
    """A deterministic random subset of facets; area statistics of a sample are unbiased."""
    n = len(triangles)
    if n <= _FIT_FACETS:
        return triangles
    keep = np.random.default_rng(0).random(n) < _FIT_FACETS / n
    return triangles[keep]


def _facet_sample(triangles: np.ndarray) -> SurfaceSample:
    """The facets themselves as the sample (centroids, unit normals, areas): for a mesh too small to
    smooth, whose vertices all sit on edges where a face meets a break."""
    cr = np.cross(triangles[:, 1] - triangles[:, 0], triangles[:, 2] - triangles[:, 0])
    length = np.linalg.norm(cr, axis=1)
    ok = length > 0
    edges = np.linalg.norm(triangles - np.roll(triangles, 1, axis=1), axis=2)
    return SurfaceSample(triangles[ok].mean(axis=1), cr[ok] / length[ok, None], 0.5 * length[ok],
                         float(np.median(edges)) if len(edges) else 0.0, 0)


def _coarse(sherd: SherdReport) -> SherdReport:
    """A coarse mesh's sherd (too few vertices to measure its noise: an archive's few hundred
    facets): its sections interpolate a few large facets, its axis rests on a few facets' normals,
    and a lip, a base and a break are told apart on a handful of them. Its kind and stance get at
    most 0.8 confidence, and the warnings say so, whatever they show."""
    kind_c, up_c = min(sherd.kind_confidence, 0.8), min(sherd.up_confidence, 0.8)
    more = ("kind_uncertain", "up_uncertain") + (("rim_uncertain",) if sherd.kind == "rim" else ()) + \
        (("base_uncertain",) if sherd.kind == "base" else ())
    warnings = tuple(dict.fromkeys(more + tuple(sherd.warnings)))
    return replace(sherd, kind_confidence=kind_c, up_confidence=up_c, warnings=warnings)


def _up_sign(t: np.ndarray, area: np.ndarray, point: np.ndarray, direction: np.ndarray, mesh: Mesh):
    """+1 if the rim lies towards +direction, -1 if not; and the cue that decided."""
    c = t.sum(axis=1) / 3.0 - point
    h = c @ direction
    corners = t - point
    hc = corners @ direction
    rc = np.linalg.norm(corners - hc[..., None] * direction, axis=2)
    lo, hi = float(hc.min()), float(hc.max())
    mid, length = (lo + hi) / 2, hi - lo
    near = rc.min(axis=1) < 0.15 * float(rc.max())  # facets reaching close to the axis
    if area[near].sum() > 0.002 * area.sum():
        # Surface crossing the axis is the base (a rim is a ring, away from the axis).
        m = float((area[near] * h[near]).sum() / area[near].sum())
        if abs(m - mid) > 0.1 * length:
            return (1 if m < mid else -1), "base"
    from ..geometry.topology import edge_table, weld
    _, faces = weld(mesh.triangles)
    et = edge_table(faces)
    open_edges = np.flatnonzero(et["counts"] == 1)
    if len(open_edges):
        f = et["first"][open_edges]
        tri, k = f // 3, f % 3
        a = mesh.triangles[tri, k]
        b = mesh.triangles[tri, (k + 1) % 3]
        w = np.linalg.norm(b - a, axis=1)
        m = float((w * (((a + b) / 2 - point) @ direction)).sum() / w.sum())
        if abs(m - mid) > 0.1 * length:
            return (1 if m > mid else -1), "open boundary"
    # The centre of mass of the enclosed volume (or of the surface, if open) sits low.
    from ..mesh.validation import signed_volume
    vol = signed_volume(mesh.triangles)
    if vol > 0:
        tt = mesh.triangles - point
        v6 = np.einsum("ij,ij->i", tt[:, 0], np.cross(tt[:, 1], tt[:, 2]))
        com_h = float((v6 * ((tt.sum(axis=1) / 4.0) @ direction)).sum() / v6.sum())
    else:
        com_h = float((area * h).sum() / area.sum())
    return (1 if com_h <= mid else -1), "centre of mass"


def _halves_disagree(sample, point: np.ndarray, direction: np.ndarray) -> float:
    """Degrees to the farthest axis that one half of a sherd (split by angle about the axis), searched
    on its own from scratch (`search_axis`), fits about as well as (within 1.5 times the score of) the
    sherd's axis; 0 when there is none. Without a rim or a base only the normal lines fix a body
    sherd's axis, and on a gently curved piece they leave it open."""
    R = rotation_to_z(direction)
    q = np.einsum("ij,kj->ik", sample.points - point, R)
    phi = np.arctan2(q[:, 1], q[:, 0])
    mid = math.atan2(float(np.sin(phi).mean()), float(np.cos(phi).mean()))
    side = ((phi - mid + math.pi) % (2 * math.pi) - math.pi) < 0
    worst = 0.0
    for part in (side, ~side):
        if part.sum() < 50:
            return math.inf
        sub = replace(sample, points=sample.points[part], normals=sample.normals[part], weights=sample.weights[part])
        here = fit_axis_lines(sub, point, direction)
        p, d, _ = search_axis(sub, directions=600, points=2000)
        own = fit_axis_lines(sub, p, d)
        off = math.degrees(math.acos(min(1.0, abs(float(own.direction @ direction)))))
        if own.score <= _RIVAL * here.score:
            worst = max(worst, off)
    return worst


def align(mesh: Mesh) -> Alignment:
    """Move a scanned vessel so its axis of revolution is +z through the origin, rim up, base at z = 0.

    Up to four starts, in order of trust: the line the normal lines meet
    (`normal_lines_axis`, a linear line complex), then the principal axes
    (`principal_axis`). Each is refined by fitting concentric circles to
    horizontal sections in its frame (`refine_axis`: Kåsa's algebraic fit,
    one radius per wall, reweighted with Tukey's biweight so that a handle
    or a spout loses its say); the start whose circles fit best wins
    (`normal_lines_axis` and `refine_axis` cite the papers). The base (surface
    crossing the axis), else the open boundary (the rim), else the centre of
    mass decides which way is up.

    A surface spanning less than 330 degrees about its axis (with 200
    vertices or more) is a sherd (`Alignment.sherd`): its axis is searched over every direction
    (`search_axis`), its stance set by its rim or its base (`sherd_stance`),
    and a body sherd's axis is trusted only when each half of it, searched
    alone, finds no other axis that fits about as well.

    Parameters
    ----------
    mesh : Mesh
        A vessel (or any body of revolution) in any position; open scans,
        noise and missing sherds are fine.

    Returns
    -------
    Alignment

    Raises
    ------
    ValueError
        The mesh has too few facets or no area.

    See Also
    --------
    slicelab.artefacts.profile : cuts the aligned vessel through its axis.
    slicelab.artefacts.normal_lines_axis, slicelab.artefacts.principal_axis : starts.
    slicelab.artefacts.refine_axis : the concentric-circle refinement.

    Examples
    --------
    >>> import numpy as np
    >>> from slicelab.samples import pot
    >>> m = pot(20, 24)
    >>> tilt = np.eye(4); tilt[:3, :3] = rotation_to_z([1, 2, 2]).T; tilt[:3, 3] = [5, -7, 3]
    >>> a = align(m.transformed(tilt))
    >>> np.round(a.axis * 3, 3).tolist(), np.round(a.mesh.bounds[:, 2], 1).tolist()
    ([1.0, 2.0, 2.0], [0.0, 120.0])
    """
    if len(mesh) < 4:
        raise ValueError(f"cannot align a mesh of {len(mesh)} facets")
    t = _fit_sample(mesh.triangles)
    area, centroid, cov = surface_moments(t)
    scale = math.sqrt(float(np.trace(cov))) or 1.0
    sample = smoothed_normals(mesh.triangles)
    noise_sd, noise_samples = sample.noise_sd, sample.noise_samples
    if noise_samples == 0 and len(mesh) <= 20_000:
        # Too few vertices to measure noise or to smooth over: each facet's own normal is exact.
        sample = _facet_sample(mesh.triangles)
    # Starts: the line complex of the smoothed normals, then the principal axes (a jug's handle can
    # make the wrong eigenvalue stand apart, so all three). Each is refined on the normal lines.
    _, eig = np.linalg.eigh(cov)
    starts = [("normals", line_complex_axis(sample.points, sample.normals, sample.weights, centroid, scale))]
    starts += [("principal axes", (centroid, v)) for v in eig.T[::-1]]
    fits = []
    for name, (p, d) in starts:  # four starts, a dozen Gauss-Newton steps each
        if any(abs(float(d @ f.direction)) > math.cos(math.radians(3)) for _, f, _ in fits):
            continue
        f = fit_axis_lines(sample, p, d)
        fits.append((name, f, angular_span(sample.points, sample.weights, f.point, f.direction)[0]))
    # An axis far off that sees the surface under a few degrees fits a gently curved sherd's
    # nearly parallel normals as well as the true one: no such axis.
    method, fit, span = min(fits, key=lambda c: (c[2] < _MIN_SPAN, c[1].score))
    circles = None
    span = min(span, covered_span(t, fit.point, fit.direction))
    whole = span >= _WHOLE_SPAN and fit.score <= _POOR_FIT
    if whole:
        circles = circle_pass(t, fit.point, fit.direction, shape=True, fixed=True)
        # An axis through a sherd sees it all round too, but its sections are no circles.
        whole = circles is not None and circles[2][3] <= _NOT_REVOLUTION * circles[2][4]
    steep = float(sample.weights[np.abs(sample.normals @ fit.direction) < 0.5].sum() / sample.weights.sum())
    if whole and steep >= 0.6:
        # The line through the circles' centres, where it fits them better, on steep walls only (on a
        # plate's shallow wall a tilt shows as a centre shift 20 times larger and it overshoots).
        moved = circle_pass(t, fit.point, fit.direction, shape=True)
        if moved is not None and moved[2][2] < circles[2][2]:
            fit = replace(fit, point=moved[0], direction=moved[1] * np.sign(float(moved[1] @ fit.direction)))
            circles = moved
    tries = []
    if not whole:
        # A sherd (or a poor fit): try every direction; the line complex settles on a line through a sherd.
        for p, d, _ in search_axis(sample, candidates=True)[:3]:  # the three best valleys
            f = fit_axis_lines(sample, p, d)
            tries.append((f, min(angular_span(sample.points, sample.weights, f.point, f.direction)[0],
                                 covered_span(t, f.point, f.direction))))
        found, found_span = min(tries, key=lambda c: (c[1] < _MIN_SPAN, c[0].score))
        sherd_like = _MIN_SPAN <= found_span < _WHOLE_SPAN and found.score <= _POOR_FIT
        if (sherd_like and span >= _WHOLE_SPAN) or \
                (found_span < _MIN_SPAN, found.score) < (span < _MIN_SPAN, fit.score):
            method, fit, span, circles = "search", found, found_span, None
    point, direction = fit.point, fit.direction / np.linalg.norm(fit.direction)
    sherd = None
    if span < _WHOLE_SPAN and len(mesh) >= _SHERD_FACETS:
        # A sherd: the rim (or the base) sets the stance and refines the axis.
        point, direction, sherd = sherd_stance(mesh, sample, point, direction, sample.noise)
        if noise_samples == 0:
            sherd = _coarse(sherd)
        cue = sherd.up_from
        span = covered_span(t, point, direction)
        if sherd.kind == "body" and sherd.axis_trusted:
            # A clean mesh's normals meet the true axis to rounding; else its halves must agree.
            off = math.inf if sample.rounds == 0 and fit.score > _CLEAN_FIT else \
                _halves_disagree(sample, point, direction)
            if off > TRUSTED_AXIS / 2:  # a rival within 2.5 degrees leaves the axis that loose
                sherd = replace(sherd, axis_trusted=False, axis_spread=off)
    if circles is None or sherd is not None:
        circles = circle_pass(t, point, direction, shape=True, min_sectors=12 if span >= _WHOLE_SPAN else 2)
    if circles is None:
        rms = rel = shape = mean_r = math.nan
    else:
        rms, rel, _, shape, mean_r = circles[2]
    if sherd is None:
        sign, cue = _up_sign(t, area, point, direction, mesh)
        direction = sign * direction
    R = rotation_to_z(direction)
    # Rotated by einsum, not matmul: numpy hands (n, 3) x (3, 3) to a threaded BLAS, which on a
    # busy machine ran 10-20x slower (15 M points: 5-8 s against 0.5 s).
    moved = np.einsum("...j,ij->...i", mesh.triangles, R) - R @ point
    z0 = float(moved[..., 2].min())
    moved[..., 2] -= z0  # the lowest corner lands exactly on z = 0
    origin = point + z0 * direction
    matrix = np.eye(4)
    matrix[:3, :3] = R
    matrix[:3, 3] = -R @ origin
    # A proper rotation keeps the winding and moves normals as it moves points.
    normals = np.einsum("...j,ij->...i", mesh.file_normals, R)
    return Alignment(Mesh(moved, normals), matrix, direction, origin, float(rms), float(rel), cue, method,
                     float(shape), float(sample.noise), float(span), math.degrees(fit.sigma_angle), float(mean_r),
                     sherd, float(fit.score), float(noise_sd), int(noise_samples))
