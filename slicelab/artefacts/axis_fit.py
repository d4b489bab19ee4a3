"""Estimators of an axis of revolution: surface moments, normal lines, concentric circles.

Plain arrays in, a line (point, unit direction) out; `slicelab.artefacts.align`
chooses between them and moves the vessel.

1. Principal axes of the surface (exact area moments, `surface_moments`): for
   a body of revolution two eigenvalues are equal and the third stands apart
   (`principal_axis`).
2. The normals of a surface of revolution all meet its axis. In Plücker
   coordinates a facet's normal line is (n, p x n) and it meets the axis
   (a, c x a) when ``n . (c x a) + (p x n) . a = 0``, which is linear in the
   axis: the least-squares axis is the smallest eigenvector of a 6x6 problem
   (a linear line complex, `line_complex_axis`; `normal_lines_axis` feeds it
   the facets), after Pottmann and Wallner.
3. Refinement (`refine_axis`): horizontal sections in the frame of the
   current axis are fitted with concentric circles (one shared centre per
   height, a radius per wall); a straight line through the centres is the new
   axis; repeat. Outer walls run counter-clockwise and inner walls clockwise
   (`slicelab.slicing.sections`), which tells the walls apart without any
   tolerance.

Each is reweighted with Tukey's biweight, so that handles, spouts and lugs
lose their say.
"""
from __future__ import annotations

import math

import numpy as np

from ..mesh.core import Mesh
from ..slicing.sections import slice_layers

__all__ = ["rotation_to_z", "surface_moments", "principal_axis", "normal_lines_axis", "line_complex_axis",
           "tukey_weights", "circle_pass", "refine_axis"]


def rotation_to_z(direction) -> np.ndarray:
    """The smallest rotation (3 x 3) taking `direction` onto +z.

    A rotation about ``direction x z`` (Rodrigues' formula); a direction
    along -z turns half a turn about x.

    See Also
    --------
    slicelab.artefacts.align : uses it to move a vessel's axis onto +z.

    Examples
    --------
    >>> R = rotation_to_z([1, 0, 0])
    >>> np.round(R @ [1, 0, 0], 12).tolist()
    [0.0, 0.0, 1.0]
    """
    a = np.asarray(direction, dtype=np.float64)
    a = a / np.linalg.norm(a)
    c = float(a[2])
    v = np.array([a[1], -a[0], 0.0])  # a x z
    s = float(np.linalg.norm(v))
    if s < 1e-15:
        return np.eye(3) if c > 0 else np.diag([1.0, -1.0, -1.0])
    k = v / s
    K = np.array([[0.0, -k[2], k[1]], [k[2], 0.0, -k[0]], [-k[1], k[0], 0.0]])
    return np.eye(3) + s * K + (1.0 - c) * (K @ K)


def surface_moments(triangles: np.ndarray):
    """Area of each facet, centroid and exact second-moment (covariance) matrix of a triangle surface.

    The integral of ``x x^T`` over a triangle with corners ``a, b, c``
    (about the centroid) is ``A / 12 (a a^T + b b^T + c c^T + s s^T)`` with
    ``s = a + b + c``: exact, no sampling.

    Parameters
    ----------
    triangles : (n, 3, 3) ndarray

    Returns
    -------
    area : (n,) ndarray
        Area of each facet.
    centroid : (3,) ndarray
        Area centroid of the surface.
    cov : (3, 3) ndarray
        Second moment of the surface about its centroid, per unit area (mm^2).

    Raises
    ------
    ValueError
        The surface has no area.

    See Also
    --------
    principal_axis : the axis of revolution from `cov`.
    normal_lines_axis : the axis from the facets' normal lines.

    Examples
    --------
    >>> from slicelab.samples import box
    >>> area, centroid, cov = surface_moments(box((0, 0, 0), (2, 2, 2)).triangles)
    >>> float(area.sum()), centroid.tolist(), np.round(np.diag(cov), 6).tolist()
    (24.0, [1.0, 1.0, 1.0], [0.555556, 0.555556, 0.555556])
    """
    t = np.asarray(triangles, dtype=np.float64)
    a, b, c = t[:, 0], t[:, 1], t[:, 2]
    cr = np.cross(b - a, c - a)
    area = 0.5 * np.sqrt(np.einsum("ij,ij->i", cr, cr))
    total = float(area.sum())
    if not total > 0:
        raise ValueError("the mesh has no area to align")
    centroid = (area[:, None] * (a + b + c)).sum(axis=0) / (3 * total)
    a, b, c = a - centroid, b - centroid, c - centroid
    s = a + b + c
    m = (np.einsum("n,ni,nj->ij", area, a, a) + np.einsum("n,ni,nj->ij", area, b, b)
         + np.einsum("n,ni,nj->ij", area, c, c) + np.einsum("n,ni,nj->ij", area, s, s)) / 12.0
    return area, centroid, m / total


