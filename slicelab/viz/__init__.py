"""Figures and previews (matplotlib, imported on first use).

==========================  =====================================================
``viz.layers``              rasters, distance fields, toolpaths, coverage, 3-D plan
``viz.preview``             depth-rendered split previews
==========================  =====================================================
"""
from __future__ import annotations

import importlib

# Submodule of each public name: they load on first use (matplotlib and the like are slow to import).
_WHERE = {"plot_raster": "layers", "plot_distance": "layers", "plot_toolpath": "layers", "plot_coverage": "layers", "plan_3d": "layers", "render_depth": "preview", "draw_split": "preview", "save_split_preview": "preview"}


__all__ = ["plot_raster", "plot_distance", "plot_toolpath", "plot_coverage", "plan_3d", "render_depth", "draw_split", "save_split_preview"]


def __getattr__(name):
    module = _WHERE.get(name)
    if module is None:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    value = getattr(importlib.import_module(f".{module}", __name__), name)
    globals()[name] = value
    return value


def __dir__():
    return sorted(set(globals()) | set(__all__))
