"""The roles of a layer's extrusions, their G-code ``;TYPE:`` words and their colours.

A layer's paths come in seven lists (`ROLES`): the first layer's skirt and brim,
printed first, the support material (`slicelab.printing.supports.columns`: sparse or
interface), then each island's four (`ISLAND_ROLES`, in the order an
island prints them). Filling is sparse, solid, top skin (solid filling
that the layer above leaves exposed) or bridge (lines laid across a gap); the
outer wall of a hole is its own kind, ``hole`` (an external perimeter in
PrusaSlicer's words, an internal loop by role), and a stretch of perimeter over
nothing is an ``overhang`` piece of its loop (`LayerPaths.pieces`). So an
extrusion is one of thirteen kinds (`KINDS`), each with its role (`ROLE_OF`). `STYLES` names each kind once for every output: the
``;TYPE:`` word PrusaSlicer's G-code viewer reads (PrusaSlicer writes skirt and
brim alike as ``Skirt/Brim``), that viewer's colour (used in the per-layer
SVGs) and the colour on white matplotlib axes (gap fill, white in the viewer,
shows blue there).

Examples
--------
>>> STYLES["external"].gcode_type, STYLES["solid"].colour, STYLES["brim"].gcode_type
('External perimeter', '#8f1fd6', 'Skirt/Brim')
>>> set(STYLES) == set(KINDS) == set(ROLE_OF)
True
>>> ROLE_OF["top"], ROLE_OF["external"]
('filling', 'external')
"""
from __future__ import annotations

from typing import NamedTuple

__all__ = ["ROLES", "ISLAND_ROLES", "FILLING_KINDS", "KINDS", "ROLE_OF", "RoleStyle", "STYLES"]

#: The path lists of an island, in the order it prints them.
ISLAND_ROLES = ("external", "internal", "gap_fill", "filling")
#: The path lists of a layer: the skirt and brim (first layer only) go before the islands.
ROLES = ("skirt", "brim", "support", *ISLAND_ROLES)
#: What a filling path is.
FILLING_KINDS = ("sparse", "solid", "top", "bridge")
#: The kind of an extrusion: its role, with filling split into its kinds.
KINDS = ("skirt", "brim", "support", "support_interface", "external", "hole", "internal", "overhang", "gap_fill",
         *FILLING_KINDS)
#: The role of each kind: filling kinds are filling, the others their own role.
ROLE_OF = {k: ("filling" if k in FILLING_KINDS else "internal" if k in ("hole", "overhang") else
              "support" if k.startswith("support") else k) for k in KINDS}


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
    "skirt": RoleStyle("Skirt/Brim", "#00876e", "#00876e"),
    "brim": RoleStyle("Skirt/Brim", "#00876e", "#00876e"),
    "support": RoleStyle("Support material", "#00ff00", "#2f9e44"),
    "support_interface": RoleStyle("Support material interface", "#008000", "#1b5e20"),
    "external": RoleStyle("External perimeter", "#e8590c", "#e8590c"),
    "hole": RoleStyle("External perimeter", "#e8590c", "#c2255c"),
    "overhang": RoleStyle("Overhang perimeter", "#1f1fff", "#364fc7"),
    "internal": RoleStyle("Perimeter", "#f59f00", "#f59f00"),
    "gap_fill": RoleStyle("Gap fill", "#ffffff", "#1c7ed6"),
    "sparse": RoleStyle("Internal infill", "#b02e26", "#b02e26"),
    "solid": RoleStyle("Solid infill", "#8f1fd6", "#8f1fd6"),
    "top": RoleStyle("Top solid infill", "#f04040", "#e03131"),
    "bridge": RoleStyle("Bridge infill", "#4d80ba", "#4d80ba"),
}
