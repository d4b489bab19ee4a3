"""Layers that repeat: the outline of a layer, compared with its neighbours', so that a prismatic stretch is planned once.

Most parts of ordinary printing are prismatic over most of their height: walls,
bosses and holes straight up, their layers the same outline, and a layer's
toolpaths the same as those two layers below (the infill turns by 90 degrees
every layer). The planner keeps the toolpaths of such a layer and reuses them
two layers up when everything they depend on is the same: the outline, the
outlines of every layer its skins and overhangs read (so it has neither), the
nozzle's start and the seam below. Sections of a wall made of triangles are
cut where the plane meets each facet's diagonal, at another place on every
layer: an outline is its loops with the vertices in line with their neighbours
left out, each from its lowest vertex. The toolpaths taken are those planning the
layer afresh gives, to a float's rounding: where the simplification of a ring
ties (a small round hole), a layer planned afresh may keep another vertex, as
good within the G-code resolution.

See Also
--------
slicelab.toolpath.planner.plan : reuses the toolpaths of repeating layers.
"""
from __future__ import annotations

import numpy as np

__all__ = ["outline_key", "same_outline", "same_point"]

#: Outlines within this distance (mm) of each other are the same: float rounding of the cut is
#: some 1e-14 mm on a part of a metre, a real step of the surface is not below a nanometre.
TOLERANCE = 1e-9


def outline_key(section) -> tuple | None:
    """A layer's outline: its loops without the vertices in line with their neighbours, each
    from its lowest (then leftmost) vertex, in the order of those vertices; None for a section
    with open chains (not compared).

    Examples
    --------
    >>> from types import SimpleNamespace
    >>> a = SimpleNamespace(open_chains=[], loops=[np.array([[0, 0], [2, 0], [2, 1], [2, 2], [0, 2]], float)])
    >>> b = SimpleNamespace(open_chains=[], loops=[np.array([[2, 2], [0, 2], [0, 0], [1, 0], [2, 0]], float)])
    >>> outline_key(a)[0].tolist()
    [[0.0, 0.0], [2.0, 0.0], [2.0, 2.0], [0.0, 2.0]]
    >>> same_outline(outline_key(a), outline_key(b))
    True
    """
    if len(section.open_chains):
        return None
    rings = []
    for loop in section.loops:  # over loops, a few
        r = np.asarray(loop, np.float64).reshape(-1, 2)
        if len(r) >= 3:
            prev, nxt = np.roll(r, 1, axis=0), np.roll(r, -1, axis=0)
            chord, off = nxt - prev, r - prev
            # The distance of each vertex from the chord of its neighbours (the chord's length
            # times it, to spare a division).
            twice = np.abs(off[:, 0] * chord[:, 1] - off[:, 1] * chord[:, 0])
            keep = twice > TOLERANCE * np.hypot(chord[:, 0], chord[:, 1])
            r = r[keep] if np.count_nonzero(keep) >= 3 else r
        k = int(np.lexsort((r[:, 0], r[:, 1]))[0])
        rings.append(np.roll(r, -k, axis=0))
    rings.sort(key=lambda r: (round(float(r[0, 1]), 6), round(float(r[0, 0]), 6), len(r)))
    return tuple(rings)


def same_outline(a, b) -> bool:
    """Whether two outlines (`outline_key`) are the same within `TOLERANCE` (None is like nothing)."""
    if a is None or b is None or len(a) != len(b):
        return False
    return all(p.shape == q.shape and bool(np.all(np.abs(p - q) <= TOLERANCE)) for p, q in zip(a, b))


def same_point(a, b) -> bool:
    """Whether two nozzle positions or seam points (None before any) are the same.

    Examples
    --------
    >>> same_point(None, None), same_point(np.array([1.0, 2.0]), np.array([1.0, 2.0])), same_point(None, (0, 0))
    (True, True, False)
    """
    if a is None or b is None:
        return a is None and b is None
    return bool(np.array_equal(np.asarray(a), np.asarray(b)))
