"""Cut a part too big for the printer into closed printable pieces, with flat or stair joints.

Seed 001 cuts big STL solids so that the pieces can be built apart and glued,
and leaves as future work stair-shaped cut faces that widen the glue area.
`partition` cuts recursively (with `slicelab.cut` for flat joints) until
every piece fits the build volume; `stair_cut` builds the stair joint.

A stair joint is a terrace: bands of height ``h`` along a step axis ``b``
(in the cut plane), each cut by its own plane ``a = q_k`` (its tread), the
treads of neighbouring bands ``d`` apart along the cut axis ``a``. Going up
and down in flights (0, d, 2d, d, 0, ...) keeps the teeth interlocking and
the joint no deeper than a flight. It is built from exact planar splits only:

1. the surface is split by every band plane ``b = w_j``, each band plane
   capped as `cut` caps a plane (its cap faces ``+b``);
2. the surface pieces and the band caps are split by every tread plane; the
   tread of band ``k`` is the cap of the closed slab (band ``k``'s surface,
   its two band caps) at ``a = q_k``;
3. each piece goes to side A (``a < q(b)``) or B; a band-cap piece between
   two treads is a riser (kept, facing the side that owns the band beyond
   it), one with the same side on both bands is inside a part (dropped).

Each cap's vertices are the split's own cut points, every split is taken
along a coordinate plane with the cut points put exactly on it, so treads,
risers and surface pieces meet edge to edge. Cut positions avoid the part's
own vertex coordinates (no facet lies in a cutting plane). Parts are checked;
a joint that does not come out watertight falls back to a flat cut (and says
so in the report).
"""
from __future__ import annotations

import warnings
from dataclasses import dataclass, field

import numpy as np

from ..geometry.chains import chain_segments
from ..geometry.planes import NEXT_CORNER, Frame
from ..geometry.topology import exact_ids
from ..mesh.core import Mesh
from ..mesh.validation import signed_volume
from .cut import Cap, cap_segments, cut, plane_edges, watertight_edges
from .sections import section
from .split import split_facets

__all__ = ["Joint", "Piece", "PartitionReport", "Partition", "partition", "stair_cut", "StairCut",
           "fit_rotation", "plot_exploded", "save_exploded_png"]

# Cyclic permutations bring axis a to z (and keep the handedness, so windings stay outward).
_PERM = {0: np.array([1, 2, 0]), 1: np.array([2, 0, 1]), 2: np.array([0, 1, 2])}
_UNPERM = {a: np.argsort(p) for a, p in _PERM.items()}
_AXES = "xyz"


# ------------------------------------------------------------------ reports
@dataclass(frozen=True)
class Joint:
    """One cut of a partition.

    Attributes
    ----------
    axis : int
        0, 1, 2 for a cut across x, y, z.
    position : float
        The flat plane (mm); a stair's treads lie at ``position`` and beyond.
    kind : str
        ``"flat"`` or ``"stair"`` (or ``"flat (stair failed)"``).
    flat_area : float
        Area of the flat section at `position` (mm^2).
    glue_area : float
        Area of the faces that are glued, on one part (mm^2).
    step_axis : int or None
        In-plane axis along which the stair's bands run.
    step : tuple or None
        (height, depth) of the stair's steps as built (mm).
    """

    axis: int
    position: float
    kind: str
    flat_area: float
    glue_area: float
    step_axis: int | None = None
    step: tuple | None = None

    @property
    def ratio(self) -> float:
        """Glue area over the flat section's area."""
        return self.glue_area / self.flat_area if self.flat_area > 0 else float("nan")


@dataclass(frozen=True)
class Piece:
    """A piece of a partition: its size and how it sits in the printer.

    Attributes
    ----------
    size : tuple of float
        Bounding-box size (x, y, z) in the part's own coordinates (mm).
    rotation : float
        Turn about z (degrees) that makes it fit the build volume.
    volume : float
        mm^3.
    watertight : bool
        Every edge shared by two facets walking it opposite ways.
    n_facets : int
    """

    size: tuple
    rotation: float
    volume: float
    watertight: bool
    n_facets: int