def principal_axis(cov: np.ndarray) -> np.ndarray:
    """The principal axis whose eigenvalue stands apart from the other two (a unit vector).

    For a body of revolution two eigenvalues of the second-moment matrix are
    equal and the third, apart from them, belongs to the axis. For a squat
    vessel all three can be close and the wrong one can stand apart: a start
    to refine, not an answer.

    Parameters
    ----------
    cov : (3, 3) ndarray
        Symmetric second-moment matrix (`surface_moments`).

    Returns
    -------
    (3,) ndarray

    See Also
    --------
    surface_moments, normal_lines_axis, refine_axis, slicelab.artefacts.align

    Examples
    --------
    >>> np.abs(principal_axis(np.diag([4.0, 1.0, 1.0]))).tolist()
    [1.0, 0.0, 0.0]
    """
    w, v = np.linalg.eigh(cov)
    return v[:, 0] if (w[1] - w[0]) > (w[2] - w[1]) else v[:, 2]


def normal_lines_axis(triangles: np.ndarray, area: np.ndarray, centroid: np.ndarray, scale: float):
    """The line that the facets' normal lines meet, in the least-squares sense (linear line complex).

    Every normal line of a surface of revolution meets its axis. In Plücker
    coordinates the normal line of a facet with centroid p and unit normal n is
    ``(n, p x n)``, and it meets the line ``(a, a_bar)`` when
    ``n . a_bar + (p x n) . a = 0``: linear in the unknown line. Minimising the
    area-weighted squares over ``a_bar``, then over unit ``a``, is a 3 x 3
    eigenproblem of a Schur complement of the 6 x 6 normal matrix [1]_ [2]_.
    Four rounds of Tukey's biweight take the say from facets whose normals
    miss the axis (handles, spouts, lugs). No starting guess is needed.

    Parameters
    ----------
    triangles : (n, 3, 3) ndarray
    area : (n,) ndarray
        Weight of each facet, normally its area (`surface_moments`).
    centroid : (3,) ndarray
        A point near the axis; coordinates are taken relative to it.
    scale : float
        A length of the surface's size (e.g. the square root of the trace of
        its second moment), for a well-conditioned problem.

    Returns
    -------
    point : (3,) ndarray
        The point of the axis nearest to `centroid`.
    direction : (3,) ndarray
        Unit direction of the axis (either sense).

    See Also
    --------
    surface_moments, principal_axis, refine_axis, slicelab.artefacts.align

    References
    ----------
    .. [1] H. Pottmann and J. Wallner, *Computational Line Geometry*, Springer, 2001.
    .. [2] H. Pottmann, M. Peternell and B. Ravani, "An introduction to line geometry
       with applications", *Computer-Aided Design* 31(1), 3-16, 1999.

    Examples
    --------
    >>> from slicelab.samples import pot
    >>> t = pot(20, 24).triangles
    >>> area, centroid, cov = surface_moments(t)
    >>> point, direction = normal_lines_axis(t, area, centroid, float(np.sqrt(np.trace(cov))))
    >>> np.round(np.abs(direction), 6).tolist(), np.round(np.abs(point[:2]), 6).tolist()
    ([0.0, 0.0, 1.0], [0.0, 0.0])
    """
    t = triangles
    n = np.cross(t[:, 1] - t[:, 0], t[:, 2] - t[:, 0])
    length = np.sqrt(np.einsum("ij,ij->i", n, n))
    ok = length > 0
    # Facet centroids and unit normals, weighted by area: handles, spouts and lugs, whose normals
    # miss the axis, lose their say in the line complex's reweighting.
    return line_complex_axis(t[ok].sum(axis=1) / 3.0, n[ok] / length[ok, None], area[ok], centroid, scale)


