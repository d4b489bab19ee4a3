"""The "grid" support style: blockier columns, gaps and notches narrower than 3 mm between support
regions filled, as PrusaSlicer's default "grid" style: fewer, sturdier columns that stand on their
own, at some more material.

See Also
--------
slicelab.printing.supports : the registry of styles.
"""
from __future__ import annotations

from .style import SupportStyle

__all__ = ["STYLE"]

STYLE = SupportStyle("grid", 3.0, "blockier columns: gaps under 3 mm between support regions filled, as "
                                  "PrusaSlicer's grid style")
