"""The axis of revolution from the surface's normal lines, for dense noisy scans and for sherds.

Every normal line of a surface of revolution meets its axis, on the whole
vessel and on any piece of it: the normal at a point lies in the meridian
plane through that point. Three steps (`slicelab.artefacts.align` runs them):

1. `smoothed_normals`: a scan's facets are about 0.3 mm wide and its noise
   0.05-0.2 mm, so each facet's own normal is off by tens of degrees. The
   facets' area vectors are summed onto the shared vertices, then averaged
   over the mesh's edges a few dozen times (a random walk of about 1.5 mm):
   the sum of the area vectors of a patch depends on its boundary only, so
   the noise averages out while the shape, a few millimetres across, stays.
   Smoothing follows the surface, not space: the inner and outer walls,
   4 mm apart, do not mix.
2. `slicelab.artefacts.axis_fit.line_complex_axis`: the least-squares line the
   normal lines meet, linear in Plücker coordinates (Pottmann and Wallner [1]_),
   as a start.
3. `fit_axis_lines`: Gauss-Newton on the geometric residual, the sine of the
   angle between a point's normal and its meridian plane, reweighted with
   Tukey's biweight [2]_ (handles, spouts and a sherd's breaks, whose normals
   miss the axis, lose their say). Unlike concentric circles on horizontal
   sections, it does not overshoot on shallow walls (a plate's wall at 12
   degrees makes a tilt look like a centre shift 20 times larger) and
   needs no full turn.

`angular_span` then tells a whole vessel from a sherd: the angle about the
axis that the surface covers.

References
----------
.. [1] H. Pottmann and J. Wallner, *Computational Line Geometry*, Springer, 2001.
.. [2] A. E. Beaton and J. W. Tukey, "The fitting of power series, meaning
   polynomials, illustrated on band-spectroscopic data", *Technometrics*
   16(2), 147-185, 1974.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .axis_fit import rotation_to_z, tukey_weights

__all__ = ["SurfaceSample", "smoothed_normals", "fit_axis_lines", "AxisFit", "angular_span"]

_REACH_PER_NOISE = 10.0    # smoothing reach, in noise standard deviations
_MAX_ROUNDS = 24           # averaging rounds at most
_SAMPLE = 150_000          # vertices kept for fitting


@dataclass(frozen=True, eq=False)
class SurfaceSample:
    """Points of a surface with smoothed unit normals and the area each stands for.

    Attributes
    ----------
    points : (n, 3) ndarray
    normals : (n, 3) ndarray
        Unit, outward.
    weights : (n,) ndarray
        Area (mm^2) per point.
    spacing : float
        Median edge length of the mesh (mm).
    rounds : int
        Averaging rounds the normals went through.
    kept_share : float
        Share of the (fine) mesh's vertices kept in the sample.
    noise : float
        Estimated standard deviation of the vertices' noise (mm), from
        residuals to local quadric fits (`slicelab.artefacts.noise`; about 0
        on a clean mesh).
    noise_sd : float
        Standard uncertainty (mm) of `noise`.
    noise_samples : int
        Vertices the noise was measured on (0: too few to say).
    """

    points: np.ndarray
    normals: np.ndarray
    weights: np.ndarray
    spacing: float
    rounds: int
    kept_share: float = 1.0
    noise: float = 0.0
    noise_sd: float = 0.0
    noise_samples: int = 0


def _area_vectors(v: np.ndarray, f: np.ndarray):
    """Per vertex: the sum of its facets' area vectors (times 2) and a third of their area."""
    t = v[f]
    cr = np.cross(t[:, 1] - t[:, 0], t[:, 2] - t[:, 0])
    nv = len(v)
    vec = np.column_stack([sum(np.bincount(f[:, k], cr[:, c], nv) for k in range(3)) for c in range(3)])
    area = sum(np.bincount(f[:, k], np.sqrt(np.einsum("ij,ij->i", cr, cr)), nv) for k in range(3)) / 6.0
    return vec, area


def _spmv(A, x: np.ndarray) -> np.ndarray:
    """A @ x column by column (one-dimensional products run several times faster)."""
    if x.ndim == 1:
        return A @ x
    return np.column_stack([A @ np.ascontiguousarray(x[:, c]) for c in range(x.shape[1])])


def _adjacency(f: np.ndarray, nv: int):
    """The vertex adjacency of a mesh as a sparse 0/1 matrix, each vertex's degree, and its facet
    edges' ends."""
    from scipy.sparse import csr_matrix
    a, b = f.reshape(-1), f[:, [1, 2, 0]].reshape(-1)
    A = csr_matrix((np.ones(len(a) * 2), (np.concatenate([a, b]), np.concatenate([b, a]))), shape=(nv, nv))
    A.sum_duplicates()
    A.data[:] = 1.0
    deg = np.maximum(np.diff(A.indptr).astype(np.float64), 1.0)
    return A, deg, a, b


