"""A sherd's lip told from its breaks, and the rim measured on it: diameter with its uncertainty, EVE.

The lip is the vessel's own surface where the outer and the inner face of
the wall meet at its top: turned on a wheel or smoothed by hand, the same in
every meridian section. A break crosses the wall along a line that wavers
and over a face whose grain is rough: its section differs from one meridian
to the next. So each end of the sherd's section strips
(`slicelab.artefacts.strips`) is judged by how far it moves between
neighbouring sections, against how far the wall's faces move (the noise,
and any error in the axis, move both alike):

* ``ratio`` = the end's spread over the faces' spread: about 1 for a lip,
  tens for an irregular break, 1.5-5 for a level break with a rough face,
  about 1 again for a level break whose face is smooth (which no geometry
  tells from a square-cut lip: the judgement then says so);
* the end with the smaller ratio is the lip when it is lip-like (ratio under
  `LIP_RATIO`); the confidence that it, and not the other, is the lip is a
  logistic function of the ratios' log-ratio, and that the sherd has a lip
  at all of the smaller ratio against `BREAK_RATIO`.

The rim is then measured where the lip is: in each section the exterior
face, fitted just below the lip's rounding, is continued up to the crest's
plane (the rim's outer edge, `slicelab.samples.vessel_truth`'s definition);
those points, in the plane normal to the axis, get a least-squares circle
(Gauss-Newton from Kåsa's fit [1]_) whose radius carries its standard
uncertainty from the fit's covariance. The EVE is the lip's arc: the angle
the crest's outer half covers about the circle's centre, over 360 degrees.

References
----------
.. [1] I. Kåsa, "A circle fitting procedure and its error analysis", *IEEE
   Transactions on Instrumentation and Measurement* IM-25(1), 8-14, 1976.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .strips import Strip

__all__ = ["LIP_RATIO", "BREAK_RATIO", "EndJudgement", "judge_ends", "lip_confidence", "up_confidence", "crest_height", "rim_points", "edge_radius",
           "fit_circle", "circle_radius", "lip_arc", "crest_plane"]

#: An end that moves between sections at most this many times as far as the faces do is lip-like.
LIP_RATIO = 2.0
#: At least this many times: a break (between the two, a lip or a smooth level break cannot be told).
BREAK_RATIO = 4.0
_FLOOR = 0.02      # mm: the faces' spread is taken as at least this (a clean mesh's sections agree to rounding)
_STEEP = 2.0       # logistic slope per unit of log-ratio: a ratio of 3 between the ends gives 0.9


def _logistic(x: float) -> float:
    return 1.0 / (1.0 + math.exp(-max(-50.0, min(50.0, x))))


def lip_confidence(ratio: float) -> float:
    """That an end of this ratio (how far it moves between sections over how far the faces move) is
    a lip: 0.5 in the middle of the grey zone between `LIP_RATIO` and `BREAK_RATIO`, 0.8 at
    `LIP_RATIO`, 0.2 at `BREAK_RATIO`.

    Examples
    --------
    >>> round(lip_confidence(1.0), 3), round(lip_confidence(8.0), 3)
    (0.985, 0.015)
    """
    mid = math.log(math.sqrt(LIP_RATIO * BREAK_RATIO))
    return _logistic(2 * _STEEP * (mid - math.log(max(ratio, 1e-9))))


def up_confidence(lip_ratio: float, other_ratio: float) -> float:
    """That the end of `lip_ratio` is the lip rather than the end of `other_ratio`: 0.5 when they are
    alike, 0.9 when the other moves three times as far.

    Examples
    --------
    >>> round(up_confidence(1.0, 3.0), 2), up_confidence(1.0, 1.0)
    (0.9, 0.5)
    """
    return _logistic(_STEEP * (math.log(max(other_ratio, 1e-9)) - math.log(max(lip_ratio, 1e-9))))


@dataclass(frozen=True, eq=False)
class EndJudgement:
    """The two ends of a sherd's section strips, which is the lip, and how sure that is.

    Attributes
    ----------
    strips : tuple of Strip
        The sections' strips, by angle.
    order : (n, 2) int ndarray
        Per strip, its end index that belongs to end 0 and to end 1.
    spread : (2,) ndarray
        How far each end moves between neighbouring sections (mm; median over pairs).
    face_spread : float
        The same for the faces (mm, at least 0.02).
    height : (2,) ndarray
        Median height of each end's centre (mm, in the frame of the sections).
    lip : int or None
        The end that is the lip (0 or 1), or None (no end is lip-like).
    kind_confidence : float
        That the sherd has a lip (when `lip` is set) or has none (when not), 0..1.
    up_confidence : float
        That the lip is `lip` and not the other end (0.5 without a lip).
    """

    strips: tuple
    order: np.ndarray
    spread: np.ndarray
    face_spread: float
    height: np.ndarray
    lip: int | None
    kind_confidence: float
    up_confidence: float

    @property
    def consistent(self) -> bool:
        """The faces agree from section to section within 0.15 wall thicknesses: the axis is the
        vessel's (else no end can be told from another)."""
        return bool(self.face_spread <= 0.15 * float(np.median([s.thickness for s in self.strips])))

    @property
    def ratio(self) -> np.ndarray:
        """Each end's spread over the faces'."""
        return self.spread / self.face_spread

    def end_points(self, i: int, which: int) -> np.ndarray:
        """The points of end `which` (0 or 1) in strip `i`."""
        return self.strips[i].end_points(int(self.order[i, which]))


