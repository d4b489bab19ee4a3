"""The printing half: layer rasters, distance fields, perimeters, infill, paths and the print plan.

==========================  =====================================================
``printing.planner``        `plan` a whole part -> `PrintPlan`
``printing.table``          `LayerPaths`: a layer's toolpaths as a table, a row per path
``printing.roles``          path kinds and roles, their G-code ``;TYPE:`` words and colours
``printing.grid``           a layer on the pixel grid: masks, rasters, hole hierarchy, distance fields
``printing.steps``          perimeters, gap fill, skins, overhangs and bridges, skirt, paths, simplification
``printing.fill``           filling lines and the infill patterns by name
``printing.supports``       support material under unheld overhangs and mid-air islands
``printing.config``         `PrintSettings` in groups, printer profiles and settings files, the bed
``printing._reuse``         layers that repeat, planned once (private)
``printing._schedule``      which runs of layers the workers take first (private)
==========================  =====================================================
"""
from __future__ import annotations

from .._lazy import attach

# Submodule of each public name: they load on first use (matplotlib and the like are slow to import).
_WHERE = {"PRINTERS": "config.printers", "FLAVORS": "config.printers", "resolve_settings": "config.printers", "read_config": "config.printers", "format_config": "config.printers", "render_gcode": "config.printers", "MARLIN_START": "config.printers", "MARLIN_END": "config.printers", "GridMask": "grid.masks", "BlockMask": "grid.masks", "bits_in_blocks": "grid.masks", "open_mask": "grid.masks", "reach_disc": "grid.masks", "LayerRaster": "grid.raster", "RasterContours": "grid.hierarchy", "rasterize": "grid.raster", "layer_mask": "grid.raster",
          "winding_numbers": "grid.raster", "raster_hierarchy": "grid.hierarchy", "draw_polylines": "grid.raster", "RULES": "grid.raster",
          "winding_blocks": "grid.raster", "raster_blocks": "grid.raster", "BLOCK": "grid.raster", "BAND": "grid.raster",
          "DistanceField": "grid.distance", "signed_mask_distance": "grid.distance", "distance_field": "grid.distance",
          "level_rings": "grid.distance",
          "level_polygons": "steps.perimeters", "Perimeters": "steps.perimeters", "layer_perimeters": "steps.perimeters",
          "medial_fill": "steps.gapfill", "mask_rings": "steps.perimeters", "perimeter_depth": "steps.perimeters",
          "perimeter_band": "steps.perimeters", "split_by_mask": "steps.perimeters", "disc": "steps.gapfill", "uncovered_blocks": "steps.gapfill",
          "medial_fill_blocks": "steps.gapfill",
          "FillLines": "fill.lines", "fill_lines": "fill.lines", "rectilinear": "fill.lines", "line_spacing": "fill.lines",
          "PATTERNS": "fill", "fill_pattern": "fill", "Pattern": "fill", "concentric": "fill.concentric", "gyroid": "fill.gyroid", "triangles": "fill.triangles",
          "GYROID_LENGTH": "fill.gyroid", "simplify_mask": "steps.simplify", "simplify_path": "steps.simplify",
          "simplify_paths": "steps.simplify", "simplify_rings": "steps.simplify", "skirt_loops": "steps.skirt",
          "skirt_margin": "steps.skirt", "with_skirt": "steps.skirt",
          "check_bed": "config.bed", "ISLAND_ROLES": "roles",
          "ROLES": "roles", "FILLING_KINDS": "roles", "KINDS": "roles", "ROLE_OF": "roles", "RoleStyle": "roles", "STYLES": "roles",
          "LayerPaths": "table", "SEAMS": "steps.order", "layer_paths": "pipeline", "plan_layer": "pipeline", "LayerInputs": "pipeline", "LayerPlan": "pipeline", "STEPS": "pipeline", "coverage_map": "steps.coverage", "covered_pixels": "steps.coverage",
          "PrintPlan": "planner", "plan": "planner", "layer_bounds": "planner",
          "PrintSettings": "config.settings", "settings_dict": "config.settings", "Bridge": "steps.overhangs", "LayerOverhangs": "steps.overhangs", "layer_overhangs": "steps.overhangs", "mark_overhangs": "steps.overhangs", "PERIMETER_KINDS": "steps.overhangs", "setting_names": "config.settings",
          "Extrusion": "config.settings", "Infill": "config.settings", "Skins": "config.settings", "Motion": "config.settings",
          "Cooling": "config.settings", "Adhesion": "config.settings", "Walls": "config.settings", "Supports": "config.settings", "PIXEL": "supports.columns", "PLACEMENTS": "supports", "SupportStyle": "supports", "support_lines": "supports", "layer_skins": "steps.skins", "SUPPORTS": "supports", "support_masks": "supports.columns", "support_paths": "supports.columns", "Machine": "config.settings", "Raster": "config.settings",
          "GROUPS": "config.settings", "outline_key": "_reuse", "same_outline": "_reuse", "same_point": "_reuse",
          "outline_size": "_reuse", "may_repeat": "_reuse", "Repeats": "_reuse",
          "same_mask": "_reuse", "RunStart": "_reuse", "start_candidates": "_reuse", "run_starts": "_reuse",
          "SKIN_COST": "_schedule", "REPEAT_COST": "_schedule", "layer_costs": "_schedule", "costliest_first": "_schedule"}


__all__ = ["PRINTERS", "FLAVORS", "resolve_settings", "read_config", "format_config", "render_gcode", "MARLIN_START", "MARLIN_END", "GridMask", "BlockMask", "bits_in_blocks", "open_mask", "reach_disc", "LayerRaster", "RasterContours", "rasterize", "layer_mask", "winding_numbers", "raster_hierarchy",
           "draw_polylines", "RULES", "winding_blocks", "raster_blocks", "BLOCK", "BAND", "DistanceField", "signed_mask_distance", "distance_field", "level_rings",
           "level_polygons", "Perimeters", "layer_perimeters", "medial_fill", "mask_rings", "perimeter_depth",
           "perimeter_band", "split_by_mask", "disc", "uncovered_blocks", "medial_fill_blocks", "FillLines",
           "fill_lines", "rectilinear", "line_spacing", "PATTERNS", "Pattern", "fill_pattern", "concentric", "gyroid", "triangles",
           "GYROID_LENGTH", "simplify_mask", "simplify_path", "simplify_paths", "simplify_rings", "skirt_loops",
           "skirt_margin", "with_skirt", "check_bed", "ISLAND_ROLES", "ROLES",
           "FILLING_KINDS", "KINDS", "ROLE_OF", "RoleStyle", "STYLES", "LayerPaths", "layer_paths", "coverage_map", "covered_pixels", "PrintSettings",
           "PrintPlan", "plan", "layer_bounds", "settings_dict", "setting_names", "Extrusion", "Infill", "Skins",
           "Motion", "Cooling", "Adhesion", "Machine", "Raster", "Walls", "Supports", "PIXEL", "SUPPORTS", "PLACEMENTS", "SupportStyle", "support_lines",
           "support_masks", "support_paths", "layer_skins", "GROUPS", "SEAMS", "Bridge", "LayerOverhangs",
           "layer_overhangs", "mark_overhangs", "PERIMETER_KINDS", "outline_key", "same_outline", "same_point", "outline_size", "may_repeat", "Repeats", "same_mask",
           "RunStart", "start_candidates", "run_starts", "SKIN_COST", "REPEAT_COST", "layer_costs", "costliest_first"]


__getattr__, __dir__ = attach(__name__, _WHERE, globals())
