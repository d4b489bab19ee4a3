"""Scanned artefacts: axis alignment, profile drawings and measurements of vessels.

A scan comes in whatever pose the scanner left it (seed 000 cut an unaligned
pot and got a meaningless section). `align` finds the axis of revolution and
moves the vessel so that the axis is +z through the origin, rim up, base at
z = 0. `profile` then cuts it through the axis at several meridional angles,
keeps each half-section (one side of the axis) as an (r, z) polygon, picks the
most typical half as the drawn profile, measures the vessel and draws it the
way archaeologists do: axis line, section filled black on one side, exterior
outline on the other, rim line, scale bar, label; 1:1 in mm.

How the axis is found
---------------------
1. Principal axes of the surface (exact area moments): for a body of
   revolution two eigenvalues are equal and the third stands apart.
2. The normals of a surface of revolution all meet its axis. In Plücker
   coordinates a facet's normal line is (n, p x n) and it meets the axis
   (a, c x a) when ``n . (c x a) + (p x n) . a = 0``, which is linear in the
   axis: the least-squares axis is the smallest eigenvector of a 6x6 problem
   (Pottmann & Wallner's linear line complexes).
3. Refinement: horizontal sections in the frame of the current axis are fitted
   with concentric circles (one shared centre per height, a radius per wall);
   a straight line through the centres is the new axis; repeat. Outer walls
   run counter-clockwise and inner walls clockwise (`slicelab.slicing.sections`), which
   tells the walls apart without any tolerance.
The candidate with the smaller circle residual wins. The rim goes up: the end
where surface crosses the axis (the base) goes down; failing that, the open
boundary marks the rim; failing that, the centre of mass goes down.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..geometry.polygons import signed_area
from ..mesh.core import Mesh
from ..slicing.sections import section, slice_layers

__all__ = ["Alignment", "align", "rotation_to_z", "HalfProfile", "Measurements", "Profile", "profile",
           "half_profiles", "pappus_volume", "clip_ring"]

_FIT_FACETS = 300_000     # facets sampled for fitting the axis; enough for a 0.01 degree fit
_UP = math.cos(math.radians(35))  # an edge "faces up/down" within 35 degrees of vertical
_NOT_REVOLUTION = 0.03    # relative circle residual above which a shape is not of revolution
_NOT_TYPICAL = 0.05       # half-sections further apart than this share of the radius: no one profile


# ------------------------------------------------------------------ alignment
@dataclass(frozen=True, eq=False)
class Alignment:
    """A mesh moved so that its axis of revolution is +z through the origin, rim up, base at z = 0.

    Attributes
    ----------
    mesh : Mesh
        The moved mesh (``input.transformed(matrix)``).
    matrix : (4, 4) ndarray
        Homogeneous rigid motion from input to aligned coordinates.
    axis : (3,) ndarray
        Unit axis direction in input coordinates, pointing from base to rim.
    origin : (3,) ndarray
        Where the axis meets the base plane, in input coordinates.
    residual : float
        RMS distance (mm) of horizontal sections from circles about the axis:
        how far the shape is from a surface of revolution.
    relative_residual : float
        `residual` divided by the mean radius of those circles.
    up_from : str
        The cue that decided which end is the rim: ``"base"``,
        ``"open boundary"`` or ``"centre of mass"``.
    method : str
        Which start won: ``"normals"`` (line complex) or ``"principal axes"``.
    """

    mesh: Mesh
    matrix: np.ndarray
    axis: np.ndarray
    origin: np.ndarray
    residual: float
    relative_residual: float
    up_from: str
    method: str

    @property
    def is_revolution(self) -> bool:
        """True when horizontal sections stay within 3 % (RMS, of the radius) of circles about the axis."""
        return bool(self.relative_residual <= _NOT_REVOLUTION)

    def __repr__(self) -> str:
        return (f"Alignment(axis={np.round(self.axis, 6).tolist()}, residual={self.residual:.4g} mm "
                f"({100 * self.relative_residual:.3g} %), up from {self.up_from}, {self.method})")

    def to_dict(self) -> dict:
        """Plain numbers for JSON (the mesh left out)."""
        return {"matrix": self.matrix.tolist(), "axis": self.axis.tolist(), "origin": self.origin.tolist(),
                "residual": self.residual, "relative_residual": self.relative_residual,
                "up_from": self.up_from, "method": self.method}


def rotation_to_z(direction) -> np.ndarray:
    """The smallest rotation (3 x 3) taking `direction` onto +z.

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


def _fit_sample(triangles: np.ndarray) -> np.ndarray:
    """A deterministic random subset of facets; area statistics of a sample are unbiased."""
    n = len(triangles)
    if n <= _FIT_FACETS:
        return triangles
    keep = np.random.default_rng(0).random(n) < _FIT_FACETS / n
    return triangles[keep]


