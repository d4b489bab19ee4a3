"""The archaeological profile drawing of a vessel: what it shows, in (r, z), and its SVG, 1:1 in mm.

Convention: a vertical axis line (dash-dot); on one side the section of the
wall filled black; on the other the exterior outline; a rim line across the
mouth; a handle, spout or lug outlined in the plane through it, on the
exterior side, and a handle's cross-section (cut level at mid-height, the
section turned into the plane of the drawing) beside it; a scale bar in
centimetres; a label with the main measurements. A sherd is drawn in sherd
position: its section only, the rim line to the reconstructed diameter
dashed, a break symbol (a jagged line) beside each end of the section that
is a break rather than the vessel's surface. Where the stance is a guess
(no rim and no base, up from the centre of mass or from an opening with no
base below it, or a low `up_confidence`)
an arrow with a question mark stands beside the section.

`parts` gives all of that in the profile's own (r, z) plane (r >= 0, z up,
mm): the DXF and CSV (`slicelab.artefacts.profile_files`) are written from it,
and `layout` mirrors it onto the page; the SVG here
(`slicelab.files.SvgDrawing`) and the PNG (`slicelab.viz.profile_png`) are
drawn from one `layout`, so none of them can disagree.
"""
from __future__ import annotations

import math
import weakref

import numpy as np

from ..files.svg import SvgDrawing

__all__ = ["layout", "profile_svg", "parts", "surfaces", "surface_runs", "orientation_uncertain", "SURFACES",
           "UNSURE_UP", "LINE", "THIN", "FONT"]

LINE = 0.35        # mm: outline pen
THIN = 0.18        # mm: axis, spread, scale bar, break symbols
FONT = 3.0         # mm: label text height
_BARS = (10, 20, 50, 100, 200, 500, 1000, 2000)
#: What each edge of a section's outline lies on: the vessel's outer or inner surface, the rim
#: (the lip, or a whole vessel's top between the two), a break (a sherd's end that is not the lip),
#: or the axis (where a half-section is cut off).
SURFACES = ("exterior", "interior", "rim", "break", "axis")
#: `up_confidence` (0-1) under which the stance is drawn as uncertain.
UNSURE_UP = 0.7
_GUESSES = ("unknown", "centre of mass", "open boundary")  # cues that leave which way is up a guess
_END_REACH = 1.25   # a strip's end: its outline within this many wall thicknesses of its extreme point
_SECTION_GAP = 8.0  # mm from a handle's outline to its cross-section drawn beside it
_PARTS = weakref.WeakKeyDictionary()  # profile -> its parts: the SVG, PNG, DXF and CSV share one


def orientation_uncertain(profile) -> bool:
    """Whether which way is up is a guess: no rim and no base (``up_from`` "unknown"), up from the
    centre of mass or from the open boundary (no base: the opening may be a break), an
    ``up_confidence`` under `UNSURE_UP` or the caution ``up_uncertain`` (where the sherd's report has them).

    Examples
    --------
    >>> from slicelab.artefacts import profile
    >>> from slicelab.samples import pot, scan
    >>> orientation_uncertain(profile(pot(20, 24), planes=2))
    False
    >>> orientation_uncertain(profile(scan("beaker", spacing=2.0, sherd="body", span=90.0)[0], planes=2))
    True
    """
    sherd, a = getattr(profile, "sherd", None), profile.alignment
    cue = sherd if sherd is not None else a
    if cue is None:  # not aligned here: the caller stood it up
        return False
    if getattr(cue, "up_from", None) in _GUESSES or "up_uncertain" in getattr(cue, "warnings", ()):
        return True
    confidence = getattr(cue, "up_confidence", None)
    return confidence is not None and math.isfinite(confidence) and confidence < UNSURE_UP


def _rows(a: np.ndarray) -> np.ndarray:
    """Each (r, z) row as one opaque value, to find rows copied from one array in another."""
    a = np.ascontiguousarray(a, dtype=np.float64).reshape(-1, 2)
    return a.view(np.dtype((np.void, 16))).ravel()


