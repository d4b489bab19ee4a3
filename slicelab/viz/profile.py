"""The archaeological profile drawing as a PNG: `slicelab.artefacts.drawing_png.profile_png`, shown
among the figures (it is drawn beside the layout it renders, in `slicelab.artefacts`)."""
from __future__ import annotations

from ..artefacts.drawing_png import profile_png

__all__ = ["profile_png"]
