"""The axis of a sherd by trying every direction: where the projected normal lines meet best.

The line complex (`slicelab.artefacts.axis_lines.line_complex_axis`) weighs
a normal line's miss by its distance from the centroid, so on a sherd it
settles on a line through the sherd itself. Here every direction of a
hemisphere is tried instead: along the true axis the normal lines, projected,
all pass through one point (the axis seen end on), found by reweighted
linear least squares; the score is the trimmed mean of the squared sines of
the normals' angles to their meridian planes about it. The best valleys are
refined on a finer grid and handed to `slicelab.artefacts.fit_axis_lines`.
"""
from __future__ import annotations

import math

import numpy as np

from .axis_fit import rotation_to_z
from .axis_lines import SurfaceSample

__all__ = ["search_axis"]

_SEARCH_SEEDS = 5          # valleys of the direction search refined
_ALL_ROUND = 33            # sectors of 10 degrees (of 36) about a line that sees the surface all round


def _hemisphere(n: int) -> np.ndarray:
    """`n` nearly even unit vectors with z >= 0 (a Fibonacci lattice)."""
    k = np.arange(n) + 0.5
    z = 1.0 - k / n
    phi = np.pi * (1 + 5 ** 0.5) * k
    s = np.sqrt(1 - z * z)
    return np.column_stack([s * np.cos(phi), s * np.sin(phi), z])


def _score_directions(p: np.ndarray, n: np.ndarray, dirs: np.ndarray, keep: float):
    """For each direction: the centre where the projected normal lines meet best, and the trimmed
    mean of the squared sines of the normals' angles to their meridian planes about it."""
    helper = np.where(np.abs(dirs[:, :1]) < 0.9, np.array([[1.0, 0.0, 0.0]]), np.array([[0.0, 1.0, 0.0]]))
    u = np.cross(dirs, helper)
    u /= np.linalg.norm(u, axis=1)[:, None]
    v = np.cross(dirs, u)
    px, py = u @ p.T, v @ p.T            # (directions, points)
    nx, ny = u @ n.T, v @ n.T
    g = nx * py - ny * px                # F = g + ny cx - nx cy
    # Normals within 11 degrees of the direction (a base's underside seen end on) say nothing of where
    # the axis is, and their residuals, near zero whatever the centre, must not shrink the scale that
    # decides who else has a say.
    informative = nx * nx + ny * ny >= 0.04
    # First as the projected normal lines meeting (distances to them, not their moments: a break face,
    # its normal square to the meridian plane, must not outweigh a shallow wall whose normals are
    # nearly parallel to the axis), then reweighted towards the sines, Tukey on them.
    w = informative / (nx * nx + ny * ny + 0.05 ** 2)
    for it in range(10):  # algebraic, then towards least absolute sines, then Tukey on them
        a11, a12, a22 = (w * ny * ny).sum(1), -(w * nx * ny).sum(1), (w * nx * nx).sum(1)
        b1, b2 = -(w * g * ny).sum(1), (w * g * nx).sum(1)
        det = a11 * a22 - a12 * a12
        det = np.where(np.abs(det) > 1e-300, det, 1e-300)
        cx, cy = (a22 * b1 - a12 * b2) / det, (a11 * b2 - a12 * b1) / det
        F = g + ny * cx[:, None] - nx * cy[:, None]
        r2 = (px - cx[:, None]) ** 2 + (py - cy[:, None]) ** 2
        e = F / np.sqrt(np.maximum(r2, 1e-24))
        if it < 4:
            # Least absolute sines first (a quarter of the surface can be break faces, whose normals
            # miss the axis by tens of degrees: least squares would follow them, and Tukey from there
            # keeps them), then Tukey's biweight from where that lands.
            w = informative / np.maximum(np.abs(e), 1e-4) / np.maximum(r2, 1e-24)
            continue
        sigma = np.nanmedian(np.where(informative, np.abs(e), np.nan), axis=1)
        sigma = np.maximum(1.4826 * np.nan_to_num(sigma, nan=1.0), 1e-9)[:, None]
        u2 = (e / (4.685 * sigma)) ** 2
        w = np.where(u2 < 1, (1 - u2) ** 2, 0.0) * informative / np.maximum(r2, 1e-24)
    e2 = e * e
    m = max(1, int(keep * e2.shape[1]))
    score = np.partition(e2, m - 1, axis=1)[:, :m].mean(axis=1)
    centre = cx[:, None] * u + cy[:, None] * v
    # Sectors of 10 degrees about the centre that hold points: a line through the surface sees it
    # all round (along the mean normal of a flattish sherd every normal lies in a meridian plane).
    k = (np.floor(np.arctan2(py - cy[:, None], px - cx[:, None]) * (18 / np.pi)).astype(np.int64) + 18) % 36
    seen = np.zeros((len(dirs), 36), bool)
    seen[np.arange(len(dirs))[:, None], k] = True
    return score, centre, seen.sum(axis=1) >= _ALL_ROUND


