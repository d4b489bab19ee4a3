"""Depth-buffer drawing of millions of facets, decimated, without a Python loop over them.

Each facet is projected onto a plane (`Projected`), tested against the pixel
centres of its bounding box, and a depth buffer keeps, in each pixel, the
facet nearest to a viewer on the side the plane's normal points to. A mesh
with more facets than the picture has pixels is drawn decimated: every facet
wider than two pixels (`add_wide`), and of the others a stratified random
sample as many as the pixels (`sample_facets`), each drawn as points
(corners and centroid) spread over the 3 x 3 pixels around them, the
coverage then closed (dilated and eroded by a pixel), so surfaces show
without holes and silhouettes stay in place; long thin facets are drawn as
points spread evenly over them rather than filled over their boxes, and pits
where a farther surface still shows through a few pixels are closed in the
depth buffer.

See Also
--------
slicelab.viz.preview : split previews drawn this way.
slicelab.viz.partition.exploded_image : exploded views drawn this way.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..geometry.ragged import within_group

__all__ = ["Projected", "sample_facets", "add_wide", "render_projected", "render_depth"]

_FACING = np.array([0.80, 0.80, 0.82])           # facets seen from outside: light grey
_BACK = np.array([0.78, 0.52, 0.33])             # facets seen from inside: terracotta


class Projected:
    """Corners of facets in the plane's frame: (3n, 3) float32 rows of (s, t, depth).

    Single precision is ample for a picture (a micrometre on a metre) and halves the memory
    every pass over a scan's millions of corners reads.

    Parameters
    ----------
    triangles : (n, 3, 3) array_like
    frame : Frame
        The plane: s along ``frame.u``, t along ``frame.v``, depth along ``frame.normal``.
    ids : (m,) int ndarray, optional
        The facets drawn, sorted (a sample); all of them when None.
    """

    def __init__(self, triangles, frame, ids=None):
        t = np.asarray(triangles, dtype=np.float64)
        self.ids = ids  # the facets drawn (indices into `triangles`); None: all of them
        t = (t if ids is None else np.take(t, ids, axis=0)).reshape(-1, 3)
        axes = np.stack([frame.u, frame.v, frame.normal]).T
        shift = frame.origin @ axes
        # Column by column: a BLAS product with an inner size of 3 is slow on millions of rows.
        self.q = np.empty((len(t), 3), np.float32)
        for k in range(3):  # the three plane coordinates
            self.q[:, k] = t[:, 0] * axes[0, k] + t[:, 1] * axes[1, k] + t[:, 2] * axes[2, k] - shift[k]

    def add(self, other: "Projected") -> None:
        """Append the facets of `other` (both decimated: with ids)."""
        self.q = np.concatenate([self.q, other.q])
        self.ids = np.concatenate([self.ids, other.ids])

    def bounds(self) -> np.ndarray:
        """(2, 2) plane-coordinate bounds of the corners."""
        if len(self.q) == 0:
            return np.zeros((2, 2))
        return np.array([[self.q[:, 0].min(), self.q[:, 1].min()], [self.q[:, 0].max(), self.q[:, 1].max()]],
                        dtype=np.float64)


#: Facets handled at once by the size pass of a decimated drawing (keeps each pass in cache).
_CHUNK = 1 << 14


def sample_facets(n: int, budget: int) -> np.ndarray | None:
    """A stratified random sample of `budget` of `n` facet indices (sorted); None when n <= budget.

    One index is drawn in each of `budget` equal runs of indices, seeded by
    `n`, so the same mesh gives the same picture.

    Examples
    --------
    >>> ids = sample_facets(1000, 10)
    >>> len(ids), bool((np.diff(ids) > 0).all()), sample_facets(5, 10) is None
    (10, True, True)
    """
    if n <= budget:
        return None
    rng = np.random.default_rng(n)  # the same picture for the same mesh
    return np.minimum(((np.arange(budget) + rng.random(budget)) * (n / budget)).astype(np.int64), n - 1)


def _wide(triangles: np.ndarray, size: float) -> np.ndarray:
    """Indices of facets with a corner more than `size` (mm, any axis) from their first corner."""
    t = np.asarray(triangles, dtype=np.float64)
    found = []
    for lo in range(0, len(t), _CHUNK):  # over chunks of facets
        c = t[lo:lo + _CHUNK]
        reach = np.zeros(len(c))
        for j in (1, 2):
            for k in range(3):
                np.maximum(reach, np.abs(c[:, j, k] - c[:, 0, k]), out=reach)
        found.append(np.flatnonzero(reach > size) + lo)
    return np.concatenate(found) if found else np.zeros(0, np.int64)


def add_wide(proj: Projected, triangles, frame, pixel: float) -> None:
    """Add to a sampled drawing every facet wider than two pixels (a large face is never left out).

    Parameters
    ----------
    proj : Projected
        A sampled drawing (with ids); left alone when it draws every facet.
    triangles : (n, 3, 3) ndarray
        All the facets `proj` was sampled from.
    frame : Frame
    pixel : float
        Pixel size (mm).
    """
    if proj.ids is None:
        return
    wide = _wide(triangles, 2 * pixel)
    # The sample is sorted: a binary search tells which wide facets it already holds.
    at = np.minimum(np.searchsorted(proj.ids, wide), len(proj.ids) - 1)
    wide = wide[proj.ids[at] != wide]
    if len(wide):
        proj.add(Projected(triangles, frame, wide))


def _spread(best, owner, shape) -> None:
    """Close the drawn points: each pixel takes the nearest of its 3 x 3 neighbours, then the
    coverage is eroded by a pixel (dilation then erosion: holes close, silhouettes stay)."""
    import cv2
    rows, cols = shape
    b, o = best.reshape(rows, cols), owner.reshape(rows, cols)
    nb, no = b.copy(), o.copy()
    for dr in (-1, 0, 1):  # the eight neighbours, not pixels
        for dc in (-1, 0, 1):
            if dr == dc == 0:
                continue
            dst = (slice(max(dr, 0), rows + min(dr, 0)), slice(max(dc, 0), cols + min(dc, 0)))
            src = (slice(max(-dr, 0), rows + min(-dr, 0)), slice(max(-dc, 0), cols + min(-dc, 0)))
            nearer = b[src] > nb[dst]
            nb[dst] = np.where(nearer, b[src], nb[dst])
            no[dst] = np.where(nearer, o[src], no[dst])
    kept = cv2.erode((no >= 0).astype(np.uint8), np.ones((3, 3), np.uint8), borderType=cv2.BORDER_REPLICATE)
    keep = kept.astype(bool) | (o >= 0)  # a drawn pixel is never erased
    best[:] = np.where(keep, nb, -np.inf).reshape(-1)
    owner[:] = np.where(keep, no, -1).reshape(-1)


#: Half-width (pixels) of the square around a pit within which its nearest pixel is found.
_PIT_REACH = 2
#: Rounds of pit closing (a round fills the middle of a longer pit, the next its ends).
_PIT_ROUNDS = 4
#: A crack a pixel wide is closed when the surface in it is this many times `tol` farther.
_CRACK = 2.0


def _close_pits(best, owner, shape, tol: float) -> None:
    """Close the depth buffer's pits: clusters of pixels showing a surface `tol` farther than
    every pixel around them.

    A decimated drawing can leave a few pixels of the nearer surface without
    any point nearby, so that points of a farther surface show through (dark
    dots, or cracks a pixel wide, on a grey surface). A pixel is in such a
    pit when all sixteen pixels two pixels away are covered and nearer by
    more than `tol` (the depth of four pixels), or its two neighbours along
    a row, a column or a diagonal by more than ``_CRACK * tol``: a smooth valley of the depth (the
    inside of a bowl seen at a grazing angle) is not that steep on both
    sides and is left alone, and so is any silhouette. Each pit pixel takes the facet of the nearest
    pixel within ``_PIT_REACH``; rounds repeat while pits are found (the
    middle of a pit three pixels long is found first, then its ends).
    """
    import cv2
    rows, cols = shape
    covered = owner.reshape(rows, cols) >= 0
    if not covered.any():
        return
    d = best.reshape(rows, cols)
    d = np.where(covered, d, np.float32(d[covered].min() - 4 * tol - 1))  # empty: farther than all
    # Both neighbours along a row, a column or a diagonal; and the ring two pixels away.
    kernels = [np.zeros((3, 3), np.uint8) for _ in range(4)]
    for k, (a, b) in zip(kernels, (((1, 0), (1, 2)), ((0, 1), (2, 1)), ((0, 0), (2, 2)), ((0, 2), (2, 0)))):
        k[a] = k[b] = 1
    ring2 = np.ones((5, 5), np.uint8)
    ring2[1:4, 1:4] = 0
    kernels.append(ring2)
    own = owner.reshape(rows, cols)
    for _ in range(_PIT_ROUNDS):  # a few rounds over the whole picture
        crack = cv2.erode(d, kernels[0], borderType=cv2.BORDER_REPLICATE)
        for k in kernels[1:4]:  # three more directions
            np.maximum(crack, cv2.erode(d, k, borderType=cv2.BORDER_REPLICATE), out=crack)
        ring = cv2.erode(d, kernels[4], borderType=cv2.BORDER_REPLICATE)
        r, c = np.nonzero(covered & ((ring - d > tol) | (crack - d > _CRACK * tol)))
        if len(r) == 0:
            break
        top = np.full(len(r), -np.inf, np.float32)
        src_r, src_c = r.copy(), c.copy()
        for dr in range(-_PIT_REACH, _PIT_REACH + 1):  # offsets of the square, not pixels
            for dc in range(-_PIT_REACH, _PIT_REACH + 1):
                rr, cc = np.clip(r + dr, 0, rows - 1), np.clip(c + dc, 0, cols - 1)
                z = d[rr, cc]
                nearer = z > top
                top[nearer], src_r[nearer], src_c[nearer] = z[nearer], rr[nearer], cc[nearer]
        d[r, c] = top
        own[r, c] = own[src_r, src_c]
    best[:] = np.where(covered, d, best.reshape(rows, cols)).reshape(-1)


def render_projected(proj: Projected, normals, frame, extent, shape, block: int, *, dtype=np.float64,
                     facing=_FACING, back=_BACK, depth_out=None) -> np.ndarray:
    """Draw projected facets into a depth buffer and shade the nearest in each pixel.

    Parameters
    ----------
    proj : Projected
    normals : (n, 3) ndarray
        Unit normals of all the facets (indexed by ``proj.ids`` when sampled).
    frame : Frame
    extent : (4,) sequence
        ``(s_min, s_max, t_min, t_max)`` (mm).
    shape : (rows, cols)
    block : int
        Candidates (facet, pixel) filled at once.
    dtype : numpy dtype, default float64
        Floats in [0, 1], or uint8 bytes.
    facing, back : (3,) sequence
        RGB of facets seen from outside and from inside, before shading.
    depth_out : (rows, cols) float32 ndarray, optional
        Receives the depth buffer (-inf where empty).

    Returns
    -------
    (rows, cols, 4) ndarray
        RGBA, row 0 at ``t_max``. A sampled `proj` is drawn decimated, as
        the module describes.
    """
    rows, cols = shape
    out = np.zeros((rows, cols, 4), dtype)
    if len(proj.q) == 0:
        if depth_out is not None:
            depth_out[...] = -np.inf
        return out
    s0, s1, t0, t1 = map(float, extent)
    # Pixel coordinates with pixel centres on integers: x to the right, y downwards.
    x = (proj.q[:, 0] * np.float32(cols / (s1 - s0)) - np.float32(s0 * cols / (s1 - s0) + 0.5)).reshape(-1, 3)
    y = (proj.q[:, 1] * np.float32(-rows / (t1 - t0)) + np.float32(t1 * rows / (t1 - t0) - 0.5)).reshape(-1, 3)
    depth = proj.q[:, 2].reshape(-1, 3)  # larger is nearer the viewer
    best = np.full(rows * cols, -np.inf, dtype=np.float32)
    owner = np.full(rows * cols, -1, dtype=np.int64)
    buf, corners = _Buffer(rows, cols, best, owner), _Corners(x, y, depth)
    # A facet within a pixel of its first corner is drawn as two points, that corner and its
    # centroid: a dense scan has several facets per pixel, and a point costs a fraction of a facet
    # expanded over its pixels. Larger facets are filled.
    reach = np.abs(x[:, 1] - x[:, 0])
    for a, b in ((x, 2), (y, 1), (y, 2)):
        np.maximum(reach, np.abs(a[:, b] - a[:, 0]), out=reach)
    decimated = proj.ids is not None
    # Decimated, points are spread over their 3 x 3 pixels: facets up to three pixels are points.
    small = reach <= (3.0 if decimated else 1.0)
    big = np.flatnonzero(~small)
    if decimated:
        _splat_corners(small, corners, buf)
        big = _splat_slivers(big, reach, corners, buf)
        _spread(best, owner, shape)
    else:
        _splat(small, corners, buf)
    if len(big):
        _fill(big, corners, buf, block)
    if decimated:
        _close_pits(best, owner, shape, 4 * max((s1 - s0) / cols, (t1 - t0) / rows))
    hit = np.flatnonzero(owner >= 0)
    drawn = owner[hit] if proj.ids is None else proj.ids[owner[hit]]
    cos = np.take(np.asarray(normals, dtype=np.float64), drawn, axis=0) @ frame.normal
    light = (0.35 + 0.65 * np.abs(cos))[:, None]
    flat = out.reshape(-1, 4)
    rgb = np.where((cos >= 0)[:, None], np.asarray(facing, dtype=np.float64), np.asarray(back, dtype=np.float64)) * light
    if depth_out is not None:
        depth_out[...] = best.reshape(rows, cols)
    full = 1.0
    if out.dtype == np.uint8:
        rgb, full = np.rint(rgb * 255), 255
    flat[hit, :3] = rgb
    flat[hit, 3] = full
    return out


@dataclass(frozen=True, eq=False)
class _Buffer:
    """A depth buffer of rows x cols pixels, flat: the nearest depth and its facet in each pixel."""

    rows: int
    cols: int
    best: np.ndarray    # (rows * cols,) float32, -inf where empty
    owner: np.ndarray   # (rows * cols,) int64, -1 where empty


@dataclass(frozen=True, eq=False)
class _Corners:
    """The facets' corners in pixel coordinates, (n, 3) each: x to the right, y downwards, depth."""

    x: np.ndarray
    y: np.ndarray
    depth: np.ndarray