def _adjacent_spread(curves) -> float:
    """Median, over neighbouring curves, of the median distance from one's points to the other's."""
    from scipy.spatial import cKDTree
    d = []
    for a, b in zip(curves[:-1], curves[1:]):  # a dozen neighbouring pairs
        if len(a) >= 2 and len(b) >= 2:
            d.append(float(np.median(cKDTree(b).query(a)[0])))
            d.append(float(np.median(cKDTree(a).query(b)[0])))
    return float(np.median(d)) if d else math.nan


def judge_ends(strips, *, exclude: int | None = None) -> EndJudgement | None:
    """Group the strips' ends into the sherd's two ends and judge which is the lip.

    Parameters
    ----------
    strips : sequence of Strip
        By angle; at least three.
    exclude : int, optional
        Never call this end the lip: +1 the higher, -1 the lower one (a base sherd's inner break,
        when the base is known to be down).

    Returns
    -------
    EndJudgement or None
        None for fewer than three strips.

    Examples
    --------
    >>> from slicelab.artefacts.strips import strip
    >>> ring = lambda k: np.array([[40, 0.8 * (k % 2)], [44, -0.5 * (k % 2)], [44, 30], [40, 30]])
    >>> j = judge_ends([strip(ring(k), 0.1 * k, 0.0) for k in range(5)])
    >>> j.lip == int(np.argmax(j.height)), j.up_confidence > 0.9, j.kind_confidence > 0.9
    (True, True, True)
    """
    strips = [s for s in strips if s is not None]
    if len(strips) < 3:
        return None
    # The longest strip's ends are the references; each strip's ends go to the nearer.
    length = [float(np.hypot(*(s.centre(0) - s.centre(1)))) for s in strips]
    ref = strips[int(np.argmax(length))]
    c0, c1 = ref.centre(0), ref.centre(1)
    order = []
    for s in strips:  # a dozen strips
        a, b = s.centre(0), s.centre(1)
        same = np.hypot(*(a - c0)) + np.hypot(*(b - c1)) <= np.hypot(*(a - c1)) + np.hypot(*(b - c0))
        order.append((0, 1) if same else (1, 0))
    order = np.array(order)
    ends = [[s.end_points(int(o[w])) for s, o in zip(strips, order)] for w in (0, 1)]
    faces = [s.points[s.end < 0] for s in strips]
    face = max(_adjacent_spread(faces), _FLOOR)
    spread = np.array([_adjacent_spread(e) for e in ends])
    height = np.array([float(np.median([c.mean(axis=0)[1] for c in e])) for e in ends])
    ratio = spread / face
    candidates = [0, 1]
    if exclude is not None:
        candidates.remove(int(np.argmax(height)) if exclude > 0 else int(np.argmin(height)))
    best = min(candidates, key=lambda k: ratio[k])
    other = 1 - best
    lip = best if ratio[best] <= math.sqrt(LIP_RATIO * BREAK_RATIO) else None
    # Confidence that the sherd has a lip: the best end's ratio against the middle of the grey zone.
    has_lip = lip_confidence(float(ratio[best]))
    up = 1.0 if exclude is not None else up_confidence(float(ratio[best]), float(ratio[other]))
    kind_conf = has_lip if lip is not None else 1.0 - has_lip
    thick = float(np.median([st.thickness for st in strips]))
    if face > 0.15 * thick:
        # The faces themselves differ from section to section: the axis is not the vessel's, and
        # no end can be told from another.
        kind_conf, up = min(kind_conf, 0.5), 0.5
    return EndJudgement(tuple(strips), order, spread, face, height, lip, float(kind_conf),
                        float(up if lip is not None else 0.5))


