"""The order step: a layer's paths in print order, island by island, each loop from its seam.

Islands are printed nearest first: the outer perimeter, then the inner ones
level by level (by default the innermost first and the outer one last, so it
is laid against material already there), gap fill, then filling. Each loop
starts at its seam (`SEAMS`), open paths are entered from their nearer end,
which keeps travel short.

See Also
--------
slicelab.printing.pipeline.plan_layer : the steps of a layer in order.
"""
from __future__ import annotations

import numpy as np

from ...geometry.polygons import points_in_ring, signed_area
from ..roles import ISLAND_ROLES
from ..seams import SNAP, concave_corners

__all__ = ["SEAMS", "order_step"]

#: Where a loop starts (its seam): the vertex nearest the nozzle, the rearmost (largest y), the
#: one nearest the seam of the layer below, or a point drawn at random (for the last two, the
#: layer's `order_step` `seam_point`, found by `slicelab.printing.seams`; rearmost without one).
SEAMS = ("nearest", "rear", "aligned", "random")


def _closed_from(ring: np.ndarray, pos: np.ndarray, seam: str = "nearest", seam_point=None) -> np.ndarray:
    """The ring as a closed polyline starting at its seam vertex (`SEAMS`)."""
    if seam in ("aligned", "random") and seam_point is not None:
        ring, k = _with_seam(ring, np.asarray(seam_point, np.float64).reshape(-1, 2))
    elif seam in ("rear", "aligned", "random"):
        back = np.flatnonzero(ring[:, 1] >= ring[:, 1].max() - 1e-9)
        k = int(back[np.argmin(ring[back, 0])])  # the rearmost, then leftmost
    else:
        k = int(np.argmin(np.hypot(*(ring - pos).T)))
    return np.concatenate((ring[k:], ring[:k + 1]))


def _with_seam(ring: np.ndarray, targets: np.ndarray) -> tuple[np.ndarray, int]:
    """The ring with a vertex at its point nearest any of the seam points (one per loop of the
    section, `slicelab.printing.seams.seam_targets`), and that vertex's index: on an edge, not at
    the nearest vertex, so that seams a vertex's spacing apart along a smooth wall do not jog;
    or the ring's concave corner within `slicelab.printing.seams.SNAP` of that point.

    Examples
    --------
    >>> sq = np.array([[0, 0], [4, 0], [4, 4], [0, 4]], float)
    >>> r, k = _with_seam(sq, np.array([[2.0, 5.0]]))
    >>> r[k].tolist(), len(r)
    ([2.0, 4.0], 5)
    """
    a = ring
    b = np.roll(ring, -1, axis=0)
    ab = b - a
    l2 = np.maximum(np.einsum("ij,ij->i", ab, ab), 1e-300)
    # Each target's nearest point on each edge: (targets, edges).
    t = np.clip(np.einsum("tej,ej->te", targets[:, None, :] - a[None, :, :], ab) / l2, 0.0, 1.0)
    foot = a[None, :, :] + t[..., None] * ab[None, :, :]
    d = np.hypot(*(foot - targets[:, None, :]).transpose(2, 0, 1))
    i, e = np.unravel_index(int(np.argmin(d)), d.shape)
    p, s = foot[i, e], t[i, e]
    # A concave corner of this loop near that point takes the seam (the section's corner the seam
    # sits in is not this offset loop's: the nearest point to it lies beside the loop's corner).
    corners, _ = concave_corners(ring)
    if len(corners):
        gap = np.hypot(*(ring[corners] - p).T)
        if gap.min() <= SNAP:
            return ring, int(corners[np.argmin(gap)])
    # Near a vertex (a thousandth of a millimetre), that vertex: no sliver of an edge.
    if s * np.sqrt(l2[e]) <= 1e-3:
        return ring, int(e)
    if (1 - s) * np.sqrt(l2[e]) <= 1e-3:
        return ring, int((e + 1) % len(ring))
    return np.insert(ring, e + 1, p, axis=0), int(e + 1)


