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
left out, each from its lowest vertex. An STL file holds float32 coordinates: its
walls lean by their rounding, and two layers of a prism differ by some
micrometres' thousandths, so outlines within the mesh's float32 rounding
(`slicelab.mesh.default_tolerance`: 8 units in the last place of its largest
coordinate, 6e-5 mm for a part 100 mm from the origin) are the same. The
toolpaths taken are those planning the layer afresh gives, to that rounding:
where the simplification of a ring ties (a small round hole), a layer planned
afresh may keep another vertex, as good within the G-code resolution.

See Also
--------
slicelab.printing.planner.plan : reuses the toolpaths of repeating layers.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["outline_size", "may_repeat", "outline_key", "same_outline", "same_point", "same_mask", "Repeats",
           "RunStart", "start_candidates", "run_starts"]


def outline_size(section) -> tuple[float, float]:
    """The area (mm^2) a section's segments enclose and their length (mm): two layers whose outlines
    are the same within a tolerance have these the same within it (`may_repeat`).

    Examples
    --------
    >>> from types import SimpleNamespace
    >>> sq = np.array([[0, 0], [2, 0], [2, 2], [0, 2]], float)
    >>> outline_size(SimpleNamespace(segments=np.stack([sq, np.roll(sq, -1, axis=0)], axis=1)))
    (4.0, 8.0)
    """
    seg = np.asarray(section.segments, np.float64).reshape(-1, 2, 2)
    if not len(seg):
        return 0.0, 0.0
    a, b = seg[:, 0], seg[:, 1]
    area = 0.5 * float(np.sum(a[:, 0] * b[:, 1] - b[:, 0] * a[:, 1]))  # the shoelace, segment by segment
    return area, float(np.hypot(*(b - a).T).sum())


def may_repeat(a: tuple, b: tuple, tolerance: float) -> bool:
    """Whether two layers' `outline_size` allow their outlines to be the same within `tolerance` mm
    (an outline moved by t changes the area by at most t times its length)."""
    return abs(a[0] - b[0]) <= 2 * tolerance * max(a[1], b[1]) + 1e-12


def outline_key(section, tolerance: float) -> tuple | None:
    """A layer's outline: its loops without the vertices within `tolerance` (mm) of the line
    through their neighbours, each from its lowest (then leftmost) vertex, in the order of those
    vertices; None for a section with open chains (not compared).

    Examples
    --------
    >>> from types import SimpleNamespace
    >>> a = SimpleNamespace(open_chains=[], loops=[np.array([[0, 0], [2, 0], [2, 1], [2, 2], [0, 2]], float)])
    >>> b = SimpleNamespace(open_chains=[], loops=[np.array([[2, 2], [0, 2], [0, 0], [1, 1e-7], [2, 0]], float)])
    >>> outline_key(a, 1e-6)[0].tolist()
    [[0.0, 0.0], [2.0, 0.0], [2.0, 2.0], [0.0, 2.0]]
    >>> same_outline(outline_key(a, 1e-6), outline_key(b, 1e-6), 1e-6), same_outline(outline_key(a, 1e-9),
    ...                                                                           outline_key(b, 1e-9), 1e-9)
    (True, False)
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
            keep = twice > tolerance * np.hypot(chord[:, 0], chord[:, 1])
            r = r[keep] if np.count_nonzero(keep) >= 3 else r
        # The lowest vertex, on a grid a hundred tolerances wide: two corners of a bottom edge whose
        # heights differ by rounding alone do not swap from one layer to the next.
        q = np.floor(r / (100 * tolerance)) if tolerance > 0 else r
        k = int(np.lexsort((q[:, 0], q[:, 1]))[0])
        rings.append(np.roll(r, -k, axis=0))
    rings.sort(key=lambda r: (round(float(r[0, 1]), 3), round(float(r[0, 0]), 3), len(r)))
    return tuple(rings)


def same_outline(a, b, tolerance: float) -> bool:
    """Whether two outlines (`outline_key`) are the same within `tolerance` mm (None is like nothing).

    Rings of as many vertices are compared vertex by vertex. A vertex nearly in line with its
    neighbours may be kept on one layer and left out on the next: rings of a few hundred
    vertices whose counts differ are compared as curves, every vertex of each within twice the
    tolerance of the other's edges (its distance from the chord is below the tolerance on one
    layer, and the layers differ by less than it).

    Examples
    --------
    >>> sq = np.array([[0, 0], [2, 0], [2, 2], [0, 2]], float)
    >>> bent = np.array([[0, 0], [2, 0], [2, 1], [2, 2], [0, 2]]) + [[0, 0], [0, 0], [1.5e-6, 0], [0, 0], [0, 0]]
    >>> same_outline((sq,), (bent,), 1e-6), same_outline((sq,), (bent,), 1e-7)
    (True, False)
    """
    if a is None or b is None or len(a) != len(b):
        return False
    for p, q in zip(a, b):  # over rings, a few
        if p.shape == q.shape:
            if not np.all(np.abs(p - q) <= tolerance):
                return False
        elif len(p) * len(q) > 250_000 or not (_within(p, q, 2 * tolerance) and _within(q, p, 2 * tolerance)):
            return False
    return True


def _within(points: np.ndarray, ring: np.ndarray, tolerance: float) -> bool:
    """Whether every point lies within `tolerance` of the ring's edges (implicitly closed)."""
    a, b = ring, np.roll(ring, -1, axis=0)
    d = b - a
    length2 = np.maximum(np.einsum("ij,ij->i", d, d), 1e-300)
    rel = points[:, None, :] - a[None, :, :]  # (points, edges, 2)
    t = np.clip(np.einsum("pej,ej->pe", rel, d) / length2, 0.0, 1.0)
    gap = rel - t[..., None] * d[None, :, :]
    return bool(np.all(np.einsum("pej,pej->pe", gap, gap).min(axis=1) <= tolerance * tolerance))