def _run(s: Strip, k: int):
    """The first and last ring index of end `k` (its run may wrap round the ring's start)."""
    idx = np.flatnonzero(s.end == k)
    gaps = np.flatnonzero(np.diff(idx) > 1)
    return (int(idx[gaps[0] + 1]), int(idx[gaps[0]])) if len(gaps) else (int(idx[0]), int(idx[-1]))


def _exterior_window(s: Strip, k: int, skip: float, length: float):
    """The exterior face next to end `k` of a strip, unsmoothed: points from `skip` to `skip +
    length` mm along the boundary away from the end, on the side of the larger radius."""
    n = len(s.points)
    first, last = _run(s, k)
    m = max(int(round(length / s.step)), 3)
    q = int(round(skip / s.step))
    raw = s.raw if s.raw is not None else s.points
    before = (first - q - np.arange(m)) % n
    after = (last + q + np.arange(m)) % n

    def face(idx):  # up to the first point of an end (a short sherd's other end)
        stop = int(np.argmax(s.end[idx] >= 0)) if (s.end[idx] >= 0).any() else len(idx)
        return idx[:max(stop, 3)]
    before, after = face(before), face(after)
    return raw[before] if s.points[before, 0].mean() > s.points[after, 0].mean() else raw[after]


def crest_height(s: Strip, k: int, up: float = 1.0) -> float:
    """The height of end `k`'s crest: the median height (unsmoothed) of its points whose normal is
    within 15 degrees of up (a flat land's whole width, a rounded lip's top), else its highest point.

    Examples
    --------
    >>> from slicelab.artefacts.strips import strip
    >>> land = strip(np.array([[40, 0], [44, 0], [44, 30], [40, 30]], float), 0.0, 0.0)
    >>> top = int(np.argmax([land.centre(k)[1] for k in (0, 1)]))
    >>> crest_height(land, top)
    30.0
    """
    sel = s.end == k
    level = sel & (up * s.normals[:, 1] >= math.cos(math.radians(15)))
    raw = s.raw if s.raw is not None else s.points
    if level.sum() >= 3:
        return float(np.median(raw[level, 1]))
    return float((up * s.points[sel, 1]).max()) * up


