"""Stair joints: cut a closed part across an axis with an interlocking terrace.

A flat joint glues only the section's area; stair-shaped cut faces widen it.
A stair joint is a terrace: bands of height ``h`` along a step axis ``b``
(in the cut plane), each cut by its own plane ``a = q_k`` (its tread), the
treads of neighbouring bands ``d`` apart along the cut axis ``a``. Going up
and down in flights (0, d, 2d, d, 0, ...) keeps the teeth interlocking and
the joint no deeper than a flight. It is built from exact planar splits only:

1. the surface is split by every band plane ``b = w_j``, each band plane
   capped as `slicelab.slicing.cut.cut` caps a plane (its cap faces ``+b``);
2. the surface pieces and the band caps are split by every tread plane; the
   tread of band ``k`` is the cap of the closed slab (band ``k``'s surface,
   its two band caps) at ``a = q_k``;
3. each piece goes to side A (``a < q(b)``) or B; a band-cap piece between
   two treads is a riser (kept, facing the side that owns the band beyond
   it), one with the same side on both bands is inside a part (dropped).

Each cap's vertices are the split's own cut points, every split is taken
along a coordinate plane with the cut points put exactly on it, so treads,
risers and surface pieces meet edge to edge. Cut positions avoid the part's
own vertex coordinates (no facet lies in a cutting plane). Both parts are
checked; a joint that does not come out watertight raises `StairCutError`,
and `slicelab.slicing.partition.partition` then falls back to a flat cut.

References
----------
.. [1] H.-C. Chae, H.-Y. Kang, S.-H. Yoo, S.-H. Lee, H.-Y. Moon, "Development of
   slicing algorithm for rapid prototyping building about big sized objects"
   (stair-shaped cut faces to widen the glue area, proposed as future work).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..geometry.chains import chain_segments
from ..geometry.planes import NEXT_CORNER, Frame
from ..geometry.ragged import within_group
from ..geometry.topology import exact_ids, manifold_summary
from ..geometry.triangles import triangle_areas
from ..mesh.core import Mesh
from .cap import Cap, cap_segments, plane_edges
from .sections import section
from .split import split_facets

__all__ = ["StairCut", "StairCutError", "stair_cut", "axis_plane"]

# Cyclic permutations bring axis a to z (and keep the handedness, so windings stay outward).
_PERM = {0: np.array([1, 2, 0]), 1: np.array([2, 0, 1]), 2: np.array([0, 1, 2])}
_UNPERM = {a: np.argsort(p) for a, p in _PERM.items()}
_AXES = "xyz"


class StairCutError(RuntimeError):
    """A stair joint that could not be built closed.

    A band or tread plane whose section does not close, a facet lying in one
    of the joint's planes, or parts that do not come out watertight.
    `slicelab.slicing.partition.partition` falls back to a flat cut then.
    """


@dataclass(frozen=True, eq=False)
class StairCut:
    """The two parts of a stair cut and how its faces came out.

    Attributes
    ----------
    rear, front : Mesh
        The part on the low side of the cut axis, and on the high side.
    treads, risers : (k, 3, 3) ndarrays
        The glued faces of `rear` (treads face +axis, risers +-step axis).
    bands : (K - 1,) ndarray
        Band planes along the step axis.
    offsets : (K,) ndarray
        The tread of each band along the cut axis.
    flat_area : float
        Area of the flat section at the base position.
    watertight : bool
        Both parts passed the edge check.
    step_axis : int
        The axis the bands follow.
    step : (float, float)
        Band height and tread offset as built (mm).
    """

    rear: Mesh
    front: Mesh
    treads: np.ndarray
    risers: np.ndarray
    bands: np.ndarray
    offsets: np.ndarray
    flat_area: float
    watertight: bool
    step_axis: int = 0
    step: tuple = (0.0, 0.0)

    @property
    def glue_area(self) -> float:
        """Area of the glued faces of one part (mm^2)."""
        return float(triangle_areas(self.treads).sum()) + float(triangle_areas(self.risers).sum())


def axis_plane(axis: int, value: float) -> tuple[np.ndarray, np.ndarray]:
    """Origin and unit normal of the plane ``x_axis = value``.

    Examples
    --------
    >>> [v.tolist() for v in axis_plane(1, 2.5)]
    [[0.0, 2.5, 0.0], [0.0, 1.0, 0.0]]
    """
    p = np.zeros(3)
    p[axis] = value
    return p, np.eye(3)[axis]


# ------------------------------------------------------------------ exact axis splits
@dataclass(frozen=True, eq=False)
class _AxisSplit:
    """Facets `rows` of a soup split by a plane ``x_axis = value`` (see `_split_axis`)."""

    rear: np.ndarray         # rear pieces, world coordinates
    front: np.ndarray        # front pieces, world coordinates
    rear_src: np.ndarray     # index into the soup of each rear piece's facet
    front_src: np.ndarray
    dist: np.ndarray         # (rows, 3) corner distances
    turned: np.ndarray       # the rows' corners with the axis turned to z
    rear_turned: np.ndarray  # rear pieces, turned
    rear_row: np.ndarray     # index into `rows` of each rear piece's facet


def _split_axis(soup: np.ndarray, axis: int, value: float, rows: np.ndarray) -> _AxisSplit:
    """Split facets `rows` of `soup` by the plane ``x_axis = value``.

    The split is done with the axis turned to z (a cyclic permutation of the
    coordinates, exact), so that the cut points land exactly on the plane.
    """
    p, q = _PERM[axis], _UNPERM[axis]
    sub = soup[rows][..., p]
    dist = sub[..., 2] - value
    frame = Frame.from_plane((0.0, 0.0, value), (0.0, 0.0, 1.0))
    front, rear, fs, rs, _ = split_facets(sub, dist, frame)
    return _AxisSplit(rear[..., q], front[..., q], rows[rs], rows[fs], dist, sub, rear, rs)


def _split_at(soup: np.ndarray, lo: np.ndarray, hi: np.ndarray, axis: int, value: float, plane: str):
    """The facets of `soup` (extents `lo`, `hi` along `axis`) that reach ``x_axis = value``, and their split.

    Raises `StairCutError` when one of them lies in the plane; `plane` names the plane there.
    """
    rows = np.flatnonzero((lo <= value) & (hi >= value))
    sp = _split_axis(soup, axis, value, rows)
    if np.any(np.all(sp.dist == 0, axis=1)):
        raise StairCutError(f"a facet lies in a {plane} plane")
    return rows, sp


def _cap_of(sp: _AxisSplit, plane: str) -> Cap:
    """The cap (facing +axis) that closes the rear pieces of a split; `StairCutError` when it is open."""
    sel = np.flatnonzero(np.any(sp.dist >= 0, axis=1)[sp.rear_row])
    src = sp.rear_row[sel]
    s, e = plane_edges(sp.rear_turned[sel], sp.turned[src], sp.dist[src], -1)
    cap = cap_segments(s, e, lambda pts: pts[:, :2])
    if not cap.closed:
        raise StairCutError(f"a {plane} plane's section did not close")
    return cap


def _replace_split(soup, lo, hi, rows, sp: _AxisSplit, axis: int):
    """Put the pieces of split facets `rows` (rear, then front) in place of those facets.

    Returns the new soup, its facets' extents `lo`/`hi` along `axis`, and the mask of the
    facets kept whole (so that per-facet tags can follow).
    """
    keep = np.ones(len(soup), bool)
    keep[rows] = False
    new = np.concatenate([sp.rear, sp.front])
    return (np.concatenate([soup[keep], new]), np.concatenate([lo[keep], new[..., axis].min(axis=1)]),
            np.concatenate([hi[keep], new[..., axis].max(axis=1)]), keep)


def _cut_axis(soup: np.ndarray, axis: int, value: float):
    """Split a closed soup by ``x_axis = value``: rear facets, front facets, the cap facing +axis."""
    lo, hi = soup[..., axis].min(axis=1), soup[..., axis].max(axis=1)
    _, sp = _split_at(soup, lo, hi, axis, value, "slab")
    cap = _cap_of(sp, "slab")
    below = hi < value
    above = lo > value
    return (np.concatenate([soup[below], sp.rear]), np.concatenate([soup[above], sp.front]),
            cap.vertices[..., _UNPERM[axis]])


def _refine_along(side: np.ndarray, slab: np.ndarray, axis: int, value: float) -> np.ndarray:
    """Insert into `side`'s edges on the plane ``x_axis = value`` the points `slab`'s pieces have there.

    `side` and `slab` met edge to edge on that plane before the slab was
    split further. Each edge of `side` in the plane is walked back by a chain
    of slab edges; the chain's inner points are new. The facet is fanned from
    its corner off the plane over them, so no other facet changes.
    """
    on_s = side[..., axis] == value
    rows, i = np.nonzero(on_s & on_s[:, NEXT_CORNER])
    if len(rows) == 0:
        return side
    on_m = slab[..., axis] == value
    flat_piece = on_m.all(axis=1)  # the slab's own cap, lying in the plane
    mr, mi = np.nonzero(on_m & on_m[:, NEXT_CORNER] & ~flat_piece[:, None])
    u3, v3 = slab[mr, mi], slab[mr, NEXT_CORNER[mi]]
    p3, r3 = side[rows, i], side[rows, NEXT_CORNER[i]]  # side edge p -> r; the slab walks r -> .. -> p
    ids, first = exact_ids(np.concatenate([u3, v3, p3, r3]))
    pts = np.concatenate([u3, v3, p3, r3])[first]
    m, k = len(u3), len(p3)
    u, v, p, r = ids[:m], ids[m:2 * m], ids[2 * m:2 * m + k], ids[2 * m + k:]
    old = np.zeros(len(first), bool)
    old[p] = True
    old[r] = True
    # Chains of slab edges that start and end at the side's own points.
    end_key = np.where(old[v], len(first) + np.arange(m), v)  # keys no edge starts with: chains stop
    chains = chain_segments(u, end_key)
    heads = chains.order[chains.bounds[:-1]]
    tails = chains.order[chains.bounds[1:] - 1]
    c_key, _ = exact_ids(np.concatenate([np.stack([u[heads], v[tails]], 1), np.stack([r, p], 1)]))
    c_of_key = np.full(c_key.max() + 1, -1)
    c_of_key[c_key[:len(heads)]] = np.arange(len(heads))
    which = c_of_key[c_key[len(heads):]]
    if np.any(which < 0) or not np.all(old[u[heads]]):
        raise StairCutError("the slab and the surface beside it do not meet edge to edge")
    n_edges = chains.bounds[which + 1] - chains.bounds[which]
    split = n_edges > 1
    if not split.any():
        return side
    rows, i, which, n_edges = rows[split], i[split], which[split], n_edges[split]
    # The chain r -> x1 .. xk -> p, run backwards: p, xk, .., x1, r; fan (c_j, c_j+1, o).
    fan = np.repeat(np.arange(len(rows)), n_edges)
    j = within_group(n_edges)  # 0 .. n-1 within a fan
    start = chains.bounds[which][fan]
    # Backwards, edge j of the fan is chain edge n-1-j, from its end point to its start point.
    e = chains.order[start + (n_edges[fan] - 1 - j)]
    a3, b3 = pts[v[e]], pts[u[e]]
    head_edge = j == 0
    a3[head_edge] = side[rows[fan[head_edge]], i[fan[head_edge]]]  # p itself, bit for bit
    last = j == n_edges[fan] - 1
    b3[last] = side[rows[fan[last]], NEXT_CORNER[i[fan[last]]]]           # r itself
    o3 = side[rows[fan], NEXT_CORNER[NEXT_CORNER[i[fan]]]]
    keep = np.ones(len(side), bool)
    keep[rows] = False
    return np.concatenate([side[keep], np.stack([a3, b3, o3], axis=1)])


def _terrace(tri: np.ndarray, a: int, b: int, bands: np.ndarray, q: np.ndarray, slab: tuple):
    """Split a closed soup by the terrace ``a = q[k]`` for ``bands[k-1] <= b < bands[k]``.

    Only the slab ``slab[0] < a < slab[1]`` around the treads is cut as a
    solid; the surface outside it is only split along the band planes, so
    that it meets the slab's pieces edge to edge.

    Returns (A triangles, B triangles, tread triangles, riser triangles of A).
    """
    s0, s1 = slab
    # 0. The slab: flat cuts just outside the treads. Its caps close it, and are dropped at the end
    #    (each is inside a part).
    L, rest, cap0 = _cut_axis(tri, a, s0)
    M, R, cap1 = _cut_axis(rest, a, s1)
    soup = np.concatenate([M, cap0[:, ::-1], cap1])

    # 1. Band planes: split the slab, cap each plane.
    lo, hi = soup[..., b].min(axis=1), soup[..., b].max(axis=1)
    caps = []
    for w in bands:  # over band planes
        rows, sp = _split_at(soup, lo, hi, b, w, "band")
        cap = _cap_of(sp, "band")
        caps.append(cap.vertices[..., _UNPERM[b]])
        soup, lo, hi, _ = _replace_split(soup, lo, hi, rows, sp, b)
    # The surface outside the slab takes the points the band planes put on its edges (fans, no cascade).
    outside_a = _refine_along(L, soup, a, s0)
    outside_b = _refine_along(R, soup, a, s1)
    band_of = np.searchsorted(bands, soup[..., b].mean(axis=1))
    # Cap pieces: plane index j (the plane between band j and band j + 1).
    plane_of = np.concatenate([np.full(len(c), j) for j, c in enumerate(caps)]) if caps else np.zeros(0, int)
    allt = np.concatenate([soup, *caps]) if caps else soup
    is_cap = np.concatenate([np.zeros(len(soup), bool), np.ones(len(plane_of), bool)])
    tag = np.concatenate([band_of, plane_of])

    # 2. Tread planes, low to high: the tread of each band whose plane it is, then split all.
    treads = []
    lo, hi = allt[..., a].min(axis=1), allt[..., a].max(axis=1)
    for value in np.unique(q):  # over tread planes
        rows, sp = _split_at(allt, lo, hi, a, value, "tread")
        src_tag, src_cap = tag[rows], is_cap[rows]
        near = np.any(sp.dist >= 0, axis=1)
        row = sp.rear_row
        for k in np.flatnonzero(q == value):  # over the bands with this tread
            # Slab k: its surface, the band cap above (as built), the one below (turned over).
            pick_surf = ~src_cap & (src_tag == k)
            pick_top = src_cap & (src_tag == k)
            pick_bot = src_cap & (src_tag == k - 1)
            sel = np.flatnonzero((pick_surf | pick_top | pick_bot)[row] & near[row])
            flip = pick_bot[row[sel]]
            pieces = sp.rear_turned[sel].copy()
            pieces[flip] = pieces[flip][:, ::-1]
            corners = sp.turned[row[sel]].copy()
            corners[flip] = corners[flip][:, ::-1]
            cd = sp.dist[row[sel]].copy()
            cd[flip] = cd[flip][:, ::-1]
            s, e = plane_edges(pieces, corners, cd, -1)
            cap = cap_segments(s, e, lambda pts: pts[:, :2])
            if not cap.closed:
                raise StairCutError("a tread's section did not close")
            treads.append(cap.vertices[..., _UNPERM[a]])
        allt, lo, hi, keep = _replace_split(allt, lo, hi, rows, sp, a)
        tag = np.concatenate([tag[keep], tag[sp.rear_src], tag[sp.front_src]])
        is_cap = np.concatenate([is_cap[keep], is_cap[sp.rear_src], is_cap[sp.front_src]])

    # 3. Sides. A piece lies between two neighbouring planes, so its lowest corner tells its side.
    low = allt[..., a].min(axis=1)
    high = allt[..., a].max(axis=1)
    surf = ~is_cap
    slab_cap = surf & (((low == s0) & (high == s0)) | ((low == s1) & (high == s1)))
    in_a = np.zeros(len(allt), bool)
    in_a[surf] = low[surf] < q[tag[surf]]
    j = tag[is_cap]
    below_a = low[is_cap] < q[j]        # the band under the plane is A here
    above_a = low[is_cap] < q[j + 1]    # the band over it
    cap_t = allt[is_cap]
    riser_up = cap_t[above_a & ~below_a]    # A above: A's face looks down (turn over)
    riser_down = cap_t[below_a & ~above_a]  # A below: as built (+b)
    tr = np.concatenate(treads) if treads else np.zeros((0, 3, 3))
    risers_a = np.concatenate([riser_down, riser_up[:, ::-1]])
    risers_b = np.concatenate([riser_up, riser_down[:, ::-1]])
    side_a = np.concatenate([outside_a, allt[surf & in_a & ~slab_cap], risers_a, tr])
    side_b = np.concatenate([allt[surf & ~in_a & ~slab_cap], outside_b, risers_b, tr[:, ::-1]])
    return side_a, side_b, tr, risers_a


def _clear_of(coords: np.ndarray, value: float, tol: float, shift: float) -> float:
    """`value`, or the nearest of ``value +- k shift / 16`` (k <= 4) that keeps clear of `coords`.

    Clear means no coordinate within `tol` (so no facet lies in the plane);
    a position at least ``shift / 64`` away from every coordinate is
    preferred, which avoids sliver facets.
    """
    if len(coords) == 0:
        return value
    steps = np.array([0, 1, -1, 2, -2, 3, -3, 4, -4]) * (shift / 16)
    cand = value + steps
    if len(coords) > 1:
        k = np.clip(np.searchsorted(coords, cand), 1, len(coords) - 1)
        gap = np.minimum(np.abs(coords[k] - cand), np.abs(coords[k - 1] - cand))
    else:
        gap = np.abs(coords[0] - cand)
    good = np.flatnonzero(gap >= shift / 64)
    if len(good):
        return float(cand[good[0]])
    best = int(np.argmax(gap))
    if gap[best] > tol:
        return float(cand[best])
    return float(value + tol * 7)


def _spaced(values, gap: float) -> np.ndarray:
    """Sorted values, dropping any closer than `gap` to (or equal to) the one kept before it."""
    v = np.sort(np.asarray(values, dtype=np.float64))
    out = []
    for x in v:  # over band planes, few
        if not out or x - out[-1] > gap:
            out.append(x)
    return np.array(out)


def _profile(n_bands: int, flight: int) -> np.ndarray:
    """Step levels 0, 1, .., flight, .., 1, 0, 1, ... of each band."""
    period = np.concatenate([np.arange(flight + 1), np.arange(flight - 1, 0, -1)]) if flight > 0 else [0]
    return np.resize(np.asarray(period, float), n_bands)


def _dilate(bands: np.ndarray, q: np.ndarray, c: float) -> tuple[np.ndarray, np.ndarray]:
    """Terrace of ``max(q(w') : |w' - w| <= c) + c``: side B moved back by a gap `c` everywhere."""
    if c <= 0:
        return bands, q
    cuts = np.unique(np.concatenate([bands - c, bands + c]))
    mids = np.concatenate([[cuts[0] - 1.0], (cuts[:-1] + cuts[1:]) / 2, [cuts[-1] + 1.0]])
    lo = np.searchsorted(bands, mids - c, side="right")
    hi = np.searchsorted(bands, mids + c, side="left")
    qq = np.array([q[i:j + 1].max() for i, j in zip(lo, hi)]) + c  # over bands, few
    keep = np.concatenate([[True], qq[1:] != qq[:-1]])
    return cuts[keep[1:]], qq[keep]


def stair_cut(mesh: Mesh, axis: int, position: float, *, step=(10.0, 20.0), flight: int = 1,
              step_axis: int | None = None, phase: int = 0, clearance: float = 0.0) -> StairCut:
    """Cut a closed part across `axis` with an interlocking stair-shaped joint.

    Parameters
    ----------
    mesh : Mesh
        Watertight, normals outward.
    axis : {0, 1, 2}
        The cut runs across this axis; `rear` is the low side.
    position : float
        The lowest tread (mm); the others lie up to ``flight * depth`` beyond.
    step : (height, depth), default (10, 20)
        Band height along the step axis and tread offset along `axis` (mm).
        The height shrinks (the depth with it) to give the section at least
        four bands. Each band edge adds a riser ``depth`` deep, so the glue
        area is about ``1 + depth / height`` times the flat one for a full
        section (2.5x for a box with four bands), less for thin rings.
    flight : int, default 1
        Steps up before stepping down again: 1 is a castellated joint
        (0, d, 0, d ...), 2 a stair going 0, d, 2d, d, 0 ...
    step_axis : int, optional
        In-plane axis the bands follow; default the longer side of the section.
    phase : int, default 0
        Start the step pattern this many bands later (moves the teeth).
    clearance : float, default 0
        Gap (mm) between the mating faces: the front part is cut back by it.

    Returns
    -------
    StairCut

    Raises
    ------
    StairCutError
        When the joint does not come out watertight (a plane's section does
        not close, or a facet lies in one of the joint's planes).
    ValueError
        For bad arguments, a plane that misses the part, or a joint that
        leaves one side empty.

    See Also
    --------
    slicelab.slicing.cut.cut : the flat cut.
    slicelab.slicing.partition.partition : cuts with flat or stair joints until every piece fits.

    References
    ----------
    .. [1] H.-C. Chae, H.-Y. Kang, S.-H. Yoo, S.-H. Lee, H.-Y. Moon, "Development
       of slicing algorithm for rapid prototyping building about big sized
       objects" (stair-shaped cut faces, proposed as future work).

    Examples
    --------
    >>> from slicelab.samples import box
    >>> from slicelab import check
    >>> s = stair_cut(box((0, 0, 0), (40, 20, 20)), 0, 18.0, step=(5.0, 7.5))
    >>> s.watertight, round(check(s.rear).volume + check(s.front).volume, 6)
    (True, 16000.0)
    >>> s.flat_area, s.glue_area  # 20 x 20 section; 4 bands: 3 risers of 7.5 x 20 each
    (400.0, 850.0)
    """
    if axis not in (0, 1, 2):
        raise ValueError(f"axis must be 0, 1 or 2, got {axis!r}")
    h, d = (float(v) for v in step)
    if not (h > 0 and d > 0 and np.isfinite(h) and np.isfinite(d)):
        raise ValueError(f"step height and depth must be positive, got {step!r}")
    if clearance < 0 or not np.isfinite(clearance):
        raise ValueError(f"clearance must be >= 0, got {clearance!r}")
    flight = max(int(flight), 1)
    t = mesh.triangles
    flat = t.reshape(-1, 3)
    scale = float(np.abs(flat).max()) if len(flat) else 1.0
    tol = 1e-9 * max(scale, 1.0)
    coords = [np.unique(flat[:, k]) for k in range(3)]
    sec = section(mesh, *axis_plane(axis, position), max_gap=0.0)
    flat_area = sec.area
    pts = sec.to_3d(sec.segments.reshape(-1, 2)) if len(sec.segments) else np.zeros((0, 3))
    others = [k for k in range(3) if k != axis]
    if len(pts) == 0:
        raise ValueError(f"the plane {_AXES[axis]} = {position:g} does not cross the part")
    ext = pts.max(axis=0) - pts.min(axis=0)
    b = step_axis if step_axis is not None else max(others, key=lambda k: ext[k])
    if b not in others:
        raise ValueError(f"step_axis must differ from axis, got {step_axis!r}")
    b0, b1 = float(pts[:, b].min()), float(pts[:, b].max())
    h_eff = min(h, (b1 - b0) / 4)
    d_eff = d * h_eff / h
    n_bands = max(int(np.ceil((b1 - b0) / h_eff)), 1)
    bands = _spaced([_clear_of(coords[b], b0 + k * h_eff, tol, h_eff) for k in range(1, n_bands)], h_eff / 2)
    levels = _profile(len(bands) + 1 + int(phase), flight)[int(phase):]
    # Every tread must be clear of the part's own vertices: move the whole terrace if one is not.
    for shift in d_eff / 64 * np.array([0, 1, -1, 2, -2, 3, -3, 4, -4, 5, -5]):
        q = position + shift + d_eff * levels
        if all(_clear_of(coords[axis], v, tol, d_eff / 8) == v for v in np.unique(q)):
            break
    position = float(q.min())
    def slab(qq):
        return (_clear_of(coords[axis], float(qq.min()) - d_eff / 4, tol, d_eff / 8),
                _clear_of(coords[axis], float(qq.max()) + d_eff / 4, tol, d_eff / 8))

    try:
        side_a, side_b, treads, risers = _terrace(t, axis, b, bands, q, slab(q))
        if clearance > 0:
            # The front part is cut by the terrace moved back by the gap, everywhere.
            bands_c, q_c = _dilate(bands, q, clearance)
            bands_c = _spaced([_clear_of(coords[b], v, tol, h_eff / 8) for v in bands_c], 0.0)
            if len(bands_c) != len(q_c) - 1:
                raise StairCutError("the clearance merged two bands")
            q_c = np.array([_clear_of(coords[axis], v, tol, d_eff / 8) for v in q_c])
            _, side_b, _, _ = _terrace(t, axis, b, bands_c, q_c, slab(q_c))
        if len(side_a) == 0 or len(side_b) == 0:
            raise ValueError(f"the joint at {_AXES[axis]} = {position:g} leaves one side empty")
        ok = manifold_summary(side_a).closed and manifold_summary(side_b).closed
    except StairCutError:
        ok, side_a, side_b = False, None, None
    if not ok:
        raise StairCutError(f"the stair joint at {_AXES[axis]} = {position:g} did not close")
    return StairCut(Mesh(side_a), Mesh(side_b), treads, risers, bands, q, flat_area, ok, b, (h_eff, d_eff))
