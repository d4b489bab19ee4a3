"""The archaeological profile drawing of a vessel: its layout and its SVG, 1:1 in mm.

Convention: a vertical axis line (dash-dot); on one side the section of the
wall filled black; on the other the exterior outline; a rim line across the
mouth; a handle, spout or lug outlined in the plane through it, on the
exterior side; a scale bar in centimetres; a label with the main measurements. A
sherd is drawn in sherd position: its section only, the rim line to the
reconstructed diameter dashed. The
SVG here (`slicelab.export.SvgDrawing`) and the PNG (`slicelab.viz.profile_png`)
are drawn from one `layout`, so they cannot disagree.
"""
from __future__ import annotations

import numpy as np

from ..export.svg import SvgDrawing

__all__ = ["layout", "profile_svg", "LINE", "THIN", "FONT"]

LINE = 0.35        # mm: outline pen
THIN = 0.18        # mm: axis, spread, scale bar
FONT = 3.0         # mm: label text height
_BARS = (10, 20, 50, 100, 200, 500, 1000, 2000)


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
        items) (layer ``appendage``, when there is one: each handle, spout or
        lug outlined in the plane through it, on the exterior side); an item is ``("polygon", rings)``, ``("line", points, width, dash)``,
        ``("rect", x, y, w, h, fill)`` or ``("text", x, y, text, size, anchor)``.

    See Also
    --------
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
    body or a base sherd has none; the label holds only what the sherd gives.

    >>> from slicelab.samples import scan
    >>> sherd, _ = scan("beaker", spacing=2.0, sherd="rim", span=90.0)
    >>> [name for name, _ in layout(profile(sherd, planes=2))["layers"]]
    ['axis', 'section', 'rim', 'scale', 'label']
    """
    if side not in ("left", "right"):
        raise ValueError(f"side must be 'left' or 'right', got {side!r}")
    s = -1.0 if side == "left" else 1.0
    h = profile.drawn
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
        handles = _appendage_lines(profile)
        if handles:  # each handle, spout or lug in the plane through it, on the exterior side
            layers.append(("appendage", [("line", mirror(x, -s), LINE, None) for x in handles]))
            r_max = max(r_max, max(float(x[:, 0].max()) for x in handles))
    elif sherd.kind == "rim":
        # Sherd position: the section alone, nothing mirrored; the rim line across the mouth to the
        # reconstructed diameter is dashed.
        top = h.polygon[int(np.argmax(h.polygon[:, 1]))]
        r_rim = m.rim_diameter / 2 if np.isfinite(m.rim_diameter) else float(top[0])
        layers.append(("rim", [("line", np.array([[s * float(top[0]), float(top[1])], [-s * r_rim, float(top[1])]]),
                                THIN, "3 1.5")]))

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
    y_text = y_bar - 10.0
    layers.append(("label", [("text", x0 + margin, y_text - 1.5 * FONT * k, t, FONT, "start")
                             for k, t in enumerate(lines)]))
    y0 = y_text - 1.5 * FONT * (len(lines) - 1) - margin
    return {"page": (x0, y0, x1, z_hi + margin), "layers": layers}


def _appendage_lines(profile) -> list:
    """Outlines (r, z) of each handle, spout or lug in the vertical plane through it, where they stand
    outside the body (`slicelab.artefacts.appendages.body_radius`, noise margin as its measurement's)."""
    import math

    from .appendages import body_radius
    from .measure import resample
    from .profiles import half_profiles
    parts = getattr(profile, "appendages", ())
    if not parts or profile.mesh is None:
        return []
    z = np.concatenate([x.polygon[:, 1] for x in profile.halves])
    edges, body = body_radius(profile.halves, float(z.min()), float(z.max()))
    margin = max(1.0, 5 * profile.measurements.noise)
    out = []
    for ap in parts:  # a few appendages
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
    slicelab.export.SvgDrawing : the SVG writer.

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