def line_complex_axis(points: np.ndarray, normals: np.ndarray, weights: np.ndarray, centroid: np.ndarray,
                      scale: float, rounds: int = 4):
    """The line that the normal lines ``(p, n)`` meet in the least-squares sense (a linear line complex).

    In Plücker coordinates the normal line is ``(n, p x n)`` and it meets the
    line ``(a, a_bar)`` when ``n . a_bar + (p x n) . a = 0``; minimising the
    weighted squares over ``a_bar``, then over unit ``a``, is a 3 x 3
    eigenproblem of a Schur complement. `rounds` rounds of Tukey's biweight
    take the say from normals that miss the axis.

    Parameters
    ----------
    points, normals : (n, 3) ndarray
    weights : (n,) ndarray
    centroid : (3,) ndarray
        Coordinates are taken relative to it.
    scale : float
        A length of the surface's size, for a well-conditioned problem.
    rounds : int

    Returns
    -------
    point : (3,) ndarray
        The point of the axis nearest to `centroid`.
    direction : (3,) ndarray
        Unit direction (either sense).

    See Also
    --------
    slicelab.artefacts.normal_lines_axis : the same from a mesh's facets.
    fit_axis_lines : the geometric refinement.
    slicelab.artefacts.axis_search.search_axis : every direction tried, for sherds.

    Examples
    --------
    >>> phi = np.linspace(0, 2, 50); z = np.linspace(0, 3, 50)
    >>> p = np.column_stack([np.cos(phi) + 1, np.sin(phi), z]); n = np.column_stack([np.cos(phi), np.sin(phi), 0 * z])
    >>> point, d = line_complex_axis(p, n, np.ones(50), p.mean(axis=0), 1.0)
    >>> np.round(np.abs(d), 6).tolist(), (np.round(point[:2], 6) + 0.0).tolist()
    ([0.0, 0.0, 1.0], [1.0, 0.0])
    """
    p = (points - centroid) / scale
    n = normals
    lines = np.hstack([np.cross(p, n), n])  # residual = lines @ [a, a_bar]
    wk = weights
    for _ in range(rounds):  # reweighted: normals that miss the axis lose their say
        M = np.einsum("n,ni,nj->ij", wk, lines, lines)
        A, B, C = M[:3, :3], M[:3, 3:], M[3:, 3:]
        Cinv = np.linalg.pinv(C)
        S = A - B @ Cinv @ B.T
        _, vec = np.linalg.eigh((S + S.T) / 2)
        a = vec[:, 0]
        a_bar = -Cinv @ B.T @ a
        wk = tukey_weights(lines @ np.concatenate([a, a_bar]), weights, 1e-9)
    return centroid + scale * np.cross(a, a_bar), a


