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

from ..mesh.core import Mesh
from . import axis
from .halves import HalfProfile, half_from_ring, half_profiles, plane_candidates, representative
from .measure import Measurements, half_outlines, measure_halves
from .partial import closing_gap, composite_half, shell_count, sherd_profile

__all__ = ["HalfProfile", "half_profiles", "Profile", "profile", "closing_gap"]

_NOT_TYPICAL = 0.05       # half-sections further apart than this share of the radius: no one profile
_MAX_CLOSING = 0.1        # an open scan's sections are closed across gaps up to this share of its size
_CLOSING_MARGIN = 1.25    # times the median gap the planes need: the noise widens some of them
_FRAGMENTS = 3            # shells (each over 0.5 % of the area) that make a mesh a reassembled vessel
_GAP = 2.0                # mm: gaps between reassembled fragments up to this are bridged


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
    capacity_refused : str
        Why the capacity is NaN though the vessel is whole ('' when it is not refused): an open scan
        whose openings are not at the rim (a broken rim, a hole).
    fragments : int
        For a vessel reassembled from fragments (`fragmentary`): the shells it holds; else 0.

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
    capacity_refused: str = ""
    fragments: int = 0

    @property
    def fragmentary(self) -> bool:
        """A vessel reassembled from fragments with gaps (three or more shells, each over 0.5 % of
        the area): drawn and measured on the union of its sections, only where preserved."""
        return self.fragments >= 3

    @property
    def rim_fraction(self) -> float:
        """Share of the rim circle kept (the EVE): a sherd's, a reassembled vessel's lip's arc, 1 for a
        whole vessel (NaN without a rim).

        Examples
        --------
        >>> from slicelab.samples import pot
        >>> profile(pot(20, 24), planes=2).rim_fraction
        1.0
        """
        if self.sherd is not None:
            return self.sherd.rim_fraction if self.sherd.kind == "rim" else float("nan")
        if not self.fragmentary:
            return 1.0
        if self.mesh is None or not math.isfinite(self.measurements.rim_diameter):
            return float("nan")
        from .lips import lip_arc
        top = float(self.drawn.polygon[:, 1].max())
        t = self.measurements.wall_thickness_mean
        arc, _ = lip_arc(self.mesh.triangles, top, t if math.isfinite(t) else 4.0, self.measurements.noise,
                         total=True)
        return arc / (2 * math.pi) if math.isfinite(arc) else float("nan")

    @property
    def warnings(self) -> list:
        """(code, sentence) for each judgement of this profile a lab should check before trusting it:
        a sherd's (`slicelab.artefacts.sherds.SherdReport.cautions`: ``kind_uncertain``,
        ``up_uncertain``, ``axis_uncertain``, ``rim_uncertain``, ``base_uncertain``),
        ``noise_uncertain`` (`slicelab.artefacts.Alignment.noise_uncertain`), ``fragmentary`` and
        ``capacity_uncertain`` (`capacity_refused`).

        Examples
        --------
        >>> from slicelab.samples import pot
        >>> profile(pot(20, 24), planes=2).warnings
        []
        """
        out = []
        if self.sherd is not None:
            out += self.sherd.cautions()
        a = self.alignment
        if a is not None and a.noise_uncertain:
            out.append(("noise_uncertain", f"the noise estimate is uncertain ({a.noise:.2f} +- {a.noise_sd:.2f} mm): "
                                           f"the outlines were smoothed by it, and the base and wall may be off"))
        if self.fragmentary:
            m = self.measurements
            gone = [n for n, v in (("height", m.height), ("rim diameter", m.rim_diameter),
                                   ("base diameter", m.base_diameter), ("capacity", m.capacity)) if not math.isfinite(v)]
            out.append(("fragmentary", f"a vessel reassembled from {self.fragments} fragments with gaps: drawn and "
                                       f"measured on the union of its sections, only where preserved"
                        + (f"; not preserved: {', '.join(gone)}" if gone else "")))
        if self.capacity_refused:
            out.append(("capacity_uncertain", f"no capacity: {self.capacity_refused}"))
        return out

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
        halves, rep, spread, m = sherd_profile(mesh, alignment, planes, max_gap)
        return Profile(tuple(halves), rep, spread, m, alignment, planes, name, mesh)
    angles = [math.pi * k / planes for k in range(planes)]
    cands = plane_candidates(mesh, angles)
    z = mesh.triangles[..., 2]
    height = float(z.max() - z.min())
    residual = alignment.residual if alignment is not None else float("nan")
    fragments = shell_count(mesh)
    if fragments >= _FRAGMENTS:
        return _fragmentary(mesh, alignment, planes, name, angles, cands, max_gap, fragments)
    halves: list[HalfProfile] = []
    for a, cand in zip(angles, cands):  # over planes
        halves += half_profiles(mesh, a, max_gap=max_gap, candidates=cand)
    closed_gap = 0.0
    refused = ""
    if not halves:
        # An open scan (the rim top not captured): every section is open. Close them across the
        # gap most planes need, if it is small beside the vessel; the report says so (`closed_gap`).
        gap, low = closing_gap(mesh, angles, cands, lowest=True)
        size = max(height, float(np.abs(mesh.triangles[..., :2]).max()))
        # The openings must be at the rim, and the rim known to be up by the base, not by the openings;
        # else (a broken rim, a hole in the upper half) the sections are closed all the same, and the
        # capacity refused.
        at_rim = low >= float(z.max()) - max(2 * gap, 0.05 * height) and \
            (alignment is None or alignment.up_from == "base")
        # Openings low on the vessel in most planes (its base missing, or cut away) leave no profile.
        _, typical = closing_gap(mesh, angles, cands, lowest="median")
        if not math.isfinite(gap) or gap > _MAX_CLOSING * size or typical < float(z.min()) + 0.5 * height:
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
        # A plane through a hole closes into a stub: its top far under the others'. Left out.
        tops = np.array([float(h.polygon[:, 1].max()) for h in halves])
        keep = tops >= float(np.median(tops)) - max(2 * closed_gap, 0.05 * height)
        halves = [h for h, k in zip(halves, keep) if k] or halves
        if not at_rim:
            refused = (f"the scan is open below its rim (a broken rim or a hole, its lowest opening "
                       f"{float(z.max()) - low:.0f} mm under the top): the sections were closed across "
                       f"{closed_gap:g} mm, and no level to fill to can be trusted")
    halves.sort(key=lambda h: h.angle)
    rep, spread = representative(halves, height)
    outs, noise = half_outlines(halves, height, alignment.noise if alignment is not None else None)
    m = measure_halves(halves, height, float(spread.max()), residual, noise, outs)
    sealed = False
    if not m.capacity > 1e-3 * m.clay_volume:  # no mouth: a sealed vessel's cavity is an inner shell
        from .cavities import cavity_volume
        void = cavity_volume(mesh)
        if void > max(m.capacity, 0.0):
            m, sealed = replace(m, capacity=void), True
    if refused:
        m = replace(m, capacity=float("nan"))
    return Profile(tuple(halves), rep, spread, m, alignment, planes, name, mesh,
                   np.array([o.z_top for o in outs]), np.array([o.max_r for o in outs]), closed_gap, sealed,
                   capacity_refused=refused)


