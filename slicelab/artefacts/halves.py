"""Half-sections of an aligned vessel through its axis, and the most typical of them.

`half_profiles` cuts an aligned mesh (axis +z) by a vertical plane through
the axis and keeps each side as an (r, z) polygon (`HalfProfile`);
`representative` picks the medoid of a set of them (the one drawn) and
measures how far each strays from it.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..geometry.polygons import signed_area
from ..mesh.core import Mesh
from ..slicing.sections import section
from .curves import UP_COSINE, clip_ring, resample

__all__ = ["HalfProfile", "half_profiles", "half_from_ring", "plane_candidates", "representative"]


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
    other_area : float
        Area (mm^2) of the other polygons of the section on this side, left out
        (a handle's or a lug's section when it does not touch the wall).

    See Also
    --------
    half_profiles : makes them.
    Profile : all of a vessel's halves and the drawn one.
    """

    angle: float
    polygon: np.ndarray
    holes: tuple
    outer: np.ndarray
    inner: np.ndarray
    top: int
    other_area: float = 0.0

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
    up = nz >= UP_COSINE
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

    See Also
    --------
    profile : half-sections at several angles, the drawn one and the measurements.
    slicelab.artefacts.clip_ring : clips each polygon of the section at the axis.
    slicelab.section

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
        best, best_area, holes, total = None, 0.0, [], 0.0
        for poly in sec.polygons:  # over the section's few polygons
            ext = clip_ring(poly.exterior, 0, keep_below=side < 0)
            if len(ext) < 3:
                continue
            ext = np.column_stack([side * ext[:, 0], ext[:, 1]])
            if side < 0:
                ext = ext[::-1]
            area = signed_area(ext)
            total += max(area, 0.0)
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
        out.append(HalfProfile(float(a % (2 * math.pi)), best, tuple(holes), outer, inner, top,
                               float(total - best_area)))
    return out


def half_from_ring(ring: np.ndarray, angle: float = 0.0, holes=()) -> HalfProfile:
    """A `HalfProfile` of a counter-clockwise (r, z) ring: its outlines split at its top.

    Examples
    --------
    >>> h = half_from_ring(np.array([[0, 0], [4, 0], [4, 8], [3, 8], [3, 1], [0, 1]], float))
    >>> h.outer[0].tolist(), h.inner[-1].tolist(), round(h.area, 6)
    ([4.0, 8.0], [0.0, 1.0], 11.0)
    """
    ring = np.asarray(ring, dtype=np.float64)
    outer, inner, top = _split_chains(ring, 0.0)
    return HalfProfile(float(angle), ring, tuple(holes), outer, inner, top)


def _rms_distance(a: np.ndarray, b: np.ndarray, tree_a, tree_b) -> float:
    """Symmetric RMS of nearest-point distances between two point sets."""
    da = tree_b.query(a)[0]
    db = tree_a.query(b)[0]
    return float(math.sqrt((np.mean(da ** 2) + np.mean(db ** 2)) / 2))


def plane_candidates(mesh: Mesh, angles) -> list[np.ndarray]:
    """Facets that may cross each vertical plane through z: a cheap superset, per plane.

    A facet can reach a plane only if its centroid lies within rho of it, rho
    being the largest horizontal distance from the centroid to a corner. The
    test runs in float32 with a margin far above float32 rounding: it only has
    to keep every facet the exact section needs.

    Examples
    --------
    >>> from slicelab.samples import pot
    >>> mesh = pot(20, 24)
    >>> [len(c) < len(mesh) // 4 for c in plane_candidates(mesh, [0.0, 1.0])]
    [True, True]
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


def representative(halves: list[HalfProfile], height: float):
    """Medoid half (least mean RMS distance to the others) and each half's Hausdorff distance to it.

    Examples
    --------
    >>> from slicelab.samples import pot
    >>> rep, spread = representative(half_profiles(pot(20, 24), 0.0), 120.0)
    >>> rep, bool(spread.max() < 0.05)  # the 24-gon's two halves differ by its facets
    (0, True)
    """
    from scipy.spatial import cKDTree
    if len(halves) == 1:
        return 0, np.zeros(1)
    coarse = [resample(np.vstack([h.polygon, h.polygon[:1]]), max(height, 1e-9) / 100)[0] for h in halves]
    trees = {i: cKDTree(p) for i, p in enumerate(coarse)}
    n = len(halves)
    rms = np.zeros((n, n))
    for i in range(n):  # tens of halves: a few hundred small queries
        for j in range(i + 1, n):
            rms[i, j] = rms[j, i] = _rms_distance(coarse[i], coarse[j], trees[i], trees[j])
    rep = int(np.argmin(rms.sum(axis=1)))
    fine = [resample(np.vstack([h.polygon, h.polygon[:1]]), max(height, 1e-9) / 1000)[0] for h in halves]
    tree_rep = cKDTree(fine[rep])

    def hausdorff(j):
        return max(float(tree_rep.query(fine[j])[0].max()), float(cKDTree(fine[j]).query(fine[rep])[0].max()))

    spread = np.array([0.0 if j == rep else hausdorff(j) for j in range(n)])
    return rep, spread