def _splat(small, corners: _Corners, buf: _Buffer) -> None:
    """Z-buffer the facets marked `small` as two points each: the first corner and the centroid."""
    f = np.flatnonzero(small)
    third = np.float32(1 / 3)
    xs, ys, zs = corners.x[f], corners.y[f], corners.depth[f]
    for px, py, z in ((xs[:, 0], ys[:, 0], zs[:, 0]), (xs.sum(axis=1) * third, ys.sum(axis=1) * third,
                                                       zs.sum(axis=1) * third)):
        _points(px, py, z, 1, buf, f)


def _splat_corners(small, corners: _Corners, buf: _Buffer) -> None:
    """Z-buffer the facets marked `small` as points: their three corners (one pass over them all)
    and their centroids."""
    f = None
    x, y, depth = corners.x, corners.y, corners.depth
    if not small.all():
        f = np.flatnonzero(small)
        x, y, depth = (np.take(a, f, axis=0) for a in (x, y, depth))  # take: faster than indexing
    third = np.float32(1 / 3)
    _points(x.reshape(-1), y.reshape(-1), depth.reshape(-1), 3, buf, f)
    _points((x[:, 0] + x[:, 1] + x[:, 2]) * third, (y[:, 0] + y[:, 1] + y[:, 2]) * third,
            (depth[:, 0] + depth[:, 1] + depth[:, 2]) * third, 1, buf, f)