@dataclass(frozen=True)
class PartitionReport:
    """What `partition` made: pieces, joints and glue area."""

    build_volume: tuple
    joint: str
    clearance: float
    pieces: list = field(default_factory=list)
    joints: list = field(default_factory=list)

    @property
    def glue_area(self) -> float:
        """Glue area of all joints (one side each, mm^2)."""
        return float(sum(j.glue_area for j in self.joints))

    @property
    def flat_area(self) -> float:
        """What flat cuts at the same positions would have given (mm^2)."""
        return float(sum(j.flat_area for j in self.joints))

    @property
    def watertight(self) -> bool:
        return all(p.watertight for p in self.pieces)

    def describe(self) -> str:
        """A small table for people."""
        bx = "x".join(f"{v:g}" for v in self.build_volume)
        lines = [f"{len(self.pieces)} pieces for a {bx} mm build volume, {self.joint} joints, "
                 f"clearance {self.clearance:g} mm; glue area {self.glue_area:.6g} mm2 "
                 f"(flat cuts: {self.flat_area:.6g} mm2)",
                 "piece  size x y z (mm)               turn   volume (mm3)   facets  watertight"]
        for k, p in enumerate(self.pieces):
            size = " x ".join(f"{v:7.2f}" for v in p.size)
            lines.append(f"{k:5d}  {size}  {p.rotation:5.1f}  {p.volume:13.6g}  {p.n_facets:7d}  "
                         f"{'yes' if p.watertight else 'NO'}")
        lines.append("joint  axis  position   kind        flat (mm2)   glue (mm2)  ratio")
        for k, j in enumerate(self.joints):
            lines.append(f"{k:5d}  {_AXES[j.axis]:>4}  {j.position:9.3f}  {j.kind:<10}  {j.flat_area:11.6g}  "
                         f"{j.glue_area:11.6g}  {j.ratio:5.2f}")
        return "\n".join(lines)

    def to_dict(self) -> dict:
        return {"build_volume": list(self.build_volume), "joint": self.joint, "clearance": self.clearance,
                "glue_area": self.glue_area, "flat_area": self.flat_area,
                "pieces": [{"size": list(p.size), "rotation": p.rotation, "volume": p.volume,
                            "watertight": p.watertight, "n_facets": p.n_facets} for p in self.pieces],
                "joints": [{"axis": _AXES[j.axis], "position": j.position, "kind": j.kind,
                            "flat_area": j.flat_area, "glue_area": j.glue_area, "ratio": j.ratio,
                            "step_axis": None if j.step_axis is None else _AXES[j.step_axis],
                            "step": None if j.step is None else list(j.step)} for j in self.joints]}


class Partition(list):
    """The pieces of a partition (a list of `Mesh`), with its `report`."""

    report: PartitionReport

    def __init__(self, pieces, report: PartitionReport):
        super().__init__(pieces)
        self.report = report


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
        Band planes along the step axis; ``offsets`` (K,) the tread of each band.
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
        return _area(self.treads) + _area(self.risers)


def _area(t: np.ndarray) -> float:
    if len(t) == 0:
        return 0.0
    return float(np.linalg.norm(np.cross(t[:, 1] - t[:, 0], t[:, 2] - t[:, 0]), axis=1).sum() / 2)


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


def _cap_of(sp: _AxisSplit) -> Cap:
    """The cap (facing +axis) that closes the rear pieces of a split."""
    sel = np.flatnonzero(np.any(sp.dist >= 0, axis=1)[sp.rear_row])
    src = sp.rear_row[sel]
    s, e = plane_edges(sp.rear_turned[sel], sp.turned[src], sp.dist[src], -1)
    return cap_segments(s, e, lambda pts: pts[:, :2])


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


