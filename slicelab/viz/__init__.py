"""Figures and previews (matplotlib, imported on first use).

==========================  =====================================================
``viz.layers``              rasters, distance fields, toolpaths, coverage, 3-D plan, PNG preview
``viz.depth``               depth-buffer drawing of millions of facets, decimated
``viz.canvas``              figures composed as pixel arrays (OpenCV), PNG
``viz.preview``             depth-rendered split previews
``viz.partition``           exploded views of cut or partitioned pieces
``viz.plates``               top views of build plates, pieces numbered
``viz.profile``             the archaeological profile drawing as a PNG
``viz.rims``                a batch's rim-diameter chart, weighted by rim EVE
==========================  =====================================================
"""
from __future__ import annotations

from .._lazy import attach

# Submodule of each public name: they load on first use (matplotlib and the like are slow to import).
_WHERE = {"save_plate_png": "plates", "plot_raster": "layers", "plot_distance": "layers", "plot_toolpath": "layers", "plot_coverage": "layers", "plan_3d": "layers", "preview_png": "layers", "render_depth": "depth", "draw_split": "preview", "save_split_preview": "preview", "plot_exploded": "partition", "save_exploded_png": "partition", "exploded_image": "partition", "profile_png": "profile", "RimChart": "rims", "rim_chart": "rims", "rim_chart_png": "rims"}


__all__ = ["save_plate_png", "plot_raster", "plot_distance", "plot_toolpath", "plot_coverage", "plan_3d", "preview_png", "render_depth", "draw_split", "save_split_preview", "plot_exploded", "exploded_image", "save_exploded_png", "profile_png", "RimChart", "rim_chart", "rim_chart_png"]


__getattr__, __dir__ = attach(__name__, _WHERE, globals())