def tukey_weights(e: np.ndarray, w: np.ndarray, floor: float) -> np.ndarray:
    """Weights `w` times Tukey's biweight of residuals `e`: beyond 4.685 robust sigmas, no say.

    Examples
    --------
    >>> tukey_weights(np.array([0.0, 1.0, 100.0]), np.ones(3), 1e-9).round(3).tolist()
    [1.0, 0.959, 0.0]
    """
    sigma = max(1.4826 * float(np.median(np.abs(e))), floor)
    u = e / (4.685 * sigma)
    return w * np.where(np.abs(u) < 1, (1 - u * u) ** 2, 0.0)


def _rings(points: np.ndarray, ccw: np.ndarray, weight: np.ndarray, centre: np.ndarray, min_sectors: int = 12):
    """Group one horizontal section's points into walls: by winding sense, then by radial gaps.

    `ccw` says, per point, whether its chain winds counter-clockwise about
    the centre (outer walls) or clockwise (inner walls); a wall must cover
    `min_sectors` sectors of 10 degrees (a handle's loop sits to one side).
    """
    rel = points - centre
    r = np.hypot(rel[:, 0], rel[:, 1])
    label = np.full(len(points), -1, dtype=np.int64)
    k = 0
    for sense in (True, False):  # outer walls wind counter-clockwise, inner walls clockwise
        idx = np.flatnonzero(ccw == sense)
        if len(idx) < 8:
            continue
        order = idx[np.argsort(r[idx])]
        rs = r[order]
        cut = np.flatnonzero(np.diff(rs) > max(1.0, 0.1 * float(np.median(rs)))) + 1
        for part in np.split(order, cut):  # a few walls per height, not points
            # A wall goes round the axis; a handle's or a lug's loop sits to one side of it.
            sector = np.unique((np.arctan2(rel[part, 1], rel[part, 0]) * (18 / np.pi)).astype(np.int64))
            if len(part) >= 8 and weight[part].sum() > 0 and len(sector) >= min_sectors:
                label[part] = k
                k += 1
    return label, k


def _chain_segments(section):
    """Segments of a section's loops and open chains (those at least 2 % as long as the longest),
    and whether each one's chain winds counter-clockwise about the origin (the sense of a whole
    chain, not of a noisy segment)."""
    chains = [np.vstack([c, c[:1]]) for c in section.loops] + [c for c in section.open_chains if len(c) > 1]
    if not chains:
        return np.zeros((0, 2, 2)), np.zeros(0, bool)
    # A plane grazing a noisy level surface leaves islands a facet or two across: not walls.
    length = np.array([float(np.hypot(*np.diff(c, axis=0).T).sum()) for c in chains])
    chains = [c for c, n in zip(chains, length) if n >= 0.02 * length.max()]
    counts = np.array([len(c) - 1 for c in chains])
    pts = np.concatenate(chains)
    ends = np.cumsum([len(c) for c in chains])
    start = np.ones(len(pts), bool)
    start[ends - 1] = False  # the last point of a chain starts no segment
    a = pts[start]
    b = pts[np.flatnonzero(start) + 1]
    chain = np.repeat(np.arange(len(chains)), counts)
    sweep = np.bincount(chain, a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0], len(chains))
    return np.stack([a, b], axis=1), (sweep > 0)[chain]


