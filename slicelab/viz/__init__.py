"""Figures and previews (matplotlib, imported on first use).

==========================  =====================================================
``viz.layers``              rasters, distance fields, toolpaths, coverage, 3-D plan, PNG preview
``viz.preview``             depth-rendered split previews
``viz.partition``           exploded views of cut or partitioned pieces
``viz.profile``             the archaeological profile drawing as a PNG
==========================  =====================================================
"""
from __future__ import annotations

import importlib

# Submodule of each public name: they load on first use (matplotlib and the like are slow to import).
_WHERE = {"plot_raster": "layers", "plot_distance": "layers", "plot_toolpath": "layers", "plot_coverage": "layers", "plan_3d": "layers", "preview_png": "layers", "render_depth": "preview", "draw_split": "preview", "save_split_preview": "preview", "plot_exploded": "partition", "save_exploded_png": "partition", "profile_png": "profile"}


__all__ = ["plot_raster", "plot_distance", "plot_toolpath", "plot_coverage", "plan_3d", "preview_png", "render_depth", "draw_split", "save_split_preview", "plot_exploded", "save_exploded_png", "profile_png"]


def __getattr__(name):
    module = _WHERE.get(name)
    if module is None:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    value = getattr(importlib.import_module(f".{module}", __name__), name)
    globals()[name] = value
    return value


def __dir__():
    return sorted(set(globals()) | set(__all__))