class _StairFailed(RuntimeError):
    pass


def _cut_axis(soup: np.ndarray, axis: int, value: float):
    """Split a closed soup by ``x_axis = value``: rear facets, front facets, the cap facing +axis."""
    lo, hi = soup[..., axis].min(axis=1), soup[..., axis].max(axis=1)
    rows = np.flatnonzero((lo <= value) & (hi >= value))
    sp = _split_axis(soup, axis, value, rows)
    if np.any(np.all(sp.dist == 0, axis=1)):
        raise _StairFailed("a facet lies in a slab plane")
    cap = _cap_of(sp)
    if not cap.closed:
        raise _StairFailed("a slab plane's section did not close")
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
        raise _StairFailed("the slab and the surface beside it do not meet edge to edge")
    n_edges = chains.bounds[which + 1] - chains.bounds[which]
    split = n_edges > 1
    if not split.any():
        return side
    rows, i, which, n_edges = rows[split], i[split], which[split], n_edges[split]
    # The chain r -> x1 .. xk -> p, run backwards: p, xk, .., x1, r; fan (c_j, c_j+1, o).
    total = int(n_edges.sum())
    fan = np.repeat(np.arange(len(rows)), n_edges)
    j = np.arange(total) - np.repeat(np.cumsum(n_edges) - n_edges, n_edges)  # 0 .. n-1 within a fan
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
        rows = np.flatnonzero((lo <= w) & (hi >= w))
        sp = _split_axis(soup, b, w, rows)
        if np.any(np.all(sp.dist == 0, axis=1)):
            raise _StairFailed("a facet lies in a band plane")
        cap = _cap_of(sp)
        if not cap.closed:
            raise _StairFailed("a band plane's section did not close")
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
        rows = np.flatnonzero((lo <= value) & (hi >= value))
        sp = _split_axis(allt, a, value, rows)
        if np.any(np.all(sp.dist == 0, axis=1)):
            raise _StairFailed("a facet lies in a tread plane")
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
                raise _StairFailed("a tread's section did not close")
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
    sec = section(mesh, _point(axis, position), np.eye(3)[axis], max_gap=0.0)
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
                raise _StairFailed("the clearance merged two bands")
            q_c = np.array([_clear_of(coords[axis], v, tol, d_eff / 8) for v in q_c])
            _, side_b, _, _ = _terrace(t, axis, b, bands_c, q_c, slab(q_c))
        if len(side_a) == 0 or len(side_b) == 0:
            raise ValueError(f"the joint at {_AXES[axis]} = {position:g} leaves one side empty")
        ok = watertight_edges(side_a)["closed"] and watertight_edges(side_b)["closed"]
    except _StairFailed:
        ok, side_a, side_b = False, None, None
    if not ok:
        raise _StairFailed(f"the stair joint at {_AXES[axis]} = {position:g} did not close")
    return StairCut(Mesh(side_a), Mesh(side_b), treads, risers, bands, q, flat_area, ok, b, (h_eff, d_eff))


def _point(axis: int, value: float) -> np.ndarray:
    p = np.zeros(3)
    p[axis] = value
    return p


