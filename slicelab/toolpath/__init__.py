"""The printing half: layer rasters, distance fields, perimeters, infill, paths and the print plan.

==========================  =====================================================
``toolpath.masks``          pixel masks on the world grid: whole windows, or blocks along a boundary
``toolpath.raster``         `rasterize` a section (or its mask alone), drawing lines
``toolpath.hierarchy``      the raster hole hierarchy: OpenCV's contour tree matched to the loops
``toolpath.distance``       the exact distance field of a layer and its level sets
``toolpath.perimeters``     erosion-based perimeters, filling limits
``toolpath.gapfill``        gap fill along the medial axis of what perimeters and filling miss
``toolpath.infill``         rectilinear filling lines
``toolpath.patterns``       infill patterns by name: rectilinear, concentric, gyroid
``toolpath.simplify``       Douglas-Peucker simplification of a layer's paths
``toolpath.skirt``          the first layer's skirt and brim
``toolpath.estimate``       print time of G-code moves (trapezoids, look-ahead)
``toolpath.bed``            `check_bed`: does the part fit the printer
``toolpath.roles``          path kinds and roles, their G-code ``;TYPE:`` words and colours
``toolpath.table``          `LayerPaths`: a layer's toolpaths as a table, a row per path
``toolpath.paths``          `layer_paths`: one layer's ordered toolpaths, coverage
``toolpath.overhangs``      bridges, unheld overhangs and mid-air islands of a layer
``toolpath.skins``         top and bottom skins by mask differences
``toolpath.supports``      support material under unheld overhangs and mid-air islands
``toolpath.settings``       `PrintSettings` in groups (extrusion, infill, skins, motion, ...)
``toolpath.printers``       printer profiles, TOML settings files, start and end G-code
``toolpath.repeats``        layers that repeat: outlines compared, a prismatic stretch planned once
``toolpath.schedule``       which runs of layers the workers take first, by an estimate of their cost
``toolpath.planner``        `plan` a whole part -> `PrintPlan`
``toolpath.pool``           the forked process pool that plans layers and formats G-code
==========================  =====================================================
"""
from __future__ import annotations

from .._lazy import attach

# Submodule of each public name: they load on first use (matplotlib and the like are slow to import).
_WHERE = {"PRINTERS": "printers", "FLAVORS": "printers", "resolve_settings": "printers", "read_config": "printers", "format_config": "printers", "render_gcode": "printers", "MARLIN_START": "printers", "MARLIN_END": "printers", "GridMask": "masks", "BlockMask": "masks", "bits_in_blocks": "masks", "open_mask": "masks", "reach_disc": "masks", "LayerRaster": "raster", "RasterContours": "hierarchy", "rasterize": "raster", "layer_mask": "raster",
          "winding_numbers": "raster", "raster_hierarchy": "hierarchy", "draw_polylines": "raster", "RULES": "raster",
          "winding_blocks": "raster", "raster_blocks": "raster", "BLOCK": "raster", "BAND": "raster",
          "DistanceField": "distance", "signed_mask_distance": "distance", "distance_field": "distance",
          "level_rings": "distance",
          "level_polygons": "perimeters", "Perimeters": "perimeters", "layer_perimeters": "perimeters",
          "medial_fill": "gapfill", "mask_rings": "perimeters", "perimeter_depth": "perimeters",
          "perimeter_band": "perimeters", "split_by_mask": "perimeters", "disc": "gapfill", "uncovered_blocks": "gapfill",
          "medial_fill_blocks": "gapfill",
          "FillLines": "infill", "fill_lines": "infill", "rectilinear": "infill", "line_spacing": "infill",
          "PATTERNS": "patterns", "fill_pattern": "patterns", "concentric": "patterns", "gyroid": "patterns",
          "GYROID_LENGTH": "patterns", "simplify_mask": "simplify", "simplify_path": "simplify",
          "simplify_paths": "simplify", "simplify_rings": "simplify", "skirt_loops": "skirt",
          "skirt_margin": "skirt", "with_skirt": "skirt", "move_times": "estimate", "format_duration": "estimate",
          "check_bed": "bed", "ISLAND_ROLES": "roles",
          "ROLES": "roles", "FILLING_KINDS": "roles", "KINDS": "roles", "ROLE_OF": "roles", "RoleStyle": "roles", "STYLES": "roles",
          "LayerPaths": "table", "SEAMS": "paths", "layer_paths": "paths", "coverage_map": "paths", "covered_pixels": "paths",
          "PrintPlan": "planner", "plan": "planner", "layer_bounds": "planner", "forked_pool": "pool",
          "PrintSettings": "settings", "settings_dict": "settings", "Bridge": "overhangs", "LayerOverhangs": "overhangs", "layer_overhangs": "overhangs", "mark_overhangs": "overhangs", "PERIMETER_KINDS": "overhangs", "setting_names": "settings",
          "Extrusion": "settings", "Infill": "settings", "Skins": "settings", "Motion": "settings",
          "Cooling": "settings", "Adhesion": "settings", "Walls": "settings", "Supports": "settings", "PIXEL": "supports", "layer_skins": "skins", "SUPPORTS": "supports", "support_masks": "supports", "support_paths": "supports", "Machine": "settings", "Raster": "settings",
          "GROUPS": "settings", "outline_key": "repeats", "same_outline": "repeats", "same_point": "repeats",
          "outline_size": "repeats", "may_repeat": "repeats", "Repeats": "repeats",
          "same_mask": "repeats", "RunStart": "repeats", "start_candidates": "repeats", "run_starts": "repeats",
          "SKIN_COST": "schedule", "REPEAT_COST": "schedule", "layer_costs": "schedule", "costliest_first": "schedule"}