def _clear_heights(local: np.ndarray, heights: np.ndarray, span: float) -> np.ndarray:
    """Move each height off level surfaces: a plane grazing a noisy floor cuts it into a litter of
    small loops. A height is clear when the facets facing within 45 degrees of up or down that it
    crosses hold under 0.1 % of the area, or under three times what a typical height crosses (a
    plate's wall is level-ish everywhere; its floor is the peak); an unclear one moves to the nearest
    clear height within 1/32 of the span (steps of 1/400), else stays."""
    cr = np.cross(local[:, 1] - local[:, 0], local[:, 2] - local[:, 0])
    dbl = np.sqrt(np.einsum("ij,ij->i", cr, cr))
    flat = np.abs(cr[:, 2]) > np.cos(np.radians(45)) * dbl
    if not flat.any():
        return heights
    z = local[flat][..., 2]
    zl, zh, w = z.min(axis=1), z.max(axis=1), dbl[flat]
    ol, oh = np.argsort(zl), np.argsort(zh)
    cl, ch = np.concatenate([[0.0], np.cumsum(w[ol])]), np.concatenate([[0.0], np.cumsum(w[oh])])
    zl, zh = zl[ol], zh[oh]

    def crossing(h):  # area of level facets with zl <= h <= zh
        return cl[np.searchsorted(zl, h, side="right")] - ch[np.searchsorted(zh, h, side="left")]

    grid = heights.min() + (heights.max() - heights.min()) * np.linspace(0.0, 1.0, 97)
    limit = max(1e-3 * float(dbl.sum()), 3.0 * float(np.median(crossing(grid))))
    offsets = span / 400 * np.concatenate([[0], np.repeat(np.arange(1, 13), 2) * np.tile([1, -1], 12)])
    out = heights.copy()
    for i, h in enumerate(heights):  # 16 planes, 25 tries each at most
        ok = np.flatnonzero(crossing(h + offsets) <= limit)
        if len(ok):
            out[i] = h + offsets[ok[0]]
    return out


def _section_fits(t: np.ndarray, point: np.ndarray, direction: np.ndarray, n_planes: int, min_sectors: int):
    """Concentric circles fitted to horizontal sections in the frame of an axis guess (see `circle_pass`):
    the frame's rotation, its height range, and per usable plane (height, centre x, centre y, weight
    kept, points, weights, wall labels, walls)."""
    R = rotation_to_z(direction)
    local = np.einsum("...j,ij->...i", t - point, R)
    z = local[..., 2]
    z0, z1 = float(z.min()), float(z.max())
    if not z1 > z0:
        return R, z0, z1, []
    heights = _clear_heights(local, z0 + (z1 - z0) * np.linspace(0.1, 0.9, n_planes), z1 - z0)
    layers = slice_layers(Mesh(local), heights=heights, max_gap=0.0)
    fits = []
    for h, s in zip(heights, layers):  # over planes
        seg, ccw = _chain_segments(s)
        if len(seg) < 4:
            continue
        # Simpson's rule along each segment: its ends and middle, weights 1/6, 4/6, 1/6 of its length,
        # so a long chord (a box's side) counts for the radii along it, not only at its corners.
        d = np.tile(seg[:, 1] - seg[:, 0], (3, 1))
        p = np.concatenate([seg[:, 0], seg.mean(axis=1), seg[:, 1]])
        length = np.hypot(d[:, 0], d[:, 1])
        w = length * np.repeat([1 / 6, 4 / 6, 1 / 6], len(seg))
        label, k = _rings(p, np.tile(ccw, 3), w, np.zeros(2), min_sectors)
        keep = label >= 0
        if k == 0 or keep.sum() < 3 + k:
            continue
        p, w, label = p[keep], w[keep], label[keep]
        # Concentric circles: x^2 + y^2 = 2 cx x + 2 cy y + g_k, linear in (cx, cy, g_k).
        A = np.zeros((len(p), 2 + k))
        A[:, 0], A[:, 1] = 2 * p[:, 0], 2 * p[:, 1]
        A[np.arange(len(p)), 2 + label] = 1.0
        b = (p ** 2).sum(axis=1)
        wk = w
        for _ in range(3):  # reweighted: a spout's bump on the outline loses its say
            sw = np.sqrt(wk)
            sol = np.linalg.lstsq(A * sw[:, None], b * sw, rcond=None)[0]
            radius = np.sqrt(np.maximum(sol[2:] + sol[0] ** 2 + sol[1] ** 2, 0.0))
            e = np.hypot(p[:, 0] - sol[0], p[:, 1] - sol[1]) - radius[label]
            wk = tukey_weights(e, w, 1e-9 * float(radius.mean()) + 1e-300)
        fits.append((h, sol[0], sol[1], wk.sum(), p, w, label, k, wk))
    return R, z0, z1, fits


