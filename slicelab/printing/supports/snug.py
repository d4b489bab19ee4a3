"""The "snug" support style: columns that follow what hangs in the air, pixel for pixel.

See Also
--------
slicelab.printing.supports : the registry of styles.
"""
from __future__ import annotations

from .style import SupportStyle

__all__ = ["STYLE"]

STYLE = SupportStyle("snug", 0.0, "columns that follow what hangs exactly, as PrusaSlicer's snug style")
