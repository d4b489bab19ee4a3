"""Vessel profiles: half-sections through the axis, the drawn profile and its measurements.

`profile` aligns a vessel (`slicelab.artefacts.align`), cuts it through the
axis at several meridional angles, keeps each half-section (one side of the
axis) as an (r, z) polygon (`half_profiles`), picks the most typical half as
the drawn profile and measures the vessel (`slicelab.artefacts.measure_halves`).
The drawing, archaeological style, is `Profile.to_svg` / `Profile.to_png`:
axis line, section filled black on one side, exterior outline on the other,
rim line, scale bar, label; 1:1 in mm.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from functools import cached_property

import numpy as np

from ..geometry.polygons import signed_area
from ..mesh.core import Mesh
from ..slicing.sections import section
from . import axis
from .measure import UP_COSINE, Measurements, clip_ring, half_outlines, measure_halves, resample

__all__ = ["HalfProfile", "half_profiles", "Profile", "profile", "closing_gap"]

_NOT_TYPICAL = 0.05       # half-sections further apart than this share of the radius: no one profile
_MAX_CLOSING = 0.1        # an open scan's sections are closed across gaps up to this share of its size
_CLOSING_MARGIN = 1.25    # times the median gap the planes need: the noise widens some of them


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


def _rms_distance(a: np.ndarray, b: np.ndarray, tree_a, tree_b) -> float:
    """Symmetric RMS of nearest-point distances between two point sets."""
    da = tree_b.query(a)[0]
    db = tree_a.query(b)[0]
    return float(math.sqrt((np.mean(da ** 2) + np.mean(db ** 2)) / 2))


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
    mesh : Mesh or None
        The aligned mesh that was cut.
    rim_tops, max_radii : ndarray
        Per half: the rim plane's height and the widest radius (smoothed outlines;
        `slicelab.artefacts.outlines.Outline`), for `ovality`, `rim_drop` and `appendage_angle`.
    closed_gap : float
        For an open scan whose sections all stayed open (the rim top not captured): the gap
        (mm) they were closed across (`closing_gap`); 0 when `max_gap` sufficed.
    sealed : bool
        No mouth: the capacity is the volume of the mesh's inner cavity shell
        (`slicelab.artefacts.cavities.cavity_volume`).

    See Also
    --------
    profile : makes one.
    slicelab.artefacts.layout : what its drawing shows, in drawing millimetres.
    """

    halves: tuple
    representative: int
    spread: np.ndarray
    measurements: Measurements
    alignment: axis.Alignment | None = None
    planes: int = 12
    name: str = ""
    mesh: Mesh | None = field(default=None, repr=False)
    rim_tops: np.ndarray = field(default_factory=lambda: np.zeros(0), repr=False)
    max_radii: np.ndarray = field(default_factory=lambda: np.zeros(0), repr=False)
    closed_gap: float = 0.0
    sealed: bool = False

    @property
    def is_revolution(self) -> bool:
        """True when the alignment fits (`Alignment.is_revolution`: circles, the noise averaged out)
        and every half-section lies within 5 % of the largest radius of the drawn one, the halves
        through a handle or a spout (`appendage_angle`) left out (a box's diagonal axis passes the
        first test, not this one)."""
        r = float(self.drawn.polygon[:, 0].max())
        ok = self.alignment is None or self.alignment.is_revolution
        s = self.spread
        if self.sherd is not None:  # its sections differ at their breaks by nature
            return bool(ok)
        if self.appendage_angle is not None:
            s = s[~self._astray()]
        return bool(ok and (float(s.max()) if len(s) else 0.0) <= _NOT_TYPICAL * r)

    @property
    def ovality(self) -> float:
        """(D_max - D_min) / D_mean of the widest diameter over the angles, in % (NaN for a sherd):
        the halves' widest radii fitted with r0 + a cos 2t + b sin 2t, 2 hypot(a, b) / r0."""
        r, t = self.max_radii, np.array([h.angle for h in self.halves])
        if self.sherd is not None or len(r) < 4:
            return float("nan")
        # Halves through a handle left out: those straying over three times the median spread (and
        # over 1 % of the radius: an exact mesh's halves differ by rounding).
        keep = self.spread <= max(3 * float(np.median(self.spread)), 0.01 * float(np.median(r)))
        if keep.sum() < 4:
            keep = np.ones(len(r), bool)
        A = np.column_stack([np.ones(len(t)), np.cos(2 * t), np.sin(2 * t)])[keep]
        sol = np.linalg.lstsq(A, r[keep], rcond=None)[0]
        return float(200 * math.hypot(sol[1], sol[2]) / sol[0]) if sol[0] > 0 else float("nan")

    @property
    def rim_drop(self) -> float:
        """How far (mm) the lowest half's rim top sits under the median rim top: a chipped or
        unevenly cut rim (0 for a level one; NaN for a sherd)."""
        if self.sherd is not None or not len(self.rim_tops):
            return float("nan")
        return float(np.median(self.rim_tops) - self.rim_tops.min())

    @property
    def appendage_angle(self) -> float | None:
        """Angle (degrees, about the aligned axis) of a handle, spout or lug, or None
        (`slicelab.artefacts.appendages.appendage_angle`: the surface clearly outside the body, on one side)."""
        if self.sherd is not None or self.mesh is None or len(self.halves) < 2:
            return None
        from .appendages import appendage_angle
        return appendage_angle(self.mesh, self.halves)

    @cached_property
    def appendages(self) -> tuple:
        """Each handle, spout or lug measured (`slicelab.artefacts.appendages.Appendage`: angle, span,
        height range, section at mid-height), largest first; empty for a sherd or a body that is not a
        solid of revolution."""
        if self.sherd is not None or self.mesh is None or len(self.halves) < 2 or not self.is_revolution:
            return ()  # no body of revolution to stand out of
        from .appendages import find_appendages
        return find_appendages(self.mesh, self.halves, self.measurements.noise)

    def _astray(self) -> np.ndarray:
        """Per half: does it stray far from the drawn one, or carry another polygon (a detached
        handle's section) over 2 % of its own area?"""
        s = self.spread
        r = float(self.drawn.polygon[:, 0].max())
        extra = np.array([h.other_area > 0.02 * h.area for h in self.halves])
        return (s > max(5 * float(np.median(s)), 0.03 * r)) | extra

    @property
    def sherd(self):
        """The sherd's report (`slicelab.artefacts.sherds.SherdReport`), or None for a whole vessel."""
        return None if self.alignment is None else self.alignment.sherd

    @property
    def drawn(self) -> HalfProfile:
        """The representative half-section."""
        return self.halves[self.representative]

    def __repr__(self) -> str:
        m = self.measurements
        if self.sherd is not None:
            return f"Profile({len(self.halves)} halves, {self.sherd.sentence()}, spread {m.spread:.3g} mm)"
        return (f"Profile({len(self.halves)} halves, height {m.height:.4g} mm, rim {m.rim_diameter:.4g} mm, "
                f"capacity {m.capacity / 1e6:.4g} l, spread {m.spread:.3g} mm)")

    def to_dict(self) -> dict:
        """Measurements, the drawn half and its outlines as plain lists (for JSON)."""
        d = self.drawn
        return {"name": self.name, "measurements": self.measurements.to_dict(),
                "representative_angle": d.angle, "angles": [h.angle for h in self.halves],
                "spread": self.spread.tolist(), "polygon": d.polygon.tolist(),
                "outer": d.outer.tolist(), "inner": d.inner.tolist(),
                "alignment": self.alignment.to_dict() if self.alignment else None,
                "sherd": self.sherd.to_dict() if self.sherd is not None else None,
                "appendages": [x.to_dict() for x in self.appendages], "sealed": self.sealed}

    def svg(self, *, side: str = "left", spread: bool = False, label: str | None = None) -> str:
        """The profile drawing as SVG text, 1:1 in mm (see `to_svg`)."""
        from .drawing import profile_svg
        return profile_svg(self, side=side, spread=spread, label=label)

    def to_svg(self, path, **kwargs) -> None:
        """Write the archaeological drawing as SVG, 1:1 in mm, atomically.

        Layers (SVG groups with ids): ``axis`` (dash-dot), ``section`` (the
        drawn half filled black on `side`), ``exterior`` (outline on the other
        side), ``rim`` (line across the mouth), ``appendage`` (each handle or
        spout in the plane through it), ``spread`` (optional: every
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
        from ..files.atomic import atomic_open
        text = self.svg(**kwargs)
        with atomic_open(path, "w", encoding="utf-8") as fh:
            fh.write(text)

    def to_png(self, path, *, dpi: float = 150.0, **kwargs) -> None:
        """Write the same drawing as a PNG (1:1 when printed at `dpi`), atomically.

        Takes the keywords of `to_svg`; the rendering is `slicelab.artefacts.drawing_png.profile_png`
        (matplotlib, imported here on first use).

        Examples
        --------
        >>> import os, tempfile
        >>> from slicelab.samples import pot
        >>> profile(pot(20, 24), planes=2).to_png(os.path.join(tempfile.mkdtemp(), "pot.png"), dpi=50)
        """
        from .drawing_png import profile_png
        profile_png(self, path, dpi=dpi, **kwargs)


def profile(mesh: Mesh, *, planes: int = 12, align: bool = True, max_gap: float = 1.0,
            name: str = "") -> Profile:
    """Cut a vessel through its axis at `planes` angles, pick the drawn profile and measure it.

    The drawn half is the medoid of the half-sections (least mean RMS
    distance to the others): a real section of the scan, not an average. The
    spread is each half's Hausdorff distance from it.

    Parameters
    ----------
    mesh : Mesh
        The vessel, in any position (aligned first unless ``align=False``, in
        which case its axis must already be +z through the origin, base at 0).
    planes : int, default 12
        Vertical planes through the axis, ``pi k / planes`` apart; each gives two halves.
    align : bool, default True
        Run `slicelab.artefacts.align` first.
    max_gap : float, default 1.0
        As in `slicelab.section`; planes whose section stays open are left out.
        When every plane's does and the openings are at the top, the base
        down (an open scan: the rim top not captured), the sections are closed across 1.25 times
        the gap most of them need (`closing_gap`), if that is under a tenth of
        the vessel's size, and `Profile.closed_gap` says so.
    name : str
        Label for the drawing.

    Returns
    -------
    Profile
        A vessel without a mouth whose mesh holds an inner cavity shell (a sealed jar) gets that
        cavity's volume as its capacity, and `Profile.sealed`.

    Raises
    ------
    ValueError
        No plane gave a closed section (the message names the `max_gap` that would close them).

    See Also
    --------
    slicelab.artefacts.align : the alignment run first.
    half_profiles : the half-sections of one plane.
    slicelab.artefacts.measure_halves : the measurements.
    Profile.to_svg, Profile.to_png : the drawing.

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
        alignment = axis.align(mesh)
        mesh = alignment.mesh
    if alignment is not None and alignment.sherd is not None:
        return _sherd_profile(mesh, alignment, planes, max_gap, name)
    angles = [math.pi * k / planes for k in range(planes)]
    cands = _candidates(mesh, angles)
    halves: list[HalfProfile] = []
    for a, cand in zip(angles, cands):  # over planes
        halves += half_profiles(mesh, a, max_gap=max_gap, candidates=cand)
    closed_gap = 0.0
    if not halves:
        # An open scan (the rim top not captured): every section is open. Close them across the
        # gap most planes need, if it is small beside the vessel; the report says so (`closed_gap`).
        gap, low = closing_gap(mesh, angles, cands, lowest=True)
        z = mesh.triangles[..., 2]
        size = max(float(z.max() - z.min()), float(np.abs(mesh.triangles[..., :2]).max()))
        # The openings must be at the rim, and the rim known to be up by the base, not by the openings.
        at_rim = low >= float(z.max()) - max(2 * gap, 0.05 * float(z.max() - z.min())) and \
            (alignment is None or alignment.up_from == "base")
        if not math.isfinite(gap) or gap > _MAX_CLOSING * size or not at_rim:
            hint = f"; --max-gap {math.ceil(_CLOSING_MARGIN * gap * 10) / 10:g} would close them" \
                if math.isfinite(gap) else ""
            raise ValueError(f"no plane through the axis gave a closed section (is the mesh aligned and closed?)"
                             f"{hint}")
        closed_gap = math.ceil(_CLOSING_MARGIN * gap * 10) / 10
        for a, cand in zip(angles, cands):  # over planes
            halves += half_profiles(mesh, a, max_gap=closed_gap, candidates=cand)
        if not halves:
            raise ValueError(f"no plane through the axis gave a closed section, even across gaps of "
                             f"{closed_gap:g} mm")
    halves.sort(key=lambda h: h.angle)
    z = mesh.triangles[..., 2]
    height = float(z.max() - z.min())
    rep, spread = _representative(halves, height)
    residual = alignment.residual if alignment is not None else float("nan")
    outs, noise = half_outlines(halves, height, alignment.noise if alignment is not None else None)
    m = measure_halves(halves, height, float(spread.max()), residual, noise, outs)
    sealed = False
    if not m.capacity > 1e-3 * m.clay_volume:  # no mouth: a sealed vessel's cavity is an inner shell
        from .cavities import cavity_volume
        void = cavity_volume(mesh)
        if void > max(m.capacity, 0.0):
            m, sealed = replace(m, capacity=void), True
    return Profile(tuple(halves), rep, spread, m, alignment, planes, name, mesh,
                   np.array([o.z_top for o in outs]), np.array([o.max_r for o in outs]), closed_gap, sealed)