def same_point(a, b, tolerance: float = 0.0) -> bool:
    """Whether two nozzle positions or seam points (None before any) are the same within `tolerance` mm
    (the layers they end differ by as much as their outlines).

    Examples
    --------
    >>> same_point(None, None), same_point(np.array([1.0, 2.0]), np.array([1.0, 2.0])), same_point(None, (0, 0))
    (True, True, False)
    >>> same_point((1.0, 2.0), (1.0, 2.0 + 1e-7), 1e-6)
    True
    """
    if a is None or b is None:
        return a is None and b is None
    a, b = np.asarray(a, np.float64), np.asarray(b, np.float64)
    return a.shape == b.shape and bool(np.all(np.abs(a - b) <= tolerance))


def same_mask(a, b) -> bool:
    """Whether two masks (None, or `slicelab.printing.grid.masks` masks) hold the same pixels, laid out
    alike (the same window and blocks): two layers' skins compared.

    Examples
    --------
    >>> from slicelab.printing.grid.masks import GridMask
    >>> m = GridMask(np.eye(3, dtype=bool), 0, 0, 0.1)
    >>> same_mask(m, GridMask(np.eye(3, dtype=bool), 0, 0, 0.1)), same_mask(m, None), same_mask(None, None)
    (True, False, True)
    """
    if a is None or b is None:
        return a is None and b is None
    if type(a) is not type(b) or (a.row0, a.col0, a.pixel_size) != (b.row0, b.col0, b.pixel_size):
        return False
    if hasattr(a, "bits"):  # blocks along the boundary
        g, h = a.blocks, b.blocks
        return (g.size, g.row0, g.col0) == (h.size, h.row0, h.col0) and tuple(a.shape) == tuple(b.shape) and \
            np.array_equal(g.table, h.table) and np.array_equal(a.bits, b.bits)
    return np.array_equal(a.mask, b.mask)


