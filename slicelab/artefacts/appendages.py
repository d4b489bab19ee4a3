"""Handles, spouts and lugs of an aligned vessel: found and measured outside the body's surface of revolution.

The body is the median over the half-sections of each one's widest radius
per height band (`body_radius`): a handle in one half does not move it. The
surface standing clearly outside it (`appendage_angle`: more than 3 mm and
4 % of the radius) marks an appendage; its angular sectors of 5 degrees
gather into separate appendages (`find_appendages`), each then measured on
the surface standing just outside the body (five noise sigmas, at least
1 mm): its angular position and span, its height range and, at mid-height,
its section (radial extent: the thickness; extent across the radius: the
width).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .curves import resample

__all__ = ["Appendage", "body_radius", "appendage_angle", "find_appendages"]

_BANDS = 200          # height bands of the body's radius
_SECTOR = 5.0         # degrees: angular bins that gather an appendage's surface
_MIN_SHARE = 0.003    # an appendage holds at least this share of the vertices (clearly outside)


@dataclass(frozen=True)
class Appendage:
    """A handle, spout or lug, in the aligned vessel's frame (axis +z, base at z = 0).

    Attributes
    ----------
    angle : float
        Direction about the axis (degrees, from +x, 0-360): the circular mean
        of the surface clearly outside the body.
    span : float
        Angle (degrees) the surface outside the body covers about the axis.
    z_from, z_to : float
        Height range (mm) of the surface outside the body.
    thickness : float
        Radial extent (mm) of its section at mid-height (NaN when nothing of it is there).
    width : float
        Extent (mm) of that section across the radius (chord at its mean radius).
    reach : float
        How far (mm) it stands out of the body at most.
    """

    angle: float
    span: float
    z_from: float
    z_to: float
    thickness: float
    width: float
    reach: float

    def to_dict(self) -> dict:
        """Plain floats."""
        return {k: float(getattr(self, k)) for k in self.__dataclass_fields__}

    def sentence(self) -> str:
        """One line: where it is and how big."""
        return (f"at {self.angle:.0f} degrees, {self.span:.0f} degrees wide, from z {self.z_from:.1f} to "
                f"{self.z_to:.1f} mm, section {self.thickness:.1f} x {self.width:.1f} mm")


def _vertices(mesh, most: int = 300_000) -> np.ndarray:
    """The mesh's facet corners, thinned to about `most` facets."""
    return mesh.triangles[:: max(1, len(mesh) // most)].reshape(-1, 3)


def body_radius(halves, z_lo: float, z_hi: float, bands: int = _BANDS):
    """The body's widest radius per height band: the median over the halves of each one's widest.

    Parameters
    ----------
    halves : sequence of HalfProfile
    z_lo, z_hi : float
        Height range split into `bands` equal bands.

    Returns
    -------
    edges : (bands + 1,) ndarray
    radius : (bands,) ndarray

    Examples
    --------
    >>> from slicelab.artefacts import half_profiles
    >>> from slicelab.samples import revolve
    >>> cup = revolve([[0, 0], [40, 0], [40, 80], [37, 80], [37, 5], [0, 5]], 256)
    >>> edges, r = body_radius(half_profiles(cup, 0.0), 0.0, 80.0, 8)
    >>> np.round(r, 6).tolist() == [40.0] * 8
    True
    """
    z = np.linspace(z_lo, z_hi, bands + 1)
    widest = np.zeros((len(halves), bands))
    for i, h in enumerate(halves):  # over half-sections
        p = resample(np.vstack([h.polygon, h.polygon[:1]]), max(z[1] - z[0], 1e-9) / 2)[0]
        k = np.clip(np.searchsorted(z, p[:, 1]) - 1, 0, bands - 1)
        np.maximum.at(widest[i], k, p[:, 0])
    return z, np.median(widest, axis=0)


def _outside(v: np.ndarray, halves):
    """Each vertex's radius, its height above the body's widest radius there, and that widest radius's maximum."""
    z, body = body_radius(halves, float(v[:, 2].min()), float(v[:, 2].max()))
    r = np.hypot(v[:, 0], v[:, 1])
    k = np.clip(np.searchsorted(z, v[:, 2]) - 1, 0, len(z) - 2)
    return r, r - body[k], float(body.max())


def appendage_angle(mesh, halves) -> float | None:
    """Angle (degrees, about the aligned axis) of a handle, spout or lug, or None.

    The surface standing more than 3 mm (and 4 % of the radius) outside the
    body's widest outline at its height (`body_radius`) and holding over
    0.3 % of the vertices, gathered on one side (their mean direction at
    least 0.7 long), is an appendage.
    """
    v = mesh.triangles.reshape(-1, 3)[:: max(1, len(mesh) // 100_000)]
    _, above, r_max = _outside(v, halves)
    out = above > max(3.0, 0.04 * r_max)
    if out.sum() < _MIN_SHARE * len(v):
        return None
    t = np.arctan2(v[out, 1], v[out, 0])
    c, s = float(np.cos(t).mean()), float(np.sin(t).mean())
    if math.hypot(c, s) < 0.7:  # not on one side
        return None
    return float(math.degrees(math.atan2(s, c)) % 360)


def find_appendages(mesh, halves, noise: float = 0.0) -> tuple[Appendage, ...]:
    """Every handle, spout or lug of an aligned vessel, measured.

    Parameters
    ----------
    mesh : Mesh
        Aligned (axis +z through the origin, base at z = 0).
    halves : sequence of HalfProfile
        Its half-sections through the axis (at least two).
    noise : float
        The scan's noise sigma (mm): the surface counts as outside the body
        above ``max(1, 5 noise)`` mm.

    Returns
    -------
    tuple of Appendage
        Largest first. The surface clearly outside the body (as in
        `appendage_angle`) in 5-degree sectors, neighbouring occupied
        sectors joined, each group over 0.3 % of the vertices; each is then
        measured on the surface just outside the body within its sectors
        widened by two sectors each way.

    Examples
    --------
    >>> from slicelab.artefacts import profile
    >>> from slicelab.samples import concat, pot, torus
    >>> ring = torus(12.0, 3.0, 48, 16).transformed(np.array(
    ...     [[0, 0, 1, 0], [1, 0, 0, 70], [0, 1, 0, 60], [0, 0, 0, 1]], float))  # a lug on +y
    >>> p = profile(concat(pot(30, 48), ring), align=False, planes=6)
    >>> [round(a.angle) for a in find_appendages(p.mesh, p.halves)]
    [90]
    """
    if len(halves) < 2:
        return ()
    v = _vertices(mesh)
    r, above, r_max = _outside(v, halves)
    t = np.degrees(np.arctan2(v[:, 1], v[:, 0])) % 360
    strong = above > max(3.0, 0.04 * r_max)
    n_bins = round(360 / _SECTOR)
    counts = np.bincount((t[strong] // _SECTOR).astype(np.int64) % n_bins, minlength=n_bins)
    occupied = counts > 0
    if occupied.all() or not occupied.any():  # a flange or a ring all round is body, not an appendage
        return ()
    # Runs of occupied sectors, round the circle: start after an empty one.
    shift = int(np.argmin(occupied))
    occ = np.roll(occupied, -shift)
    edge = np.diff(np.concatenate([[0], occ.astype(np.int8), [0]]))
    starts, stops = np.flatnonzero(edge == 1), np.flatnonzero(edge == -1)
    weak = above > max(1.0, 5 * noise)
    found = []
    for a, b in zip(starts, stops):  # a few runs
        bins = (np.arange(a, b) + shift) % n_bins
        if counts[bins].sum() < _MIN_SHARE * len(v):
            continue
        seed = strong & np.isin((t // _SECTOR).astype(np.int64) % n_bins, bins)
        rad = np.radians(t[seed])
        mean = math.degrees(math.atan2(float(np.sin(rad).mean()), float(np.cos(rad).mean()))) % 360
        lo = ((a + shift - 2) * _SECTOR - mean + 180) % 360 - 180  # the widened sectors, about the mean
        hi = ((b + shift + 2) * _SECTOR - mean + 180) % 360 - 180
        d = (t - mean + 180) % 360 - 180
        part = weak & (d >= lo) & (d <= hi)
        zs = v[part, 2]
        z0, z1 = float(zs.min()), float(zs.max())
        mid = part & (np.abs(v[:, 2] - (z0 + z1) / 2) <= max(1.0, 0.02 * (z1 - z0)))
        if mid.any():
            thickness = float(r[mid].max() - r[mid].min())
            width = float(np.radians(d[mid].max() - d[mid].min()) * r[mid].mean())
        else:
            thickness = width = float("nan")
        found.append((int(seed.sum()), Appendage(
            angle=mean, span=float(d[part].max() - d[part].min()), z_from=z0, z_to=z1, thickness=thickness,
            width=width, reach=float(above[part].max()))))
    return tuple(ap for _, ap in sorted(found, key=lambda x: -x[0]))