def rim_points(judgement: EndJudgement, up: float = 1.0):
    """Per strip: the angle, the lip's crest height and the rim's outer edge radius there.

    The crest's height is `crest_height`'s; the edge is where the exterior
    face, fitted (unsmoothed) from half a wall thickness to three wall
    thicknesses below the lip's end (a quadratic across the face's principal
    direction), reaches the crest's height.

    Returns
    -------
    angle, z_top, r_edge : (n,) ndarray

    Examples
    --------
    >>> from slicelab.artefacts.strips import strip
    >>> ring = np.array([[40, 0], [44, 0], [44, 30], [40, 30]], float)
    >>> wavy = [ring + [[0, 0.7 * (k % 2)], [0, -0.4 * (k % 2)], [0, 0], [0, 0]] for k in range(5)]
    >>> j = judge_ends([strip(w, 0.1 * k, 0.0) for k, w in enumerate(wavy)])
    >>> a, z, r = rim_points(j)
    >>> np.round(z, 3).tolist(), np.round(r, 3).tolist()
    ([30.0, 30.0, 30.0, 30.0, 30.0], [44.0, 44.0, 44.0, 44.0, 44.0])
    """
    if judgement.lip is None:
        raise ValueError("the sherd has no lip")
    out = []
    for i, s in enumerate(judgement.strips):  # a dozen strips
        k = int(judgement.order[i, judgement.lip])
        top = crest_height(s, k, up)
        t = s.thickness
        win = _exterior_window(s, k, 0.5 * t, 2.5 * t)
        out.append((s.angle, top, edge_radius(win, top)))
    a, z, r = (np.array(x) for x in zip(*out))
    return a, z, r


def edge_radius(win: np.ndarray, top: float) -> float:
    """Radius at which a face's points, fitted by a quadratic off their principal direction, reach
    height `top` (the crossing nearest the window's point nearest that height; that point's radius if
    the face runs level).

    Examples
    --------
    >>> z = np.linspace(0, 10, 50)
    >>> round(edge_radius(np.column_stack([40 + 0.5 * z, z]), 14.0), 6)
    47.0
    """
    c = win.mean(axis=0)
    _, _, vt = np.linalg.svd(win - c, full_matrices=False)
    d, nrm = vt[0], vt[1]
    tau, w = (win - c) @ d, (win - c) @ nrm
    coef = np.polyfit(tau, w, 2) if np.ptp(tau) > 0 else np.array([0.0, 0.0, 0.0])
    # z(tau) = c_z + tau d_z + w(tau) n_z = top: a quadratic in tau.
    poly = np.array([coef[0] * nrm[1], d[1] + coef[1] * nrm[1], c[1] + coef[2] * nrm[1] - top])
    roots = np.roots(poly) if abs(poly[0]) > 1e-12 else (np.array([-poly[2] / poly[1]]) if abs(poly[1]) > 1e-9
                                                       else np.array([]))
    roots = roots[np.isreal(roots)].real
    if not len(roots) or abs(d[1]) < 0.05:
        return float(win[np.argmin(np.abs(win[:, 1] - top)), 0])
    t0 = roots[np.argmin(np.abs(roots - tau[np.argmin(np.abs(win[:, 1] - top))]))]
    return float(c[0] + t0 * d[0] + np.polyval(coef, t0) * nrm[0])


def fit_circle(x: np.ndarray, y: np.ndarray, centre_sd: bool = False):
    """Least-squares circle through points: centre, radius and the radius's standard uncertainty.

    Kåsa's algebraic fit as a start, then Gauss-Newton on the geometric
    residuals; the uncertainty is from the fit's covariance (residual
    variance times the inverse normal matrix), NaN for three points or fewer.
    With ``centre_sd``, also the centre's (the root of its covariance's trace).

    Examples
    --------
    >>> t = np.radians(np.linspace(0, 60, 13))
    >>> cx, cy, r, sd = fit_circle(50 * np.cos(t) + 1, 50 * np.sin(t) - 2)
    >>> round(cx, 6), round(cy, 6), round(r, 6), sd < 1e-6
    (1.0, -2.0, 50.0, True)
    """
    x, y = np.asarray(x, float), np.asarray(y, float)
    A = np.column_stack([2 * x, 2 * y, np.ones_like(x)])
    sol = np.linalg.lstsq(A, x * x + y * y, rcond=None)[0]
    cx, cy = sol[0], sol[1]
    r = math.sqrt(max(float(sol[2] + cx * cx + cy * cy), 0.0))
    for _ in range(20):  # Gauss-Newton on the geometric distance
        dx, dy = x - cx, y - cy
        d = np.hypot(dx, dy)
        d = np.maximum(d, 1e-12)
        res = d - r
        J = np.column_stack([-dx / d, -dy / d, -np.ones_like(d)])
        step = np.linalg.lstsq(J, -res, rcond=None)[0]
        cx, cy, r = cx + step[0], cy + step[1], r + step[2]
        if np.abs(step).max() < 1e-12 * max(r, 1.0):
            break
    dx, dy = x - cx, y - cy
    d = np.maximum(np.hypot(dx, dy), 1e-12)
    res = d - r
    if len(x) <= 3:
        return (float(cx), float(cy), float(r), math.nan) + ((math.nan,) if centre_sd else ())
    J = np.column_stack([-dx / d, -dy / d, -np.ones_like(d)])
    cov = np.linalg.pinv(J.T @ J) * float(res @ res) / (len(x) - 3)
    out = (float(cx), float(cy), float(r), math.sqrt(max(float(cov[2, 2]), 0.0)))
    return out + ((math.sqrt(max(float(cov[0, 0] + cov[1, 1]), 0.0)),) if centre_sd else ())


