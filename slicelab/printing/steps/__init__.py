"""The steps of a layer's toolpaths: perimeters, gap fill, skins, overhangs and bridges, skirt,
ordering into paths, simplification.

==========================  =====================================================
``steps.perimeters``        erosion-based perimeters, filling limits
``steps.gapfill``           gap fill along the medial axis of what perimeters and filling miss
``steps.skins``             top and bottom skins by mask differences
``steps.overhangs``         bridges, unheld overhangs and mid-air islands of a layer
``steps.skirt``             the first layer's skirt and brim
``steps.filling``           the fill step: sparse, solid, top and bridge lines, gaps in solid filling
``steps.order``             the order step: islands, loops from their seams, paths nearest first
``steps.coverage``          how a layer's extrusions cover it
``steps.simplify``          Douglas-Peucker simplification of a layer's paths
==========================  =====================================================
"""