def circle_pass(t: np.ndarray, point, direction, n_planes: int = 16, min_sectors: int = 12,
                shape: bool = False, fixed: bool = False):
    """Fit concentric circles to horizontal sections in the frame of an axis guess.

    16 sections from 10 % to 90 % of the height; in each, the chains are
    told apart by their winding about the axis (outer walls run
    counter-clockwise, inner walls clockwise: the sense of a whole chain, so
    noise cannot flip it), grouped into walls by radial gaps, and fitted with
    one centre and a radius per wall.

    Parameters
    ----------
    t : (n, 3, 3) ndarray
    point, direction : (3,) array_like
        The axis guess.
    n_planes : int
    min_sectors : int
        Sectors of 10 degrees a wall must cover (12 for a whole vessel; a sherd's arcs cover fewer).
    shape : bool
        Also return the shape residual and the mean radius.
    fixed : bool
        Measure the residuals about the guess itself (returned as the line) instead of
        about the line through the fitted centres.

    Returns
    -------
    tuple or None
        The line through the fitted centres (point, direction, in input
        coordinates) and (RMS radial residual about that line, the same
        relative to the mean radius, median relative deviation; with
        `shape`, then the RMS of the radial deviations averaged over sectors
        of 10 degrees of each wall, the shape's own departure from circles
        with the noise averaged out and the points the biweight dropped (a
        handle's root) left out, and the mean radius), or None when no
        section has a usable wall.

    See Also
    --------
    refine_axis : repeats it.

    Examples
    --------
    >>> from slicelab.samples import pot
    >>> p, d, (rms, rel, med, shape, r) = circle_pass(pot(40, 48).triangles, [0, 0, 0], [0, 0, 1], shape=True)
    >>> bool(rms < 0.2), bool(shape < 0.01), round(r)
    (True, True, 54)
    """
    point = np.asarray(point, dtype=np.float64)
    direction = np.asarray(direction, dtype=np.float64)
    R, z0, z1, fits = _section_fits(t, point, direction, n_planes, min_sectors)
    if len(fits) < 2:
        return None
    h, cx, cy, W = (np.array([f[i] for f in fits]) for i in range(4))
    Wk = W
    x0 = kx = y0 = ky = 0.0
    for _ in range(0 if fixed else 3):  # reweighted over planes too: a height through a handle may still stray
        G = np.stack([np.ones_like(h), h], axis=1) * np.sqrt(Wk)[:, None]
        (x0, kx), (y0, ky) = (np.linalg.lstsq(G, c * np.sqrt(Wk), rcond=None)[0] for c in (cx, cy))
        Wk = tukey_weights(np.hypot(cx - (x0 + kx * h), cy - (y0 + ky * h)), W, 1e-9 * (z1 - z0))
        if not Wk.sum() > 0:
            Wk = W
            break
    # Residual of the revolution model: radii about the fitted line, one radius per wall.
    errors, weights, rsum = [], [], 0.0
    shape_sq, shape_w = 0.0, 0.0
    for (hj, _, _, _, p, w, label, k, wk) in fits:  # over planes
        dx, dy = p[:, 0] - (x0 + kx * hj), p[:, 1] - (y0 + ky * hj)
        r = np.hypot(dx, dy)
        radius = np.bincount(label, wk * r, k) / np.maximum(np.bincount(label, wk, k), 1e-300)
        err = r - radius[label]
        errors.append(err)
        weights.append(w)
        rsum += float((w * radius[label]).sum())
        if shape:  # the deviation averaged per wall and sector of 10 degrees, outliers (a handle's root) out
            sector = label * 36 + (np.floor((np.arctan2(dy, dx) + np.pi) / (2 * np.pi) * 36).astype(np.int64) % 36)
            sw = np.bincount(sector, wk, 36 * k)
            mean = np.bincount(sector, wk * err, 36 * k) / np.maximum(sw, 1e-300)
            shape_sq += float((sw * mean * mean).sum())
            shape_w += float(sw.sum())
    e, w = np.abs(np.concatenate(errors)), np.concatenate(weights)
    rms = math.sqrt(float((w * e * e).sum() / w.sum()))
    mean_r = rsum / w.sum()
    # The median deviation judges between axes: a spout or a handle moves the RMS, not the median.
    o = np.argsort(e)
    median = float(e[o][np.searchsorted(np.cumsum(w[o]), 0.5 * w.sum())])
    new_dir = R.T @ np.array([kx, ky, 1.0])
    new_dir /= np.linalg.norm(new_dir)
    res = (rms, rms / mean_r, median / mean_r)
    if shape:
        res = res + (math.sqrt(shape_sq / max(shape_w, 1e-300)), mean_r)
    return point + R.T @ np.array([x0, y0, 0.0]), new_dir, res