__all__ = ["PRINTERS", "FLAVORS", "resolve_settings", "read_config", "format_config", "render_gcode", "MARLIN_START", "MARLIN_END", "GridMask", "BlockMask", "bits_in_blocks", "open_mask", "reach_disc", "LayerRaster", "RasterContours", "rasterize", "layer_mask", "winding_numbers", "raster_hierarchy",
           "draw_polylines", "RULES", "winding_blocks", "raster_blocks", "BLOCK", "BAND", "DistanceField", "signed_mask_distance", "distance_field", "level_rings",
           "level_polygons", "Perimeters", "layer_perimeters", "medial_fill", "mask_rings", "perimeter_depth",
           "perimeter_band", "split_by_mask", "disc", "uncovered_blocks", "medial_fill_blocks", "FillLines",
           "fill_lines", "rectilinear", "line_spacing", "PATTERNS", "fill_pattern", "concentric", "gyroid",
           "GYROID_LENGTH", "simplify_mask", "simplify_path", "simplify_paths", "simplify_rings", "skirt_loops",
           "skirt_margin", "with_skirt", "move_times", "format_duration", "check_bed", "ISLAND_ROLES", "ROLES",
           "FILLING_KINDS", "KINDS", "ROLE_OF", "RoleStyle", "STYLES", "LayerPaths", "layer_paths", "coverage_map", "covered_pixels", "PrintSettings",
           "PrintPlan", "forked_pool", "plan", "layer_bounds", "settings_dict", "setting_names", "Extrusion", "Infill", "Skins",
           "Motion", "Cooling", "Adhesion", "Machine", "Raster", "Walls", "Supports", "PIXEL", "SUPPORTS",
           "support_masks", "support_paths", "layer_skins", "GROUPS", "SEAMS", "Bridge", "LayerOverhangs",
           "layer_overhangs", "mark_overhangs", "PERIMETER_KINDS", "outline_key", "same_outline", "same_point", "outline_size", "may_repeat", "Repeats", "same_mask",
           "RunStart", "start_candidates", "run_starts", "SKIN_COST", "REPEAT_COST", "layer_costs", "costliest_first"]


__getattr__, __dir__ = attach(__name__, _WHERE, globals())
