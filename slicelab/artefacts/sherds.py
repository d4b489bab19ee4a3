"""Sherds: a fragment of a vessel recognised, set in its stance by its lip or base, and measured.

Most of a lab's finds are sherds. `slicelab.artefacts.align` finds a
sherd's axis from its own surface (the normal lines of any piece of a
surface of revolution meet the axis; `slicelab.artefacts.axis_lines`) and
calls it a sherd when its facets do not go round that axis. `sherd_stance`
then:

1. cuts the sherd by meridian planes inside the angles every height of it
   covers (`slicelab.artefacts.strips.core_interval`: a section elsewhere
   meets a side break); each section is a strip of wall whose two ends cross
   the wall (`slicelab.artefacts.strips.strip`);
2. looks for a base: a broad plane face square to the axis at one extreme,
   the wall rising from its outer edge;
3. judges which end is the lip (`slicelab.artefacts.lips.judge_ends`): the
   vessel's own surface is the same in every section, a break is not;
4. fixes the stance: the lip up, or the base down; with neither, the
   stance is a guess; each decision (kind, up) carries a confidence, and
   where the alternatives are close a warning code says so rather than
   picking one silently;
5. measures the rim (a least-squares circle through the lip's outer edge in
   each section, with its uncertainty; the EVE from the lip's arc) or the
   base (the footprint's edge, and the share of its circle kept), and judges
   whether the axis can be trusted: fits on the two halves of the sherd
   (split by angle) must agree with the whole (`SherdReport`).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..mesh.core import Mesh
from .axis_fit import rotation_to_z
from .axis_lines import SurfaceSample, fit_axis_lines
from .bases import base_measure, base_side
from .lips import BREAK_RATIO, LIP_RATIO, circle_radius, judge_ends, lip_arc, lip_confidence, rim_points, \
    up_confidence
from .strips import core_interval, meridian_rings, sherd_interval, strip

__all__ = ["SherdReport", "sherd_interval", "meridian_rings", "sherd_wall", "sherd_stance", "TRUSTED_AXIS",
           "CONFIDENT"]

#: Degrees the halves' axes may stray from the whole's before the axis is not trusted.
TRUSTED_AXIS = 5.0
#: A decision less sure than this gets a warning code.
CONFIDENT = 0.85
_SECTIONS = 13
_RIM_SD = 0.01     # a rim diameter less sure than this share of itself gets a warning


@dataclass(frozen=True)
class SherdReport:
    """What a sherd is, how sure that is, and what can be measured on it.

    Attributes
    ----------
    kind : str
        ``"rim"``, ``"base"`` or ``"body"``.
    span : float
        Degrees the sherd covers about the axis.
    rim_span : float
        Degrees of rim kept: the lip's arc (NaN without a rim).
    rim_fraction : float
        `rim_span` / 360: the sherd's EVE (NaN without a rim; a body or base sherd carries none).
    rim_diameter : float
        The rim's outer diameter (mm; NaN without a rim): a least-squares circle through the lip's
        outer edge in the plane normal to the axis.
    base_diameter : float
        Diameter of the footprint's edge (mm; NaN without a base).
    axis_trusted : bool
        The sherd's two halves (split by angle) agree with the whole: for a rim or a base, their
        level faces' planes within `TRUSTED_AXIS` degrees and their axes' offsets within 3 % of the
        radius; for a body sherd, their axes within a third of `TRUSTED_AXIS`, and then (checked by
        `slicelab.artefacts.align`) each half, searched on its own, finds no axis more than half of
        `TRUSTED_AXIS` away that fits it about as well, and a clean mesh's normals meet the axis
        to rounding.
    axis_spread : float
        The angle (degrees) between the halves' planes, or between their axes and the whole's,
        or to a rival axis.
    up_from : str
        ``"rim"``, ``"base plane"`` or ``"unknown"`` (the stance is a guess).
    rim_diameter_sd : float
        Standard uncertainty of `rim_diameter` (mm; NaN without a rim).
    base_fraction : float
        Share of the footprint's circle the sherd keeps (NaN without a base).
    kind_confidence : float
        How sure `kind` is, 0..1: that the lip is a lip and not a level break (a rim sherd), that
        neither end is a lip (a body sherd), that the base is a base.
    up_confidence : float
        How sure the stance is, 0..1 (0.5: a guess).
    axis_confidence : float
        How sure the axis is, 0..1: 1 when the halves agree exactly, 0.5 at the trust limit.
    end_ratios : tuple of float
        How far each end of the sections moves between neighbours, over how far the faces move
        (`slicelab.artefacts.lips.EndJudgement.ratio`): the lip first.
    warnings : tuple of str
        Codes of the decisions a lab should check: ``kind_uncertain``, ``up_uncertain``,
        ``axis_uncertain``, ``rim_uncertain``, ``base_uncertain`` (see `SherdReport.cautions`).
    base_diameter_sd : float
        Standard uncertainty of `base_diameter` (mm; NaN without a base).
    """

    kind: str
    span: float
    rim_span: float = math.nan
    rim_fraction: float = math.nan
    rim_diameter: float = math.nan
    base_diameter: float = math.nan
    axis_trusted: bool = False
    axis_spread: float = math.nan
    up_from: str = "unknown"
    rim_diameter_sd: float = math.nan
    base_fraction: float = math.nan
    kind_confidence: float = math.nan
    up_confidence: float = 0.5
    axis_confidence: float = 0.0
    end_ratios: tuple = field(default=())
    warnings: tuple = field(default=())
    base_diameter_sd: float = math.nan

    def sentence(self) -> str:
        """One line for a report, e.g. ``sherd: rim, 62 degrees, 17 % of the rim``.

        Examples
        --------
        >>> SherdReport("rim", 62.0, 61.0, 61 / 360, 97.6, axis_trusted=True, up_from="rim").sentence()
        'sherd: rim, 62 degrees, 17 % of the rim (rim diameter 97.6 mm)'
        >>> SherdReport("rim", 62.0, 61.0, 61 / 360, 97.6, axis_trusted=True, up_from="rim", rim_diameter_sd=0.4).sentence()
        'sherd: rim, 62 degrees, 17 % of the rim (rim diameter 97.6 +- 0.4 mm)'
        >>> SherdReport("body", 40.0).sentence()
        'body sherd: no axis can be trusted (40 degrees)'
        """
        if not self.axis_trusted:
            return f"{self.kind} sherd: no axis can be trusted ({self.span:.0f} degrees)"
        text = f"sherd: {self.kind}, {self.span:.0f} degrees"
        if self.kind == "rim" and math.isfinite(self.rim_fraction):
            text += f", {100 * self.rim_fraction:.0f} % of the rim"
            if math.isfinite(self.rim_diameter):
                sd = f" +- {self.rim_diameter_sd:.1f}" if math.isfinite(self.rim_diameter_sd) else ""
                text += f" (rim diameter {self.rim_diameter:.1f}{sd} mm)"
        if self.kind == "base" and math.isfinite(self.base_diameter):
            text += f" (base diameter {self.base_diameter:.1f} mm"
            text += f", {100 * self.base_fraction:.0f} % of the base)" if math.isfinite(self.base_fraction) else ")"
        return text

    def cautions(self) -> list:
        """(code, sentence) for each of `warnings`.

        Examples
        --------
        >>> SherdReport("rim", 60.0, kind_confidence=0.6, up_confidence=0.55,
        ...             warnings=("kind_uncertain", "up_uncertain")).cautions()[1][1][:45]
        'which end is the lip is uncertain (55 % sure)'
        """
        said = {"kind_uncertain": f"the sherd's kind ({self.kind}) is uncertain "
                                  f"({100 * self.kind_confidence:.0f} % sure): "
                + ("an end the same in every section may be a level break (a coil joint) rather than a lip"
                   if self.kind == "rim" else "an end looks almost like a lip; check for a rim"),
                "up_uncertain": f"which end is the lip is uncertain ({100 * self.up_confidence:.0f} % sure): an "
                                f"end that runs level may be the lip or a level break; the drawing may stand "
                                f"on its head",
                "axis_uncertain": "the sherd's axis is uncertain: " + (
                    f"its halves disagree by {self.axis_spread:.1f} degrees" if math.isfinite(self.axis_spread)
                    else "its halves could not each be fitted"),
                "rim_uncertain": f"the rim diameter and EVE are uncertain: {self.rim_diameter:.1f} +- "
                                 f"{self.rim_diameter_sd:.1f} mm, {100 * self.rim_fraction:.0f} % of the rim "
                                 f"(a short or coarse lip, an axis not trusted, or a lip that may be a level break)",
                "base_uncertain": f"the base diameter is uncertain: {self.base_diameter:.1f} +- "
                                  f"{self.base_diameter_sd:.1f} mm (a short arc, or an axis not trusted)"}
        return [(w, said.get(w, w)) for w in self.warnings]

    def to_dict(self) -> dict:
        """Plain values (NaN where a measurement does not apply; tuples as lists)."""
        return {k: (list(v) if isinstance(v, tuple) else v) for k, v in
                ((k, getattr(self, k)) for k in self.__dataclass_fields__)}


def sherd_wall(ring: np.ndarray, noise: float = 0.0) -> np.ndarray:
    """Wall thickness along a sherd's section: from each point of its faces (`slicelab.artefacts.strips`)
    to the other face, the points within a wall thickness of the strip's ends left out.

    Examples
    --------
    >>> strip_ = np.array([[40, 0], [44, 0], [44, 30], [40, 30]], float)
    >>> t = sherd_wall(strip_)
    >>> round(float(t.min()), 3), round(float(t.max()), 3)
    (4.0, 4.0)
    """
    from scipy.spatial import cKDTree
    s = strip(ring, 0.0, noise)
    if s is None:
        return np.zeros(0)
    face = s.end < 0
    ends = s.points[~face]
    pts = s.points[face]
    near_end = cKDTree(ends).query(pts)[0] <= s.thickness
    # The faces: split where the boundary's run of face points breaks (at the ends).
    idx = np.flatnonzero(face)
    cut = np.flatnonzero(np.diff(idx) > 1)
    parts = np.split(idx, cut + 1)
    if len(parts) > 2:  # the run that wraps round the ring's start
        parts = [np.concatenate([parts[-1], parts[0]])] + parts[1:-1]
    if len(parts) < 2:
        return np.zeros(0)
    a, b = sorted(parts, key=len)[-2:]
    d = cKDTree(s.points[b]).query(s.points[a])[0]
    keep = ~near_end[np.searchsorted(idx, a)]
    return d[keep]


def _plane_normal(pts: np.ndarray):
    """Unit normal (z >= 0) of the best plane through points, three rounds of dropping those over
    three robust sigmas off it; None for fewer than 20 points."""
    nrm = None
    for _ in range(3):  # robust rounds
        if len(pts) < 20:
            return nrm
        c = pts.mean(axis=0)
        _, _, vt = np.linalg.svd(pts - c, full_matrices=False)
        nrm = vt[2] if vt[2][2] >= 0 else -vt[2]
        dist = (pts - c) @ nrm
        pts = pts[np.abs(dist) <= max(3 * 1.4826 * float(np.median(np.abs(dist))), 1e-12)]
    return nrm


def _frame(mesh: Mesh, p, d):
    R = rotation_to_z(d)
    return R, Mesh(np.einsum("...j,ij->...i", mesh.triangles - p, R))


def _strips(local: Mesh, verts: np.ndarray, noise: float, count: int = _SECTIONS):
    """Meridian sections inside the sherd's core angles, as strips (None dropped): `count`, or as many
    as the facets are wide about the axis (sections between a coarse mesh's vertices only interpolate
    its neighbours, so a break's wavering would look smooth)."""
    start, width = sherd_interval(verts)
    lo, hi = core_interval(verts, start, width)
    phi = np.arctan2(local.triangles[..., 1], local.triangles[..., 0])
    facet = float(np.median(np.ptp(np.unwrap(phi, axis=1), axis=1)))
    count = int(np.clip((hi - lo) / max(facet, 1e-9), 4, count))
    margin = 0.04 * (hi - lo)
    angles = start + lo + margin + (hi - lo - 2 * margin) * np.linspace(0.0, 1.0, count)
    rings = meridian_rings(local, angles)
    out = [strip(r, a, noise) for a, r in zip(angles, rings) if r is not None and len(r) >= 8]
    return [s for s in out if s is not None], start, width


def _confidence(spread: float, limit: float) -> float:
    """0..1 from an axis spread (degrees) against its trust limit: 1 at 0, 0.5 at the limit."""
    return 1.0 / (1.0 + (spread / limit) ** 2) if math.isfinite(spread) else 0.0


def sherd_stance(mesh: Mesh, sample: SurfaceSample, point, direction, noise: float):
    """The stance of a sherd (lip up, or base down), its axis refined by the lip or base, and its report.

    Parameters
    ----------
    mesh : Mesh
        The sherd in input coordinates.
    sample : SurfaceSample
        Its smoothed normals (`slicelab.artefacts.axis_lines.smoothed_normals`).
    point, direction : (3,) ndarray
        The axis fitted to the normal lines (either sense).
    noise : float
        The scan's noise sigma (mm).

    Returns
    -------
    point, direction : (3,) ndarray
        The axis, `direction` from base to rim.
    report : SherdReport

    See Also
    --------
    slicelab.artefacts.align : calls it for a fragment.
    slicelab.artefacts.lips.judge_ends : which end is the lip.

    Examples
    --------
    >>> from slicelab.samples import scan
    >>> from slicelab.artefacts import smoothed_normals, search_axis
    >>> sherd, truth = scan("beaker", spacing=1.0, sherd="rim", span=90.0)
    >>> s = smoothed_normals(sherd.triangles)
    >>> p, d, _ = search_axis(s)
    >>> p, d, report = sherd_stance(sherd, s, p, d, 0.0)
    >>> report.kind, report.up_from, bool(d @ truth["axis"] > np.cos(np.radians(1)))
    ('rim', 'rim', True)
    """
    point = np.asarray(point, dtype=np.float64)
    direction = np.asarray(direction, dtype=np.float64) / np.linalg.norm(direction)
    tol = max(4 * noise, 0.3)
    R, local = _frame(mesh, point, direction)
    verts = local.triangles.reshape(-1, 3)
    strips, _, _ = _strips(local, verts, noise)
    t_wall = float(np.median([s.thickness for s in strips])) if strips else 4.0
    base = base_side(verts, t_wall, tol)
    kind, up_from = "body", "unknown"
    kind_conf, up_conf = 0.5, 0.5
    lip_judgement = None
    first = judge_ends(strips, exclude=-base if base else None)
    rival = 1.0  # how sure the kind can be at most: less when a base and a lip both stand a chance
    if base and first is not None and first.lip is not None and first.kind_confidence > 0.5:
        # A lip at the other end too: a whole profile's sherd, a plate's wall or a bowl's low, nearly
        # level wall taken for a base. The lip decides (the EVE is what a lab counts); when it is
        # not sure, neither is the kind, and the warning says so.
        base = 0
        rival = max(first.kind_confidence, 0.5)
    if base:
        kind, up_from, kind_conf, up_conf = "base", "base plane", 0.95, 0.97
        direction = base * direction
    elif first is not None:
        kind_conf = first.kind_confidence
        # Each end that may be the lip is tried: set up, the axis refined by its crest's plane, and
        # judged again; the hypotheses are compared under their own best axes.
        tries = []
        for k in (0, 1):
            if first.ratio[k] > 3 * BREAK_RATIO:
                continue  # an irregular break: no lip
            d_k = direction if first.height[k] >= first.height[1 - k] else -direction
            p_k, d_k, j_k = _lip_axis(mesh, sample, point, d_k, noise)
            if j_k is not None:
                top = int(np.argmax(j_k.height))
                tries.append((float(j_k.ratio[top]), p_k, d_k, j_k, top))
        if tries:
            tries.sort(key=lambda x: x[0])
            best = tries[0]
            if best[0] <= math.sqrt(LIP_RATIO * BREAK_RATIO):
                kind, up_from = "rim", "rim"
                point, direction = best[1], best[2]
                j, top = best[3], best[4]
                lip_judgement = _lip_up(j)
                kind_conf = lip_confidence(best[0]) if j.consistent else 0.5
                # Up: this hypothesis's lip against the other end, in its frame and in the other's.
                rival = min([float(j.ratio[1 - top])] + [x[0] for x in tries[1:]])
                up_conf = up_confidence(best[0], rival) if j.consistent else 0.5
            else:
                kind_conf = 1.0 - lip_confidence(best[0])
    kind_conf = min(kind_conf, rival)
    face_of = None
    if kind == "base":
        point, direction = _level_face(mesh, sample, point, direction, "base", tol, t_wall)
    if kind in ("rim", "base"):
        def face_of(p, d):
            return _face(mesh, p, d, kind, tol, t_wall)
    spread, trusted, offset = _trust(mesh, sample, point, direction, face_of)
    # The axis's position: uncertain by about half the halves' disagreement, and by the noise.
    axis_sd = max(0.5 * offset, 2.5 * noise)
    if kind in ("rim", "base"):
        point, centre_sd, radius = _recentre(mesh, point, direction, noise, kind, tol, axis_sd)
        if not trusted and spread <= TRUSTED_AXIS and centre_sd <= 0.01 * radius:
            # The normal lines of a flat base leave the halves' offsets loose; its circle does not.
            trusted = True
    R, local = _frame(mesh, point, direction)
    verts = local.triangles.reshape(-1, 3)
    start, width = sherd_interval(verts)
    rim_span = rim_fraction = rim_d = rim_sd = base_d = base_sd = base_frac = math.nan
    ratios = ()
    arc_step = 0.0
    if kind == "rim":
        j = lip_judgement  # in this frame already (only a base's axis is moved onto its circle)
        if j is not None:
            ratios = (float(j.ratio[j.lip]), float(j.ratio[1 - j.lip]))
            a, z_top, r_edge = rim_points(j)
            radius, sd = circle_radius(a, r_edge, axis_sd)
            rim_d, rim_sd = 2 * radius, 2 * sd
            arc, arc_step = lip_arc(local.triangles, float(np.median(z_top)), t_wall, noise)
            if math.isfinite(arc):
                rim_span = math.degrees(arc)
                rim_fraction = rim_span / 360.0
    elif kind == "base":
        base_d, base_sd, base_frac = base_measure(verts, _strips(local, verts, noise)[0], noise, tol, axis_sd)
    warnings = []
    if kind_conf < CONFIDENT:
        warnings.append("kind_uncertain")
    if kind != "body" and up_conf < CONFIDENT:
        warnings.append("up_uncertain")
    if not trusted:
        warnings.append("axis_uncertain")
    if kind == "rim" and (not math.isfinite(rim_sd) or rim_sd > _RIM_SD * rim_d or not math.isfinite(rim_fraction)
                          or arc_step > math.radians(3.6) or not trusted or up_conf < CONFIDENT):
        # (a lip of facets over 3.6 degrees wide: each end of its arc is a point of EVE uncertain;
        # an axis not trusted: the circle the lip is measured on is not the vessel's; the stance
        # uncertain: the end measured as the lip may be a level break, its circle another diameter)
        warnings.append("rim_uncertain")
    if kind == "base" and (not math.isfinite(base_sd) or base_sd > _RIM_SD * base_d or not trusted):
        warnings.append("base_uncertain")
    limit = TRUSTED_AXIS if face_of is not None else TRUSTED_AXIS / 3
    report = SherdReport(kind, math.degrees(width), rim_span, rim_fraction, rim_d, base_d, bool(trusted),
                         float(spread), up_from, rim_sd, base_frac, float(kind_conf), float(up_conf),
                         _confidence(spread, limit), ratios, tuple(warnings), base_sd)
    return point, direction, report


def _lip_up(j):
    """The judgement with its lip the higher end (the frame is lip up once the stance is set)."""
    from dataclasses import replace
    return replace(j, lip=int(np.argmax(j.height)))


def _face(mesh: Mesh, p, d, kind: str, tol: float, t_wall: float):
    """A rim's crest band (the top 2 tol, about its own median radius) or a base's underside band
    (the bottom 2 tol): its vertices in the frame of (p, d), and the frame."""
    R_, loc = _frame(mesh, p, d)
    v = np.unique(loc.triangles.reshape(-1, 3), axis=0)
    r_ = np.hypot(v[:, 0], v[:, 1])
    if kind == "rim":
        band = v[:, 2] >= v[:, 2].max() - 2 * tol
        sel = band & (np.abs(r_ - float(np.median(r_[band]))) <= 1.5 * t_wall)
    else:
        sel = v[:, 2] <= v[:, 2].min() + 2 * tol
    return v[sel], R_


def _lip_axis(mesh: Mesh, sample: SurfaceSample, point, direction, noise: float, rounds: int = 2):
    """The axis refined under the hypothesis that the sherd's higher end is its lip: the normal lines'
    direction and the plane of the lip's crest across the sections (`slicelab.artefacts.lips.crest_plane`),
    combined by their covariances (a clean mesh's normals fix it; a flat land's plane fixes the tilt
    along the arc, a short arc's not across it); the offsets from the normal lines. Returns the point,
    the direction (the lip's way up) and the judgement of the ends in that frame."""
    from .lips import crest_plane
    j = None
    for _ in range(rounds):  # two rounds: the crest seen in a nearly level frame
        f = fit_axis_lines(sample, point, direction)
        R, local = _frame(mesh, f.point, f.direction)
        j = judge_ends(_strips(local, local.triangles.reshape(-1, 3), noise)[0])
        point, direction = f.point, f.direction
        if j is None:
            break
        j = _lip_up(j)
        tilt, cov_p = crest_plane(j)
        cov_n = f.cov[:2, :2] if f.cov is not None else np.full((2, 2), np.inf)
        if not np.all(np.isfinite(cov_p)):
            break
        info_p = np.linalg.pinv(cov_p + 1e-14 * np.eye(2))
        info_n = np.linalg.pinv(cov_n + 1e-14 * np.eye(2)) if np.all(np.isfinite(cov_n)) else np.zeros((2, 2))
        t = np.linalg.solve(info_p + info_n + 1e-12 * np.eye(2), info_p @ tilt)
        d = R.T @ np.array([t[0], t[1], 1.0])
        direction = d / np.linalg.norm(d)
        point = fit_axis_lines(sample, point, direction, tilt=False).point
    if j is not None:
        R, local = _frame(mesh, point, direction)
        j2 = judge_ends(_strips(local, local.triangles.reshape(-1, 3), noise)[0])
        j = _lip_up(j2) if j2 is not None else j
    return point, direction, j


def _level_face(mesh: Mesh, sample: SurfaceSample, point, direction, kind: str, tol: float, t_wall: float):
    """The axis refined by a level face: its plane's normal gives the direction (three rounds: a
    tilted start sees part of the face, each round more), the normal lines the offsets."""
    for _ in range(3):  # a few rounds
        face, R = _face(mesh, point, direction, kind, tol, t_wall)
        nrm = _plane_normal(face)
        if nrm is None or nrm[2] <= math.cos(math.radians(10)):
            break
        direction = R.T @ nrm
        point = fit_axis_lines(sample, point, direction, tilt=False).point
        if nrm[2] >= math.cos(math.radians(0.01)):
            break
    return point, direction


def _recentre(mesh: Mesh, point, direction, noise: float, kind: str, tol: float, axis_sd: float):
    """The axis moved onto the centre of the rim's (or the base's) circle when that centre lies off
    the axis by more than three of its own uncertainties and three of the axis's (the normal lines
    of a flat base or a gently curved plate barely place the axis; the circle does)."""
    from .bases import base_points
    from .lips import fit_circle
    R, local = _frame(mesh, point, direction)
    verts = local.triangles.reshape(-1, 3)
    strips = _strips(local, verts, noise)[0]
    if kind == "rim":
        j = judge_ends(strips)
        if j is None:
            return point, math.inf, math.nan
        a, _, r = rim_points(_lip_up(j))
    else:
        _, a, r = base_points(verts, strips, tol)
    if len(r) < 5:
        return point, math.inf, math.nan
    cx, cy, radius, _, sd_c = fit_circle(r * np.cos(a), r * np.sin(a), centre_sd=True)
    off = math.hypot(cx, cy)
    # Only a base's circle, and over 40 degrees of it: a rim's wall places the axis better than a short
    # arc does, and a short arc's centre is looser than its residuals say.
    if kind == "base" and np.ptp(a) >= math.radians(40) and math.isfinite(sd_c) and off > 3 * sd_c \
            and off > 3 * axis_sd:
        point = point + R.T @ np.array([cx, cy, 0.0])
    return point, (sd_c if math.isfinite(sd_c) else math.inf), radius


def _trust(mesh, sample, point, direction, face_of):
    """The halves' disagreement (degrees), whether the axis is trusted (see `SherdReport`), and the
    largest distance (mm) of a half's axis from the whole's."""
    R, local = _frame(mesh, point, direction)
    start, width = sherd_interval(local.triangles.reshape(-1, 3))
    q = np.einsum("ij,kj->ik", sample.points - point, R)
    phi = (np.arctan2(q[:, 1], q[:, 0]) - start) % (2 * np.pi)
    spread, offset = 0.0, 0.0
    ref_r = float(np.median(np.hypot(q[:, 0], q[:, 1])))
    if face_of is not None:
        face, _ = face_of(point, direction)
        fphi = (np.arctan2(face[:, 1], face[:, 0]) - start) % (2 * np.pi)
        normals = [_plane_normal(face[part]) for part in (fphi < width / 2, fphi >= width / 2)]
        spread = math.inf if any(n is None for n in normals) else \
            math.degrees(math.acos(min(1.0, abs(float(normals[0] @ normals[1])))))
    for part in (phi < width / 2, phi >= width / 2):
        if part.sum() < 50:
            spread = math.inf
            continue
        sub = SurfaceSample(sample.points[part], sample.normals[part], sample.weights[part], sample.spacing,
                            sample.rounds, sample.kept_share, sample.noise)
        f = fit_axis_lines(sub, point, direction, tilt=face_of is None)
        gap = f.point - point
        offset = max(offset, float(np.linalg.norm(gap - (gap @ direction) * direction)))
        if face_of is None:
            spread = max(spread, math.degrees(math.acos(min(1.0, abs(float(f.direction @ direction))))))
    if face_of is None:
        return spread, spread <= TRUSTED_AXIS / 3, offset
    return spread, spread <= TRUSTED_AXIS and offset <= 0.03 * ref_r, offset