def closing_gap(mesh: Mesh, angles, candidates=None, *, lowest: bool = False):
    """The `max_gap` (mm) that closes the sections of an open scan through the axis at `angles`.

    Per plane, each open chain's end is paired with the nearest chain start
    (the way `slicelab.section` joins them, nearest first); the plane needs the
    largest of those distances. The answer is the median over the planes
    whose sections are open (a hole in the wall opens a few planes only, an
    uncaptured rim all of them); infinite when none is open. With
    ``lowest=True``, also the height of the lowest open end (where the scan
    is open: at the rim, or lower).

    Examples
    --------
    >>> from slicelab.samples import scan
    >>> mesh, _ = scan("beaker", spacing=2.0, pose=False, open_rim=True)
    >>> round(closing_gap(mesh, [0.0, 1.0]), 1)  # the rim top, 3 mm wide, was not captured
    3.0
    """
    from scipy.spatial import cKDTree
    need, low = [], math.inf
    for k, a in enumerate(angles):  # a few planes
        c, s = math.cos(a), math.sin(a)
        sub = mesh if candidates is None else Mesh(mesh.triangles[candidates[k]])
        sec = section(sub, (0.0, 0.0, 0.0), (s, -c, 0.0), max_gap=0.0)
        if not sec.open_chains:
            continue
        ends = np.array([ch[-1] for ch in sec.open_chains])
        starts = np.array([ch[0] for ch in sec.open_chains])
        need.append(float(cKDTree(starts).query(ends)[0].max()))
        low = min(low, float(ends[:, 1].min()), float(starts[:, 1].min()))
    gap = float(np.median(need)) if need else math.inf
    return (gap, low) if lowest else gap


