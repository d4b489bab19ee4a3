"""Where each layer's loops start: an object-wide pass over the sections, before any layer is planned.

A perimeter loop starts and ends at its seam, and the seam shows on the
printed surface as a line of small blobs. With aligned seams (the default,
PrusaSlicer's ``seam_position = aligned``) the seams of consecutive layers
sit one over the other, so that line is straight and, where the outline has
a concave corner, hidden in it. `seam_targets` finds, layer by layer up the
whole part, a seam point on every loop of the section:

- a loop that continues one of the layer below (a seam of that layer lies
  within `reach` of it) takes its vertex nearest that seam, or, where a
  concave corner lies within `snap` of that vertex, the corner;
- a loop that starts (the first layer, an island or a hole that appears)
  takes its sharpest concave corner, or, with none, its rearmost vertex.

With random seams (``seam_position = random``) `random_targets` draws each
loop's seam at random along its length instead, seeded by the layer's number.

The planner passes each layer its targets (`plan_layer`'s `seam`): each
perimeter loop then starts at its vertex nearest them. As the pass runs over
the sections of the whole part before the layers are planned, in any order
and by any number of workers, nothing of the planning shows in the seams.

References
----------
.. [1] PrusaSlicer, ``src/libslic3r/GCode/SeamPlacer.cpp``: seams aligned along the object,
   candidates at concave corners preferred.

See Also
--------
slicelab.printing.steps.order.order_step : each loop started at its seam.
"""
from __future__ import annotations

import numpy as np

__all__ = ["seam_targets", "random_targets", "concave_corners", "SNAP", "REACH"]

#: A concave corner within this distance (mm) of the seam carried up takes the seam.
SNAP = 1.0
#: A seam of the layer below farther than this (mm) from a loop does not continue on it.
REACH = 3.0
#: A corner counts as concave when the outline turns into the material by more than this (degrees).
CONCAVE = 30.0


def concave_corners(ring: np.ndarray, threshold: float = CONCAVE) -> tuple[np.ndarray, np.ndarray]:
    """Indices of a ring's concave corners (material on the left: a right turn) sharper than
    `threshold` degrees, and how sharp each vertex turns (degrees, positive where concave).

    Examples
    --------
    >>> L = np.array([[0, 0], [4, 0], [4, 2], [2, 2], [2, 4], [0, 4]], float)   # an L, counter-clockwise
    >>> idx, turn = concave_corners(L)
    >>> idx.tolist(), np.round(turn[idx], 6).tolist()
    ([3], [90.0])
    """
    r = np.asarray(ring, np.float64)
    a = r - np.roll(r, 1, axis=0)
    b = np.roll(r, -1, axis=0) - r
    cross = a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]
    dot = np.einsum("ij,ij->i", a, b)
    turn = -np.degrees(np.arctan2(cross, dot))  # a right turn goes into the material: concave
    return np.flatnonzero(turn > threshold), turn


def _start(ring: np.ndarray) -> np.ndarray:
    """The seam of a loop that starts: its sharpest concave corner, else its rearmost (then leftmost) vertex."""
    idx, turn = concave_corners(ring)
    if len(idx):
        return ring[idx[np.argmax(turn[idx])]]
    back = np.flatnonzero(ring[:, 1] >= ring[:, 1].max() - 1e-9)
    return ring[back[np.argmin(ring[back, 0])]]


def _carried(ring: np.ndarray, below: np.ndarray, reach: float, snap: float) -> np.ndarray | None:
    """The seam of a loop that continues a seam of the layer below (None if none is within `reach`)."""
    d = np.hypot(*(ring[:, None, :] - below[None, :, :]).transpose(2, 0, 1))  # (vertices, seams below)
    near = d.min(axis=1)
    k = int(np.argmin(near))
    if near[k] > reach:
        return None
    idx, turn = concave_corners(ring)
    if len(idx):  # a concave corner near the seam hides it
        gap = np.hypot(*(ring[idx] - ring[k]).T)
        close = gap <= snap
        if close.any():
            return ring[idx[close][np.argmin(gap[close])]]
    return ring[k]