def lip_arc(triangles: np.ndarray, z_top: float, thickness: float, noise: float, total: bool = False):
    """The angle (radians) the lip's crest covers about the axis (the frame's z), and the angle its
    typical facet spans (how coarse the mesh is there): the facets of the
    crest's band (its top 0.05 wall thicknesses, widened by the noise, facing up within 60 degrees)
    on its outer quarter across the crest (the rim's edge: a break crossing the lip aslant covers more
    further in; all of a crest narrower than a tenth of the wall, as a bevel's ridge),
    each covering the angles between its corners (`slicelab.artefacts.strips.covered_span`):
    a coarse mesh's few facets count for what they span. With ``total``, the sum of the arcs covered
    (a reassembled vessel's rim pieces), not the span.

    Examples
    --------
    >>> from slicelab.samples import revolve
    >>> ring = revolve([[0, 0], [44, 0], [44, 30], [40, 30], [40, 2], [0, 2]], 36).triangles
    >>> keep = (np.degrees(np.arctan2(ring[..., 1], ring[..., 0])) % 360 <= 60.001).all(axis=1)
    >>> arc, step = lip_arc(ring[keep], 30.0, 4.0, 0.0)
    >>> round(float(np.degrees(arc))), round(float(np.degrees(step)))
    (60, 10)
    """
    from .strips import covered_span
    t = np.asarray(triangles, dtype=np.float64)
    c = t.mean(axis=1)
    cr = np.cross(t[:, 1] - t[:, 0], t[:, 2] - t[:, 0])
    up = cr[:, 2] >= 0.5 * np.linalg.norm(cr, axis=1)
    band = up & (c[:, 2] >= z_top - max(0.05 * thickness, 3 * noise))
    if band.sum() < 2:
        return math.nan, math.nan
    r = np.hypot(c[band, 0], c[band, 1])
    # The outer quarter across the crest, not along it: an axis a few hundredths of a mm off centre
    # tilts the radius along the arc by more than a narrow (bevelled, rounded) crest is wide, and
    # the quarter would keep one end of the arc only. So the radius's offset term is taken out first.
    phi_c = np.arctan2(c[band, 1], c[band, 0])
    basis = np.column_stack([np.ones_like(phi_c), np.cos(phi_c), np.sin(phi_c)])
    across = r - basis @ np.linalg.lstsq(basis, r, rcond=None)[0]
    # A crest narrower than a tenth of the wall (a bevel's ridge) has no outer edge to choose: a
    # quarter of it would follow the mesh's own small wobbles (hundredths of a mm) along the arc.
    # (The quarter's edge is eased by a tenth of the crest's width: the offset fit leaves a few
    # hundredths of a mm between facets that are equally far out.)
    width = np.quantile(across, 0.9) - np.quantile(across, 0.1)
    outer = t[band][across >= np.quantile(across, 0.75) - 0.1 * width] if width > 0.1 * thickness else t[band]
    arc = math.radians(covered_span(outer, np.zeros(3), np.array([0.0, 0.0, 1.0]), bins=1440, total=total))
    # How coarse the crest's facets are (radians about the axis): each end of the arc is that uncertain.
    phi = np.arctan2(outer[..., 1], outer[..., 0])
    step = float(np.median(np.ptp(np.unwrap(phi, axis=1), axis=1)))
    return arc, step