class Repeats:
    """Which layers of a run of layers repeat, and the toolpaths they take (the planner's worker
    keeps one for each run of layers it plans).

    Parameters
    ----------
    sections : dict
        Layer index -> section: the layers planned and every layer their skins read.
    n : int
        Layers in the part.
    reach : (int, int)
        Layers below and above whose outlines a layer's skins and overhangs read (the bottom
        layers and one more, the top layers).
    tolerance : float
        mm (`slicelab.mesh.default_tolerance`).
    enabled : bool
        False where the toolpaths change with height (gyroid infill).

    Examples
    --------
    >>> from types import SimpleNamespace
    >>> sq = np.array([[0, 0], [2, 0], [2, 2], [0, 2]], float)
    >>> layer = SimpleNamespace(open_chains=[], loops=[sq], segments=np.stack([sq, np.roll(sq, -1, axis=0)], 1))
    >>> r = Repeats({k: layer for k in range(10)}, 10, (2, 1), 1e-9)
    >>> [r.steady(k) for k in range(10)]
    [False, False, True, True, True, True, True, True, True, False]
    >>> r.keep(3, None, None, (None, None), "paths of layer 3")
    >>> r.take(5, None, None), r.take(4, None, None), r.take(5, (0.0, 0.0), None), r.take(5, None, None, (None, None))
    ('paths of layer 3', None, None, 'paths of layer 3')
    """

    def __init__(self, sections: dict, n: int, reach: tuple, tolerance: float, enabled: bool = True):
        self.n, self.below, self.above = n, int(reach[0]), int(reach[1])
        self.tolerance = float(tolerance)
        # Outlines are compared only where the areas say they may be the same (a curved part's
        # layers never are).
        self.sections = sections
        self.size = size = {j: outline_size(sec) for j, sec in sections.items()} if enabled else {}
        maybe = {j for j in size if j - 1 in size and may_repeat(size[j], size[j - 1], self.tolerance)}
        self.keys = {j: outline_key(sections[j], self.tolerance) for j in sorted(maybe | {j - 1 for j in maybe})}
        self.same_below = {j: same_outline(self.keys[j], self.keys[j - 1], self.tolerance) for j in maybe}
        self.kept = {}  # parity -> (outline, start, seam below, skins, steady, what the layer made)

    def clear(self) -> None:
        """Forget the layers kept (a run of layers starts)."""
        self.kept.clear()

    def _outline(self, k: int, other: int):
        """Layer k's outline where layer `other` may have the same (their areas say so), else None."""
        if k not in self.keys:
            if k not in self.size or other not in self.size or \
                    not may_repeat(self.size[k], self.size[other], self.tolerance):
                return None
            self.keys[k] = outline_key(self.sections[k], self.tolerance)
        return self.keys[k]

    def steady(self, k: int) -> bool:
        """Whether layer k and every layer its skins and overhangs read (all in the part) have one
        outline: it has no skin, no overhang and no bridge."""
        lo, hi = k - self.below, k + self.above
        return k > 0 and lo >= 0 and hi < self.n and all(self.same_below.get(j, False) for j in range(lo + 1, hi + 1))

    def take(self, k: int, start, seam, skins: tuple | None = None):
        """What layer k - 2 made (`keep`), if layer k has its outline, starts where it did and has
        the same seam below (within the tolerance); else None.

        Without `skins`, before anything of layer k is made: only a steady layer (`steady`) takes
        what a steady layer made. With `skins` (masks, once layer k's are known), any layer whose
        skins are those of layer k - 2, pixel for pixel, takes what it made (a step within reach).
        """
        got = self.kept.get(k % 2)
        if got is None:
            return None
        key, at, below, masks, steady, value = got
        if skins is None:
            if not (steady and self.steady(k)):
                return None
            outline = self.keys[k]
        elif all(same_mask(a, b) for a, b in zip(masks, skins)):
            outline = self._outline(k, k - 2)
        else:
            return None
        t = self.tolerance
        ok = same_point(at, start, t) and same_point(below, seam, t) and same_outline(key, outline, t)
        return value if ok else None

    def keep(self, k: int, start, seam, skins: tuple, value) -> None:
        """Keep what layer k made from `start`, `seam` and `skins` for the layer two above (when its
        outline may be this one's)."""
        steady = self.steady(k)
        key = self.keys[k] if steady else self._outline(k, k + 2)
        if key is None:
            self.kept.pop(k % 2, None)
        else:
            self.kept[k % 2] = (key, start, seam, skins, steady, value)