#: R2 low-discrepancy sequence steps: points spread evenly over a triangle, in any number.
_R2 = (0.7548776662466927, 0.5698402909980532)


def _splat_slivers(big, reach, corners: _Corners, buf: _Buffer) -> np.ndarray:
    """Draw as points the facets of `big` whose pixel box is mostly empty (long thin facets, such as a
    fan-triangulated cap's: filling tests every pixel of the box); returns the others, to be filled.

    A sliver gets twice as many points as it covers pixels plus twice its length in pixels, spread
    evenly over it (a low-discrepancy sequence, shifted at random for each sliver), so that the
    3 x 3 spread that follows leaves it without gaps.
    """
    if len(big) == 0:
        return big
    x, y, depth = corners.x, corners.y, corners.depth
    xb, yb = np.take(x, big, axis=0).astype(np.float64), np.take(y, big, axis=0).astype(np.float64)
    area = 0.5 * np.abs((xb[:, 1] - xb[:, 0]) * (yb[:, 2] - yb[:, 0]) - (xb[:, 2] - xb[:, 0]) * (yb[:, 1] - yb[:, 0]))
    box = (np.ptp(xb, axis=1) + 1) * (np.ptp(yb, axis=1) + 1)
    thin = box > 8 * area + 64
    if not thin.any():
        return big
    f = big[thin]
    k = (np.ceil(2 * area[thin] + 2 * reach[f]) + 3).astype(np.int64)
    # The sequence is shifted by a random offset for each sliver (the same for the same drawing),
    # so that slivers meeting at a corner do not all leave its neighbourhood empty.
    shift = np.random.default_rng(len(f)).random((len(f), 2))
    j = within_group(k).astype(np.float64)
    local = np.repeat(np.arange(len(f)), k)
    u, v = np.modf(j * _R2[0] + shift[local, 0])[0], np.modf(j * _R2[1] + shift[local, 1])[0]
    fold = u + v > 1  # the square's far half folded onto the triangle
    u[fold], v[fold] = 1 - u[fold], 1 - v[fold]
    fid = f[local]
    u, v = u.astype(np.float32), v.astype(np.float32)
    pts = []
    for a in (x, y, depth):  # the three coordinates
        c = np.take(a, f, axis=0)[local]
        pts.append(c[:, 0] + u * (c[:, 1] - c[:, 0]) + v * (c[:, 2] - c[:, 0]))
    _points(*pts, 1, buf, fid)
    return big[~thin]