def seam_targets(sections, *, reach: float = REACH, snap: float = SNAP) -> list:
    """The seam points of every layer, bottom up: for each section, an (m, 2) array, a point per loop
    (None for an empty section).

    Parameters
    ----------
    sections : sequence of Section
        The layers, bottom to top.
    reach : float
        How far (mm) a seam of the layer below may be from a loop and still continue on it.
    snap : float
        How far (mm) from the seam carried up a concave corner may lie and take it.

    Returns
    -------
    list of (m, 2) ndarray or None

    Examples
    --------
    >>> from types import SimpleNamespace
    >>> L = np.array([[0, 0], [4, 0], [4, 2], [2, 2], [2, 4], [0, 4]], float)
    >>> layers = [SimpleNamespace(loops=[L]), SimpleNamespace(loops=[L + 0.01]), SimpleNamespace(loops=[L + [20, 0]])]
    >>> [t.tolist() for t in seam_targets(layers)]   # in the L's concave corner, held there; a new island
    [[[2.0, 2.0]], [[2.01, 2.01]], [[22.0, 2.0]]]
    """
    out, below = [], None
    for sec in sections:  # over layers, bottom up: each continues the one below
        rings = [np.asarray(r, np.float64).reshape(-1, 2) for r in getattr(sec, "loops", []) if len(r) >= 3]
        if not rings:
            out.append(None)
            below = None
            continue
        pts = []
        for ring in rings:  # over the section's loops, a few
            p = _carried(ring, below, reach, snap) if below is not None else None
            pts.append(_start(ring) if p is None else p)
        below = np.array(pts)
        out.append(below)
    return out


def random_targets(sections, *, seed: int = 0) -> list:
    """A seam point on every loop of every layer, drawn at random along the loop's length
    (PrusaSlicer's ``seam_position = random``): the blobs of the seams are spread over the
    surface instead of lined up. The draw is seeded by the layer's number, so every run, in any
    order and by any number of workers, gives the same seams.

    Parameters
    ----------
    sections : sequence of Section
        The layers, bottom to top.
    seed : int
        Another seed gives other seams.

    Returns
    -------
    list of (m, 2) ndarray or None
        As `seam_targets`: a point per loop (on the loop), None for an empty section.

    Examples
    --------
    >>> from types import SimpleNamespace
    >>> sq = np.array([[0, 0], [4, 0], [4, 4], [0, 4]], float)
    >>> t = random_targets([SimpleNamespace(loops=[sq])] * 3)
    >>> [p.shape for p in t], len({tuple(p[0]) for p in t})     # one point a layer, each elsewhere
    ([(1, 2), (1, 2), (1, 2)], 3)
    >>> all(np.isclose(np.abs(p[0] - 2).max(), 2) for p in t)  # on the square's edges
    True
    """
    out = []
    for k, sec in enumerate(sections):  # over layers: each its own draw
        rings = [np.asarray(r, np.float64).reshape(-1, 2) for r in getattr(sec, "loops", []) if len(r) >= 3]
        if not rings:
            out.append(None)
            continue
        u = np.random.default_rng([seed, k]).random(len(rings))
        pts = []
        for ring, f in zip(rings, u):  # over the section's loops, a few
            edges = np.roll(ring, -1, axis=0) - ring
            cum = np.concatenate(([0.0], np.cumsum(np.hypot(*edges.T))))
            at = f * cum[-1]
            e = min(int(np.searchsorted(cum, at, side="right")) - 1, len(ring) - 1)
            t = (at - cum[e]) / max(cum[e + 1] - cum[e], 1e-300)
            pts.append(ring[e] + t * edges[e])
        out.append(np.array(pts))
    return out
