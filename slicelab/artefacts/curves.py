"""Plain curve tools of the (r, z) half-plane, beneath every other artefacts module.

`clip_ring` clips a closed ring to a half-plane (Sutherland-Hodgman), `resample`
spaces points evenly along a polyline with their arc-length weights, and
`UP_COSINE` says when an edge faces up. They take and return arrays only, so
that the sections, outlines, measurements and drawings can all use them
without importing one another.

See Also
--------
slicelab.artefacts.measure : the measurements built on them.
"""
from __future__ import annotations

import math

import numpy as np

__all__ = ["clip_ring", "resample", "UP_COSINE"]

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