def _fragmentary(mesh: Mesh, alignment, planes: int, name: str, angles, cands, max_gap: float,
                 fragments: int) -> Profile:
    """A vessel reassembled from fragments: measured on the union of its sections (`composite_half`),
    closed across gaps up to 2 mm; where that union does not reach the axis or the top, the numbers
    that need them (capacity, height, base thickness) are NaN."""
    half, share = composite_half(mesh, angles, cands, max_gap, bridge=_GAP)
    if half is None:
        raise ValueError("no plane through the axis crossed a closed fragment (are the fragments closed?)")
    z = mesh.triangles[..., 2]
    height = float(z.max() - z.min())
    noise = alignment.noise if alignment is not None else None
    outs, noise = half_outlines([half], height, noise)
    residual = alignment.residual if alignment is not None else float("nan")
    m = measure_halves([half], height, 0.0, residual, noise, outs)
    reaches_axis = float(half.polygon[:, 0].min()) <= 1e-6
    reaches_top = float(half.polygon[:, 1].max()) >= float(z.max()) - max(2.0, 0.02 * height)
    reaches_foot = float(half.polygon[:, 1].min()) <= float(z.min()) + max(2.0, 0.02 * height)
    nan = float("nan")
    m = replace(m, fragmentary=True,
                capacity=m.capacity if reaches_axis and reaches_top else nan,
                base_thickness=m.base_thickness if reaches_axis else nan,
                height=m.height if reaches_top and reaches_foot else nan,
                rim_diameter=m.rim_diameter if reaches_top else nan,
                base_diameter=m.base_diameter if reaches_foot else nan)
    return Profile((half,), 0, np.zeros(1), m, alignment, planes, name, mesh,
                   np.array([o.z_top for o in outs]), np.array([o.max_r for o in outs]), 0.0, False,
                   fragments=fragments)