def _surface_moments(t: np.ndarray):
    """Area, centroid and exact second-moment (covariance) matrix of a triangle surface."""
    a, b, c = t[:, 0], t[:, 1], t[:, 2]
    cr = np.cross(b - a, c - a)
    area = 0.5 * np.sqrt(np.einsum("ij,ij->i", cr, cr))
    total = float(area.sum())
    if not total > 0:
        raise ValueError("the mesh has no area to align")
    centroid = (area[:, None] * (a + b + c)).sum(axis=0) / (3 * total)
    a, b, c = a - centroid, b - centroid, c - centroid
    s = a + b + c
    # Exact: the integral of x x^T over a triangle is A/12 (sum v v^T + s s^T).
    m = (np.einsum("n,ni,nj->ij", area, a, a) + np.einsum("n,ni,nj->ij", area, b, b)
         + np.einsum("n,ni,nj->ij", area, c, c) + np.einsum("n,ni,nj->ij", area, s, s)) / 12.0
    return area, centroid, m / total


def _principal_axis(cov: np.ndarray) -> np.ndarray:
    w, v = np.linalg.eigh(cov)
    # The eigenvalue that stands apart from the other two belongs to the axis.
    return v[:, 0] if (w[1] - w[0]) > (w[2] - w[1]) else v[:, 2]


def _normal_lines_axis(t: np.ndarray, area: np.ndarray, centroid: np.ndarray, scale: float):
    """Least-squares line that the facets' normal lines meet (linear line complex)."""
    p = (t.sum(axis=1) / 3.0 - centroid) / scale
    n = np.cross(t[:, 1] - t[:, 0], t[:, 2] - t[:, 0])
    length = np.sqrt(np.einsum("ij,ij->i", n, n))
    ok = length > 0
    n = n[ok] / length[ok, None]
    p, w = p[ok], area[ok]
    lines = np.hstack([np.cross(p, n), n])  # residual = lines @ [a, a_bar]
    wk = w
    for _ in range(4):  # reweighted: handles, spouts and lugs, whose normals miss the axis, lose their say
        M = np.einsum("n,ni,nj->ij", wk, lines, lines)
        A, B, C = M[:3, :3], M[:3, 3:], M[3:, 3:]
        # Minimise over a_bar for each a, then over unit a: a Schur complement eigenproblem.
        Cinv = np.linalg.pinv(C)
        S = A - B @ Cinv @ B.T
        _, vec = np.linalg.eigh((S + S.T) / 2)
        a = vec[:, 0]
        a_bar = -Cinv @ B.T @ a
        wk = _tukey(lines @ np.concatenate([a, a_bar]), w, 1e-9)
    point = np.cross(a, a_bar)  # foot of the axis line (direction a, moment a_bar) on the origin
    return centroid + scale * point, a


def _tukey(e: np.ndarray, w: np.ndarray, floor: float) -> np.ndarray:
    """Weights `w` times Tukey's biweight of residuals `e`: beyond 4.685 robust sigmas, no say."""
    sigma = max(1.4826 * float(np.median(np.abs(e))), floor)
    u = e / (4.685 * sigma)
    return w * np.where(np.abs(u) < 1, (1 - u * u) ** 2, 0.0)


def _rings(points: np.ndarray, direction: np.ndarray, weight: np.ndarray, centre: np.ndarray):
    """Group one horizontal section's points into walls: by winding sense, then by radial gaps."""
    rel = points - centre
    ccw = rel[:, 0] * direction[:, 1] - rel[:, 1] * direction[:, 0] > 0
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
            if len(part) >= 8 and weight[part].sum() > 0 and len(sector) >= 12:
                label[part] = k
                k += 1
    return label, k


def _circle_pass(t: np.ndarray, point: np.ndarray, direction: np.ndarray, n_planes: int = 16):
    """Fit concentric circles to horizontal sections in the frame of an axis guess.

    Returns the line through the fitted centres (point, direction, in input
    coordinates) and (RMS radial residual about that line, the same relative
    to the mean radius, median relative deviation), or None when no section
    has a usable wall.
    """
    R = rotation_to_z(direction)
    local = np.einsum("...j,ij->...i", t - point, R)
    z = local[..., 2]
    z0, z1 = float(z.min()), float(z.max())
    if not z1 > z0:
        return None
    heights = z0 + (z1 - z0) * np.linspace(0.1, 0.9, n_planes)
    layers = slice_layers(Mesh(local), heights=heights, max_gap=0.0)
    fits = []
    for h, s in zip(heights, layers):  # over planes
        seg = s.segments
        if len(seg) < 4:
            continue
        # Simpson's rule along each segment: its ends and middle, weights 1/6, 4/6, 1/6 of its length,
        # so a long chord (a box's side) counts for the radii along it, not only at its corners.
        d = np.tile(seg[:, 1] - seg[:, 0], (3, 1))
        p = np.concatenate([seg[:, 0], seg.mean(axis=1), seg[:, 1]])
        length = np.hypot(d[:, 0], d[:, 1])
        w = length * np.repeat([1 / 6, 4 / 6, 1 / 6], len(seg))
        label, k = _rings(p, d, w, np.zeros(2))
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
            wk = _tukey(e, w, 1e-9 * float(radius.mean()) + 1e-300)
        fits.append((h, sol[0], sol[1], wk.sum(), p, w, label, k))
    if len(fits) < 2:
        return None
    h, cx, cy, W = (np.array([f[i] for f in fits]) for i in range(4))
    Wk = W
    for _ in range(3):  # reweighted over planes too: a height through a handle may still stray
        G = np.stack([np.ones_like(h), h], axis=1) * np.sqrt(Wk)[:, None]
        (x0, kx), (y0, ky) = (np.linalg.lstsq(G, c * np.sqrt(Wk), rcond=None)[0] for c in (cx, cy))
        Wk = _tukey(np.hypot(cx - (x0 + kx * h), cy - (y0 + ky * h)), W, 1e-9 * (z1 - z0))
        if not Wk.sum() > 0:
            Wk = W
            break
    # Residual of the revolution model: radii about the fitted line, one radius per wall.
    errors, weights, rsum = [], [], 0.0
    for (hj, _, _, _, p, w, label, k) in fits:  # over planes
        r = np.hypot(p[:, 0] - (x0 + kx * hj), p[:, 1] - (y0 + ky * hj))
        radius = np.bincount(label, w * r, k) / np.bincount(label, w, k)
        errors.append(r - radius[label])
        weights.append(w)
        rsum += float((w * radius[label]).sum())
    e, w = np.abs(np.concatenate(errors)), np.concatenate(weights)
    rms = math.sqrt(float((w * e * e).sum() / w.sum()))
    mean_r = rsum / w.sum()
    # The median deviation judges between axes: a spout or a handle moves the RMS, not the median.
    o = np.argsort(e)
    median = float(e[o][np.searchsorted(np.cumsum(w[o]), 0.5 * w.sum())])
    new_dir = R.T @ np.array([kx, ky, 1.0])
    new_dir /= np.linalg.norm(new_dir)
    return point + R.T @ np.array([x0, y0, 0.0]), new_dir, (rms, rms / mean_r, median / mean_r)