# ------------------------------------------------------------------ fitting
def fit_rotation(mesh: Mesh, build_volume, *, rotate: bool = True) -> float | None:
    """Turn about z (degrees) that makes the part fit the build volume, or None.

    Tries the part as it lies, then (with `rotate`) turned by 90 degrees, then
    every direction of an edge of its convex hull in plan (the smallest
    enclosing rectangles are aligned with one) and every half degree (a long
    part may only fit along the diagonal).

    Examples
    --------
    >>> from slicelab.samples import box
    >>> fit_rotation(box((0, 0, 0), (250, 100, 10)), (200, 300, 100))
    90.0
    >>> fit_rotation(box((0, 0, 0), (250, 100, 10)), (200, 200, 100)) is None
    True
    """
    X, Y, Z = (float(v) for v in build_volume)
    lo, hi = mesh.bounds
    e = hi - lo
    tol = 1e-9 * max(float(np.abs(mesh.bounds).max()), 1.0)
    if e[2] > Z + tol:
        return None
    if e[0] <= X + tol and e[1] <= Y + tol:
        return 0.0
    if not rotate:
        return None
    if e[0] <= Y + tol and e[1] <= X + tol:
        return 90.0
    from scipy.spatial import ConvexHull
    xy = mesh.triangles.reshape(-1, 3)[:, :2]
    try:
        hull = xy[ConvexHull(xy).vertices]
    except Exception:  # flat or degenerate outline
        return None
    edges = np.roll(hull, -1, axis=0) - hull
    # Hull edge directions hold the smallest rectangles; a sweep finds the diagonal fits.
    ang = np.concatenate([np.arctan2(edges[:, 1], edges[:, 0]) % (np.pi / 2), np.radians(np.arange(0.5, 90, 0.5))])
    c, s = np.cos(ang), np.sin(ang)
    u = hull @ np.stack([c, s])           # extents along each edge direction
    v = hull @ np.stack([-s, c])
    wu, wv = np.ptp(u, axis=0), np.ptp(v, axis=0)
    ok = ((wu <= X + tol) & (wv <= Y + tol)) | ((wu <= Y + tol) & (wv <= X + tol))
    if not ok.any():
        return None
    k = int(np.flatnonzero(ok)[0])
    a = -np.degrees(ang[k])  # turn the edge onto x
    if not (wu[k] <= X + tol and wv[k] <= Y + tol):
        a += 90.0
    return float(a % 360.0)


def _counts(e: np.ndarray, V: np.ndarray, margin: float) -> np.ndarray:
    step = V - margin
    return np.where(e <= V, 1, np.ceil((e - margin) / np.maximum(step, 1e-300))).astype(int)


def _components(t: np.ndarray) -> tuple[int, np.ndarray]:
    """Facets grouped into edge-connected shells: (count, label of each facet)."""
    from ..geometry.topology import shells, weld
    if len(t) == 0:
        return 0, np.zeros(0, np.int64)
    return shells(weld(t)[1])


def _n_shells(t: np.ndarray) -> int:
    return _components(t)[0]


def _bodies(m: Mesh) -> list[Mesh]:
    """Split a part into separate bodies: each outer shell with the cavities inside it.

    A shell of negative volume (a cavity) goes with the smallest outer shell
    whose box holds it; anything unclear stays together.
    """
    k, lab = _components(m.triangles)
    if k < 2:
        return [m]
    t = m.triangles
    order = np.argsort(lab, kind="stable")
    cuts = np.searchsorted(lab[order], np.arange(k + 1))
    shells = [t[order[cuts[i]:cuts[i + 1]]] for i in range(k)]
    vol = np.array([signed_volume(s) for s in shells])
    box = np.array([[s.reshape(-1, 3).min(axis=0), s.reshape(-1, 3).max(axis=0)] for s in shells])
    outer = np.flatnonzero(vol > 0)
    if len(outer) < 2:
        return [m]
    groups = {int(i): [i] for i in outer}
    for i in np.flatnonzero(vol <= 0):  # cavities: into the smallest outer shell around them
        holds = [j for j in outer if np.all(box[j, 0] <= box[i, 0]) and np.all(box[i, 1] <= box[j, 1])]
        if not holds:
            return [m]
        groups[int(min(holds, key=lambda j: vol[j]))].append(i)
    # Outer shells inside another's box may be islands in its cavity: keep those together.
    merged = {}
    for j in sorted(groups, key=lambda j: -vol[j]):
        home = next((r for r in merged if np.all(box[r, 0] <= box[j, 0]) and np.all(box[j, 1] <= box[r, 1])), None)
        if home is None:
            merged[j] = list(groups[j])
        else:
            merged[home] += groups[j]
    if len(merged) < 2:
        return [m]
    return [Mesh(np.concatenate([shells[i] for i in members])) for members in merged.values()]