def refine_axis(triangles: np.ndarray, point, direction, iterations: int = 6):
    """Repeat concentric-circle fits from an axis guess; keep the axis with the smallest residual seen.

    Each pass cuts 16 horizontal sections in the frame of the current axis
    (from 10 % to 90 % of its height), fits each with concentric circles
    (one centre, a radius per wall; linear, as in Kåsa's fit [1]_), reweighted
    with Tukey's biweight [2]_, and takes the line through the centres as the
    next axis. On a true body of revolution every pass improves and the
    passes converge; on a teapot (spout, handle) they can wander, and the
    best one is kept: the one with the smallest median relative deviation.

    Parameters
    ----------
    triangles : (n, 3, 3) ndarray
    point : (3,) array_like
        A point of the guessed axis.
    direction : (3,) array_like
        Unit direction of the guessed axis.
    iterations : int, default 6
        Most passes.

    Returns
    -------
    point : (3,) ndarray
        A point of the refined axis.
    direction : (3,) ndarray
        Its unit direction, in the sense of the guess.
    residuals : tuple of float or None
        RMS radial distance (mm) of the sections from circles about the axis,
        the same relative to the mean radius, and the median relative
        deviation; None when no section had a usable wall (the guess is
        returned).

    See Also
    --------
    normal_lines_axis, principal_axis : starting guesses.
    slicelab.artefacts.align

    References
    ----------
    .. [1] I. Kåsa, "A circle fitting procedure and its error analysis", *IEEE
       Transactions on Instrumentation and Measurement* IM-25(1), 8-14, 1976.
    .. [2] A. E. Beaton and J. W. Tukey, "The fitting of power series, meaning
       polynomials, illustrated on band-spectroscopic data", *Technometrics*
       16(2), 147-185, 1974.

    Examples
    --------
    >>> from slicelab.samples import pot
    >>> tilt = np.array([np.sin(0.05), 0.0, np.cos(0.05)])  # 2.9 degrees off, 1 mm aside
    >>> point, direction, (rms, rel, median) = refine_axis(pot(40, 48).triangles, [1.0, 0.0, 0.0], tilt)
    >>> bool(np.degrees(np.arccos(direction[2])) < 0.2), bool(rel < 1e-3)
    (True, True)
    """
    t = triangles
    best = (point, direction, None)
    for _ in range(iterations):  # a few fixed-point passes
        fit = circle_pass(t, point, direction)
        if fit is None:
            break
        new_point, new_dir, res = fit
        if new_dir @ direction < 0:
            new_dir = -new_dir
        turn = math.acos(min(1.0, abs(float(new_dir @ direction))))
        point, direction = new_point, new_dir
        if best[2] is None or res[2] <= 1.02 * best[2][2]:  # ties go to the later, more converged pass
            best = (point, direction, res)
        elif res[2] > 1.5 * best[2][2]:
            break  # wandering off
        if turn < 1e-6:
            break
    return best