@dataclass(frozen=True, eq=False)
class RunStart:
    """What the first layers of a run of steady layers make, for every run that starts alike.

    Attributes
    ----------
    layers : tuple
        Each layer's `slicelab.printing.pipeline.LayerResult`, as the planner makes it.
    pos : ndarray or None
        The nozzle's position after the last of them.
    kept : dict
        What `Repeats` keeps after them (the layers two above take from it).
    below_solid : mask or None
        The solid skin of the last of them.
    """

    layers: tuple
    pos: object
    kept: dict
    below_solid: object = None


def start_candidates(sections: dict, n: int, reach: tuple, tolerance: float, run: int, length: int,
                     size=None) -> list:
    """The run starts (multiples of `run` after the first) whose first `length` layers, and every
    layer their skins read, have the areas of the layers below them within `tolerance` mm: those
    whose outlines `run_starts` compares (a cheap test, areas alone). `size` (optional) holds
    each layer's `outline_size`, made here where needed if not given.

    Examples
    --------
    >>> from types import SimpleNamespace
    >>> sq = np.array([[0, 0], [2, 0], [2, 2], [0, 2]], float)
    >>> layer = SimpleNamespace(open_chains=[], loops=[sq], segments=np.stack([sq, np.roll(sq, -1, axis=0)], 1))
    >>> start_candidates({k: layer for k in range(50)}, 50, (4, 3), 1e-9, 20, 6)
    [20, 40]
    """
    below, above = int(reach[0]), int(reach[1])
    size = {} if size is None else {j: size[j] for j in sections}

    def alike_by_area(j):  # layer j and the one below may have one outline (their areas say so)
        for i in (j - 1, j):
            if i not in size:
                size[i] = outline_size(sections[i]) if i in sections else None
        return size[j - 1] is not None and size[j] is not None and may_repeat(size[j], size[j - 1], tolerance)

    return [k for k in range(run, n - length + 1, run)  # over run starts after the first
            if k - below >= 0 and k + length - 1 + above < n
            and all(alike_by_area(j) for j in range(k - below + 1, k + length + above))]


def run_starts(sections: dict, n: int, reach: tuple, tolerance: float, run: int, length: int,
               candidates=None) -> dict:
    """The runs of layers that start alike: run start k -> the run start k0 whose first `length`
    layers it repeats (k0 -> k0 for the first of them).

    A run of `run` layers starts with the nozzle afresh, so its first layers are planned anew
    even in a prismatic stretch, until their toolpaths repeat two layers apart. A run whose
    first `length` layers are steady (`Repeats.steady`: no skin, no overhang) and have the
    outlines of those of an earlier such run, within `tolerance` mm, makes what that run made:
    the planner makes those layers once (`RunStart`), however the runs are grouped. Only the
    `start_candidates` are compared (`candidates`, if already known), and only stretches that
    more than one run starts in count.

    Examples
    --------
    >>> from types import SimpleNamespace
    >>> sq = np.array([[0, 0], [2, 0], [2, 2], [0, 2]], float)
    >>> layer = SimpleNamespace(open_chains=[], loops=[sq], segments=np.stack([sq, np.roll(sq, -1, axis=0)], 1))
    >>> run_starts({k: layer for k in range(100)}, 100, (4, 3), 1e-9, 20, 6)
    {20: 20, 40: 20, 60: 20, 80: 20}
    """
    below, above = int(reach[0]), int(reach[1])
    if candidates is None:
        candidates = start_candidates(sections, n, reach, tolerance, run, length)
    near = {j for k in candidates for j in range(k - below, k + length + above)}
    r = Repeats({j: sections[j] for j in sorted(near)}, n, reach, tolerance)
    found, firsts = {}, []
    for k in candidates:
        if not all(r.steady(j) for j in range(k, k + length)):
            continue
        keys = [r.keys.get(j) for j in range(k, k + length)]
        for k0, keys0 in firsts:  # over earlier outlines, few
            if all(same_outline(a, b, r.tolerance) for a, b in zip(keys, keys0)):
                found[k] = k0
                break
        else:
            firsts.append((k, keys))
            found[k] = k
    return {k: k0 for k, k0 in found.items() if sum(1 for v in found.values() if v == k0) > 1}