def _refine(t, point, direction, iterations: int = 6):
    """Repeat circle passes from an axis guess; keep the axis with the smallest residual seen.

    On a true body of revolution every pass improves and the passes converge;
    on a teapot (spout, handle) they can wander, and the best one is kept.
    """
    best = (point, direction, None)
    for _ in range(iterations):  # a few fixed-point passes
        fit = _circle_pass(t, point, direction)
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


def _up_sign(t: np.ndarray, area: np.ndarray, point: np.ndarray, direction: np.ndarray, mesh: Mesh):
    """+1 if the rim lies towards +direction, -1 if not; and the cue that decided."""
    c = t.sum(axis=1) / 3.0 - point
    h = c @ direction
    corners = t - point
    hc = corners @ direction
    rc = np.linalg.norm(corners - hc[..., None] * direction, axis=2)
    lo, hi = float(hc.min()), float(hc.max())
    mid, length = (lo + hi) / 2, hi - lo
    near = rc.min(axis=1) < 0.15 * float(rc.max())  # facets reaching close to the axis
    if area[near].sum() > 0.002 * area.sum():
        # Surface crossing the axis is the base (a rim is a ring, away from the axis).
        m = float((area[near] * h[near]).sum() / area[near].sum())
        if abs(m - mid) > 0.1 * length:
            return (1 if m < mid else -1), "base"
    from ..geometry.topology import edge_table, weld
    _, faces = weld(mesh.triangles)
    et = edge_table(faces)
    open_edges = np.flatnonzero(et["counts"] == 1)
    if len(open_edges):
        f = et["first"][open_edges]
        tri, k = f // 3, f % 3
        a = mesh.triangles[tri, k]
        b = mesh.triangles[tri, (k + 1) % 3]
        w = np.linalg.norm(b - a, axis=1)
        m = float((w * (((a + b) / 2 - point) @ direction)).sum() / w.sum())
        if abs(m - mid) > 0.1 * length:
            return (1 if m > mid else -1), "open boundary"
    # The centre of mass of the enclosed volume (or of the surface, if open) sits low.
    from ..mesh.validation import signed_volume
    vol = signed_volume(mesh.triangles)
    if vol > 0:
        tt = mesh.triangles - point
        v6 = np.einsum("ij,ij->i", tt[:, 0], np.cross(tt[:, 1], tt[:, 2]))
        com_h = float((v6 * ((tt.sum(axis=1) / 4.0) @ direction)).sum() / v6.sum())
    else:
        com_h = float((area * h).sum() / area.sum())
    return (1 if com_h <= mid else -1), "centre of mass"


