"""Support material under unheld overhangs and mid-air islands, in styles.

`SUPPORTS` is the one table of support styles: each module below defines one
`SupportStyle`, and adding a style is one module and one line here. Where
supports stand (`PrintSettings.support`: on the bed or the part, or only on
the bed) is a setting apart from their style (`PrintSettings.support_style`).

==========================  =====================================================
``supports.columns``        support masks projected down from what is unheld, and their lines
``supports.style``          what a style is: `SupportStyle`
``supports.snug``           columns that follow what hangs exactly
``supports.grid``           blockier columns, small gaps between regions filled
==========================  =====================================================
"""
from __future__ import annotations

from . import grid, snug
from .columns import PLACEMENTS, support_paths
from .style import SupportStyle

__all__ = ["SUPPORTS", "SupportStyle", "PLACEMENTS", "support_lines"]

#: The support styles by name.
SUPPORTS: dict[str, SupportStyle] = {s.name: s for s in (snug.STYLE, grid.STYLE)}


def support_lines(sections, unheld, settings) -> list[list]:
    """The support rows of every layer under `settings` (its `Supports` group and line width).

    See Also
    --------
    slicelab.printing.supports.columns.support_paths : the lines, for any style.
    """
    s = settings.supports
    w = settings.extrusion.line_width
    # The settings give the gaps between lines, as PrusaSlicer does: a line width more apart.
    return support_paths(sections, unheld, mode=s.support, line_width=w, spacing=s.support_spacing + w,
                         interface_spacing=s.support_interface_spacing + w, xy_gap=s.support_xy_gap,
                         z_gap_layers=s.support_z_gap_layers, interface_layers=s.support_interface_layers,
                         sheath=s.support_sheath, close=SUPPORTS[s.support_style].close)