def _island_of(points: np.ndarray, exteriors: list, areas: np.ndarray) -> np.ndarray:
    """Index of the smallest exterior containing each point (-1 if none)."""
    out = np.full(len(points), -1, np.int64)
    best = np.full(len(points), np.inf)
    if len(points) == 0:
        return out
    for k, ext in enumerate(exteriors):  # over islands
        inside = points_in_ring(points, ext)
        sel = inside & (areas[k] < best)
        out[sel], best[sel] = k, areas[k]
    return out


def _islands(section, per, fills) -> tuple:
    """The islands of a layer and what each holds: its outer loop (level 0 of the walls), its inner
    loops and holes' walls, its gap fill and its filling (each by index), grouped by the smallest
    outer loop round each; a path no loop holds is an island of its own."""
    gap_fill, paths_f = fills.gap_fill, fills.paths
    # Islands: the outer rings of the first perimeter (or the section's own polygons).
    level0 = per.rings[0] if per.rings else []
    exteriors = [p.exterior for p in level0] if level0 else [p.exterior for p in section.polygons]
    areas = np.array([abs(signed_area(e)) for e in exteriors])
    loops_internal = []  # (level, ring, kind): inner perimeters, and the walls of holes at level 0
    for k, polys in enumerate(per.rings):
        for p in polys:
            if k > 0:
                loops_internal.append((k, p.exterior, "internal"))
            loops_internal += [(k, h, "hole" if k == 0 else "internal") for h in p.holes]
    groups: dict[int, dict[str, list]] = {}

    def put(island, role, item):
        groups.setdefault(int(island), {r: [] for r in ISLAND_ROLES})[role].append(item)

    if level0:
        for i in range(len(level0)):
            put(i, "external", i)
    rep = lambda items: np.array([x[0] for x in items]).reshape(-1, 2)  # noqa: E731
    owner = _island_of(rep([r for _, r, _ in loops_internal]), exteriors, areas)
    for j, o in enumerate(owner):
        put(o, "internal", j)
    loose = -1
    owner = _island_of(rep(gap_fill), exteriors, areas)
    for j, o in enumerate(owner):
        if o < 0:  # a thin wall with no perimeter: an island of its own
            o, loose = loose, loose - 1
        put(o, "gap_fill", j)
    owner = _island_of(rep(paths_f), exteriors, areas)
    for j, o in enumerate(owner):
        if o < 0:
            o, loose = loose, loose - 1
        put(o, "filling", j)
    return level0, loops_internal, groups