def align(mesh: Mesh) -> Alignment:
    """Move a scanned vessel so its axis of revolution is +z through the origin, rim up, base at z = 0.

    Parameters
    ----------
    mesh : Mesh
        A vessel (or any body of revolution) in any position; open scans,
        noise and missing sherds are fine.

    Returns
    -------
    Alignment

    Raises
    ------
    ValueError
        The mesh has too few facets or no area.

    Examples
    --------
    >>> import numpy as np
    >>> from slicelab.samples import pot
    >>> m = pot(20, 24)
    >>> tilt = np.eye(4); tilt[:3, :3] = rotation_to_z([1, 2, 2]).T; tilt[:3, 3] = [5, -7, 3]
    >>> a = align(m.transformed(tilt))
    >>> np.round(a.axis * 3, 3).tolist(), np.round(a.mesh.bounds[:, 2], 1).tolist()
    ([1.0, 2.0, 2.0], [0.0, 120.0])
    """
    if len(mesh) < 4:
        raise ValueError(f"cannot align a mesh of {len(mesh)} facets")
    t = _fit_sample(mesh.triangles)
    area, centroid, cov = _surface_moments(t)
    scale = math.sqrt(float(np.trace(cov))) or 1.0
    # Starts in order of trust; the next is tried only while the best fit is poor (over 1 %), and
    # never twice in one basin. The other two principal axes come last: a jug's handle can make
    # the wrong eigenvalue stand apart.
    _, eig = np.linalg.eigh(cov)
    apart = _principal_axis(cov)
    starts = [("normals", _normal_lines_axis(t, area, centroid, scale)), ("principal axes", (centroid, apart))]
    starts += [("principal axes", (centroid, v)) for v in eig.T if abs(float(v @ apart)) < 0.5]
    results, tried = [], []
    for name, (p, d) in starts:  # at most four starts, a few passes each
        fits = [r[3][2] for r in results if r[3] is not None]
        if fits and min(fits) <= 0.01:
            break
        if any(abs(float(d @ e)) > math.cos(math.radians(3)) for e in tried):
            continue
        tried.append(d)
        results.append((name, *_refine(t, p, d)))
        tried.append(results[-1][2])
    fitted = [r for r in results if r[3] is not None]
    if fitted:
        method, point, direction, (rms, rel, _) = min(fitted, key=lambda r: r[3][2])
    else:
        method, point, direction, _ = results[0]
        rms = rel = math.inf
    direction = direction / np.linalg.norm(direction)
    sign, cue = _up_sign(t, area, point, direction, mesh)
    direction = sign * direction
    R = rotation_to_z(direction)
    # Rotated by einsum, not matmul: numpy hands (n, 3) x (3, 3) to a threaded BLAS, which on a
    # busy machine ran 10-20x slower (15 M points: 5-8 s against 0.5 s).
    moved = np.einsum("...j,ij->...i", mesh.triangles, R) - R @ point
    z0 = float(moved[..., 2].min())
    moved[..., 2] -= z0  # the lowest corner lands exactly on z = 0
    origin = point + z0 * direction
    matrix = np.eye(4)
    matrix[:3, :3] = R
    matrix[:3, 3] = -R @ origin
    # A proper rotation keeps the winding and moves normals as it moves points.
    normals = np.einsum("...j,ij->...i", mesh.file_normals, R)
    return Alignment(Mesh(moved, normals), matrix, direction, origin, float(rms), float(rel), cue, method)


_align = align  # `profile` has a parameter called align


