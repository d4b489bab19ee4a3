"""The printing half: layer rasters, perimeters, infill, paths and the print plan.

==========================  =====================================================
``toolpath.raster``         `rasterize` a section, the raster hole hierarchy
``toolpath.perimeters``     erosion-based perimeters from an exact distance field
``toolpath.infill``         rectilinear filling lines
``toolpath.paths``          `layer_paths`: one layer's ordered toolpaths
``toolpath.planner``        `plan` a whole part -> `PrintPlan`, `PrintSettings`
==========================  =====================================================
"""
from __future__ import annotations

import importlib

# Submodule of each public name: they load on first use (matplotlib and the like are slow to import).
_WHERE = {"GridMask": "raster", "LayerRaster": "raster", "RasterContours": "raster", "rasterize": "raster", "winding_numbers": "raster", "raster_hierarchy": "raster", "RULES": "raster", "SegmentIndex": "perimeters", "DistanceField": "perimeters", "distance_field": "perimeters", "level_rings": "perimeters", "level_polygons": "perimeters", "Perimeters": "perimeters", "layer_perimeters": "perimeters", "trace_skeleton": "perimeters", "signed_mask_distance": "perimeters", "medial_fill": "perimeters", "simplify_ring": "perimeters", "mask_rings": "perimeters", "march": "perimeters", "FillLines": "infill", "fill_lines": "infill", "rectilinear": "infill", "line_spacing": "infill", "LayerPaths": "paths", "layer_paths": "paths", "coverage_map": "paths", "ROLES": "paths", "PrintSettings": "planner", "PrintPlan": "planner", "plan": "planner", "layer_bounds": "planner"}


__all__ = ["GridMask", "LayerRaster", "RasterContours", "rasterize", "winding_numbers", "raster_hierarchy", "RULES", "SegmentIndex", "DistanceField", "distance_field", "level_rings", "level_polygons", "Perimeters", "layer_perimeters", "trace_skeleton", "signed_mask_distance", "medial_fill", "simplify_ring", "mask_rings", "march", "FillLines", "fill_lines", "rectilinear", "line_spacing", "LayerPaths", "layer_paths", "coverage_map", "ROLES", "PrintSettings", "PrintPlan", "plan", "layer_bounds"]


def __getattr__(name):
    module = _WHERE.get(name)
    if module is None:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    value = getattr(importlib.import_module(f".{module}", __name__), name)
    globals()[name] = value
    return value


def __dir__():
    return sorted(set(globals()) | set(__all__))