def _strip_ends(ring: np.ndarray):
    """The indices of a strip-shaped ring's two ends (its farthest pair of points, as
    `slicelab.artefacts.sherds` finds a sherd's ends) and its thickness (twice its area over its
    perimeter)."""
    from ..geometry.polygons import signed_area
    step = max(1, len(ring) // 400)
    p = ring[::step]
    d = np.linalg.norm(p[:, None] - p[None], axis=2)
    i, j = np.unravel_index(int(np.argmax(d)), d.shape)
    perimeter = float(np.hypot(*np.diff(np.vstack([ring, ring[:1]]), axis=0).T).sum())
    return int(i) * step, int(j) * step, 2 * abs(signed_area(ring)) / max(perimeter, 1e-12)


def _run_around(ring: np.ndarray, k: int, reach: float) -> np.ndarray:
    """Indices of the ring's points within `reach` of point `k`, walked along the ring both ways from
    `k` (one unbroken stretch of the outline, wrapping round)."""
    n = len(ring)
    near = np.roll(np.linalg.norm(ring - ring[k], axis=1) <= reach, -k)  # near[m]: m steps on from k
    if near.all():
        return np.arange(n)
    ahead = int(np.argmin(near))           # k and the near points after it
    behind = int(np.argmin(near[::-1]))    # the near points before k (near[::-1][m]: m + 1 steps back)
    return (k - behind + np.arange(behind + ahead)) % n


def surfaces(half, sherd=None) -> np.ndarray:
    """The surface (`SURFACES`) of each edge of a half-section's outline: edge k runs from point k of
    ``half.polygon`` to point k + 1 (the last back to the first).

    A whole vessel's outline is its exterior and interior outlines
    (`slicelab.artefacts.HalfProfile`: an edge between two points of one is
    on that surface), the rim between them at the top and the axis where the
    half is cut off. A sherd's section is a strip: its two ends (the outline
    within 1.25 wall thicknesses of each of its farthest pair of points) are
    breaks, but for the upper end of a rim sherd, which is the lip
    (``"rim"``); of the two long sides between them, the one holding more of
    the half's exterior outline is the exterior.

    Parameters
    ----------
    half : HalfProfile
    sherd : SherdReport, optional
        The profile's sherd report, for a sherd.

    Returns
    -------
    (len(half.polygon),) ndarray of str

    Examples
    --------
    >>> from slicelab.artefacts import profile
    >>> from slicelab.samples import pot, scan
    >>> p = profile(pot(20, 24), planes=2)
    >>> [str(x) for x in surfaces(p.drawn)[[0, p.drawn.top, -1]]]  # the base, the flat rim top, the axis
    ['exterior', 'rim', 'axis']
    >>> p = profile(scan("beaker", spacing=2.0, sherd="rim", span=90.0)[0], planes=2)
    >>> sorted(set(surfaces(p.drawn, p.sherd)))
    ['break', 'exterior', 'interior', 'rim']
    """
    p = half.polygon
    n = len(p)
    rows = _rows(p)
    outer = np.isin(rows, _rows(half.outer)) if len(half.outer) else np.zeros(n, bool)
    inner = np.isin(rows, _rows(half.inner)) if len(half.inner) else np.zeros(n, bool)
    on_axis = p[:, 0] <= 0.0
    on_axis &= np.roll(on_axis, -1)  # both ends of the edge on the axis
    labels = np.full(n, "rim", dtype=object)
    if sherd is None:
        labels[inner & np.roll(inner, -1)] = "interior"
        labels[outer & np.roll(outer, -1)] = "exterior"
        labels[on_axis] = "axis"
        return labels
    # A sherd: each edge takes the part its first point lies in, the ends or one of the sides.
    i, j, t = _strip_ends(p)
    ends = [_run_around(p, k, _END_REACH * t) for k in (i, j)]
    at_end = np.zeros(n, bool)
    for e in ends:
        at_end[e] = True
    if not at_end.all():  # the long sides: the unbroken stretches between the ends
        start = int(np.argmax(at_end))
        order = (start + np.arange(n)) % n
        side = np.cumsum(np.diff(np.concatenate([[1], at_end[order].astype(np.int8)])) == -1)
        stretches = [order[(side == s) & ~at_end[order]] for s in np.unique(side[~at_end[order]])]
        scores = sorted(((int(outer[x].sum()) - int(inner[x].sum()), k) for k, x in enumerate(stretches)),
                        reverse=True)
        for rank, (_, k) in enumerate(scores):  # two stretches; the more exterior one is the exterior
            labels[stretches[k]] = "exterior" if rank == 0 else "interior"
    lip = None
    if sherd.kind == "rim":  # the upper end is the lip
        lip = int(np.argmax([float(p[e, 1].mean()) for e in ends]))
    for k, e in enumerate(ends):
        labels[e] = "rim" if k == lip else "break"
    labels[on_axis] = "axis"
    return labels


def surface_runs(ring: np.ndarray, labels) -> list:
    """The closed outline cut where the surface of its edges (`labels`, edge k from point k to k + 1)
    changes: ``(surface, points)`` for each unbroken stretch, from the first point of its first edge
    to the last point of its last, so that together they walk every edge of the ring once.

    Examples
    --------
    >>> sq = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], float)
    >>> [(s, len(q)) for s, q in surface_runs(sq, np.array(["break", "exterior", "exterior", "break"]))]
    [('exterior', 3), ('break', 3)]
    """
    labels = np.asarray(labels, dtype=object)
    n = len(ring)
    change = np.flatnonzero(labels != np.roll(labels, 1))
    if not len(change):
        return [(str(labels[0]), np.vstack([ring, ring[:1]]))]
    out = []
    for a, b in zip(change, np.roll(change, -1)):  # a few stretches
        idx = np.arange(a, b + (n if b <= a else 0) + 1) % n
        out.append((str(labels[a]), ring[idx]))
    return out


def _break_symbol(face: np.ndarray, ring: np.ndarray, t: float) -> np.ndarray:
    """A jagged break line across the end of a strip-shaped ring (a sherd's section of wall `t` thick)
    beyond its break `face`: perpendicular to the wall there, 1 mm wider than it each way, its
    jag clear of the outline by 0.6 mm."""
    c = face.mean(axis=0)
    dist = np.linalg.norm(ring - c, axis=1)
    body = ring[(dist > 2 * t) & (dist < 4 * t)]  # the wall a few thicknesses in from this end
    if len(body):
        v = c - body.mean(axis=0)
    else:  # a stub of a sherd: across its end, outside the outline (counter-clockwise: on its right)
        v = np.array([face[-1, 1] - face[0, 1], face[0, 0] - face[-1, 0]])
    if not np.linalg.norm(v) > 1e-12:
        return np.zeros((0, 2))
    v = v / np.linalg.norm(v)  # out of the wall through this end
    u = np.array([-v[1], v[0]])
    across = (face - c) @ u
    lo, hi = float(across.min()) - 1.0, float(across.max()) + 1.0
    zig = min(1.2, 0.15 * (hi - lo))
    # How far the outline reaches out along the wall under the line (the face, and the surfaces
    # beside it within the line's width), so that the jag back towards the wall stays clear of it.
    near = ring[dist <= 2 * (hi - lo)]
    under = near[((near - c) @ u >= lo) & ((near - c) @ u <= hi)]
    reach = float(np.concatenate([(face - c) @ v, (under - c) @ v]).max())
    mid = c + u * (lo + hi) / 2 + v * (reach + zig + 0.6)
    return np.array([mid + u * (lo - hi) / 2, mid - u * zig, mid - u * zig / 3 + v * zig,
                     mid + u * zig / 3 - v * zig, mid + u * zig, mid + u * (hi - lo) / 2])


def _appendage_lines(profile) -> list:
    """Outlines (r, z) of each handle, spout or lug in the vertical plane through it, where they stand
    outside the body (`slicelab.artefacts.appendages.body_radius`, noise margin as its measurement's)."""
    from .appendages import body_radius
    from .curves import resample
    from .halves import half_profiles
    found = getattr(profile, "appendages", ())
    if not found or profile.mesh is None:
        return []
    z = np.concatenate([x.polygon[:, 1] for x in profile.halves])
    edges, body = body_radius(profile.halves, float(z.min()), float(z.max()))
    margin = max(1.0, 5 * profile.measurements.noise)
    out = []
    for ap in found:  # a few appendages
        a = math.radians(ap.angle)
        halves = [x for x in half_profiles(profile.mesh, a)
                  if abs((x.angle - a + math.pi) % (2 * math.pi) - math.pi) < 1e-6]
        for ring in [r for x in halves for r in (x.polygon, *x.holes)]:
            p = resample(np.vstack([ring, ring[:1]]), 0.25)[0][:-1]
            k = np.clip(np.searchsorted(edges, p[:, 1]) - 1, 0, len(body) - 1)
            away = p[:, 0] > body[k] + margin
            if away.all() or not away.any():
                continue
            p, away = np.roll(p, -int(np.argmin(away)), axis=0), np.roll(away, -int(np.argmin(away)))
            step = np.diff(np.concatenate([[0], away.astype(np.int8), [0]]))
            out += [p[i:j] for i, j in zip(np.flatnonzero(step == 1), np.flatnonzero(step == -1)) if j - i > 1]
    return out


def _appendage_sections(profile) -> list:
    """Each handle's cross-section at its mid-height: the loops of the horizontal section there that
    lie wholly within the handle's angular span (10 degrees more each way), in (radial, across)
    coordinates about the handle's direction, with the height. A spout joined to the wall there
    has no loop of its own: nothing is drawn for it."""
    from ..slicing.sections import section
    out = []
    for ap in getattr(profile, "appendages", ()) if profile.mesh is not None else ():  # a few appendages
        z = (ap.z_from + ap.z_to) / 2
        c, s = math.cos(math.radians(ap.angle)), math.sin(math.radians(ap.angle))
        turn = np.array([[c, -s], [s, c]])  # (x, y) -> (radial, across)
        for poly in section(profile.mesh, (0.0, 0.0, z), (0.0, 0.0, 1.0)).polygons:  # a few loops
            e = poly.exterior
            off = (np.degrees(np.arctan2(e[:, 1], e[:, 0])) - ap.angle + 180) % 360 - 180
            if np.abs(off).max() <= ap.span / 2 + 10:
                out.append((z, e[:, :2] @ turn, [h[:, :2] @ turn for h in poly.holes]))
    return out


def parts(profile) -> dict:
    """What the drawing shows, in the profile's (r, z) plane (mm, r >= 0 away from the axis, z up).

    Parameters
    ----------
    profile : Profile

    Returns
    -------
    dict
        ``half`` (the drawn `HalfProfile`), ``surfaces`` (`surfaces` of its
        outline), ``runs`` (`surface_runs`: the outline in stretches, each
        with its surface), ``break_faces`` (the stretches that are breaks),
        ``break_symbols`` (a jagged line beside each), ``appendages`` (each
        handle, spout or lug outlined in the vertical plane through it,
        outside the body), ``appendage_sections`` (each handle's cross-section
        at mid-height turned into the plane, as ``(rings, cut)``: its outline
        and voids placed 8 mm beyond the outermost handle, across the handle
        upwards, and the cut line across the handle at that height) and
        ``uncertain`` (`orientation_uncertain`).

    See Also
    --------
    layout : mirrors them onto the page.
    slicelab.artefacts.profile_files : writes them as DXF and CSV.

    Examples
    --------
    >>> from slicelab.artefacts import profile
    >>> from slicelab.samples import scan
    >>> p = profile(scan("pot", spacing=2.0, sherd="body", span=90.0)[0], planes=2)
    >>> d = parts(p)
    >>> len(d["break_faces"]), len(d["break_symbols"]), d["uncertain"]
    (2, 2, True)
    """
    cached = _PARTS.get(profile)
    if cached is not None:
        return cached
    sherd = getattr(profile, "sherd", None)
    h = profile.drawn
    labels = surfaces(h, sherd)
    runs = surface_runs(h.polygon, labels)
    faces = [q for s, q in runs if s == "break"]
    t = _strip_ends(h.polygon)[2] if faces else 0.0
    handles = _appendage_lines(profile) if sherd is None else []
    sections = _appendage_sections(profile) if sherd is None else []
    placed = []
    if sections:
        beyond = max([float(x[:, 0].max()) for x in handles] + [float(ring[:, 0].max()) for _, ring, _ in sections])
        for z, ring, holes in sections:  # each handle's loop, its radial extent kept, turned upright
            r0, mid = float(ring[:, 0].min()), (float(ring[:, 1].min()) + float(ring[:, 1].max())) / 2

            def place(q, r0=r0, mid=mid, z=z):
                return np.column_stack([beyond + _SECTION_GAP + q[:, 0] - r0, z + q[:, 1] - mid])
            cut = np.array([[r0, z], [float(ring[:, 0].max()), z]])
            placed.append(([place(ring), *[place(x) for x in holes]], cut))
    out = {"half": h, "surfaces": labels, "runs": runs, "break_faces": faces,
           "break_symbols": [b for b in (_break_symbol(q, h.polygon, t) for q in faces) if len(b)], "appendages": handles,
           "appendage_sections": placed, "uncertain": orientation_uncertain(profile)}
    _PARTS[profile] = out
    return out


def layout(profile, *, side: str = "left", spread: bool = False, label: str | None = None) -> dict:
    """Everything to draw, in drawing millimetres (x right, y up, the axis at x = 0).

    Parameters
    ----------
    profile : Profile
    side : {"left", "right"}, default "left"
        Where the section goes; the exterior outline takes the other side.
    spread : bool, default False
        Also draw every other half-section (layer ``spread``).
    label : str, optional
        First line of the label (default: the profile's name).

    Returns
    -------
    dict
        ``page`` (x0, y0, x1, y1) and ``layers``: an ordered list of (id,
        items). Beside ``axis``, ``section``, ``exterior``, ``rim``, ``scale``
        and ``label``: ``appendage`` (each handle, spout or lug outlined in the
        plane through it, on the exterior side), ``appendage_section`` (each
        handle's cross-section beside it, and the dashed line where it is
        cut), ``break`` (a jagged line beside each end of a sherd's section
        that is a break), ``stance`` (an arrow and a question mark: which way
        is up is uncertain), each only when there is one. An item is
        ``("polygon", rings)``, ``("line", points, width, dash)``, ``("rect",
        x, y, w, h, fill)`` or ``("text", x, y, text, size, anchor)``.

    See Also
    --------
    parts : what is drawn, in the profile's (r, z) plane.
    profile_svg : draws it as SVG.
    slicelab.viz.profile_png : draws it with matplotlib.

    Examples
    --------
    >>> from slicelab.artefacts import profile
    >>> from slicelab.samples import pot
    >>> [name for name, _ in layout(profile(pot(20, 24), planes=2))["layers"]]
    ['axis', 'section', 'exterior', 'rim', 'scale', 'label']

    A sherd is drawn in sherd position: its section on `side` at its radius
    from the reconstructed axis, no exterior mirrored from it; a rim sherd's
    rim line runs dashed across the mouth to the reconstructed diameter, a
    body or a base sherd has none; its breaks are marked; the label holds
    only what the sherd gives.

    >>> from slicelab.samples import scan
    >>> sherd, _ = scan("beaker", spacing=2.0, sherd="rim", span=90.0)
    >>> [name for name, _ in layout(profile(sherd, planes=2))["layers"]]
    ['axis', 'section', 'rim', 'break', 'scale', 'label']
    """
    if side not in ("left", "right"):
        raise ValueError(f"side must be 'left' or 'right', got {side!r}")
    s = -1.0 if side == "left" else 1.0
    d = parts(profile)
    h = d["half"]
    m = profile.measurements

    def mirror(p, sign):
        return np.column_stack([sign * p[:, 0], p[:, 1]])

    others = [x for k, x in enumerate(profile.halves) if k != profile.representative] if spread else []
    r_max = max(float(x.polygon[:, 0].max()) for x in [h, *others])
    z_lo = min(float(x.polygon[:, 1].min()) for x in [h, *others])
    z_hi = max(float(x.polygon[:, 1].max()) for x in [h, *others])
    layers = []
    layers.append(("axis", [("line", np.array([[0.0, z_lo - 5], [0.0, z_hi + 5]]), THIN, "6 1.5 1 1.5")]))
    if others:
        layers.append(("spread", [("line", np.vstack([mirror(x.polygon, s), mirror(x.polygon[:1], s)]),
                                   THIN, None) for x in others]))
    layers.append(("section", [("polygon", [mirror(h.polygon, s), *[mirror(x, s) for x in h.holes]])]))
    sherd = getattr(profile, "sherd", None)
    if sherd is None:  # a whole vessel: its exterior on the other side, the rim line across the mouth
        layers.append(("exterior", [("line", mirror(h.outer, -s), LINE, None)]))
        rim_in = h.inner[0] if len(h.inner) else h.polygon[h.top]
        rim_out = h.outer[0] if len(h.outer) else h.polygon[h.top]
        layers.append(("rim", [("line", np.array([[s * rim_in[0], rim_in[1]], [-s * rim_out[0], rim_out[1]]]),
                                LINE, None)]))
        if d["appendages"]:  # each handle, spout or lug in the plane through it, on the exterior side
            layers.append(("appendage", [("line", mirror(x, -s), LINE, None) for x in d["appendages"]]))
            r_max = max(r_max, max(float(x[:, 0].max()) for x in d["appendages"]))
        if d["appendage_sections"]:  # beside it, each handle's cross-section and where it is cut
            items = []
            for rings, cut in d["appendage_sections"]:
                items += [("polygon", [mirror(x, -s) for x in rings]), ("line", mirror(cut, -s), THIN, "1.5 1")]
                r_max = max(r_max, max(float(x[:, 0].max()) for x in rings))
            layers.append(("appendage_section", items))
    elif sherd.kind == "rim":
        # Sherd position: the section alone, nothing mirrored; the rim line across the mouth to the
        # reconstructed diameter is dashed.
        top = h.polygon[int(np.argmax(h.polygon[:, 1]))]
        r_rim = m.rim_diameter / 2 if np.isfinite(m.rim_diameter) else float(top[0])
        layers.append(("rim", [("line", np.array([[s * float(top[0]), float(top[1])], [-s * r_rim, float(top[1])]]),
                                THIN, "3 1.5")]))
    if d["break_symbols"]:
        layers.append(("break", [("line", mirror(b, s), THIN, None) for b in d["break_symbols"]]))
        r_max = max(r_max, max(float(b[:, 0].max()) for b in d["break_symbols"]))
    if d["uncertain"]:  # an arrow up with a question mark beside the section
        x = s * (float(h.polygon[:, 0].max()) + 6.0)
        top = float(h.polygon[:, 1].max())
        layers.append(("stance", [("line", np.array([[x, top - 14.0], [x, top - 2.0]]), LINE, None),
                                  ("line", np.array([[x - 1.5, top - 5.0], [x, top - 2.0], [x + 1.5, top - 5.0]]),
                                   LINE, None),
                                  ("text", x + s * 3.5, top - 9.0, "?", 2 * FONT, "middle")]))
        r_max = max(r_max, abs(x) + 6.0)

    margin = 10.0
    width = max(2 * (r_max + margin), 110.0)
    x0, x1 = -width / 2, width / 2
    # Scale bar: the longest round length within 60 % of the vessel's width, in five blocks.
    bar = max([b for b in _BARS if b <= max(0.6 * 2 * r_max, _BARS[0])])
    y_bar = z_lo - 12.0
    bx = x0 + margin
    items = [("rect", bx + k * bar / 5, y_bar, bar / 5, 2.0, "black" if k % 2 == 0 else "white")
             for k in range(5)]
    items += [("text", bx, y_bar - 4.5, "0", FONT, "middle"),
              ("text", bx + bar, y_bar - 4.5, f"{bar / 10:g} cm", FONT, "middle")]
    layers.append(("scale", items))
    name = label if label is not None else (profile.name or ("sherd" if sherd is not None else "vessel"))
    lines = [name] + _label_lines(m, sherd)
    if d["uncertain"]:
        cue = (sherd if sherd is not None else profile.alignment).up_from
        lines.append(f"orientation uncertain (up from {cue})" if cue in _GUESSES else "orientation uncertain")
    y_text = y_bar - 10.0
    layers.append(("label", [("text", x0 + margin, y_text - 1.5 * FONT * k, t, FONT, "start")
                             for k, t in enumerate(lines)]))
    y0 = y_text - 1.5 * FONT * (len(lines) - 1) - margin
    return {"page": (x0, y0, x1, z_hi + margin), "layers": layers}
def _finite(d: dict) -> dict:
    """`d` with NaN (a measurement that does not apply) as None."""
    return {k: (None if isinstance(v, float) and v != v else v) for k, v in d.items()}


def _label_lines(m, sherd) -> list:
    """The label's lines of measurements, each number only where it applies (never NaN)."""
    import math

    def part(text, v, fmt=".1f", unit=""):
        return f"{text} {v:{fmt}}{unit}" if v is not None and math.isfinite(v) else None

    dims = [part("H", m.height), part("rim \u00d8", m.rim_diameter), part("max \u00d8", m.max_diameter),
            part("base \u00d8", m.base_diameter)]
    dims = [d for d in dims if d]
    first = " \u00b7 ".join(dims) + " mm" if dims else ""
    wall = ""
    if math.isfinite(m.wall_thickness_min) and math.isfinite(m.wall_thickness_max):
        wall = f"wall {m.wall_thickness_min:.1f}\u2013{m.wall_thickness_max:.1f} mm"
    cap = part("capacity", m.capacity / 1e6 if math.isfinite(m.capacity) else None, ".3g", " l")
    second = " \u00b7 ".join(x for x in (wall, cap, "scale 1:1") if x)
    lines = [first, second]
    if sherd is not None:
        lines.insert(0, sherd.sentence())
    return [x for x in lines if x]


def profile_svg(profile, *, side: str = "left", spread: bool = False, label: str | None = None) -> str:
    """SVG text of the drawing: 1 user unit = 1 mm, one group per layer.

    Parameters
    ----------
    profile : Profile
    side, spread, label
        As in `layout`.

    Returns
    -------
    str

    See Also
    --------
    layout : what is drawn.
    slicelab.artefacts.Profile.to_svg : writes it to a file.
    slicelab.viz.profile_png : the same layout as a PNG.
    slicelab.files.SvgDrawing : the SVG writer.

    Examples
    --------
    >>> import xml.etree.ElementTree as ET
    >>> from slicelab.artefacts import profile
    >>> from slicelab.samples import pot
    >>> root = ET.fromstring(profile_svg(profile(pot(20, 24), planes=2)))
    >>> sorted(g.get("id") for g in root.iter("{http://www.w3.org/2000/svg}g"))
    ['axis', 'exterior', 'label', 'rim', 'scale', 'section']
    """
    lay = layout(profile, side=side, spread=spread, label=label)
    svg = SvgDrawing(lay["page"], title=label if label is not None else (profile.name or "vessel"),
                     desc=f"slicelab profile drawing, 1:1 in mm; {_finite(profile.measurements.to_dict())!r}")
    for name, items in lay["layers"]:
        with svg.group(name):
            for it in items:
                kind = it[0]
                if kind == "polygon":
                    svg.path(it[1], closed=True, fill="black", fill_rule="evenodd", stroke="black",
                             stroke_width=LINE, stroke_linejoin="round")
                elif kind == "line" and name == "spread":
                    svg.polyline(it[1], fill="none", stroke="#999999", stroke_width=it[2])
                elif kind == "line":
                    svg.polyline(it[1], fill="none", stroke="black", stroke_width=it[2], stroke_linejoin="round",
                                 stroke_dasharray=it[3])
                elif kind == "rect":
                    _, x, y, rw, rh, fill = it
                    svg.rect(x, y, rw, rh, fill=fill, stroke="black", stroke_width=THIN)
                elif kind == "text":
                    _, x, y, text, size, anchor = it
                    svg.text(x, y, text, font_family="sans-serif", font_size=size, text_anchor=anchor)
    return svg.to_string()
