"""The roles of a layer's extrusions, their G-code ``;TYPE:`` words and their colours.

A layer's paths come in four lists (`ROLES`); its filling is sparse or
solid, so an extrusion is one of five kinds (`KINDS`). `STYLES` names each
kind once for every output: the ``;TYPE:`` word PrusaSlicer's G-code viewer
reads, that viewer's colour (used in the per-layer SVGs) and the colour on
white matplotlib axes (gap fill, white in the viewer, shows blue there).

Examples
--------
>>> STYLES["external"].gcode_type, STYLES["solid"].colour
('External perimeter', '#8f1fd6')
>>> set(STYLES) == set(KINDS)
True
"""
from __future__ import annotations

from typing import NamedTuple

__all__ = ["ROLES", "FILLING_KINDS", "KINDS", "RoleStyle", "STYLES"]

#: The path lists of a layer, in the order an island prints them.
ROLES = ("external", "internal", "gap_fill", "filling")
#: What a filling path is.
FILLING_KINDS = ("sparse", "solid")
#: The kind of an extrusion: its role, with filling split into its kinds.
KINDS = ("external", "internal", "gap_fill", *FILLING_KINDS)


class RoleStyle(NamedTuple):
    """How outputs name and draw one kind of extrusion.

    Attributes
    ----------
    gcode_type : str
        The word after ``;TYPE:`` in G-code (PrusaSlicer's names).
    colour : str
        PrusaSlicer's colour for it (per-layer SVGs).
    plot_colour : str
        Its colour on white plots.
    """

    gcode_type: str
    colour: str
    plot_colour: str


STYLES = {
    "external": RoleStyle("External perimeter", "#e8590c", "#e8590c"),
    "internal": RoleStyle("Perimeter", "#f59f00", "#f59f00"),
    "gap_fill": RoleStyle("Gap fill", "#ffffff", "#1c7ed6"),
    "sparse": RoleStyle("Internal infill", "#b02e26", "#b02e26"),
    "solid": RoleStyle("Solid infill", "#8f1fd6", "#8f1fd6"),
}