def _points(px, py, z, per: int, buf: _Buffer, facets=None) -> None:
    """Z-buffer points in pixel coordinates; point ``i`` belongs to facet ``i // per`` (an index into
    `facets` when given) and is drawn in the pixel whose centre is nearest."""
    if len(px) == 0:
        return
    rows, cols, best, owner = buf.rows, buf.cols, buf.best, buf.owner
    if px.min() >= -0.5 and py.min() >= -0.5 and px.max() < cols - 0.5 and py.max() < rows - 0.5:
        # All inside (as in a split's panels, padded around the drawing): truncation rounds.
        pix = (py + np.float32(0.5)).astype(np.int64) * cols + (px + np.float32(0.5)).astype(np.int64)
        inside = None
    else:
        c, r = np.rint(px).astype(np.int64), np.rint(py).astype(np.int64)
        inside = np.flatnonzero((c >= 0) & (c < cols) & (r >= 0) & (r < rows))
        pix, z = r[inside] * cols + c[inside], z[inside]
    np.maximum.at(best, pix, z)
    win = np.flatnonzero(z == best[pix])
    point = win if inside is None else inside[win]
    fid = point // per if per > 1 else point
    owner[pix[win]] = fid if facets is None else facets[fid]


def _fill(f, corners: _Corners, buf: _Buffer, block: int) -> None:
    """Z-buffer facets `f` over every pixel centre inside them (edge functions), in blocks."""
    rows, cols, best, owner = buf.rows, buf.cols, buf.best, buf.owner
    x, y, depth = (a[f].astype(np.float64) for a in (corners.x, corners.y, corners.depth))
    c_lo = np.clip(np.ceil(x.min(axis=1)), 0, cols).astype(np.int64)
    c_hi = np.clip(np.floor(x.max(axis=1)), -1, cols - 1).astype(np.int64)
    r_lo = np.clip(np.ceil(y.min(axis=1)), 0, rows).astype(np.int64)
    r_hi = np.clip(np.floor(y.max(axis=1)), -1, rows - 1).astype(np.int64)
    w = np.maximum(c_hi - c_lo + 1, 0)
    count = w * np.maximum(r_hi - r_lo + 1, 0)
    live = np.flatnonzero(count > 0)  # facets that hold at least one pixel centre in their box
    if len(live) == 0:
        return
    ends = np.searchsorted(np.cumsum(count[live]), np.arange(block, int(count[live].sum()) + block, block))
    start = 0
    for stop in np.unique(np.minimum(ends + 1, len(live))):  # over blocks of facets, not facets
        sel = live[start:stop]
        start = stop
        if len(sel) == 0:
            continue
        k = count[sel]
        local = np.repeat(sel, k)
        fid = f[local]
        j = within_group(k)
        px = c_lo[local] + j % w[local]
        py = r_lo[local] + j // w[local]
        # Edge functions: the pixel centre is inside when all three have the facet's orientation.
        xa, ya = x[local], y[local]
        e0 = (xa[:, 1] - xa[:, 0]) * (py - ya[:, 0]) - (ya[:, 1] - ya[:, 0]) * (px - xa[:, 0])
        e1 = (xa[:, 2] - xa[:, 1]) * (py - ya[:, 1]) - (ya[:, 2] - ya[:, 1]) * (px - xa[:, 1])
        e2 = (xa[:, 0] - xa[:, 2]) * (py - ya[:, 2]) - (ya[:, 0] - ya[:, 2]) * (px - xa[:, 2])
        total = e0 + e1 + e2
        inside = (((e0 >= 0) & (e1 >= 0) & (e2 >= 0)) | ((e0 <= 0) & (e1 <= 0) & (e2 <= 0))) & (total != 0)
        fid, pix = fid[inside], (py * cols + px)[inside]
        # Depth at the pixel centre from the barycentric weights (e1 weighs corner 0, e2 corner 1).
        dz = depth[local[inside]]
        z = ((e1[inside] * dz[:, 0] + e2[inside] * dz[:, 1] + e0[inside] * dz[:, 2]) / total[inside]).astype(np.float32)
        cand = np.full(rows * cols, -np.inf, dtype=np.float32)
        np.maximum.at(cand, pix, z)
        win = (z == cand[pix]) & (z > best[pix])
        best[pix[win]] = z[win]
        owner[pix[win]] = fid[win]