def _sherd_profile(mesh: Mesh, alignment, planes: int, max_gap: float, name: str) -> Profile:
    """A sherd's profile: `planes` sections across its span, the drawn one the medoid; what the
    sherd holds is measured (its rim or base, its wall), the rest is NaN."""
    from ..mesh.validation import signed_volume
    from .sherds import sherd_interval, sherd_wall
    start, width = sherd_interval(mesh.triangles.reshape(-1, 3))
    angles = start + width * (np.arange(planes) + 0.5) / planes
    halves = []
    for a in angles:  # over planes
        halves += [h for h in half_profiles(mesh, float(a), max_gap=max_gap)
                   if abs((h.angle - a + math.pi) % (2 * math.pi) - math.pi) < 1e-6]
    if not halves:
        raise ValueError("no plane through the axis gave a closed section of the sherd (is it closed?)")
    z = mesh.triangles[..., 2]
    rep, spread = _representative(halves, float(z.max() - z.min()))
    report = alignment.sherd
    walls = [sherd_wall(h.polygon) for h in halves]
    walls = [w for w in walls if len(w)]
    nan = float("nan")

    def med(x):
        return float(np.median(x)) if len(x) else nan

    m = Measurements(
        height=nan, rim_diameter=report.rim_diameter, max_diameter=nan, max_diameter_height=nan,
        base_diameter=report.base_diameter, wall_thickness_min=med([w.min() for w in walls]),
        wall_thickness_mean=med([w.mean() for w in walls]), wall_thickness_max=med([w.max() for w in walls]),
        base_thickness=nan, capacity=nan, clay_volume=abs(signed_volume(mesh.triangles)), halves=len(halves),
        spread=float(spread.max()), residual=alignment.residual, noise=alignment.noise)
    return Profile(tuple(halves), rep, spread, m, alignment, planes, name, mesh)


def _representative(halves: list[HalfProfile], height: float):
    """Medoid half (least mean RMS distance to the others) and each half's Hausdorff distance to it."""
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