def search_axis(sample: SurfaceSample, *, directions: int = 1500, points: int = 4000, keep: float = 0.7,
                seed: int = 0, candidates: bool = False, coarse: int = 1200):
    """The axis direction whose meridian planes hold the sample's normals best, by trying them all.

    For each of `directions` nearly even directions (scored on `coarse` of the
    sample's points, then 300 more within 5 degrees of each of the best five,
    scored on up to `points`), the normal lines are projected along it: about
    the true axis they all pass through one point, found by linear least
    squares; the score is the trimmed mean (best `keep` share) of the
    squared sines of the normals' angles to their meridian planes about
    that point. Needs no start and no full turn: it finds a sherd's axis,
    where the line complex (`line_complex_axis`) settles on a line through
    the sherd. Lines that see the surface all round (33 or more of 36
    sectors of 10 degrees) rank after those that do not: along a flattish
    sherd's mean normal every normal lies in a meridian plane too.

    Returns
    -------
    point : (3,) ndarray
    direction : (3,) ndarray
    score : float
        The trimmed mean square sine at the best direction.

    With ``candidates=True``, a list of such (point, direction, score), one
    per valley searched, best first (those seeing the surface all round last).

    See Also
    --------
    fit_axis_lines : refines it.

    Examples
    --------
    >>> from slicelab.samples import scan
    >>> from slicelab.artefacts import smoothed_normals
    >>> sherd, truth = scan("pot", spacing=2.0, sherd="rim", span=90.0)
    >>> point, d, score = search_axis(smoothed_normals(sherd.triangles))
    >>> bool(abs(d @ truth["axis"]) > np.cos(np.radians(5)))
    True
    """
    rng = np.random.default_rng(seed)
    idx = np.arange(len(sample.points))
    if len(idx) > points:
        idx = rng.choice(idx, size=points, replace=False, p=sample.weights / sample.weights.sum())
    origin = sample.points[idx].mean(axis=0)
    p, n = sample.points[idx] - origin, sample.normals[idx]

    def scored(dirs, m=None):  # the first m points (a random subset) or all
        pm, nm = p[:m], n[:m]
        parts = [_score_directions(pm, nm, dirs[k:k + 100], keep) for k in range(0, len(dirs), 100)]
        return tuple(np.concatenate([x[i] for x in parts]) for i in range(3))

    dirs = _hemisphere(directions)
    # The coarse grid on a subset: the cost follows what the mesh holds, up to `coarse` points.
    scores, centres, round_ = scored(dirs, coarse)
    # The best few coarse directions (each at least 6 degrees from a better one), each refined by
    # 300 directions within 5 degrees of it: a sherd's valley can be narrower than the coarse grid.
    # Lines that see the surface all round come last: for a whole vessel that is its axis, for a
    # sherd a line through it.
    seeds = []
    for i in np.lexsort((scores, round_)):  # best first; a handful kept
        if all(abs(float(dirs[i] @ dirs[j])) < math.cos(math.radians(6)) for j in seeds):
            seeds.append(i)
        if len(seeds) == _SEARCH_SEEDS:
            break
    local = _hemisphere(1200)
    local = np.vstack([[0.0, 0.0, 1.0], local[local[:, 2] >= math.cos(math.radians(5))][:299]])
    found = []
    for i in seeds:  # a handful of valleys
        fine = local @ rotation_to_z(dirs[i])
        sc, ce, ro = scored(fine)
        sc = np.where(ro == round_[i], sc, np.inf)  # the valley's own kind
        j = int(np.argmin(sc)) if np.isfinite(sc).any() else 0
        found.append((bool(round_[i]), float(sc[j]), fine[j], ce[j]))
    found.sort(key=lambda f: f[:2])
    if candidates:
        return [(origin + c, d, sc) for _, sc, d, c in found]
    _, best_score, best_dir, best_centre = found[0]
    return origin + best_centre, best_dir, best_score