def crest_plane(judgement: EndJudgement):
    """The plane of the lip's crest across the sections, as a tilt from the frame's z axis: the
    least-squares plane ``z = a + b x + c y`` through each section's crest point, returning the
    tilt (-b, -c) of its normal and the tilt's 2 x 2 covariance (residual variance times the
    inverse normal matrix; infinite for fewer than four sections).

    Examples
    --------
    >>> from slicelab.artefacts.strips import strip
    >>> ring = np.array([[40, 0], [44, 0], [44, 30], [40, 30]], float)
    >>> a = np.radians(np.arange(0, 60, 10))
    >>> j = judge_ends([strip(ring + [[0, 0.5 * (k % 2)], [0, 0.5 * (k % 2)], [0, 0], [0, 0]], x, 0.0)
    ...                 for k, x in enumerate(a)])
    >>> tilt, cov = crest_plane(j)
    >>> np.round(tilt, 9).tolist(), bool(np.all(np.abs(cov) < 1e-12))
    ([0.0, 0.0], True)
    """
    if judgement.lip is None:
        raise ValueError("the sherd has no lip")
    pts = []
    for i, s in enumerate(judgement.strips):  # a dozen strips
        k = int(judgement.order[i, judgement.lip])
        end = s.end_points(k)
        r = float(end[np.argmax(end[:, 1]), 0])
        pts.append((r * math.cos(s.angle), r * math.sin(s.angle), crest_height(s, k)))
    p = np.array(pts)
    if len(p) < 4:
        return np.zeros(2), np.full((2, 2), np.inf)
    X = np.column_stack([np.ones(len(p)), p[:, 0] - p[:, 0].mean(), p[:, 1] - p[:, 1].mean()])
    coef, *_ = np.linalg.lstsq(X, p[:, 2], rcond=None)
    res = p[:, 2] - X @ coef
    var = float(res @ res) / (len(p) - 3)
    cov = np.linalg.pinv(X.T @ X)[1:, 1:] * var
    return -coef[1:], cov


def circle_radius(angle: np.ndarray, r: np.ndarray, axis_sd: float = 0.0):
    """The radius of a circle through points given about an axis (angle, radius), and its standard
    uncertainty: the least-squares circle's (`fit_circle`, its centre free: a short arc leaves it
    loose) and the mean radius about the axis (its uncertainty the points' scatter and the axis
    position's, `axis_sd`), combined by inverse variance; when the two disagree by more than their
    uncertainties say, the uncertainty grows by the ratio (the Birge ratio): a centre off the axis
    means the axis, or the circle, is not what it seems.

    Examples
    --------
    >>> a = np.radians(np.linspace(0, 60, 13))
    >>> r, sd = circle_radius(a, np.full(13, 50.0))
    >>> round(r, 9), sd < 1e-6
    (50.0, True)
    """
    a, r = np.asarray(angle, float), np.asarray(r, float)
    k = len(r)
    if k < 2:
        return (float(r[0]) if k else math.nan), math.nan
    r_ax = float(np.mean(r))
    sd_ax = math.sqrt(float(np.var(r, ddof=1)) / k + axis_sd ** 2)
    if k <= 3:
        return r_ax, sd_ax
    _, _, r_fit, sd_fit = fit_circle(r * np.cos(a), r * np.sin(a))
    if not (math.isfinite(sd_fit) and sd_fit > 0) or not sd_ax > 0:
        return (r_ax, sd_ax) if sd_ax > 0 else (r_fit, sd_fit)
    w1, w2 = 1 / sd_fit ** 2, 1 / sd_ax ** 2
    radius = (w1 * r_fit + w2 * r_ax) / (w1 + w2)
    chi = abs(r_fit - r_ax) / math.hypot(sd_fit, sd_ax)
    return float(radius), float(max(1.0, chi) / math.sqrt(w1 + w2))
