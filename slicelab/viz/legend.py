"""The legend of a toolpath picture: each kind of extrusion drawn, in its colour, with its name.

Kinds that share a name and a colour (the skirt and the brim, PrusaSlicer's
``Skirt/Brim``) make one entry; the names are PrusaSlicer's ``;TYPE:`` words
(`slicelab.printing.roles.STYLES`), except the outer wall of a hole, which is
drawn in its own colour. The travel between paths, drawn in grey on the layer
panels, has an entry too. Drawn with OpenCV on a `slicelab.viz.canvas.Canvas`.

Examples
--------
>>> [e.label for e in legend_entries({"brim", "skirt", "bridge", "external"}, travel=True)]
['Skirt/Brim', 'External perimeter', 'Bridge infill', 'Travel']
>>> legend_entries({"bridge"})[0].rgb
(77, 128, 186)
"""
from __future__ import annotations

from typing import NamedTuple

from ..printing.roles import KINDS, STYLES

__all__ = ["LegendEntry", "legend_entries", "legend_size", "draw_legend", "rgb", "TRAVEL_RGB"]

#: The grey of travel moves on the layer panels.
TRAVEL_RGB = (200, 200, 200)
#: Names where the ``;TYPE:`` word would give two colours one name.
_NAMES = {"hole": "Hole perimeter"}
_ROW, _SWATCH, _PAD, _TITLE = 22, 26, 10, "Roles"


class LegendEntry(NamedTuple):
    """One line of the legend: a name, its colour (RGB bytes) and the kinds it stands for."""

    label: str
    rgb: tuple
    kinds: tuple


def rgb(colour: str) -> tuple:
    """``"#e8590c"`` as bytes ``(232, 89, 12)``."""
    return tuple(int(colour[j:j + 2], 16) for j in (1, 3, 5))


def legend_entries(kinds, *, travel: bool = False) -> list[LegendEntry]:
    """The entries for the kinds drawn (in `slicelab.printing.roles.KINDS` order), and travel."""
    out: dict = {}
    for k in KINDS:  # over the thirteen kinds
        if k in kinds:
            key = (_NAMES.get(k, STYLES[k].gcode_type), rgb(STYLES[k].plot_colour))
            out[key] = out.get(key, ()) + (k,)
    entries = [LegendEntry(label, colour, ks) for (label, colour), ks in out.items()]
    if travel:
        entries.append(LegendEntry("Travel", TRAVEL_RGB, ()))
    return entries


def legend_size(entries) -> tuple[int, int]:
    """Width and height (pixels) the legend of `entries` takes."""
    import cv2
    widths = [cv2.getTextSize(e.label, cv2.FONT_HERSHEY_SIMPLEX, 0.45, 1)[0][0] for e in entries]
    return _PAD + _SWATCH + 8 + max(widths + [60]) + _PAD, _PAD + _ROW * (len(entries) + 1) + _PAD


def draw_legend(canvas, entries, x: int, y: int) -> list[tuple]:
    """Draw the legend with its top-left corner at (x, y): a frame, a title, and per entry a
    thick stroke of its colour and its name. Returns each entry's stroke box ``(x, y, w, h)``."""
    import cv2
    w, h = legend_size(entries)
    cv2.rectangle(canvas.rgb, (x, y), (x + w - 1, y + h - 1), (160, 160, 160), 1)
    canvas.text(_TITLE, x + _PAD, y + _PAD + 13, scale=1.1)
    boxes = []
    for i, e in enumerate(entries):  # over the entries, a dozen at most
        mid = y + _PAD + _ROW * (i + 1) + _ROW // 2
        x0 = x + _PAD
        canvas.rgb[mid - 3:mid + 4, x0:x0 + _SWATCH] = e.rgb  # a solid stroke: its exact colour
        boxes.append((x0, mid - 3, _SWATCH, 7))
        canvas.text(e.label, x0 + _SWATCH + 8, mid + 5)
    return boxes