# ------------------------------------------------------------------ partition
def partition(mesh: Mesh, build_volume=(200.0, 200.0, 200.0), *, joint: str = "flat", clearance: float = 0.0,
              step=(10.0, 20.0), flight: int = 1, rotate: bool = True, candidates: int = 9,
              max_pieces: int = 512) -> Partition:
    """Cut a solid recursively until every piece fits the build volume.

    Each piece that does not fit is cut across the axis that needs the most
    pieces (``ceil(size / usable build size)``, with the part turned by 90
    degrees about z when that needs fewer), at the position, among
    `candidates` spread over the range that keeps that count, whose section
    is smallest. Pieces may be turned about z to fit (`rotate`).

    Parameters
    ----------
    mesh : Mesh
        Watertight, normals outward (check it first with `slicelab.check`).
    build_volume : (X, Y, Z)
        The printer's build volume (mm).
    joint : {"flat", "stair"}
        Flat cuts, or stair joints (`stair_cut`) that interlock and at least
        double the glue area for the default step. A stair that would not
        close, or would leave loose fragments, falls back to a flat cut (see
        the report's joints).
    clearance : float, default 0
        Glue gap between mating faces (mm); the upper piece is cut back.
    step, flight
        The stair's (height, depth) and flight, as in `stair_cut`.
    rotate : bool, default True
        Allow turning pieces about z to fit.
    candidates : int, default 9
        Cut positions tried per cut.
    max_pieces : int, default 512
        Safety limit.

    Returns
    -------
    Partition
        A list of `Mesh` in the part's own coordinates (they assemble into
        the input), with ``.report`` (`PartitionReport`): each piece's size,
        turn and volume, each joint's flat and glue area.

    Examples
    --------
    >>> from slicelab.samples import box
    >>> parts = partition(box((0, 0, 0), (300, 120, 80)), (200, 200, 200))
    >>> len(parts), [p.watertight for p in parts.report.pieces]
    (2, [True, True])
    >>> round(sum(p.volume for p in parts.report.pieces), 6)
    2880000.0
    """
    V = np.asarray(build_volume, dtype=np.float64).reshape(-1)
    if V.shape != (3,) or not np.all(np.isfinite(V)) or np.any(V <= 0):
        raise ValueError(f"build volume must be three positive sizes, got {build_volume!r}")
    if joint not in ("flat", "stair"):
        raise ValueError(f"joint must be 'flat' or 'stair', got {joint!r}")
    if not (clearance >= 0 and np.isfinite(clearance)):
        raise ValueError(f"clearance must be >= 0, got {clearance!r}")
    h, d = (float(v) for v in step)
    margin = clearance + (flight * d if joint == "stair" else 0.0)
    if np.any(V <= margin):
        raise ValueError(f"the joint ({margin:g} mm deep with clearance) does not fit the build volume")
    if len(mesh) == 0:
        raise ValueError("the mesh has no facets")

    done, joints = [], []
    pending = [mesh]
    while pending:  # over pieces
        m = pending.pop()
        turn = fit_rotation(m, V, rotate=rotate)
        if turn is not None:
            done.append((m, turn))
            continue
        bodies = _bodies(m)
        if len(bodies) > 1:  # separate bodies are printed apart: no cut needed between them
            pending += bodies
            continue
        if len(done) + len(pending) + 2 > max_pieces:
            raise ValueError(f"more than {max_pieces} pieces needed: is the build volume right?")
        axis, V_axis, n = _plan(m, V, margin, rotate)
        lo, hi = m.bounds[:, axis]
        usable = V_axis - margin
        w0, w1 = hi - (n - 1) * usable, lo + usable
        pad = 1e-3 * (w1 - w0) if w1 > w0 else 0.0
        pos = np.linspace(w0 + pad, w1 - pad, max(int(candidates), 1)) if w1 > w0 else np.array([(w0 + w1) / 2])
        areas = np.array([section(m, _point(axis, p), np.eye(3)[axis], max_gap=0.0).area for p in pos])
        order = np.argsort(areas + 1e-9 * np.abs(pos - (w0 + w1) / 2), kind="stable")
        best = float(pos[order[0]])
        rear, front, jt = _cut_joint(m, axis, best, joint, clearance, (h, d), flight)
        joints.append(jt)
        pending += [p for p in (front, rear) if len(p)]

    pieces = [m for m, _ in done]
    infos = []
    for m, turn in done:  # over pieces
        we = watertight_edges(m.triangles)
        lo, hi = m.bounds
        infos.append(Piece(tuple(float(v) for v in hi - lo), float(turn), signed_volume(m.triangles),
                           bool(we["closed"]), len(m)))
    report = PartitionReport(tuple(float(v) for v in V), joint, float(clearance), infos, joints)
    return Partition(pieces, report)