def smoothed_normals(triangles: np.ndarray, *, reach: float | None = None, sample: int = _SAMPLE,
                     seed: int = 0) -> SurfaceSample:
    """Vertices of a mesh with their normals averaged over a patch about `reach` mm across.

    Parameters
    ----------
    triangles : (n, 3, 3) ndarray
    reach : float, optional
        Smoothing reach (mm); default 10 times the noise the mesh shows
        (`slicelab.artefacts.noise_estimate`; a clean mesh is not smoothed), at most about 3.5
        vertex spacings (24 rounds).
    sample : int
        Vertices kept (a deterministic random subset).
    seed : int

    Returns
    -------
    SurfaceSample

    See Also
    --------
    fit_axis_lines : fits the axis to them.

    Examples
    --------
    >>> from slicelab.samples import pot
    >>> s = smoothed_normals(pot(20, 24).triangles)
    >>> s.rounds, bool(np.allclose(np.linalg.norm(s.normals, axis=1), 1.0))
    (0, True)
    """
    from ..geometry.topology import weld
    v, f = weld(triangles)
    if not len(f):
        raise ValueError("the mesh has no facets")
    area_vec, area = _area_vectors(v, f)
    nv = len(v)
    A, deg, a, b = _adjacency(f, nv)
    from .noise import noise_estimate
    est = noise_estimate(v, f)
    noise = est.sigma
    stride = max(1, len(a) // 200_000)
    step = np.linalg.norm(v[a[::stride]] - v[b[::stride]], axis=1)
    spacing = float(np.median(step)) if len(step) else 0.0
    if reach is None:
        reach = _REACH_PER_NOISE * noise
    # A random walk of k rounds over edges about `spacing` long reaches about spacing * sqrt(k / 2).
    rounds = int(min(_MAX_ROUNDS, math.floor(2 * (reach / spacing) ** 2))) if spacing > 0 else 0
    cols = [np.ascontiguousarray(area_vec[:, c], dtype=np.float32) for c in range(3)]
    A32 = A.astype(np.float32)
    scale = (1.0 / (deg + 1.0)).astype(np.float32)
    for _ in range(rounds):  # sparse averaging over edges (the vertex itself included), in float32
        cols = [(A32 @ c + c) * scale for c in cols]
    n = np.column_stack(cols).astype(np.float64)
    length = np.linalg.norm(n, axis=1)
    ok = length > 0
    # Near a sharp edge (a rim's corner, a sherd's break) the averaging mixed two faces' normals,
    # tilting them out of the meridian plane, and a clean mesh's vertex there averages two faces; on
    # a break's rough face the normals turn every which way: leave out the vertices whose (smoothed)
    # normal still turns fast, over three times the median turn to the neighbours' mean (and over
    # 0.15, so a clean smooth surface, whose median turn is nearly nil, keeps its vertices).
    unit = np.divide(n, length[:, None], out=np.zeros_like(n), where=ok[:, None])
    turn = np.linalg.norm(_spmv(A, unit) / deg[:, None] - unit, axis=1)
    limit = 3.0 * float(np.median(turn[ok])) if ok.any() else 0.0
    if nv >= 200:  # a coarse mesh's vertices all sit on edges: none left out
        ok &= turn <= (limit if rounds else max(limit, 0.15))
    keep = np.flatnonzero(ok)
    if len(keep) > sample:
        keep = keep[np.random.default_rng(seed).random(len(keep)) < sample / len(keep)]
    return SurfaceSample(v[keep], n[keep] / length[keep, None], area[keep], spacing, rounds,
                         len(keep) / max(nv, 1), noise, est.sd, est.samples)


@dataclass(frozen=True)
class AxisFit:
    """An axis fitted to normal lines.

    Attributes
    ----------
    point : (3,) ndarray
        The point of the axis nearest the weighted centroid of the inliers.
    direction : (3,) ndarray
        Unit direction.
    rms : float
        Weighted RMS of the residual (sine of the normals' angle to their meridian planes).
    inliers : float
        Share of the weight that kept a say.
    sigma_angle : float
        Standard error of the direction (radians), from the fit's covariance.
    sigma_offset : float
        Standard error of the axis position at the centroid (mm).
    score : float
        Mean of the smallest 70 % of the squared residuals: compares fits from different starts
        (the Tukey weights of each fit differ).
    cov : (4, 4) ndarray
        Covariance of the two tilts (radians; the direction's x and y in the frame
        `rotation_to_z(direction)`) and the two offsets (mm) of the axis.
    """

    point: np.ndarray
    direction: np.ndarray
    rms: float
    inliers: float
    sigma_angle: float
    sigma_offset: float
    score: float = 0.0
    cov: np.ndarray | None = None


def _residuals(points, normals, point, R):
    q = np.einsum("ij,kj->ik", points - point, R)
    m = np.einsum("ij,kj->ik", normals, R)
    x, y = q[:, 0], q[:, 1]
    r = np.hypot(x, y)
    F = -m[:, 0] * y + m[:, 1] * x
    return q, m, r, F


def _trimmed(e: np.ndarray, keep: float = 0.7) -> float:
    """Mean of the smallest `keep` share of the squared residuals."""
    e2 = e * e
    m = max(1, int(keep * len(e2)))
    return float(np.partition(e2, m - 1)[:m].mean())


def _jacobian(q, m, r, F):
    """Derivatives of the residual F / r by the tilts (about y, x) and the offsets (x, y) of the axis.

    Moving the frame to the axis (alpha, beta, 1) through (gamma, delta, 0)
    changes a point by (-gamma - alpha z, -delta - beta z, alpha x + beta y)
    and a normal by (-alpha n_z, -beta n_z, alpha n_x + beta n_y), to first order.
    """
    x, y, z = q[:, 0], q[:, 1], q[:, 2]
    rs = np.maximum(r, 1e-12)
    r3 = rs ** 3
    return np.column_stack([(m[:, 2] * y - m[:, 1] * z) / rs + F * x * z / r3,
                            (m[:, 0] * z - m[:, 2] * x) / rs + F * y * z / r3,
                            -m[:, 1] / rs + F * x / r3,
                            m[:, 0] / rs + F * y / r3])


def fit_axis_lines(sample: SurfaceSample, point, direction, *, iterations: int = 12, tilt: bool = True) -> AxisFit:
    """Gauss-Newton fit of the axis that the sample's normal lines meet, robustly reweighted.

    The residual of a point p with unit normal n is ``n . t``, t the unit
    vector about the axis at p (normal to p's meridian plane): zero on a
    surface of revolution, whatever part of it was scanned. Four unknowns:
    two tilts and two offsets of the axis, in the frame of the current
    guess. Tukey's biweight (`tukey_weights`) drops points whose normals
    miss the axis.

    Parameters
    ----------
    sample : SurfaceSample
    point, direction : (3,) array_like
        The start.
    iterations : int
    tilt : bool
        Fit the direction too (else only the offsets, the direction held).

    Returns
    -------
    AxisFit

    See Also
    --------
    smoothed_normals, line_complex_axis, slicelab.artefacts.align

    Examples
    --------
    >>> from slicelab.samples import pot
    >>> s = smoothed_normals(pot(40, 48).triangles)
    >>> fit = fit_axis_lines(s, [1.0, 0.0, 50.0], [0.05, 0.0, 1.0])
    >>> bool(abs(fit.direction[2]) > np.cos(np.radians(0.01))), bool(np.hypot(*fit.point[:2]) < 0.01)
    (True, True)
    """
    p, nrm, w0 = sample.points, sample.normals, sample.weights
    point = np.asarray(point, dtype=np.float64)
    direction = np.asarray(direction, dtype=np.float64)
    direction = direction / np.linalg.norm(direction)
    size = float(np.sqrt(((p - p.mean(axis=0)) ** 2).sum(axis=1).mean())) or 1.0
    r0 = 0.02 * size
    wk = w0.copy()
    for it in range(iterations):  # a few Gauss-Newton steps
        R = rotation_to_z(direction)
        # Centre the frame on the inliers, so that the tilts and the offsets stay apart.
        centre = (wk[:, None] * p).sum(axis=0) / max(wk.sum(), 1e-300)
        point = point + direction * float((centre - point) @ direction)
        q, m, r, F = _residuals(p, nrm, point, R)
        rs = np.maximum(r, 1e-12)
        e = F / rs
        # Near the axis the meridian plane is ill defined: less say within 2 % of the size.
        w_geo = w0 * (r / (r + r0)) ** 2
        if it:
            # The scale from normals at least 11 degrees off the axis: those along it (a base's
            # underside) have no residual wherever the axis is, and would shrink the scale until
            # the points that place the axis lose their say. A clean mesh's sines of 1e-7 are rounding.
            informative = np.hypot(m[:, 0], m[:, 1]) >= 0.2
            scale = np.abs(e[informative]) if informative.sum() >= 10 else np.abs(e)
            sigma = max(1.4826 * float(np.median(scale)), 1e-7)
            u = e / (4.685 * sigma)
            wk = w_geo * np.where(np.abs(u) < 1, (1 - u * u) ** 2, 0.0)
        else:
            wk = w_geo
        J = _jacobian(q, m, r, F)
        if not tilt:
            J = J.copy()
            J[:, :2] = 0.0
        JW = J * wk[:, None]
        H = J.T @ JW
        g = JW.T @ e
        scale = np.sqrt(np.maximum(np.diag(H), 1e-300))
        step = -np.linalg.lstsq(H / np.outer(scale, scale), g / scale, rcond=1e-12)[0] / scale
        # Backtracking: a step must lower the trimmed score (`AxisFit.score`), or it is halved.
        now = _trimmed(e)
        for _ in range(8):  # halvings
            a_local = np.array([step[0], step[1], 1.0])
            new_dir = R.T @ (a_local / np.linalg.norm(a_local))
            new_point = point + R.T @ np.array([step[2], step[3], 0.0])
            _, _, r_new, F_new = _residuals(p, nrm, new_point, rotation_to_z(new_dir))
            if _trimmed(F_new / np.maximum(r_new, 1e-12)) <= now:
                break
            step = step / 2
        else:
            break  # no step lowers it: converged
        direction, point = new_dir, new_point
        if np.abs(step[:2]).max() < 1e-10 and np.abs(step[2:]).max() < 1e-9 * size:
            break
    R = rotation_to_z(direction)
    q, m, r, F = _residuals(p, nrm, point, R)
    e = F / np.maximum(r, 1e-12)
    W = max(float(wk.sum()), 1e-300)
    rms = math.sqrt(float((wk * e * e).sum()) / W)
    # Sandwich covariance of the last step (the weights are areas, not inverse variances), times
    # the number of kept points that share one smoothing patch (their residuals are not independent).
    J = _jacobian(q, m, r, F)
    H = J.T @ (J * wk[:, None])
    B = J.T @ (J * (wk * wk * e * e)[:, None])
    Hinv = np.linalg.pinv(H)
    shared = max(1.0, 0.5 * math.pi * sample.rounds * sample.kept_share)
    cov = Hinv @ B @ Hinv * shared
    sigma_angle = math.sqrt(max(float(cov[0, 0] + cov[1, 1]), 0.0))
    sigma_offset = math.sqrt(max(float(cov[2, 2] + cov[3, 3]), 0.0))
    score = _trimmed(e)
    return AxisFit(point, direction, rms, float(wk.sum() / max(w0.sum(), 1e-300)), sigma_angle, sigma_offset, score,
                   cov)


def angular_span(points: np.ndarray, weights: np.ndarray, point, direction, bins: int = 360):
    """Angle about an axis that a surface covers (degrees), and where its largest gap is centred.

    A bin of one degree counts as covered when it holds more than 2 % of
    the average weight per bin; the span is the full turn minus the largest
    run of empty bins (a hole in one height band leaves no gap: other
    heights cover it).

    Returns
    -------
    span : float
        Degrees; 360 for a whole vessel.
    gap_centre : float
        Angle (radians, in the axis frame of `rotation_to_z`) of the middle of
        the largest gap; 0 when there is none.

    Examples
    --------
    >>> phi = np.radians(np.arange(0, 90, 0.5))
    >>> pts = np.column_stack([np.cos(phi), np.sin(phi), 0 * phi])
    >>> round(angular_span(pts, np.ones(len(phi)), [0, 0, 0], [0, 0, 1])[0])
    90
    """
    R = rotation_to_z(direction)
    q = np.einsum("ij,kj->ik", np.asarray(points) - np.asarray(point, float), R)
    phi = np.arctan2(q[:, 1], q[:, 0])
    k = np.floor((phi + np.pi) / (2 * np.pi) * bins).astype(np.int64) % bins
    hist = np.bincount(k, weights, bins)
    covered = hist > 0.02 * hist.sum() / bins
    if covered.all():
        return 360.0, 0.0
    if not covered.any():
        return 0.0, 0.0
    # Longest circular run of empty bins.
    empty = np.concatenate([~covered, ~covered])
    edges = np.diff(np.concatenate([[0], empty.astype(np.int8), [0]]))
    starts, ends = np.flatnonzero(edges == 1), np.flatnonzero(edges == -1)
    lengths = np.minimum(ends - starts, bins)
    i = int(np.argmax(lengths))
    gap = int(lengths[i])
    centre = (starts[i] + gap / 2) % bins
    return 360.0 * (bins - gap) / bins, float(centre / bins * 2 * np.pi - np.pi)