def render_depth(triangles, normals, frame, extent, shape, *, block: int = 4_000_000,
                 decimate: bool | int = True, colour=None, with_depth: bool = False):
    """Shade of the facet nearest the viewer in each pixel (orthographic, along -normal).

    Facets that cover pixel centres are expanded over the pixels of their
    bounding box and tested with edge functions, in blocks of about `block`
    candidates; facets smaller than a pixel (a dense scan's) are drawn as two
    points each (first corner and centroid), a few operations per facet. A
    depth buffer keeps the nearest. With more facets than pixels (and
    `decimate`), the drawing is decimated as the module describes.

    Parameters
    ----------
    triangles : (n, 3, 3) ndarray
    normals : (n, 3) ndarray
        Unit facet normals (for shading and to tell outside from inside).
    frame : Frame
        The plane; the viewer looks along ``-frame.normal``.
    extent : (4,) sequence
        ``(s_min, s_max, t_min, t_max)`` of the image in plane coordinates (mm).
    shape : (rows, cols)
    block : int
        Candidates (facet, pixel) handled at once; bounds the memory used.
    decimate : bool or int, default True
        Draw a mesh of more facets than pixels (or than this number) from a
        sample (every facet wider than two pixels kept); False draws every facet.
    colour : (3,) sequence, optional
        RGB in [0, 1] of every facet, shaded; by default facets seen from
        outside are light grey and those seen from inside terracotta.
    with_depth : bool, default False
        Also return the depth buffer.

    Returns
    -------
    (rows, cols, 4) float ndarray
        RGBA, row 0 at ``t_max`` (as `imshow` draws it with ``origin="upper"``);
        transparent where no facet projects.
    (rows, cols) float32 ndarray
        With `with_depth`: each pixel's distance along ``frame.normal`` from
        the plane (larger is nearer the viewer), -inf where no facet projects.

    Examples
    --------
    >>> from slicelab.samples import box
    >>> from slicelab.geometry import Frame
    >>> m = box((0, 0, 0), (1, 1, 1))
    >>> img = render_depth(m.triangles, m.normals, Frame.from_plane((0, 0, 0), (0, 0, 1)),
    ...                    (-1, 2, -1, 2), (30, 30))
    >>> img.shape, float(img[..., 3].sum())  # the unit square: 10 x 10 pixels of 0.1 mm
    ((30, 30, 4), 100.0)
    """
    s0, s1, t0, t1 = map(float, extent)
    rows, cols = shape
    pixel = max((s1 - s0) / cols, (t1 - t0) / rows)
    budget = rows * cols if decimate is True else int(decimate)
    proj = Projected(triangles, frame, sample_facets(len(triangles), max(budget, 1)) if decimate else None)
    add_wide(proj, triangles, frame, pixel)
    depth = np.empty(shape, np.float32) if with_depth else None
    facing, back = (_FACING, _BACK) if colour is None else (colour, colour)
    img = render_projected(proj, normals, frame, extent, shape, block, facing=facing, back=back, depth_out=depth)
    return (img, depth) if with_depth else img