def _plan(m: Mesh, V: np.ndarray, margin: float, rotate: bool):
    """Axis to cut, its build size, and how many pieces it needs along it."""
    e = np.ptp(m.triangles.reshape(-1, 3), axis=0)
    options = [V] + ([V[[1, 0, 2]]] if rotate else [])
    best = None
    for W in options:  # as it lies, turned by 90 degrees
        n = _counts(e, W, margin)
        key = (int(np.prod(n)), -int(n.max()))
        if best is None or key < best[0]:
            best = (key, W, n)
    _, W, n = best
    cand = np.flatnonzero(n == n.max())
    axis = int(cand[np.argmax(e[cand] / W[cand])])
    return axis, float(W[axis]), int(n[axis])


def _cut_joint(m: Mesh, axis: int, pos: float, joint: str, clearance: float, step, flight: int):
    normal = np.eye(3)[axis]
    flat_area = section(m, _point(axis, pos), normal, max_gap=0.0).area
    kind = "flat"
    if joint == "stair":
        # Teeth that cross a hole can leave loose fragments: try the other phase and the
        # other step axis, and keep the first stair with no more bodies than a flat cut.
        flat_shells = None
        others = [k for k in range(3) if k != axis]
        for step_axis in (None, *others):
            for phase in (0, 1):
                h = float(step[0])
                for _ in range(3):  # narrower bands add risers where the glue area falls short of 2x
                    try:
                        sc = stair_cut(m, axis, pos, step=(h, step[1]), flight=flight, step_axis=step_axis,
                                       phase=phase, clearance=clearance)
                    except (_StairFailed, ValueError):
                        sc = None
                        break
                    ratio = sc.glue_area / sc.flat_area if sc.flat_area > 0 else 0.0
                    if ratio >= 2.0 or ratio <= 1.0:
                        break
                    h = min(sc.step[0], h) * (ratio - 1.0) / 1.15
                if sc is None:
                    continue
                if flat_shells is None:
                    with warnings.catch_warnings():
                        warnings.simplefilter("ignore")
                        r0, f0 = cut(m, _point(axis, pos), normal)
                    flat_shells = _n_shells(r0.triangles) + _n_shells(f0.triangles)
                if _n_shells(sc.rear.triangles) + _n_shells(sc.front.triangles) <= flat_shells:
                    return sc.rear, sc.front, Joint(axis, pos, "stair", sc.flat_area, sc.glue_area,
                                                    sc.step_axis, tuple(float(v) for v in sc.step))
        kind = "flat (stair failed)"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        rear, front = res = cut(m, _point(axis, pos), normal)
        if clearance > 0:
            front = cut(m, _point(axis, pos + clearance), normal)[1]
    return rear, front, Joint(axis, pos, kind, flat_area, res.report.rear_cap.area)


