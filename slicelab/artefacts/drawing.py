"""The archaeological profile drawing of a vessel, as SVG and PNG, 1:1 in mm.

Convention: a vertical axis line (dash-dot); on one side the section of the
wall filled black; on the other the exterior outline; a rim line across the
mouth; a scale bar in centimetres; a label with the main measurements. Both
outputs are drawn from one layout, so the SVG and the PNG cannot disagree.
"""
from __future__ import annotations

from xml.sax.saxutils import escape

import numpy as np

__all__ = ["layout", "profile_svg", "profile_png"]

LINE = 0.35        # mm: outline pen
THIN = 0.18        # mm: axis, spread, scale bar
FONT = 3.0         # mm: label text height
_BARS = (10, 20, 50, 100, 200, 500, 1000, 2000)


def layout(profile, *, side: str = "left", spread: bool = False, label: str | None = None) -> dict:
    """Everything to draw, in drawing millimetres (x right, y up, the axis at x = 0).

    Returns a dict with ``page`` (x0, y0, x1, y1) and ``layers``: an ordered
    list of (id, items); an item is ``("polygon", rings)``, ``("line", points, width, dash)``,
    ``("rect", x, y, w, h, fill)`` or ``("text", x, y, text, size, anchor)``.

    Examples
    --------
    >>> from slicelab.artefacts import profile
    >>> from slicelab.samples import pot
    >>> [name for name, _ in layout(profile(pot(20, 24), planes=2))["layers"]]
    ['axis', 'section', 'exterior', 'rim', 'scale', 'label']
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
    layers.append(("exterior", [("line", mirror(h.outer, -s), LINE, None)]))
    rim_in = h.inner[0] if len(h.inner) else h.polygon[h.top]
    rim_out = h.outer[0] if len(h.outer) else h.polygon[h.top]
    layers.append(("rim", [("line", np.array([[s * rim_in[0], rim_in[1]], [-s * rim_out[0], rim_out[1]]]),
                            LINE, None)]))

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
    name = label if label is not None else (profile.name or "vessel")
    lines = [name,
             f"H {m.height:.1f} \u00b7 rim \u00d8 {m.rim_diameter:.1f} \u00b7 max \u00d8 {m.max_diameter:.1f} "
             f"\u00b7 base \u00d8 {m.base_diameter:.1f} mm",
             f"wall {m.wall_thickness_min:.1f}\u2013{m.wall_thickness_max:.1f} mm \u00b7 capacity "
             f"{m.capacity / 1e6:.3g} l \u00b7 scale 1:1"]
    y_text = y_bar - 10.0
    layers.append(("label", [("text", x0 + margin, y_text - 1.5 * FONT * k, t, FONT, "start")
                             for k, t in enumerate(lines)]))
    y0 = y_text - 1.5 * FONT * (len(lines) - 1) - margin
    return {"page": (x0, y0, x1, z_hi + margin), "layers": layers}


def profile_svg(profile, *, side: str = "left", spread: bool = False, label: str | None = None) -> str:
    """SVG text of the drawing: 1 user unit = 1 mm, one group per layer.

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
    x0, y0, x1, y1 = lay["page"]
    w, h = x1 - x0, y1 - y0

    def pts(p):  # SVG's y grows downwards
        return " ".join(f"{x - x0:.4f},{y1 - y:.4f}" for x, y in p)

    out = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{w:.4f}mm" height="{h:.4f}mm" '
           f'viewBox="0 0 {w:.4f} {h:.4f}">',
           f"<title>{escape(label if label is not None else (profile.name or 'vessel'))}</title>",
           f"<desc>slicelab profile drawing, 1:1 in mm; {escape(repr(profile.measurements.to_dict()))}</desc>"]
    for name, items in lay["layers"]:
        out.append(f'<g id="{name}">')
        for it in items:
            kind = it[0]
            if kind == "polygon":
                d = " ".join("M" + pts(r).replace(" ", " L") + " Z" for r in it[1])
                out.append(f'<path d="{d}" fill="black" fill-rule="evenodd" stroke="black" '
                           f'stroke-width="{LINE}" stroke-linejoin="round"/>')
            elif kind == "line":
                dash = f' stroke-dasharray="{it[3]}"' if it[3] else ""
                out.append(f'<polyline points="{pts(it[1])}" fill="none" stroke="black" '
                           f'stroke-width="{it[2]}" stroke-linejoin="round"{dash}/>'
                           if name != "spread" else
                           f'<polyline points="{pts(it[1])}" fill="none" stroke="#999999" '
                           f'stroke-width="{it[2]}"/>')
            elif kind == "rect":
                _, x, y, rw, rh, fill = it
                out.append(f'<rect x="{x - x0:.4f}" y="{y1 - y - rh:.4f}" width="{rw:.4f}" height="{rh:.4f}" '
                           f'fill="{fill}" stroke="black" stroke-width="{THIN}"/>')
            elif kind == "text":
                _, x, y, text, size, anchor = it
                out.append(f'<text x="{x - x0:.4f}" y="{y1 - y:.4f}" font-family="sans-serif" '
                           f'font-size="{size}" text-anchor="{anchor}">{escape(text)}</text>')
        out.append("</g>")
    out.append("</svg>")
    return "\n".join(out) + "\n"