def order_step(section, per, fills, *, line_width: float, seam: str = "nearest", seam_point=None,
               external_first: bool = False, start=None) -> tuple:
    """A layer's rows (kind, path, width) in print order, and the travel between them (mm).

    Parameters
    ----------
    section : Section
    per : Perimeters
        The walls: rings by level.
    fills : Fills
        The filling and gap fill (`slicelab.printing.steps.filling.fill_step`).
    line_width : float
    seam : {"nearest", "rear", "aligned", "random"}
        Where each perimeter loop starts (`SEAMS`).
    seam_point : (2,) or (m, 2) array_like, optional
        For ``seam="aligned"`` or ``"random"``: each loop starts at its point nearest these points
        (the layer's seam points, `slicelab.printing.seams.seam_targets` or `random_targets`).
    external_first : bool
        Print each island's outer perimeter (and its holes' walls) before the inner ones.
    start : (2,) array_like, optional
        Nozzle position before the layer (default: the layer's lower-left corner).

    Returns
    -------
    kinds, paths, widths : list
    travel : float
    """
    w = float(line_width)
    if seam not in SEAMS:
        raise ValueError(f"seam must be one of {', '.join(SEAMS)}, got {seam!r}")
    gap_fill, gap_widths, paths_f, kinds = fills.gap_fill, fills.gap_widths, fills.paths, fills.kinds
    level0, loops_internal, groups = _islands(section, per, fills)

    lo = section.bounds()[0] if len(section.segments) else np.zeros(2)
    pos = np.asarray(lo if start is None else start, np.float64)
    out_kind, out_paths, out_w = [], [], []  # the table's rows, in print order
    travel = 0.0
    first = True

    def go(path):
        nonlocal pos, travel, first
        if not first:
            travel += float(np.hypot(*(path[0] - pos)))
        first = False
        pos = path[-1]

    def entry_points(g):
        pts = []
        for role in ISLAND_ROLES:
            for j in g[role]:
                if role == "external":
                    pts.append(level0[j].exterior)
                elif role == "internal":
                    pts.append(loops_internal[j][1])
                elif role == "gap_fill":
                    pts.append(gap_fill[j][[0, -1]])
                else:
                    pts.append(paths_f[j][[0, -1]])
            if pts:
                break
        return np.concatenate(pts)

    def open_order(cands, paths_of, loops):
        """Yield the paths in print order, each with how to print it: from its start, from its
        end (reversed), or, for a loop (when `loops`), from its vertex nearest the nozzle. The
        next is the nearest to the nozzle (the first in `cands` on ties, its start before its end)."""
        paths = [paths_of(j) for j in cands]
        ring = np.array([loops and len(q) > 3 and np.array_equal(q[0], q[-1]) for q in paths], bool)
        ends = np.array([[q[0], q[-1]] for q in paths], np.float64).reshape(-1, 2, 2)
        alive = np.ones(len(paths), bool)
        while alive.any():  # over the paths: one vectorised distance per pick
            d = np.hypot(*(ends - pos).transpose(2, 0, 1))
            d[~alive] = np.inf
            for i in np.flatnonzero(ring & alive):  # loops (concentric filling), few
                d[i] = (float(np.min(np.hypot(*(paths[i][:-1] - pos).T))), np.inf)
            i, e = divmod(int(np.argmin(d)), 2)
            alive[i] = False
            yield cands[i], ("loop" if ring[i] else ("end" if e else "start"))

    remaining = dict(groups)
    while remaining:  # over islands, nearest first
        key = min(remaining, key=lambda g: float(np.min(np.hypot(*(entry_points(remaining[g]) - pos).T))))
        g = remaining.pop(key)
        # The island's loops: its outer perimeter, its holes' walls and the inner perimeters,
        # level by level (outer level first, or innermost first with the outer loop last).
        loops = [(0, level0[j].exterior, "external") for j in g["external"]]
        loops += [loops_internal[j] for j in g["internal"]]
        order = sorted(set(lv for lv, _, _ in loops), reverse=not external_first)
        for level in order:  # over perimeter levels, few
            same = [lp for lp in loops if lp[0] == level]
            outer = [lp for lp in same if lp[2] == "external"]
            rest = [lp for lp in same if lp[2] != "external"]
            queue = outer + rest if external_first else rest
            while queue or (not external_first and outer):
                if not queue:
                    queue, outer = outer, []
                i = min(range(len(queue)), key=lambda i: float(np.min(np.hypot(*(queue[i][1] - pos).T))))
                lp = queue.pop(i)
                path = _closed_from(lp[1], pos, seam, seam_point)
                go(path)
                out_kind.append(lp[2]), out_paths.append(path), out_w.append(w)
        for role, source in (("gap_fill", gap_fill), ("filling", paths_f)):
            for j, how in open_order(list(g[role]), lambda j: source[j], role == "filling"):  # nearest first
                path = {"start": source[j], "end": source[j][::-1]}.get(how)
                path = _closed_from(source[j][:-1], pos) if path is None else path
                go(path)
                if role == "gap_fill":
                    out_kind.append("gap_fill"), out_paths.append(path)
                    out_w.append(gap_widths[j][::-1] if how == "end" else gap_widths[j])
                else:
                    out_kind.append(kinds[j]), out_paths.append(path), out_w.append(w)
    return out_kind, out_paths, out_w, travel