# ------------------------------------------------------------------ pictures
def plot_exploded(pieces, ax=None, *, spread: float = 0.25, max_facets: int = 200_000, elev: float = 25.0,
                  azim: float = -60.0):
    """Draw pieces pushed apart from their common centre, shaded, in an orthographic view.

    A painter's algorithm over a 2-D PolyCollection: fast enough for a few
    hundred thousand facets (beyond `max_facets` the smallest facets are left out).

    Returns the matplotlib Axes.
    """
    import matplotlib.pyplot as plt
    from matplotlib.collections import PolyCollection
    if ax is None:
        _, ax = plt.subplots(figsize=(7, 6))
    pieces = [p for p in pieces if len(p)]
    if not pieces:
        return ax
    allb = np.array([p.bounds for p in pieces])
    centre = (allb[:, 0].min(axis=0) + allb[:, 1].max(axis=0)) / 2
    size = float(np.max(allb[:, 1].max(axis=0) - allb[:, 0].min(axis=0)))
    el, az = np.radians(elev), np.radians(azim)
    view = np.array([np.cos(el) * np.cos(az), np.cos(el) * np.sin(az), np.sin(el)])  # towards the viewer
    right = np.array([-np.sin(az), np.cos(az), 0.0])
    up = np.cross(view, right)
    light = view + np.array([0.3, 0.2, 0.6])
    light /= np.linalg.norm(light)
    total = sum(len(p) for p in pieces)
    cmap = plt.get_cmap("tab10" if len(pieces) <= 10 else "tab20")
    polys, colours, depth = [], [], []
    for k, p in enumerate(pieces):  # over pieces
        c = p.bounds.mean(axis=0)
        shift = (c - centre) * spread * 2
        t = p.triangles
        keep = np.arange(len(t))
        if total > max_facets:  # the largest facets cover the most: drop slivers first
            area = np.linalg.norm(np.cross(t[:, 1] - t[:, 0], t[:, 2] - t[:, 0]), axis=1)
            keep = np.argsort(-area)[:max(1, int(len(t) * max_facets / total))]
        t = t[keep] + shift
        n = p.normals[keep]
        facing = n @ view > 0
        t, n = t[facing], n[facing]
        shade = 0.35 + 0.65 * np.clip(n @ light, 0, 1)
        base = np.array(cmap(k % cmap.N)[:3])
        colours.append(np.clip(base[None, :] * shade[:, None], 0, 1))
        polys.append(np.stack([t @ right, t @ up], axis=-1))
        depth.append((t @ view).mean(axis=1))
    polys = np.concatenate(polys)
    colours = np.concatenate(colours)
    order = np.argsort(np.concatenate(depth))
    # Edges in the face colour close the hairline seams anti-aliasing leaves between facets.
    ax.add_collection(PolyCollection(polys[order], facecolors=colours[order], edgecolors=colours[order],
                                     linewidths=0.3))
    flat = polys.reshape(-1, 2)
    ax.set_xlim(flat[:, 0].min() - 0.02 * size, flat[:, 0].max() + 0.02 * size)
    ax.set_ylim(flat[:, 1].min() - 0.02 * size, flat[:, 1].max() + 0.02 * size)
    ax.set_aspect("equal")
    ax.set_axis_off()
    return ax


def save_exploded_png(pieces, path, *, title: str | None = None, dpi: int = 120, **kwargs) -> None:
    """Write `plot_exploded` of the pieces to a PNG file, atomically.

    Examples
    --------
    >>> import tempfile, os
    >>> from slicelab.samples import box
    >>> from slicelab import cut
    >>> save_exploded_png(cut(box(), (0, 0, 0.5), (0, 0, 1)), os.path.join(tempfile.mkdtemp(), "p.png"))
    """
    import matplotlib
    matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt

    from ..mesh.io import atomic_path
    fig, ax = plt.subplots(figsize=(7, 6))
    plot_exploded(pieces, ax, **kwargs)
    if title:
        ax.set_title(title)
    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=dpi, bbox_inches="tight", format="png")
    plt.close(fig)