def profile_png(profile, path, *, dpi: float = 150.0, side: str = "left", spread: bool = False,
                label: str | None = None) -> None:
    """Render the drawing with matplotlib (no pyplot: safe in worker threads) and write a PNG atomically.

    Examples
    --------
    >>> import os, tempfile
    >>> from slicelab.artefacts import profile
    >>> from slicelab.samples import pot
    >>> profile_png(profile(pot(20, 24), planes=2), os.path.join(tempfile.mkdtemp(), "p.png"), dpi=40)
    """
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure
    from matplotlib.patches import PathPatch, Rectangle
    from matplotlib.path import Path as MplPath

    from ..mesh.io import atomic_path
    lay = layout(profile, side=side, spread=spread, label=label)
    x0, y0, x1, y1 = lay["page"]
    pt = 72.0 / 25.4  # points per mm
    fig = Figure(figsize=((x1 - x0) / 25.4, (y1 - y0) / 25.4), dpi=dpi)
    FigureCanvasAgg(fig)
    ax = fig.add_axes((0, 0, 1, 1))
    ax.set_xlim(x0, x1)
    ax.set_ylim(y0, y1)
    ax.set_axis_off()
    for name, items in lay["layers"]:
        for it in items:
            kind = it[0]
            if kind == "polygon":
                verts, codes = [], []
                for r in it[1]:
                    verts += [*r, r[0]]
                    codes += [MplPath.MOVETO] + [MplPath.LINETO] * (len(r) - 1) + [MplPath.CLOSEPOLY]
                ax.add_patch(PathPatch(MplPath(np.array(verts), codes), facecolor="black", edgecolor="black",
                                       linewidth=LINE * pt))
            elif kind == "line":
                style = {"linestyle": (0, tuple(float(v) / it[2] for v in it[3].split()))} if it[3] else {}
                ax.plot(it[1][:, 0], it[1][:, 1], color="#999999" if name == "spread" else "black",
                        linewidth=it[2] * pt, solid_joinstyle="round", **style)
            elif kind == "rect":
                _, x, y, rw, rh, fill = it
                ax.add_patch(Rectangle((x, y), rw, rh, facecolor=fill, edgecolor="black", linewidth=THIN * pt))
            elif kind == "text":
                _, x, y, text, size, anchor = it
                ax.text(x, y, text, fontsize=size * pt, ha="center" if anchor == "middle" else "left",
                        va="baseline", family="sans-serif")
    with atomic_path(path) as tmp:
        fig.savefig(tmp, format="png", dpi=dpi)