# ------------------------------------------------------------------- profiles
def clip_ring(ring: np.ndarray, axis: int = 0, keep_below: bool = False, at: float = 0.0) -> np.ndarray:
    """Clip a closed ring to the half-plane ``x[axis] >= at`` (or ``<=``), keeping its orientation.

    Sutherland-Hodgman against one line: a concave ring stays one ring (pieces
    joined by zero-width bridges along the line, which add no area).

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


def pappus_volume(ring: np.ndarray) -> float:
    """Volume swept by a closed (r, z) ring turned once about the z axis (Pappus).

    ``2 pi`` times the ring's first moment about the axis, exact for a polygon;
    positive for a counter-clockwise ring.

    Examples
    --------
    >>> round(pappus_volume(np.array([[0, 0], [1, 0], [1, 1], [0, 1]], float)) / np.pi, 12)
    1.0
    """
    p = np.asarray(ring, dtype=np.float64)
    if len(p) < 3:
        return 0.0
    r, z = p[:, 0], p[:, 1] - p[:, 1].mean()
    r1, z1 = np.roll(r, -1), np.roll(z, -1)
    return float(2 * np.pi * ((r + r1) * (r * z1 - r1 * z)).sum() / 6.0)


@dataclass(frozen=True, eq=False)
class HalfProfile:
    """One side of a section through the axis, in (r, z): r >= 0 away from the axis, z up.

    Attributes
    ----------
    angle : float
        Direction of this half-plane about the axis (radians, from +x).
    polygon : (k, 2) ndarray
        The wall's section, counter-clockwise (material on the left).
    holes : tuple of (k, 2) ndarray
        Voids inside the wall (clockwise).
    outer : (k, 2) ndarray
        Exterior outline, from the rim's outer edge down to the axis (or the lowest point).
    inner : (k, 2) ndarray
        Interior outline, from the rim's inner edge down to the axis (or the lowest point).
    top : int
        Index in `polygon` of the highest point (where the rim is).
    """

    angle: float
    polygon: np.ndarray
    holes: tuple
    outer: np.ndarray
    inner: np.ndarray
    top: int

    @property
    def area(self) -> float:
        """Section area (mm^2)."""
        return signed_area(self.polygon) + sum(signed_area(h) for h in self.holes)


def _split_chains(ring: np.ndarray, axis_tol: float):
    """Split a counter-clockwise (r, z) ring at its top into exterior and interior outlines."""
    k = len(ring)
    top = int(np.argmax(ring[:, 1]))
    d = np.roll(ring, -1, axis=0) - ring  # edge e runs from ring[e] to ring[e + 1]
    length = np.hypot(d[:, 0], d[:, 1])
    nz = np.divide(-d[:, 0], length, out=np.zeros(k), where=length > 0)  # outward normal (dz, -dr)
    up = nz >= _UP
    on_axis = ring[:, 0] <= axis_tol
    fwd = (top + np.arange(k)) % k          # ring indices walking forward from the top
    bwd = (top - np.arange(k)) % k          # and backward
    # The rim: edges that face up on either side of the top point.
    n_in = int(np.argmin(up[fwd])) if not up.all() else 0
    n_out = int(np.argmin(up[(bwd - 1) % k])) if not up.all() else 0
    if on_axis.any():
        stop_in = int(np.argmax(on_axis[fwd[n_in:]])) + n_in if on_axis[fwd[n_in:]].any() else k - 1
        stop_out = int(np.argmax(on_axis[bwd[n_out:]])) + n_out if on_axis[bwd[n_out:]].any() else k - 1
    else:
        low = int(np.argmin(ring[:, 1]))
        stop_in = int((low - top) % k)
        stop_out = int((top - low) % k)
    inner = ring[fwd[n_in:max(stop_in, n_in) + 1]]
    outer = ring[bwd[n_out:max(stop_out, n_out) + 1]]
    return outer, inner, top


def half_profiles(mesh: Mesh, angle: float, *, max_gap: float = 1.0, candidates=None) -> list[HalfProfile]:
    """Both halves of the section of an aligned mesh by the vertical plane through z at `angle`.

    Parameters
    ----------
    mesh : Mesh
        Aligned: axis of revolution along +z through the origin.
    angle : float
        Radians; the halves point along ``(cos a, sin a)`` and the opposite way.
    max_gap : float
        As in `slicelab.section`.
    candidates : (n,) int ndarray, optional
        Facets that may cross the plane (a superset); the others are skipped.

    Returns
    -------
    list of HalfProfile
        Zero, one or two halves; a plane whose section has open chains (a hole
        in the scan) gives none.

    Examples
    --------
    >>> from slicelab.samples import pot
    >>> h = half_profiles(pot(20, 24), 0.0)
    >>> len(h), round(float(h[0].polygon[:, 0].max()), 3)
    (2, 61.937)
    """
    c, s = math.cos(angle), math.sin(angle)
    sub = mesh if candidates is None else Mesh(mesh.triangles[candidates])
    # Normal (sin a, -cos a, 0): the frame's u = v x normal then points along (cos a, sin a).
    sec = section(sub, (0.0, 0.0, 0.0), (s, -c, 0.0), max_gap=max_gap)
    if sec.open_chains or not sec.loops:
        return []
    scale = float(np.abs(sec.bounds()).max()) or 1.0
    out = []
    for side, a in ((1.0, angle), (-1.0, angle + math.pi)):
        best, best_area, holes = None, 0.0, []
        for poly in sec.polygons:  # over the section's few polygons
            ext = clip_ring(poly.exterior, 0, keep_below=side < 0)
            if len(ext) < 3:
                continue
            ext = np.column_stack([side * ext[:, 0], ext[:, 1]])
            if side < 0:
                ext = ext[::-1]
            area = signed_area(ext)
            if area > best_area:
                hs = []
                for h in poly.holes:
                    hc = clip_ring(h, 0, keep_below=side < 0)
                    if len(hc) >= 3:
                        hc = np.column_stack([side * hc[:, 0], hc[:, 1]])
                        hs.append(hc[::-1] if side < 0 else hc)
                best, best_area, holes = ext, area, hs
        if best is None or best_area <= 0:
            continue
        # Points on the axis (clipped there, or poles a rounding error off it) sit exactly at r = 0.
        tol = 1e-9 * scale
        best = np.where((best[:, 0] <= tol)[:, None], np.column_stack([np.zeros(len(best)), best[:, 1]]), best)
        # A vertex lying in the plane is met by two facets: drop repeats a rounding error apart.
        best = best[np.abs(best - np.roll(best, 1, axis=0)).max(axis=1) > tol]
        if len(best) < 3:
            continue
        outer, inner, top = _split_chains(best, 0.0)
        out.append(HalfProfile(float(a % (2 * math.pi)), best, tuple(holes), outer, inner, top))
    return out


def _resample(chain: np.ndarray, step: float):
    """Points about every `step` along a polyline, their arc-length weights and source edges."""
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


def _edge_facing(chain: np.ndarray, reverse: bool) -> np.ndarray:
    """Outward normal z-component of each edge of a chain cut from a CCW ring."""
    d = np.diff(chain, axis=0)
    if reverse:  # the chain walks the ring backwards
        d = -d
    length = np.hypot(d[:, 0], d[:, 1])
    return np.divide(-d[:, 0], length, out=np.zeros(len(d)), where=length > 0)


def _wall_thickness(half: HalfProfile, step: float):
    """Perpendicular wall thickness along the interior outline (floor and rim excluded).

    Each interior sample's distance to the nearest of the exterior's samples,
    taken `step` apart: off the true distance d by at most step^2 / 8d.
    """
    from scipy.spatial import cKDTree
    inner, outer = half.inner, half.outer
    if len(inner) < 2 or len(outer) < 2:
        return np.zeros(0), np.zeros(0)
    o_pts, _, o_edge = _resample(outer, step)
    # The underside of the base is not wall: leave out interior points nearest to it.
    underside = _edge_facing(outer, reverse=True)[o_edge] <= -_UP
    pts, wts, i_edge = _resample(inner, step)
    wall = _edge_facing(inner, reverse=False)[i_edge] < _UP  # the floor faces up
    pts, wts = pts[wall], wts[wall]
    if len(pts) == 0:
        return np.zeros(0), np.zeros(0)
    dist, idx = cKDTree(o_pts).query(pts)
    keep = ~underside[idx]
    return dist[keep], wts[keep]


def _rms_distance(a: np.ndarray, b: np.ndarray, tree_a, tree_b) -> float:
    """Symmetric RMS of nearest-point distances between two point sets."""
    da = tree_b.query(a)[0]
    db = tree_a.query(b)[0]
    return float(math.sqrt((np.mean(da ** 2) + np.mean(db ** 2)) / 2))


@dataclass(frozen=True)
class Measurements:
    """A vessel's measurements from its half-sections (mm, mm^3).

    Diameters, heights and thicknesses are medians over the half-sections (a
    handle in one half does not move them); volumes are means (uniform angles:
    the mean is a quadrature of the volume integral in cylindrical
    coordinates, handle included). Wall thickness is perpendicular (what calipers give), pooled
    over every half, floor and rim excluded. Capacity is the cavity filled to
    the lowest rim top, by Pappus' theorem.
    """

    height: float
    rim_diameter: float
    max_diameter: float
    max_diameter_height: float
    base_diameter: float
    wall_thickness_min: float
    wall_thickness_mean: float
    wall_thickness_max: float
    base_thickness: float
    capacity: float
    clay_volume: float
    halves: int
    spread: float
    residual: float

    def to_dict(self) -> dict:
        """Plain floats (NaN where a measurement does not apply)."""
        return {k: getattr(self, k) for k in self.__dataclass_fields__}

    def __str__(self) -> str:
        rows = [("height", self.height, "mm"), ("rim diameter", self.rim_diameter, "mm"),
                ("max diameter", self.max_diameter, "mm"),
                ("  at height", self.max_diameter_height, "mm"),
                ("base diameter", self.base_diameter, "mm"),
                ("wall min/mean/max", None, "mm"), ("base thickness", self.base_thickness, "mm"),
                ("capacity", self.capacity / 1e6, "l"), ("clay volume", self.clay_volume / 1e3, "cm3"),
                ("half-sections", self.halves, ""), ("spread", self.spread, "mm"),
                ("axis residual", self.residual, "mm")]
        out = []
        for name, v, unit in rows:
            if v is None:
                text = (f"{self.wall_thickness_min:.3f} / {self.wall_thickness_mean:.3f} / "
                        f"{self.wall_thickness_max:.3f}")
            else:
                text = f"{v:.6g}" if isinstance(v, float) else str(v)
            out.append(f"{name:<18}{text} {unit}".rstrip())
        return "\n".join(out)


def _base_thickness(half: HalfProfile, underside: np.ndarray) -> float:
    """Floor height minus underside height, averaged over the inner half of the base's radius.

    Averaged rather than read at the axis alone, where one noisy vertex on
    each side would decide it.
    """
    inner = half.inner
    up = _edge_facing(inner, reverse=False)[::-1] >= _UP
    run = int(np.argmin(up)) if not up.all() else len(up)
    floor = inner[::-1][: run + 1]  # from the axis outwards, while the interior faces up
    r_lim = 0.5 * min(float(floor[:, 0].max()), float(underside[:, 0].max()))
    if len(floor) < 2 or len(underside) < 2 or not r_lim > 0:
        on_axis = half.polygon[half.polygon[:, 0] == 0, 1]
        return float(on_axis.max() - on_axis.min())
    r = np.linspace(0.0, r_lim, 65)

    def height(chain):
        o = np.argsort(chain[:, 0], kind="stable")
        return np.interp(r, chain[o, 0], chain[o, 1])

    return float(np.mean(height(floor) - height(underside)))


def _measure(halves: list[HalfProfile], height: float, spread: float, residual: float) -> Measurements:
    nan = float("nan")
    rim, rmax, zmax, base, base_t, clay = [], [], [], [], [], []
    thick, thick_w = [], []
    step = max(height, 1e-9) / 2000
    for h in halves:  # over half-sections (tens)
        ring = h.polygon
        rim.append(h.outer[0, 0] if len(h.outer) else nan)
        k = int(np.argmax(ring[:, 0]))
        rmax.append(ring[k, 0])
        zmax.append(ring[k, 1])
        # Footprint: the exterior's downward-facing run at its bottom end.
        face = _edge_facing(h.outer, reverse=True)
        down = face[::-1] <= -_UP
        run = int(np.argmin(down)) if not down.all() else len(down)
        base.append(h.outer[::-1][run, 0] if len(h.outer) else nan)
        if (ring[:, 0] == 0).sum() >= 2:
            base_t.append(_base_thickness(h, h.outer[::-1][: run + 1]))
        clay.append(pappus_volume(ring) + sum(pappus_volume(x) for x in h.holes))
        t, w = _wall_thickness(h, step)
        thick.append(t)
        thick_w.append(w)
    # Capacity: fill to the lowest rim top, i.e. the level where it would spill.
    level = min(float(h.polygon[:, 1].max()) for h in halves)
    cap = []
    for h in halves:  # over half-sections
        ring = h.polygon
        on_axis = ring[:, 0] == 0
        if not on_axis.any():
            continue
        k = len(ring)
        fwd = (h.top + np.arange(k)) % k
        stop = int(np.argmax(on_axis[fwd]))
        cavity = np.vstack([ring[fwd[:stop + 1]], [[0.0, ring[h.top, 1]]]])
        cavity = clip_ring(cavity, 1, keep_below=True, at=level)
        cap.append(abs(pappus_volume(cavity)))
    t = np.concatenate(thick) if thick else np.zeros(0)
    w = np.concatenate(thick_w) if thick_w else np.zeros(0)

    def mean(x):
        x = np.asarray(x, dtype=float)
        return float(np.mean(x)) if len(x) else nan

    def median(x):  # lengths read off single halves: a handle or a spout in one half must not move them
        x = np.asarray(x, dtype=float)
        return float(np.median(x)) if len(x) else nan

    return Measurements(
        height=float(height), rim_diameter=2 * median(rim), max_diameter=2 * median(rmax),
        max_diameter_height=median(zmax), base_diameter=2 * median(base),
        wall_thickness_min=float(t.min()) if len(t) else nan,
        wall_thickness_mean=float((t * w).sum() / w.sum()) if len(t) else nan,
        wall_thickness_max=float(t.max()) if len(t) else nan,
        base_thickness=median(base_t), capacity=mean(cap), clay_volume=mean(clay),
        halves=len(halves), spread=float(spread), residual=float(residual))


def _candidates(mesh: Mesh, angles) -> list[np.ndarray]:
    """Facets that may cross each vertical plane through z: a cheap superset, per plane.

    A facet can reach a plane only if its centroid lies within rho of it, rho
    being the largest horizontal distance from the centroid to a corner. The
    test runs in float32 with a margin far above float32 rounding: it only has
    to keep every facet the exact section needs.
    """
    t = mesh.triangles
    x = t[..., 0].astype(np.float32)
    y = t[..., 1].astype(np.float32)
    cx = (x[:, 0] + x[:, 1] + x[:, 2]) / np.float32(3)
    cy = (y[:, 0] + y[:, 1] + y[:, 2]) / np.float32(3)
    rho2 = np.zeros(len(t), np.float32)
    for k in range(3):  # three corners
        dx, dy = x[:, k] - cx, y[:, k] - cy
        np.maximum(rho2, dx * dx + dy * dy, out=rho2)
    size = float(np.abs(x).max() + np.abs(y).max()) if len(t) else 1.0
    rho = np.sqrt(rho2) * np.float32(1 + 1e-5) + np.float32(1e-5 * size)
    out = []
    for a in angles:  # over planes
        d = cx * np.float32(math.sin(a))
        d -= cy * np.float32(math.cos(a))
        np.abs(d, out=d)
        out.append(np.flatnonzero(d <= rho))
    return out


@dataclass(frozen=True, eq=False)
class Profile:
    """A vessel's profile: every half-section through the axis, the drawn one, measurements.

    Attributes
    ----------
    halves : tuple of HalfProfile
        Two per usable plane, at angles ``pi k / planes`` and opposite.
    representative : int
        Index of the most typical half (the medoid: least mean distance to the others);
        it is the one drawn.
    spread : (len(halves),) ndarray
        Hausdorff distance (mm) of each half from the representative.
    measurements : Measurements
    alignment : Alignment or None
    planes : int
        Planes asked for (planes whose section had holes are left out).
    name : str
        Label for drawings.
    """

    halves: tuple
    representative: int
    spread: np.ndarray
    measurements: Measurements
    alignment: Alignment | None = None
    planes: int = 12
    name: str = ""
    mesh: Mesh | None = field(default=None, repr=False)

    @property
    def is_revolution(self) -> bool:
        """True when the alignment fits (`Alignment.is_revolution`) and every half-section lies
        within 5 % of the largest radius of the drawn one (a box's diagonal axis passes the
        first test, not this one)."""
        r = float(self.drawn.polygon[:, 0].max())
        ok = self.alignment is None or self.alignment.is_revolution
        return bool(ok and self.measurements.spread <= _NOT_TYPICAL * r)

    @property
    def drawn(self) -> HalfProfile:
        """The representative half-section."""
        return self.halves[self.representative]

    def __repr__(self) -> str:
        m = self.measurements
        return (f"Profile({len(self.halves)} halves, height {m.height:.4g} mm, rim {m.rim_diameter:.4g} mm, "
                f"capacity {m.capacity / 1e6:.4g} l, spread {m.spread:.3g} mm)")

    def to_dict(self) -> dict:
        """Measurements, the drawn half and its outlines as plain lists (for JSON)."""
        d = self.drawn
        return {"name": self.name, "measurements": self.measurements.to_dict(),
                "representative_angle": d.angle, "angles": [h.angle for h in self.halves],
                "spread": self.spread.tolist(), "polygon": d.polygon.tolist(),
                "outer": d.outer.tolist(), "inner": d.inner.tolist(),
                "alignment": self.alignment.to_dict() if self.alignment else None}

    def svg(self, *, side: str = "left", spread: bool = False, label: str | None = None) -> str:
        """The profile drawing as SVG text, 1:1 in mm (see `to_svg`)."""
        from .drawing import profile_svg
        return profile_svg(self, side=side, spread=spread, label=label)

    def to_svg(self, path, **kwargs) -> None:
        """Write the archaeological drawing as SVG, 1:1 in mm, atomically.

        Layers (SVG groups with ids): ``axis`` (dash-dot), ``section`` (the
        drawn half filled black on `side`), ``exterior`` (outline on the other
        side), ``rim`` (line across the mouth), ``spread`` (optional: every
        other half in grey), ``scale`` (bar in cm), ``label``.

        Parameters
        ----------
        path : str or os.PathLike
        side : {"left", "right"}
            Where the section goes; the exterior view takes the other side.
        spread : bool
            Also draw every other half-section in grey behind the section.
        label : str, optional
            First line of the label (default: the profile's name).

        Examples
        --------
        >>> import os, tempfile
        >>> from slicelab.samples import pot
        >>> p = profile(pot(20, 24), planes=2)
        >>> p.to_svg(os.path.join(tempfile.mkdtemp(), "pot.svg"), side="right")
        """
        from ..export.files import atomic_open
        text = self.svg(**kwargs)
        with atomic_open(path, "w", encoding="utf-8") as fh:
            fh.write(text)

    def to_png(self, path, *, dpi: float = 150.0, **kwargs) -> None:
        """Write the same drawing as a PNG (1:1 when printed at `dpi`), atomically.

        Examples
        --------
        >>> import os, tempfile
        >>> from slicelab.samples import pot
        >>> profile(pot(20, 24), planes=2).to_png(os.path.join(tempfile.mkdtemp(), "pot.png"), dpi=50)
        """
        from .drawing import profile_png
        profile_png(self, path, dpi=dpi, **kwargs)


def profile(mesh: Mesh, *, planes: int = 12, align: bool = True, max_gap: float = 1.0,
            name: str = "") -> Profile:
    """Cut a vessel through its axis at `planes` angles, pick the drawn profile and measure it.

    Parameters
    ----------
    mesh : Mesh
        The vessel, in any position (aligned first unless ``align=False``, in
        which case its axis must already be +z through the origin, base at 0).
    planes : int, default 12
        Vertical planes through the axis, ``pi k / planes`` apart; each gives two halves.
    align : bool, default True
        Run `slicelab.align` first.
    max_gap : float, default 1.0
        As in `slicelab.section`; planes whose section stays open are left out.
    name : str
        Label for the drawing.

    Returns
    -------
    Profile

    Raises
    ------
    ValueError
        No plane gave a closed section.

    Examples
    --------
    >>> from slicelab.samples import pot, pot_dimensions
    >>> p = profile(pot(30, 48), planes=4)
    >>> round(p.measurements.max_diameter / pot_dimensions()["max_diameter"], 2)
    1.0
    """
    planes = int(planes)
    if planes < 1:
        raise ValueError(f"planes must be at least 1, got {planes}")
    alignment = None
    if align:
        alignment = _align(mesh)
        mesh = alignment.mesh
    angles = [math.pi * k / planes for k in range(planes)]
    halves: list[HalfProfile] = []
    for a, cand in zip(angles, _candidates(mesh, angles)):  # over planes
        halves += half_profiles(mesh, a, max_gap=max_gap, candidates=cand)
    if not halves:
        raise ValueError("no plane through the axis gave a closed section (is the mesh aligned and closed?)")
    halves.sort(key=lambda h: h.angle)
    z = mesh.triangles[..., 2]
    height = float(z.max() - z.min())
    rep, spread = _representative(halves, height)
    residual = alignment.residual if alignment is not None else float("nan")
    m = _measure(halves, height, float(spread.max()), residual)
    return Profile(tuple(halves), rep, spread, m, alignment, planes, name, mesh)


def _representative(halves: list[HalfProfile], height: float):
    """Medoid half (least mean RMS distance to the others) and each half's Hausdorff distance to it."""
    from scipy.spatial import cKDTree
    if len(halves) == 1:
        return 0, np.zeros(1)
    coarse = [_resample(np.vstack([h.polygon, h.polygon[:1]]), max(height, 1e-9) / 100)[0] for h in halves]
    trees = {i: cKDTree(p) for i, p in enumerate(coarse)}
    n = len(halves)
    rms = np.zeros((n, n))
    for i in range(n):  # tens of halves: a few hundred small queries
        for j in range(i + 1, n):
            rms[i, j] = rms[j, i] = _rms_distance(coarse[i], coarse[j], trees[i], trees[j])
    rep = int(np.argmin(rms.sum(axis=1)))
    fine = [_resample(np.vstack([h.polygon, h.polygon[:1]]), max(height, 1e-9) / 1000)[0] for h in halves]
    tree_rep = cKDTree(fine[rep])

    def hausdorff(j):
        return max(float(tree_rep.query(fine[j])[0].max()), float(cKDTree(fine[j]).query(fine[rep])[0].max()))

    spread = np.array([0.0 if j == rep else hausdorff(j) for j in range(n)])
    return rep, spread
